//! Exact geometric predicates (Shewchuk's adaptive arithmetic via the `robust` crate),
//! with the sign conventions this crate uses everywhere:
//!
//! * [`orient3d`]`(a, b, c, d) > 0` ⇔ `d` lies on the side of plane `abc` that the normal
//!   `(b − a) × (c − a)` points to, i.e. `det[b−a, c−a, d−a] > 0`.
//! * [`insphere`]`(a, b, c, d, e) > 0` ⇔ `e` lies strictly inside the sphere through
//!   `a, b, c, d`, for a tetrahedron with `orient3d(a, b, c, d) > 0`.
//!
//! The returned values have the correct sign exactly; their magnitude is only approximate.

use glam::DVec3;
use robust::{Coord, Coord3D};

#[inline(always)]
fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

/// Exact orientation of `d` relative to the oriented plane `abc` (see module docs).
#[inline]
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    // Shewchuk's orient3d is positive when d is *below* abc (abc counter-clockwise from
    // above), the opposite of our convention.
    -robust::orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// Exact in-sphere test (see module docs).
#[inline]
pub fn insphere(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> f64 {
    // Shewchuk's insphere expects his positive orientation, ours is its negative.
    -robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e))
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
    fn circumcenter_is_equidistant() {
        let (a, b, c, d) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
        let cc = circumcenter(a, b, c, d).unwrap();
        assert!((cc - DVec3::splat(0.5)).length() < 1e-15);
        assert!(circumcenter(a, b, c, DVec3::new(1.0, 1.0, 0.0)).is_none());
    }
}
