//! The render pipelines of the scene (the surface lit by the studio's lights or a matcap,
//! ground, depth-tested lines, lines on top,
//! and the shadow map's depth) and the uniform buffer they share, created once per target
//! format and sample count.

use super::buffers::{LineVertex, SurfaceVertex, Uniforms};
use super::DEPTH_FORMAT;

/// The shadow map's side in texels.
pub(super) const SHADOW_SIZE: u32 = 512;

/// The shade's side in texels (`SHADE_SIZE` in `shaders/scene.wgsl` says the same).
pub(super) const SHADE_SIZE: u32 = 128;

/// The shade's format.
const SHADE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The pipelines and their uniforms.
pub(super) struct Pipelines {
    /// The surface with both sides of its faces drawn (an open sheet shows its inside).
    pub surface: wgpu::RenderPipeline,
    /// The surface with the faces turned away from the eye skipped: a closed surface
    /// turned outward never shows them, and on a software rasterizer every triangle costs
    /// (`bench draw`: 46,850 vertices at 1280 × 800, see BENCHMARKS).
    pub closed_surface: wgpu::RenderPipeline,
    /// The same two lit by a matcap (`fs_matcap`).
    pub matcap: wgpu::RenderPipeline,
    pub closed_matcap: wgpu::RenderPipeline,
    pub ground: wgpu::RenderPipeline,
    pub lines: wgpu::RenderPipeline,
    pub top: wgpu::RenderPipeline,
    /// The surface's depth into the shadow map, and the shadow map into the shade.
    pub shadow: wgpu::RenderPipeline,
    pub shade: wgpu::RenderPipeline,
    pub uniforms: wgpu::Buffer,
    /// The uniforms and the shade, for the scene's pass.
    pub bind_group: wgpu::BindGroup,
    /// The uniforms alone, for the shadow map's pass.
    pub shadow_bind_group: wgpu::BindGroup,
    /// The uniforms and the shadow map, for the shade's pass.
    pub shade_bind_group: wgpu::BindGroup,
    pub shadow_map: wgpu::TextureView,
    pub shade_view: wgpu::TextureView,
}

impl Pipelines {
    /// Compiles `shaders/scene.wgsl` and builds the pipelines for targets of `format`
    /// with `samples` samples a pixel.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, samples: u32) -> Pipelines {
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
        let uniform_entry = wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let map_entry = wgpu::BindGroupLayoutEntry {
            binding: 1,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let (shade_entry, sampler_entry) = (texture_entry(2), sampler_entry(3));
        let layout_of = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let layout = layout_of("scene", &[uniform_entry, shade_entry, sampler_entry]);
        let shadow_layout = layout_of("shadow map", &[uniform_entry]);
        let shade_layout = layout_of("shade", &[uniform_entry, map_entry]);
        let texture = |label, size, format, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: size,
                        height: size,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: usage | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let shadow_map = texture("shadow map", SHADOW_SIZE, DEPTH_FORMAT, attachment);
        let shade_view = texture("shade", SHADE_SIZE, SHADE_FORMAT, attachment);
        let sampler = linear_sampler(device, "shade");
        let group = |label, layout, entries: &[wgpu::BindGroupEntry]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries,
            })
        };
        let uniform = wgpu::BindGroupEntry {
            binding: 0,
            resource: uniforms.as_entire_binding(),
        };
        let bind_group = group(
            "scene",
            &layout,
            &[
                uniform.clone(),
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&shade_view),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
            ],
        );
        let shadow_bind_group = group("shadow map", &shadow_layout, std::slice::from_ref(&uniform));
        let shade_bind_group = group(
            "shade",
            &shade_layout,
            &[
                uniform,
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&shadow_map),
                },
            ],
        );
        let pipeline_layout_of = |label, layout| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            })
        };
        let pipeline_layout = pipeline_layout_of("scene", &layout);
        let shadow_pipeline_layout = pipeline_layout_of("shadow map", &shadow_layout);
        let shade_pipeline_layout = pipeline_layout_of("shade", &shade_layout);
        let multisample = wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        };
        let surface_attributes =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 3 => Float32];
        let color_attributes = wgpu::vertex_attr_array![2 => Float32x4];
        let surface_pipeline = |label: &str, cull_mode, fragment: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
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
                    cull_mode,
                    ..Default::default()
                },
                depth_stencil: depth(true, wgpu::CompareFunction::Less),
                multisample,
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fragment),
                    compilation_options: Default::default(),
                    targets: &[target(format, None)],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
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
                depth_stencil: depth(false, compare),
                multisample,
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some("fs_lines"),
                    compilation_options: Default::default(),
                    targets: &[target(format, Some(wgpu::BlendState::ALPHA_BLENDING))],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let lines_pipeline = lines("lines", wgpu::CompareFunction::LessEqual);
        let top_pipeline = lines("lines on top", wgpu::CompareFunction::Always);
        // The ground: drawn after the surface, tested against its depth, blended as it
        // fades out.
        let ground = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("ground"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_ground"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: depth(false, wgpu::CompareFunction::LessEqual),
            multisample,
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_ground"),
                compilation_options: Default::default(),
                targets: &[target(format, Some(wgpu::BlendState::ALPHA_BLENDING))],
            }),
            multiview_mask: None,
            cache: None,
        });
        let shadow = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadow map"),
            layout: Some(&shadow_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_shadow"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<SurfaceVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &surface_attributes,
                })],
            },
            primitive: Default::default(),
            depth_stencil: depth(true, wgpu::CompareFunction::Less),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let shade = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shade"),
            layout: Some(&shade_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_shade"),
                compilation_options: Default::default(),
                targets: &[Some(SHADE_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        Pipelines {
            surface: surface_pipeline("surface", None, "fs_surface"),
            closed_surface: surface_pipeline(
                "closed surface",
                Some(wgpu::Face::Back),
                "fs_surface",
            ),
            matcap: surface_pipeline("surface, matcap", None, "fs_matcap"),
            closed_matcap: surface_pipeline(
                "closed surface, matcap",
                Some(wgpu::Face::Back),
                "fs_matcap",
            ),
            ground,
            lines: lines_pipeline,
            top: top_pipeline,
            shadow,
            shade,
            uniforms,
            bind_group,
            shadow_bind_group,
            shade_bind_group,
            shadow_map,
            shade_view,
        }
    }
}

/// Depth tested with `compare` against the scene's depth buffer, written when `write`.
fn depth(write: bool, compare: wgpu::CompareFunction) -> Option<wgpu::DepthStencilState> {
    Some(wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    })
}

/// A colour target of `format`, blended by `blend`.
fn target(
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
) -> Option<wgpu::ColorTargetState> {
    Some(wgpu::ColorTargetState {
        format,
        blend,
        write_mask: wgpu::ColorWrites::ALL,
    })
}

/// A filterable texture read by the fragment stage, at `binding`.
pub(super) fn texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// A filtering sampler for the fragment stage, at `binding`.
pub(super) fn sampler_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    }
}

/// A sampler that filters linearly both ways.
pub(super) fn linear_sampler(device: &wgpu::Device, label: &str) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(label),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}
