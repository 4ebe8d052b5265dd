//! The puppeteer's panels (egui): file, material, pose, cuts, overlays and stats, one file
//! each. They edit the core's [`Session`] directly and hand what needs the window (opening
//! files, framing) back as [`Action`]s.

mod cuts;
mod file;
mod material;
mod overlays;
mod pose;
mod stats;

use crate::session::{Overlays, Session};

/// Something the panel asks the window to do.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Open a mesh file (the path as typed).
    OpenMesh(String),
    /// Load a rig file.
    LoadRig(String),
    /// Save the current rig.
    SaveRig(String),
    /// Export the current surface as OBJ.
    ExportObj(String),
    /// Frame the model in the view.
    Frame,
}

/// Frame statistics shown in the panel.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// Frames drawn per second.
    pub fps: f32,
    /// Simulation steps per second.
    pub steps_per_second: f32,
    /// Time of the last step.
    pub step_ms: f32,
}

/// Panel state that is not part of the session.
pub struct PanelState {
    /// The overlays shown.
    pub overlays: Overlays,
    /// The mesh path field.
    pub open_path: String,
    /// The rig path field.
    pub rig_path: String,
    /// The export path field.
    pub export_path: String,
    /// Last message: text and whether it is an error.
    pub message: Option<(String, bool)>,
    /// Loading: stage and fraction.
    pub loading: Option<(String, f32)>,
    /// Frame statistics.
    pub stats: Stats,
}

impl Default for PanelState {
    fn default() -> Self {
        PanelState {
            overlays: Overlays::default(),
            open_path: String::new(),
            rig_path: "puppet.rig.toml".into(),
            export_path: "puppet.obj".into(),
            message: None,
            loading: None,
            stats: Stats::default(),
        }
    }
}

/// Draws the side panel; returns the actions the window must carry out.
pub fn side_panel(
    ui: &mut egui::Ui,
    state: &mut PanelState,
    session: Option<&mut Session>,
) -> Vec<Action> {
    let mut actions = Vec::new();
    egui::Panel::left("puppet")
        .resizable(true)
        .default_size(290.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.heading("puppet");
                file::file_section(ui, state, &mut actions);
                if let Some((stage, fraction)) = &state.loading {
                    ui.add(
                        egui::ProgressBar::new(*fraction)
                            .text(stage.as_str())
                            .show_percentage(),
                    );
                }
                if let Some((text, error)) = &state.message {
                    let color = if *error {
                        egui::Color32::from_rgb(255, 110, 100)
                    } else {
                        egui::Color32::from_rgb(150, 220, 150)
                    };
                    ui.colored_label(color, text.as_str());
                }
                if let Some(session) = session {
                    ui.separator();
                    material::material_section(ui, session);
                    ui.separator();
                    pose::pose_section(ui, session);
                    ui.separator();
                    cuts::cut_section(ui, state, session);
                    ui.separator();
                    overlays::overlay_section(ui, state, &mut actions);
                    ui.separator();
                    stats::stats_section(ui, state, session);
                }
            });
        });
    actions
}
