//! Reading an accessor's elements whatever their component type: floats, and the
//! integers `KHR_mesh_quantization` allows for positions, weights and animation outputs
//! (normalized or not), through the buffer views the file holds or the ones
//! `EXT_meshopt_compression` decoded ([`super::meshopt`]).

use super::{bad, MeshError};
use gltf::accessor::{DataType, Dimensions};

/// The bytes of every buffer, and of every buffer view that had to be decoded first.
pub(super) struct Data {
    /// Each buffer's bytes, by index (a meshopt fallback buffer is empty).
    pub buffers: Vec<Vec<u8>>,
    /// Per buffer view, its decoded bytes when it was compressed.
    pub decoded: Vec<Option<Vec<u8>>>,
}

impl Data {
    /// The bytes of `view`: the decoded ones, or its range of its buffer.
    fn view(&self, view: &gltf::buffer::View) -> Result<&[u8], MeshError> {
        if let Some(Some(bytes)) = self.decoded.get(view.index()) {
            return Ok(bytes);
        }
        let buffer = self.buffers.get(view.buffer().index()).ok_or_else(|| {
            bad(format!(
                "buffer view {} names a missing buffer",
                view.index()
            ))
        })?;
        view.offset()
            .checked_add(view.length())
            .and_then(|end| buffer.get(view.offset()..end))
            .ok_or_else(|| {
                bad(format!(
                    "buffer view {} reaches past the end of its buffer",
                    view.index()
                ))
            })
    }
}

/// Components per element.
fn width(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 | Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// The elements of `accessor` as `f32`, `dims` components each (the accessor must have
/// that many): integers converted as the glTF spec says (`x / 127`, `x / 255`, … for
/// normalized ones, clamped at −1; as they are otherwise).
///
/// # Errors
/// A parse error when the accessor has another width, is sparse, or reaches past its
/// buffer view.
pub(super) fn floats(
    accessor: &gltf::Accessor,
    data: &Data,
    dims: usize,
) -> Result<Vec<f32>, MeshError> {
    let normalized = accessor.normalized();
    let convert = move |kind: DataType, b: &[u8]| -> f32 {
        match (kind, normalized) {
            (DataType::F32, _) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            (DataType::I8, true) => (b[0] as i8 as f32 / 127.0).max(-1.0),
            (DataType::U8, true) => b[0] as f32 / 255.0,
            (DataType::I16, true) => (i16::from_le_bytes([b[0], b[1]]) as f32 / 32767.0).max(-1.0),
            (DataType::U16, true) => u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
            (DataType::I8, false) => b[0] as i8 as f32,
            (DataType::U8, false) => b[0] as f32,
            (DataType::I16, false) => i16::from_le_bytes([b[0], b[1]]) as f32,
            (DataType::U16, false) => u16::from_le_bytes([b[0], b[1]]) as f32,
            (DataType::U32, true) => {
                u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32 / u32::MAX as f32
            }
            (DataType::U32, false) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
        }
    };
    elements(accessor, data, dims, convert)
}

/// The elements of an accessor of unsigned integers (indices, joint numbers) as `u32`.
///
/// # Errors
/// As [`floats`], and when the components are not unsigned integers.
pub(super) fn unsigned(
    accessor: &gltf::Accessor,
    data: &Data,
    dims: usize,
) -> Result<Vec<u32>, MeshError> {
    if !matches!(
        accessor.data_type(),
        DataType::U8 | DataType::U16 | DataType::U32
    ) {
        return Err(bad(format!(
            "accessor {} should hold unsigned integers",
            accessor.index()
        )));
    }
    elements(accessor, data, dims, |kind, b| match kind {
        DataType::U8 => b[0] as u32,
        DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as u32,
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    })
}

fn elements<T: Default + Clone>(
    accessor: &gltf::Accessor,
    data: &Data,
    dims: usize,
    convert: impl Fn(DataType, &[u8]) -> T,
) -> Result<Vec<T>, MeshError> {
    let index = accessor.index();
    if width(accessor.dimensions()) != dims {
        return Err(bad(format!(
            "accessor {index} has {} components per element, {dims} expected",
            width(accessor.dimensions())
        )));
    }
    if accessor.sparse().is_some() {
        return Err(bad(format!(
            "accessor {index} is sparse, which this reader does not take"
        )));
    }
    let count = accessor.count();
    let kind = accessor.data_type();
    let size = kind.size();
    // Without a buffer view the elements are zeros (as many as a file could hold).
    let Some(view) = accessor.view() else {
        if count > 1 << 26 {
            return Err(bad(format!("accessor {index} claims {count} elements")));
        }
        return Ok(vec![T::default(); count * dims]);
    };
    let bytes = data.view(&view)?;
    let packed = size * dims;
    let stride = view.stride().unwrap_or(packed).max(packed);
    let start = accessor.offset();
    let end = match count {
        0 => start,
        n => (n - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(start + packed))
            .unwrap_or(usize::MAX),
    };
    let bytes = bytes.get(start..end).ok_or_else(|| {
        bad(format!(
            "accessor {index} reaches past the end of its buffer view"
        ))
    })?;
    let mut out = Vec::with_capacity(count * dims);
    for e in 0..count {
        let at = &bytes[e * stride..e * stride + packed];
        out.extend(at.chunks_exact(size).map(|b| convert(kind, b)));
    }
    Ok(out)
}
