//! Edges smoothed after the scene is drawn (FXAA, `shaders/fxaa.wgsl`): the anti-aliasing
//! a software rasterizer can afford while the puppet moves. [`MSAA`](super::scene::MSAA)
//! samples cost llvmpipe two to three times the frame; this pass costs one read of the
//! picture, over the surface's box on screen (`puppet bench draw`). The scene is drawn with
//! one sample; the pixels the pass reads are copied out of the target, and it writes them
//! back smoothed.

use super::buffers::GrowBuffer;
use super::pipelines::{linear_sampler, sampler_entry, texture_entry};
use super::Gpu;
use glam::{Mat4, Vec2, Vec3};

/// The pass and the copy of the scene it reads.
pub(super) struct Fxaa {
    /// The plain format of the scene's (read and written by the pass: the values as
    /// stored, no sRGB conversion a texel).
    plain: wgpu::TextureFormat,
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// The copy of the scene the pass reads, at the size last drawn, and its bind group.
    scene: Option<(wgpu::Texture, wgpu::BindGroup)>,
    /// The cells the pass draws, two triangles each, in normalized device coordinates.
    cells: GrowBuffer,
    cpu_cells: Vec<[f32; 2]>,
    /// Where the last frame's edges are ([`Fxaa::find`]).
    found: Cells,
}

impl Fxaa {
    /// The pass for a scene drawn in `format`, into targets of that format or its plain
    /// one.
    pub(super) fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Fxaa {
        let plain = format.remove_srgb_suffix();
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("fxaa.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/fxaa.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fxaa"),
            entries: &[texture_entry(0), sampler_entry(1)],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fxaa"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("fxaa"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_cells"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 8,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x2],
                })],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_fxaa"),
                compilation_options: Default::default(),
                targets: &[Some(plain.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let sampler = linear_sampler(device, "fxaa");
        Fxaa {
            plain,
            pipeline,
            layout,
            sampler,
            scene: None,
            cells: GrowBuffer::new(device, "fxaa cells", wgpu::BufferUsages::VERTEX),
            cpu_cells: Vec::new(),
            found: Cells::default(),
        }
    }

    /// Finds the cells with edges of the surface to smooth ([`edge_rects`]) on a target
    /// of `size`, for the next [`Fxaa::smooth`].
    pub(super) fn find(
        &mut self,
        (positions, normals, triangles): (&[Vec3], &[Vec3], &[[u32; 3]]),
        view_proj: Mat4,
        eye: Vec3,
        size: [u32; 2],
    ) {
        let found = &mut self.found;
        edge_rects(positions, normals, triangles, view_proj, eye, size, found);
    }

    /// Records the pass over the cells [`Fxaa::find`] found of `target`'s pixels, which
    /// holds the scene (of their size, viewable in the plain format, with `COPY_SRC`):
    /// the pixels the pass reads are copied out first, then the cells' are written back
    /// smoothed.
    pub(super) fn smooth(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Texture,
    ) {
        let rects = &self.found.rects;
        let size = [target.width(), target.height()];
        let inside =
            |&[x, y, w, h]: &[u32; 4]| w > 0 && h > 0 && x + w <= size[0] && y + h <= size[1];
        if rects.is_empty() || !rects.iter().all(inside) {
            return;
        }
        // Their box, grown by what the pass reads around a pixel: what is copied.
        let (mut lo, mut hi) = ([u32::MAX; 2], [0u32; 2]);
        for &[x, y, w, h] in rects {
            lo = [lo[0].min(x), lo[1].min(y)];
            hi = [hi[0].max(x + w), hi[1].max(y + h)];
        }
        self.cpu_cells.clear();
        let ndc = |x: u32, y: u32| {
            [
                x as f32 / size[0] as f32 * 2.0 - 1.0,
                1.0 - y as f32 / size[1] as f32 * 2.0,
            ]
        };
        for &[x, y, w, h] in rects {
            let (a, b, c, d) = (ndc(x, y), ndc(x + w, y), ndc(x + w, y + h), ndc(x, y + h));
            self.cpu_cells.extend([a, b, c, a, c, d]);
        }
        self.cells.write(gpu, bytemuck::cast_slice(&self.cpu_cells));
        let stale = self
            .scene
            .as_ref()
            .is_some_and(|(t, _)| [t.width(), t.height()] != size);
        if stale {
            self.scene = None;
        }
        let (scene, group) = self.scene.get_or_insert_with(|| {
            let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("scene before fxaa"),
                size: target.size(),
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: self.plain,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            let read = texture.create_view(&Default::default());
            let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("fxaa"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&read),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Sampler(&self.sampler),
                    },
                ],
            });
            (texture, group)
        });
        let (x0, y0) = (lo[0].saturating_sub(REACH), lo[1].saturating_sub(REACH));
        let (x1, y1) = ((hi[0] + REACH).min(size[0]), (hi[1] + REACH).min(size[1]));
        let origin = wgpu::Origin3d { x: x0, y: y0, z: 0 };
        encoder.copy_texture_to_texture(
            wgpu::TexelCopyTextureInfo {
                origin,
                ..target.as_image_copy()
            },
            wgpu::TexelCopyTextureInfo {
                origin,
                ..scene.as_image_copy()
            },
            wgpu::Extent3d {
                width: x1 - x0,
                height: y1 - y0,
                depth_or_array_layers: 1,
            },
        );
        let view = target.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.plain),
            ..Default::default()
        });
        let mut pass = super::colour_pass(encoder, "fxaa", &view, wgpu::LoadOp::Load);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &*group, &[]);
        pass.set_vertex_buffer(0, self.cells.buffer.slice(..));
        pass.draw(0..self.cpu_cells.len() as u32, 0..1);
    }
}

/// How far (pixels) from a pixel the pass reads (`SPAN_MAX` in `shaders/fxaa.wgsl`, and
/// one).
const REACH: u32 = 9;

/// The cells [`edge_rects`] found, and its scratch, kept from frame to frame.
#[derive(Debug, Default)]
pub(super) struct Cells {
    /// Whether each vertex's normal faces the eye.
    facing: Vec<bool>,
    /// Each cell of the target, row by row: whether the pass runs over it.
    marked: Vec<bool>,
    /// The marked cells as runs along each row: x, y, width, height in pixels.
    pub rects: Vec<[u32; 4]>,
}

/// Side (pixels) of the cells the pass runs over.
const CELL: u32 = 8;

/// How far (pixels) around a triangle on the silhouette its cells reach.
const MARGIN: f32 = 3.0;

/// The pixels (x, y, width, height) with edges of the surface to smooth on a target of
/// `size`, seen through `view_proj` from `eye`: the cells of [`CELL`] pixels over the
/// triangles the silhouette crosses (their corners' normals face the eye on one side and
/// away on the other: where the surface turns away, and where a part passes in front of
/// another), grown by [`MARGIN`], merged into runs along each row. A software
/// rasterizer pays the pass by the pixel: on Spot 1280 × 800 the cells are a fraction of
/// its box on screen (`puppet bench draw`). The whole target where some corner lies
/// behind the eye. Into `cells.rects`.
pub(super) fn edge_rects(
    positions: &[Vec3],
    normals: &[Vec3],
    triangles: &[[u32; 3]],
    view_proj: Mat4,
    eye: Vec3,
    [width, height]: [u32; 2],
    cells: &mut Cells,
) {
    let (cols, rows) = (
        width.div_ceil(CELL) as usize,
        height.div_ceil(CELL) as usize,
    );
    let Cells {
        facing,
        marked,
        rects,
    } = cells;
    rects.clear();
    marked.clear();
    marked.resize(cols * rows, false);
    facing.clear();
    facing.extend(
        positions
            .iter()
            .zip(normals)
            .map(|(&p, &n)| n.dot(eye - p) > 0.0),
    );
    let size = Vec2::new(width as f32, height as f32);
    let pixel = |i: u32| -> Option<Vec2> {
        let clip = view_proj * positions.get(i as usize)?.extend(1.0);
        (clip.w > 1e-6).then(|| {
            let ndc = Vec2::new(clip.x, clip.y) / clip.w;
            Vec2::new(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 * size
        })
    };
    for t in triangles {
        let f = t.map(|i| facing.get(i as usize).copied().unwrap_or(true));
        if f[0] == f[1] && f[1] == f[2] {
            continue;
        }
        let (Some(a), Some(b), Some(c)) = (pixel(t[0]), pixel(t[1]), pixel(t[2])) else {
            rects.push([0, 0, width, height]);
            return;
        };
        let lo = (a.min(b).min(c) - MARGIN).max(Vec2::ZERO);
        let hi = (a.max(b).max(c) + MARGIN).min(size - 1.0);
        if !(lo.cmple(hi).all()) {
            continue;
        }
        let (c0, r0) = ((lo.x as u32 / CELL) as usize, (lo.y as u32 / CELL) as usize);
        let (c1, r1) = ((hi.x as u32 / CELL) as usize, (hi.y as u32 / CELL) as usize);
        for r in r0..=r1.min(rows - 1) {
            marked[r * cols + c0..=r * cols + c1.min(cols - 1)].fill(true);
        }
    }
    for r in 0..rows {
        let row = &marked[r * cols..(r + 1) * cols];
        let mut c = 0;
        while c < cols {
            if !row[c] {
                c += 1;
                continue;
            }
            let start = c;
            while c < cols && row[c] {
                c += 1;
            }
            let (x, y) = (start as u32 * CELL, r as u32 * CELL);
            rects.push([
                x,
                y,
                (c as u32 * CELL).min(width) - x,
                ((r as u32 + 1) * CELL).min(height) - y,
            ]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a sphere framed in the view, the cells follow its outline: every pixel of it
    /// lies in one, its middle in none, and they are a small share of the picture.
    #[test]
    fn the_cells_follow_the_outline() {
        let mesh = crate::mesh::shapes::icosphere(1.0, 4);
        let positions: Vec<Vec3> = mesh.positions.iter().map(|p| p.as_vec3()).collect();
        // (On a sphere about the origin the normal is the position.)
        let normals: Vec<Vec3> = positions.iter().map(|p| p.normalize()).collect();
        let mut camera = crate::session::Camera::default();
        camera.frame(Vec3::splat(-1.0), Vec3::splat(1.0));
        let size = [640, 400];
        let view_proj = camera.view_proj(640.0 / 400.0);
        let eye = camera.eye();
        let mut cells = Cells::default();
        edge_rects(
            &positions,
            &normals,
            &mesh.triangles,
            view_proj,
            eye,
            size,
            &mut cells,
        );
        let rects = cells.rects.clone();
        let inside = |p: Vec2| {
            rects.iter().any(|&[x, y, w, h]| {
                p.x >= x as f32 && p.x < (x + w) as f32 && p.y >= y as f32 && p.y < (y + h) as f32
            })
        };
        let to_pixel = |p: Vec3| {
            let c = view_proj * p.extend(1.0);
            let n = Vec2::new(c.x, c.y) / c.w;
            Vec2::new(n.x + 1.0, 1.0 - n.y) * 0.5 * Vec2::new(640.0, 400.0)
        };
        // The outline: where the sphere's surface turns from the eye.
        let (right, up) = (
            camera.view().inverse().transform_vector3(Vec3::X),
            camera.view().inverse().transform_vector3(Vec3::Y),
        );
        let d = eye.length();
        let rim = (1.0 - 1.0 / (d * d)).sqrt();
        let centre = eye.normalize() / d;
        for k in 0..64 {
            let a = k as f32 / 64.0 * std::f32::consts::TAU;
            let p = centre + (right * a.cos() + up * a.sin()) * rim;
            assert!(
                inside(to_pixel(p)),
                "the outline's pixel at {a:.2} rad is in no cell"
            );
        }
        assert!(!inside(to_pixel(Vec3::ZERO)), "the middle is in a cell");
        let area: u32 = rects.iter().map(|r| r[2] * r[3]).sum();
        assert!(
            f64::from(area) < 0.2 * 640.0 * 400.0,
            "the cells cover {area} of 256,000 pixels"
        );
        // Whole, gone to NaN, partly behind the eye, or far off screen: cells within the
        // target, no panic.
        let mut broken = positions.clone();
        broken[7] = Vec3::NAN;
        let behind = positions.iter().map(|&p| p + eye * 1.5).collect::<Vec<_>>();
        let far = positions.iter().map(|&p| p * 1e30).collect::<Vec<_>>();
        for (what, p) in [
            ("whole", &positions),
            ("NaN", &broken),
            ("behind", &behind),
            ("far", &far),
        ] {
            edge_rects(
                p,
                &normals,
                &mesh.triangles,
                view_proj,
                eye,
                size,
                &mut cells,
            );
            for &[x, y, w, h] in &cells.rects {
                assert!(w > 0 && h > 0 && x + w <= 640 && y + h <= 400, "{what}");
            }
        }
    }
}
