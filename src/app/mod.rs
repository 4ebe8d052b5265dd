//! The window: winit events, the wgpu surface, egui, and the loop that steps the simulation
//! on its fixed step while drawing at the display rate.
//!
//! The loop sleeps (`ControlFlow::Wait`, no redraw) whenever the session is idle (pose
//! unchanged and the motion died out, or paused), nothing is loading and egui wants no
//! repaint; any input wakes it.

mod input;
mod loader;

use crate::render::{self, Camera, Gpu, SceneRenderer};
use crate::scene::RigSpec;
use crate::ui::{panels, Action, PanelState, Session};
use anyhow::{anyhow, Context as _, Result};
use glam::Vec2;
use input::{Drag, Input};
use loader::Loader;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

/// What the window starts with.
pub struct Options {
    /// The validated mesh to open and its display name.
    pub mesh: crate::mesh::Mesh,
    pub name: String,
    pub rig: RigSpec,
    /// Save a screenshot here after `frames` frames and exit (documentation, tests).
    pub screenshot: Option<PathBuf>,
    pub frames: u32,
    /// Test hook: once the puppet is built, drag the section under the window centre the
    /// way a mouse would, then take the screenshot.
    pub drive: bool,
}

/// Opens the window and runs until it is closed.
pub fn run(options: Options) -> Result<()> {
    let event_loop = EventLoop::new().context(
        "cannot open a window (no display?); the headless commands are `puppet skeleton`, `puppet simulate` and `puppet bench`",
    )?;
    let mut app = App {
        options: Some(options),
        window: None,
        error: None,
    };
    event_loop.run_app(&mut app).context("window event loop")?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct App {
    options: Option<Options>,
    window: Option<WindowState>,
    error: Option<anyhow::Error>,
}

struct WindowState {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    scene: SceneRenderer,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    camera: Camera,
    panel: PanelState,
    session: Option<Session>,
    loader: Option<Loader>,
    input: Input,
    last_frame: Instant,
    frames: u32,
    /// Frame statistics over the last second.
    meter: (Instant, u32, u32, f64),
    screenshot: Option<PathBuf>,
    exit_after: Option<u32>,
    drive: Option<u32>,
    repaint_at: Option<Instant>,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let Some(options) = self.options.take() else {
            return;
        };
        match WindowState::new(event_loop, options) {
            Ok(w) => {
                w.window.request_redraw();
                self.window = Some(w);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(w) = self.window.as_mut() else {
            return;
        };
        let response = w.egui_state.on_window_event(&w.window, &event);
        if response.repaint {
            w.window.request_redraw();
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                w.config.width = size.width.max(1);
                w.config.height = size.height.max(1);
                w.surface.configure(&w.gpu.device, &w.config);
                w.window.request_redraw();
            }
            WindowEvent::RedrawRequested => match w.redraw() {
                Ok(true) => {}
                Ok(false) => event_loop.exit(),
                Err(e) => {
                    self.error = Some(e);
                    event_loop.exit();
                }
            },
            WindowEvent::DroppedFile(path) => {
                w.start_loading(Some(path), None);
            }
            WindowEvent::ModifiersChanged(m) => w.input.modifiers = m.state(),
            _ if response.consumed => {}
            WindowEvent::CursorMoved { position, .. } => {
                w.cursor_moved(Vec2::new(position.x as f32, position.y as f32));
            }
            WindowEvent::MouseInput { state, button, .. } => {
                w.mouse_button(button, state == ElementState::Pressed);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                w.camera.zoom(steps);
                w.window.request_redraw();
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                w.key(&event.logical_key);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(w) = self.window.as_mut() else {
            return;
        };
        let busy = w.loader.is_some()
            || w.session.as_ref().is_some_and(|s| !s.is_idle())
            || w.screenshot.is_some()
            || w.drive.is_some();
        if busy {
            // Simulate and draw at most at 60 frames per second.
            let next = w.last_frame + Duration::from_micros(16_667);
            if Instant::now() >= next {
                w.window.request_redraw();
                event_loop.set_control_flow(ControlFlow::Wait);
            } else {
                event_loop.set_control_flow(ControlFlow::WaitUntil(next));
            }
        } else if let Some(at) = w.repaint_at {
            if Instant::now() >= at {
                w.repaint_at = None;
                w.window.request_redraw();
                event_loop.set_control_flow(ControlFlow::Wait);
            } else {
                event_loop.set_control_flow(ControlFlow::WaitUntil(at));
            }
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}

impl WindowState {
    fn new(event_loop: &ActiveEventLoop, options: Options) -> Result<WindowState> {
        let attributes = Window::default_attributes()
            .with_title(format!("puppet — {}", options.name))
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 800.0));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot create the window")?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| anyhow!("cannot draw into the window: {e}"))?;
        let gpu = Gpu::with_instance(instance, Some(&surface))?;
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| anyhow!("the graphics adapter cannot present to this window"))?;
        let caps = surface.get_capabilities(&gpu.adapter);
        // egui wants a non-sRGB target and the scene an sRGB one: configure the plain format
        // and draw the scene through an sRGB view of the same texture.
        let base = caps
            .formats
            .iter()
            .map(|f| f.remove_srgb_suffix())
            .find(|f| f.add_srgb_suffix() != *f)
            .unwrap_or(config.format);
        config.format = base;
        config.view_formats = vec![base.add_srgb_suffix()];
        config.present_mode = if caps.present_modes.contains(&wgpu::PresentMode::Fifo) {
            wgpu::PresentMode::Fifo
        } else {
            caps.present_modes
                .first()
                .copied()
                .unwrap_or(wgpu::PresentMode::Fifo)
        };
        surface.configure(&gpu.device, &config);
        let scene = SceneRenderer::new(&gpu, config.format.add_srgb_suffix());
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(
            &gpu.device,
            config.format,
            egui_wgpu::RendererOptions::default(),
        );
        let mut state = WindowState {
            window,
            surface,
            config,
            gpu,
            scene,
            egui_ctx,
            egui_state,
            egui_renderer,
            camera: Camera::default(),
            panel: PanelState::default(),
            session: None,
            loader: None,
            input: Input::default(),
            last_frame: Instant::now(),
            frames: 0,
            meter: (Instant::now(), 0, 0, 0.0),
            screenshot: options.screenshot,
            exit_after: None,
            drive: options.drive.then_some(0),
            repaint_at: None,
        };
        if state.screenshot.is_some() {
            state.exit_after = Some(options.frames.max(1));
        }
        state.loader = Some(Loader::build(options.mesh, options.name, options.rig));
        Ok(state)
    }

    fn viewport(&self) -> Vec2 {
        Vec2::new(self.config.width as f32, self.config.height as f32)
    }

    /// Starts loading a mesh (or the current one with a new rig) in the background; the
    /// current puppet stays until the new one is ready.
    fn start_loading(&mut self, path: Option<PathBuf>, rig: Option<RigSpec>) {
        let rig = rig.unwrap_or_else(|| {
            let mut spec = self
                .session
                .as_ref()
                .map(|s| s.puppet.current_spec())
                .unwrap_or_default();
            spec.cuts.clear();
            spec.root = crate::joints::ROOT.into();
            spec
        });
        match path {
            Some(p) => self.loader = Some(Loader::open(p, rig)),
            None => {
                if let Some(s) = &self.session {
                    self.loader = Some(Loader::build(s.puppet.mesh.clone(), s.name.clone(), rig));
                }
            }
        }
        self.panel.message = None;
        self.window.request_redraw();
    }

    fn poll_loader(&mut self) {
        let Some(loader) = &mut self.loader else {
            self.panel.loading = None;
            return;
        };
        match loader.poll() {
            loader::Status::Working(stage, fraction) => {
                self.panel.loading = Some((stage, fraction));
            }
            loader::Status::Done(result) => {
                self.loader = None;
                self.panel.loading = None;
                match result {
                    Ok((puppet, name)) => {
                        let (lo, hi) = puppet.mesh.bounds();
                        self.camera.frame(lo.as_vec3(), hi.as_vec3());
                        self.window.set_title(&format!("puppet — {name}"));
                        self.panel.message = Some((format!("opened {name}"), false));
                        self.session = Some(Session::new(*puppet, name));
                    }
                    Err(message) => {
                        log::error!("{message}");
                        self.panel.message = Some((message, true));
                    }
                }
            }
        }
    }

    fn cursor_moved(&mut self, at: Vec2) {
        let delta = at - self.input.cursor;
        self.input.cursor = at;
        let height = self.viewport().y;
        match self.input.drag {
            Drag::None => return,
            Drag::Orbit => self.camera.orbit(delta),
            Drag::Pan => self.camera.pan(delta, height),
            Drag::Rotate => {
                if let Some(s) = &mut self.session {
                    s.rotate_selected(input::trackball(&self.camera, delta, height));
                }
            }
        }
        self.window.request_redraw();
    }

    fn mouse_button(&mut self, button: MouseButton, pressed: bool) {
        if !pressed {
            self.input.drag = Drag::None;
            return;
        }
        let (origin, dir) = self.camera.ray(self.input.cursor, self.viewport());
        let additive = self.input.modifiers.shift_key() || self.input.modifiers.control_key();
        self.input.drag = match button {
            MouseButton::Left => match &mut self.session {
                Some(s) => {
                    let hit = s.pick(origin, dir);
                    match hit {
                        Some(h) if self.panel.cut_tool => {
                            let right = self.camera.view().row(0).truncate().as_dvec3();
                            let section = s.section_at(&h);
                            s.draft = Some(crate::ui::CutDraft {
                                section,
                                point: h.point.as_dvec3(),
                                normal: self.panel.cut_normal(right),
                                pivot: None,
                                name: s.fresh_section_name(),
                            });
                            s.revision += 1;
                            Drag::None
                        }
                        Some(h) => {
                            let section = s.section_at(&h);
                            if !s.selection.contains(&section) || additive {
                                s.select(Some(section), additive);
                            }
                            s.checkpoint();
                            Drag::Rotate
                        }
                        None => {
                            if !additive {
                                s.select(None, false);
                            }
                            Drag::Orbit
                        }
                    }
                }
                None => Drag::Orbit,
            },
            MouseButton::Right | MouseButton::Middle => Drag::Pan,
            _ => Drag::None,
        };
        self.window.request_redraw();
    }

    fn key(&mut self, key: &Key) {
        let ctrl = self.input.modifiers.control_key();
        let shift = self.input.modifiers.shift_key();
        match key {
            Key::Character(c) => match (c.to_lowercase().as_str(), ctrl) {
                ("f", false) => self.frame_model(),
                ("w", false) => self.panel.overlays.wireframe ^= true,
                ("r", false) => {
                    if let Some(s) = &mut self.session {
                        s.reset_pose();
                    }
                }
                ("z", true) if shift => self.redo(),
                ("z", true) => self.undo(),
                ("y", true) => self.redo(),
                _ => {}
            },
            Key::Named(NamedKey::Space) => {
                if let Some(s) = &mut self.session {
                    s.paused ^= true;
                    s.wake();
                }
            }
            Key::Named(NamedKey::Escape) => {
                self.panel.cut_tool = false;
                if let Some(s) = &mut self.session {
                    s.draft = None;
                    s.select(None, false);
                }
            }
            _ => {}
        }
        self.window.request_redraw();
    }

    fn undo(&mut self) {
        if let Some(s) = &mut self.session {
            s.undo();
        }
    }

    fn redo(&mut self) {
        if let Some(s) = &mut self.session {
            s.redo();
        }
    }

    fn frame_model(&mut self) {
        if let Some(s) = &self.session {
            let (lo, hi) = s.puppet.mesh.bounds();
            self.camera.frame(lo.as_vec3(), hi.as_vec3());
        }
    }

    fn act(&mut self, action: Action) {
        let result: Result<String, String> = match action {
            Action::OpenMesh(path) => {
                self.start_loading(Some(PathBuf::from(path)), None);
                return;
            }
            Action::Frame => {
                self.frame_model();
                return;
            }
            Action::LoadRig(path) => match RigSpec::load(std::path::Path::new(&path)) {
                Ok(spec) => {
                    let mesh = spec.mesh.clone();
                    self.start_loading(mesh, Some(spec));
                    return;
                }
                Err(e) => Err(format!("{path}: {e}")),
            },
            Action::SaveRig(path) => match &self.session {
                Some(s) => std::fs::write(&path, s.puppet.current_spec().to_toml(None))
                    .map(|_| format!("saved {path}"))
                    .map_err(|e| format!("{path}: cannot write: {e}")),
                None => return,
            },
            Action::ExportObj(path) => match &self.session {
                Some(s) => export_obj(s, &path),
                None => return,
            },
        };
        self.panel.message = Some(match result {
            Ok(m) => (m, false),
            Err(m) => (m, true),
        });
    }

    /// Draws one frame; returns false when the app should exit (screenshot taken).
    fn redraw(&mut self) -> Result<bool> {
        let now = Instant::now();
        let dt = (now - self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        self.poll_loader();
        self.drive_test();
        let mut steps = 0;
        if let Some(s) = &mut self.session {
            steps = s.advance(dt, 8);
        }
        self.meter_frame(steps);

        let raw = self.egui_state.take_egui_input(&self.window);
        let panel = &mut self.panel;
        let session = &mut self.session;
        let mut actions = Vec::new();
        let output = self.egui_ctx.run_ui(raw, |ui| {
            actions = panels::side_panel(ui, panel, session.as_mut());
        });
        self.egui_state
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
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: output.pixels_per_point,
        };
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                self.egui_renderer
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
        if let Some(s) = &self.session {
            self.scene
                .prepare(&self.gpu, s, &self.camera, self.panel.overlays, aspect);
        }
        let take_shot = self.exit_after.is_some_and(|n| self.frames + 1 >= n)
            && self.session.is_some()
            && self.drive.is_none();
        if let Some(frame) = frame {
            self.draw(&frame.texture, &primitives, &screen);
            self.gpu.queue.present(frame);
        }
        if take_shot {
            if let Some(path) = self.screenshot.clone() {
                let image = self.capture(&primitives, &screen)?;
                image
                    .save_png(&path)
                    .map_err(|e| anyhow!("{}: cannot write: {e}", path.display()))?;
                self.report(&path);
                for id in &output.textures_delta.free {
                    self.egui_renderer.free_texture(id);
                }
                return Ok(false);
            }
        }
        for id in &output.textures_delta.free {
            self.egui_renderer.free_texture(id);
        }
        if self.session.is_some() && self.loader.is_none() {
            self.frames += 1;
        }
        Ok(true)
    }

    /// The scene through an sRGB view, then the panels through the plain view (egui
    /// blends in gamma space).
    fn draw(
        &mut self,
        texture: &wgpu::Texture,
        primitives: &[egui::ClippedPrimitive],
        screen: &egui_wgpu::ScreenDescriptor,
    ) {
        let plain = texture.create_view(&Default::default());
        let view = &plain;
        let srgb = texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.config.format.add_srgb_suffix()),
            ..Default::default()
        });
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        if self.session.is_some() {
            self.scene.render_to(
                &self.gpu,
                &mut encoder,
                &srgb,
                self.config.width,
                self.config.height,
            );
        }
        let extra = self.egui_renderer.update_buffers(
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
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load,
                        store: wgpu::StoreOp::Store,
                    },
                    depth_slice: None,
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.egui_renderer
                .render(&mut pass.forget_lifetime(), primitives, screen);
        }
        self.gpu
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
    }

    /// The frame (scene and panels) rendered once more into a texture and read back.
    fn capture(
        &mut self,
        primitives: &[egui::ClippedPrimitive],
        screen: &egui_wgpu::ScreenDescriptor,
    ) -> Result<render::Image> {
        let texture = self.gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("screenshot"),
            size: wgpu::Extent3d {
                width: self.config.width,
                height: self.config.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.config.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[self.config.format.add_srgb_suffix()],
        });
        self.draw(&texture, primitives, screen);
        Ok(render::image::read_texture(&self.gpu, &texture)?)
    }

    fn meter_frame(&mut self, steps: u32) {
        let (start, frames, total_steps, step_ms) = &mut self.meter;
        *frames += 1;
        *total_steps += steps;
        if steps > 0 {
            if let Some(s) = &self.session {
                let t = s.puppet.sim.last_times();
                *step_ms = t.total() * 1e3;
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

    /// The window test's synthetic drag: press on the section under the window's centre
    /// column, move, release, all through the mouse handlers.
    fn drive_test(&mut self) {
        let Some(k) = self.drive else {
            return;
        };
        let Some(s) = &self.session else {
            return;
        };
        let size = self.viewport();
        // Aim at the pivot of the last section, or the model centre.
        let target = match s.puppet.joints.sections().len() {
            1 => s.puppet.sim.positions().get(0),
            n => s.pivot_world(n - 1).as_vec3(),
        };
        let Some(at) = self.camera.project(target, size) else {
            self.drive = None;
            return;
        };
        match k {
            0 => {
                self.cursor_moved(at);
                self.mouse_button(MouseButton::Left, true);
            }
            1..=10 => self.cursor_moved(self.input.cursor + Vec2::new(0.0, 9.0)),
            11 => self.mouse_button(MouseButton::Left, false),
            _ => {
                self.drive = None;
                return;
            }
        }
        self.drive = Some(k + 1);
    }

    /// One line on stdout for tests and scripts: what the screenshot shows.
    fn report(&self, path: &std::path::Path) {
        let Some(s) = &self.session else {
            return;
        };
        let turned: Vec<String> = s
            .local
            .iter()
            .enumerate()
            .filter(|(_, l)| l.rotation.angle_between(glam::DQuat::IDENTITY) > 1e-6)
            .map(|(i, l)| {
                format!(
                    "{}:{:.1}",
                    s.puppet.joints.sections()[i].name,
                    l.rotation.angle_between(glam::DQuat::IDENTITY).to_degrees()
                )
            })
            .collect();
        let line = serde_json::json!({
            "screenshot": path.display().to_string(),
            "width": self.config.width,
            "height": self.config.height,
            "frames": self.frames + 1,
            "selection": s.selection.iter().map(|&i| s.puppet.joints.sections()[i].name.clone()).collect::<Vec<_>>(),
            "turned": turned,
            "adapter": self.gpu.adapter.get_info().name,
        });
        println!("{line}");
    }
}

fn export_obj(s: &Session, path: &str) -> Result<String, String> {
    s.puppet
        .save_surface(std::path::Path::new(path), "exported by puppet")
        .map(|_| format!("exported {path}"))
        .map_err(|e| format!("{path}: {e}"))
}
