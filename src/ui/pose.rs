//! The Pose section: what is selected, reset, undo and redo.

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
}
