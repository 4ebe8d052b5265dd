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
//! Orientation convention: every tetrahedron `[v0, v1, v2, v3]` is positively oriented
//! (`orient3d(v0, v1, v2, v3) > 0`), and [`FACE`]`[i]` lists the face opposite `vi` so that
//! `vi` lies on its positive side.

use crate::geom::hilbert::{brio_order, SplitMix};
use crate::geom::predicates::{collinear, insphere, orient3d};
use glam::DVec3;

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

/// Is tetrahedron `t` in conflict with (its circumsphere strictly containing) `q`?
#[inline(always)]
fn conflict(pts: &[DVec3], cells: &[Cell], t: u32, q: DVec3) -> bool {
    let p = |v: u32| pts[v as usize];
    let cell = cells[t as usize];
    let tv = cell.v;
    if let Some(k) = tv.iter().position(|&v| v == INFINITE) {
        let f = FACE[k];
        let o = orient3d(p(tv[f[0]]), p(tv[f[1]]), p(tv[f[2]]), q);
        if o != 0.0 {
            return o > 0.0;
        }
        return sphere_conflict(pts, cells[cell.n[k] as usize].v, q);
    }
    sphere_conflict(pts, tv, q)
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

/// A Delaunay tetrahedralization of a point set (vertex ids are input indices).
pub struct Delaunay {
    /// Points in insertion order: internal vertex `k` is input point `input_id[k]`.
    pts: Vec<DVec3>,
    input_id: Vec<u32>,
    cells: Vec<Cell>,
    free: Vec<u32>,
    mark: Vec<u8>,
    rng: SplitMix,
    hint: u32,
    duplicate_of: Vec<u32>,
    // Scratch, reused by every insertion.
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

impl Delaunay {
    /// Tetrahedralizes `points`.
    ///
    /// # Errors
    /// Fewer than four points, a non-finite coordinate, or no four points spanning a volume.
    pub fn new(points: &[DVec3]) -> Result<Self, DelaunayError> {
        Self::with_progress(points, &|_| {})
    }

    /// As [`Delaunay::new`], calling `progress(fraction)` now and then.
    pub fn with_progress(points: &[DVec3], progress: &dyn Fn(f64)) -> Result<Self, DelaunayError> {
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

        let mut dt = Delaunay {
            pts: order.iter().map(|&i| points[i as usize]).collect(),
            input_id: order,
            cells: Vec::with_capacity(7 * n),
            free: Vec::new(),
            mark: Vec::with_capacity(7 * n),
            rng: SplitMix(0x1234_5678),
            hint: 0,
            duplicate_of: vec![NONE; n],
            stack: Vec::new(),
            cavity: Vec::new(),
            boundary: Vec::new(),
            created: Vec::new(),
            local: vec![NO_LOCAL; n + 1],
            local_verts: Vec::new(),
            link: Box::new([NONE; LINK_MAX * LINK_MAX]),
            sorted: Vec::new(),
            #[cfg(test)]
            sorted_links: 0,
        };
        dt.init_simplex([0, 1, 2, 3]);
        let step = (n / 64).max(1 << 14);
        for k in 4..n {
            dt.insert(k as u32);
            if k % step == 0 {
                progress(k as f64 / n as f64);
            }
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
        let mut ids = vec![self.alloc(t0)];
        for f in FACE {
            let (x, y, z) = (t0[f[0]], t0[f[1]], t0[f[2]]);
            ids.push(self.alloc([x, z, y, INFINITE]));
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
        self.hint = ids[0];
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

    fn alloc(&mut self, v: [u32; 4]) -> u32 {
        if let Some(t) = self.free.pop() {
            self.cells[t as usize].v = v;
            t
        } else {
            self.cells.push(Cell { v, n: [NONE; 4] });
            self.mark.push(UNSEEN);
            (self.cells.len() - 1) as u32
        }
    }

    fn locate(&mut self, q: DVec3) -> Located {
        let mut t = self.hint;
        let mut prev = NONE;
        let limit = 4 * self.cells.len() + 64;
        for _ in 0..limit {
            let Cell { v: tv, n: adj } = self.cells[t as usize];
            if tv.contains(&INFINITE) {
                return Located::Tet(t);
            }
            let r = self.rng.next_u64() as usize;
            let mut next = NONE;
            for k in 0..4 {
                let j = (r + k) & 3;
                let n = adj[j];
                if n == prev {
                    continue;
                }
                let f = FACE[j];
                if orient3d(self.p(tv[f[0]]), self.p(tv[f[1]]), self.p(tv[f[2]]), q) < 0.0 {
                    next = n;
                    break;
                }
            }
            if next == NONE {
                if let Some(&v) = tv.iter().find(|&&v| self.p(v) == q) {
                    return Located::Vertex(v);
                }
                return Located::Tet(t);
            }
            prev = t;
            t = next;
        }
        self.locate_exhaustive(q)
    }

    /// Fallback that cannot loop: scan every tetrahedron. Never needed in a correct
    /// Delaunay triangulation (visibility walks terminate there); kept as a guard.
    fn locate_exhaustive(&self, q: DVec3) -> Located {
        log::warn!("delaunay: walk did not terminate; scanning");
        for (t, cell) in self.cells.iter().enumerate() {
            let tv = cell.v;
            if tv[0] == FREE {
                continue;
            }
            if let Some(k) = tv.iter().position(|&v| v == INFINITE) {
                let f = FACE[k];
                if orient3d(self.p(tv[f[0]]), self.p(tv[f[1]]), self.p(tv[f[2]]), q) > 0.0 {
                    return Located::Tet(t as u32);
                }
                continue;
            }
            let inside = FACE
                .iter()
                .all(|f| orient3d(self.p(tv[f[0]]), self.p(tv[f[1]]), self.p(tv[f[2]]), q) >= 0.0);
            if inside {
                if let Some(&v) = tv.iter().find(|&&v| self.p(v) == q) {
                    return Located::Vertex(v);
                }
                return Located::Tet(t as u32);
            }
        }
        Located::Tet(self.hint)
    }

    #[inline(never)]
    fn insert(&mut self, p: u32) {
        let q = self.p(p);
        let t0 = match self.locate(q) {
            Located::Tet(t) => t,
            Located::Vertex(v) => {
                self.duplicate_of[self.input_id[p as usize] as usize] = self.input_id[v as usize];
                return;
            }
        };
        // The fields as separate borrows, so that the loops below keep them in registers.
        let Delaunay {
            pts,
            cells,
            free,
            mark,
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
        let inf_slot = pts.len();
        // 1. The cavity: all tetrahedra whose circumsphere contains q (a connected set), and
        // its boundary faces, each vertex numbered locally for the linking in step 3.
        cavity.clear();
        boundary.clear();
        stack.clear();
        local_verts.clear();
        mark[t0 as usize] = IN;
        cavity.push(t0);
        stack.push(t0);
        let (cells_s, mark_s, local_s): (&[Cell], &mut [u8], &mut [u8]) = (cells, mark, local);
        while let Some(t) = stack.pop() {
            let Cell { v: tv, n: adj } = cells_s[t as usize];
            for (j, f) in FACE.iter().enumerate() {
                let n = adj[j];
                let m = mark_s[n as usize];
                if m == IN {
                    continue;
                }
                if m != OUT {
                    if conflict(pts, cells_s, n, q) {
                        mark_s[n as usize] = IN;
                        cavity.push(n);
                        stack.push(n);
                        continue;
                    }
                    mark_s[n as usize] = OUT;
                }
                let slot = cells_s[n as usize]
                    .n
                    .iter()
                    .position(|&x| x == t)
                    .unwrap_or(0) as u8;
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
        // 2. Fill the cavity with a fan of tetrahedra from q to its boundary, reusing the
        // cavity's own slots first.
        for &t in cavity.iter() {
            mark[t as usize] = UNSEEN;
        }
        created.clear();
        for (k, b) in boundary.iter().enumerate() {
            mark[b.out as usize] = UNSEEN;
            let cell = Cell {
                v: [b.v[0], b.v[1], b.v[2], p],
                n: [NONE, NONE, NONE, b.out],
            };
            let nt = if let Some(&t) = cavity.get(k) {
                cells[t as usize] = cell;
                t
            } else if let Some(t) = free.pop() {
                cells[t as usize] = cell;
                t
            } else {
                cells.push(cell);
                mark.push(UNSEEN);
                (cells.len() - 1) as u32
            };
            cells[b.out as usize].n[b.slot as usize] = nt;
            created.push(nt);
            if !b.v.contains(&INFINITE) {
                *hint = nt;
            }
        }
        for &t in cavity.iter().skip(boundary.len()) {
            cells[t as usize].v = [FREE; 4];
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
            let cells: &mut [Cell] = cells;
            for (b, &nt) in boundary.iter().zip(created.iter()) {
                let [l0, l1, l2] = b.l;
                let n = &mut cells[nt as usize].n;
                n[0] = link[at(l2, l1)];
                n[1] = link[at(l0, l2)];
                n[2] = link[at(l1, l0)];
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
                cells[(a >> 2) as usize].n[(a & 3) as usize] = b >> 2;
                cells[(b >> 2) as usize].n[(b & 3) as usize] = a >> 2;
            }
        }
        for &x in local_verts.iter() {
            local[(x as usize).min(inf_slot)] = NO_LOCAL;
        }
    }

    /// Finite tetrahedra (positively oriented, vertex ids are input indices).
    pub fn finite_tets(&self) -> Vec<[u32; 4]> {
        self.finite_tets_internal(0, 1)
            .map(|tv| tv.map(|v| self.input_id[v as usize]))
            .collect()
    }

    /// The inserted points in insertion order (the internal ids that
    /// [`Delaunay::finite_tets_internal`] uses) and the input index of each.
    pub fn insertion_order(&self) -> (&[DVec3], &[u32]) {
        (&self.pts, &self.input_id)
    }

    /// The finite tetrahedra among the records of part `part` of `parts` equal parts (in
    /// record order), with internal vertex ids (see [`Delaunay::insertion_order`]): no
    /// copy, and vertices close in memory are close in space, so per-vertex passes stay in
    /// cache better than over input indices.
    pub fn finite_tets_internal(
        &self,
        part: usize,
        parts: usize,
    ) -> impl Iterator<Item = [u32; 4]> + '_ {
        let len = self.cells.len();
        let (lo, hi) = (len * part / parts.max(1), len * (part + 1) / parts.max(1));
        self.cells[lo.min(len)..hi.min(len)]
            .iter()
            .filter(|c| c.v[0] != FREE && !c.v.contains(&INFINITE))
            .map(|c| c.v)
    }

    /// For each input point, `Some(v)` when it coincided with the input point `v` and was
    /// not inserted.
    pub fn duplicate_of(&self, point: usize) -> Option<u32> {
        let d = self.duplicate_of[point];
        (d != NONE).then_some(d)
    }

    /// Number of live tetrahedra, infinite ones included.
    pub fn tet_count(&self) -> usize {
        self.cells.len() - self.free.len()
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
