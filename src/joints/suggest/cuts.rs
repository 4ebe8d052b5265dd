//! The cut rules (step 3 of the module docs): which segments of the join tree are limbs, and
//! where a limb or a part of the body is cut: at its base, at narrowings, where it widens
//! into an extremity, along a digit, in the middle of a long stretch.

use super::rules::{
    BASE, BEND, BODY_THICK, DIGIT, DIP, ELONGATED, FLAT, HEAD, LONG, LONG_TO_WRIST, MATCHED,
    NARROW, PROTRUDES, SLENDER, SMALL, SOCKET, THINNER, WRIST,
};
use super::tree::Tree;
use glam::DVec3;

impl Tree<'_> {
    /// Every cut's place, parent-first: `parent` indexes this list. `mirror`: the mesh's
    /// mirror plane (unit normal, offset), if it has one.
    pub(super) fn limbs(&self, mirror: Option<(DVec3, f64)>) -> Vec<Limb> {
        let mut out = Vec::new();
        if self.segments.is_empty() {
            return out;
        }
        let children = &self.children;
        // The segment holding the root (the smallest g).
        let Some(root) = (0..self.segments.len()).find(|&k| {
            self.segments[k].parent.is_none()
                && self.segments[k]
                    .vertices
                    .iter()
                    .any(|&v| self.g[v as usize] == 0.0)
        }) else {
            return out;
        };
        // Each segment's base cut, if it is a limb; and its owner: the nearest limb at or
        // below it (the root's segment for the body).
        let n = self.segments.len();
        let mut base: Vec<Option<Limb>> = (0..n)
            .map(|k| match self.segments[k].parent {
                Some(p) if !self.segments[k].vertices.is_empty() => self.base_cut(k, p, children),
                _ => None,
            })
            .collect();
        // A part no thinner than the body that still reaches out, with two or more limbs of
        // its own (a head with ears and horns), turns at its base too.
        for k in 0..n {
            let seg = &self.segments[k].vertices;
            if base[k].is_some() || seg.is_empty() || k == root {
                continue;
            }
            let Some(parent) = self.segments[k].parent else {
                continue;
            };
            let hanging = self.limbs_hanging(k, children, &base);
            let low = self.lowest(seg);
            let high = self.highest(&self.subtree(k, children));
            // One with none, as thick as half the body (an ant's abdomen), turns at the
            // waist it hangs from. (Thick by its rings: a rough surface's medial balls are
            // small.)
            if hanging.is_empty()
                && low > 0.0
                && high - low >= HEAD
                && self.widest_ring(k) >= BODY_THICK * self.core.1
            {
                base[k] = self.waist(k, parent);
                continue;
            }
            if hanging.len() < 2 || low <= 0.0 || high - low < HEAD || parent == root {
                continue;
            }
            // Its limbs are thin beside it (ears and horns on a head, fingers on a hand),
            // measured against its base or its own widest ring, whichever is wider (an
            // ant's antennae beside its head, not its thin neck): where one is about as
            // wide (a wrist below a palm), this is a stretch of the body where limbs meet,
            // not a part of its own.
            let Some(cut) = self.cut_at(k, low + BASE) else {
                continue;
            };
            let beside = cut.width.max(self.widest_ring(k));
            if hanging.iter().all(|&w| w <= SLENDER * beside) && self.narrows_at(k, parent, &cut) {
                base[k] = Some(cut);
            }
        }
        let mut owner = vec![root; n];
        let mut stack = vec![root];
        while let Some(k) = stack.pop() {
            for &c in &children[k] {
                owner[c] = if base[c].is_some() { c } else { owner[k] };
                stack.push(c);
            }
        }
        // Limbs hanging from each owner, and those of them no limb grows from (tips).
        let hanging: Vec<(usize, usize)> = (0..n)
            .filter(|&k| base[k].is_some())
            .filter_map(|k| self.segments[k].parent.map(|p| (k, owner[p])))
            .collect();
        let mut limbs_from = vec![0usize; n];
        for &(_, o) in &hanging {
            limbs_from[o] += 1;
        }
        let mut tips_from = vec![0usize; n];
        for &(k, o) in &hanging {
            if limbs_from[k] == 0 {
                tips_from[o] += 1;
            }
        }
        // The root is a palm when the tips hanging from it are about as thick as its core
        // (a hand's fingers): they are its digits. A body's arms and legs are slenderer.
        let mut tip_radii: Vec<f64> = hanging
            .iter()
            .filter(|&&(k, o)| o == root && limbs_from[k] == 0)
            .map(|&(k, _)| self.radius(&self.segments[k].vertices))
            .collect();
        let palm = !tip_radii.is_empty()
            && crate::stats::median(&mut tip_radii).unwrap_or(f64::INFINITY)
                > SLENDER * self.core.1;
        let shape = Shape {
            children,
            base: &base,
            owner: &owner,
            limbs_from: &limbs_from,
            tips_from: &tips_from,
            palm,
            root,
        };
        self.walk(root, None, &shape, &mut out);
        // A neck across the core: first, and what hangs from the core past it hangs
        // from it.
        if let Some(neck) = self.trunk_cut() {
            put_first(&mut out, neck);
        }
        if let Some(mirror) = mirror {
            self.copy_to_the_other_side(&mut out, mirror);
        }
        out
    }

    /// A cut off the mirror plane `(n, o)` with no cut near its mirror image, on a limb
    /// whose mirror image is cut (or on the body), is copied there: a knee found on one leg
    /// only.
    fn copy_to_the_other_side(&self, out: &mut Vec<Limb>, (n, o): (DVec3, f64)) {
        let image = |p: DVec3| super::frame::image((n, o), p);
        let size = self.size_of_mesh;
        let partner: Vec<Option<usize>> = out
            .iter()
            .map(|l| {
                let want = image(l.pivot);
                out.iter()
                    .enumerate()
                    .map(|(j, m)| (j, m.pivot.distance(want)))
                    .filter(|&(_, d)| d <= MATCHED * size)
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(j, _)| j)
            })
            .collect();
        let mut copies = Vec::new();
        for (i, l) in out.iter().enumerate() {
            if partner[i].is_some() || (l.pivot.dot(n) - o).abs() < MATCHED * size {
                continue;
            }
            // Its parent's image: the partner of a limb, the parent itself when that lies
            // on the mirror plane (an ear found on one side of a head).
            let parent = match l.parent {
                Some(p) => match partner[p] {
                    Some(q) => Some(q),
                    None => continue,
                },
                None => None,
            };
            copies.push(Limb {
                parent,
                point: image(l.point),
                normal: super::frame::reflect(n, l.normal),
                pivot: image(l.pivot),
                ..*l
            });
        }
        out.extend(copies);
    }

    /// Visits segment `k` (whose limb, the nearest cut below it, is `limb`), adding the
    /// cuts at its base and inside it, then its children.
    pub(super) fn walk(&self, k: usize, limb: Option<usize>, shape: &Shape, out: &mut Vec<Limb>) {
        let mut current = limb;
        if let Some(base) = shape.base[k] {
            out.push(Limb {
                parent: limb,
                ..base
            });
            current = Some(out.len() - 1);
        }
        // An extremity: two or more limbs grow from it (a hand, a foot: cut where it
        // widens). A digit: a tip among four or more that grow from one extremity, not
        // from the body unless the body is a palm (a hand on its own).
        // A part of the body that is no limb (a thick neck and head) may still narrow
        // (at the neck): only narrowings there.
        let limb = shape.base[k].is_some();
        let parent = self.segments[k]
            .parent
            .map_or(shape.root, |p| shape.owner[p]);
        let extremity = limb && shape.limbs_from[k] >= 2;
        let digit = limb
            && shape.limbs_from[k] == 0
            && shape.tips_from[parent] >= 4
            && (parent != shape.root || shape.palm);
        let part = limb
            || (self.segments[k].vertices.len() >= 16
                && self.segments[k]
                    .parent
                    .is_some_and(|p| self.protrudes(k, p, shape.children)));
        if k != shape.root && part {
            for inner in self.inner_cuts(k, limb, extremity, digit) {
                out.push(Limb {
                    parent: current,
                    ..inner
                });
                current = Some(out.len() - 1);
            }
        }
        // Children from the thickest down, so a section tree reads naturally.
        let mut kids = shape.children[k].clone();
        kids.sort_by(|&a, &b| {
            let (ra, rb) = (
                self.radius(&self.segments[a].vertices),
                self.radius(&self.segments[b].vertices),
            );
            rb.total_cmp(&ra)
        });
        for c in kids {
            self.walk(c, current, shape, out);
        }
    }

    /// The widths of the limbs that hang from segment `k`, directly or through forks that
    /// are no limbs.
    pub(super) fn limbs_hanging(
        &self,
        k: usize,
        children: &[Vec<usize>],
        base: &[Option<Limb>],
    ) -> Vec<f64> {
        let mut out = Vec::new();
        for &c in &children[k] {
            match base[c] {
                Some(limb) => out.push(limb.width),
                None => out.extend(self.limbs_hanging(c, children, base)),
            }
        }
        out
    }

    /// The cut at the base of segment `k` where it hangs from `parent`, if `k` (with what
    /// grows from it) is a limb: thinner than the parent there and long enough.
    pub(super) fn base_cut(
        &self,
        k: usize,
        parent: usize,
        children: &[Vec<usize>],
    ) -> Option<Limb> {
        let seg = &self.segments[k].vertices;
        let whole = self.subtree(k, children);
        let low = self.lowest(seg);
        let high = self.highest(&whole);
        let r = self.radius(seg);
        if r <= 0.0 || high - low < ELONGATED {
            return None;
        }
        // Thinner than the parent just below the fork: by the rings' sizes, not their
        // medial radii (a finger is as thick as the flat palm it grows from, not as wide).
        // (Its own ring one to three radii out: at the fork itself it is not round.)
        let own = self.size(&self.ring(seg, low + 1.0, low + 3.0));
        // The trunk it grows from, one to three of its radii below the fork (through short
        // forks where other limbs join close by, like the webs between fingers).
        let below = self.trunk_ring(parent, low - 3.0, low - 1.0);
        // A limb growing right from the core (a finger from the palm) has no trunk below
        // it: the core's own vertices are only the root's ball, so the body is measured
        // beside the limb instead, by everything else as far from the core.
        let beside = || {
            let mut mine = vec![false; self.g.len()];
            for &v in &whole {
                mine[v as usize] = true;
            }
            (0..self.g.len() as u32)
                .filter(|&v| {
                    !mine[v as usize] && (low + 1.0..low + 3.0).contains(&self.g[v as usize])
                })
                .collect::<Vec<u32>>()
        };
        let parent_size = if below.is_empty() {
            self.size(&self.segments[parent].vertices)
                .max(self.size(&beside()))
        } else {
            self.size(&below)
        };
        if !is_limb(own, parent_size, high - low, r) {
            return None;
        }
        // Growing right from the core and forking within a few radii (a pelvis that
        // both legs hang from), it is a part of the body, not a limb.
        if below.is_empty() && children[k].len() >= 2 && self.highest(seg) - low < HEAD {
            return None;
        }
        if !self.protrudes(k, parent, children) {
            return None;
        }
        // Through the ring a radius above the fork, across the axis there: far enough out
        // that the plane does not reach a neighbour at the fork (the other leg at the
        // crotch). It turns about the ball of its root, a radius in from the cut (the
        // head of a femur sits inside the hip, above the crotch).
        // (Only a limb thinner than the core: a head as thick as the body turns where it
        // is cut.)
        self.cut_at(k, low + BASE).map(|cut| {
            let ring = self.ring(seg, low + BASE - 0.25, low + BASE + 0.25);
            let r = self.radius(&ring);
            let inward = if r <= THINNER * self.core.1 {
                0.5 * r
            } else {
                0.0
            };
            Limb {
                pivot: cut.pivot - cut.normal * inward,
                socket: if inward > 0.0 { SOCKET * r } else { 0.0 },
                ..cut
            }
        })
    }

    /// Does segment `k` (with what grows from it) stick out of the thickest medial ball of
    /// the trunk `parent` near its fork by [`PROTRUDES`] of its own size and by [`SMALL`] of
    /// the mesh? A nose, an eye, an ear flat on a head, a face in front of a skull, a belly
    /// do not: they are bumps, neither limbs nor cut inside.
    pub(super) fn protrudes(&self, k: usize, parent: usize, children: &[Vec<usize>]) -> bool {
        let seg = &self.segments[k].vertices;
        let low = self.lowest(seg);
        let own = self.size(&self.ring(seg, low + 1.0, low + 3.0));
        let below_empty = self.trunk_ring(parent, low - 3.0, low - 1.0).is_empty();
        let (anchor, anchor_radius) = self
            .trunk_ring(parent, low - 3.0, low + 0.5)
            .iter()
            .map(|&v| {
                (
                    self.skeleton.points[v as usize],
                    self.skeleton.distance[v as usize],
                )
            })
            .chain(below_empty.then_some(self.core))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or(self.core);
        let stick = self
            .subtree(k, children)
            .iter()
            .map(|&v| self.mesh.positions[v as usize].distance(anchor))
            .fold(0.0, f64::max)
            - anchor_radius;
        stick >= PROTRUDES * own && stick >= SMALL * self.size_of_mesh
    }

    /// The cut at the waist part `k` (no limbs of its own, growing from `parent`) hangs
    /// from, across the line from the body's core to it: the narrowest slice of the part
    /// and the segments it grows from, between the core and the part's widest slice, when
    /// it is at most [`NARROW`] of the widest on both sides (an ant's abdomen past its
    /// waist). The rings of `g` do not find it: they tilt across a short waist.
    fn waist(&self, k: usize, parent: usize) -> Option<Limb> {
        let (centre, _) = self.core;
        let positions = &self.mesh.positions;
        let part = self.subtree(k, &self.children);
        let mut body = part.clone();
        let mut s = Some(parent);
        while let Some(p) = s {
            body.extend_from_slice(&self.segments[p].vertices);
            s = self.segments[p].parent;
        }
        let middle =
            part.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / part.len().max(1) as f64;
        let axis = (middle - centre).normalize_or_zero();
        let r = self.radius(&part);
        if axis == DVec3::ZERO || r.is_nan() || r <= 0.0 {
            return None;
        }
        let step = 0.5 * r;
        let t: Vec<f64> = body
            .iter()
            .map(|&v| (positions[v as usize] - centre).dot(axis))
            .collect();
        let bins = (t.iter().copied().fold(0.0, f64::max) / step).ceil() as usize;
        if !(4..=4096).contains(&bins) {
            return None;
        }
        let (slices, size) = self.slices(&body, &t, 0.0, step, bins);
        let widest = (0..bins)
            .filter(|&b| size[b].is_finite())
            .max_by(|&a, &b| size[a].total_cmp(&size[b]))?;
        // The widest slice (the part's, or nothing is cut), and the narrowest before it
        // with something wider before that.
        let mut best: Option<(usize, f64)> = None;
        for b in 1..widest {
            if !size[b].is_finite() {
                continue;
            }
            let ratio = size[b] / super::trunk::widest(&size[..b]).min(size[widest]);
            if ratio <= NARROW && best.is_none_or(|(_, q)| ratio < q) {
                best = Some((b, ratio));
            }
        }
        let (b, _) = best?;
        let (point, pivot) = self.centre(&slices[b]);
        let pivot = pivot - axis * (pivot - point).dot(axis);
        let expected = body
            .iter()
            .filter(|&&v| (positions[v as usize] - point).dot(axis) > 0.0)
            .count();
        Some(Limb::across(point, axis, pivot, size[b], expected))
    }

    /// The size of segment `k`'s widest ring, from a radius past its base to its end.
    fn widest_ring(&self, k: usize) -> f64 {
        let seg = &self.segments[k].vertices;
        let (low, high) = (self.lowest(seg), self.highest(seg));
        let mut widest: f64 = 0.0;
        let mut at = low + 1.0;
        while at < high {
            let ring = self.ring(seg, at, at + 0.5);
            if ring.len() >= 3 {
                widest = widest.max(self.size(&ring));
            }
            at += 0.5;
        }
        widest
    }

    /// Is `cut`, at the base of segment `k` that grows from `parent`, a clear narrowing: at
    /// most [`NARROW`] of the trunk below it and of the part's own widest ring?
    fn narrows_at(&self, k: usize, parent: usize, cut: &Limb) -> bool {
        let seg = &self.segments[k].vertices;
        let low = self.lowest(seg);
        let below = self.trunk_ring(parent, low - 3.0, low - 1.0);
        let trunk = if below.is_empty() {
            self.size(&self.segments[parent].vertices)
        } else {
            self.size(&below)
        };
        cut.width <= NARROW * trunk.min(self.widest_ring(k))
    }

    /// The profile of segment `k` from its base up, in bins half its radius long: the
    /// median skeletal distance and the mean distance of the surface from the ring's centre
    /// of each ring (empty rings interpolated), smoothed over three bins.
    pub(super) fn profile(&self, k: usize) -> Option<Profile> {
        let seg = &self.segments[k].vertices;
        let r = self.radius(seg);
        if seg.len() < 16 || r <= 0.0 {
            return None;
        }
        let low = self.lowest(seg);
        let high = self.highest(seg);
        let step = 0.5;
        let bins = ((high - low) / step).floor() as usize;
        if bins < 6 {
            return None;
        }
        let mut d = vec![f64::NAN; bins];
        let mut size = vec![f64::NAN; bins];
        let mut centre = [
            vec![f64::NAN; bins],
            vec![f64::NAN; bins],
            vec![f64::NAN; bins],
        ];
        for b in 0..bins {
            let lo = low + b as f64 * step;
            let ring = self.ring(seg, lo, lo + step);
            if ring.len() >= 3 {
                d[b] = self.radius(&ring);
                let (c, _) = self.centre(&ring);
                for (axis, v) in centre.iter_mut().enumerate() {
                    v[b] = c[axis];
                }
                size[b] = ring
                    .iter()
                    .map(|&v| (self.mesh.positions[v as usize] - c).length())
                    .sum::<f64>()
                    / ring.len() as f64;
            }
        }
        let (d, size) = (smooth(&fill(&d)?), smooth(&fill(&size)?));
        let [x, y, z] = [fill(&centre[0])?, fill(&centre[1])?, fill(&centre[2])?];
        let centre = (0..bins).map(|b| DVec3::new(x[b], y[b], z[b])).collect();
        Some(Profile {
            low,
            step,
            d,
            size,
            centre,
        })
    }

    /// Cuts inside segment `k`, from its base up: at clear narrowings; where it widens into
    /// an extremity that other limbs grow from (a wrist, an ankle: `extremity`); and along
    /// a long digit (`digit`: a tip among several of an extremity) at its two joints (see
    /// [`Profile::cut_bins`]).
    pub(super) fn inner_cuts(
        &self,
        k: usize,
        limb: bool,
        extremity: bool,
        digit: bool,
    ) -> Vec<Limb> {
        let Some(p) = self.profile(k) else {
            return Vec::new();
        };
        p.cut_bins(limb, extremity, digit)
            .into_iter()
            .filter_map(|b| self.cut_at(k, p.low + (b as f64 + 0.5) * p.step))
            .collect()
    }

    /// A cut through the ring of `seg` at level `at`, across the axis (from the centre of
    /// the ring a radius below to the one a radius above), its pivot on the axis.
    pub(super) fn cut_at(&self, k: usize, at: f64) -> Option<Limb> {
        let seg = &self.segments[k].vertices;
        let half = 0.25;
        let ring = self.ring(seg, at - half, at + half);
        let below = self.ring(seg, at - 1.0 - half, at - 1.0 + half);
        let above = self.ring(seg, at + 1.0 - half, at + 1.0 + half);
        if ring.is_empty() {
            return None;
        }
        let (point, pivot) = self.centre(&ring);
        let from = if below.is_empty() {
            point
        } else {
            self.centre(&below).0
        };
        let to = if above.is_empty() {
            point
        } else {
            self.centre(&above).0
        };
        let normal = (to - from).normalize_or_zero();
        if normal == DVec3::ZERO || !normal.is_finite() {
            return None;
        }
        // The pivot on the plane, at the axis.
        let pivot = pivot - normal * (pivot - point).dot(normal);
        let expected = self
            .subtree(k, &self.children)
            .iter()
            .filter(|&&v| self.g[v as usize] >= at)
            .count();
        Some(Limb {
            parent: None,
            expected,
            socket: 0.0,
            width: self.size(&ring),
            point,
            normal,
            pivot,
            past: Some((k, at)),
        })
    }
}

/// What [`Tree::limbs`] found of the tree's shape, for [`Tree::walk`].
pub(super) struct Shape<'a> {
    pub(super) children: &'a [Vec<usize>],
    /// Each segment's base cut, if it is a limb.
    pub(super) base: &'a [Option<Limb>],
    /// The nearest limb at or below each segment (the root's segment for the body).
    pub(super) owner: &'a [usize],
    /// Per owner: limbs that hang from it, and those of them no limb grows from.
    pub(super) limbs_from: &'a [usize],
    pub(super) tips_from: &'a [usize],
    /// The root is a palm: the tips hanging from it are digits.
    pub(super) palm: bool,
    /// The root's segment.
    pub(super) root: usize,
}

/// A segment's profile (see [`Tree::profile`]).
pub(super) struct Profile {
    /// `g` at its base.
    pub(super) low: f64,
    /// Bin length.
    pub(super) step: f64,
    /// Per bin: median skeletal distance, and mean distance from the ring's centre.
    pub(super) d: Vec<f64>,
    pub(super) size: Vec<f64>,
    /// Per bin: the ring's centre (the limb's axis).
    pub(super) centre: Vec<DVec3>,
}

impl Profile {
    /// The bins of the cuts inside a part with this profile, from its base up, in order: at
    /// clear narrowings; where a limb widens into an extremity (`extremity`); along a digit
    /// (`digit`) at 45 % and 72 % of its length; in the middle of a limb's long stretch
    /// without a joint. `limb`: the part is a limb, cut at its base (a part of the body is
    /// cut only where it narrows).
    pub(super) fn cut_bins(&self, limb: bool, extremity: bool, digit: bool) -> Vec<usize> {
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

/// Is a protrusion a limb? Its ring `own` wide (the size of [`Tree::size`]) must be thinner
/// than the `trunk` it grows from ([`THINNER`]) and longer than it is wide: `length` (in
/// local radii, `radius` its medial radius) at least [`ELONGATED`] times its width in
/// radii. A nose is neither; a finger on a palm is both.
pub(super) fn is_limb(own: f64, trunk: f64, length: f64, radius: f64) -> bool {
    own > 0.0 && own <= THINNER * trunk && length >= ELONGATED * own / radius
}

/// Empty bins (NaN) take the value of the nearest bins on either side; `None` if all are.
pub(super) fn fill(v: &[f64]) -> Option<Vec<f64>> {
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
pub(super) fn smooth(v: &[f64]) -> Vec<f64> {
    (0..v.len())
        .map(|b| {
            let (a, c) = (b.saturating_sub(1), (b + 1).min(v.len() - 1));
            (v[a] + v[b] + v[c]) / 3.0
        })
        .collect()
}

/// A suggested cut before it is named.
#[derive(Clone, Copy, Debug)]
pub(super) struct Limb {
    /// The cut below it (index in the list), `None` for one on the root.
    pub(super) parent: Option<usize>,
    /// How many vertices lie past it in the join tree: a plane that takes far more has
    /// slipped past the limb into the body.
    pub(super) expected: usize,
    /// The size ([`Tree::size`]) of its ring.
    pub(super) width: f64,
    pub(super) point: DVec3,
    pub(super) normal: DVec3,
    pub(super) pivot: DVec3,
    /// How much deeper its pivot goes when it turns out to be a shoulder or a hip (named
    /// in step 5): [`SOCKET`] of its root ring's radius for a limb thinner than the core
    /// (whose pivot went in from the cut), else 0.
    pub(super) socket: f64,
    /// The segment it cuts and the level of `g` it cuts at (`None` for a cut across a
    /// slice of the body: the core at a neck, a waist).
    pub(super) past: Option<(usize, f64)>,
}

impl Limb {
    /// A cut of the root across a slice of the body of size `width` (a neck across the
    /// core, a waist), not at a level of `g`, with `expected` vertices past it.
    pub(super) fn across(
        point: DVec3,
        normal: DVec3,
        pivot: DVec3,
        width: f64,
        expected: usize,
    ) -> Limb {
        Limb {
            parent: None,
            expected,
            width,
            socket: 0.0,
            point,
            normal,
            pivot,
            past: None,
        }
    }
}

/// Puts `neck`, a cut across the body, first in `limbs` (parent-first, indexed by
/// position): what hangs from the body past it hangs from it.
pub(super) fn put_first(limbs: &mut Vec<Limb>, neck: Limb) {
    for limb in limbs.iter_mut() {
        limb.parent = match limb.parent {
            Some(p) => Some(p + 1),
            None if (limb.point - neck.point).dot(neck.normal) > 0.0 => Some(0),
            None => None,
        };
    }
    limbs.insert(0, neck);
}
