//! The Voronoi-based medial skeleton (paper §3.1): one skeletal point per mesh vertex,
//! `sp_i = p_i − d_i n_i`, so the skeletal mesh `S` keeps the mesh's connectivity and
//! `M = S + dN`.
//!
//! Stages ([`build`]):
//! 1. **Tetrahedralize** the vertices ([`crate::delaunay`]); tetrahedron circumcentres are
//!    the Voronoi vertices, and each is a Voronoi vertex of the cells of its four corners,
//!    at distance `R` (the circumradius) from each of them.
//! 2. **Classify** every circumcentre: slivers (volume tiny against the longest edge cubed;
//!    their circumcentres are ill-conditioned garbage) are ignored, the rest are tested
//!    against the mesh with its exact winding number ([`crate::geom::inside`]), not the
//!    paper's local face-normal check, which misclassifies in concave regions (nor the
//!    ray's parity, which calls a self-overlap outside). The shrinking
//!    balls ([`Method::ShrinkingBall`], the default [`Method::FittedBall`]) read only the
//!    Delaunay edges and skip this stage.
//! 3. **Distance** per vertex from the inside Voronoi vertices of its cell: [`Method::Mean`]
//!    is the paper (their mean distance), [`Method::Pole`] the inner pole (the farthest one;
//!    Amenta et al.); the shrinking balls from the Delaunay neighbours, a minimum that
//!    stage 1 takes over each edge as it is made (the fitted ball's normals and starts come
//!    from a local fit of the surface first; a fitted ball that holds one of the
//!    vertices its fit stands for is then searched through the Delaunay graph, since the
//!    vertex limiting it may hide behind that one). A vertex with none gets `d = 0`
//!    (`sp = p`) and is counted.
//! 4. **Clamp** to the local thickness: a ray from `p_i` along `−n_i` first leaves the object
//!    at distance `t_i`; a ball tangent at `p_i` with its centre on that ray fits only if its
//!    diameter is at most `t_i`, so `d_i ≤ t_i / 2` bounds the true medial radius and keeps
//!    `sp_i` inside the object.
//!
//! During stage 1 the other core builds the inside oracle (for the methods that classify)
//! and the BVH, then measures `t_i` for as many vertices as it can while the
//! tetrahedralization is serial; whenever one of its parallel phases waits for a second
//! worker, this core runs it first (`rayon::yield_now`, between packets of eight rays and
//! every few thousand triangles of the BVH build), and whenever the tetrahedralizing core
//! finishes its side of a phase first, it casts rays until the other side is done (both
//! claim packets from one counter). Stage 4 does the rest. Stages 2 and 3
//! (for the methods that classify) and 4 use both cores. No result depends on the thread
//! count or on how far the overlap got (tested).
//!
//! Files: `build` (the stages, run together), `shrinking_ball` (the balls on the
//! tetrahedralization's edge hook), `voronoi` (stages 2–3 for the classifying methods),
//! `thickness` (stage 4), `cache` (skeletons cached by mesh content), `method` (how `d_i`
//! is taken, and the parameters). The analytic shapes
//! with known medial radii it is measured against are `crate::bench::truth`.

mod build;
pub mod cache;
mod method;
mod shrinking_ball;
mod thickness;
mod voronoi;

pub use build::build;
pub use method::{Method, SkeletonParams};
pub use shrinking_ball::{tangent_radius, Tangent, SEARCH_MAX, SETTLE_SLACK};

use crate::delaunay::DelaunayError;
use glam::DVec3;

/// The skeleton of a mesh.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Skeleton {
    /// Skeletal distance `d_i` per vertex.
    pub distance: Vec<f64>,
    /// Skeletal points `sp_i = p_i − d_i n_i`.
    #[serde(skip)]
    pub points: Vec<DVec3>,
    /// Vertices without any inside Voronoi vertex, or for [`Method::ShrinkingBall`] without
    /// any Delaunay neighbour on the inner side (`sp_i = p_i`).
    pub fallback: usize,
    /// Vertices whose distance was limited by the local thickness by more than 1 %.
    pub clamped: usize,
    /// Vertices of riders (small separate parts, see [`crate::mesh::Parts`]): no skeleton of
    /// their own, `d = 0` and `sp = p`.
    pub riders: usize,
    /// Finite tetrahedra of the Delaunay tetrahedralization.
    pub tetrahedra: usize,
    /// Circumcentres used (inside, not slivers); 0 for [`Method::ShrinkingBall`], which
    /// classifies none.
    pub inside_voronoi_vertices: usize,
    /// Seconds per stage, in order.
    pub seconds: Vec<(&'static str, f64)>,
}

impl Skeleton {
    /// [`Skeleton::keep_inside`] where a skeleton can leave its mesh: after repairs
    /// (`repaired`: a filled hole's rim), and on a mesh of two or more body parts (`parts`,
    /// the mesh's: each part's skeleton is built on that part alone, [`build`]). Returns
    /// how many moved.
    pub fn hold_inside(
        &mut self,
        mesh: &crate::mesh::Mesh,
        parts: &crate::mesh::Parts,
        repaired: bool,
    ) -> usize {
        if repaired || parts.body_parts().len() > 1 {
            self.keep_inside(mesh)
        } else {
            0
        }
    }

    /// Moves every skeletal point that lies outside `mesh` (by its exact winding number)
    /// back towards its vertex, halving its distance until it is inside (at most 30
    /// times, then `d = 0`); returns how many moved. A safety net for repaired meshes,
    /// where a filled hole's rim can fold and turn a normal into the object, so that no
    /// face stops its ball; a tidy surface needs none of it (the loader calls it only
    /// after repairs that leave rims).
    pub fn keep_inside(&mut self, mesh: &crate::mesh::Mesh) -> usize {
        let inside = crate::geom::inside::InsideTest::new(mesh);
        let mut moved = 0;
        for (v, p) in mesh.positions.iter().enumerate() {
            let (d, sp) = (self.distance[v], self.points[v]);
            if d <= 0.0 || inside.contains(sp) {
                continue;
            }
            let n = (*p - sp) / d;
            let mut d = d;
            for _ in 0..30 {
                d *= 0.5;
                if inside.contains(*p - d * n) {
                    break;
                }
            }
            if !inside.contains(*p - d * n) {
                d = 0.0;
            }
            self.distance[v] = d;
            self.points[v] = *p - d * n;
            moved += 1;
        }
        moved
    }
}

/// Why no skeleton could be built.
#[derive(Debug, thiserror::Error)]
pub enum SkeletonError {
    /// No tetrahedralization of the vertices.
    #[error("tetrahedralization failed: {0}")]
    Delaunay(#[from] DelaunayError),
    /// Not one normal per vertex (normals, vertices).
    #[error("{0} normals for {1} vertices")]
    Normals(usize, usize),
}
#[cfg(test)]
mod tests;
