//! Surface self-intersections: which faces of a triangle mesh cross another face.
//!
//! Two faces that share no vertex intersect when an edge of one crosses the other
//! (general position); the crossing test uses the exact [`orient3d`] predicate, so the
//! count does not depend on rounding. Faces that share a vertex or an edge are not
//! compared (their contact is the mesh's own), and coplanar overlaps are not counted.
//! Candidate pairs come from a uniform grid of the faces' bounding boxes.

use super::predicates::orient3d;
use glam::DVec3;
use std::collections::HashMap;

/// Faces that cross another face in `now` and did not in `rest` (the same triangles).
///
/// # Panics
/// If a triangle names a vertex beyond either position list.
pub fn new_crossings(rest: &[DVec3], now: &[DVec3], triangles: &[[u32; 3]]) -> usize {
    let before = intersecting_faces(rest, triangles);
    let after = intersecting_faces(now, triangles);
    before
        .iter()
        .zip(&after)
        .filter(|(b, a)| **a && !**b)
        .count()
}

/// Per face, whether it crosses another face it shares no vertex with.
///
/// # Panics
/// If a triangle names a vertex beyond `positions`.
pub fn intersecting_faces(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<bool> {
    let mut hit = vec![false; triangles.len()];
    let corners = |f: usize| triangles[f].map(|i| positions[i as usize]);
    let boxes: Vec<(DVec3, DVec3)> = (0..triangles.len())
        .map(|f| {
            let [a, b, c] = corners(f);
            (a.min(b).min(c), a.max(b).max(c))
        })
        .filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
        .collect();
    if boxes.len() != triangles.len() || triangles.is_empty() {
        return hit;
    }
    // Cell size: twice the mean box diagonal, so a face overlaps few cells.
    let mean = boxes.iter().map(|(l, h)| (*h - *l).length()).sum::<f64>() / boxes.len() as f64;
    let cell = (2.0 * mean).max(f64::MIN_POSITIVE);
    let origin = boxes
        .iter()
        .fold(DVec3::splat(f64::INFINITY), |m, b| m.min(b.0));
    let key = |p: DVec3| {
        let k = ((p - origin) / cell).floor();
        (k.x as i64, k.y as i64, k.z as i64)
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
    for (f, (lo, hi)) in boxes.iter().enumerate() {
        let (a, b) = (key(*lo), key(*hi));
        // A degenerate huge face would fill the grid; such a mesh is compared by its
        // first cells only.
        if (b.0 - a.0 + 1) * (b.1 - a.1 + 1) * (b.2 - a.2 + 1) > 4096 {
            continue;
        }
        for x in a.0..=b.0 {
            for y in a.1..=b.1 {
                for z in a.2..=b.2 {
                    grid.entry((x, y, z)).or_default().push(f as u32);
                }
            }
        }
    }
    for (&cell_key, faces) in &grid {
        for (k, &f) in faces.iter().enumerate() {
            for &g in &faces[k + 1..] {
                let (f, g) = (f as usize, g as usize);
                let (bf, bg) = (boxes[f], boxes[g]);
                if bf.0.cmpgt(bg.1).any() || bg.0.cmpgt(bf.1).any() {
                    continue;
                }
                // Each pair once: in the first cell both boxes overlap.
                let first = key(bf.0.max(bg.0));
                if first != cell_key {
                    continue;
                }
                if triangles[f].iter().any(|v| triangles[g].contains(v)) {
                    continue;
                }
                if (hit[f] && hit[g]) || !cross(corners(f), corners(g)) {
                    continue;
                }
                hit[f] = true;
                hit[g] = true;
            }
        }
    }
    hit
}

/// Do two triangles (no shared vertex) cross: does an edge of one pass through the other?
fn cross(t: [DVec3; 3], u: [DVec3; 3]) -> bool {
    (0..3).any(|e| edge_crosses(t[e], t[(e + 1) % 3], u))
        || (0..3).any(|e| edge_crosses(u[e], u[(e + 1) % 3], t))
}

/// Does the segment `pq` pass through the interior of triangle `abc`?
fn edge_crosses(p: DVec3, q: DVec3, [a, b, c]: [DVec3; 3]) -> bool {
    let (sp, sq) = (orient3d(a, b, c, p), orient3d(a, b, c, q));
    if sp == 0.0 || sq == 0.0 || (sp > 0.0) == (sq > 0.0) {
        return false;
    }
    let s = [
        orient3d(p, q, a, b),
        orient3d(p, q, b, c),
        orient3d(p, q, c, a),
    ];
    s.iter().all(|&x| x > 0.0) || s.iter().all(|&x| x < 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_mesh_does_not_cross_itself_and_two_overlapping_ones_do() {
        let m = crate::mesh::shapes::uv_sphere(1.0, 16, 12);
        assert!(!intersecting_faces(&m.positions, &m.triangles).contains(&true));
        // A second copy moved by half a radius: the faces near the two spheres' crossing
        // circle cross, the rest do not.
        let n = m.positions.len() as u32;
        let mut positions = m.positions.clone();
        positions.extend(m.positions.iter().map(|p| *p + DVec3::new(0.5, 0.0, 0.0)));
        let mut triangles = m.triangles.clone();
        triangles.extend(m.triangles.iter().map(|t| t.map(|i| i + n)));
        let hit = intersecting_faces(&positions, &triangles);
        let count = hit.iter().filter(|&&h| h).count();
        assert!(count > 20 && count < triangles.len() / 2, "{count}");
    }

    #[test]
    fn an_edge_through_a_triangle_crosses_it_and_one_beside_it_does_not() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let through = [
            DVec3::new(0.2, 0.2, -1.0),
            DVec3::new(0.2, 0.2, 1.0),
            DVec3::new(5.0, 5.0, 0.0),
        ];
        let beside = [
            DVec3::new(2.0, 2.0, -1.0),
            DVec3::new(2.0, 2.0, 1.0),
            DVec3::new(5.0, 5.0, 0.0),
        ];
        assert!(cross(t, through));
        assert!(!cross(t, beside));
    }
}
