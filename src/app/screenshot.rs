//! `--screenshot`: the frame rendered once more into a texture and read back.

use super::WindowState;
use crate::render;
use anyhow::Result;

impl WindowState {
    /// The frame (scene and panels) rendered once more into a texture and read back.
    pub fn capture(
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
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[self.config.format.add_srgb_suffix()],
        });
        self.draw(&texture, primitives, screen);
        Ok(render::image::read_texture(&self.gpu, &texture)?)
    }
}
