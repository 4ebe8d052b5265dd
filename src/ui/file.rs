//! The File section: open a mesh, load and save a rig, export the surface.

use super::{Action, PanelState};

pub(super) fn file_section(ui: &mut egui::Ui, state: &mut PanelState, actions: &mut Vec<Action>) {
    ui.collapsing("File", |ui| {
        ui.label("Mesh (OBJ), or drop a file on the window:");
        ui.horizontal(|ui| {
            ui.text_edit_singleline(&mut state.open_path);
            if ui.button("Open").clicked() && !state.open_path.trim().is_empty() {
                actions.push(Action::OpenMesh(state.open_path.trim().to_string()));
            }
        });
        ui.label("Rig file:");
        ui.horizontal(|ui| {
            ui.text_edit_singleline(&mut state.rig_path);
            if ui.button("Load").clicked() {
                actions.push(Action::LoadRig(state.rig_path.trim().to_string()));
            }
            if ui.button("Save").clicked() {
                actions.push(Action::SaveRig(state.rig_path.trim().to_string()));
            }
        });
        ui.label("Export the current surface:");
        ui.horizontal(|ui| {
            ui.text_edit_singleline(&mut state.export_path);
            if ui.button("Export OBJ").clicked() {
                actions.push(Action::ExportObj(state.export_path.trim().to_string()));
            }
        });
    });
}
