//! Geometry kernel shared by the skeleton: exact predicates, spatial orders, ray casting and
//! inside/outside classification (exact on closed surfaces, the generalized winding number on
//! open ones). Everything here is `f64` and deterministic.
//!
//! * `predicates`, `exact`: orientation and in-sphere tests, exact arithmetic;
//! * `hilbert`: Hilbert keys and the randomized insertion order;
//! * `bvh`: a bounding volume hierarchy over triangles for ray casts;
//! * `inside`, `winding`: inside or outside, exact or by winding number;
//! * `intersect`: faces crossing other faces;
//! * `balls`, `cells`: medial balls as colliders, and the grid their maps hash;
//! * `occlusion`: how much of the sky the medial balls hide from each vertex (creases).

pub mod balls;
pub mod bvh;
pub mod cells;
pub mod exact;
pub mod hilbert;
pub mod inside;
pub mod intersect;
pub mod occlusion;
pub mod predicates;
pub mod winding;

use glam::DVec3;

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

/// The distance from `p` to the triangle `t`.
pub fn point_triangle(p: DVec3, t: [DVec3; 3]) -> f64 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (p - (a + ab * v)).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (p - (a + ac * w)).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + (c - b) * w)).length();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_triangle_distance_matches_the_cases() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        assert!((point_triangle(DVec3::new(0.2, 0.2, 1.0), t) - 1.0).abs() < 1e-12);
        assert!((point_triangle(DVec3::new(-1.0, -1.0, 0.0), t) - 2f64.sqrt()).abs() < 1e-12);
        assert!((point_triangle(DVec3::new(0.5, -1.0, 0.0), t) - 1.0).abs() < 1e-12);
        assert!((point_triangle(DVec3::new(1.0, 1.0, 0.0), t) - 0.5f64.sqrt()).abs() < 1e-12);
    }
}
