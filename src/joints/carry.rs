//! Carried sections: a band whose strip over the parent reaches another child's seam
//! carries that child whole, at the share of the band's motion its seam moves with (see
//! [`super::band`]'s module docs, *carried*). Here: which children a band's first blend
//! moves at their seam, and the order the bands compose in once some carry others.

use super::Joints;

impl Joints {
    /// The parent's other children that a band's `weights` (vertex, position; see
    /// [`Joints::bounded`]) move at their seam with the parent, each with its seam's mean
    /// position (its vertices next to the parent's, 0 where the band leaves them): what
    /// carries them (see [`super::band`]: *carried*). `carries(s)` says which may be.
    pub(super) fn seam_positions(
        &self,
        child: usize,
        parent: usize,
        weights: &[(usize, f64)],
        carries: impl Fn(usize) -> bool,
    ) -> Vec<(usize, f64)> {
        let n = self.section_of.len();
        let mut at = vec![0.0; n];
        for &(i, x) in weights {
            if let Some(a) = at.get_mut(i) {
                *a = x;
            }
        }
        let mut sum = vec![(0.0, 0usize); self.sections.len()];
        for i in (0..n).filter(|&i| !self.body.is_rider(i)) {
            let s = usize::from(self.section_of[i]);
            if s == child || self.sections[s].parent != Some(parent) || !carries(s) {
                continue;
            }
            let on_seam = self.body.neighbours(i).iter().any(|&j| {
                !self.body.is_rider(j as usize)
                    && usize::from(self.section_of[j as usize]) == parent
            });
            if on_seam {
                sum[s].0 += at[i];
                sum[s].1 += 1;
            }
        }
        sum.iter()
            .enumerate()
            .filter(|(_, &(x, count))| count > 0 && x > 0.0)
            .map(|(s, &(x, count))| (s, x / count as f64))
            .collect()
    }
}

/// Each of `count` band slots' place in the order their motions compose in: slot order,
/// but the carrier of each `(carrier, carried)` edge first (the edges go from thicker to
/// thinner joints, so they never close a loop; a slot left on one would go last).
pub(super) fn carriers_first(count: usize, edges: &[(usize, usize)]) -> Vec<usize> {
    use std::cmp::Reverse;
    let mut before = vec![0usize; count];
    for &(_, b) in edges {
        before[b] += 1;
    }
    let mut ready: std::collections::BinaryHeap<Reverse<usize>> = (0..count)
        .filter(|&s| before[s] == 0)
        .map(Reverse)
        .collect();
    let mut place = vec![usize::MAX; count];
    let mut next = 0;
    while let Some(Reverse(s)) = ready.pop() {
        place[s] = next;
        next += 1;
        for &(a, b) in edges {
            if a == s {
                before[b] -= 1;
                if before[b] == 0 {
                    ready.push(Reverse(b));
                }
            }
        }
    }
    for (s, p) in place.iter_mut().enumerate() {
        if *p == usize::MAX {
            *p = count + s;
        }
    }
    place
}
