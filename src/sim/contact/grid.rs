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
        }
    }

    /// Empties the grid (the balls stay in the set).
    pub(super) fn clear(&mut self) {
        self.grid.clear();
    }

    /// Puts ball `b`, at `c` and reaching `r`, in every cell of size `cell` its box meets.
    pub(super) fn insert(&mut self, b: u32, c: Vec3, r: f32, cell: f32) {
        let (lo, hi) = (key(c - r, cell), key(c + r, cell));
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
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
