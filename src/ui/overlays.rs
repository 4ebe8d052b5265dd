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
        if let Some(on) = &mut state.anti_aliasing {
            ui.checkbox(on, "anti-aliasing").on_hover_text(
                "smooth edges (4 samples a pixel) while the puppet moves too; off by default \
                 on a software renderer, where it costs two to three times the frame. Off, \
                 a still view is smoothed once it stops",
            );
        }
    });
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
