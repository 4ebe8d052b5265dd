//! Angle-weighted vertex normals (Thürmer & Wüthrich): each face contributes its unit normal
//! weighted by the corner angle at the vertex, so the result does not depend on how a flat
//! region happens to be triangulated.

use super::{Mesh, MeshError};
use glam::DVec3;

/// Unit outward normal per vertex.
///
/// Zero-area faces contribute nothing. A vertex whose faces all have zero area falls back to
/// the sum of its faces' unnormalised normals.
///
/// # Errors
/// [`MeshError::Degenerate`] when a vertex has no defined normal at all.
pub fn vertex_normals(mesh: &Mesh) -> Result<Vec<DVec3>, MeshError> {
    let mut acc = vec![DVec3::ZERO; mesh.positions.len()];
    let mut fallback = vec![DVec3::ZERO; mesh.positions.len()];
    for t in &mesh.triangles {
        let p = t.map(|i| mesh.positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let len = n.length();
        for k in 0..3 {
            fallback[t[k] as usize] += n;
        }
        if len.is_nan() || len <= 0.0 {
            continue;
        }
        let unit = n / len;
        for k in 0..3 {
            let e1 = p[(k + 1) % 3] - p[k];
            let e2 = p[(k + 2) % 3] - p[k];
            // atan2 of |cross| and dot is accurate for tiny and near-straight angles.
            let angle = e1.cross(e2).length().atan2(e1.dot(e2));
            acc[t[k] as usize] += angle * unit;
        }
    }
    acc.iter()
        .zip(&fallback)
        .enumerate()
        .map(|(i, (a, f))| {
            a.try_normalize()
                .or_else(|| f.try_normalize())
                .ok_or_else(|| {
                    MeshError::Degenerate(format!(
                        "vertex {} has no defined normal (its faces cancel out or have no area)",
                        i + 1
                    ))
                })
        })
        .collect()
}
