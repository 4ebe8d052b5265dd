//! How the skeletal distance is taken ([`Method`]) and the skeleton's parameters
//! ([`SkeletonParams`]).

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
