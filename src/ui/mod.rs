//! The puppeteer's panels (egui), one file each: `file` (and a skinned file's clips),
//! `export` (a take), `material`, `world` (gravity, floor), `regions` (other materials,
//! pinning, the brush), `pose`, `cuts`, `overlays`, `controls` (live input), `stats`, and
//! `timeline` (the animation's, at the bottom). They edit the core's [`Session`] and hand
//! what needs the window (opening files, framing) back as [`Action`]s.

mod controls;
mod cuts;
mod export;
mod file;
mod material;
mod overlays;
mod pose;
mod regions;
mod stats;
mod timeline;
mod world;

pub use file::file_name;

use crate::session::{Overlays, Session};
pub use controls::LiveCounts;

/// What a file dialog is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilePurpose {
    /// Open a mesh.
    OpenMesh,
    /// Load a rig file.
    LoadRig,
    /// Save the rig.
    SaveRig,
    /// Export the current surface.
    ExportSurface,
    /// Open an animation file and play it.
    OpenAnimation,
    /// Save the animation loaded.
    SaveAnimation,
    /// Bake the animation to `.glb`, `.pc2`, a folder of OBJ files or a video.
    ExportAnimation,
    /// Load a controls file (live devices mapped to sections).
    LoadControls,
    /// Save the controls as they stand (with what was learned and calibrated).
    SaveControls,
}

/// Something the panel asks the window to do.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Ask for a file with the system's dialog.
    Browse(FilePurpose),
    /// Use this file (typed, picked from the recent files, or from a dialog).
    File(FilePurpose, std::path::PathBuf),
    /// Frame the model in the view.
    Frame,
    /// Replace the cuts with the ones suggested by the skeleton.
    SuggestJoints,
    /// Start or stop learning: the control that moves drives the section clicked.
    Learn,
    /// Start calibrating the controls.
    Calibrate,
    /// End calibrating: keep the ranges seen (true) or drop them.
    CalibrateDone(bool),
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
    /// How the moving view's edges are smoothed; `None` before a window has a choice.
    pub anti_aliasing: Option<crate::render::AntiAliasing>,
    /// The choices this adapter and window offer.
    pub anti_aliasing_offered: Vec<crate::render::AntiAliasing>,
    /// The path field (for a typed path when there is no file dialog).
    pub path: String,
    /// Files opened recently, the latest first.
    pub recent: Vec<std::path::PathBuf>,
    /// The full path of the file shown, if it came from a file.
    pub source: Option<std::path::PathBuf>,
    /// The first-run hint is shown in the view.
    pub hint: bool,
    /// Where the side panel is (in egui points), from the last frame.
    pub rect: Option<egui::Rect>,
    /// Its width in pixels.
    pub width_px: f32,
    /// Last message: text and whether it is an error.
    pub message: Option<(String, bool)>,
    /// Loading: stage and fraction.
    pub loading: Option<(String, f32)>,
    /// The puppet shown took this many seconds from its file, read as the report says.
    pub opened: Option<(f64, Option<crate::mesh::LoadReport>)>,
    /// Frame statistics.
    pub stats: Stats,
    /// The live controls, when the command line gave some.
    pub live: Option<LiveCounts>,
}

impl Default for PanelState {
    fn default() -> Self {
        PanelState {
            overlays: Overlays::default(),
            anti_aliasing: None,
            anti_aliasing_offered: Vec::new(),
            path: String::new(),
            recent: Vec::new(),
            source: None,
            hint: false,
            rect: None,
            width_px: 0.0,
            message: None,
            loading: None,
            opened: None,
            stats: Stats::default(),
            live: None,
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
    let mut session = session;
    if let Some(s) = session.as_deref_mut() {
        timeline::timeline(ui, s);
    }
    let shown = session.as_ref().map(|s| s.name.clone());
    let panel = egui::Panel::left("puppet")
        .resizable(true)
        .default_size(290.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.heading("puppet");
                file::file_section(ui, state, shown.as_deref(), &mut actions);
                if let Some(s) = session.as_deref_mut() {
                    file::clip_row(ui, s, state);
                }
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
                    export::export_section(ui, session, &mut actions);
                    ui.separator();
                    material::material_section(ui, session);
                    ui.separator();
                    world::world_section(ui, session);
                    ui.separator();
                    regions::regions_section(ui, session);
                    ui.separator();
                    pose::pose_section(ui, session);
                    ui.separator();
                    cuts::cut_section(ui, state, session, &mut actions);
                    ui.separator();
                    overlays::overlay_section(ui, state, &mut actions);
                    ui.separator();
                    controls::controls_section(ui, state.live.as_ref(), &mut actions);
                    ui.separator();
                    stats::stats_section(ui, state, session);
                }
            });
        });
    let rect = panel.response.rect;
    state.rect = Some(rect);
    state.width_px = rect.right() * ui.ctx().pixels_per_point();
    if state.hint {
        // Above the timeline, when there is one.
        let bottom = ui.available_rect_before_wrap().bottom();
        hint(ui.ctx(), rect.right(), bottom);
    }
    actions
}

/// The first-run hint, at the bottom of the 3D view (not interactable: clicks go through
/// it to the model).
fn hint(ctx: &egui::Context, left: f32, bottom: f32) {
    let view = ctx.content_rect();
    let centre = egui::pos2(
        (left + view.right()) * 0.5,
        bottom.min(view.bottom()) - 24.0,
    );
    egui::Area::new(egui::Id::unique("first-run hint"))
        .interactable(false)
        .pivot(egui::Align2::CENTER_BOTTOM)
        .fixed_pos(centre)
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                ui.label(
                    egui::RichText::new("Drag a coloured part of the puppet to turn it").strong(),
                );
                ui.label("drag the background to look around · right-drag to pan · wheel to zoom");
                ui.label("Cuts (left): suggest joints, or cut your own with the cut tool (C)");
            });
        });
}
