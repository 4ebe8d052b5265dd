//! Exact geometric predicates with the sign conventions this crate uses everywhere. Each
//! evaluates a semi-static floating-point filter first; undecided cases go to Shewchuk's
//! adaptive arithmetic (`robust` crate) for orientations and to our expansion evaluator
//! ([`super::exact`]) for in-sphere tests.
//!
//!
//! * [`orient3d`]`(a, b, c, d) > 0` ⇔ `d` lies on the side of plane `abc` that the normal
//!   `(b − a) × (c − a)` points to, i.e. `det[b−a, c−a, d−a] > 0`.
//! * [`insphere`]`(a, b, c, d, e) > 0` ⇔ `e` lies strictly inside the sphere through
//!   `a, b, c, d`, for a tetrahedron with `orient3d(a, b, c, d) > 0`.
//!
//! The returned values have the correct sign exactly; their magnitude is only approximate.

use super::max2;
use glam::DVec3;
use robust::{Coord, Coord3D};

/// The largest absolute coordinate of four vectors.
#[inline(always)]
fn max_abs(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    let m = |v: DVec3| max2(max2(v.x.abs(), v.y.abs()), v.z.abs());
    max2(max2(m(a), m(b)), max2(m(c), m(d)))
}

#[inline(always)]
fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

/// Exact orientation of `d` relative to the oriented plane `abc` (see module docs).
///
/// A semi-static filter answers most calls: the determinant is evaluated exactly as in
/// Shewchuk's code, and his error bound `(7 + 56ε)ε · permanent` is bounded above by
/// `45ε · M³`, `M` the largest coordinate difference (the permanent is at most `6M³`).
/// Only inconclusive cases pay for the adaptive exact evaluation.
#[inline]
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    let (ad, bd, cd) = (a - d, b - d, c - d);
    let det = ad.z * (bd.x * cd.y - cd.x * bd.y)
        + bd.z * (cd.x * ad.y - ad.x * cd.y)
        + cd.z * (ad.x * bd.y - bd.x * ad.y);
    let m = max_abs(ad, bd, cd, DVec3::ZERO);
    let bound = 45.0 * f64::EPSILON * 0.5 * m * m * m;
    if m > 1e-80 && (det > bound || -det > bound) {
        // Shewchuk's orient3d is positive when d is *below* abc (abc counter-clockwise
        // from above), the opposite of our convention.
        return -det;
    }
    -robust::orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// Exact in-sphere test (see module docs), with a semi-static filter as in [`orient3d`]:
/// Shewchuk's bound `(16 + 224ε)ε · permanent` with the permanent at most `72 M⁵`.
#[inline(always)]
pub fn insphere(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> f64 {
    let (ae, be, ce, de) = (a - e, b - e, c - e, d - e);
    let ab = ae.x * be.y - be.x * ae.y;
    let bc = be.x * ce.y - ce.x * be.y;
    let cd = ce.x * de.y - de.x * ce.y;
    let da = de.x * ae.y - ae.x * de.y;
    let ac = ae.x * ce.y - ce.x * ae.y;
    let bd = be.x * de.y - de.x * be.y;
    let abc = ae.z * bc - be.z * ac + ce.z * ab;
    let bcd = be.z * cd - ce.z * bd + de.z * bc;
    let cda = ce.z * da + de.z * ac + ae.z * cd;
    let dab = de.z * ab + ae.z * bd + be.z * da;
    let alift = ae.length_squared();
    let blift = be.length_squared();
    let clift = ce.length_squared();
    let dlift = de.length_squared();
    let det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
    let m = max_abs(ae, be, ce, de);
    let m2 = m * m;
    let bound = 1200.0 * f64::EPSILON * 0.5 * m2 * m2 * m;
    if m > 1e-50 && (det > bound || -det > bound) {
        // Shewchuk's insphere expects his positive orientation, ours is its negative.
        return -det;
    }
    -super::exact::insphere_sign(
        a.to_array(),
        b.to_array(),
        c.to_array(),
        d.to_array(),
        e.to_array(),
    )
}

/// Exact 2D orientation: positive when `a, b, c` turn counter-clockwise.
#[inline]
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    robust::orient2d(
        Coord { x: a[0], y: a[1] },
        Coord { x: b[0], y: b[1] },
        Coord { x: c[0], y: c[1] },
    )
}

/// True when three points are exactly collinear.
pub fn collinear(a: DVec3, b: DVec3, c: DVec3) -> bool {
    orient2d([a.x, a.y], [b.x, b.y], [c.x, c.y]) == 0.0
        && orient2d([a.y, a.z], [b.y, b.z], [c.y, c.z]) == 0.0
        && orient2d([a.z, a.x], [b.z, b.x], [c.z, c.x]) == 0.0
}

/// Circumcentre of a tetrahedron, or `None` when it is flat (or the result not finite).
#[inline]
pub fn circumcenter(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Option<DVec3> {
    let (u, v, w) = (b - a, c - a, d - a);
    let det = u.dot(v.cross(w));
    if det == 0.0 {
        return None;
    }
    let num = u.length_squared() * v.cross(w)
        + v.length_squared() * w.cross(u)
        + w.length_squared() * u.cross(v);
    let cc = a + num / (2.0 * det);
    cc.is_finite().then_some(cc)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_convention() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert!(orient3d(a, b, c, DVec3::Z) > 0.0);
        assert!(orient3d(a, b, c, -DVec3::Z) < 0.0);
        assert_eq!(orient3d(a, b, c, DVec3::new(3.0, 7.0, 0.0)), 0.0);
    }

    #[test]
    fn insphere_convention() {
        let (a, b, c, d) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
        assert!(orient3d(a, b, c, d) > 0.0);
        assert!(insphere(a, b, c, d, DVec3::splat(0.25)) > 0.0);
        assert!(insphere(a, b, c, d, DVec3::splat(5.0)) < 0.0);
        // (1,1,1) lies exactly on the sphere through the four corners.
        assert_eq!(insphere(a, b, c, d, DVec3::ONE), 0.0);
    }

    #[test]
    fn filters_agree_with_exact_predicates_near_degeneracy() {
        // Nearly coplanar / cospherical configurations straddle the filter bound.
        let mut rng = crate::random::SplitMix(3);
        let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        for i in 0..20_000 {
            let scale = 10f64.powi(i % 7 - 3);
            let (a, b, c) = (
                DVec3::new(u(), u(), 0.0) * scale,
                DVec3::new(u(), u(), 0.0) * scale,
                DVec3::new(u(), u(), 0.0) * scale,
            );
            let d = DVec3::new(u(), u(), u() * 1e-15) * scale;
            let exact = -robust::orient3d(c3(a), c3(b), c3(c), c3(d));
            assert_eq!(orient3d(a, b, c, d).signum(), exact.signum());
            // e on (or within rounding of) the unit sphere through four sphere points.
            let s = |v: DVec3| v.normalize() * scale;
            let (p, q, r, t) = (
                s(a + DVec3::Z),
                s(b - DVec3::Z),
                s(c + DVec3::X),
                s(d + DVec3::Y),
            );
            let e = s(DVec3::new(u(), u(), u()));
            let exact = -robust::insphere(c3(p), c3(q), c3(r), c3(t), c3(e));
            assert_eq!(insphere(p, q, r, t, e).signum(), exact.signum());
        }
    }

    #[test]
    fn circumcenter_is_equidistant() {
        let (a, b, c, d) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
        let cc = circumcenter(a, b, c, d).unwrap();
        assert!((cc - DVec3::splat(0.5)).length() < 1e-15);
        assert!(circumcenter(a, b, c, DVec3::new(1.0, 1.0, 0.0)).is_none());
    }
}
