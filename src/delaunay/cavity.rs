//! One insertion (Bowyer–Watson) by one worker: find the cavity (every tetrahedron whose
//! circumsphere holds the point), fill it with a fan of new tetrahedra from the point to
//! its boundary, and link them to each other without hashing.
//!
//! **Linking without hashing.** The new tetrahedra meet each other across faces through the
//! point and one edge of the cavity boundary, a consistently oriented sphere on which every
//! edge appears once in each direction. Boundary vertices get local numbers as the cavity
//! is found, and a table indexed by (local start, local end) pairs each edge with its
//! reverse: no probing and nothing to clear. Cavities with [`LINK_MAX`] or more boundary
//! vertices (a point far outside the hull) sort their edges instead.

use super::cell::{Cell, Tets, FREE, IN, NONE, OUT, UNSEEN};
use super::hook::EdgeHook;
use super::parallel::MIXED;
use super::walk::Located;
use super::{FACE, INFINITE};
use crate::geom::predicates::{insphere, orient3d};
use crate::random::SplitMix;
use glam::DVec3;

/// Cavities whose boundary has fewer vertices than this (all but a few) link their new
/// tetrahedra through a `LINK_MAX²` table indexed by local vertex numbers; larger ones sort.
pub(super) const LINK_MAX: usize = 64;
const NO_LOCAL: u8 = u8::MAX;

/// A boundary face of the cavity: its vertices (oriented towards the cavity), the tetrahedron
/// outside it and which of that tetrahedron's neighbour slots points into the cavity.
#[derive(Clone, Copy)]
struct BoundaryFace {
    v: [u32; 3],
    /// Local numbers of `v` (see [`LINK_MAX`]).
    l: [u8; 3],
    out: u32,
    slot: u8,
}
/// Is tetrahedron `t` in conflict with (its circumsphere strictly containing) `q`? `None`
/// when answering would read a slot the worker does not own (only with `CHECKED`).
///
/// # Safety
/// As [`Worker::insert`]; `t` is owned.
#[inline(always)]
unsafe fn conflict<const CHECKED: bool>(
    pts: &[DVec3],
    tets: Tets,
    owner: &[u8],
    side: u8,
    t: u32,
    q: DVec3,
) -> Option<bool> {
    let p = |v: u32| pts[v as usize];
    let cell = tets.get(t);
    let tv = cell.v;
    if let Some(k) = tv.iter().position(|&v| v == INFINITE) {
        let f = FACE[k];
        let o = orient3d(p(tv[f[0]]), p(tv[f[1]]), p(tv[f[2]]), q);
        if o != 0.0 {
            return Some(o > 0.0);
        }
        // Only read: `MIXED` tetrahedra do not change during a parallel round.
        let n = cell.n[k];
        if CHECKED && owner[n as usize] != side && owner[n as usize] != MIXED {
            return None;
        }
        return Some(sphere_conflict(pts, tets.get(n).v, q));
    }
    Some(sphere_conflict(pts, tv, q))
}

/// Does the sphere through the (positively oriented) `tv` strictly contain `q`? A tie (q
/// cospherical) is "outside": q is the latest point (see module docs).
#[inline(always)]
fn sphere_conflict(pts: &[DVec3], tv: [u32; 4], q: DVec3) -> bool {
    let p = |v: u32| pts[v as usize];
    insphere(p(tv[0]), p(tv[1]), p(tv[2]), p(tv[3]), q) > 0.0
}

/// What became of one insertion.
pub(super) enum Outcome {
    /// Done.
    Inserted,
    /// The point coincides with this vertex and was not inserted.
    Duplicate(u32),
    /// More free slots are needed (serial); nothing was changed.
    NeedSlots(usize),
    /// The insertion would touch a slot of another side, or this worker has too few free
    /// slots (parallel); nothing was changed.
    Blocked,
}

/// One thread's insertion state (its side, the walk's random source and start, the free
/// slots it may fill) and an insertion's scratch, kept apart: the scratch is cleared by
/// every insertion and allocates nothing once its buffers have grown.
pub(super) struct Worker {
    /// The side whose slots this worker may touch in a parallel phase.
    pub side: u8,
    pub rng: SplitMix,
    /// A live finite tetrahedron this worker may read (in a parallel phase, one of its
    /// side's or a `MIXED` one).
    pub hint: u32,
    /// Free slots this worker may fill, the last first.
    pub free: Vec<u32>,
    /// The slots the last insertion filled.
    pub created: Vec<u32>,
    scratch: Scratch,
    /// How many insertions linked by sorting (tests check that path is exercised).
    #[cfg(test)]
    pub sorted_links: usize,
}

/// What one insertion uses and forgets.
struct Scratch {
    stack: Vec<u32>,
    cavity: Vec<u32>,
    boundary: Vec<BoundaryFace>,
    /// Local number of each vertex on the current cavity boundary (`NO_LOCAL` otherwise;
    /// the last entry stands for [`INFINITE`]), and the vertices numbered.
    local: Vec<u8>,
    local_verts: Vec<u32>,
    link: Box<[u32; LINK_MAX * LINK_MAX]>,
    sorted: Vec<(u64, u32)>,
}

impl Worker {
    pub fn new(side: u8, seed: u64, points: usize) -> Self {
        Worker {
            side,
            rng: SplitMix(seed),
            hint: 0,
            free: Vec::new(),
            created: Vec::new(),
            scratch: Scratch {
                stack: Vec::new(),
                cavity: Vec::new(),
                boundary: Vec::new(),
                local: vec![NO_LOCAL; points + 1],
                local_verts: Vec::new(),
                link: Box::new([NONE; LINK_MAX * LINK_MAX]),
                sorted: Vec::new(),
            },
            #[cfg(test)]
            sorted_links: 0,
        }
    }

    /// Inserts internal point `p` (Bowyer–Watson).
    ///
    /// # Safety
    /// `tets` views live arrays and, with `CHECKED`, `owner` is as long. Without `CHECKED`,
    /// no other thread touches the arrays. With it, the call writes or marks only slots
    /// with `owner[slot] == self.side` and those on its free list (which must be free and
    /// labelled `self.side`), and reads only those and `MIXED` ones; it checks each label
    /// before touching a slot and returns [`Outcome::Blocked`] instead. So no slot one
    /// worker writes is touched by the other, and nobody writes a `MIXED` slot, provided
    /// that `owner` does not change during the phase and every live tetrahedron is labelled
    /// with the side of all its finite vertices or `MIXED`. The new tetrahedra keep that
    /// true: their vertices are the cavity's and `p`, all on this side. `hook` is told of
    /// the new edges, all between points of this side.
    #[inline(never)]
    pub(super) unsafe fn insert<const CHECKED: bool, H: EdgeHook>(
        &mut self,
        tets: Tets,
        owner: &[u8],
        pts: &[DVec3],
        hook: &H,
        p: u32,
    ) -> Outcome {
        let q = pts[p as usize];
        let t0 = match self.locate::<CHECKED>(tets, owner, pts, q) {
            None => return Outcome::Blocked,
            Some(Located::Vertex(v)) => return Outcome::Duplicate(v),
            Some(Located::Tet(t)) => t,
        };
        // The fields as separate borrows, so that the loops below keep them in registers.
        let Worker {
            side,
            free,
            hint,
            created,
            scratch:
                Scratch {
                    stack,
                    cavity,
                    boundary,
                    local,
                    local_verts,
                    link,
                    sorted,
                },
            #[cfg(test)]
            sorted_links,
            ..
        } = self;
        let side = *side;
        let owned = |t: u32| !CHECKED || owner[t as usize] == side;
        let finite = |t: u32| !tets.get(t).v.contains(&INFINITE);
        // The walk may end in a tetrahedron it may only read.
        if !owned(t0) {
            if finite(t0) {
                *hint = t0;
            }
            return Outcome::Blocked;
        }
        let inf_slot = local.len() - 1;
        // 1. The cavity: all tetrahedra whose circumsphere contains q (a connected set), and
        // its boundary faces, each vertex numbered locally for the linking in step 3.
        cavity.clear();
        boundary.clear();
        stack.clear();
        local_verts.clear();
        tets.set_mark(t0, IN);
        cavity.push(t0);
        stack.push(t0);
        // Every tetrahedron found in conflict has its neighbours prefetched (see below).
        tets.prefetch_neighbours(t0);
        let local_s: &mut [u8] = local;
        let mut blocked = false;
        'search: while let Some(t) = stack.pop() {
            let Cell { v: tv, n: adj } = tets.get(t);
            for (j, f) in FACE.iter().enumerate() {
                let n = adj[j];
                if !owned(n) {
                    blocked = true;
                    break 'search;
                }
                let m = tets.mark(n);
                if m == IN {
                    continue;
                }
                if m != OUT {
                    match conflict::<CHECKED>(pts, tets, owner, side, n, q) {
                        Some(true) => {
                            tets.set_mark(n, IN);
                            cavity.push(n);
                            stack.push(n);
                            // Its neighbours are fetched now, while the rest of this
                            // tetrahedron's are tested, not when it is popped: this loop
                            // is bound by memory latency.
                            tets.prefetch_neighbours(n);
                            continue;
                        }
                        Some(false) => tets.set_mark(n, OUT),
                        None => {
                            blocked = true;
                            break 'search;
                        }
                    }
                }
                let slot = tets.get(n).n.iter().position(|&x| x == t).unwrap_or(0) as u8;
                let v = [tv[f[0]], tv[f[1]], tv[f[2]]];
                let l = v.map(|x| {
                    let s = &mut local_s[(x as usize).min(inf_slot)];
                    if *s == NO_LOCAL && local_verts.len() < LINK_MAX {
                        *s = local_verts.len() as u8;
                        local_verts.push(x);
                    }
                    *s
                });
                boundary.push(BoundaryFace { v, l, out: n, slot });
            }
        }
        // Every mark set above is on a cavity tetrahedron or a boundary face's outside one.
        for &t in cavity.iter() {
            tets.set_mark(t, UNSEEN);
        }
        for b in boundary.iter() {
            tets.set_mark(b.out, UNSEEN);
        }
        let need = boundary.len().saturating_sub(cavity.len());
        if blocked || free.len() < need {
            for &x in local_verts.iter() {
                local[(x as usize).min(inf_slot)] = NO_LOCAL;
            }
            if finite(t0) {
                *hint = t0;
            }
            return if blocked || CHECKED {
                Outcome::Blocked
            } else {
                Outcome::NeedSlots(need)
            };
        }
        // 2. Fill the cavity with a fan of tetrahedra from q to its boundary, in the
        // cavity's own slots first, then in free ones (the last on the list first).
        created.clear();
        let from_free = free.len() - need;
        let slots = cavity.iter().chain(free[from_free..].iter().rev());
        for (b, &nt) in boundary.iter().zip(slots) {
            tets.set(
                nt,
                Cell {
                    v: [b.v[0], b.v[1], b.v[2], p],
                    n: [NONE, NONE, NONE, b.out],
                },
            );
            tets.set_n(b.out, b.slot as usize, nt);
            created.push(nt);
            if !b.v.contains(&INFINITE) {
                *hint = nt;
            }
        }
        free.truncate(from_free);
        for &t in cavity.iter().skip(boundary.len()) {
            tets.set(
                t,
                Cell {
                    v: [FREE; 4],
                    n: [NONE; 4],
                },
            );
            free.push(t);
        }
        // 3. Link the new tetrahedra to each other. The face opposite local vertex i (i < 3)
        // holds q and the boundary edge (v[i+1], v[i+2]); the boundary is a consistently
        // oriented sphere, so the neighbour across it is the tetrahedron whose boundary face
        // holds that edge reversed. Small cavities (all but a few) use a table indexed by
        // the local numbers of the edge's ends, larger ones sort the edges.
        if local_verts.len() < LINK_MAX {
            // The masks change nothing (local numbers are below LINK_MAX here) but let the
            // compiler see that every index is inside the table.
            let at = |a: u8, b: u8| (a as usize % LINK_MAX) * LINK_MAX + (b as usize % LINK_MAX);
            let link: &mut [u32; LINK_MAX * LINK_MAX] = link;
            for (b, &nt) in boundary.iter().zip(created.iter()) {
                let [l0, l1, l2] = b.l;
                link[at(l1, l2)] = nt;
                link[at(l2, l0)] = nt;
                link[at(l0, l1)] = nt;
            }
            for (b, &nt) in boundary.iter().zip(created.iter()) {
                let [l0, l1, l2] = b.l;
                tets.set_n(nt, 0, link[at(l2, l1)]);
                tets.set_n(nt, 1, link[at(l0, l2)]);
                tets.set_n(nt, 2, link[at(l1, l0)]);
            }
        } else {
            #[cfg(test)]
            {
                *sorted_links += 1;
            }
            sorted.clear();
            for (b, &nt) in boundary.iter().zip(created.iter()) {
                let v = b.v;
                for (i, (x, y)) in [(v[1], v[2]), (v[2], v[0]), (v[0], v[1])]
                    .into_iter()
                    .enumerate()
                {
                    let key = ((x.min(y) as u64) << 32) | x.max(y) as u64;
                    sorted.push((key, (nt << 2) | i as u32));
                }
            }
            sorted.sort_unstable();
            for pair in sorted.chunks_exact(2) {
                debug_assert_eq!(pair[0].0, pair[1].0, "cavity boundary not closed");
                let [(_, a), (_, b)] = [pair[0], pair[1]];
                tets.set_n(a >> 2, (a & 3) as usize, b >> 2);
                tets.set_n(b >> 2, (b & 3) as usize, a >> 2);
            }
        }
        // 4. The new edges join p to the cavity boundary's vertices (all numbered unless
        // there are LINK_MAX or more; then the faces list them, some more than once). They
        // lie on this worker's side, like the cavity: the hook's contract.
        if local_verts.len() < LINK_MAX {
            for &v in local_verts.iter().filter(|&&v| v != INFINITE) {
                hook.edge(pts, p, v);
            }
        } else {
            for &v in boundary
                .iter()
                .flat_map(|b| &b.v)
                .filter(|&&v| v != INFINITE)
            {
                hook.edge(pts, p, v);
            }
        }
        for &x in local_verts.iter() {
            local[(x as usize).min(inf_slot)] = NO_LOCAL;
        }
        Outcome::Inserted
    }
}
