//! The contacts' broad phase: balls by grid cell, one grid per set of balls that move
//! together (see [`super::Colliders`]).

use crate::geom::cells::Cells;
use glam::Vec3;

/// A set of balls, posed and gridded together.
#[derive(Clone, Debug)]
pub(super) struct Set {
    pub(super) balls: Vec<u32>,
    /// Per transform: a ball of the set moves with it.
    pub(super) transforms: Vec<bool>,
    /// Balls too big for the grid (tested against every tile's box).
    pub(super) big: Vec<u32>,
    /// Posed again in the last step (its `before` is not its `posed`).
    pub(super) moved: bool,
    /// The others by grid cell.
    grid: Cells<[i32; 3], Vec<u32>>,
    /// Per ball of the set (by its place in `balls`): the box of cells it is listed in.
    at: Vec<Option<([i32; 3], [i32; 3])>>,
}

impl Set {
    /// The set of `balls`, which move with the transforms flagged in `transforms`, `big`
    /// of them too big for the grid; its grid empty.
    pub(super) fn new(balls: Vec<u32>, transforms: Vec<bool>, big: Vec<u32>) -> Set {
        Set {
            balls,
            transforms,
            big,
            moved: false,
            grid: Cells::default(),
            at: Vec::new(),
        }
    }

    /// Empties the grid (the balls stay in the set).
    pub(super) fn clear(&mut self) {
        self.grid.clear();
        self.at.clear();
        self.at.resize(self.balls.len(), None);
    }

    /// Lists the set's `i`-th ball, `b`, at `c` and reaching `r`, in every cell of size
    /// `cell` its box meets, and in no other: a ball that stays in the cells it was listed
    /// in costs a comparison (a limb's band turning beside a still body moves only its own
    /// balls, and most of those by less than a cell).
    pub(super) fn place(&mut self, i: usize, b: u32, c: Vec3, r: f32, cell: f32) {
        let (lo, hi) = (key(c - r, cell), key(c + r, cell));
        if self.at.len() <= i {
            self.at.resize(self.balls.len().max(i + 1), None);
        }
        if self.at[i] == Some((lo, hi)) {
            return;
        }
        // Only the cells it leaves and those it enters change (a ball crossing a cell's
        // side stays in most of its cells).
        let within = |k: [i32; 3], (a, e): ([i32; 3], [i32; 3])| {
            (0..3).all(|j| a[j] <= k[j] && k[j] <= e[j])
        };
        let was = self.at[i].replace((lo, hi));
        if let Some((a, e)) = was {
            for x in a[0]..=e[0] {
                for y in a[1]..=e[1] {
                    for z in a[2]..=e[2] {
                        if within([x, y, z], (lo, hi)) {
                            continue;
                        }
                        if let Some(list) = self.grid.get_mut(&[x, y, z]) {
                            if let Some(k) = list.iter().position(|&o| o == b) {
                                list.swap_remove(k);
                            }
                        }
                    }
                }
            }
        }
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    if was.is_some_and(|w| within([x, y, z], w)) {
                        continue;
                    }
                    self.grid.entry([x, y, z]).or_default().push(b);
                }
            }
        }
    }

    /// Appends to `out` the big balls and those in the cells `a..=b` (with repeats).
    pub(super) fn gather(&self, a: [i32; 3], b: [i32; 3], out: &mut Vec<u32>) {
        out.extend_from_slice(&self.big);
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                for z in a[2]..=b[2] {
                    if let Some(list) = self.grid.get(&[x, y, z]) {
                        out.extend_from_slice(list);
                    }
                }
            }
        }
    }

    /// Whether a big ball or one in the cells `a..=b` is a `hit`.
    pub(super) fn any(&self, a: [i32; 3], b: [i32; 3], hit: impl Fn(u32) -> bool) -> bool {
        self.big.iter().any(|&ball| hit(ball))
            || (a[0]..=b[0]).any(|x| {
                (a[1]..=b[1]).any(|y| {
                    (a[2]..=b[2]).any(|z| {
                        self.grid
                            .get(&[x, y, z])
                            .is_some_and(|list| list.iter().any(|&ball| hit(ball)))
                    })
                })
            })
    }
}

/// The grid cell of `p`.
pub(super) fn key(p: Vec3, cell: f32) -> [i32; 3] {
    let k = (p / cell).floor();
    let clamp = |x: f32| x.clamp(-1e9, 1e9) as i32;
    [clamp(k.x), clamp(k.y), clamp(k.z)]
}

/// How many cells the box of cells `a..=b` holds.
pub(super) fn cells(a: [i32; 3], b: [i32; 3]) -> i64 {
    (0..3)
        .map(|i| i64::from(b[i]) - i64::from(a[i]) + 1)
        .product()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each cell's balls, sorted, over the cells `a..=b`.
    fn listed(set: &Set, a: [i32; 3], b: [i32; 3]) -> Vec<([i32; 3], Vec<u32>)> {
        let mut out = Vec::new();
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                for z in a[2]..=b[2] {
                    let mut balls = Vec::new();
                    set.gather([x, y, z], [x, y, z], &mut balls);
                    balls.sort_unstable();
                    out.push(([x, y, z], balls));
                }
            }
        }
        out
    }

    /// Balls placed again one by one, some moved far, some a little, some not at all,
    /// are listed in the cells a set listed anew puts them in, and in no other.
    #[test]
    fn a_ball_placed_again_is_listed_where_a_new_set_lists_it() {
        let n = 200u32;
        let mut rng = crate::random::SplitMix(11);
        let mut unit = move || (rng.next_u64() >> 40) as f32 / (1u32 << 24) as f32;
        let (cell, r) = (1.0f32, 0.3f32);
        let mut at: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(unit(), unit(), unit()) * 6.0)
            .collect();
        let mut kept = Set::new((0..n).collect(), vec![true], Vec::new());
        kept.clear();
        for (i, &c) in at.iter().enumerate() {
            kept.place(i, i as u32, c, r, cell);
        }
        for round in 0..10 {
            for (i, c) in at.iter_mut().enumerate() {
                let step = match (i + round) % 3 {
                    0 => 0.0,
                    1 => 0.05,
                    _ => 2.5,
                };
                *c += (Vec3::new(unit(), unit(), unit()) - 0.5) * step;
                kept.place(i, i as u32, *c, r, cell);
            }
            let mut fresh = Set::new((0..n).collect(), vec![true], Vec::new());
            fresh.clear();
            for (i, &c) in at.iter().enumerate() {
                fresh.place(i, i as u32, c, r, cell);
            }
            let (a, b) = ([-3; 3], [9; 3]);
            assert_eq!(listed(&kept, a, b), listed(&fresh, a, b), "round {round}");
        }
    }
}
