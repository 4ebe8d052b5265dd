//! Medial balls as colliders: which of a body's balls (one per surface vertex, centre its
//! skeletal point and radius its skeletal distance) are worth testing, and which pairs of
//! balls and points were neighbours at rest.
//!
//! Most balls are nearly inside a bigger one of the same part: [`thin`] keeps a ball only
//! where it reaches more than [`THIN`] of its radius beyond every bigger ball kept, largest
//! first. The simulation's contacts (`sim::contact`) and the pose limit
//! (`joints::collide`) test the same balls.

use glam::DVec3;
use std::collections::HashMap;

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

/// The balls kept (indices into `centers`), largest first: a ball is dropped when a bigger
/// ball of the same `part` kept before it covers all but [`THIN`] of its radius. Balls with
/// a radius that is not finite and positive are dropped.
pub fn thin(centers: &[DVec3], radii: &[f64], part: &[u16]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..centers.len().min(radii.len()))
        .filter(|&i| radii[i].is_finite() && radii[i] > 0.0 && centers[i].is_finite())
        .collect();
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]).then(a.cmp(&b)));
    let Some(&largest) = order.first() else {
        return Vec::new();
    };
    let part = |i: usize| part.get(i).copied().unwrap_or(0);
    // A grid of cells twice the largest radius: a covering ball is in a neighbouring cell.
    let cell = (2.0 * radii[largest]).max(f64::MIN_POSITIVE);
    let key = |p: DVec3| {
        let k = (p / cell).floor();
        [k.x as i64, k.y as i64, k.z as i64]
    };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    let mut kept = Vec::new();
    for i in order {
        let (c, r, k) = (centers[i], radii[i], key(centers[i]));
        let covered = (-1..=1).any(|dx| {
            (-1..=1).any(|dy| {
                (-1..=1).any(|dz| {
                    grid.get(&[k[0] + dx, k[1] + dy, k[2] + dz])
                        .is_some_and(|list| {
                            list.iter().any(|&j| {
                                part(j) == part(i)
                                    && centers[j].distance(c) + r <= radii[j] + THIN * r
                            })
                        })
                })
            })
        });
        if !covered {
            grid.entry(k).or_default().push(i);
            kept.push(i);
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

    #[test]
    fn neighbours_reach_a_few_of_the_smaller_radii() {
        assert!(neighbours(1.0 + 1.9 * 0.1, 1.0, 0.1));
        assert!(!neighbours(1.0 + 2.1 * 0.1, 1.0, 0.1));
        assert!(neighbours(1.0 + 1.9, 1.0, 5.0));
    }
}
