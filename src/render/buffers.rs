//! Vertex layouts shared with `shaders/scene.wgsl`, and vertex buffers that grow.

use super::Gpu;
use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct Uniforms {
    pub view_proj: [[f32; 4]; 4],
    /// World to the shadow map's clip space.
    pub shadow_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    /// Towards the key light; w: 1 when the shader encodes gamma itself.
    pub key: [f32; 4],
    /// Towards the fill light.
    pub fill: [f32; 4],
    /// Towards the rim light (behind the puppet).
    pub rim: [f32; 4],
    /// The world's up; w: 1 when the ground is drawn.
    pub up: [f32; 4],
    /// The ground's centre; w: half its side.
    pub ground: [f32; 4],
    /// Its two directions across up; their w: the grid's spacing, and how far (world
    /// units) above the ground an occluder's shadow fades.
    pub across_a: [f32; 4],
    pub across_b: [f32; 4],
    /// The camera's right and up in the world (a matcap reads the normal in their frame);
    /// the right's w: how much of the matcap's rim takes the part's colour (0: white).
    pub camera_right: [f32; 4],
    pub camera_up: [f32; 4],
    /// The matcap's light in the camera's frame; w: how far it wraps round the shape.
    pub matcap_light: [f32; 4],
    /// The matcap's ambient, rim, highlight and the highlight's exponent.
    pub matcap_terms: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Default, Pod, Zeroable)]
pub(super) struct SurfaceVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// How much of the sky the body hides here (0: open; see `geom::occlusion`).
    pub occlusion: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Default, Pod, Zeroable)]
pub(super) struct LineVertex {
    pub position: [f32; 3],
    pub color: [f32; 4],
}

/// A vertex buffer that grows (doubling) when the data outgrows it.
pub(super) struct GrowBuffer {
    pub buffer: wgpu::Buffer,
    label: &'static str,
    usage: wgpu::BufferUsages,
}

impl GrowBuffer {
    pub fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages) -> Self {
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

    pub fn write(&mut self, gpu: &Gpu, data: &[u8]) {
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
