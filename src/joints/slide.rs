//! A fan's slide: as a fan band turns, its child's end of the band moves along the cut's
//! normal by as much as keeps the child's volume, to first order (see [`super::band`]:
//! *Volume*).
//!
//! A fan turns the skin at share `w` of the band by `w` of the child's turn about the
//! pivot. Where the child's cross-sections do not lie centred on the pivot's line (a
//! head forward of its neck's pivot, an arm whose pivot is on the body's side), the side
//! the turn compresses is not the side it stretches, and the child gains or loses volume
//! in proportion to the angle: one way for a nod, the other way for the opposite nod
//! (turned alone by 60°, the koala's arm +13.2 … −13.1 %, the dog's tail +8.7 … −8.8 %).
//!
//! The child's capped volume `V` (its faces, each cut across it closed by a fan from the
//! cut's centroid, as `bench poses` measures it: [`capped_volume_gradient`]) changes, for
//! a turn by the rotation vector `Φ a`, by `Φ a · G` to first order, with
//! `G = Σᵢ (wᵢ − 1) qᵢ × ∂V/∂pᵢ` over the child's vertices in the band (`qᵢ` from the
//! pivot; the rest of the child turns whole, and no rigid motion changes `V`). Moving
//! the band's skin by `σ g(w)` along the normal `n`, with `g` ([`profile`]) 0 up to the
//! seam and rising evenly to 1 at the band's child end (the child moves by `σ n` with
//! it: [`super::Band::shift`]), changes `V` by `σ H`, `H = Σᵢ (g(wᵢ) − 1) n · ∂V/∂pᵢ`:
//! the child's side of the band lengthens or shortens, as a neck does when the head
//! nods. The parent's skin does not slide (sliding it too, across a trunk where the
//! normal is the trunk's own, stretched its edges: 99 % of edges within 1.5× on up to
//! three characters fewer). `G` and `H` are measured once per rig ([`super::Band::slide`] is
//! `G / H`), so a pose costs a dot product: `σ = −Φ a · G / H`, at most [`MAX_SLIDE`]
//! local radii either way. A child that turns about a hinge it shares (a jaw, and the
//! head whose pivot that hinge is) does not slide: it must stay on the hinge.
//!
//! [`capped_volume_gradient`]: crate::mesh::measure::capped_volume_gradient

use super::band::{weight, LEVELS};
use super::{Band, Joints};
use crate::mesh::measure::capped_volume_gradient;
use glam::{DQuat, DVec3};

/// Largest slide, in local medial radii of the band: where the first order overshoots
/// (a turn near a half turn), the child moves no farther. Chosen by `puppet bench
/// poses` on half of its characters from ¼, ½ and 1: with 1 the largest worst stretch
/// rose 7 % over no slide (with ½, 3 %) for one pose fewer with a section beyond ±5 %.
pub const MAX_SLIDE: f64 = 0.5;

/// Where across a fan band (`x`, `0..=1`) its share of the child's motion is `w`: the
/// inverse of [`weight`].
pub(super) fn along(w: f64) -> f64 {
    let w = w.clamp(0.0, 1.0);
    // At a level (what a pose asks for), from a table made once.
    let step = w * LEVELS as f64;
    if step.fract() == 0.0 {
        static AT_LEVELS: std::sync::OnceLock<[f64; LEVELS + 1]> = std::sync::OnceLock::new();
        let table = AT_LEVELS
            .get_or_init(|| std::array::from_fn(|k| invert_weight(k as f64 / LEVELS as f64)));
        return table[step as usize];
    }
    invert_weight(w)
}

/// [`along`] by Newton's method from `x = w`: the slope of [`weight`] is 0.5 … 1.25, so
/// it converges to rounding in a few steps.
fn invert_weight(w: f64) -> f64 {
    let mut x = w;
    for _ in 0..8 {
        let slope = 0.5 * (6.0 * x * (1.0 - x) + 1.0);
        x = (x - (weight(x) - w) / slope).clamp(0.0, 1.0);
    }
    x
}

/// Largest slide per radian of turn, in local medial radii: where `H` is near zero (a
/// child whose volume a slide hardly changes) `G / H` says little, and a small turn
/// should not slide the child its largest. Over the 223 fan bands of `bench poses` the
/// measured rate is 0.15 radii per radian at the median, 0.52 at the 90th percentile,
/// 3.5 at the 99th; with this cap the population's figures are unchanged.
pub const MAX_RATE: f64 = 2.0;

/// The slide's share at share `w` of a fan band whose cut lies at `at_cut` of its
/// length: 0 on the parent's side, rising evenly along the band from the cut to 1 at
/// the child's end.
pub(super) fn profile(at_cut: f64, w: f64) -> f64 {
    ((along(w) - at_cut) / (1.0 - at_cut).max(1e-9)).clamp(0.0, 1.0)
}

impl Band {
    /// How far a fan's child end slides along its normal (`σ`, see the module docs) when
    /// the child turns by `rotation`: at most [`MAX_SLIDE`] local radii either way; 0
    /// for an arc, or at rest.
    pub fn slide_for(&self, rotation: DQuat) -> f64 {
        if self.arc || self.slide == DVec3::ZERO {
            return 0.0;
        }
        let q = if rotation.w < 0.0 {
            -rotation
        } else {
            rotation
        };
        let (axis, angle) = q.normalize().to_axis_angle();
        let limit = MAX_SLIDE * self.radius;
        (-angle * axis.dot(self.slide)).clamp(-limit, limit)
    }
}

impl Joints {
    /// Measures every fan band's slide (`G / H`, see the module docs) from the levels
    /// its vertices got (`entries`: vertex, band slot, level; `slots`: each slot's cut).
    /// Nothing without the mesh's triangles and rest positions.
    pub(super) fn measure_slides(&mut self, entries: &[(u32, u16, u16)], slots: &[usize]) {
        let n = self.section_of.len();
        let body = self.body.clone();
        if body.triangles.is_empty() || body.rest.len() != n {
            return;
        }
        // Each section's faces, and each slot's vertices in its child with their levels.
        let mut faces: Vec<Vec<[u32; 3]>> = vec![Vec::new(); self.sections.len()];
        for t in &body.triangles {
            let s = self.section_of[t[0] as usize];
            if t.iter().all(|&i| self.section_of[i as usize] == s) {
                faces[usize::from(s)].push(*t);
            }
        }
        let mut by_slot: Vec<Vec<(u32, u16)>> = vec![Vec::new(); slots.len()];
        for &(i, slot, level) in entries {
            let child = self.bands[slots[usize::from(slot)]]
                .as_ref()
                .map(|b| b.child);
            if child == Some(usize::from(self.section_of[i as usize])) {
                by_slot[usize::from(slot)].push((i, level));
            }
        }
        let mut gradient = vec![DVec3::ZERO; n];
        for (slot, &k) in slots.iter().enumerate() {
            // A child that turns about a hinge it shares (a jaw and its head) stays on it:
            // only one that turns about its own cut's pivot slides.
            let own_pivot =
                |b: &&Band| !self.cuts[k].shared_pivot && self.sections[b.child].pivot == b.pivot;
            let Some(band) = self.bands[k].as_ref().filter(|b| !b.arc).filter(own_pivot) else {
                continue;
            };
            let pairs = capped_volume_gradient(&body.rest, &faces[band.child]);
            for &(v, g) in &pairs {
                gradient[v as usize] = g;
            }
            let pivot = self.sections[band.child].pivot;
            let at_cut = band.cut_share();
            let (mut turn, mut slide) = (DVec3::ZERO, 0.0);
            for &(i, level) in &by_slot[slot] {
                let w = f64::from(level) / LEVELS as f64;
                let dv = gradient[i as usize];
                turn += (body.rest[i as usize] - pivot).cross(dv) * (w - 1.0);
                slide += (profile(at_cut, w) - 1.0) * band.normal.dot(dv);
            }
            for &(v, _) in &pairs {
                gradient[v as usize] = DVec3::ZERO;
            }
            let per_turn = turn / slide;
            let band = self.bands[k].as_mut().expect("a band");
            band.slide = if per_turn.is_finite() {
                per_turn.clamp_length_max(MAX_RATE * band.radius)
            } else {
                DVec3::ZERO
            };
        }
    }
}
