//! The Material section: Table 1's presets and a slider per parameter.

use crate::session::Session;
use crate::sim::{self, Constraint, Params, MAX_STIFFENING, MAX_STIFFNESS};

pub(super) fn material_section(ui: &mut egui::Ui, session: &mut Session) {
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
    ui.add(egui::Slider::new(&mut p.stiffening, 0..=MAX_STIFFENING).text("stiffening"))
        .on_hover_text("bone springs soft near rest and hard far from it (0: Hooke)");
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
            || p.min_length != before.min_length
            || p.stiffening != before.stiffening
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
