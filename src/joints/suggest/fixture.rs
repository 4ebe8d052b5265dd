//! Characters the stages' unit tests run on: a mesh of the repository with its skeleton,
//! built once per test run.

use super::body::Body;
use super::limbs::{self, Limb};
use super::names::{self, Named};
use super::place::{self, Placed};
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

/// The shipped human as a puppet with its suggested joints.
///
/// # Panics
/// When it does not build or its joints are not suggested: it is the repository's own.
pub(crate) fn suggested_human() -> crate::puppet::Puppet {
    suggested("tests/data/meshes/human.obj")
}

/// The mesh at `path` (from the repository's root) as a puppet with its suggested joints
/// (a skinned file's own joints replaced).
///
/// # Panics
/// When it does not build or its joints are not suggested: it is the repository's own.
pub(crate) fn suggested(path: &str) -> crate::puppet::Puppet {
    let (mesh, _) = character(path);
    let mut puppet = crate::puppet::Puppet::build(
        mesh.clone(),
        crate::puppet::RigFile::default(),
        crate::progress::silent(),
    )
    .expect("the character builds");
    puppet.suggest_joints().expect("its joints");
    puppet
}

/// The shipped human run through the stages up to the one a test is of.
pub(crate) struct Staged {
    pub(crate) mesh: &'static Mesh,
    pub(crate) skeleton: &'static Skeleton,
    /// Stages 1–2.
    pub(crate) body: Body<'static>,
    /// Stage 3.
    pub(crate) limbs: Vec<Limb>,
    /// Stage 4.
    pub(crate) placed: Placed,
}

impl Staged {
    /// The human through stage 4 (its cuts placed, under the root `root`).
    pub(crate) fn human() -> Staged {
        Staged::of("tests/data/meshes/human.obj")
    }

    /// The mesh at `path` (from the repository's root) through stage 4.
    pub(crate) fn of(path: &str) -> Staged {
        let (mesh, skeleton) = character(path);
        let body = Body::of(mesh, skeleton, &crate::mesh::attachments(mesh), None);
        let mirror = body.cues.mirror;
        let limbs = limbs::of(&body.tree(), mirror);
        let placed = place::place(
            mesh,
            skeleton,
            &body.hosts,
            &crate::mesh::attachments(mesh),
            "root",
            &limbs,
            mirror,
        );
        Staged {
            mesh,
            skeleton,
            body,
            limbs,
            placed,
        }
    }

    /// Stage 5 on it, with up given or found.
    pub(crate) fn named(&self, up: Option<glam::DVec3>) -> Named {
        let body = &self.body;
        let radius = &self.skeleton.distance;
        let given = crate::mesh::orientation::Given { up, front: None };
        names::name(
            &body.character,
            radius,
            &self.placed,
            given,
            body.cues,
            "root",
        )
    }
}
