//! The Controls section: the live input (`--controls`, `--listen`), its port, each
//! control's value and how many messages were ignored; *Learn* and *Calibrate*; loading
//! and saving the controls file.

use super::{Action, FilePurpose};

/// What the panel and the report show of the live input.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct LiveCounts {
    /// The UDP port OSC arrives on (0: none).
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
    /// While learning: what it waits for, or the control that moved.
    pub learning: Option<String>,
    /// While calibrating: each control's raw range so far, in file order.
    pub calibrating: Option<Vec<Option<[f64; 2]>>>,
}

pub(super) fn controls_section(
    ui: &mut egui::Ui,
    live: Option<&LiveCounts>,
    actions: &mut Vec<Action>,
) {
    ui.strong("Controls");
    let Some(live) = live else {
        ui.small(
            "A glove, MIDI controller or gamepad: learn its controls, or load a controls file.",
        );
        ui.horizontal_wrapped(|ui| {
            learn_button(ui, false, actions);
            if ui.button("Load controls…").clicked() {
                actions.push(Action::Browse(FilePurpose::LoadControls));
            }
        });
        return;
    };
    if live.port != 0 {
        ui.small(format!(
            "OSC on UDP port {}: {} messages used",
            live.port, live.used
        ));
    } else {
        ui.small(format!("{} messages used", live.used));
    }
    for (k, (name, value)) in live.values.iter().enumerate() {
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
            if let Some(Some(Some([lo, hi]))) = live.calibrating.as_ref().map(|c| c.get(k)) {
                ui.small(format!("{lo:.3}–{hi:.3}"));
            }
        });
    }
    let ignored = live.unknown + live.ignored + live.bad_packets;
    if ignored > 0 {
        ui.small(format!(
            "ignored: {} for no control, {} malformed values, {} packets not OSC",
            live.unknown, live.ignored, live.bad_packets
        ));
    }
    if let Some(step) = &live.learning {
        ui.colored_label(egui::Color32::from_rgb(255, 200, 90), step.as_str());
    }
    ui.horizontal_wrapped(|ui| {
        learn_button(ui, live.learning.is_some(), actions);
        if live.calibrating.is_some() {
            if ui
                .button("Done")
                .on_hover_text("keep the ranges the controls were moved over")
                .clicked()
            {
                actions.push(Action::CalibrateDone(true));
            }
            if ui.button("Cancel").clicked() {
                actions.push(Action::CalibrateDone(false));
            }
        } else if ui
            .add_enabled(!live.values.is_empty(), egui::Button::new("Calibrate"))
            .on_hover_text("move every control end to end, then Done")
            .clicked()
        {
            actions.push(Action::Calibrate);
        }
    });
    if live.calibrating.is_some() {
        ui.colored_label(
            egui::Color32::from_rgb(255, 200, 90),
            "calibrating: move every control end to end, then Done",
        );
    }
    ui.horizontal_wrapped(|ui| {
        if ui.button("Load controls…").clicked() {
            actions.push(Action::Browse(FilePurpose::LoadControls));
        }
        if ui.button("Save controls…").clicked() {
            actions.push(Action::Browse(FilePurpose::SaveControls));
        }
    });
}

fn learn_button(ui: &mut egui::Ui, learning: bool, actions: &mut Vec<Action>) {
    let label = if learning {
        "Stop learning"
    } else {
        "Learn (L)"
    };
    if ui
        .selectable_label(learning, label)
        .on_hover_text("move a control, then click the section it drives (as MIDI learn)")
        .clicked()
    {
        actions.push(Action::Learn);
    }
}
