//! `--screenshot`: the frame rendered once more into a texture, saved as PNG, and a report
//! of what it shows for tests and scripts (the command line prints it).

use super::window::WindowState;
use crate::render;
use anyhow::Result;
use std::path::Path;

/// What a screenshot shows.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Report {
    /// Where it was saved.
    pub screenshot: String,
    /// Its size in pixels.
    pub width: u32,
    /// Its size in pixels.
    pub height: u32,
    /// Frames drawn with the puppet.
    pub frames: u32,
    /// The selected sections.
    pub selection: Vec<String>,
    /// Turned sections as `name:degrees`.
    pub turned: Vec<String>,
    /// The graphics adapter.
    pub adapter: String,
}

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
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[self.config.format.add_srgb_suffix()],
        });
        self.draw(&texture, primitives, screen);
        Ok(render::image::read_texture(&self.gpu, &texture)?)
    }

    /// What the screenshot at `path` shows.
    pub fn report(&self, path: &Path) -> Option<Report> {
        let s = self.session.as_ref()?;
        let sections = s.puppet.joints.sections();
        let turned = s
            .local
            .iter()
            .enumerate()
            .map(|(i, l)| (i, l.rotation.angle_between(glam::DQuat::IDENTITY)))
            .filter(|&(_, angle)| angle > 1e-6)
            .map(|(i, angle)| format!("{}:{:.1}", sections[i].name, angle.to_degrees()))
            .collect();
        Some(Report {
            screenshot: path.display().to_string(),
            width: self.config.width,
            height: self.config.height,
            frames: self.frames + 1,
            selection: s
                .selection
                .iter()
                .map(|&i| sections[i].name.clone())
                .collect(),
            turned,
            adapter: self.gpu.adapter.get_info().name,
        })
    }
}
