//! Angle-weighted vertex normals (Thürmer & Wüthrich): each face contributes its unit normal
//! weighted by the corner angle at the vertex, so the result does not depend on how a flat
//! region happens to be triangulated.
//!
//! Each thread owns a range of vertices and goes through all faces in order, adding the
//! corners at its own vertices: the sums are those of one pass face by face, to the bit,
//! whatever the number of threads.

use super::edges::{target, third, HalfEdges};
use super::{Mesh, MeshError};
use glam::DVec3;
use rayon::prelude::*;

/// Unit outward normal per vertex.
///
/// Zero-area faces contribute nothing. A vertex whose faces all have zero area falls back to
/// the sum of its faces' unnormalised normals.
///
/// # Errors
/// [`MeshError::Degenerate`] when a vertex has no defined normal at all.
pub fn vertex_normals(mesh: &Mesh) -> Result<Vec<DVec3>, MeshError> {
    let n = mesh.positions.len();
    let threads = if mesh.triangles.len() < 50_000 {
        1
    } else {
        rayon::current_num_threads().clamp(1, 16)
    };
    let mut normals = vec![DVec3::ZERO; n];
    let mut pieces = Vec::with_capacity(threads);
    let mut rest = &mut normals[..];
    for k in 0..threads {
        let (lo, hi) = ((n * k / threads) as u32, (n * (k + 1) / threads) as u32);
        let (piece, tail) = rest.split_at_mut((hi - lo) as usize);
        pieces.push((lo, hi, piece));
        rest = tail;
    }
    let missing: Option<usize> = pieces
        .into_par_iter()
        .map(|(lo, hi, out)| normals_of_range(mesh, lo, hi, out))
        .reduce(
            || None,
            |a, b| match (a, b) {
                (Some(x), Some(y)) => Some(x.min(y)),
                (x, y) => x.or(y),
            },
        );
    match missing {
        Some(i) => Err(MeshError::Degenerate(format!(
            "vertex {} has no defined normal (its faces cancel out or have no area)",
            i + 1
        ))),
        None => Ok(normals),
    }
}

/// The normals of vertices `lo..hi` into `out`; the first vertex without one, if any.
fn normals_of_range(mesh: &Mesh, lo: u32, hi: u32, out: &mut [DVec3]) -> Option<usize> {
    let len = (hi - lo) as usize;
    let mut acc = vec![DVec3::ZERO; len];
    let mut fallback = vec![DVec3::ZERO; len];
    let mine = |v: u32| v >= lo && v < hi;
    for t in &mesh.triangles {
        if !t.iter().any(|&v| mine(v)) {
            continue;
        }
        let p = t.map(|i| mesh.positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let length = n.length();
        for k in 0..3 {
            if mine(t[k]) {
                fallback[(t[k] - lo) as usize] += n;
            }
        }
        if length.is_nan() || length <= 0.0 {
            continue;
        }
        let unit = n / length;
        for k in 0..3 {
            if !mine(t[k]) {
                continue;
            }
            let e1 = p[(k + 1) % 3] - p[k];
            let e2 = p[(k + 2) % 3] - p[k];
            // atan2 of |cross| and dot is accurate for tiny and near-straight angles.
            let angle = e1.cross(e2).length().atan2(e1.dot(e2));
            acc[(t[k] - lo) as usize] += angle * unit;
        }
    }
    let mut missing = None;
    for (i, slot) in out.iter_mut().enumerate() {
        match acc[i]
            .try_normalize()
            .or_else(|| fallback[i].try_normalize())
        {
            Some(n) => *slot = n,
            None => {
                missing.get_or_insert(lo as usize + i);
            }
        }
    }
    missing
}

/// What a local fit of the surface says at each vertex ([`fit_surface`]).
pub struct SurfaceFit {
    /// Unit outward normals: the fitted height's, or the rough one where the fit is not
    /// taken.
    pub normals: Vec<DVec3>,
    /// Radius of the largest principal curvature towards the inside (`1 / κ`): the largest
    /// ball tangent at the vertex that the surface around it allows. Infinite where the
    /// surface does not bend inwards or the fit is not taken.
    pub curvature_radius: Vec<f64>,
    /// Whether the fit was taken: the vertex's fitted patch, its 1-ring, is then described
    /// by the normal and the curvature.
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

/// Normals and curvature from a local height fit. In the frame of the `rough` normal at
/// `p`, the height `z = d x + e y + (a x² + b xy + c y²) σ` (`σ = |q − p|² / (x² + y²)`) is
/// fitted to the 1-ring by least squares; where it bends by more than `FIT_BEND` across
/// the 1-ring, or the 1-ring is too small, the fit takes the 1- and 2-ring with the four
/// cubic terms (times `σ` too), weighted by `exp(−(ρ/w)²)` (`ρ` the distance across the
/// normal, `w` `FIT_REACH` times the mean distance of the points). Points more than 45°
/// off the tangent plane are not on the patch and take no part.
///
/// The factor `σ` makes the model exact on any sphere in any frame: a point `q` of a sphere
/// of radius `R` tangent at `p` satisfies `n·(q − p) = −|q − p|² / 2R`. A plain polynomial
/// height overestimates a circle's curvature by `1 / (1 + cos φ)` over an arc `φ`, 7 % at
/// 30° between vertices. The normal's error falls with the cube of the edge length (the
/// 2-ring fit) whatever the triangles around `p` look like, where the angle-weighted normal
/// tilts by a few degrees on an uneven fan (see `ARCHITECTURE.md`, skeleton). A vertex
/// whose fit is ill-conditioned, or turns its normal by more than `FIT_MAX_TURN` (a
/// crease, a corner: no smooth surface to fit), keeps its rough normal, no curvature and
/// no patch.
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
                .then(|| fit(p, r, near, 0.0))
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
                fit(p, r, near, FIT_REACH)
            });
            match fitted {
                Some(f) if f.normal.dot(r) >= cos_max && faced(v, f.normal) => {
                    let radius = if f.curvature > 0.0 {
                        1.0 / f.curvature
                    } else {
                        f64::INFINITY
                    };
                    (f.normal, radius, true)
                }
                _ => (r, f64::INFINITY, false),
            }
        })
        .collect();
    let mut out = SurfaceFit {
        normals: Vec::with_capacity(fits.len()),
        curvature_radius: Vec::with_capacity(fits.len()),
        fitted: Vec::with_capacity(fits.len()),
        rings: half,
    };
    for (n, radius, fitted) in fits {
        out.normals.push(n);
        out.curvature_radius.push(radius);
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

/// With this many points or more the fit is a cubic.
pub const CUBIC_MIN: usize = 12;

/// One vertex's fit.
#[derive(Clone, Copy, Debug)]
struct Fit {
    /// The height's unit normal at the vertex.
    normal: DVec3,
    /// Its largest principal curvature towards the inside (negative: none).
    curvature: f64,
    /// Its largest principal curvature in absolute value times the mean distance of the
    /// points.
    bend: f64,
}

/// The height through `p` fitted to `points` in the frame of `n` ([`fit_surface`]):
/// weighted when `reach > 0`, a quadric, or a cubic when there are enough points for one.
fn fit(p: DVec3, n: DVec3, points: &[DVec3], reach: f64) -> Option<Fit> {
    // Scaled to unit mean distance, for conditioning.
    let sum: f64 = points.iter().map(|&q| q.distance(p)).sum();
    if points.len() < 5 || sum.is_nan() || sum <= 0.0 {
        return None;
    }
    let scale = points.len() as f64 / sum;
    if points.len() >= CUBIC_MIN {
        fit_terms::<9>(p, n, points, scale, reach)
    } else {
        fit_terms::<5>(p, n, points, scale, reach)
    }
}

/// [`fit`] with the first `K` terms of the height (5: a quadric, 9: a cubic): weighted
/// normal equations solved by Cholesky (`None` when they are singular).
#[inline(always)]
fn fit_terms<const K: usize>(
    p: DVec3,
    n: DVec3,
    points: &[DVec3],
    scale: f64,
    reach: f64,
) -> Option<Fit> {
    let u = n.any_orthonormal_vector();
    let w = n.cross(u);
    let spread = if reach > 0.0 {
        1.0 / (reach * reach)
    } else {
        0.0
    };
    // The upper triangle of the normal equations' matrix, and their right-hand side.
    let (mut a, mut b) = ([[0.0f64; K]; K], [0.0f64; K]);
    for &q in points {
        let d = (q - p) * scale;
        let (x, y, z) = (d.dot(u), d.dot(w), d.dot(n));
        let across = x * x + y * y;
        // More than 45° off the tangent plane: not on the patch.
        if z * z >= across {
            continue;
        }
        let weight = (-across * spread).exp();
        let sphere = (across + z * z) / across;
        let terms = [
            x,
            y,
            sphere * x * x,
            sphere * x * y,
            sphere * y * y,
            sphere * x * x * x,
            sphere * x * x * y,
            sphere * x * y * y,
            sphere * y * y * y,
        ];
        for i in 0..K {
            let wi = weight * terms[i];
            b[i] += wi * z;
            for j in i..K {
                a[i][j] += wi * terms[j];
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
    // `Rᵀ y = b`, then `R s = y`.
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
    let normal = (n - u * b[0] - w * b[1]).normalize();
    // Principal curvatures of the graph `z(x, y)` at `p` (the eigenvalues of `I⁻¹ II`),
    // taking the quadratic terms as its second derivatives: exact to first order in the
    // rough normal's tilt.
    let (fx, fy) = (b[0], b[1]);
    let (fxx, fxy, fyy) = (2.0 * b[2], b[3], 2.0 * b[4]);
    let g = (1.0 + fx * fx + fy * fy).sqrt();
    let (e, f, h) = (1.0 + fx * fx, fx * fy, 1.0 + fy * fy);
    let det = e * h - f * f;
    let (l, m, nn) = (fxx / g, fxy / g, fyy / g);
    let (s11, s12) = ((h * l - f * m) / det, (h * m - f * nn) / det);
    let (s21, s22) = ((e * m - f * l) / det, (e * nn - f * m) / det);
    let (half_trace, det_s) = (0.5 * (s11 + s22), s11 * s22 - s12 * s21);
    let root = (half_trace * half_trace - det_s).max(0.0).sqrt();
    // The height falls towards the inside: the most negative curvature bends inwards most.
    let (low, high) = (half_trace - root, half_trace + root);
    let out = Fit {
        normal,
        curvature: -low * scale,
        bend: low.abs().max(high.abs()),
    };
    (normal.is_finite() && out.curvature.is_finite()).then_some(out)
}
