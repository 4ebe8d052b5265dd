//! Creating the window: its wgpu surface (format and present mode chosen from what the
//! adapter offers), the scene renderer and egui.

use super::settings::Settings;
use super::{Egui, Options, WindowState};
use crate::render::{AntiAliasing, Gpu};
use crate::session::loader::Loader;
use crate::session::pointer::Pointer;
use crate::session::Camera;
use crate::ui::PanelState;
use anyhow::{anyhow, Context as _, Result};
use std::sync::Arc;
use std::time::Instant;
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::ModifiersState;
use winit::window::Window;

impl WindowState {
    pub fn new(
        event_loop: &ActiveEventLoop,
        options: Options,
        proxy: winit::event_loop::EventLoopProxy<super::Wake>,
    ) -> Result<WindowState> {
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
        // The still frame is copied into the window's texture (`still`).
        let copies = caps.usages.contains(wgpu::TextureUsages::COPY_DST);
        if copies {
            config.usage |= wgpu::TextureUsages::COPY_DST;
        }
        // FXAA copies the pixels it reads out of it.
        let gives_copies = caps.usages.contains(wgpu::TextureUsages::COPY_SRC);
        if gives_copies {
            config.usage |= wgpu::TextureUsages::COPY_SRC;
        }
        config.present_mode = if caps.present_modes.contains(&wgpu::PresentMode::Fifo) {
            wgpu::PresentMode::Fifo
        } else {
            caps.present_modes
                .first()
                .copied()
                .unwrap_or(wgpu::PresentMode::Fifo)
        };
        surface.configure(&gpu.device, &config);
        let view_format = config.format.add_srgb_suffix();
        let settings = Settings::load();
        let lighting = options.lighting.or(settings.lighting).unwrap_or_default();
        let can_msaa = crate::render::scene::msaa_supported(&gpu, view_format);
        let offered: Vec<AntiAliasing> = AntiAliasing::ALL
            .into_iter()
            .filter(|a| match a {
                AntiAliasing::Msaa => can_msaa,
                AntiAliasing::Fxaa => gives_copies,
                AntiAliasing::Off => true,
            })
            .collect();
        let default = if crate::render::scene::window_msaa(&gpu, view_format) {
            AntiAliasing::Msaa
        } else if gives_copies {
            AntiAliasing::Fxaa
        } else {
            AntiAliasing::Off
        };
        let anti_aliasing = settings
            .anti_aliasing
            .filter(|a| offered.contains(a))
            .unwrap_or(default);
        let scene = anti_aliasing.renderer(&gpu, view_format);
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
            still: None,
            copies,
            can_msaa,
            last_key: None,
            drawn_samples: 1,
            drawn_fxaa: false,
            still_frame: false,
            egui: Egui {
                ctx: egui_ctx,
                state: egui_state,
                renderer: egui_renderer,
            },
            camera: Camera::default(),
            panel: PanelState {
                overlays: crate::session::Overlays {
                    lighting,
                    ..Default::default()
                },
                anti_aliasing: Some(anti_aliasing),
                anti_aliasing_offered: offered,
                ..PanelState::default()
            },
            session: None,
            loader: None,
            pointer: Pointer::default(),
            modifiers: ModifiersState::default(),
            last_frame: Instant::now(),
            frames: 0,
            meter: (Instant::now(), 0, 0, 0.0),
            repaint_at: None,
            settings,
            lighting,
            dialog: None,
            load: options.load,
            hooks: options.hooks,
            live: options
                .live
                .map(|live| super::live::Live::start(live, proxy.clone())),
            proxy,
        };
        state.panel.recent = state.settings.recent.clone();
        state.panel.hint = !state.settings.hint_done;
        state.loader = Some(Loader::build(
            options.mesh,
            options.name,
            options.source,
            options.load_report,
            options.rig_file,
            options.after,
        ));
        Ok(state)
    }
}
