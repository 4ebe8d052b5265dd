//! Exact inside/outside classification of points against a closed mesh: the winding number
//! by signed ray crossings.
//!
//! The ray goes from the query point in `+z`. Triangles are bucketed by their projection on
//! a uniform xy grid, so a query only looks at the triangles of one column, sorted by their
//! top `z` so the scan stops at the first triangle entirely below the point. Degenerate
//! cases (the ray through an edge or a vertex, the point on the surface) are resolved by
//! Simulation of Simplicity: the query is perturbed to `(x + ε, y + ε², z − ε³)`, and every
//! sign is taken from exact predicates. Because shared edges are evaluated by the same exact
//! predicate from both sides, every perturbed ray crosses the surface a well-defined number
//! of times, including on coplanar and cospherical input.
//!
//! Each crossing counts +1 where the ray leaves through the face (the face's normal points
//! up the ray) and −1 where it enters, so the sum is the **winding number** of the closed
//! surface around the point, exactly (Jacobson et al. 2013 show the same number as a sum of
//! solid angles; on a closed surface both are this integer). A point is inside when it is
//! not zero. On a surface that does not cross itself this is the ray's parity; where the
//! surface passes through itself (an arm through the body, fingers through each other, a
//! loose eye in its socket) the overlap counts 2 and stays inside, where the parity would
//! call it outside. Surfaces with a boundary need the generalized winding number
//! ([`super::winding`]).

use super::predicates::{orient2d, orient3d};
use crate::mesh::Mesh;
use glam::DVec3;

/// Point-in-closed-mesh oracle.
pub struct InsideTest {
    tris: Vec<[DVec3; 3]>,
    /// Per triangle: x range, y range, lowest z.
    boxes: Vec<TriBox>,
    lo: [f64; 2],
    hi: DVec3,
    inv_cell: f64,
    nx: usize,
    ny: usize,
    cell_start: Vec<u32>,
    /// Per cell, `(top z, triangle)` by decreasing top z.
    cell_tris: Vec<(f64, u32)>,
}

/// A triangle's bounds, as the query reads them.
#[derive(Clone, Copy, Debug)]
struct TriBox {
    x: [f64; 2],
    y: [f64; 2],
    z_low: f64,
}

impl InsideTest {
    /// Buckets the triangles of `mesh` (which must be closed for the answer to mean
    /// anything).
    pub fn new(mesh: &Mesh) -> Self {
        let (lo3, hi) = mesh.bounds();
        let lo = [lo3.x, lo3.y];
        let (w, h) = ((hi.x - lo3.x).max(1e-300), (hi.y - lo3.y).max(1e-300));
        // About one cell per triangle keeps columns short without a huge grid (fewer cells
        // were slower, more gained nothing and cost memory).
        let target = (mesh.triangles.len() as f64).max(1.0);
        let cell = (w * h / target).sqrt().max(w.max(h) / 4096.0);
        let inv_cell = 1.0 / cell;
        let nx = ((w * inv_cell) as usize + 1).min(4096);
        let ny = ((h * inv_cell) as usize + 1).min(4096);
        let tris: Vec<[DVec3; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|i| mesh.positions[i as usize]))
            .collect();
        let boxes: Vec<TriBox> = tris
            .iter()
            .map(|t| {
                let lo = t[0].min(t[1]).min(t[2]);
                let hi = t[0].max(t[1]).max(t[2]);
                TriBox {
                    x: [lo.x, hi.x],
                    y: [lo.y, hi.y],
                    z_low: lo.z,
                }
            })
            .collect();
        let mut this = InsideTest {
            tris,
            boxes,
            lo,
            hi,
            inv_cell,
            nx,
            ny,
            cell_start: vec![0; nx * ny + 1],
            cell_tris: Vec::new(),
        };
        let ranges: Vec<[usize; 4]> = this
            .boxes
            .iter()
            .map(|b| {
                [
                    this.cx(b.x[0]),
                    this.cx(b.x[1]),
                    this.cy(b.y[0]),
                    this.cy(b.y[1]),
                ]
            })
            .collect();
        for r in &ranges {
            for y in r[2]..=r[3] {
                for x in r[0]..=r[1] {
                    this.cell_start[y * nx + x + 1] += 1;
                }
            }
        }
        for i in 0..nx * ny {
            this.cell_start[i + 1] += this.cell_start[i];
        }
        let mut fill = this.cell_start.clone();
        this.cell_tris = vec![(0.0, 0); this.cell_start[nx * ny] as usize];
        for (ti, r) in ranges.iter().enumerate() {
            let t = &this.tris[ti];
            let top = t[0].z.max(t[1].z).max(t[2].z);
            for y in r[2]..=r[3] {
                for x in r[0]..=r[1] {
                    let c = y * nx + x;
                    this.cell_tris[fill[c] as usize] = (top, ti as u32);
                    fill[c] += 1;
                }
            }
        }
        for c in 0..nx * ny {
            let (a, b) = (this.cell_start[c] as usize, this.cell_start[c + 1] as usize);
            this.cell_tris[a..b].sort_unstable_by(|p, q| q.0.total_cmp(&p.0).then(p.1.cmp(&q.1)));
        }
        this
    }

    #[inline]
    fn cx(&self, x: f64) -> usize {
        (((x - self.lo[0]) * self.inv_cell).max(0.0) as usize).min(self.nx - 1)
    }

    #[inline]
    fn cy(&self, y: f64) -> usize {
        (((y - self.lo[1]) * self.inv_cell).max(0.0) as usize).min(self.ny - 1)
    }

    /// True when `q` is inside the mesh: its winding number is not zero. A point exactly on
    /// the surface is classified as if it were moved by `(ε, ε², −ε³)`: deterministically,
    /// on whichever side that lands.
    pub fn contains(&self, q: DVec3) -> bool {
        self.winding(q) != 0
    }

    /// The winding number of the (closed, oriented) mesh around `q`: +1 inside a part whose
    /// normals point out, 2 where two such parts overlap, 0 outside.
    pub fn winding(&self, q: DVec3) -> i32 {
        if !q.is_finite()
            || q.x < self.lo[0]
            || q.y < self.lo[1]
            || q.x > self.hi.x
            || q.y > self.hi.y
            || q.z > self.hi.z
        {
            return 0;
        }
        let c = self.cy(q.y) * self.nx + self.cx(q.x);
        let list = &self.cell_tris[self.cell_start[c] as usize..self.cell_start[c + 1] as usize];
        let mut winding = 0i32;
        for &(top, ti) in list {
            if top < q.z {
                break; // this and every later triangle lie entirely below the point
            }
            let b = &self.boxes[ti as usize];
            // Cheap bounding-box reject in the projection (the perturbation is
            // infinitesimal, so closed bounds are exact).
            if q.x < b.x[0] || q.x > b.x[1] || q.y < b.y[0] || q.y > b.y[1] {
                continue;
            }
            winding += crossing(&self.tris[ti as usize], q, b.z_low > q.z);
        }
        winding
    }
}

/// How the perturbed upward ray from `q` crosses triangle `t` (whose projected bounding box
/// contains `q`): +1 leaving through it (its normal points up), −1 entering, 0 missing it.
#[inline]
fn crossing(t: &[DVec3; 3], q: DVec3, surely_above: bool) -> i32 {
    let (a, b, c) = ([t[0].x, t[0].y], [t[1].x, t[1].y], [t[2].x, t[2].y]);
    let area = orient2d(a, b, c);
    if area == 0.0 {
        return 0; // vertical triangle: a perturbed ray never crosses it
    }
    let s = area > 0.0;
    let sign = if s { 1 } else { -1 };
    let p = [q.x, q.y];
    if perturbed_side(a, b, p) != s || perturbed_side(b, c, p) != s || perturbed_side(c, a, p) != s
    {
        return 0;
    }
    if surely_above {
        return sign;
    }
    // Above when q is on the side away from the normal's z-direction; on the plane counts
    // as below the face (q is perturbed by -ε³ in z).
    let o = orient3d(t[0], t[1], t[2], q);
    let above = if s { o <= 0.0 } else { o >= 0.0 };
    if above {
        sign
    } else {
        0
    }
}

/// Sign (true = positive) of orient2d(a, b, p + (ε, ε²)).
#[inline]
fn perturbed_side(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    let o = orient2d(a, b, p);
    if o != 0.0 {
        return o > 0.0;
    }
    // d/dpx = -(by - ay), d/dpy = (bx - ax)
    let dy = b[1] - a[1];
    if dy != 0.0 {
        return dy < 0.0;
    }
    b[0] - a[0] > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn sphere_inside_and_outside() {
        let m = shapes::uv_sphere(1.0, 12, 24);
        let t = InsideTest::new(&m);
        assert!(t.contains(DVec3::ZERO));
        assert!(t.contains(DVec3::new(0.5, -0.3, 0.2)));
        assert!(!t.contains(DVec3::new(1.5, 0.0, 0.0)));
        assert!(!t.contains(DVec3::new(0.0, 0.0, -1.2)));
        assert!(!t.contains(DVec3::new(0.0, 0.0, 1.2)));
    }

    #[test]
    fn rays_through_vertices_and_edges_count_once() {
        // A cube grid: the +z ray from points on the grid lines passes exactly through
        // vertices and edges of the top and bottom faces.
        let m = shapes::cube_grid(1.0, 4);
        let t = InsideTest::new(&m);
        for i in 0..=8 {
            for j in 0..=8 {
                let x = -0.5 + i as f64 / 8.0;
                let y = -0.5 + j as f64 / 8.0;
                // Points on the faces x = -0.5 and y = -0.5 are perturbed inwards (+ε, +ε²).
                let inside_xy = i < 8 && j < 8;
                assert_eq!(t.contains(DVec3::new(x, y, 0.1)), inside_xy, "({x}, {y})");
                assert!(!t.contains(DVec3::new(x, y, 0.75)));
                assert!(!t.contains(DVec3::new(x, y, -0.75)));
            }
        }
    }

    /// Two spheres whose volumes overlap, as one mesh: the overlap is inside (winding 2),
    /// where the parity of the crossings would call it outside.
    #[test]
    fn overlapping_parts_count_twice_and_stay_inside() {
        let mut m = shapes::uv_sphere(1.0, 12, 24);
        let other = shapes::uv_sphere(1.0, 12, 24);
        let n = m.positions.len() as u32;
        m.positions.extend(
            other
                .positions
                .iter()
                .map(|p| *p + DVec3::new(1.0, 0.1, 0.05)),
        );
        m.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + n)));
        let t = InsideTest::new(&m);
        assert_eq!(t.winding(DVec3::new(0.5, 0.05, 0.0)), 2);
        assert!(t.contains(DVec3::new(0.5, 0.05, 0.0)));
        assert_eq!(t.winding(DVec3::new(-0.5, 0.0, 0.0)), 1);
        assert_eq!(t.winding(DVec3::new(1.6, 0.1, 0.0)), 1);
        assert_eq!(t.winding(DVec3::new(3.0, 0.0, 0.0)), 0);
        // Turned inside out, the same part counts −1: still not outside.
        let mut flipped = shapes::uv_sphere(1.0, 12, 24);
        for tri in &mut flipped.triangles {
            tri.swap(1, 2);
        }
        let t = InsideTest::new(&flipped);
        assert_eq!(t.winding(DVec3::ZERO), -1);
        assert!(t.contains(DVec3::ZERO));
    }
}
