//! Medial balls as colliders: which of a body's balls (one per surface vertex, centre its
//! skeletal point and radius its skeletal distance) are worth testing, and which pairs of
//! balls and points were neighbours at rest.
//!
//! Most balls are nearly inside a bigger one of the same part: [`thin`] keeps a ball only
//! where it reaches more than [`THIN`] of its radius beyond every bigger ball kept, largest
//! first. The simulation's contacts (`sim::contact`) and the pose limit
//! (`joints::collide`) test the same balls.

use crate::geom::cells::Cells;
use glam::DVec3;

/// A ball is dropped when a bigger ball of its part kept so far leaves less than this share
/// of its radius outside: along a limb, balls about half a radius apart are kept, whose
/// union dips between two of them by 3 % of the radius.
pub const THIN: f64 = 0.25;

/// The two sides of a joint near each other at rest never collide: a point (or ball) of
/// the joint's flesh (`Joints::joint_flesh`) within this many local radii of a ball's
/// surface at rest (the smaller of the two radii). That is where each side's balls meet the
/// other side's surface and where the joint band's own contact holds the inner fold
/// (`joints::band::CONTACT_REACH`). Other parts near each other at rest do collide.
pub const NEIGHBOURS: f64 = 2.0;

/// A grid cell for `radii`: twice the 90th percentile, so most balls meet a few cells and
/// the few bigger ones are kept apart.
pub fn cell(radii: &[f64]) -> f64 {
    let mut sorted: Vec<f64> = radii.iter().copied().filter(|r| r.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    sorted
        .get(sorted.len() * 9 / 10)
        .map_or(1.0, |r| 2.0 * r)
        .max(f64::MIN_POSITIVE)
}

/// Whether a thing at rest distance `distance` from a ball's centre, the ball of radius
/// `radius`, the thing of local radius `own`, were neighbours at rest (see [`NEIGHBOURS`]).
pub fn neighbours(distance: f64, radius: f64, own: f64) -> bool {
    distance < radius + NEIGHBOURS * radius.min(own)
}

/// A kept ball is listed in every grid cell its box meets while that is at most this many
/// cells; a bigger one is tested against every ball that follows.
const MOST_CELLS: f64 = 512.0;

/// The balls kept (indices into `centers`), largest first: a ball is dropped when a bigger
/// ball of the same `part` kept before it covers all but [`THIN`] of its radius. Balls with
/// a radius that is not finite and positive are dropped.
///
/// A ball that covers another contains its centre, so each kept ball is listed in the grid
/// cells (twice the 90th percentile radius, [`cell`]) its box meets, and a ball looks only in
/// its centre's cell: on a statue whose plinth's balls are twenty times a limb's, one grid
/// of cells as wide as the largest ball put every ball in a few cells and tested each
/// against nearly all kept before it.
pub fn thin(centers: &[DVec3], radii: &[f64], part: &[u16]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..centers.len().min(radii.len()))
        .filter(|&i| radii[i].is_finite() && radii[i] > 0.0 && centers[i].is_finite())
        .collect();
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]).then(a.cmp(&b)));
    let cell = cell(&order.iter().map(|&i| radii[i]).collect::<Vec<_>>());
    let part = |i: usize| part.get(i).copied().unwrap_or(0);
    let key = |p: DVec3| {
        let k = (p / cell).floor();
        [k.x as i64, k.y as i64, k.z as i64]
    };
    let mut grid: Cells<[i64; 3], Vec<usize>> = Cells::default();
    let mut huge: Vec<usize> = Vec::new();
    let mut kept = Vec::new();
    for i in order {
        let (c, r) = (centers[i], radii[i]);
        let covers =
            |&j: &usize| part(j) == part(i) && centers[j].distance(c) + r <= radii[j] + THIN * r;
        let covered =
            huge.iter().any(covers) || grid.get(&key(c)).is_some_and(|l| l.iter().any(covers));
        if covered {
            continue;
        }
        kept.push(i);
        let (lo, hi) = (key(c - r), key(c + r));
        let cells: f64 = (0..3)
            .map(|a| (hi[a] as f64 - lo[a] as f64) + 1.0)
            .product();
        if cells > MOST_CELLS {
            huge.push(i);
            continue;
        }
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    grid.entry([x, y, z]).or_default().push(i);
                }
            }
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_balls_are_thinned_and_parts_keep_their_own() {
        let centers = [
            DVec3::ZERO,
            DVec3::new(0.05, 0.0, 0.0),
            DVec3::new(0.9, 0.0, 0.0),
            DVec3::new(0.05, 0.0, 0.0),
            DVec3::ZERO,
        ];
        let radii = [1.0, 0.5, 0.5, 0.5, f64::NAN];
        // The second is inside the first; the third sticks out by more than half its
        // radius; the fourth is another part's; the fifth is no ball.
        assert_eq!(thin(&centers, &radii, &[0, 0, 0, 1, 0]), [0, 2, 3]);
    }

    /// The grid finds what testing every kept ball finds, on balls of radii a thousand
    /// times apart in a few parts, some of them too big for the grid.
    #[test]
    fn thinning_by_grid_keeps_what_testing_every_ball_keeps() {
        fn every(centers: &[DVec3], radii: &[f64], part: &[u16]) -> Vec<usize> {
            let mut order: Vec<usize> = (0..centers.len()).collect();
            order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]).then(a.cmp(&b)));
            let mut kept: Vec<usize> = Vec::new();
            for i in order {
                let covered = kept.iter().any(|&j| {
                    part[j] == part[i]
                        && centers[j].distance(centers[i]) + radii[i] <= radii[j] + THIN * radii[i]
                });
                if !covered {
                    kept.push(i);
                }
            }
            kept
        }
        let mut rng = crate::random::SplitMix(7);
        let mut unit = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        for round in 0..20 {
            let n = 300 + 100 * round;
            let centers: Vec<DVec3> = (0..n)
                .map(|_| DVec3::new(unit(), unit(), unit()) * 10.0)
                .collect();
            // A few of them far bigger than the grid's cells (a plinth's).
            let radii: Vec<f64> = (0..n)
                .map(|_| 10f64.powf(-3.0 * unit()) * if unit() < 0.02 { 30.0 } else { 1.0 })
                .collect();
            let part: Vec<u16> = (0..n).map(|_| (unit() * 3.0) as u16).collect();
            assert_eq!(
                thin(&centers, &radii, &part),
                every(&centers, &radii, &part)
            );
        }
    }

    #[test]
    fn neighbours_reach_a_few_of_the_smaller_radii() {
        assert!(neighbours(1.0 + 1.9 * 0.1, 1.0, 0.1));
        assert!(!neighbours(1.0 + 2.1 * 0.1, 1.0, 0.1));
        assert!(neighbours(1.0 + 1.9, 1.0, 5.0));
    }
}
