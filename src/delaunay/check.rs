//! Checking a tetrahedralization against its definition (tests and debugging).

use super::cell::{FREE, NONE};
use super::{Delaunay, INFINITE};

/// What is wrong with a tetrahedralization, found by [`Delaunay::check`].
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct Inconsistent(pub String);
use crate::geom::predicates::{insphere, orient3d};

impl Delaunay {
    /// Checks the structure: symmetric adjacency with matching faces, every finite
    /// tetrahedron positively oriented, the local Delaunay property across every finite
    /// face, and every non-duplicate point a vertex. Cost O(tetrahedra).
    pub fn check(&self) -> Result<(), Inconsistent> {
        let mut is_vertex = vec![false; self.pts.len()];
        for (t, cell) in self.cells.iter().enumerate() {
            let tv = &cell.v;
            if tv[0] == FREE {
                continue;
            }
            for &v in tv {
                if v != INFINITE {
                    is_vertex[self.input_id[v as usize] as usize] = true;
                }
            }
            let finite = !tv.contains(&INFINITE);
            if finite
                && orient3d(
                    self.point(tv[0]),
                    self.point(tv[1]),
                    self.point(tv[2]),
                    self.point(tv[3]),
                ) <= 0.0
            {
                return Err(Inconsistent(format!(
                    "tet {t} {tv:?} is not positively oriented"
                )));
            }
            for j in 0..4 {
                let n = cell.n[j];
                if n == NONE || self.cells[n as usize].v[0] == FREE {
                    return Err(Inconsistent(format!("tet {t} has a missing neighbour {j}")));
                }
                let Some(k) = self.cells[n as usize]
                    .n
                    .iter()
                    .position(|&x| x as usize == t)
                else {
                    return Err(Inconsistent(format!(
                        "adjacency {t} -> {n} is not symmetric"
                    )));
                };
                if self.face_key(t as u32, j) != self.face_key(n, k) {
                    return Err(Inconsistent(format!(
                        "tets {t} and {n} do not share their face"
                    )));
                }
                let opposite = self.cells[n as usize].v[k];
                if finite && opposite != INFINITE {
                    let [a, b, c, d] = tv.map(|v| self.point(v));
                    if insphere(a, b, c, d, self.point(opposite)) > 0.0 {
                        return Err(Inconsistent(format!(
                            "tet {t}: vertex {opposite} inside its circumsphere"
                        )));
                    }
                }
            }
        }
        for (i, &v) in is_vertex.iter().enumerate() {
            if !v && self.duplicate_of[i] == NONE {
                return Err(Inconsistent(format!(
                    "point {i} is missing from the tetrahedralization"
                )));
            }
        }
        Ok(())
    }
}
