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
//!   cavity mark per tetrahedron, cleared after each insertion. Freed slots are reused, and
//!   all scratch buffers live in the struct, so an insertion allocates nothing once the
//!   arrays have grown. Ids are mapped back to input indices only in the output.
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

/// A boundary face of the cavity: its vertices (oriented towards the cavity), the tetrahedron
/// outside it and which of that tetrahedron's neighbour slots points into the cavity.
#[derive(Clone, Copy)]
struct BoundaryFace {
    v: [u32; 3],
    out: u32,
    slot: u8,
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
    table: Vec<(u64, u32)>,
    table_used: Vec<u32>,
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
            table: Vec::new(),
            table_used: Vec::new(),
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

    /// Is tetrahedron `t` in conflict with (its circumsphere strictly containing) `q`?
    #[inline]
    fn conflict(&self, t: u32, q: DVec3) -> bool {
        let cell = self.cells[t as usize];
        let tv = cell.v;
        if let Some(k) = tv.iter().position(|&v| v == INFINITE) {
            let f = FACE[k];
            let o = orient3d(self.p(tv[f[0]]), self.p(tv[f[1]]), self.p(tv[f[2]]), q);
            if o != 0.0 {
                return o > 0.0;
            }
            return self.sphere_conflict(self.cells[cell.n[k] as usize].v, q);
        }
        self.sphere_conflict(tv, q)
    }

    #[inline]
    fn sphere_conflict(&self, tv: [u32; 4], q: DVec3) -> bool {
        // A tie (q cospherical) is "outside": q is the latest point (see module docs).
        insphere(
            self.p(tv[0]),
            self.p(tv[1]),
            self.p(tv[2]),
            self.p(tv[3]),
            q,
        ) > 0.0
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

    fn insert(&mut self, p: u32) {
        let q = self.p(p);
        let t0 = match self.locate(q) {
            Located::Tet(t) => t,
            Located::Vertex(v) => {
                self.duplicate_of[self.input_id[p as usize] as usize] = self.input_id[v as usize];
                return;
            }
        };
        // 1. The cavity: all tetrahedra whose circumsphere contains q (a connected set).
        self.cavity.clear();
        self.boundary.clear();
        self.stack.clear();
        self.mark[t0 as usize] = IN;
        self.cavity.push(t0);
        self.stack.push(t0);
        while let Some(t) = self.stack.pop() {
            let Cell { v: tv, n: adj } = self.cells[t as usize];
            for (j, f) in FACE.iter().enumerate() {
                let n = adj[j];
                let m = self.mark[n as usize];
                if m == IN {
                    continue;
                }
                if m != OUT {
                    if self.conflict(n, q) {
                        self.mark[n as usize] = IN;
                        self.cavity.push(n);
                        self.stack.push(n);
                        continue;
                    }
                    self.mark[n as usize] = OUT;
                }
                let slot = self.cells[n as usize]
                    .n
                    .iter()
                    .position(|&x| x == t)
                    .unwrap_or(0) as u8;
                self.boundary.push(BoundaryFace {
                    v: [tv[f[0]], tv[f[1]], tv[f[2]]],
                    out: n,
                    slot,
                });
            }
        }
        // 2. Free the cavity and fill it with a fan of tetrahedra from q to its boundary.
        for i in 0..self.cavity.len() {
            let t = self.cavity[i];
            self.cells[t as usize].v = [FREE; 4];
            self.mark[t as usize] = UNSEEN;
            self.free.push(t);
        }
        self.created.clear();
        for i in 0..self.boundary.len() {
            let b = self.boundary[i];
            self.mark[b.out as usize] = UNSEEN;
            let nt = self.alloc([b.v[0], b.v[1], b.v[2], p]);
            self.cells[nt as usize].n[3] = b.out;
            self.cells[b.out as usize].n[b.slot as usize] = nt;
            self.created.push(nt);
        }
        // 3. Link the new tetrahedra to each other through their shared edges on the
        // boundary: the face opposite local vertex i (i < 3) holds q and one boundary edge.
        let need = (self.created.len() * 6).next_power_of_two().max(16);
        if self.table.len() < need {
            self.table = vec![(u64::MAX, 0); need];
        }
        let mask = need - 1;
        let shift = 64 - need.trailing_zeros();
        for ci in 0..self.created.len() {
            let nt = self.created[ci];
            let v = self.cells[nt as usize].v;
            for (i, (x, y)) in [(v[1], v[2]), (v[0], v[2]), (v[0], v[1])]
                .into_iter()
                .enumerate()
            {
                let key = ((x.min(y) as u64) << 32) | x.max(y) as u64;
                let mut h = (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> shift) as usize & mask;
                loop {
                    let (k, val) = self.table[h];
                    if k == u64::MAX {
                        self.table[h] = (key, (nt << 2) | i as u32);
                        self.table_used.push(h as u32);
                        break;
                    }
                    if k == key {
                        let (ot, oi) = (val >> 2, (val & 3) as usize);
                        self.cells[nt as usize].n[i] = ot;
                        self.cells[ot as usize].n[oi] = nt;
                        break;
                    }
                    h = (h + 1) & mask;
                }
            }
            if !v.contains(&INFINITE) {
                self.hint = nt;
            }
        }
        for &h in &self.table_used {
            self.table[h as usize].0 = u64::MAX;
        }
        self.table_used.clear();
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
