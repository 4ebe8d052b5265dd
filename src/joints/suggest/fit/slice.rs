//! The mesh's slice by a plane: the loop of it around a point, and how far a limb's root
//! cut can move toward the body while that loop stays the limb's (stage 6: a shoulder or a
//! hip).

use crate::joints::suggest::rules::ROUND;
use crate::joints::suggest::union_find::UnionFind;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A cube of side `s` with its lowest corner at `at`, as twelve triangles.
    fn cube(mesh: &mut Mesh, at: DVec3, s: f64) {
        let base = mesh.positions.len() as u32;
        for k in 0..8 {
            let corner = DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64);
            mesh.positions.push(at + corner * s);
        }
        let faces = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        for f in faces {
            mesh.triangles.push([base + f[0], base + f[1], base + f[2]]);
            mesh.triangles.push([base + f[0], base + f[2], base + f[3]]);
        }
    }

    #[test]
    fn a_slice_s_loop_is_the_one_around_the_point() {
        let mut mesh = Mesh {
            positions: Vec::new(),
            triangles: Vec::new(),
        };
        cube(&mut mesh, DVec3::ZERO, 1.0);
        // A second, bigger cube beside it: its loop is another one.
        cube(&mut mesh, DVec3::new(3.0, 0.0, 0.0), 2.0);
        let all = mesh.triangles.clone();
        let centre = DVec3::new(0.5, 0.5, 0.5);
        let reach = loop_reach(&mesh, &all, centre, DVec3::Z).unwrap();
        assert!((reach - 0.5f64.sqrt()).abs() < 1e-9, "{reach}");
        // Past the cubes, nothing is sliced.
        assert_eq!(
            loop_reach(&mesh, &all, DVec3::new(0.5, 0.5, 5.0), DVec3::Z),
            None
        );
        // The cut moves down the small cube's side until it leaves it (a tenth of the
        // width at a time): the loop's reach stays the same to its bottom.
        let slicer = Slicer::new(&mesh);
        let moved = slicer.toward_body(DVec3::new(0.5, 0.5, 0.93), DVec3::Z, 0.5);
        assert!((moved - 0.9).abs() < 1e-9, "{moved}");
    }
}
