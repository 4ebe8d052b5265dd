//! Angle-weighted vertex normals (Thürmer & Wüthrich): each face contributes its unit normal
//! weighted by the corner angle at the vertex, so the result does not depend on how a flat
//! region happens to be triangulated.
//!
//! Each thread owns a range of vertices and goes through all faces in order, adding the
//! corners at its own vertices: the sums are those of one pass face by face, to the bit,
//! whatever the number of threads.

use super::{Mesh, MeshError};
use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Unit outward normal per vertex.
///
/// Zero-area faces contribute nothing. A vertex whose faces all have zero area falls back to
/// the sum of its faces' unnormalised normals.
///
/// # Errors
/// [`MeshError::Degenerate`] when a vertex has no defined normal at all.
pub fn vertex_normals(mesh: &Mesh) -> Result<Vec<DVec3>, MeshError> {
    let n = mesh.positions.len();
    let threads = if mesh.triangles.len() < 50_000 {
        1
    } else {
        rayon::current_num_threads().clamp(1, 16)
    };
    let mut normals = vec![DVec3::ZERO; n];
    let mut pieces = Vec::with_capacity(threads);
    let mut rest = &mut normals[..];
    for k in 0..threads {
        let (lo, hi) = ((n * k / threads) as u32, (n * (k + 1) / threads) as u32);
        let (piece, tail) = rest.split_at_mut((hi - lo) as usize);
        pieces.push((lo, hi, piece));
        rest = tail;
    }
    let missing: Option<usize> = pieces
        .into_par_iter()
        .map(|(lo, hi, out)| normals_of_range(mesh, lo, hi, out))
        .reduce(
            || None,
            |a, b| match (a, b) {
                (Some(x), Some(y)) => Some(x.min(y)),
                (x, y) => x.or(y),
            },
        );
    match missing {
        Some(i) => Err(MeshError::Degenerate(format!(
            "vertex {} has no defined normal (its faces cancel out or have no area)",
            i + 1
        ))),
        None => Ok(normals),
    }
}

/// Area-weighted unit normals of the surface `positions` with faces `triangles` into
/// `out`, what the viewport shades with (a vertex of no face, or whose faces cancel: up).
/// Faces naming a vertex beyond `positions` are skipped.
pub fn area_normals_into(positions: &[Vec3], triangles: &[[u32; 3]], out: &mut Vec<Vec3>) {
    out.clear();
    out.resize(positions.len(), Vec3::ZERO);
    for t in triangles {
        if t.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let face = (b - a).cross(c - a);
        for &i in t {
            out[i as usize] += face;
        }
    }
    out.iter_mut().for_each(|n| *n = n.normalize_or(Vec3::Y));
}

/// The normals of vertices `lo..hi` into `out`; the first vertex without one, if any.
fn normals_of_range(mesh: &Mesh, lo: u32, hi: u32, out: &mut [DVec3]) -> Option<usize> {
    let len = (hi - lo) as usize;
    let mut acc = vec![DVec3::ZERO; len];
    let mut fallback = vec![DVec3::ZERO; len];
    let mine = |v: u32| v >= lo && v < hi;
    for t in &mesh.triangles {
        if !t.iter().any(|&v| mine(v)) {
            continue;
        }
        let p = t.map(|i| mesh.positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let length = n.length();
        for k in 0..3 {
            if mine(t[k]) {
                fallback[(t[k] - lo) as usize] += n;
            }
        }
        if length.is_nan() || length <= 0.0 {
            continue;
        }
        let unit = n / length;
        for k in 0..3 {
            if !mine(t[k]) {
                continue;
            }
            let e1 = p[(k + 1) % 3] - p[k];
            let e2 = p[(k + 2) % 3] - p[k];
            // atan2 of |cross| and dot is accurate for tiny and near-straight angles.
            let angle = e1.cross(e2).length().atan2(e1.dot(e2));
            acc[(t[k] - lo) as usize] += angle * unit;
        }
    }
    let mut missing = None;
    for (i, slot) in out.iter_mut().enumerate() {
        match acc[i]
            .try_normalize()
            .or_else(|| fallback[i].try_normalize())
        {
            Some(n) => *slot = n,
            None => {
                missing.get_or_insert(lo as usize + i);
            }
        }
    }
    missing
}
