//! The pose limit's broad phase: the pairs of balls of different sections that lie near
//! each other, listed once and kept from move to move (a Verlet list) while no ball
//! strays farther than its margin (see the parent module's docs).

use super::Balls;
use crate::geom::cells::SortedCells;
use glam::{DAffine3, DVec3};

/// The margin a list is made with, as a share of the grid's cell (twice the 90th
/// percentile radius): a larger one lists more pairs and is made again less often.
const SKIN: f64 = 1.0;

/// Bins of each block of pairs by gap ([`Block`]).
const BINS: usize = 8;

/// The most slots (pairs of sections times bins) the pairs are counted into; beyond, as
/// with hundreds of sections, they are sorted.
const COUNTED: usize = 1 << 18;

/// The pairs of balls that may press while every ball stays within its margin of where
/// it was when they were listed. Kept by the puppet between moves; made again
/// ([`Near::cover`]) when a move takes a ball farther.
#[derive(Clone, Debug, Default)]
pub struct Near {
    /// Where each ball was when the pairs were listed (empty: not listed).
    at: Vec<DVec3>,
    /// How far each ball may stray from `at` before the pairs are listed again.
    margin: Vec<f64>,
    /// Twice the largest margin: the gaps of the pairs listed are under it.
    skin: f64,
    /// The pairs, each once, by pair of sections (`blocks`), each block's binned by
    /// their gap when listed; pairs that never press are left out.
    pairs: Vec<Pair>,
    /// The runs of `pairs` of one pair of sections.
    blocks: Vec<Block>,
    /// How many times the pairs were listed.
    lists: usize,
}

/// Two balls listed as near ([`Near`]).
#[derive(Clone, Copy, Debug)]
struct Pair {
    a: u32,
    b: u32,
    /// How far apart their surfaces lay when listed: they press only once the two have
    /// strayed that far together.
    gap: f64,
}

/// The listed pairs of balls of two sections, by their gap: bin `k` is
/// `pairs[bins[k]..bins[k + 1]]`, the first holding those that overlapped when listed,
/// bin `k` those whose gap was under `k / BINS` of the margin.
#[derive(Clone, Copy, Debug)]
struct Block {
    sections: (u32, u32),
    bins: [u32; BINS + 2],
}

impl Near {
    /// How many times the pairs were listed (each a pass over every ball).
    pub fn lists(&self) -> usize {
        self.lists
    }

    /// Makes sure the list holds every pair that may press anywhere between the ball
    /// positions `from` and `to` (two samples of a move, a ball straying at most its step
    /// between them): listed again at `from` when some ball would stray farther than its
    /// margin from where it was listed.
    pub(super) fn cover(&mut self, balls: &Balls, from: &[DVec3], to: &[DVec3]) {
        let holds = self.at.len() == to.len()
            && (0..to.len()).all(|b| {
                let (p, q) = (from[b], to[b]);
                !(p.is_finite() && q.is_finite())
                    || q.distance(self.at[b]) + p.distance(q) <= self.margin[b]
            });
        if !holds {
            self.list(balls, from, to);
        }
    }

    /// Lists the pairs of balls at `from` whose gap is under their two margins, less those
    /// that never press. A ball's margin is half of [`SKIN`] of the grid's cell, or twice
    /// its step from `from` to `to` where that is more (a move sampled coarser than its
    /// balls: the list then holds at `to`). Small balls (at most half a cell across) of
    /// the base margin by grid cells, the rest (big or fast) against the small ones in the
    /// cells their reach meets, and against each other where their reaches overlap along
    /// one axis.
    fn list(&mut self, balls: &Balls, from: &[DVec3], to: &[DVec3]) {
        self.lists += 1;
        let posed = from;
        self.at.clear();
        self.at.extend_from_slice(posed);
        let base = 0.5 * SKIN * balls.cell;
        self.margin.clear();
        self.margin.extend(from.iter().zip(to).map(|(p, q)| {
            let step = p.distance(*q);
            if step.is_finite() {
                base.max(2.0 * step)
            } else {
                base
            }
        }));
        let margin = &self.margin;
        self.skin = 2.0 * margin.iter().copied().fold(base, f64::max);
        self.pairs.clear();
        let half = 0.5 * balls.cell;
        let size = balls.cell + 2.0 * base;
        let key = |p: DVec3| {
            let k = (p / size).floor();
            [k.x as i64, k.y as i64, k.z as i64]
        };
        let wide = |b: usize| balls.radius[b] > half || margin[b] > base;
        let mut others = Vec::new();
        // The grid holds each small ball's rank by section, so a cell's balls come by
        // section and pairs of one section are passed over a run at a time.
        let mut order: Vec<usize> = (0..posed.len()).collect();
        order.sort_by_key(|&b| (balls.section[b], b));
        let mut cells = Vec::new();
        for (rank, &b) in order.iter().enumerate() {
            let p = posed[b];
            if !p.is_finite() {
                continue;
            }
            if wide(b) {
                others.push(b);
            } else {
                cells.push((key(p), rank as u32));
            }
        }
        let small = cells.len() as i64;
        let grid = SortedCells::new(cells);
        let gap =
            |a: usize, b: usize| posed[a].distance(posed[b]) - balls.radius[a] - balls.radius[b];
        // (Per pair, its two sections' key.)
        let sections = balls.section.iter().copied().max().map_or(0, |s| s + 1);
        let mut found: Vec<(usize, Pair)> = Vec::new();
        let mut add = |a: usize, b: usize| {
            let (sa, sb) = (balls.section[a], balls.section[b]);
            if sa != sb {
                let g = gap(a, b);
                if g < margin[a] + margin[b] && !balls.never(a, b) {
                    let (a, b) = if sa < sb { (a, b) } else { (b, a) };
                    let key = sa.min(sb) * sections + sa.max(sb);
                    let (a, b) = (a as u32, b as u32);
                    found.push((key, Pair { a, b, gap: g }));
                }
            }
        };
        let section_of = |e: &([i64; 3], u32)| balls.section[order[e.1 as usize]];
        // Each pair of small balls of two sections once: a cell's own, then those with
        // the cells after it (the half of its 26 neighbours that come later in the grid's
        // order).
        for (k, run) in grid.runs() {
            let mut first = 0;
            while first < run.len() {
                let s = section_of(&run[first]);
                let end = first + run[first..].partition_point(|e| section_of(e) == s);
                for &(_, a) in &run[first..end] {
                    for &(_, b) in &run[end..] {
                        add(order[a as usize], order[b as usize]);
                    }
                }
                first = end;
            }
            let [x, y, z] = k;
            let later = [
                (x, y, z + 1, z + 1),
                (x, y + 1, z - 1, z + 1),
                (x + 1, y - 1, z - 1, z + 1),
                (x + 1, y, z - 1, z + 1),
                (x + 1, y + 1, z - 1, z + 1),
            ];
            for (x, y, z0, z1) in later {
                for e in grid.row(x, y, z0, z1) {
                    let b = order[e.1 as usize];
                    // The run's balls of other sections than `b`'s.
                    let s = balls.section[b];
                    let lo = run.partition_point(|f| section_of(f) < s);
                    let hi = lo + run[lo..].partition_point(|f| section_of(f) == s);
                    for &(_, a) in run[..lo].iter().chain(&run[hi..]) {
                        add(order[a as usize], b);
                    }
                }
            }
        }
        // A big or fast ball against the small ones in the cells its reach meets.
        for &a in &others {
            let reach = DVec3::splat(balls.radius[a] + margin[a] + half + base);
            let (lo, hi) = (key(posed[a] - reach), key(posed[a] + reach));
            let cells: i64 = (0..3).map(|d| (hi[d] - lo[d] + 1).max(0)).product();
            if cells <= small {
                grid.each_in(lo, hi, |b| add(a, order[b as usize]));
            } else {
                for (_, b) in grid.runs().flat_map(|(_, run)| run) {
                    add(a, order[*b as usize]);
                }
            }
        }
        // And against each other: those whose reaches overlap along x.
        let span = |b: usize| {
            let r = balls.radius[b] + margin[b];
            (posed[b].x - r, posed[b].x + r)
        };
        others.sort_unstable_by(|&a, &b| span(a).0.total_cmp(&span(b).0));
        for (n, &a) in others.iter().enumerate() {
            let end = span(a).1;
            for &b in &others[n + 1..] {
                if span(b).0 > end {
                    break;
                }
                add(a, b);
            }
        }
        self.lay_out(found, sections, COUNTED);
    }

    /// Keeps `found` (pairs with their sections' key, `sections` of them) by pair of
    /// sections, each block by its gap's bin: counted, then laid out, or sorted where
    /// there are more than `counted` slots (pairs of sections times bins) to count.
    fn lay_out(&mut self, mut found: Vec<(usize, Pair)>, sections: usize, counted: usize) {
        let skin = self.skin;
        let bin =
            |g: f64| ((g / skin * BINS as f64).floor() + 1.0).clamp(0.0, BINS as f64) as usize;
        let slots = sections * sections * (BINS + 1);
        self.blocks.clear();
        self.pairs.clear();
        if slots > counted {
            found.sort_unstable_by_key(|&(key, pair)| (key, bin(pair.gap)));
            self.pairs.extend(found.iter().map(|&(_, pair)| pair));
            let mut start = 0;
            for run in found.chunk_by(|x, y| x.0 == y.0) {
                let key = run[0].0;
                let bins = std::array::from_fn(|k| {
                    (start + run.partition_point(|&(_, p)| bin(p.gap) < k)) as u32
                });
                self.blocks.push(Block {
                    sections: ((key / sections) as u32, (key % sections) as u32),
                    bins,
                });
                start += run.len();
            }
            return;
        }
        let slot = |key: usize, g: f64| key * (BINS + 1) + bin(g);
        let mut count = vec![0u32; slots + 1];
        for &(key, pair) in &found {
            count[slot(key, pair.gap) + 1] += 1;
        }
        for k in 1..count.len() {
            count[k] += count[k - 1];
        }
        let mut next = count.clone();
        self.pairs.resize(
            found.len(),
            Pair {
                a: 0,
                b: 0,
                gap: 0.0,
            },
        );
        for &(key, pair) in &found {
            let k = slot(key, pair.gap);
            self.pairs[next[k] as usize] = pair;
            next[k] += 1;
        }
        for key in 0..sections * sections {
            let bins = &count[key * (BINS + 1)..=(key + 1) * (BINS + 1)];
            if bins[0] < bins[BINS + 1] {
                self.blocks.push(Block {
                    sections: ((key / sections) as u32, (key % sections) as u32),
                    bins: std::array::from_fn(|k| bins[k]),
                });
            }
        }
    }

    /// The deepest press among the listed pairs of balls at `posed` whose sections move
    /// apart (their balls' `group` differs: [`groups`]), or the first found deeper than
    /// `stop`, with the pair's balls. Only pairs whose balls have strayed together farther
    /// than their gap are tested: none of the rest can press.
    pub(super) fn deepest(
        &self,
        balls: &Balls,
        group: &[u32],
        posed: &[DVec3],
        stop: f64,
    ) -> (f64, Option<(usize, usize)>) {
        let mut deepest = (0.0f64, None);
        // How far each ball strayed from where it was listed (not finite: as far as can
        // be), and the farthest of each section's.
        let mut farthest = vec![
            0.0f64;
            self.blocks
                .iter()
                .map(|b| b.sections.1 as usize + 1)
                .max()
                .unwrap_or(0)
        ];
        let strayed: Vec<f64> = posed
            .iter()
            .zip(&self.at)
            .enumerate()
            .map(|(b, (p, q))| {
                let d = p.distance(*q);
                let d = if d.is_finite() { d } else { f64::INFINITY };
                if let Some(f) = farthest.get_mut(balls.section[b]) {
                    *f = f.max(d);
                }
                d
            })
            .collect();
        for block in &self.blocks {
            let (sa, sb) = (block.sections.0 as usize, block.sections.1 as usize);
            let (start, end) = (block.bins[0] as usize, block.bins[BINS + 1] as usize);
            let Some(first) = self.pairs.get(start).filter(|_| start < end) else {
                continue;
            };
            if group[first.a as usize] == group[first.b as usize] {
                continue;
            }
            // No pair of the two sections strayed together farther than this: the bins
            // whose gaps may be under it.
            let bound = farthest[sa] + farthest[sb];
            let last = ((bound / self.skin * BINS as f64).floor() + 2.0).min(BINS as f64 + 1.0);
            let end = block.bins[last as usize] as usize;
            for &Pair { a, b, gap } in &self.pairs[start..end] {
                let (a, b) = (a as usize, b as usize);
                if strayed[a] + strayed[b] <= gap {
                    continue;
                }
                let p = balls.press_near(a, b, posed[a], posed[b]);
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
}

impl Near {
    /// The pairs of sections (each once, the lower first) of the listed pairs of balls
    /// that press at `posed`, whatever their motion.
    pub(super) fn pressing(&self, balls: &Balls, posed: &[DVec3]) -> Vec<(usize, usize)> {
        self.blocks
            .iter()
            .filter(|block| {
                let pairs = &self.pairs[block.bins[0] as usize..block.bins[BINS + 1] as usize];
                pairs.iter().any(|&Pair { a, b, .. }| {
                    let (a, b) = (a as usize, b as usize);
                    balls.press_near(a, b, posed[a], posed[b]) > 0.0
                })
            })
            .map(|block| (block.sections.0 as usize, block.sections.1 as usize))
            .collect()
    }
}

/// Per ball of `balls`, a group: balls of two sections whose relative transform is the
/// same at `start` and `end` (they move together, or neither moves) share one, and cannot
/// come to press over the move.
pub(super) fn groups(balls: &Balls, start: &[DAffine3], end: &[DAffine3]) -> Vec<u32> {
    let sections = start.len().max(end.len());
    // Each section's motion over the move; two move together when theirs are the same.
    let motion: Vec<DAffine3> = (0..sections)
        .map(|s| match (start.get(s), end.get(s)) {
            (Some(a), Some(b)) => *b * a.inverse(),
            _ => DAffine3::IDENTITY,
        })
        .collect();
    // The first section of each group.
    let mut first: Vec<usize> = Vec::new();
    let group: Vec<u32> = (0..sections)
        .map(|s| {
            first
                .iter()
                .position(|&f| motion[f].abs_diff_eq(motion[s], 1e-9))
                .unwrap_or_else(|| {
                    first.push(s);
                    first.len() - 1
                }) as u32
        })
        .collect();
    // (A section beyond the pose's does not move.)
    let still = motion
        .iter()
        .position(|m| m.abs_diff_eq(DAffine3::IDENTITY, 1e-9))
        .map_or(u32::MAX, |s| group[s]);
    balls
        .section
        .iter()
        .map(|&s| group.get(s).copied().unwrap_or(still))
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

    /// The listed pairs, kept along a move and listed again where it strays, find the
    /// same deepest press as every pair of balls does (brute force) at every pose along
    /// it, over random balls in four sections, two of them turning; and the list is made
    /// far fewer times than there are poses.
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
            let group = groups(&balls, &world(0.0), &world(1.0));
            // Every pair of balls of sections moving apart, brute force.
            let brute = |now: &[DVec3]| {
                let mut deepest = 0.0f64;
                for a in 0..n {
                    for b in a + 1..n {
                        if group[a] != group[b] {
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
                let mut last = balls.posed(&world(0.0));
                for k in 0..=steps {
                    let w = world(k as f64 / steps as f64);
                    let now = balls.posed(&w);
                    near.cover(&balls, &last, &now);
                    last = now;
                    if steps > 64 && k % 8 != 0 {
                        continue;
                    }
                    let found = near.deepest(&balls, &group, &last, f64::INFINITY).0;
                    assert_eq!(found, brute(&last), "trial {trial}, step {k} of {steps}");
                    pressed += usize::from(found > balls.squash);
                    if steps > 64 {
                        continue;
                    }
                    // The pairs of sections pressing, every ball against every other.
                    let mut sections = Vec::new();
                    for x in 0..n {
                        for y in x + 1..n {
                            let (sx, sy) = (balls.section[x], balls.section[y]);
                            let pair = (sx.min(sy), sx.max(sy));
                            if balls.press(x, y, last[x], last[y]) > 0.0
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
        // Sorted rather than counted (as with hundreds of sections): the same blocks, each
        // bin the same pairs.
        let n = 2000;
        let found: Vec<(usize, Pair)> = (0..n as u32)
            .map(|k| {
                let key = (rng.next_u64() % 36) as usize;
                let gap = unit(&mut rng) * 1.2 - 0.1;
                (
                    key,
                    Pair {
                        a: k,
                        b: k + 1,
                        gap,
                    },
                )
            })
            .collect();
        let (mut counted, mut sorted) = (Near::default(), Near::default());
        counted.skin = 1.0;
        sorted.skin = 1.0;
        counted.lay_out(found.clone(), 6, usize::MAX);
        sorted.lay_out(found, 6, 0);
        assert_eq!(counted.blocks.len(), sorted.blocks.len());
        for (c, s) in counted.blocks.iter().zip(&sorted.blocks) {
            assert_eq!((c.sections, c.bins), (s.sections, s.bins));
            for k in 0..=BINS {
                let set = |near: &Near, b: &Block| {
                    let mut v: Vec<u32> = near.pairs[b.bins[k] as usize..b.bins[k + 1] as usize]
                        .iter()
                        .map(|p| p.a)
                        .collect();
                    v.sort_unstable();
                    v
                };
                assert_eq!(set(&counted, c), set(&sorted, s));
            }
        }
        assert!(lists < 20 * 1024 / 16, "{lists} lists");
    }
}
