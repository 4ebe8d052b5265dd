//! Step 5 of the module docs, its second half: names by role, within the frame `frame`
//! finds (the mirror plane, up, front and left).
//!
//! * **Roles.** The root's limbs off the mirror plane: pointing up from above the root's
//!   centre, ears, unless its root's mirror image lies by an arm's or a leg's, at most half
//!   as far as by another ear's (an arm raised higher than the other), and one above the
//!   centre whose root's mirror image lies by an ear's, at most half as far as by another
//!   limb's, is an ear too (the far ear of a head turned aside); of the others, when
//!   one pair stands on the ground ([`GROUND`]) and the rest do not, a biped: the standing
//!   pair are legs and the largest raised limb on each side an arm (arms held out or
//!   hanging down); when all stand, pairs from the front: arms (forelegs) and legs,
//!   numbered legs from three pairs on. A part on the plane hanging down with two or more
//!   off it (a pelvis the legs hang from, cut at a waist) is the `hips`, and those parts
//!   count as the root's limbs. On the plane, of those not growing from the back
//!   end and ending no thinner than any limb off the plane, the one whose far half is
//!   thickest (a head ends in a bulb, a tail in a point), leaning up, counted twice when it
//!   carries parts off the plane (ears, antennae), is the neck (or the head if nothing
//!   follows it); one pointing back or growing from the back end is the tail (a
//!   scorpion's, raised over its back), or the abdomen when it ends as thick as the head;
//!   with no head, a short one (a snout on a head not cut from the body) is no joint.
//!   Down a limb the names go on: `arm`, `forearm`, `hand`; `leg`, `shin`, `foot`; `neck`,
//!   `head`; four or five digits of a hand are `thumb`, `index`, `middle`, `ring`,
//!   `little` (the thumb the one turned most from the others), of a foot `toe1`….
//!   A neck's one short part with none of its own, thin beside it (a snout, a beak turned
//!   aside), is the head's end, no joint, and the neck is the `head`.
//!   A head's parts off the plane are ears; with two on a side, the one pointing most up
//!   is a horn; one long and round (`ANTENNA`) is an antenna.
//!   Side suffixes come from the side of the mirror plane; what fits no role keeps a
//!   number.

use super::frame::*;
use super::rules::{ANTENNA, SLENDER};
use crate::joints::Joints;
use crate::mesh::Mesh;
use glam::DVec3;

/// The sections of a suggestion as [`roles`] reads them.
pub struct Roles {
    /// Per section, its name by role (index 0 is the root and keeps its name); `None`
    /// where no role fits.
    pub names: Vec<Option<String>>,
    /// The frame they were named in.
    pub frame: Frame,
    /// Sections that are the end of their parent, no joint (a head's snout): their cuts
    /// are taken back.
    pub ends: Vec<usize>,
}

/// Role names for the sections of `joints`, in the frame found for them. `radius` is each
/// vertex's skeletal distance, `mirror` the mesh's mirror plane ([`mirror_plane`]) and
/// `base` the outward normal of its flat base ([`flat_base`]).
pub fn roles(
    mesh: &Mesh,
    radius: &[f64],
    joints: &Joints,
    up: Option<DVec3>,
    mirror: Option<(DVec3, f64)>,
    base: Option<DVec3>,
) -> Roles {
    let sections = joints.sections();
    let n = sections.len();
    let mut children = vec![Vec::new(); n];
    for (s, sec) in sections.iter().enumerate() {
        if let Some(p) = sec.parent {
            children[p].push(s);
        }
    }
    // Each section's subtree: the vertices in it and in what hangs from it.
    let mut within: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (v, &s) in joints.section_of().iter().enumerate() {
        let mut t = Some(s as usize);
        while let Some(at) = t {
            within[at].push(v);
            t = sections[at].parent;
        }
    }
    let mut naming = Naming {
        mesh,
        radius,
        sections,
        children,
        within,
        // The mirror plane first: a limb's reach says whether it carries parts off it.
        frame: Frame {
            mirror,
            ..Frame::default()
        },
        names: vec![None; n],
        ends: Vec::new(),
        size: mesh.longest_side().max(1e-12),
        base,
    };
    let limbs: Vec<(usize, Reach)> = naming.children[0]
        .iter()
        .map(|&s| (s, naming.reach(s)))
        .collect();
    let reaches: Vec<Reach> = limbs.iter().map(|l| l.1).collect();
    naming.frame = frame(&mesh.positions, mirror, &reaches, up, base);
    naming.root(&limbs);
    Roles {
        names: naming.names,
        frame: naming.frame,
        ends: naming.ends,
    }
}

/// What naming the sections needs: the section tree, each subtree's vertices, the frame.
struct Naming<'a> {
    mesh: &'a Mesh,
    /// Each vertex's skeletal distance.
    radius: &'a [f64],
    sections: &'a [crate::joints::Section],
    children: Vec<Vec<usize>>,
    within: Vec<Vec<usize>>,
    frame: Frame,
    names: Vec<Option<String>>,
    /// Sections that are no joint (see [`Roles::ends`]).
    ends: Vec<usize>,
    /// The mesh's size (the longest side of its bounding box).
    size: f64,
    /// The outward normal of its flat base ([`flat_base`]), if it has one.
    base: Option<DVec3>,
}

impl Naming<'_> {
    /// Section `s`'s pivot, its tip (the farthest point from the pivot of it and what hangs
    /// from it; of a part on the mirror plane, not what it carries off it: a head's ears or
    /// antennae) and how thick its far half is.
    fn reach(&self, s: usize) -> Reach {
        let pivot = self.sections[s].pivot;
        // A part on the mirror plane with parts of its own off it (a head's ears).
        let midline = self.side(pivot).is_none();
        let off: Vec<usize> = self.children[s]
            .iter()
            .copied()
            .filter(|&c| midline && self.side(self.sections[c].pivot).is_some())
            .collect();
        let mut aside = Vec::new();
        if !off.is_empty() {
            aside = vec![false; self.mesh.positions.len()];
            for &c in &off {
                for &v in &self.within[c] {
                    aside[v] = true;
                }
            }
        }
        let own = || {
            self.within[s]
                .iter()
                .copied()
                .filter(|&v| !aside.get(v).copied().unwrap_or(false))
        };
        let tip = own()
            .map(|v| self.mesh.positions[v])
            .max_by(|a, b| a.distance(pivot).total_cmp(&b.distance(pivot)))
            .unwrap_or(pivot);
        let reach = tip.distance(pivot);
        let end = own()
            .filter(|&v| self.mesh.positions[v].distance(pivot) >= 0.5 * reach)
            .map(|v| self.radius[v])
            .fold(0.0, f64::max);
        Reach {
            pivot,
            tip,
            end,
            paired: !off.is_empty(),
        }
    }

    /// On a flat base (a bust), the root's part that holds the mesh's top: its head on its
    /// neck, whichever way it faces.
    fn on_the_bust(&self) -> Option<usize> {
        self.base?;
        let up = self.frame.up;
        let top = (0..self.mesh.positions.len()).max_by(|&a, &b| {
            let height = |v: usize| self.mesh.positions[v].dot(up);
            height(a).total_cmp(&height(b))
        })?;
        self.children[0]
            .iter()
            .copied()
            .find(|&c| self.within[c].contains(&top))
    }

    /// The side of the mirror plane `p` is on (`None` on the plane, or with no plane).
    fn side(&self, p: DVec3) -> Option<&'static str> {
        let (n, o) = self.frame.mirror?;
        let d = p.dot(n) - o;
        if d.abs() < OFF_PLANE * self.size {
            return None;
        }
        Some(if d * n.dot(self.frame.left) > 0.0 {
            "L"
        } else {
            "R"
        })
    }

    /// Names the root's limbs and what hangs from them.
    fn root(&mut self, limbs: &[(usize, Reach)]) {
        let frame = self.frame;
        if frame.mirror.is_none() {
            // No mirror plane: a hand on its own, or a creature posed off its symmetry;
            // on a flat base, a bust sculpted off its symmetry, whose one part holding its
            // top is its head on its neck.
            self.digits(0, "");
            if let Some(head) = self.on_the_bust() {
                self.chain(head, Family::Neck, "");
            }
            return;
        }
        let within = &self.within[0];
        let centre = within
            .iter()
            .map(|&v| self.mesh.positions[v])
            .sum::<DVec3>()
            / within.len().max(1) as f64;
        // On the mirror plane; off it pointing up from above the centre (ears); the rest
        // (arms and legs).
        let mut midline: Vec<(usize, Reach)> = Vec::new();
        let mut ears: Vec<(usize, Reach)> = Vec::new();
        let mut legs: Vec<(usize, Reach)> = Vec::new();
        // A part on the plane hanging down with two or more parts off it (a pelvis both
        // legs hang from, cut as one with a loincloth) is the hips: its parts are the
        // body's limbs.
        let mut parts: Vec<(usize, Reach)> = Vec::new();
        for &(s, r) in limbs {
            let carried: Vec<usize> = self.children[s]
                .iter()
                .copied()
                .filter(|&c| self.side(self.sections[c].pivot).is_some())
                .collect();
            if self.side(r.pivot).is_none()
                && r.direction().dot(frame.up) < -0.5
                && carried.len() >= 2
            {
                self.names[s] = Some("hips".into());
                parts.extend(carried.into_iter().map(|c| (c, self.reach(c))));
            } else {
                parts.push((s, r));
            }
        }
        for &(s, r) in &parts {
            if self.side(r.pivot).is_none() {
                midline.push((s, r));
            } else if r.raised(frame.up, centre) {
                ears.push((s, r));
            } else {
                legs.push((s, r));
            }
        }
        // A limb pointing up whose root's mirror image lies by an arm's or a leg's, at most
        // half as far from it as from another ear's, is that limb's pair (an arm raised
        // higher than the other), not an ear.
        if let Some(plane) = frame.mirror {
            let nearest = |p: DVec3, of: &[(usize, Reach)]| {
                of.iter()
                    .map(|l| l.1.pivot.distance(p))
                    .fold(f64::INFINITY, f64::min)
            };
            let (raised, kept): (Vec<_>, Vec<_>) = ears.iter().partition(|(s, r)| {
                let image = image(plane, r.pivot);
                let others: Vec<(usize, Reach)> =
                    ears.iter().copied().filter(|e| e.0 != *s).collect();
                !others.is_empty() && nearest(image, &legs) < 0.5 * nearest(image, &others)
            });
            legs.extend(raised);
            ears = kept;
            // And the other way: a limb above the centre whose root's mirror image lies by
            // an ear's, at most half as far from it as from any other limb's, is that
            // ear's pair (the far ear of a head turned aside, its section reaching down the
            // side of the head).
            let (turned, kept): (Vec<_>, Vec<_>) = legs.iter().partition(|(s, r)| {
                let image = image(plane, r.pivot);
                let others: Vec<(usize, Reach)> =
                    legs.iter().copied().filter(|l| l.0 != *s).collect();
                (r.pivot - centre).dot(frame.up) > 0.0
                    && nearest(image, &ears) < 0.5 * nearest(image, &others)
            });
            ears.extend(turned);
            legs = kept;
        }
        // A lone pair that does not hang down, from above the centre, and short (an ear's
        // flap, not an arm's length) is a head's ears: the root is the head (a monkey's
        // head modelled on its own), and a part on the plane is its face, no neck.
        let flaps = |l: &(usize, Reach)| {
            l.1.direction().dot(frame.up) > -0.5
                && (l.1.pivot - centre).dot(frame.up) > 0.0
                && l.1.short()
        };
        if ears.is_empty()
            && legs.len() == 2
            && legs.iter().all(flaps)
            && self.side(legs[0].1.pivot) != self.side(legs[1].1.pivot)
        {
            ears.append(&mut legs);
        }
        let only_a_head = legs.is_empty() && !ears.is_empty();
        // Midline: the head ([`head_of`]), not growing from the back end, ending no thinner
        // than any part off the plane (a head ends in a bulb; a snout on a head not cut from
        // the body does not, nor does a tail); the tail points back, or grows from the back
        // end (a scorpion's, raised over its back).
        let back = -FRONT_END * self.size;
        let behind = |r: &Reach| (r.pivot - centre).dot(frame.front) < back;
        let head = {
            let ahead: Vec<(usize, Reach)> =
                midline.iter().copied().filter(|l| !behind(&l.1)).collect();
            let on: Vec<&Reach> = ahead.iter().map(|l| &l.1).collect();
            let thickest = legs
                .iter()
                .chain(&ears)
                .map(|l| l.1.end)
                .fold(0.0, f64::max);
            let bust = self
                .on_the_bust()
                .and_then(|b| midline.iter().copied().find(|l| l.0 == b));
            bust.or_else(|| head_of(&on, thickest, frame.up).map(|h| ahead[h]))
                .filter(|_| !only_a_head)
        };
        for &(s, r) in &midline {
            let behind = behind(&r);
            if Some(s) == head.map(|h| h.0) {
                self.chain(s, Family::Neck, "");
            } else if head.is_none() && r.short() && self.children[s].is_empty() && !behind {
                // A short bump on the plane (a snout on a head not cut from the body) is
                // no joint.
                self.ends.push(s);
            } else if r.direction().dot(frame.front) < -0.3 || behind {
                // Ending as thick as the head: an abdomen; thinner, a tail.
                let thick = head.is_some_and(|h| r.end >= h.1.end);
                let family = if thick { Family::Abdomen } else { Family::Tail };
                self.chain(s, family, "");
            }
        }
        let height = |p: DVec3| p.dot(frame.up);
        let lowest = |s: usize| {
            self.within[s]
                .iter()
                .map(|&v| height(self.mesh.positions[v]))
                .fold(f64::INFINITY, f64::min)
        };
        let (floor, top) = self
            .mesh
            .positions
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(height(p)), hi.max(height(p)))
            });
        // A biped: one pair stands on the ground and the rest do not (arms hanging down
        // or held out), legs and arms; of the raised limbs, one per side (the largest) is
        // an arm, and the others keep their numbers.
        let stands: Vec<bool> = legs
            .iter()
            .map(|l| lowest(l.0) <= floor + GROUND * (top - floor))
            .collect();
        let standing = stands.iter().filter(|&&st| st).count();
        if (1..=2).contains(&standing) && standing < legs.len() {
            let side = |r: &Reach| self.side(r.pivot).unwrap_or("L");
            let arms: Vec<usize> = ["L", "R"]
                .iter()
                .filter_map(|&lr| {
                    legs.iter()
                        .zip(&stands)
                        .filter(|(l, &st)| !st && side(&l.1) == lr)
                        .max_by_key(|(l, _)| self.within[l.0].len())
                        .map(|(l, _)| l.0)
                })
                .collect();
            // Of the other raised limbs, one above its side's arm, and smaller, is an ear
            // (a head not cut from the body: it sits on the shoulders as wide as its neck).
            let arm_on = |lr: &str| {
                legs.iter()
                    .find(|l| arms.contains(&l.0) && side(&l.1) == lr)
                    .copied()
            };
            let ear = |s: usize, r: &Reach| {
                arm_on(side(r)).is_some_and(|(a, ar)| {
                    height(r.pivot) > height(ar.pivot) + ar.end
                        && self.within[s].len() < self.within[a].len()
                })
            };
            let families: Vec<(usize, Option<Family>, &str)> = legs
                .iter()
                .zip(&stands)
                .map(|(&(s, r), &st)| {
                    let family = if st {
                        Some(Family::Leg)
                    } else if arms.contains(&s) {
                        Some(Family::Arm)
                    } else if ear(s, &r) {
                        Some(Family::Ear)
                    } else {
                        None
                    };
                    (s, family, side(&r))
                })
                .collect();
            for (s, family, lr) in families {
                if let Some(family) = family {
                    self.chain(s, family, lr);
                }
            }
        } else {
            self.limbs_from_the_front(&mut legs, centre);
        }
        for &(s, r) in &ears {
            let lr = self.side(r.pivot).unwrap_or("L");
            self.chain(s, Family::Ear, lr);
        }
    }

    /// Names limbs that all stand (or none does) in pairs from the front: arms (forelegs)
    /// and legs, or numbered legs from three pairs on; with two pairs, one pointing down
    /// and one not, legs and arms.
    fn limbs_from_the_front(&mut self, legs: &mut [(usize, Reach)], centre: DVec3) {
        let frame = self.frame;
        let along = |r: &Reach| (r.pivot - centre).dot(frame.front);
        legs.sort_by(|a, b| along(&b.1).total_cmp(&along(&a.1)));
        let pairs = legs.len().div_ceil(2);
        let downward = |r: &Reach| r.direction().dot(frame.up) < -0.5;
        let biped = legs.iter().filter(|l| downward(&l.1)).count() == 2 && pairs <= 2;
        for (k, &(s, r)) in legs.iter().enumerate() {
            let lr = self.side(r.pivot).unwrap_or("L");
            let rank = k / 2;
            let family = if biped {
                if downward(&r) {
                    Family::Leg
                } else {
                    Family::Arm
                }
            } else if pairs >= 3 {
                Family::Numbered(rank + 1)
            } else if pairs == 2 && rank == 0 {
                Family::Arm
            } else if downward(&r) || pairs == 2 {
                Family::Leg
            } else {
                Family::Arm
            };
            self.chain(s, family, lr);
        }
    }

    /// Names section `s` and the single chain that follows it with `family`'s names (side
    /// `tag`), then what branches from the chain: digits of a hand or foot, ears of a head.
    fn chain(&mut self, s: usize, family: Family, tag: &str) {
        let list = family.names();
        let mut at = s;
        let mut k = 0;
        loop {
            let base = if k < list.len() {
                list[k].clone()
            } else {
                format!("{}.{}", list[list.len() - 1], k - list.len() + 2)
            };
            self.names[at] = Some(tagged(&base, tag));
            match self.children[at].as_slice() {
                [] => return,
                // A lone part with none of its own, at most SLENDER as thick as the limb it
                // hangs from, is a digit on it (a thumb on an arm whose hand is not cut),
                // not the limb's next stretch.
                [only] if self.lone_digit(at, *only, family) => {
                    let digit = if family == Family::Arm {
                        "thumb"
                    } else {
                        "toe"
                    };
                    self.names[*only] = Some(tagged(digit, tag));
                    return;
                }
                // A neck's one short part with none of its own, at most SLENDER as thick as
                // the neck (a snout, a beak turned aside, not a head), is the head's end,
                // no joint: the neck is the head.
                [only]
                    if family == Family::Neck
                        && self.children[*only].is_empty()
                        && self.reach(*only).short()
                        && self.reach(*only).end <= SLENDER * self.reach(at).end =>
                {
                    self.ends.push(*only);
                    self.names[at] = Some(tagged("head", tag));
                    return;
                }
                [only] if !(family == Family::Neck && k + 1 >= list.len()) => {
                    at = *only;
                    k += 1;
                }
                _ => break,
            }
        }
        if family != Family::Neck {
            self.digits(at, tag);
            return;
        }
        // A neck whose head has no cut of its own is the head.
        if k == 0 && self.children[at].len() >= 2 {
            self.names[at] = Some(tagged("head", tag));
        }
        // Off the plane: ears; on it, below the head: a jaw. A head's one short part on the
        // plane (a snout, a muzzle, a nose: at most SNOUT of its own thickness long) is its
        // end, no joint; a jaw is one of two (an open mouth).
        let kids = self.children[at].clone();
        let on_plane: Vec<usize> = kids
            .iter()
            .copied()
            .filter(|&c| self.side(self.sections[c].pivot).is_none())
            .collect();
        // With two or more parts on one side (ears and horns), the one pointing most
        // up is a horn.
        let up = self.frame.up;
        let horns: Vec<usize> = ["L", "R"]
            .iter()
            .filter_map(|&lr| {
                let mine: Vec<usize> = kids
                    .iter()
                    .copied()
                    .filter(|&c| self.side(self.sections[c].pivot) == Some(lr))
                    .collect();
                if mine.len() < 2 {
                    return None;
                }
                mine.into_iter()
                    .map(|c| (c, self.reach(c).direction().dot(up)))
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(c, _)| c)
            })
            .collect();
        for c in kids {
            match self.side(self.sections[c].pivot) {
                Some(lr) if horns.contains(&c) => self.chain(c, Family::Horn, lr),
                Some(lr) if self.feeler(c) => self.chain(c, Family::Antenna, lr),
                Some(lr) => self.chain(c, Family::Ear, lr),
                None => {
                    if on_plane.len() == 1 && self.reach(c).short() && self.children[c].is_empty() {
                        self.ends.push(c);
                        continue;
                    }
                    self.chain(c, Family::Jaw, "");
                }
            }
        }
    }

    /// Whether `c`, the only part of limb section `at` (of `family`), is a digit on it: an
    /// arm's or a leg's (an insect's numbered legs' digits are its feet's `toe1`…), with no
    /// parts of its own, its far half at most [`SLENDER`] as
    /// thick as the far half of the limb with it.
    fn lone_digit(&self, at: usize, c: usize, family: Family) -> bool {
        matches!(family, Family::Arm | Family::Leg)
            && self.children[c].is_empty()
            && self.reach(c).end <= SLENDER * self.reach(at).end
    }

    /// Whether head part `c` is a feeler (an insect's antenna, not an ear or a horn): at
    /// least [`ANTENNA`] times as long as its far half is thick, and that far half round,
    /// no wider across than thick (a big flat ear is long against its thickness too).
    fn feeler(&self, c: usize) -> bool {
        let r = self.reach(c);
        let reach = r.tip.distance(r.pivot);
        if reach < ANTENNA * r.end {
            return false;
        }
        // The far half's spread across its long axis: the root mean square of its points'
        // distances from that axis, per direction across (a round tube of radius `t`
        // spreads 0.71 t; a flat ear as much as it is wide).
        let far: Vec<DVec3> = self.within[c]
            .iter()
            .map(|&v| self.mesh.positions[v])
            .filter(|p| p.distance(r.pivot) >= 0.5 * reach)
            .collect();
        let mean = far.iter().sum::<DVec3>() / far.len().max(1) as f64;
        let axis = super::trunk::long_axis(far.iter().map(|&p| p - mean));
        let across = far
            .iter()
            .map(|&p| (p - mean).reject_from_normalized(axis).length_squared())
            .sum::<f64>()
            / (2 * far.len()).max(1) as f64;
        across.sqrt() <= r.end
    }

    /// Names the branches of section `at`: four or five digits as fingers (thumb first) or
    /// toes; each digit's chain goes on with `.2`, `.3`…. A branch of the root pointing
    /// away from the digits (a forearm below a palm) is the forearm.
    fn digits(&mut self, at: usize, tag: &str) {
        let kids = self.children[at].clone();
        if kids.len() < 2 {
            return;
        }
        let dirs: Vec<DVec3> = kids.iter().map(|&c| self.reach(c).direction()).collect();
        let mean = dirs.iter().sum::<DVec3>().normalize_or_zero();
        let digits: Vec<usize> = (0..kids.len())
            .filter(|&i| dirs[i].dot(mean) > 0.0)
            .collect();
        let toes = self.names[at]
            .as_deref()
            .is_some_and(|n| n.starts_with("foot"));
        // A hand not cut at its wrist: of two parts, one with two or more digits of its
        // own and one with none, the first is the hand and the other its thumb.
        if !toes && at != 0 && digits.len() == 2 {
            let (a, b) = (kids[digits[0]], kids[digits[1]]);
            let palm = |c: usize| self.children[c].len() >= 2;
            let bare = |c: usize| self.children[c].is_empty();
            let pair = if palm(a) && bare(b) {
                Some((a, b))
            } else if palm(b) && bare(a) {
                Some((b, a))
            } else {
                None
            };
            if let Some((hand, thumb)) = pair {
                self.names[hand] = Some(tagged("hand", tag));
                self.digit(thumb, &tagged("thumb", tag));
                self.digits(hand, tag);
                return;
            }
        }
        if !toes && (4..=5).contains(&digits.len()) {
            // The thumb is the digit turned most from the others; the rest by distance
            // from it.
            let others = |i: usize| {
                digits
                    .iter()
                    .filter(|&&j| j != i)
                    .map(|&j| dirs[j])
                    .sum::<DVec3>()
                    .normalize_or_zero()
            };
            let thumb = digits
                .iter()
                .copied()
                .min_by(|&a, &b| dirs[a].dot(others(a)).total_cmp(&dirs[b].dot(others(b))))
                .unwrap_or(digits[0]);
            let base = self.sections[kids[thumb]].pivot;
            let mut order = digits.clone();
            order.sort_by(|&a, &b| {
                let d = |i: usize| self.sections[kids[i]].pivot.distance(base);
                d(a).total_cmp(&d(b))
            });
            let fingers = ["thumb", "index", "middle", "ring", "little"];
            let skip = 5 - digits.len();
            for (rank, &i) in order.iter().enumerate() {
                let name = if rank == 0 {
                    fingers[0]
                } else {
                    fingers[rank + skip]
                };
                self.digit(kids[i], &tagged(name, tag));
            }
        } else if digits.len() >= 2 {
            let base = if toes { "toe" } else { "finger" };
            for (rank, &i) in digits.iter().enumerate() {
                self.digit(kids[i], &tagged(&format!("{base}{}", rank + 1), tag));
            }
        }
        if at == 0 {
            for (i, &c) in kids.iter().enumerate() {
                if !digits.contains(&i) && self.names[c].is_none() {
                    self.digit(c, &tagged("forearm", tag));
                }
            }
        }
    }

    /// Names a digit's chain: `index`, `index.2`, `index.3`….
    fn digit(&mut self, s: usize, name: &str) {
        let mut at = s;
        let mut k = 1;
        loop {
            self.names[at] = Some(if k == 1 {
                name.to_string()
            } else {
                format!("{name}.{k}")
            });
            match self.children[at].as_slice() {
                [only] => {
                    at = *only;
                    k += 1;
                }
                _ => return,
            }
        }
    }
}

/// What a chain of cuts down one limb is called.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Family {
    Arm,
    Leg,
    /// Legs numbered from the front (an insect's).
    Numbered(usize),
    Neck,
    Tail,
    /// A head's part on the mirror plane below it, one of two (an open mouth).
    Jaw,
    /// A part pointing back that ends as thick as the head (an insect's).
    Abdomen,
    Ear,
    Horn,
    /// A head's long thin part off the plane (an insect's feeler).
    Antenna,
}

impl Family {
    /// The names down the chain, base first.
    fn names(self) -> Vec<String> {
        match self {
            Family::Arm => vec!["arm".into(), "forearm".into(), "hand".into()],
            Family::Leg => vec!["leg".into(), "shin".into(), "foot".into()],
            Family::Numbered(k) => vec![format!("leg{k}"), format!("shin{k}"), format!("foot{k}")],
            Family::Neck => vec!["neck".into(), "head".into()],
            Family::Tail => vec!["tail".into()],
            Family::Jaw => vec!["jaw".into()],
            Family::Abdomen => vec!["abdomen".into()],
            Family::Ear => vec!["ear".into()],
            Family::Horn => vec!["horn".into()],
            Family::Antenna => vec!["antenna".into()],
        }
    }
}

/// The name of the same role on the other side: `index.R.2` for `index.L.2`; `None` for a
/// name with no side.
pub fn other_side(name: &str) -> Option<String> {
    let words: Vec<&str> = name.split('.').collect();
    if !words.iter().any(|&w| w == "L" || w == "R") {
        return None;
    }
    let swapped: Vec<&str> = words
        .iter()
        .map(|&w| match w {
            "L" => "R",
            "R" => "L",
            w => w,
        })
        .collect();
    Some(swapped.join("."))
}

/// Is `role` a limb's root that turns in a ball joint: a shoulder (`arm.L`) or a hip
/// (`leg.R`, an insect's `leg2.L`)?
pub(super) fn is_ball_joint(role: &str) -> bool {
    let base = role.split('.').next().unwrap_or("");
    base == "arm"
        || base
            .strip_prefix("leg")
            .is_some_and(|k| k.chars().all(|c| c.is_ascii_digit()))
}

/// `base` with its side: `arm.L`; `tail` on the plane.
fn tagged(base: &str, tag: &str) -> String {
    if tag.is_empty() {
        base.to_string()
    } else {
        format!("{base}.{tag}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on two boxes side by side, mirrored across x = 1, with a tail off to one side.
    fn figure(tail: bool) -> Vec<DVec3> {
        let mut p = Vec::new();
        for i in 0..10 {
            for j in 0..20 {
                for k in 0..6 {
                    let (x, y, z) = (i as f64 * 0.1, j as f64 * 0.1, k as f64 * 0.1);
                    p.push(DVec3::new(0.05 + x, y, z));
                    p.push(DVec3::new(1.95 - x, y, z));
                }
            }
        }
        if tail {
            for j in 0..20 {
                p.push(DVec3::new(
                    1.5 + j as f64 * 0.02,
                    0.0,
                    -0.5 - j as f64 * 0.05,
                ));
            }
        }
        p
    }

    #[test]
    fn the_mirror_plane_is_found_across_the_axis_it_mirrors() {
        let (n, o) = mirror_plane(&figure(false)).unwrap();
        assert_eq!(n, DVec3::X);
        assert!((o - 1.0).abs() < 0.02, "{o}");
        // A few points off the plane (a curled tail) move nothing.
        let (n, o) = mirror_plane(&figure(true)).unwrap();
        assert_eq!(n, DVec3::X);
        assert!((o - 1.0).abs() < 0.02, "{o}");
        // A lopsided cloud has none.
        let lopsided: Vec<DVec3> = (0..500)
            .map(|i| {
                let t = i as f64;
                DVec3::new(
                    (t * 0.37).sin().abs() * t.sqrt(),
                    (t * 0.11).cos(),
                    t * 0.01,
                )
            })
            .collect();
        assert!(mirror_plane(&lopsided).is_none());
    }

    #[test]
    fn a_bust_with_no_limbs_stands_on_its_flat_base() {
        // A ball cut flat below, modelled z-up: a bust's base at its far end along -z.
        let mut bust = crate::mesh::shapes::icosphere(1.0, 3);
        for p in &mut bust.positions {
            p.z = p.z.max(-0.6);
        }
        assert_eq!(flat_base(&bust), Some(DVec3::NEG_Z));
        // Round all over, or flat where it is not at the far end, there is none.
        assert_eq!(flat_base(&crate::mesh::shapes::icosphere(1.0, 3)), None);
        let (n, o) = mirror_plane(&bust.positions).unwrap();
        assert!(n.dot(DVec3::Z).abs() < 0.5, "{n}");
        let f = frame(&bust.positions, Some((n, o)), &[], None, flat_base(&bust));
        assert_eq!(f.up, DVec3::Z);
        // A given up wins, and without a base the convention stays.
        let given = frame(
            &bust.positions,
            Some((n, o)),
            &[],
            Some(DVec3::X),
            Some(DVec3::NEG_Z),
        );
        assert_eq!(given.up, DVec3::X);
        assert_eq!(
            frame(&bust.positions, Some((n, o)), &[], None, None).up,
            DVec3::Y
        );
    }

    #[test]
    fn legs_hanging_along_an_axis_make_the_other_way_up() {
        let plane = figure(false);
        // Four legs off the plane hanging along -z: z is up, front across it and x.
        let leg = |x: f64, y: f64| Reach {
            pivot: DVec3::new(x, y, 0.0),
            tip: DVec3::new(x, y, -1.0),
            end: 0.1,
            paired: false,
        };
        let limbs = [leg(0.5, 0.2), leg(1.5, 0.2), leg(0.5, 1.8), leg(1.5, 1.8)];
        let f = frame(&plane, mirror_plane(&plane), &limbs, None, None);
        assert_eq!(f.up, DVec3::Z);
        assert!(f.front.dot(DVec3::Y).abs() > 0.99);
        assert!((f.left - f.up.cross(f.front)).length() < 1e-12);
        // Given, up is kept.
        assert_eq!(
            frame(&plane, mirror_plane(&plane), &limbs, Some(DVec3::Y), None).up,
            DVec3::Y
        );
        // Sprawled legs say little: +y stays.
        let sprawl = |x: f64, y: f64, s: f64| Reach {
            pivot: DVec3::new(x, y, 0.0),
            tip: DVec3::new(x + s, y, -0.3),
            end: 0.1,
            paired: false,
        };
        let limbs = [sprawl(0.5, 0.2, -1.0), sprawl(1.5, 0.2, 1.0)];
        assert_eq!(
            frame(&plane, mirror_plane(&plane), &limbs, None, None).up,
            DVec3::Y
        );
    }

    /// A section tree for naming: section `s` a row of `count` vertices from its pivot
    /// along its direction (`along[s]`), under `parent[s]`, each vertex of skeletal distance
    /// `radius(s)`; a section's `within` holds what hangs from it too. Named by `name`.
    fn named<T>(
        along: &[(DVec3, DVec3)],
        parent: &[Option<usize>],
        count: usize,
        radius: impl Fn(usize) -> f64,
        name: impl FnOnce(&mut Naming) -> T,
    ) -> T {
        let mut positions = Vec::new();
        let mut radii = Vec::new();
        let mut within = vec![Vec::new(); along.len()];
        for (s, &(pivot, dir)) in along.iter().enumerate() {
            for k in 0..count {
                // Into this section and every one it hangs from.
                let mut at = Some(s);
                while let Some(a) = at {
                    within[a].push(positions.len());
                    at = parent[a];
                }
                positions.push(pivot + dir * (0.02 * k as f64));
                radii.push(radius(s));
            }
        }
        let sections: Vec<crate::joints::Section> = (0..along.len())
            .map(|s| crate::joints::Section {
                name: format!("s{s}"),
                parent: parent[s],
                pivot: along[s].0,
                vertices: count,
            })
            .collect();
        let mut children = vec![Vec::new(); along.len()];
        for (s, p) in parent.iter().enumerate() {
            if let Some(p) = p {
                children[*p].push(s);
            }
        }
        let mesh = Mesh {
            positions,
            triangles: Vec::new(),
        };
        let mut naming = Naming {
            mesh: &mesh,
            radius: &radii,
            sections: &sections,
            children,
            within,
            frame: Frame::default(),
            names: vec![None; along.len()],
            ends: Vec::new(),
            size: 1.0,
            base: None,
        };
        name(&mut naming)
    }

    /// A forearm ending in two parts, one carrying fingers (a hand not cut at its wrist)
    /// and one carrying none (Homer's): the first is the hand, the other its thumb, and
    /// the hand's parts are fingers.
    #[test]
    fn a_part_carrying_fingers_beside_a_bare_one_is_a_hand_and_its_thumb() {
        // Sections: 0 the body, 1 the forearm, 2 the palm, 3 the thumb, 4–6 fingers.
        let along = [
            (DVec3::ZERO, DVec3::Y),
            (DVec3::new(0.3, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.6, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.55, 0.0, 0.05), DVec3::new(0.6, 0.0, 0.8)),
            (DVec3::new(0.7, 0.0, -0.03), DVec3::X),
            (DVec3::new(0.7, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.7, 0.0, 0.03), DVec3::X),
        ];
        let parent = [None, Some(0), Some(1), Some(1), Some(2), Some(2), Some(2)];
        let names = named(
            &along,
            &parent,
            5,
            |_| 0.01,
            |naming| {
                naming.digits(1, "L");
                naming.names.clone()
            },
        );
        let names: Vec<Option<&str>> = names.iter().map(|n| n.as_deref()).collect();
        assert_eq!(names[2], Some("hand.L"), "{names:?}");
        assert_eq!(names[3], Some("thumb.L"), "{names:?}");
        for s in 4..7 {
            assert!(
                names[s].is_some_and(|n| n.starts_with("finger")),
                "{names:?}"
            );
        }
    }

    /// An arm whose hand is not cut, with one thin part of its own (Cheburashka's thumb
    /// sticking out, 13 and 17 vertices): that part is its thumb, not its forearm; a part
    /// as thick as the arm's far end is the forearm.
    #[test]
    fn an_arm_s_lone_thin_part_is_its_thumb() {
        let name = |thumb_radius: f64| {
            // Sections: 0 the body, 1 the arm, 2 its one part.
            let along = [
                (DVec3::ZERO, DVec3::Y),
                (DVec3::new(0.3, 0.0, 0.0), DVec3::X),
                (DVec3::new(0.45, 0.0, 0.02), DVec3::Z),
            ];
            let radius = |s: usize| if s == 2 { thumb_radius } else { 0.03 };
            named(&along, &[None, Some(0), Some(1)], 8, radius, |naming| {
                naming.chain(1, Family::Arm, "L");
                naming.names[2].clone()
            })
        };
        assert_eq!(name(0.007).as_deref(), Some("thumb.L"));
        assert_eq!(name(0.025).as_deref(), Some("forearm.L"));
    }
}
