//! Whole sections: every piece of a section's surface hangs from where the section does.
//!
//! A cut sorts vertices by their **skeletal points**, which keeps a thin limb whole but can
//! leave a patch of the surface with the wrong section where the medial skeleton runs
//! elsewhere than the skin: a patch of the body's skin lying inside a claw folded against
//! it (its skeletal points are the body's), a patch of a penguin's body inside its head.
//! Such a patch is an island: every mesh edge leaving it goes into other sections. When
//! those turn, the island stays with its own section and the skin around it tears (8–15×
//! on the scorpion's claws in `puppet bench poses`).
//!
//! So once the joints have a surface ([`Joints::set_surface`]: a puppet's do), each
//! section keeps
//! * its largest connected piece of surface (through mesh edges between its own vertices)
//!   on each part of the body (a surface connected through mesh edges and attachments:
//!   two characters in one file are two parts, and each keeps its root),
//! * every other piece that borders the section's parent (two legs cut by one plane are
//!   two pieces, each on the body), and
//! * every piece that borders no other section (a separate part of the mesh);
//!
//! and any other piece joins the section it shares the most mesh edges with, until no
//! piece moves ([`Joints::make_whole`]), once a batch of cuts is in. Riders are left to
//! their hosts. A moved vertex lies across the bands where the nearest unmoved vertex of
//! its new section does ([`Joints::borrow_points`]): its own skeletal point, in another
//! section, would put it at the wrong end of them.
//!
//! # Parts beside a cut
//! A cut's plane crossing a limb crosses the mesh's parts around it (a sleeve, a trouser
//! leg: each a connected component of its own triangles, whatever attaches it) around
//! its pivot, and they bend with the limb. A part beside the limb does not: a backpack
//! that the waist's cut split in two had its halves turned about a pivot far from them
//! and torn apart (3.97× in `puppet bench poses`). So, once the sections are whole, a part
//! (not the largest of those attached together) that the cuts split between two
//! sections, and whose rest positions projected on each cut's plane between them leave
//! the cut's pivot outside their hull (a gap of more than half a turn as seen from the
//! pivot), goes whole to the section it hangs from: the one its attachments reach most (a
//! bedroll on a back goes with the back, not the head), or without any, the one holding
//! most of it. No band then takes it by its skeletal point, and a band's width is
//! measured on the sections as they were before it moved ([`Joints::make_parts_whole`]).
//! The suggestion weighs its cuts before parts go whole (its balloon check took an
//! adventurer's head back once the bedroll by it had gone whole to his back).
//!
//! Cuts still split the sections by skeletal points (each vertex's is kept apart from its
//! whole section), so what a cut takes does not depend on which pieces moved before it,
//! and the suggestion, which reasons on the skeleton and has no surface, sees the
//! skeleton's sections.

use super::Joints;
use std::collections::HashMap;

/// Passes at most: a piece that moves can leave pieces of its new section to move in the
/// next pass.
const MAX_PASSES: usize = 4;

impl Joints {
    /// Moves every stray piece of a section to the section around it (see the module
    /// docs). Returns how many vertices moved.
    pub(super) fn make_whole(&mut self) -> usize {
        self.changing();
        let body = &self.body;
        let n = self.section_of.len();
        if body.neighbours.is_empty() || self.sections.len() < 2 {
            return 0;
        }
        let own = |i: usize| !body.is_rider(i);
        const NONE: u32 = u32::MAX;
        let mut moved = 0;
        // Each vertex's part of the body: its connected surface through mesh edges and
        // attachments, whatever the sections (two characters in one file are two parts).
        let mut part = vec![NONE; n];
        let mut stack: Vec<u32> = Vec::new();
        let mut parts = 0;
        for seed in 0..n {
            if part[seed] != NONE || !own(seed) {
                continue;
            }
            part[seed] = parts;
            stack.push(seed as u32);
            while let Some(v) = stack.pop() {
                for &w in body.neighbours(v as usize) {
                    if part[w as usize] == NONE && own(w as usize) {
                        part[w as usize] = parts;
                        stack.push(w);
                    }
                }
            }
            parts += 1;
        }
        let mut piece = vec![NONE; n];
        // Vertices piece by piece, and where each piece starts in it.
        let mut order: Vec<u32> = Vec::with_capacity(n);
        let mut starts: Vec<usize> = Vec::new();
        for _ in 0..MAX_PASSES {
            piece.fill(NONE);
            order.clear();
            starts.clear();
            for seed in 0..n {
                if piece[seed] != NONE || !own(seed) {
                    continue;
                }
                let p = starts.len() as u32;
                starts.push(order.len());
                piece[seed] = p;
                order.push(seed as u32);
                let mut next = order.len() - 1;
                while let Some(&v) = order.get(next) {
                    next += 1;
                    for &w in body.neighbours(v as usize) {
                        let w = w as usize;
                        if piece[w] == NONE && own(w) && self.section_of[w] == self.section_of[seed]
                        {
                            piece[w] = p;
                            order.push(w as u32);
                        }
                    }
                }
            }
            starts.push(order.len());
            let pieces = starts.len() - 1;
            // Each section's largest piece on each part of the body.
            let mut largest: HashMap<(u16, u32), (usize, usize)> = HashMap::new();
            for p in 0..pieces {
                let size = starts[p + 1] - starts[p];
                let v = order[starts[p]] as usize;
                let key = (self.section_of[v], part[v]);
                if largest.get(&key).is_none_or(|&(_, m)| size > m) {
                    largest.insert(key, (p, size));
                }
            }
            let mut changed = false;
            let mut borders: Vec<(u16, usize)> = Vec::new();
            for p in 0..pieces {
                let vertices = &order[starts[p]..starts[p + 1]];
                let s = self.section_of[vertices[0] as usize];
                let key = (s, part[vertices[0] as usize]);
                if largest.get(&key).is_some_and(|&(q, _)| q == p) {
                    continue;
                }
                borders.clear();
                for &v in vertices {
                    for &w in body.neighbours(v as usize) {
                        let w = w as usize;
                        if !own(w) || self.section_of[w] == s {
                            continue;
                        }
                        let t = self.section_of[w];
                        match borders.iter_mut().find(|b| b.0 == t) {
                            Some(b) => b.1 += 1,
                            None => borders.push((t, 1)),
                        }
                    }
                }
                let parent = self.sections[usize::from(s)].parent;
                if borders.is_empty()
                    || borders.iter().any(|&(t, _)| Some(usize::from(t)) == parent)
                {
                    continue;
                }
                // The section it shares most edges with (the lower index on a tie).
                let Some(&(to, _)) = borders
                    .iter()
                    .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
                else {
                    continue;
                };
                for &v in vertices {
                    self.section_of[v as usize] = to;
                }
                moved += vertices.len();
                changed = true;
            }
            if !changed {
                break;
            }
        }
        if self.parts_whole {
            moved += self.make_parts_whole(&part);
        }
        moved
    }

    /// The sections that reach across the body's mirror plane `(n, o)` (unit normal,
    /// offset): a section whose pivot lies off the plane by more than its band's local
    /// medial radius `r` (a limb on one side: an arm, a leg; not a neck or a tail on the
    /// plane) and that holds a skeletal point more than `r` across it. Such a limb's cut
    /// slipped into the body: a shoulder's plane tilted up through the head takes the
    /// head with the arm, and turning the arm turns the whole chest (a spacesuit's
    /// `arm.L` in `puppet bench suggest`, its *across the body* column). Riders, which go
    /// with their hosts, are not read. Sections in order; none without a finite plane.
    pub fn across_mirror(&self, (n, o): (glam::DVec3, f64)) -> Vec<usize> {
        if !(n.is_finite() && o.is_finite()) || n == glam::DVec3::ZERO {
            return Vec::new();
        }
        let n = n.normalize();
        // (A section on the plane is off it by rounding alone.)
        let (lo, hi) = crate::mesh::bounds(&self.body.points);
        let least = 1e-9 * (hi - lo).length();
        let mut out = Vec::new();
        for (k, section) in self.sections.iter().enumerate().skip(1) {
            let r = self
                .bands
                .get(k - 1)
                .and_then(Option::as_ref)
                .map_or(0.0, |b| b.radius)
                .max(least);
            let points = (0..self.section_of.len())
                .filter(|&i| usize::from(self.section_of[i]) == k && !self.body.is_rider(i))
                .filter_map(|i| self.body.points.get(i).copied());
            if crate::mesh::mirror::reaches_across((n, o), section.pivot, r, points) {
                out.push(k);
            }
        }
        out
    }

    /// Turns on or off whether parts split beside a cut go whole to one section (on
    /// unless turned off; see [`Joints::make_parts_whole`]), and assigns the sections
    /// again when that changes, and the bands where a part is or was whole.
    pub(crate) fn set_parts_whole(&mut self, on: bool) {
        self.changing();
        if self.parts_whole == on {
            return;
        }
        self.parts_whole = on;
        let had = !self.whole_part.is_empty();
        self.assign_sections(true);
        if had || !self.whole_part.is_empty() {
            self.refresh_bands();
        }
    }

    /// Moves every part of the mesh that the cuts split in two and that lies beside each
    /// cut between its two sections whole to the section it hangs from (see the module
    /// docs); `joined` is each vertex's group of parts attached together. Returns how
    /// many vertices moved.
    fn make_parts_whole(&mut self, joined: &[u32]) -> usize {
        let body = &self.body;
        let n = self.section_of.len();
        let part_of = &body.part_of;
        if body.rest.len() != n || part_of.len() != n {
            return 0;
        }
        let mut members: HashMap<u32, Vec<u32>> = HashMap::new();
        for (v, &p) in part_of.iter().enumerate() {
            if !body.is_rider(v) {
                members.entry(p).or_default().push(v as u32);
            }
        }
        // The largest part of each group attached together.
        let mut largest: HashMap<u32, usize> = HashMap::new();
        for vertices in members.values() {
            let p = joined[vertices[0] as usize];
            let m = largest.entry(p).or_default();
            *m = (*m).max(vertices.len());
        }
        let mut moved = 0;
        let mut parts: Vec<&Vec<u32>> = members.values().collect();
        parts.sort_unstable_by_key(|v| v[0]);
        let mut counts: Vec<(u16, usize)> = Vec::new();
        for vertices in parts {
            if largest.get(&joined[vertices[0] as usize]) == Some(&vertices.len()) {
                continue;
            }
            counts.clear();
            for &v in vertices {
                let s = self.section_of[v as usize];
                match counts.iter_mut().find(|c| c.0 == s) {
                    Some(c) => c.1 += 1,
                    None => counts.push((s, 1)),
                }
            }
            if counts.len() != 2 {
                continue;
            }
            // The section it hangs from: the one its attachments reach most, or without
            // any, the one holding most of it (the lower index on a tie).
            let mut attached: Vec<(u16, usize)> = Vec::new();
            let own = part_of[vertices[0] as usize];
            for &v in vertices {
                for &w in body.neighbours(v as usize) {
                    if !body.is_rider(w as usize) && part_of[w as usize] != own {
                        let s = self.section_of[w as usize];
                        match attached.iter_mut().find(|c| c.0 == s) {
                            Some(c) => c.1 += 1,
                            None => attached.push((s, 1)),
                        }
                    }
                }
            }
            let from = if attached.is_empty() {
                &counts
            } else {
                &attached
            };
            let Some(&(to, _)) = from.iter().max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
            else {
                continue;
            };
            if !counts.iter().any(|c| c.0 == to) {
                continue;
            }
            // Beside every cut between its two sections (cut `k` made section `k + 1`).
            let beside = self
                .between(usize::from(counts[0].0), usize::from(counts[1].0))
                .iter()
                .filter_map(|&s| s.checked_sub(1))
                .all(|k| self.beside_cut(k, vertices));
            if !beside {
                continue;
            }
            if self.whole_part.len() != n {
                self.whole_part = vec![super::NOT_MOVED; n];
            }
            for &v in vertices {
                let v = v as usize;
                self.whole_part[v] = self.section_of[v];
                if self.section_of[v] != to {
                    self.section_of[v] = to;
                    moved += 1;
                }
            }
        }
        moved
    }

    /// Do the rest positions of `vertices`, projected on cut `k`'s plane, leave its pivot
    /// outside their hull? (Not for a sphere or a box.)
    fn beside_cut(&self, k: usize, vertices: &[u32]) -> bool {
        let Some(cut) = self.cuts.get(k) else {
            return false;
        };
        if cut.shape != super::Shape::Plane {
            return false;
        }
        let normal = cut.normal.normalize_or_zero();
        let pivot = cut.pivot.unwrap_or(cut.point);
        let (u, w) = normal.any_orthonormal_pair();
        let mut angles: Vec<f64> = Vec::with_capacity(vertices.len());
        for &v in vertices {
            let d = self.body.rest[v as usize] - pivot;
            let (x, y) = (d.dot(u), d.dot(w));
            if x == 0.0 && y == 0.0 {
                return false;
            }
            angles.push(y.atan2(x));
        }
        angles.sort_unstable_by(f64::total_cmp);
        let (Some(&first), Some(&last)) = (angles.first(), angles.last()) else {
            return false;
        };
        let gap = angles
            .windows(2)
            .map(|a| a[1] - a[0])
            .fold(first + std::f64::consts::TAU - last, f64::max);
        gap > std::f64::consts::PI
    }

    /// Gives each vertex of a moved piece the skeletal point of the nearest vertex (in
    /// mesh edges) of its new section that was not moved: where the piece lies across
    /// that section's bands. A piece's own skeletal points lie in another section, which
    /// would put it at the wrong end of a band.
    pub(super) fn borrow_points(&mut self) {
        self.changing();
        let n = self.section_of.len();
        let body = &self.body;
        let moved = |i: usize| !body.is_rider(i) && self.section_of[i] != self.skeletal_of[i];
        self.borrowed = (0..n as u32).collect();
        let mut reached: Vec<bool> = (0..n).map(|i| !moved(i)).collect();
        let mut queue: std::collections::VecDeque<u32> = (0..n)
            .filter(|&i| {
                !moved(i)
                    && !body.is_rider(i)
                    && body.neighbours(i).iter().any(|&w| {
                        moved(w as usize) && self.section_of[w as usize] == self.section_of[i]
                    })
            })
            .map(|i| i as u32)
            .collect();
        while let Some(v) = queue.pop_front() {
            let v = v as usize;
            for &w in body.neighbours(v) {
                let w = w as usize;
                if !reached[w] && self.section_of[w] == self.section_of[v] {
                    reached[w] = true;
                    self.borrowed[w] = self.borrowed[v];
                    queue.push_back(w as u32);
                }
            }
        }
    }
}
