//! Each section's volume kept in a pose, measured: the slides ([`super::slide`]) keep it
//! to first order from rates found once per rig, and what they leave (large turns, three
//! bends on one section, a trunk whose side neither slides nor swells, a slide held at its
//! largest) is measured in the pose and given back by swelling the bands' levels.
//!
//! A band's side swells in two ways, each by a bump `b(x)` 0 at the band's end and at the
//! cut and 1 halfway ([`bump`] on the parent's side, [`child_bump`] on the child's), so
//! nothing beyond the band moves: across the band's line (the line through its pivot
//! along its normal) its levels scale by `1 + f b(x)`, and along the normal they move by
//! `f b(x)` of the band's radius. The flesh around a bent elbow or a turned hip bulges
//! (or thins) by what its section lost (or gained). A section's capped volume `V` (as
//! `bench poses` measures it) changes by `f K` to first order, `K = Σᵢ b(xᵢ) dᵢ · ∂V/∂pᵢ`
//! over the section's vertices on that side of the band (`dᵢ` the vertex's motion per
//! unit of swell: its offset across the line, or the radius along the normal), found
//! once per rig ([`Kept`]).
//!
//! In a pose, once the levels are made, each kept section's volume is measured where the
//! bones hold its surface (only its faces that touch a vertex not moving with it, seen
//! from the section's own frame, against the same at rest), and one Newton step swells
//! the sides that bound it, `Δf = −ΔV K / Σ K²` over its sides, for what lies beyond
//! [`TOLERANCE`] of its size (its volume, or a hundredth of the whole's for one that
//! holds little: a sheet, a fin). Each side's swell is held to [`MAX_KEEP`], and below it
//! to what the side's width allows: neighbours at levels apart move apart by up to the
//! bump's slope times a vertex's motion, so a wide child on a short band (the
//! stegosaurus's body) swells little. The swollen bands' levels, and what composes them,
//! are made again from the motions the slides left. The Newton step is first order, so a
//! second ([`NEWTON_STEPS`]) measures again the sections the first found changed by
//! more than [`AGAIN`] of their size, and the sections at their bands' other ends (a
//! side's swell moves the seam both are capped across), and swells their sides by what
//! is left: what a large change's square leaves, what a side held at its largest leaves
//! to the others, and what one end's swell took from the other.
//!
//! A band is not swollen where it carries a sibling: the sibling would ride a level
//! that no longer matches its seam. A sibling's seam in its strip swells with it (the
//! trunk between a shoulder and a neck), and the sibling's own volume is measured and
//! given back in its turn: measured on `bench poses`, leaving those bands out kept 130
//! and 166 poses of the development and held-out halves beyond ±5 % against 111 and
//! 138, with a pose more past 3× on the development half. A band where a rider's host
//! lies swells like any other: the rider (an eye, a crown, a backpack) rides on its
//! host's motion made rigid ([`super::band::Twin`]), not scaled with the level about a
//! line it may lie far from (what swelling those bands gives: `docs/performance-log.md`,
//! seventh session of 2026-12-04). The suggestion's tear check poses without swelling
//! ([`super::PoseScratch::first_order`]).

use super::band::LEVELS;
use super::slide::{along, bump};
use super::{Band, Joints};
use crate::mesh::measure::Capped;
use glam::{DAffine3, DMat3, DVec3};

/// Largest swell a side of a band is given to keep its section's volume: a share of
/// each vertex's distance from the band's line (across it), or of the band's radius
/// (along it), and no more than the side's width allows a vertex to move (see
/// [`Kept`]). Chosen with [`TOLERANCE`], and again from 0.2, 0.25, 0.3 and 0.35 once
/// the bands that host riders swell too, by the same rule on the same development
/// halves: 0.3 (poses beyond ±5 % 74 → 69, the worst stretch's 90th percentile +0.1 %;
/// 0.35 put a pose more past 3×). The held-out halves are in `docs/performance-log.md`.
pub const MAX_KEEP: f64 = 0.3;

/// Newton steps a pose takes towards its sections' volumes at most: the first measures
/// every kept section, a later one those the first found changed by more than [`AGAIN`]
/// of their size (the step is first order: what a large change leaves, and what a side
/// held at its largest leaves to the others, a second step gives back), and the
/// sections at the other ends of their bands. A side's swell moves the seam its band's
/// two sections are both capped across, so what one section gets back the other may
/// lose (the cow's arms, when its trunk swells). Chosen on the development half of
/// `puppet bench poses`' three corpora (20 seeds): poses with a section beyond ±5 % 111
/// with one step, 100 with two measuring every section again, 103 and 104 measuring
/// again those past 2 % and 5 %, 100 with three; later, with the other ends measured
/// again, 42 → 36 (the held-out half 60 → 55), every pose's worst stretch the same.
/// Measuring again only those past [`AGAIN`] and their bands' other ends keeps the
/// pose's cost (what each choice measured: `docs/performance-log.md`).
pub const NEWTON_STEPS: usize = 2;

/// See [`NEWTON_STEPS`].
pub const AGAIN: f64 = 0.05;

/// What one Newton step of [`Joints::keep_volumes`] leaves for the next.
#[derive(Clone, Debug, Default)]
pub struct Newton {
    /// This is a pose's first step.
    pub(super) first: bool,
    /// Per kept section, whether a later step measures it again.
    pub(super) again: Vec<bool>,
    /// Per band, whether this step changed its swells.
    pub(super) changed: Vec<bool>,
    /// The kept sections a later step measures because a band's other end changed.
    ends: Vec<u16>,
}

/// The share of a section's volume it may gain or lose before a pose gives it back:
/// within it nothing swells. Chosen with [`MAX_KEEP`] by `puppet bench poses` (20
/// seeds) on the development half of the shipped, in-pieces and downloaded characters
/// from 1, 2 and 3 % (and 0.15, 0.25 and 0.4): the fewest poses with a section beyond
/// ±5 % whose worst stretch held (no more poses past 3×, its 90th percentile within
/// 0.5 %, no more poses with 1 % of their edges past 1.5×). The held-out half is in
/// `docs/performance-log.md`.
pub const TOLERANCE: f64 = 0.01;

/// A section's volume change is measured against at least this share of the whole
/// mesh's volume (a small section's change is small beside the character, whatever its
/// share): see [`section_size`].
pub const SMALL_SECTION: f64 = 0.01;

/// A section's size, what its volume change is measured against (by `bench poses`, the
/// presses, the swells and the suggestion's balloon check alike): its `volume` at rest,
/// or [`SMALL_SECTION`] of the `whole` mesh's for one that holds little (a sheet, a fin).
pub fn section_size(volume: f64, whole: f64) -> f64 {
    volume.abs().max(SMALL_SECTION * whole)
}

/// The child side's swell's share at `x` across a band (`0..=1`) whose cut lies at
/// `at_cut` of its length: 0 at the cut and at the band's child end, 1 halfway between,
/// 0 on the parent's side.
pub(super) fn child_bump(at_cut: f64, x: f64) -> f64 {
    let u = ((x - at_cut) / (1.0 - at_cut).max(1e-9)).clamp(0.0, 1.0);
    4.0 * u * (1.0 - u)
}

/// One section whose volume a pose keeps (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Kept {
    /// The section.
    section: usize,
    /// Its faces that touch a vertex not moving with it, each cut across them capped.
    around: Capped,
    /// The point their volume is measured from, in the section's own frame.
    apex: DVec3,
    /// Their volume from `apex` at rest.
    rest: f64,
    /// The section's whole capped volume at rest (its size).
    size: f64,
    /// Its vertices that move with another transform than the section's.
    moved: Vec<u32>,
    /// The band sides that swell it.
    sides: Vec<Side>,
    /// `Σ K²` over `sides`.
    norm: f64,
}

/// One side of a band that swells a kept section, one way (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Side {
    /// The band, by its index among the bands that exist.
    band: u16,
    /// 0 and 1: the parent's and the child's side, across the band's line; 2 and 3: the
    /// same along its normal (the index into a band's swells).
    mode: u8,
    /// `K`: the section's volume per unit of swell.
    rate: f64,
    /// Its largest swell.
    cap: f64,
    /// The kept section at the band's other end, when it has one (by its index among
    /// the kept sections).
    other: Option<u16>,
}

impl Band {
    /// The share of a side's swell at weight `w` of the band, for (parent's, child's).
    pub(super) fn keep_shares(&self, w: f64) -> [f64; 2] {
        let x = if self.arc {
            w.clamp(0.0, 1.0)
        } else {
            along(w)
        };
        let at_cut = self.cut_share();
        [bump(at_cut, x), child_bump(at_cut, x)]
    }

    /// The motion `own` at weight `w` of the band with its sides swollen by `keep`
    /// (see the module docs): across the band's line by the parent's and child's
    /// shares `keep[0]`, `keep[1]`, and along its normal by `keep[2]`, `keep[3]` of its
    /// radius, before `own`.
    pub(super) fn kept(&self, own: DAffine3, keep: [f64; 4], w: f64) -> DAffine3 {
        if keep == [0.0; 4] {
            return own;
        }
        let [p, c] = self.keep_shares(w);
        let f = keep[0] * p + keep[1] * c;
        let along = (keep[2] * p + keep[3] * c) * self.radius;
        if f == 0.0 && along == 0.0 {
            return own;
        }
        let n = self.normal;
        let across = DMat3::IDENTITY * (1.0 + f) - DMat3::from_cols(n * n.x, n * n.y, n * n.z) * f;
        // `own * T(pivot + n along) * across * T(-pivot)` as one product (the same bits).
        let matrix3 = own.matrix3 * across;
        DAffine3 {
            matrix3,
            translation: matrix3 * -self.pivot
                + (own.matrix3 * (self.pivot + n * along) + own.translation),
        }
    }
}

impl Joints {
    /// Finds the sections a pose keeps the volume of, and the rates their bands' sides
    /// swell them by (see the module docs), from the levels every vertex got (`entries`:
    /// vertex, band slot, level; `slots`: each slot's cut). Once every vertex has its
    /// transform.
    pub(super) fn measure_kept(
        &mut self,
        entries: &[(u32, u16, u16)],
        slots: &[usize],
        surfaces: &[Capped],
    ) {
        self.kept.clear();
        let body = self.body.clone();
        let n = self.section_of.len();
        if body.triangles.is_empty() || body.rest.len() != n {
            return;
        }
        // Which bands may swell: none that carries a sibling. A third section's vertices
        // in a strip (a sibling's seam) swell with it; that section's own volume is
        // measured and given back in its turn. A rider on a swelling band rides on its
        // host's motion made rigid (`band::Twin`).
        let mut may = vec![true; slots.len()];
        for (slot, &k) in slots.iter().enumerate() {
            if self.carried.iter().any(|c| c.iter().any(|&(b, _)| b == k)) {
                may[slot] = false;
            }
        }
        // The gradient of each section's capped volume where it may swell.
        let sections = self.sections.len();
        let mut wanted = vec![false; sections];
        for (slot, &k) in slots.iter().enumerate() {
            if let Some(band) = self.bands[k].as_ref().filter(|_| may[slot]) {
                wanted[band.parent] = true;
                wanted[band.child] = true;
            }
        }
        let mut gradient = vec![DVec3::ZERO; n];
        for (_, capped) in surfaces.iter().enumerate().filter(|(s, _)| wanted[*s]) {
            for (v, g) in capped.volume_gradient(&body.rest) {
                gradient[v as usize] = g;
            }
        }
        // Per section, the sides that swell it and their rates.
        let mut sides: Vec<Vec<Side>> = vec![Vec::new(); sections];
        let mut rates = vec![[0.0f64; 4]; slots.len()];
        // Per band side, its farthest vertex from the band's line.
        let mut reach = vec![[0.0f64; 2]; slots.len()];
        for &(i, slot, level) in entries {
            let Some(band) = self.bands[slots[usize::from(slot)]]
                .as_ref()
                .filter(|_| may[usize::from(slot)])
            else {
                continue;
            };
            let s = usize::from(self.section_of[i as usize]);
            if s != band.child && s != band.parent {
                continue;
            }
            let side = usize::from(s == band.child);
            let share = band.keep_shares(f64::from(level) / LEVELS as f64)[side];
            let q = body.rest[i as usize] - band.pivot;
            let across = q - band.normal * q.dot(band.normal);
            let g = gradient[i as usize];
            rates[usize::from(slot)][side] += share * across.dot(g);
            rates[usize::from(slot)][side + 2] += share * band.radius * band.normal.dot(g);
            if share > 0.0 {
                let r = &mut reach[usize::from(slot)][side];
                *r = r.max(across.length());
            }
        }
        for (slot, &k) in slots.iter().enumerate() {
            let Some(band) = self.bands[k].as_ref().filter(|_| may[slot]) else {
                continue;
            };
            for (side, s) in [band.parent, band.child, band.parent, band.child]
                .into_iter()
                .enumerate()
            {
                let rate = rates[slot][side];
                // A swell moves a vertex by its share of it; neighbours at levels apart
                // move apart by up to the bump's slope times that: held to what the side's
                // width allows.
                let width = if side % 2 == 0 {
                    band.width
                } else {
                    band.child_width
                };
                let moves = if side < 2 {
                    reach[slot][side]
                } else {
                    band.radius
                };
                let cap = MAX_KEEP * (width / moves.max(f64::MIN_POSITIVE)).min(1.0);
                if rate.is_finite() && rate.abs() > f64::MIN_POSITIVE {
                    sides[s].push(Side {
                        band: slot as u16,
                        mode: side as u8,
                        rate,
                        cap,
                        other: None,
                    });
                }
            }
        }
        // A section's size: its volume, or a share of the whole's for one that holds
        // little (a sheet, a fin), whose volume no swell should chase.
        let whole = body.whole;
        // Per section, its vertices that move with another transform than its own.
        let mut moved_of: Vec<Vec<u32>> = vec![Vec::new(); sections];
        for (v, &s) in self.section_of.iter().enumerate() {
            let s = usize::from(s);
            if !sides[s].is_empty() && usize::from(self.transform_of[v]) != s {
                moved_of[s].push(v as u32);
            }
        }
        for (s, sides) in sides.into_iter().enumerate() {
            if sides.is_empty() {
                continue;
            }
            let moved = |v: u32| usize::from(self.transform_of[v as usize]) != s;
            let Some(capped) = surfaces.get(s) else {
                continue;
            };
            let size = section_size(capped.volume(&body.rest), whole);
            let around = capped.around(moved);
            let moved_vertices = std::mem::take(&mut moved_of[s]);
            let apex = self.sections[s].pivot;
            let rest = around.volume_from(&body.rest, apex);
            let norm = sides.iter().map(|x| x.rate * x.rate).sum();
            self.kept.push(Kept {
                section: s,
                around,
                apex,
                rest,
                size,
                moved: moved_vertices,
                sides,
                norm,
            });
        }
        // Each side's band's other end, among the kept sections.
        let mut kept_of = vec![None; sections];
        for (n, kept) in self.kept.iter().enumerate() {
            kept_of[kept.section] = u16::try_from(n).ok();
        }
        let ends: Vec<Option<(usize, usize)>> = (slots.iter())
            .map(|&k| self.bands[k].as_ref().map(|b| (b.parent, b.child)))
            .collect();
        for kept in &mut self.kept {
            for side in &mut kept.sides {
                let Some(&Some((parent, child))) = ends.get(usize::from(side.band)) else {
                    continue;
                };
                let end = if side.mode % 2 == 0 { child } else { parent };
                side.other = kept_of.get(end).copied().flatten();
            }
        }
    }

    /// Each section's surface at rest: its faces (those whose three vertices it holds),
    /// each cut across them capped. Found once per [`Joints::refresh_bands`], for the
    /// slides' rates and the swells'; empty for a section no band ends on or starts from
    /// (neither reads it), and for every section while the rest positions are unknown.
    pub(super) fn capped_sections(&self) -> Vec<Capped> {
        use rayon::prelude::*;
        let mut banded = vec![false; self.sections.len()];
        if self.body.rest.len() == self.section_of.len() {
            for band in self.bands.iter().flatten() {
                banded[band.parent] = true;
                banded[band.child] = true;
            }
        }
        let mut faces: Vec<Vec<[u32; 3]>> = vec![Vec::new(); self.sections.len()];
        for t in &self.body.triangles {
            let s = usize::from(self.section_of[t[0] as usize]);
            if banded[s]
                && t.iter()
                    .all(|&i| usize::from(self.section_of[i as usize]) == s)
            {
                faces[s].push(*t);
            }
        }
        faces.into_par_iter().map(Capped::from_faces).collect()
    }

    /// Measures each kept section's volume in the pose whose section transforms are
    /// `world` and whose transforms (the simulation's) are `transforms`, and adds to
    /// `keep` (per band, its sides' swells) one Newton step towards the volume each had
    /// at rest. `positions`: scratch, the rest positions once grown. `newton`: on the
    /// first, every kept section is measured, and those that changed by more than
    /// [`AGAIN`] of their size are marked in `newton.again`, with the kept sections at
    /// the other ends of their bands; on a later step, only those.
    /// Marks in `newton.changed` each band whose swells changed, and returns whether any
    /// did.
    pub(super) fn keep_volumes(
        &self,
        world: &[DAffine3],
        transforms: &[glam::Affine3A],
        positions: &mut Vec<DVec3>,
        keep: &mut [[f64; 4]],
        newton: &mut Newton,
    ) -> bool {
        if self.kept.is_empty() {
            return false;
        }
        let rest = &self.body.rest;
        if positions.len() != rest.len() {
            positions.clone_from(rest);
        }
        let first = newton.again.len() != self.kept.len() || newton.first;
        if first {
            newton.again.clear();
            newton.again.resize(self.kept.len(), false);
        }
        newton.changed.clear();
        newton.changed.resize(keep.len(), false);
        let mut changed = false;
        for (n, kept) in self.kept.iter().enumerate() {
            if !first && !newton.again[n] {
                continue;
            }
            let back = world[kept.section].inverse();
            for &v in &kept.moved {
                let t = transforms[usize::from(self.transform_of[v as usize])];
                let at = t.transform_point3(rest[v as usize].as_vec3()).as_dvec3();
                positions[v as usize] = back.transform_point3(at);
            }
            let change = kept.around.volume_from(positions, kept.apex) - kept.rest;
            if first {
                newton.again[n] = change.abs() > AGAIN * kept.size;
            }
            // Only what lies beyond the tolerance is given back.
            let tolerance = TOLERANCE * kept.size;
            let change = change.signum() * (change.abs() - tolerance).max(0.0);
            if !change.is_finite() || kept.norm <= 0.0 {
                continue;
            }
            for &Side {
                band,
                mode,
                rate,
                cap,
                ..
            } in &kept.sides
            {
                let k = &mut keep[usize::from(band)][usize::from(mode)];
                let next = (*k - change * rate / kept.norm).clamp(-cap, cap);
                changed |= (next - *k).abs() > 1e-6;
                newton.changed[usize::from(band)] |= next != *k;
                *k = next;
            }
        }
        if first {
            // What a band's swell gives one end its seam may take from the other.
            newton.ends.clear();
            for (kept, _) in self.kept.iter().zip(&newton.again).filter(|(_, &a)| a) {
                newton
                    .ends
                    .extend(kept.sides.iter().filter_map(|x| x.other));
            }
            for &n in &newton.ends {
                newton.again[usize::from(n)] = true;
            }
        }
        changed
    }
}
