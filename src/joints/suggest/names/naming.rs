//! What naming the sections reads, and the root's limbs named: ears, arms and legs by how
//! they stand, the neck or head and the tail on the mirror plane.

use super::chains::Family;
use crate::joints::suggest::rules::{FRONT_END, GROUND, OFF_PLANE, SNOUT, WAIST};
use crate::mesh::orientation::{head_of, image, Frame, Reach};
use crate::mesh::Mesh;
use glam::DVec3;

/// It reaches at most [`SNOUT`] times its far half's thickness: a snout, a muzzle, a nose,
/// not a limb's length.
pub(super) fn short(r: &Reach) -> bool {
    r.tip.distance(r.pivot) <= SNOUT * r.end
}

/// What naming the sections needs: the section tree, each subtree's vertices, the frame.
pub(super) struct Naming<'a> {
    pub(super) mesh: &'a Mesh,
    /// Each vertex's skeletal distance.
    pub(super) radius: &'a [f64],
    pub(super) sections: &'a [crate::joints::Section],
    pub(super) children: Vec<Vec<usize>>,
    pub(super) within: Vec<Vec<usize>>,
    pub(super) frame: Frame,
    pub(super) names: Vec<Option<String>>,
    /// Sections that are no joint (see [`Roles::ends`]).
    pub(super) ends: Vec<usize>,
    /// The mesh's size (the longest side of its bounding box).
    pub(super) size: f64,
    /// The outward normal of its flat base ([`flat_base`]), if it has one.
    pub(super) base: Option<DVec3>,
}

impl Naming<'_> {
    /// Section `s`'s pivot, its tip (the farthest point from the pivot of it and what hangs
    /// from it; of a part on the mirror plane, not what it carries off it: a head's ears or
    /// antennae) and how thick its far half is.
    pub(super) fn reach(&self, s: usize) -> Reach {
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
        // (What it carries off the plane, by the way each part points.)
        // (Each is off the plane: its own reach carries nothing in turn.)
        let carried = (!off.is_empty()).then(|| {
            off.iter()
                .map(|&c| self.reach(c).direction())
                .sum::<DVec3>()
                .normalize_or_zero()
        });
        Reach {
            pivot,
            tip,
            end,
            carried,
        }
    }

    /// On a flat base (a bust), the root's part that holds the mesh's top: its head on its
    /// neck, whichever way it faces.
    pub(super) fn on_the_bust(&self) -> Option<usize> {
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
    pub(super) fn side(&self, p: DVec3) -> Option<&'static str> {
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
    pub(super) fn root(&mut self, limbs: &[(usize, Reach)]) {
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
        // body's limbs. So is the end of a chain of such parts, each the one part of the
        // last, all on the plane and hanging down (a shirt's hem, then the trousers'
        // waist, then the crotch): the ones above it are the `waist`.
        let mut parts: Vec<(usize, Reach)> = Vec::new();
        let off_plane = |n: &Self, s: usize| -> Vec<usize> {
            n.children[s]
                .iter()
                .copied()
                .filter(|&c| n.side(n.sections[c].pivot).is_some())
                .collect()
        };
        let hanging =
            |n: &Self, r: &Reach| n.side(r.pivot).is_none() && r.direction().dot(frame.up) < -0.5;
        for &(s, r) in limbs {
            let mut chain = vec![s];
            let mut at = s;
            while off_plane(self, at).is_empty() && self.children[at].len() == 1 {
                let next = self.children[at][0];
                if chain.len() >= WAIST || !hanging(self, &self.reach(next)) {
                    break;
                }
                chain.push(next);
                at = next;
            }
            let carried = off_plane(self, at);
            if hanging(self, &r) && carried.len() >= 2 {
                for &c in &chain[..chain.len() - 1] {
                    self.names[c] = Some("waist".into());
                }
                self.names[at] = Some("hips".into());
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
                && short(&l.1)
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
            // With ears of its own the root holds the head (a head as thick as the body it
            // sits on, part of the core): a short part on the plane ahead of it with
            // nothing of its own is its snout, no joint (a cat's, a wolf's muzzle).
            let snout = |h: &(usize, Reach)| {
                !ears.is_empty() && short(&h.1) && self.children[h.0].is_empty()
            };
            bust.or_else(|| {
                head_of(&on, thickest, frame.up)
                    .map(|h| ahead[h])
                    .filter(|h| !snout(h))
            })
            .filter(|_| !only_a_head)
        };
        for &(s, r) in &midline {
            let behind = behind(&r);
            if Some(s) == head.map(|h| h.0) {
                self.chain(s, Family::Neck, "");
            } else if head.is_none() && short(&r) && self.children[s].is_empty() && !behind {
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
    pub(super) fn limbs_from_the_front(&mut self, legs: &mut [(usize, Reach)], centre: DVec3) {
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
}
