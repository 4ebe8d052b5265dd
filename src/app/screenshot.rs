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
        let texture = render::colour_target(
            &self.gpu,
            "screenshot",
            [self.config.width, self.config.height],
            self.config.format,
            wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST,
            &[self.config.format.add_srgb_suffix()],
        );
        self.draw(&texture, primitives, screen);
        Ok(render::image::read_texture(&self.gpu, &texture)?)
    }
}
