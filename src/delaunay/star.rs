//! [`Stars`]: the Delaunay neighbours of a vertex after the build, by a walk around it
//! through the tetrahedra's neighbour links from one tetrahedron that holds it.

use super::cell::FREE;
use super::{Delaunay, INFINITE};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// One tetrahedron holding each vertex (internal ids), to walk around it.
pub struct Stars<'a> {
    delaunay: &'a Delaunay,
    cell_of: Vec<u32>,
}

impl Delaunay {
    /// The stars of every vertex: one pass over the tetrahedra, on every core.
    pub fn stars(&self) -> Stars<'_> {
        let cell_of: Vec<AtomicU32> = (0..self.pts.len())
            .map(|_| AtomicU32::new(INFINITE))
            .collect();
        self.cells
            .par_iter()
            .enumerate()
            .with_min_len(4096)
            .for_each(|(t, c)| {
                if c.v[0] == FREE {
                    return;
                }
                for &v in &c.v {
                    if v != INFINITE {
                        // Any tetrahedron holding `v` will do: whichever store lands last.
                        cell_of[v as usize].store(t as u32, Ordering::Relaxed);
                    }
                }
            });
        Stars {
            delaunay: self,
            cell_of: cell_of.into_iter().map(AtomicU32::into_inner).collect(),
        }
    }
}

impl Stars<'_> {
    /// The Delaunay neighbours of the vertex with internal id `v` (the insertion order,
    /// [`Delaunay::insertion_order`]) into `out`, each once, in increasing order; none for a
    /// duplicate (never inserted).
    pub fn neighbours(&self, v: u32, scratch: &mut StarScratch, out: &mut Vec<u32>) {
        out.clear();
        let start = self.cell_of[v as usize];
        if start == INFINITE {
            return;
        }
        scratch.clear();
        scratch.insert(start);
        let mut next = 0;
        while let Some(&t) = scratch.cells.get(next) {
            next += 1;
            let c = &self.delaunay.cells[t as usize];
            for i in 0..4 {
                let u = c.v[i];
                if u == v {
                    continue;
                }
                if u != INFINITE {
                    out.push(u);
                }
                // The face opposite `u` holds `v`: its neighbour is in the star.
                scratch.insert(c.n[i]);
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

/// Scratch for [`Stars::neighbours`]: the tetrahedra of a star, in the order met, and an
/// open-addressing set of them (a star has tens of tetrahedra; a linear search of them
/// would cost more than the walk).
#[derive(Default)]
pub struct StarScratch {
    cells: Vec<u32>,
    /// Slots holding a tetrahedron or `INFINITE` (empty); a power of two long.
    table: Vec<u32>,
}

impl StarScratch {
    fn clear(&mut self) {
        for &t in &self.cells {
            let mut h = Self::hash(t, self.table.len());
            while self.table[h] != INFINITE {
                self.table[h] = INFINITE;
                h = (h + 1) & (self.table.len() - 1);
            }
        }
        self.cells.clear();
    }

    #[inline(always)]
    fn hash(t: u32, len: usize) -> usize {
        (t.wrapping_mul(0x9E37_79B9) as usize) & (len - 1)
    }

    /// Adds `t` unless it is there already.
    fn insert(&mut self, t: u32) {
        if 2 * (self.cells.len() + 1) > self.table.len() {
            self.table = vec![INFINITE; (4 * (self.cells.len() + 1)).next_power_of_two().max(64)];
            for &c in &self.cells {
                let mut h = Self::hash(c, self.table.len());
                while self.table[h] != INFINITE {
                    h = (h + 1) & (self.table.len() - 1);
                }
                self.table[h] = c;
            }
        }
        let mut h = Self::hash(t, self.table.len());
        loop {
            match self.table[h] {
                x if x == t => return,
                INFINITE => break,
                _ => h = (h + 1) & (self.table.len() - 1),
            }
        }
        self.table[h] = t;
        self.cells.push(t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use std::collections::BTreeSet;

    /// The stars' neighbours are the vertices sharing a finite tetrahedron, or an infinite
    /// one (a hull edge), with the vertex, on a sphere (every vertex on the hull) and a cube
    /// grid (inner vertices and cospherical ties).
    #[test]
    fn stars_are_the_vertices_sharing_a_tetrahedron() {
        for pts in [
            shapes::icosphere(1.0, 3).positions,
            shapes::cube_grid(2.0, 6).positions,
        ] {
            let delaunay = Delaunay::new(&pts).unwrap();
            let n = delaunay.insertion_order().0.len();
            let mut expected = vec![BTreeSet::new(); n];
            for c in &delaunay.cells {
                if c.v[0] == FREE {
                    continue;
                }
                for &a in &c.v {
                    for &b in &c.v {
                        if a != b && a != INFINITE && b != INFINITE {
                            expected[a as usize].insert(b);
                        }
                    }
                }
            }
            let stars = delaunay.stars();
            let (mut scratch, mut out) = (StarScratch::default(), Vec::new());
            for (v, want) in expected.iter().enumerate() {
                stars.neighbours(v as u32, &mut scratch, &mut out);
                let got: BTreeSet<u32> = out.iter().copied().collect();
                assert_eq!(got.len(), out.len(), "vertex {v}: a neighbour twice");
                assert_eq!(&got, want, "vertex {v}");
            }
        }
    }
}
