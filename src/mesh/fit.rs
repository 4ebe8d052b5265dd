//! The local surface fit: at each vertex, a surface fitted to its neighbours gives a normal
//! far more accurate than the angle-weighted one on an uneven fan, and the largest ball
//! tangent at the vertex that the surface around it allows (the fitted ball's start,
//! `skeleton`). Why this design, and what else was measured: `ARCHITECTURE.md`, skeleton.
//!
//! Two models of the surface, both `z = Σ cₖ tₖ(x, y, z)` in the frame of the rough normal
//! at `p` (scaled to unit mean distance of the points):
//! * the **height** `z = d x + e y + (a x² + b xy + c y² + cubic terms) σ`, with
//!   `σ = |q − p|² / (x² + y²)`, exact on any sphere in any frame (a point of a sphere
//!   tangent at `p` has `n·(q − p) = −|q − p|² / 2R`);
//! * the **quadric** `z = d x + e y + a x² + b xy + c y² + f xz + g yz + h z²`, an implicit
//!   quadric through `p`, exact on every ellipsoid (where a sphere's model misjudges the
//!   curvature at the tips and rim) but not on a torus.
//!
//! Over the 1-ring the height alone is fitted. Where it bends by more than [`FIT_BEND`]
//! across the 1-ring, the fit takes the 1- and 2-ring with Gaussian weights, fits both
//! models and keeps the quadric where its residual is under [`QUADRIC_RESIDUAL`] times the
//! height's. That wider fit describes the patch around `p`, not only the point: the ball
//! starts at the smallest one tangent at `p` through the fitted surface, sampled across the
//! points' reach ([`smallest_ball`]), which is where the surface bends away between
//! vertices (a thin rim an edge away) that the vertices alone would miss.

use super::edges::{target, third, HalfEdges};
use super::Mesh;
use glam::DVec3;
use rayon::prelude::*;

/// What a local fit of the surface says at each vertex ([`fit_surface`]).
pub struct SurfaceFit {
    /// Unit outward normals: the fitted surface's, or the rough one where the fit is not
    /// taken.
    pub normals: Vec<DVec3>,
    /// The **fitted radius**: the largest ball tangent at the vertex (centre on
    /// `−normal`) that the fitted surface allows. The radius of the largest principal
    /// curvature towards the inside (`1 / κ`), or less where the fit takes the 2-ring and
    /// the fitted surface bends in further away. Infinite where the surface does not bend
    /// inwards or the fit is not taken.
    pub fitted_radius: Vec<f64>,
    /// Whether the fit was taken: the vertex's fitted patch, its 1-ring, is then described
    /// by the normal and the fitted radius.
    pub fitted: Vec<bool>,
    /// The mesh's edges.
    rings: HalfEdges,
}

impl SurfaceFit {
    /// Whether `v` and `w` share an edge: `w` is on `v`'s 1-ring.
    pub fn adjacent(&self, v: u32, w: u32) -> bool {
        self.rings.count(v, w) > 0 || self.rings.count(w, v) > 0
    }

    /// The vertices of `v`'s 1-ring (one per edge from `v`).
    pub fn ring(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.rings.row(v).iter().map(|&e| target(e))
    }
}

/// Normals and fitted radii from a local fit of the surface around each vertex (the
/// module's doc says which fit where). Points more than 45° off the tangent plane are not
/// on the patch and take no part.
///
/// A plain polynomial height overestimates a circle's curvature by `1 / (1 + cos φ)` over
/// an arc `φ`, 7 % at 30° between vertices; the height's factor `σ` removes that. The
/// normal's error falls with the cube of the edge length (the 2-ring fit) whatever the
/// triangles around `p` look like, where the angle-weighted normal tilts by a few degrees
/// on an uneven fan (see `ARCHITECTURE.md`, skeleton). A vertex whose fit is
/// ill-conditioned, or turns its normal by more than [`FIT_MAX_TURN`] (a crease, a corner:
/// no smooth surface to fit), keeps its rough normal, no fitted radius and no patch.
pub fn fit_surface(mesh: &Mesh, rough: &[DVec3]) -> SurfaceFit {
    let pos = &mesh.positions;
    let half = HalfEdges::new(pos.len(), &mesh.triangles);
    let ring = |v: u32| half.row(v).iter().map(|&e| target(e));
    // Every face around `v` must face the fitted normal, so that `-n` points into the
    // object at `v` (the ray of the thickness clamp starts inside).
    let faced = |v: u32, n: DVec3| {
        let p = pos[v as usize];
        half.row(v).iter().all(|&e| {
            let (b, c) = (pos[target(e) as usize], pos[third(e) as usize]);
            (b - p).cross(c - p).dot(n) > 0.0
        })
    };
    let cos_max = FIT_MAX_TURN.to_radians().cos();
    let fits: Vec<(DVec3, f64, bool)> = (0..pos.len() as u32)
        .into_par_iter()
        .with_min_len(1024)
        .map_init(Vec::new, |near: &mut Vec<DVec3>, v| {
            let (p, r) = (pos[v as usize], rough[v as usize]);
            near.clear();
            near.extend(ring(v).map(|w| pos[w as usize]));
            let first = (near.len() >= FIT_MIN)
                .then(|| fit_ring(p, r, near))
                .flatten()
                .filter(|f| f.bend <= FIT_BEND);
            let fitted = first.or_else(|| {
                // The 1- and 2-ring, each vertex once (a short list: a linear search).
                for w in ring(v).flat_map(ring) {
                    let q = pos[w as usize];
                    if w != v && !near.contains(&q) {
                        near.push(q);
                    }
                }
                fit_wide(p, r, near)
            });
            match fitted {
                Some(f) if f.normal.dot(r) >= cos_max && faced(v, f.normal) => {
                    (f.normal, f.radius, true)
                }
                _ => (r, f64::INFINITY, false),
            }
        })
        .collect();
    let mut out = SurfaceFit {
        normals: Vec::with_capacity(fits.len()),
        fitted_radius: Vec::with_capacity(fits.len()),
        fitted: Vec::with_capacity(fits.len()),
        rings: half,
    };
    for (n, radius, fitted) in fits {
        out.normals.push(n);
        out.fitted_radius.push(radius);
        out.fitted.push(fitted);
    }
    out
}

/// Width of the 2-ring fit's weights, in mean distances of its points from the vertex.
/// Chosen by `puppet bench skeleton`: 0.45 and 0.7 leave the ellipsoid or the capsule
/// worse at the coarsest resolution (`docs/performance-log.md`).
pub const FIT_REACH: f64 = 0.55;

/// Fewer neighbours than this and the fit takes the 2-ring.
pub const FIT_MIN: usize = 6;

/// The 1-ring's fit is kept where the surface bends less than this across the mean
/// distance of the 1-ring (its largest principal curvature times that distance); where it
/// bends more, the fit takes the 2-ring and the cubic terms.
pub const FIT_BEND: f64 = 0.25;

/// A fitted normal further than this from the rough one (degrees) is not taken.
pub const FIT_MAX_TURN: f64 = 25.0;

/// With this many points or more the height is a cubic.
pub const CUBIC_MIN: usize = 12;

/// The 2-ring fit keeps the quadric where its weighted mean squared residual is under this
/// fraction of the height's. Chosen by `puppet bench skeleton`: at 1 (the better fit wins)
/// the coarse torus, which neither model describes exactly, takes the quadric at some
/// vertices and its 95th percentile goes from 2.8 to 4.7 %; 0.3, 0.1 and 0.01 give the
/// same table.
pub const QUADRIC_RESIDUAL: f64 = 0.3;

/// With this many points or more the 2-ring fit tries the quadric.
pub const QUADRIC_MIN: usize = 10;

/// The fitted surface is sampled in this many directions around the normal, at half and
/// all of the points' reach in each ([`smallest_ball`]).
const BALL_DIRECTIONS: usize = 16;

/// One vertex's fit.
#[derive(Clone, Copy, Debug)]
struct Fit {
    /// The fitted surface's unit normal at the vertex.
    normal: DVec3,
    /// The fitted radius ([`SurfaceFit::fitted_radius`]).
    radius: f64,
    /// Its largest principal curvature in absolute value times the mean distance of the
    /// points.
    bend: f64,
}

/// The frame of a fit: the rough normal `n` at `p`, two tangents, and the scale that makes
/// the mean distance of the points 1 (for conditioning).
struct Frame {
    p: DVec3,
    n: DVec3,
    u: DVec3,
    w: DVec3,
    scale: f64,
    /// `1 / width²` of the Gaussian weights, 0 for none.
    spread: f64,
}

impl Frame {
    fn new(p: DVec3, n: DVec3, points: &[DVec3], reach: f64) -> Option<Frame> {
        let sum: f64 = points.iter().map(|&q| q.distance(p)).sum();
        if points.len() < 5 || sum.is_nan() || sum <= 0.0 {
            return None;
        }
        let u = n.any_orthonormal_vector();
        Some(Frame {
            p,
            n,
            u,
            w: n.cross(u),
            scale: points.len() as f64 / sum,
            spread: if reach > 0.0 {
                1.0 / (reach * reach)
            } else {
                0.0
            },
        })
    }

    /// `q` in the frame.
    fn project(&self, q: DVec3) -> DVec3 {
        let d = (q - self.p) * self.scale;
        DVec3::new(d.dot(self.u), d.dot(self.w), d.dot(self.n))
    }

    /// `q` in the frame, and its weight; `None` more than 45° off the tangent plane.
    fn local(&self, q: DVec3) -> Option<(DVec3, f64)> {
        let l = self.project(q);
        let across = l.x * l.x + l.y * l.y;
        (l.z * l.z < across).then(|| (l, (-across * self.spread).exp()))
    }

    /// A unit vector of the frame in world coordinates.
    fn world(&self, l: DVec3) -> DVec3 {
        (self.u * l.x + self.w * l.y + self.n * l.z).normalize()
    }
}

/// The height's terms: `K` = 5 (a quadric) or 9 (a cubic), each but the slopes times `σ`.
fn height_terms<const K: usize>(l: DVec3) -> [f64; K] {
    let (x, y, z) = (l.x, l.y, l.z);
    let s = (x * x + y * y + z * z) / (x * x + y * y);
    let all = [
        x,
        y,
        s * x * x,
        s * x * y,
        s * y * y,
        s * x * x * x,
        s * x * x * y,
        s * x * y * y,
        s * y * y * y,
    ];
    std::array::from_fn(|k| all[k])
}

/// The implicit quadric's terms.
fn quadric_terms(l: DVec3) -> [f64; 8] {
    let (x, y, z) = (l.x, l.y, l.z);
    [x, y, x * x, x * y, y * y, x * z, y * z, z * z]
}

/// The coefficients of `z = Σ cₖ tₖ` fitted to `points` by weighted least squares (normal
/// equations solved by Cholesky; `None` when they are singular), and the weighted mean
/// squared residual.
fn solve<const K: usize>(
    frame: &Frame,
    points: &[DVec3],
    terms: impl Fn(DVec3) -> [f64; K],
) -> Option<([f64; K], f64)> {
    // The upper triangle of the normal equations' matrix, and their right-hand side.
    let (mut a, mut b) = ([[0.0f64; K]; K], [0.0f64; K]);
    for (l, weight) in points.iter().filter_map(|&q| frame.local(q)) {
        let t = terms(l);
        for i in 0..K {
            let wi = weight * t[i];
            b[i] += wi * l.z;
            for j in i..K {
                a[i][j] += wi * t[j];
            }
        }
    }
    // Cholesky, `a = Rᵀ R` with `R` upper triangular, in place.
    for i in 0..K {
        for j in i..K {
            let s = a[i][j] - (0..i).map(|k| a[k][i] * a[k][j]).sum::<f64>();
            if j == i {
                // Not positive definite (or NaN): singular.
                if s.is_nan() || s < 1e-9 {
                    return None;
                }
                a[i][i] = s.sqrt();
            } else {
                a[i][j] = s / a[i][i];
            }
        }
    }
    // `Rᵀ y = b`, then `R c = y`.
    for i in 0..K {
        let mut s = b[i];
        for k in 0..i {
            s -= a[k][i] * b[k];
        }
        b[i] = s / a[i][i];
    }
    for i in (0..K).rev() {
        let mut s = b[i];
        for k in i + 1..K {
            s -= a[i][k] * b[k];
        }
        b[i] = s / a[i][i];
    }
    let (mut sum, mut weights) = (0.0, 0.0);
    for (l, weight) in points.iter().filter_map(|&q| frame.local(q)) {
        let t = terms(l);
        let r = l.z - (0..K).map(|k| t[k] * b[k]).sum::<f64>();
        sum += weight * r * r;
        weights += weight;
    }
    Some((b, sum / weights))
}

/// Principal curvatures `(low, high)` of a 2×2 symmetric matrix `[[m11, m12], [m12, m22]]`.
fn eigenvalues(m11: f64, m12: f64, m22: f64) -> (f64, f64) {
    let half_trace = 0.5 * (m11 + m22);
    let root = (0.25 * (m11 - m22).powi(2) + m12 * m12).sqrt();
    (half_trace - root, half_trace + root)
}

/// The height's local unit normal and its principal curvatures towards the inside, the
/// quadratic terms taken as the second derivatives (exact to first order in the rough
/// normal's tilt).
fn height_shape(c: &[f64; 9]) -> (DVec3, f64, f64) {
    // The eigenvalues of `I⁻¹ II` of the graph `z(x, y)`.
    let (fx, fy) = (c[0], c[1]);
    let (fxx, fxy, fyy) = (2.0 * c[2], c[3], 2.0 * c[4]);
    let g = (1.0 + fx * fx + fy * fy).sqrt();
    let (e, f, h) = (1.0 + fx * fx, fx * fy, 1.0 + fy * fy);
    let det = e * h - f * f;
    let (l, m, nn) = (fxx / g, fxy / g, fyy / g);
    let (s11, s12) = ((h * l - f * m) / det, (h * m - f * nn) / det);
    let (s21, s22) = ((e * m - f * l) / det, (e * nn - f * m) / det);
    let half_trace = 0.5 * (s11 + s22);
    let root = (half_trace * half_trace - (s11 * s22 - s12 * s21))
        .max(0.0)
        .sqrt();
    // The height falls towards the inside: the most negative curvature bends inwards most.
    let (low, high) = (half_trace - root, half_trace + root);
    (DVec3::new(-fx, -fy, 1.0).normalize(), -high, -low)
}

/// The quadric's local unit normal and principal curvatures towards the inside: of the
/// level set `F = 0`, `F = z − Σ cₖ tₖ`, whose inside is `F < 0`.
fn quadric_shape(c: &[f64; 8]) -> (DVec3, f64, f64) {
    let grad = DVec3::new(-c[0], -c[1], 1.0);
    let length = grad.length();
    let normal = grad / length;
    // The Hessian of `F`, projected on the tangent plane, over `|∇F|`.
    let hessian = glam::DMat3::from_cols(
        DVec3::new(-2.0 * c[2], -c[3], -c[5]),
        DVec3::new(-c[3], -2.0 * c[4], -c[6]),
        DVec3::new(-c[5], -c[6], -2.0 * c[7]),
    );
    let t1 = normal.any_orthonormal_vector();
    let t2 = normal.cross(t1);
    let m = |a: DVec3, b: DVec3| a.dot(hessian * b) / length;
    let (low, high) = eigenvalues(m(t1, t1), m(t1, t2), m(t2, t2));
    (normal, low, high)
}

/// The height fitted to `points`: a cubic when there are enough points for one, else a
/// quadric (its cubic coefficients 0); and its residual ([`solve`]).
fn solve_height(frame: &Frame, points: &[DVec3]) -> Option<([f64; 9], f64)> {
    if points.len() >= CUBIC_MIN {
        solve(frame, points, height_terms::<9>)
    } else {
        let (c, residual) = solve(frame, points, height_terms::<5>)?;
        Some((
            std::array::from_fn(|k| c.get(k).copied().unwrap_or(0.0)),
            residual,
        ))
    }
}

/// The 1-ring's fit: the height, unweighted.
fn fit_ring(p: DVec3, n: DVec3, points: &[DVec3]) -> Option<Fit> {
    let frame = Frame::new(p, n, points, 0.0)?;
    finish(
        &frame,
        height_shape(&solve_height(&frame, points)?.0),
        f64::INFINITY,
    )
}

/// The 1- and 2-ring's fit, weighted: the height, or the quadric where it fits far better;
/// the radius no larger than the smallest ball through the fitted surface.
fn fit_wide(p: DVec3, n: DVec3, points: &[DVec3]) -> Option<Fit> {
    let frame = Frame::new(p, n, points, FIT_REACH)?;
    let height = solve_height(&frame, points);
    // Fewer points and the quadric's 8 terms fit them all, noise included.
    let quadric = (points.len() >= QUADRIC_MIN)
        .then(|| solve(&frame, points, quadric_terms))
        .flatten();
    let quadric_wins = match (&height, &quadric) {
        (Some((_, h)), Some((_, q))) => *q < QUADRIC_RESIDUAL * h,
        (None, Some(_)) => true,
        _ => false,
    };
    let (shape, ball) = if quadric_wins {
        let (c, _) = quadric?;
        let shape = quadric_shape(&c);
        // z = L + a x² + b xy + c y² + (f x + g y) z + h z².
        let quadratic = |x: f64, y: f64| {
            let rest = c[0] * x + c[1] * y + c[2] * x * x + c[3] * x * y + c[4] * y * y;
            (c[7], c[5] * x + c[6] * y - 1.0, rest)
        };
        (shape, smallest_ball(&frame, points, shape.0, quadratic))
    } else {
        let (c, _) = height?;
        let shape = height_shape(&c);
        // z = L + P σ with σ = 1 + z² / ρ²: L + P + (P / ρ²) z².
        let quadratic = |x: f64, y: f64| {
            let t = height_terms::<9>(DVec3::new(x, y, 0.0));
            let bend: f64 = c.iter().zip(t).skip(2).map(|(c, t)| c * t).sum();
            let slope = c[0] * x + c[1] * y;
            (bend / (x * x + y * y), -1.0, slope + bend)
        };
        (shape, smallest_ball(&frame, points, shape.0, quadratic))
    };
    finish(&frame, shape, ball)
}

/// The fit in world terms: the normal, and the radius from the larger inward curvature, no
/// larger than `ball` (in the frame's scale).
fn finish(frame: &Frame, (normal, low, high): (DVec3, f64, f64), ball: f64) -> Option<Fit> {
    let radius = if high > 0.0 {
        1.0 / high
    } else {
        f64::INFINITY
    }
    .min(ball);
    let out = Fit {
        normal: frame.world(normal),
        radius: radius / frame.scale,
        bend: low.abs().max(high.abs()),
    };
    (out.normal.is_finite() && out.radius > 0.0).then_some(out)
}

/// The smallest ball tangent at `p` (the frame's origin) along the local `normal` through
/// the fitted surface, sampled in [`BALL_DIRECTIONS`] directions at half and all of the
/// reach of the points within 45° of each (no farther: past the points the fit is an
/// extrapolation). Both models hold `z` on their right, as `A z² + (B + 1) z + C`:
/// `quadratic(x, y)` gives `(A, B, C)` of `A z² + B z + C = 0`, whose root nearest the
/// tangent plane is the surface. A sample without that root, or more than 45° off the
/// tangent plane, is left out.
fn smallest_ball(
    frame: &Frame,
    points: &[DVec3],
    normal: DVec3,
    quadratic: impl Fn(f64, f64) -> (f64, f64, f64),
) -> f64 {
    let mut reach = [0.0f64; BALL_DIRECTIONS];
    let directions: [(f64, f64); BALL_DIRECTIONS] = std::array::from_fn(|k| {
        let angle = std::f64::consts::TAU * k as f64 / BALL_DIRECTIONS as f64;
        (angle.cos(), angle.sin())
    });
    for &q in points {
        let l = frame.project(q);
        let within = (l.x * l.x + l.y * l.y).sqrt() * std::f64::consts::FRAC_1_SQRT_2;
        for (r, (cos, sin)) in reach.iter_mut().zip(directions) {
            let along = l.x * cos + l.y * sin;
            if along > within {
                *r = r.max(along);
            }
        }
    }
    let mut best = f64::INFINITY;
    for (&r, (cos, sin)) in reach.iter().zip(directions) {
        if r == 0.0 {
            continue;
        }
        for fraction in [0.5, 1.0] {
            let (x, y) = (cos * r * fraction, sin * r * fraction);
            let (a, b, c) = quadratic(x, y);
            // The root that tends to `−C / B` as `A` vanishes (`B` near −1).
            let root = (b * b - 4.0 * a * c).sqrt();
            let z = 2.0 * c / (root - b);
            let l = DVec3::new(x, y, z);
            let s = -2.0 * normal.dot(l);
            if root - b > 0.0 && z * z < x * x + y * y && s > 0.0 {
                best = best.min(l.length_squared() / s);
            }
        }
    }
    best
}
