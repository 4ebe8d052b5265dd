//! The window (behind the `gui` feature): winit events, the wgpu surface, egui, and the
//! loop that steps the simulation on its fixed step while drawing at the display rate.
//! Everything the puppeteer does is decided by the core's [`Session`]; this module maps
//! window events onto it and draws what it shows.
//!
//! * this file: [`run`] and the event loop (which events go where, when to sleep);
//! * `window`: creating the window, its surface and egui;
//! * `frame`: one frame (step, panels, draw, present);
//! * `actions`: keys and panel actions (open, save, export, undo);
//! * `screenshot`, `report`: `--screenshot`, and what the window shows as data (`--report`);
//! * `settings`: what the app remembers between runs (recent files, the first-run hint);
//! * `still`: the still frame, anti-aliased once nothing moves where frames are not;
//! * `hooks`, `drive`: what tests ask of the window ([`TestHooks`]), the synthetic drag;
//! * `dialog`: the system's file dialog, on a thread;
//! * `live`: live input devices (OSC, MIDI, gamepads) feeding the session.
//!
//! The window decides nothing about the puppet: what follows a load (suggested joints, an
//! animation) is the core's [`crate::session::loader`], what a key or a panel does is a
//! call on the [`Session`].
//!
//! The loop waits (`ControlFlow::Wait`, no redraw) whenever the session is not running
//! (settled or paused), nothing is loading and egui wants no repaint; any input wakes it.

mod actions;
mod dialog;
mod drive;
mod frame;
mod hooks;
mod live;
mod report;
mod screenshot;
mod settings;
mod still;
mod window;

pub use hooks::TestHooks;
pub use live::{LiveOptions, Wake, DEFAULT_PORT};
pub use report::Report;

use crate::puppet::RigFile;
use crate::render::{Gpu, SceneRenderer};
use crate::session::loader::{AfterLoad, Loader};
use crate::session::pointer::Button;
use crate::session::pointer::Pointer;
use crate::session::Camera;
use crate::session::Session;
use crate::ui::PanelState;
use anyhow::{Context as _, Result};
use glam::Vec2;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::ModifiersState;
use winit::window::Window;
use winit::window::WindowId;

/// What the window starts with.
pub struct Options {
    /// The validated mesh to open.
    pub mesh: crate::mesh::Mesh,
    /// How it was read (repairs, riders, seconds per stage).
    pub load_report: Option<crate::mesh::LoadReport>,
    /// How meshes opened from the window are read.
    pub load: crate::mesh::LoadOptions,
    /// Its display name (the file's name).
    pub name: String,
    /// The file's full path, when it came from a file.
    pub source: Option<PathBuf>,
    /// The rig to build it with.
    pub rig_file: RigFile,
    /// What to do once it is built: suggest joints, play an animation.
    pub after: AfterLoad,
    /// What scripts and tests ask of the window.
    pub hooks: TestHooks,
    /// Live controls (`--controls`, `--listen`), if any.
    pub live: Option<LiveOptions>,
    /// How the surface is lit at first (`--lighting`; without it, as the settings
    /// remember; the panel changes it).
    pub lighting: Option<crate::session::Lighting>,
}

/// Everything the open window holds: the window and its GPU surface, egui, and the
/// session the puppeteer works on, read and changed through the session's own methods.
struct WindowState {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    scene: SceneRenderer,
    /// The still frame's renderer (`still`), made the first time the view stands still
    /// while the window draws without anti-aliasing.
    still: Option<still::Still>,
    /// The surface takes copies (the still frame is copied under the panels).
    copies: bool,
    /// The adapter draws [`crate::render::scene::MSAA`] samples into the surface's format
    /// (the still frame's).
    can_msaa: bool,
    /// What the scene's image depended on at the frame before (`still::Key`).
    last_key: Option<still::Key>,
    /// Samples a pixel the last frame's scene was drawn with, and whether its edges were
    /// smoothed after (FXAA).
    drawn_samples: u32,
    drawn_fxaa: bool,
    /// The frame being drawn copies the still frame instead of drawing the scene.
    still_frame: bool,
    egui: Egui,
    /// The panels' own state (messages, recent files, what is shown).
    panel: PanelState,
    camera: Camera,
    pointer: Pointer,
    modifiers: ModifiersState,
    /// The puppet being played, once one is built.
    session: Option<Session>,
    /// A puppet being built (the session stays until it is ready).
    loader: Option<Loader>,
    /// How meshes opened from the window are read.
    load: crate::mesh::LoadOptions,
    last_frame: Instant,
    /// Frames drawn since the puppet was ready.
    frames: u32,
    /// Frame statistics over the last second: start, frames, steps, last step time (ms).
    meter: (Instant, u32, u32, f64),
    /// When egui asked to be drawn again.
    repaint_at: Option<Instant>,
    /// What the app remembers between runs.
    settings: settings::Settings,
    /// The lighting the panel showed last: when the puppeteer picks another, the
    /// settings remember it.
    lighting: crate::session::Lighting,
    /// A file dialog being shown.
    dialog: Option<dialog::Dialog>,
    hooks: TestHooks,
    /// Live controls, once the command line or the panel started them.
    live: Option<live::Live>,
    /// Wakes the loop from the live input's threads.
    proxy: winit::event_loop::EventLoopProxy<Wake>,
}

/// egui's context, its window state and its renderer.
struct Egui {
    ctx: egui::Context,
    state: egui_winit::State,
    renderer: egui_wgpu::Renderer,
}

/// Opens the window and runs until it is closed. With a screenshot requested, returns what
/// it shows.
pub fn run(options: Options) -> Result<Option<Report>> {
    let event_loop = EventLoop::<Wake>::with_user_event().build().context(
        "cannot open a window (no display?); the headless commands are `puppet skeleton`, `puppet suggest`, `puppet simulate` and `puppet bench`",
    )?;
    let proxy = event_loop.create_proxy();
    let mut app = App {
        proxy,
        options: Some(options),
        window: None,
        error: None,
        report: None,
    };
    event_loop.run_app(&mut app).context("window event loop")?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(app.report),
    }
}

struct App {
    /// Wakes the loop from the live input's thread.
    proxy: winit::event_loop::EventLoopProxy<Wake>,
    options: Option<Options>,
    window: Option<WindowState>,
    error: Option<anyhow::Error>,
    report: Option<Report>,
}

impl ApplicationHandler<Wake> for App {
    fn user_event(&mut self, _event_loop: &ActiveEventLoop, event: Wake) {
        match event {
            Wake::Input => {
                if let Some(w) = &self.window {
                    w.window.request_redraw();
                }
            }
        }
    }

    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let Some(options) = self.options.take() else {
            return;
        };
        match WindowState::new(event_loop, options, self.proxy.clone()) {
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
        let response = w.egui.state.on_window_event(&w.window, &event);
        // egui asks for a repaint after every event, `RedrawRequested` included: honouring
        // that one would redraw forever (a settled window must cost nothing). What egui
        // itself needs after a frame comes back as the frame's repaint delay.
        if response.repaint && !matches!(event, WindowEvent::RedrawRequested) {
            w.window.request_redraw();
        }
        match event {
            WindowEvent::CloseRequested => {
                w.write_report();
                event_loop.exit();
            }
            WindowEvent::Resized(size) => {
                w.config.width = size.width.max(1);
                w.config.height = size.height.max(1);
                w.surface.configure(&w.gpu.device, &w.config);
                w.window.request_redraw();
            }
            WindowEvent::RedrawRequested => match w.redraw() {
                Ok(frame::Next::Continue) => {}
                Ok(frame::Next::Exit(report)) => {
                    self.report = report.map(|r| *r);
                    event_loop.exit();
                }
                Err(e) => {
                    self.error = Some(e);
                    event_loop.exit();
                }
            },
            // A dropped animation plays; a dropped rig or controls file loads; anything else
            // opens as a mesh.
            WindowEvent::DroppedFile(path) => {
                let text_file = path.extension().is_some_and(|e| {
                    e.eq_ignore_ascii_case("toml") || e.eq_ignore_ascii_case("json")
                });
                let purpose = if !text_file {
                    crate::ui::FilePurpose::OpenMesh
                } else if crate::session::playback::is_animation_file(&path) {
                    crate::ui::FilePurpose::OpenAnimation
                } else if crate::controls::file::is_controls_file(&path) {
                    crate::ui::FilePurpose::LoadControls
                } else {
                    crate::ui::FilePurpose::LoadRig
                };
                w.use_file(purpose, path);
                w.window.request_redraw();
            }
            WindowEvent::ModifiersChanged(m) => {
                let m = m.state();
                w.pointer.toggle = m.shift_key() || m.control_key();
                w.modifiers = m;
            }
            // The pointer's position always goes to the puppet's pointer (it acts only on
            // a drag of its own).
            WindowEvent::CursorMoved { position, .. } => {
                w.cursor_moved(Vec2::new(position.x as f32, position.y as f32));
            }
            // Whether a press is the panels' or the model's is decided by where the cursor
            // is now, not by egui's hover state of the last frame: after a move from the
            // panel, a press and release arriving before the next frame (a tap, a fast
            // click) would otherwise go to the panel and be lost.
            WindowEvent::MouseInput { state, button, .. } => {
                let button = match button {
                    MouseButton::Left => Button::Left,
                    MouseButton::Right => Button::Right,
                    MouseButton::Middle => Button::Middle,
                    _ => return,
                };
                let pressed = state == ElementState::Pressed;
                if !pressed || !w.over_panels() {
                    w.mouse_button(button, pressed);
                }
            }
            WindowEvent::MouseWheel { delta, .. } if !w.over_panels() => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                w.camera.zoom(steps);
                w.window.request_redraw();
            }
            // Keys go to a text field being typed in, otherwise to the puppet: one action
            // per press (a held key's repeats, or the presses the system replays when the
            // window gains focus with a key down, would toggle the brush or the recording
            // again).
            WindowEvent::KeyboardInput {
                event,
                is_synthetic: false,
                ..
            } if event.state == ElementState::Pressed && !event.repeat && !response.consumed => {
                w.hooks.keys += 1;
                match w.key(&event.logical_key) {
                    actions::KeyOutcome::Quit => {
                        w.write_report();
                        event_loop.exit();
                    }
                    // The report says at once that the key arrived (`--report` only).
                    actions::KeyOutcome::Handled => w.write_report(),
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(w) = self.window.as_mut() else {
            return;
        };
        let busy = w.loader.is_some()
            || w.session.as_ref().is_some_and(Session::is_running)
            || w.hooks.busy();
        let exporting = w.session.as_ref().is_some_and(|s| s.export_job().is_some());
        if (w.dialog.is_some() || exporting) && !busy {
            // Look for the dialog's answer (the export's progress) ten times a second.
            let at = Instant::now() + Duration::from_millis(100);
            w.repaint_at = Some(w.repaint_at.map_or(at, |r| r.min(at)));
        }
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
    fn viewport(&self) -> Vec2 {
        Vec2::new(self.config.width as f32, self.config.height as f32)
    }

    /// Is the cursor over the side panel or a popup of egui's (or is egui dragging
    /// something)? Decided from where they were in the last frame, which does not move
    /// with the pointer. (The view itself is egui's background layer: not a panel.)
    fn over_panels(&self) -> bool {
        let ppp = self.egui.ctx.pixels_per_point().max(1e-3);
        let at = egui::pos2(self.pointer.cursor.x / ppp, self.pointer.cursor.y / ppp);
        let popup = self
            .egui
            .ctx
            .layer_id_at(at)
            .is_some_and(|l| l.order != egui::Order::Background);
        self.egui.ctx.egui_is_using_pointer()
            || popup
            || self.panel.rect.is_some_and(|r| r.contains(at))
    }

    fn cursor_moved(&mut self, at: Vec2) {
        let viewport = self.viewport();
        if self
            .pointer
            .moved(at, self.session.as_mut(), &mut self.camera, viewport)
        {
            self.window.request_redraw();
        }
    }

    fn mouse_button(&mut self, button: Button, pressed: bool) {
        if pressed {
            let viewport = self.viewport();
            self.pointer
                .press(button, self.session.as_mut(), &self.camera, viewport);
        } else {
            self.pointer.release();
        }
        self.window.request_redraw();
    }

    /// The session, if a puppet is loaded.
    fn session(&self) -> Option<&Session> {
        self.session.as_ref()
    }
}
