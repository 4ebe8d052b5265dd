//! The Material section: Table 1's presets and a slider per material parameter, then the
//! solver's constraint.

use crate::session::Session;
use crate::sim::{self, Constraint, Material, MAX_STIFFENING, MAX_STIFFNESS};

/// The preset menu: Table 1's names and "custom"; the name chosen, if it changed.
pub(super) fn preset_menu(
    ui: &mut egui::Ui,
    id: impl std::hash::Hash + std::fmt::Debug,
    now: &str,
) -> Option<String> {
    let mut preset = now.to_string();
    egui::ComboBox::from_id_salt(id)
        .selected_text(preset.as_str())
        .width(90.0)
        .show_ui(ui, |ui| {
            for m in sim::presets() {
                ui.selectable_value(&mut preset, m.name.clone(), m.name.as_str());
            }
            ui.selectable_value(&mut preset, "custom".to_string(), "custom");
        });
    (preset != now).then_some(preset)
}

/// A slider per field of a material.
pub(super) fn material_sliders(ui: &mut egui::Ui, m: &mut Material) {
    ui.add(egui::Slider::new(&mut m.damping, 0.0..=1.0).text("C_vd damping"));
    ui.add(egui::Slider::new(&mut m.stiffness, 0.0..=MAX_STIFFNESS).text("D stiffness"));
    ui.add(egui::Slider::new(&mut m.bone_distance, 0.0..=1.0).text("d_B bone distance"));
    ui.add(egui::Slider::new(&mut m.max_length, 1.0..=3.0).text("sl_max max length"));
    ui.add(egui::Slider::new(&mut m.min_length, 0.0..=1.0).text("f_min min length"));
    stiffening_slider(ui, &mut m.stiffening);
}

/// The stiffening exponent's slider.
pub(super) fn stiffening_slider(ui: &mut egui::Ui, stiffening: &mut u32) {
    ui.add(egui::Slider::new(stiffening, 0..=MAX_STIFFENING).text("stiffening"))
        .on_hover_text("bone springs soft near rest and hard far from it (0: Hooke)");
}

pub(super) fn material_section(ui: &mut egui::Ui, session: &mut Session) {
    ui.strong("Material");
    ui.horizontal(|ui| {
        if let Some(name) = preset_menu(ui, "base material", &session.puppet.rig_file.preset) {
            session.set_preset(&name);
        }
        ui.label("preset");
    });
    let mut material = session.puppet.sim.params().material;
    let before = material;
    material_sliders(ui, &mut material);
    if material != before {
        session.set_material(material);
    }
    let mut solver = session.puppet.sim.params().solver;
    let before = solver;
    ui.horizontal(|ui| {
        ui.radio_value(
            &mut solver.constraint,
            Constraint::Circumsphere,
            "circumsphere",
        );
        ui.radio_value(
            &mut solver.constraint,
            Constraint::SpringReduction,
            "spring reduction",
        );
    });
    if solver.constraint == Constraint::SpringReduction {
        ui.add(egui::Slider::new(&mut solver.reduction_iterations, 1..=64).text("iterations"));
    }
    if solver != before {
        let params = sim::Params {
            solver,
            ..*session.puppet.sim.params()
        };
        session.set_params(params);
    }
    if session.puppet.sim.params().is_static() {
        ui.small("static material: the surface follows the bones (not integrated)");
    }
    let mut paused = session.is_paused();
    if ui.checkbox(&mut paused, "pause simulation").changed() {
        session.set_paused(paused);
    }
}
