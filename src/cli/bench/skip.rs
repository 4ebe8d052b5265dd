//! What sleeping saves, and what it costs in accuracy: the standard scenario (the limb swings
//! for 1 s, then holds) run with every tile integrated and, in lockstep, with sleeping at
//! several tile sizes. Lockstep means the runs alternate step by step, so load on the
//! shared machine hits them alike. Error: distance of every vertex to the full run at every
//! step, RMS and max, relative to the bounding-box diagonal.

use super::table::{self, Column, Table};
use super::{median_p95, Base, Input};
use crate::cli::LoadArgs;
use anyhow::{bail, Result};
use puppet::sim::Constraint;
use puppet::sim::{Options, Params, Simulation, REFERENCE_STEP};

/// The bound the issue sets on the skipping error (relative to the diagonal).
pub const MAX_ERROR: f64 = 1e-3;

#[derive(serde::Serialize)]
struct Row {
    config: String,
    tile: usize,
    ms_per_step_swing: f64,
    ms_per_step_hold: f64,
    ms_per_step_all: f64,
    awake_share_swing: f64,
    awake_share_hold: f64,
    rms_error: f64,
    max_error: f64,
}

#[derive(serde::Serialize)]
struct Report {
    mesh: String,
    vertices: usize,
    springs: usize,
    limb_vertices: usize,
    steps: usize,
    rows: Vec<Row>,
}

/// `puppet bench skip`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Loop subdivision steps (each quadruples the faces; at most 6).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(0..=6))]
    subdivisions: u8,
    /// The constraint.
    #[arg(long, value_enum, default_value_t = Constraint::Circumsphere)]
    constraint: Constraint,
    /// Frames of the scenario.
    #[arg(long, default_value_t = 120)]
    frames: usize,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &Args, load: &LoadArgs) -> Result<()> {
    let base = Base::load(&args.input, load, None)?;
    let swing = 1.0;
    let scenario = base.scenario(args.subdivisions as usize, swing)?;
    let mut params = Params::default();
    params.solver.constraint = args.constraint;
    params.solver.time_step = REFERENCE_STEP;
    let tiles = [64usize, 256, 1024, 4096, usize::MAX];
    let mut configs: Vec<(String, Options)> = vec![(
        "full (no sleeping)".into(),
        Options {
            sleeping: false,
            ..Options::default()
        },
    )];
    for &t in &tiles {
        let name = if t == usize::MAX {
            "sleeping, one tile = whole mesh".to_string()
        } else if t == Options::default().tile {
            format!("sleeping, tile {t} (default)")
        } else {
            format!("sleeping, tile {t}")
        };
        configs.push((
            name,
            Options {
                tile: t.min(scenario.mesh.positions.len()),
                ..Options::default()
            },
        ));
    }
    configs.push((
        format!("sleeping, tile {}, threshold 1e-5", Options::default().tile),
        Options {
            sleep_threshold: 1e-5,
            ..Options::default()
        },
    ));
    let rig = scenario.rig(params.material.bone_distance);
    let mut sims: Vec<Simulation> = configs
        .iter()
        .map(|(_, o)| {
            let mut s = Simulation::with_options(rig.clone(), params, *o);
            s.set_sections(scenario.joints.section_of().to_vec());
            s
        })
        .collect();
    drop(rig);
    let n = sims[0].rig().len();
    let springs = sims[0].rig().spring_count();
    let steps = args.frames.max(2);
    let swing_steps = (swing / REFERENCE_STEP as f64).round() as usize;
    let k = sims.len();
    let mut times = vec![(Vec::new(), Vec::new()); k];
    let mut awake = vec![(Vec::new(), Vec::new()); k];
    let mut sum2 = vec![0.0f64; k];
    let mut worst = vec![0.0f64; k];
    for step in 0..steps {
        let pose = scenario.pose(step as f64 * REFERENCE_STEP as f64);
        for (c, sim) in sims.iter_mut().enumerate() {
            let t = std::time::Instant::now();
            sim.step(&pose);
            let ms = t.elapsed().as_secs_f64() * 1e3;
            let (all, integrated) = sim.tiles();
            let share = integrated as f64 / all.max(1) as f64;
            if step < swing_steps {
                times[c].0.push(ms);
                awake[c].0.push(share);
            } else {
                times[c].1.push(ms);
                awake[c].1.push(share);
            }
        }
        let (full, rest) = sims.split_at(1);
        let reference = full[0].positions();
        for (c, sim) in rest.iter().enumerate() {
            let x = sim.positions();
            for i in 0..n {
                let d = (x.get(i) - reference.get(i)).length() as f64;
                sum2[c + 1] += d * d;
                worst[c + 1] = worst[c + 1].max(d);
            }
        }
    }
    let diag = scenario.diagonal;
    let rows: Vec<Row> = configs
        .iter()
        .enumerate()
        .map(|(c, (name, _))| {
            let all: Vec<f64> = times[c].0.iter().chain(&times[c].1).copied().collect();
            Row {
                config: name.clone(),
                tile: sims[c].options().tile,
                ms_per_step_swing: median_p95(times[c].0.clone()).0,
                ms_per_step_hold: median_p95(times[c].1.clone()).0,
                ms_per_step_all: median_p95(all).0,
                awake_share_swing: median_p95(awake[c].0.clone()).0,
                awake_share_hold: median_p95(awake[c].1.clone()).0,
                rms_error: (sum2[c] / (steps * n) as f64).sqrt() / diag,
                max_error: worst[c] / diag,
            }
        })
        .collect();
    let report = Report {
        mesh: base.name.clone(),
        vertices: n,
        springs,
        limb_vertices: scenario.limb_vertices(),
        steps,
        rows,
    };
    if args.json {
        table::json(&report)?;
    } else {
        println!(
            "{} subdivided {}x: {} vertices, {} springs, limb {} vertices; {} steps ({} swinging, then holding); {} constraint",
            report.mesh,
            args.subdivisions,
            n,
            springs,
            report.limb_vertices,
            steps,
            swing_steps.min(steps),
            args.constraint
        );
        println!();
        let mut table = Table::new(&[
            Column::Text("configuration"),
            Column::Figure("ms/step swing"),
            Column::Figure("ms/step hold"),
            Column::Figure("ms/step all"),
            Column::Figure("tiles awake swing"),
            Column::Figure("hold"),
            Column::Figure("RMS error"),
            Column::Figure("max error"),
        ]);
        table.start();
        for r in &report.rows {
            table.row(&[
                r.config.to_string(),
                format!("{:.3}", r.ms_per_step_swing),
                format!("{:.3}", r.ms_per_step_hold),
                format!("{:.3}", r.ms_per_step_all),
                format!("{:.0} %", 100.0 * r.awake_share_swing),
                format!("{:.0} %", 100.0 * r.awake_share_hold),
                format!("{:.1e}", r.rms_error),
                format!("{:.1e}", r.max_error),
            ]);
        }
    }
    let default_tile = Options::default().tile.min(n);
    if let Some(r) = report
        .rows
        .iter()
        .find(|r| r.tile == default_tile && r.config.ends_with("(default)"))
    {
        if r.max_error >= MAX_ERROR {
            bail!(
                "sleeping strays {:.2e} of the diagonal from the full run (bound {MAX_ERROR:e})",
                r.max_error
            );
        }
    }
    Ok(())
}
