//! A character's mirror plane ([`mirror_plane`]): the mesh mirrored through the plane
//! across each axis through its centroid, kept where the mirrored vertices land near the
//! mesh (see `orientation`, whose first cue it is).

use super::edges::{target, third, HalfEdges};
use super::grid::Grid;
use glam::DVec3;

/// The mirrored vertices lie within this share of the mesh's size of a vertex (median).
pub const MIRRORED: f64 = 0.012;

/// The mirror image of the point `p` in the plane of unit normal `n` and offset `o`
/// (the points `q` with `q·n = o`).
pub fn image((n, o): (DVec3, f64), p: DVec3) -> DVec3 {
    p - n * 2.0 * (p.dot(n) - o)
}

/// The mirror image of the direction `v` in a plane of unit normal `n`.
pub fn reflect(n: DVec3, v: DVec3) -> DVec3 {
    v - n * 2.0 * v.dot(n)
}

/// Whether a limb turning about `pivot` reaches across the mirror plane `(n, o)` (unit
/// normal, offset) with one of its `points`: its pivot lies off the plane by more than
/// `radius` (a limb on one side, an arm, a leg; not a neck or a tail on the plane) and a
/// point lies more than `radius` across it, on the other side. Such a limb's cut slipped
/// through the body: a shoulder's plane tilted up through the collar takes the head and
/// the chest with the arm. A pivot not finite reaches nowhere.
pub fn reaches_across(
    (n, o): (DVec3, f64),
    pivot: DVec3,
    radius: f64,
    points: impl IntoIterator<Item = DVec3>,
) -> bool {
    let off = pivot.dot(n) - o;
    off.abs() > radius
        && points
            .into_iter()
            .any(|p| -(p.dot(n) - o) * off.signum() > radius)
}

/// The mirror plane across one of the axes, if the mesh has one (see the module docs).
///
/// How far a mirrored vertex lands from the surface is read off the faces around the
/// nearest vertex (their half-edges, `edges`; `triangles` empty: from that vertex).
/// With `up` given, only a plane that holds it.
pub fn mirror_plane(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    up: Option<DVec3>,
) -> Option<(DVec3, f64)> {
    if positions.len() < 8 {
        return None;
    }
    let (lo, hi) = crate::mesh::bounds(positions);
    let size = (hi - lo).max_element();
    if size <= 0.0 || !size.is_finite() {
        return None;
    }
    let centroid = positions.iter().sum::<DVec3>() / positions.len() as f64;
    let cell = size / 48.0;
    let all: Vec<u32> = (0..positions.len() as u32).collect();
    let grid = Grid::with_cell(positions, &all, cell);
    let around = HalfEdges::new(positions.len(), triangles);
    let step = (positions.len() / 1500).max(1);
    let mut best: Option<(f64, DVec3, f64)> = None;
    for n in [DVec3::X, DVec3::Y, DVec3::Z] {
        if up.is_some_and(|u| u.dot(n).abs() > 0.5) {
            continue;
        }
        let mut offset = centroid.dot(n);
        let mut median = f64::INFINITY;
        // Twice: the second time through the plane the first pairs put halfway.
        for _ in 0..2 {
            let mut gaps = Vec::new();
            let mut shifts = Vec::new();
            for p in positions.iter().step_by(step) {
                let m = image((n, offset), *p);
                let (q, d) = grid
                    .nearest_around(positions, m, 2.0 * cell)
                    .map_or((m, 2.0 * cell), |(d, v)| {
                        (positions[v as usize], gap(&around, positions, v, m, d))
                    });
                gaps.push(d);
                shifts.push((q - m).dot(n));
            }
            median = crate::stats::median(&mut gaps).unwrap_or(f64::INFINITY);
            offset += 0.5 * crate::stats::median(&mut shifts).unwrap_or(f64::INFINITY);
        }
        if best.is_none_or(|b| median < b.0) {
            best = Some((median, n, offset));
        }
    }
    let (median, n, offset) = best?;
    (median <= MIRRORED * size).then_some((n, offset))
}

/// How far `q` lies from the faces around vertex `v` (at most `d`, its distance from `v`).
fn gap(around: &HalfEdges, positions: &[DVec3], v: u32, q: DVec3, d: f64) -> f64 {
    around
        .row(v)
        .iter()
        .map(|&e| {
            let t = [v, target(e), third(e)].map(|i| positions[i as usize]);
            crate::geom::point_triangle(q, t)
        })
        .fold(d, f64::min)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Points on two boxes side by side, mirrored across x = 1, with a tail off to one side.
    pub(crate) fn figure(tail: bool) -> Vec<DVec3> {
        let mut p = Vec::new();
        for i in 0..10 {
            for j in 0..20 {
                for k in 0..6 {
                    let (x, y, z) = (i as f64 * 0.1, j as f64 * 0.1, k as f64 * 0.1);
                    p.push(DVec3::new(0.05 + x, y, z));
                    p.push(DVec3::new(1.95 - x, y, z));
                }
            }
        }
        if tail {
            for j in 0..20 {
                p.push(DVec3::new(
                    1.5 + j as f64 * 0.02,
                    0.0,
                    -0.5 - j as f64 * 0.05,
                ));
            }
        }
        p
    }

    #[test]
    fn the_mirror_plane_is_found_across_the_axis_it_mirrors() {
        let (n, o) = mirror_plane(&figure(false), &[], None).unwrap();
        assert_eq!(n, DVec3::X);
        assert!((o - 1.0).abs() < 0.02, "{o}");
        // A few points off the plane (a curled tail) move nothing.
        let (n, o) = mirror_plane(&figure(true), &[], None).unwrap();
        assert_eq!(n, DVec3::X);
        assert!((o - 1.0).abs() < 0.02, "{o}");
        // A lopsided cloud has none.
        let lopsided: Vec<DVec3> = (0..500)
            .map(|i| {
                let t = i as f64;
                DVec3::new(
                    (t * 0.37).sin().abs() * t.sqrt(),
                    (t * 0.11).cos(),
                    t * 0.01,
                )
            })
            .collect();
        assert!(mirror_plane(&lopsided, &[], None).is_none());
    }

    #[test]
    fn a_surface_mirrored_but_not_its_vertices_has_its_plane() {
        // A sphere bent so that only x = 0 mirrors it, its longitudes turned by a quarter
        // of their spacing: each vertex's mirror image lands on the surface between two
        // vertices, a sixtieth of the size from the nearest.
        let mut body = crate::mesh::shapes::uv_sphere(1.0, 24, 48);
        let turn = glam::DQuat::from_rotation_y(std::f64::consts::TAU / 48.0 * 0.25);
        for p in &mut body.positions {
            let q = turn * *p;
            *p = DVec3::new(q.x, q.y + 0.3 * q.z * q.z, q.z + 0.2 * q.y * q.y);
        }
        let (n, o) = mirror_plane(&body.positions, &body.triangles, None).expect("mirrored");
        assert_eq!(n, DVec3::X);
        assert!(o.abs() < 0.01, "{o}");
        // Read off the vertices alone, it is not.
        assert_eq!(mirror_plane(&body.positions, &[], None), None);
        // With up given along x, a plane must hold it: none does.
        assert_eq!(
            mirror_plane(&body.positions, &body.triangles, Some(DVec3::X)),
            None
        );
        // With up along y, the plane holds it.
        let up = Some(DVec3::Y);
        assert_eq!(
            mirror_plane(&body.positions, &body.triangles, up).map(|(n, _)| n),
            Some(DVec3::X)
        );
    }
}
