//! Micro-benchmarks of the simulation step on the standard scenario (`puppet::bench::scenario`):
//! Spot (2,930 vertices) and Spot Loop-subdivided twice (46,850 vertices).
//! `cargo bench --bench step`.
//!
//! * `pose`: the joints' world transforms for one frame (f64, then f32);
//! * `step/<constraint>`: one full step with every tile integrated (stages 0–5; the fused
//!   kernel is nearly all of it);
//! * `asleep`: a step when every tile sleeps (stages 0 and 5 only: the bookkeeping cost);
//! * `reference-f64`: one step of the f64 reference solver.

use criterion::{criterion_group, criterion_main, Criterion};
use puppet::bench::scenario::{reference::Reference, Scenario};
use puppet::joints::PoseScratch;
use puppet::mesh::{parse_obj, subdivide_loop_values, vertex_normals};
use puppet::sim::{Constraint, Options, Params, Pose, Simulation};
use std::hint::black_box;

fn scenario(level: usize) -> Scenario {
    let (mut mesh, _) = parse_obj(include_bytes!("../assets/spot.obj")).expect("embedded mesh");
    let normals = vertex_normals(&mesh).expect("normals");
    let sk = puppet::skeleton::build(
        &mesh,
        &normals,
        &Default::default(),
        puppet::progress::silent(),
    )
    .expect("skeleton");
    let mut distance = sk.distance;
    for _ in 0..level {
        (mesh, distance) = subdivide_loop_values(&mesh, &distance);
    }
    Scenario::standard(mesh, distance, f64::INFINITY).expect("scenario")
}

fn stages(c: &mut Criterion) {
    for (name, level) in [("spot", 0), ("spot-x16", 2)] {
        let scenario = scenario(level);
        let mut g = c.benchmark_group(name);
        g.sample_size(20);
        // Two poses in turn: the same pose asked for again is the one made last, not
        // made again (`Joints::pose_into`).
        let mut scratch = PoseScratch::default();
        let locals = [scenario.local(0.25), scenario.local(0.5)];
        let mut k = 0;
        g.bench_function("pose", |b| {
            b.iter(|| {
                scenario
                    .joints
                    .pose_into(black_box(&locals[k % 2]), &mut scratch);
                k += 1;
            })
        });
        for constraint in [Constraint::Circumsphere, Constraint::SpringReduction] {
            let mut params = Params::default();
            params.solver.constraint = constraint;
            let options = Options {
                sleeping: false,
                ..Options::default()
            };
            let mut sim = Simulation::with_options(
                scenario.rig(params.material.bone_distance),
                params,
                options,
            );
            sim.set_sections(scenario.joints.section_of().to_vec());
            let poses: Vec<Pose> = (0..60).map(|k| scenario.pose(k as f64 / 60.0)).collect();
            let mut k = 0;
            let label = match constraint {
                Constraint::Circumsphere => "step/circumsphere",
                Constraint::SpringReduction => "step/reduction",
            };
            g.bench_function(label, |b| {
                b.iter(|| {
                    sim.step(&poses[k % poses.len()]);
                    k += 1;
                })
            });
        }
        let params = Params::default();
        let mut sim = Simulation::new(scenario.rig(params.material.bone_distance), params);
        sim.set_sections(scenario.joints.section_of().to_vec());
        let rest = scenario.pose(0.0);
        while !sim.is_asleep() {
            sim.step(&rest);
        }
        g.bench_function("asleep", |b| b.iter(|| sim.step(black_box(&rest))));
        let mut r = Reference::new(&scenario, params, 1.0 / 60.0);
        let world = scenario.world(0.25);
        g.bench_function("reference-f64", |b| b.iter(|| r.step(black_box(&world))));
        g.finish();
    }
}

criterion_group!(benches, stages);
criterion_main!(benches);
