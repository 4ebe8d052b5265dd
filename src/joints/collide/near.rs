//! The pose limit's broad phase: the pairs of balls of two sections that lie near each
//! other, listed in the sections' own frames and kept from move to move (a Verlet list)
//! while the two sections have not moved farther *relative to each other* than the list
//! allows (see the parent module's docs).
//!
//! A section's balls move rigidly with it, so whether two balls press depends only on
//! their two sections' relative transform. A hand swung from the shoulder keeps its
//! fingers' pairs, listed in the palm's frame, where a list by world position is made
//! again every step the hand moves a ball's margin. Each pair of sections whose bounds
//! come near is a block ([`Block`]): the pairs of balls within its width in the first
//! section's frame, kept while no ball of the second has moved more than its clearance
//! in that frame; the other pairs of sections are passed over while their bounding
//! spheres stay apart.

use super::Balls;
use crate::geom::cells::SortedCells;
use glam::{DAffine3, DVec3};

/// The width a block is listed with where its sections move slowly, as a share of the
/// grid's cell (twice the 90th percentile radius): a wider one lists more pairs and is
/// made again less often.
const SKIN: f64 = 0.25;

/// A block listed again within this many covers of the last is listed twice as wide,
/// up to [`WIDEST`] cells.
const SHORT: u64 = 8;

/// The widest a block is listed, in cells, unless its sections move faster.
const WIDEST: f64 = 2.0;

/// Bins of each block's pairs by gap ([`Block`]).
const BINS: usize = 8;

/// No block ([`Near`]'s `slot`).
const NONE: u32 = u32::MAX;

/// The pairs of balls that may press, by pair of sections, each kept while its two
/// sections move little relative to each other. Kept by the puppet between moves; made
/// again pair of sections by pair ([`Near::cover`]) when a move takes one farther.
#[derive(Clone, Debug, Default)]
pub struct Near {
    /// Per section, its balls and their bounds in its rest frame (made with the first
    /// list, for `made_for`: the balls' count and cell).
    parts: Vec<Part>,
    made_for: (usize, u64),
    /// Per pair of sections (`a * sections + b`, `a < b`), its block in `blocks`, or
    /// [`NONE`].
    slot: Vec<u32>,
    blocks: Vec<Block>,
    /// The blocks whose sections' bounds came near over the move last covered: the only
    /// ones whose balls may press there.
    live: Vec<u32>,
    /// The frames of the pose last covered up to, and how many covers were made: a
    /// block's `now` is its relative transform there when its `stamp` is that count.
    frames: Option<Frames>,
    covers: u64,
    /// Scratch of [`Near::cover`]: per section, its bounding sphere's centre and how far
    /// its balls moved over the move covered.
    spheres: Vec<(DVec3, f64)>,
    /// How many times a move listed pairs again.
    lists: usize,
}

/// One section's balls in its rest frame.
#[derive(Clone, Debug, Default)]
struct Part {
    /// Its balls (those with a finite centre and radius).
    balls: Vec<u32>,
    /// The centre of its bounding sphere, how far from it the balls' centres lie, and how
    /// far their surfaces do.
    centre: DVec3,
    spread: f64,
    reach: f64,
    /// Its balls by size: class `k` holds radii up to `2^k` half cells (class 0, every
    /// radius up to half a cell), in a grid whose cells are `2^k` times [`GRID`] cells
    /// wide. A big ball is then looked up only where it can reach.
    grids: Vec<SortedCells>,
}

/// A grid cell of a [`Part`]'s smallest balls, in the balls' cell ([`Balls`]' `cell`).
const GRID: f64 = 2.0;

/// The size class of a ball of radius `r` ([`Part`]'s `grids`), for half a cell `half`.
fn class(r: f64, half: f64) -> usize {
    if r <= half {
        0
    } else {
        ((r / half).log2().ceil() as usize).min(60)
    }
}

/// Two balls listed as near ([`Near`]), `a` of a block's first section, `b` of its second.
#[derive(Clone, Copy, Debug)]
struct Pair {
    a: u32,
    b: u32,
    /// How far apart their surfaces lay when listed: they press only once the second's
    /// balls have moved that far in the first's frame.
    gap: f64,
}

/// The listed pairs of balls of two sections (`sections`: the one whose frame they are
/// listed in, the part of the wider spread, then the other), by gap:
/// bin `k` is `pairs[bins[k]..bins[k + 1]]`, the first holding those that overlapped
/// when listed, bin `k` those whose gap was under `k / BINS` of the width.
#[derive(Clone, Debug)]
struct Block {
    sections: (u32, u32),
    /// The second section's rest frame in the first's when listed.
    at: DAffine3,
    /// The pairs listed are those whose gap was under it.
    width: f64,
    /// How far the second section's balls may move in the first's frame before a pair
    /// not listed may press: the width, or more where the two parts' bounds lay apart.
    clear: f64,
    pairs: Vec<Pair>,
    bins: [u32; BINS + 2],
    /// The second section's rest frame in the first's in the pose last covered up to
    /// (when `stamp` is [`Near`]'s `covers`), kept for the next move's start.
    now: DAffine3,
    stamp: u64,
    /// The cover it was listed in ([`Near`]'s `covers`).
    listed: u64,
}

/// The world transforms of a pose, each section's with its inverse.
#[derive(Clone, Debug)]
struct Frames {
    world: Vec<DAffine3>,
    inverse: Vec<DAffine3>,
}

impl Frames {
    /// The frames of `world` for `sections` sections (a section beyond it does not move).
    fn new(world: &[DAffine3], sections: usize) -> Frames {
        let world: Vec<DAffine3> = (0..sections)
            .map(|s| world.get(s).copied().unwrap_or(DAffine3::IDENTITY))
            .collect();
        let inverse = world.iter().map(DAffine3::inverse).collect();
        Frames { world, inverse }
    }

    /// Section `b`'s rest frame in section `a`'s.
    fn relative(&self, a: usize, b: usize) -> DAffine3 {
        self.inverse[a] * self.world[b]
    }
}

/// How far at most a ball of `part` lies in rigid frame `to` from where it lay in `from`:
/// the part's centre's move and the turn between them times its spread (the spectral
/// norm of the difference of two rotations is `sqrt(3 - trace(R1ᵀ R2))`). Infinite when
/// either is not finite.
fn moved(from: &DAffine3, to: &DAffine3, part: &Part) -> f64 {
    let shift = from
        .transform_point3(part.centre)
        .distance(to.transform_point3(part.centre));
    let (r, s) = (from.matrix3, to.matrix3);
    let trace = r.x_axis.dot(s.x_axis) + r.y_axis.dot(s.y_axis) + r.z_axis.dot(s.z_axis);
    let d = shift + (3.0 - trace).max(0.0).sqrt() * part.spread;
    if d.is_finite() && trace.is_finite() {
        d
    } else {
        f64::INFINITY
    }
}

impl Near {
    /// How many times a move listed pairs again (a block or more).
    pub fn lists(&self) -> usize {
        self.lists
    }

    /// Makes the parts for `balls` when they are not made for them yet (forgetting every
    /// block); the number of sections.
    fn prepare(&mut self, balls: &Balls) -> usize {
        let made_for = (balls.len(), balls.cell.to_bits());
        if self.made_for == made_for && !self.parts.is_empty() {
            return self.parts.len();
        }
        let sections = balls.section.iter().copied().max().map_or(0, |s| s + 1);
        let mut parts = vec![Part::default(); sections];
        for b in 0..balls.len() {
            if balls.center[b].is_finite() && balls.radius[b].is_finite() {
                parts[balls.section[b]].balls.push(b as u32);
            }
        }
        let (half, size) = (0.5 * balls.cell, GRID * balls.cell);
        for part in &mut parts {
            let Some(&first) = part.balls.first() else {
                continue;
            };
            let first = balls.center[first as usize];
            let (lo, hi) = part.balls.iter().fold((first, first), |(lo, hi), &b| {
                let c = balls.center[b as usize];
                (lo.min(c), hi.max(c))
            });
            part.centre = 0.5 * (lo + hi);
            let mut cells: Vec<Vec<([i64; 3], u32)>> = Vec::new();
            for &b in &part.balls {
                let (c, r) = (balls.center[b as usize], balls.radius[b as usize]);
                let d = c.distance(part.centre);
                part.spread = part.spread.max(d);
                part.reach = part.reach.max(d + r);
                let k = class(r, half);
                if cells.len() <= k {
                    cells.resize(k + 1, Vec::new());
                }
                cells[k].push((key(c, size * (1u64 << k) as f64), b));
            }
            part.grids = cells.into_iter().map(SortedCells::new).collect();
        }
        self.parts = parts;
        self.made_for = made_for;
        self.slot = vec![NONE; sections * sections];
        self.blocks.clear();
        self.live.clear();
        self.frames = None;
        sections
    }

    /// Makes sure the blocks hold every pair that may press anywhere between the poses
    /// whose world transforms are `from` and `to` (two samples of a move, a section
    /// moving at most its step between them): each pair of sections whose bounding
    /// spheres come within their two steps at `to` has a block, listed again at `from`
    /// when its second section would move farther than the block's clearance in the
    /// first's frame.
    pub(super) fn cover(&mut self, balls: &Balls, from: &[DAffine3], to: &[DAffine3]) {
        let sections = self.prepare(balls);
        let t = Frames::new(to, sections);
        // The last pose covered up to is most often this move's start: its frames and its
        // blocks' relative transforms are known.
        let (f, known) = match self.frames.take() {
            Some(f) if f.world.len() == sections && same(&f.world, from) => (f, Some(self.covers)),
            _ => (Frames::new(from, sections), None),
        };
        self.covers += 1;
        let parts = std::mem::take(&mut self.parts);
        // Each section's bounding sphere's centre at `to`, and how far its balls moved.
        let mut spheres = std::mem::take(&mut self.spheres);
        spheres.clear();
        spheres.extend((0..sections).map(|s| {
            (
                t.world[s].transform_point3(parts[s].centre),
                moved(&f.world[s], &t.world[s], &parts[s]),
            )
        }));
        let base = SKIN * balls.cell;
        let mut listed = false;
        self.live.clear();
        for a in 0..sections {
            if parts[a].balls.is_empty() {
                continue;
            }
            for b in a + 1..sections {
                let part = &parts[b];
                if part.balls.is_empty() {
                    continue;
                }
                let ((ca, sa), (cb, sb)) = (spheres[a], spheres[b]);
                let reach = parts[a].reach + part.reach + sa + sb;
                // (Not finite: passed over, as balls that are nowhere never press.)
                let near = ca.distance_squared(cb) < reach * reach;
                if !near {
                    continue;
                }
                let k = self.slot[a * sections + b];
                // The block's frame is the part of the wider spread: the other's balls
                // move less in it (a head turning on a body sweeps the body's far end
                // round in the head's frame).
                let (p, q) = if parts[a].spread >= part.spread {
                    (a, b)
                } else {
                    (b, a)
                };
                let part = &parts[q];
                let now = t.relative(p, q);
                let then = match self.blocks.get(k as usize) {
                    Some(block) if Some(block.stamp) == known => block.now,
                    _ => f.relative(p, q),
                };
                let by = moved(&then, &now, part);
                if let Some(block) = self.blocks.get_mut(k as usize) {
                    if moved(&block.at, &now, part) + by <= block.clear {
                        (block.now, block.stamp) = (now, self.covers);
                        self.live.push(k);
                        continue;
                    }
                }
                listed = true;
                // A block its sections outgrew within a few covers is listed wider, up
                // to a few cells: a head nodding on a thick neck lists its few pairs once
                // rather than every other step.
                let width = match self.blocks.get(k as usize) {
                    Some(block) if self.covers - block.listed < SHORT => {
                        (2.0 * block.width).min(WIDEST * balls.cell)
                    }
                    _ => base,
                };
                let mut block = list(balls, &parts, (p, q), then, width.max(2.0 * by));
                block.listed = self.covers;
                (block.now, block.stamp) = (now, self.covers);
                let k = if k == NONE {
                    self.blocks.push(block);
                    let k = (self.blocks.len() - 1) as u32;
                    self.slot[a * sections + b] = k;
                    k
                } else {
                    self.blocks[k as usize] = block;
                    k
                };
                self.live.push(k);
            }
        }
        self.parts = parts;
        self.spheres = spheres;
        self.frames = Some(t);
        self.lists += usize::from(listed);
    }

    /// The deepest press among the listed pairs of balls in the pose whose world
    /// transforms are `world` whose sections move apart (their `group`s differ:
    /// [`groups`]), or the first found deeper than `stop`, with the pair's balls. Only a
    /// block's pairs whose gap is under how far its second section's balls have moved in
    /// the first's frame are tested: none of the rest can press.
    pub(super) fn deepest(
        &self,
        balls: &Balls,
        group: &[u32],
        world: &[DAffine3],
        stop: f64,
    ) -> (f64, Option<(usize, usize)>) {
        let mut deepest = (0.0f64, None);
        // The pose last covered up to (the move's sample) or one between two (bisected).
        let sections = self.parts.len();
        let w = match &self.frames {
            Some(f) if f.world.len() == sections && same(&f.world, world) => None,
            _ => Some(Frames::new(world, sections)),
        };
        for &k in &self.live {
            let block = &self.blocks[k as usize];
            let (sa, sb) = (block.sections.0 as usize, block.sections.1 as usize);
            if block.pairs.is_empty() || group.get(sa) == group.get(sb) {
                continue;
            }
            let now = w.as_ref().map_or(block.now, |w| w.relative(sa, sb));
            let by = moved(&block.at, &now, &self.parts[sb]);
            let last = ((by / block.width * BINS as f64).floor() + 2.0).min(BINS as f64 + 1.0);
            let end = block.bins[last as usize] as usize;
            for &Pair { a, b, .. } in &block.pairs[..end] {
                let (a, b) = (a as usize, b as usize);
                let p =
                    balls.press_near(a, b, balls.center[a], now.transform_point3(balls.center[b]));
                if p > deepest.0 {
                    deepest = (p, Some((a, b)));
                    if p > stop {
                        return deepest;
                    }
                }
            }
        }
        deepest
    }

    /// The pairs of sections (each once, the lower first) of the listed pairs of balls
    /// that press in the pose whose world transforms are `world` (last covered), whatever
    /// their motion.
    pub(super) fn pressing(&self, balls: &Balls, world: &[DAffine3]) -> Vec<(usize, usize)> {
        let w = Frames::new(world, self.parts.len());
        self.live
            .iter()
            .map(|&k| &self.blocks[k as usize])
            .filter(|block| {
                let (sa, sb) = (block.sections.0 as usize, block.sections.1 as usize);
                let now = w.relative(sa, sb);
                block.pairs.iter().any(|&Pair { a, b, .. }| {
                    let (a, b) = (a as usize, b as usize);
                    let pb = now.transform_point3(balls.center[b]);
                    balls.press_near(a, b, balls.center[a], pb) > 0.0
                })
            })
            .map(|block| {
                let (a, b) = (block.sections.0 as usize, block.sections.1 as usize);
                (a.min(b), a.max(b))
            })
            .collect()
    }
}

/// The grid cell of size `size` point `p` lies in.
fn key(p: DVec3, size: f64) -> [i64; 3] {
    let k = (p / size).floor();
    [k.x as i64, k.y as i64, k.z as i64]
}

/// The block of sections `a` and `b` of `parts` listed with the second's rest frame at
/// `at` in the first's: every pair of their balls whose gap is under `width`, less those
/// that never press. The smaller part's balls are looked up in the other's grid.
fn list(balls: &Balls, parts: &[Part], (a, b): (usize, usize), at: DAffine3, width: f64) -> Block {
    let mut pairs = Vec::new();
    let (pa, pb) = (&parts[a], &parts[b]);
    // The first section's balls are looked up in the second's frame, or the second's in
    // the first's.
    let (ask, grid, into, asked_first) = if pa.balls.len() <= pb.balls.len() {
        (pa, pb, at.inverse(), true)
    } else {
        (pb, pa, at, false)
    };
    let centre_at = at.transform_point3(pb.centre);
    let apart = centre_at.distance(pa.centre) - pa.reach - pb.reach;
    let (half, size) = (0.5 * balls.cell, GRID * balls.cell);
    if into.is_finite() {
        for &x in &ask.balls {
            let x = x as usize;
            let (q, rx) = (into.transform_point3(balls.center[x]), balls.radius[x]);
            if q.distance(grid.centre) - grid.reach - rx >= width {
                continue;
            }
            let mut test = |y: u32| {
                let y = y as usize;
                let gap = q.distance(balls.center[y]) - rx - balls.radius[y];
                if gap < width && !balls.never(x, y) {
                    let (a, b) = if asked_first { (x, y) } else { (y, x) };
                    pairs.push(Pair {
                        a: a as u32,
                        b: b as u32,
                        gap,
                    });
                }
            };
            for (k, cells) in grid.grids.iter().enumerate() {
                let scale = (1u64 << k) as f64;
                let reach = DVec3::splat(rx + width + half * scale);
                let size = size * scale;
                cells.each_in(key(q - reach, size), key(q + reach, size), &mut test);
            }
        }
    }
    let bin = |g: f64| ((g / width * BINS as f64).floor() + 1.0).clamp(0.0, BINS as f64) as usize;
    pairs.sort_unstable_by_key(|p| bin(p.gap));
    let bins = std::array::from_fn(|k| pairs.partition_point(|p| bin(p.gap) < k) as u32);
    Block {
        sections: (a as u32, b as u32),
        at,
        width,
        clear: if apart.is_finite() {
            width.max(apart)
        } else {
            width
        },
        pairs,
        bins,
        now: at,
        stamp: 0,
        listed: 0,
    }
}

/// Whether `world` (a pose's world transforms, one per section it has) is `frames`,
/// padded with sections that do not move.
fn same(frames: &[DAffine3], world: &[DAffine3]) -> bool {
    world.len() <= frames.len()
        && frames
            .iter()
            .enumerate()
            .all(|(s, f)| *f == world.get(s).copied().unwrap_or(DAffine3::IDENTITY))
}

/// Per section (of `sections`), a group: two sections whose relative transform is the
/// same at `start` and `end` (they move together, or neither moves) share one, and their
/// balls cannot come to press over the move.
pub(super) fn groups(sections: usize, start: &[DAffine3], end: &[DAffine3]) -> Vec<u32> {
    // Each section's motion over the move (a section beyond the pose's does not move);
    // two move together when theirs are the same.
    let motion: Vec<DAffine3> = (0..sections.max(start.len()).max(end.len()))
        .map(|s| match (start.get(s), end.get(s)) {
            (Some(a), Some(b)) => *b * a.inverse(),
            _ => DAffine3::IDENTITY,
        })
        .collect();
    // The first section of each group.
    let mut first: Vec<usize> = Vec::new();
    motion
        .iter()
        .enumerate()
        .map(|(s, m)| {
            first
                .iter()
                .position(|&f| motion[f].abs_diff_eq(*m, 1e-9))
                .unwrap_or_else(|| {
                    first.push(s);
                    first.len() - 1
                }) as u32
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::balls;
    use crate::random::SplitMix;

    fn unit(rng: &mut SplitMix) -> f64 {
        (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The listed pairs, kept along a move and listed again where two sections stray
    /// from each other, find the same deepest press as every pair of balls does (brute
    /// force) at every pose along it and halfway between two, over random balls in four
    /// sections, two of them turning; and the pairs are listed again far fewer times
    /// than there are poses.
    #[test]
    fn the_listed_pairs_press_as_every_pair_does_all_along_a_move() {
        let mut rng = SplitMix(11);
        let mut pressed = 0;
        let mut lists = 0;
        for trial in 0..20 {
            let n = 400;
            let mut balls = Balls::default();
            for _ in 0..n {
                balls
                    .center
                    .push(DVec3::new(unit(&mut rng), unit(&mut rng), unit(&mut rng)));
                let big = unit(&mut rng) < 0.05;
                balls.radius.push(if big {
                    0.2
                } else {
                    0.01 + 0.04 * unit(&mut rng)
                });
                balls.section.push((unit(&mut rng) * 4.0) as usize % 4);
            }
            balls.joint = (0..n).map(|k| (k % 3) as u16).collect();
            balls.sides = vec![None, Some((1, 0)), Some((2, 0)), Some((3, 1))];
            balls.cell = balls::cell(&balls.radius);
            // Every other trial with the sections' kin worked out (the fast path of
            // `Balls::never`), the others without.
            if trial % 2 == 0 {
                balls.necks = vec![None; 4];
                balls.kin = balls.kin(4);
            }
            let turn = |s: f64, axis: DVec3| {
                DAffine3::from_translation(DVec3::splat(0.5))
                    * DAffine3::from_axis_angle(axis, s * (1.0 + trial as f64 * 0.1))
                    * DAffine3::from_translation(DVec3::splat(-0.5))
            };
            let world = |s: f64| {
                vec![
                    DAffine3::IDENTITY,
                    turn(s, DVec3::Y),
                    DAffine3::IDENTITY,
                    turn(-s, DVec3::X),
                ]
            };
            let group = groups(4, &world(0.0), &world(1.0));
            // Every pair of balls of sections moving apart, brute force.
            let brute = |now: &[DVec3]| {
                let mut deepest = 0.0f64;
                for a in 0..n {
                    for b in a + 1..n {
                        if group[balls.section[a]] != group[balls.section[b]] {
                            deepest = deepest.max(balls.press(a, b, now[a], now[b]));
                        }
                    }
                }
                deepest
            };
            // Along the move in coarse steps (each listed again, with margins as wide as
            // the steps), then in fine ones (a drag's: the list kept for many).
            for steps in [64, 1024] {
                let mut near = Near::default();
                let mut last = world(0.0);
                for k in 0..=steps {
                    let w = world(k as f64 / steps as f64);
                    near.cover(&balls, &last, &w);
                    last = w.clone();
                    if steps > 64 && k % 8 != 0 {
                        continue;
                    }
                    let found = near.deepest(&balls, &group, &w, f64::INFINITY).0;
                    let posed = balls.posed(&w);
                    let expected = brute(&posed);
                    assert!(
                        (found - expected).abs() <= 1e-9 * expected.max(1.0),
                        "trial {trial}, step {k} of {steps}: {found} against {expected}"
                    );
                    pressed += usize::from(found > balls.squash);
                    if steps > 64 {
                        continue;
                    }
                    // Halfway through the move just covered (as a bisection asks).
                    if k > 0 {
                        let mid = world((k as f64 - 0.5) / steps as f64);
                        let found = near.deepest(&balls, &group, &mid, f64::INFINITY).0;
                        let expected = brute(&balls.posed(&mid));
                        assert!(
                            (found - expected).abs() <= 1e-9 * expected.max(1.0),
                            "trial {trial}, halfway to step {k}: {found} against {expected}"
                        );
                    }
                    // The pairs of sections pressing, every ball against every other.
                    let mut sections = Vec::new();
                    for x in 0..n {
                        for y in x + 1..n {
                            let (sx, sy) = (balls.section[x], balls.section[y]);
                            let pair = (sx.min(sy), sx.max(sy));
                            if balls.press(x, y, posed[x], posed[y]) > 0.0
                                && !sections.contains(&pair)
                            {
                                sections.push(pair);
                            }
                        }
                    }
                    let mut by_grid = balls.pressing_sections(&w);
                    sections.sort_unstable();
                    by_grid.sort_unstable();
                    assert_eq!(by_grid, sections, "trial {trial}, step {k}");
                }
                if steps > 64 {
                    lists += near.lists();
                }
            }
        }
        assert!(pressed > 100, "{pressed} poses pressed");
        assert!(lists < 20 * 1024 / 4, "{lists} lists");
    }
}
