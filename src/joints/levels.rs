//! A band's weights rounded to its levels, with short edges kept on one level.
//!
//! A band moves its vertices by [`LEVELS`] steps of its motion, not by their exact weight:
//! a vertex at weight `w` moves with level `round(w · LEVELS)`. Two ends of an edge whose
//! weights round to neighbouring levels turn apart by a step, `θ / LEVELS` of the joint's
//! angle `θ`, about a pivot `R` away: an extension of about `θ R / LEVELS`, which on an edge
//! much shorter than that is a tear (a human's neck, edges a twentieth of the mean length
//! 0.12 from the pivot, 4.7× with the head turned 90°).
//!
//! But two weights less than a step apart can always share a level within a step of
//! both. So the band's short edges (at most [`SHORT`] of the mean length of its vertices'
//! edges), shortest first, join their ends into one group while the group's weights stay
//! within one step; each group takes the level nearest its mean weight that is within a
//! step of all its members. A vertex's level is still within a step of its weight, and a
//! short edge inside a group moves rigidly.

use super::band::LEVELS;
use super::Joints;

/// Edges at most this share of the band's mean edge length keep their ends on one level
/// (where their weights allow). Chosen on every other character of `puppet bench poses`
/// from 0 (none), ¼, ½ and 1, as `JUMP` was ([`super::blend`]); `docs/performance-log.md`
/// has the other half.
pub const SHORT: f64 = 0.25;

impl Joints {
    /// The level of each vertex of `weights` (`(vertex, weight in 0..=1)`, in order), short
    /// edges' ends sharing one where they can (see the module docs).
    pub(super) fn levels(&self, weights: &[(usize, f64)]) -> Vec<u16> {
        let step = |w: f64| w.clamp(0.0, 1.0) * LEVELS as f64;
        let rounded = |w: f64| step(w).round() as u16;
        let n = self.section_of.len();
        let body = &self.body;
        if body.rest.len() != n || weights.len() < 2 {
            return weights.iter().map(|&(_, w)| rounded(w)).collect();
        }
        // Each vertex's place in `weights`.
        let mut at = vec![u32::MAX; n];
        for (k, &(i, _)) in weights.iter().enumerate() {
            if let Some(slot) = at.get_mut(i) {
                *slot = k as u32;
            }
        }
        let mut edges: Vec<(f64, u32, u32)> = Vec::new();
        let mut total = 0.0;
        let mut count = 0usize;
        for &(i, _) in weights {
            for &j in body.neighbours(i) {
                let j = j as usize;
                let length = body.rest[i].distance(body.rest[j]);
                total += length;
                count += 1;
                let (a, b) = (at[i], at.get(j).copied().unwrap_or(u32::MAX));
                if b != u32::MAX && a < b {
                    edges.push((length, a, b));
                }
            }
        }
        if count == 0 {
            return weights.iter().map(|&(_, w)| rounded(w)).collect();
        }
        let short = SHORT * total / count as f64;
        edges.retain(|e| e.0 <= short);
        edges.sort_by(|x, y| x.0.total_cmp(&y.0));
        // Groups (union-find), each with its weights' least, largest and sum, in steps.
        let m = weights.len();
        let mut parent: Vec<u32> = (0..m as u32).collect();
        let mut low: Vec<f64> = weights.iter().map(|&(_, w)| step(w)).collect();
        let mut high = low.clone();
        let mut sum = low.clone();
        let mut size = vec![1u32; m];
        fn root(parent: &mut [u32], mut k: u32) -> u32 {
            while parent[k as usize] != k {
                let up = parent[parent[k as usize] as usize];
                parent[k as usize] = up;
                k = up;
            }
            k
        }
        for (_, a, b) in edges {
            let (a, b) = (root(&mut parent, a), root(&mut parent, b));
            if a == b {
                continue;
            }
            let (a, b) = (a as usize, b as usize);
            let (lo, hi) = (low[a].min(low[b]), high[a].max(high[b]));
            // Within one step, a level lies within a step of every member.
            if hi - lo >= 1.0 {
                continue;
            }
            parent[b] = a as u32;
            low[a] = lo;
            high[a] = hi;
            sum[a] += sum[b];
            size[a] += size[b];
        }
        (0..m as u32)
            .map(|k| {
                let r = root(&mut parent, k) as usize;
                if size[r] == 1 {
                    return rounded(weights[k as usize].1);
                }
                let mean = sum[r] / f64::from(size[r]);
                // Every level in `high.floor() ..= low.ceil()` is within a step of all.
                mean.round().clamp(high[r].floor(), low[r].ceil()) as u16
            })
            .collect()
    }
}
