//! Composing a pose down the section tree: `W(s) = W(parent) · T(pivot + t) · R · T(−pivot)`.

use super::band::LEVELS;
use super::{Joints, Local, Section};
use crate::sim::Pose;
use glam::{Affine3A, DAffine3, DQuat};

impl Joints {
    /// World transform of every section for the given local poses (one per section; missing
    /// entries are at rest), composed from the root down (see module docs).
    pub fn world(&self, local: &[Local]) -> Vec<DAffine3> {
        let mut world = Vec::new();
        self.world_into(local, &mut world);
        world
    }

    /// [`Joints::world`] into existing storage.
    pub fn world_into(&self, local: &[Local], world: &mut Vec<DAffine3>) {
        world.clear();
        world.resize(self.sections.len(), DAffine3::IDENTITY);
        for &s in &self.order {
            let l = local.get(s).copied().unwrap_or_default();
            let pivot = self.sections[s].pivot;
            let own = DAffine3::from_translation(pivot + l.translation)
                * DAffine3::from_quat(l.rotation)
                * DAffine3::from_translation(-pivot);
            world[s] = match self.sections[s].parent {
                Some(p) => world[p] * own,
                None => own,
            };
        }
    }

    /// The simulation's pose (single precision) for the given local poses.
    pub fn pose(&self, local: &[Local]) -> Pose {
        let mut scratch = PoseScratch::default();
        self.pose_into(local, &mut scratch);
        scratch.pose
    }

    /// [`Joints::pose`] reusing `scratch` (nothing allocated once it has grown): every
    /// section's transform, then every joint band's levels (see [`super::band`]).
    pub fn pose_into<'a>(&self, local: &[Local], scratch: &'a mut PoseScratch) -> &'a Pose {
        self.world_into(local, &mut scratch.world);
        let transforms = &mut scratch.pose.transforms;
        transforms.clear();
        transforms.extend(scratch.world.iter().map(to_f32));
        for band in self.bands.iter().flatten() {
            let l = local.get(band.child).copied().unwrap_or_default();
            let pivot = self.sections[band.child].pivot;
            let parent = scratch.world[band.parent];
            for level in 1..LEVELS {
                let w = level as f64 / LEVELS as f64;
                let own = DAffine3::from_translation(pivot + l.translation * w)
                    * DAffine3::from_quat(DQuat::IDENTITY.slerp(l.rotation, w))
                    * DAffine3::from_translation(-pivot);
                transforms.push(to_f32(&(parent * own)));
            }
        }
        &scratch.pose
    }
}

/// Storage for [`Joints::pose_into`].
#[derive(Clone, Debug)]
pub struct PoseScratch {
    world: Vec<DAffine3>,
    pose: Pose,
}

impl Default for PoseScratch {
    fn default() -> Self {
        PoseScratch {
            world: Vec::new(),
            pose: Pose::rest(1),
        }
    }
}

/// An f64 affine transform in f32.
pub fn to_f32(t: &DAffine3) -> Affine3A {
    Affine3A::from_cols_array(&t.to_cols_array().map(|v| v as f32))
}

/// Section indices ordered so every parent precedes its children.
pub(super) fn parents_first(sections: &[Section]) -> Vec<usize> {
    let mut children = vec![Vec::new(); sections.len()];
    let mut roots = Vec::new();
    for (i, s) in sections.iter().enumerate() {
        match s.parent {
            Some(p) => children[p].push(i),
            None => roots.push(i),
        }
    }
    let mut order = Vec::with_capacity(sections.len());
    let mut stack = roots;
    while let Some(s) = stack.pop() {
        order.push(s);
        stack.extend(children[s].iter().rev());
    }
    order
}
