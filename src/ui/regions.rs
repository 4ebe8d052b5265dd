//! The Regions section: other materials on parts of the surface (paper §5) and pinning,
//! assigned by section or painted with the brush.

use crate::puppet::{Paint, Region};
use crate::session::Session;
use crate::sim::Material;

/// Adds the selected sections' names to `paint` (once each).
fn add_selected(paint: &mut Paint, session: &Session) {
    for &k in &session.selection {
        if let Some(s) = session.puppet.joints.sections().get(k) {
            if !paint.sections.contains(&s.name) {
                paint.sections.push(s.name.clone());
            }
        }
    }
}

/// What a paint covers, in words.
fn describe(paint: &Paint) -> String {
    let painted = paint.weights.iter().filter(|&&w| w > 0.0).count();
    let mut parts: Vec<String> = paint.sections.clone();
    parts.extend(paint.groups.iter().map(|g| format!("group {g}")));
    if painted > 0 {
        parts.push(format!("{painted} painted vertices"));
    }
    if parts.is_empty() {
        "nowhere yet".into()
    } else {
        parts.join(" + ")
    }
}

pub(super) fn regions_section(ui: &mut egui::Ui, session: &mut Session) {
    ui.strong("Regions");
    let mut regions = session.puppet.rig_file.regions.clone();
    let mut pin = session.puppet.rig_file.pin.clone();
    let before = (regions.clone(), pin.clone());
    let mut remove = None;
    let mut preset_chosen = None;
    for (k, r) in regions.iter_mut().enumerate() {
        ui.horizontal(|ui| {
            let mut painting = session.paint_tool.active && session.paint_tool.target == Some(k);
            if ui
                .toggle_value(&mut painting, r.name.as_str())
                .on_hover_text("paint this region with the brush")
                .changed()
            {
                session.set_brush(Some(k), painting);
            }
            if let Some(name) = super::material::preset_menu(ui, ("region material", k), &r.preset)
            {
                preset_chosen = Some((k, name));
            }
            if ui
                .small_button("+ selected")
                .on_hover_text("add the selected sections to this region")
                .clicked()
            {
                add_selected(&mut r.paint, session);
            }
            if ui.small_button("clear").clicked() {
                r.paint = Paint::default();
            }
            if ui.small_button("remove").clicked() {
                remove = Some(k);
            }
        });
        ui.horizontal(|ui| {
            ui.small(describe(&r.paint));
            super::material::stiffening_slider(ui, &mut r.material.stiffening);
        });
    }
    if let Some(k) = remove {
        regions.remove(k);
        session.set_brush(None, false);
    }
    if ui
        .button("New region")
        .on_hover_text("another material (water) on the selected sections; paint to add more")
        .clicked()
    {
        let mut region = Region {
            name: format!("region {}", regions.len() + 1),
            preset: "water".into(),
            material: Material::preset("water").unwrap_or_default(),
            paint: Paint::default(),
        };
        add_selected(&mut region.paint, session);
        regions.push(region);
    }
    let groups = &session.puppet.groups;
    if !groups.is_empty() {
        ui.horizontal_wrapped(|ui| {
            ui.small("the file's groups:");
            for name in &groups.names {
                let taken = regions.iter().any(|r| r.paint.groups.contains(name));
                if ui
                    .add_enabled(!taken, egui::Button::new(name.as_str()).small())
                    .on_hover_text("a region of this group's faces, in the base material until you pick another")
                    .clicked()
                {
                    regions.push(Region {
                        name: name.clone(),
                        preset: session.puppet.rig_file.preset.clone(),
                        material: session.puppet.sim.params().material,
                        paint: Paint {
                            groups: vec![name.clone()],
                            ..Paint::default()
                        },
                    });
                }
            }
        });
    }
    ui.horizontal(|ui| {
        let mut painting = session.paint_tool.active && session.paint_tool.target.is_none();
        if ui
            .toggle_value(&mut painting, "pin")
            .on_hover_text("paint where the surface is glued to its bones")
            .changed()
        {
            session.set_brush(None, painting);
        }
        if ui.small_button("+ selected").clicked() {
            add_selected(&mut pin, session);
        }
        if ui.small_button("clear").clicked() {
            pin = Paint::default();
        }
        ui.small(describe(&pin));
    });
    if session.paint_tool.active {
        let size = session.puppet.mesh.diagonal() as f32;
        let tool = &mut session.paint_tool;
        ui.add(
            egui::Slider::new(&mut tool.radius, 0.005 * size..=0.5 * size)
                .logarithmic(true)
                .text("brush radius"),
        );
        ui.add(egui::Slider::new(&mut tool.falloff, 0.0..=1.0).text("falloff"));
        ui.checkbox(&mut tool.erase, "erase");
        ui.small("drag on the model to paint (B toggles the brush)");
    }
    if (regions.clone(), pin.clone()) != before {
        session.set_regions(regions, pin);
    }
    if let Some((k, name)) = preset_chosen {
        session.set_region_preset(k, &name);
    }
}
