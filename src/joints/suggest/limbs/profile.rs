//! A segment's profile along its axis (`g` in bins: the skeletal distance, the ring's size
//! and centre) and where a part with that profile is cut.

use crate::joints::suggest::rules::{
    BASE, BEND, DIGIT, DIP, ELONGATED, FLAT, LONG, LONG_TO_WRIST, SOCKET, WRIST,
};
use glam::DVec3;

/// A segment's profile (see [`Tree::profile`]).
pub(crate) struct Profile {
    /// `g` at its base.
    pub(crate) low: f64,
    /// Bin length.
    pub(crate) step: f64,
    /// Per bin: median skeletal distance, and mean distance from the ring's centre.
    pub(crate) d: Vec<f64>,
    pub(crate) size: Vec<f64>,
    /// Per bin: the ring's centre (the limb's axis).
    pub(crate) centre: Vec<DVec3>,
}

impl Profile {
    /// The bins of the cuts inside a part with this profile, from its base up, in order: at
    /// clear narrowings; where a limb widens into an extremity (`extremity`); along a digit
    /// (`digit`) at 45 % and 72 % of its length; in the middle of a limb's long stretch
    /// without a joint. `limb`: the part is a limb, cut at its base (a part of the body is
    /// cut only where it narrows).
    pub(crate) fn cut_bins(&self, limb: bool, extremity: bool, digit: bool) -> Vec<usize> {
        let bins = self.d.len();
        // Bins of cuts; a cut keeps three bins (1.5 radii) from another and from the top,
        // and two radii from the base cut.
        let mut at: Vec<usize> = Vec::new();
        let first = if limb {
            (2.0 * (BASE + 1.5)) as usize
        } else {
            3
        };
        let free = |at: &[usize], b: usize| {
            b >= first && b + 3 <= bins && at.iter().all(|&c| c.abs_diff(b) >= 3)
        };
        // Narrowings: a minimum of the skeletal distance or of the ring's size clearly below
        // the thickest within three radii (six bins) before it and the thicker part after it.
        for b in 1..bins - 1 {
            // (The part past it widens again within three radii: the end of a taper into
            // a foot whose rings the bend distorts is no narrowing.)
            let narrows = |v: &[f64]| {
                let here = v[b];
                let before = v[b.saturating_sub(6)..b]
                    .iter()
                    .copied()
                    .fold(0.0, f64::max);
                let after = v[b + 1..].iter().copied().fold(0.0, f64::max);
                let soon = v[b + 1..(b + 7).min(bins)]
                    .iter()
                    .copied()
                    .fold(0.0, f64::max);
                here <= v[b - 1]
                    && here <= v[b + 1]
                    && here <= (1.0 - DIP) * before.min(after)
                    && here <= (1.0 - DIP) * soon
            };
            // (A dip of the skeletal distance alone, where the rings bulge, is the middle of
            // a round end, a big ear's: no narrowing.)
            let bulge = {
                let near = &self.size[b.saturating_sub(2)..(b + 3).min(bins)];
                self.size[b] > (1.0 + DIP) * near.iter().copied().fold(f64::INFINITY, f64::min)
            };
            if ((narrows(&self.d) && !bulge) || narrows(&self.size)) && free(&at, b) {
                at.push(b);
            }
        }
        if !limb {
            at.sort_unstable();
            return at;
        }
        // Where it widens into an extremity: the narrowest ring of its last half, if the
        // extremity is clearly wider.
        if extremity {
            let half = bins / 2;
            if let Some(b) = (half..bins).min_by(|&a, &b| self.size[a].total_cmp(&self.size[b])) {
                let wider = self.size[b..].iter().copied().fold(0.0, f64::max);
                if wider >= (1.0 + DIP) * self.size[b] && free(&at, b) {
                    at.push(b);
                }
            }
        }
        // Where the axis bends (a bent knee, an ankle, a hock): the sharpest turn over
        // three radii either side, if it turns by at least BEND, and no other cut within
        // those three radii (the same joint, a narrowing at an ankle). A short limb that
        // ends at an extremity (an arm bent forward, two radii from its elbow to its hand)
        // is measured over as much as it has, down to 1.5 radii either side, up to that
        // end (no round tip there).
        let w: usize = if extremity {
            ((bins.max(1) - 1) / 2).clamp(3, 6)
        } else {
            6
        };
        let turn = |b: usize| {
            if b < w || b + w >= bins {
                return 0.0;
            }
            let u = self.centre[b] - self.centre[b - w];
            let v = self.centre[b + w] - self.centre[b];
            u.angle_between(v).to_degrees()
        };
        // (Not within two and a half radii of the base, where the axis turns out of the trunk, nor
        // within three of the tip, where it rounds.)
        let end = if extremity { w } else { 5 };
        for b in 5..bins.saturating_sub(end) {
            let t = turn(b);
            let alone = at.iter().all(|&c| c.abs_diff(b) >= w);
            if t >= BEND && t >= turn(b - 1) && t >= turn(b + 1) && free(&at, b) && alone {
                at.push(b);
            }
        }
        // A digit's two joints, at 45 % and 72 % of its length (where a finger's bend),
        // unless narrowings already cut it.
        if digit && at.is_empty() && bins as f64 * self.step >= DIGIT {
            for share in [0.45, 0.72] {
                let b = (share * bins as f64) as usize;
                if free(&at, b) {
                    at.push(b);
                }
            }
        }
        // A long first stretch, from the base to the first joint (an upper arm whose elbow
        // neither narrows nor bends, a dog's straight leg down to its wrist), bends in the
        // middle; later stretches are between
        // joints already found (a shin between a knee and an ankle).
        // (A digit's two joints stand in for this, unless something else cut it.)
        at.sort_unstable();
        if !digit || !at.is_empty() {
            let ends: Vec<usize> = std::iter::once(first / 2)
                .chain(at.iter().copied())
                .chain(std::iter::once(bins))
                .collect();
            // Metres along the axis from the base, bin by bin (the middle of a tapering
            // stretch is nearer its thin end in local radii).
            let mut along = vec![0.0; bins];
            for b in 1..bins {
                along[b] = along[b - 1] + self.centre[b].distance(self.centre[b - 1]);
            }
            for w in ends.windows(2).take(1) {
                let (a, b) = (w[0], w[1]);
                // (From fewer radii when that joint lies in the limb's last part: a wrist
                // or an ankle, with an elbow or a knee still to come before it.)
                let len = (b - a) as f64 * self.step;
                // (None in a flat part: its length in radii of its thickness says nothing
                // of an elbow.)
                let median =
                    |v: &[f64]| crate::stats::median(&mut v.to_vec()).unwrap_or(f64::INFINITY);
                let flat =
                    median(&self.size[a..b.min(bins)]) > FLAT * median(&self.d[a..b.min(bins)]);
                let to_wrist = b < bins && b as f64 >= WRIST * bins as f64;
                if !flat && (len >= LONG || (to_wrist && len >= LONG_TO_WRIST)) {
                    // (The middle of the bone, from the ball of the limb's root: [`SOCKET`]
                    // of the radius at the cut behind the base ring, where a shoulder's or
                    // a hip's pivot goes. A thigh whose top hides in the trunk is counted
                    // whole, and its knee is not placed low.)
                    let ball = along[0] - SOCKET * self.d[1];
                    let half = 0.5 * (ball + along[b.min(bins - 1)]);
                    let mid = (0..b.min(bins))
                        .find(|&m| along[m] >= half)
                        .unwrap_or((a + b) / 2);
                    if free(&at, mid) {
                        at.push(mid);
                    }
                }
            }
            at.sort_unstable();
        }
        at
    }
}

/// Is a protrusion a limb? Its ring `own` wide (the size of [`Tree::size`]) must be at most
/// `thinner` of the `trunk` it grows from ([`THINNER`], or [`PAIR_THINNER`] for one of a
/// pair that splits the trunk) and longer than it is wide: `length` (in local radii,
/// `radius` its medial radius) at least [`ELONGATED`] times its width in radii. A nose is
/// neither; a finger on a palm is both.
pub(crate) fn is_limb(own: f64, trunk: f64, length: f64, radius: f64, thinner: f64) -> bool {
    own > 0.0 && own <= thinner * trunk && length >= ELONGATED * own / radius
}

/// Empty bins (NaN) take the value of the nearest bins on either side; `None` if all are.
pub(crate) fn fill(v: &[f64]) -> Option<Vec<f64>> {
    let known: Vec<usize> = (0..v.len()).filter(|&i| v[i].is_finite()).collect();
    let (&first, &last) = (known.first()?, known.last()?);
    let mut out = v.to_vec();
    for (i, o) in out.iter_mut().enumerate() {
        if o.is_finite() {
            continue;
        }
        *o = if i < first {
            v[first]
        } else if i > last {
            v[last]
        } else {
            let a = known
                .iter()
                .rev()
                .find(|&&k| k < i)
                .copied()
                .unwrap_or(first);
            let b = known.iter().find(|&&k| k > i).copied().unwrap_or(last);
            let t = (i - a) as f64 / (b - a).max(1) as f64;
            v[a] + (v[b] - v[a]) * t
        };
    }
    Some(out)
}

/// A moving average over three bins.
pub(crate) fn smooth(v: &[f64]) -> Vec<f64> {
    (0..v.len())
        .map(|b| {
            let (a, c) = (b.saturating_sub(1), (b + 1).min(v.len() - 1));
            (v[a] + v[b] + v[c]) / 3.0
        })
        .collect()
}
