//! The Cuts section: the cut tool (shape, axis, the draft's plane or size and pivot,
//! apply) and the list of applied cuts (band, shared pivot, remove).

use super::{Action, PanelState};
use crate::joints::Shape;
use crate::session::{CutAxis, CutDraft, Session, ShapeKind};
use glam::DVec3;

pub(super) fn cut_section(
    ui: &mut egui::Ui,
    state: &mut PanelState,
    session: &mut Session,
    actions: &mut Vec<Action>,
) {
    ui.strong("Cuts");
    if ui
        .button("Suggest joints")
        .on_hover_text("cut where the limbs, neck, tail, ears and fingers narrow (replaces the cuts; undo brings them back)")
        .clicked()
    {
        actions.push(Action::SuggestJoints);
    }
    ui.horizontal(|ui| {
        if ui
            .selectable_label(session.cut_tool.active, "Cut tool (C)")
            .clicked()
        {
            session.set_cut_tool(!session.cut_tool.active);
        }
        if ui
            .selectable_label(session.cut_tool.move_pivots, "Move pivots (P)")
            .on_hover_text("drag a cut's pivot to move it on the cut's plane (with Shift: anywhere, facing the view); Ctrl+Z puts it back")
            .clicked()
        {
            session.set_move_pivots(!session.cut_tool.move_pivots);
        }
        for (axis, label) in [
            (CutAxis::X, "X"),
            (CutAxis::Y, "Y"),
            (CutAxis::Z, "Z"),
            (CutAxis::View, "view"),
        ] {
            if ui
                .selectable_label(session.cut_tool.axis == axis, label)
                .clicked()
            {
                session.set_cut_axis(axis);
            }
        }
    });
    ui.horizontal(|ui| {
        ui.label("shape");
        for (kind, label, hint) in [
            (
                ShapeKind::Plane,
                "plane",
                "the side the normal points to (a limb)",
            ),
            (
                ShapeKind::Sphere,
                "sphere",
                "what is inside (a tail tip, an ear, a nose)",
            ),
            (
                ShapeKind::Box,
                "box",
                "what is inside; the axis button sets its third axis",
            ),
        ] {
            if ui
                .selectable_label(session.cut_tool.shape == kind, label)
                .on_hover_text(hint)
                .clicked()
            {
                session.set_cut_shape(kind);
            }
        }
    });
    if session.cut_tool.active && session.draft.is_none() {
        ui.label("click the model where the cut should go");
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
                session.set_cut_tool(false);
            }
            Err(e) => state.message = Some((e.to_string(), true)),
        }
    }
    if cancel {
        session.cancel_draft();
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
            let cut = session.puppet.joints.cuts().iter().find(|c| c.name == name);
            if let Some(mut shared) = cut.map(|c| c.shared_pivot) {
                // The section it splits now (a later cut may have adopted it).
                let sections = session.puppet.joints.sections();
                let parent = index
                    .and_then(|k| sections[k].parent)
                    .map_or("", |p| sections[p].name.as_str())
                    .to_string();
                if ui
                    .checkbox(&mut shared, "shared pivot")
                    .on_hover_text(format!(
                        "'{parent}' turns about this cut's pivot too (both jaws of a mouth \
                         about one hinge); Move pivots (P) to drag it"
                    ))
                    .changed()
                {
                    session.set_shared_pivot(&name, shared);
                }
            }
            let joints = &session.puppet.joints;
            let k = joints.cuts().iter().position(|c| c.name == name);
            let kind = match k
                .and_then(|k| joints.bands().get(k))
                .and_then(Option::as_ref)
            {
                Some(b) if b.arc => {
                    "\nBends as an arc (two limbs meet): the part also moves out along the bend"
                }
                Some(_) => "\nTurns about the pivot (a limb on a trunk, or a shared hinge)",
                None => "",
            };
            let cut = k.map(|k| &joints.cuts()[k]);
            if let Some(mut band) = cut.map(|c| c.band_factor()) {
                let r = ui
                    .add(
                        egui::DragValue::new(&mut band)
                            .range(0.0..=crate::joints::MAX_BAND)
                            .speed(0.02)
                            .prefix("band "),
                    )
                    .on_hover_text(format!(
                        "joint band half-width in local medial radii: the bone points \
                         this near the cut turn by part of the angle (0: a hinge){kind}"
                    ));
                if r.changed() {
                    let first = r.drag_started() || !r.dragged();
                    session.set_band(&name, band, first);
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
    match &mut d.shape {
        Shape::Plane | Shape::Skin => {}
        Shape::Sphere { radius } => {
            ui.add(
                egui::DragValue::new(radius)
                    .range(size * 1e-4..=size)
                    .speed(size * 0.002)
                    .prefix("radius "),
            );
        }
        Shape::Box { size: extent } => {
            ui.horizontal(|ui| {
                ui.label("size");
                for v in [&mut extent.x, &mut extent.y, &mut extent.z] {
                    ui.add(
                        egui::DragValue::new(v)
                            .range(size * 1e-4..=size * 2.0)
                            .speed(size * 0.002),
                    );
                }
            });
        }
    }
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
    ui.checkbox(
        &mut d.connected,
        "only the piece clicked (not everything beyond the plane)",
    );
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
