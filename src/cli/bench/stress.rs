//! `puppet bench --stress`: randomized scenarios that try to break the solver.
//!
//! Each scenario draws a mesh (an icosahedron of 12 vertices up to Spot subdivided once, 11.7k
//! vertices), a scale (1e-4, 1 or 1e4), up to two random cuts (half with a joint band of any width), every parameter anywhere in
//! its range with a bias to the extremes (`C_vd` 0..1, `D` from 1e-6 to the maximum the UI
//! allows, `d_B` 0..1, `sl_max` 1..3, `f_min` 0..1, 1..64 reduction iterations, either
//! constraint), a fixed step from 1/240 to 1/60 s and frames from 1/240 to 1/10 s long (a
//! long frame runs several fixed steps, as the window does), and poses that jump by up to
//! 180° (and up to half the model size) in one frame, or to a random pose of every joint at
//! once (`puppet::puppet::poses`: ±60°, ±90° at the root), the bands blended over the mesh. After every step it checks: every
//! coordinate finite, every mass point inside its constraint region (within 1e-5 of the
//! model size), and bounded motion: no mass point moves farther in one step than its
//! target moved plus the diameter of its region; and no surface spring between two points
//! in their regions stretches beyond its two targets' distance by more than their play
//! around them. It reports the worst surface-spring strain seen (the bones' own: a random
//! pivot stretches them without bound) and the worst beyond the bones'.
//!
//! Half the scenarios have gravity in a random direction up to 10 g, up along any of the
//! six axis directions, a third a floor across it (anywhere from below the puppet to its
//! middle, friction 0..1: points on it may leave their constraint, none may be below it),
//! half collision between sections (each new pose held back by the pose limit where parts
//! meet, as every path that poses a part is; now and then turned on or off mid-scenario,
//! whatever the pose), a third one to three material layers (by
//! section or painted per vertex with weights 0, 1 or random, each material drawn like the
//! parameters), a third pin weights (0, 1 or random), and the bone-spring stiffening
//! exponent is drawn from 0 to 4. A quarter of the scenarios are rigged by a random skin
//! (2 to 6 joints, every vertex weighted to its four nearest) instead of random cuts: its
//! joints as skin cuts, its weights mixing the sections (`joints::skin`).

use super::table;
use anyhow::{bail, Result};
use glam::{DQuat, DVec3, Vec3};
use puppet::bench::scenario::Scenario;
use puppet::joints::{Cut, Joints, Local, Shape, ROOT};
use puppet::mesh::{self, shapes, subdivide_loop, Mesh};
use puppet::random::SplitMix;
use puppet::sim::{
    Constraint, Layer, Material, Params, Regions, Simulation, Solver, World, MAX_GRAVITY,
    MAX_STIFFENING, MAX_STIFFNESS, REFERENCE_STEP,
};

/// Steps a point stays exempt from its region after a contact last held it (its value in
/// `pushed` when held): it comes back in the step after the contact lets go, or, in a
/// sleeping tile, which that wakes, in the one after that.
const HELD: u8 = 3;

struct Rng(SplitMix);

impl Rng {
    fn unit(&mut self) -> f64 {
        (self.0.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn below(&mut self, n: usize) -> usize {
        (self.unit() * n as f64) as usize % n.max(1)
    }
    /// Uniform in `lo..hi`, or one of the ends with probability 1/4 each.
    fn extreme(&mut self, lo: f64, hi: f64) -> f64 {
        match self.below(4) {
            0 => lo,
            1 => hi,
            _ => self.range(lo, hi),
        }
    }
    fn direction(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            if v.length_squared() > 1e-6 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

#[derive(serde::Serialize, Default)]
struct Report {
    seed: u64,
    scenarios: usize,
    steps: u64,
    vertex_steps: u64,
    /// The largest surface-spring strain: the bones' own (a random pivot stretches
    /// them), plus what the points' play around their targets adds.
    worst_strain: f64,
    worst_strain_scenario: String,
    /// The largest stretch of a spring beyond its targets' distance, over its rest length
    /// (bounded by its points' play by the checks).
    worst_strain_beyond_bones: f64,
    /// Largest one-step displacement as a share of its bound (≤ 1 by the checks).
    worst_motion_share: f64,
    /// Largest constraint excess seen, relative to the model size (≤ 1e-5 by the checks).
    worst_constraint_excess: f64,
    /// Joint bands drawn that bend as an arc and as a fan (see `joints::band`).
    arcs: usize,
    fans: usize,
    /// Random poses of every joint at once drawn (`puppet::puppet::poses`).
    poses: usize,
    /// New poses the pose limit held back where parts meet (collision on).
    held: usize,
    /// Times collision was turned on or off in the middle of a scenario, the pose as it
    /// was (parts may press when it comes on).
    toggled: usize,
    /// Scenarios with up along each axis direction (+x, −x, +y, −y, +z, −z).
    up: [usize; 6],
    /// Scenarios rigged by a random skin (its joints as skin cuts, its weights mixing
    /// the sections: `joints::skin`), and the mixes they had.
    skins: usize,
    mixes: usize,
    /// Scenarios on a mesh in pieces, its parts attached where they meet.
    pieces: usize,
    /// Scenarios on a mesh with riders (small separate parts that go with a host), and
    /// the riders' transforms made rigid about a host that moves with a band
    /// (`joints::band::Twin`) they had.
    riders: usize,
    twins: usize,
    /// How many scenarios drew each option (so a run can show every one was tried).
    drawn: Drawn,
    seconds: f64,
}

/// Scenarios that drew each option of [`random_params`] and [`random_regions`].
#[derive(serde::Serialize, Default)]
struct Drawn {
    circumsphere: usize,
    spring_reduction: usize,
    gravity: usize,
    floor: usize,
    collision: usize,
    /// Collision with the body's flesh giving (`flesh` > 0).
    soft_flesh: usize,
    stiffening: usize,
    layers: usize,
    pins: usize,
}

/// One base mesh with its skeletal distances.
struct Base {
    name: &'static str,
    mesh: Mesh,
    distance: Vec<f64>,
}

fn bases() -> Result<Vec<Base>> {
    let (spot, _) = mesh::parse_obj(crate::cli::DEFAULT_MESH)?;
    let meshes: Vec<(&'static str, Mesh)> = vec![
        ("icosahedron", shapes::icosphere(1.0, 0)),
        ("icosphere-2", shapes::icosphere(1.0, 2)),
        ("capsule", shapes::capsule(0.3, 0.8, 6, 6, 12)),
        ("torus", shapes::torus(1.0, 0.3, 24, 8)),
        ("pieces", pieces()),
        ("spot", spot.clone()),
        ("spot-subdivided", subdivide_loop(&spot)),
    ];
    meshes
        .into_iter()
        .map(|(name, mesh)| {
            let normals = mesh::vertex_normals(&mesh)?;
            let sk = puppet::skeleton::build(
                &mesh,
                &normals,
                &puppet::skeleton::SkeletonParams::default(),
                puppet::progress::silent(),
            )?;
            Ok(Base {
                name,
                mesh,
                distance: sk.distance,
            })
        })
        .collect()
}

/// A character in three pieces, each pushed into the next: a body, an upper arm, a
/// forearm (attached where they meet, `mesh::attachments`), and two riders, small
/// separate spheres beside the shoulder and on the upper arm (each goes with its host,
/// rigid where the host's band swells: `joints::band::Twin`).
fn pieces() -> Mesh {
    let mut out = shapes::capsule(0.3, 0.5, 6, 6, 12);
    let piece = shapes::capsule(0.12, 0.3, 4, 4, 10);
    for x in [0.6, 1.3] {
        let base = out.positions.len() as u32;
        // Lying along x, its middle at (x, 0.3, 0).
        out.positions.extend(
            piece
                .positions
                .iter()
                .map(|p| DVec3::new(p.y + x, 0.3 - p.x, p.z)),
        );
        out.triangles
            .extend(piece.triangles.iter().map(|t| t.map(|v| v + base)));
    }
    for (centre, radius) in [
        (DVec3::new(0.0, 0.3, 0.34), 0.03),
        (DVec3::new(0.6, 0.45, 0.0), 0.025),
    ] {
        let rider = shapes::icosphere(radius, 1);
        let base = out.positions.len() as u32;
        out.positions
            .extend(rider.positions.iter().map(|&p| p + centre));
        out.triangles
            .extend(rider.triangles.iter().map(|t| t.map(|v| v + base)));
    }
    out
}

/// `puppet bench stress`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Seed of the random scenarios.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Simulation steps in all.
    #[arg(long, default_value_t = 100_000)]
    steps: u64,
    /// Print JSON instead of a summary.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &Args) -> Result<()> {
    let started = std::time::Instant::now();
    let bases = bases()?;
    let mut rng = Rng(SplitMix(args.seed));
    let mut report = Report {
        seed: args.seed,
        ..Report::default()
    };
    while report.steps < args.steps {
        // The largest mesh rarely and briefly, so short runs still see many scenarios.
        let b = if rng.below(10) == 0 {
            bases.len() - 1
        } else {
            rng.below(bases.len() - 1)
        };
        let base = &bases[b];
        let scale = [1e-4, 1.0, 1e4][rng.below(3)];
        let mesh = Mesh {
            positions: base.mesh.positions.iter().map(|p| *p * scale).collect(),
            triangles: base.mesh.triangles.clone(),
        };
        let distance: Vec<f64> = base.distance.iter().map(|d| d * scale).collect();
        let normals = mesh::vertex_normals(&mesh)?;
        let (lo, hi) = mesh.bounds();
        let scenario = Scenario {
            joints: Joints::new(&[], ROOT),
            normals,
            distance,
            limb: 0,
            axis: DVec3::X,
            swing_seconds: 0.0,
            diagonal: (hi - lo).length(),
            mesh,
        };
        let name = format!(
            "#{} {} x{scale:e} (seed {})",
            report.scenarios, base.name, args.seed
        );
        let budget = if b == bases.len() - 1 { 100 } else { 2_000 };
        let steps = (rng.range(50.0, budget as f64) as u64).min(args.steps - report.steps);
        run_scenario(&scenario, &name, steps.max(1), &mut rng, &mut report)?;
        report.scenarios += 1;
    }
    report.seconds = started.elapsed().as_secs_f64();
    if args.json {
        table::json(&report)?;
    } else {
        println!(
            "stress (seed {}): {} scenarios ({} joint bands bent as arcs, {} as fans, {} rigged by a skin), {} steps, {} vertex-steps in {:.1} s: no NaN, every point inside its constraint, motion bounded",
            report.seed, report.scenarios, report.arcs, report.fans, report.skins, report.steps, report.vertex_steps, report.seconds
        );
        println!(
            "worst surface-spring strain {:.3} ({}), {:.3} beyond its bones'; worst motion {:.3} of its bound; worst constraint excess {:.1e} of the model size",
            report.worst_strain,
            report.worst_strain_scenario,
            report.worst_strain_beyond_bones,
            report.worst_motion_share,
            report.worst_constraint_excess
        );
    }
    Ok(())
}

fn random_params(rng: &mut Rng) -> Params {
    // Drawn in this order (the figures quoted for a seed depend on it).
    let damping = rng.extreme(0.0, 1.0) as f32;
    let stiffness = if rng.below(4) == 0 {
        1e-6
    } else {
        rng.extreme(0.0, MAX_STIFFNESS as f64) as f32
    };
    let bone_distance = rng.extreme(0.0, 1.0) as f32;
    let max_length = rng.extreme(1.0, 3.0) as f32;
    let min_length = rng.extreme(0.0, 1.0) as f32;
    let solver = Solver {
        constraint: if rng.below(2) == 0 {
            Constraint::Circumsphere
        } else {
            Constraint::SpringReduction
        },
        reduction_iterations: 1 + rng.below(64) as u32,
        time_step: rng.range(1.0 / 240.0, REFERENCE_STEP as f64) as f32,
    };
    let world = World {
        gravity: if rng.below(2) == 0 {
            (rng.direction() * rng.extreme(0.0, MAX_GRAVITY as f64))
                .to_array()
                .map(|g| g as f32)
        } else {
            [0.0; 3]
        },
        floor: rng.below(3) == 0,
        floor_height: 0.0,
        floor_friction: rng.extreme(0.0, 1.0) as f32,
        ..World::default()
    };
    let material = Material {
        damping,
        stiffness,
        bone_distance,
        max_length,
        min_length,
        stiffening: rng.below(MAX_STIFFENING as usize + 1) as u32,
    };
    // Collision last, so the draws before it are what they were.
    let world = World {
        collision: rng.below(2) == 0,
        collision_margin: rng.extreme(0.0, puppet::sim::params::MAX_MARGIN as f64) as f32,
        flesh: rng.extreme(0.0, puppet::sim::params::MAX_FLESH as f64) as f32,
        ..world
    };
    Params {
        material,
        solver,
        world,
    }
}

/// Material layers (by section, or painted at random with soft weights) and pin weights at
/// extreme values, each in a third of the scenarios.
/// A skin of 2 to 6 joints at the skeletal points of random vertices, each below the
/// nearest joint drawn before it, every vertex weighted to its four nearest joints by
/// inverse squared distance.
fn random_skin(rng: &mut Rng, points: &[DVec3]) -> puppet::mesh::Skin {
    use puppet::mesh::skin::{SkinJoint, Weights, NO_WEIGHTS};
    let k = 2 + rng.below(5);
    let at: Vec<DVec3> = (0..k).map(|_| points[rng.below(points.len())]).collect();
    let joints: Vec<SkinJoint> = (0..k)
        .map(|j| SkinJoint {
            name: format!("joint{j}"),
            parent: (0..j).min_by(|&a, &b| at[a].distance(at[j]).total_cmp(&at[b].distance(at[j]))),
            rest: glam::DMat4::from_translation(at[j]),
            weight: 0.0,
        })
        .collect();
    let weights: Vec<Weights> = points
        .iter()
        .map(|p| {
            let mut near: Vec<(u32, f64)> = at
                .iter()
                .enumerate()
                .map(|(j, a)| (j as u32, 1.0 / (a.distance_squared(*p) + 1e-12)))
                .collect();
            near.sort_by(|a, b| b.1.total_cmp(&a.1));
            near.truncate(4);
            let total: f64 = near.iter().map(|n| n.1).sum();
            let mut w = NO_WEIGHTS;
            for (slot, n) in w.iter_mut().zip(&near) {
                *slot = (n.0, (n.1 / total) as f32);
            }
            w
        })
        .collect();
    puppet::mesh::Skin {
        joints,
        clips: Vec::new(),
        vertex_joint: weights.iter().map(|w| w[0].0).collect(),
        weights,
    }
}

fn random_regions(rng: &mut Rng, section_of: &[u16]) -> Regions {
    let n = section_of.len();
    let mut regions = Regions::default();
    let weight = |rng: &mut Rng| match rng.below(4) {
        0 => 1.0,
        1 => rng.unit() as f32,
        _ => 0.0,
    };
    if rng.below(3) == 0 {
        for _ in 0..1 + rng.below(3) {
            // A whole set of parameters drawn, as ever, though a layer keeps its material.
            let material = random_params(rng).material;
            let by_section: Vec<f32> = (0..64).map(|_| weight(rng)).collect();
            let painted = rng.below(2) == 0;
            let weight = (0..n)
                .map(|i| {
                    if painted {
                        weight(rng)
                    } else {
                        by_section[section_of[i] as usize % 64]
                    }
                })
                .collect();
            regions.layers.push(Layer { material, weight });
        }
    }
    if rng.below(3) == 0 {
        regions.pin = (0..n).map(|_| weight(rng)).collect();
    }
    regions
}

fn run_scenario(
    scenario: &Scenario,
    name: &str,
    steps: u64,
    rng: &mut Rng,
    report: &mut Report,
) -> Result<()> {
    let params = random_params(rng);
    let (lo, hi) = scenario.mesh.bounds();
    let size = scenario.diagonal;
    // Up to two random cuts, planes, spheres or boxes, some sharing their pivot with the
    // section they cut (a refused cut, e.g. one that misses the skeleton, is skipped).
    let points: Vec<DVec3> = scenario
        .mesh
        .positions
        .iter()
        .zip(&scenario.normals)
        .zip(&scenario.distance)
        .map(|((p, n), d)| *p - *d * *n)
        .collect();
    // With the mesh, so the bands blend over the surface (`joints::blend`).
    // Riders go with their hosts, as a loaded character's do.
    let parts = mesh::Parts::of(&scenario.mesh);
    let hosts = if parts.riders() > 0 {
        report.riders += 1;
        parts.hosts(&scenario.mesh.positions)
    } else {
        Vec::new()
    };
    let mut joints = Joints::with_mesh(&points, &scenario.mesh.triangles, &hosts, ROOT);
    let attachments = mesh::attachments(&scenario.mesh);
    if !attachments.is_empty() {
        report.pieces += 1;
    }
    joints.attach_parts(&attachments);
    joints.set_surface(&scenario.mesh.positions, &scenario.distance);
    // A quarter of the scenarios are rigged by a random skin instead of random cuts.
    let skinned = rng.below(4) == 0;
    if skinned {
        joints.set_skin(Some(std::sync::Arc::new(random_skin(rng, &points))));
        if let Some(skin) = joints.skin_joints() {
            joints = joints.without_cuts(&skin.root);
            for cut in skin.cuts {
                let _ = joints.add_cut(cut);
            }
        }
        report.skins += 1;
        report.mixes += joints.mixes().len();
    }
    let name = &if skinned {
        format!("{name}, rigged by a random skin")
    } else {
        name.to_string()
    };
    for c in 0..if skinned { 0 } else { rng.below(3) } {
        let point = lo + (hi - lo) * DVec3::new(rng.unit(), rng.unit(), rng.unit());
        let sections: Vec<String> = joints.sections().iter().map(|s| s.name.clone()).collect();
        let _ = joints.add_cut(Cut {
            name: format!("cut{c}"),
            section: sections[rng.below(sections.len())].clone(),
            point,
            normal: rng.direction(),
            pivot: None,
            connected: false,
            // Half the cuts with a joint band of any width.
            band: (rng.below(2) == 1).then(|| rng.range(0.0, puppet::joints::MAX_BAND)),
            shape: match rng.below(3) {
                0 => Shape::Plane,
                1 => Shape::Sphere {
                    radius: rng.range(0.02, 0.6) * size,
                },
                _ => Shape::Box {
                    size: DVec3::new(rng.unit(), rng.unit(), rng.unit()) * size + 1e-3 * size,
                },
            },
            shared_pivot: rng.below(3) == 0,
        });
    }
    report.twins += joints.twins();
    for band in joints.bands().iter().flatten() {
        if band.arc {
            report.arcs += 1;
        } else {
            report.fans += 1;
        }
    }
    let mut sim = Simulation::new(scenario.rig(params.material.bone_distance), params);
    sim.set_sections(joints.transform_of().to_vec());
    sim.set_joint_sections(joints.joint_sections());
    let regions = random_regions(rng, joints.section_of());
    let drawn = &mut report.drawn;
    drawn.layers += usize::from(!regions.layers.is_empty());
    drawn.pins += usize::from(!regions.pin.is_empty());
    sim.set_regions(regions);
    let p = *sim.params();
    match p.solver.constraint {
        Constraint::Circumsphere => drawn.circumsphere += 1,
        Constraint::SpringReduction => drawn.spring_reduction += 1,
    }
    drawn.gravity += usize::from(p.world.gravity != [0.0; 3]);
    drawn.floor += usize::from(p.world.floor);
    drawn.collision += usize::from(p.world.collision);
    drawn.soft_flesh += usize::from(p.world.collision && p.world.flesh > 0.0);
    drawn.stiffening += usize::from(p.material.stiffening > 0);
    // Up along any of the six axis directions (the floor lies across it).
    sim.set_up(rng.direction().as_vec3());
    let up = sim.up();
    report.up[2 * up.axis + usize::from(up.sign < 0.0)] += 1;
    // The floor somewhere between a little below the puppet and its middle.
    let floor = p.world.floor.then(|| {
        let height = rng.range(-0.1, 0.5) * (hi - lo)[up.axis];
        let mut q = p;
        q.world.floor_height = height as f32;
        sim.set_params(q);
        sim.floor_height().map_or(f64::NEG_INFINITY, f64::from)
    });
    let mut p = *sim.params();
    let n = sim.rig().len();
    let mut local = vec![Local::default(); joints.sections().len()];
    let mut pose = joints.pose(&local);
    let mut targets: Vec<Vec3> = (0..n).map(|i| sim.target(i)).collect();
    let mut before: Vec<Vec3> = sim.positions().to_vec();
    let tolerance = 1e-5 * size;
    // Per vertex: a contact held it in one of the last three steps (it may be outside its
    // constraint, and come back from there: in the step after the contact lets go, or,
    // in a sleeping tile, which that wakes, in the one after that).
    let mut pushed = vec![0u8; n];
    let h = p.solver.time_step as f64;
    let mut done = 0;
    let mut debt = 0.0;
    while done < steps {
        // A frame: maybe a pose jump, then as many fixed steps as the frame holds (≤ 8).
        // Now and then a cut's pivot moves anywhere near the puppet (its bands follow).
        if joints.sections().len() > 1 && rng.below(20) == 0 {
            let k = 1 + rng.below(joints.sections().len() - 1);
            let to = lo + (hi - lo) * DVec3::new(rng.unit(), rng.unit(), rng.unit()) * 1.4;
            joints.set_pivot(k, to - (hi - lo) * 0.2);
            sim.set_sections(joints.transform_of().to_vec());
            sim.set_joint_sections(joints.joint_sections());
            pose = joints.pose(&local);
        }
        // Now and then collision is turned on or off, whatever the pose (a puppeteer's
        // checkbox): parts may already press when it comes on.
        if rng.below(40) == 0 {
            p.world.collision = !p.world.collision;
            sim.set_params(p);
            report.toggled += 1;
        }
        let was = local.clone();
        if rng.below(12) == 0 {
            // A puppeteer's pose: every joint at once (`puppet::poses`).
            local = puppet::puppet::poses::random_pose(
                &joints,
                puppet::puppet::poses::Spread::default(),
                &mut rng.0,
            );
            pose = joints.pose(&local);
            report.poses += 1;
        } else if rng.below(3) == 0 {
            let s = rng.below(local.len());
            local[s] = Local {
                rotation: DQuat::from_axis_angle(
                    rng.direction(),
                    rng.range(-180.0, 180.0).to_radians(),
                ),
                translation: rng.direction() * rng.range(0.0, 0.5) * size,
            };
            pose = joints.pose(&local);
        }
        // With collision on, a new pose is held back where parts meet, as every path that
        // poses a part does (`Puppet::hold_back`).
        if p.world.collision && local != was {
            let mut balls = joints.balls();
            balls.set_squash(f64::from(p.world.flesh));
            if let Some(reached) = balls.hold(
                &joints,
                &was,
                &local,
                &mut Vec::new(),
                &mut Default::default(),
            ) {
                local = reached;
                pose = joints.pose(&local);
                report.held += 1;
            }
        }
        debt += rng.range(1.0 / 240.0, 0.1);
        let mut k = 0;
        while debt >= h && k < 8 && done < steps {
            sim.step(&pose);
            debt -= h;
            k += 1;
            done += 1;
            pushed.iter_mut().for_each(|p| *p = p.saturating_sub(1));
            for i in sim.in_contact() {
                pushed[i] = HELD;
            }
            check(
                &sim,
                &p,
                floor,
                &mut targets,
                &mut before,
                &pushed,
                tolerance,
                size,
                name,
                report,
            )?;
        }
        if k == 8 {
            debt = 0.0;
        }
    }
    report.steps += done;
    report.vertex_steps += done * n as u64;
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn check(
    sim: &Simulation,
    base: &Params,
    floor: Option<f64>,
    targets: &mut [Vec3],
    before: &mut [Vec3],
    pushed: &[u8],
    tolerance: f64,
    size: f64,
    name: &str,
    report: &mut Report,
) -> Result<()> {
    let up = sim.up();
    let x = sim.positions();
    let rig = sim.rig();
    let step = sim.steps();
    // How far each point may lie from its target: its region; unbounded on the floor or
    // while a contact holds it or it comes back from one.
    let mut reach = vec![f64::INFINITY; rig.len()];
    for i in 0..rig.len() {
        let p = &Params {
            material: sim.regions().material_of(i, &base.material),
            ..*base
        };
        let y = x.get(i);
        if !y.is_finite() {
            bail!("stress scenario {name}, step {step}: vertex {i} is not finite ({y}) with {p:?}");
        }
        let target = sim.target(i);
        let l = rig.bone_length[i] as f64;
        // The region's radius around the target, and the constraint excess.
        let (radius, excess) = if sim.is_static() {
            (0.0, (y - target).length() as f64)
        } else {
            match p.solver.constraint {
                Constraint::Circumsphere => {
                    let rho = (p.material.max_length as f64 - 1.0) * l;
                    (rho, (y - target).length() as f64 - rho)
                }
                Constraint::SpringReduction => {
                    let (bi, bo) = sim.bone_points(i);
                    let (lo, hi) = (
                        p.material.min_length as f64 * l,
                        p.material.max_length as f64 * l,
                    );
                    let excess = [bi, bo]
                        .iter()
                        .map(|b| {
                            let len = (y - *b).length() as f64;
                            (len - hi).max(lo - len)
                        })
                        .fold(f64::MIN, f64::max);
                    ((p.material.max_length as f64 + 1.0) * l, excess)
                }
            }
        };
        // A point on the floor may be outside its constraint (the floor wins); none is
        // below it.
        let (on_floor, lift) = match floor {
            Some(height) => {
                let below = height - up.height(y) as f64;
                if below > tolerance {
                    bail!("stress scenario {name}, step {step}: vertex {i} is {below:e} below the floor with {p:?}");
                }
                // How far the floor reaches into the region now and at the last step.
                let lift = |t: Vec3| (height - (up.height(t) as f64 - radius)).max(0.0);
                (below >= -tolerance, lift(target) + lift(targets[i]))
            }
            None => (false, 0.0),
        };
        // A contact wins over the constraint, as the floor does; such a point comes back
        // from wherever it was put.
        if pushed[i] > 0 {
            targets[i] = target;
            before[i] = y;
            continue;
        }
        if !on_floor {
            reach[i] = radius + tolerance;
            report.worst_constraint_excess = report.worst_constraint_excess.max(excess / size);
            if excess > tolerance {
                bail!("stress scenario {name}, step {step}: vertex {i} is {excess:e} outside its constraint with {p:?}");
            }
        }
        let moved = (y - before[i]).length() as f64;
        let bound = (target - targets[i]).length() as f64 + 2.0 * radius + lift + 2.0 * tolerance;
        if moved > bound {
            bail!("stress scenario {name}, step {step}: vertex {i} moved {moved:e}, more than its bound {bound:e} (radius {radius:e}, lift {lift:e}, from {} to {y}, target {target}, floor {floor:?}), with {p:?}", before[i]);
        }
        if bound > 0.0 {
            report.worst_motion_share = report.worst_motion_share.max(moved / bound);
        }
        targets[i] = target;
        before[i] = y;
    }
    // The skin stretches as far as its bones say (a random pivot stretches them without
    // bound) and no farther than its points' play around their targets.
    for s in &rig.springs {
        if s.rest > 0.0 {
            let (a, b) = (s.a as usize, s.b as usize);
            let len = (x.get(b) - x.get(a)).length() as f64;
            let strain = (len / s.rest as f64 - 1.0).abs();
            if strain > report.worst_strain {
                report.worst_strain = strain;
                report.worst_strain_scenario = name.to_string();
            }
            let play = reach[a] + reach[b];
            if play.is_finite() {
                let bones = (targets[b] - targets[a]).length() as f64;
                let beyond = (len - bones).max(0.0);
                report.worst_strain_beyond_bones =
                    report.worst_strain_beyond_bones.max(beyond / s.rest as f64);
                if beyond > play {
                    bail!("stress scenario {name}, step {step}: the spring {a}–{b} is {len:e} long, {beyond:e} more than its targets lie apart, beyond its points' play {play:e}");
                }
            }
        }
    }
    Ok(())
}
