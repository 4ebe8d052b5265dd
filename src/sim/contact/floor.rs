//! The floor as a contact: the half-space below `y = height`, which no point passes.
//!
//! Its response is the balls' ([`super`]): a point that would pass it goes onto it, its
//! motion into it is dropped, and its sliding motion keeps `keep` (`1 − friction` per
//! reference step). The kernel applies it to eight points at once ([`Floor::slide`] in
//! stage 3b, [`Floor::hold`] in stage 4b); the ball contacts (stage 4c) and a static
//! material's posed points call the same code for one point ([`Floor::lift`]), so a point
//! a ball pushes into the floor ends on it, as the kernel's do.

use super::super::lanes::{Lanes, Portable, V3};
use glam::Vec3;

/// The floor of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floor {
    /// Its `y`.
    pub height: f32,
    /// The share of its sliding motion a point touching the floor keeps in one step.
    pub keep: f32,
}

impl Floor {
    /// Stage 3b: a point predicted at `new` from `x` that would pass the floor goes onto
    /// it, keeping `keep` of its sliding motion from `x`. (Before the constraint, so
    /// friction never holds a point away from its bones.)
    #[inline(always)]
    pub(in crate::sim) fn slide<V: Lanes>(self, new: V3<V>, x: V3<V>) -> V3<V> {
        let (height, keep) = (V::splat(self.height), V::splat(self.keep));
        let below = new.y.lt(height);
        V3 {
            x: below.select(x.x + (new.x - x.x) * keep, new.x),
            y: below.select(height, new.y),
            z: below.select(x.z + (new.z - x.z) * keep, new.z),
        }
    }

    /// Stage 4b: no point ends below the floor. (After the constraint, which it wins over:
    /// a section posed into the floor squashes against it.)
    #[inline(always)]
    pub(in crate::sim) fn hold<V: Lanes>(self, new: V3<V>) -> V3<V> {
        let height = V::splat(self.height);
        V3 {
            y: new.y.lt(height).select(height, new.y),
            ..new
        }
    }

    /// [`Floor::hold`] for one point: where it goes when the floor lifts it.
    pub fn lift(self, x: Vec3) -> Option<Vec3> {
        let one = Portable::splat;
        let held = self.hold(V3 {
            x: one(x.x),
            y: one(x.y),
            z: one(x.z),
        });
        let y = held.y.to_array()[0];
        (y != x.y).then_some(Vec3::new(x.x, y, x.z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_below_the_floor_is_lifted_onto_it_and_keeps_part_of_its_slide() {
        let floor = Floor {
            height: 1.0,
            keep: 0.25,
        };
        assert_eq!(
            floor.lift(Vec3::new(2.0, 0.5, 3.0)),
            Some(Vec3::new(2.0, 1.0, 3.0))
        );
        assert_eq!(floor.lift(Vec3::new(2.0, 1.5, 3.0)), None);
        let v = |x: f32, y: f32, z: f32| V3 {
            x: Portable::splat(x),
            y: Portable::splat(y),
            z: Portable::splat(z),
        };
        let s = floor.slide(v(4.0, 0.0, 1.0), v(0.0, 2.0, 1.0));
        let first = |l: Portable| l.to_array()[0];
        assert_eq!((first(s.x), first(s.y), first(s.z)), (1.0, 1.0, 1.0));
        // Above the floor it does nothing.
        let s = floor.slide(v(4.0, 3.0, 1.0), v(0.0, 2.0, 1.0));
        assert_eq!((first(s.x), first(s.y), first(s.z)), (4.0, 3.0, 1.0));
    }
}
