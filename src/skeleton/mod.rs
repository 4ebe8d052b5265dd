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
//!    against the mesh with the exact ray-parity oracle ([`crate::geom::inside`]), not the
//!    paper's local face-normal check, which misclassifies in concave regions.
//! 3. **Distance** per vertex from the inside Voronoi vertices of its cell: [`Method::Mean`]
//!    is the paper (their mean distance), [`Method::Pole`] the inner pole (the farthest one;
//!    Amenta et al.). A vertex with none gets `d = 0` (`sp = p`) and is counted.
//! 4. **Clamp** to the local thickness: a ray from `p_i` along `−n_i` first leaves the object
//!    at distance `t_i`; a ball tangent at `p_i` with its centre on that ray fits only if its
//!    diameter is at most `t_i`, so `d_i ≤ t_i / 2` bounds the true medial radius and keeps
//!    `sp_i` inside the object.

pub mod cache;
pub mod truth;

use crate::delaunay::{Delaunay, DelaunayError};
use crate::geom::bvh::Bvh;
use crate::geom::inside::InsideTest;
use crate::mesh::Mesh;
use crate::progress::Progress;
use glam::DVec3;
use rayon::prelude::*;
use std::time::Instant;

/// How the skeletal distance `d_i` is taken from the inside Voronoi vertices of cell `i`.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
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
    /// Delaunay neighbours of `p` is exact, no kd-tree needed. The default (best worst case
    /// in the accuracy table of `BENCHMARKS.md`).
    #[default]
    ShrinkingBall,
}

impl Method {
    /// All methods, for reports.
    pub const ALL: [Method; 3] = [Method::Mean, Method::Pole, Method::ShrinkingBall];

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Method::Mean => "mean",
            Method::Pole => "pole",
            Method::ShrinkingBall => "shrinking-ball",
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!("unknown skeleton method '{s}' (expected mean, pole or shrinking-ball)")
            })
    }
}

/// Skeleton parameters.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SkeletonParams {
    /// Distance method. Default: [`Method::ShrinkingBall`], chosen by the accuracy table in
    /// `BENCHMARKS.md`.
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
    /// Vertices without any inside Voronoi vertex (`sp_i = p_i`).
    pub fallback: usize,
    /// Vertices whose distance was limited by the local thickness by more than 1 %.
    pub clamped: usize,
    /// Finite tetrahedra of the Delaunay tetrahedralization.
    pub tetrahedra: usize,
    /// Circumcentres used (inside, not slivers).
    pub inside_voronoi_vertices: usize,
    /// Seconds per stage, in order.
    pub seconds: Vec<(&'static str, f64)>,
}

/// Why no skeleton could be built.
#[derive(Debug, thiserror::Error)]
pub enum SkeletonError {
    #[error("tetrahedralization failed: {0}")]
    Delaunay(#[from] DelaunayError),
    #[error("{0} normals for {1} vertices")]
    Normals(usize, usize),
}

/// Builds the skeleton of a validated mesh with unit outward `normals`.
pub fn build(
    mesh: &Mesh,
    normals: &[DVec3],
    params: &SkeletonParams,
    progress: Progress,
) -> Result<Skeleton, SkeletonError> {
    let n = mesh.positions.len();
    if normals.len() != n {
        return Err(SkeletonError::Normals(normals.len(), n));
    }
    let mut seconds = Vec::new();
    let clock = Instant::now();

    // 1. Tetrahedralize (the oracle and the BVH are built on the other core meanwhile).
    progress("tetrahedralize", 0.0);
    let ((dt, t_dt), ((inside, bvh), t_aux)) = rayon::join(
        || {
            let t = Instant::now();
            let dt = Delaunay::with_progress(&mesh.positions, &|f| progress("tetrahedralize", f));
            (dt, t.elapsed().as_secs_f64())
        },
        || {
            let t = Instant::now();
            let r = rayon::join(
                || InsideTest::new(mesh),
                || Bvh::new(&mesh.positions, &mesh.triangles),
            );
            (r, t.elapsed().as_secs_f64())
        },
    );
    let dt = dt?;
    seconds.push(("tetrahedralize", t_dt));
    seconds.push(("inside-oracle+bvh (parallel)", t_aux));

    // 2. Classify circumcentres: the circumradius if inside (negated for slivers), NaN if
    // outside or undefined.
    let t = Instant::now();
    progress("voronoi", 0.0);
    let pts = &mesh.positions;
    let tets = dt.finite_tets();
    let sliver = params.sliver_ratio;
    let radius: Vec<f64> = tets
        .par_iter()
        .map(|tv| {
            let [a, b, c, d] = tv.map(|v| pts[v as usize]);
            let (u, v, w) = (b - a, c - a, d - a);
            let vol6 = u.dot(v.cross(w)).abs();
            let lmax2 = u
                .length_squared()
                .max(v.length_squared())
                .max(w.length_squared())
                .max((c - b).length_squared())
                .max((d - b).length_squared())
                .max((d - c).length_squared());
            let sign = if vol6 < sliver * lmax2 * lmax2.sqrt() {
                -1.0
            } else {
                1.0
            };
            match crate::geom::predicates::circumcenter(a, b, c, d) {
                Some(cc) if inside.contains(cc) => sign * (cc - a).length(),
                _ => f64::NAN,
            }
        })
        .collect();
    seconds.push(("voronoi", t.elapsed().as_secs_f64()));

    // 3. Per-vertex distance.
    let t = Instant::now();
    let mut acc = vec![Acc::default(); n];
    let mut sliver_acc = vec![Acc::default(); n];
    let mut used = 0;
    for (tv, &r) in tets.iter().zip(&radius) {
        if r.is_nan() {
            continue;
        }
        let target = if r > 0.0 {
            used += 1;
            &mut acc
        } else {
            &mut sliver_acc
        };
        for &v in tv {
            target[v as usize].add(r.abs());
        }
    }
    for i in 0..n {
        if acc[i].count == 0 {
            acc[i] = sliver_acc[i];
        }
    }
    if params.method == Method::ShrinkingBall {
        shrinking_ball(pts, normals, &tets, &mut acc);
    }
    // Duplicated positions (only possible without welding) share their vertex's cell.
    for i in 0..n {
        if let Some(v) = dt.duplicate_of(i) {
            acc[i] = acc[v as usize];
        }
    }
    let mut distance: Vec<f64> = acc
        .iter()
        .map(|a| match (a.count, params.method) {
            (0, _) => 0.0,
            (c, Method::Mean) => a.sum / c as f64,
            (_, Method::Pole) => a.max,
            (_, Method::ShrinkingBall) => a.ball.min(a.max),
        })
        .collect();
    let fallback = acc.iter().filter(|a| a.count == 0).count();
    seconds.push(("distance", t.elapsed().as_secs_f64()));

    // 4. Clamp to half the thickness along -n.
    let t = Instant::now();
    progress("thickness", 0.0);
    let t_min = 1e-9 * mesh.diagonal();
    let clamped_flags: Vec<bool> = distance
        .par_iter_mut()
        .enumerate()
        .map(|(i, d)| {
            if *d == 0.0 {
                return false;
            }
            let vi = i as u32;
            // Only a hit closer than 2d can clamp: a segment query, pruned to the local scale.
            let reach = 2.0 * *d;
            let hit = bvh.cast_within(pts[i], -normals[i], t_min, reach, |tri| tri.contains(&vi));
            match hit {
                Some(h) if h.t * 0.5 < *d => {
                    // Count only real corrections, not rounding-level ones (a sphere's
                    // centre is at exactly half the thickness).
                    let significant = h.t * 0.5 < *d * 0.99;
                    *d = h.t * 0.5;
                    significant
                }
                _ => false,
            }
        })
        .collect();
    let clamped = clamped_flags.iter().filter(|&&c| c).count();
    seconds.push(("thickness", t.elapsed().as_secs_f64()));

    let points = pts
        .iter()
        .zip(normals)
        .zip(&distance)
        .map(|((p, nrm), d)| *p - *d * *nrm)
        .collect();
    seconds.push(("total", clock.elapsed().as_secs_f64()));
    progress("done", 1.0);
    Ok(Skeleton {
        distance,
        points,
        fallback,
        clamped,
        tetrahedra: tets.len(),
        inside_voronoi_vertices: used,
        seconds,
    })
}

/// Per-vertex accumulator of inside Voronoi vertices.
#[derive(Clone, Copy, Debug)]
struct Acc {
    sum: f64,
    max: f64,
    count: u32,
    ball: f64,
}

impl Default for Acc {
    fn default() -> Self {
        Acc {
            sum: 0.0,
            max: 0.0,
            count: 0,
            ball: f64::INFINITY,
        }
    }
}

impl Acc {
    #[inline]
    fn add(&mut self, r: f64) {
        self.sum += r;
        self.max = self.max.max(r);
        self.count += 1;
    }
}

/// Shrinking-ball radius per vertex over its Delaunay edges (see [`Method::ShrinkingBall`]).
/// The pole distance stays an upper bound (`min` with it in the caller): the tangent ball can
/// never be larger than the largest empty ball through `p`.
fn shrinking_ball(pts: &[DVec3], normals: &[DVec3], tets: &[[u32; 4]], acc: &mut [Acc]) {
    const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
    for tv in tets {
        for (i, j) in EDGES {
            let (a, b) = (tv[i] as usize, tv[j] as usize);
            let d = pts[b] - pts[a];
            let len2 = d.length_squared();
            let sa = -2.0 * normals[a].dot(d);
            if sa > 0.0 {
                let r = len2 / sa;
                if r < acc[a].ball {
                    acc[a].ball = r;
                }
            }
            let sb = 2.0 * normals[b].dot(d);
            if sb > 0.0 {
                let r = len2 / sb;
                if r < acc[b].ball {
                    acc[b].ball = r;
                }
            }
        }
    }
}
