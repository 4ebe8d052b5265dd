//! Stages 2–3 for the methods that read the inside Voronoi vertices ([`Method::Mean`],
//! [`Method::Pole`]): classify every circumcentre (slivers aside) with the exact inside
//! oracle, and accumulate each vertex's inside Voronoi vertices.

use super::{Method, SkeletonParams};
use crate::delaunay::Delaunay;
use crate::geom::inside::InsideTest;
use glam::DVec3;
use rayon::prelude::*;
use std::time::Instant;

/// Stages 2–3 for the methods that read the inside Voronoi vertices: the distance per
/// vertex, the fallback count, the number of inside circumcentres used and the number of
/// tetrahedra.
pub(super) fn voronoi_distances(
    delaunay: &Delaunay,
    pts: &[DVec3],
    inside: &InsideTest,
    params: &SkeletonParams,
    seconds: &mut Vec<(&'static str, f64)>,
) -> (Vec<f64>, usize, usize, usize) {
    let tets = delaunay.finite_tets();
    // 2. The circumradius if inside (negated for slivers), NaN if outside or undefined.
    let t = Instant::now();
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

    // 3. The tetrahedra are split in two fixed halves accumulated on both cores and merged
    // in a fixed order: the result does not depend on the thread count.
    let t = Instant::now();
    let half = tets.len() / 2;
    let n = pts.len();
    let (first, second) = rayon::join(
        || accumulate(n, &tets[..half], &radius[..half]),
        || accumulate(n, &tets[half..], &radius[half..]),
    );
    let used = first.used + second.used;
    let mut acc = first.acc;
    let mut sliver_acc = first.sliver_acc;
    for (a, b) in acc.iter_mut().zip(&second.acc) {
        a.merge(b);
    }
    for (a, b) in sliver_acc.iter_mut().zip(&second.sliver_acc) {
        a.merge(b);
    }
    for (a, s) in acc.iter_mut().zip(&sliver_acc) {
        if a.count == 0 {
            // Vertices whose every inside Voronoi vertex comes from a sliver use those.
            *a = *s;
        }
    }
    let distance = acc
        .iter()
        .map(|a| match (a.count, params.method) {
            (0, _) => 0.0,
            (c, Method::Mean) => a.sum / c as f64,
            _ => a.max,
        })
        .collect();
    // Duplicates (never inserted) take their vertex's distance in the caller.
    let fallback = (0..n)
        .filter(|&i| acc[i].count == 0 && delaunay.duplicate_of(i).is_none())
        .count();
    seconds.push(("distance", t.elapsed().as_secs_f64()));
    (distance, fallback, used, tets.len())
}

/// Per-vertex accumulator of inside Voronoi vertices.
#[derive(Clone, Copy, Debug, Default)]
struct Acc {
    sum: f64,
    max: f64,
    count: u32,
}

impl Acc {
    #[inline]
    fn add(&mut self, r: f64) {
        self.sum += r;
        self.max = self.max.max(r);
        self.count += 1;
    }

    fn merge(&mut self, o: &Acc) {
        self.sum += o.sum;
        self.max = self.max.max(o.max);
        self.count += o.count;
    }
}

/// Per-vertex accumulators over a run of tetrahedra.
struct Accumulated {
    acc: Vec<Acc>,
    sliver_acc: Vec<Acc>,
    used: usize,
}

/// Accumulates the inside circumradii `radius` of `tets` (negative for slivers, NaN when
/// outside) on their corners, for `n` vertices.
fn accumulate(n: usize, tets: &[[u32; 4]], radius: &[f64]) -> Accumulated {
    let mut acc = vec![Acc::default(); n];
    let mut sliver_acc = vec![Acc::default(); n];
    let mut used = 0;
    for (tv, &r) in tets.iter().zip(radius) {
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
    Accumulated {
        acc,
        sliver_acc,
        used,
    }
}
