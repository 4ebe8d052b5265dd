//! The pose limit: a section turned into another part of the body stops where their
//! medial balls meet, however fast it was dragged.
//!
//! Each section's balls ([`crate::geom::balls::thin`] of the skeleton's) move rigidly with
//! its world transform. Two balls of different sections *press* by how far they overlap
//! in a pose, over the smaller radius; pairs at one joint that were neighbours at rest
//! ([`crate::geom::balls::neighbours`]: the two sides of a joint) never press, nor does a
//! ball of a joint's flesh with one of the section across that joint that touched it at
//! rest (within [`TOUCHING`]: a chest's big ball reaching into the armpit), nor two balls
//! of a joint's two sides both in its neck ([`NECK`]: a thick neck's crease closing as
//! the head turns); parts that merely rest near each other (an arm hanging by the body)
//! do, and two other balls that overlapped at rest (a mesh's own overlap) press only by
//! how much deeper they go. A pose is
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
//! presses may move anywhere that presses no more (a puppet takes one that presses when
//! collision comes on back to where its parts meet first, `Puppet::hold_back`, and finds
//! them with [`Balls::pressing_sections`]).
//!
//! The samples share their broad phase (`near`, [`Near`]): per pair of sections whose
//! bounding spheres come near, the pairs of their balls within a width of each other,
//! listed in one section's frame and kept from move to move (a Verlet list) while the
//! other's balls have not moved farther than that in it. A ball's press depends only on
//! its two sections' relative transform, so a hand swung from the shoulder keeps its
//! fingers' pairs; only the pairs of sections that moved apart are listed again. A
//! sample then tests only the listed pairs of sections whose relative transform the move
//! changes, and of those only pairs whose gap is under how far they moved.

use super::{Joints, Local};
use crate::geom::balls;
use glam::{DAffine3, DVec3};
pub use near::Near;

mod near;

/// How near at rest, as a share of the smaller ball's radius, a ball of a joint's flesh
/// and one of the section across that joint lie for them never to press.
const TOUCHING: f64 = 0.25;

/// How far from a joint's pivot its neck reaches, in the distance from the pivot to the
/// nearest surface vertex: balls of its two sides both within it never press.
const NECK: f64 = 2.0;

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
    /// Per section, the neck of the joint it hangs from; `None` for the root, or without a
    /// surface.
    necks: Vec<Option<Neck>>,
    /// Per pair of sections (`a * sections + b`), whether two of their balls may be a pair
    /// that never presses ([`Balls::never`]): the two sides of a joint, or sections a
    /// joint's flesh lies in; every other pair of sections presses wherever it meets.
    /// Empty: any pair may.
    kin: Vec<bool>,
}

/// Where a joint's two sides meet: balls of both within it never press.
#[derive(Clone, Copy, Debug)]
struct Neck {
    /// The point the section below the joint turns about (its cut's pivot, or a shared
    /// one).
    pivot: DVec3,
    /// How far from the pivot the neck reaches: [`NECK`] times the distance from the
    /// pivot to the nearest surface vertex.
    reach: f64,
    /// The section across the joint.
    parent: usize,
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
            necks: Vec::new(),
            kin: Vec::new(),
        };
        out.necks = self
            .sections
            .iter()
            .map(|section| {
                let surface = body
                    .rest
                    .iter()
                    .map(|p| p.distance(section.pivot))
                    .fold(f64::INFINITY, f64::min);
                Some(Neck {
                    pivot: section.pivot,
                    reach: NECK * surface,
                    parent: section.parent?,
                })
                .filter(|_| surface.is_finite())
            })
            .collect();
        out.cell = balls::cell(&out.radius);
        out.kin = out.kin(self.sections.len());
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
        let mut near = Near::default();
        near.cover(self, world, world);
        // Moving sections each in their own group, the still ones in one.
        let group: Vec<u32> = (0..self.sections())
            .map(|s| {
                if moving.get(s) == Some(&true) {
                    s as u32 + 1
                } else {
                    0
                }
            })
            .collect();
        near.deepest(self, &group, world, f64::INFINITY).0
    }

    /// The pairs of sections (each once, the lower first) with balls that press each
    /// other in the pose whose world transforms are `world` (see [`Balls::press_near`]).
    pub fn pressing_sections(&self, world: &[DAffine3]) -> Vec<(usize, usize)> {
        let mut near = Near::default();
        near.cover(self, world, world);
        let mut out = near.pressing(self, world);
        out.sort_unstable();
        out
    }

    /// How many sections the balls lie in (one past the highest).
    fn sections(&self) -> usize {
        self.section.iter().copied().max().map_or(0, |s| s + 1)
    }

    /// The deepest press of pair `a`, `b` at `pa`, `pb` (0 when they do not press or
    /// were neighbours at rest): what the listed pairs are checked against.
    #[cfg(test)]
    fn press(&self, a: usize, b: usize, pa: DVec3, pb: DVec3) -> f64 {
        if self.never(a, b) {
            return 0.0;
        }
        self.press_near(a, b, pa, pb)
    }

    /// How deep pair `a`, `b` presses at `pa`, `pb`, the pair known to be one that may
    /// press (not [`Balls::never`]; a listed pair, [`Near`]).
    fn press_near(&self, a: usize, b: usize, pa: DVec3, pb: DVec3) -> f64 {
        let (ra, rb) = (self.radius[a], self.radius[b]);
        let small = ra.min(rb);
        let depth = ra + rb - pa.distance(pb);
        if depth <= self.squash * small {
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

    /// [`Balls::kin`] worked out for `sections` sections (empty when the joints' flesh is
    /// unknown: then any pair near at rest never presses).
    fn kin(&self, sections: usize) -> Vec<bool> {
        if self.joint.len() != self.len() || self.section.iter().any(|&s| s >= sections) {
            return Vec::new();
        }
        let mut kin = vec![false; sections * sections];
        let mut mark = |a: usize, b: usize| {
            kin[a * sections + b] = true;
            kin[b * sections + a] = true;
        };
        for (child, neck) in self.necks.iter().enumerate() {
            if let Some(n) = neck.filter(|n| n.parent < sections && child < sections) {
                mark(child, n.parent);
            }
        }
        for &(child, parent) in self.sides.iter().flatten() {
            if child < sections && parent < sections {
                mark(child, parent);
            }
        }
        // The sections each joint's flesh lies in.
        let mut flesh: Vec<Vec<usize>> = vec![Vec::new(); self.sides.len() + 1];
        for (b, &j) in self.joint.iter().enumerate() {
            if let Some(list) = flesh.get_mut(usize::from(j)).filter(|_| j != 0) {
                if !list.contains(&self.section[b]) {
                    list.push(self.section[b]);
                }
            }
        }
        for list in &flesh {
            for &a in list {
                for &b in list {
                    mark(a, b);
                }
            }
        }
        kin
    }

    /// Whether pair `a`, `b` never presses, whatever the pose: one section; two balls of a
    /// joint's two sides both in its neck; the two sides of a joint that were neighbours at
    /// rest (the surfaces within a few of the smaller radii); or a ball of a joint's flesh
    /// and one of the section across that joint that touched it at rest, within
    /// [`TOUCHING`] (a chest's big ball reaching into the armpit does not hold the arm up).
    fn never(&self, a: usize, b: usize) -> bool {
        let (sa, sb) = (self.section[a], self.section[b]);
        if sa == sb {
            return true;
        }
        let sections = self.necks.len();
        if !self.kin.is_empty() && !self.kin[sa * sections + sb] {
            return false;
        }
        let (ra, rb) = (self.radius[a], self.radius[b]);
        let small = ra.min(rb);
        let at_rest = self.center[a].distance(self.center[b]);
        // Balls of the two sides of one joint both near its pivot hold the flesh the joint
        // bends (a thick neck's crease), wherever the joint's band ends.
        if self.in_neck(a, b) {
            return true;
        }
        let joint = self.joint.get(a).copied();
        if joint.is_none() || (joint != Some(0) && joint == self.joint.get(b).copied()) {
            return balls::neighbours(at_rest - small, ra.max(rb), small);
        }
        ra + rb - at_rest > -TOUCHING * small && (self.across(a, b) || self.across(b, a))
    }

    /// Whether balls `a` and `b` lie on the two sides of one joint, both within its neck
    /// of its pivot.
    fn in_neck(&self, a: usize, b: usize) -> bool {
        let (sa, sb) = (self.section[a], self.section[b]);
        let neck = |child: usize, parent: usize| match self.necks.get(child) {
            Some(&Some(Neck {
                pivot,
                reach,
                parent: p,
            })) => {
                p == parent
                    && self.center[a].distance(pivot) < reach
                    && self.center[b].distance(pivot) < reach
            }
            _ => false,
        };
        neck(sa, sb) || neck(sb, sa)
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
        near: &mut Near,
    ) -> Option<Vec<Local>> {
        let mut reach = self.reach(joints, from, to, near);
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
                reach = self.reach(joints, &at, &goal, near);
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
    /// the sections of the pair that pressed first. The pairs tested are `near`'s, listed
    /// again where the move takes a ball past its margin.
    fn reach(&self, joints: &Joints, from: &[Local], to: &[Local], near: &mut Near) -> Reach {
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
        let group = near::groups(self.sections(), &start, &end);
        // Samples close enough that no ball jumps more than half its radius: two balls
        // then move less than half their radii together between samples, and neither
        // passes through the other. Balls under [`SMALLEST`] of the grid's cell count as
        // that big (a crumb of a ball, at a crease, would ask for thousands of samples;
        // the contacts keep such crumbs apart).
        let floor = SMALLEST * self.cell;
        let (mut far, mut smallest, mut jumps) = (0.0f64, f64::INFINITY, 0.0f64);
        for b in (0..self.len()).filter(|&b| moving.get(self.section[b]) == Some(&true)) {
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
        let mut along = Along::new(joints, from, to);
        let (mut last, mut now, mut probe) = (start, Vec::new(), Vec::new());
        // Listed (when need be) with the first step's speeds.
        along.world_into(1.0 / samples as f64, &mut now);
        near.cover(self, &last, &now);
        let already = near
            .deepest(self, &group, &last, f64::INFINITY)
            .0
            .max(self.squash);
        let allowed = |p: f64| p <= already + 1e-9;
        let mut good = 0.0;
        for k in 1..=samples {
            let s = k as f64 / samples as f64;
            if k > 1 {
                along.world_into(s, &mut now);
            }
            near.cover(self, &last, &now);
            if allowed(near.deepest(self, &group, &now, already + 1e-9).0) {
                good = s;
                std::mem::swap(&mut last, &mut now);
                continue;
            }
            let mut bad = s;
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (good + bad);
                along.world_into(mid, &mut probe);
                if allowed(near.deepest(self, &group, &probe, already + 1e-9).0) {
                    good = mid;
                } else {
                    bad = mid;
                }
            }
            // The pair that presses deepest past the bisection's last allowed pose.
            along.world_into(bad, &mut probe);
            let pressed = near
                .deepest(self, &group, &probe, f64::INFINITY)
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

    /// Every ball's centre in the pose whose world transforms are `world`.
    #[cfg(test)]
    fn posed(&self, world: &[DAffine3]) -> Vec<DVec3> {
        (0..self.len())
            .map(|b| {
                world
                    .get(self.section[b])
                    .map_or(self.center[b], |w| w.transform_point3(self.center[b]))
            })
            .collect()
    }
}

/// How far a move goes (`Balls::reach`) and, when it stops short, the two sections
/// whose balls pressed.
#[derive(Clone, Copy, Debug)]
struct Reach {
    share: f64,
    pressed: Option<(usize, usize)>,
}

/// The pose a share `s` of the way from `from` to `to`: each section's rotation slerped,
/// its translation lerped.
pub fn between(from: &[Local], to: &[Local], s: f64) -> Vec<Local> {
    let mut out = Vec::new();
    between_into(from, to, s, &mut out);
    out
}

/// [`between`] into existing storage.
fn between_into(from: &[Local], to: &[Local], s: f64, out: &mut Vec<Local>) {
    out.clear();
    out.extend((0..from.len().max(to.len())).map(|k| {
        let a = from.get(k).copied().unwrap_or_default();
        let b = to.get(k).copied().unwrap_or_default();
        Local {
            rotation: a.rotation.slerp(b.rotation, s).normalize(),
            translation: a.translation.lerp(b.translation, s),
        }
    }));
}

/// The poses along a move that `Balls::reach` samples, each section's world transform
/// made in storage kept from sample to sample (a move takes up to [`MAX_SAMPLES`] and
/// its bisections, every step of a drag).
struct Along<'a> {
    joints: &'a Joints,
    from: &'a [Local],
    to: &'a [Local],
    local: Vec<Local>,
    turns: Vec<DVec3>,
    slides: Vec<crate::joints::Slide>,
}

impl<'a> Along<'a> {
    fn new(joints: &'a Joints, from: &'a [Local], to: &'a [Local]) -> Self {
        Along {
            joints,
            from,
            to,
            local: Vec::new(),
            turns: Vec::new(),
            slides: Vec::new(),
        }
    }

    /// The world transforms `s` (0..1) along the move into `world`
    /// ([`Joints::world`] of [`between`]).
    fn world_into(&mut self, s: f64, world: &mut Vec<DAffine3>) {
        between_into(self.from, self.to, s, &mut self.local);
        self.joints
            .world_slid_into(&self.local, world, (&mut self.turns, &mut self.slides));
    }
}
