//! The dynamics: exact rest, constraints after every step, energy decay, Table 1 semantics,
//! thread-count independence and extreme parameters.

mod common;
use glam::{Affine3A, Quat, Vec3};
use puppet::mesh::{parse_obj, vertex_normals};
use puppet::progress::silent;
use puppet::rig::Rig;
use puppet::sim::{
    presets, Constraint, Material, Options, Params, Pose, Simulation, Solver, World,
};
use puppet::skeleton::{build, SkeletonParams};
use std::sync::OnceLock;

/// Spot-small's rig (441 vertices): built once.
fn rig() -> Rig {
    static RIG: OnceLock<Rig> = OnceLock::new();
    RIG.get_or_init(|| {
        let text = std::fs::read(common::test_mesh("spot-small.obj")).unwrap();
        let (mesh, _) = parse_obj(&text).unwrap();
        let normals = vertex_normals(&mesh).unwrap();
        let sk = build(&mesh, &normals, &SkeletonParams::default(), silent()).unwrap();
        Rig::new(&mesh, &normals, &sk.distance, 0.5)
    })
    .clone()
}

fn preset(name: &str) -> Params {
    Params::from(Material::preset(name).unwrap())
}

/// `params` with another constraint.
fn with_constraint(mut params: Params, constraint: Constraint) -> Params {
    params.solver.constraint = constraint;
    params
}

fn turned(deg: f32) -> Pose {
    Pose {
        transforms: vec![Affine3A::from_quat(Quat::from_axis_angle(
            Vec3::new(0.3, 1.0, 0.2).normalize(),
            deg.to_radians(),
        ))],
    }
}

/// Largest distance of a mass point from its (posed) rest position.
fn max_deviation(sim: &Simulation) -> f32 {
    let p = sim.positions();
    (0..sim.rig().len())
        .map(|i| (p.get(i) - sim.target(i)).length())
        .fold(0.0, f32::max)
}

fn assert_constraint(sim: &Simulation, step: usize) {
    let p = *sim.params();
    let rig = sim.rig();
    let scale = 1e-5 * 2.0; // spot-small spans about 2 units
    for i in 0..rig.len() {
        let x = sim.positions().get(i);
        assert!(x.is_finite(), "step {step}: vertex {i} is not finite");
        if let Some(y) = sim.floor_height() {
            // The floor wins over the constraint.
            assert!(x.y >= y, "step {step}: vertex {i} below the floor");
            if x.y == y {
                continue;
            }
        }
        let l = rig.bone_length[i];
        match p.solver.constraint {
            Constraint::Circumsphere => {
                let d = (x - sim.target(i)).length();
                assert!(
                    d <= (p.material.max_length - 1.0) * l + scale,
                    "step {step}: vertex {i} at {d}"
                );
            }
            Constraint::SpringReduction => {
                let (bi, bo) = sim.bone_points(i);
                for b in [bi, bo] {
                    let len = (x - b).length();
                    assert!(
                        len <= p.material.max_length * l + scale
                            && len >= p.material.min_length * l - scale,
                        "step {step}: vertex {i} bone spring {len} outside [{}, {}]",
                        p.material.min_length * l,
                        p.material.max_length * l
                    );
                }
            }
        }
    }
}

/// With sleeping off, so every step computes every point (asleep, a tile stops after
/// `SLEEP_AFTER` steps and the claim would hold whatever the forces did).
#[test]
fn rig_at_rest_stays_exactly_at_rest_for_10000_steps() {
    let awake = puppet::sim::Options {
        sleeping: false,
        ..puppet::sim::Options::default()
    };
    for m in presets() {
        for constraint in [Constraint::Circumsphere, Constraint::SpringReduction] {
            let params = with_constraint(Params::from(m.material), constraint);
            let mut sim = Simulation::with_options(rig(), params, awake);
            let rest = sim.positions().to_vec();
            let pose = Pose::rest(1);
            for _ in 0..10_000 {
                sim.step(&pose);
            }
            assert!(
                sim.positions().to_vec() == rest,
                "{} {constraint:?} drifted",
                m.name
            );
        }
    }
}

#[test]
fn constraints_hold_after_every_step() {
    for constraint in [Constraint::Circumsphere, Constraint::SpringReduction] {
        for m in presets() {
            let params = with_constraint(Params::from(m.material), constraint);
            let mut sim = Simulation::new(rig(), params);
            for step in 0..300 {
                // A violent pose: 90 degrees at once, then swinging.
                let pose = turned(if step < 100 { 90.0 } else { 90.0 - step as f32 });
                sim.step(&pose);
                assert_constraint(&sim, step);
            }
        }
    }
}

#[test]
fn kinetic_energy_decays_with_static_bones() {
    for constraint in [Constraint::Circumsphere, Constraint::SpringReduction] {
        let params = with_constraint(preset("thick skin"), constraint);
        let mut sim = Simulation::new(rig(), params);
        sim.step(&turned(40.0)); // disturbance: a sudden pose change, then held
        let pose = turned(40.0);
        let mut windows = Vec::new();
        for _ in 0..6 {
            let mut e = 0.0;
            for _ in 0..50 {
                sim.step(&pose);
                e += sim.kinetic_energy();
            }
            windows.push(e);
        }
        assert!(windows[0] > 0.0, "the disturbance must move something");
        for w in windows.windows(2) {
            assert!(w[1] <= w[0], "{constraint:?}: energy grew: {windows:?}");
        }
        assert!(
            windows[5] < 1e-6 * windows[0],
            "{constraint:?}: not settled: {windows:?}"
        );
    }
}

#[test]
fn sl_max_one_means_no_elastic_movement() {
    let mut params = preset("water");
    params.material.max_length = 1.0;
    let mut sim = Simulation::new(rig(), params);
    for step in 0..50 {
        sim.step(&turned(step as f32 * 3.0));
        assert_eq!(max_deviation(&sim), 0.0);
    }
    // Plastic (bones on the surface) likewise.
    let mut sim = Simulation::new(rig(), preset("plastic"));
    sim.step(&turned(60.0));
    assert_eq!(max_deviation(&sim), 0.0);
}

/// Deformation under the same pose change, and settle time (steps until the motion is below
/// 1e-9 of the initial kinetic energy), per preset.
fn response(params: Params) -> (f32, usize) {
    let mut sim = Simulation::new(rig(), params);
    let pose = turned(45.0);
    let mut deform = 0.0f32;
    let mut settle = 0;
    let mut e0 = 0.0;
    for step in 0..3000 {
        sim.step(&pose);
        deform = deform.max(max_deviation(&sim));
        let e = sim.kinetic_energy();
        if step == 0 {
            e0 = e;
        }
        if e > 1e-9 * e0 {
            settle = step;
        }
    }
    (deform, settle)
}

#[test]
fn table_1_semantics() {
    let (skin, skin_settle) = response(preset("skin"));
    let (thick, thick_settle) = response(preset("thick skin"));
    let (water, water_settle) = response(preset("water"));
    let (cloth, cloth_settle) = response(preset("tight cloth"));
    let (plastic, _) = response(preset("plastic"));
    // Deformation follows the movement room (sl_max - 1) * d_B.
    assert_eq!(plastic, 0.0);
    assert!(
        skin < thick && skin < cloth,
        "skin {skin} thick {thick} cloth {cloth}"
    );
    assert!(
        thick < water && cloth < water,
        "thick {thick} cloth {cloth} water {water}"
    );
    // Water (C_vd = 0.99) oscillates longest. (Between the others the movement room matters
    // as much as C_vd: a tight constraint damps too, as the paper notes.)
    for other in [skin_settle, thick_settle, cloth_settle] {
        assert!(water_settle > other, "water {water_settle} vs {other}");
    }
    // With everything else equal and in the underdamped range of the presets, more velocity
    // kept means longer oscillation. (Far below, e.g. C_vd = 0.5, the system is overdamped
    // and creeps: settle time is not monotonic there, as for any damped oscillator.)
    let settle = |c: f32| {
        let mut params = preset("thick skin");
        params.material.damping = c;
        response(params).1
    };
    let (a, b, c) = (settle(0.85), settle(0.93), settle(0.99));
    assert!(
        a < b && b < c,
        "settle steps at C_vd 0.85/0.93/0.99: {a} {b} {c}"
    );
}

#[test]
fn same_result_with_one_and_two_threads() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut sim = Simulation::new(rig(), preset("water"));
            for step in 0..200 {
                sim.step(&turned(step as f32));
            }
            sim.positions().to_vec()
        })
    };
    assert!(run(1) == run(2));
}

#[test]
fn results_do_not_depend_on_the_step_size_much() {
    // The same preset at 60 and 240 steps/s: the deformation under the same pose change
    // agrees (D and C_vd are defined per reference step).
    let at = |h: f32| {
        let mut sim = Simulation::new(
            rig(),
            Params {
                solver: Solver {
                    time_step: h,
                    ..Solver::default()
                },
                ..preset("skin")
            },
        );
        let pose = turned(45.0);
        let mut peak = 0.0f32;
        for _ in 0..(1.0 / h) as usize {
            sim.step(&pose);
            peak = peak.max(max_deviation(&sim));
        }
        peak
    };
    let (a, b) = (at(1.0 / 60.0), at(1.0 / 240.0));
    assert!(
        (a - b).abs() <= 0.25 * a.max(b),
        "peak deformation {a} vs {b}"
    );
}

#[test]
fn extreme_parameters_never_produce_nan() {
    let mut rng = puppet::random::SplitMix(5);
    let mut u = || (rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
    for _ in 0..20 {
        // Drawn in the order the test has always drawn them.
        let damping = [0.0, 1.0, u()][(u() * 3.0) as usize % 3];
        let stiffness = [0.0, 1e-6, 1.0, 5.0][(u() * 4.0) as usize % 4];
        let bone_distance = [0.0, 1.0, u()][(u() * 3.0) as usize % 3];
        let max_length = 1.0 + 2.0 * u();
        let min_length = u();
        let solver = Solver {
            constraint: if u() < 0.5 {
                Constraint::Circumsphere
            } else {
                Constraint::SpringReduction
            },
            reduction_iterations: 1 + (u() * 8.0) as u32,
            time_step: [1.0 / 240.0, 1.0 / 10.0, f32::NAN][(u() * 3.0) as usize % 3],
        };
        let world = World {
            gravity: [u() * 40.0 - 20.0, f32::NAN, -u()],
            floor: u() < 0.5,
            floor_height: u() - 0.5,
            floor_friction: u() * 2.0,
            ..World::default()
        };
        let material = Material {
            damping,
            stiffness,
            bone_distance,
            max_length,
            min_length,
            stiffening: (u() * 8.0) as u32,
        };
        // Drawn last, so the draws before are what they were.
        let world = World {
            collision: u() < 0.5,
            collision_margin: [u() * 0.2 - 0.05, f32::NAN][(u() * 2.0) as usize % 2],
            flesh: [u() * 1.5 - 0.25, f32::NAN][(u() * 2.0) as usize % 2],
            ..world
        };
        let params = Params {
            material,
            solver,
            world,
        };
        let mut sim = Simulation::new(rig(), params);
        for step in 0..100 {
            let pose = turned(u() * 360.0 - 180.0);
            sim.step(&pose);
            assert_constraint(&sim, step);
        }
    }
}

#[test]
fn changing_bone_distance_is_cheap_and_consistent() {
    let mut sim = Simulation::new(rig(), preset("water"));
    let d = sim.rig().skeletal_distance.clone();
    let mut params = preset("water");
    params.material.bone_distance = 0.25;
    sim.set_params(params);
    for (l, d) in sim.rig().bone_length.iter().zip(&d) {
        assert!((l - 0.25 * d).abs() <= 1e-6 * d.max(1.0));
    }
    params.material.bone_distance = 0.0;
    sim.set_params(params);
    assert!(sim.params().is_static());
}

#[test]
fn the_guides_material_example_parses() {
    let readme = include_str!("../docs/guide.md");
    let start = readme
        .find("```toml\n")
        .expect("the guide has a TOML example")
        + 8;
    let len = readme[start..].find("```").unwrap();
    let materials = puppet::sim::parse_materials(&readme[start..start + len]).unwrap();
    assert_eq!(materials[0].name, "jelly");
}

/// Two sections of spot-small: the vertices with `x > 0.3` (the head end) form section 1.
fn two_sections(sim: &mut Simulation) -> Vec<u16> {
    let sections: Vec<u16> = sim
        .rig()
        .rest
        .iter()
        .map(|p| u16::from(p.x > 0.3))
        .collect();
    sim.set_sections(sections.clone());
    sections
}

fn head_turned(deg: f32) -> Pose {
    Pose {
        transforms: vec![
            Affine3A::IDENTITY,
            Affine3A::from_rotation_translation(
                Quat::from_axis_angle(Vec3::Y, deg.to_radians()),
                Vec3::ZERO,
            ),
        ],
    }
}

/// Where the CPU has AVX2 (its build of the kernel runs only there). Without it the two
/// runs would both be portable: the test says so and stops, and fails under CI, whose
/// machine has AVX2.
#[test]
fn simd_and_portable_kernels_agree_bit_for_bit() {
    #[cfg(target_arch = "x86_64")]
    let avx2 = std::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    let avx2 = false;
    if !avx2 {
        assert!(
            std::env::var_os("CI").is_none(),
            "no AVX2 on the CI machine: the SIMD kernel cannot be compared"
        );
        eprintln!("not run: this CPU has no AVX2, so both kernels would be the portable one");
        return;
    }
    for constraint in [Constraint::Circumsphere, Constraint::SpringReduction] {
        let run = |simd: bool| {
            let options = Options {
                simd,
                ..Options::default()
            };
            let params = with_constraint(preset("water"), constraint);
            let mut sim = Simulation::with_options(rig(), params, options);
            for step in 0..200 {
                sim.step(&turned(step as f32 * 2.0));
            }
            sim.positions().to_vec()
        };
        assert!(run(true) == run(false), "{constraint:?}");
    }
}

/// Tiles whose slots move with different sections gather each slot's transform; tiles of
/// one slot take their only section's. Both, and both kernels, give the same positions.
#[test]
fn tiles_mixing_sections_take_each_slots_own_transform() {
    let run = |tile: usize, simd: bool| {
        let options = Options {
            sleeping: false,
            tile,
            simd,
            ..Options::default()
        };
        let rig = rig();
        let sections = (0..rig.len()).map(|i| (i % 3) as u16).collect();
        let mut sim = Simulation::with_options(rig, preset("skin"), options);
        sim.set_sections(sections);
        for step in 0..60 {
            let a = step as f32;
            let pose = Pose {
                transforms: vec![
                    Affine3A::IDENTITY,
                    Affine3A::from_rotation_translation(
                        Quat::from_rotation_x(0.01 * a),
                        Vec3::new(0.0, 0.001 * a, 0.0),
                    ),
                    Affine3A::from_rotation_translation(
                        Quat::from_rotation_z(-0.02 * a),
                        Vec3::new(0.002 * a, 0.0, 0.0),
                    ),
                ],
            };
            sim.step(&pose);
        }
        sim.positions().to_vec()
    };
    let one_slot_tiles = run(1, false);
    assert!(one_slot_tiles == run(256, false) && one_slot_tiles == run(256, true));
}

#[test]
fn tile_size_does_not_change_the_result_without_sleeping() {
    let run = |tile: usize| {
        let options = Options {
            sleeping: false,
            tile,
            ..Options::default()
        };
        let mut sim = Simulation::with_options(rig(), preset("skin"), options);
        for step in 0..100 {
            sim.step(&turned(step as f32));
        }
        sim.positions().to_vec()
    };
    let a = run(256);
    assert!(a == run(1) && a == run(37) && a == run(100_000));
}

#[test]
fn still_tiles_sleep_and_a_pose_change_wakes_them_in_the_same_step() {
    let mut sim = Simulation::new(rig(), preset("skin"));
    two_sections(&mut sim);
    // Disturb, then let it settle with a constant pose: every tile falls asleep.
    for _ in 0..5 {
        sim.step(&head_turned(30.0));
    }
    let mut steps = 0;
    while !sim.is_asleep() {
        sim.step(&head_turned(30.0));
        steps += 1;
        assert!(steps < 5_000, "never fell asleep");
    }
    // Asleep, a step with the same pose integrates no tile and changes nothing at all.
    let before = sim.positions().to_vec();
    sim.step(&head_turned(30.0));
    assert!(sim.positions().to_vec() == before);
    let (tiles, integrated) = sim.tiles();
    assert!(tiles >= 1 && integrated == 0);
    // A pose change at step k moves the sleeping head at step k.
    sim.step(&head_turned(45.0));
    let after = sim.positions().to_vec();
    let moved = (0..after.len())
        .filter(|&i| sim.rig().rest[i].x > 0.3 && after[i] != before[i])
        .count();
    let head = sim.rig().rest.iter().filter(|p| p.x > 0.3).count();
    assert!(
        moved > head / 2,
        "only {moved} of {head} head vertices moved"
    );
    // A parameter change wakes everything too.
    let mut sim2 = Simulation::new(rig(), preset("skin"));
    for _ in 0..2000 {
        sim2.step(&Pose::rest(1));
    }
    assert!(sim2.is_asleep());
    sim2.set_params(preset("water"));
    assert!(!sim2.is_asleep());
}

#[test]
fn motion_wakes_neighbouring_tiles_before_it_reaches_them() {
    // Small tiles, so the moving head is many tiles away from the tail.
    let options = Options {
        tile: 8,
        ..Options::default()
    };
    let mut sim = Simulation::with_options(rig(), preset("water"), options);
    two_sections(&mut sim);
    let mut full = Simulation::with_options(
        rig(),
        preset("water"),
        Options {
            sleeping: false,
            ..options
        },
    );
    two_sections(&mut full);
    let scale = 2.0f32; // spot-small's size
    let mut worst = 0.0f32;
    for step in 0..600 {
        let pose = head_turned(if step < 300 { 40.0 } else { 0.0 });
        sim.step(&pose);
        full.step(&pose);
        let (a, b) = (sim.positions(), full.positions());
        for i in 0..a.len() {
            worst = worst.max((a.get(i) - b.get(i)).length());
        }
    }
    assert!(
        worst < 1e-3 * scale,
        "sleeping run strays {worst} from the full run"
    );
}

#[test]
fn every_spring_sits_in_its_lane_and_padding_is_a_spring_without_stiffness() {
    use puppet::sim::layout::Layout;
    let rig = rig();
    for tile in [1, 37, 256, 100_000] {
        let l = Layout::new(&rig, tile);
        assert_eq!(l.lane_stiffness.len(), l.lane_offsets().len());
        let groups: usize = (0..l.tiles())
            .map(|t| l.tile_range(t).len().div_ceil(Layout::LANES))
            .sum();
        assert_eq!(l.group_start.len(), groups + 1);
        let mut seen = 0;
        for t in 0..l.tiles() {
            let r = l.tile_range(t);
            let g0 = t * l.groups_per_tile();
            // Row `row` of a group holds the row-th spring of each of its slots (neighbours as
            // offsets, 4 × the slot), padded with the slot itself and stiffness 0; lanes past a
            // short group's end repeat its last slot.
            for (gi, group) in r.clone().step_by(Layout::LANES).enumerate() {
                let g = g0 + gi;
                let span = l.group_start[g] as usize..l.group_start[g + 1] as usize;
                let (neighbours, stiffness) =
                    (&l.lane_offsets()[span.clone()], &l.lane_stiffness[span]);
                assert_eq!(neighbours.len() % Layout::LANES, 0);
                let valence = (group..(group + Layout::LANES).min(r.end))
                    .map(|k| (l.start[k + 1] - l.start[k]) as usize)
                    .max();
                assert_eq!(neighbours.len() / Layout::LANES, valence.unwrap_or(0));
                for (row, (qs, rs)) in neighbours
                    .chunks(Layout::LANES)
                    .zip(stiffness.chunks(Layout::LANES))
                    .enumerate()
                {
                    for lane in 0..Layout::LANES {
                        let k = (group + lane).min(r.end - 1);
                        let e = l.start[k] as usize + row;
                        if e < l.start[k + 1] as usize {
                            assert_eq!(qs[lane], 4 * l.edges[e].neighbour, "tile {tile} slot {k}");
                            assert_eq!(rs[lane], l.edges[e].stiffness);
                            seen += usize::from(group + lane < r.end);
                        } else {
                            assert_eq!(qs[lane] as usize, 4 * k, "tile {tile} slot {k} row {row}");
                            assert_eq!(rs[lane], 0.0);
                        }
                    }
                }
            }
        }
        assert_eq!(seen, l.edges.len(), "tile {tile}: every half-spring once");
    }
}
