//! A fan's slide: as a fan band turns, each side of the band moves along the cut's
//! normal by as much as keeps its section's volume, to first order (see
//! [`super::band`]: *Volume*).
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
//! nods.
//!
//! The parent's side of the band bends too, and changes the parent's volume `V′` the
//! same way (a thigh under a turning shin, a head under a turning ear) by
//! `Φ a · G′`, `G′ = Σᵢ wᵢ qᵢ × ∂V′/∂pᵢ` over the parent's vertices in the band. Its own
//! slide `σ′`, rising evenly from the band's parent end to 1 at the cut ([`rise`]; the
//! child's side and the child move with it whole), changes `V′` by `σ′ H′`. A vertex of
//! either section may lie at a level across the cut, so each slide moves both volumes a
//! little: the two are solved together, `[H′ H′_c; H_p H] [σ′ σ] = −Φ a · [G′ G]`, and
//! the child moves by both. A trunk's side (the root's) does not slide: there the normal
//! is the limb's, across the trunk's own surface, so its slide moved the limb in and out
//! of the body (the robot's arms met its chest 1° sooner, a leg crossed with soft flesh
//! squashed 4 times deeper), for 10 of 500 poses of `bench poses` beyond ±5 % it saved.
//! Nor does the side of a child that turns about a hinge at the cut's rim (a pivot more
//! than a local radius off the cut's centre line: a jaw hinged at its back, 1.3 radii
//! off; over the population's bands at most 1.0): its slide moved the hinge, and the
//! jaw's tip opened a third as far.
//!
//! Both are measured once per rig ([`Band::slide`] and [`Band::parent_slide`], per unit
//! of turn), so a pose costs two dot products, `σ = −Φ a · slide`, each at most
//! [`MAX_SLIDE`] local radii either way. A child that turns about a hinge it shares (a
//! jaw, and the head whose pivot that hinge is) does not slide: it must stay on the
//! hinge.
//!
//! In a pose the skin slides along the normal turned with it ([`Band::slid`]: at share
//! `w` of the band, `slerp(I, R, w) n`), the band's own direction there; to first order
//! this is the slide above. Along the parent's unturned normal, a head turned 80° slid
//! sideways instead of lengthening its neck, and kept its volume no better than half as
//! well (the koala's ear +24.6 % against −11.9 %; `bench poses`: 139 poses of 500 with a
//! section beyond ±5 % against 124).
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

/// The child side's slide's share at `x` across a band (`0..=1`) whose cut lies at
/// `at_cut` of its length: 0 on the parent's side, rising evenly along the band from the
/// cut to 1 at the child's end.
pub(super) fn profile(at_cut: f64, x: f64) -> f64 {
    ((x - at_cut) / (1.0 - at_cut).max(1e-9)).clamp(0.0, 1.0)
}

/// The parent side's slide's share at `x` across a band (`0..=1`) whose cut lies at
/// `at_cut` of its length: rising evenly from 0 at the band's parent end to 1 at the
/// cut, 1 beyond.
pub(super) fn rise(at_cut: f64, x: f64) -> f64 {
    (x / at_cut.max(1e-9)).clamp(0.0, 1.0)
}

/// How far a fan band's two sides slide along its normal in a pose (see the module
/// docs), in mesh units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Slide {
    /// The parent's side (`σ′`), rising from the band's parent end to the cut.
    pub parent: f64,
    /// The child's side (`σ`), rising from the cut to the band's child end.
    pub child: f64,
}

impl Band {
    /// How far the bone points that move with share `w` of the child's motion slide
    /// when the band's two sides slide by `slide`: each side's slide by its share at `w`
    /// ([`rise`], [`profile`]), along the normal turned by `turned` (those bone points'
    /// share of the child's turn: the band's own direction there, so a neck lengthens
    /// along itself when the head is turned far).
    pub(super) fn slid(&self, turned: DQuat, slide: Slide, w: f64) -> DVec3 {
        if slide == Slide::default() {
            return DVec3::ZERO;
        }
        let (x, at_cut) = (along(w), self.cut_share());
        let by = slide.parent * rise(at_cut, x) + slide.child * profile(at_cut, x);
        turned * self.normal * by
    }

    /// How far a fan's two sides slide along its normal (`σ′` and `σ`, see the module
    /// docs) when the child turns by `rotation`: each at most [`MAX_SLIDE`] local radii
    /// either way; nothing for an arc, or at rest.
    pub fn slide_for(&self, rotation: DQuat) -> Slide {
        if self.arc || (self.slide == DVec3::ZERO && self.parent_slide == DVec3::ZERO) {
            return Slide::default();
        }
        let q = if rotation.w < 0.0 {
            -rotation
        } else {
            rotation
        };
        let (axis, angle) = q.normalize().to_axis_angle();
        let limit = MAX_SLIDE * self.radius;
        let by = |per_turn: DVec3| (-angle * axis.dot(per_turn)).clamp(-limit, limit);
        Slide {
            parent: by(self.parent_slide),
            child: by(self.slide),
        }
    }
}

impl Joints {
    /// Measures every fan band's two slides per unit of turn (see the module docs) from
    /// the levels its vertices got (`entries`: vertex, band slot, level; `slots`: each slot's cut).
    /// Nothing without the mesh's triangles and rest positions.
    pub(super) fn measure_slides(&mut self, entries: &[(u32, u16, u16)], slots: &[usize]) {
        let n = self.section_of.len();
        let body = self.body.clone();
        if body.triangles.is_empty() || body.rest.len() != n {
            return;
        }
        // Each section's faces, and each slot's vertices on either side with their levels.
        let mut faces: Vec<Vec<[u32; 3]>> = vec![Vec::new(); self.sections.len()];
        for t in &body.triangles {
            let s = self.section_of[t[0] as usize];
            if t.iter().all(|&i| self.section_of[i as usize] == s) {
                faces[usize::from(s)].push(*t);
            }
        }
        // Per slot, its vertices on each side with their levels.
        let mut by_slot: Vec<[Vec<(u32, u16)>; 2]> = vec![[Vec::new(), Vec::new()]; slots.len()];
        for &(i, slot, level) in entries {
            let Some(band) = self.bands[slots[usize::from(slot)]].as_ref() else {
                continue;
            };
            let s = usize::from(self.section_of[i as usize]);
            let side = if s == band.child {
                1
            } else if s == band.parent {
                0
            } else {
                continue;
            };
            by_slot[usize::from(slot)][side].push((i, level));
        }
        // A child that turns about a hinge it shares (a jaw and its head) stays on it:
        // only one that turns about its own cut's pivot slides.
        let sliding = |k: usize| {
            self.bands[k].as_ref().filter(|b| {
                !b.arc && !self.cuts[k].shared_pivot && self.sections[b.child].pivot == b.pivot
            })
        };
        // Whether a sliding band's parent side slides too: not a trunk's (the root's),
        // nor one under a child hinged at the cut's rim (a jaw: the hinge stays put; see
        // the module docs).
        let parent_slides = |k: usize, band: &Band| {
            let pivot = self.sections[band.child].pivot;
            let rim = (self.cuts[k].point - pivot)
                .reject_from(band.normal)
                .length()
                > band.radius;
            self.sections[band.parent].parent.is_some() && !rim
        };
        // Each vertex's gradient of its own section's capped volume, where a side slides.
        let mut gradient = vec![DVec3::ZERO; n];
        let mut wanted = vec![false; self.sections.len()];
        for &k in slots {
            if let Some(band) = sliding(k) {
                wanted[band.child] = true;
                wanted[band.parent] |= parent_slides(k, band);
            }
        }
        for (faces, _) in faces.iter().zip(&wanted).filter(|(_, &w)| w) {
            for (v, g) in capped_volume_gradient(&body.rest, faces) {
                gradient[v as usize] = g;
            }
        }
        let mut measured = Vec::new();
        for (slot, &k) in slots.iter().enumerate() {
            let Some(band) = sliding(k) else {
                continue;
            };
            let pivot = self.sections[band.child].pivot;
            let at_cut = band.cut_share();
            // Per side (parent, child): how its capped volume changes per unit of turn
            // (`G`; the child's side turns by `w − 1` of the turn against the child, the
            // parent's by `w` against the parent) and per unit of each side's slide (`H`:
            // a vertex of either section may lie at a level across the cut).
            let mut turn = [DVec3::ZERO; 2];
            let mut slide = [[0.0; 2]; 2];
            for side in 0..2 {
                for &(i, level) in &by_slot[slot][side] {
                    let w = f64::from(level) / LEVELS as f64;
                    let x = along(w);
                    let dv = gradient[i as usize];
                    let q = body.rest[i as usize] - pivot;
                    // The child's vertices move against the child, which moves by both.
                    let against = if side == 1 { 1.0 } else { 0.0 };
                    turn[side] += q.cross(dv) * (w - against);
                    let normal = band.normal.dot(dv);
                    slide[side][0] += (rise(at_cut, x) - against) * normal;
                    slide[side][1] += (profile(at_cut, x) - against) * normal;
                }
            }
            // Both slides together keep both volumes: `H [σ′, σ] = −Φ a · [G′, G]`.
            let [[a, b], [c, d]] = slide;
            let det = a * d - b * c;
            let per_turn = if !parent_slides(k, band) {
                [DVec3::ZERO, turn[1] / d]
            } else if det.abs() > 1e-6 * (a * d).abs() {
                [
                    (turn[0] * d - turn[1] * b) / det,
                    (turn[1] * a - turn[0] * c) / det,
                ]
            } else {
                [turn[0] / a, turn[1] / d]
            }
            .map(|v| {
                if v.is_finite() {
                    v.clamp_length_max(MAX_RATE * band.radius)
                } else {
                    DVec3::ZERO
                }
            });
            measured.push((k, per_turn));
        }
        for (k, per_turn) in measured {
            if let Some(band) = self.bands[k].as_mut() {
                [band.parent_slide, band.slide] = per_turn;
            }
        }
    }
}
