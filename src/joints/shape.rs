//! Cut shapes (paper §5): a cut is a plane, a sphere or a box. Everything a cut does with its
//! shape goes through the signed distance of a skeletal point from its surface (positive on
//! the side the new section takes) and the surface's normal near a point; the rest of the
//! joints do not know which shape it is.
//!
//! * **plane** through the cut's point with its normal: the new section is the side the
//!   normal points to (a limb);
//! * **sphere** about the cut's point: the new section is inside (a tail tip, an ear, a
//!   nose);
//! * **box** centred on the cut's point, `size` its full extents along its axes: the new
//!   section is inside. Its third axis is the cut's normal, its first the world's x made
//!   perpendicular to it (the world's y when the normal is along x), so a box with normal
//!   `+z` is axis-aligned.
//! * **skin**: the vertices the file's skin gives most to the joint the cut is named after,
//!   or to a joint below it ([`crate::mesh::Skin`]); its point and normal (the joint's rest
//!   place and its bone's direction) act as a plane's for the band and the pivot.

use super::Cut;
use glam::{DMat3, DVec3};

/// The shape of a cut (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Shape {
    /// A plane through the point with the normal; the new section is on its positive side.
    #[default]
    Plane,
    /// A ball of this radius about the point; the new section is inside.
    Sphere {
        /// Radius (mesh units, > 0).
        radius: f64,
    },
    /// A box about the point, with these full extents along its axes; the new section is
    /// inside.
    Box {
        /// Full extents (mesh units, each > 0).
        size: DVec3,
    },
    /// The skin's joint of the cut's name and the joints below it (see the module docs).
    Skin,
}

impl Shape {
    /// The name a rig file and a panel use.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Plane => "plane",
            Shape::Sphere { .. } => "sphere",
            Shape::Box { .. } => "box",
            Shape::Skin => "skin",
        }
    }

    /// Is every size finite and positive?
    pub fn is_valid(&self) -> bool {
        match *self {
            Shape::Plane | Shape::Skin => true,
            Shape::Sphere { radius } => radius.is_finite() && radius > 0.0,
            Shape::Box { size } => size.is_finite() && size.min_element() > 0.0,
        }
    }
}

impl Cut {
    /// The axes of the cut's frame (columns; the third is its unit normal): a box's axes,
    /// see the module docs.
    pub fn axes(&self) -> DMat3 {
        Cut::box_axes(self.normal.normalize_or(DVec3::Z))
    }

    /// The box's axes (columns) for a unit `normal`: see the module docs.
    fn box_axes(normal: DVec3) -> DMat3 {
        let pick = if normal.x.abs() > 0.9 {
            DVec3::Y
        } else {
            DVec3::X
        };
        let x = (pick - normal * pick.dot(normal)).normalize();
        DMat3::from_cols(x, normal.cross(x), normal)
    }

    /// Signed distance of `p` from the cut's surface, positive on the side the new section
    /// takes. `normal` is the cut's unit normal.
    pub(super) fn signed(&self, p: DVec3, normal: DVec3) -> f64 {
        let v = p - self.point;
        match self.shape {
            Shape::Plane | Shape::Skin => v.dot(normal),
            Shape::Sphere { radius } => radius - v.length(),
            Shape::Box { size } => {
                let local = Cut::box_axes(normal).transpose() * v;
                let q = local.abs() - size * 0.5;
                let outside = q.max(DVec3::ZERO).length();
                -(outside + q.max_element().min(0.0))
            }
        }
    }

    /// Unit normal of the cut's surface at the point of it nearest `p`, pointing into the
    /// new section (the plane's normal; for a sphere or a box, inwards); zero when the
    /// cut's normal is.
    pub fn normal_near(&self, p: DVec3) -> DVec3 {
        let normal = self.normal.normalize_or_zero();
        let v = p - self.point;
        match self.shape {
            Shape::Plane | Shape::Skin => normal,
            Shape::Sphere { .. } => (-v).normalize_or(normal),
            Shape::Box { size } => {
                let axes = Cut::box_axes(normal);
                let local = axes.transpose() * v;
                // The face whose plane is nearest, by how far `p` is past it (or short of it).
                let q = local.abs() - size * 0.5;
                let k = if q.x >= q.y && q.x >= q.z {
                    0
                } else if q.y >= q.z {
                    1
                } else {
                    2
                };
                -axes.col(k) * local[k].signum()
            }
        }
    }
}
