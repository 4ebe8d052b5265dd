//! The shrinking ball (Ma et al. 2012) taken from the tetrahedralization as it is built:
//! the largest ball tangent at `p` (centre on `−n`) with no vertex inside has radius
//! `min_q |q − p|² / (−2 n·(q − p))`. Its limiting vertex `q` and `p` lie on an empty
//! sphere, so `pq` is a Delaunay edge: the minimum over the Delaunay neighbours is exact.
//! Every edge is made by the insertion of its later end, so [`ShrinkingBalls`], an
//! [`EdgeHook`], takes the minimum over each new edge once, with no pass over the finished
//! tetrahedra (an edge destroyed later only offers a candidate no smaller than the
//! minimum).
//!
//! The fitted ball ([`Tangent`]) starts at the fitted radius and is not shrunk
//! by its patch (the 1-ring neighbours within 45° of the tangent plane). Its limiting
//! vertex's sphere may then hold a patch vertex, so `pq` need not be a Delaunay edge: the
//! minimum over the Delaunay neighbours is an upper bound, exact wherever the limiting
//! sphere is empty (see `ARCHITECTURE.md`), and the thickness clamp bounds it anyway.

use crate::delaunay::{Delaunay, EdgeHook, StarScratch};
use crate::mesh::SurfaceFit;
use glam::DVec3;
use rayon::prelude::*;
use std::cell::UnsafeCell;
use std::time::Instant;

/// Radius of the ball tangent at `p` with its centre on `−n` (unit) and `q` on its sphere,
/// `|q − p|² / (−2 n·(q − p))`; infinite when `q` is not on the inner side of the tangent
/// plane. The shrinking ball of `p` is the minimum over the other points. The definition:
/// running minima use [`Tangent::lower`], which gives the same bits without the
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

/// The most vertices one search of `ShrinkingBalls::settle` visits.
pub const SEARCH_MAX: usize = 4096;

/// `ShrinkingBalls::settle` leaves a ball that may be this much (relative) too large:
/// a patch vertex on the ball's sphere up to rounding (every vertex of a sphere is) does
/// not make it search the whole sphere.
pub const SETTLE_SLACK: f64 = 1e-6;

/// A point's tangent ball before any vertex shrinks it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangent {
    /// Unit normal: the ball's centre is on `−normal`.
    pub normal: DVec3,
    /// The radius it starts from: infinite (the shrinking ball), or the fitted radius
    /// (the fitted ball), which stands for the vertices of the fitted patch.
    pub start: f64,
    /// Whether the 1-ring is a fitted patch: a neighbour within 45° of the tangent plane is
    /// then described by the normal and `start`, and does not shrink the ball.
    pub patch: bool,
}

impl Tangent {
    /// The shrinking ball's: no start, no patch, every vertex limits it.
    pub fn plain(normal: DVec3) -> Self {
        Tangent {
            normal,
            start: f64::INFINITY,
            patch: false,
        }
    }

    /// The fitted balls' ([`crate::mesh::fit_surface`]).
    pub fn fitted(fit: &SurfaceFit) -> Vec<Tangent> {
        fit.normals
            .iter()
            .zip(&fit.fitted_radius)
            .zip(&fit.fitted)
            .map(|((&normal, &start), &patch)| Tangent {
                normal,
                start,
                patch,
            })
            .collect()
    }

    /// `*x = x.min(tangent_radius(p, normal, q))`, exactly (see `lower_ball`),
    /// unless `q` is on the patch: `neighbour()` (asked only then) says whether it is on
    /// the 1-ring.
    #[inline(always)]
    pub fn lower(&self, x: &mut f64, p: DVec3, q: DVec3, neighbour: impl FnOnce() -> bool) {
        lower_ball(self.normal, x, p, q, || self.patch && neighbour());
    }
}

/// [`Tangent::lower`] with the patch asked only when needed: `*x` lowered to
/// `tangent_radius(p, normal, q)` unless `q` is within 45° of the tangent plane and
/// `on_patch()`. Exactly, without the division (or the write) when it cannot lower `x`,
/// which is most of the time for a running minimum: `|d|² ≥ x·s·(1 + 4ε)` (the product
/// rounded) implies `|d|² > x·s`, so the rounded quotient is at least `x`.
#[inline(always)]
fn lower_ball(normal: DVec3, x: &mut f64, p: DVec3, q: DVec3, on_patch: impl FnOnce() -> bool) {
    let d = q - p;
    let s = -2.0 * normal.dot(d);
    if s > 0.0 {
        let l = d.length_squared();
        if l < *x * s * (1.0 + 4.0 * f64::EPSILON) {
            // Within 45° of the tangent plane: `−n·d < |d| / √2`.
            if s * s < 2.0 * l && on_patch() {
                return;
            }
            let r = l / s;
            if r < *x {
                *x = r;
            }
        }
    }
}

/// The shrinking-ball radius of every point, being taken over the Delaunay edges as they
/// are made: the normals and radii in insertion order (internal ids).
pub(super) struct ShrinkingBalls<'a> {
    balls: Balls,
    /// Whether each point's 1-ring is a fitted patch ([`Tangent::patch`]); empty without
    /// a fit.
    patch: Vec<bool>,
    /// The input index of each point, and the fit that knows the 1-rings (the fitted
    /// ball's patches).
    input: Vec<u32>,
    fit: Option<&'a SurfaceFit>,
}

/// A ball being shrunk: its normal and radius side by side, so that offering an edge reads
/// one cache line per end.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct Ball {
    normal: DVec3,
    radius: f64,
}

/// Balls the two workers of a parallel phase lower concurrently, each only its own side's
/// (the [`EdgeHook`] contract).
struct Balls(Box<[UnsafeCell<Ball>]>);

// SAFETY: concurrent calls of `ShrinkingBalls::edge` never touch the same entry (the
// `EdgeHook` contract: the two workers never offer edges with a vertex in common), and
// nothing reads the radii until the tetrahedralization is done.
unsafe impl Sync for Balls {}

impl<'a> ShrinkingBalls<'a> {
    /// The balls of the points whose input indices are `order` at their start, with their
    /// `tangents` in input order.
    /// `fit` knows the 1-rings where some tangent has a patch.
    pub fn new(tangents: &[Tangent], order: &[u32], fit: Option<&'a SurfaceFit>) -> Self {
        let tangent = |i: &u32| tangents[*i as usize];
        ShrinkingBalls {
            balls: Balls(
                order
                    .iter()
                    .map(|i| {
                        let t = tangent(i);
                        UnsafeCell::new(Ball {
                            normal: t.normal,
                            radius: t.start,
                        })
                    })
                    .collect(),
            ),
            patch: if fit.is_some() {
                order.iter().map(|i| tangent(i).patch).collect()
            } else {
                Vec::new()
            },
            input: if fit.is_some() {
                order.to_vec()
            } else {
                Vec::new()
            },
            fit,
        }
    }

    /// Makes every fitted ball the largest one tangent at its point, no larger than its
    /// start and empty of the vertices off its patch, whatever the Delaunay edges offered
    /// (`positions` in input order). Returns how many balls were searched and how many of
    /// those searches gave up after [`SEARCH_MAX`] vertices (their radius stays an upper
    /// bound, which the thickness clamp bounds).
    ///
    /// Why only some: the minimum over the Delaunay neighbours off the patch gives a ball
    /// `B`. If no patch vertex is strictly inside `B`, `B` is exact: a vertex `q` off the
    /// patch with a smaller ball `B' ⊂ B` would leave `B'` free of patch vertices, so the
    /// shrinking ball inside `B'` (empty of every vertex) would be limited by a vertex off
    /// the patch on an empty sphere through `p`, a Delaunay neighbour smaller than the
    /// minimum. Otherwise the ball is searched: the vertices in a closed ball, with `p` on
    /// its sphere, are connected by Delaunay edges among themselves (lifted to the
    /// paraboloid, the ball is a half-space, and the part of the lower hull below a plane is
    /// connected), so a walk from `p` through them meets every vertex that can shrink it.
    pub fn settle(&mut self, delaunay: &Delaunay, positions: &[DVec3]) -> (usize, usize) {
        let Some(fit) = self.fit else {
            return (0, 0);
        };
        let (pts, input) = delaunay.insertion_order();
        let patch = &self.patch;
        let mut balls: Vec<&mut Ball> = self.balls.0.iter_mut().map(UnsafeCell::get_mut).collect();
        // The patch vertices of `k` strictly inside its ball (shrunk by the slack).
        let inside = |k: usize| {
            let (Ball { normal, radius: r }, p) = (*balls[k], pts[k]);
            fit.ring(input[k]).filter(move |&w| {
                let d = positions[w as usize] - p;
                let s = -2.0 * normal.dot(d);
                let l = d.length_squared();
                s > 0.0 && s * s < 2.0 * l && l < r * s * (1.0 - SETTLE_SLACK)
            })
        };
        let hides = |k: usize| {
            patch[k]
                && delaunay.duplicate_of(input[k] as usize).is_none()
                && inside(k).next().is_some()
        };
        let hidden: Vec<usize> = (0..patch.len())
            .into_par_iter()
            .with_min_len(1024)
            .filter(|&k| hides(k))
            .collect();
        if hidden.is_empty() {
            return (0, 0);
        }
        let stars = delaunay.stars();
        let mut internal = vec![0; input.len()];
        for (k, &i) in input.iter().enumerate() {
            internal[i as usize] = k as u32;
        }
        let searched: Vec<(f64, bool)> = hidden
            .par_iter()
            .with_min_len(64)
            .map_init(
                || (StarScratch::default(), Vec::new(), Vec::new()),
                |(cells, near, seen), &k| {
                    let (
                        Ball {
                            normal,
                            radius: mut r,
                        },
                        p,
                    ) = (*balls[k], pts[k]);
                    // The walk starts from the patch vertices inside: every vertex inside
                    // that is a Delaunay neighbour of `p` is one (one off the patch would
                    // have shrunk the ball), so no path through `p` is lost.
                    seen.clear();
                    seen.extend(inside(k).map(|w| internal[w as usize]));
                    let mut next = 0;
                    while let Some(&x) = seen.get(next) {
                        next += 1;
                        stars.neighbours(x, cells, near);
                        for &y in near.iter() {
                            let d = pts[y as usize] - p;
                            let s = -2.0 * normal.dot(d);
                            // Outside the closed ball shrunk by the slack, or seen.
                            if !(s > 0.0 && d.length_squared() <= r * s * (1.0 - SETTLE_SLACK))
                                || seen.contains(&y)
                            {
                                continue;
                            }
                            // A searched ball has a patch (`hides`).
                            lower_ball(normal, &mut r, p, pts[y as usize], || {
                                fit.adjacent(input[k], input[y as usize])
                            });
                            seen.push(y);
                            if seen.len() > SEARCH_MAX {
                                return (r, true);
                            }
                        }
                    }
                    (r, false)
                },
            )
            .collect();
        let mut gave_up = 0;
        for (&k, (r, capped)) in hidden.iter().zip(searched) {
            balls[k].radius = r;
            gave_up += usize::from(capped);
        }
        (hidden.len(), gave_up)
    }

    /// The radii in insertion order: infinite for a point with no start and no other point
    /// on the inner side of its tangent plane off its patch, and for a duplicate (never
    /// inserted).
    pub fn into_radii(self) -> Vec<f64> {
        self.balls
            .0
            .into_vec()
            .into_iter()
            .map(|b| b.into_inner().radius)
            .collect()
    }
}

impl EdgeHook for ShrinkingBalls<'_> {
    /// Offers the Delaunay edge `ab` to the balls of `a` and `b` ([`Tangent::lower`], which
    /// rounds alike whichever end comes first).
    #[inline(always)]
    unsafe fn edge(&self, pts: &[DVec3], a: u32, b: u32) {
        for (v, w) in [(a as usize, b as usize), (b as usize, a as usize)] {
            // SAFETY: no other thread touches the radius of `v` meanwhile (the contract).
            let ball = unsafe { &mut *self.balls.0[v].get() };
            lower_ball(ball.normal, &mut ball.radius, pts[v], pts[w], || {
                self.fit
                    .is_some_and(|f| self.patch[v] && f.adjacent(self.input[v], self.input[w]))
            });
        }
    }
}

/// Stage 3 for the shrinking balls (no stage 2): the tetrahedralization took the
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
    use crate::mesh::shapes;
    use crate::random::SplitMix;

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
            let tangents: Vec<Tangent> = normals.iter().map(|&n| Tangent::plain(n)).collect();
            let build = |first: usize, threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| {
                        Delaunay::with_phases_from(&pts, &|| false, first, |order| {
                            ShrinkingBalls::new(&tangents, order, None)
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
        let tangents = normals.map(Tangent::plain);
        let built = Delaunay::with_edge_hook(&pts, &|_| {}, &|| false, |order| {
            ShrinkingBalls::new(&tangents, order, None)
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
                Tangent::plain(n).lower(&mut lowered, p, q, || false);
                assert_eq!(lowered.to_bits(), x.min(r).to_bits(), "{p} {n} {q} x = {x}");
                checked += usize::from(r.is_finite());
            }
        }
        assert!(checked > 300_000, "{checked}");
    }
}
