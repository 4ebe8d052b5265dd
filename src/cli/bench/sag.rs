//! `puppet bench sag`: how far each Table 1 preset sags under gravity, and how long it
//! takes to settle.
//!
//! The puppet hangs on its bones (no cut, rest pose) with gravity pulling down; the step runs
//! with the default options (sleeping on) until every tile sleeps, which is the solver's
//! own "settled". The sag is the largest distance of a vertex from its rest position,
//! relative to the bounding-box diagonal. Exit status 2 when a preset does not settle
//! within the time limit or a value is not finite.

use super::table::{self, Column, Table};
use super::{Base, Input};
use crate::cli::LoadArgs;
use anyhow::{bail, Result};
use puppet::sim::{presets, Params, Pose, Simulation};

/// `puppet bench sag`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Gravity in g, pulling down (`-y`).
    #[arg(long, default_value_t = 1.0)]
    gravity: f32,
    /// Simulated seconds a preset may take to settle.
    #[arg(long, default_value_t = 60.0)]
    limit: f64,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct Row {
    material: String,
    /// Largest vertex displacement from rest, relative to the bounding-box diagonal.
    sag: f64,
    /// Simulated seconds until every tile sleeps.
    settle_seconds: f64,
    /// Wall-clock milliseconds that took.
    settle_wall_ms: f64,
    steps: u64,
}

#[derive(serde::Serialize)]
struct Report {
    mesh: String,
    vertices: usize,
    gravity: f32,
    /// Ordered from the least sag to the most.
    presets: Vec<Row>,
}

pub fn run(args: &Args, load: &LoadArgs) -> Result<()> {
    if !(args.gravity.is_finite() && args.gravity.abs() <= puppet::sim::MAX_GRAVITY) {
        bail!("--gravity: {} is outside -10..10", args.gravity);
    }
    if !(args.limit.is_finite() && args.limit > 0.0) {
        bail!(
            "--limit: {} is not a positive number of seconds",
            args.limit
        );
    }
    let base = Base::load(&args.input, load, None)?;
    let (lo, hi) = base.mesh.bounds();
    let diagonal = (hi - lo).length();
    let scenario = base.scenario_of(base.mesh.clone(), base.distance.clone(), f64::INFINITY)?;
    let pose = Pose::rest(1);
    let mut rows = Vec::new();
    for m in presets() {
        let mut params = Params::from(m.material);
        params.world.gravity = [0.0, -args.gravity, 0.0];
        let mut sim = Simulation::new(scenario.rig(params.material.bone_distance), params);
        let h = sim.params().solver.time_step as f64;
        let limit = (args.limit / h).ceil() as u64;
        let started = std::time::Instant::now();
        while !sim.is_asleep() {
            if sim.steps() >= limit {
                bail!(
                    "{}: '{}' did not settle in {} s",
                    base.name,
                    m.name,
                    args.limit
                );
            }
            sim.step(&pose);
        }
        let wall = started.elapsed().as_secs_f64() * 1e3;
        let x = sim.positions();
        let sag = (0..x.len())
            .map(|i| (x.get(i) - sim.rig().rest[i]).length() as f64)
            .fold(0.0, f64::max)
            / diagonal;
        if !sag.is_finite() {
            bail!("{}: '{}' sag is not finite", base.name, m.name);
        }
        rows.push(Row {
            material: m.name,
            sag,
            settle_seconds: sim.steps() as f64 * h,
            settle_wall_ms: wall,
            steps: sim.steps(),
        });
    }
    rows.sort_by(|a, b| a.sag.total_cmp(&b.sag));
    let report = Report {
        mesh: base.name.clone(),
        vertices: base.mesh.positions.len(),
        gravity: args.gravity,
        presets: rows,
    };
    if args.json {
        return table::json(&report);
    }
    println!(
        "{} ({} vertices), gravity {} g down, sleeping on, from the least sag to the most",
        report.mesh, report.vertices, report.gravity
    );
    println!();
    let mut table = Table::new(&[
        Column::Text("preset"),
        Column::Figure("sag (of the diagonal)"),
        Column::Figure("settled after (simulated s)"),
        Column::Figure("wall ms"),
        Column::Figure("steps"),
    ]);
    table.start();
    for r in &report.presets {
        table.row(&[
            r.material.to_string(),
            format!("{:.4} %", 100.0 * r.sag),
            format!("{:.2}", r.settle_seconds),
            format!("{:.0}", r.settle_wall_ms),
            r.steps.to_string(),
        ]);
    }
    Ok(())
}
