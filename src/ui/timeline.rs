//! The timeline at the bottom, while an animation is loaded: play/pause, restart, loop (the
//! whole animation, or a range of it),
//! the time and frame at the timeline's rate, and a ruler with the playhead and the keys
//! of the selected sections as ticks (click or drag on it to scrub). Space plays, ←/→ step
//! a frame, Home/End jump (`app::actions`).

use crate::session::Session;

pub(super) fn timeline(ui: &mut egui::Ui, session: &mut Session) {
    let Some((t, duration)) = session.playback_time() else {
        return;
    };
    egui::Panel::bottom("timeline").show(ui, |ui| {
        ui.horizontal(|ui| {
            let playing = session.is_playing();
            if ui
                .button(if playing { "Pause" } else { "Play" })
                .on_hover_text("Space")
                .clicked()
            {
                session.toggle_play();
            }
            if ui.button("Restart").on_hover_text("Home").clicked() {
                session.restart();
            }
            let mut looping = session
                .playback
                .as_ref()
                .is_some_and(|p| p.animation.looping);
            if ui.checkbox(&mut looping, "loop").changed() {
                session.set_looping(looping);
            }
            let range = session.playback.as_ref().and_then(|p| p.loop_range);
            let mut ranged = range.is_some();
            if ui
                .checkbox(&mut ranged, "range")
                .on_hover_text("play only a part, over and over")
                .changed()
            {
                session.set_loop_range(ranged.then_some((0.0, duration.max(1e-3))));
            }
            if let Some((mut from, mut to)) = range {
                let a = ui.add(
                    egui::DragValue::new(&mut from)
                        .range(0.0..=duration)
                        .speed(0.01)
                        .suffix(" s"),
                );
                let b = ui.add(
                    egui::DragValue::new(&mut to)
                        .range(0.0..=duration)
                        .speed(0.01)
                        .suffix(" s"),
                );
                if a.changed() || b.changed() {
                    session.set_loop_range(Some((from, to)));
                }
            }
            let fps = &mut session.export_settings.fps;
            ui.add(egui::DragValue::new(fps).range(1.0..=240.0).suffix(" fps"))
                .on_hover_text("the timeline's frame rate (←/→ step a frame; Export uses it)");
            let frame = (t * *fps + 1e-6).floor() as u64;
            ui.monospace(format!("{t:6.2} / {duration:.2} s   frame {frame}"));
        });
        ruler(ui, session, t, duration);
    });
}

/// The ruler: the animation's length across, the playhead, a tick per key of the selected
/// sections; a click or a drag scrubs.
fn ruler(ui: &mut egui::Ui, session: &mut Session, t: f64, duration: f64) {
    let width = ui.available_width();
    let (rect, response) =
        ui.allocate_exact_size(egui::vec2(width, 18.0), egui::Sense::click_and_drag());
    let end = duration.max(t).max(1e-3);
    let x_of = |time: f64| rect.left() + (time / end).clamp(0.0, 1.0) as f32 * rect.width();
    let painter = ui.painter_at(rect);
    let visuals = ui.visuals();
    painter.rect_filled(rect, 2.0, visuals.extreme_bg_color);
    // The loop range.
    if let Some((from, to)) = session.playback.as_ref().and_then(|p| p.loop_range) {
        let band = egui::Rect::from_x_y_ranges(x_of(from)..=x_of(to), rect.y_range());
        painter.rect_filled(band, 0.0, visuals.selection.bg_fill.gamma_multiply(0.5));
    }
    // Whole seconds.
    for s in 0..=(end.floor() as usize).min(10_000) {
        let x = x_of(s as f64);
        painter.line_segment(
            [
                egui::pos2(x, rect.bottom() - 5.0),
                egui::pos2(x, rect.bottom()),
            ],
            egui::Stroke::new(1.0, visuals.weak_text_color()),
        );
    }
    // Keys of the selected sections.
    if let Some(p) = &session.playback {
        let sections = session.puppet.joints.sections();
        let key_colour = egui::Color32::from_rgb(255, 190, 80);
        for &s in &session.selection {
            let Some(name) = sections.get(s).map(|x| &x.name) else {
                continue;
            };
            for track in p.animation.track.iter().filter(|tr| &tr.section == name) {
                for key in &track.key {
                    let x = x_of(key.time);
                    painter.line_segment(
                        [
                            egui::pos2(x, rect.top() + 3.0),
                            egui::pos2(x, rect.bottom() - 3.0),
                        ],
                        egui::Stroke::new(2.0, key_colour),
                    );
                }
            }
        }
    }
    let x = x_of(t);
    painter.line_segment(
        [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
        egui::Stroke::new(2.0, visuals.strong_text_color()),
    );
    let response =
        response.on_hover_text("click or drag to scrub; ticks: keys of the selected sections");
    if response.clicked() || response.dragged() {
        if let Some(pos) = response.interact_pointer_pos() {
            let at = ((pos.x - rect.left()) / rect.width().max(1.0)).clamp(0.0, 1.0) as f64 * end;
            if (at - t).abs() > 1e-9 {
                session.scrub(at);
            }
        }
    }
}
