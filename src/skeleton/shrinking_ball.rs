//! The shrinking ball (Ma et al. 2012) taken from the tetrahedralization as it is built:
//! the largest ball tangent at `p` (centre on `−n`) with no vertex inside has radius
//! `min_q |q − p|² / (−2 n·(q − p))`. Its limiting vertex `q` and `p` lie on an empty
//! sphere, so `pq` is a Delaunay edge: the minimum over the Delaunay neighbours is exact.
//! Every edge is made by the insertion of its later end, so [`ShrinkingBalls`], an
//! [`EdgeHook`], takes the minimum over each new edge once, with no pass over the finished
//! tetrahedra (an edge destroyed later only offers a candidate no smaller than the
//! minimum).

use crate::delaunay::{Delaunay, EdgeHook};
use glam::DVec3;
use std::cell::UnsafeCell;
use std::time::Instant;

/// Radius of the ball tangent at `p` with its centre on `−n` (unit) and `q` on its sphere,
/// `|q − p|² / (−2 n·(q − p))`; infinite when `q` is not on the inner side of the tangent
/// plane. The shrinking ball of `p` is the minimum over the other points. The definition:
/// running minima use [`lower_tangent_radius`], which gives the same bits without the
/// division.
#[inline(always)]
pub fn tangent_radius(p: DVec3, n: DVec3, q: DVec3) -> f64 {
    let d = q - p;
    let s = -2.0 * n.dot(d);
    if s > 0.0 {
        d.length_squared() / s
    } else {
        f64::INFINITY
    }
}

/// `*x = x.min(tangent_radius(p, n, q))`, exactly, without the division (or the write)
/// when it cannot lower `x`, which is most of the time for a running minimum:
/// `|d|² ≥ x·s·(1 + 4ε)` (the product rounded) implies `|d|² > x·s`, so the rounded
/// quotient is at least `x`.
#[inline(always)]
pub fn lower_tangent_radius(x: &mut f64, p: DVec3, n: DVec3, q: DVec3) {
    let d = q - p;
    let s = -2.0 * n.dot(d);
    if s > 0.0 {
        let l = d.length_squared();
        if l < *x * s * (1.0 + 4.0 * f64::EPSILON) {
            let r = l / s;
            if r < *x {
                *x = r;
            }
        }
    }
}

/// The shrinking-ball radius of every point, being taken over the Delaunay edges as they
/// are made: the normals and radii in insertion order (internal ids).
pub(super) struct ShrinkingBalls {
    normals: Vec<DVec3>,
    radius: Radii,
}

/// Radii the two workers of a parallel phase lower concurrently, each only its own side's
/// (the [`EdgeHook`] contract).
struct Radii(Box<[UnsafeCell<f64>]>);

// SAFETY: concurrent calls of `ShrinkingBalls::edge` never touch the same entry (the
// `EdgeHook` contract: the two workers never offer edges with a vertex in common), and
// nothing reads the radii until the tetrahedralization is done.
unsafe impl Sync for Radii {}

impl ShrinkingBalls {
    /// No ball yet for the points whose input indices are `order`, with unit `normals` in
    /// input order.
    pub fn new(normals: &[DVec3], order: &[u32]) -> Self {
        ShrinkingBalls {
            normals: order.iter().map(|&i| normals[i as usize]).collect(),
            radius: Radii(
                order
                    .iter()
                    .map(|_| UnsafeCell::new(f64::INFINITY))
                    .collect(),
            ),
        }
    }

    /// The radii in insertion order: infinite for a point with no other on the inner side
    /// of its tangent plane, and for a duplicate (never inserted).
    pub fn into_radii(self) -> Vec<f64> {
        self.radius
            .0
            .into_vec()
            .into_iter()
            .map(UnsafeCell::into_inner)
            .collect()
    }
}

impl EdgeHook for ShrinkingBalls {
    /// Offers the Delaunay edge `ab` to the balls of `a` and `b` ([`tangent_radius`], which
    /// rounds alike whichever end comes first).
    #[inline(always)]
    unsafe fn edge(&self, pts: &[DVec3], a: u32, b: u32) {
        for (v, w) in [(a as usize, b as usize), (b as usize, a as usize)] {
            // SAFETY: no other thread touches the radius of `v` meanwhile (the contract).
            let r = unsafe { &mut *self.radius.0[v].get() };
            lower_tangent_radius(r, pts[v], self.normals[v], pts[w]);
        }
    }
}

/// Stage 3 for [`Method::ShrinkingBall`] (no stage 2): the tetrahedralization took the
/// minimum over the Delaunay edges as it made them ([`ShrinkingBalls`]),
/// `ball` in insertion order; mapped back to input order here. Returns the distances, the
/// fallback count, 0 circumcentres used and the number of tetrahedra.
pub(super) fn ball_distances(
    delaunay: &Delaunay,
    ball: &[f64],
    seconds: &mut Vec<(&'static str, f64)>,
) -> (Vec<f64>, usize, usize, usize) {
    let t = Instant::now();
    let (_, input) = delaunay.insertion_order();
    // Every input point has an internal id; duplicates (never inserted) take their
    // vertex's distance in the caller.
    let mut distance = vec![0.0; input.len()];
    let mut fallback = 0;
    for (&i, &b) in input.iter().zip(ball) {
        if b < f64::INFINITY {
            distance[i as usize] = b;
        } else if delaunay.duplicate_of(i as usize).is_none() {
            fallback += 1;
        }
    }
    seconds.push(("distance", t.elapsed().as_secs_f64()));
    (distance, fallback, 0, delaunay.finite_tet_count())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::delaunay::Delaunay;
    use crate::geom::hilbert::SplitMix;
    use crate::mesh::shapes;

    /// Points on a unit sphere and eight far corners: cavities with many boundary vertices.
    fn sphere_and_far_corners() -> Vec<DVec3> {
        let mut rng = SplitMix(5);
        let mut u = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let mut pts: Vec<DVec3> = (0..1000)
            .map(|_| (DVec3::new(u(), u(), u()) - DVec3::splat(0.5)).normalize())
            .collect();
        for x in [-1e3, 1e3] {
            for y in [-1e3, 1e3] {
                for z in [-1e3, 1e3] {
                    pts.push(DVec3::new(x, y, z));
                }
            }
        }
        pts
    }

    /// The shrinking balls taken over the edges as they are made (serially, and in parallel
    /// phases from early on) are those of the definition, a
    /// minimum over all points (brute force; equal up to rounding near ties, never smaller),
    /// and do not depend on the thread count. On bumpy, cospherical and coplanar inputs, and
    /// one with big cavities.
    #[test]
    fn tangent_balls_are_the_minimum_over_all_points() {
        let mut bumpy = shapes::icosphere(1.0, 4).positions;
        let mut rng = SplitMix(21);
        for p in &mut bumpy {
            *p *= 1.0 + 0.05 * ((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64);
        }
        let inputs = [
            ("bumpy sphere", bumpy),
            ("uv sphere", shapes::uv_sphere(1.0, 24, 48).positions),
            ("cube grid", shapes::cube_grid(2.0, 12).positions),
            // Cavities with LINK_MAX boundary vertices or more.
            ("far corners", sphere_and_far_corners()),
        ];
        for (name, pts) in inputs {
            // Any unit vectors will do; these point roughly outwards.
            let normals: Vec<DVec3> = pts
                .iter()
                .map(|p| (*p + DVec3::new(0.1, -0.2, 0.05)).normalize())
                .collect();
            let brute = brute_balls(&pts, &normals);
            let build = |first: usize, threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| {
                        Delaunay::with_phases_from(&pts, &|| false, first, |order| {
                            ShrinkingBalls::new(&normals, order)
                        })
                    })
                    .map(|(delaunay, balls)| (delaunay, balls.into_radii()))
                    .unwrap()
            };
            let serial = build(pts.len(), 1);
            let one = build(40, 1);
            let two = build(40, 2);
            assert_eq!(one.1, two.1, "{name}");
            for built in [&serial, &two] {
                assert_balls(built, &brute, name);
            }
        }
        // Four points: every edge is made by the first tetrahedron, none by an insertion.
        let pts = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        // The first with no point on its inner side.
        let normals = [DVec3::ONE.normalize(), DVec3::X, DVec3::Y, DVec3::Z];
        let built = Delaunay::with_edge_hook(&pts, &|_| {}, &|| false, |order| {
            ShrinkingBalls::new(&normals, order)
        })
        .map(|(delaunay, balls)| (delaunay, balls.into_radii()))
        .unwrap();
        let brute = brute_balls(&pts, &normals);
        assert_eq!(brute, [f64::INFINITY, 0.5, 0.5, 0.5]);
        assert_balls(&built, &brute, "tetrahedron");
    }

    /// The shrinking ball's definition: a minimum over all points.
    fn brute_balls(pts: &[DVec3], normals: &[DVec3]) -> Vec<f64> {
        pts.iter()
            .zip(normals)
            .map(|(&p, &n)| {
                pts.iter()
                    .map(|&q| (q - p, -2.0 * n.dot(q - p)))
                    .filter(|&(_, s)| s > 0.0)
                    .map(|(d, s)| d.length_squared() / s)
                    .fold(f64::INFINITY, f64::min)
            })
            .collect()
    }

    /// The balls (insertion order) are `brute`'s (input order) up to rounding near ties.
    fn assert_balls((delaunay, ball): &(Delaunay, Vec<f64>), brute: &[f64], name: &str) {
        let (_, input) = delaunay.insertion_order();
        for (&i, &r) in input.iter().zip(ball) {
            let b = brute[i as usize];
            assert!(
                r >= b && r <= b * (1.0 + 1e-12),
                "{name}: point {i}: {r} against {b}"
            );
        }
    }

    /// The running minimum without the division is the running minimum with it, exactly: on
    /// random offers and on the boundary cases of its shortcut (`x` the offered radius itself
    /// and its neighbouring floats, 0, ∞, offers on the outer side).
    #[test]
    fn lowering_a_tangent_radius_is_exact() {
        let mut rng = SplitMix(21);
        let mut u = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let mut checked = 0;
        for i in 0..200_000 {
            let scale = 10f64.powi(i % 9 - 4);
            let p = DVec3::new(u(), u(), u()) * scale;
            let n = DVec3::new(u(), u(), u()).normalize();
            let q = p + DVec3::new(u(), u(), u()) * scale * 0.1;
            let r = tangent_radius(p, n, q);
            let near = [
                r,
                r.next_up(),
                r.next_down(),
                r * (1.0 + 3e-16),
                r * (1.0 - 3e-16),
            ];
            let far = [0.0, f64::INFINITY, scale * u().abs(), near[i as usize % 5]];
            for x in far {
                let mut lowered = x;
                lower_tangent_radius(&mut lowered, p, n, q);
                assert_eq!(lowered.to_bits(), x.min(r).to_bits(), "{p} {n} {q} x = {x}");
                checked += usize::from(r.is_finite());
            }
        }
        assert!(checked > 300_000, "{checked}");
    }
}
