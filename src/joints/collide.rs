//! The pose limit: a section turned into another part of the body stops where their
//! medial balls meet, however fast it was dragged.
//!
//! Each section's balls ([`crate::geom::balls::thin`] of the skeleton's) move rigidly with
//! its world transform. Two balls of different sections *press* by how far they overlap
//! in a pose, over the smaller radius; pairs at one joint that were neighbours at rest
//! ([`crate::geom::balls::neighbours`]: the two sides of a joint) never press, nor does a
//! ball of a joint's flesh with one of the section across that joint that touched it at
//! rest (within [`TOUCHING`]: a chest's big ball reaching into the armpit); parts that
//! merely rest near each other (an arm hanging by the body) do, and two other balls that
//! overlapped at rest (a mesh's own overlap) press only by how much deeper they go. A pose is
//! allowed while no pair presses more than the flesh gives ([`Balls::set_squash`]: by
//! default nothing, a part stops at the other's surface), and the simulation's contacts
//! keep the surfaces apart ([`crate::sim::contact`]).
//!
//! A move stops only the parts that met ([`Balls::hold`]): the joints between the two
//! parts that pressed stop where they met, and the rest of the move goes on.
//!
//! `Balls::reach` walks from the pose the puppet has to the one asked for (each section's
//! rotation slerped, its translation lerped) in steps no ball moves more than half the
//! smallest moving radius in, so nothing passes through a part between two samples, and
//! bisects to the last allowed pose before the first that is not. A pose that already
//! presses (collision just turned on) may move anywhere that presses no more.
//!
//! The samples share their broad phase: before the walk, each moving ball gathers the
//! still balls near the box its centre sweeps over the move, less the pairs that never
//! press and those farther than it moves ([`Still::sweep`]); a sample then tests only
//! those pairs, skipping a pair until its moving ball has moved past their gap. Moving
//! balls are tested against each other only where one reaches the box of another section
//! moving apart from its own.

use super::{Joints, Local};
use crate::geom::balls;
use crate::geom::cells::Cells;
use glam::{DAffine3, DVec3};

/// How near at rest, as a share of the smaller ball's radius, a ball of a joint's flesh
/// and one of the section across that joint lie for them never to press.
const TOUCHING: f64 = 0.25;

/// Samples at most along a move (beyond them the move's sampling is coarser).
const MAX_SAMPLES: usize = 64;

/// The smallest ball the sampling of a move heeds, as a share of the grid's cell (twice
/// the 90th percentile radius).
const SMALLEST: f64 = 0.125;

/// Bisection steps between the last allowed sample and the first that is not.
const BISECTIONS: usize = 4;

/// Pairs of parts that may stop a move each before the rest of it stops too
/// ([`Balls::hold`]): each costs a walk along what is left of the move.
const ROUNDS: usize = 32;

/// The balls of a puppet's sections.
#[derive(Clone, Debug, Default)]
pub struct Balls {
    center: Vec<DVec3>,
    radius: Vec<f64>,
    section: Vec<usize>,
    /// The joint whose flesh each ball's vertex is (0: none, [`Joints::joint_flesh`];
    /// empty: unknown).
    joint: Vec<u16>,
    /// Grid cell ([`balls::cell`]).
    cell: f64,
    /// How far two parts may overlap, as a share of the smaller ball's radius
    /// ([`Balls::set_squash`]).
    squash: f64,
    /// Per cut, the sections on its two sides (the child, its parent); `None` for a cut
    /// whose section is gone.
    sides: Vec<Option<(usize, usize)>>,
}

impl Joints {
    /// The balls the pose limit tests (see the module docs).
    pub fn balls(&self) -> Balls {
        let body = &self.body;
        let n = body.points.len().min(body.radius.len());
        let kept = balls::thin(
            &body.points[..n],
            &body.radius[..n],
            &self.section_of[..n.min(self.section_of.len())],
        );
        let flesh = self.joint_flesh();
        let mut out = Balls {
            // (None known: every pair near at rest is a joint's flesh.)
            joint: if flesh.is_empty() {
                Vec::new()
            } else {
                kept.iter()
                    .map(|&i| flesh.get(i).copied().unwrap_or(0))
                    .collect()
            },
            center: kept.iter().map(|&i| body.points[i]).collect(),
            radius: kept.iter().map(|&i| body.radius[i]).collect(),
            section: kept
                .iter()
                .map(|&i| usize::from(self.section_of.get(i).copied().unwrap_or(0)))
                .collect(),
            cell: 0.0,
            squash: 0.0,
            sides: self
                .cuts
                .iter()
                .map(|c| {
                    let child = self.find(&c.name)?;
                    Some((child, self.sections[child].parent?))
                })
                .collect(),
        };
        out.cell = balls::cell(&out.radius);
        out
    }
}

impl Balls {
    /// Lets two parts overlap by `squash` of the smaller ball's radius (a puppet sets the
    /// flesh's give, `World::flesh`: soft flesh lets a part sink in, and the contacts dent
    /// it). By default 0: a part stops at the other's surface. (A fixed quarter, with each
    /// move going on past the parts that met, let the contacts push deep points out alone
    /// and tear the skin around them on 24 of 250 random poses, up to 13.8×; with none, on
    /// 10, up to 5.4×: `docs/performance-log.md`, 2026-11-30.)
    pub fn set_squash(&mut self, squash: f64) {
        self.squash = if squash.is_finite() {
            squash.max(0.0)
        } else {
            0.0
        };
    }

    /// The overlap [`Balls::set_squash`] allows.
    pub fn squash(&self) -> f64 {
        self.squash
    }

    /// Number of balls.
    pub fn len(&self) -> usize {
        self.center.len()
    }

    /// True when there is none.
    pub fn is_empty(&self) -> bool {
        self.center.is_empty()
    }

    /// How much the deepest pair of balls presses in the pose whose world transforms are
    /// `world` (see the module docs), among pairs with a ball of a section in `moving`.
    pub fn pressing(&self, world: &[DAffine3], moving: &[bool]) -> f64 {
        Still::new(self, world, moving).pressing(world, f64::INFINITY)
    }

    /// The deepest press of pair `a`, `b` at `pa`, `pb` (0 when they do not press or
    /// were neighbours at rest).
    fn press(&self, a: usize, b: usize, pa: DVec3, pb: DVec3) -> f64 {
        let (ra, rb) = (self.radius[a], self.radius[b]);
        let small = ra.min(rb);
        let depth = ra + rb - pa.distance(pb);
        if depth <= self.squash * small || self.never(a, b) {
            return 0.0;
        }
        // The two sides of a joint press when they were not neighbours at rest: an arm
        // hanging by the body presses it when it turns in.
        let joint = self.joint.get(a).copied();
        if joint.is_none() || (joint != Some(0) && joint == self.joint.get(b).copied()) {
            return depth / small;
        }
        // Other parts press by how much deeper they go than they lay at rest (a mesh's
        // own overlap).
        let at_rest_overlap = ra + rb - self.center[a].distance(self.center[b]);
        let beyond = depth - at_rest_overlap.max(0.0);
        if beyond <= self.squash * small {
            return 0.0;
        }
        beyond / small
    }

    /// Whether pair `a`, `b` never presses, whatever the pose: one section; the two sides
    /// of a joint that were neighbours at rest (the surfaces within a few of the smaller
    /// radii); or a ball of a joint's flesh and one of the section across that joint that
    /// touched it at rest, within [`TOUCHING`] (a chest's big ball reaching into the armpit
    /// does not hold the arm up).
    fn never(&self, a: usize, b: usize) -> bool {
        if self.section[a] == self.section[b] {
            return true;
        }
        let (ra, rb) = (self.radius[a], self.radius[b]);
        let small = ra.min(rb);
        let at_rest = self.center[a].distance(self.center[b]);
        let joint = self.joint.get(a).copied();
        if joint.is_none() || (joint != Some(0) && joint == self.joint.get(b).copied()) {
            return balls::neighbours(at_rest - small, ra.max(rb), small);
        }
        ra + rb - at_rest > -TOUCHING * small && (self.across(a, b) || self.across(b, a))
    }

    /// Whether ball `a` is of a joint's flesh and `b` of the section across that joint.
    fn across(&self, a: usize, b: usize) -> bool {
        let Some(&j) = self.joint.get(a) else {
            return false;
        };
        let Some(&Some((child, parent))) = self.sides.get(usize::from(j).wrapping_sub(1)) else {
            return false;
        };
        let (sa, sb) = (self.section[a], self.section[b]);
        (sa == child && sb == parent) || (sa == parent && sb == child)
    }

    /// The pose the puppet reaches on its way from `from` to `to` when each turn goes as
    /// far as it can: the whole move goes as far as `Balls::reach` allows; then the
    /// joints between the two parts that pressed (on the way from one up to the section
    /// they both hang from, and down to the other) stop there, and the rest of the move
    /// goes on, again, until it is all made or [`ROUNDS`] parts have met. A finger
    /// meeting the palm stops that finger, not the other four; a hand meeting a thigh
    /// stops that arm and that leg, not the head.
    ///
    /// `None` when the whole move is allowed. The sections of each pair of parts that met
    /// go into `met`.
    pub fn hold(
        &self,
        joints: &Joints,
        from: &[Local],
        to: &[Local],
        met: &mut Vec<(usize, usize)>,
    ) -> Option<Vec<Local>> {
        let mut reach = self.reach(joints, from, to);
        if reach.share >= 1.0 {
            return None;
        }
        let mut at = from.to_vec();
        // (A pose shorter than the other is at rest beyond its end.)
        at.resize(from.len().max(to.len()), Local::default());
        let mut goal = to.to_vec();
        goal.resize(at.len(), Local::default());
        for round in 0..ROUNDS {
            if round > 0 {
                reach = self.reach(joints, &at, &goal);
                if reach.share >= 1.0 {
                    return Some(goal);
                }
            }
            if reach.share > 0.0 {
                at = between(&at, &goal, reach.share);
            }
            let Some((a, b)) = reach.pressed else {
                break;
            };
            met.push((a, b));
            let mut stopped = false;
            for s in joints.path(a, b) {
                if let (Some(g), Some(&now)) = (goal.get_mut(s), at.get(s)) {
                    stopped |= *g != now;
                    *g = now;
                }
            }
            if !stopped {
                break;
            }
        }
        Some(at)
    }

    /// How far (0..1) along the move from `from` to `to` the puppet can go before two
    /// parts press more than the squash (see the module docs): 1 when the whole move is
    /// allowed, 0 when no part can move more than a hundredth of its smallest ball; and
    /// the sections of the pair that pressed first.
    fn reach(&self, joints: &Joints, from: &[Local], to: &[Local]) -> Reach {
        let all = Reach {
            share: 1.0,
            pressed: None,
        };
        let start = joints.world(from);
        let end = joints.world(to);
        let moving: Vec<bool> = start
            .iter()
            .zip(&end)
            .map(|(a, b)| !a.abs_diff_eq(*b, 1e-12))
            .collect();
        if self.is_empty() || !moving.iter().any(|&m| m) {
            return all;
        }
        let mut still = Still::new(self, &start, &moving);
        still.relative(&start, &end);
        // Samples close enough that no ball jumps more than half its radius: two balls
        // then move less than half their radii together between samples, and neither
        // passes through the other. Balls under [`SMALLEST`] of the grid's cell count as
        // that big (a crumb of a ball, at a crease, would ask for thousands of samples;
        // the contacts keep such crumbs apart).
        let floor = SMALLEST * self.cell;
        let (mut far, mut smallest, mut jumps) = (0.0f64, f64::INFINITY, 0.0f64);
        for &b in &still.movers {
            let (s, c) = (self.section[b], self.center[b]);
            let moved = start[s]
                .transform_point3(c)
                .distance(end[s].transform_point3(c));
            let r = self.radius[b].max(floor);
            far = far.max(moved);
            smallest = smallest.min(r);
            jumps = jumps.max(moved / (0.5 * r));
        }
        let samples = (jumps.ceil() as usize).clamp(1, MAX_SAMPLES);
        // The still balls each moving ball may meet anywhere along the move, once: each
        // sample then tests only those pairs.
        let poses: Vec<Vec<DAffine3>> = (0..=samples)
            .map(|k| joints.world(&between(from, to, k as f64 / samples as f64)))
            .collect();
        still.sweep(&poses);
        let pressing =
            |s: f64, stop: f64| still.pressing(&joints.world(&between(from, to, s)), stop);
        let already = pressing(0.0, f64::INFINITY).max(self.squash);
        let allowed = |p: f64| p <= already + 1e-9;
        let mut good = 0.0;
        for k in 1..=samples {
            let s = k as f64 / samples as f64;
            if allowed(pressing(s, already + 1e-9)) {
                good = s;
                continue;
            }
            let mut bad = s;
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (good + bad);
                if allowed(pressing(mid, already + 1e-9)) {
                    good = mid;
                } else {
                    bad = mid;
                }
            }
            // The pair that presses past the bisection's last allowed pose.
            let pressed = still
                .deepest(&joints.world(&between(from, to, bad)), already + 1e-9)
                .1
                .map(|(a, b)| (self.section[a], self.section[b]));
            // A creep of less than a hundredth of a ball is no move: a limb held against
            // the body settles.
            let share = if good * far < 0.01 * smallest {
                0.0
            } else {
                good
            };
            return Reach { share, pressed };
        }
        all
    }
}

/// How far a move goes (`Balls::reach`) and, when it stops short, the two sections
/// whose balls pressed.
#[derive(Clone, Copy, Debug)]
struct Reach {
    share: f64,
    pressed: Option<(usize, usize)>,
}

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
}

/// The balls that do not move during a move, in a grid, and those that do.
struct Still<'a> {
    balls: &'a Balls,
    /// Per pair of sections (`a * n + b`): their relative transform changes in the move.
    apart: Vec<bool>,
    sections: usize,
    /// Balls of moving sections.
    movers: Vec<usize>,
    /// The others, posed: small ones by grid cell, big ones (over a cell) apart.
    posed: Vec<DVec3>,
    grid: Cells<[i64; 3], Vec<u32>>,
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
    fn new(balls: &'a Balls, world: &[DAffine3], moving: &[bool]) -> Still<'a> {
        let sections = moving.len().max(world.len());
        let mut out = Still {
            balls,
            apart: vec![true; sections * sections],
            sections,
            movers: Vec::new(),
            posed: vec![DVec3::ZERO; balls.len()],
            grid: Cells::default(),
            extent: ([i64::MAX; 3], [i64::MIN; 3]),
            big: Vec::new(),
            gridded: vec![false; balls.len()],
            swept: None,
            start: Vec::new(),
        };
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
                out.grid.entry(k).or_default().push(b as u32);
                out.gridded[b] = true;
            }
        }
        out
    }

    /// Marks the pairs of moving sections that move together (their relative transform
    /// the same at both ends): their balls cannot come to press.
    fn relative(&mut self, start: &[DAffine3], end: &[DAffine3]) {
        let n = self.sections.min(start.len()).min(end.len());
        for a in 0..n {
            for b in 0..n {
                let before = start[a].inverse() * start[b];
                let after = end[a].inverse() * end[b];
                self.apart[a * self.sections + b] = !before.abs_diff_eq(after, 1e-9);
            }
        }
    }

    /// Finds, for the move through the poses `poses` (world transforms at its samples,
    /// first to last), the small still balls each moving ball may press: those in the
    /// cells within its radius and a cell of the box its centre sweeps, grown by its
    /// longest step between samples, and no farther than it moves (a pair presses only
    /// once the moving ball has moved by their gap at the start, plus the squash). Pairs
    /// that never press are left out.
    fn sweep(&mut self, poses: &[Vec<DAffine3>]) {
        let balls = self.balls;
        let cell = balls.cell;
        let mut pairs = Vec::new();
        let mut wide = vec![false; self.movers.len()];
        let (lo, hi) = self.extent;
        self.start.clear();
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
            let grow = balls.radius[a] + cell + step;
            let (a_lo, a_hi) = (self.key(min - grow), self.key(max + grow));
            let span = (0..3).map(|d| (a_hi[d].min(hi[d]) - a_lo[d].max(lo[d]) + 1).max(0));
            let count: i64 = span.product();
            if !(min.is_finite() && max.is_finite()) || count > 4096 {
                wide[i] = true;
                continue;
            }
            for x in a_lo[0].max(lo[0])..=a_hi[0].min(hi[0]) {
                for y in a_lo[1].max(lo[1])..=a_hi[1].min(hi[1]) {
                    for z in a_lo[2].max(lo[2])..=a_hi[2].min(hi[2]) {
                        if let Some(list) = self.grid.get(&[x, y, z]) {
                            for &b in list {
                                let gap = self.gap(a, b as usize, first);
                                if gap < reach && !balls.never(a, b as usize) {
                                    pairs.push(Pair {
                                        mover: i as u32,
                                        ball: b,
                                        gap,
                                    });
                                }
                            }
                        }
                    }
                }
            }
        }
        self.swept = Some(Swept { pairs, wide });
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
    fn pressing(&self, world: &[DAffine3], stop: f64) -> f64 {
        self.deepest(world, stop).0
    }

    /// [`Still::pressing`], with the balls of the pair found (`None` when none presses).
    fn deepest(&self, world: &[DAffine3], stop: f64) -> (f64, Option<(usize, usize)>) {
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
        let mut grid: Cells<[i64; 3], Vec<u32>> = Cells::default();
        let mut big = Vec::new();
        for (i, &a) in self.movers.iter().enumerate() {
            if !near[i] {
                continue;
            }
            if balls.radius[a] > balls.cell || !movers[i].is_finite() {
                big.push(i);
            } else {
                grid.entry(key(movers[i])).or_default().push(i as u32);
            }
        }
        for (i, &a) in self.movers.iter().enumerate() {
            if !near[i] || balls.radius[a] > balls.cell || !movers[i].is_finite() {
                continue;
            }
            let k = key(movers[i]);
            for x in k[0] - 1..=k[0] + 1 {
                for y in k[1] - 1..=k[1] + 1 {
                    for z in k[2] - 1..=k[2] + 1 {
                        for &j in grid.get(&[x, y, z]).map_or(&[][..], |v| v.as_slice()) {
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
        if let Some(Swept { pairs, wide }) = &self.swept {
            // How far each moving ball is from where it started: a pair presses only past
            // its gap.
            let moved: Vec<f64> = movers
                .iter()
                .zip(&self.start)
                .map(|(p, q)| p.distance(*q))
                .collect();
            for &Pair { mover, ball, gap } in pairs {
                let (i, b) = (mover as usize, ball as usize);
                if moved[i] <= gap {
                    continue;
                }
                if deeper(&mut deepest, self.movers[i], b, movers[i], self.posed[b]) {
                    return deepest;
                }
            }
            for (i, &a) in self.movers.iter().enumerate() {
                let pa = movers[i];
                for &b in &self.big {
                    if deeper(&mut deepest, a, b as usize, pa, self.posed[b as usize]) {
                        return deepest;
                    }
                }
                if wide[i] {
                    for b in (0..balls.len()).filter(|&b| self.gridded[b]) {
                        if deeper(&mut deepest, a, b, pa, self.posed[b]) {
                            return deepest;
                        }
                    }
                }
            }
            return deepest;
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
            for x in span(0) {
                for y in span(1) {
                    for z in span(2) {
                        if let Some(list) = self.grid.get(&[x, y, z]) {
                            for &b in list {
                                let b = b as usize;
                                if deeper(&mut deepest, a, b, pa, self.posed[b]) {
                                    return deepest;
                                }
                            }
                        }
                    }
                }
            }
        }
        deepest
    }
}

/// The pose a share `s` of the way from `from` to `to`: each section's rotation slerped,
/// its translation lerped.
pub fn between(from: &[Local], to: &[Local], s: f64) -> Vec<Local> {
    (0..from.len().max(to.len()))
        .map(|k| {
            let a = from.get(k).copied().unwrap_or_default();
            let b = to.get(k).copied().unwrap_or_default();
            Local {
                rotation: a.rotation.slerp(b.rotation, s).normalize(),
                translation: a.translation.lerp(b.translation, s),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix;

    fn unit(rng: &mut SplitMix) -> f64 {
        (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The swept pairs find what the grid finds at every pose along a move: the same
    /// deepest press, over random balls in four sections, two of them turning.
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
                pressed += usize::from(a > balls.squash);
            }
            let pairs = &swept.swept.as_ref().expect("swept").pairs;
            assert!(pairs.len() < grid.movers.len() * (n - grid.movers.len()));
        }
        assert!(pressed > 100, "{pressed} poses pressed");
    }
}
