//! A measured press: parts of a shipped mesh cut off and turned into the rest of the body
//! (arms down past the sides, legs crossed, a head turned into a shoulder), settled, and the
//! surface measured (`puppet bench collide`, the collision tests):
//! * faces crossing another face that did not at rest ([`intersecting_faces`], exact);
//! * the deepest penetration: how far a vertex lies inside another part (a point just
//!   outside the surface at it has generalized winding number 1 against the faces of the
//!   other sections, not 0; vertices inside at rest do not count), as the distance to the
//!   nearest face of the other sections, in % of the diagonal;
//! * each section's volume change (the volume its faces enclose with each cut across it
//!   closed, [`capped_volume`]: what the piece holds, which no rigid motion changes),
//!   relative to its size ([`section_size`]: that volume or a hundredth of the whole
//!   mesh's, whichever is larger): the extremes;
//! * the dents: how far a vertex of the body (the root section) and of a turned part lies
//!   inside where its bones hold it (its target, along the target surface's inward
//!   normal), in % of the diagonal: soft flesh dents the body, hard flesh squashes the
//!   part.
//!
//! [`intersecting_faces`]: crate::geom::intersect::intersecting_faces
//! [`capped_volume`]: crate::mesh::measure::capped_volume
//! [`section_size`]: crate::joints::section_size

use super::{BuildError, Puppet, RigFile};
use crate::anim::{Animation, Ease, Key, Track};
use crate::geom::intersect::new_crossings;
use crate::geom::point_triangle;
use crate::geom::winding::Winding;
use crate::joints::{section_size, Cut, Local, Shape};
use crate::mesh::measure::{capped_volume, cone_volume};
use crate::mesh::{self, Mesh};
use crate::sim::Params;
use glam::DVec3;

/// Seconds over which the pose is reached (a smooth ramp), then [`HOLD`] seconds held.
pub const RAMP: f64 = 0.5;

/// Seconds the pose is held before the surface is measured.
pub const HOLD: f64 = 1.5;

/// One part turned: a cut of the root and its turn.
#[derive(Clone, Copy, Debug)]
pub struct Turn {
    /// A point of the cut's plane.
    pub point: DVec3,
    /// The plane's normal, into the part.
    pub normal: DVec3,
    /// The axis it turns about.
    pub axis: DVec3,
    /// The angle (degrees).
    pub degrees: f64,
}

/// A pose that presses parts of a mesh into each other.
#[derive(Clone, Copy, Debug)]
pub struct Press {
    /// What it is ("human arms down 95°").
    pub name: &'static str,
    /// The mesh file (in `tests/data/meshes`, or `assets` for `spot.obj`).
    pub mesh: &'static str,
    /// The parts turned.
    pub turns: &'static [Turn],
}

const fn turn(point: [f64; 3], normal: [f64; 3], axis: [f64; 3], degrees: f64) -> Turn {
    Turn {
        point: DVec3::from_array(point),
        normal: DVec3::from_array(normal),
        axis: DVec3::from_array(axis),
        degrees,
    }
}

/// The human's shoulders (fixed planes near where `puppet suggest` cuts), turned down by
/// `d` degrees.
const fn arms(d: f64) -> [Turn; 2] {
    [
        turn(
            [-0.199, 1.336, -0.038],
            [-0.980, -0.053, 0.192],
            [0.0, 0.0, 1.0],
            d,
        ),
        turn(
            [0.199, 1.336, -0.038],
            [0.980, -0.053, 0.192],
            [0.0, 0.0, 1.0],
            -d,
        ),
    ]
}

const ARMS_95: [Turn; 2] = arms(95.0);
const ARMS_105: [Turn; 2] = arms(105.0);

/// The human's shoulders cut as a user cuts them by eye: planes across x at ±0.2, turned
/// down by `d` degrees.
const fn square_arms(d: f64) -> [Turn; 2] {
    [
        turn([-0.2, 1.336, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], d),
        turn([0.2, 1.336, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], -d),
    ]
}

const SQUARE_95: [Turn; 2] = square_arms(95.0);
const SQUARE_105: [Turn; 2] = square_arms(105.0);
const LEGS: [Turn; 1] = [turn(
    [0.069, 0.610, 0.011],
    [0.109, -0.989, -0.099],
    [0.0, 0.0, 1.0],
    -25.0,
)];
const HEAD: [Turn; 1] = [turn(
    [-0.003, 1.451, 0.017],
    [-0.007, 0.897, 0.442],
    [0.0, 0.0, 1.0],
    100.0,
)];
const FINGER: [Turn; 1] = [turn(
    [-0.117, 0.571, 0.063],
    [-0.071, 0.974, -0.217],
    [1.0, 0.0, 0.0],
    165.0,
)];
const COW: [Turn; 1] = [turn(
    [0.0, 0.250, -0.119],
    [0.0, 0.286, -0.958],
    [0.0, 1.0, 0.0],
    130.0,
)];

/// The presses `puppet bench collide` measures.
pub const PRESSES: [Press; 8] = [
    Press {
        name: "human arms down 95°",
        mesh: "human.obj",
        turns: &ARMS_95,
    },
    Press {
        name: "human arms down 105°",
        mesh: "human.obj",
        turns: &ARMS_105,
    },
    Press {
        name: "human arms down 95°, cut at x = ±0.2",
        mesh: "human.obj",
        turns: &SQUARE_95,
    },
    Press {
        name: "human arms down 105°, cut at x = ±0.2",
        mesh: "human.obj",
        turns: &SQUARE_105,
    },
    Press {
        name: "human legs crossed",
        mesh: "human.obj",
        turns: &LEGS,
    },
    Press {
        name: "human head into a shoulder",
        mesh: "human.obj",
        turns: &HEAD,
    },
    Press {
        name: "hand index curled into the palm",
        mesh: "hand.obj",
        turns: &FINGER,
    },
    Press {
        name: "cow head into its flank",
        mesh: "spot.obj",
        turns: &COW,
    },
];

/// What a settled press measured.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Pressed {
    /// Faces crossing another face that did not at rest.
    pub crossing: usize,
    /// Faces in all.
    pub faces: usize,
    /// The deepest a vertex lies inside another part, in % of the diagonal.
    pub deepest: f64,
    /// Vertices inside another part.
    pub inside: usize,
    /// The smallest and largest relative volume change of a section.
    pub volume: [f64; 2],
    /// Kinetic energy left at the end (how settled it is).
    pub kinetic: f64,
    /// Median step time over the hold (ms).
    pub step_ms: f64,
    /// Tiles still awake at the end, of all (sleeping: a settled press costs nothing).
    pub awake: [usize; 2],
    /// The smallest angle a part reached, in degrees (collision stops a part early).
    pub reached: f64,
    /// The deepest dent of the body and of the turned parts, in % of the diagonal.
    pub dent: [f64; 2],
}

impl Press {
    /// The rig: each part a connected cut of the root with the default band.
    pub fn rig(&self, params: Params) -> RigFile {
        let cuts = self
            .turns
            .iter()
            .enumerate()
            .map(|(k, t)| Cut {
                name: format!("part {}", k + 1),
                section: crate::joints::ROOT.into(),
                point: t.point,
                normal: t.normal,
                pivot: None,
                connected: true,
                band: None,
                shape: Shape::Plane,
                shared_pivot: false,
            })
            .collect();
        RigFile {
            cuts,
            params,
            ..RigFile::default()
        }
    }

    /// The puppet of `mesh` posed by a hand (see [`Press::posed_by`]).
    pub fn posed(&self, mesh: &Mesh, params: Params) -> Result<Posed, BuildError> {
        self.posed_by(mesh, params, Drive::Hand)
    }

    /// The animation that turns the parts as the press does: a smooth ramp to the angle
    /// over [`RAMP`] seconds, held to [`HOLD`] seconds after it.
    pub fn animation(&self) -> Animation {
        Animation {
            duration: RAMP + HOLD,
            looping: false,
            track: self
                .turns
                .iter()
                .enumerate()
                .map(|(n, t)| {
                    let key = |time: f64, angle: f64| Key {
                        time,
                        axis: t.axis.to_array(),
                        angle,
                        translation: None,
                    };
                    Track {
                        section: format!("part {}", n + 1),
                        ease: Ease::Smooth,
                        key: vec![key(0.0, 0.0), key(RAMP, t.degrees)],
                    }
                })
                .collect(),
        }
    }

    /// The puppet of `mesh` posed over [`RAMP`] seconds and held [`HOLD`] seconds, by a
    /// hand or by an animation; both go through [`Puppet::step_toward`], so with collision
    /// on each step's pose is held back where parts meet.
    pub fn posed_by(&self, mesh: &Mesh, params: Params, drive: Drive) -> Result<Posed, BuildError> {
        let mut p = Puppet::build(mesh.clone(), self.rig(params), crate::progress::silent())?;
        let dt = f64::from(p.sim.params().solver.time_step);
        let steps = ((RAMP + HOLD) / dt).ceil() as usize;
        let mut local = vec![Local::default(); p.joints.sections().len()];
        let mut scratch = crate::joints::PoseScratch::default();
        let bound = self
            .animation()
            .bind(&p.joints)
            .map_err(|e| BuildError::Regions(e.to_string()))?;
        let mut times = Vec::new();
        for k in 1..=steps {
            let start = std::time::Instant::now();
            match drive {
                Drive::Hand => {
                    let s = (k as f64 * dt / RAMP).min(1.0);
                    let s = s * s * (3.0 - 2.0 * s);
                    let mut wanted = local.clone();
                    for (n, t) in self.turns.iter().enumerate() {
                        if let Some(section) = p.joints.find(&format!("part {}", n + 1)) {
                            wanted[section] = Local::axis_angle(t.axis, t.degrees * s);
                        }
                    }
                    p.step_toward(&wanted, &mut local, &mut scratch);
                }
                Drive::Animation => p.step_animated(&bound, k as u64, &mut local, &mut scratch),
            }
            if k as f64 * dt > RAMP {
                times.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        Ok(Posed {
            puppet: p,
            times,
            local,
        })
    }

    /// Poses `mesh` by a hand, settles it and measures it.
    pub fn press(&self, mesh: &Mesh, params: Params) -> Result<Pressed, BuildError> {
        self.press_by(mesh, params, Drive::Hand)
    }

    /// Poses `mesh` by a hand or an animation, settles it and measures it.
    pub fn press_by(
        &self,
        mesh: &Mesh,
        params: Params,
        drive: Drive,
    ) -> Result<Pressed, BuildError> {
        let Posed {
            puppet,
            mut times,
            local,
        } = self.posed_by(mesh, params, drive)?;
        let mut out = measure(&puppet);
        out.step_ms = crate::stats::median(&mut times).unwrap_or(0.0);
        out.reached = local
            .iter()
            .skip(1)
            .map(|l| l.rotation.angle_between(glam::DQuat::IDENTITY).to_degrees())
            .fold(f64::INFINITY, f64::min);
        Ok(out)
    }
}

/// What turns the parts of a press.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Drive {
    /// A hand (a drag or a glove): each step's pose set from the ramp, as the window sets
    /// it.
    Hand,
    /// The same ramp written as an animation file ([`Press::animation`]), played as
    /// `simulate --anim` and the window play one.
    Animation,
}

/// A press's puppet at its end, the step times of its hold (ms) and the pose it holds.
pub struct Posed {
    /// The puppet.
    pub puppet: Puppet,
    /// Each step's time over the hold (ms).
    pub times: Vec<f64>,
    /// The sections' poses at the end.
    pub local: Vec<Local>,
}

/// Measures a posed puppet's surface (see the module's list).
pub fn measure(p: &Puppet) -> Pressed {
    let rest = &p.mesh.positions;
    let now: Vec<DVec3> = (0..rest.len())
        .map(|i| p.sim.positions().get(i).as_dvec3())
        .collect();
    let triangles = &p.mesh.triangles;
    let crossing = new_crossings(rest, &now, triangles);
    let section_of = p.joints.section_of();
    let (lo, hi) = p.mesh.bounds();
    let diagonal = (hi - lo).length().max(f64::MIN_POSITIVE);
    // Inside another part: a point just outside the surface at a vertex (a thousandth of
    // the diagonal along its normal) has generalized winding number 1 against the faces
    // of the other sections (those with no corner in the vertex's section), 0 when it is
    // outside them; an ear flopping into its own head is not a press. Vertices inside at
    // rest (a mesh's own overlaps) do not count.
    let offset = 1e-3 * diagonal;
    let sections = p.joints.sections().len();
    let others: Vec<Vec<[u32; 3]>> = (0..sections)
        .map(|s| {
            triangles
                .iter()
                .copied()
                .filter(|t| t.iter().all(|&i| usize::from(section_of[i as usize]) != s))
                .collect()
        })
        .collect();
    let inside_others = |positions: &[DVec3]| -> Vec<bool> {
        let posed = Mesh {
            positions: positions.to_vec(),
            triangles: triangles.clone(),
        };
        let normals = mesh::vertex_normals(&posed).unwrap_or_default();
        let windings: Vec<Winding> = others
            .iter()
            .map(|faces| Winding::new(positions, faces))
            .collect();
        positions
            .iter()
            .enumerate()
            .map(|(v, &x)| {
                let n = normals.get(v).copied().unwrap_or(DVec3::ZERO);
                let s = usize::from(section_of[v]);
                !others[s].is_empty() && windings[s].at(x + n * offset) > 0.5
            })
            .collect()
    };
    let inside_at_rest = inside_others(rest);
    let inside_now = inside_others(&now);
    let mut deepest = 0.0f64;
    let mut inside = 0;
    for (v, &x) in now.iter().enumerate() {
        if !inside_now[v] || inside_at_rest[v] {
            continue;
        }
        inside += 1;
        let nearest = others[usize::from(section_of[v])]
            .iter()
            .map(|t| point_triangle(x, t.map(|i| now[i as usize])))
            .fold(f64::INFINITY, f64::min);
        if nearest.is_finite() {
            deepest = deepest.max(nearest);
        }
    }
    // Dents: how far inside its target a vertex lies, along the target surface's normal.
    let targets: Vec<DVec3> = (0..rest.len())
        .map(|i| p.sim.target(i).as_dvec3())
        .collect();
    let target_normals = mesh::vertex_normals(&Mesh {
        positions: targets.clone(),
        triangles: triangles.clone(),
    })
    .unwrap_or_default();
    let mut dent = [0.0f64; 2];
    for (v, (&x, &t)) in now.iter().zip(&targets).enumerate() {
        let n = target_normals.get(v).copied().unwrap_or(DVec3::ZERO);
        let part = usize::from(section_of[v] != 0);
        dent[part] = dent[part].max((t - x).dot(n));
    }
    let volume = section_volumes(p, &now);
    Pressed {
        crossing,
        faces: triangles.len(),
        deepest: 100.0 * deepest / diagonal,
        inside,
        volume,
        kinetic: p.sim.kinetic_energy(),
        step_ms: 0.0,
        awake: {
            let (all, awake) = p.sim.tiles();
            [awake, all]
        },
        reached: 0.0,
        dent: dent.map(|d| 100.0 * d / diagonal),
    }
}

/// The smallest and largest relative volume change of a section of `p` whose surface is at
/// `now`: each section's faces with every cut across it closed by a fan from the cut's
/// loop's centroid ([`capped_volume`]), at rest and now, against that volume or
/// [`SMALL_SECTION`](crate::joints::SMALL_SECTION) of the whole mesh's, whichever is
/// larger ([`section_size`]).
///
/// Not the cone from the section's pivot: closed at its pivot, a section counts a far cut
/// that tilts as volume lost or gained (a tube bent 60° as an arc holds what it held,
/// −0.05 % capped, and reads +8.6 % as a cone from its near cut: `mesh::measure`'s
/// tests).
pub fn section_volumes(p: &Puppet, now: &[DVec3]) -> [f64; 2] {
    section_volume_extremes(p, now).map(|(change, _)| change)
}

/// [`section_volumes`] with the section that changes by each (`None` where no section
/// holds a volume).
pub fn section_volume_extremes(p: &Puppet, now: &[DVec3]) -> [(f64, Option<usize>); 2] {
    let rest = &p.mesh.positions;
    let triangles = &p.mesh.triangles;
    let section_of = p.joints.section_of();
    let mut volume = [(f64::INFINITY, None), (f64::NEG_INFINITY, None)];
    let whole = cone_volume(rest, triangles, &vec![true; triangles.len()], DVec3::ZERO).abs();
    for s in 0..p.joints.sections().len() {
        let faces: Vec<bool> = triangles
            .iter()
            .map(|t| t.iter().all(|&i| usize::from(section_of[i as usize]) == s))
            .collect();
        let a = capped_volume(rest, triangles, &faces);
        let against = section_size(a, whole);
        if against < 1e-12 {
            continue;
        }
        let change = (capped_volume(now, triangles, &faces) - a) / against;
        if change < volume[0].0 {
            volume[0] = (change, Some(s));
        }
        if change > volume[1].0 {
            volume[1] = (change, Some(s));
        }
    }
    volume
}
