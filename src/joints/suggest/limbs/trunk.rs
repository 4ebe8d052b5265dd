//! A cut across the body's core (stage 3): a head as thick as the body it
//! sits on is part of the core, which no other rule cuts; where the core clearly narrows
//! between two thick parts (a neck), the part away from the root turns there.

use super::Limb;
use crate::joints::suggest::body::Tree;
use crate::joints::suggest::rules::{ELONGATED, NARROW};
use glam::DVec3;

impl Tree<'_> {
    /// The cut across the core at its clearest narrowing along its long axis, if one is at
    /// most [`NARROW`] of the widest slices on both sides and the part past it reaches at
    /// least [`ELONGATED`] radii: its plane faces away from the root.
    pub(crate) fn trunk_cut(&self) -> Option<Limb> {
        let core: Vec<u32> = (0..self.g.len() as u32)
            .filter(|&v| self.g[v as usize] == 0.0)
            .collect();
        let (root, reach) = self.core;
        if core.len() < 64 || reach <= 0.0 {
            return None;
        }
        let positions = &self.mesh.positions;
        let at = |v: u32| positions[v as usize];
        let mean = core.iter().map(|&v| at(v)).sum::<DVec3>() / core.len() as f64;
        let axis = long_axis(core.iter().map(|&v| at(v) - mean));
        let t: Vec<f64> = core.iter().map(|&v| (at(v) - mean).dot(axis)).collect();
        let lo = t.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = t.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        // Slices half a radius thick: each one's centre and size.
        let step = 0.5 * reach;
        let bins = ((hi - lo) / step).floor() as usize;
        if bins < 8 {
            return None;
        }
        let (slices, size) = self.slices(&core, &t, lo, step, bins);
        // The clearest narrowing with a part at least ELONGATED radii long past it.
        let reach_bins = (ELONGATED / 0.5).ceil() as usize;
        let mut best: Option<(usize, f64)> = None;
        for b in 2..bins.saturating_sub(2) {
            if !size[b].is_finite() {
                continue;
            }
            let ratio = size[b] / widest(&size[..b]).min(widest(&size[b + 1..]));
            let root_before = (root - mean).dot(axis) < lo + (b as f64 + 0.5) * step;
            let past = if root_before { bins - 1 - b } else { b };
            if ratio <= NARROW && past >= reach_bins && best.is_none_or(|(_, r)| ratio < r) {
                best = Some((b, ratio));
            }
        }
        let (b, _) = best?;
        let (point, _) = self.centre(&slices[b]);
        let level = lo + (b as f64 + 0.5) * step;
        let normal = if (root - mean).dot(axis) < level {
            axis
        } else {
            -axis
        };
        let expected = positions
            .iter()
            .filter(|&&p| (p - point).dot(normal) > 0.0)
            .count();
        Some(Limb::across(point, normal, point, size[b], expected))
    }
}

impl Tree<'_> {
    /// `vertices` in slices `step` thick from `lo` along their `t` (one per vertex; those
    /// below `lo` left out, those past the last slice in it), and each slice's size (NaN
    /// for a slice of fewer than 8 vertices).
    pub(crate) fn slices(
        &self,
        vertices: &[u32],
        t: &[f64],
        lo: f64,
        step: f64,
        bins: usize,
    ) -> (Vec<Vec<u32>>, Vec<f64>) {
        let mut slices: Vec<Vec<u32>> = vec![Vec::new(); bins];
        for (&v, &tv) in vertices.iter().zip(t) {
            if tv >= lo && bins > 0 {
                slices[(((tv - lo) / step) as usize).min(bins - 1)].push(v);
            }
        }
        let size = slices
            .iter()
            .map(|s| if s.len() >= 8 { self.size(s) } else { f64::NAN })
            .collect();
        (slices, size)
    }
}

/// The largest of `sizes` that is a number (0 for none).
pub(crate) fn widest(sizes: &[f64]) -> f64 {
    sizes
        .iter()
        .copied()
        .filter(|s| s.is_finite())
        .fold(0.0, f64::max)
}

/// The direction along which `points` (about their mean) spread most: power iteration on
/// their covariance.
pub(crate) fn long_axis(points: impl Iterator<Item = DVec3>) -> DVec3 {
    let mut cov = glam::DMat3::ZERO;
    for p in points {
        cov += glam::DMat3::from_cols(p * p.x, p * p.y, p * p.z);
    }
    let mut axis = DVec3::new(0.577, 0.577, 0.577);
    for _ in 0..32 {
        let next = (cov * axis).normalize_or_zero();
        if next == DVec3::ZERO {
            return DVec3::Y;
        }
        axis = next;
    }
    axis
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_long_axis_is_the_way_points_spread_most() {
        let points: Vec<DVec3> = (0..40)
            .map(|k| {
                let t = k as f64 / 39.0 - 0.5;
                DVec3::new(0.1 * (k % 3) as f64 - 0.1, 2.0 * t, t)
            })
            .collect();
        let axis = long_axis(points.into_iter());
        let want = DVec3::new(0.0, 2.0, 1.0).normalize();
        assert!(axis.dot(want).abs() > 0.999, "{axis}");
    }
}
