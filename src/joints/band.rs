//! Joint bands (paper §5, "joint points"): the bone points near a cut move at a rate
//! between the two sections, so a bent joint is a smooth bend instead of a hinge whose skin
//! folds over a corner.
//!
//! Each cut has a band of half-width `W = band × r` about its plane, `r` the local medial
//! radius (the median skeletal distance of the child's vertices nearest the plane) and
//! `band` the cut's factor ([`Cut::band`], [`DEFAULT_BAND`] when unset; 0 is a hinge).
//! A vertex of the child or the parent whose skeletal point lies at signed distance `d`
//! from the plane (positive into the child), `|d| < W`, moves with the weight
//! `w = smoothstep((d + W) / 2W)` of the child's own motion: its transform is
//!
//! `W(parent) · T(pivot + w·t) · slerp(I, R, w) · T(−pivot)`
//!
//! (`R`, `t` the child's local rotation and translation): a rotation about the cut's pivot
//! by a fraction of the child's angle. Interpolating the rotation, not the matrices, keeps
//! every blended bone point at its distance from the pivot, so the limb does not shrink
//! through the bend. Nested cuts compose because each band blends a child with its own
//! parent's world transform.
//!
//! A parent vertex joins the band only on the parent's side of the plane and near the
//! pivot (within the child's cross-section, `2.5 r` from the pivot in the plane), so the
//! other leg at a hip cut or the body beside a shoulder stays put.
//!
//! The weight is quantised to [`LEVELS`] steps: the simulation gets one transform per
//! level and band (after the sections' own) and each vertex the index of its transform, so
//! the step's kernel is unchanged and a joint that does not bend wakes nothing.

use super::{Cut, Joints};
use glam::DVec3;

/// Band half-width in local medial radii when a cut does not say: 0, a hinge, until the
/// measurements of issue 26 (self-intersections, volume, dihedral angles at 45–135°)
/// choose the default.
pub const DEFAULT_BAND: f64 = 0.0;

/// Largest band factor accepted.
pub const MAX_BAND: f64 = 4.0;

/// Weight steps per band (the transforms between the parent's, level 0, and the child's).
pub const LEVELS: usize = 64;

/// Most transforms the simulation can index (it stores a `u16` per vertex).
const MAX_TRANSFORMS: usize = u16::MAX as usize + 1;

/// One cut's band.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// The section the cut made.
    pub child: usize,
    /// Its parent now.
    pub parent: usize,
    /// Half-width of the band (mesh units).
    pub width: f64,
    /// The local medial radius it was measured from.
    pub radius: f64,
}

impl Cut {
    /// The band factor this cut uses (its own, or [`DEFAULT_BAND`]), clamped to
    /// `0..=MAX_BAND`; 0 when not finite.
    pub fn band_factor(&self) -> f64 {
        let b = self.band.unwrap_or(DEFAULT_BAND);
        if b.is_finite() {
            b.clamp(0.0, MAX_BAND)
        } else {
            0.0
        }
    }
}

fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

impl Joints {
    /// The bands of the cuts, in cut order (`None` for a hinge: band 0, or no radii).
    pub fn bands(&self) -> &[Option<Band>] {
        &self.bands
    }

    /// Per vertex, the transform it moves with: its section's (`< sections().len()`), or a
    /// band level's (see the module docs). What the simulation is given.
    pub fn transform_of(&self) -> &[u16] {
        &self.transform_of
    }

    /// Sets the band factor of the cut named `name` (`None`: the default); returns false
    /// when there is no such cut.
    pub fn set_band(&mut self, name: &str, band: Option<f64>) -> bool {
        let Some(cut) = self.cuts.iter_mut().find(|c| c.name == name) else {
            return false;
        };
        cut.band = band
            .filter(|b| b.is_finite())
            .map(|b| b.clamp(0.0, MAX_BAND));
        self.refresh_bands();
        true
    }

    /// Recomputes the bands and every vertex's transform (after the cuts changed).
    pub(super) fn refresh_bands(&mut self) {
        let n = self.section_of.len();
        self.transform_of.clone_from(&self.section_of);
        self.bands = vec![None; self.cuts.len()];
        if self.body.radius.len() != n {
            return;
        }
        let sections = self.sections.len();
        // Per vertex, how deep inside its band it is (|d| / W); the nearest plane wins.
        let mut depth = vec![f64::INFINITY; n];
        let mut slot = 0;
        for (k, cut) in self.cuts.iter().enumerate() {
            let factor = cut.band_factor();
            let Some(child) = self.find(&cut.name) else {
                continue;
            };
            let Some(parent) = self.sections[child].parent else {
                continue;
            };
            let first = sections + slot * (LEVELS - 1);
            if factor <= 0.0 || first + LEVELS - 1 > MAX_TRANSFORMS {
                continue;
            }
            let normal = cut.normal.normalize_or_zero();
            let pivot = self.sections[child].pivot;
            let own = |i: usize| !self.body.is_rider(i);
            let signed = |i: usize| (self.body.points[i] - cut.point).dot(normal);
            // The local medial radius: the child's vertices nearest the plane.
            let mut near: Vec<(f64, f64)> = (0..n)
                .filter(|&i| own(i) && self.section_of[i] as usize == child)
                .map(|i| (signed(i).abs(), self.body.radius[i]))
                .collect();
            if near.is_empty() {
                continue;
            }
            let m = (near.len() / 50).max(8).min(near.len());
            near.select_nth_unstable_by(m - 1, |a, b| a.0.total_cmp(&b.0));
            let mut radii: Vec<f64> = near[..m].iter().map(|x| x.1).collect();
            radii.sort_by(f64::total_cmp);
            let radius = radii[radii.len() / 2];
            let width = factor * radius;
            if !(width.is_finite() && width > 0.0) {
                continue;
            }
            let reach = 2.5 * radius;
            let in_plane = |p: DVec3| {
                let v = p - pivot;
                (v - normal * v.dot(normal)).length()
            };
            for i in (0..n).filter(|&i| own(i)) {
                let s = self.section_of[i] as usize;
                let d = signed(i);
                let member = (s == child && d < width)
                    || (s == parent
                        && d <= 0.0
                        && d > -width
                        && in_plane(self.body.points[i]) <= reach);
                if !member || d.abs() / width >= depth[i] {
                    continue;
                }
                let w = smoothstep((d + width) / (2.0 * width));
                let level = (w * LEVELS as f64).round() as usize;
                depth[i] = d.abs() / width;
                self.transform_of[i] = match level {
                    0 => parent as u16,
                    l if l >= LEVELS => child as u16,
                    l => (first + l - 1) as u16,
                };
            }
            self.bands[k] = Some(Band {
                child,
                parent,
                width,
                radius,
            });
            slot += 1;
        }
        // Riders move with their host.
        for i in 0..n {
            if let Some(&h) = self.body.host.get(i).filter(|&&h| h != super::NO_HOST) {
                self.transform_of[i] = self.transform_of[h as usize];
            }
        }
    }
}
