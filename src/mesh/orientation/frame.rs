//! Up, front and left from the cues and the root's limbs (the suggestion's fifth stage;
//! the rules in the parent module's docs).

use super::{
    head_of, Cues, Frame, Given, Reach, APART, AXES, BULK, DETAIL, FEET, FRONT_END, GROUND, LONG,
    OFF_PLANE, STANDING, TAIL_END, TOES,
};
use super::{soled, soles};
use glam::DVec3;

/// The frame of a mesh with the cues `cues` whose root has `limbs` (see the module docs);
/// up and front as far as `given`.
pub fn frame(positions: &[DVec3], cues: Cues, limbs: &[Reach], given: Given) -> Frame {
    let Cues {
        mirror,
        base,
        flat,
        bulk,
        detail,
    } = cues;
    let size = crate::mesh::longest_side(positions);
    let centre = positions.iter().sum::<DVec3>() / positions.len().max(1) as f64;
    let axes = AXES;
    // The mesh's extent along `d`, near end and far end.
    let span = |d: DVec3| {
        positions
            .iter()
            .map(|p| p.dot(d))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            })
    };
    // The root's limbs off the mirror plane (none without one).
    let off_plane =
        |l: &Reach| mirror.is_some_and(|(n, o)| (l.pivot.dot(n) - o).abs() >= OFF_PLANE * size);
    let off: Vec<&Reach> = limbs.iter().filter(|l| off_plane(l)).collect();
    // Up from a flat base, along the mirror plane.
    let base_up = base
        .map(|b| -b)
        .filter(|u| mirror.is_none_or(|(n, _)| u.dot(n).abs() < 0.5));
    let up = match (given.up, mirror) {
        (Some(u), _) => u.normalize_or(DVec3::Y),
        // Without a plane, soles at one end only say down where no base does.
        (None, None) => base_up
            .or_else(|| soles(&flat).map(|down| -down))
            .unwrap_or(DVec3::Y),
        (None, Some(_)) if base_up.is_some() && off.is_empty() => base_up.unwrap_or(DVec3::Y),
        (None, Some((n, _))) => {
            // How well each direction across the plane does as down, by where the tips
            // of the limbs off the plane lie from the mesh's centre (legs and arms; a tail
            // or a neck says nothing about up). From the centre, not from the limb's own
            // cut: a stubby leg cut at its ankle is a foot pointing forward.
            // Each limb says as much as it is thick (the legs carry the body; ears and a
            // raised arm's thin hand say less).
            let thickest = off.iter().map(|l| l.end).fold(0.0, f64::max);
            let weight = |l: &Reach| {
                if thickest > 0.0 {
                    l.end / thickest
                } else {
                    1.0
                }
            };
            let down = |d: DVec3| -> f64 {
                off.iter()
                    .map(|l| {
                        weight(l) * (l.tip - centre).normalize_or_zero().dot(d).max(0.0).powi(2)
                    })
                    .sum()
            };
            let best = axes
                .iter()
                .copied()
                .filter(|a| a.dot(n).abs() < 0.5)
                .max_by(|a, b| down(*a).total_cmp(&down(*b)))
                .unwrap_or(DVec3::NEG_Y);
            // Those that point way `d` at all (legs hanging; not arms held out, nor ears),
            // and whether one of them reaches the mesh's far end that way (stands on the
            // ground, [`GROUND`]: sprawled legs hang back no farther than a tail).
            let hanging = |d: DVec3| -> Vec<&Reach> {
                off.iter()
                    .copied()
                    .filter(|l| (l.tip - centre).dot(d) > 0.0)
                    .collect()
            };
            let stands = |d: DVec3| {
                let (near, far) = span(d);
                hanging(d)
                    .iter()
                    .any(|l| far - l.tip.dot(d) <= GROUND * (far - near))
            };
            // (Only limbs that clearly hang along it move up off +y: sprawled legs say
            // little; all the root's limbs doing so, or those that point that way at all
            // and stand on the ground (a biped's legs, its arms held out).)
            let best_stands = stands(best);
            let votes = |of: &[&Reach]| of.iter().map(|l| weight(l)).sum::<f64>();
            let clearly = down(best) >= 0.5 * votes(&off)
                || (best_stands && down(best) >= 0.5 * votes(&hanging(best)));
            // (+y does nearly as well, unless only the other stands on the ground: a
            // sitting animal's forelegs reach forward as far as its legs hang.)
            let y_as_well =
                down(DVec3::NEG_Y) >= 0.67 * down(best) && (stands(DVec3::NEG_Y) || !best_stands);
            // (Sprawled legs that say little of up still all end on the ground, one way
            // only: a lizard, an insect or a scorpion modelled with any axis up.)
            let grounded = |d: DVec3| {
                let (near, far) = span(d);
                off.len() >= 4
                    && off
                        .iter()
                        .all(|l| far - l.tip.dot(d) <= FEET * (far - near))
            };
            let on_the_ground: Vec<DVec3> = axes
                .iter()
                .copied()
                .filter(|a| a.dot(n).abs() < 0.5 && grounded(*a))
                .collect();
            // (Three feet or more on the ground one way only, standing apart across it:
            // that way is down, however thick the other limbs, cut with the hindquarters,
            // or whichever way they reach. Apart: ears and a raised hand side by side on
            // a head's top are no stance.)
            let stance = |d: DVec3| {
                let (near, far) = span(d);
                let feet: Vec<DVec3> = off
                    .iter()
                    .filter(|l| far - l.tip.dot(d) <= GROUND * (far - near))
                    .map(|l| l.tip)
                    .collect();
                feet.len() >= STANDING
                    && axes[..].iter().step_by(2).all(|&e| {
                        if e.dot(d).abs() > 0.5 {
                            return true;
                        }
                        let (a, b) = span(e);
                        let (lo, hi) = feet
                            .iter()
                            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
                                (lo.min(t.dot(e)), hi.max(t.dot(e)))
                            });
                        hi - lo >= APART * (b - a)
                    })
            };
            let standing: Vec<DVec3> = axes
                .iter()
                .copied()
                .filter(|a| a.dot(n).abs() < 0.5 && stance(*a))
                .collect();
            // (+y across the mirror plane cannot be up: a character lying on its side, or
            // modelled with x or z up, has only its limbs to say.)
            let y_along = DVec3::Y.dot(n).abs() < 0.5;
            // (Soles at the end the limbs or the convention put on top, and hardly any
            // flat at the other: that end is down. A cartoon hero's huge head may be the
            // root, its ears the only limbs off the plane, its legs hanging from a child.
            // A stance is left as it is.) `soled_end(u)`: the end along `u` is flat as soles
            // are, the other not.
            let soled_end = |u: DVec3| {
                AXES.iter()
                    .position(|&a| a == u)
                    .is_some_and(|k| soled(&flat, k))
            };
            let right_way_up = |u: DVec3| if soled_end(u) { -u } else { u };
            // (Soles at one end along the plane only: that end is down, before what the
            // limbs say or the convention: a quadruped whose legs are read as a hand's
            // digits, modelled upside down or z up.)
            let soled_ends: Vec<DVec3> = axes
                .iter()
                .copied()
                .filter(|&a| a.dot(n).abs() < 0.5 && soled_end(a))
                .collect();
            if let [down] = standing.as_slice() {
                -*down
            } else if let [down] = soled_ends.as_slice() {
                -*down
            } else if let (false, [down]) = (clearly, on_the_ground.as_slice()) {
                right_way_up(-*down)
            } else if y_along && (y_as_well || !clearly) {
                right_way_up(DVec3::Y)
            } else {
                right_way_up(-best)
            }
        }
    };
    // Front: across up and the plane's normal (or the convention without a plane).
    let convention = if up.y.abs() >= 0.5 {
        DVec3::Z
    } else {
        DVec3::NEG_Y
    };
    let axis = match mirror {
        Some((n, _)) => up.cross(n).normalize_or(convention),
        None => (convention - up * convention.dot(up)).normalize_or(DVec3::Z),
    };
    let on_plane = |l: &Reach| !off_plane(l);
    // The part on the plane most like a head grows from the other end of the body than the
    // tail (a cat stretching looks up and back; a penguin), or leans forward; else the feet
    // point forward. Most like a head: with ears on the body (a head not cut from it), of
    // two or more parts on the plane the one nearest them; else [`head_of`].
    let midline: Vec<&Reach> = limbs.iter().filter(|l| on_plane(l)).collect();
    let ears: Vec<DVec3> = limbs
        .iter()
        .filter(|l| !on_plane(l) && l.raised(up, centre))
        .map(|l| l.pivot)
        .collect();
    let head = if ears.is_empty() || midline.len() < 2 {
        head_of(&midline, 0.0, up).map(|h| midline[h])
    } else {
        let at = ears.iter().sum::<DVec3>() / ears.len() as f64;
        midline
            .iter()
            .copied()
            .min_by(|a, b| a.pivot.distance(at).total_cmp(&b.pivot.distance(at)))
    };
    // (With no other part on the plane there is nothing to tell a head from a tail by:
    // a scorpion's raised tail.)
    let placed = head.map_or(0.0, |h| {
        let along = |l: &Reach| (h.pivot - l.pivot).dot(axis);
        midline
            .iter()
            .map(|l| along(l))
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap_or(0.0)
    });
    // (A lone part on the plane much thinner than the limbs is a tail, leaning back.)
    let limbs_end = || {
        let mut ends: Vec<f64> = off.iter().map(|l| l.end).collect();
        crate::stats::median(&mut ends).unwrap_or(0.0)
    };
    let tail = midline.len() == 1 && head.is_some_and(|h| h.end < TAIL_END * limbs_end());
    let lean = head.map_or(0.0, |h| h.direction().dot(axis)) * if tail { -1.0 } else { 1.0 };
    let feet: f64 = limbs
        .iter()
        .filter(|l| l.direction().dot(up) < -0.5)
        .map(|l| (l.tip - l.pivot).dot(axis))
        .sum();
    let toes = || toes(positions, up, axis) / size.max(f64::MIN_POSITIVE);
    // (A front given along the plane's normal, a model facing across its own mirror
    // plane, is the file's mistake: the cues decide.)
    let declared = given.front.map(|f| f.dot(axis)).filter(|d| d.abs() > 0.5);
    // How much finer the surface is made at the front end of `axis` than at the back.
    let finer = {
        let a = axis.abs();
        let k = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        if a[k] > 0.99 {
            detail[k] * axis[k].signum()
        } else {
            0.0
        }
    };
    let legs_hang = limbs.iter().any(|l| l.direction().dot(up) < -0.5);
    // How far the solid's centre of mass lies ahead of the middle of its length along
    // `axis`, for that length.
    let bulk_ahead = bulk.map_or(0.0, |b| {
        let (a, z) = span(axis);
        if z > a {
            (b.dot(axis) - 0.5 * (a + z)) / (z - a)
        } else {
            0.0
        }
    });
    // No limb off the plane and none reaching the ground: nothing to stand on.
    let swims = off.is_empty() && {
        let (near, far) = span(-up);
        limbs
            .iter()
            .all(|l| far - l.tip.dot(-up) > GROUND * (far - near))
    };
    let long = {
        let ((a, b), (c, d)) = (span(axis), span(up));
        b - a >= LONG * (d - c)
    };
    let sign = if let Some(declared) = declared {
        declared.signum()
    } else if legs_hang && long && finer.abs() >= DETAIL.ln() {
        // Legs hang from a long body: the end modelled finer is the face.
        finer.signum()
    } else if swims && long && bulk_ahead.abs() >= BULK {
        // Nothing to stand on (a fish, a whale): its bulk lies toward its head.
        bulk_ahead.signum()
    } else if placed.abs() > FRONT_END * size {
        placed.signum()
    } else if lean.abs() > 0.3 {
        lean.signum()
    } else if feet.abs() > 1e-9 {
        // Legs hang: their soles say it, where they clearly lie ahead of the shins, else
        // the limbs' tips.
        let toes = toes();
        if toes.abs() >= TOES {
            toes.signum()
        } else {
            feet.signum()
        }
    } else if axis.dot(convention) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let front = axis * sign;
    // (Plus zero: an axis turned over is written `0`, not `-0`, in `--json`.)
    Frame {
        up: up + DVec3::ZERO,
        front: front + DVec3::ZERO,
        left: up.cross(front) + DVec3::ZERO,
        mirror,
    }
}

/// How far the soles (the vertices in the lowest 4 % of the height along `up`) lie ahead of
/// the shins above them (8–15 %) along `axis`: feet point forward, on a person in shoes as
/// on a paw.
pub(super) fn toes(positions: &[DVec3], up: DVec3, axis: DVec3) -> f64 {
    let height = |p: &DVec3| p.dot(up);
    let (lo, hi) = positions
        .iter()
        .map(height)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), h| {
            (a.min(h), b.max(h))
        });
    let along = |from: f64, to: f64| {
        let (lo, hi) = (lo + from * (hi - lo), lo + to * (hi - lo));
        let (sum, n) = positions
            .iter()
            .filter(|p| (lo..=hi).contains(&height(p)))
            .fold((0.0, 0usize), |(s, n), p| (s + p.dot(axis), n + 1));
        (n > 0).then(|| sum / n as f64)
    };
    match (along(0.0, 0.04), along(0.08, 0.15)) {
        (Some(soles), Some(shins)) => soles - shins,
        _ => 0.0,
    }
}
