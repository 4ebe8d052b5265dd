//! The GPU device: instance, adapter, device and queue, created once, for a window or for
//! offscreen images.

/// Why drawing is impossible.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No adapter at all.
    #[error("no graphics adapter ({0}); install a Vulkan or OpenGL driver (on Debian: mesa-vulkan-drivers)")]
    Adapter(String),
    /// The adapter refused a device.
    #[error("cannot open the graphics device: {0}")]
    Device(String),
    /// Mapping the read-back buffer failed.
    #[error("cannot read the image back from the GPU: {0}")]
    Readback(String),
}

/// The instance, adapter, device and queue, created once.
pub struct Gpu {
    /// The wgpu instance.
    pub instance: wgpu::Instance,
    /// The adapter chosen (on this project's machines: llvmpipe).
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// A device for offscreen rendering (no window; needs no display).
    pub fn headless() -> Result<Gpu, RenderError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        Gpu::with_instance(instance, None)
    }

    /// A device on `instance` that can present to `surface`.
    pub fn with_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Gpu, RenderError> {
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: surface,
            apply_limit_buckets: false,
        }))
        .map_err(|e| RenderError::Adapter(e.to_string()))?;
        let info = adapter.get_info();
        log::info!(
            "graphics adapter: {} ({:?}, {:?})",
            info.name,
            info.device_type,
            info.backend
        );
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("puppet"),
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(Gpu {
            instance,
            adapter,
            device,
            queue,
        })
    }
}
