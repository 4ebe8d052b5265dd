//! The egui side panel: file, material, pose, cuts, overlays and stats. It edits the
//! [`Session`] directly and hands what needs the window (opening files, framing) back as
//! [`Action`]s.

use crate::session::{CutAxis, CutDraft, Overlays, Session};
use crate::sim::{self, Constraint, Params, MAX_STIFFNESS};
use glam::DVec3;

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
                file_section(ui, state, &mut actions);
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
                    material_section(ui, session);
                    ui.separator();
                    pose_section(ui, session);
                    ui.separator();
                    cut_section(ui, state, session);
                    ui.separator();
                    overlay_section(ui, state, &mut actions);
                    ui.separator();
                    stats_section(ui, state, session);
                }
            });
        });
    actions
}

fn file_section(ui: &mut egui::Ui, state: &mut PanelState, actions: &mut Vec<Action>) {
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

fn material_section(ui: &mut egui::Ui, session: &mut Session) {
    ui.strong("Material");
    let mut preset = session.puppet.rig_file.material.clone();
    egui::ComboBox::from_label("preset")
        .selected_text(preset.as_str())
        .show_ui(ui, |ui| {
            for m in sim::presets() {
                ui.selectable_value(&mut preset, m.name.clone(), m.name.as_str());
            }
            ui.selectable_value(&mut preset, "custom".to_string(), "custom");
        });
    if preset != session.puppet.rig_file.material && !session.set_preset(&preset) {
        session.puppet.rig_file.material = preset;
    }
    let mut p: Params = *session.puppet.sim.params();
    let before = p;
    ui.add(egui::Slider::new(&mut p.damping, 0.0..=1.0).text("C_vd damping"));
    ui.add(egui::Slider::new(&mut p.stiffness, 0.0..=MAX_STIFFNESS).text("D stiffness"));
    ui.add(egui::Slider::new(&mut p.bone_distance, 0.0..=1.0).text("d_B bone distance"));
    ui.add(egui::Slider::new(&mut p.max_length, 1.0..=3.0).text("sl_max max length"));
    ui.add(egui::Slider::new(&mut p.min_length, 0.0..=1.0).text("f_min min length"));
    ui.horizontal(|ui| {
        ui.radio_value(&mut p.constraint, Constraint::Circumsphere, "circumsphere");
        ui.radio_value(
            &mut p.constraint,
            Constraint::SpringReduction,
            "spring reduction",
        );
    });
    if p.constraint == Constraint::SpringReduction {
        ui.add(egui::Slider::new(&mut p.reduction_iterations, 1..=64).text("iterations"));
    }
    if p != before {
        if p.damping != before.damping
            || p.stiffness != before.stiffness
            || p.bone_distance != before.bone_distance
            || p.max_length != before.max_length
        {
            session.puppet.rig_file.material = "custom".into();
        }
        session.set_params(p);
    }
    if session.puppet.sim.params().is_static() {
        ui.small("static material: the surface follows the bones (not integrated)");
    }
    ui.checkbox(&mut session.paused, "pause simulation");
}

fn pose_section(ui: &mut egui::Ui, session: &mut Session) {
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

fn cut_section(ui: &mut egui::Ui, state: &mut PanelState, session: &mut Session) {
    ui.strong("Cuts");
    ui.horizontal(|ui| {
        ui.toggle_value(&mut session.cut_tool.active, "Cut tool");
        for (axis, label) in [
            (CutAxis::X, "X"),
            (CutAxis::Y, "Y"),
            (CutAxis::Z, "Z"),
            (CutAxis::View, "view"),
        ] {
            if ui
                .selectable_value(&mut session.cut_tool.axis, axis, label)
                .clicked()
            {
                if let Some(d) = &mut session.draft {
                    d.normal = match axis {
                        CutAxis::X => DVec3::X,
                        CutAxis::Y => DVec3::Y,
                        CutAxis::Z => DVec3::Z,
                        CutAxis::View => d.normal,
                    };
                }
            }
        }
    });
    if session.cut_tool.active && session.draft.is_none() {
        ui.label("click the model where the plane should go");
    }
    let mut apply = false;
    let mut cancel = false;
    if let Some(d) = &mut session.draft {
        draft_editor(ui, d, session.puppet.mesh.diagonal());
        ui.horizontal(|ui| {
            apply = ui.button("Apply cut").clicked();
            cancel = ui.button("Cancel").clicked();
        });
    }
    if apply {
        match session.apply_draft() {
            Ok(()) => {
                state.message = None;
                session.cut_tool.active = false;
            }
            Err(e) => state.message = Some((e.to_string(), true)),
        }
    }
    if cancel {
        session.draft = None;
        session.cut_tool.active = false;
    }
    let cuts: Vec<String> = session
        .puppet
        .joints
        .cuts()
        .iter()
        .map(|c| c.name.clone())
        .collect();
    for name in cuts {
        ui.horizontal(|ui| {
            let index = session.puppet.joints.find(&name);
            let selected = index.is_some_and(|i| session.selection.contains(&i));
            if ui.selectable_label(selected, name.as_str()).clicked() {
                session.select(index, ui.input(|i| i.modifiers.shift));
            }
            if ui.small_button("remove").clicked() {
                if let Err(e) = session.remove_cut(&name) {
                    state.message = Some((e.to_string(), true));
                }
            }
        });
    }
}

fn draft_editor(ui: &mut egui::Ui, d: &mut CutDraft, size: f64) {
    ui.horizontal(|ui| {
        ui.label("name");
        ui.text_edit_singleline(&mut d.name);
    });
    // Offset along the normal and tilt of the normal, applied incrementally.
    let mut offset = 0.0;
    ui.add(
        egui::Slider::new(&mut offset, -0.05..=0.05)
            .text("move")
            .fixed_decimals(3),
    );
    if offset != 0.0 {
        d.point += d.normal.normalize_or_zero() * offset * size;
    }
    let (mut yaw, mut pitch) = (0.0f64, 0.0f64);
    ui.add(egui::Slider::new(&mut yaw, -5.0..=5.0).text("turn °"));
    ui.add(egui::Slider::new(&mut pitch, -5.0..=5.0).text("tilt °"));
    if yaw != 0.0 || pitch != 0.0 {
        let n = d.normal.normalize_or(DVec3::Y);
        let side = n.any_orthonormal_vector();
        let q = glam::DQuat::from_axis_angle(n.cross(side), yaw.to_radians())
            * glam::DQuat::from_axis_angle(side, pitch.to_radians());
        d.normal = q * n;
    }
    if ui.button("flip side").clicked() {
        d.normal = -d.normal;
    }
    let mut custom = d.pivot.is_some();
    ui.checkbox(
        &mut custom,
        "place the pivot (default: centroid of the nearest skeletal points)",
    );
    match (custom, d.pivot) {
        (false, _) => d.pivot = None,
        (true, None) => d.pivot = Some(d.point),
        (true, Some(pivot)) => {
            let n = d.normal.normalize_or(DVec3::Y);
            let u = n.any_orthonormal_vector();
            let v = n.cross(u);
            let (mut du, mut dv, mut dn) = (0.0f64, 0.0f64, 0.0f64);
            ui.add(
                egui::Slider::new(&mut du, -0.05..=0.05)
                    .text("pivot ←→")
                    .fixed_decimals(3),
            );
            ui.add(
                egui::Slider::new(&mut dv, -0.05..=0.05)
                    .text("pivot ↓↑")
                    .fixed_decimals(3),
            );
            ui.add(
                egui::Slider::new(&mut dn, -0.05..=0.05)
                    .text("pivot along normal")
                    .fixed_decimals(3),
            );
            d.pivot = Some(pivot + (u * du + v * dv + n * dn) * size);
        }
    }
}

fn overlay_section(ui: &mut egui::Ui, state: &mut PanelState, actions: &mut Vec<Action>) {
    ui.strong("Show");
    let o = &mut state.overlays;
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut o.wireframe, "wireframe");
        ui.checkbox(&mut o.skeleton, "skeleton");
        ui.checkbox(&mut o.bone_points, "bone points");
        ui.checkbox(&mut o.bone_springs, "bone springs");
        ui.checkbox(&mut o.cuts, "cut planes");
        ui.checkbox(&mut o.pivots, "pivots");
    });
    if ui.button("Frame model (F)").clicked() {
        actions.push(Action::Frame);
    }
}

fn stats_section(ui: &mut egui::Ui, state: &PanelState, session: &Session) {
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
                if session.paused {
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
    });
    ui.small("drag: turn selection or orbit · right drag: pan · wheel: zoom · F: frame · R: reset pose · Ctrl+Z/Y: undo/redo · W: wireframe · Space: pause");
}
