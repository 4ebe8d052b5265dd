//! Which balls a slot ignores: those of sections it does not meet, and those of the flesh
//! about its joint that were its neighbours at rest ([`balls::neighbours`]). A group of
//! points reads what its slots share once, and where they lie at rest ([`Rest`]), so that
//! building its list of balls reads a slot only for a ball at the edge of their joint's
//! flesh.

use super::{Colliders, Stage, GROUP};
use crate::geom::balls;
use crate::sim::layout::Layout;
use glam::Vec3;
use std::ops::Range;

/// Where a group of slots lies at rest: a sphere about their rest positions and the
/// least and largest skeletal distance among them. A ball of their joint's flesh is
/// then neighbour of all of them, or of none, by its distance to the sphere (most of
/// them), without reading each slot.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Rest {
    centre: Vec3,
    spread: f32,
    own: (f32, f32),
}

/// Each tile's groups of [`GROUP`] slots in turn, as many per tile as the fullest tile
/// holds (a short last tile's missing groups empty): where each lies at rest, with its
/// slots' skeletal distances `slot_radius`.
pub(super) fn rest_of_groups(layout: &Layout, slot_radius: &[f32]) -> Vec<Rest> {
    (0..layout.tiles())
        .flat_map(|t| {
            let r = layout.tile_range(t);
            (r.start..r.start + layout.tile.max(1))
                .step_by(GROUP)
                .map(move |k0| k0..(k0 + GROUP).min(r.end))
        })
        .map(|slots| {
            let rest = |k: usize| layout.slots.rest.get(k);
            let n = slots.len().max(1) as f32;
            let centre = slots.clone().map(rest).sum::<Vec3>() / n;
            let spread = slots
                .clone()
                .map(|k| rest(k).distance(centre))
                .fold(0.0, f32::max);
            let own = slots
                .filter_map(|k| slot_radius.get(k).copied())
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), r| {
                    (lo.min(r), hi.max(r))
                });
            Rest {
                centre,
                spread,
                own,
            }
        })
        .collect()
}

impl Colliders {
    /// Whether slot `k` never yields to ball `b` nor is dented by it, wherever both are:
    /// their sections do not meet, or the ball is of the flesh about the slot's joint and
    /// was its neighbour at rest (at a joint the two sides touch at rest, and the band
    /// holds the fold).
    pub(super) fn ignores(&self, stage: &Stage, k: usize, b: usize) -> bool {
        if self.meets(self.slot_section[k], self.section[b]).is_none() {
            return true;
        }
        let joint = self.slot_joint.get(k).copied().unwrap_or(0);
        (self.everywhere || (joint != 0 && joint == self.joint[b]))
            && balls::neighbours(
                f64::from(stage.layout.slots.rest.get(k).distance(self.center[b])),
                f64::from(self.radius[b] + stage.margin),
                f64::from(self.slot_radius[k]),
            )
    }

    /// The joint section and the joint that all of `slots` share (`None` where they
    /// differ): what [`Colliders::ignored_by_all`] reads once for a group.
    pub(super) fn shared(&self, slots: Range<usize>) -> (Option<u16>, Option<u16>) {
        let same = |of: &[u16]| {
            let of = of.get(slots.clone()).unwrap_or(&[]);
            of.first().copied().filter(|&a| of.iter().all(|&x| x == a))
        };
        (same(&self.slot_section), same(&self.slot_joint))
    }

    /// Whether every slot of `slots` (the group `index`), which share the section and
    /// joint `shared` ([`Colliders::shared`]), ignores ball `b` ([`Colliders::ignores`]):
    /// read from what they share and where they lie at rest ([`Rest`]), and point by
    /// point only for a ball of their joint's flesh near the edge of neighbourhood.
    pub(super) fn ignored_by_all(
        &self,
        stage: &Stage,
        (slots, index): (&Range<usize>, usize),
        (section, joint): (Option<u16>, Option<u16>),
        b: usize,
    ) -> bool {
        if let Some(s) = section {
            if self.meets(s, self.section[b]).is_none() {
                return true;
            }
            let flesh = self.everywhere || joint.is_some_and(|j| j != 0 && j == self.joint[b]);
            if !flesh && joint.is_some() {
                return false;
            }
            if let (true, Some(g)) = (flesh, self.group_rest.get(index)) {
                // Neighbours ([`balls::neighbours`]) within `r + NEIGHBOURS · min(r, own)`:
                // all of them when even the farthest slot is, none when even the nearest
                // is not (a thousandth short of either, the slots are read).
                let d = self.center[b].distance(g.centre);
                let r = self.radius[b] + stage.margin;
                let within = |own: f32| r + balls::NEIGHBOURS as f32 * r.min(own);
                let tolerance = 1e-3 * (d + g.spread + within(g.own.1));
                if d + g.spread + tolerance < within(g.own.0) {
                    return true;
                }
                if d - g.spread - tolerance >= within(g.own.1) {
                    return false;
                }
            }
        }
        slots.clone().all(|k| self.ignores(stage, k, b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joints::{Cut, Local, PoseScratch};
    use crate::puppet::{Puppet, RigFile};
    use glam::{DQuat, DVec3};

    /// The group's shortcut ([`Colliders::ignored_by_all`]) says what reading each of its
    /// slots says, for every group and every ball, at several margins; and it does
    /// decide some balls of a joint's flesh by the group's rest sphere alone.
    #[test]
    fn a_group_ignores_a_ball_exactly_when_each_of_its_slots_does() {
        let mesh = crate::mesh::shapes::capsule(0.3, 1.0, 8, 48, 32);
        let spec = RigFile {
            cuts: vec![
                Cut::plane("arm", "root", DVec3::ZERO, DVec3::Y),
                Cut::plane("hand", "arm", DVec3::new(0.0, 0.8, 0.0), DVec3::Y),
            ],
            ..RigFile::default()
        };
        let mut puppet = Puppet::build(mesh, spec, crate::progress::silent()).unwrap();
        let mut params = *puppet.sim.params();
        params.world.collision = true;
        puppet.sim.set_params(params);
        let mut local = vec![Local::default(); puppet.joints.sections().len()];
        local[1].rotation = DQuat::from_rotation_x(1.0);
        let mut scratch = PoseScratch::default();
        puppet
            .sim
            .step(puppet.joints.pose_into(&local, &mut scratch));
        let sim = &puppet.sim;
        let c = sim.contacts.as_ref().expect("collision on: contacts built");
        assert!(c.slot_joint.iter().any(|&j| j != 0), "a joint's flesh");
        let (mut flesh, mut decided) = (0, 0);
        for margin in [0.0, 0.01, 0.1] {
            let stage = Stage {
                layout: &sim.layout,
                transforms: &[],
                changed: &[],
                margin,
                keep: 0.0,
                flesh: 0.0,
                tile_motion: &[],
                floor: None,
            };
            for t in 0..sim.layout.tiles() {
                let r = sim.layout.tile_range(t);
                for k0 in (r.start..r.end).step_by(GROUP) {
                    let slots = k0..(k0 + GROUP).min(r.end);
                    let index = t * sim.layout.tile.div_ceil(GROUP) + (k0 - r.start) / GROUP;
                    let shared = c.shared(slots.clone());
                    for b in 0..c.center.len() {
                        let each = slots.clone().all(|k| c.ignores(&stage, k, b));
                        assert_eq!(
                            c.ignored_by_all(&stage, (&slots, index), shared, b),
                            each,
                            "group {index}, ball {b}, margin {margin}"
                        );
                        if shared.1.is_some_and(|j| j != 0 && j == c.joint[b])
                            && shared.0.is_some_and(|s| c.meets(s, c.section[b]).is_some())
                        {
                            flesh += 1;
                            let g = c.group_rest[index];
                            let d = c.center[b].distance(g.centre);
                            let r = c.radius[b] + margin;
                            let within = |own: f32| r + balls::NEIGHBOURS as f32 * r.min(own);
                            decided += usize::from(
                                d + g.spread < 0.99 * within(g.own.0)
                                    || d - g.spread > 1.01 * within(g.own.1),
                            );
                        }
                    }
                }
            }
        }
        assert!(
            flesh > 0 && decided > 0,
            "{decided} of {flesh} decided by the sphere"
        );
    }
}
