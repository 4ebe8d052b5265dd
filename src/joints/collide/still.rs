//! The pose limit's broad phase: the balls that do not move during a move, in a grid,
//! and the pairs each stretch of the move may press (see the parent module's docs).

use super::{Balls, MAX_CELLS};
use crate::geom::cells::SortedCells;
use glam::{DAffine3, DVec3};

/// A moving ball and a small still ball that may press during a move.
#[derive(Clone, Copy, Debug)]
struct Pair {
    /// The moving ball's index among [`Still::movers`].
    mover: u32,
    /// The still ball.
    ball: u32,
    /// How far the moving ball must move from where it starts before they can press.
    gap: f64,
}

/// What [`Still::sweep`] found for a move.
#[derive(Clone, Debug)]
struct Swept {
    /// The pairs that may press somewhere along it.
    pairs: Vec<Pair>,
    /// Per moving ball: too big or too fast for pairs (it tests every small still ball).
    wide: Vec<bool>,
    /// The pairs of moving balls (indices into [`Still::movers`]) of sections moving
    /// apart whose boxes over the stretch meet, less those that never press, each with
    /// how far the two must move together from where they start before they can press.
    movers: Vec<(u32, u32, f64)>,
}

/// The balls that do not move during a move, in a grid, and those that do.
pub(super) struct Still<'a> {
    balls: &'a Balls,
    /// Per pair of sections (`a * n + b`): their relative transform changes in the move.
    apart: Vec<bool>,
    sections: usize,
    /// Balls of moving sections.
    pub(super) movers: Vec<usize>,
    /// The others, posed: small ones by grid cell, big ones (over a cell) apart.
    posed: Vec<DVec3>,
    grid: SortedCells,
    /// The lowest and highest cell holding a ball.
    extent: ([i64; 3], [i64; 3]),
    big: Vec<u32>,
    /// Per ball: in the grid.
    gridded: Vec<bool>,
    /// Once swept ([`Still::sweep`]): the pairs that may press somewhere along the move.
    swept: Option<Swept>,
    /// Where each moving ball starts the move.
    start: Vec<DVec3>,
}

impl<'a> Still<'a> {
    pub(super) fn new(balls: &'a Balls, world: &[DAffine3], moving: &[bool]) -> Still<'a> {
        let sections = moving.len().max(world.len());
        let mut out = Still {
            balls,
            apart: vec![true; sections * sections],
            sections,
            movers: Vec::new(),
            posed: vec![DVec3::ZERO; balls.len()],
            grid: SortedCells::default(),
            extent: ([i64::MAX; 3], [i64::MIN; 3]),
            big: Vec::new(),
            gridded: vec![false; balls.len()],
            swept: None,
            start: Vec::new(),
        };
        let mut cells = Vec::new();
        for b in 0..balls.len() {
            let s = balls.section[b];
            if moving.get(s).copied().unwrap_or(false) {
                out.movers.push(b);
                continue;
            }
            let p = world
                .get(s)
                .map_or(balls.center[b], |w| w.transform_point3(balls.center[b]));
            out.posed[b] = p;
            if balls.radius[b] > balls.cell || !p.is_finite() {
                out.big.push(b as u32);
            } else {
                let k = out.key(p);
                for (d, &kd) in k.iter().enumerate() {
                    out.extent.0[d] = out.extent.0[d].min(kd);
                    out.extent.1[d] = out.extent.1[d].max(kd);
                }
                cells.push((k, b as u32));
                out.gridded[b] = true;
            }
        }
        out.grid = SortedCells::new(cells);
        out
    }

    /// Marks the pairs of moving sections that move together (their relative transform
    /// the same at both ends): their balls cannot come to press.
    pub(super) fn relative(&mut self, start: &[DAffine3], end: &[DAffine3]) {
        let n = self.sections.min(start.len()).min(end.len());
        for a in 0..n {
            for b in 0..n {
                let before = start[a].inverse() * start[b];
                let after = end[a].inverse() * end[b];
                self.apart[a * self.sections + b] = !before.abs_diff_eq(after, 1e-9);
            }
        }
    }

    /// Finds, for the stretch of a move through the poses `poses` (world transforms at its
    /// samples, first to last), the still balls each moving ball may press: the big ones
    /// and the small ones in the cells within its radius and a cell of the box its centre
    /// sweeps, grown by its longest step between samples, no farther than it moves (a
    /// pair presses only once the moving ball has moved by their gap at the start, plus
    /// the squash); and the pairs of moving balls that may press ([`Still::moving_pairs`]).
    /// Pairs that never press are left out.
    pub(super) fn sweep(&mut self, poses: &[Vec<DAffine3>]) {
        let balls = self.balls;
        let cell = balls.cell;
        let mut pairs = Vec::new();
        let mut wide = vec![false; self.movers.len()];
        let (lo, hi) = self.extent;
        self.start.clear();
        // Each moving ball's box over the stretch, its radius and a step about it.
        let mut boxes = Vec::with_capacity(self.movers.len());
        for (i, &a) in self.movers.iter().enumerate() {
            let s = balls.section[a];
            let at = |w: &Vec<DAffine3>| {
                w.get(s)
                    .map_or(balls.center[a], |m| m.transform_point3(balls.center[a]))
            };
            let (mut min, mut max) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            let (mut step, mut far) = (0.0f64, 0.0f64);
            let first = poses.first().map_or(balls.center[a], at);
            self.start.push(first);
            let mut last: Option<DVec3> = None;
            for w in poses {
                let p = at(w);
                min = min.min(p);
                max = max.max(p);
                far = far.max(p.distance(first));
                if let Some(q) = last {
                    step = step.max(p.distance(q));
                }
                last = Some(p);
            }
            // Between samples a ball strays at most a step from them.
            let reach = far + step;
            let own = balls.radius[a] + step;
            boxes.push((min - own, max + own));
            let grow = balls.radius[a] + cell + step;
            let (a_lo, a_hi) = (self.key(min - grow), self.key(max + grow));
            let span = (0..3).map(|d| (a_hi[d].min(hi[d]) - a_lo[d].max(lo[d]) + 1).max(0));
            let count: i64 = span.product();
            if !(min.is_finite() && max.is_finite()) || count > 4096 {
                wide[i] = true;
                continue;
            }
            // A still ball it may press along the stretch: no farther than it moves.
            let mut consider = |b: u32| {
                let gap = self.gap(a, b as usize, first);
                if gap < reach && !balls.never(a, b as usize) {
                    pairs.push(Pair {
                        mover: i as u32,
                        ball: b,
                        gap,
                    });
                }
            };
            self.big.iter().for_each(|&b| consider(b));
            let from = [a_lo[0].max(lo[0]), a_lo[1].max(lo[1]), a_lo[2].max(lo[2])];
            let to = [a_hi[0].min(hi[0]), a_hi[1].min(hi[1]), a_hi[2].min(hi[2])];
            self.grid.each_in(from, to, consider);
        }
        let movers = self.moving_pairs(&boxes);
        self.swept = Some(Swept {
            pairs,
            wide,
            movers,
        });
    }

    /// The pairs of moving balls whose `boxes` (over a stretch) meet, of sections moving
    /// apart, less those that never press: each pair once, found in the grid cell
    /// holding the low corner of where the two boxes meet. A ball whose box spans more
    /// than [`MAX_CELLS`] cells (or is not finite) is paired with every other box it meets.
    fn moving_pairs(&self, boxes: &[(DVec3, DVec3)]) -> Vec<(u32, u32, f64)> {
        let balls = self.balls;
        // Cells twice the still grid's: most small balls' boxes span a few.
        let size = 2.0 * balls.cell;
        let key = |p: DVec3| {
            let k = (p / size).floor();
            [k.x as i64, k.y as i64, k.z as i64]
        };
        let (sa, sb) = (
            |i: usize| balls.section[self.movers[i]],
            |j: usize| balls.section[self.movers[j]],
        );
        let pressable = |i: usize, j: usize| {
            let (a, b) = (self.movers[i], self.movers[j]);
            sa(i) != sb(j)
                && self
                    .apart
                    .get(sa(i) * self.sections + sb(j))
                    .copied()
                    .unwrap_or(true)
                && !balls.never(a, b)
        };
        // Only a ball whose box meets the box of another section moving apart from its
        // own may press one of its balls: most lie far from every other part.
        let mut section_box = vec![(DVec3::INFINITY, DVec3::NEG_INFINITY); self.sections];
        for (i, &(lo, hi)) in boxes.iter().enumerate() {
            if let Some(b) = section_box.get_mut(sa(i)) {
                *b = (b.0.min(lo), b.1.max(hi));
            }
        }
        let boxes_meet = |(a0, a1): (DVec3, DVec3), (b0, b1): (DVec3, DVec3)| {
            a0.cmple(b1).all() && b0.cmple(a1).all()
        };
        // Per section, the others moving apart from it whose boxes meet its own.
        let others: Vec<Vec<usize>> = (0..self.sections)
            .map(|s| {
                (0..self.sections)
                    .filter(|&t| {
                        t != s
                            && self
                                .apart
                                .get(s * self.sections + t)
                                .copied()
                                .unwrap_or(true)
                            && boxes_meet(section_box[s], section_box[t])
                    })
                    .collect()
            })
            .collect();
        let near = |i: usize| {
            let (lo, hi) = boxes[i];
            !(lo.is_finite() && hi.is_finite())
                || others
                    .get(sa(i))
                    .is_some_and(|o| o.iter().any(|&t| boxes_meet(boxes[i], section_box[t])))
        };
        // The grid holds each ball's rank by section, so a cell's balls come by section.
        let mut order: Vec<usize> = (0..boxes.len()).collect();
        order.sort_by_key(|&i| (sa(i), i));
        let mut rank = vec![0u32; boxes.len()];
        for (r, &i) in order.iter().enumerate() {
            rank[i] = r as u32;
        }
        let mut cells = Vec::new();
        let mut wide = Vec::new();
        // Each box's lowest cell: where two boxes meet begins in the higher of theirs.
        let mut low = vec![[0i64; 3]; boxes.len()];
        for (i, &(lo, hi)) in boxes.iter().enumerate() {
            if !near(i) {
                continue;
            }
            let (k0, k1) = (key(lo), key(hi));
            let count: i64 = (0..3).map(|d| (k1[d] - k0[d] + 1).max(0)).product();
            if !(lo.is_finite() && hi.is_finite()) || count > MAX_CELLS {
                wide.push(i);
                continue;
            }
            low[i] = k0;
            for x in k0[0]..=k1[0] {
                for y in k0[1]..=k1[1] {
                    for z in k0[2]..=k1[2] {
                        cells.push(([x, y, z], rank[i]));
                    }
                }
            }
        }
        let grid = SortedCells::new(cells);
        let mut out = Vec::new();
        for (cell, list) in grid.runs() {
            // A cell's balls by section: each pairs only with those of later sections.
            let mut first = 0;
            while first < list.len() {
                let s = sa(order[list[first].1 as usize]);
                let end = first + list[first..].partition_point(|e| sa(order[e.1 as usize]) == s);
                for &(_, i) in &list[first..end] {
                    let i = order[i as usize];
                    for &(_, j) in &list[end..] {
                        let j = order[j as usize];
                        let (a, b) = (low[i], low[j]);
                        if [a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])] == cell
                            && boxes_meet(boxes[i], boxes[j])
                            && pressable(i, j)
                        {
                            out.push((i as u32, j as u32, self.pair_gap(i, j)));
                        }
                    }
                }
                first = end;
            }
        }
        let is_wide = {
            let mut w = vec![false; boxes.len()];
            for &i in &wide {
                w[i] = true;
            }
            w
        };
        for &i in &wide {
            for j in 0..boxes.len() {
                let both_finite = boxes[i].0.is_finite() && boxes[i].1.is_finite();
                if j != i
                    && (!is_wide[j] || j > i)
                    && (!both_finite || boxes_meet(boxes[i], boxes[j]))
                    && pressable(i, j)
                {
                    out.push((i as u32, j as u32, self.pair_gap(i, j)));
                }
            }
        }
        out
    }

    /// How far moving balls `i` and `j` (indices into [`Still::movers`]) must move, the
    /// two together, from where they start before they can press (see [`Still::gap`]).
    fn pair_gap(&self, i: usize, j: usize) -> f64 {
        let balls = self.balls;
        let (a, b) = (self.movers[i], self.movers[j]);
        let (ra, rb) = (balls.radius[a], balls.radius[b]);
        self.start[i].distance(self.start[j]) - ra - rb + balls.squash * ra.min(rb)
    }

    /// How far moving ball `a`, at `at`, must move before it can press still ball `b`:
    /// their gap plus the squash (see [`Balls::press`]).
    fn gap(&self, a: usize, b: usize, at: DVec3) -> f64 {
        let balls = self.balls;
        let (ra, rb) = (balls.radius[a], balls.radius[b]);
        at.distance(self.posed[b]) - ra - rb + balls.squash * ra.min(rb)
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        let k = (p / self.balls.cell).floor();
        [k.x as i64, k.y as i64, k.z as i64]
    }

    /// The deepest press of a moving ball in the pose `world`, or the first found deeper
    /// than `stop` (a move is refused as soon as one pair presses too much).
    pub(super) fn pressing(&self, world: &[DAffine3], stop: f64) -> f64 {
        self.deepest(world, stop).0
    }

    /// [`Still::pressing`], with the balls of the pair found (`None` when none presses).
    pub(super) fn deepest(&self, world: &[DAffine3], stop: f64) -> (f64, Option<(usize, usize)>) {
        let balls = self.balls;
        let posed = |b: usize| {
            world
                .get(balls.section[b])
                .map_or(balls.center[b], |w| w.transform_point3(balls.center[b]))
        };
        let movers: Vec<DVec3> = self.movers.iter().map(|&b| posed(b)).collect();
        let mut deepest = (0.0f64, None);
        // Keeps the deeper press; true once it is deeper than `stop`.
        let deeper = |deepest: &mut (f64, Option<(usize, usize)>),
                      a: usize,
                      b: usize,
                      pa: DVec3,
                      pb: DVec3| {
            let p = balls.press(a, b, pa, pb);
            if p > deepest.0 {
                *deepest = (p, Some((a, b)));
            }
            deepest.0 > stop
        };
        // Moving balls of sections moving apart from each other (two arms turned into
        // each other): once swept, the pairs whose boxes meet over the stretch.
        if let Some(swept) = &self.swept {
            // How far each moving ball is from where it started: a pair presses only past
            // its gap.
            let moved: Vec<f64> = movers
                .iter()
                .zip(&self.start)
                .map(|(p, q)| p.distance(*q))
                .collect();
            let Swept { pairs, wide, .. } = swept;
            for &(i, j, gap) in &swept.movers {
                let (i, j) = (i as usize, j as usize);
                if moved[i] + moved[j] <= gap {
                    continue;
                }
                if deeper(
                    &mut deepest,
                    self.movers[i],
                    self.movers[j],
                    movers[i],
                    movers[j],
                ) {
                    return deepest;
                }
            }
            for &Pair { mover, ball, gap } in pairs {
                let (i, b) = (mover as usize, ball as usize);
                if moved[i] <= gap {
                    continue;
                }
                if deeper(&mut deepest, self.movers[i], b, movers[i], self.posed[b]) {
                    return deepest;
                }
            }
            // A ball too big or too fast for pairs tests every still ball.
            for (i, &a) in self.movers.iter().enumerate().filter(|&(i, _)| wide[i]) {
                let pa = movers[i];
                let gridded = (0..balls.len()).filter(|&b| self.gridded[b]);
                for b in self.big.iter().map(|&b| b as usize).chain(gridded) {
                    if deeper(&mut deepest, a, b, pa, self.posed[b]) {
                        return deepest;
                    }
                }
            }
            return deepest;
        }
        {
            // Moving balls of sections moving apart from each other (two arms turned into
            // each other): small ones by grid cell, each pair once.
            let sections = self.sections;
            let apart = |a: usize, b: usize| {
                self.apart
                    .get(balls.section[a] * sections + balls.section[b])
                    .copied()
                    .unwrap_or(true)
            };
            // Cells twice the still grid's: two small balls (at most a cell across each) that
            // overlap lie in neighbouring cells.
            let wide = 2.0 * balls.cell;
            let key = |p: DVec3| {
                let k = (p / wide).floor();
                [k.x as i64, k.y as i64, k.z as i64]
            };
            // Only a moving ball that reaches the box of another section moving apart from its
            // own can press one of its balls: most lie far from every other part.
            let mut boxes = vec![(DVec3::INFINITY, DVec3::NEG_INFINITY); sections];
            for (i, &a) in self.movers.iter().enumerate() {
                let (s, r) = (balls.section[a], balls.radius[a]);
                if let Some(b) = boxes.get_mut(s) {
                    *b = (b.0.min(movers[i] - r), b.1.max(movers[i] + r));
                }
            }
            let near: Vec<bool> = self
                .movers
                .iter()
                .enumerate()
                .map(|(i, &a)| {
                    let (s, r, p) = (balls.section[a], balls.radius[a], movers[i]);
                    !p.is_finite()
                        || boxes.iter().enumerate().any(|(t, &(lo, hi))| {
                            t != s
                                && self.apart.get(s * sections + t).copied().unwrap_or(true)
                                && (p - r).cmple(hi).all()
                                && lo.cmple(p + r).all()
                        })
                })
                .collect();
            let mut cells = Vec::new();
            let mut big = Vec::new();
            for (i, &a) in self.movers.iter().enumerate() {
                if !near[i] {
                    continue;
                }
                if balls.radius[a] > balls.cell || !movers[i].is_finite() {
                    big.push(i);
                } else {
                    cells.push((key(movers[i]), i as u32));
                }
            }
            let grid = SortedCells::new(cells);
            for (i, &a) in self.movers.iter().enumerate() {
                if !near[i] || balls.radius[a] > balls.cell || !movers[i].is_finite() {
                    continue;
                }
                let k = key(movers[i]);
                for x in k[0] - 1..=k[0] + 1 {
                    for y in k[1] - 1..=k[1] + 1 {
                        for &(_, j) in grid.row(x, y, k[2] - 1, k[2] + 1) {
                            let (j, b) = (j as usize, self.movers[j as usize]);
                            if j > i
                                && apart(a, b)
                                && deeper(&mut deepest, a, b, movers[i], movers[j])
                            {
                                return deepest;
                            }
                        }
                    }
                }
            }
            for &i in &big {
                let a = self.movers[i];
                for (j, &b) in self.movers.iter().enumerate() {
                    let other_big = balls.radius[b] > balls.cell || !movers[j].is_finite();
                    if near[j]
                        && (!other_big || j > i)
                        && apart(a, b)
                        && deeper(&mut deepest, a, b, movers[i], movers[j])
                    {
                        return deepest;
                    }
                }
            }
        }
        for (i, &a) in self.movers.iter().enumerate() {
            let pa = movers[i];
            for &b in &self.big {
                let b = b as usize;
                if deeper(&mut deepest, a, b, pa, self.posed[b]) {
                    return deepest;
                }
            }
            // Small still balls within reach: the cells about it (a small ball's radius is
            // at most one cell).
            let reach = ((balls.radius[a] + balls.cell) / balls.cell).ceil() as i64;
            if reach > 8 || !pa.is_finite() {
                for b in 0..balls.len() {
                    if self.gridded[b] && deeper(&mut deepest, a, b, pa, self.posed[b]) {
                        return deepest;
                    }
                }
                continue;
            }
            // The cells about it that hold any ball.
            let k = self.key(pa);
            let (lo, hi) = self.extent;
            let span = |d: usize| (k[d] - reach).max(lo[d])..=(k[d] + reach).min(hi[d]);
            let (z0, z1) = (*span(2).start(), *span(2).end());
            for x in span(0) {
                for y in span(1) {
                    for &(_, b) in self.grid.row(x, y, z0, z1) {
                        let b = b as usize;
                        if deeper(&mut deepest, a, b, pa, self.posed[b]) {
                            return deepest;
                        }
                    }
                }
            }
        }
        deepest
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::balls;
    use crate::random::SplitMix;

    fn unit(rng: &mut SplitMix) -> f64 {
        (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The swept pairs find what the grid finds at every pose along a move, and along a
    /// stretch of it swept alone: the same deepest press, over random balls in four
    /// sections, two of them turning.
    #[test]
    fn the_swept_pairs_press_as_the_grid_does_all_along_a_move() {
        let mut rng = SplitMix(11);
        let mut pressed = 0;
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
            let moving = vec![false, true, false, true];
            let mut grid = Still::new(&balls, &world(0.0), &moving);
            grid.relative(&world(0.0), &world(1.0));
            let mut swept = Still::new(&balls, &world(0.0), &moving);
            swept.relative(&world(0.0), &world(1.0));
            let samples = 16;
            let poses: Vec<Vec<DAffine3>> = (0..=samples)
                .map(|k| world(k as f64 / samples as f64))
                .collect();
            swept.sweep(&poses);
            for k in 0..=64 {
                let s = k as f64 / 64.0;
                let w = world(s);
                let (a, b) = (
                    grid.pressing(&w, f64::INFINITY),
                    swept.pressing(&w, f64::INFINITY),
                );
                assert_eq!(a, b, "trial {trial}, s {s}");
                // Every pair, brute force: a moving ball against every still one, and
                // against every moving one of a section turning apart from its own.
                let at = |b: usize| w[balls.section[b]].transform_point3(balls.center[b]);
                let mut brute = 0.0f64;
                for &m in &grid.movers {
                    for o in 0..n {
                        let other_moves = moving[balls.section[o]];
                        if other_moves && (o <= m || balls.section[o] == balls.section[m]) {
                            continue;
                        }
                        brute = brute.max(balls.press(m, o, at(m), at(o)));
                    }
                }
                assert_eq!(a, brute, "trial {trial}, s {s}");
                // The pairs of sections pressing, every ball against every other.
                let mut sections = Vec::new();
                for x in 0..n {
                    for y in x + 1..n {
                        let (sx, sy) = (balls.section[x], balls.section[y]);
                        let pair = (sx.min(sy), sx.max(sy));
                        if balls.press(x, y, at(x), at(y)) > 0.0 && !sections.contains(&pair) {
                            sections.push(pair);
                        }
                    }
                }
                let mut found = balls.pressing_sections(&w);
                sections.sort_unstable();
                found.sort_unstable();
                assert_eq!(found, sections, "trial {trial}, s {s}");
                pressed += usize::from(a > balls.squash);
            }
            let pairs = &swept.swept.as_ref().expect("swept").pairs;
            assert!(pairs.len() < grid.movers.len() * (n - grid.movers.len()));
            // A stretch of the move swept alone (`Balls::reach` sweeps one at a time):
            // the same presses anywhere along it.
            let mut stretch = Still::new(&balls, &world(0.0), &moving);
            stretch.relative(&world(0.0), &world(1.0));
            stretch.sweep(&poses[4..=8]);
            for k in 16..=32 {
                let w = world(k as f64 / 64.0);
                assert_eq!(
                    grid.pressing(&w, f64::INFINITY),
                    stretch.pressing(&w, f64::INFINITY),
                    "trial {trial}, stretch, s {k}/64"
                );
            }
        }
        assert!(pressed > 100, "{pressed} poses pressed");
    }
}
