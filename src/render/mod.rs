//! Drawing with wgpu (behind the `gui` feature): the lit surface in section colours and the
//! overlay lines that the core's [`View`] describes, into a window or an offscreen image.
//! Nothing here decides what to draw; the core does.
//!
//! * [`gpu`]: the device, created once;
//! * `pipelines`, `buffers`: the pipelines of `shaders/scene.wgsl` and the buffers they read;
//! * `fxaa`: edges smoothed after a one-sample scene (`shaders/fxaa.wgsl`);
//! * [`scene`]: [`SceneRenderer`] (`new` creates, `prepare` uploads what changed, `paint`
//!   draws);
//! * [`image`]: images read back from the GPU, PNG files, comparisons for tests;
//! * [`video`]: a take's frames into `ffmpeg`, or PNG files without it.

mod buffers;
mod fxaa;
pub mod gpu;
pub mod image;
mod pipelines;
pub mod scene;
pub mod video;

pub use gpu::{Gpu, RenderError};
pub use image::Image;
pub use scene::SceneRenderer;

use crate::session::{Camera, View};

/// How the window smooths edges while the view moves (a still view is drawn once more
/// with [`scene::MSAA`] samples whichever, where the adapter has them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AntiAliasing {
    /// [`scene::MSAA`] samples a pixel: the best edges, two to three times the frame on
    /// a software rasterizer.
    Msaa,
    /// One sample, the edges smoothed after (FXAA) over the cells the surface's silhouette
    /// crosses.
    Fxaa,
    /// One sample, the edges stepped while anything moves.
    #[default]
    Off,
}

impl AntiAliasing {
    /// Every choice, in the panel's order.
    pub const ALL: [AntiAliasing; 3] = [AntiAliasing::Msaa, AntiAliasing::Fxaa, AntiAliasing::Off];

    /// What the panel calls it.
    pub fn label(self) -> &'static str {
        match self {
            AntiAliasing::Msaa => "4 samples",
            AntiAliasing::Fxaa => "smoothed (FXAA)",
            AntiAliasing::Off => "off while moving",
        }
    }

    /// A renderer for the moving view into targets of `format` (FXAA's targets give
    /// copies: see [`SceneRenderer::render_to`]).
    pub fn renderer(self, gpu: &Gpu, format: wgpu::TextureFormat) -> SceneRenderer {
        match self {
            AntiAliasing::Msaa => SceneRenderer::with_samples(gpu, format, scene::MSAA),
            AntiAliasing::Fxaa => SceneRenderer::with_fxaa(gpu, format),
            AntiAliasing::Off => SceneRenderer::with_samples(gpu, format, 1),
        }
    }

    /// What `renderer` draws with.
    pub fn of(renderer: &SceneRenderer) -> AntiAliasing {
        if renderer.samples() > 1 {
            AntiAliasing::Msaa
        } else if renderer.fxaa() {
            AntiAliasing::Fxaa
        } else {
            AntiAliasing::Off
        }
    }
}

/// Reads the names [`AntiAliasing`] is written as, and the settings of versions that had
/// a switch (`true`: [`AntiAliasing::Msaa`], `false`: [`AntiAliasing::Off`]).
impl<'de> serde::Deserialize<'de> for AntiAliasing {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Written {
            Switch(bool),
            Name(String),
        }
        match Written::deserialize(d)? {
            Written::Switch(true) => Ok(AntiAliasing::Msaa),
            Written::Switch(false) => Ok(AntiAliasing::Off),
            Written::Name(name) => match name.as_str() {
                "msaa" => Ok(AntiAliasing::Msaa),
                "fxaa" => Ok(AntiAliasing::Fxaa),
                "off" => Ok(AntiAliasing::Off),
                _ => Err(serde::de::Error::custom(format!(
                    "unknown anti-aliasing `{name}` (msaa, fxaa or off)"
                ))),
            },
        }
    }
}

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
        // (FXAA writes through the plain format.)
        &[OFFSCREEN_FORMAT.remove_srgb_suffix()],
    );
    renderer.prepare(gpu, view, camera, width as f32 / height as f32);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.render_to(gpu, &mut encoder, &texture);
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
