//! Joint bands (paper §5, "joint points"): the bone points near a cut move at a rate
//! between the two sections, so a bent joint is a smooth bend instead of a hinge whose skin
//! folds over a corner.
//!
//! Each cut has a band of half-width `W = band × r` about its plane (a sphere's or a box's
//! surface alike: `d` below is the signed distance from it, [`super::Shape`]), `r` the local
//! medial radius (the median skeletal distance of the child's vertices nearest the cut) and
//! `band` the cut's factor ([`Cut::band`], [`DEFAULT_BAND`] when unset; 0 is a hinge),
//! but never wider than the child reaches beyond the cut (its skeletal points' largest
//! `d`), so the far end of a short section (a jaw, a head on a short neck) turns whole.
//! On the child's side the band also ends where the child stops being a limb of about
//! that radius ([`BULB`]; at least half of `W`): a head beyond its neck turns whole
//! and the neck takes the bend. Across a face the skeleton is too uneven to blend by
//! (the two lips' skeletal points lie centimetres apart): a band reaching into it turns
//! neighbouring vertices by different angles and the lips cross (`bench collide`, the
//! head bent into a shoulder).
//! A vertex of the child or the parent whose skeletal point lies at signed distance `d`
//! from the plane (positive into the child), `−W < d < W_c` (`W_c ≤ W` the child's side),
//! lies at `x = (d + W) / (W + W_c)` across the band (a child's vertex only where it is
//! joined to the seam through such vertices: a limb that curls back to the plane is not
//! in the band there). That is the first guess; the share
//! `x` each vertex gets is then blended over the surface around the cut's seam
//! ([`super::blend`]: across a face or a thick trunk neighbouring skeletal points lie far
//! apart, and the skin between them tore), and the vertex moves with a share `w` of the
//! child's motion, in one of two ways.
//!
//! **An arc, where two limbs meet** (an elbow, a knee, a finger's joint): the parent is
//! a limb too, its skeleton a line along its axis (at most [`ARC_SPREAD`] of its
//! skeletal points on the band's parent side lie more than `r` from the pivot's line; a
//! trunk's skeleton is a sheet across it), and the child turns about its own cut's pivot
//! (a part that shares a hinge, a jaw and its head, stays on the hinge). The band bends like a bent tube:
//! `w = x`, and the bone points at `w` turn by `Q(w) = slerp(I, R, w)` (`R` the child's
//! local rotation) about the point of a bent centre line,
//!
//! `T(c(w)) · Q(w) · T(−(s + n·w·L))`, with `c(w) = s + L ∫₀ʷ Q(u) n du + w·e`
//!
//! (`s` the band's parent end on the cut's normal `n` through the pivot, `L = W + W_c`,
//! `e` what the arc does not give: the child's translation). Each level stays square to
//! the centre line, which turns at the same rate all along it and keeps its length: a
//! 90° bend of a band `±4 r` is a quarter circle of radius `5.1 r`, its inner side `4.1 r`
//! from the centre. So the child does not turn about its pivot alone: it also moves by
//! [`Band::shift`], where the bent centre line takes its end (at 90°, about `1.5 r`
//! towards the inside of the bend and along the limb). Pinned at the pivot instead, the
//! centre line must either shorten (a quarter circle of radius `W` loses a fifth of the
//! band's length at 90°, and the compressed skin buckles: `bench joints` read +52° to
//! +170° at 90°) or turn twice as fast at the pivot as on average (the fan below).
//!
//! **A fan, where a limb leaves a trunk** (a shoulder, a neck on a body, a finger on a
//! palm): the trunk does not bend with the limb, and a shoulder's arc would slide the
//! chest's skin beside the armpit (`bench collide`: 17 faces crossing with the arms
//! down 95°, against none). `w = weight(x)` ([`weight`]) and the transform is
//!
//! `T(pivot + w·t) · slerp(I, R, w) · T(−pivot)`
//!
//! (`t` the child's local translation, `pivot` the point it turns about): a rotation about
//! the pivot by a share of the child's angle, so every blended bone point keeps its
//! distance from the pivot.
//!
//! Either way the transform is relative to the parent's world transform, so nested cuts
//! compose.
//!
//! **Carried**: a band blends the parent's skin over a strip as wide as the joint is
//! thick ([`super::blend`]), and that strip can reach the seam of one of the parent's
//! other children (a wide head's band reaches the shoulders). Such a sibling, where its
//! seam moves with at least [`CARRY_MIN`] of the turn, rides on the band whole: at its
//! seam's mean share of the band's motion (its vertices next to the parent's, in a first
//! blend), its world transform is `W(parent) · M_band(share) · own`, so its far end
//! moves with its seam instead of staying behind (sheared so, the stuffed toy's arms
//! changed their volume by up to 42 % in random poses), and the parent's skin around its
//! seam blends from that share.
//! A thicker joint's band carries its thinner siblings, never the other way round (by
//! the bands' local radii), so the bands that move a vertex compose in one order, the
//! carrier first.
//!
//! A parent vertex joins the band only on the parent's side of the plane and near the
//! pivot (within the child's cross-section, `2.5 r` from the pivot across the normal of the
//! cut's surface there), so the other leg at a hip cut or the body beside a shoulder stays
//! put.
//!
//! # Volume
//! Turning part of the bone points by part of the angle keeps a symmetric cross-section's
//! volume to first order (the inner side is compressed as much as the outer is stretched,
//! and an arc keeps its centre line's length),
//! but the simulated skin does not: the stretched outer side pulls in like a rubber band
//! over a bend. So a bent band also swells across the cut's normal, away from the pivot's
//! line, by `BULGE · φ · 4w(1 − w)` of each vertex's distance from it (`φ` the bend angle in
//! radians, `w` the weight): nothing at the band's ends or at rest, most at its middle. The
//! swelling moves a vertex with its bone points (a translation in its contact transform,
//! below), so the bone springs keep their lengths and the constraints stay feasible. [`BULGE`] is chosen by
//! `puppet bench joints` (the region's volume within 3 % at 45–135° on the human elbow and
//! knee and two finger joints, `BENCHMARKS.md`).
//!
//! A fan keeps a symmetric child's volume, but not one whose cross-sections lie off the
//! pivot's line (a head forward of its neck), nor its parent's: each side of the band
//! lengthens or shortens along the normal by what keeps its section's volume to first
//! order, and the child moves with both ([`super::slide`], [`Band::shift`]).
//!
//! # Contacts
//! Bent far enough, the inner sides of the two parts of a limb meet (at 135° a limb of
//! radius `r` overlaps itself up to `2.4 r` from the pivot in a fan; an arc's inner side
//! folds only where the band is shorter than the limb is thick). The two sides then meet
//! on the *contact plane*: for a fan, through the pivot, halfway between the cut's plane
//! and the child's turned one; for an arc, the cut's surface where the band's motion
//! takes it. Every vertex moving with the band's parent, child or levels whose rest
//! position lies within [`CONTACT_REACH`] radii of the cut (at least the band's width)
//! and within 2.5 radii of the pivot's line has a transform of its own: its band motion
//! (and swelling), plus, in an arc, when it is on the inner side of the bend and its posed
//! rest position crosses the contact plane farther than it lay across the cut's plane at
//! rest (a rounded cut leaves some of the parent's skin beyond its plane, which a push
//! from where it lay would move at the first degree of bend), the push back by the
//! difference. Its side is its
//! weight's (past the weight at the cut: the child's), and the push fades out towards the
//! limb's middle, beyond its sides, towards the reach's end and where the side changes,
//! so the pushed skin stays whole. A fan is not pushed: a trunk beside a limb is not the
//! limb's other side, and pushing it tore the skin (`puppet bench poses`). The bone
//! points move with it, so the simulated skin is held on its side like any other target;
//! nothing changes in the step's kernel, and the transforms stay those of the band while
//! nothing crosses.
//!
//! # Transforms
//! The weight is quantised to [`LEVELS`] steps: the simulation gets one transform per
//! level and band (after the sections' own), then one per vertex where bands overlap
//! ([`Blend`]: the bands' motions composed), then one per contact, and each vertex the
//! index of its transform, so the step's kernel is unchanged and a joint that does not
//! bend wakes nothing. The simulation indexes transforms with a `u16`: a band whose
//! contacts would pass 65,536 transforms in all (a limb of tens of thousands of vertices)
//! bends without them.

use super::blend::{Guess, Harmonic, Hold};
use super::{Cut, Joints};
use glam::{DAffine3, DMat3, DQuat, DVec3};

/// One cut's band as [`Joints::compute_band`] finds it, before it is numbered.
struct Computed {
    /// The band, its `first_level` not yet given.
    band: Band,
    /// Each of its vertices with its level.
    levels: Vec<(u32, u16)>,
    /// Its weights before their slope was bounded, for the second pass, and the
    /// sections it carries.
    blended: Blended,
}

impl Computed {
    /// The sections the band carries, each at its level.
    fn carried(&self) -> impl Iterator<Item = (usize, u16)> + '_ {
        self.blended.carried.iter().map(|&(s, x)| {
            let level = (self.band.share(x).clamp(0.0, 1.0) * LEVELS as f64).round();
            (s, level as u16)
        })
    }
}

/// A band's weights before their slope is bounded, and what made them: what the second
/// pass bounds again ([`Joints::bound`]).
struct Blended {
    hold: Hold,
    guess: Vec<Guess>,
    /// Without the sections it carries.
    alone: Harmonic,
    /// The sections it carries, each at its position across it.
    carried: Vec<(usize, f64)>,
    /// With them, where it carries any.
    with_carried: Option<Harmonic>,
}

/// Band half-width in local medial radii when a cut does not say, chosen by
/// `puppet bench joints` (no face crossing at 45–135° on the measured joints; the widest
/// band smooths the bend the most, `BENCHMARKS.md`).
pub const DEFAULT_BAND: f64 = 4.0;

/// Largest band factor accepted.
pub const MAX_BAND: f64 = 6.0;

/// Weight steps per band (the transforms between the parent's, level 0, and the child's).
pub const LEVELS: usize = 64;

/// How far from the plane, in local medial radii, a band's contacts reach (at least its
/// width): at 135° the two sides of a limb of radius `r` overlap up to `tan(67.5°) r ≈
/// 2.4 r` from the pivot.
pub const CONTACT_REACH: f64 = 3.0;

/// A child wider than this many local medial radii beyond its cut is a bulb (a head on
/// its neck), where the band's child side ends.
pub const BULB: f64 = 1.5;

/// How much a bent band swells across the limb, per radian of bend, at its middle (see the
/// module docs).
pub const BULGE: f64 = 0.0125;

/// A band bends as an arc when at most this share of its parent's skeletal points on its
/// side of the band lie off the limb's line (see the module docs and `Joints::spread`):
/// measured, a limb's parent side has 0–14 % (the human's upper arms and thighs, finger
/// bones), a trunk's 33–100 % (a chest beside a shoulder, a pelvis, a palm, a body under
/// a neck).
pub const ARC_SPREAD: f64 = 0.25;

/// The least share of a band's motion a sibling's seam must move with for the sibling to
/// ride on the band whole (see the module docs: carried); below it the seam is blended as
/// the parent's skin. Chosen on half of `puppet bench poses`' characters and pieces
/// (every other one) from 1/128, 0.05, 0.1 and 0.2, by characters within 3× on every
/// pose, then the worst stretch's 90th percentile, then the poses with a section's
/// volume beyond ±5 %; `docs/performance-log.md` has the other half.
pub const CARRY_MIN: f64 = 0.1;

/// Over how many local medial radii a band's weight is smoothed where its first guess
/// jumps between neighbouring vertices (see `blend`).
const SMOOTH: f64 = 1.0;

/// Most transforms the simulation can index (it stores a `u16` per vertex).
const MAX_TRANSFORMS: usize = u16::MAX as usize + 1;

/// A rider's transform (see the module docs of [`super`]: riders): the motion of the
/// transform its host moves with (a band's level, a blend, a contact, a mix), made rigid
/// about the host. A level swollen to keep a section's volume ([`super::volume`])
/// scales the flesh across the band's line; the rider keeps its shape and follows its
/// host's place and turn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Twin {
    /// The transform the host moves with.
    pub(super) source: u16,
    /// The host at rest.
    pub(super) anchor: glam::Vec3,
}

impl Twin {
    /// The rigid motion closest to `t` that moves the anchor where `t` does: `t`'s
    /// rotation by polar decomposition (Newton's iteration on `(M + M⁻ᵀ) / 2`), and the
    /// translation that puts the anchor at `t(anchor)`. `t` itself where it is not
    /// invertible.
    pub(super) fn rigid(&self, t: &glam::Affine3A) -> glam::Affine3A {
        let mut r = glam::Mat3::from(t.matrix3);
        for _ in 0..8 {
            let det = r.determinant();
            if !det.is_finite() || det.abs() < 1e-12 {
                return *t;
            }
            let next = (r + r.inverse().transpose()) * 0.5;
            let done = (next - r).abs_diff_eq(glam::Mat3::ZERO, 1e-7);
            r = next;
            if done {
                break;
            }
        }
        let at = t.transform_point3(self.anchor);
        glam::Affine3A::from_mat3_translation(r, at - r * self.anchor)
    }
}

/// A vertex where two or more bands overlap (a short thigh between the hip's band and the
/// knee's, the body between a neck's band and a shoulder's): it moves with the bands
/// composed, `W(base) · M_above(w) · Π M_below(w)`, each band's motion at its level there
/// (see [`Joints::assign_levels`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blend {
    /// The section whose world transform the motions compose on.
    pub base: u16,
    /// The bands (by slot: their order among the bands that exist) and levels, the band
    /// that made the vertex's section first; `count` of them are used.
    pub parts: [(u16, u16); MAX_BLEND],
    /// How many of `parts` are used.
    pub count: u8,
}

/// Most bands a vertex blends.
pub const MAX_BLEND: usize = 8;

/// One cut's band (by default none: zero wide, nothing measured yet).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Band {
    /// The section the cut made.
    pub child: usize,
    /// Its parent now.
    pub parent: usize,
    /// Half-width of the band on the parent's side (mesh units).
    pub width: f64,
    /// How far it reaches into the child (mesh units, at most `width`; see the module
    /// docs).
    pub child_width: f64,
    /// The local medial radius it was measured from.
    pub radius: f64,
    /// The cut's pivot (where the two sides meet; not always the point the child turns
    /// about, see [`super::Section::pivot`]).
    pub pivot: DVec3,
    /// The unit normal of the cut's surface at the pivot, into the child.
    pub normal: DVec3,
    /// Index of its first level's transform in the pose.
    pub first_level: usize,
    /// It bends as an arc (both sides are limbs), not as a fan about the pivot (see the
    /// module docs).
    pub arc: bool,
    /// The vertices that may touch the other side when the joint bends (see the module
    /// docs), each with the next transform from `first_contact` on.
    pub contacts: Vec<Contact>,
    /// Index of the first contact's transform in the pose.
    pub first_contact: usize,
    /// The child side's slide per unit of turn (see [`super::slide`]; an arc's is
    /// measured through its own motion): its levels move along the normal (turned with
    /// them) by `−Φ a · slide` times their profile.
    pub slide: DVec3,
    /// A fan's parent side's slide per unit of turn (see [`super::slide`]), the child's
    /// side and the child moving with it whole; zero for an arc and on a trunk.
    pub parent_slide: DVec3,
    /// A fan's trunk side's swell per unit of turn (see [`super::slide`]): where its
    /// parent is the root, whose side does not slide, its levels on the parent's side of
    /// the cut scale about the pivot by `1 − Φ a · swell` times their [`super::slide::bump`].
    pub swell: DVec3,
    /// Where this band's child section is bent by two bands at once (its own and a
    /// child's, overlapping on a short section): the second-order change of its volume
    /// those bends make together, `Σ a_xᵀ C a_y` over pairs of sections' rotation
    /// vectors (see [`super::slide`]), which the two slides take back too.
    pub cross: Vec<Cross>,
    /// How far each side slides (parent's, child's) per unit of that change.
    pub cross_slide: [f64; 2],
}

/// Two bands that bend one section over the same vertices (see [`Band::cross`]): the
/// sections whose rotations turn them, and how the section's volume changes with the two
/// rotation vectors together, `a_xᵀ C a_y`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cross {
    /// The section whose rotation turns the first band.
    pub x: usize,
    /// The section whose rotation turns the second.
    pub y: usize,
    /// `C`, per unit of turn squared (mesh units cubed).
    pub coefficient: DMat3,
}

/// A vertex near a cut that is kept on its own side of the bend's contact plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The vertex.
    pub vertex: u32,
    /// The weight step it moves with, `0..=LEVELS` (0: the parent, `LEVELS`: the child).
    pub level: usize,
    /// On the child's side of the cut's plane at rest.
    pub child_side: bool,
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

/// The share of the child's motion at `x` across the band (0 at the parent's end, 1 at
/// the child's): half smoothstep, half linear. The bend per unit length follows its slope,
/// and the inner side of the bend is compressed in proportion: smoothstep alone bends
/// 1.5 times the mean rate at the middle, linear alone starts at full rate with a corner
/// at each end; the mean of the two bends at most 1.25 times the mean rate and starts at
/// half of it. Chosen by `puppet bench joints`: at 90° it sharpens the ring finger's
/// largest crease by 28° instead of 31°, and at 135° the knee's by 33° instead of 49°
/// and the middle finger's by 37° instead of 68°.
pub(super) fn weight(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    0.5 * (x * x * (3.0 - 2.0 * x) + x)
}

impl Band {
    /// The share of the turn at position `x` across the band (`0..=1`): `x` itself on an
    /// arc, [`weight`] of it on a fan.
    fn share(&self, x: f64) -> f64 {
        if self.arc {
            x
        } else {
            weight(x)
        }
    }

    /// The band's parent end and child end on its centre line at rest, and its length.
    pub(super) fn ends(&self) -> (DVec3, DVec3, f64) {
        (
            self.pivot - self.normal * self.width,
            self.pivot + self.normal * self.child_width,
            self.width + self.child_width,
        )
    }

    /// The weight at the cut's surface: where a vertex's side of the bend changes.
    pub(super) fn weight_at_cut(&self) -> f64 {
        self.share(self.cut_share())
    }

    /// The share of the band at the cut's surface (its parent side's share of its
    /// length).
    pub(super) fn cut_share(&self) -> f64 {
        self.width / (self.width + self.child_width)
    }

    /// How far the child moves beyond a turn by `rotation` about the cut's pivot: along
    /// an arc, the bent centre line keeps its length, so it reaches past the corner a
    /// turn about the pivot would make (see the module docs), zero at rest and for a
    /// twist; and its `slide` along the normal turned with it
    /// ([`super::Joints::slide`], [`Band::slid`]).
    pub fn shift(&self, rotation: DQuat, slide: super::Slide) -> DVec3 {
        if !self.arc {
            return self.slid(rotation, slide, 1.0);
        }
        let (start, end, _) = self.ends();
        start + self.bent(rotation).point(1.0) - (self.pivot + rotation * (end - self.pivot))
            + self.slid(rotation, slide, 1.0)
    }

    /// The motion, relative to the parent, of the bone points at share `w` of the band
    /// (0: the parent end, 1: the child end), `child` the child's own motion and
    /// `rotation` its rotation: turned by share `w` of the rotation, about the point of
    /// the bent centre line at `w` (see the module docs).
    pub(super) fn motion(&self, rotation: DQuat, child: &DAffine3, w: f64) -> DAffine3 {
        let bent = self.bent(rotation);
        bent.motion(w, bent.spread(child, DVec3::ZERO))
    }
}

/// The axis and angle (`0..=π`) of the shortest turn a rotation makes.
pub(super) fn axis_angle(rotation: DQuat) -> (DVec3, f64) {
    let q = if rotation.w < 0.0 {
        -rotation
    } else {
        rotation
    };
    q.normalize().to_axis_angle()
}

impl Joints {
    /// Gives every vertex its transform from the levels the bands give it (`entries`:
    /// vertex, band slot, level; `slots`: each slot's cut): its section's where no band
    /// moves it, a band's level where one does, and where several do, a [`Blend`] of its
    /// own (numbered from `next` on, which it advances; where the simulation's transforms
    /// would run out, the band that moves it farthest alone).
    ///
    /// A band moves a vertex of its child (*above* it: the band that made its section), of
    /// its parent (*below*), or of one of the parent's other children near the seam
    /// (*beside*: an arm beside a wide head's band moves with the shoulder it hangs from).
    /// The motions compose on the vertex's parent section's world transform, the bands of
    /// that parent first (above and beside, in slot order), then those of its own section
    /// (below, in slot order): the same order at every vertex, so neighbours agree.
    fn assign_levels(
        &mut self,
        entries: &mut [(u32, u16, u16)],
        slots: &[usize],
        slot_rank: &[usize],
        next: &mut usize,
    ) {
        self.changing();
        self.blends.clear();
        entries.sort_unstable();
        let levels = LEVELS as u16;
        // The slot of the band that made each section.
        let mut made = vec![None; self.sections.len()];
        for (slot, &k) in slots.iter().enumerate() {
            if let Some(band) = &self.bands[k] {
                made[band.child] = Some(slot as u16);
            }
        }
        let mut at = 0;
        while at < entries.len() {
            let i = entries[at].0 as usize;
            let mut end = at;
            while end < entries.len() && entries[end].0 as usize == i {
                end += 1;
            }
            let s = usize::from(self.section_of[i]);
            // Each band that moves the vertex away from its own section: how far, whether
            // it is a band of the section's parent (above or beside), slot and level.
            let mut parts: Vec<(u16, bool, u16, u16)> = Vec::new();
            for &(_, slot, level) in &entries[at..end] {
                let Some(band) = self.bands[slots[usize::from(slot)]].as_ref() else {
                    continue;
                };
                let (away, upper) = if band.child == s {
                    (levels - level.min(levels), true)
                } else if band.parent == s {
                    (level, false)
                } else if Some(band.parent) == self.sections[s].parent && made[s].is_some() {
                    (level, true)
                } else {
                    continue;
                };
                if away > 0 {
                    parts.push((away, upper, slot, level));
                }
            }
            at = end;
            parts.sort_by(|a, b| b.0.cmp(&a.0).then(a.2.cmp(&b.2)));
            parts.truncate(MAX_BLEND - 1);
            // A band beside carries the vertex's own section on it: its own band, whole
            // where it does not move the vertex.
            let beside = parts.iter().any(|p| p.1 && Some(p.2) != made[s]);
            if beside && !parts.iter().any(|p| Some(p.2) == made[s]) {
                if let Some(own) = made[s] {
                    parts.push((0, true, own, levels));
                }
            }
            let Some(&(_, _, slot, level)) = parts.first() else {
                continue;
            };
            if parts.len() == 1 || *next >= MAX_TRANSFORMS {
                let band = self.bands[slots[usize::from(slot)]]
                    .as_ref()
                    .expect("a band");
                self.transform_of[i] = match level {
                    0 => band.parent as u16,
                    l if l >= levels => band.child as u16,
                    l => (band.first_level + usize::from(l) - 1) as u16,
                };
                continue;
            }
            // The parent's bands first, then the section's own; each in slot order, but a
            // carrier before what it carries.
            parts.sort_by_key(|p| (!p.1, slot_rank[usize::from(p.2)]));
            let base = if parts[0].1 {
                self.sections[s].parent.unwrap_or(s)
            } else {
                s
            };
            let mut blend = Blend {
                base: base as u16,
                parts: [(0, 0); MAX_BLEND],
                count: parts.len() as u8,
            };
            for (k, p) in parts.iter().enumerate() {
                blend.parts[k] = (p.2, p.3);
            }
            self.transform_of[i] = *next as u16;
            self.blends.push(blend);
            *next += 1;
        }
    }

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
        self.changing();
        let Some(cut) = self.cuts.iter_mut().find(|c| c.name == name) else {
            return false;
        };
        cut.band = band
            .filter(|b| b.is_finite())
            .map(|b| b.clamp(0.0, MAX_BAND));
        self.refresh_bands();
        true
    }

    /// Cut `k`'s band on its own (its local radius `radius`, each cut's rank by thickness
    /// `rank`, and each section's `rank_of_section`): `None` where it has none.
    fn compute_band(
        &self,
        k: usize,
        radius: Option<(f64, usize, usize)>,
        rank: &[usize],
        rank_of_section: &(dyn Fn(usize) -> usize + Sync),
    ) -> Option<Computed> {
        // A skin cut's vertices blend by the file's weights instead ([`super::skin`]).
        if self.cuts[k].shape == super::Shape::Skin && self.body.skin.is_some() {
            return None;
        }
        let factor = self.cuts[k].band_factor();
        if factor <= 0.0 {
            return None;
        }
        let (radius, child, parent) = radius?;
        // No wider than the child reaches beyond the cut, so its far end turns whole (a
        // short section: a jaw, a head on a short neck).
        let width = (factor * radius).min(self.depth(k, child));
        if !(width.is_finite() && width > 0.0) {
            return None;
        }
        // The child's side: no farther than the child stays a limb.
        let reach = self.tube(k, child, radius).clamp(0.5 * width, width);
        // Two limbs bend as an arc; a limb on a trunk turns as a fan, and so does a
        // part that turns about a hinge it shares (a jaw and its head, which must stay
        // at the hinge).
        let (pivot, normal) = self.cut_frame(k);
        let arc = !self.cuts[k].shared_pivot
            && self.sections[child].pivot == pivot
            && self.spread(k, parent, radius, width) <= ARC_SPREAD;
        // The band's vertices by their skeletal points, then blended over the surface
        // around the seam (`blend`).
        let guess: Vec<Guess> = self
            .near_cut(k, radius, width)
            .into_iter()
            .filter(|&(_, d)| d < reach)
            .map(|(vertex, d)| Guess {
                vertex,
                x: ((d + width) / (width + reach)).clamp(0.0, 1.0),
            })
            .collect();
        // An arc's levels are places along its bent centre line, which a vertex's
        // weight must match (on a limb its skeletal point does, and is continuous);
        // a fan's blend over the surface.
        // The share of the turn the seam moves with: where the cut lies along the band.
        let at_cut = width / (width + reach);
        let seam = if arc { at_cut } else { weight(at_cut) };
        let hold = if arc {
            Hold::Exact {
                span: width + reach,
                smooth: SMOOTH * radius,
                seam,
            }
        } else {
            Hold::Soft {
                reach,
                smooth: SMOOTH * radius,
                seam,
            }
        };
        let band = Band {
            child,
            parent,
            width,
            child_width: reach,
            radius,
            pivot,
            normal,
            arc,
            ..Band::default()
        };
        let alone = self.harmonic(child, parent, pivot, normal, hold, &guess, &[]);
        let blended = Blended {
            hold,
            guess,
            alone,
            carried: Vec::new(),
            with_carried: None,
        };
        // The parent's thinner children whose seams the band moves ride on it whole
        // (see the module docs: carried).
        Some(self.bound(band, blended, &[], |s| rank_of_section(s) > rank[k]))
    }

    /// `band` from its harmonic weights (`blended`) with their slope bounded, together
    /// with the other bands' where `overlap` counts two or more ([`super::blend`]: *Where
    /// bands overlap*; empty on the first pass): the sections it carries (those `carries`
    /// allows) found from the weights without them, and the weights solved again with
    /// them unless `blended` already holds them so.
    fn bound(
        &self,
        band: Band,
        blended: Blended,
        overlap: &[u8],
        carries: impl Fn(usize) -> bool,
    ) -> Computed {
        let Blended {
            hold,
            guess,
            alone,
            carried: was,
            with_carried,
        } = blended;
        let weights = self.bounded(&alone, overlap);
        let carried = self.carried_by(&band, &weights, carries);
        let (weights, with_carried) = match with_carried {
            _ if carried.is_empty() => (weights, None),
            Some(h) if carried == was => (self.bounded(&h, overlap), Some(h)),
            _ => {
                let h = self.harmonic(
                    band.child,
                    band.parent,
                    band.pivot,
                    band.normal,
                    hold,
                    &guess,
                    &carried,
                );
                (self.bounded(&h, overlap), Some(h))
            }
        };
        let blended = Blended {
            hold,
            guess,
            alone,
            carried,
            with_carried,
        };
        self.leveled(band, weights, blended)
    }

    /// The sections `band` carries (those `carries` allows, whose seams its `weights`
    /// move by at least [`CARRY_MIN`] of the turn), each at its position across it.
    fn carried_by(
        &self,
        band: &Band,
        weights: &[(usize, f64)],
        carries: impl Fn(usize) -> bool,
    ) -> Vec<(usize, f64)> {
        self.seam_positions(band.child, band.parent, weights, carries)
            .into_iter()
            .filter(|&(_, x)| band.share(x) >= CARRY_MIN)
            .collect()
    }

    /// `band` with its `weights` as levels.
    fn leveled(&self, band: Band, weights: Vec<(usize, f64)>, blended: Blended) -> Computed {
        // Each vertex's share of the motion, rounded to the band's levels.
        let shares: Vec<(usize, f64)> = weights
            .into_iter()
            .map(|(i, x)| (i, band.share(x)))
            .collect();
        let levels = self.levels(&shares);
        let levels = shares
            .iter()
            .zip(levels)
            .map(|(&(i, _), level)| (i as u32, level))
            .collect();
        Computed {
            band,
            levels,
            blended,
        }
    }

    /// How many riders' hosts move with a band (a level, a blend, a contact, a mix), each
    /// rider of theirs on a [`Twin`], numbered after every other transform.
    pub fn twins(&self) -> usize {
        self.twins.len()
    }

    /// Gives each rider (see the module docs of [`super`]) its host's transform: its
    /// section's as it is, a band's level's (or a blend's, a contact's, a mix's) as a
    /// [`Twin`] numbered from `next`, one per host, made rigid about the host. Where the
    /// transforms would run out, the host's own.
    fn ride(&mut self, next: usize) {
        self.twins.clear();
        let sections = self.sections.len();
        let placed = self.body.rest.len() == self.section_of.len();
        // Per host that moves with more than its section: its twin.
        let mut twin_of: std::collections::HashMap<u32, usize> = Default::default();
        for &h in self
            .body
            .host
            .iter()
            .filter(|&&h| h != super::NO_HOST && placed)
        {
            let source = self.transform_of[h as usize];
            if usize::from(source) < sections {
                continue;
            }
            twin_of.entry(h).or_insert_with(|| {
                self.twins.push(Twin {
                    source,
                    anchor: self.body.rest[h as usize].as_vec3(),
                });
                self.twins.len() - 1
            });
        }
        if next + self.twins.len() > MAX_TRANSFORMS {
            self.twins.clear();
            twin_of.clear();
        }
        for i in 0..self.body.host.len() {
            let h = self.body.host[i];
            if h != super::NO_HOST {
                self.transform_of[i] = twin_of
                    .get(&h)
                    .map_or(self.transform_of[h as usize], |&k| (next + k) as u16);
            }
        }
    }

    /// Recomputes the bands and every vertex's transform (after the cuts changed).
    pub(super) fn refresh_bands(&mut self) {
        self.changing();
        let n = self.section_of.len();
        self.transform_of.clone_from(&self.section_of);
        self.bands = vec![None; self.cuts.len()];
        let sections = self.sections.len();
        // Each band's level at each of its vertices: (vertex, band slot, level).
        let mut entries: Vec<(u32, u16, u16)> = Vec::new();
        // The cut of each band slot.
        let mut slots: Vec<usize> = Vec::new();
        let mut slot = 0;
        // Each cut's local radius, once: for its band and its flesh.
        let radii: Vec<Option<(f64, usize, usize)>> =
            (0..self.cuts.len()).map(|k| self.local_radius(k)).collect();
        self.flesh = self.flesh_of(&radii);
        // Which bands may carry which (see the module docs: carried): a thicker joint's
        // band carries its thinner siblings, never the other way round, so the bands
        // that move a vertex compose in one order (by rank) everywhere.
        let thickness = |k: usize| radii[k].map_or(0.0, |r| r.0);
        let mut by_thickness: Vec<usize> = (0..self.cuts.len()).collect();
        by_thickness.sort_by(|&a, &b| thickness(b).total_cmp(&thickness(a)).then(a.cmp(&b)));
        let mut rank = vec![0; self.cuts.len()];
        for (r, &k) in by_thickness.iter().enumerate() {
            rank[k] = r;
        }
        let mut section_rank = vec![usize::MAX; sections];
        for (k, r) in radii.iter().enumerate() {
            if let Some(x) = r.and_then(|r| section_rank.get_mut(r.1)) {
                *x = rank[k];
            }
        }
        let rank_of_section = |s: usize| section_rank.get(s).copied().unwrap_or(usize::MAX);
        // (carried section, carrying cut, level)
        let mut carries: Vec<(usize, usize, u16)> = Vec::new();
        // Each cut's band on its own (in parallel: each reads the joints only), then
        // numbered in the cuts' order.
        use rayon::prelude::*;
        let mut computed: Vec<Option<Computed>> = (0..self.cuts.len())
            .into_par_iter()
            .map(|k| self.compute_band(k, radii[k], &rank, &rank_of_section))
            .collect();
        // Where two or more bands move a vertex partly, their slopes add: the bands
        // with such a vertex on their parent's side are computed again, bounded together
        // there (`blend`: *Where bands overlap*).
        let mut overlap = vec![0u8; n];
        for c in computed.iter().flatten() {
            for &(i, level) in &c.levels {
                if level > 0 && usize::from(level) < LEVELS {
                    let o = &mut overlap[i as usize];
                    *o = o.saturating_add(1);
                }
            }
        }
        let shares = |c: &Computed| {
            c.levels.iter().any(|&(i, _)| {
                overlap[i as usize] >= 2
                    && usize::from(self.section_of[i as usize]) == c.band.parent
            })
        };
        computed = computed
            .into_par_iter()
            .enumerate()
            .map(|(k, c)| match c {
                Some(c) if shares(&c) => Some(self.bound(c.band, c.blended, &overlap, |s| {
                    rank_of_section(s) > rank[k]
                })),
                c => c,
            })
            .collect();
        for (k, c) in computed.into_iter().enumerate() {
            let first = sections + slot * (LEVELS - 1);
            if first + LEVELS - 1 > MAX_TRANSFORMS {
                continue;
            }
            let Some(c) = c else {
                continue;
            };
            for (s, level) in c.carried() {
                carries.push((s, k, level));
            }
            for &(i, level) in &c.levels {
                entries.push((i, slot as u16, level));
            }
            slots.push(k);
            self.bands[k] = Some(Band {
                first_level: first,
                ..c.band
            });
            slot += 1;
        }
        // A carried section's vertices in its own band ride on its carriers too (the rest
        // of it does through its world transform).
        self.carried = vec![Vec::new(); sections];
        let mut slot_of_cut = vec![None; self.cuts.len()];
        for (slot, &k) in slots.iter().enumerate() {
            slot_of_cut[k] = Some(slot as u16);
        }
        carries.sort_by_key(|&(s, k, _)| (s, rank[k]));
        for &(s, k, level) in &carries {
            self.carried[s].push((k, level));
        }
        let mut carry_edges: Vec<(usize, usize)> = Vec::new();
        if !carries.is_empty() {
            let own_slot = |s: usize| {
                self.cuts
                    .iter()
                    .enumerate()
                    .find(|&(k, _)| radii[k].is_some_and(|r| r.1 == s))
                    .and_then(|(k, _)| slot_of_cut[k])
            };
            let own: Vec<Option<u16>> = (0..sections).map(own_slot).collect();
            for &(s, k, _) in &carries {
                if let (Some(c), Some(o)) = (slot_of_cut[k], own[s]) {
                    carry_edges.push((usize::from(c), usize::from(o)));
                }
            }
            let mut more = Vec::new();
            for &(i, slot, level) in &entries {
                let s = usize::from(self.section_of[i as usize]);
                if own[s] != Some(slot) || usize::from(level) >= LEVELS {
                    continue;
                }
                for &(k, carried_level) in &self.carried[s] {
                    if let Some(c) = slot_of_cut[k] {
                        more.push((i, c, carried_level));
                    }
                }
            }
            entries.extend(more);
        }
        let slot_rank = super::carry::carriers_first(slots.len(), &carry_edges);
        let mut next = sections + slot * (LEVELS - 1);
        self.assign_levels(&mut entries, &slots, &slot_rank, &mut next);
        let surfaces = self.capped_sections();
        self.measure_slides(&entries, &slots, &surfaces);
        self.band_of = vec![None; sections];
        for (k, band) in self.bands.iter().enumerate() {
            if let Some(slot) = band.as_ref().and_then(|b| self.band_of.get_mut(b.child)) {
                *slot = Some(k);
            }
        }
        // Contacts, once every vertex has its level: a vertex moving with this band's
        // parent, child or one of its levels, within reach of the plane, gets a transform
        // of its own (the first band to reach it keeps it).
        let mut taken = vec![false; n];
        for k in 0..self.cuts.len() {
            let Some(band) = &self.bands[k] else {
                continue;
            };
            let (child, parent, first) = (band.child as u16, band.parent as u16, band.first_level);
            let reach = band.width.max(CONTACT_REACH * band.radius);
            let at_cut = band.weight_at_cut();
            let mut contacts = Vec::new();
            for i in self.near_surface(band, reach) {
                let t = self.transform_of[i];
                let level = match t {
                    _ if taken[i] => continue,
                    t if t == parent => 0,
                    t if t == child => LEVELS,
                    t if (first..first + LEVELS - 1).contains(&(t as usize)) => {
                        t as usize - first + 1
                    }
                    _ => continue,
                };
                // Its side by its weight, which is continuous over the surface (its
                // skeletal point's side is not, across a face).
                contacts.push((i, level, level as f64 / LEVELS as f64 >= at_cut));
            }
            if next + contacts.len() > MAX_TRANSFORMS {
                continue;
            }
            let band = self.bands[k].as_mut().expect("a band");
            band.first_contact = next;
            for (j, &(i, level, child_side)) in contacts.iter().enumerate() {
                taken[i] = true;
                self.transform_of[i] = (next + j) as u16;
                band.contacts.push(Contact {
                    vertex: i as u32,
                    level,
                    child_side,
                });
            }
            next += contacts.len();
        }
        let next = self.refresh_mixes(next, MAX_TRANSFORMS);
        self.ride(next);
        self.measure_kept(&entries, &slots, &surfaces);
    }
}
