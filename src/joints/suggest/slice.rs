//! The mesh's slice by a plane: the loop of it around a point, and how far a limb's root
//! cut can move toward the body while that loop stays the limb's (step 5 of the module
//! docs: a shoulder or a hip).

use super::rules::ROUND;
use super::union_find::UnionFind;
use crate::mesh::Mesh;
use glam::DVec3;
use std::collections::HashMap;

/// How far the loop of the slice of `triangles` (of `mesh`) nearest `point`, by the plane
/// through it (unit `normal`), reaches from `point`; `None` when the plane slices none.
pub(super) fn loop_reach(
    mesh: &Mesh,
    triangles: &[[u32; 3]],
    point: DVec3,
    normal: DVec3,
) -> Option<f64> {
    let positions = &mesh.positions;
    let side = |v: u32| (positions[v as usize] - point).dot(normal);
    // Each edge the plane crosses is a point of the slice; the two a triangle holds are
    // joined.
    let mut ids: HashMap<(u32, u32), usize> = HashMap::new();
    let mut at: Vec<DVec3> = Vec::new();
    let mut joined: Vec<(usize, usize)> = Vec::new();
    for t in triangles {
        let mut crossing = [0usize; 2];
        let mut k = 0;
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let (sa, sb) = (side(a), side(b));
            if (sa > 0.0) == (sb > 0.0) || k == 2 {
                continue;
            }
            crossing[k] = *ids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (pa, pb) = (positions[a as usize], positions[b as usize]);
                at.push(pa + (pb - pa) * (sa / (sa - sb)));
                at.len() - 1
            });
            k += 1;
        }
        if k == 2 {
            joined.push((crossing[0], crossing[1]));
        }
    }
    let mut loops = UnionFind::new(at.len());
    for (a, b) in joined {
        loops.union(a, b);
    }
    let nearest =
        (0..at.len()).min_by(|&a, &b| at[a].distance(point).total_cmp(&at[b].distance(point)))?;
    let own = loops.find(nearest);
    (0..at.len())
        .filter(|&i| loops.find(i) == own)
        .map(|i| at[i].distance(point))
        .reduce(f64::max)
}

/// A mesh to slice, with each triangle's bounding ball (to slice only those near a cut).
pub(super) struct Slicer<'a> {
    mesh: &'a Mesh,
    balls: Vec<(DVec3, f64)>,
}

impl<'a> Slicer<'a> {
    pub(super) fn new(mesh: &'a Mesh) -> Slicer<'a> {
        let balls = mesh
            .triangles
            .iter()
            .map(|t| {
                let p = t.map(|v| mesh.positions[v as usize]);
                let c = (p[0] + p[1] + p[2]) / 3.0;
                (c, p.iter().map(|q| q.distance(c)).fold(0.0, f64::max))
            })
            .collect();
        Slicer { mesh, balls }
    }

    /// How far a limb's root cut through `point` (unit `normal`, into the limb) can move
    /// toward the body, in steps of a tenth of the limb's `width`, while the slice's loop
    /// around it stays within [`ROUND`] widths of its point: up to where the limb meets the
    /// trunk (thighs that touch below the crotch tilt the rings that cut them).
    pub(super) fn toward_body(&self, point: DVec3, normal: DVec3, width: f64) -> f64 {
        if width.is_nan() || width <= 0.0 {
            return 0.0;
        }
        let reach = ROUND * width;
        let (step, steps) = (0.1 * width, 40);
        // Only the triangles near the cut's path: a loop that leaves `reach` crosses a
        // triangle within a width past it.
        let near: Vec<usize> = (0..self.balls.len())
            .filter(|&i| {
                let (c, r) = self.balls[i];
                let along = (point - c).dot(normal).clamp(0.0, steps as f64 * step);
                c.distance(point - normal * along) - r <= reach + width
            })
            .collect();
        let within = |t: f64| {
            let at = point - normal * t;
            let near: Vec<[u32; 3]> = near
                .iter()
                .filter(|&&i| self.balls[i].0.distance(at) - self.balls[i].1 <= reach + width)
                .map(|&i| self.mesh.triangles[i])
                .collect();
            loop_reach(self.mesh, &near, at, normal).is_some_and(|r| r <= reach)
        };
        if !within(0.0) {
            return 0.0;
        }
        let mut best = 0.0;
        for i in 1..=steps {
            let t = i as f64 * step;
            if !within(t) {
                break;
            }
            best = t;
        }
        best
    }
}
