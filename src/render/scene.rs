//! [`SceneRenderer`]: draws what a core [`View`] describes. Resources are created once
//! ([`SceneRenderer::new`]), [`SceneRenderer::prepare`] uploads only what the view's
//! revision counters say changed, [`SceneRenderer::paint`] records the draws.
//!
//! A frame is two passes: the shadow map (the surface's depth seen down the ground's up,
//! only when the surface or the ground moved), then the scene into a multisampled target
//! ([`MSAA`] samples where the adapter has them, else one) resolved into the caller's.
//! A renderer made [`SceneRenderer::with_fxaa`] draws one sample and smooths the edges
//! after: the surface and the ground into the caller's target, the cells the silhouette
//! crosses smoothed there (`render::fxaa`), then the overlays over them, crisp.
//! A closed surface turned outward (most puppets: loading closes holes and turns parts
//! inside out the right way) is drawn without the faces turned away from the eye, which
//! never show; an open one with both sides, its inside lit as seen.

use super::buffers::{GrowBuffer, LineVertex, SurfaceVertex, Uniforms};
use super::fxaa::Fxaa;
use super::pipelines::Pipelines;
use super::{Gpu, BACKGROUND, DEPTH_FORMAT};
use crate::geom::occlusion::Occluders;
use crate::session::view::{Ground, Lighting, Line, Revisions};
use crate::session::{Camera, View};
use glam::{Mat4, Vec3};

/// Samples a pixel where the adapter supports them for the target and depth formats.
pub const MSAA: u32 = 4;

/// Whether the adapter draws [`MSAA`] samples a pixel into `format` and the depth buffer.
pub fn msaa_supported(gpu: &Gpu, format: wgpu::TextureFormat) -> bool {
    let supported = |f| {
        gpu.adapter
            .get_texture_format_features(f)
            .flags
            .sample_count_supported(MSAA)
    };
    supported(format) && supported(DEPTH_FORMAT)
}

/// Whether the window draws [`MSAA`] samples by default: where the adapter supports them
/// and is a GPU. A software rasterizer (llvmpipe) covers every sample of every triangle,
/// and [`MSAA`] samples cost it two to three times the frame (`puppet bench draw`), so
/// there it smooths the moving view's edges with FXAA instead
/// ([`crate::render::AntiAliasing`]) and the panel can choose samples.
pub fn window_msaa(gpu: &Gpu, format: wgpu::TextureFormat) -> bool {
    gpu.adapter.get_info().device_type != wgpu::DeviceType::Cpu && msaa_supported(gpu, format)
}

/// The key, fill and rim lights' directions in the camera's frame (x right, y up, z
/// towards the viewer): the key high on one side, the fill low on the other, the rim
/// behind and above.
const KEY: Vec3 = Vec3::new(0.4, 0.8, 0.6);
const FILL: Vec3 = Vec3::new(-0.7, 0.1, 0.5);
const RIM: Vec3 = Vec3::new(-0.2, 0.5, -1.0);

/// A matcap's look ([`Lighting`]): its light in the camera's frame, how far the light
/// wraps round the shape, the ambient, the rim, the highlight and its exponent, and how
/// much of the rim takes the part's colour.
struct Matcap {
    light: Vec3,
    wrap: f32,
    ambient: f32,
    rim: f32,
    highlight: f32,
    exponent: f32,
    tint: f32,
}

/// The matcap a lighting reads from (`None`: the studio's lights).
fn matcap(lighting: Lighting) -> Option<Matcap> {
    match lighting {
        Lighting::Studio => None,
        Lighting::Clay => Some(Matcap {
            light: Vec3::new(-0.65, 0.55, 0.5),
            wrap: 0.0,
            ambient: 0.14,
            rim: 0.12,
            highlight: 0.08,
            exponent: 20.0,
            tint: 0.0,
        }),
        Lighting::Jelly => Some(Matcap {
            light: Vec3::new(-0.4, 0.6, 0.7),
            wrap: 0.5,
            ambient: 0.08,
            rim: 0.55,
            highlight: 0.6,
            exponent: 90.0,
            tint: 1.0,
        }),
    }
}

/// How far above the ground (in the ground's half sides) an occluder's shadow has
/// faded to its lightest.
const SHADOW_FADE: f32 = 0.75;

/// The GPU side of drawing a puppet.
pub struct SceneRenderer {
    encode_gamma: bool,
    format: wgpu::TextureFormat,
    samples: u32,
    /// Edges smoothed after a one-sample scene ([`SceneRenderer::with_fxaa`]).
    fxaa: Option<Fxaa>,
    /// The surface's triangles (kept with FXAA, which finds the edges to smooth on
    /// them), and the last `prepare`'s camera: its eye and its view and projection.
    cpu_triangles: Vec<[u32; 3]>,
    eye: Vec3,
    view_proj: Mat4,
    pipelines: Pipelines,
    /// The multisampled colour target (with more than one sample).
    target: Option<(wgpu::Texture, wgpu::TextureView)>,
    /// The ground of the last `prepare`, whether the shadow map shows the surface as it is
    /// now, and the ground it was drawn for.
    ground: Option<Ground>,
    /// The surface is lit by a matcap (the last `prepare`'s [`Lighting`]).
    matcap: bool,
    shadow_fresh: bool,
    shadow_ground: Option<Ground>,
    vertices: GrowBuffer,
    colors: GrowBuffer,
    indices: GrowBuffer,
    index_count: u32,
    /// The surface is closed and turned outward: its back faces are skipped.
    closed: bool,
    /// Draw the back faces of a closed surface too ([`SceneRenderer::draw_back_faces`]).
    back_faces: bool,
    /// The surface coarsened for the shadow map ([`shadow_triangles`]).
    shadow_indices: GrowBuffer,
    shadow_count: u32,
    lines: GrowBuffer,
    line_count: u32,
    top: GrowBuffer,
    top_count: u32,
    depth: Option<(wgpu::Texture, wgpu::TextureView)>,
    /// What the last `prepare` uploaded, to skip work when nothing changed.
    seen: Option<Revisions>,
    /// Uploads done by the last `prepare` (for tests and the idle measurement).
    pub last_uploads: usize,
    /// Shadow map passes recorded so far (for tests: one per change of the surface).
    pub shadow_passes: usize,
    cpu_vertices: Vec<SurfaceVertex>,
    cpu_normals: Vec<Vec3>,
    /// The medial balls that shade creases, made for each new puppet (and its sections)
    /// while the view asks for them, and the surface's occlusion.
    occluders: Option<Occluders>,
    /// Whether the vertices last uploaded were shaded in creases.
    occluding: bool,
    cpu_positions: Vec<Vec3>,
    cpu_occlusion: Vec<f32>,
    cpu_colors: Vec<[f32; 4]>,
    cpu_lines: Vec<Line>,
    cpu_top: Vec<Line>,
    gpu_lines: Vec<LineVertex>,
}

impl SceneRenderer {
    /// Creates pipelines and buffers for drawing into targets of `format`, with [`MSAA`]
    /// samples a pixel where the adapter supports them, else one (images: quality first).
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> SceneRenderer {
        let samples = if msaa_supported(gpu, format) { MSAA } else { 1 };
        SceneRenderer::with_samples(gpu, format, samples)
    }

    /// [`SceneRenderer::new`] with `samples` samples a pixel (1: no anti-aliasing).
    pub fn with_samples(gpu: &Gpu, format: wgpu::TextureFormat, samples: u32) -> SceneRenderer {
        let device = &gpu.device;
        let vertex = wgpu::BufferUsages::VERTEX;
        let samples = samples.max(1);
        SceneRenderer {
            encode_gamma: !format.is_srgb(),
            format,
            samples,
            fxaa: None,
            cpu_triangles: Vec::new(),
            eye: Vec3::ZERO,
            view_proj: Mat4::IDENTITY,
            pipelines: Pipelines::new(device, format, samples),
            target: None,
            ground: None,
            matcap: false,
            shadow_fresh: false,
            shadow_ground: None,
            vertices: GrowBuffer::new(device, "surface vertices", vertex),
            colors: GrowBuffer::new(device, "surface colours", vertex),
            indices: GrowBuffer::new(device, "surface indices", wgpu::BufferUsages::INDEX),
            index_count: 0,
            closed: false,
            back_faces: false,
            shadow_indices: GrowBuffer::new(
                device,
                "shadow map indices",
                wgpu::BufferUsages::INDEX,
            ),
            shadow_count: 0,
            lines: GrowBuffer::new(device, "overlay lines", vertex),
            line_count: 0,
            top: GrowBuffer::new(device, "overlay lines on top", vertex),
            top_count: 0,
            depth: None,
            seen: None,
            last_uploads: 0,
            shadow_passes: 0,
            cpu_vertices: Vec::new(),
            cpu_normals: Vec::new(),
            occluders: None,
            occluding: false,
            cpu_positions: Vec::new(),
            cpu_occlusion: Vec::new(),
            cpu_colors: Vec::new(),
            cpu_lines: Vec::new(),
            cpu_top: Vec::new(),
            gpu_lines: Vec::new(),
        }
    }

    /// A renderer that draws one sample a pixel and smooths the edges after (FXAA): the
    /// anti-aliasing a software rasterizer affords while the puppet moves (`puppet bench
    /// draw`).
    pub fn with_fxaa(gpu: &Gpu, format: wgpu::TextureFormat) -> SceneRenderer {
        SceneRenderer {
            fxaa: Some(Fxaa::new(&gpu.device, format)),
            ..SceneRenderer::with_samples(gpu, format, 1)
        }
    }

    /// Samples a pixel this renderer draws with.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Whether this renderer smooths edges after drawing ([`SceneRenderer::with_fxaa`]).
    pub fn fxaa(&self) -> bool {
        self.fxaa.is_some()
    }

    /// The depth buffer and, with more than one sample, the multisampled colour target
    /// for a target of `width × height`, recreated when the size changes.
    fn size_targets(&mut self, gpu: &Gpu, width: u32, height: u32) {
        let texture = |label, format| {
            let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: width.max(1),
                    height: height.max(1),
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: self.samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            });
            let view = texture.create_view(&Default::default());
            (texture, view)
        };
        let stale = |t: &Option<(wgpu::Texture, wgpu::TextureView)>| {
            t.as_ref()
                .is_none_or(|(t, _)| t.width() != width.max(1) || t.height() != height.max(1))
        };
        if stale(&self.depth) {
            self.depth = Some(texture("depth", DEPTH_FORMAT));
        }
        if self.samples > 1 && stale(&self.target) {
            self.target = Some(texture("multisampled colour", self.format));
        }
    }

    /// Uploads the camera, and what changed since the last call (another puppet re-uploads
    /// everything).
    pub fn prepare(&mut self, gpu: &Gpu, view: &View, camera: &Camera, aspect: f32) {
        let eye = camera.eye();
        let to_world = camera.view().inverse();
        let light = |v: Vec3| to_world.transform_vector3(v).normalize().extend(0.0);
        let now = view.revisions();
        let before = self.seen.replace(now);
        self.last_uploads = 0;
        let changed = |f: fn(&Revisions) -> u64| before.is_none_or(|b| f(&b) != f(&now));
        let new_puppet = changed(|r| r.puppet);
        // The ground moves only with the puppet, the floor or its own switch (all in the
        // overlays' counter): a pass over the vertices, not done every frame.
        if new_puppet || changed(|r| r.overlays) {
            self.ground = view.ground();
        }
        let ground = self.ground;
        let g = ground.unwrap_or(Ground {
            centre: Vec3::ZERO,
            up: camera.up,
            across: [Vec3::X, Vec3::Z],
            half: 1.0,
            spacing: 1.0,
        });
        let look = matcap(view.lighting());
        let view_proj = camera.view_proj(aspect);
        let u = Uniforms {
            view_proj: view_proj.to_cols_array_2d(),
            shadow_proj: shadow_proj(&g).to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
            key: light(KEY)
                .with_w(if self.encode_gamma { 1.0 } else { 0.0 })
                .to_array(),
            fill: light(FILL).to_array(),
            rim: light(RIM).to_array(),
            up: g
                .up
                .normalize_or(Vec3::Y)
                .extend(if ground.is_some() { 1.0 } else { 0.0 })
                .to_array(),
            ground: g.centre.extend(g.half).to_array(),
            across_a: g.across[0].extend(g.spacing).to_array(),
            across_b: g.across[1].extend(SHADOW_FADE * g.half).to_array(),
            camera_right: to_world
                .transform_vector3(Vec3::X)
                .normalize()
                .extend(look.as_ref().map_or(0.0, |m| m.tint))
                .to_array(),
            camera_up: to_world
                .transform_vector3(Vec3::Y)
                .normalize()
                .extend(0.0)
                .to_array(),
            matcap_light: look
                .as_ref()
                .map_or(Vec3::Z, |m| m.light.normalize())
                .extend(look.as_ref().map_or(0.0, |m| m.wrap))
                .to_array(),
            matcap_terms: look
                .as_ref()
                .map_or([0.0; 4], |m| [m.ambient, m.rim, m.highlight, m.exponent]),
        };
        self.matcap = look.is_some();
        gpu.queue
            .write_buffer(&self.pipelines.uniforms, 0, bytemuck::bytes_of(&u));
        if new_puppet || changed(|r| r.surface) {
            self.shadow_fresh = false;
        }
        if new_puppet {
            let indices: Vec<u32> = view.triangles().iter().flatten().copied().collect();
            self.cpu_triangles.clear();
            if self.fxaa.is_some() {
                self.cpu_triangles.extend_from_slice(view.triangles());
            }
            self.indices.write(gpu, bytemuck::cast_slice(&indices));
            self.index_count = indices.len() as u32;
            self.closed = view.closed();
            let coarse = shadow_triangles(view);
            self.shadow_indices
                .write(gpu, bytemuck::cast_slice(&coarse));
            self.shadow_count = coarse.len() as u32;
            self.last_uploads += 1;
        }
        // Other sections: other balls shade each part (see `geom::occlusion`).
        let layout = changed(|r| r.layout);
        if new_puppet || layout {
            self.occluders = None;
        }
        if self.occluders.is_none() && view.shades_creases() {
            self.occluders = Some(view.occluders());
        }
        // Creases shaded or not, or from other sections: the vertices again (the shadow
        // map stays).
        let occluding = view.shades_creases();
        if new_puppet || changed(|r| r.surface) || layout || occluding != self.occluding {
            self.occluding = occluding;
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
        (self.eye, self.view_proj) = (eye, view_proj);
    }

    /// Positions, area-weighted normals and (while the view shades creases) occlusion of
    /// the current surface.
    fn update_vertices(&mut self, view: &View) {
        let x = view.positions();
        self.cpu_positions.clear();
        self.cpu_positions.extend((0..x.len()).map(|i| x.get(i)));
        let (positions, normals) = (&self.cpu_positions, &mut self.cpu_normals);
        crate::mesh::area_normals_into(positions, view.triangles(), normals);
        self.cpu_vertices.clear();
        self.cpu_vertices
            .extend(
                positions
                    .iter()
                    .zip(normals.iter())
                    .map(|(p, n)| SurfaceVertex {
                        position: p.to_array(),
                        normal: n.to_array(),
                        occlusion: 0.0,
                    }),
            );
        match &mut self.occluders {
            Some(occluders) if view.shades_creases() => {
                occluders.shade(positions, normals, &mut self.cpu_occlusion);
                for (v, &o) in self.cpu_vertices.iter_mut().zip(&self.cpu_occlusion) {
                    v.occlusion = o;
                }
            }
            _ => {}
        }
    }

    /// Whether the surface's faces turned away from the eye are skipped: it is closed and
    /// turned outward, and [`SceneRenderer::draw_back_faces`] is off.
    pub fn skips_back_faces(&self) -> bool {
        self.closed && !self.back_faces
    }

    /// Draws the faces turned away from the eye even on a closed surface (a camera inside
    /// the puppet then sees its inside, at the cost of drawing every face).
    pub fn draw_back_faces(&mut self, on: bool) {
        self.back_faces = on;
    }

    /// Records the scene into `pass` (cleared colour and depth are the caller's, and the
    /// shadow map is [`SceneRenderer::render_shadow`]'s).
    pub fn paint(&self, pass: &mut wgpu::RenderPass<'_>) {
        self.paint_surface(pass);
        self.paint_overlays(pass);
    }

    /// Whether the view has overlay lines to draw.
    fn has_overlays(&self) -> bool {
        self.line_count > 0 || self.top_count > 0
    }

    /// Records the surface and the ground into `pass`.
    fn paint_surface(&self, pass: &mut wgpu::RenderPass<'_>) {
        let p = &self.pipelines;
        pass.set_bind_group(0, &p.bind_group, &[]);
        if self.index_count > 0 {
            pass.set_pipeline(match (self.skips_back_faces(), self.matcap) {
                (true, false) => &p.closed_surface,
                (false, false) => &p.surface,
                (true, true) => &p.closed_matcap,
                (false, true) => &p.matcap,
            });
            pass.set_vertex_buffer(0, self.vertices.buffer.slice(..));
            pass.set_vertex_buffer(1, self.colors.buffer.slice(..));
            pass.set_index_buffer(self.indices.buffer.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
        if self.ground.is_some() {
            pass.set_pipeline(&p.ground);
            pass.draw(0..6, 0..1);
        }
    }

    /// Records the overlay lines into `pass`, tested against the surface's depth.
    fn paint_overlays(&self, pass: &mut wgpu::RenderPass<'_>) {
        let p = &self.pipelines;
        pass.set_bind_group(0, &p.bind_group, &[]);
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

    /// Records the surface's depth into the shadow map, and from it the shade over the
    /// ground, when the surface or the ground moved since it last did (nothing without a
    /// ground).
    pub fn render_shadow(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if self.ground.is_none() || (self.shadow_fresh && self.shadow_ground == self.ground) {
            return;
        }
        self.shadow_fresh = true;
        self.shadow_ground = self.ground;
        self.shadow_passes += 1;
        let p = &self.pipelines;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow map"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &p.shadow_map,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if self.shadow_count > 0 {
            pass.set_pipeline(&p.shadow);
            pass.set_bind_group(0, &p.shadow_bind_group, &[]);
            pass.set_vertex_buffer(0, self.vertices.buffer.slice(..));
            pass.set_index_buffer(
                self.shadow_indices.buffer.slice(..),
                wgpu::IndexFormat::Uint32,
            );
            pass.draw_indexed(0..self.shadow_count, 0, 0..1);
        }
        drop(pass);
        let load = wgpu::LoadOp::Clear(wgpu::Color::BLACK);
        let mut pass = super::colour_pass(encoder, "shade", &p.shade_view, load);
        pass.set_pipeline(&p.shade);
        pass.set_bind_group(0, &p.shade_bind_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Renders the shadow map if it is stale, then draws the scene into `target` (cleared
    /// to the background; through the multisampled target, resolved into it) with this
    /// renderer's depth buffer. `target` is viewable in this renderer's format. With
    /// [`SceneRenderer::with_fxaa`] the surface and the ground go through the smoothing
    /// pass first, then the overlays are drawn over them, and `target` also gives copies
    /// and is viewable in its plain format.
    pub fn render_to(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Texture,
    ) {
        let (width, height) = (target.width(), target.height());
        self.render_shadow(encoder);
        self.size_targets(gpu, width, height);
        let color = target.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.format),
            ..Default::default()
        });
        if let Some(mut fxaa) = self.fxaa.take() {
            self.render_smoothed(gpu, encoder, &mut fxaa, target, &color);
            self.fxaa = Some(fxaa);
            return;
        }
        let Some((_, depth)) = &self.depth else {
            return;
        };
        let (view, resolve_target) = match &self.target {
            Some((_, multisampled)) if self.samples > 1 => (multisampled, Some(&color)),
            _ => (&color, None),
        };
        let clear = (wgpu::LoadOp::Clear(BACKGROUND), wgpu::LoadOp::Clear(1.0));
        let mut pass = scene_pass(
            encoder,
            "scene",
            (view, resolve_target),
            depth,
            clear,
            false,
        );
        self.paint(&mut pass);
    }

    /// [`SceneRenderer::render_to`] through `fxaa`: the surface and the ground into
    /// `target` through `color`, smoothed along the surface's edges, the overlays
    /// over that (tested against the surface's depth, kept from the first pass only when
    /// there are overlays).
    fn render_smoothed(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        fxaa: &mut Fxaa,
        target: &wgpu::Texture,
        color: &wgpu::TextureView,
    ) {
        let Some((_, depth)) = &self.depth else {
            return;
        };
        let (width, height) = (target.width(), target.height());
        let overlays = self.has_overlays();
        {
            let clear = (wgpu::LoadOp::Clear(BACKGROUND), wgpu::LoadOp::Clear(1.0));
            let mut pass = scene_pass(encoder, "scene", (color, None), depth, clear, overlays);
            self.paint_surface(&mut pass);
        }
        let surface = (
            &self.cpu_positions[..],
            &self.cpu_normals[..],
            &self.cpu_triangles[..],
        );
        fxaa.find(surface, self.view_proj, self.eye, [width, height]);
        fxaa.smooth(gpu, encoder, target);
        if overlays {
            let load = (wgpu::LoadOp::Load, wgpu::LoadOp::Load);
            let mut pass = scene_pass(encoder, "overlays", (color, None), depth, load, false);
            self.paint_overlays(&mut pass);
        }
    }
}

/// Begins a pass of the scene on `view` (resolved into `resolve` when multisampled), its
/// colour and depth loaded as `load` says, the depth kept after it when `keep_depth`.
fn scene_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    (view, resolve_target): (&wgpu::TextureView, Option<&wgpu::TextureView>),
    depth: &wgpu::TextureView,
    load: (wgpu::LoadOp<wgpu::Color>, wgpu::LoadOp<f32>),
    keep_depth: bool,
) -> wgpu::RenderPass<'e> {
    let keep = |kept| {
        if kept {
            wgpu::StoreOp::Store
        } else {
            wgpu::StoreOp::Discard
        }
    };
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            resolve_target,
            ops: wgpu::Operations {
                load: load.0,
                store: keep(resolve_target.is_none()),
            },
            depth_slice: None,
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations {
                load: load.1,
                store: keep(keep_depth),
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Cells across the bounding-box diagonal that the shadow's surface is coarsened to.
const SHADOW_CELLS: f32 = 64.0;

/// The surface's triangles coarsened for the shadow map, as indices into the same
/// vertices (so they move with it): each vertex stands for the first vertex in its cell of
/// a grid [`SHADOW_CELLS`] across the diagonal (at the positions when the puppet came),
/// and triangles whose corners fall in fewer than three cells are dropped. The shadow is
/// soft over about two cells, so the coarse outline does not show, and the pass draws a
/// few thousand triangles instead of every one (on a software rasterizer the surface's
/// triangles, not its pixels, are what a pass costs).
fn shadow_triangles(view: &View) -> Vec<u32> {
    let x = view.positions();
    let n = x.len();
    let cell = (view.size() as f32 / SHADOW_CELLS).max(f32::MIN_POSITIVE);
    let mut first: std::collections::HashMap<[i64; 3], u32> = Default::default();
    let stand: Vec<u32> = (0..n)
        .map(|i| {
            let key = (x.get(i) / cell).floor().as_i64vec3().to_array();
            *first.entry(key).or_insert(i as u32)
        })
        .collect();
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::new();
    for t in view.triangles() {
        let c = t.map(|i| stand.get(i as usize).copied().unwrap_or(i));
        if c[0] == c[1] || c[1] == c[2] || c[0] == c[2] {
            continue;
        }
        // The same triangle either way round casts the same shadow: keep it once.
        let mut key = c;
        key.sort_unstable();
        if seen.insert(key) {
            out.extend_from_slice(&c);
        }
    }
    out
}

/// World to the shadow map's clip space: an orthographic view down `g.up` onto the ground,
/// two half sides wide (the puppet's reach) and deep from twice the half side above the
/// ground to as far below (the shader reads depths back into heights by that range).
fn shadow_proj(g: &Ground) -> Mat4 {
    let up = g.up.normalize_or(Vec3::Y);
    let reach = g.half.max(1e-6);
    let eye = g.centre + up * 2.0 * reach;
    let view = glam::camera::rh::view::look_at_mat4(eye, g.centre, g.across[1]);
    let proj = glam::camera::rh::proj::directx::orthographic(
        -reach,
        reach,
        -reach,
        reach,
        0.0,
        4.0 * reach,
    );
    proj * view
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
