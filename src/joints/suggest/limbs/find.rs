//! The cut rules (stage 3, see the module docs): which segments of the join tree are limbs, and
//! where a limb or a part of the body is cut: at its base, at narrowings, where it widens
//! into an extremity, along a digit, in the middle of a long stretch.

use super::limb::{parents_first, put_first};
use super::profile::{fill, is_limb, smooth, Profile};
use super::Limb;
use crate::joints::suggest::body::Tree;
use crate::joints::suggest::rules::{
    BASE, BODY_THICK, ELONGATED, HEAD, MATCHED, NARROW, PAIR_THINNER, PAIR_WIDTH, PROTRUDES,
    SLENDER, SMALL, SOCKET, THINNER,
};
use glam::DVec3;

impl Tree<'_> {
    /// Every cut's place, parent-first: `parent` indexes this list. `mirror`: the mesh's
    /// mirror plane (unit normal, offset), if it has one.
    pub(crate) fn limbs(&self, mirror: Option<(DVec3, f64)>) -> Vec<Limb> {
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
                Some(p) if !self.segments[k].vertices.is_empty() => {
                    self.base_cut(k, p, children, mirror)
                }
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
    /// only. The copy carries the cuts there that mirror what hangs below the cut it
    /// copies (that leg's ankle), which hung beside it from its parent or from higher up.
    fn copy_to_the_other_side(&self, out: &mut Vec<Limb>, (n, o): (DVec3, f64)) {
        let image = |p: DVec3| crate::mesh::orientation::image((n, o), p);
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
        let mut sources = Vec::new();
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
            sources.push(i);
            copies.push(Limb {
                parent,
                point: image(l.point),
                normal: crate::mesh::orientation::reflect(n, l.normal),
                pivot: image(l.pivot),
                ..*l
            });
        }
        let first = out.len();
        out.extend(copies);
        // A copy takes its place in the chain: the cuts on the other side that mirror what
        // hangs from the cut it copies (an ankle below a knee found on one leg only) hang
        // from it, not beside it from its parent or from higher up.
        let parents: Vec<Option<usize>> = out.iter().map(|l| l.parent).collect();
        let below = |mut d: usize, i: usize| loop {
            if d == i {
                return true;
            }
            match parents[d] {
                Some(p) => d = p,
                None => return false,
            }
        };
        let mut moved = false;
        for (c, &i) in sources.iter().enumerate() {
            let copy = first + c;
            let parent = out[copy].parent;
            for m in 0..first {
                // It hangs from the copy's parent or from a cut (or the body) above that.
                let above = match (out[m].parent, parent) {
                    (a, b) if a == b => true,
                    (Some(a), Some(b)) => below(b, a),
                    (None, Some(_)) => true,
                    _ => false,
                };
                // (Never a cut the copy hangs below: that would close a loop.)
                let under = parent.is_some_and(|b| below(b, m));
                if above && !under && partner[m].is_some_and(|d| d != i && below(d, i)) {
                    out[m].parent = Some(copy);
                    moved = true;
                }
            }
        }
        if moved {
            parents_first(out);
        }
    }

    /// Visits segment `k` (whose limb, the nearest cut below it, is `limb`), adding the
    /// cuts at its base and inside it, then its children.
    pub(crate) fn walk(&self, k: usize, limb: Option<usize>, shape: &Shape, out: &mut Vec<Limb>) {
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
    pub(crate) fn limbs_hanging(
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
    pub(crate) fn base_cut(
        &self,
        k: usize,
        parent: usize,
        children: &[Vec<usize>],
        mirror: Option<(DVec3, f64)>,
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
        let ring = self.own_ring(seg, low);
        let own = self.size(&ring);
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
        // One of a mirrored pair that splits the trunk between them (two legs at a
        // crotch) is measured against the pair's share of it: two touching rings side by
        // side are 4/pi of one's size together, so a pair that does not narrow at all
        // stands at 0.79 of the trunk. (Looked for only where it decides.)
        let between = own > THINNER * parent_size && own <= PAIR_THINNER * parent_size;
        let thinner = if between && self.split_in_pair(k, &ring, parent, children, mirror) {
            PAIR_THINNER
        } else {
            THINNER
        };
        if !is_limb(own, parent_size, high - low, r, thinner) {
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

    /// Is segment `k` (its ring `own` one to three radii out), growing from `parent`, one
    /// of a mirrored pair that split the trunk between them (two legs at a crotch): off
    /// the plane `mirror` by half its ring's size, with a sibling that is its mirror image
    /// (their rings within [`MATCHED`] of the mesh's size of each other's image, and as
    /// wide within [`PAIR_WIDTH`])?
    pub(super) fn split_in_pair(
        &self,
        k: usize,
        own: &[u32],
        parent: usize,
        children: &[Vec<usize>],
        mirror: Option<(DVec3, f64)>,
    ) -> bool {
        let Some(plane) = mirror else {
            return false;
        };
        let ring_of = |s: usize| {
            let seg = &self.segments[s].vertices;
            let low = self.lowest(seg);
            self.ring(seg, low + 1.0, low + 3.0)
        };
        if own.len() < 3 {
            return false;
        }
        let (centre, size) = (self.centre(own).0, self.size(own));
        // (Off the plane by half its own size at least: a ring across it is the trunk's.
        // Two legs side by side stand a whole size off it, as near as the mesh's
        // `MATCHED`: the human's, 4.8 % and 5.0 % of its height.)
        if (centre.dot(plane.0) - plane.1).abs() < 0.5 * size {
            return false;
        }
        let tolerance = MATCHED * self.size_of_mesh;
        let image = crate::mesh::orientation::image(plane, centre);
        children[parent].iter().any(|&o| {
            let ring = ring_of(o);
            o != k
                && ring.len() >= 3
                && self.centre(&ring).0.distance(image) <= tolerance
                && (self.size(&ring) - size).abs() <= PAIR_WIDTH * size
        })
    }

    /// Does segment `k` (with what grows from it) stick out of the thickest medial ball of
    /// the trunk `parent` near its fork by [`PROTRUDES`] of its own size and by [`SMALL`] of
    /// the mesh? A nose, an eye, an ear flat on a head, a face in front of a skull, a belly
    /// do not: they are bumps, neither limbs nor cut inside.
    pub(crate) fn protrudes(&self, k: usize, parent: usize, children: &[Vec<usize>]) -> bool {
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
    pub(crate) fn profile(&self, k: usize) -> Option<Profile> {
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
    pub(crate) fn inner_cuts(
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

    /// A limb's own ring past its fork at `low` (the lowest `g` of its segment `seg`):
    /// its vertices one to three radii out, where it is round; on a low-poly limb whose
    /// edges span more than two radii that window can hold none, and it is then the row
    /// of vertices just past its start ([`Tree::past_level`]). Empty only where the
    /// segment does not reach a radius past its fork.
    pub(crate) fn own_ring(&self, seg: &[u32], low: f64) -> Vec<u32> {
        let ring = self.ring(seg, low + 1.0, low + 3.0);
        if ring.is_empty() {
            self.past_level(seg, low + 1.0)
        } else {
            ring
        }
    }

    /// A cut through the ring of `seg` at level `at`, across the axis (from the centre of
    /// the ring a radius below to the one a radius above), its pivot on the axis.
    pub(crate) fn cut_at(&self, k: usize, at: f64) -> Option<Limb> {
        let seg = &self.segments[k].vertices;
        let half = 0.25;
        let ring = self.ring(seg, at - half, at + half);
        let (mut below, mut above) = (
            self.ring(seg, at - 1.0 - half, at - 1.0 + half),
            self.ring(seg, at + 1.0 - half, at + 1.0 + half),
        );
        // On a low-poly limb, whose edges span more than a radius each, both windows a
        // radius either side can be empty, and the cut would have no normal: the rows
        // of vertices just past those levels give it (`Tree::past_level`).
        if below.is_empty() && above.is_empty() {
            below = self.past_level(seg, at - 1.0);
            above = self.past_level(seg, at + 1.0);
        }
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
pub(crate) struct Shape<'a> {
    pub(crate) children: &'a [Vec<usize>],
    /// Each segment's base cut, if it is a limb.
    pub(crate) base: &'a [Option<Limb>],
    /// The nearest limb at or below each segment (the root's segment for the body).
    pub(crate) owner: &'a [usize],
    /// Per owner: limbs that hang from it, and those of them no limb grows from.
    pub(crate) limbs_from: &'a [usize],
    pub(crate) tips_from: &'a [usize],
    /// The root is a palm: the tips hanging from it are digits.
    pub(crate) palm: bool,
    /// The root's segment.
    pub(crate) root: usize,
}
