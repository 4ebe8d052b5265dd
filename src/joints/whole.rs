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
        moved
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
