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
//! `thickness` (stage 4), `cache` (skeletons cached by mesh content). The analytic shapes
//! with known medial radii it is measured against are `crate::bench::truth`.

mod build;
pub mod cache;
mod shrinking_ball;
mod thickness;
mod voronoi;

pub use build::build;
pub use shrinking_ball::{tangent_radius, Tangent, SEARCH_MAX, SETTLE_SLACK};

use crate::delaunay::DelaunayError;
use glam::DVec3;

/// How the skeletal distance `d_i` is taken from the inside Voronoi vertices of cell `i`.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// The paper: the mean distance of the inside (non-sliver) Voronoi vertices.
    Mean,
    /// The inner pole: the farthest inside Voronoi vertex.
    Pole,
    /// The shrinking ball (Ma et al. 2012): the largest ball tangent at `p_i` (centre on
    /// `−n_i`) with no vertex inside, `min_q |q − p|² / (−2 n·(q − p))`. Its limiting vertex
    /// `q` and `p` lie on an empty sphere, so `pq` is a Delaunay edge: the minimum over the
    /// Delaunay neighbours of `p` is exact, no kd-tree needed, and no circumcentre has to be
    /// classified (the cheapest method: no inside oracle). A vertex with no Delaunay
    /// neighbour on the inner side of its tangent plane is a fallback. Along angle-weighted
    /// normals, which tilt on an uneven fan: see [`Method::FittedBall`].
    ShrinkingBall,
    /// The shrinking ball on a fitted surface ([`crate::mesh::fit_surface`]): along the
    /// fitted normal, starting at the fitted radius, shrunk by every vertex but
    /// the 1-ring neighbours the fit stands for ([`Tangent`]). Within 1 % median and 3 %
    /// p95 on tidy and uneven meshes (alternating gaps, jittered, decimated) where the
    /// shrinking ball is off by up to 43 % (`docs/engine-benchmarks.md`); exact to its definition
    /// whatever the Delaunay edges offer (`ShrinkingBalls::settle`). The default.
    #[default]
    FittedBall,
}

impl Method {
    /// All methods, for reports.
    pub const ALL: [Method; 4] = [
        Method::Mean,
        Method::Pole,
        Method::ShrinkingBall,
        Method::FittedBall,
    ];

    /// Whether the method reads the inside Voronoi vertices, so that every circumcentre
    /// must be classified against the mesh.
    pub fn needs_oracle(self) -> bool {
        !self.is_ball()
    }

    /// Whether the method is a shrinking ball (taken over the Delaunay edges as they are
    /// made, no inside oracle).
    pub fn is_ball(self) -> bool {
        matches!(self, Method::ShrinkingBall | Method::FittedBall)
    }

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Method::Mean => "mean",
            Method::Pole => "pole",
            Method::ShrinkingBall => "shrinking-ball",
            Method::FittedBall => "fitted-ball",
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Skeleton parameters.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SkeletonParams {
    /// Distance method. Default: [`Method::FittedBall`], chosen by the accuracy table in
    /// `docs/engine-benchmarks.md`.
    pub method: Method,
    /// A tetrahedron is a sliver when `6 V / l_max³` is below this (a regular tetrahedron
    /// has `1/√2`). Default `1e-3`. Vertices whose every inside Voronoi vertex comes from a
    /// sliver use those rather than nothing.
    pub sliver_ratio: f64,
}

impl Default for SkeletonParams {
    fn default() -> Self {
        SkeletonParams {
            method: Method::default(),
            sliver_ratio: 1e-3,
        }
    }
}

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
mod tests {
    use super::build::{build_with, Overlap};
    use super::thickness::ring_bounds;
    use super::*;
    use crate::mesh::{shapes, Mesh};

    /// A 1.5:1:0.5 ellipsoid whose vertices are pushed out by up to 3 % at random, so that
    /// balls are limited by the far side, by the local curvature and by the bumps.
    fn bumpy_ellipsoid(seed: u64) -> Mesh {
        let mut mesh = shapes::ellipsoid(1.5, 1.0, 0.5, 24, 48);
        let mut rng = crate::random::SplitMix(seed);
        for p in &mut mesh.positions {
            *p *= 1.0 + 0.03 * ((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64);
        }
        mesh
    }

    /// The default method, checked against its definition by brute force over all vertices
    /// (no Delaunay edges): every ball is no larger than its start (the fitted curvature
    /// radius) and empty of the vertices off its patch, and unless the thickness clamp
    /// shrank it by more than 1 %, it is the largest such ball: its start, or some vertex
    /// off the patch lies on it. On a bumpy ellipsoid, where balls are limited by the far
    /// side, by the local curvature and by the bumps.
    #[test]
    fn fitted_ball_is_the_largest_tangent_ball_empty_off_its_patch() {
        let mesh = bumpy_ellipsoid(3);
        let normals = crate::mesh::vertex_normals(&mesh).unwrap();
        let none = |_: &str, _: f64| {};
        let sk = build(&mesh, &normals, &SkeletonParams::default(), &none).unwrap();
        assert_eq!(sk.fallback, 0);
        let start = crate::mesh::fit_surface(&mesh, &normals).fitted_radius;
        let brute = crate::bench::truth::fitted_balls_by_brute_force(&mesh, &normals);
        let pts = &mesh.positions;
        let (mut largest, mut started) = (0, 0);
        for (i, (&d, &brute)) in sk.distance.iter().zip(&brute).enumerate() {
            assert!(
                d > 0.0 && d <= brute * (1.0 + 1e-12),
                "vertex {i}: {d} > {brute}"
            );
            // A clamp of less than 1 % is not counted as one.
            largest += usize::from(d >= brute * 0.99);
            started += usize::from(brute == start[i]);
        }
        // Only clamped balls may be smaller than the largest one.
        assert!(
            largest + sk.clamped >= pts.len(),
            "{largest} + {}",
            sk.clamped
        );
        // Both limits occur: the curvature and a vertex.
        assert!(started > 0 && started < pts.len(), "{started} started");
    }

    /// Two balls modelled apart and pushed into each other (the second one a capsule, as an
    /// arm pushed into a body): each part's skeleton is its own, as if the other were not
    /// there, and every skeletal point is inside by the winding number.
    #[test]
    fn overlapping_parts_each_get_their_own_skeleton() {
        let ball = shapes::icosphere(1.0, 3);
        let arm = shapes::capsule(0.3, 0.8, 8, 8, 16);
        let mut mesh = ball.clone();
        let n = mesh.positions.len() as u32;
        let shift = DVec3::new(1.0, 0.0, 0.0);
        // The capsule lies along z: turn it to lie along x, its far end out of the ball.
        mesh.positions.extend(
            arm.positions
                .iter()
                .map(|p| DVec3::new(p.z, p.y, -p.x) + shift),
        );
        mesh.triangles
            .extend(arm.triangles.iter().map(|t| t.map(|i| i + n)));
        let normals = crate::mesh::vertex_normals(&mesh).unwrap();
        let none = |_: &str, _: f64| {};
        let params = SkeletonParams::default();
        let sk = build(&mesh, &normals, &params, &none).unwrap();
        assert_eq!(sk.riders, 0);
        let alone = |m: &Mesh| build(m, &crate::mesh::vertex_normals(m).unwrap(), &params, &none);
        let ball_alone = alone(&ball).unwrap();
        assert_eq!(&sk.distance[..n as usize], &ball_alone.distance[..]);
        let inside = crate::geom::inside::InsideTest::new(&mesh);
        for (v, p) in sk.points.iter().enumerate() {
            assert!(inside.contains(*p), "skeletal point {v} outside");
        }
        // The ball's points near the arm are not pulled to the surface by the arm's
        // buried vertices: every ball vertex keeps most of its radius.
        let least = sk.distance[..n as usize]
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        assert!(least > 0.8, "{least}");
    }

    /// The mesh-neighbour bound that shortens the thickness rays cast during the
    /// tetrahedralization holds (twice every shrinking-ball radius), and is not loose
    /// everywhere (or the shortcut would be worthless), on a bumpy ellipsoid.
    #[test]
    fn ring_bounds_bound_the_shrinking_ball() {
        let mesh = bumpy_ellipsoid(5);
        let normals = crate::mesh::vertex_normals(&mesh).unwrap();
        let none = |_: &str, _: f64| {};
        for method in [Method::ShrinkingBall, Method::FittedBall] {
            let params = SkeletonParams {
                method,
                ..SkeletonParams::default()
            };
            let sk = build(&mesh, &normals, &params, &none).unwrap();
            // The bound is taken over the tangents the balls use.
            let tangents = match method {
                Method::FittedBall => Tangent::fitted(&crate::mesh::fit_surface(&mesh, &normals)),
                _ => normals.iter().map(|&n| Tangent::plain(n)).collect(),
            };
            let bound = ring_bounds(&mesh.positions, &tangents, &mesh.triangles, &|| {});
            let mut tight = 0;
            for (i, (&d, &b)) in sk.distance.iter().zip(&bound).enumerate() {
                assert!(2.0 * d <= b, "{method} vertex {i}: 2d = {} > {b}", 2.0 * d);
                tight += usize::from(b < 6.0 * d);
            }
            // The bounded radius is within 3 times the radius for most vertices.
            assert!(
                tight > sk.distance.len() / 2,
                "{method}: {tight} tight bounds"
            );
        }
    }

    /// A repeated position (possible without welding) is never inserted in the
    /// tetrahedralization: it takes its twin's distance and is no fallback, in every method.
    #[test]
    fn a_duplicated_position_shares_its_twins_distance() {
        let mut mesh = shapes::cube_grid(1.0, 3);
        let mut normals = crate::mesh::vertex_normals(&mesh).unwrap();
        mesh.positions.push(mesh.positions[5]);
        normals.push(normals[5]);
        let none = |_: &str, _: f64| {};
        for method in Method::ALL {
            let params = SkeletonParams {
                method,
                ..SkeletonParams::default()
            };
            let sk = build(&mesh, &normals, &params, &none).unwrap();
            let last = mesh.positions.len() - 1;
            assert_eq!(sk.fallback, 0, "{method}");
            assert!(sk.distance[5] > 0.0, "{method}");
            assert_eq!(sk.distance[last], sk.distance[5], "{method}");
        }
    }

    /// The thickness of a vertex is measured either alongside the tetrahedralization
    /// (unbounded ray) or after it (a segment of length 2d): the skeleton must not depend on
    /// which, nor on how many vertices the overlap reached.
    #[test]
    fn thickness_measured_early_or_late_gives_the_same_skeleton() {
        // A long thin box, where the thickness clamp matters.
        let mut mesh = shapes::cube_grid(1.0, 6);
        for p in &mut mesh.positions {
            p.x *= 6.0;
            p.y *= 0.5;
        }
        let normals = crate::mesh::vertex_normals(&mesh).unwrap();
        let none = |_: &str, _: f64| {};
        for method in Method::ALL {
            let params = SkeletonParams {
                method,
                ..SkeletonParams::default()
            };
            let late = build_with(&mesh, &normals, &params, &none, Overlap::Nothing).unwrap();
            let early = build_with(&mesh, &normals, &params, &none, Overlap::Everything).unwrap();
            let real = build(&mesh, &normals, &params, &none).unwrap();
            assert_eq!(late.distance, early.distance, "{method}");
            assert_eq!(late.distance, real.distance, "{method}");
            assert_eq!(late.clamped, early.clamped, "{method}");
            // The shrinking ball already fits the local thickness; the others need clamping.
            if !method.is_ball() {
                assert!(late.clamped > 0, "{method}: the clamp was not exercised");
            }
        }
    }
}
