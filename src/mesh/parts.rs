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

use super::grid::Grid;
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
pub(crate) fn components(n: usize, triangles: &[[u32; 3]]) -> Vec<u32> {
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
}
