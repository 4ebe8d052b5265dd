//! The Stats section: sizes, step time, rates, state.

use super::PanelState;
use crate::session::Session;

pub(super) fn stats_section(ui: &mut egui::Ui, state: &PanelState, session: &Session) {
    ui.strong("Stats");
    let p = &session.puppet;
    egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
        let rows = [
            ("mesh", session.name.clone()),
            ("vertices", p.mesh.positions.len().to_string()),
            ("springs", p.sim.rig().spring_count().to_string()),
            ("sections", p.joints.sections().len().to_string()),
            ("step", format!("{:.2} ms", state.stats.step_ms)),
            ("steps/s", format!("{:.0}", state.stats.steps_per_second)),
            ("fps", format!("{:.0}", state.stats.fps)),
            (
                "state",
                if session.is_paused() {
                    "paused".into()
                } else if session.is_settled() {
                    "settled".into()
                } else {
                    "simulating".into()
                },
            ),
        ];
        for (k, v) in rows {
            ui.label(k);
            ui.label(v);
            ui.end_row();
        }
        if let Some((seconds, report)) = &state.opened {
            // The whole path from the file, stage by stage on hover.
            ui.label("opened in");
            let label = ui.label(format!("{seconds:.2} s"));
            let mut stages: Vec<String> = report
                .iter()
                .flat_map(|r| r.seconds.iter())
                .map(|(k, v)| format!("{k} {:.0} ms", v * 1e3))
                .collect();
            stages.extend(
                p.skeleton
                    .seconds
                    .iter()
                    .filter(|(k, _)| *k == "total")
                    .map(|(_, v)| format!("skeleton {:.0} ms", v * 1e3)),
            );
            label.on_hover_text(stages.join(", "));
            ui.end_row();
            // What loading repaired, one line each.
            let repairs = report.as_ref().map(|r| r.warnings()).unwrap_or_default();
            for (k, line) in repairs.iter().enumerate() {
                ui.label(if k == 0 { "on load" } else { "" });
                ui.small(line);
                ui.end_row();
            }
        }
    });
    ui.small("drag: turn selection or orbit · right drag: pan · wheel: zoom · F: frame · R: reset pose · Ctrl+Z/Y: undo/redo · W: wireframe · Space: pause");
}
