//! The edge hook: how a caller learns of every Delaunay edge as it is made, without a pass
//! over the finished tetrahedra (the skeleton takes its shrinking balls this way).

use glam::DVec3;

/// Told of every Delaunay edge once, as it is made: the first tetrahedron's six edges, then
/// the edges that join each inserted point to the vertices of its cavity's boundary. Every
/// edge of the final tetrahedralization is made this way; an edge removed by a later
/// insertion was offered too.
///
/// Vertices are internal ids, in insertion order; `pts` are the points in that order. The
/// hook is made from the input index of each internal id ([`super::Delaunay::with_edge_hook`]).
pub trait EdgeHook: Sync {
    /// The edge between internal vertices `a` and `b` was made.
    ///
    /// # Safety
    /// What the tetrahedralization guarantees, so that an implementation may keep
    /// per-vertex state without locks: the two workers of a parallel phase call this
    /// concurrently, but never with a vertex in common (each only joins points of its own
    /// side), and no other call overlaps theirs.
    unsafe fn edge(&self, pts: &[DVec3], a: u32, b: u32);
}

/// No hook: nothing to learn.
impl EdgeHook for () {
    #[inline(always)]
    unsafe fn edge(&self, _: &[DVec3], _: u32, _: u32) {}
}
