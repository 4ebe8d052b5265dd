//! Drawing the puppet with wgpu: the lit surface in section colours and the overlays
//! (wireframe, skeletal points, bone points and springs, cut planes, pivots), into a window
//! or an offscreen image.
//!
//! GPU resources are created once ([`SceneRenderer::new`]); [`SceneRenderer::prepare`]
//! uploads only what changed since the last call (positions and normals when the
//! simulation moved, colours when sections or the selection changed, overlay geometry only
//! for overlays that are shown) and [`SceneRenderer::paint`] records the draws. Shaders are
//! the sibling file `shaders/scene.wgsl`.

pub mod camera;
pub mod image;

pub use camera::Camera;
pub use image::Image;

use crate::ui::Session;
use bytemuck::{Pod, Zeroable};
use glam::{DVec3, Vec3};

/// Why drawing is impossible.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("no graphics adapter ({0}); install a Vulkan or OpenGL driver (on Debian: mesa-vulkan-drivers)")]
    Adapter(String),
    #[error("cannot open the graphics device: {0}")]
    Device(String),
    #[error("cannot read the image back from the GPU: {0}")]
    Readback(String),
}

/// The instance, adapter, device and queue, created once.
pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
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

/// Which overlays are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Overlays {
    pub wireframe: bool,
    pub skeleton: bool,
    pub bone_points: bool,
    pub bone_springs: bool,
    pub cuts: bool,
    pub pivots: bool,
}

impl Default for Overlays {
    fn default() -> Self {
        Overlays {
            wireframe: false,
            skeleton: false,
            bone_points: false,
            bone_springs: false,
            cuts: true,
            pivots: true,
        }
    }
}

impl Overlays {
    fn any(&self) -> bool {
        self.wireframe
            || self.skeleton
            || self.bone_points
            || self.bone_springs
            || self.cuts
            || self.pivots
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Uniforms {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Default, Pod, Zeroable)]
struct SurfaceVertex {
    position: [f32; 3],
    normal: [f32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Default, Pod, Zeroable)]
struct LineVertex {
    position: [f32; 3],
    color: [f32; 4],
}

/// A vertex buffer that grows (doubling) when the data outgrows it.
struct GrowBuffer {
    buffer: wgpu::Buffer,
    label: &'static str,
    usage: wgpu::BufferUsages,
}

impl GrowBuffer {
    fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        GrowBuffer {
            buffer: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 1024,
                usage,
                mapped_at_creation: false,
            }),
            label,
            usage,
        }
    }

    fn write(&mut self, gpu: &Gpu, data: &[u8]) {
        if data.len() as u64 > self.buffer.size() {
            let size = (data.len() as u64).next_power_of_two().max(1024);
            self.buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(self.label),
                size,
                usage: self.usage,
                mapped_at_creation: false,
            });
        }
        if !data.is_empty() {
            gpu.queue.write_buffer(&self.buffer, 0, data);
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

/// What the last `prepare` uploaded, to skip work when nothing changed.
#[derive(Clone, Copy, PartialEq)]
struct Seen {
    puppet: u64,
    revision: u64,
    layout: u64,
    draft: u64,
    overlays: Overlays,
}

/// The GPU side of drawing a puppet.
pub struct SceneRenderer {
    encode_gamma: bool,
    surface_pipeline: wgpu::RenderPipeline,
    lines_pipeline: wgpu::RenderPipeline,
    top_pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    vertices: GrowBuffer,
    colors: GrowBuffer,
    indices: GrowBuffer,
    index_count: u32,
    lines: GrowBuffer,
    line_count: u32,
    top: GrowBuffer,
    top_count: u32,
    depth: Option<(wgpu::Texture, wgpu::TextureView)>,
    seen: Option<Seen>,
    /// Uploads done by the last `prepare` (for tests and the idle measurement).
    pub last_uploads: usize,
    cpu_vertices: Vec<SurfaceVertex>,
    cpu_normals: Vec<Vec3>,
    cpu_colors: Vec<[f32; 4]>,
    cpu_lines: Vec<LineVertex>,
    cpu_top: Vec<LineVertex>,
    edges: Vec<(u32, u32)>,
}

impl SceneRenderer {
    /// Creates pipelines and buffers for drawing into targets of `format`.
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> SceneRenderer {
        let device = &gpu.device;
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/scene.wgsl").into()),
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("uniforms"),
            size: std::mem::size_of::<Uniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("uniforms"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("uniforms"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let surface_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let color_attributes = wgpu::vertex_attr_array![2 => Float32x4];
        let surface_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("surface"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_surface"),
                compilation_options: Default::default(),
                buffers: &[
                    Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<SurfaceVertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &surface_attributes,
                    }),
                    Some(wgpu::VertexBufferLayout {
                        array_stride: 16,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &color_attributes,
                    }),
                ],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_surface"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let line_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4];
        let lines = |label: &str, compare: wgpu::CompareFunction| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_lines"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<LineVertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &line_attributes,
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::LineList,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(compare),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some("fs_lines"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let lines_pipeline = lines("lines", wgpu::CompareFunction::LessEqual);
        let top_pipeline = lines("lines on top", wgpu::CompareFunction::Always);
        let vertex = wgpu::BufferUsages::VERTEX;
        SceneRenderer {
            encode_gamma: !format.is_srgb(),
            surface_pipeline,
            lines_pipeline,
            top_pipeline,
            uniforms,
            bind_group,
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
            edges: Vec::new(),
        }
    }

    /// The depth buffer for a target of `width × height`, recreated when the size changes.
    pub fn depth_view(&mut self, gpu: &Gpu, width: u32, height: u32) -> &wgpu::TextureView {
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
        &self.depth.as_ref().expect("depth buffer just created").1
    }

    /// Uploads what changed since the last call (a new session re-uploads everything).
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        session: &Session,
        camera: &Camera,
        overlays: Overlays,
        aspect: f32,
    ) {
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
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));

        let now = Seen {
            puppet: session.id,
            revision: session.revision,
            layout: session.layout_revision,
            draft: draft_key(session),
            overlays,
        };
        let before = self.seen;
        self.seen = Some(now);
        self.last_uploads = 0;
        let new_puppet = before.is_none_or(|b| b.puppet != now.puppet);
        if new_puppet {
            let indices: Vec<u32> = session
                .puppet
                .mesh
                .triangles
                .iter()
                .flatten()
                .copied()
                .collect();
            self.indices.write(gpu, bytemuck::cast_slice(&indices));
            self.index_count = indices.len() as u32;
            self.edges = crate::mesh::unique_edges(&session.puppet.mesh.triangles);
            self.last_uploads += 1;
        }
        let moved = new_puppet || before.is_none_or(|b| b.revision != now.revision);
        if moved {
            self.update_vertices(session);
            self.vertices
                .write(gpu, bytemuck::cast_slice(&self.cpu_vertices));
            self.last_uploads += 1;
        }
        let relaid =
            new_puppet || before.is_none_or(|b| b.layout != now.layout || b.draft != now.draft);
        if relaid {
            self.update_colors(session);
            self.colors
                .write(gpu, bytemuck::cast_slice(&self.cpu_colors));
            self.last_uploads += 1;
        }
        let overlays_changed = before.is_none_or(|b| b.overlays != now.overlays);
        // Every overlay (and the cut draft) follows the pose or the surface.
        if overlays_changed || relaid || (moved && (overlays.any() || session.draft.is_some())) {
            self.update_overlays(session, overlays);
            self.lines.write(gpu, bytemuck::cast_slice(&self.cpu_lines));
            self.top.write(gpu, bytemuck::cast_slice(&self.cpu_top));
            self.line_count = self.cpu_lines.len() as u32;
            self.top_count = self.cpu_top.len() as u32;
            self.last_uploads += 1;
        }
    }

    fn update_vertices(&mut self, session: &Session) {
        let x = session.puppet.sim.positions();
        let n = x.len();
        self.cpu_vertices.clear();
        self.cpu_vertices.resize(n, SurfaceVertex::default());
        let normals = &mut self.cpu_normals;
        normals.clear();
        normals.resize(n, Vec3::ZERO);
        for t in &session.puppet.mesh.triangles {
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

    fn update_colors(&mut self, session: &Session) {
        let sections = session.puppet.joints.section_of();
        let draft = session.draft.as_ref();
        let points = &session.puppet.skeleton.points;
        self.cpu_colors.clear();
        self.cpu_colors
            .extend(sections.iter().enumerate().map(|(i, &s)| {
                let s = s as usize;
                let mut c = section_color(s);
                if session.selection.contains(&s) {
                    c = mix(c, [1.0, 0.42, 0.08], 0.55);
                }
                if let Some(d) = draft {
                    if d.section == s && (points[i] - d.point).dot(d.normal) > 0.0 {
                        c = mix(c, [0.1, 0.75, 1.0], 0.6);
                    }
                }
                [c[0], c[1], c[2], 1.0]
            }));
    }

    fn update_overlays(&mut self, session: &Session, o: Overlays) {
        self.cpu_lines.clear();
        self.cpu_top.clear();
        let (lines, top) = (&mut self.cpu_lines, &mut self.cpu_top);
        let p = &session.puppet;
        let x = p.sim.positions();
        let size = p.mesh.diagonal() as f32;
        let world = p.joints.world(&session.local);
        if o.wireframe {
            for &(a, b) in &self.edges {
                push_line(
                    lines,
                    x.get(a as usize),
                    x.get(b as usize),
                    [0.02, 0.02, 0.02, 0.55],
                );
            }
        }
        if o.skeleton {
            let sections = p.joints.section_of();
            for (i, sp) in p.skeleton.points.iter().enumerate() {
                let w = world[sections[i] as usize].transform_point3(*sp).as_vec3();
                push_cross(top, w, size * 0.002, [0.95, 0.9, 0.2, 0.9]);
            }
        }
        if o.bone_springs {
            for i in 0..x.len() {
                let (bi, bo) = p.sim.bone_points(i);
                let xi = x.get(i);
                push_line(lines, bi, xi, [0.3, 0.9, 0.4, 0.7]);
                push_line(lines, xi, bo, [0.9, 0.35, 0.3, 0.7]);
            }
        }
        if o.bone_points {
            for i in 0..x.len() {
                let (bi, bo) = p.sim.bone_points(i);
                push_cross(lines, bi, size * 0.0015, [0.3, 0.9, 0.4, 1.0]);
                push_cross(lines, bo, size * 0.0015, [0.9, 0.35, 0.3, 1.0]);
            }
        }
        let half = p.mesh.diagonal() * 0.18;
        if o.cuts {
            let sections = p.joints.sections();
            for (k, cut) in p.joints.cuts().iter().enumerate() {
                let parent = sections[k + 1].parent.unwrap_or(0);
                let w = &world[parent];
                let centre = w.transform_point3(sections[k + 1].pivot);
                let normal = w.transform_vector3(cut.normal);
                push_plane(lines, centre, normal, half, [0.85, 0.85, 0.95, 0.8]);
            }
        }
        if let Some(d) = &session.draft {
            let w = &world[d.section.min(world.len() - 1)];
            let (centre, normal) = (w.transform_point3(d.point), w.transform_vector3(d.normal));
            push_plane(top, centre, normal, half * 1.3, [0.1, 0.8, 1.0, 1.0]);
            if let Some(pivot) = d.pivot {
                let c = w.transform_point3(pivot).as_vec3();
                push_cross(top, c, size * 0.025, [0.1, 0.8, 1.0, 1.0]);
            }
        }
        if o.pivots {
            for (s, section) in p.joints.sections().iter().enumerate().skip(1) {
                let c = world[s].transform_point3(section.pivot).as_vec3();
                let color = if session.selection.contains(&s) {
                    [1.0, 0.5, 0.1, 1.0]
                } else {
                    [1.0, 1.0, 1.0, 1.0]
                };
                push_cross(top, c, size * 0.02, color);
            }
        }
    }

    /// Records the scene into `pass` (cleared colour and depth are the caller's).
    pub fn paint(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, &self.bind_group, &[]);
        if self.index_count > 0 {
            pass.set_pipeline(&self.surface_pipeline);
            pass.set_vertex_buffer(0, self.vertices.buffer.slice(..));
            pass.set_vertex_buffer(1, self.colors.buffer.slice(..));
            pass.set_index_buffer(self.indices.buffer.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
        if self.line_count > 0 {
            pass.set_pipeline(&self.lines_pipeline);
            pass.set_vertex_buffer(0, self.lines.buffer.slice(..));
            pass.draw(0..self.line_count, 0..1);
        }
        if self.top_count > 0 {
            pass.set_pipeline(&self.top_pipeline);
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
        let depth = &self.depth.as_ref().expect("depth buffer").1;
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

fn push_line(out: &mut Vec<LineVertex>, a: Vec3, b: Vec3, color: [f32; 4]) {
    out.push(LineVertex {
        position: a.to_array(),
        color,
    });
    out.push(LineVertex {
        position: b.to_array(),
        color,
    });
}

/// Three axis-aligned segments of half-length `r` through `c`.
fn push_cross(out: &mut Vec<LineVertex>, c: Vec3, r: f32, color: [f32; 4]) {
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        push_line(out, c - axis * r, c + axis * r, color);
    }
}

/// A square of half-size `half` in the plane, hatched, with its normal as a stroke.
fn push_plane(out: &mut Vec<LineVertex>, centre: DVec3, normal: DVec3, half: f64, color: [f32; 4]) {
    let n = normal.normalize_or(DVec3::Y);
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let at = |a: f64, b: f64| (centre + (u * a + v * b) * half).as_vec3();
    let corners = [at(-1.0, -1.0), at(1.0, -1.0), at(1.0, 1.0), at(-1.0, 1.0)];
    for k in 0..4 {
        push_line(out, corners[k], corners[(k + 1) % 4], color);
    }
    let faint = [color[0], color[1], color[2], color[3] * 0.4];
    for t in [-0.5, 0.0, 0.5] {
        push_line(out, at(t, -1.0), at(t, 1.0), faint);
    }
    push_line(
        out,
        centre.as_vec3(),
        (centre + n * half * 0.6).as_vec3(),
        color,
    );
}

/// Changes when the cut draft changes (plane, section or pivot).
fn draft_key(session: &Session) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    if let Some(d) = &session.draft {
        d.section.hash(&mut h);
        for v in [d.point, d.normal, d.pivot.unwrap_or(DVec3::NAN)] {
            v.to_array().map(f64::to_bits).hash(&mut h);
        }
    }
    h.finish()
}

/// sRGB hex colour to linear.
fn srgb(hex: u32) -> [f32; 3] {
    let ch = |s: u32| {
        let c = ((hex >> s) & 0xff) as f32 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    [ch(16), ch(8), ch(0)]
}

/// Colour of a section: a warm latex tone for the root, then a palette.
pub fn section_color(section: usize) -> [f32; 3] {
    const PALETTE: [u32; 8] = [
        0xe8c39e, 0x8fb8de, 0xa8d5a2, 0xe5a3b8, 0xd8c878, 0xb4a6e0, 0x86d0c8, 0xe0a878,
    ];
    srgb(PALETTE[section % PALETTE.len()])
}

fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t)
}

/// Renders a session offscreen into an RGBA image (sRGB), `width × height` pixels.
pub fn render_image(
    gpu: &Gpu,
    renderer: &mut SceneRenderer,
    session: &Session,
    camera: &Camera,
    overlays: Overlays,
    width: u32,
    height: u32,
) -> Result<Image, RenderError> {
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("offscreen"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: OFFSCREEN_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    renderer.prepare(gpu, session, camera, overlays, width as f32 / height as f32);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.render_to(gpu, &mut encoder, &view, width, height);
    gpu.queue.submit([encoder.finish()]);
    image::read_texture(gpu, &texture)
}

/// The format offscreen images are rendered in.
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
