//! The floor as a contact: the half-space below `height` along the puppet's up (one of the
//! six axis directions, [`Up`]), which no point passes.
//!
//! Its response is the balls' ([`super`]): a point that would pass it goes onto it, its
//! motion into it is dropped, and its sliding motion keeps `keep` (`1 − friction` per
//! reference step). The kernel applies it to eight points at once ([`Floor::slide`] in
//! stage 3b, [`Floor::hold`] in stage 4b); the ball contacts (stage 4c) and a static
//! material's posed points call the same code for one point ([`Floor::lift`]), so a point
//! a ball pushes into the floor ends on it, as the kernel's do.

use super::super::lanes::{Lanes, Portable, V3};
use glam::Vec3;

/// Up along an axis: `sign × position[axis]` is a point's height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Up {
    /// 0, 1 or 2: x, y or z.
    pub axis: usize,
    /// +1 or −1.
    pub sign: f32,
}

impl Default for Up {
    /// `+y`.
    fn default() -> Up {
        Up { axis: 1, sign: 1.0 }
    }
}

impl Up {
    /// The axis direction nearest `v` (`+y` when `v` is zero or not finite).
    pub fn nearest(v: Vec3) -> Up {
        if !v.is_finite() || v == Vec3::ZERO {
            return Up::default();
        }
        let a = v.abs();
        let axis = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        Up {
            axis,
            sign: if v[axis] < 0.0 { -1.0 } else { 1.0 },
        }
    }

    /// The unit vector.
    pub fn vector(self) -> Vec3 {
        let mut v = Vec3::ZERO;
        v[self.axis] = self.sign;
        v
    }

    /// A point's height.
    pub fn height(self, p: Vec3) -> f32 {
        self.sign * p[self.axis]
    }
}

/// The floor of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floor {
    /// Which way is up.
    pub up: Up,
    /// Its height along up.
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
        let keep = V::splat(self.keep);
        let (height, level) = self.along::<V>();
        let kept = |n: V, o: V| o + (n - o) * keep;
        match self.up.axis {
            0 => {
                let below = (new.x * level).lt(height);
                V3 {
                    x: below.select(height * level, new.x),
                    y: below.select(kept(new.y, x.y), new.y),
                    z: below.select(kept(new.z, x.z), new.z),
                }
            }
            2 => {
                let below = (new.z * level).lt(height);
                V3 {
                    x: below.select(kept(new.x, x.x), new.x),
                    y: below.select(kept(new.y, x.y), new.y),
                    z: below.select(height * level, new.z),
                }
            }
            _ => {
                let below = (new.y * level).lt(height);
                V3 {
                    x: below.select(kept(new.x, x.x), new.x),
                    y: below.select(height * level, new.y),
                    z: below.select(kept(new.z, x.z), new.z),
                }
            }
        }
    }

    /// Stage 4b: no point ends below the floor. (After the constraint, which it wins over:
    /// a section posed into the floor squashes against it.)
    #[inline(always)]
    pub(in crate::sim) fn hold<V: Lanes>(self, new: V3<V>) -> V3<V> {
        let (height, level) = self.along::<V>();
        let lift = |c: V| (c * level).lt(height).select(height * level, c);
        match self.up.axis {
            0 => V3 {
                x: lift(new.x),
                ..new
            },
            2 => V3 {
                z: lift(new.z),
                ..new
            },
            _ => V3 {
                y: lift(new.y),
                ..new
            },
        }
    }

    /// The height and the sign of up, in lanes (the sign is ±1, so `c × sign` is exact).
    #[inline(always)]
    fn along<V: Lanes>(self) -> (V, V) {
        (V::splat(self.height), V::splat(self.up.sign))
    }

    /// [`Floor::hold`] for one point: where it goes when the floor lifts it.
    pub fn lift(self, x: Vec3) -> Option<Vec3> {
        let one = Portable::splat;
        let held = self.hold(V3 {
            x: one(x.x),
            y: one(x.y),
            z: one(x.z),
        });
        let first = |l: Portable| l.to_array()[0];
        let out = Vec3::new(first(held.x), first(held.y), first(held.z));
        (out != x).then_some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_below_the_floor_is_lifted_onto_it_and_keeps_part_of_its_slide() {
        let floor = Floor {
            up: Up::default(),
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

    /// Up along −z: the floor holds points above it along −z, exactly at its height.
    #[test]
    fn a_floor_along_any_axis_direction_lifts_along_it() {
        let floor = Floor {
            up: Up::nearest(Vec3::new(0.1, 0.2, -3.0)),
            height: 1.0,
            keep: 0.25,
        };
        assert_eq!(
            floor.up,
            Up {
                axis: 2,
                sign: -1.0
            }
        );
        // Height along −z is −z: a point at z = 0 is below a floor at height 1.
        assert_eq!(
            floor.lift(Vec3::new(2.0, 0.5, 0.0)),
            Some(Vec3::new(2.0, 0.5, -1.0))
        );
        assert_eq!(floor.lift(Vec3::new(2.0, 0.5, -1.5)), None);
        let x = Up::nearest(Vec3::X);
        assert_eq!(
            (x.vector(), x.height(Vec3::new(3.0, 1.0, 1.0))),
            (Vec3::X, 3.0)
        );
        assert_eq!(Up::nearest(Vec3::ZERO), Up::default());
    }
}
