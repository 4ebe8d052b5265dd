//! [`SceneRenderer`]: draws what a core [`View`] describes. Resources are created once
//! ([`SceneRenderer::new`]), [`SceneRenderer::prepare`] uploads only what the view's
//! revision counters say changed, [`SceneRenderer::paint`] records the draws.

use super::buffers::{GrowBuffer, LineVertex, SurfaceVertex, Uniforms};
use super::pipelines::Pipelines;
use super::{Gpu, BACKGROUND, DEPTH_FORMAT};
use crate::session::view::{Line, Revisions};
use crate::session::{Camera, View};
use glam::Vec3;

/// The GPU side of drawing a puppet.
pub struct SceneRenderer {
    encode_gamma: bool,
    pipelines: Pipelines,
    vertices: GrowBuffer,
    colors: GrowBuffer,
    indices: GrowBuffer,
    index_count: u32,
    lines: GrowBuffer,
    line_count: u32,
    top: GrowBuffer,
    top_count: u32,
    depth: Option<(wgpu::Texture, wgpu::TextureView)>,
    /// What the last `prepare` uploaded, to skip work when nothing changed.
    seen: Option<Revisions>,
    /// Uploads done by the last `prepare` (for tests and the idle measurement).
    pub last_uploads: usize,
    cpu_vertices: Vec<SurfaceVertex>,
    cpu_normals: Vec<Vec3>,
    cpu_colors: Vec<[f32; 4]>,
    cpu_lines: Vec<Line>,
    cpu_top: Vec<Line>,
    gpu_lines: Vec<LineVertex>,
}

impl SceneRenderer {
    /// Creates pipelines and buffers for drawing into targets of `format`.
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> SceneRenderer {
        let device = &gpu.device;
        let vertex = wgpu::BufferUsages::VERTEX;
        SceneRenderer {
            encode_gamma: !format.is_srgb(),
            pipelines: Pipelines::new(device, format),
            vertices: GrowBuffer::new(device, "surface vertices", vertex),
            colors: GrowBuffer::new(device, "surface colours", vertex),
            indices: GrowBuffer::new(device, "surface indices", wgpu::BufferUsages::INDEX),
            index_count: 0,
            lines: GrowBuffer::new(device, "overlay lines", vertex),
            line_count: 0,
            top: GrowBuffer::new(device, "overlay lines on top", vertex),
            top_count: 0,
            depth: None,
            seen: None,
            last_uploads: 0,
            cpu_vertices: Vec::new(),
            cpu_normals: Vec::new(),
            cpu_colors: Vec::new(),
            cpu_lines: Vec::new(),
            cpu_top: Vec::new(),
            gpu_lines: Vec::new(),
        }
    }

    /// The depth buffer for a target of `width × height`, recreated when the size changes.
    fn depth_view(&mut self, gpu: &Gpu, width: u32, height: u32) -> &wgpu::TextureView {
        let stale = self
            .depth
            .as_ref()
            .is_none_or(|(t, _)| t.width() != width || t.height() != height);
        if stale {
            let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("depth"),
                size: wgpu::Extent3d {
                    width: width.max(1),
                    height: height.max(1),
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: DEPTH_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            });
            let view = texture.create_view(&Default::default());
            self.depth = Some((texture, view));
        }
        &self.depth.get_or_insert_with(|| unreachable!()).1
    }

    /// Uploads the camera, and what changed since the last call (another puppet re-uploads
    /// everything).
    pub fn prepare(&mut self, gpu: &Gpu, view: &View, camera: &Camera, aspect: f32) {
        let eye = camera.eye();
        let light = (camera
            .view()
            .inverse()
            .transform_vector3(Vec3::new(0.4, 0.8, 0.6)))
        .normalize();
        let u = Uniforms {
            view_proj: camera.view_proj(aspect).to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
            light: light
                .extend(if self.encode_gamma { 1.0 } else { 0.0 })
                .to_array(),
        };
        gpu.queue
            .write_buffer(&self.pipelines.uniforms, 0, bytemuck::bytes_of(&u));

        let now = view.revisions();
        let before = self.seen.replace(now);
        self.last_uploads = 0;
        let changed = |f: fn(&Revisions) -> u64| before.is_none_or(|b| f(&b) != f(&now));
        let new_puppet = changed(|r| r.puppet);
        if new_puppet {
            let indices: Vec<u32> = view.triangles().iter().flatten().copied().collect();
            self.indices.write(gpu, bytemuck::cast_slice(&indices));
            self.index_count = indices.len() as u32;
            self.last_uploads += 1;
        }
        if new_puppet || changed(|r| r.surface) {
            self.update_vertices(view);
            self.vertices
                .write(gpu, bytemuck::cast_slice(&self.cpu_vertices));
            self.last_uploads += 1;
        }
        if new_puppet || changed(|r| r.colours) {
            view.colours(&mut self.cpu_colors);
            self.colors
                .write(gpu, bytemuck::cast_slice(&self.cpu_colors));
            self.last_uploads += 1;
        }
        if new_puppet || changed(|r| r.overlays) {
            view.lines(&mut self.cpu_lines, &mut self.cpu_top);
            self.line_count =
                upload_lines(gpu, &mut self.lines, &self.cpu_lines, &mut self.gpu_lines);
            self.top_count = upload_lines(gpu, &mut self.top, &self.cpu_top, &mut self.gpu_lines);
            self.last_uploads += 1;
        }
    }

    /// Positions and area-weighted normals of the current surface.
    fn update_vertices(&mut self, view: &View) {
        let x = view.positions();
        let n = x.len();
        self.cpu_vertices.clear();
        self.cpu_vertices.resize(n, SurfaceVertex::default());
        let normals = &mut self.cpu_normals;
        normals.clear();
        normals.resize(n, Vec3::ZERO);
        for t in view.triangles() {
            let [a, b, c] = t.map(|i| x.get(i as usize));
            let face = (b - a).cross(c - a);
            for &i in t {
                normals[i as usize] += face;
            }
        }
        for (i, v) in self.cpu_vertices.iter_mut().enumerate() {
            v.position = x.get(i).to_array();
            v.normal = normals[i].normalize_or(Vec3::Y).to_array();
        }
    }

    /// Records the scene into `pass` (cleared colour and depth are the caller's).
    pub fn paint(&self, pass: &mut wgpu::RenderPass<'_>) {
        let p = &self.pipelines;
        pass.set_bind_group(0, &p.bind_group, &[]);
        if self.index_count > 0 {
            pass.set_pipeline(&p.surface);
            pass.set_vertex_buffer(0, self.vertices.buffer.slice(..));
            pass.set_vertex_buffer(1, self.colors.buffer.slice(..));
            pass.set_index_buffer(self.indices.buffer.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
        if self.line_count > 0 {
            pass.set_pipeline(&p.lines);
            pass.set_vertex_buffer(0, self.lines.buffer.slice(..));
            pass.draw(0..self.line_count, 0..1);
        }
        if self.top_count > 0 {
            pass.set_pipeline(&p.top);
            pass.set_vertex_buffer(0, self.top.buffer.slice(..));
            pass.draw(0..self.top_count, 0..1);
        }
    }

    /// Begins a pass on `color` (cleared to the background) with this renderer's depth
    /// buffer and paints the scene.
    pub fn render_to(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        width: u32,
        height: u32,
    ) {
        self.depth_view(gpu, width, height);
        let Some((_, depth)) = &self.depth else {
            return;
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(BACKGROUND),
                    store: wgpu::StoreOp::Store,
                },
                depth_slice: None,
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        self.paint(&mut pass);
    }
}

/// Writes `lines` into `buffer` as line-list vertices (through `scratch`); returns the
/// vertex count.
fn upload_lines(
    gpu: &Gpu,
    buffer: &mut GrowBuffer,
    lines: &[Line],
    scratch: &mut Vec<LineVertex>,
) -> u32 {
    scratch.clear();
    scratch.extend(lines.iter().flat_map(|l| {
        [l.a, l.b].map(|p| LineVertex {
            position: p.to_array(),
            color: l.color,
        })
    }));
    buffer.write(gpu, bytemuck::cast_slice(scratch));
    scratch.len() as u32
}
