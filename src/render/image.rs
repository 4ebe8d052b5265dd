//! RGBA images read back from the GPU: PNG files and the comparisons render tests use.

use super::{Gpu, RenderError};
use std::path::Path;

/// Why an image could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The file could not be opened or written.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// PNG encoding failed.
    #[error("{0}")]
    Encode(#[from] png::EncodingError),
    /// PNG decoding failed.
    #[error("{0}")]
    Decode(#[from] png::DecodingError),
    /// Not 8-bit RGB or RGBA (the colour type and depth).
    #[error("unsupported PNG format {0}")]
    Format(String),
    /// Too large to hold in memory.
    #[error("image too large")]
    TooLarge,
}

/// An 8-bit RGBA image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Four bytes per pixel, rows top to bottom.
    pub rgba: Vec<u8>,
}

impl Image {
    /// The pixel at `(x, y)`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// Writes a PNG.
    pub fn save_png(&self, path: &Path) -> Result<(), ImageError> {
        let file = std::fs::File::create(path)?;
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header()?;
        Ok(writer.write_image_data(&self.rgba)?)
    }

    /// Reads an 8-bit RGB or RGBA PNG.
    pub fn load_png(path: &Path) -> Result<Image, ImageError> {
        let file = std::fs::File::open(path)?;
        let decoder = png::Decoder::new(std::io::BufReader::new(file));
        let mut reader = decoder.read_info()?;
        let size = reader.output_buffer_size().ok_or(ImageError::TooLarge)?;
        let mut buf = vec![0; size];
        let info = reader.next_frame(&mut buf)?;
        let rgba = match (info.color_type, info.bit_depth) {
            (png::ColorType::Rgba, png::BitDepth::Eight) => buf[..info.buffer_size()].to_vec(),
            (png::ColorType::Rgb, png::BitDepth::Eight) => buf[..info.buffer_size()]
                .chunks(3)
                .flat_map(|c| [c[0], c[1], c[2], 255])
                .collect(),
            other => return Err(ImageError::Format(format!("{other:?}"))),
        };
        Ok(Image {
            width: info.width,
            height: info.height,
            rgba,
        })
    }

    /// Mean absolute difference per channel (0..255) against an image of the same size.
    pub fn mean_abs_diff(&self, other: &Image) -> Option<f64> {
        if (self.width, self.height) != (other.width, other.height) {
            return None;
        }
        let sum: u64 = self
            .rgba
            .iter()
            .zip(&other.rgba)
            .map(|(a, b)| a.abs_diff(*b) as u64)
            .sum();
        Some(sum as f64 / self.rgba.len().max(1) as f64)
    }

    /// Share of pixels that differ from `background` by more than `tolerance` in a channel.
    pub fn coverage(&self, background: [u8; 3], tolerance: u8) -> f64 {
        let hits = self
            .rgba
            .chunks(4)
            .filter(|p| (0..3).any(|k| p[k].abs_diff(background[k]) > tolerance))
            .count();
        hits as f64 / (self.width * self.height).max(1) as f64
    }
}

/// Copies a 2D RGBA8 or BGRA8 texture (with `COPY_SRC`) into an [`Image`].
pub fn read_texture(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Image, RenderError> {
    let (width, height) = (texture.width(), texture.height());
    let unpadded = width * 4;
    let padded =
        unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: (padded * height) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    gpu.queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| RenderError::Readback(e.to_string()))?
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    let bgra = matches!(
        texture.format(),
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    );
    let mut rgba = Vec::with_capacity((unpadded * height) as usize);
    {
        let data = buffer
            .get_mapped_range(..)
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        for row in data.chunks(padded as usize) {
            for p in row[..unpadded as usize].chunks(4) {
                if bgra {
                    rgba.extend_from_slice(&[p[2], p[1], p[0], p[3]]);
                } else {
                    rgba.extend_from_slice(p);
                }
            }
        }
    }
    buffer.unmap();
    Ok(Image {
        width,
        height,
        rgba,
    })
}
