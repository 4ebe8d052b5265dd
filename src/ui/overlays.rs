//! The Show section: which overlays are drawn.

use super::{Action, PanelState};
use crate::session::Lighting;

pub(super) fn overlay_section(
    ui: &mut egui::Ui,
    state: &mut PanelState,
    actions: &mut Vec<Action>,
) {
    ui.strong("Show");
    let o = &mut state.overlays;
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut o.wireframe, "wireframe");
        ui.checkbox(&mut o.skeleton, "skeleton");
        ui.checkbox(&mut o.bone_points, "bone points");
        ui.checkbox(&mut o.bone_springs, "bone springs");
        ui.checkbox(&mut o.cuts, "cut planes");
        ui.checkbox(&mut o.pivots, "pivots");
        ui.checkbox(&mut o.repairs, "repairs")
            .on_hover_text("filled holes (orange edges) and split vertices (magenta)");
        ui.checkbox(&mut o.ground, "ground")
            .on_hover_text("the ground under the puppet, its soft shadow and a faint grid");
        ui.checkbox(&mut o.occlusion, "creases").on_hover_text(
            "shade creases (armpits, a mouth, a bent joint) by how much of the sky the body \
             hides there",
        );
    });
    if let Some(chosen) = &mut state.anti_aliasing {
        ui.horizontal(|ui| {
            ui.label("anti-aliasing");
            egui::ComboBox::from_id_salt("anti-aliasing")
                .selected_text(chosen.label())
                .show_ui(ui, |ui| {
                    for &a in &state.anti_aliasing_offered {
                        ui.selectable_value(chosen, a, a.label());
                    }
                })
                .response
                .on_hover_text(
                    "how edges are smoothed while the puppet or the camera moves. 4 samples: \
                     the best, but two to three times the frame on a software renderer; \
                     smoothed (FXAA): a pass over the puppet's edges, the default there; off \
                     while moving: the fastest. Whichever, a still view is drawn once more \
                     with 4 samples as soon as it stops",
                );
        });
    }
    ui.horizontal(|ui| {
        ui.label("lighting");
        let lighting = &mut state.overlays.lighting;
        egui::ComboBox::from_id_salt("lighting")
            .selected_text(lighting.label())
            .show_ui(ui, |ui| {
                for &l in <Lighting as clap::ValueEnum>::value_variants() {
                    ui.selectable_value(lighting, l, l.label());
                }
            })
            .response
            .on_hover_text(
                "studio: lights placed around the puppet; a matcap: light fixed to the \
                 camera, so a shape reads the same from every side (clay: matte; jelly: \
                 glossy, its edges glowing in the part's colour)",
            );
    });
    if ui.button("Frame model (F)").clicked() {
        actions.push(Action::Frame);
    }
}
