//! `EXT_meshopt_compression` (what gltfpack writes for the web): a buffer view whose
//! extension names compressed bytes is decoded by meshoptimizer (the `meshopt` crate)
//! into the plain bytes the view describes, before any accessor reads it.
//!
//! meshoptimizer's decoders are safe on untrusted bytes, but they `assert` their sizes
//! (a C assert aborts the process): every size is checked here first, so a bad file gets
//! an error line.

use super::{bad, MeshError};
use serde_json::Value;

/// The extension's name in a file.
pub(super) const EXTENSION: &str = "EXT_meshopt_compression";

/// The most bytes one decoded view may take (a file claiming more is refused, not
/// allocated).
const MAX_BYTES: usize = 1 << 31;

/// What the extension says of one buffer view.
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: String,
    filter: String,
}

fn field(object: &Value, name: &str) -> Option<usize> {
    object.get(name)?.as_u64().map(|v| v as usize)
}

/// Is buffer `index` of the raw JSON a fallback buffer (no bytes of its own; its views
/// are all compressed)?
pub(super) fn is_fallback(json: &Value, index: usize) -> bool {
    json.pointer(&format!("/buffers/{index}/extensions/{EXTENSION}/fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// Each buffer view's decoded bytes where the raw JSON says it is compressed.
///
/// # Errors
/// A parse error naming the view when its description or its bytes are bad.
pub(super) fn decode_views(
    json: &Value,
    buffers: &[Vec<u8>],
) -> Result<Vec<Option<Vec<u8>>>, MeshError> {
    let views = json
        .get("bufferViews")
        .and_then(Value::as_array)
        .map(Vec::as_slice)
        .unwrap_or(&[]);
    views
        .iter()
        .enumerate()
        .map(
            |(i, view)| match view.pointer(&format!("/extensions/{EXTENSION}")) {
                None => Ok(None),
                Some(ext) => {
                    let c = describe(ext).ok_or_else(|| {
                        bad(format!(
                            "buffer view {i}: its {EXTENSION} description is incomplete"
                        ))
                    })?;
                    decode(&c, buffers)
                        .map(Some)
                        .map_err(|why| bad(format!("buffer view {i}: {EXTENSION}: {why}")))
                }
            },
        )
        .collect()
}

fn describe(ext: &Value) -> Option<Compressed> {
    Some(Compressed {
        buffer: field(ext, "buffer")?,
        offset: field(ext, "byteOffset").unwrap_or(0),
        length: field(ext, "byteLength")?,
        stride: field(ext, "byteStride")?,
        count: field(ext, "count")?,
        mode: ext.get("mode")?.as_str()?.to_string(),
        filter: ext
            .get("filter")
            .and_then(Value::as_str)
            .unwrap_or("NONE")
            .to_string(),
    })
}

fn decode(c: &Compressed, buffers: &[Vec<u8>]) -> Result<Vec<u8>, String> {
    let source = buffers
        .get(c.buffer)
        .and_then(|b| b.get(c.offset..c.offset.checked_add(c.length)?))
        .ok_or("the compressed bytes lie outside their buffer")?;
    let size = c
        .count
        .checked_mul(c.stride)
        .filter(|&n| n <= MAX_BYTES)
        .ok_or("the decoded view would be too large")?;
    let mut out = vec![0u8; size];
    let dst = out.as_mut_ptr().cast();
    let (src, len) = (source.as_ptr(), source.len());
    let code = match c.mode.as_str() {
        "ATTRIBUTES" => {
            if c.stride == 0 || c.stride > 256 || !c.stride.is_multiple_of(4) {
                return Err(format!("an attribute stride of {} bytes", c.stride));
            }
            // SAFETY: `out` holds count × stride bytes, the stride is one the decoder
            // accepts, and the decoder reads at most `len` bytes of `src`.
            unsafe { meshopt::ffi::meshopt_decodeVertexBuffer(dst, c.count, c.stride, src, len) }
        }
        "TRIANGLES" | "INDICES" => {
            if c.stride != 2 && c.stride != 4 {
                return Err(format!("an index size of {} bytes", c.stride));
            }
            if c.mode == "TRIANGLES" {
                if !c.count.is_multiple_of(3) {
                    return Err(format!("{} triangle corners", c.count));
                }
                // SAFETY: as above, for an index size of 2 or 4 and whole triangles.
                unsafe { meshopt::ffi::meshopt_decodeIndexBuffer(dst, c.count, c.stride, src, len) }
            } else {
                // SAFETY: as above, for an index size of 2 or 4.
                unsafe {
                    meshopt::ffi::meshopt_decodeIndexSequence(dst, c.count, c.stride, src, len)
                }
            }
        }
        other => return Err(format!("unknown mode '{other}'")),
    };
    if code != 0 {
        return Err(format!("the compressed bytes do not decode (code {code})"));
    }
    let (count, stride) = (c.count, c.stride);
    let dst = out.as_mut_ptr().cast();
    match (c.filter.as_str(), c.mode.as_str()) {
        ("NONE", _) => {}
        (_, "TRIANGLES" | "INDICES") => return Err("a filter on indices".into()),
        ("OCTAHEDRAL", _) if stride == 4 || stride == 8 => {
            // SAFETY: `out` holds count × stride bytes, stride 4 or 8 as the filter needs.
            unsafe { meshopt::ffi::meshopt_decodeFilterOct(dst, count, stride) }
        }
        ("QUATERNION", _) if stride == 8 => {
            // SAFETY: as above, stride 8.
            unsafe { meshopt::ffi::meshopt_decodeFilterQuat(dst, count, stride) }
        }
        ("EXPONENTIAL", _) => {
            // SAFETY: as above; the stride is a multiple of 4 (checked for attributes).
            unsafe { meshopt::ffi::meshopt_decodeFilterExp(dst, count, stride) }
        }
        (filter, _) => {
            return Err(format!(
                "the filter '{filter}' with a stride of {stride} bytes"
            ))
        }
    }
    Ok(out)
}
