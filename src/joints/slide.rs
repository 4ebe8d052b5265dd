//! A band's slide: as a fan band turns, each side of the band moves along the cut's
//! normal by as much as keeps its section's volume, to first order (see
//! [`super::band`]: *Volume*); an arc's child side does too (*Arcs*, below).
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
//! # A trunk's side
//! A trunk's side of the band (the root's, which does not slide) swells instead: its
//! levels on the parent's side of the cut scale about the pivot by `1 + s b(x)`, `b`
//! ([`bump`]) 0 at the band's parent end and at the cut and 1 halfway, so the limb and
//! the trunk beyond the band stay where they were and the skin around the limb's root
//! moves out from the pivot (or in) by what keeps the trunk's capped volume. A swell `s`
//! changes it by `s K′`, `K′ = Σᵢ b(xᵢ) qᵢ · ∂V′/∂pᵢ` over the trunk's vertices in the
//! band, and the child's by `s K` over the child's vertices on that side of the cut, so
//! the swell and the child's slide are solved together, `[K′ H′_c; K H] [s σ] = −Φ a ·
//! [G′ G]`, once per rig ([`Band::swell`]), and a pose costs a dot product more, `s = −Φ
//! a · swell`, at most [`MAX_SWELL`] either way. The bone points of a swollen level
//! spread by the same share. A band whose strip holds a third section's vertices (a
//! sibling's seam: the ant's and the cow's legs side by side) or carries one does not
//! swell: the sibling would scale with it (the ant's legs changed by up to 15 %). Turned
//! alone by its own turns of `bench poses`' seeds 1–20, 75 of the downloads' 552 joints
//! changed some section by more than 5 % alone, 22 of them their trunk; with the swell
//! 72 and 19 (most of those bands hold a sibling's seam; swelling every band, 8).
//!
//! # Two bends on one section
//! Where a section is bent at both ends by bands that overlap on it (a short thigh between
//! the hip's fan and the knee's band, an upper arm, a tail between two joints), each band
//! alone keeps its volume but the two together do not: their volume factors multiply,
//! `(1 + ε₁)(1 + ε₂)`, and where both compress the same side (a hip and a knee bent the
//! same way) `ε₁ ε₂` does not cancel. Turned alone, the lizard's thigh keeps its volume
//! within 1 %; turned with its knee, by 60° each, it changed by up to 13 %. That
//! second-order change, `a_xᵀ C a_y` for each pair of bands that move some vertex of the
//! section both (`a_x`, `a_y` their sections' rotation vectors), is measured once per rig
//! by turning the two by ±[`CROSS_AT`] about each pair of axes (36 volumes of the faces
//! they move, `measure_cross`), and the section's own band's two slides take it
//! back with the first-order change ([`Band::cross`], [`Band::cross_slide`]): a band's
//! slide depends on the turns of its child's children too ([`Joints::slide`]). On `bench
//! poses`, 124 → 88 of 500 poses with a section beyond ±5 %. A band's own second-order
//! change (its volume's even part, `½ aᵀ M a`) was measured too and left out: fitted per
//! band, it changed no pose where the bones hold the surface (135 → 135 beyond ±5 %).
//!
//! # Arcs
//! An arc keeps its bent centre line's length, but a child whose cross-sections lie off
//! that line (a hoof forward of its shin, a scorpion's foot) still gains on one side what
//! it loses on the other: turned alone by ±60° about four axes, the 46 arcs of the lizard,
//! the dino, the horse and the scorpion changed their child's volume by 5.4 % at the
//! median arc and 58.5 % at the worst (the horse's hoof). So an arc's child side slides
//! too, as a fan's does: its levels rise from the cut to the band's child end
//! ([`profile`]) along the normal turned with them, the child moves by the whole slide,
//! and the arc spreads the rest of the child's translation evenly along itself as before
//! ([`super::Band::motion`]). Its `G` is measured through the arc's own motion, by
//! central differences over turns by ±[`ARC_AT`] about each axis (the change is odd in
//! the turn to within 0.2 %: volumes differenced over 0.1 and 1.1 radians gave the same
//! slide, so the tangent at rest is taken, each vertex's motion dotted with the volume's
//! gradient), and `H` from the same gradient, as a fan's ([`Joints::arc_slide`]). The
//! parent's side does not slide (its bend moves the child off the pivot already), and no
//! cross term is measured for an arc. The same turns: 1.2 % at the median arc, 11.4 % at the worst (the hoof, its
//! slide held at [`MAX_SLIDE`]). Spreading the slide evenly along the whole band instead
//! (the parent's side too) kept more volume (`bench poses`: 70 poses beyond ±5 % against
//! 67 here from 77) but stretched an edge 3.12× in one settled pose; rising on the child's
//! side only, the stretch is unchanged.
//!
//! [`capped_volume_gradient`]: crate::mesh::measure::capped_volume_gradient

use super::band::{axis_angle, weight, Cross, LEVELS};
use super::{Band, Joints, Local};
use crate::mesh::measure::Capped;
use glam::{DAffine3, DMat3, DQuat, DVec3};

/// Largest slide, in local medial radii of the band: where the first order overshoots
/// (a turn near a half turn), the child moves no farther. Chosen by `puppet bench
/// poses` (20 seeds) on the development half of the shipped, in-pieces and downloaded
/// characters from ½, ¾, 1 and 1½: poses with a section beyond ±5 % 292, 275, 258, 251
/// of 860, none more past 3×, the worst stretch's 90th percentile 2.16, 2.16, 2.17,
/// 2.21; past 1 the volume gains little for the stretch it costs. The held-out half is
/// in `docs/performance-log.md`. A low-poly limb's band is a few edges long, and its
/// child needs a slide of most of a radius to keep its volume at 60°.
pub const MAX_SLIDE: f64 = 1.0;

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

/// The turn (radians) by which an arc's motion is differenced to give its child's change
/// of volume per unit of turn at rest ([`Joints::arc_slide`]; see the module docs: the
/// change is odd in the turn, so the tangent holds over the turns a pose makes).
const ARC_AT: f64 = 1e-3;

/// The turn (radians) by which two bends are turned together to measure the change they
/// make together ([`Band::cross`]).
const CROSS_AT: f64 = std::f64::consts::FRAC_PI_4;

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

/// The trunk side's swell's share at `x` across a band (`0..=1`) whose cut lies at
/// `at_cut` of its length: 0 at the band's parent end and at the cut, 1 halfway between,
/// 0 on the child's side.
pub(super) fn bump(at_cut: f64, x: f64) -> f64 {
    let u = (x / at_cut.max(1e-9)).clamp(0.0, 1.0);
    4.0 * u * (1.0 - u)
}

/// Largest swell of a trunk's side (a share of its size about the pivot; see the module
/// docs, *A trunk's side*). Chosen by `puppet bench poses` (20 seeds) on the development
/// half of the shipped, in-pieces and downloaded characters from 0.05, 0.1, 0.15 and
/// 0.25: poses with a section beyond ±5 % 244, 240, 240, 239 of 860 (258 without), 4
/// past 3× at each, the worst stretch's 90th percentile 2.159, 2.164, 2.172, 2.243; the
/// held-out half is in `docs/performance-log.md`.
pub const MAX_SWELL: f64 = 0.1;

/// How far a fan band's two sides slide along its normal in a pose (see the module
/// docs), in mesh units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Slide {
    /// The parent's side (`σ′`), rising from the band's parent end to the cut.
    pub parent: f64,
    /// The child's side (`σ`), rising from the cut to the band's child end.
    pub child: f64,
    /// A trunk's side's swell about the pivot (a share), by its [`bump`].
    pub swell: f64,
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
        // An arc's share is its place along the band; a fan's, its weight there.
        let x = if self.arc {
            w.clamp(0.0, 1.0)
        } else {
            along(w)
        };
        let at_cut = self.cut_share();
        let by = slide.parent * rise(at_cut, x) + slide.child * profile(at_cut, x);
        turned * self.normal * by
    }

    /// How far a band's two sides slide along its normal (`σ′` and `σ`, see the module
    /// docs; an arc's parent side does not) when the child turns by `rotation` and the
    /// bends overlapping on its child section change its volume together by `cross`
    /// ([`Band::cross`]): each at most [`MAX_SLIDE`] local radii either way; nothing at
    /// rest.
    pub fn slide_for(&self, rotation: DQuat, cross: f64) -> Slide {
        if self.slides() {
            self.slide_turned(turn(rotation), cross)
        } else {
            Slide::default()
        }
    }

    /// Whether the band's sides slide or swell in any pose.
    fn slides(&self) -> bool {
        self.slide != DVec3::ZERO || self.parent_slide != DVec3::ZERO || self.swell != DVec3::ZERO
    }

    /// How the bends overlapping on the child change its volume together
    /// ([`Band::cross`]), each section's turn (a rotation vector, [`turn`]) from `turn_of`.
    fn cross_turned(&self, turn_of: impl Fn(usize) -> DVec3) -> f64 {
        self.cross
            .iter()
            .map(|c| turn_of(c.x).dot(c.coefficient * turn_of(c.y)))
            .sum()
    }

    /// [`Band::slide_for`] from the child's turn as a rotation vector ([`turn`]).
    fn slide_turned(&self, a: DVec3, cross: f64) -> Slide {
        let limit = MAX_SLIDE * self.radius;
        let by = |per_turn: DVec3, per_cross: f64| {
            (-a.dot(per_turn) - cross * per_cross).clamp(-limit, limit)
        };
        Slide {
            parent: by(self.parent_slide, self.cross_slide[0]),
            child: by(self.slide, self.cross_slide[1]),
            swell: (-a.dot(self.swell)).clamp(-MAX_SWELL, MAX_SWELL),
        }
    }
}

/// The rotation vector (axis times angle, the angle `0..=π`) of the shortest turn a
/// rotation makes.
fn turn(rotation: DQuat) -> DVec3 {
    let (axis, angle) = axis_angle(rotation);
    axis * angle
}

impl Joints {
    /// How far the two sides of `band` slide in a pose whose sections turn by
    /// `rotation_of(section)` ([`Band::slide_for`], with its bends' [`Band::cross`]).
    pub fn slide(&self, band: &Band, rotation_of: impl Fn(usize) -> DQuat) -> Slide {
        let cross = band.cross_turned(|s| turn(rotation_of(s)));
        band.slide_for(rotation_of(band.child), cross)
    }

    /// [`Joints::slide`] of every band in the pose `local`, each section's turn found
    /// once (a band's cross terms read two sections' turns each): per section, the
    /// slide of the band that ends in it (nothing where none does). `turns` and
    /// `slides` are storage, refilled.
    pub(super) fn slides_into(
        &self,
        local: &[Local],
        turns: &mut Vec<DVec3>,
        slides: &mut Vec<Slide>,
    ) {
        let n = self.sections.len();
        turns.clear();
        turns.extend((0..n).map(|s| turn(local.get(s).map_or(DQuat::IDENTITY, |l| l.rotation))));
        slides.clear();
        slides.resize(n, Slide::default());
        for s in 0..n {
            let Some(band) = self.band_ending_in(s).filter(|b| b.slides()) else {
                continue;
            };
            slides[s] = band.slide_turned(turns[s], band.cross_turned(|k| turns[k]));
        }
    }
}

impl Joints {
    /// Measures every fan band's two slides per unit of turn (see the module docs) from
    /// the levels its vertices got (`entries`: vertex, band slot, level; `slots`: each slot's cut).
    /// Nothing without the mesh's triangles and rest positions.
    pub(super) fn measure_slides(
        &mut self,
        entries: &[(u32, u16, u16)],
        slots: &[usize],
        surfaces: &[Capped],
    ) {
        self.changing();
        let n = self.section_of.len();
        let body = self.body.clone();
        if body.triangles.is_empty() || body.rest.len() != n {
            return;
        }
        // Per slot, its vertices on each side with their levels.
        let mut by_slot: Vec<[Vec<(u32, u16)>; 2]> = vec![[Vec::new(), Vec::new()]; slots.len()];
        // Whether a slot's band moves a vertex of a third section (a sibling's seam in its
        // strip): a trunk's swell would scale that section's skin too.
        let mut third = vec![false; slots.len()];
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
                third[usize::from(slot)] = true;
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
        // An arc's child side slides too (its parent's does not): see `arc_slide`.
        let arc_sliding = |k: usize| {
            self.bands[k].as_ref().filter(|b| {
                b.arc && !self.cuts[k].shared_pivot && self.sections[b.child].pivot == b.pivot
            })
        };
        let mut gradient = vec![DVec3::ZERO; n];
        let mut wanted = vec![false; self.sections.len()];
        for &k in slots {
            if let Some(band) = sliding(k) {
                wanted[band.child] = true;
                wanted[band.parent] |=
                    parent_slides(k, band) || self.sections[band.parent].parent.is_none();
            }
            if let Some(band) = arc_sliding(k) {
                wanted[band.child] = true;
            }
        }
        for (capped, _) in surfaces.iter().zip(&wanted).filter(|(_, &w)| w) {
            for (v, g) in capped.volume_gradient(&body.rest) {
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
            let mut swell = [0.0; 2];
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
                    swell[side] += bump(at_cut, x) * q.dot(dv);
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
            // Per unit of the child's volume change the bends make together, each side's
            // slide (the right-hand side `[0, 1]`).
            let cross_slide = if parent_slides(k, band) && det.abs() > 1e-6 * (a * d).abs() {
                [-b / det, a / det]
            } else {
                [0.0, 1.0 / d]
            }
            .map(|x| if x.is_finite() { x } else { 0.0 });
            // A trunk's side swells instead (the child's slide moves its volume too).
            // Solved with the child's slide: `[K′ H′_c; K H] [s, σ] = −Φ a · [G′ G]`.
            let carries = self.carried.iter().any(|c| c.iter().any(|&(b, _)| b == k));
            let trunk = self.sections[band.parent].parent.is_none() && !third[slot] && !carries;
            let [kp, kc] = swell;
            let det = kp * d - b * kc;
            let (per_turn, swell) = if trunk && det.abs() > 1e-6 * (kp * d).abs() {
                let s = (turn[0] * d - turn[1] * b) / det;
                let sigma = (turn[1] * kp - turn[0] * kc) / det;
                if s.is_finite() && sigma.is_finite() {
                    (
                        [DVec3::ZERO, sigma.clamp_length_max(MAX_RATE * band.radius)],
                        s,
                    )
                } else {
                    (per_turn, DVec3::ZERO)
                }
            } else {
                (per_turn, DVec3::ZERO)
            };
            measured.push((k, per_turn, cross_slide, swell));
        }
        // Each band's cross terms on their own (in parallel: each reads the joints only,
        // with a scratch of its thread's, which it leaves as it found it).
        let crosses: Vec<Vec<Cross>> = {
            use rayon::prelude::*;
            measured
                .par_iter()
                .map_init(
                    || (body.rest.clone(), vec![false; n]),
                    |scratch, &(k, _, _, _)| {
                        self.measure_cross(k, surfaces, &by_slot, slots, scratch)
                    },
                )
                .collect()
        };
        let arcs: Vec<(usize, DVec3)> = slots
            .iter()
            .enumerate()
            .filter_map(|(slot, &k)| {
                let band = arc_sliding(k)?;
                Some((k, self.arc_slide(band, &by_slot[slot][1], &gradient)))
            })
            .collect();
        for ((k, per_turn, cross_slide, swell), cross) in measured.into_iter().zip(crosses) {
            if let Some(band) = self.bands[k].as_mut() {
                [band.parent_slide, band.slide] = per_turn;
                band.swell = swell;
                band.cross = cross;
                band.cross_slide = cross_slide;
            }
        }
        for (k, slide) in arcs {
            if let Some(band) = self.bands[k].as_mut() {
                band.slide = slide;
            }
        }
    }

    /// An arc band's child side's slide per unit of turn (see the module docs: *Arcs*):
    /// `G / H`, `G` the change of its child's capped volume per unit of turn (each band
    /// vertex's motion against the child, by central differences over turns by
    /// ±[`ARC_AT`] about each axis through the band's own motion, [`Band::motion`], dotted
    /// with its gradient), and `H` its change per unit of slide, which moves a vertex at
    /// share `w` of the band by its [`profile`] there against the child. `levels`: the
    /// child's vertices in the band with their levels; `gradient`: each vertex's gradient
    /// of its section's capped volume.
    fn arc_slide(&self, band: &Band, levels: &[(u32, u16)], gradient: &[DVec3]) -> DVec3 {
        let body = &self.body;
        let slide: f64 = levels
            .iter()
            .map(|&(i, level)| {
                let w = f64::from(level) / LEVELS as f64;
                (profile(band.cut_share(), w) - 1.0) * band.normal.dot(gradient[i as usize])
            })
            .sum();
        if levels.is_empty() || slide.abs() < f64::MIN_POSITIVE {
            return DVec3::ZERO;
        }
        let pivot = band.pivot;
        // Each level's motion against the child for a turn by `v`.
        let against_child = |v: DVec3| -> Vec<DAffine3> {
            let rotation = DQuat::from_scaled_axis(v);
            let child = DAffine3::from_translation(band.shift(rotation, Slide::default()))
                * turn_about(pivot, rotation);
            let back = child.inverse();
            (0..=LEVELS)
                .map(|l| back * band.motion(rotation, &child, l as f64 / LEVELS as f64))
                .collect()
        };
        let turn = DVec3::from_array(std::array::from_fn(|k| {
            let e = DVec3::AXES[k] * ARC_AT;
            let (plus, minus) = (against_child(e), against_child(-e));
            levels
                .iter()
                .map(|&(i, level)| {
                    let (x, l) = (body.rest[i as usize], usize::from(level));
                    let moved = plus[l].transform_point3(x) - minus[l].transform_point3(x);
                    gradient[i as usize].dot(moved) / (2.0 * ARC_AT)
                })
                .sum::<f64>()
        }));
        let per_turn = turn / slide;
        if per_turn.is_finite() {
            per_turn.clamp_length_max(MAX_RATE * band.radius)
        } else {
            DVec3::ZERO
        }
    }

    /// The bends that change the volume of the child of cut `k`'s band together (see
    /// [`Band::cross`]): each pair of bands that moves some of its vertices both (its own
    /// band's child side and a child's band's parent side, or two children's), with the
    /// second-order change they make together, measured by turning the two by
    /// ±[`CROSS_AT`] about each pair of axes. `surfaces`: each section's, capped; `by_slot`:
    /// each slot's vertices on its parent's and child's side with their levels.
    fn measure_cross(
        &self,
        k: usize,
        surfaces: &[Capped],
        by_slot: &[[Vec<(u32, u16)>; 2]],
        slots: &[usize],
        scratch: &mut (Vec<DVec3>, Vec<bool>),
    ) -> Vec<Cross> {
        let Some(own) = self.bands[k].as_ref() else {
            return Vec::new();
        };
        let section = own.child;
        // The bends on the section: its own band's child side, then its children's
        // bands' parent sides; each with its vertices' levels.
        let mut bends: Vec<Bend> = Vec::new();
        for (slot, &c) in slots.iter().enumerate() {
            let Some(band) = self.bands[c].as_ref() else {
                continue;
            };
            let side = if c == k {
                1
            } else if band.parent == section {
                0
            } else {
                continue;
            };
            bends.push(Bend {
                band,
                own: c == k,
                levels: &by_slot[slot][side],
            });
        }
        // The own band first, the children's in slot order: the order a vertex's
        // motions compose in.
        bends.sort_by_key(|e| !e.own);
        if bends.len() < 2 {
            return Vec::new();
        }
        let Some(region) = surfaces.get(section) else {
            return Vec::new();
        };
        let body = &self.body;
        let (at, is_moved) = scratch;
        // The motion of bend `e` turned by the rotation vector `v` at each level,
        // relative to the section.
        let motions = |e: &Bend, v: DVec3, into: &mut Vec<DAffine3>| {
            let (band, own) = (e.band, e.own);
            let rotation = DQuat::from_scaled_axis(v);
            let pivot = self.sections[band.child].pivot;
            let child = DAffine3::from_translation(band.shift(rotation, Slide::default()))
                * turn_about(pivot, rotation);
            into.clear();
            into.extend((0..=LEVELS).map(|level| {
                let w = level as f64 / LEVELS as f64;
                if own {
                    // The child's side against the child: turned back by `1 − w`.
                    turn_about(pivot, DQuat::from_scaled_axis(v * (w - 1.0)))
                } else if band.arc {
                    band.motion(rotation, &child, w)
                } else {
                    turn_about(pivot, DQuat::from_scaled_axis(v * w))
                }
            }));
        };
        let (mut of_x, mut of_y) = (Vec::new(), Vec::new());
        let mut cross = Vec::new();
        for x in 0..bends.len() {
            for y in x + 1..bends.len() {
                // Every vertex either bend moves, at its weight in each (the own band's
                // child side at 1 elsewhere, a child's parent side at 0), if some vertex
                // moves with both.
                let at_y: std::collections::HashMap<u32, u16> =
                    bends[y].levels.iter().copied().collect();
                let rest_weight = |e: usize| if bends[e].own { LEVELS as u16 } else { 0 };
                let mut moved: Vec<(u32, u16, u16)> = bends[x]
                    .levels
                    .iter()
                    .map(|&(i, wx)| (i, wx, at_y.get(&i).copied().unwrap_or(rest_weight(y))))
                    .collect();
                if !moved.iter().any(|m| at_y.contains_key(&m.0)) {
                    continue;
                }
                let in_x: std::collections::HashSet<u32> =
                    bends[x].levels.iter().map(|&(i, _)| i).collect();
                moved.extend(
                    bends[y]
                        .levels
                        .iter()
                        .filter(|(i, _)| !in_x.contains(i))
                        .map(|&(i, wy)| (i, rest_weight(x), wy)),
                );
                for &(i, _, _) in &moved {
                    is_moved[i as usize] = true;
                }
                let part = region.around(|v| is_moved[v as usize]);
                for &(i, _, _) in &moved {
                    is_moved[i as usize] = false;
                }
                let apex = self.sections[section].pivot;
                let rest_volume = part.volume_from(at, apex);
                let mut change = |vx: DVec3, vy: DVec3| {
                    motions(&bends[x], vx, &mut of_x);
                    motions(&bends[y], vy, &mut of_y);
                    for &(i, lx, ly) in &moved {
                        let m = of_x[usize::from(lx)] * of_y[usize::from(ly)];
                        at[i as usize] = m.transform_point3(body.rest[i as usize]);
                    }
                    let v = part.volume_from(at, apex) - rest_volume;
                    for &(i, _, _) in &moved {
                        at[i as usize] = body.rest[i as usize];
                    }
                    v
                };
                let mut coefficient = [[0.0; 3]; 3];
                let axes = [DVec3::X, DVec3::Y, DVec3::Z];
                for (i, &ex) in axes.iter().enumerate() {
                    for (j, &ey) in axes.iter().enumerate() {
                        let mut sum = 0.0;
                        for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                            sum += sx * sy * change(ex * (sx * CROSS_AT), ey * (sy * CROSS_AT));
                        }
                        // Column `j`, row `i`: `a_xᵀ C a_y`.
                        coefficient[j][i] = sum / (4.0 * CROSS_AT * CROSS_AT);
                    }
                }
                let coefficient = DMat3::from_cols_array_2d(&coefficient);
                if coefficient.is_finite() {
                    cross.push(Cross {
                        x: bends[x].band.child,
                        y: bends[y].band.child,
                        coefficient,
                    });
                }
            }
        }
        cross
    }
}

/// A band that bends a section ([`Joints::measure_cross`]): the section's own band's
/// child side, or a child's band's parent side, with the levels of its vertices there.
struct Bend<'a> {
    band: &'a Band,
    own: bool,
    levels: &'a [(u32, u16)],
}

/// A turn by `rotation` about `pivot`.
fn turn_about(pivot: DVec3, rotation: DQuat) -> DAffine3 {
    DAffine3::from_translation(pivot)
        * DAffine3::from_quat(rotation)
        * DAffine3::from_translation(-pivot)
}
