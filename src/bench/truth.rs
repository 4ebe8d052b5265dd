//! Ground truth for the skeleton: analytic shapes with known medial radii, and the accuracy
//! report (`puppet bench --skeleton`, `docs/engine-benchmarks.md`, and the bounds asserted in tests).
//!
//! The medial radius at a surface point `p` with normal `n` is the radius of the largest
//! ball inside the object that touches `p`: its centre is `p − r n`. For a sphere it is the
//! radius, for a capsule and a torus the tube radius. For an ellipsoid it is
//! `r(p) = min(1/κ_max(p), min_q |q − p|² / (−2 n·(q − p)))` over surface points `q` with
//! `n·(q − p) < 0` (the ball through `p` and `q` tangent at `p`), found by dense sampling
//! plus local refinement.

use super::decimate;
use crate::mesh::{shapes, vertex_normals, Mesh};
use crate::skeleton::{build, Method, SkeletonParams};
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// An analytic test shape.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "shape", rename_all = "kebab-case")]
pub enum Shape {
    /// A sphere about the origin.
    Sphere {
        /// Its radius.
        radius: f64,
    },
    /// Semi-axes along x, y (the polar axis of the generator), z.
    Ellipsoid {
        /// Semi-axis along x.
        a: f64,
        /// Semi-axis along y.
        b: f64,
        /// Semi-axis along z.
        c: f64,
    },
    /// A cylinder with hemispherical caps along y.
    Capsule {
        /// Its radius.
        radius: f64,
        /// Half the length of the cylinder part.
        half: f64,
    },
    /// A torus about the y axis.
    Torus {
        /// Ring radius (centre to tube axis).
        major: f64,
        /// Tube radius.
        minor: f64,
    },
}

impl Shape {
    /// True medial radius at surface point `p`.
    pub fn medial_radius(&self, p: DVec3) -> f64 {
        match *self {
            Shape::Sphere { radius } => radius,
            Shape::Capsule { radius, .. } => radius,
            Shape::Torus { minor, .. } => minor,
            Shape::Ellipsoid { a, b, c } => ellipsoid_medial_radius(DVec3::new(a, b, c), p),
        }
    }

    /// Short name for tables.
    pub fn name(&self) -> String {
        match *self {
            Shape::Sphere { .. } => "sphere".into(),
            Shape::Ellipsoid { a, b, c } => format!("ellipsoid {a}:{b}:{c}"),
            Shape::Capsule { .. } => "capsule".into(),
            Shape::Torus { .. } => "torus".into(),
        }
    }
}

fn ellipsoid_point(axes: DVec3, theta: f64, phi: f64) -> DVec3 {
    DVec3::new(
        axes.x * theta.sin() * phi.cos(),
        axes.y * theta.cos(),
        axes.z * theta.sin() * phi.sin(),
    )
}

fn ellipsoid_medial_radius(axes: DVec3, p: DVec3) -> f64 {
    let inv2 = 1.0 / (axes * axes);
    let grad = p * inv2;
    let n = grad.normalize();
    // Local bound: 1 / largest normal curvature, kappa(t) = sum t_i^2 / a_i^2 / |grad|.
    let t1 = n.any_orthonormal_vector();
    let t2 = n.cross(t1);
    let h = |u: DVec3, v: DVec3| (u * v * inv2).element_sum() / grad.length();
    let (m11, m12, m22) = (h(t1, t1), h(t1, t2), h(t2, t2));
    let kmax = 0.5 * (m11 + m22) + (0.25 * (m11 - m22).powi(2) + m12 * m12).sqrt();
    // Samples very close to p lose all precision to cancellation; their limit (q -> p) is
    // the curvature bound 1/kmax, which is in the minimum anyway.
    let near = 1e-3 * axes.max_element();
    let f = |theta: f64, phi: f64| {
        let q = ellipsoid_point(axes, theta, phi);
        let d = q - p;
        let s = -2.0 * n.dot(d);
        if d.length() > near && s > 0.0 {
            d.length_squared() / s
        } else {
            f64::INFINITY
        }
    };
    // Coarse grid, then pattern search around the best few samples.
    let (nt, np) = (90, 180);
    let mut best: Vec<(f64, f64, f64)> = Vec::with_capacity(nt * np);
    for i in 0..nt {
        let theta = PI * (i as f64 + 0.5) / nt as f64;
        for j in 0..np {
            let phi = TAU * j as f64 / np as f64;
            best.push((f(theta, phi), theta, phi));
        }
    }
    best.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut r = 1.0 / kmax;
    for &(mut v, mut theta, mut phi) in best.iter().take(4) {
        let mut step = PI / nt as f64;
        while step > 1e-9 {
            let mut improved = false;
            for (d_theta, d_phi) in [(step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)] {
                let (t2, p2) = ((theta + d_theta).clamp(1e-12, PI - 1e-12), phi + d_phi);
                let v2 = f(t2, p2);
                if v2 < v {
                    (v, theta, phi) = (v2, t2, p2);
                    improved = true;
                }
            }
            if !improved {
                step *= 0.5;
            }
        }
        r = r.min(v);
    }
    r
}

/// One test case: a shape at a resolution.
pub struct Case {
    /// The shape, which knows the true medial radius.
    pub shape: Shape,
    /// A mesh whose vertices lie on it.
    pub mesh: Mesh,
    /// Human-readable resolution ("32x64", "ico 4", ...).
    pub resolution: String,
}

/// The standard cases: each shape at three resolutions (`levels` of them, 1..=3).
pub fn cases(levels: usize) -> Vec<Case> {
    let mut out = Vec::new();
    for k in 0..levels.clamp(1, 3) {
        let s = 1usize << k; // 1, 2, 4
        let (rings, segs) = (16 * s, 32 * s);
        out.push(Case {
            shape: Shape::Sphere { radius: 1.0 },
            mesh: shapes::uv_sphere(1.0, rings, segs),
            resolution: format!("uv {rings}x{segs}"),
        });
        out.push(Case {
            shape: Shape::Sphere { radius: 1.0 },
            mesh: shapes::icosphere(1.0, 3 + k),
            resolution: format!("ico {}", 3 + k),
        });
        out.push(Case {
            shape: Shape::Ellipsoid {
                a: 1.5,
                b: 1.0,
                c: 0.5,
            },
            mesh: shapes::ellipsoid(1.5, 1.0, 0.5, rings, segs),
            resolution: format!("uv {rings}x{segs}"),
        });
        out.push(Case {
            shape: Shape::Capsule {
                radius: 0.5,
                half: 1.0,
            },
            mesh: shapes::capsule(0.5, 1.0, 8 * s, 16 * s, segs),
            resolution: format!("{}x{segs}", 32 * s),
        });
        out.push(Case {
            shape: Shape::Torus {
                major: 1.0,
                minor: 0.35,
            },
            mesh: shapes::torus(1.0, 0.35, 32 * s, 12 * s),
            resolution: format!("{}x{}", 32 * s, 12 * s),
        });
        // Uneven meshes: every vertex exactly on the surface, the fans around them not.
        let ellipsoid = Shape::Ellipsoid {
            a: 1.5,
            b: 1.0,
            c: 0.5,
        };
        let thin = Shape::Capsule {
            radius: 0.3,
            half: 1.0,
        };
        out.push(Case {
            shape: thin,
            mesh: shapes::uneven_capsule(0.3, 1.0, 8 * s, 16 * s, 2 * segs),
            resolution: format!("alternating gaps {}x{}", 32 * s, 2 * segs),
        });
        out.push(Case {
            shape: thin,
            mesh: shapes::capsule(0.3, 1.0, 8 * s, 2, 2 * segs),
            resolution: format!("skinny {}x{}", 16 * s + 2, 2 * segs),
        });
        out.push(Case {
            shape: Shape::Sphere { radius: 1.0 },
            mesh: shapes::jittered_ellipsoid(DVec3::ONE, 3 + k, 0.3, 1 + k as u64),
            resolution: format!("jittered ico {}", 3 + k),
        });
        out.push(Case {
            shape: ellipsoid,
            mesh: shapes::jittered_ellipsoid(DVec3::new(1.5, 1.0, 0.5), 3 + k, 0.3, 11 + k as u64),
            resolution: format!("jittered ico {}", 3 + k),
        });
        let fine = shapes::icosphere(1.0, 4 + k);
        let target = fine.positions.len() / 4;
        out.push(Case {
            shape: Shape::Sphere { radius: 1.0 },
            mesh: decimate(&fine, target),
            resolution: format!("decimated ico {} to {target}", 4 + k),
        });
        let mut fine = fine;
        for p in &mut fine.positions {
            *p *= DVec3::new(1.5, 1.0, 0.5);
        }
        out.push(Case {
            shape: ellipsoid,
            mesh: decimate(&fine, target),
            resolution: format!("decimated ico {} to {target}", 4 + k),
        });
    }
    out
}

/// Accuracy of one method on one case.
#[derive(Clone, Debug, serde::Serialize)]
pub struct AccuracyRow {
    /// The shape's name.
    pub shape: String,
    /// The mesh's resolution.
    pub resolution: String,
    /// Its vertices.
    pub vertices: usize,
    /// The skeleton method.
    pub method: Method,
    /// Median of `|d_i − r_i| / r_i`.
    pub median_rel_error: f64,
    /// 95th percentile of the same.
    pub p95_rel_error: f64,
    /// Vertices that fell back to `d = 0`.
    pub fallback: usize,
    /// Vertices whose distance the thickness bound cut by more than 1 %.
    pub clamped: usize,
    /// Time to build the skeleton.
    pub seconds: f64,
}

/// Runs every method on every case.
pub fn accuracy(cases: &[Case], methods: &[Method], sliver_ratio: f64) -> Vec<AccuracyRow> {
    let mut rows = Vec::new();
    for case in cases {
        let truth: Vec<f64> = case
            .mesh
            .positions
            .par_iter()
            .map(|&p| case.shape.medial_radius(p))
            .collect();
        let Ok(normals) = vertex_normals(&case.mesh) else {
            continue;
        };
        for &method in methods {
            let params = SkeletonParams {
                method,
                sliver_ratio,
            };
            let t = std::time::Instant::now();
            let Ok(sk) = build(&case.mesh, &normals, &params, crate::progress::silent()) else {
                continue;
            };
            let seconds = t.elapsed().as_secs_f64();
            let errors = sk
                .distance
                .iter()
                .zip(&truth)
                .map(|(d, r)| (d - r).abs() / r)
                .collect();
            let (median_rel_error, p95_rel_error) = crate::stats::median_p95(errors);
            rows.push(AccuracyRow {
                shape: case.shape.name(),
                resolution: case.resolution.clone(),
                vertices: case.mesh.positions.len(),
                method,
                median_rel_error,
                p95_rel_error,
                fallback: sk.fallback,
                clamped: sk.clamped,
                seconds,
            });
        }
    }
    rows
}

/// The fitted ball of every vertex by its definition, brute force over all vertices (no
/// Delaunay edges; O(n²), for tests): from the fitted radius, lowered by every
/// vertex off the patch ([`crate::skeleton::Tangent::lower`]). What the default method computes
/// before the thickness clamp, up to [`crate::skeleton::SETTLE_SLACK`].
pub fn fitted_balls_by_brute_force(mesh: &Mesh, normals: &[DVec3]) -> Vec<f64> {
    let fit = crate::mesh::fit_surface(mesh, normals);
    let pts = &mesh.positions;
    crate::skeleton::Tangent::fitted(&fit)
        .par_iter()
        .enumerate()
        .map(|(i, t)| {
            let mut r = t.start;
            for (j, &q) in pts.iter().enumerate() {
                t.lower(&mut r, pts[i], q, || fit.adjacent(i as u32, j as u32));
            }
            r
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipsoid_truth_reduces_to_the_sphere() {
        let axes = DVec3::splat(2.0);
        for p in [
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
            DVec3::splat(2.0 / 3f64.sqrt()),
        ] {
            let r = ellipsoid_medial_radius(axes, p);
            assert!((r - 2.0).abs() < 1e-6, "r = {r}");
        }
    }

    #[test]
    fn ellipsoid_truth_at_the_tips_is_the_curvature_radius() {
        // At (a, 0, 0) the largest normal curvature is a / min(b, c)^2.
        let (a, b, c) = (1.5, 1.0, 0.5);
        let r = ellipsoid_medial_radius(DVec3::new(a, b, c), DVec3::new(a, 0.0, 0.0));
        assert!((r - c * c / a).abs() < 1e-6, "r = {r}");
        // At the end of the shortest axis the ball is limited by the opposite side or the
        // curvature c / a^2 ... whichever is smaller; it must not exceed c.
        let r = ellipsoid_medial_radius(DVec3::new(a, b, c), DVec3::new(0.0, 0.0, c));
        assert!(r <= c + 1e-9 && r > 0.0);
    }
}
