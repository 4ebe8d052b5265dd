//! Stage 3 of the suggestion: which protrusions of the tree are limbs, and where each is
//! cut.
//!
//! A segment that hangs from a fork, is narrower than the trunk below it
//! (`THINNER`, by the rings' sizes; `PAIR_THINNER` for one of a mirrored pair that split
//! the trunk between them, two legs at a crotch), longer than wide, and sticks out of the trunk's
//! thickest medial ball by `PROTRUDES` of its size and `SMALL` of the mesh (an ear on a
//! head, a face, a nose, an eye do not: they are bumps, and get no cuts at all) is a
//! *limb*: it is cut at its base, and turns about a point half its radius in from the
//! cut; once named (step 5), a shoulder's or a hip's cut moves toward the body while
//! the mesh's slice around it stays within `ROUND` of the limb's width (up to where it
//! meets the trunk: thighs that touch below the crotch tilt the rings of `g`), and it
//! turns a whole radius in from there (`SOCKET`: the ball of a hip sits above the
//! crotch, inside the trunk). A part growing from the core that
//! forks within `HEAD` radii (a pelvis both legs hang from) is body. A part as wide as
//! the body with two or more limbs of its own, each at most `SLENDER` of its width or
//! of its base's, whichever is wider (a head with ears and horns, a hand with fingers,
//! an ant's head with antennae thicker than its neck), is cut at its base too (`HEAD`),
//! if that base is a clear narrowing (`NARROW`: a neck, not a waist as wide as the
//! hips). One with no limbs of its own, as thick as `BODY_THICK` of the body (an ant's
//! abdomen), is cut at the narrowest slice across the line from the core to it, when
//! that is a clear narrowing (a waist).
//! Inside a part, cuts go where the medial radius or the ring's size narrows below the
//! widest within three radii before it and widens again soon (`DIP`: an elbow, a knee, a
//! neck, not the wobble of a coarse mesh's rings); where the axis, over three radii either side, bends (`BEND`:
//! a bent knee, an ankle, a hock; not within those three radii of another cut; a short
//! limb ending at an extremity over as much as it has, down to 1.5 radii); where a
//! limb widens into an extremity that limbs grow from (a wrist); along a digit (a tip
//! among four or more of one extremity, or of a root whose tips are more than `SLENDER`
//! of its thickness: a palm, not a body) at 45 % and 72 % of its length; and halfway, in
//! metres, along a limb's first stretch, from the ball of its root (`SOCKET` of a radius
//! in from its base) to its first joint, when that is longer than `LONG` radii (an elbow or a knee that neither narrows nor bends; a shin
//! between a knee and an ankle already found is not cut again; nor is a flat part,
//! `FLAT`: a big thin ear's length in radii of its thickness says nothing).
//! The core itself is cut only at a clear narrowing along its long axis (`NARROW`): a
//! head as thick as the body it sits on (a teddy's) is part of the core, and turns at
//! its neck, with what hangs from it past the neck.
//!
//! * `find`: the walk over the tree's segments, limb by limb;
//! * `profile`: a segment's profile along its axis, and the cuts inside it;
//! * `trunk`: the cut across the core at a neck or a waist;
//! * `limb`: the stage's output, a cut's place before it applies.

mod find;
mod limb;
mod profile;
mod trunk;

#[cfg(test)]
mod tests;

pub(crate) use limb::Limb;
pub(crate) use trunk::long_axis;

use super::body::Tree;
use super::rules::{BODY_THICK, BODY_TIPS};
use glam::DVec3;

/// Every cut's place on `tree`, parent-first (`parent` indexes the list); `mirror`, the
/// body's mirror plane (unit normal, offset), if it has one. When the root found is a big
/// head on the body ([`Tree::body_elsewhere`]), the tree is rooted again in the body and
/// the head turns at the cut that hung the body from it, the other way round.
pub(crate) fn of(tree: &Tree, mirror: Option<(DVec3, f64)>) -> Vec<Limb> {
    let limbs = tree.limbs(mirror);
    if tree.standing {
        return limbs;
    }
    let Some((root, body)) = tree.body_elsewhere(&limbs) else {
        return limbs;
    };
    let mesh = tree.mesh;
    let mut out = Tree::rooted(mesh, tree.skeleton, tree.graph.clone(), Some(root)).limbs(mirror);
    // The head the tree was first rooted in turns at the cut that hung the body from it,
    // the other way round, unless a cut from the body near there already takes it; what
    // hangs from the body past that cut hangs from the head.
    let head = tree.core.0;
    let past = |l: &Limb, p: DVec3| (p - l.point).dot(l.normal) > 0.0;
    if out.iter().any(|l| {
        l.parent.is_none() && past(l, head) && l.point.distance(body.point) < 2.0 * body.width
    }) {
        return out;
    }
    let neck = Limb {
        parent: None,
        normal: -body.normal,
        expected: mesh
            .positions
            .iter()
            .filter(|&&p| (p - body.point).dot(body.normal) < 0.0)
            .count(),
        past: None,
        socket: 0.0,
        ..body
    };
    limb::put_first(&mut out, neck);
    out
}

impl Tree<'_> {
    /// Where the body is when the root found is not on it: a limb of the root with more
    /// tips than all the root's other limbs together, at least [`BODY_TIPS`], as thick
    /// inside as [`BODY_THICK`] of the root (a big head's body, hanging from the head by a
    /// neck, with the arms and legs; not an arm with its fingers) holds it. Its thickest
    /// vertex past the cut is returned, to root the tree there instead, with that cut.
    pub(crate) fn body_elsewhere(&self, limbs: &[Limb]) -> Option<(usize, Limb)> {
        let n = limbs.len();
        let mut tips = vec![0usize; n];
        let mut has_child = vec![false; n];
        for l in limbs {
            if let Some(p) = l.parent {
                has_child[p] = true;
            }
        }
        // Each leaf counts for the root limb it hangs from.
        let top = |mut i: usize| {
            while let Some(p) = limbs[i].parent {
                i = p;
            }
            i
        };
        for i in 0..n {
            if !has_child[i] {
                tips[top(i)] += 1;
            }
        }
        let all: usize = tips.iter().sum();
        let (best, most) = (0..n)
            .filter(|&i| limbs[i].parent.is_none())
            .map(|i| (i, tips[i]))
            .max_by_key(|&(_, t)| t)?;
        if most < BODY_TIPS || most <= all - most {
            return None;
        }
        let (k, at) = limbs[best].past?;
        let (v, d) = self
            .subtree(k, &self.children)
            .into_iter()
            .filter(|&v| self.g[v as usize] >= at)
            .map(|v| (v as usize, self.skeleton.distance[v as usize]))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        (d >= BODY_THICK * self.core.1).then_some((v, limbs[best]))
    }
}
