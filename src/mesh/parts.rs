//! Parts: the connected pieces of a mesh, and which of them are the *body* and which ride
//! along.
//!
//! Downloaded characters often come with separate small pieces: eyes, teeth, eyebrows,
//! buttons. They have no skeleton worth the name, and inside the body (an eye in its
//! socket) they would stop the body's medial balls and spoil its skeleton. So a part whose
//! surface area is under [`RIDER_AREA`] of the largest part's is a *rider*: the skeleton is
//! built on the body alone, a rider's vertices get `d = 0` (`sp = p`, their bone springs
//! hold them rigidly) and each rider goes with the section of the body vertex nearest to it
//! (see `joints`). Riders need not be closed.

use super::Mesh;
use glam::DVec3;
use rayon::prelude::*;

/// A part is a rider when its area is below this fraction of the largest part's.
pub const RIDER_AREA: f64 = 0.1;

/// The parts of a mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Parts {
    /// Part of each vertex (numbered in order of first vertex).
    pub part_of: Vec<u32>,
    /// Surface area of each part.
    pub area: Vec<f64>,
    /// Whether each part is a rider.
    pub rider: Vec<bool>,
}

impl Parts {
    /// The parts of `mesh` (by shared vertices) and which ride along.
    pub fn of(mesh: &Mesh) -> Parts {
        Parts::measured(mesh).0
    }

    /// [`Parts::of`], with the volume of each part and the faces of zero area, measured in
    /// the same pass over the faces.
    pub(super) fn measured(mesh: &Mesh) -> (Parts, Measures) {
        let part_of = components(mesh.positions.len(), &mesh.triangles);
        let parts = part_of.iter().map(|&p| p as usize + 1).max().unwrap_or(0);
        let face = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let cross = (b - a).cross(c - a);
            (
                0.5 * cross.length(),
                a.dot(b.cross(c)) / 6.0,
                usize::from(cross == DVec3::ZERO),
            )
        };
        let (area, volume, zero_area_faces) = if parts == 1 {
            let (a, v, z) = mesh
                .triangles
                .par_iter()
                .map(face)
                .reduce(|| (0.0, 0.0, 0), |x, y| (x.0 + y.0, x.1 + y.1, x.2 + y.2));
            (vec![a], vec![v], z)
        } else {
            let (mut area, mut volume, mut zero) = (vec![0.0; parts], vec![0.0; parts], 0);
            for t in &mesh.triangles {
                let (a, v, z) = face(t);
                let k = part_of[t[0] as usize] as usize;
                area[k] += a;
                volume[k] += v;
                zero += z;
            }
            (area, volume, zero)
        };
        // A vertex no face uses is not a part that could ride (validated meshes have none).
        let mut has_faces = vec![parts == 1 && !mesh.triangles.is_empty(); parts];
        if parts > 1 {
            for t in &mesh.triangles {
                has_faces[part_of[t[0] as usize] as usize] = true;
            }
        }
        let largest = area.iter().copied().fold(0.0, f64::max);
        let rider = area
            .iter()
            .zip(&has_faces)
            .map(|(&a, &faces)| faces && a < RIDER_AREA * largest)
            .collect();
        (
            Parts {
                part_of,
                area,
                rider,
            },
            Measures {
                volume,
                zero_area_faces,
            },
        )
    }

    /// Number of parts.
    pub fn len(&self) -> usize {
        self.area.len()
    }

    /// No parts (no vertices).
    pub fn is_empty(&self) -> bool {
        self.area.is_empty()
    }

    /// Number of riders.
    pub fn riders(&self) -> usize {
        self.rider.iter().filter(|&&r| r).count()
    }

    /// Is vertex `v` on a rider?
    pub fn is_rider_vertex(&self, v: usize) -> bool {
        self.rider[self.part_of[v] as usize]
    }

    /// For each vertex of a rider, the body vertex its part goes with: the body vertex
    /// nearest to any of the part's vertices. `None` for body vertices (and for everything
    /// when there are no riders).
    pub fn hosts(&self, positions: &[DVec3]) -> Vec<Option<u32>> {
        let n = positions.len();
        if self.riders() == 0 {
            return vec![None; n];
        }
        let body: Vec<u32> = (0..n as u32)
            .filter(|&v| !self.is_rider_vertex(v as usize))
            .collect();
        let grid = Grid::new(positions, &body);
        let mut best: Vec<(f64, u32)> = vec![(f64::INFINITY, u32::MAX); self.len()];
        for v in 0..n {
            let part = self.part_of[v] as usize;
            if !self.rider[part] {
                continue;
            }
            // (Only nearer than the part's best so far counts.)
            if let Some((d, h)) = grid.nearest_within(positions, positions[v], best[part].0) {
                if d < best[part].0 {
                    best[part] = (d, h);
                }
            }
        }
        (0..n)
            .map(|v| {
                let part = self.part_of[v] as usize;
                (self.rider[part] && best[part].1 != u32::MAX).then_some(best[part].1)
            })
            .collect()
    }

    /// The body: its vertices in order (`old`), and for every vertex its index in the body
    /// mesh (`None` on riders), with the body's triangles.
    pub fn body(&self, mesh: &Mesh) -> (Mesh, Vec<u32>) {
        self.select(mesh, |k| !self.rider[k])
    }

    /// The body parts with faces, by number (a vertex no face uses is a part of its own,
    /// with no area).
    pub fn body_parts(&self) -> Vec<usize> {
        (0..self.len())
            .filter(|&k| !self.rider[k] && self.area[k] > 0.0)
            .collect()
    }

    /// One part as a mesh of its own, with the index in `mesh` of each of its vertices;
    /// `loose`: with the vertices no face uses (unwelded twins, which take their twin's
    /// skeleton).
    pub fn part(&self, mesh: &Mesh, k: usize, loose: bool) -> (Mesh, Vec<u32>) {
        self.select(mesh, |j| {
            j == k || (loose && !self.rider[j] && self.area[j] <= 0.0)
        })
    }

    /// The parts whose flag in `keep` (one per part) is set, as one mesh, and the index in
    /// `mesh` of each of its vertices.
    ///
    /// # Panics
    /// If `keep` has fewer flags than there are parts.
    pub fn select_parts(&self, mesh: &Mesh, keep: &[bool]) -> (Mesh, Vec<u32>) {
        self.select(mesh, |k| keep[k])
    }

    /// The parts `keep` says yes to, as one mesh, and the index in `mesh` of each vertex.
    fn select(&self, mesh: &Mesh, keep: impl Fn(usize) -> bool) -> (Mesh, Vec<u32>) {
        let kept = |v: usize| keep(self.part_of[v] as usize);
        let mut index = vec![u32::MAX; mesh.positions.len()];
        let mut old = Vec::new();
        let mut positions = Vec::new();
        for (v, p) in mesh.positions.iter().enumerate() {
            if kept(v) {
                index[v] = old.len() as u32;
                old.push(v as u32);
                positions.push(*p);
            }
        }
        let triangles = mesh
            .triangles
            .iter()
            .filter(|t| kept(t[0] as usize))
            .map(|t| t.map(|v| index[v as usize]))
            .collect();
        (
            Mesh {
                positions,
                triangles,
            },
            old,
        )
    }
}

/// What [`Parts::measured`] measures besides areas.
pub(super) struct Measures {
    /// Signed volume of each part (positive when outward oriented and closed).
    pub volume: Vec<f64>,
    /// Faces of exactly zero area.
    pub zero_area_faces: usize,
}

/// Connected components by shared vertices, numbered in order of their first vertex.
pub(super) fn components(n: usize, triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for t in triangles {
        let r0 = find(&mut parent, t[0]);
        for &v in &t[1..] {
            let r = find(&mut parent, v);
            if r != r0 {
                // The smaller root wins, so numbering follows the first vertex.
                let (lo, hi) = (r.min(r0), r.max(r0));
                parent[hi as usize] = lo;
            }
        }
    }
    let mut number = vec![u32::MAX; n];
    let mut next = 0;
    let mut out = vec![0u32; n];
    for v in 0..n as u32 {
        let r = find(&mut parent, v) as usize;
        if number[r] == u32::MAX {
            number[r] = next;
            next += 1;
        }
        out[v as usize] = number[r];
    }
    out
}

/// A uniform grid of some points, for nearest-point queries.
pub(super) struct Grid {
    lo: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// Cell of each entry of `points`, sorted: `start[c]..start[c + 1]`.
    start: Vec<u32>,
    points: Vec<u32>,
}

impl Grid {
    pub(super) fn new(positions: &[DVec3], which: &[u32]) -> Grid {
        let ps: Vec<DVec3> = which.iter().map(|&v| positions[v as usize]).collect();
        let (lo, hi) = super::bounds(&ps);
        let extent = (hi - lo).max(DVec3::splat(1e-300));
        // About two points per cell, at most 2^21 cells.
        let cells = (which.len() as f64 / 2.0).clamp(1.0, f64::from(1u32 << 21));
        let cell = (extent.x * extent.y * extent.z / cells)
            .cbrt()
            .max(extent.max_element() / 128.0);
        let dims = [0, 1, 2].map(|k| ((extent[k] / cell) as usize + 1).min(1 << 10));
        let cell_of = |p: DVec3| {
            let c = [0, 1, 2].map(|k| (((p[k] - lo[k]) / cell).max(0.0) as usize).min(dims[k] - 1));
            (c[2] * dims[1] + c[1]) * dims[0] + c[0]
        };
        let total = dims[0] * dims[1] * dims[2];
        let mut start = vec![0u32; total + 1];
        for p in &ps {
            start[cell_of(*p) + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut points = vec![0u32; which.len()];
        for (k, p) in ps.iter().enumerate() {
            let c = cell_of(*p);
            points[fill[c] as usize] = which[k];
            fill[c] += 1;
        }
        Grid {
            lo,
            cell,
            dims,
            start,
            points,
        }
    }

    /// The nearest grid point to `q` and its squared distance (of two as near, the lower
    /// index).
    pub(super) fn nearest(&self, positions: &[DVec3], q: DVec3) -> Option<(f64, u32)> {
        self.nearest_within(positions, q, f64::INFINITY)
    }

    /// [`Grid::nearest`] among the points whose squared distance to `q` is at most
    /// `limit`: `None` when there is none. A search with a limit stops at the cells that
    /// lie farther, where one without searches on until it finds a point.
    pub(super) fn nearest_within(
        &self,
        positions: &[DVec3],
        q: DVec3,
        limit: f64,
    ) -> Option<(f64, u32)> {
        if self.points.is_empty() {
            return None;
        }
        let c = [0, 1, 2].map(|k| {
            (((q[k] - self.lo[k]) / self.cell).floor() as i64).clamp(0, self.dims[k] as i64 - 1)
        });
        let mut best = (f64::INFINITY, u32::MAX);
        let visit = |cc: [i64; 3], best: &mut (f64, u32)| {
            if (0..3).any(|k| cc[k] < 0 || cc[k] >= self.dims[k] as i64) {
                return;
            }
            let id =
                (cc[2] as usize * self.dims[1] + cc[1] as usize) * self.dims[0] + cc[0] as usize;
            for &v in &self.points[self.start[id] as usize..self.start[id + 1] as usize] {
                let d = positions[v as usize].distance_squared(q);
                if d <= limit && (d < best.0 || (d == best.0 && v < best.1)) {
                    *best = (d, v);
                }
            }
        };
        // Grow shells of cells until the best is closer than anything beyond the shell.
        let max_r = self.dims.iter().max().copied().unwrap_or(1) as i64;
        for r in 0..=max_r {
            // Every cell of shell r lies at least r - 1 cells from q.
            let gap = (r - 1).max(0) as f64 * self.cell;
            if gap * gap > limit {
                break;
            }
            // The shell's cells only: all of its two faces across z and y, and the two
            // ends across x of the rows between.
            for dz in -r..=r {
                for dy in -r..=r {
                    if dz.abs() == r || dy.abs() == r {
                        for dx in -r..=r {
                            visit([c[0] + dx, c[1] + dy, c[2] + dz], &mut best);
                        }
                    } else {
                        visit([c[0] - r, c[1] + dy, c[2] + dz], &mut best);
                        if r > 0 {
                            visit([c[0] + r, c[1] + dy, c[2] + dz], &mut best);
                        }
                    }
                }
            }
            // Everything outside shell r is at least r cells away from q's cell.
            let reach = r as f64 * self.cell;
            if best.1 != u32::MAX && best.0 <= reach * reach {
                break;
            }
        }
        (best.1 != u32::MAX).then_some(best)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn a_small_sphere_inside_rides() {
        let big = shapes::uv_sphere(1.0, 24, 12);
        let small = shapes::uv_sphere(0.1, 8, 6);
        let mut mesh = big.clone();
        let off = mesh.positions.len() as u32;
        mesh.positions.extend(
            small
                .positions
                .iter()
                .map(|p| *p + DVec3::new(0.5, 0.0, 0.0)),
        );
        mesh.triangles
            .extend(small.triangles.iter().map(|t| t.map(|v| v + off)));
        let parts = Parts::of(&mesh);
        assert_eq!(parts.len(), 2);
        assert_eq!(parts.rider, vec![false, true]);
        let hosts = parts.hosts(&mesh.positions);
        assert!(hosts[..off as usize].iter().all(Option::is_none));
        let h = hosts[off as usize].expect("a host");
        // The body vertex nearest to the small sphere: on the big sphere's +x side.
        assert!(
            mesh.positions[h as usize].x > 0.9,
            "{:?}",
            mesh.positions[h as usize]
        );
        assert!(hosts[off as usize..].iter().all(|&x| x == Some(h)));
        let (body, old) = parts.body(&mesh);
        assert_eq!(body, big);
        assert_eq!(old.len(), big.positions.len());
    }

    #[test]
    fn nearest_matches_brute_force() {
        let m = shapes::uv_sphere(1.0, 30, 15);
        let all: Vec<u32> = (0..m.positions.len() as u32).collect();
        let grid = Grid::new(&m.positions, &all);
        for k in 0..50 {
            let q = DVec3::new(
                (k as f64 * 0.37).sin() * 1.7,
                (k as f64).cos() * 0.3,
                0.1 * k as f64 - 2.5,
            );
            let brute = all
                .iter()
                .map(|&v| (m.positions[v as usize].distance_squared(q), v))
                .fold((f64::INFINITY, u32::MAX), |a, b| {
                    if b.0 < a.0 || (b.0 == a.0 && b.1 < a.1) {
                        b
                    } else {
                        a
                    }
                });
            assert_eq!(grid.nearest(&m.positions, q), Some(brute));
            // Within a bound: the same point when it is that near, else none.
            for limit in [0.0, 0.01, 0.1, 0.5, 2.0, 10.0] {
                let within = grid.nearest_within(&m.positions, q, limit);
                assert_eq!(within, (brute.0 <= limit).then_some(brute), "{q} {limit}");
            }
        }
    }
}
