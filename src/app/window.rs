//! Creating the window: its wgpu surface (format and present mode chosen from what the
//! adapter offers), the scene renderer and egui.

use super::dialog::Dialog;
use super::settings::Settings;
use super::Options;
use crate::render::{Gpu, SceneRenderer};
use crate::session::loader::Loader;
use crate::session::pointer::Pointer;
use crate::session::{Camera, Session};
use crate::ui::PanelState;
use anyhow::{anyhow, Context as _, Result};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::ModifiersState;
use winit::window::Window;

/// Everything the open window holds.
pub(super) struct WindowState {
    pub window: Arc<Window>,
    pub surface: wgpu::Surface<'static>,
    pub config: wgpu::SurfaceConfiguration,
    pub gpu: Gpu,
    pub scene: SceneRenderer,
    pub egui_ctx: egui::Context,
    pub egui_state: egui_winit::State,
    pub egui_renderer: egui_wgpu::Renderer,
    pub camera: Camera,
    pub panel: PanelState,
    pub session: Option<Session>,
    pub loader: Option<Loader>,
    pub pointer: Pointer,
    pub modifiers: ModifiersState,
    pub last_frame: Instant,
    /// Frames drawn since the puppet was ready.
    pub frames: u32,
    /// Key presses the window received (the report says how many, so a test driving it
    /// knows a key arrived).
    pub keys: u64,
    /// Frame statistics over the last second: start, frames, steps, last step time (ms).
    pub meter: (Instant, u32, u32, f64),
    pub screenshot: Option<PathBuf>,
    pub exit_after: Option<u32>,
    /// The window test's synthetic drag: its next event.
    pub drive: Option<u32>,
    /// When egui asked to be drawn again.
    pub repaint_at: Option<Instant>,
    /// What the app remembers between runs.
    pub settings: Settings,
    /// A file dialog being shown.
    pub dialog: Option<Dialog>,
    /// Where `--report` writes.
    pub report_path: Option<PathBuf>,
    /// Suggest joints on the puppet being loaded, once it is built.
    pub suggest: bool,
    /// Play this animation on the puppet being loaded, once it is built.
    pub animation: Option<crate::anim::Animation>,
    /// How meshes opened from the window are read.
    pub load: crate::mesh::LoadOptions,
}

impl WindowState {
    pub fn new(event_loop: &ActiveEventLoop, options: Options) -> Result<WindowState> {
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
            pointer: Pointer::default(),
            modifiers: ModifiersState::default(),
            last_frame: Instant::now(),
            frames: 0,
            keys: 0,
            meter: (Instant::now(), 0, 0, 0.0),
            screenshot: options.screenshot,
            exit_after: None,
            drive: options.drive.then_some(0),
            repaint_at: None,
            settings: Settings::load(),
            dialog: None,
            report_path: options.report,
            suggest: false,
            animation: options.animation,
            load: options.load,
        };
        state.panel.recent = state.settings.recent.clone();
        state.panel.hint = !state.settings.hint_done;
        if state.screenshot.is_some() {
            state.exit_after = Some(options.frames.max(1));
        }
        state.loader = Some(Loader::build(
            options.mesh,
            options.name,
            options.source,
            options.load_report,
            options.rig_file,
        ));
        state.suggest = options.suggest;
        Ok(state)
    }
}
