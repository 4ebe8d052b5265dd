//! *Export animation*: the frames and format to write, then the export's progress with a
//! Cancel (it runs on its own thread; the window keeps playing).

use super::{Action, FilePurpose};
use crate::session::Session;

pub(super) fn export_section(ui: &mut egui::Ui, session: &mut Session, actions: &mut Vec<Action>) {
    let Some(range) = session.export_range() else {
        return;
    };
    if let Some(job) = session.export_job() {
        let (fraction, frames) = (job.progress(), job.frames);
        let name = super::file_name(&job.path);
        ui.horizontal(|ui| {
            ui.add(
                egui::ProgressBar::new(fraction as f32)
                    .desired_width(180.0)
                    .text(format!("{name}: {frames} frames"))
                    .show_percentage(),
            );
            if ui.button("Cancel").clicked() {
                session.cancel_export();
            }
        });
        return;
    }
    ui.collapsing("Export animation", |ui| {
        // The animation's last frame at the chosen rate.
        let whole = session.playback.as_ref().map_or(range.last, |p| {
            crate::puppet::bake::FrameRange::of_duration(p.animation.duration, range.fps).last
        });
        let s = &mut session.export_settings;
        ui.horizontal(|ui| {
            ui.label("frames");
            ui.add(egui::DragValue::new(&mut s.first).range(1..=whole.max(1)));
            ui.label("to");
            let mut last = if s.last == 0 { whole } else { s.last };
            if ui
                .add(egui::DragValue::new(&mut last).range(s.first..=whole.max(s.first)))
                .changed()
            {
                s.last = if last >= whole { 0 } else { last };
            }
            ui.label("every");
            ui.add(egui::DragValue::new(&mut s.step).range(1..=1000));
        });
        ui.horizontal(|ui| {
            ui.add(
                egui::DragValue::new(&mut s.fps)
                    .range(1.0..=240.0)
                    .suffix(" fps"),
            );
            ui.checkbox(&mut s.quantize, "16-bit .glb")
                .on_hover_text("KHR_mesh_quantization: about two thirds of the size");
        });
        if ui
            .button("Export animation…")
            .on_hover_text(
                ".glb (shape keys, game engines), .pc2 + .obj (Mesh Cache), a folder of OBJ files, \
                 or a video (.mp4: the view as the window shows it)",
            )
            .clicked()
        {
            actions.push(Action::Browse(FilePurpose::ExportAnimation));
        }
    });
}
