//! Geometry kernel shared by the skeleton: exact predicates, spatial orders, ray casting and
//! inside/outside classification (exact on closed surfaces, the generalized winding number on
//! open ones). Everything here is `f64` and deterministic.
//!
//! * `predicates`, `exact`: orientation and in-sphere tests, exact arithmetic;
//! * `hilbert`: Hilbert keys and the randomized insertion order;
//! * `bvh`: a bounding volume hierarchy over triangles for ray casts;
//! * `inside`, `winding`: inside or outside, exact or by winding number;
//! * `intersect`: faces crossing other faces;
//! * `balls`, `cells`: medial balls as colliders, and the grid their maps hash.

pub mod balls;
pub mod bvh;
pub mod cells;
pub mod exact;
pub mod hilbert;
pub mod inside;
pub mod intersect;
pub mod predicates;
pub mod winding;

/// The smaller of two values neither of which is NaN: one comparison (`f64::min` and
/// `f32::min` add NaN handling, measurably slower in the hot loops of this module).
#[inline(always)]
pub fn min2<T: PartialOrd>(a: T, b: T) -> T {
    if a < b {
        a
    } else {
        b
    }
}

/// The larger of two values neither of which is NaN (see [`min2`]).
#[inline(always)]
pub fn max2<T: PartialOrd>(a: T, b: T) -> T {
    if a > b {
        a
    } else {
        b
    }
}
