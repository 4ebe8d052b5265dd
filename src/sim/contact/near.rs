//! Kept lists of the balls near a tile and near each group of its points (see
//! [`super::Colliders`]): each gathered for a box a little larger than its points need, and
//! read again in later steps while the points stay inside that box and no ball that moved
//! comes near the tile. A settling pose gathers once instead of every step, and a group
//! far from every ball reads none.

use glam::Vec3;

/// How much larger than its points' box a list is gathered for, in grid cells: the points
/// and the balls may move this far before it is gathered again.
pub(super) const SKIN: f32 = 0.25;

/// While the balls move, a list is gathered this many of their last step's motions
/// larger (when that is more than [`SKIN`]): it then lasts a few steps of a swing
/// instead of one.
pub(super) const STEPS: f32 = 10.0;

/// The balls that may meet some points, for a box.
#[derive(Clone, Debug, Default)]
pub(super) struct List {
    /// The box the list was gathered for.
    lo: Vec3,
    hi: Vec3,
    /// The stamp it was gathered under (none yet: never kept).
    stamp: Option<u32>,
    /// How far the balls had travelled ([`super::Colliders`]' odometer) before the step
    /// it was gathered in: a ball left out lies at least that much less than the box's
    /// skin away.
    at: f64,
    /// The balls, sorted, each once.
    pub(super) balls: Vec<u32>,
}

impl List {
    /// Whether the list, gathered under `stamp`, still holds every ball that meets
    /// `lo..hi`: that box lies within the one it was gathered for. (The caller checks that
    /// no ball that moved came near.)
    pub(super) fn covers(&self, stamp: u32, lo: Vec3, hi: Vec3) -> bool {
        self.stamp == Some(stamp) && self.lo.cmple(lo).all() && hi.cmple(self.hi).all()
    }

    /// The box the list was gathered for.
    pub(super) fn bounds(&self) -> (Vec3, Vec3) {
        (self.lo, self.hi)
    }

    /// Marks the list, just gathered for `lo..hi` under `stamp`, kept, the balls having
    /// travelled `at` before this step.
    pub(super) fn keep(&mut self, stamp: u32, lo: Vec3, hi: Vec3, at: f64) {
        (self.lo, self.hi, self.stamp, self.at) = (lo, hi, Some(stamp), at);
    }

    /// How far a ball may have moved since the list was gathered (in that step
    /// included), when the balls have `travelled` in all: a box this much larger than
    /// the points' must lie within the list's.
    pub(super) fn drift(&self, travelled: f64) -> f32 {
        (travelled - self.at).max(0.0) as f32
    }
}

/// A tile's lists: the balls near it (stamped with the colliders' generation), and near
/// each group of its points (stamped with the tile list's gathering, and taken from it).
#[derive(Clone, Debug, Default)]
pub(super) struct Near {
    pub(super) tile: List,
    /// Counts the tile list's gatherings.
    pub(super) gathered: u32,
    pub(super) groups: Vec<List>,
    /// Per point of the tile, where it was when last tested and how far it may move
    /// from there, in a step where no ball moves, before it can meet a ball of its
    /// group's list (negative: test it).
    pub(super) room: Vec<(Vec3, f32)>,
    /// How far every point of the tile may move from where it was when the tile was last
    /// read, in steps where no ball moves, before one may meet a ball of its group's list
    /// or leave that list's box (not positive: read it), and how far they may have moved
    /// since (summed in `f64`, so that no step's motion is rounded away).
    pub(super) slack: f32,
    pub(super) drift: f64,
    /// What the tile's groups said of the balls its list held ([`Ignored`]).
    pub(super) ignored: Ignored,
}

/// The balls every point of a tile ignores (the flesh about their joint), and those some
/// point heeds, as [`super::Colliders::ignored_by_all`] said for each of the tile's groups:
/// it reads only where they lie at rest, the margin and the pairs of sections that
/// collide, so it holds for a generation of the colliders. A tile turning beside its
/// joint's flesh gathers its list again every few steps; each ball is asked once.
#[derive(Clone, Debug, Default)]
pub(super) struct Ignored {
    /// The generation it holds for (none yet: nothing known).
    stamp: Option<u32>,
    /// Each sorted.
    ignored: Vec<u32>,
    heeded: Vec<u32>,
}

impl Ignored {
    /// Leaves out of `balls` (sorted) those every point ignores, by `ignored_by_all` for
    /// a ball not known yet, under the colliders' generation `stamp`.
    pub(super) fn retain(
        &mut self,
        stamp: u32,
        balls: &mut Vec<u32>,
        mut ignored_by_all: impl FnMut(u32) -> bool,
    ) {
        if self.stamp != Some(stamp) {
            self.stamp = Some(stamp);
            self.ignored.clear();
            self.heeded.clear();
        }
        let (known_ignored, known_heeded) = (self.ignored.len(), self.heeded.len());
        balls.retain(|&b| {
            if self.ignored[..known_ignored].binary_search(&b).is_ok() {
                false
            } else if self.heeded[..known_heeded].binary_search(&b).is_ok() {
                true
            } else if ignored_by_all(b) {
                self.ignored.push(b);
                false
            } else {
                self.heeded.push(b);
                true
            }
        });
        if self.ignored.len() > known_ignored {
            self.ignored.sort_unstable();
        }
        if self.heeded.len() > known_heeded {
            self.heeded.sort_unstable();
        }
    }
}

impl Near {
    /// Forgets the lists (a tile that was not tested while balls moved: one may have come
    /// near its box unseen).
    pub(super) fn forget(&mut self) {
        self.tile.stamp = None;
    }

    /// Whether the tile need not be read in a step where no ball moves and its points
    /// moved at most `m`: all of them are still within their rooms and their lists' boxes,
    /// the lists kept under `stamp`.
    pub(super) fn within(&mut self, stamp: u32, m: f32) -> bool {
        self.drift += f64::from(m);
        self.tile.stamp == Some(stamp) && self.drift < f64::from(self.slack)
    }

    /// Marks the tile read, its points with `slack` to move (see [`Near::slack`]).
    pub(super) fn read(&mut self, slack: f32) {
        (self.slack, self.drift) = (slack, 0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The balls kept are those the question keeps, in order; each ball is asked once
    /// per generation, and again in a new one.
    #[test]
    fn a_ball_is_asked_once_a_generation() {
        let ignored = |b: u32| b.is_multiple_of(3);
        let mut known = Ignored::default();
        let mut asked = Vec::new();
        for (stamp, balls) in [
            (1, vec![1, 3, 4, 6, 9]),
            (1, vec![0, 3, 4, 7, 9]),
            (2, vec![3, 4]),
        ] {
            let mut kept = balls.clone();
            known.retain(stamp, &mut kept, |b| {
                asked.push((stamp, b));
                ignored(b)
            });
            let want: Vec<u32> = balls.into_iter().filter(|&b| !ignored(b)).collect();
            assert_eq!(kept, want);
        }
        let mut once = asked.clone();
        once.sort_unstable();
        once.dedup();
        assert_eq!(once.len(), asked.len(), "{asked:?}");
        assert_eq!(asked.len(), 5 + 2 + 2);
    }
}
