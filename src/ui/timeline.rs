//! The timeline at the bottom, while an animation is loaded: play/pause, restart, scrub,
//! loop, the time. Space plays, ←/→ step a frame, Home/End jump (`app::actions`).

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
            let mut at = t.min(duration.max(t));
            let end = duration.max(t).max(1e-3);
            let slider = ui.add(
                egui::Slider::new(&mut at, 0.0..=end)
                    .show_value(false)
                    .text(format!("{t:.2} / {duration:.2} s")),
            );
            if slider.changed() {
                session.scrub(at);
            }
            let mut looping = session
                .playback
                .as_ref()
                .is_some_and(|p| p.animation.looping);
            if ui.checkbox(&mut looping, "loop").changed() {
                session.set_looping(looping);
            }
        });
    });
}
