//! A measured bend of one joint: cut a limb, turn it by an angle over half a second, let
//! it settle, and measure the surface against the rest mesh (`puppet bench joints`, the
//! joint tests).
//!
//! Measured over the *joint region*, the vertices within [`REGION`] local medial radii of
//! the cut's plane on the limb (see [`crate::joints::Joints::joint_region`]):
//! * faces crossing another face that did not at rest ([`intersecting_faces`]);
//! * the change of the whole mesh's volume, and of the region's with the cuts across it
//!   closed ([`capped_volume`]: unchanged by a rigid motion, only the deformation counts);
//! * the largest dihedral angle between neighbouring faces of the region, and the rest
//!   mesh's;
//! * the crease: the largest rise of one edge's dihedral angle over its own rest angle,
//!   of the surface and of the band's targets alone (the bone motion).
//!
//! [`intersecting_faces`]: crate::geom::intersect::intersecting_faces

use super::{BuildError, Puppet, RigFile};
use crate::geom::intersect::intersecting_faces;
use crate::joints::{Cut, Local, Shape};
use crate::mesh::measure::{capped_volume, cone_volume, largest_crease, largest_dihedral};
use crate::mesh::Mesh;
use crate::sim::Params;
use glam::DVec3;

/// Half-width of the measured region, in local medial radii.
pub const REGION: f64 = crate::joints::MAX_BAND;

/// Seconds over which the bend is applied (a smooth ramp), then [`HOLD`] seconds held.
pub const RAMP: f64 = 0.5;

/// Seconds the bend is held before the surface is measured.
pub const HOLD: f64 = 2.5;

/// A joint of a test mesh: a connected cut of the root and the axis it bends about.
#[derive(Clone, Copy, Debug)]
pub struct Joint {
    /// What it is ("human elbow").
    pub name: &'static str,
    /// The mesh file (in `tests/data/meshes`).
    pub mesh: &'static str,
    /// A point of the cut's plane.
    pub point: DVec3,
    /// The plane's normal, into the limb's far part.
    pub normal: DVec3,
    /// The bend's axis (a positive angle flexes the joint).
    pub axis: DVec3,
}

/// The joints the bends are measured on: the cuts `puppet suggest` makes at the human's
/// right elbow and knee and at the proximal joints of the hand's middle and ring fingers.
pub const JOINTS: [Joint; 4] = [
    Joint {
        name: "human elbow",
        mesh: "human.obj",
        point: DVec3::new(-0.476, 1.333, -0.038),
        normal: DVec3::new(-0.997, 0.081, 0.005),
        axis: DVec3::Y,
    },
    Joint {
        name: "human knee",
        mesh: "human.obj",
        point: DVec3::new(0.082, 0.446, -0.011),
        normal: DVec3::new(0.171, -0.956, -0.240),
        axis: DVec3::X,
    },
    Joint {
        name: "middle finger",
        mesh: "hand.obj",
        point: DVec3::new(0.018, 0.780, 0.054),
        normal: DVec3::new(0.099, 0.989, 0.113),
        axis: DVec3::X,
    },
    Joint {
        name: "ring finger",
        mesh: "hand.obj",
        point: DVec3::new(-0.128, 0.752, 0.059),
        normal: DVec3::new(0.010, 0.998, 0.070),
        axis: DVec3::X,
    },
];

/// Name of the cut a bend makes.
pub const CUT: &str = "limb";

/// What a settled bend measured.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Bent {
    /// The angle (degrees).
    pub degrees: f64,
    /// Faces crossing another face that did not at rest.
    pub crossing: usize,
    /// Faces of the region.
    pub region_faces: usize,
    /// Relative change of the whole mesh's volume.
    pub volume: f64,
    /// Relative change of the region's volume, its cuts closed.
    pub region_volume: f64,
    /// Largest dihedral angle in the region (degrees).
    pub dihedral: f64,
    /// The rest mesh's (degrees).
    pub rest_dihedral: f64,
    /// The largest rise of an edge's dihedral angle over its own rest angle in the region
    /// (degrees; [`largest_crease`]).
    pub crease: f64,
    /// The same of the band's targets alone (the bone motion, no simulation).
    pub target_crease: f64,
    /// Kinetic energy left at the end (how settled it is).
    pub kinetic: f64,
}

impl Joint {
    /// The cut: a connected cut of the root with the default pivot and the given band.
    pub fn cut(&self, band: Option<f64>) -> Cut {
        Cut {
            name: CUT.into(),
            section: crate::joints::ROOT.into(),
            point: self.point,
            normal: self.normal,
            pivot: None,
            connected: true,
            band,
            shape: Shape::Plane,
            shared_pivot: false,
        }
    }

    /// The rotation by `degrees` about the bend axis made perpendicular to the cut's normal.
    pub fn rotation(&self, degrees: f64) -> Local {
        let n = self.normal.normalize_or_zero();
        Local::axis_angle(self.axis - n * self.axis.dot(n), degrees)
    }

    /// Builds the puppet of `mesh` with this joint's cut (band `band`), bends it by
    /// `degrees` and measures it settled.
    pub fn bend(
        &self,
        mesh: &Mesh,
        band: Option<f64>,
        degrees: f64,
        params: Params,
    ) -> Result<Bent, BuildError> {
        Ok(measure(&self.bent(mesh, band, degrees, params)?, degrees))
    }

    /// The puppet of `mesh` with this joint's cut (band `band`), bent by `degrees` over
    /// [`RAMP`] seconds and held [`HOLD`] seconds.
    pub fn bent(
        &self,
        mesh: &Mesh,
        band: Option<f64>,
        degrees: f64,
        params: Params,
    ) -> Result<Puppet, BuildError> {
        let spec = RigFile {
            cuts: vec![self.cut(band)],
            params,
            ..RigFile::default()
        };
        let mut p = Puppet::build(mesh.clone(), spec, crate::progress::silent())?;
        let child = p.joints.find(CUT).unwrap_or(0);
        let dt = f64::from(p.sim.params().solver.time_step);
        let steps = ((RAMP + HOLD) / dt).ceil() as usize;
        let mut local = vec![Local::default(); p.joints.sections().len()];
        let mut scratch = crate::joints::PoseScratch::default();
        for k in 1..=steps {
            let s = (k as f64 * dt / RAMP).min(1.0);
            local[child] = self.rotation(degrees * s * s * (3.0 - 2.0 * s));
            p.sim.step(p.joints.pose_into(&local, &mut scratch));
        }
        Ok(p)
    }
}

/// Measures a puppet's surface against its rest mesh over the region of the cut [`CUT`]
/// (bent by `degrees`, which is reported).
pub fn measure(p: &Puppet, degrees: f64) -> Bent {
    let rest = &p.mesh.positions;
    let now: Vec<DVec3> = (0..rest.len())
        .map(|i| p.sim.positions().get(i).as_dvec3())
        .collect();
    let targets: Vec<DVec3> = (0..rest.len())
        .map(|i| p.sim.target(i).as_dvec3())
        .collect();
    let triangles = &p.mesh.triangles;
    let region_faces: Vec<bool> = match p.joints.joint_region(CUT, REGION) {
        Some((region, _)) => triangles
            .iter()
            .map(|t| t.iter().any(|&v| region[v as usize]))
            .collect(),
        None => vec![false; triangles.len()],
    };
    let (before, after) = (
        intersecting_faces(rest, triangles),
        intersecting_faces(&now, triangles),
    );
    let crossing = (0..triangles.len())
        .filter(|&f| region_faces[f] && after[f] && !before[f])
        .count();
    let all = vec![true; triangles.len()];
    let change = |a: f64, b: f64| if a != 0.0 { b / a - 1.0 } else { 0.0 };
    Bent {
        degrees,
        crossing,
        region_faces: region_faces.iter().filter(|&&r| r).count(),
        volume: change(
            cone_volume(rest, triangles, &all, DVec3::ZERO),
            cone_volume(&now, triangles, &all, DVec3::ZERO),
        ),
        region_volume: change(
            capped_volume(rest, triangles, &region_faces),
            capped_volume(&now, triangles, &region_faces),
        ),
        dihedral: largest_dihedral(&now, triangles, &region_faces),
        rest_dihedral: largest_dihedral(rest, triangles, &region_faces),
        crease: largest_crease(rest, &now, triangles, &region_faces),
        target_crease: largest_crease(rest, &targets, triangles, &region_faces),
        kinetic: p.sim.kinetic_energy(),
    }
}
