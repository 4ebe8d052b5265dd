//! The File section: what is open (its file name; the full path on hover), open a mesh,
//! recent files, load and save a rig, export the surface. Files come from the system's
//! dialog, the recent list, a typed path, or a file dropped on the window.

use super::{Action, FilePurpose, PanelState};
use std::path::{Path, PathBuf};

pub(super) fn file_section(
    ui: &mut egui::Ui,
    state: &mut PanelState,
    shown: Option<&str>,
    actions: &mut Vec<Action>,
) {
    if let Some(name) = shown {
        let label = ui.label(egui::RichText::new(name).strong());
        if let Some(source) = &state.source {
            label.on_hover_text(source.display().to_string());
        }
    }
    ui.horizontal_wrapped(|ui| {
        if ui.button("Open mesh…").clicked() {
            actions.push(Action::Browse(FilePurpose::OpenMesh));
        }
        if !state.recent.is_empty() {
            egui::ComboBox::from_id_salt("recent")
                .selected_text("Recent")
                .show_ui(ui, |ui| {
                    for path in &state.recent {
                        let response = ui.selectable_label(false, file_name(path));
                        if response.on_hover_text(path.display().to_string()).clicked() {
                            actions.push(Action::File(purpose_of(path), path.clone()));
                        }
                    }
                });
        }
    });
    ui.horizontal_wrapped(|ui| {
        if ui.button("Load rig…").clicked() {
            actions.push(Action::Browse(FilePurpose::LoadRig));
        }
        if ui.button("Save rig…").clicked() {
            actions.push(Action::Browse(FilePurpose::SaveRig));
        }
        if ui.button("Export OBJ…").clicked() {
            actions.push(Action::Browse(FilePurpose::ExportSurface));
        }
    });
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Open animation…")
            .on_hover_text("an animation file (the format `puppet simulate --anim` reads)")
            .clicked()
        {
            actions.push(Action::Browse(FilePurpose::OpenAnimation));
        }
        if ui.button("Save animation…").clicked() {
            actions.push(Action::Browse(FilePurpose::SaveAnimation));
        }
    });
    ui.collapsing("Type a path", |ui| {
        ui.small("for systems without a file dialog; or drop a file on the window");
        ui.text_edit_singleline(&mut state.path);
        let path = PathBuf::from(state.path.trim());
        let typed = !state.path.trim().is_empty();
        ui.horizontal_wrapped(|ui| {
            for (label, purpose) in [
                ("Open", FilePurpose::OpenMesh),
                ("Load rig", FilePurpose::LoadRig),
                ("Save rig", FilePurpose::SaveRig),
                ("Export", FilePurpose::ExportSurface),
                ("Open anim", FilePurpose::OpenAnimation),
                ("Save anim", FilePurpose::SaveAnimation),
                ("Export anim", FilePurpose::ExportAnimation),
                ("Load controls", FilePurpose::LoadControls),
                ("Save controls", FilePurpose::SaveControls),
            ] {
                if ui.add_enabled(typed, egui::Button::new(label)).clicked() {
                    actions.push(Action::File(purpose, path.clone()));
                }
            }
        });
    });
}

/// The clips of a skinned file: choosing one plays it (the sections named after its
/// joints move as it moves them; record over it like any animation).
pub(super) fn clip_row(
    ui: &mut egui::Ui,
    session: &mut crate::session::Session,
    state: &mut PanelState,
) {
    let clips = session.clips();
    if clips.is_empty() {
        return;
    }
    ui.horizontal_wrapped(|ui| {
        egui::ComboBox::from_id_salt("clips")
            .selected_text(format!("Clips ({})", clips.len()))
            .show_ui(ui, |ui| {
                for (name, seconds) in &clips {
                    if ui
                        .selectable_label(false, format!("{name}  {seconds:.2} s"))
                        .clicked()
                    {
                        state.message = Some(match session.play_clip(name) {
                            Ok(()) => (format!("playing clip '{name}'"), false),
                            Err(e) => (format!("clip '{name}': {e}"), true),
                        });
                    }
                }
            })
            .response
            .on_hover_text(
                "the clips of the file's skin: choose one to play it through the puppet",
            );
    });
}

/// A path as the panel shows it: its file name (never a `..` path).
pub fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// A recent file is a rig when it is named like one, else a mesh.
fn purpose_of(path: &Path) -> FilePurpose {
    let name = file_name(path).to_ascii_lowercase();
    if name.ends_with(".toml") || name.ends_with(".json") {
        FilePurpose::LoadRig
    } else {
        FilePurpose::OpenMesh
    }
}
