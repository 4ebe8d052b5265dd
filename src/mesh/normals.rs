//! Angle-weighted vertex normals (Thürmer & Wüthrich): each face contributes its unit normal
//! weighted by the corner angle at the vertex, so the result does not depend on how a flat
//! region happens to be triangulated.
//!
//! Each thread owns a range of vertices and goes through all faces in order, adding the
//! corners at its own vertices: the sums are those of one pass face by face, to the bit,
//! whatever the number of threads.

use super::edges::{target, third, HalfEdges};
use super::{Mesh, MeshError};
use glam::DVec3;
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

/// Normals from a local quadric fit: in the frame of the `rough` normal at `p`, the height
/// `z = a x² + b xy + c y² + d x + e y` through `p` is fitted to the neighbours (the
/// 1-ring, with the 2-ring where the 1-ring has fewer than [`FIT_MIN`] vertices) by least
/// squares, and the normal is the height's at `p`. On a smooth surface its error falls with the cube of the edge length
/// whatever the triangles around `p` look like, where the angle-weighted normal tilts by
/// a few degrees on an uneven fan (see `ARCHITECTURE.md`, skeleton). A vertex whose fit is
/// ill-conditioned, or turns its normal by more than [`FIT_MAX_TURN`] (a crease, a corner:
/// no smooth surface to fit), keeps its rough normal.
pub fn fitted_normals(mesh: &Mesh, rough: &[DVec3]) -> Vec<DVec3> {
    let pos = &mesh.positions;
    let half = HalfEdges::new(pos.len(), &mesh.triangles);
    let ring = |v: u32| half.row(v).iter().map(|&e| target(e));
    // Every face around `v` must face the fitted normal, so that `-n` points into the
    // object at `v` (the ray of the thickness clamp starts inside).
    let faced = |v: u32, n: DVec3| {
        let p = pos[v as usize];
        half.row(v).iter().all(|&e| {
            let (b, c) = (pos[target(e) as usize], pos[third(e) as usize]);
            (b - p).cross(c - p).dot(n) > 0.0
        })
    };
    let cos_max = FIT_MAX_TURN.to_radians().cos();
    (0..pos.len() as u32)
        .into_par_iter()
        .with_min_len(1024)
        .map(|v| {
            let (p, r) = (pos[v as usize], rough[v as usize]);
            let fitted = if half.row(v).len() >= FIT_MIN {
                fit(p, r, ring(v).map(|w| pos[w as usize]))
            } else {
                let mut near: Vec<u32> = ring(v).chain(ring(v).flat_map(ring)).collect();
                near.retain(|&x| x != v);
                near.sort_unstable();
                near.dedup();
                fit(p, r, near.iter().map(|&w| pos[w as usize]))
            };
            match fitted {
                Some(f) if f.dot(rough[v as usize]) >= cos_max && faced(v, f) => f,
                _ => rough[v as usize],
            }
        })
        .collect()
}

/// Fewer neighbours than this and the fit takes the 2-ring too.
pub const FIT_MIN: usize = 6;

/// A fitted normal further than this from the rough one (degrees) is not taken.
pub const FIT_MAX_TURN: f64 = 25.0;

/// The normal of the height through `p` fitted to `points` in the frame of `n`: a quadric,
/// or a cubic when there are enough points for one.
fn fit(p: DVec3, n: DVec3, points: impl Iterator<Item = DVec3> + Clone) -> Option<DVec3> {
    let u = n.any_orthonormal_vector();
    let w = n.cross(u);
    // Scaled to unit mean distance, for conditioning.
    let (sum, count) = points
        .clone()
        .fold((0.0, 0usize), |(s, c), q| (s + q.distance(p), c + 1));
    if count < 5 || sum <= 0.0 {
        return None;
    }
    let k = if count >= CUBIC_MIN { 9 } else { 5 };
    let scale = count as f64 / sum;
    let mut m = [[0.0f64; 10]; 9];
    for q in points {
        let d = (q - p) * scale;
        let (x, y, z) = (d.dot(u), d.dot(w), d.dot(n));
        let row = [
            x,
            y,
            x * x,
            x * y,
            y * y,
            x * x * x,
            x * x * y,
            x * y * y,
            y * y * y,
        ];
        for i in 0..k {
            for j in 0..k {
                m[i][j] += row[i] * row[j];
            }
            m[i][9] += row[i] * z;
        }
    }
    // Gaussian elimination with partial pivoting.
    for col in 0..k {
        let pivot = (col..k).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col].abs() < 1e-9 {
            return None;
        }
        m.swap(col, pivot);
        let top = m[col];
        for row in &mut m[col + 1..k] {
            let f = row[col] / top[col];
            for (x, t) in row[col..].iter_mut().zip(&top[col..]) {
                *x -= f * t;
            }
        }
    }
    let mut s = [0.0; 9];
    for r in (0..k).rev() {
        let mut acc = m[r][9];
        for c in r + 1..k {
            acc -= m[r][c] * s[c];
        }
        s[r] = acc / m[r][r];
    }
    let (gx, gy) = (s[0], s[1]);
    let out = (n - u * gx - w * gy).normalize();
    out.is_finite().then_some(out)
}

/// With this many points or more the fit is a cubic.
pub const CUBIC_MIN: usize = 12;
