//! One frame: poll the loader, step the simulation for the time that passed, run the
//! panels, upload what changed and draw the scene and the panels.

use super::{still, Report, WindowState};
use crate::render::{self, AntiAliasing};
use crate::session::loader::Status;
use crate::session::Session;
use anyhow::{anyhow, Result};
use std::time::{Duration, Instant};

/// What the event loop does after a frame.
pub(super) enum Next {
    /// Keep running.
    Continue,
    /// The screenshot was taken: exit with its report.
    Exit(Option<Box<Report>>),
}

impl WindowState {
    /// Draws one frame.
    pub fn redraw(&mut self) -> Result<Next> {
        let now = Instant::now();
        let seconds = (now - self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        self.poll_loader();
        self.poll_dialog();
        self.drive_test();
        let mut steps = 0;
        if let Some(s) = &mut self.session {
            if let Some(live) = &mut self.live {
                let view = (self.camera.target - self.camera.eye()).as_dvec3();
                if let Some(message) = live.pump(s, view) {
                    self.panel.message = Some(message);
                }
                self.panel.live = Some(live.counts());
            }
            steps = s.advance(seconds, 8);
            if let Some(said) = s.poll_export() {
                self.panel.message = Some(match said {
                    Ok(m) => (m, false),
                    Err(m) => (m, true),
                });
            }
        }
        self.meter_frame(steps);

        let raw = self.egui.state.take_egui_input(&self.window);
        let panel = &mut self.panel;
        let session = &mut self.session;
        let mut actions = Vec::new();
        let output = self.egui.ctx.run_ui(raw, |ui| {
            actions = crate::ui::side_panel(ui, panel, session.as_mut());
        });
        self.egui
            .state
            .handle_platform_output(&self.window, output.platform_output);
        for a in actions {
            self.act(a);
        }
        if let Some(vo) = output.viewport_output.get(&egui::ViewportId::ROOT) {
            if vo.repaint_delay.is_zero() {
                self.window.request_redraw();
            } else if vo.repaint_delay < Duration::from_secs(3600) {
                self.repaint_at = Some(Instant::now() + vo.repaint_delay);
            }
        }
        let primitives = self
            .egui
            .ctx
            .tessellate(output.shapes, output.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: output.pixels_per_point,
        };
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                self.egui
                    .renderer
                    .update_texture(&self.gpu.device, &self.gpu.queue, *id, delta);
            }
        }

        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => Some(f),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.gpu.device, &self.config);
                self.window.request_redraw();
                None
            }
            _ => None,
        };
        let aspect = self.config.width as f32 / self.config.height.max(1) as f32;
        // Another anti-aliasing chosen in the panel: a renderer for it (it uploads
        // everything again).
        if let Some(chosen) = self.panel.anti_aliasing {
            if chosen != AntiAliasing::of(&self.scene) {
                let format = self.config.format.add_srgb_suffix();
                self.scene = chosen.renderer(&self.gpu, format);
                self.settings.anti_aliasing = Some(chosen);
                self.settings.save();
            }
        }
        // Another lighting picked in the panel: remembered for the next run.
        if self.panel.overlays.lighting != self.lighting {
            self.lighting = self.panel.overlays.lighting;
            self.settings.lighting = Some(self.lighting);
            self.settings.save();
        }
        self.still_frame = false;
        if let Some(s) = &self.session {
            let view = s.view(self.panel.overlays);
            let size = [self.config.width, self.config.height];
            let key = still::Key::of(&view, &self.camera, self.panel.overlays, size);
            // The still frame: where the window draws with fewer samples than it could,
            // once nothing moves and the view is what it was at the frame before.
            let at_rest = self.scene.samples() < render::scene::MSAA
                && self.can_msaa
                && self.copies
                && !s.is_running()
                && !s.is_playing()
                && !s.is_recording()
                && self.loader.is_none()
                && self.pointer.drag == crate::session::pointer::Drag::None;
            if at_rest && self.last_key == Some(key) {
                let format = self.config.format;
                let still = self
                    .still
                    .get_or_insert_with(|| still::Still::new(&self.gpu, format));
                still.draw(&self.gpu, &view, &self.camera, key, format);
                self.still_frame = true;
            } else {
                self.scene.prepare(&self.gpu, &view, &self.camera, aspect);
                if at_rest {
                    // Drawn again once it stayed so.
                    let at = Instant::now() + still::STILL_AFTER;
                    self.repaint_at = Some(self.repaint_at.map_or(at, |r| r.min(at)));
                }
            }
            self.last_key = Some(key);
        }
        let take_shot = self.hooks.exit_after.is_some_and(|n| self.frames + 1 >= n)
            && self.session.is_some()
            && self.hooks.drive.is_none();
        if let Some(frame) = frame {
            self.draw(&frame.texture, &primitives, &screen);
            self.gpu.queue.present(frame);
        }
        let mut next = Next::Continue;
        if take_shot {
            if let Some(path) = self.hooks.screenshot.clone() {
                let image = self.capture(&primitives, &screen)?;
                image
                    .save_png(&path)
                    .map_err(|e| anyhow!("{}: cannot write: {e}", path.display()))?;
                next = Next::Exit(Some(Box::new(self.report(Some(&path)))));
            }
        }
        for id in &output.textures_delta.free {
            self.egui.renderer.free_texture(id);
        }
        if self.session.is_some() && self.loader.is_none() {
            self.frames += 1;
        }
        // The first turn of a section ends the first-run hint for good.
        if self.panel.hint && self.pointer.drag == crate::session::pointer::Drag::Rotate {
            let turned = self
                .session
                .as_ref()
                .is_some_and(|s| s.local.iter().any(|l| l.rotation != glam::DQuat::IDENTITY));
            if turned {
                self.panel.hint = false;
                self.settings.hint_done = true;
                self.settings.save();
            }
        }
        // While an animation plays or a take records the puppet never settles: report
        // every frame then.
        let quiet = !self.session.as_ref().is_some_and(Session::is_running);
        let playing = self
            .session
            .as_ref()
            .is_some_and(|s| s.is_playing() || s.is_recording());
        if self.loader.is_none() && (quiet || playing) {
            self.write_report();
        }
        Ok(next)
    }

    /// Takes the file dialog's answer, when there is one.
    fn poll_dialog(&mut self) {
        let Some(dialog) = &mut self.dialog else {
            return;
        };
        if let Some(answer) = dialog.poll() {
            let purpose = dialog.purpose;
            self.dialog = None;
            if let Some(path) = answer {
                self.use_file(purpose, path);
            }
        }
    }

    /// Takes the loader's progress, or its puppet when it is done (the current puppet
    /// stays when loading failed).
    fn poll_loader(&mut self) {
        let Some(loader) = &mut self.loader else {
            self.panel.loading = None;
            return;
        };
        match loader.poll() {
            Status::Working(stage, fraction) => {
                self.panel.loading = Some((stage, fraction));
            }
            Status::Done(result) => {
                let result = *result;
                self.loader = None;
                self.panel.loading = None;
                match result {
                    Ok(opened) => {
                        let (lo, hi) = opened.session.puppet.mesh.bounds();
                        self.camera.frame(lo.as_vec3(), hi.as_vec3());
                        self.camera.up = opened.session.puppet.up().as_vec3();
                        self.window
                            .set_title(&format!("puppet — {}", opened.session.name));
                        self.panel.message = Some(opened.message());
                        // A repaired file shows where, until the user turns it off.
                        self.panel.overlays.repairs = !opened.session.repairs.is_empty();
                        self.panel.opened = Some((opened.seconds, opened.report));
                        self.panel.source = opened.source;
                        self.session = Some(*opened.session);
                    }
                    Err(e) => {
                        let message = e.to_string();
                        log::error!("{message}");
                        self.panel.message = Some((message, true));
                    }
                }
            }
        }
    }

    /// The scene through an sRGB view, then the panels through the plain view (egui
    /// blends in gamma space).
    pub fn draw(
        &mut self,
        texture: &wgpu::Texture,
        primitives: &[egui::ClippedPrimitive],
        screen: &egui_wgpu::ScreenDescriptor,
    ) {
        let plain = texture.create_view(&Default::default());
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        let image = self
            .still
            .as_ref()
            .and_then(|s| s.kept())
            .filter(|_| self.still_frame);
        if let Some(image) = image {
            encoder.copy_texture_to_texture(
                image.as_image_copy(),
                texture.as_image_copy(),
                image.size(),
            );
            self.drawn_samples = crate::render::scene::MSAA;
            self.drawn_fxaa = false;
        } else if self.session.is_some() {
            self.scene.render_to(&self.gpu, &mut encoder, texture);
            self.drawn_samples = self.scene.samples();
            self.drawn_fxaa = self.scene.fxaa();
        }
        let extra = self.egui.renderer.update_buffers(
            &self.gpu.device,
            &self.gpu.queue,
            &mut encoder,
            primitives,
            screen,
        );
        {
            let load = if self.session.is_some() {
                wgpu::LoadOp::Load
            } else {
                wgpu::LoadOp::Clear(render::BACKGROUND)
            };
            let pass = render::colour_pass(&mut encoder, "egui", &plain, load);
            self.egui
                .renderer
                .render(&mut pass.forget_lifetime(), primitives, screen);
        }
        self.gpu
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
    }

    /// Frame statistics for the panel, over the last second.
    fn meter_frame(&mut self, steps: u32) {
        let (start, frames, total_steps, step_ms) = &mut self.meter;
        *frames += 1;
        *total_steps += steps;
        if steps > 0 {
            if let Some(s) = &self.session {
                *step_ms = s.puppet.sim.last_times().total() * 1e3;
            }
        }
        let elapsed = start.elapsed().as_secs_f32();
        if elapsed >= 1.0 {
            self.panel.stats.fps = *frames as f32 / elapsed;
            self.panel.stats.steps_per_second = *total_steps as f32 / elapsed;
            self.panel.stats.step_ms = *step_ms as f32;
            *start = Instant::now();
            *frames = 0;
            *total_steps = 0;
        }
    }
}
