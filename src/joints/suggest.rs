//! Joints suggested from the skeleton (see [`suggest`]).

use super::Cut;
use crate::mesh::Mesh;
use crate::skeleton::Skeleton;

/// Cuts where the protrusions of `mesh` narrow, organised parent-first as a section tree
/// under the root section `root`.
pub fn suggest(_mesh: &Mesh, _skeleton: &Skeleton, _root: &str) -> Vec<Cut> {
    Vec::new()
}
