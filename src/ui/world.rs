//! The World section: gravity (strength and direction), the floor, and collision between
//! sections.

use crate::session::Session;
use crate::sim::params::{MAX_FLESH, MAX_MARGIN};
use crate::sim::{Params, MAX_GRAVITY};

/// The six axis directions by name.
const AXES: [(&str, [f32; 3]); 6] = [
    ("−y", [0.0, -1.0, 0.0]),
    ("+y", [0.0, 1.0, 0.0]),
    ("−x", [-1.0, 0.0, 0.0]),
    ("+x", [1.0, 0.0, 0.0]),
    ("−z", [0.0, 0.0, -1.0]),
    ("+z", [0.0, 0.0, 1.0]),
];

/// Gravity directions offered by name, down (against the puppet's `up`) first; anything
/// else shows as "custom".
pub(super) fn directions(up: glam::Vec3) -> Vec<(String, [f32; 3])> {
    let name = |v: glam::Vec3| {
        AXES.iter()
            .find(|(_, a)| glam::Vec3::from(*a).distance(v) < 1e-4)
            .map_or("?", |(n, _)| n)
    };
    let mut out = vec![
        (format!("down ({})", name(-up)), (-up).to_array()),
        (format!("up ({})", name(up)), up.to_array()),
    ];
    out.extend(
        AXES.iter()
            .filter(|(_, a)| glam::Vec3::from(*a).distance(up) > 1e-4)
            .filter(|(_, a)| glam::Vec3::from(*a).distance(-up) > 1e-4)
            .map(|(n, a)| (n.to_string(), *a)),
    );
    out
}

/// Strength and unit direction of a gravity vector (down, against `up`, when it is zero).
pub(super) fn split(g: [f32; 3], up: glam::Vec3) -> (f32, [f32; 3]) {
    let v = glam::Vec3::from(g);
    let s = v.length();
    if s > 0.0 && s.is_finite() {
        (s, (v / s).to_array())
    } else {
        (0.0, (-up).to_array())
    }
}

pub(super) fn world_section(ui: &mut egui::Ui, session: &mut Session) {
    ui.strong("World");
    let mut w = session.puppet.sim.params().world;
    let before = w;
    let up = session.puppet.sim.up();
    let named = directions(up.vector());
    let (mut strength, mut direction) = split(w.gravity, up.vector());
    ui.add(
        egui::Slider::new(&mut strength, 0.0..=MAX_GRAVITY)
            .text("gravity (g)")
            .logarithmic(true)
            .smallest_positive(0.01),
    )
    .on_hover_text("9.81 m/s² on a puppet one metre across, whatever the mesh's units");
    let name = named
        .iter()
        .find(|(_, d)| glam::Vec3::from(*d).distance(direction.into()) < 1e-4)
        .map_or("custom", |(n, _)| n.as_str());
    egui::ComboBox::from_label("direction")
        .selected_text(name)
        .show_ui(ui, |ui| {
            for (n, d) in &named {
                ui.selectable_value(&mut direction, *d, n.as_str());
            }
        });
    w.gravity = direction.map(|c| c * strength);
    let up_name = directions(up.vector())
        .into_iter()
        .nth(1)
        .map(|(n, _)| n)
        .unwrap_or_default();
    ui.checkbox(&mut w.floor, "floor").on_hover_text(format!(
        "a ground plane the surface cannot pass, across the puppet's {up_name}"
    ));
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
