//! The Controls section: the live input (`--controls`), its port, each control's value
//! and how many messages were ignored.

/// What the panel and the report show of the live input.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct LiveCounts {
    /// The UDP port OSC arrives on.
    pub port: u16,
    /// Messages that reached a control.
    pub used: usize,
    /// Messages no control reads.
    pub unknown: usize,
    /// Samples ignored as malformed (missing, not a number, non-finite, huge).
    pub ignored: usize,
    /// Packets that were not OSC.
    pub bad_packets: usize,
    /// Each control's name and its current 0..1 value.
    pub values: Vec<(String, Option<f64>)>,
}

pub(super) fn controls_section(ui: &mut egui::Ui, live: &LiveCounts) {
    ui.strong("Controls");
    ui.small(format!(
        "OSC on UDP port {}: {} messages used",
        live.port, live.used
    ));
    for (name, value) in &live.values {
        ui.horizontal(|ui| {
            let v = value.unwrap_or(0.0) as f32;
            ui.add(
                egui::ProgressBar::new(v)
                    .desired_width(110.0)
                    .text(match value {
                        Some(v) => format!("{v:.2}"),
                        None => "—".into(),
                    }),
            );
            ui.label(name.as_str());
        });
    }
    let ignored = live.unknown + live.ignored + live.bad_packets;
    if ignored > 0 {
        ui.small(format!(
            "ignored: {} for no control, {} malformed values, {} packets not OSC",
            live.unknown, live.ignored, live.bad_packets
        ));
    }
}
