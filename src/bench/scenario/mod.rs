//! Standard scenarios for benchmarks, the stability stress and the accuracy reference: one
//! definition shared by `puppet bench`, the tests and the criterion benches, so every
//! number in `BENCHMARKS.md` and `docs/engine-benchmarks.md` comes from the same animation.
//!
//! **The standard scenario.** The mesh is cut across its longest bounding-box axis at
//! [`LIMB_AT`] of its extent; the smaller end (the "limb", about a fifth of the mesh) swings
//! about an axis in the cut plane, `SWING_DEGREES · sin(2π t / SWING_PERIOD)`, for
//! `swing_seconds`, then holds still at rest pose. The rest of the mesh (the "body") is
//! never posed: whatever moves there is dragged by the springs across the cut.
//!
//! [`reference`](mod@reference) integrates the same equations in `f64` (the accuracy reference).

pub mod reference;

use crate::joints::{Cut, JointError, Joints, Local, Shape, ROOT};
use crate::mesh::{self, Mesh, MeshError};
use crate::rig::Rig;
use crate::sim::Pose;
use glam::{DAffine3, DVec3};

/// Where the standard cut sits along the longest axis (fraction of the extent).
pub const LIMB_AT: f64 = 0.8;
/// Amplitude of the limb's swing (degrees).
pub const SWING_DEGREES: f64 = 40.0;
/// Period of the swing (seconds).
pub const SWING_PERIOD: f64 = 1.0;

/// Why the standard scenario cannot be set up on a mesh.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The mesh has no normals (degenerate).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The standard cut leaves a side empty.
    #[error(transparent)]
    Joints(#[from] JointError),
}

/// A mesh with skeletal distances, one cut and the limb's animation.
#[derive(Clone, Debug)]
pub struct Scenario {
    /// The mesh.
    pub mesh: Mesh,
    /// Its unit vertex normals.
    pub normals: Vec<DVec3>,
    /// Its skeletal distances.
    pub distance: Vec<f64>,
    /// The body and the limb.
    pub joints: Joints,
    /// Index of the limb section.
    pub limb: usize,
    /// Rotation axis of the limb (unit, in the cut plane).
    pub axis: DVec3,
    /// Seconds the limb swings before it holds still.
    pub swing_seconds: f64,
    /// Bounding-box diagonal of the mesh.
    pub diagonal: f64,
}

impl Scenario {
    /// The standard scenario on a validated mesh with its skeletal distances (see the module
    /// docs).
    ///
    /// # Errors
    /// When the mesh has no normals (degenerate) or the cut leaves a side empty (a mesh
    /// whose skeleton does not extend along its longest axis).
    pub fn standard(
        mesh: Mesh,
        distance: Vec<f64>,
        swing_seconds: f64,
    ) -> Result<Scenario, ScenarioError> {
        let normals = mesh::vertex_normals(&mesh)?;
        let points: Vec<DVec3> = mesh
            .positions
            .iter()
            .zip(&normals)
            .zip(&distance)
            .map(|((p, n), d)| *p - *d * *n)
            .collect();
        let (lo, hi) = mesh.bounds();
        let ext = hi - lo;
        let axis_index = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let along = DVec3::AXES[axis_index];
        let across = DVec3::AXES[(axis_index + 1) % 3];
        let mut joints = Joints::new(&points, ROOT);
        let limb = joints.add_cut(Cut {
            name: "limb".into(),
            section: ROOT.into(),
            point: lo + ext * LIMB_AT,
            normal: along,
            pivot: None,
            connected: false,
            band: None,
            shape: Shape::Plane,
            shared_pivot: false,
        })?;
        Ok(Scenario {
            diagonal: ext.length(),
            mesh,
            normals,
            distance,
            joints,
            limb,
            axis: across,
            swing_seconds,
        })
    }

    /// The rig for a bone distance factor.
    pub fn rig(&self, bone_distance: f32) -> Rig {
        Rig::new(&self.mesh, &self.normals, &self.distance, bone_distance)
    }

    /// Local poses at time `t` (seconds).
    pub fn local(&self, t: f64) -> Vec<Local> {
        let mut local = vec![Local::default(); self.joints.sections().len()];
        if t < self.swing_seconds {
            let angle = SWING_DEGREES * (std::f64::consts::TAU * t / SWING_PERIOD).sin();
            local[self.limb] = Local::axis_angle(self.axis, angle);
        }
        local
    }

    /// World transforms per section at time `t`, in `f64`.
    pub fn world(&self, t: f64) -> Vec<DAffine3> {
        self.joints.world(&self.local(t))
    }

    /// The simulation's pose at time `t`.
    pub fn pose(&self, t: f64) -> Pose {
        self.joints.pose(&self.local(t))
    }

    /// Vertices in the limb.
    pub fn limb_vertices(&self) -> usize {
        self.joints.sections()[self.limb].vertices
    }
}
