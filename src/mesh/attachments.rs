//! Attachments: where a body's separate parts touch or pass into each other.
//!
//! A character modelled in pieces (a mech's plates, a hand pushed into its sleeve, a shin
//! under its trousers) is one puppet where its pieces meet. An *attachment* joins a vertex of
//! one body part to the nearest vertex of another body part when it lies inside that part
//! (its generalized winding number, [`crate::geom::winding`]) or touches it: within a
//! quarter of the two vertices' longest edges together, so a seam where two pieces share
//! their rings is joined, and two legs half an edge apart are not. Riders (see `parts`)
//! have hosts instead. The suggestion walks the mesh's edges and its attachments as one graph,
//! and connected cuts and whole sections take a piece with what is attached to it.

use super::grid::Grid;
use super::{Mesh, Parts};
use crate::geom::winding::Winding;
use glam::DVec3;
use rayon::prelude::*;

/// The attachments of `mesh` between its body parts, each pair of vertices once, lower first
/// (none for a mesh of one body part).
pub fn attachments(mesh: &Mesh) -> Vec<(u32, u32)> {
    Parts::of(mesh).attachments(mesh)
}

/// A body part, looked up for attachments.
struct Piece {
    part: usize,
    grid: Grid,
    winding: Winding,
    /// Its vertices' longest reach.
    far: f64,
    /// Its box, grown by its longest edge.
    lo: DVec3,
    hi: DVec3,
}

/// The pieces' boxes in a uniform grid (cells as large as the median box), so a vertex
/// looks only at the pieces whose boxes share its cell: a mesh of thousands of pieces is
/// not every vertex against every piece.
struct Boxes {
    cell: f64,
    cells: std::collections::HashMap<[i64; 3], Vec<usize>>,
    /// Pieces whose boxes span too many cells, looked at by every vertex.
    big: Vec<usize>,
}

/// A box spanning more cells than this is looked at by every vertex.
const MOST_CELLS: i64 = 512;

impl Boxes {
    fn new(pieces: &[Piece]) -> Boxes {
        let mut sizes: Vec<f64> = pieces
            .iter()
            .map(|p| (p.hi - p.lo).max_element())
            .filter(|e| e.is_finite() && *e > 0.0)
            .collect();
        let cell = crate::stats::median(&mut sizes).unwrap_or(1.0);
        let mut out = Boxes {
            cell,
            cells: Default::default(),
            big: Vec::new(),
        };
        for (k, p) in pieces.iter().enumerate() {
            let (lo, hi) = (out.key(p.lo), out.key(p.hi));
            let span = (0..3)
                .map(|d| hi[d].saturating_sub(lo[d]).saturating_add(1))
                .fold(1i64, i64::saturating_mul);
            if !(1..=MOST_CELLS).contains(&span) {
                out.big.push(k);
                continue;
            }
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        out.cells.entry([x, y, z]).or_default().push(k);
                    }
                }
            }
        }
        out
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        let k = (p / self.cell).floor();
        [k.x, k.y, k.z].map(|c| c.clamp(-1e15, 1e15) as i64)
    }

    /// The pieces whose boxes may hold `p`.
    fn near(&self, p: DVec3) -> impl Iterator<Item = usize> + '_ {
        let here = self.cells.get(&self.key(p)).map_or(&[][..], Vec::as_slice);
        here.iter().chain(&self.big).copied()
    }
}

impl Parts {
    /// The attachments between the body parts of `mesh` (these parts' mesh), each pair of
    /// vertices once, lower first; see the module docs.
    pub fn attachments(&self, mesh: &Mesh) -> Vec<(u32, u32)> {
        let body = self.body_parts();
        if body.len() < 2 {
            return Vec::new();
        }
        let positions = &mesh.positions;
        let n = positions.len();
        // Each vertex's longest edge: how far it reaches for an attachment.
        let mut reach = vec![0.0f64; n];
        for t in &mesh.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let l = positions[a as usize].distance(positions[b as usize]);
                for v in [a, b] {
                    let r = &mut reach[v as usize];
                    *r = r.max(l);
                }
            }
        }
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); self.len()];
        for (v, &k) in self.part_of.iter().enumerate() {
            members[k as usize].push(v as u32);
        }
        let mut faces: Vec<Vec<[u32; 3]>> = vec![Vec::new(); self.len()];
        for t in &mesh.triangles {
            faces[self.part_of[t[0] as usize] as usize].push(*t);
        }
        // Each body part's grid, winding number, and box grown by its longest reach.
        let found: Vec<Piece> = body
            .par_iter()
            .map(|&k| {
                let ps: Vec<DVec3> = members[k].iter().map(|&v| positions[v as usize]).collect();
                let (lo, hi) = super::bounds(&ps);
                let far = members[k]
                    .iter()
                    .map(|&v| reach[v as usize])
                    .fold(0.0, f64::max);
                Piece {
                    part: k,
                    grid: Grid::new(positions, &members[k]),
                    winding: Winding::new(positions, &faces[k]),
                    far,
                    lo: lo - DVec3::splat(far),
                    hi: hi + DVec3::splat(far),
                }
            })
            .collect();
        let boxes = Boxes::new(&found);
        let mut out: Vec<(u32, u32)> = found
            .par_iter()
            .flat_map_iter(|a| {
                let found = &found;
                let reach = &reach;
                let boxes = &boxes;
                members[a.part].iter().flat_map(move |&v| {
                    let p = positions[v as usize];
                    boxes.near(p).filter_map(move |k| {
                        let b = &found[k];
                        if b.part == a.part || p.cmplt(b.lo).any() || p.cmpgt(b.hi).any() {
                            return None;
                        }
                        // A vertex touches at most this far (the reach of the farthest
                        // reaching of the piece's): the nearest is looked for that far
                        // first, and farther only when `p` lies inside the piece.
                        let most = 0.25 * (reach[v as usize] + b.far);
                        let near = b.grid.nearest_within(positions, p, most * most);
                        if let Some((d2, w)) = near {
                            let touch = 0.25 * (reach[v as usize] + reach[w as usize]);
                            if d2 <= touch * touch {
                                return Some((v.min(w), v.max(w)));
                            }
                        }
                        if b.winding.at(p) <= 0.5 {
                            return None;
                        }
                        // (Found within the bound, it is the nearest of all.)
                        let (_, w) = near.or_else(|| b.grid.nearest(positions, p))?;
                        Some((v.min(w), v.max(w)))
                    })
                })
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh::{shapes, Mesh};
    use glam::DVec3;

    /// Two spheres of radius 1 with centres `gap + 2` apart.
    fn pair(gap: f64) -> (Mesh, usize) {
        let a = shapes::uv_sphere(1.0, 24, 48);
        let mut mesh = a.clone();
        let off = mesh.positions.len();
        mesh.positions.extend(
            a.positions
                .iter()
                .map(|p| *p + DVec3::new(2.0 + gap, 0.0, 0.0)),
        );
        mesh.triangles
            .extend(a.triangles.iter().map(|t| t.map(|v| v + off as u32)));
        (mesh, off)
    }

    #[test]
    fn parts_that_overlap_are_attached_where_they_meet() {
        let (mesh, off) = pair(-0.2);
        let attachments = super::attachments(&mesh);
        assert!(!attachments.is_empty());
        for &(a, b) in &attachments {
            assert!(
                (a as usize) < off && b as usize >= off,
                "{a}-{b} joins two parts"
            );
            // Both ends near the plane the spheres cross at (x = 0.9).
            for v in [a, b] {
                let x = mesh.positions[v as usize].x;
                assert!((x - 0.9).abs() < 0.25, "vertex {v} at x = {x}");
            }
        }
    }

    #[test]
    fn parts_a_gap_apart_or_one_part_have_none() {
        assert!(super::attachments(&pair(0.5).0).is_empty());
        assert!(super::attachments(&shapes::uv_sphere(1.0, 16, 8)).is_empty());
    }
}
