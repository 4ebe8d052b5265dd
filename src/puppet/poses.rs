//! Random poses of a puppet's joints, settled, and the surface measured against its rest
//! shape (`puppet bench poses`, the pose tests, the stress test): what a puppeteer does
//! first to a character, turning every joint at once.
//!
//! A pose ([`random_pose`]) turns every section but the root about a random axis across
//! its cut (square to the cut's normal), by an angle drawn evenly within
//! ±[`Spread::limb`] degrees, or ±[`Spread::root`] for a section hanging from the root (a
//! head, a hip, a shoulder). [`settle`] reaches it over [`RAMP`] seconds and holds it
//! [`HOLD`] seconds; [`measure`] then reads:
//! * every edge's **stretch**, its posed length over its rest length: the worst, the 99th
//!   percentile, and the shares over 1.5× and 2× (a torn skin is an edge many times its
//!   length);
//! * the **faces crossing** another face that did not at rest (exact);
//! * each **section's volume** change ([`super::press::section_volumes`]), and the whole
//!   surface's;
//! * whether any position is not finite.

use super::press::section_volume_extremes;
use super::Puppet;
use crate::geom::intersect::new_crossings;
pub use crate::joints::spread::{one_turned, random_pose, Spread};
use crate::joints::{Local, PoseScratch};
use crate::mesh::measure::cone_volume;
use glam::{DQuat, DVec3};

/// Seconds over which a pose is reached (a smooth ramp from rest).
pub const RAMP: f64 = 0.5;

/// Seconds a pose is held before the surface is measured.
pub const HOLD: f64 = 1.0;

/// Brings `puppet` from its present pose (at rest) to `target` over [`RAMP`] seconds, each
/// section slerped from rest, and holds it [`HOLD`] seconds, each step through
/// [`Puppet::step_toward`] (with collision on, a part stops where it meets another).
/// Returns each step's time and its pose limit's ([`Puppet::hold_back`]), in ms, and the
/// pose reached.
pub fn settle(puppet: &mut Puppet, target: &[Local]) -> (Vec<[f64; 2]>, Vec<Local>) {
    let dt = f64::from(puppet.sim.params().solver.time_step);
    let steps = ((RAMP + HOLD) / dt).ceil() as usize;
    let mut local = vec![Local::default(); target.len()];
    let mut wanted = local.clone();
    let mut scratch = PoseScratch::default();
    let mut times = Vec::with_capacity(steps);
    for k in 1..=steps {
        let s = (k as f64 * dt / RAMP).min(1.0);
        let s = s * s * (3.0 - 2.0 * s);
        for (l, t) in wanted.iter_mut().zip(target) {
            *l = Local {
                rotation: DQuat::IDENTITY.slerp(t.rotation, s),
                translation: t.translation * s,
            };
        }
        // Timed apart: the pose limit, then the step (what `step_toward` does).
        let start = std::time::Instant::now();
        let before = std::mem::replace(&mut local, wanted.clone());
        puppet.hold_back(&before, &mut local);
        let held = start.elapsed().as_secs_f64() * 1e3;
        let start = std::time::Instant::now();
        puppet
            .sim
            .step(puppet.joints.pose_into(&local, &mut scratch));
        times.push([start.elapsed().as_secs_f64() * 1e3, held]);
    }
    (times, local)
}

/// What [`measure`] read off a posed surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Surface {
    /// The largest edge stretch (posed length over rest length).
    pub worst: f64,
    /// The two vertices of that edge (`None` where no edge has a length).
    #[serde(skip)]
    pub worst_edge: Option<[usize; 2]>,
    /// The 99th percentile of the edges' stretch.
    pub p99: f64,
    /// The share of edges stretched more than 1.5×.
    pub over_1_5: f64,
    /// The share of edges stretched more than 2×.
    pub over_2: f64,
    /// Faces crossing another face that did not at rest.
    pub crossing: usize,
    /// The smallest and largest relative volume change of a section (an open piece of
    /// the surface, each cut across it closed: [`super::press::section_volumes`]).
    pub volume: [f64; 2],
    /// The sections that change by those (`None` where no section holds a volume).
    #[serde(skip)]
    pub volume_sections: [Option<usize>; 2],
    /// The relative volume change of the whole surface.
    pub whole: f64,
    /// How far the vertex farthest from where its bones hold it lies from there, in its
    /// own medial radius (skeletal distance; at least the mesh's median, as a crease's or
    /// a tip's own is a crumb): flesh squashed by a contact moves a share of its own
    /// radius; a piece left behind, or caught on another part, more.
    pub behind: f64,
    /// Some position is not finite.
    pub nan: bool,
}

/// The surface of `puppet` as its simulation holds it now in the pose `local`, against its
/// rest mesh (see the module docs).
pub fn measure(puppet: &Puppet, local: &[Local]) -> Surface {
    let x = puppet.sim.positions();
    let now: Vec<DVec3> = (0..x.len()).map(|i| x.get(i).as_dvec3()).collect();
    measure_at(puppet, &now, local)
}

/// Where the bones of `puppet` hold its surface in the pose `local` (each vertex's rest
/// position moved by its transform, before the simulation): the rig's own share of a
/// pose's stretch, without settling.
pub fn targets(puppet: &Puppet, local: &[Local]) -> Vec<DVec3> {
    let pose = puppet.joints.pose(local);
    let transform_of = puppet.joints.transform_of();
    puppet
        .mesh
        .positions
        .iter()
        .zip(transform_of)
        .map(|(&x, &t)| {
            pose.transforms
                .get(usize::from(t))
                .map_or(x, |m| m.transform_point3(x.as_vec3()).as_dvec3())
        })
        .collect()
}

/// [`measure`] for the surface at `now` (one position per vertex of the rest mesh).
pub fn measure_at(puppet: &Puppet, now: &[DVec3], local: &[Local]) -> Surface {
    let rest = &puppet.mesh.positions;
    if now.iter().any(|p| !p.is_finite()) {
        return Surface {
            worst: f64::INFINITY,
            p99: f64::INFINITY,
            over_1_5: 1.0,
            over_2: 1.0,
            nan: true,
            ..Surface::default()
        };
    }
    let mut stretch: Vec<(f64, [usize; 2])> = crate::mesh::unique_edges(&puppet.mesh.triangles)
        .into_iter()
        .filter_map(|(a, b)| {
            let (a, b) = (a as usize, b as usize);
            let r = rest[a].distance(rest[b]);
            (r > 0.0).then(|| (now[a].distance(now[b]) / r, [a, b]))
        })
        .collect();
    stretch.sort_by(|x, y| x.0.total_cmp(&y.0));
    let worst_edge = stretch.last().map(|s| s.1);
    let stretch: Vec<f64> = stretch.into_iter().map(|s| s.0).collect();
    let n = stretch.len().max(1) as f64;
    let share = |limit: f64| stretch.iter().filter(|&&s| s > limit).count() as f64 / n;
    let volume = section_volume_extremes(puppet, now);
    Surface {
        worst: stretch.last().copied().unwrap_or(1.0),
        worst_edge,
        p99: stretch
            .get(((stretch.len() as f64 * 0.99) as usize).min(stretch.len().saturating_sub(1)))
            .copied()
            .unwrap_or(1.0),
        over_1_5: share(1.5),
        over_2: share(2.0),
        crossing: new_crossings(rest, now, &puppet.mesh.triangles),
        volume: volume.map(|(change, _)| change),
        volume_sections: volume.map(|(_, s)| s),
        whole: {
            let all = vec![true; puppet.mesh.triangles.len()];
            let at_rest = cone_volume(rest, &puppet.mesh.triangles, &all, DVec3::ZERO);
            let posed = cone_volume(now, &puppet.mesh.triangles, &all, DVec3::ZERO);
            if at_rest.abs() > 0.0 {
                posed / at_rest - 1.0
            } else {
                0.0
            }
        },
        behind: {
            // In the vertex's own medial radius, at least the median over the vertices
            // with a skeleton of their own (a rider's is 0: a snake's two finely made
            // eyes hold most of its vertices): flesh a contact squashes moves a share of
            // its own radius (a thigh pressed by the other thigh, a few centimetres), a
            // piece caught or left behind more.
            let distance = &puppet.skeleton.distance;
            let mut d: Vec<f64> = distance.iter().copied().filter(|&r| r > 0.0).collect();
            let floor = crate::stats::median(&mut d)
                .unwrap_or(1.0)
                .max(f64::MIN_POSITIVE);
            targets(puppet, local)
                .iter()
                .zip(now)
                .enumerate()
                .map(|(i, (t, x))| {
                    t.distance(*x) / distance.get(i).map_or(floor, |&r| r.max(floor))
                })
                .fold(0.0, f64::max)
        },
        nan: false,
    }
}

/// The largest edge stretch (posed length over rest length) of `puppet`'s surface as its
/// simulation holds it now (infinite where a position is not finite).
pub fn worst_stretch(puppet: &Puppet) -> f64 {
    let rest = &puppet.mesh.positions;
    let x = puppet.sim.positions();
    let mut worst = 1.0f64;
    for t in &puppet.mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let (a, b) = (a as usize, b as usize);
            let r = rest[a].distance(rest[b]);
            let now = x.get(a).as_dvec3().distance(x.get(b).as_dvec3());
            if r > 0.0 {
                let s = now / r;
                worst = if s.is_finite() {
                    worst.max(s)
                } else {
                    f64::INFINITY
                };
            }
        }
    }
    worst
}
