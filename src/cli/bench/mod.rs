//! `puppet bench`: every measurement in `BENCHMARKS.md`, headless.
//!
//! * (default) step throughput on the standard scenario ([`puppet::scenario`]), and the largest
//!   Loop subdivision of the input that still holds 60 steps/s ([`throughput`]);
//! * `--accuracy`: run time against error for each configuration, against a converged `f64`
//!   reference, with the Pareto front ([`accuracy`]);
//! * `--stress`: randomized scenarios that try to break the solver ([`stress`]);
//! * `--skip`: what sleeping saves on a scenario where only the limb moves, and what it costs
//!   in accuracy ([`skip`]);
//! * `--machine`: copy bandwidth and a plain scalar spring loop, as yardsticks ([`machine`]);
//! * `--skeleton`, `--skeleton-speed`: the skeleton's accuracy and speed ([`skeleton`]).

mod accuracy;
mod machine;
mod skeleton;
mod skip;
mod stress;
mod throughput;

use super::load_mesh;
use anyhow::{anyhow, bail, Result};
use puppet::mesh::{subdivide_loop_values, vertex_normals, Mesh};
use puppet::scenario::Scenario;
use puppet::sim::Constraint;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Mesh to measure on; the embedded Spot when omitted.
    pub mesh: Option<PathBuf>,
    /// Throughput: Loop-subdivide the mesh until it has at least this many springs.
    #[arg(long)]
    pub springs: Option<usize>,
    /// Throughput: instead of a mesh file, a generated torus (tube radius half the ring
    /// radius) with about --springs springs (five per vertex), its skeletal distance the
    /// exact one (the tube radius): sizes between the fourfold steps of subdivision.
    #[arg(long, requires = "springs", conflicts_with = "mesh")]
    pub torus: bool,
    /// Constraint for the throughput, skip and stress measurements.
    #[arg(long, default_value = "circumsphere", value_parser = ["circumsphere", "reduction"])]
    pub method: String,
    /// Timed steps per size (throughput) or frames of the scenario (skip).
    #[arg(long, default_value_t = 120)]
    pub frames: usize,
    /// Throughput at every subdivision level 0..=--subdivisions, not only up to the first
    /// size that misses 60 steps/s.
    #[arg(long)]
    pub scaling: bool,
    /// Loop subdivision steps (each quadruples the faces; at most 6).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(0..=6))]
    pub subdivisions: u8,
    /// Run time against error, with a converged f64 reference.
    #[arg(long)]
    pub accuracy: bool,
    /// Randomized stability stress.
    #[arg(long)]
    pub stress: bool,
    /// Seed of the stress scenarios.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Simulation steps of the stress run, in all.
    #[arg(long, default_value_t = 100_000)]
    pub steps: u64,
    /// Cost and error of sleeping (skipping still tiles).
    #[arg(long)]
    pub skip: bool,
    /// This machine's copy bandwidth and a plain scalar spring loop (yardsticks).
    #[arg(long)]
    pub machine: bool,
    /// Skeleton accuracy against analytic shapes.
    #[arg(long)]
    pub skeleton: bool,
    /// Resolutions per shape for --skeleton (1 to 3).
    #[arg(long, default_value_t = 3)]
    pub levels: usize,
    /// Skeleton time per stage on the mesh subdivided 0..=--subdivisions times.
    #[arg(long)]
    pub skeleton_speed: bool,
    /// Runs per measurement; the median is reported.
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
    /// Print JSON instead of Markdown tables.
    #[arg(long)]
    pub json: bool,
}

impl Args {
    fn constraint(&self) -> Constraint {
        if self.method == "reduction" {
            Constraint::SpringReduction
        } else {
            Constraint::Circumsphere
        }
    }
}

pub fn run(args: &Args) -> Result<()> {
    let modes = [
        args.accuracy,
        args.stress,
        args.skip,
        args.machine,
        args.skeleton,
        args.skeleton_speed,
    ];
    if modes.iter().filter(|&&m| m).count() > 1 {
        bail!(
            "choose one of --accuracy, --stress, --skip, --machine, --skeleton, --skeleton-speed"
        );
    }
    if args.accuracy {
        accuracy::run(args)
    } else if args.stress {
        stress::run(args)
    } else if args.skip {
        skip::run(args)
    } else if args.machine {
        machine::run(args)
    } else if args.skeleton {
        skeleton::accuracy(args)
    } else if args.skeleton_speed {
        skeleton::speed(args)
    } else {
        throughput::run(args)
    }
}

/// The largest generated torus (20M vertices, a few GB once rigged).
const MAX_TORUS_SPRINGS: usize = 100_000_000;

/// The input mesh with its real skeletal distances (computed once, on the unsubdivided
/// mesh).
struct Base {
    mesh: Mesh,
    distance: Vec<f64>,
    name: String,
}

impl Base {
    fn load(args: &Args) -> Result<Base> {
        if let (true, Some(springs)) = (args.torus, args.springs) {
            if springs > MAX_TORUS_SPRINGS {
                bail!("--torus: at most {MAX_TORUS_SPRINGS} springs, got {springs}");
            }
            return Ok(Base::torus(springs));
        }
        let (mesh, _, name) = load_mesh(args.mesh.as_deref())?;
        let normals = vertex_normals(&mesh).map_err(|e| anyhow!("{name}: {e}"))?;
        let sk = puppet::skeleton::build(
            &mesh,
            &normals,
            &puppet::skeleton::SkeletonParams::default(),
            puppet::progress::silent(),
        )
        .map_err(|e| anyhow!("{name}: {e}"))?;
        Ok(Base {
            mesh,
            distance: sk.distance,
            name,
        })
    }

    /// A torus with about `springs` springs: a grid of `2k × k` vertices (three edges and
    /// two bone springs per vertex), ring radius 2, tube radius 1. Its medial axis is the
    /// ring's core circle, so every vertex's skeletal distance is exactly the tube radius.
    fn torus(springs: usize) -> Base {
        let vertices = springs.div_ceil(5).max(18);
        let k = ((vertices as f64 / 2.0).sqrt().ceil() as usize).max(3);
        let mesh = puppet::mesh::shapes::torus(2.0, 1.0, 2 * k, k);
        let distance = vec![1.0; mesh.positions.len()];
        Base {
            name: format!("a generated torus ({} × {k} vertices)", 2 * k),
            mesh,
            distance,
        }
    }

    /// The mesh and distances Loop-subdivided `level` times. Subdivided vertices take the
    /// mean skeletal distance of their edge's ends: the step's cost does not depend on the
    /// values, and multi-million-vertex skeletons would dominate the run.
    fn subdivided(&self, level: usize) -> (Mesh, Vec<f64>) {
        let (mut mesh, mut distance) = (self.mesh.clone(), self.distance.clone());
        for _ in 0..level {
            (mesh, distance) = subdivide_loop_values(&mesh, &distance);
        }
        (mesh, distance)
    }

    /// The standard scenario on a (subdivided) copy of the mesh.
    fn scenario_of(&self, mesh: Mesh, distance: Vec<f64>, swing_seconds: f64) -> Result<Scenario> {
        Scenario::standard(mesh, distance, swing_seconds).map_err(|e| anyhow!("{}: {e}", self.name))
    }

    /// The standard scenario on the mesh Loop-subdivided `level` times.
    fn scenario(&self, level: usize, swing_seconds: f64) -> Result<Scenario> {
        let (mesh, distance) = self.subdivided(level);
        self.scenario_of(mesh, distance, swing_seconds)
    }
}

/// Median and 95th percentile.
fn median_p95(v: Vec<f64>) -> (f64, f64) {
    puppet::skeleton::truth::median_p95(v)
}

fn method_name(c: Constraint) -> &'static str {
    match c {
        Constraint::Circumsphere => "circumsphere",
        Constraint::SpringReduction => "reduction",
    }
}
