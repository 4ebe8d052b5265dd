//! A band's weight over the surface: continuous across the seam, however the skeleton
//! runs under it.
//!
//! A band's first guess weights each vertex by where its skeletal point lies across the
//! band ([`super::band`]). That is a continuous deformation only where the skeleton is a
//! line under the skin (a limb): across a face, or a thick trunk, two neighbouring
//! vertices can have skeletal points far apart (the lips of a mouth), or lie on either
//! side of the band's reach (a body vertex just beyond `2.5 r` of a wide neck beside one
//! inside it), and the skin between them tears when the joint turns (the pose issue
//! measured 44× on the human's face, 65× on the koala's neck).
//!
//! So the weight is the **harmonic** extension of the sections' labels (1 on the child's
//! subtree, 0 elsewhere) over a free region around the seam, the mesh edges where the
//! labels change: each free vertex's share is the average of its neighbours' (weighted by
//! inverse edge length), and a vertex outside the region keeps its label. The free region
//! is
//! * the band itself (the vertices its first guess moves), and
//! * the parent's vertices within [`SEAM_REACH`] × the seam's radius (how far the seam
//!   lies from the pivot's line, across the cut's normal) of the seam, along the surface:
//!   a thick joint (a head on a body, a hip) bends over a strip as wide as it is thick:
//!   where the seam moves with share `w` of the turn (a half to two thirds on an arc, up
//!   to 0.7 on a fan, whose child side starts deeper in the turn), a turn by `θ` stretches a
//!   strip `R` radii wide by about `1 + θ w / R` at most, so the strip is `SEAM_REACH · w
//!   / 0.5` radii wide, its stretch bounded alike on both kinds. Each
//!   seam vertex reaches by its own radius (at least the median's): a flat seam (an ear,
//!   a flipper) lies far from the pivot's line at its edges, a turn moves them farther,
//!   and a strip as wide as the median's tears there (`puppet bench poses`).
//!
//! The child's vertices beyond the band stay 1 (a head beyond its neck turns whole), and
//! every vertex of another section keeps its label, so only this band's two sections
//! blend. On a limb the harmonic weight is the first guess again (linear along a tube).
//! The system is solved by conjugate gradients, from the first guess.
//!
//! The harmonic weight can still step steeply where the child's side is held deep in the
//! turn beside a parent's vertex near the pivot (a flipper's seam: its weight went 0.68 →
//! 0.84 over an edge a seventh of the skin's thickness there, 4.2× at the penguin's
//! flipper turned). So its **slope is bounded** last: along an edge it changes by at most
//! [`SLOPE`] per edge length over the distance from the pivot, which bounds how far a turn
//! pulls the edge's ends apart. Each free weight becomes the mean of the largest function
//! under the weights with that slope and the smallest over them: where the weights keep
//! the slope both are the weight, and a step is spread evenly to either side. A step
//! against a fixed weight (a vertex of another section, which keeps its label) can only
//! move its free end, so each free weight is first held within the slope of every fixed
//! one: a neck beside a hindquarters' band stays within the slope of the head, which that
//! band does not move (a downloaded deer tore 5.0× there when the mean halved the step).
//!
//! **Where bands overlap** on a parent's side, their turns add: three limbs of one trunk
//! (an arm, a neck and a waist) each move the skin of an armpit partly, each within its
//! own slope, and a pose that turns all three stretched an edge there 3.4× (a downloaded
//! king). So a band's slope is bounded twice: the first pass counts, per vertex, the
//! bands that move it partly (a level strictly between the parent's and the child's);
//! the second bounds again, from the same harmonic weights, the slope of each band with
//! such a vertex on its parent's side, along an edge whose two ends lie on that side and
//! are moved by `o ≥ 2` bands (the larger count), by `SLOPE / √o`. A gentler slope
//! spreads a step wider, and where the free strip has no room for it the step stays
//! against a fixed weight or at the strip's edge: so each edge that the shared bound
//! leaves steeper than the bound alone did gets the bound alone back at its ends and
//! their neighbours, up to [`SHARED_TRIES`] times, then the band keeps the bound alone.
//! Only the parent's side shares: the child's side of one band where another's parent
//! side overlaps it (a rat's head under its ears) tore more when shared. `SLOPE / o` and
//! `SLOPE / o^¼` were measured too, chosen on half of `puppet bench poses`' characters
//! (every other one); the other half is in `docs/performance-log.md`.

use super::Joints;
use glam::DVec3;
use std::collections::BinaryHeap;

/// How far along the surface, in seam radii, the parent's side of a band reaches from the
/// seam where the seam moves with half the turn (an arc's); a seam that moves with share
/// `w` of it reaches `w / 0.5` times as far, so the strip's stretch is bounded alike (see
/// the module docs). Chosen on half of `puppet bench poses`' characters (every other one)
/// from 0.75 to 2.25 (a fan's and an arc's apart too, and in proportion to the share), by
/// characters within 3× on every pose, then the worst stretch's 90th percentile, then its
/// median; that half reads nearly alike over the range, the other half's figures are in
/// `docs/performance-log.md`.
pub const SEAM_REACH: f64 = 1.25;

/// How many times a limb's slope (the band's weight over its length) a first guess may
/// change along an edge before it is a jump, not a limb's skeleton (a head's skeletal
/// points at its centre, a chest's under a tucked arm). Chosen on half of
/// `puppet bench poses`' characters (every other one) from 1.5, 2, 3, 4, 6 and none, by
/// characters within 3× on every pose, then the worst stretch's 90th percentile, then its
/// median; `docs/performance-log.md` has the other half.
pub const JUMP: f64 = 2.0;

/// How much a band's weight may change along an edge, per the edge's length over its
/// distance from the pivot (at least the seam's radius): a turn by `θ` radians moves the
/// ends of an edge whose weights differ by `Δw` apart by at most `θ Δw` times their
/// distance from the pivot, so the rig stretches such an edge by at most `1 + θ · SLOPE`
/// (2.6× at 90°). Chosen on half of `puppet bench poses`' characters (every other one)
/// from 0.5, 0.75, 1, 1.25, 1.5 and 2 (and none), as [`SEAM_REACH`] was; a smaller slope
/// spreads a step farther than the free strip reaches and tears at its edge.
/// `docs/performance-log.md` has the other half.
pub const SLOPE: f64 = 1.0;

/// How many times a band's slope bounded together with the others' ([`Joints::limit_slope`])
/// gives the bound alone back around the edges it leaves steeper, before it keeps the
/// bound alone everywhere (see the module docs: *Where bands overlap*).
const SHARED_TRIES: usize = 4;

/// What a band's slope is bounded together with: per vertex, how many bands move it
/// partly (`overlap`, empty on the first pass), on the band's `parent`'s side; and its
/// free weights as the first pass bounded them (`alone`).
#[derive(Clone, Copy)]
struct Shared<'a> {
    overlap: &'a [u8],
    parent: usize,
    alone: &'a [f64],
}

/// A band's weight over the surface before its slope is bounded ([`Joints::harmonic`]).
pub(super) enum Harmonic {
    /// Nothing to solve: the weights as they stand (no seam: the first guess, its slope
    /// bounded on its own).
    Done(Vec<(usize, f64)>),
    /// The harmonic extension over the free region.
    Solved(Solved),
}

/// The harmonic weight of a band's free vertices, and what bounding its slope reads.
pub(super) struct Solved {
    /// The free vertices.
    free: Vec<usize>,
    /// The free vertices' weights.
    x: Vec<f64>,
    /// The same with the slope bounded by each band alone (the first pass).
    alone: Vec<f64>,
    /// The band's vertices held exactly at their first guess.
    kept: Vec<(usize, f64)>,
    /// The pivot the slope is measured from, and the least distance from it.
    pivot: DVec3,
    radius: f64,
    /// The band's sections, and those it carries at their positions: what the fixed
    /// vertices' weights are made from again (`Joints::labels`; kept small, where a
    /// vertex's weight for every band would not be).
    child: usize,
    parent: usize,
    carried: Vec<(usize, f64)>,
}

/// A vertex's place in a band's free weights when it has none: fixed at its label.
const NOT: u32 = u32::MAX;
/// … when it is the band's own, held exactly at its first guess.
const KEPT: u32 = u32::MAX - 1;

/// Conjugate-gradient steps at most, and the residual (relative to the first) at which
/// the weights are taken as solved.
const MAX_ITERATIONS: usize = 400;
const TOLERANCE: f64 = 1e-6;

/// How a band's own vertices keep their first guess.
#[derive(Clone, Copy, Debug)]
pub(super) enum Hold {
    /// Exactly: an arc's levels are places along its bent centre line, which a vertex's
    /// weight must match (on a limb its skeletal point gives it, continuously); only the
    /// parent's side around it is blended, and the band's vertices within `smooth` of a
    /// place where the first guess jumps (see [`JUMP`]).
    Exact {
        /// The band's length, child and parent side together: over it the weight goes
        /// from 0 to 1.
        span: f64,
        /// How far around a jump the weight is blended instead.
        smooth: f64,
        /// The share of the turn the band moves the seam with (see [`SEAM_REACH`]).
        seam: f64,
    },
    /// Softly, a fan's: the child's within about `smooth` of a jump, the parent's not at
    /// all, and the child's vertices within `reach` of the seam blend too.
    Soft {
        /// How far into the child the seam's neighbourhood blends.
        reach: f64,
        /// Over what distance a jump in the first guess is smoothed.
        smooth: f64,
        /// The share of the turn the band moves the seam with (see [`SEAM_REACH`]).
        seam: f64,
    },
}

/// A band's vertex with its weight's first guess.
pub(super) struct Guess {
    /// The vertex.
    pub vertex: usize,
    /// Its position across the band (0: the parent's end, 1: the child's).
    pub x: f64,
}

impl Joints {
    /// Band `k`'s free vertices with their position across it (`0..=1`, see the module
    /// docs) before its slope is bounded ([`Joints::bounded`]), from `guess` (the band's
    /// own vertices, by their skeletal points), `child` and `parent` its sections and
    /// `pivot`, `normal` its frame. The parent's other children in `carried` (section,
    /// position) ride on the band at that position, their subtrees with them, and the
    /// parent's skin around their seams is free too (see [`super::band`]: *carried*).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn harmonic(
        &self,
        child: usize,
        parent: usize,
        pivot: DVec3,
        normal: DVec3,
        hold: Hold,
        guess: &[Guess],
        carried: &[(usize, f64)],
    ) -> Harmonic {
        let (exact, width, smooth, seam_share) = match hold {
            Hold::Exact { smooth, seam, .. } => (true, 0.0, smooth, seam),
            Hold::Soft {
                reach,
                smooth,
                seam,
            } => (false, reach, smooth, seam),
        };
        // A seam that moves with more of the turn than half bends over a wider strip.
        let seam_reach = SEAM_REACH * (seam_share / 0.5).max(1.0);
        let n = self.section_of.len();
        let body = &self.body;
        if body.start.len() != n + 1 || body.rest.len() != n {
            return Harmonic::Done(guess.iter().map(|g| (g.vertex, g.x)).collect());
        }
        // Which sections move with the child.
        let moves = self.moves_with(child);
        let label = |i: usize| f64::from(u8::from(moves[usize::from(self.section_of[i])]));
        // The sections carried, each at its position, their subtrees with them.
        let carry = self.carry_of(parent, carried);
        let ours = |i: usize| {
            let s = usize::from(self.section_of[i]);
            !self.body.is_rider(i) && (s == child || s == parent)
        };
        // The parent's other children: near the seam they move with the parent's side
        // (unless carried whole).
        let beside = |i: usize| {
            let s = usize::from(self.section_of[i]);
            !self.body.is_rider(i)
                && s != child
                && self.sections[s].parent == Some(parent)
                && carry[s].is_none()
        };
        // The seam, and how far it lies from the pivot's line.
        let mut seam = Vec::new();
        let mut radii = Vec::new();
        for i in (0..n).filter(|&i| ours(i) || beside(i)) {
            let l = label(i);
            if self
                .body
                .neighbours(i)
                .iter()
                .any(|&j| !self.body.is_rider(j as usize) && label(j as usize) != l)
            {
                seam.push(i);
                let v = body.rest[i] - pivot;
                radii.push((v - normal * v.dot(normal)).length());
            }
        }
        let across = radii.clone();
        let Some(radius) = crate::stats::median(&mut radii) else {
            // No seam: the child is a piece that meets its parent only where the two
            // pass into each other (a walker's leg). Nothing blends across, but its
            // first guess still keeps the slope (module docs).
            let fixed = self.labels(&moves, &carry);
            return Harmonic::Done(self.sloped_guess(guess, &fixed, pivot, normal));
        };
        let reach = seam_reach * radius;
        // Free: the band, and the parent's vertices within `reach` of the seam.
        let mut index = vec![NOT; n];
        let mut free: Vec<usize> = Vec::new();
        let mut x: Vec<f64> = Vec::new();
        // A fixed vertex's weight: its label, or (held exactly) its first guess.
        let mut fixed = self.labels(&moves, &carry);
        let mut kept: Vec<(usize, f64)> = Vec::new();
        let loose = match hold {
            Hold::Exact { span, smooth, .. } => {
                self.jumps(guess, span, smooth, &moves, (pivot, radius))
            }
            Hold::Soft { .. } => Vec::new(),
        };
        for g in guess {
            if exact && !loose.get(g.vertex).copied().unwrap_or(false) {
                fixed[g.vertex] = g.x;
                kept.push((g.vertex, g.x));
                index[g.vertex] = KEPT;
            } else if index[g.vertex] == NOT && (ours(g.vertex) || exact) {
                index[g.vertex] = free.len() as u32;
                free.push(g.vertex);
                x.push(g.x);
            }
        }
        // The parent's side within `reach` of the seam; the child's within the band's
        // width of it (across a face, a lip whose skeletal point lies deep in the head),
        // unless that frees the whole child (it must keep vertices that turn whole).
        let parent_side = |i: usize| usize::from(self.section_of[i]) == parent || beside(i);
        // Each seam vertex reaches by its own radius, at least the median's (module docs).
        let mut from: Vec<(usize, f64)> = seam
            .iter()
            .zip(&across)
            .map(|(&i, &r)| (i, seam_reach * r.max(radius)))
            .collect();
        from.extend(
            guess
                .iter()
                .map(|g| g.vertex)
                .filter(|&i| parent_side(i))
                .map(|i| (i, reach)),
        );
        // Around a carried section's seam the parent's skin blends from its position.
        if !carried.is_empty() {
            from.extend(
                (0..n)
                    .filter(|&i| {
                        usize::from(self.section_of[i]) == parent
                            && !self.body.is_rider(i)
                            && self
                                .body
                                .neighbours(i)
                                .iter()
                                .any(|&j| carry[usize::from(self.section_of[j as usize])].is_some())
                    })
                    .map(|i| (i, reach)),
            );
        }
        for i in self.within_each(&from, |i| (ours(i) || beside(i)) && parent_side(i)) {
            if index[i] == NOT && parent_side(i) {
                index[i] = free.len() as u32;
                free.push(i);
                x.push(0.0);
            }
        }
        let child_side = |i: usize| usize::from(self.section_of[i]) == child;
        if width > 0.0 {
            let near: Vec<usize> = self
                .within(&seam, width, |i| ours(i) && child_side(i))
                .into_iter()
                .map(|(i, _)| i)
                .filter(|&i| index[i] == NOT && child_side(i))
                .collect();
            // (`near` holds distinct fixed vertices of the child: some stays fixed when
            // there are more.)
            let fixed_child = (0..n).filter(|&i| child_side(i) && index[i] == NOT).count();
            if fixed_child > near.len() {
                for i in near {
                    index[i] = free.len() as u32;
                    free.push(i);
                    x.push(1.0);
                }
            }
        }
        // The system: for each free vertex, Σ a_ij (x_i − x_j) = 0 over its neighbours,
        // a_ij = 1 / |e_ij|, the fixed neighbours' labels on the right.
        let m = free.len();
        // The band's own vertices are held to their first guess, softly: it gives the
        // weight's shape along a limb, and the smoothing its continuity over the surface
        // within about `smooth` of a jump.
        let held = if exact {
            0
        } else {
            guess.iter().filter(|g| index[g.vertex] != NOT).count()
        };
        let mut diagonal = vec![0.0; m];
        let mut rhs = vec![0.0; m];
        let mut start = Vec::with_capacity(m + 1);
        let mut columns: Vec<u32> = Vec::new();
        let mut values: Vec<f64> = Vec::new();
        start.push(0u32);
        for (r, &i) in free.iter().enumerate() {
            for &j in self.body.neighbours(i) {
                let j = j as usize;
                if self.body.is_rider(j) {
                    continue;
                }
                let a = 1.0 / body.rest[i].distance(body.rest[j]).max(1e-12);
                diagonal[r] += a;
                if index[j] == NOT || index[j] == KEPT {
                    rhs[r] += a * fixed[j];
                } else {
                    columns.push(index[j]);
                    values.push(a);
                }
            }
            start.push(columns.len() as u32);
            if r < held && usize::from(self.section_of[i]) == child {
                let e = self
                    .body
                    .neighbours(i)
                    .iter()
                    .map(|&j| body.rest[i].distance(body.rest[j as usize]))
                    .sum::<f64>()
                    / self.body.neighbours(i).len().max(1) as f64;
                let hold = diagonal[r] * (e / smooth).powi(2);
                diagonal[r] += hold;
                rhs[r] += hold * x[r];
            }
        }
        let multiply = |v: &[f64], out: &mut [f64]| {
            for r in 0..m {
                let mut s = diagonal[r] * v[r];
                for e in start[r] as usize..start[r + 1] as usize {
                    s -= values[e] * v[columns[e] as usize];
                }
                out[r] = s;
            }
        };
        conjugate_gradient(&multiply, &diagonal, &rhs, &mut x);
        let mut alone = x.clone();
        self.limit_slope(&free, &index, &fixed, &mut alone, (pivot, radius), None);
        Harmonic::Solved(Solved {
            free,
            x,
            alone,
            kept,
            pivot,
            radius,
            child,
            parent,
            carried: carried.to_vec(),
        })
    }

    /// Per section, the position across a band of `parent` at which it is carried
    /// (`carried`, each with its subtree), `None` for the others.
    fn carry_of(&self, parent: usize, carried: &[(usize, f64)]) -> Vec<Option<f64>> {
        let mut carry: Vec<Option<f64>> = vec![None; self.sections.len()];
        for &(s, x) in carried {
            if let Some(c) = carry.get_mut(s) {
                *c = Some(x);
            }
        }
        for &s in &self.order {
            if let Some(p) = self.sections[s].parent.filter(|&p| p != parent) {
                carry[s] = carry[s].or(carry[p]);
            }
        }
        carry
    }

    /// Per vertex, its section's label: the position it is carried at (`carry`), else 1
    /// where the section `moves` with the child and 0 elsewhere.
    fn labels(&self, moves: &[bool], carry: &[Option<f64>]) -> Vec<f64> {
        self.section_of
            .iter()
            .map(|&s| {
                let s = usize::from(s);
                carry[s].unwrap_or(f64::from(u8::from(moves[s])))
            })
            .collect()
    }

    /// The weights of `harmonic` with their slope bounded (`limit_slope`), together with
    /// the other bands' where `overlap` (per vertex, how many bands move it partly; empty
    /// on the first pass) counts two or more on the parent's side (the module docs:
    /// *Where bands overlap*).
    pub(super) fn bounded(&self, harmonic: &Harmonic, overlap: &[u8]) -> Vec<(usize, f64)> {
        let h = match harmonic {
            Harmonic::Done(weights) => return weights.clone(),
            Harmonic::Solved(h) => h,
        };
        let shares = overlap.len() == self.section_of.len()
            && h.free
                .iter()
                .any(|&i| overlap[i] >= 2 && usize::from(self.section_of[i]) == h.parent);
        let x = if shares {
            // The fixed weights and each vertex's place, as the first pass had them.
            let moves = self.moves_with(h.child);
            let mut fixed = self.labels(&moves, &self.carry_of(h.parent, &h.carried));
            let mut index = vec![NOT; fixed.len()];
            for &(i, w) in &h.kept {
                fixed[i] = w;
                index[i] = KEPT;
            }
            for (r, &i) in h.free.iter().enumerate() {
                index[i] = r as u32;
            }
            let mut x = h.x.clone();
            let shared = Shared {
                overlap,
                parent: h.parent,
                alone: &h.alone,
            };
            self.limit_slope(
                &h.free,
                &index,
                &fixed,
                &mut x,
                (h.pivot, h.radius),
                Some(shared),
            );
            x
        } else {
            h.alone.clone()
        };
        h.free
            .iter()
            .zip(x)
            .map(|(&i, x)| (i, x.clamp(0.0, 1.0)))
            .chain(h.kept.iter().copied())
            .collect()
    }

    /// The first guess `guess` with its slope bounded ([`SLOPE`], `limit_slope`) against
    /// the `fixed` weights of the vertices outside it, for a band with no seam: the
    /// radius the slope is measured from is the guess's median distance from the pivot's
    /// line (`normal` through `pivot`). A rider keeps its guess.
    fn sloped_guess(
        &self,
        guess: &[Guess],
        fixed: &[f64],
        pivot: DVec3,
        normal: DVec3,
    ) -> Vec<(usize, f64)> {
        let rest = &self.body.rest;
        let mut index = vec![NOT; fixed.len()];
        let (mut free, mut x, mut across, mut riders) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for g in guess {
            if self.body.is_rider(g.vertex) {
                riders.push((g.vertex, g.x));
            } else if index[g.vertex] == NOT {
                index[g.vertex] = free.len() as u32;
                free.push(g.vertex);
                x.push(g.x);
                across.push((rest[g.vertex] - pivot).reject_from(normal).length());
            }
        }
        let radius = crate::stats::median(&mut across).unwrap_or(0.0);
        self.limit_slope(&free, &index, fixed, &mut x, (pivot, radius), None);
        free.into_iter()
            .zip(x)
            .map(|(i, x)| (i, x.clamp(0.0, 1.0)))
            .chain(riders)
            .collect()
    }

    /// Which of the band's vertices lie within `smooth` of a jump in their first guess
    /// `guess` (`span` the band's length, `moves` per section: the band's child or a section
    /// hanging from it), by vertex: an edge
    /// whose two ends' guesses differ by more than [`JUMP`] times what a limb's skeleton
    /// gives over its length, or by more than [`SLOPE`] allows that far from the pivot (a
    /// fin's tip, far off the pivot's line, on a limb's ramp); `pivot` and `radius` as in
    /// `limit_slope`. A vertex of the child or of a section hanging from it, outside the
    /// band, counts as 1 (a thumb at the end of a palm the wrist's band covers turns whole
    /// with the hand).
    fn jumps(
        &self,
        guess: &[Guess],
        span: f64,
        smooth: f64,
        moves: &[bool],
        (pivot, radius): (DVec3, f64),
    ) -> Vec<bool> {
        let n = self.section_of.len();
        let mut first = vec![f64::NAN; n];
        for g in guess {
            first[g.vertex] = g.x;
        }
        let rest = &self.body.rest;
        let mut from = Vec::new();
        for g in guess {
            let i = g.vertex;
            let jumps = self.body.neighbours(i).iter().any(|&j| {
                let j = j as usize;
                let other = match first[j] {
                    x if !x.is_nan() => x,
                    _ if moves[usize::from(self.section_of[j])] && !self.body.is_rider(j) => 1.0,
                    _ => return false,
                };
                let (step, length) = ((g.x - other).abs(), rest[i].distance(rest[j]));
                // Steeper than a limb's skeleton gives, or than the slope allows this far
                // from the pivot (a fin's tip, far off the pivot's line).
                let far = rest[i]
                    .distance(pivot)
                    .max(rest[j].distance(pivot))
                    .max(radius);
                step * span > JUMP * length || step > SLOPE * length / far
            });
            if jumps {
                from.push(i);
            }
        }
        let mut loose = vec![false; n];
        if from.is_empty() {
            return loose;
        }
        for (i, _) in self.within(&from, smooth, |i| !first[i].is_nan()) {
            loose[i] = true;
        }
        loose
    }

    /// Bounds the weight's slope over the free vertices `free` (their weights `x`, each
    /// one's place in `x` by `index`, every other vertex's weight in `fixed`, which stays):
    /// along an edge it changes by at most [`SLOPE`] times the edge's length over its
    /// distance from `pivot` (at least `radius`), and less where `shared` counts other
    /// bands moving the band's parent's side there (the module docs: *Where bands
    /// overlap*), where that leaves no step steeper than the bound alone left it.
    fn limit_slope(
        &self,
        free: &[usize],
        index: &[u32],
        fixed: &[f64],
        x: &mut [f64],
        (pivot, radius): (DVec3, f64),
        shared: Option<Shared<'_>>,
    ) {
        if free.is_empty() {
            return;
        }
        let rest = &self.body.rest;
        let bound = |i: usize, j: usize| {
            let far = rest[i]
                .distance(pivot)
                .max(rest[j].distance(pivot))
                .max(radius);
            SLOPE * rest[i].distance(rest[j]) / far
        };
        // Per vertex on the band's parent's side, how many bands move it partly.
        let shared_by = |i: usize| match shared {
            Some(Shared {
                overlap, parent, ..
            }) if overlap.len() == rest.len() && usize::from(self.section_of[i]) == parent => {
                Some(overlap[i])
            }
            _ => None,
        };
        let alone = match shared {
            Some(s) => s.alone.to_vec(),
            None => {
                let mut alone = x.to_vec();
                self.bound_slope(free, index, fixed, &mut alone, &bound);
                alone
            }
        };
        if !free.iter().any(|&i| shared_by(i).is_some_and(|o| o >= 2)) {
            x.copy_from_slice(&alone);
            return;
        }
        let value = |i: usize, x: &[f64]| match index[i] {
            k if (k as usize) < x.len() => x[k as usize],
            _ => fixed[i],
        };
        // Vertices where the strip has no room for the shared bound: each edge whose step
        // it leaves steeper than the bound alone did, its ends and their neighbours.
        let mut no_room = vec![false; rest.len()];
        for _ in 0..SHARED_TRIES {
            let cost = |i: usize, j: usize| {
                let o = shared_by(i).zip(shared_by(j)).map_or(0, |(a, b)| a.max(b));
                if o >= 2 && !no_room[i] && !no_room[j] {
                    bound(i, j) / f64::from(o).sqrt()
                } else {
                    bound(i, j)
                }
            };
            let mut together = x.to_vec();
            self.bound_slope(free, index, fixed, &mut together, &cost);
            let mut steeper = Vec::new();
            for &i in free {
                for &j in self.body.neighbours(i) {
                    let j = j as usize;
                    if self.body.is_rider(j) {
                        continue;
                    }
                    let past = |w: &[f64]| (value(i, w) - value(j, w)).abs() - bound(i, j);
                    if past(&together) > past(&alone).max(0.0) + 1e-9 {
                        steeper.extend([i, j]);
                    }
                }
            }
            if steeper.is_empty() {
                x.copy_from_slice(&together);
                return;
            }
            for i in steeper {
                no_room[i] = true;
                for &j in self.body.neighbours(i) {
                    no_room[j as usize] = true;
                }
            }
        }
        x.copy_from_slice(&alone);
    }

    /// [`Joints::limit_slope`] by the bound `cost` per edge: each free weight is first
    /// held within that slope of every fixed weight (where they leave room), then becomes
    /// the mean of the largest function under the weights with that slope and the
    /// smallest over them (see the module docs), each by Dijkstra seeded at the ends of
    /// the edges that step more steeply: no other weight can lower or raise a neighbour.
    fn bound_slope(
        &self,
        free: &[usize],
        index: &[u32],
        fixed: &[f64],
        x: &mut [f64],
        cost: &impl Fn(usize, usize) -> f64,
    ) {
        let value = |i: usize, x: &[f64]| match index[i] {
            k if (k as usize) < x.len() => x[k as usize],
            _ => fixed[i],
        };
        let len = x.len();
        let is_free = |j: usize| (index[j] as usize) < len;
        // First each free weight within the slope of every fixed one, where the fixed ones
        // leave room for that: the mean below halves a step, and against a fixed weight
        // only the free end can move (a neck beside a tail's band, its weight a step
        // above its head's).
        let mut fixed_seeds = Vec::new();
        for &i in free {
            for &j in self.body.neighbours(i) {
                let j = j as usize;
                if !is_free(j) && !self.body.is_rider(j) {
                    fixed_seeds.push(j);
                }
            }
        }
        let mut upper = vec![f64::INFINITY; len];
        self.lower_from(
            &mut upper,
            fixed_seeds.iter().map(|&j| (j, fixed[j])),
            index,
            &cost,
        );
        // (The most under a weight less the cost: the least over its negative plus it.)
        let mut lower = vec![f64::INFINITY; len];
        self.lower_from(
            &mut lower,
            fixed_seeds.iter().map(|&j| (j, -fixed[j])),
            index,
            &cost,
        );
        lower.iter_mut().for_each(|w| *w = -*w);
        for (k, w) in x.iter_mut().enumerate() {
            if lower[k] <= upper[k] {
                *w = w.clamp(lower[k], upper[k]);
            }
        }
        // Only a step steeper than the slope moves a weight: the ends of such edges seed
        // the two passes (the lower end the pass under, the higher the pass over).
        let (mut low, mut high) = (Vec::new(), Vec::new());
        for &i in free {
            let v = value(i, x);
            for &j in self.body.neighbours(i) {
                let j = j as usize;
                if self.body.is_rider(j) || (is_free(j) && j < i) {
                    continue;
                }
                let w = value(j, x);
                if (v - w).abs() > cost(i, j) {
                    let (lo, hi) = if v < w { (i, j) } else { (j, i) };
                    low.push(lo);
                    high.push(hi);
                }
            }
        }
        if low.is_empty() {
            return;
        }
        // Under: the least over sources of weight + cost to reach; over: the most over
        // sources of weight − cost.
        let mut under = x.to_vec();
        self.lower_from(
            &mut under,
            low.iter().map(|&i| (i, value(i, x))),
            index,
            &cost,
        );
        let mut over: Vec<f64> = x.iter().map(|w| -w).collect();
        self.lower_from(
            &mut over,
            high.iter().map(|&i| (i, -value(i, x))),
            index,
            &cost,
        );
        over.iter_mut().for_each(|w| *w = -*w);
        for (k, w) in x.iter_mut().enumerate() {
            *w = 0.5 * (under[k] + over[k]);
        }
    }

    /// Lowers each free weight in `out` (its place by `index`; a vertex is free when that
    /// place is inside `out`) to the least over `seeds` (vertex, weight) of the seed's weight
    /// plus the `cost` of the way there over free vertices (Dijkstra; riders are no way).
    fn lower_from(
        &self,
        out: &mut [f64],
        seeds: impl IntoIterator<Item = (usize, f64)>,
        index: &[u32],
        cost: &impl Fn(usize, usize) -> f64,
    ) {
        let len = out.len();
        let is_free = |j: usize| (index[j] as usize) < len;
        let mut heap: BinaryHeap<Near> = seeds.into_iter().map(|(i, v)| Near(v, i)).collect();
        while let Some(Near(v, i)) = heap.pop() {
            if is_free(i) && v > out[index[i] as usize] {
                continue;
            }
            for &j in self.body.neighbours(i) {
                let j = j as usize;
                if !is_free(j) || self.body.is_rider(j) {
                    continue;
                }
                let c = v + cost(i, j);
                if c < out[index[j] as usize] {
                    out[index[j] as usize] = c;
                    heap.push(Near(c, j));
                }
            }
        }
    }

    /// The vertices (where `pass` holds) within each source's own reach of it along mesh
    /// edges (`from`: vertex, reach; Dijkstra on the reach left).
    fn within_each(&self, from: &[(usize, f64)], pass: impl Fn(usize) -> bool) -> Vec<usize> {
        let n = self.section_of.len();
        let mut left = vec![f64::NEG_INFINITY; n];
        let mut heap = BinaryHeap::new();
        for &(i, reach) in from {
            if reach > left[i] {
                left[i] = reach;
                heap.push(Left(reach, i));
            }
        }
        let mut out = Vec::new();
        while let Some(Left(l, i)) = heap.pop() {
            if l < left[i] {
                continue;
            }
            left[i] = f64::INFINITY;
            out.push(i);
            for &j in self.body.neighbours(i) {
                let j = j as usize;
                if !pass(j) {
                    continue;
                }
                let rest = l - self.body.rest[i].distance(self.body.rest[j]);
                if rest >= 0.0 && rest > left[j] {
                    left[j] = rest;
                    heap.push(Left(rest, j));
                }
            }
        }
        out
    }

    /// The vertices (where `pass` holds) within `reach` of `from` along mesh edges, with
    /// their distance (Dijkstra).
    fn within(
        &self,
        from: &[usize],
        reach: f64,
        pass: impl Fn(usize) -> bool,
    ) -> Vec<(usize, f64)> {
        let n = self.section_of.len();
        let mut best = vec![f64::INFINITY; n];
        let mut heap = BinaryHeap::new();
        for &i in from {
            best[i] = 0.0;
            heap.push(Near(0.0, i));
        }
        let mut out = Vec::new();
        while let Some(Near(d, i)) = heap.pop() {
            if d > best[i] {
                continue;
            }
            out.push((i, d));
            for &j in self.body.neighbours(i) {
                let j = j as usize;
                if !pass(j) {
                    continue;
                }
                let e = d + self.body.rest[i].distance(self.body.rest[j]);
                if e <= reach && e < best[j] {
                    best[j] = e;
                    heap.push(Near(e, j));
                }
            }
        }
        out
    }
}

/// A vertex and the reach left there, most first in a max-heap.
#[derive(PartialEq)]
struct Left(f64, usize);

impl Eq for Left {}

impl PartialOrd for Left {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Left {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0).then(other.1.cmp(&self.1))
    }
}

/// A vertex and its distance, nearest first in a max-heap.
#[derive(PartialEq)]
struct Near(f64, usize);

impl Eq for Near {}

impl PartialOrd for Near {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Near {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

/// Solves `A x = b` for a symmetric positive semi-definite `A` (given by `multiply`, with
/// its `diagonal` as the preconditioner) from the `x` given.
fn conjugate_gradient(
    multiply: &dyn Fn(&[f64], &mut [f64]),
    diagonal: &[f64],
    b: &[f64],
    x: &mut [f64],
) {
    let m = b.len();
    if m == 0 {
        return;
    }
    let mut r = vec![0.0; m];
    multiply(x, &mut r);
    for k in 0..m {
        r[k] = b[k] - r[k];
    }
    let precondition = |r: &[f64], z: &mut [f64]| {
        for k in 0..m {
            z[k] = if diagonal[k] > 0.0 {
                r[k] / diagonal[k]
            } else {
                0.0
            };
        }
    };
    let mut z = vec![0.0; m];
    precondition(&r, &mut z);
    let mut p = z.clone();
    let mut rz: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
    let first = rz.abs().sqrt().max(f64::MIN_POSITIVE);
    let mut ap = vec![0.0; m];
    for _ in 0..MAX_ITERATIONS {
        if rz.abs().sqrt().is_nan() || rz.abs().sqrt() <= TOLERANCE * first {
            break;
        }
        multiply(&p, &mut ap);
        let pap: f64 = p.iter().zip(&ap).map(|(a, b)| a * b).sum();
        if pap.is_nan() || pap <= 0.0 {
            break;
        }
        let alpha = rz / pap;
        for k in 0..m {
            x[k] += alpha * p[k];
            r[k] -= alpha * ap[k];
        }
        precondition(&r, &mut z);
        let next: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
        let beta = next / rz;
        rz = next;
        for k in 0..m {
            p[k] = z[k] + beta * p[k];
        }
    }
}
