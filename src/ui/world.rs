//! The World section: gravity (strength and direction), the floor, and collision between
//! sections.

use crate::session::Session;
use crate::sim::params::{MAX_FLESH, MAX_MARGIN};
use crate::sim::{Params, MAX_GRAVITY};

/// Gravity directions offered by name; anything else shows as "custom".
const DIRECTIONS: [(&str, [f32; 3]); 6] = [
    ("down (−y)", [0.0, -1.0, 0.0]),
    ("up (+y)", [0.0, 1.0, 0.0]),
    ("−x", [-1.0, 0.0, 0.0]),
    ("+x", [1.0, 0.0, 0.0]),
    ("−z", [0.0, 0.0, -1.0]),
    ("+z", [0.0, 0.0, 1.0]),
];

/// Strength and unit direction of a gravity vector (down when it is zero).
pub(super) fn split(g: [f32; 3]) -> (f32, [f32; 3]) {
    let v = glam::Vec3::from(g);
    let s = v.length();
    if s > 0.0 && s.is_finite() {
        (s, (v / s).to_array())
    } else {
        (0.0, DIRECTIONS[0].1)
    }
}

pub(super) fn world_section(ui: &mut egui::Ui, session: &mut Session) {
    ui.strong("World");
    let mut w = session.puppet.sim.params().world;
    let before = w;
    let (mut strength, mut direction) = split(w.gravity);
    ui.add(
        egui::Slider::new(&mut strength, 0.0..=MAX_GRAVITY)
            .text("gravity (g)")
            .logarithmic(true)
            .smallest_positive(0.01),
    )
    .on_hover_text("9.81 m/s² on a puppet one metre across, whatever the mesh's units");
    let name = DIRECTIONS
        .iter()
        .find(|(_, d)| glam::Vec3::from(*d).distance(direction.into()) < 1e-4)
        .map_or("custom", |(n, _)| n);
    egui::ComboBox::from_label("direction")
        .selected_text(name)
        .show_ui(ui, |ui| {
            for (n, d) in DIRECTIONS {
                ui.selectable_value(&mut direction, d, n);
            }
        });
    w.gravity = direction.map(|c| c * strength);
    ui.checkbox(&mut w.floor, "floor")
        .on_hover_text("a ground plane the surface cannot pass (up is +y)");
    if w.floor {
        let size = session.puppet.mesh.diagonal() as f32;
        ui.add(
            egui::Slider::new(&mut w.floor_height, -0.5 * size..=0.5 * size)
                .text("height above the lowest point"),
        );
        ui.add(egui::Slider::new(&mut w.floor_friction, 0.0..=1.0).text("friction"));
    }
    ui.checkbox(&mut w.collision, "collision")
        .on_hover_text("parts stop where they meet another part of the body: a limb dragged into it, a finger into the palm");
    if w.collision {
        let mut percent = w.collision_margin * 100.0;
        ui.add(
            egui::Slider::new(&mut percent, 0.0..=MAX_MARGIN * 100.0).text("margin (% of size)"),
        )
        .on_hover_text("the gap kept between touching parts");
        w.collision_margin = percent / 100.0;
        ui.add(egui::Slider::new(&mut w.flesh, 0.0..=MAX_FLESH).text("flesh gives"))
            .on_hover_text("how far a part pressed into the body dents it, as a share of its thickness there (0: hard)");
        if !w.floor {
            ui.add(egui::Slider::new(&mut w.floor_friction, 0.0..=1.0).text("friction"));
        }
    }
    if w != before {
        let params = Params {
            world: w,
            ..*session.puppet.sim.params()
        };
        session.set_params(params);
    }
}
