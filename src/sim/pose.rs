//! What goes into a step and what comes out: the pose (one rigid transform per joint
//! section) and the positions, read through the rig's vertex numbering.

use super::layout::Packed;
use glam::{Affine3A, Vec3};

/// A pose: one rigid transform per joint section (section 0 is the whole object until joints
/// cut it).
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// World transform of each section.
    pub transforms: Vec<Affine3A>,
}

impl Pose {
    /// Every section at rest.
    pub fn rest(sections: usize) -> Pose {
        Pose {
            transforms: vec![Affine3A::IDENTITY; sections.max(1)],
        }
    }
}

/// Mass-point positions, read through the rig's vertex numbering (the solver stores them in
/// its own order, see [`super::layout`]).
#[derive(Clone, Copy, Debug)]
pub struct Positions<'a> {
    pub(super) points: &'a Packed,
    pub(super) slot: &'a [u32],
}

impl Positions<'_> {
    /// Position of rig vertex `i`.
    ///
    /// # Panics
    /// If `i` is not a vertex of the rig.
    #[inline]
    pub fn get(&self, i: usize) -> Vec3 {
        self.points.get(self.slot[i] as usize)
    }

    /// Number of mass points.
    pub fn len(&self) -> usize {
        self.slot.len()
    }

    /// True for a rig without vertices.
    pub fn is_empty(&self) -> bool {
        self.slot.is_empty()
    }

    /// All positions in vertex order.
    pub fn to_vec(&self) -> Vec<Vec3> {
        (0..self.len()).map(|i| self.get(i)).collect()
    }
}

impl PartialEq for Positions<'_> {
    /// Same positions for every vertex (exact `f32` equality).
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && (0..self.len()).all(|i| self.get(i) == other.get(i))
    }
}
