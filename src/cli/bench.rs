//! `puppet bench`: measurements that go into `BENCHMARKS.md`.
//!
//! * `--skeleton`: skeleton accuracy against analytic shapes (median and 95th-percentile
//!   relative error of `d_i` per method, shape and resolution).
//! * `--skeleton-speed [MESH]`: skeleton time per stage on a mesh Loop-subdivided 0..=N times
//!   (median of `--runs`), with peak memory.

use super::load_mesh;
use anyhow::{bail, Result};
use puppet::mesh::{subdivide_loop, vertex_normals};
use puppet::rig::Rig;
use puppet::sim::{Constraint, Params, Pose, Simulation};
use puppet::skeleton::{self, truth, Method, SkeletonParams};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Mesh for the speed measurements; the embedded Spot when omitted.
    pub mesh: Option<PathBuf>,
    /// Skeleton accuracy against analytic shapes.
    #[arg(long)]
    pub skeleton: bool,
    /// Resolutions per shape for --skeleton (1 to 3).
    #[arg(long, default_value_t = 3)]
    pub levels: usize,
    /// Skeleton time per stage on the mesh subdivided 0..=--subdivisions times.
    #[arg(long)]
    pub skeleton_speed: bool,
    /// Loop subdivision steps for --skeleton-speed and --sim (each quadruples the faces;
    /// at most 6, since Spot at 6 already has 12M vertices).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(0..=6))]
    pub subdivisions: u8,
    /// Runs per size; the median is reported.
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
    /// Simulation step throughput on the mesh subdivided 0..=--subdivisions times.
    #[arg(long)]
    pub sim: bool,
    /// Constraint for --sim.
    #[arg(long, default_value = "circumsphere", value_parser = ["circumsphere", "reduction"])]
    pub method: String,
    /// Timed steps per size for --sim (after 20 warm-up steps).
    #[arg(long, default_value_t = 200)]
    pub steps: usize,
    /// Print JSON instead of Markdown tables.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &Args) -> Result<()> {
    if !args.skeleton && !args.skeleton_speed && !args.sim {
        bail!("nothing to measure: pass --skeleton, --skeleton-speed and/or --sim");
    }
    if args.sim {
        sim(args)?;
    }
    if args.skeleton {
        accuracy(args)?;
    }
    if args.skeleton_speed {
        speed(args)?;
    }
    Ok(())
}

fn accuracy(args: &Args) -> Result<()> {
    let cases = truth::cases(args.levels);
    let rows = truth::accuracy(&cases, &Method::ALL, SkeletonParams::default().sliver_ratio);
    if args.json {
        println!("{}", serde_json::to_string(&rows)?);
        return Ok(());
    }
    println!("| shape | resolution | vertices | method | median rel. error | p95 rel. error | fallback | clamped |");
    println!("|---|---|---:|---|---:|---:|---:|---:|");
    for r in &rows {
        println!(
            "| {} | {} | {} | {} | {:.4} | {:.4} | {} | {} |",
            r.shape,
            r.resolution,
            r.vertices,
            r.method,
            r.median_rel_error,
            r.p95_rel_error,
            r.fallback,
            r.clamped
        );
    }
    Ok(())
}

#[derive(serde::Serialize)]
struct SpeedRow {
    vertices: usize,
    faces: usize,
    runs: usize,
    seconds_median: f64,
    stages_median: Vec<(String, f64)>,
    peak_rss_mib: Option<f64>,
}

fn speed(args: &Args) -> Result<()> {
    let (mut mesh, _, name) = load_mesh(args.mesh.as_deref())?;
    let mut rows = Vec::new();
    for level in 0..=args.subdivisions as usize {
        if level > 0 {
            mesh = subdivide_loop(&mesh);
        }
        let normals = vertex_normals(&mesh)?;
        let params = SkeletonParams::default();
        let mut totals = Vec::new();
        let mut stages: Vec<Vec<(&'static str, f64)>> = Vec::new();
        for _ in 0..args.runs.max(1) {
            let t = std::time::Instant::now();
            let sk = skeleton::build(&mesh, &normals, &params, puppet::progress::silent())?;
            totals.push(t.elapsed().as_secs_f64());
            stages.push(sk.seconds);
        }
        let stages_median = stages[0]
            .iter()
            .enumerate()
            .map(|(k, (stage, _))| {
                let (m, _) = truth::median_p95(stages.iter().map(|s| s[k].1).collect());
                (stage.to_string(), m)
            })
            .collect();
        let (seconds_median, _) = truth::median_p95(totals);
        rows.push(SpeedRow {
            vertices: mesh.positions.len(),
            faces: mesh.triangles.len(),
            runs: args.runs.max(1),
            seconds_median,
            stages_median,
            peak_rss_mib: peak_rss_mib(),
        });
    }
    if args.json {
        println!("{}", serde_json::to_string(&rows)?);
        return Ok(());
    }
    println!(
        "skeleton speed on {name} (Loop-subdivided), default parameters, median of {} runs",
        args.runs.max(1)
    );
    println!();
    println!("| vertices | faces | total ms | stages (ms) | peak RSS MiB |");
    println!("|---:|---:|---:|---|---:|");
    for r in &rows {
        let st: Vec<String> = r
            .stages_median
            .iter()
            .filter(|(s, _)| s != "total")
            .map(|(s, v)| format!("{s} {:.1}", v * 1e3))
            .collect();
        println!(
            "| {} | {} | {:.1} | {} | {} |",
            r.vertices,
            r.faces,
            r.seconds_median * 1e3,
            st.join(", "),
            r.peak_rss_mib
                .map(|m| format!("{m:.0}"))
                .unwrap_or_else(|| "?".into())
        );
    }
    Ok(())
}

/// Peak resident memory of this process so far (Linux), in MiB.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

#[derive(serde::Serialize)]
struct SimRow {
    vertices: usize,
    springs: usize,
    steps: usize,
    method: &'static str,
    ms_per_step_median: f64,
    ms_per_step_p95: f64,
    bones_ms_median: f64,
    fused_ms_median: f64,
    springs_per_second: f64,
    threads: usize,
}

/// Step throughput. The scene: the whole puppet swings ±30° about a tilted axis (the pose
/// changes every step, so stage 1 always runs and the constraint is active). Subdivided rigs
/// use the base mesh's median skeletal distance for every vertex: the step's cost does not
/// depend on the values, and recomputing multi-million-vertex skeletons would dominate.
fn sim(args: &Args) -> Result<()> {
    let (base, _, name) = load_mesh(args.mesh.as_deref())?;
    let normals = vertex_normals(&base)?;
    let sk = skeleton::build(
        &base,
        &normals,
        &SkeletonParams::default(),
        puppet::progress::silent(),
    )?;
    let (_, d_median, _) = super::skeleton::min_median_max(&sk.distance);
    let constraint = if args.method == "reduction" {
        Constraint::SpringReduction
    } else {
        Constraint::Circumsphere
    };
    let params = Params {
        constraint,
        ..Params::default()
    };
    let mut mesh = base.clone();
    let mut rows = Vec::new();
    for level in 0..=args.subdivisions as usize {
        if level > 0 {
            mesh = subdivide_loop(&mesh);
        }
        let normals = vertex_normals(&mesh)?;
        let distance = if level == 0 {
            sk.distance.clone()
        } else {
            vec![d_median; mesh.positions.len()]
        };
        let rig = Rig::new(&mesh, &normals, &distance, params.bone_distance);
        let springs = rig.spring_count();
        let mut sim = Simulation::new(rig, params);
        let axis = glam::Vec3::new(0.3, 1.0, 0.2).normalize();
        let pose = |k: usize| Pose {
            transforms: vec![glam::Affine3A::from_quat(glam::Quat::from_axis_angle(
                axis,
                (30f32).to_radians() * (k as f32 * 0.05).sin(),
            ))],
        };
        let (mut total, mut bones, mut fused) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..args.steps + 20 {
            let t = std::time::Instant::now();
            sim.step(&pose(k));
            let dt = t.elapsed().as_secs_f64();
            if k >= 20 {
                total.push(dt * 1e3);
                let st = sim.last_times();
                bones.push(st.wake * 1e3);
                fused.push(st.fused * 1e3);
            }
        }
        let (med, p95) = truth::median_p95(total);
        rows.push(SimRow {
            vertices: mesh.positions.len(),
            springs,
            steps: args.steps,
            method: if constraint == Constraint::Circumsphere {
                "circumsphere"
            } else {
                "reduction"
            },
            ms_per_step_median: med,
            ms_per_step_p95: p95,
            bones_ms_median: truth::median_p95(bones).0,
            fused_ms_median: truth::median_p95(fused).0,
            springs_per_second: springs as f64 / (med * 1e-3),
            threads: rayon::current_num_threads(),
        });
    }
    if args.json {
        println!("{}", serde_json::to_string(&rows)?);
        return Ok(());
    }
    println!(
        "simulation step on {name} (Loop-subdivided), {} constraint, {} threads, median/p95 of {} steps",
        args.method,
        rayon::current_num_threads(),
        args.steps
    );
    println!();
    println!("| vertices | springs | ms/step median | p95 | bones ms | springs+verlet+constraint ms | springs/s | steps/s |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in &rows {
        println!(
            "| {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2e} | {:.0} |",
            r.vertices,
            r.springs,
            r.ms_per_step_median,
            r.ms_per_step_p95,
            r.bones_ms_median,
            r.fused_ms_median,
            r.springs_per_second,
            1e3 / r.ms_per_step_median
        );
    }
    Ok(())
}
