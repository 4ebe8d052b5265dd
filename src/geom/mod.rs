//! Geometry kernel shared by the skeleton: exact predicates, spatial orders, ray casting and
//! inside/outside classification. Everything here is `f64` and deterministic.

pub mod bvh;
pub mod exact;
pub mod hilbert;
pub mod inside;
pub mod predicates;
