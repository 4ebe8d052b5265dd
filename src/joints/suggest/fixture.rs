//! Characters the stages' unit tests run on: a mesh of the repository with its skeleton,
//! built once per test run.

use crate::mesh::Mesh;
use crate::skeleton::Skeleton;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// The mesh at `path` (from the repository's root) and its skeleton, as `Puppet` builds
/// them.
///
/// # Panics
/// When the file does not load or build: the fixtures are the repository's own meshes.
pub(crate) fn character(path: &str) -> &'static (Mesh, Skeleton) {
    static BUILT: OnceLock<Mutex<HashMap<String, &'static (Mesh, Skeleton)>>> = OnceLock::new();
    let built = BUILT.get_or_init(Default::default);
    let mut built = built.lock().unwrap_or_else(|e| e.into_inner());
    built.entry(path.to_string()).or_insert_with(|| {
        let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
        let (mesh, _) = crate::mesh::load(&file).expect("a fixture loads");
        let puppet = crate::puppet::Puppet::build(mesh, Default::default(), &|_, _| {})
            .expect("a fixture builds");
        Box::leak(Box::new((puppet.mesh, puppet.skeleton)))
    })
}

/// The shipped human (SMPL's template: no riders, mirrored across x, +y up, facing +z).
pub(crate) fn human() -> &'static (Mesh, Skeleton) {
    character("tests/data/meshes/human.obj")
}
