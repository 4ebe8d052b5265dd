//! Exact 3D Delaunay tetrahedralization: incremental Bowyer–Watson.
//!
//! Why hand-written: the crates tried on this kind of machine either abort or loop on
//! cospherical and coplanar input (which is *normal* input here: UV spheres, cube grids), drop
//! vertices, or are AGPL (see `shared/STACK.md`). The design:
//!
//! * **Exact predicates** ([`crate::geom::predicates`]): every orientation and in-sphere sign
//!   is exact, so the combinatorics can never become inconsistent.
//! * **Symbolic perturbation.** Ties in the in-sphere test (five cospherical points) are
//!   broken as if the lifted coordinate of each point were perturbed by a term that is larger
//!   for later-inserted points (Edelsbrunner–Mücke / Devillers–Teillaud). Because the point
//!   being inserted is always the latest, a tie always means "not in conflict", which costs
//!   nothing. The result is a valid Delaunay tetrahedralization of the unperturbed points in
//!   which no tetrahedron is flat.
//! * **A vertex at infinity** ([`INFINITE`]): every convex-hull face carries an infinite
//!   tetrahedron, so points outside the current hull need no special case and no bounding
//!   "super tetrahedron" distorts the hull. An infinite tetrahedron is in conflict with `p` when
//!   `p` is strictly beyond its hull face; when `p` lies exactly in the face's plane, its
//!   status is that of the finite neighbour across the face (the half-space is the limit of
//!   the spheres through that face), which keeps the cavity consistent.
//! * **BRIO + Hilbert order** ([`crate::geom::hilbert`]) keeps location walks short;
//!   location is a remembering stochastic visibility walk from the last created tetrahedron.
//! * Memory is laid out for a latency-bound walk: one 32-byte, 32-aligned record per
//!   tetrahedron (four vertex ids and the neighbour opposite each: one cache line visit, not
//!   two), vertices renumbered in insertion order (so the points a cavity touches were
//!   inserted close together in time and sit close together in memory), and one byte of
//!   cavity mark per tetrahedron, cleared after each insertion. The new tetrahedra take the
//!   cavity's own slots first (so they stay where their neighbours already are in memory),
//!   and all scratch buffers live in the struct, so an insertion allocates nothing once the
//!   arrays have grown. Ids are mapped back to input indices only in the output.
//! * **Linking without hashing.** The new tetrahedra meet each other across faces through
//!   `q` and one edge of the cavity boundary, a consistently oriented sphere on which every
//!   edge appears once in each direction. Boundary vertices get local numbers as the
//!   cavity is found, and a table indexed by (local start, local end) pairs each edge with
//!   its reverse: no probing and nothing to clear. Cavities with `LINK_MAX` (64) or more
//!   boundary vertices (a point far outside the hull) sort their edges instead.
//!
//! * **Shrinking balls as the edges are made** ([`Delaunay::with_tangent_balls`]): every
//!   edge joins an inserted point to its cavity's boundary, so a per-point minimum over
//!   the Delaunay edges needs no pass over the finished tetrahedra.
//!
//! * **Two threads** for inputs of 32,768 points or more: after a serial start, the points
//!   are inserted in doubling phases by two workers, one per side of a median plane, each
//!   touching only tetrahedra whose vertices are all on its side (see [`Delaunay`]). The
//!   result does not depend on the thread count or on timing. A caller with other work
//!   passes it as an `idle` hook, which the calling thread runs whenever it has finished
//!   its side and waits for the other.
//!
//! Orientation convention: every tetrahedron `[v0, v1, v2, v3]` is positively oriented
//! (`orient3d(v0, v1, v2, v3) > 0`), and [`FACE`]`[i]` lists the face opposite `vi` so that
//! `vi` lies on its positive side.

use crate::geom::hilbert::{brio_order, SplitMix};
use crate::geom::predicates::{collinear, insphere, orient3d};
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// The vertex at infinity.
pub const INFINITE: u32 = u32::MAX;
const FREE: u32 = u32::MAX - 1;
const NONE: u32 = u32::MAX;

/// Local vertex indices of the face opposite vertex `i`, ordered so that vertex `i` lies on
/// the positive side of the face.
pub const FACE: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];

/// Why no tetrahedralization exists.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum DelaunayError {
    #[error("need at least 4 points, got {0}")]
    TooFew(usize),
    #[error("point {0} has a non-finite coordinate")]
    NonFinite(usize),
    #[error("all points are {0}: they span no volume")]
    Flat(&'static str),
}

/// One tetrahedron: its vertices (internal ids) and the neighbour opposite each vertex.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct Cell {
    v: [u32; 4],
    n: [u32; 4],
}

impl Cell {
    /// A live (not free) tetrahedron without the vertex at infinity.
    fn is_live_finite(&self) -> bool {
        self.v[0] != FREE && !self.v.contains(&INFINITE)
    }
}

/// Cavity marks (reset to `UNSEEN` after every insertion).
const UNSEEN: u8 = 0;
const IN: u8 = 1;
const OUT: u8 = 2;

/// Cavities whose boundary has fewer vertices than this (all but a few) link their new
/// tetrahedra through a `LINK_MAX²` table indexed by local vertex numbers; larger ones sort.
const LINK_MAX: usize = 64;
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
/// Owner of a slot in the parallel phases: a side (0 or 1) when every finite vertex of its
/// tetrahedron lies on that side of the split plane, `MIXED` otherwise (and for free slots
/// that belong to no worker).
const MIXED: u8 = 2;

/// Below this many points the insertion is serial: the phases would cost more than they
/// save (measured in `BENCHMARKS.md`).
const PARALLEL_MIN: usize = 1 << 15;

/// The tetrahedron records and their cavity marks as raw pointers, so that the two workers
/// of a parallel phase can each write their own slots of the same arrays. Every access is
/// bounds-checked; what keeps the accesses free of data races is the ownership rule stated
/// on [`Worker::insert`].
#[derive(Clone, Copy)]
struct Tets {
    cells: *mut Cell,
    mark: *mut u8,
    len: usize,
}

// SAFETY: a `Tets` is only dereferenced under the ownership rule of `Worker::insert`: while
// several threads hold it, each reads and writes only slots that no other thread touches.
unsafe impl Send for Tets {}
unsafe impl Sync for Tets {}

impl Tets {
    /// A view of `cells` and `mark`, valid until either is touched through the `Vec`s again.
    fn new(cells: &mut Vec<Cell>, mark: &mut Vec<u8>) -> Self {
        assert_eq!(cells.len(), mark.len());
        Tets {
            cells: cells.as_mut_ptr(),
            mark: mark.as_mut_ptr(),
            len: cells.len(),
        }
    }

    /// # Safety
    /// The arrays are alive and no other thread writes slot `t` meanwhile.
    #[inline(always)]
    unsafe fn get(self, t: u32) -> Cell {
        assert!((t as usize) < self.len);
        *self.cells.add(t as usize)
    }

    /// # Safety
    /// The arrays are alive and no other thread reads or writes slot `t` meanwhile.
    #[inline(always)]
    unsafe fn set(self, t: u32, cell: Cell) {
        assert!((t as usize) < self.len);
        *self.cells.add(t as usize) = cell;
    }

    /// Sets neighbour `j` of `t`.
    ///
    /// # Safety
    /// As [`Tets::set`].
    #[inline(always)]
    unsafe fn set_n(self, t: u32, j: usize, n: u32) {
        assert!((t as usize) < self.len);
        (*self.cells.add(t as usize)).n[j & 3] = n;
    }

    /// Asks for slot `t`'s record and mark to be brought into cache (a hint: no access).
    #[inline(always)]
    fn prefetch(self, t: u32) {
        #[cfg(target_arch = "x86_64")]
        if (t as usize) < self.len {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            // SAFETY: a prefetch never faults and reads nothing; the addresses are in bounds.
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(self.cells.add(t as usize) as *const i8);
                _mm_prefetch::<_MM_HINT_T0>(self.mark.add(t as usize) as *const i8);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (self, t);
    }

    /// Prefetches the four neighbours of `t` ([`Tets::prefetch`]).
    ///
    /// # Safety
    /// As [`Tets::get`].
    #[inline(always)]
    unsafe fn prefetch_neighbours(self, t: u32) {
        for n in self.get(t).n {
            self.prefetch(n);
        }
    }

    /// # Safety
    /// As [`Tets::get`].
    #[inline(always)]
    unsafe fn mark(self, t: u32) -> u8 {
        assert!((t as usize) < self.len);
        *self.mark.add(t as usize)
    }

    /// # Safety
    /// As [`Tets::set`].
    #[inline(always)]
    unsafe fn set_mark(self, t: u32, m: u8) {
        assert!((t as usize) < self.len);
        *self.mark.add(t as usize) = m;
    }
}

/// Radius of the ball tangent at `p` with its centre on `−n` (unit) and `q` on its sphere,
/// `|q − p|² / (−2 n·(q − p))`; infinite when `q` is not on the inner side of the tangent
/// plane. The shrinking ball of `p` is the minimum over the other points (see
/// [`Delaunay::with_tangent_balls`]). The definition: running minima use
/// [`lower_tangent_radius`], which gives the same bits without the division.
#[inline(always)]
pub fn tangent_radius(p: DVec3, n: DVec3, q: DVec3) -> f64 {
    let d = q - p;
    let s = -2.0 * n.dot(d);
    if s > 0.0 {
        d.length_squared() / s
    } else {
        f64::INFINITY
    }
}

/// `*x = x.min(tangent_radius(p, n, q))`, exactly, without the division (or the write)
/// when it cannot lower `x`, which is most of the time for a running minimum:
/// `|d|² ≥ x·s·(1 + 4ε)` (the product rounded) implies `|d|² > x·s`, so the rounded
/// quotient is at least `x`.
#[inline(always)]
pub fn lower_tangent_radius(x: &mut f64, p: DVec3, n: DVec3, q: DVec3) {
    let d = q - p;
    let s = -2.0 * n.dot(d);
    if s > 0.0 {
        let l = d.length_squared();
        if l < *x * s * (1.0 + 4.0 * f64::EPSILON) {
            let r = l / s;
            if r < *x {
                *x = r;
            }
        }
    }
}

/// The tangent balls being computed (see [`Delaunay::with_tangent_balls`]): the radii as a
/// raw pointer for the same reason as [`Tets`] (the two workers of a parallel phase update
/// the radii of their own sides' vertices in the same array), bounds-checked on every
/// access; the normals, which nobody writes, as a slice.
#[derive(Clone, Copy)]
struct BallView<'a> {
    normals: &'a [DVec3],
    radius: *mut f64,
}

// SAFETY: as for `Tets`: while several threads hold a `BallView`, each touches only the
// radii of its own side's vertices (see `Worker::insert`).
unsafe impl Send for BallView<'_> {}
unsafe impl Sync for BallView<'_> {}

impl BallView<'_> {
    /// Offers the Delaunay edge `ab` to the tangent balls of `a` and `b`
    /// ([`tangent_radius`], which rounds alike whichever end comes first).
    ///
    /// # Safety
    /// The radii are alive and no other thread touches those of `a` and `b` meanwhile.
    #[inline(always)]
    unsafe fn edge(self, pts: &[DVec3], a: u32, b: u32) {
        for (v, w) in [(a as usize, b as usize), (b as usize, a as usize)] {
            // In bounds: `normals` is as long as the radii.
            lower_tangent_radius(&mut *self.radius.add(v), pts[v], self.normals[v], pts[w]);
        }
    }
}

/// Per-point data of [`Delaunay::with_tangent_balls`], in insertion order.
struct TangentBalls {
    normals: Vec<DVec3>,
    radius: Vec<f64>,
}

impl TangentBalls {
    fn view(&mut self) -> BallView<'_> {
        assert_eq!(self.normals.len(), self.radius.len());
        BallView {
            normals: &self.normals,
            radius: self.radius.as_mut_ptr(),
        }
    }
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

enum Located {
    Tet(u32),
    Vertex(u32),
}

/// What became of one insertion.
enum Outcome {
    Inserted,
    /// The point coincides with this vertex and was not inserted.
    Duplicate(u32),
    /// More free slots are needed (serial); nothing was changed.
    NeedSlots(usize),
    /// The insertion would touch a slot of another side, or this worker has too few free
    /// slots (parallel); nothing was changed.
    Blocked,
}

/// One thread's insertion state: the walk's random source and start, the free slots it may
/// fill, and an insertion's scratch (so that an insertion allocates nothing once the buffers
/// have grown).
struct Worker {
    /// The side whose slots this worker may touch in a parallel phase.
    side: u8,
    rng: SplitMix,
    /// A live finite tetrahedron this worker may read (in a parallel phase, one of its
    /// side's or a `MIXED` one).
    hint: u32,
    free: Vec<u32>,
    stack: Vec<u32>,
    cavity: Vec<u32>,
    boundary: Vec<BoundaryFace>,
    created: Vec<u32>,
    /// Local number of each vertex on the current cavity boundary (`NO_LOCAL` otherwise;
    /// the last entry stands for [`INFINITE`]), and the vertices numbered.
    local: Vec<u8>,
    local_verts: Vec<u32>,
    link: Box<[u32; LINK_MAX * LINK_MAX]>,
    sorted: Vec<(u64, u32)>,
    /// How many insertions linked by sorting (tests check that path is exercised).
    #[cfg(test)]
    sorted_links: usize,
}

impl Worker {
    fn new(side: u8, seed: u64, points: usize) -> Self {
        Worker {
            side,
            rng: SplitMix(seed),
            hint: 0,
            free: Vec::new(),
            stack: Vec::new(),
            cavity: Vec::new(),
            boundary: Vec::new(),
            created: Vec::new(),
            local: vec![NO_LOCAL; points + 1],
            local_verts: Vec::new(),
            link: Box::new([NONE; LINK_MAX * LINK_MAX]),
            sorted: Vec::new(),
            #[cfg(test)]
            sorted_links: 0,
        }
    }

    /// Finds the tetrahedron containing `q` (or an infinite one whose hull face `q` is
    /// beyond), or the vertex at `q`: a remembering stochastic visibility walk from the
    /// hint. `None` when the walk reaches a slot of another side (only with `CHECKED`).
    ///
    /// # Safety
    /// As [`Worker::insert`].
    unsafe fn locate<const CHECKED: bool>(
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
            let Cell { v: tv, n: adj } = tets.get(t);
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
    /// true: their vertices are the cavity's and `p`, all on this side. `ball`'s entries of
    /// the same vertices are the only ones it touches.
    #[inline(never)]
    unsafe fn insert<const CHECKED: bool>(
        &mut self,
        tets: Tets,
        owner: &[u8],
        pts: &[DVec3],
        ball: Option<BallView<'_>>,
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
            stack,
            cavity,
            boundary,
            created,
            local,
            local_verts,
            link,
            sorted,
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
        // lie on this worker's side, like the cavity.
        if let Some(ball) = ball {
            if local_verts.len() < LINK_MAX {
                for &v in local_verts.iter().filter(|&&v| v != INFINITE) {
                    ball.edge(pts, p, v);
                }
            } else {
                for &v in boundary
                    .iter()
                    .flat_map(|b| &b.v)
                    .filter(|&&v| v != INFINITE)
                {
                    ball.edge(pts, p, v);
                }
            }
        }
        for &x in local_verts.iter() {
            local[(x as usize).min(inf_slot)] = NO_LOCAL;
        }
        Outcome::Inserted
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

/// The owner label of a tetrahedron with vertices `v`, given each vertex's side.
fn owner_of(side: &[u8], v: [u32; 4]) -> u8 {
    if v[0] == FREE {
        return MIXED;
    }
    let sides = v
        .iter()
        .filter(|&&x| x != INFINITE)
        .fold(0u8, |acc, &x| acc | 1 << side[x as usize]);
    match sides {
        1 => 0,
        2 => 1,
        _ => MIXED,
    }
}

/// Appends `add` free records (labelled `label` when labels are kept); returns the first.
fn grow(
    cells: &mut Vec<Cell>,
    mark: &mut Vec<u8>,
    owner: Option<&mut Vec<u8>>,
    add: usize,
    label: u8,
) -> usize {
    let start = cells.len();
    let free = Cell {
        v: [FREE; 4],
        n: [NONE; 4],
    };
    cells.resize(start + add, free);
    mark.resize(start + add, UNSEEN);
    if let Some(owner) = owner {
        owner.resize(start + add, label);
    }
    start
}

/// Is `t` a live finite tetrahedron?
fn live_finite(cells: &[Cell], t: u32) -> bool {
    cells.get(t as usize).is_some_and(Cell::is_live_finite)
}

/// Where the parallel phases start for `n` points: after the first sixteenth, or never
/// below [`PARALLEL_MIN`].
fn first_parallel(n: usize) -> usize {
    if n >= PARALLEL_MIN {
        n / 16
    } else {
        n
    }
}

/// The side of each point of `pts` of the plane through their median along `axis`: side 1
/// when the coordinate is at least the median.
fn median_sides(pts: &[DVec3], axis: usize) -> Vec<u8> {
    let mut coords: Vec<f64> = pts.iter().map(|p| p[axis]).collect();
    let mid = coords.len() / 2;
    let split = match coords.is_empty() {
        true => 0.0,
        false => *coords.select_nth_unstable_by(mid, f64::total_cmp).1,
    };
    pts.par_iter().map(|p| u8::from(p[axis] >= split)).collect()
}

/// State of the parallel phases: the points are split by a plane into two sides; a worker
/// per side inserts that side's points, touching only tetrahedra whose finite vertices are
/// all on its side.
struct Parallel {
    /// Side of each point (internal ids) of the median plane chosen by
    /// [`Delaunay::start_parallel`] (see [`median_sides`]).
    side: Vec<u8>,
    /// Owner label of each slot (see [`MIXED`]); as long as the records.
    owner: Vec<u8>,
    workers: [Worker; 2],
}

/// A Delaunay tetrahedralization of a point set (vertex ids are input indices).
///
/// # Two threads
/// Inputs of 32,768 points or more are inserted in phases after a serial start
/// (the first sixteenth of the insertion order; the phases then double in size). A plane
/// through the median of the points along one axis (the one whose plane cuts the fewest
/// tetrahedra of the serial start) splits them into two sides;
/// in a phase, each side's worker inserts its side's points of the phase, changing only
/// tetrahedra whose finite vertices are all on its side (labelled before the phase; its
/// walks may also pass through tetrahedra straddling the plane, which nobody changes
/// during a phase). An insertion that would change anything else is deferred, and the deferred points are inserted serially after the phase, in insertion
/// order. A worker's insertions only ever test spheres through its own side's points and
/// earlier ones, so every test gives the answer it would give in a serial insertion of
/// the same points in some interleaved order: the result is the Delaunay tetrahedralization
/// (with the same tie-breaking as the serial one for each such order), and it is the same
/// whether the workers run concurrently or one after the other, so it never depends on
/// the thread count or on timing.
pub struct Delaunay {
    /// Points in insertion order: internal vertex `k` is input point `input_id[k]`.
    pts: Vec<DVec3>,
    input_id: Vec<u32>,
    cells: Vec<Cell>,
    mark: Vec<u8>,
    duplicate_of: Vec<u32>,
    /// The serial insertion's state.
    serial: Worker,
    /// Present when built by [`Delaunay::with_tangent_balls`].
    ball: Option<TangentBalls>,
    /// Present during the parallel phases.
    par: Option<Box<Parallel>>,
    /// How many insertions the parallel phases deferred (tests check both paths run).
    #[cfg(test)]
    deferred: usize,
}

impl Delaunay {
    /// Tetrahedralizes `points`.
    ///
    /// # Errors
    /// Fewer than four points, a non-finite coordinate, or no four points spanning a volume.
    pub fn new(points: &[DVec3]) -> Result<Self, DelaunayError> {
        Self::with_progress(points, &|_| {})
    }

    /// As [`Delaunay::new`], calling `progress(fraction)` now and then (from the calling
    /// thread).
    pub fn with_progress(points: &[DVec3], progress: &dyn Fn(f64)) -> Result<Self, DelaunayError> {
        Self::build_phased(
            points,
            None,
            progress,
            &|| false,
            first_parallel(points.len()),
        )
    }

    /// As [`Delaunay::with_progress`], also computing the *shrinking ball* of every point
    /// `p` with unit normal `n` (`normals` in input order): the largest ball tangent at
    /// `p` with its centre on `−n` and no point inside, of radius
    /// `min_q |q − p|² / (−2 n·(q − p))` over the points `q` with `n·(q − p) < 0`
    /// (infinite when there is none); see [`Delaunay::tangent_balls`].
    ///
    /// The minimising `q` and `p` lie on an empty sphere, so `pq` is a Delaunay edge. Every
    /// edge is created by the insertion of its later end, joined to a vertex of that
    /// point's cavity, so the minimum is taken there, over each new edge once (an edge
    /// destroyed later only adds a candidate no smaller than the minimum). On koala ×16
    /// this replaced a pass over the finished tetrahedra (several times each edge) that
    /// took 0.4 s on both cores.
    ///
    /// `idle` is the caller's other work, in small units: whenever the calling thread has
    /// inserted its side of a parallel phase while the other worker still runs on another
    /// thread, it calls `idle()` until that worker is done or `idle` returns false (no work
    /// left). Without the hook, that thread would wait: the two sides of a phase never
    /// take exactly as long (koala ×16: the other side 7–70 ms later in each phase).
    ///
    /// # Panics
    /// When `normals` and `points` differ in length.
    pub fn with_tangent_balls(
        points: &[DVec3],
        normals: &[DVec3],
        progress: &dyn Fn(f64),
        idle: &(dyn Fn() -> bool + Sync),
    ) -> Result<Self, DelaunayError> {
        assert_eq!(points.len(), normals.len(), "one normal per point");
        let first = first_parallel(points.len());
        Self::build_phased(points, Some(normals), progress, idle, first)
    }

    /// As [`Delaunay::with_tangent_balls`] (`normals` optional), with the parallel phases
    /// starting at insertion `first_parallel` (none when it is `points.len()` or more).
    fn build_phased(
        points: &[DVec3],
        normals: Option<&[DVec3]>,
        progress: &dyn Fn(f64),
        idle: &(dyn Fn() -> bool + Sync),
        first_parallel: usize,
    ) -> Result<Self, DelaunayError> {
        let n = points.len();
        if n < 4 {
            return Err(DelaunayError::TooFew(n));
        }
        if n >= (u32::MAX / 2) as usize {
            return Err(DelaunayError::TooFew(0));
        }
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            return Err(DelaunayError::NonFinite(i));
        }
        let mut order = brio_order(points, 0x5EED_CAFE);
        let p0 = points[order[0] as usize];
        let k1 = order
            .iter()
            .position(|&i| points[i as usize] != p0)
            .ok_or(DelaunayError::Flat("identical"))?;
        let p1 = points[order[k1] as usize];
        let k2 = order
            .iter()
            .position(|&i| !collinear(p0, p1, points[i as usize]))
            .ok_or(DelaunayError::Flat("collinear"))?;
        let p2 = points[order[k2] as usize];
        let k3 = order
            .iter()
            .position(|&i| orient3d(p0, p1, p2, points[i as usize]) != 0.0)
            .ok_or(DelaunayError::Flat("coplanar"))?;
        // Move the first simplex to the front, keep the rest in BRIO order.
        let first = [order[0], order[k1], order[k2], order[k3]];
        let mut rest: Vec<u32> = Vec::with_capacity(n);
        rest.extend_from_slice(&first);
        for (k, &i) in order.iter().enumerate() {
            if k != 0 && k != k1 && k != k2 && k != k3 {
                rest.push(i);
            }
        }
        order = rest;

        let ball = normals.map(|normals| TangentBalls {
            normals: order.iter().map(|&i| normals[i as usize]).collect(),
            radius: vec![f64::INFINITY; n],
        });
        let mut dt = Delaunay {
            pts: order.iter().map(|&i| points[i as usize]).collect(),
            input_id: order,
            // The parallel phases leave some slots unused: 8 per point is enough for the
            // inputs measured (only address space until used).
            cells: Vec::with_capacity(8 * n),
            mark: Vec::with_capacity(8 * n),
            duplicate_of: vec![NONE; n],
            serial: Worker::new(MIXED, 0x1234_5678, n),
            ball,
            par: None,
            #[cfg(test)]
            deferred: 0,
        };
        dt.init_simplex([0, 1, 2, 3]);
        let step = (n / 64).max(1 << 14);
        let serial_end = first_parallel.clamp(4, n);
        for k in 4..serial_end {
            dt.insert(k as u32);
            if k % step == 0 {
                progress(k as f64 / n as f64);
            }
        }
        if serial_end < n {
            dt.start_parallel();
            let mut lo = serial_end;
            while lo < n {
                // Doubling phases; a last one of less than half the previous joins it.
                let hi = if 3 * lo > n { n } else { 2 * lo };
                dt.phase(lo, hi, idle);
                progress(hi as f64 / n as f64);
                lo = hi;
            }
            dt.end_parallel();
        }
        progress(1.0);
        Ok(dt)
    }

    fn init_simplex(&mut self, v: [u32; 4]) {
        let [a, b, mut c, mut d] = v;
        if orient3d(self.p(a), self.p(b), self.p(c), self.p(d)) < 0.0 {
            std::mem::swap(&mut c, &mut d);
        }
        let t0 = [a, b, c, d];
        let mut ids = vec![self.push(t0)];
        for f in FACE {
            let (x, y, z) = (t0[f[0]], t0[f[1]], t0[f[2]]);
            ids.push(self.push([x, z, y, INFINITE]));
        }
        for &t in &ids {
            for i in 0..4 {
                let face = self.face_key(t, i);
                for &u in &ids {
                    if u == t {
                        continue;
                    }
                    for j in 0..4 {
                        if self.face_key(u, j) == face {
                            self.cells[t as usize].n[i] = u;
                        }
                    }
                }
            }
        }
        self.serial.hint = ids[0];
        // The first edges are made here, not by an insertion.
        if let Some(ball) = &mut self.ball {
            let view = ball.view();
            for (i, &a) in t0.iter().enumerate() {
                for &b in &t0[i + 1..] {
                    // SAFETY: the arrays are alive and nothing else runs.
                    unsafe { view.edge(&self.pts, a, b) };
                }
            }
        }
    }

    fn face_key(&self, t: u32, i: usize) -> [u32; 3] {
        let tv = self.cells[t as usize].v;
        let mut k = FACE[i].map(|j| tv[j]);
        k.sort_unstable();
        k
    }

    #[inline(always)]
    fn p(&self, v: u32) -> DVec3 {
        self.pts[v as usize]
    }

    fn push(&mut self, v: [u32; 4]) -> u32 {
        self.cells.push(Cell { v, n: [NONE; 4] });
        self.mark.push(UNSEEN);
        (self.cells.len() - 1) as u32
    }

    /// Inserts internal point `p` on this thread.
    fn insert(&mut self, p: u32) {
        loop {
            let tets = Tets::new(&mut self.cells, &mut self.mark);
            // SAFETY: no other thread runs, and the arrays are not touched otherwise
            // during the call.
            let ball = self.ball.as_mut().map(TangentBalls::view);
            let outcome = unsafe { self.serial.insert::<false>(tets, &[], &self.pts, ball, p) };
            match outcome {
                Outcome::Inserted => {
                    if let Some(par) = &mut self.par {
                        for &t in &self.serial.created {
                            let v = self.cells[t as usize].v;
                            par.owner[t as usize] = owner_of(&par.side, v);
                        }
                    }
                    return;
                }
                Outcome::Duplicate(v) => {
                    self.duplicate_of[self.input_id[p as usize] as usize] =
                        self.input_id[v as usize];
                    return;
                }
                Outcome::NeedSlots(k) => {
                    // Between parallel rounds, from the workers' spare slots first: free,
                    // and relabelled above once used. Growing could move the whole array
                    // (190 ms of copying in the last phase on Spot ×256).
                    if let Some(par) = &mut self.par {
                        let [a, b] = &mut par.workers;
                        let spare = if a.free.len() >= b.free.len() { a } else { b };
                        if spare.free.len() >= k {
                            let at = spare.free.len() - k.max(256).min(spare.free.len());
                            self.serial.free.splice(0..0, spare.free.drain(at..));
                            continue;
                        }
                    }
                    // Grow in chunks (few retries); the new slots go under the freed ones,
                    // which are reused first.
                    let add = k.max(self.cells.len() / 64).max(256);
                    let owner = self.par.as_mut().map(|par| &mut par.owner);
                    let start = grow(&mut self.cells, &mut self.mark, owner, add, MIXED) as u32;
                    let fresh = (start..start + add as u32).rev();
                    self.serial.free.splice(0..0, fresh);
                }
                Outcome::Blocked => return, // only with CHECKED
            }
        }
    }

    /// Splits the points by a median plane and labels every slot (see [`Parallel`]); the
    /// insertions keep the labels up to date from then on.
    ///
    /// Of the three axes, the plane cuts the fewest tetrahedra inserted so far: a point
    /// whose cavity meets a cut tetrahedron is deferred, and the cuts so far predict the
    /// later ones (measured: the deferred points follow the order of these counts on
    /// Spot ×256, koala ×4 and scorpion ×16).
    fn start_parallel(&mut self) {
        let n = self.pts.len();
        let cells = &self.cells;
        let cut = |side: &[u8]| {
            cells
                .par_iter()
                .filter(|c| c.v[0] != FREE && owner_of(side, c.v) == MIXED)
                .count()
        };
        let side = (0..3)
            .map(|axis| median_sides(&self.pts, axis))
            .min_by_key(|side| cut(side))
            .unwrap_or_default();
        let owner = self
            .cells
            .par_iter()
            .map(|c| owner_of(&side, c.v))
            .collect();
        self.par = Some(Box::new(Parallel {
            side,
            owner,
            workers: [
                Worker::new(0, 0x0A11_CE00, n),
                Worker::new(1, 0x0B0B_0000, n),
            ],
        }));
    }

    /// Inserts the points `lo..hi` (internal ids): a parallel round split by the median
    /// plane of all points, then the deferred ones serially. (A second parallel round for
    /// the deferred points, split across the first plane, was measured slower than
    /// inserting them serially: on Spot ×256 it deferred 39 % of them again and took as
    /// long per point as the serial insertion.)
    fn phase(&mut self, lo: usize, hi: usize, idle: &(dyn Fn() -> bool + Sync)) {
        let deferred = self.round((lo as u32..hi as u32).collect(), idle);
        #[cfg(test)]
        {
            self.deferred += deferred.len();
        }
        let clock = std::time::Instant::now();
        for &p in &deferred {
            self.insert(p);
        }
        log::debug!(
            "delaunay: phase {lo}..{hi}: {} serial, {:.1} ms",
            deferred.len(),
            clock.elapsed().as_secs_f64() * 1e3
        );
    }

    /// Inserts the points `seq` (internal ids, in insertion order) on both workers by the
    /// current labels; returns the deferred ones, in insertion order. Leaves the serial
    /// walk's hint on a live tetrahedron. Runs `idle` while waiting for the other worker.
    fn round(&mut self, points: Vec<u32>, idle: &(dyn Fn() -> bool + Sync)) -> Vec<u32> {
        let Delaunay {
            pts,
            input_id,
            cells,
            mark,
            duplicate_of,
            serial,
            par,
            ball,
            ..
        } = self;
        let Some(par) = par.as_deref_mut() else {
            return points;
        };
        let count = points.len();
        let mut seq: [Vec<u32>; 2] = [Vec::new(), Vec::new()];
        for p in points {
            seq[par.side[p as usize] as usize].push(p);
        }
        let mut deferred = Vec::new();
        for (s, seq) in seq.iter_mut().enumerate() {
            let worker = &mut par.workers[s];
            // Enough free slots labelled with this side (about 6.5 new tetrahedra per point
            // on average; a worker that runs out defers the rest).
            let need = 8 * seq.len() + 1024;
            if worker.free.len() < need {
                let add = need - worker.free.len();
                let start = grow(cells, mark, Some(&mut par.owner), add, s as u8) as u32;
                worker.free.splice(0..0, (start..start + add as u32).rev());
            }
            // Walks start from a tetrahedron of this side.
            let ours = |t: u32| live_finite(cells, t) && par.owner[t as usize] == s as u8;
            if !ours(worker.hint) {
                match (0..cells.len() as u32).rev().find(|&t| ours(t)) {
                    Some(t) => worker.hint = t,
                    None => deferred.append(seq), // nothing of this side yet
                }
            }
        }
        let tets = Tets::new(cells, mark);
        let ball = ball.as_mut().map(TangentBalls::view);
        let owner = &par.owner[..];
        let run = |w: &mut Worker, seq: &[u32]| {
            let (mut deferred, mut duplicates) = (Vec::new(), Vec::new());
            for &p in seq {
                // SAFETY: both workers hold `tets` over the same live arrays, which nothing
                // else touches until both return; `owner` labels every slot as
                // `Worker::insert` requires (set by `start_parallel`, kept up to date by
                // `Delaunay::insert` and by the workers, the fresh slots above labelled with
                // their worker's side), each worker has its own side and free list, and
                // `ball` views live arrays that nothing else touches either.
                match unsafe { w.insert::<true>(tets, owner, pts, ball, p) } {
                    Outcome::Inserted => {}
                    Outcome::Duplicate(v) => duplicates.push((p, v)),
                    Outcome::Blocked | Outcome::NeedSlots(_) => deferred.push(p),
                }
            }
            (deferred, duplicates)
        };
        let [w0, w1] = &mut par.workers;
        let clock = std::time::Instant::now();
        // Side 1 runs on another thread if one takes it, else after side 0 on this one.
        let (started, finished) = (AtomicBool::new(false), AtomicBool::new(false));
        let ((d0, u0), (d1, u1)) = rayon::join(
            || {
                let done = run(w0, &seq[0]);
                while started.load(Ordering::Relaxed) && !finished.load(Ordering::Relaxed) {
                    if !idle() {
                        break;
                    }
                }
                done
            },
            || {
                started.store(true, Ordering::Relaxed);
                let done = run(w1, &seq[1]);
                finished.store(true, Ordering::Relaxed);
                done
            },
        );
        for (p, v) in u0.into_iter().chain(u1) {
            duplicate_of[input_id[p as usize] as usize] = input_id[v as usize];
        }
        deferred.extend(d0.into_iter().chain(d1));
        deferred.sort_unstable();
        log::debug!(
            "delaunay: {count} points in parallel, {:.1} ms, {} deferred",
            clock.elapsed().as_secs_f64() * 1e3,
            deferred.len()
        );
        // The serial walk starts from a tetrahedron still alive.
        let hint = [serial.hint, w0.hint, w1.hint]
            .into_iter()
            .find(|&t| live_finite(cells, t))
            .or_else(|| (0..cells.len() as u32).find(|&t| live_finite(cells, t)));
        serial.hint = hint.unwrap_or(0);
        deferred
    }

    /// Ends the parallel phases: the workers' free slots go to the serial list.
    fn end_parallel(&mut self) {
        if let Some(par) = self.par.take() {
            for w in par.workers {
                self.serial.free.extend(w.free);
                #[cfg(test)]
                {
                    self.serial.sorted_links += w.sorted_links;
                }
            }
        }
    }

    /// How many insertions linked their new tetrahedra by sorting.
    #[cfg(test)]
    fn sorted_links(&self) -> usize {
        self.serial.sorted_links
    }

    /// Finite tetrahedra (positively oriented, vertex ids are input indices).
    pub fn finite_tets(&self) -> Vec<[u32; 4]> {
        self.cells
            .iter()
            .filter(|c| c.is_live_finite())
            .map(|c| c.v.map(|v| self.input_id[v as usize]))
            .collect()
    }

    /// The inserted points in insertion order (the internal ids of
    /// [`Delaunay::tangent_balls`]) and the input index of each.
    pub fn insertion_order(&self) -> (&[DVec3], &[u32]) {
        (&self.pts, &self.input_id)
    }

    /// The shrinking-ball radius of every inserted point, in insertion order (see
    /// [`Delaunay::insertion_order`]), when built by [`Delaunay::with_tangent_balls`]:
    /// infinite for a point with no other on the inner side of its tangent plane, and for
    /// a duplicate (never inserted).
    pub fn tangent_balls(&self) -> Option<&[f64]> {
        self.ball.as_ref().map(|b| &b.radius[..])
    }

    /// Number of finite tetrahedra (one pass over the records, on every core).
    pub fn finite_tet_count(&self) -> usize {
        self.cells.par_iter().filter(|c| c.is_live_finite()).count()
    }

    /// For each input point, `Some(v)` when it coincided with the input point `v` and was
    /// not inserted.
    pub fn duplicate_of(&self, point: usize) -> Option<u32> {
        let d = self.duplicate_of[point];
        (d != NONE).then_some(d)
    }

    /// Number of live tetrahedra, infinite ones included.
    pub fn tet_count(&self) -> usize {
        self.cells.len() - self.serial.free.len()
    }

    /// Checks the structure: symmetric adjacency with matching faces, every finite
    /// tetrahedron positively oriented, the local Delaunay property across every finite
    /// face, and every non-duplicate point a vertex. Cost O(tetrahedra).
    pub fn check(&self) -> Result<(), String> {
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
            if finite && orient3d(self.p(tv[0]), self.p(tv[1]), self.p(tv[2]), self.p(tv[3])) <= 0.0
            {
                return Err(format!("tet {t} {tv:?} is not positively oriented"));
            }
            for j in 0..4 {
                let n = cell.n[j];
                if n == NONE || self.cells[n as usize].v[0] == FREE {
                    return Err(format!("tet {t} has a missing neighbour {j}"));
                }
                let Some(k) = self.cells[n as usize]
                    .n
                    .iter()
                    .position(|&x| x as usize == t)
                else {
                    return Err(format!("adjacency {t} -> {n} is not symmetric"));
                };
                if self.face_key(t as u32, j) != self.face_key(n, k) {
                    return Err(format!("tets {t} and {n} do not share their face"));
                }
                let opposite = self.cells[n as usize].v[k];
                if finite && opposite != INFINITE {
                    let [a, b, c, d] = tv.map(|v| self.p(v));
                    if insphere(a, b, c, d, self.p(opposite)) > 0.0 {
                        return Err(format!(
                            "tet {t}: vertex {opposite} inside its circumsphere"
                        ));
                    }
                }
            }
        }
        for (i, &v) in is_vertex.iter().enumerate() {
            if !v && self.duplicate_of[i] == NONE {
                return Err(format!("point {i} is missing from the tetrahedralization"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
