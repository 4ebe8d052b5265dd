//! The Pose section: what is selected, reset, undo and redo, recording a take.

use crate::session::Session;

pub(super) fn pose_section(ui: &mut egui::Ui, session: &mut Session) {
    ui.strong("Pose");
    let names: Vec<String> = session
        .selection
        .iter()
        .map(|&s| session.puppet.joints.sections()[s].name.clone())
        .collect();
    ui.label(if names.is_empty() {
        "click a section to select it, drag to turn it; Shift+click adds".to_string()
    } else {
        format!("selected: {}", names.join(", "))
    });
    ui.horizontal(|ui| {
        if ui.button("Reset pose").clicked() {
            session.reset_pose();
        }
        if ui
            .add_enabled(session.can_undo(), egui::Button::new("Undo"))
            .clicked()
        {
            session.undo();
        }
        if ui
            .add_enabled(session.can_redo(), egui::Button::new("Redo"))
            .clicked()
        {
            session.redo();
        }
    });
    record(ui, session);
}

/// Recording a take: start/stop, how closely keys follow it, slow motion.
fn record(ui: &mut egui::Ui, session: &mut Session) {
    ui.horizontal(|ui| {
        if session.is_recording() {
            let label = format!("Stop ({:.1} s)", session.recorded_seconds());
            if ui
                .button(egui::RichText::new(label).color(egui::Color32::from_rgb(255, 110, 100)))
                .clicked()
            {
                session.recorder.said = Some(session.stop_recording().unwrap_or_else(|e| e));
            }
        } else if ui
            .button("Record")
            .on_hover_text(
                "Ctrl+R; turn sections while recording; Stop makes the take the animation \
                 (or records it over the animation from where it stands)",
            )
            .clicked()
        {
            session.start_recording();
        }
    });
    if let Some(said) = &session.recorder.said {
        ui.small(said.as_str());
    }
    ui.add(
        egui::Slider::new(&mut session.recorder.tolerance, 0.1..=10.0)
            .logarithmic(true)
            .text("key tolerance (°)"),
    );
    ui.add(egui::Slider::new(&mut session.recorder.speed, 0.1..=1.0).text("recording speed"))
        .on_hover_text("below 1: record in slow motion, play back at normal speed");
}
