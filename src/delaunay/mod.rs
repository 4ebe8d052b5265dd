//! Exact 3D Delaunay tetrahedralization: incremental Bowyer–Watson. Why it is written here
//! and not taken from a crate: `ARCHITECTURE.md`.
//!
//! * `cell`: the tetrahedron records and the raw view the workers share;
//! * `walk`: point location (a remembering stochastic visibility walk);
//! * `cavity`: one insertion (cavity, fan, linking without hashing);
//! * `build`: insertion order and the serial insertions;
//! * `parallel`: the two-worker phases;
//! * [`hook`]: [`EdgeHook`], how a caller learns of every edge as it is made;
//! * `star`: [`Stars`], the Delaunay neighbours of a vertex after the build;
//! * `check`: [`Delaunay::check`] against the definition.
//!
//! The design in brief:
//! * **Exact predicates** ([`crate::geom::predicates`]): every orientation and in-sphere
//!   sign is exact, so the combinatorics can never become inconsistent.
//! * **Symbolic perturbation.** Ties in the in-sphere test (five cospherical points) are
//!   broken as if the lifted coordinate of each point were perturbed by a term that is larger
//!   for later-inserted points (Edelsbrunner–Mücke / Devillers–Teillaud). Because the point
//!   being inserted is always the latest, a tie always means "not in conflict", which costs
//!   nothing. The result is a valid Delaunay tetrahedralization of the unperturbed points in
//!   which no tetrahedron is flat.
//! * **A vertex at infinity** ([`INFINITE`]): every convex-hull face carries an infinite
//!   tetrahedron, so points outside the current hull need no special case and no bounding
//!   "super tetrahedron" distorts the hull. An infinite tetrahedron is in conflict with `p`
//!   when `p` is strictly beyond its hull face; when `p` lies exactly in the face's plane,
//!   its status is that of the finite neighbour across the face (the half-space is the limit
//!   of the spheres through that face), which keeps the cavity consistent.
//! * **BRIO + Hilbert order** ([`crate::geom::hilbert`]) keeps location walks short.
//! * **Memory laid out for a latency-bound walk**: vertices renumbered in insertion order
//!   (the points a cavity touches sit close together in memory), new tetrahedra in the
//!   cavity's own slots first, every scratch buffer reused, so an insertion allocates
//!   nothing once the arrays have grown. Ids are mapped back to input indices only in the
//!   output.
//!
//! Orientation convention: every tetrahedron `[v0, v1, v2, v3]` is positively oriented
//! (`orient3d(v0, v1, v2, v3) > 0`), and [`FACE`]`[i]` lists the face opposite `vi` so that
//! `vi` lies on its positive side.

mod build;
mod cavity;
mod cell;
mod check;
pub mod hook;
mod parallel;
mod star;
mod walk;

pub use check::Inconsistent;
pub use hook::EdgeHook;
pub use star::{StarScratch, Stars};

use cell::{Cell, NONE};
use glam::DVec3;
use rayon::prelude::*;

/// The vertex at infinity.
pub const INFINITE: u32 = u32::MAX;

/// Local vertex indices of the face opposite vertex `i`, ordered so that vertex `i` lies on
/// the positive side of the face.
pub const FACE: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];

/// Why no tetrahedralization exists.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum DelaunayError {
    /// Fewer than four points.
    #[error("need at least 4 points, got {0}")]
    TooFew(usize),
    /// More points than the 32-bit ids can number.
    #[error("{0} points is more than the 2^31 the tetrahedralization supports")]
    TooMany(usize),
    /// A point with a NaN or infinite coordinate (its index).
    #[error("point {0} has a non-finite coordinate")]
    NonFinite(usize),
    /// No four points span a volume.
    #[error("all points are {0}: they span no volume")]
    Flat(&'static str),
}

/// A Delaunay tetrahedralization of a point set (vertex ids in the output are input
/// indices).
///
/// # Two threads
/// Inputs of 32,768 points or more are inserted in phases after a serial start
/// (the first sixteenth of the insertion order; the phases then double in size). A plane
/// through the median of the points along one axis (the one whose plane cuts the fewest
/// tetrahedra of the serial start) splits them into two sides; in a phase, each side's
/// worker inserts its side's points of the phase, changing only tetrahedra whose finite
/// vertices are all on its side (labelled before the phase; its walks may also pass
/// through tetrahedra straddling the plane, which nobody changes during a phase). An
/// insertion that would change anything else is deferred, and the deferred points are
/// inserted serially after the phase, in insertion order. A worker's insertions only ever
/// test spheres through its own side's points and earlier ones, so every test gives the
/// answer it would give in a serial insertion of the same points in some interleaved
/// order: the result is the Delaunay tetrahedralization (with the same tie-breaking as the
/// serial one for each such order), and it is the same whether the workers run
/// concurrently or one after the other, so it never depends on the thread count or on
/// timing.
pub struct Delaunay {
    /// Points in insertion order: internal vertex `k` is input point `input_id[k]`.
    pts: Vec<DVec3>,
    input_id: Vec<u32>,
    cells: Vec<Cell>,
    duplicate_of: Vec<u32>,
    /// Free records among `cells`.
    free: usize,
    /// How many insertions the parallel phases deferred (tests check both paths run).
    #[cfg(test)]
    deferred: usize,
    /// How many insertions linked their new tetrahedra by sorting.
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

    /// As [`Delaunay::new`], calling `progress(fraction)` now and then (from the calling
    /// thread).
    pub fn with_progress(points: &[DVec3], progress: &dyn Fn(f64)) -> Result<Self, DelaunayError> {
        let first = parallel::first_parallel(points.len());
        build::build(points, progress, &|| false, first, |_| ()).map(|(delaunay, ())| delaunay)
    }

    /// As [`Delaunay::with_progress`], telling a hook of every edge as it is made (see
    /// [`EdgeHook`]). `make_hook` gets the input index of every point in insertion order
    /// (the hook's vertex ids are positions in it).
    ///
    /// `idle` is the caller's other work, in small units: whenever the calling thread has
    /// inserted its side of a parallel phase while the other worker still runs on another
    /// thread, it calls `idle()` until that worker is done or `idle` returns false (no work
    /// left). Without it, that thread would wait: the two sides of a phase never take
    /// exactly as long.
    pub fn with_edge_hook<H: EdgeHook>(
        points: &[DVec3],
        progress: &dyn Fn(f64),
        idle: &(dyn Fn() -> bool + Sync),
        make_hook: impl FnOnce(&[u32]) -> H,
    ) -> Result<(Self, H), DelaunayError> {
        let first = parallel::first_parallel(points.len());
        build::build(points, progress, idle, first, make_hook)
    }

    /// As [`Delaunay::with_edge_hook`], with the parallel phases starting at insertion
    /// `first_parallel` (none when it is `points.len()` or more): tests run both paths on
    /// small inputs.
    #[cfg(test)]
    pub(crate) fn with_phases_from<H: EdgeHook>(
        points: &[DVec3],
        idle: &(dyn Fn() -> bool + Sync),
        first_parallel: usize,
        make_hook: impl FnOnce(&[u32]) -> H,
    ) -> Result<(Self, H), DelaunayError> {
        build::build(points, &|_| {}, idle, first_parallel, make_hook)
    }

    #[inline(always)]
    fn point(&self, v: u32) -> DVec3 {
        self.pts[v as usize]
    }

    /// The vertices of face `i` of tetrahedron `t`, sorted (to compare faces).
    fn face_key(&self, t: u32, i: usize) -> [u32; 3] {
        let tv = self.cells[t as usize].v;
        let mut k = FACE[i].map(|j| tv[j]);
        k.sort_unstable();
        k
    }

    /// How many insertions linked their new tetrahedra by sorting.
    #[cfg(test)]
    fn sorted_links(&self) -> usize {
        self.sorted_links
    }

    /// Finite tetrahedra (positively oriented, vertex ids are input indices).
    pub fn finite_tets(&self) -> Vec<[u32; 4]> {
        self.cells
            .iter()
            .filter(|c| c.is_live_finite())
            .map(|c| c.v.map(|v| self.input_id[v as usize]))
            .collect()
    }

    /// The inserted points in insertion order (the internal ids of an [`EdgeHook`]) and
    /// the input index of each.
    pub fn insertion_order(&self) -> (&[DVec3], &[u32]) {
        (&self.pts, &self.input_id)
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
        self.cells.len() - self.free
    }
}

#[cfg(test)]
mod tests;
