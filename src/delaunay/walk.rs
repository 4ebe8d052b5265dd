//! Point location: a remembering stochastic visibility walk from the worker's last
//! tetrahedron (short, because points arrive in BRIO + Hilbert order), with an exhaustive
//! scan as a guard that never loops.

use super::cavity::Worker;
use super::cell::{Tets, FREE, NONE};
use super::{FACE, INFINITE};
use crate::geom::predicates::orient3d;
use glam::DVec3;

/// Where a point is.
pub(super) enum Located {
    /// Inside (or on) this tetrahedron, or beyond this infinite one's hull face.
    Tet(u32),
    /// On this vertex.
    Vertex(u32),
}

impl Worker {
    /// Finds the tetrahedron containing `q` (or an infinite one whose hull face `q` is
    /// beyond), or the vertex at `q`: a remembering stochastic visibility walk from the
    /// hint. `None` when the walk reaches a slot of another side (only with `CHECKED`).
    ///
    /// # Safety
    /// As [`Worker::insert`].
    pub(super) unsafe fn locate<const CHECKED: bool>(
        &mut self,
        tets: Tets,
        owner: &[u8],
        pts: &[DVec3],
        q: DVec3,
    ) -> Option<Located> {
        let p = |v: u32| pts[v as usize];
        let mut t = self.hint;
        let mut prev = NONE;
        let limit = 4 * tets.len + 64;
        // Another side's tetrahedra may be changing; `MIXED` ones are read-only meanwhile.
        let other = 1 - self.side.min(1);
        if CHECKED && owner[t as usize] == other {
            return None;
        }
        for _ in 0..limit {
            let super::cell::Cell { v: tv, n: adj } = tets.get(t);
            if tv.contains(&INFINITE) {
                return Some(Located::Tet(t));
            }
            let r = self.rng.next_u64() as usize;
            let mut next = NONE;
            // With CHECKED, an exit towards q into another side's tetrahedron is passed
            // over for another exit towards q if there is one (any such choice is a valid
            // visibility walk).
            let mut blocked = false;
            for k in 0..4 {
                let j = (r + k) & 3;
                let n = adj[j];
                if n == prev {
                    continue;
                }
                let f = FACE[j];
                if orient3d(p(tv[f[0]]), p(tv[f[1]]), p(tv[f[2]]), q) < 0.0 {
                    if CHECKED && owner[n as usize] == other {
                        blocked = true;
                        continue;
                    }
                    next = n;
                    break;
                }
            }
            if next == NONE {
                if blocked {
                    // The next walk starts here, near this point (where the next points
                    // are): `t` is finite and this side's or `MIXED`.
                    self.hint = t;
                    return None;
                }
                if let Some(&v) = tv.iter().find(|&&v| p(v) == q) {
                    return Some(Located::Vertex(v));
                }
                return Some(Located::Tet(t));
            }
            prev = t;
            t = next;
        }
        if CHECKED {
            return None;
        }
        Some(locate_exhaustive(tets, pts, q, self.hint))
    }
}

/// Fallback location that cannot loop: scan every tetrahedron. Never needed in a correct
/// Delaunay triangulation (visibility walks terminate there); kept as a guard.
///
/// # Safety
/// `tets` views live arrays no other thread touches.
unsafe fn locate_exhaustive(tets: Tets, pts: &[DVec3], q: DVec3, hint: u32) -> Located {
    log::warn!("delaunay: walk did not terminate; scanning");
    let p = |v: u32| pts[v as usize];
    for t in 0..tets.len as u32 {
        let tv = tets.get(t).v;
        if tv[0] == FREE {
            continue;
        }
        if let Some(k) = tv.iter().position(|&v| v == INFINITE) {
            let f = FACE[k];
            if orient3d(p(tv[f[0]]), p(tv[f[1]]), p(tv[f[2]]), q) > 0.0 {
                return Located::Tet(t);
            }
            continue;
        }
        let inside = FACE
            .iter()
            .all(|f| orient3d(p(tv[f[0]]), p(tv[f[1]]), p(tv[f[2]]), q) >= 0.0);
        if inside {
            if let Some(&v) = tv.iter().find(|&&v| p(v) == q) {
                return Located::Vertex(v);
            }
            return Located::Tet(t);
        }
    }
    Located::Tet(hint)
}
