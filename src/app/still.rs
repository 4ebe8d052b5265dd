//! The still frame: where the window draws one sample a pixel (a software rasterizer, on
//! which [`MSAA`] samples cost two to three times the frame, `puppet bench draw`; its
//! edges smoothed by FXAA or not), the scene is drawn once more with [`MSAA`] samples as
//! soon as nothing in it changed for a frame (the puppet settled, the camera let go), into an image kept until the view
//! changes again. Every frame in between copies that image under the panels: a hover over
//! the panel redraws the panel, not the scene. While anything moves the window draws as
//! fast as before; [`STILL_AFTER`] after the last change, the still frame.

use crate::render::scene::MSAA;
use crate::render::{Gpu, SceneRenderer};
use crate::session::view::{Overlays, Revisions};
use crate::session::{Camera, View};
use std::time::Duration;

/// How long after the last frame that changed the view the still frame is drawn.
pub(super) const STILL_AFTER: Duration = Duration::from_millis(150);

/// What the scene's image depends on: when none of it changed since the frame before,
/// the view is still.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Key {
    revisions: Revisions,
    camera: Camera,
    overlays: Overlays,
    size: [u32; 2],
}

impl Key {
    pub(super) fn of(view: &View, camera: &Camera, overlays: Overlays, size: [u32; 2]) -> Key {
        Key {
            revisions: view.revisions(),
            camera: *camera,
            overlays,
            size,
        }
    }
}

/// The anti-aliased renderer and the image it drew last.
pub(super) struct Still {
    scene: SceneRenderer,
    image: Option<(wgpu::Texture, Key)>,
}

impl Still {
    /// A renderer with [`MSAA`] samples for images of `format` (drawn through its sRGB
    /// view, as the window draws the scene).
    pub(super) fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Still {
        Still {
            scene: SceneRenderer::with_samples(gpu, format.add_srgb_suffix(), MSAA),
            image: None,
        }
    }

    /// The image drawn last, if any.
    pub(super) fn kept(&self) -> Option<&wgpu::Texture> {
        self.image.as_ref().map(|(t, _)| t)
    }

    /// Draws the scene of `view` as `camera` sees it, anti-aliased, `key.size` pixels in
    /// `format`, unless the picture kept ([`Still::kept`]) is already of `key`.
    pub(super) fn draw(
        &mut self,
        gpu: &Gpu,
        view: &View,
        camera: &Camera,
        key: Key,
        format: wgpu::TextureFormat,
    ) {
        if self.image.as_ref().is_some_and(|(_, k)| *k == key) {
            return;
        }
        let [width, height] = key.size.map(|s| s.max(1));
        let texture = match self.image.take() {
            Some((t, _)) if t.width() == width && t.height() == height => t,
            _ => crate::render::colour_target(
                gpu,
                "still frame",
                [width, height],
                format,
                wgpu::TextureUsages::COPY_SRC,
                &[format.add_srgb_suffix()],
            ),
        };
        self.scene
            .prepare(gpu, view, camera, width as f32 / height as f32);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.scene.render_to(gpu, &mut encoder, &texture);
        gpu.queue.submit(Some(encoder.finish()));
        self.image = Some((texture, key));
    }
}
