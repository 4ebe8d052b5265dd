//! Drawing with wgpu (behind the `gui` feature): the lit surface in section colours and the
//! overlay lines that the core's [`View`] describes, into a window or an offscreen image.
//! Nothing here decides what to draw; the core does.
//!
//! * [`gpu`]: the device, created once;
//! * `pipelines`, `buffers`: the pipelines of `shaders/scene.wgsl` and the buffers they read;
//! * [`scene`]: [`SceneRenderer`] (`new` creates, `prepare` uploads what changed, `paint`
//!   draws);
//! * [`image`]: images read back from the GPU, PNG files, comparisons for tests;
//! * [`video`]: a take's frames into `ffmpeg`, or PNG files without it.

mod buffers;
pub mod gpu;
pub mod image;
mod pipelines;
pub mod scene;
pub mod video;

pub use gpu::{Gpu, RenderError};
pub use image::Image;
pub use scene::SceneRenderer;

use crate::session::{Camera, View};

/// Format of the depth buffer.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The colour behind the model (linear RGB).
pub const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.030,
    g: 0.034,
    b: 0.042,
    a: 1.0,
};

/// The format offscreen images are rendered in.
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Renders a view offscreen into an RGBA image (sRGB), `width × height` pixels.
pub fn render_image(
    gpu: &Gpu,
    renderer: &mut SceneRenderer,
    view: &View,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Result<Image, RenderError> {
    let texture = colour_target(
        gpu,
        "offscreen",
        [width, height],
        OFFSCREEN_FORMAT,
        wgpu::TextureUsages::COPY_SRC,
        &[],
    );
    let target = texture.create_view(&Default::default());
    renderer.prepare(gpu, view, camera, width as f32 / height as f32);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.render_to(gpu, &mut encoder, &target, width, height);
    gpu.queue.submit([encoder.finish()]);
    image::read_texture(gpu, &texture)
}

/// A texture of `size` pixels in `format` (one sample) to draw into, with `usage` besides,
/// viewable as `view_formats` too.
pub fn colour_target(
    gpu: &Gpu,
    label: &str,
    [width, height]: [u32; 2],
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
    view_formats: &[wgpu::TextureFormat],
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | usage,
        view_formats,
    })
}

/// Begins a pass that draws into `view` alone (no depth), loading it as `load` says.
pub fn colour_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
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
    })
}
