//! The PC2 point cache (Blender's Mesh Cache modifier, 3ds Max): a 32-byte header
//! (`POINTCACHE2\0`, version 1, point count, start frame, sample rate, sample count, all
//! little-endian) and then every sample's points as three `f32`.

use super::{ExportError, Frames};

/// The file's bytes.
///
/// # Errors
/// [`ExportError`] when a frame does not fit or the counts pass PC2's 32-bit fields.
pub fn write(take: &Frames) -> Result<Vec<u8>, ExportError> {
    take.check()?;
    let points = i32::try_from(take.rest.len())
        .map_err(|_| ExportError::TooLarge("PC2 holds at most 2^31 points".into()))?;
    let samples = i32::try_from(take.frames.len())
        .map_err(|_| ExportError::TooLarge("PC2 holds at most 2^31 samples".into()))?;
    let mut out = Vec::with_capacity(32 + take.frames.len() * take.rest.len() * 12);
    out.extend_from_slice(b"POINTCACHE2\0");
    out.extend_from_slice(&1i32.to_le_bytes());
    out.extend_from_slice(&points.to_le_bytes());
    // Start frame and sample rate (frames between samples) in the take's frame numbers:
    // sample j is frame `first + j × step`, the state at that frame over the frame rate,
    // as the OBJ frames' headers say.
    out.extend_from_slice(&(take.first as f32).to_le_bytes());
    out.extend_from_slice(&(take.step.max(1) as f32).to_le_bytes());
    out.extend_from_slice(&samples.to_le_bytes());
    for frame in &take.frames {
        for p in frame {
            for c in p.to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn header_and_samples() {
        let take = Frames {
            triangles: vec![[0, 1, 2]],
            rest: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            frames: vec![vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![Vec3::ONE; 3]],
            fps: 30.0,
            first: 1,
            step: 1,
        };
        let b = write(&take).unwrap();
        assert_eq!(&b[..12], b"POINTCACHE2\0");
        let i = |at: usize| i32::from_le_bytes(b[at..at + 4].try_into().unwrap());
        let f = |at: usize| f32::from_le_bytes(b[at..at + 4].try_into().unwrap());
        assert_eq!((i(12), i(16), f(20), f(24), i(28)), (1, 3, 1.0, 1.0, 2));
        assert_eq!(b.len(), 32 + 2 * 3 * 12);
        assert_eq!(f(32 + 3 * 12), 1.0);
        let bad = Frames {
            frames: vec![vec![Vec3::NAN; 3]],
            ..take
        };
        assert!(write(&bad).is_err());
    }
}
