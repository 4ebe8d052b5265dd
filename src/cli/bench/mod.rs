//! `puppet bench MODE`: every measurement in `BENCHMARKS.md` and
//! `docs/engine-benchmarks.md`, headless, one subcommand per mode:
//!
//! * `throughput`: step throughput on the standard scenario ([`puppet::bench::scenario`]), and the
//!   largest Loop subdivision of the input that still holds 60 steps/s ([`throughput`]);
//! * `accuracy`: run time against error for each configuration, against a converged `f64`
//!   reference, with the Pareto front ([`accuracy`]);
//! * `stress`: randomized scenarios that try to break the solver ([`stress`]);
//! * `skip`: what sleeping saves on a scenario where only the limb moves, and what it costs
//!   in accuracy ([`skip`]);
//! * `sag`: how far each Table 1 preset sags under gravity, and how long it takes to
//!   settle ([`sag`]);
//! * `export`: time and size of a take in each export format ([`export`]);
//! * `joints`: a bent joint's surface, hinge against bands ([`joints`]);
//! * `collide`: parts pressed into the body, collision off and on ([`collide`]);
//! * `poses`: a population of characters in seeded random poses: skin stretch, crossings,
//!   volumes ([`poses`]);
//! * `suggest`: suggested joints against the labelled characters' references ([`suggest`]);
//! * `skeleton`, `skeleton-speed`, `skeleton-change`: the skeleton's accuracy, its speed,
//!   and how far real meshes' points move between methods ([`skeleton`]);
//! * `machine`: copy bandwidth and a plain scalar spring loop, as yardsticks ([`machine`]);
//! * `controls`: live input latency, an OSC packet to the step that shows it ([`controls`]);
//! * `draw`: a viewport frame's cost, and what each part of the look adds ([`draw`]).
//!
//! Each prints its rows through one writer, `table`: a Markdown table a row at a time, or
//! the report as one line of JSON.

mod accuracy;
mod collide;
mod controls;
#[cfg(feature = "gui")]
mod draw;
mod export;
mod joints;
mod machine;
mod poses;
mod sag;
mod skeleton;
mod skip;
mod stress;
mod suggest;
mod table;
mod throughput;

use super::{load_mesh, LoadArgs};
use anyhow::{anyhow, bail, Result};
use puppet::bench::scenario::Scenario;
use puppet::mesh::{subdivide_loop_values, vertex_normals, Mesh};
use std::path::PathBuf;

/// `puppet bench MODE`: one subcommand per measurement.
#[derive(clap::Subcommand, Debug)]
pub enum Bench {
    /// Step throughput on the standard scenario, and the largest Loop subdivision of the
    /// input that holds 60 steps/s.
    Throughput(throughput::Args),
    /// Run time against error of each configuration, against a converged f64 reference.
    Accuracy(accuracy::Args),
    /// Randomized scenarios that try to break the solver.
    Stress(stress::Args),
    /// What sleeping saves, and what it costs in accuracy.
    Skip(skip::Args),
    /// How far each Table 1 preset sags under gravity, and how long it takes to settle.
    Sag(sag::Args),
    /// Time and file size of a take in each export format.
    Export(export::Args),
    /// A bent joint's surface: faces crossing, volume, dihedral angles, hinge against bands.
    Joints(joints::Args),
    /// Parts pressed into the body (arms down, legs crossed…), collision off and on:
    /// crossing faces, deepest penetration, section volumes, step cost.
    Collide(collide::Args),
    /// A population of characters in seeded random poses, each with its suggested joints:
    /// edge stretch, crossing faces, section volumes, NaN, time.
    Poses(poses::Args),
    /// Suggested joints against the labelled set's references: recall, spurious cuts,
    /// names, joint-to-joint distance, time.
    Suggest(suggest::Args),
    /// Skeleton accuracy against analytic shapes.
    Skeleton(skeleton::AccuracyArgs),
    /// Time from file to skeleton, per stage, on the mesh Loop-subdivided 0..=N times.
    SkeletonSpeed(skeleton::SpeedArgs),
    /// How far the skeletal points of real meshes move from one method to another, and
    /// whether every one is still inside.
    SkeletonChange(skeleton::ChangeArgs),
    /// This machine's copy bandwidth and a plain scalar spring loop (yardsticks).
    Machine(machine::Args),
    /// Latency of live input: from an OSC packet leaving the sender to the end of the step
    /// that shows it.
    Controls(controls::Args),
    /// What a frame of the viewport costs, and what anti-aliasing and the ground with its
    /// shadow add.
    #[cfg(feature = "gui")]
    Draw(draw::Args),
}

/// The input of the step measurements.
#[derive(clap::Args, Debug, Clone)]
pub struct Input {
    /// Mesh to measure on; the embedded Spot when omitted.
    pub mesh: Option<PathBuf>,
}

pub fn run(bench: &Bench, load: &LoadArgs) -> Result<()> {
    match bench {
        Bench::Throughput(args) => throughput::run(args, load),
        Bench::Accuracy(args) => accuracy::run(args, load),
        Bench::Stress(args) => stress::run(args),
        Bench::Skip(args) => skip::run(args, load),
        Bench::Sag(args) => sag::run(args, load),
        Bench::Export(args) => export::run(args, load),
        Bench::Joints(args) => joints::run(args),
        Bench::Collide(args) => collide::run(args, load),
        Bench::Poses(args) => poses::run(args, load),
        Bench::Suggest(args) => suggest::run(args, load),
        Bench::Skeleton(args) => skeleton::accuracy(args),
        Bench::SkeletonSpeed(args) => skeleton::speed(args, load),
        Bench::SkeletonChange(args) => skeleton::change(args, load),
        Bench::Machine(args) => machine::run(args),
        Bench::Controls(args) => controls::run(args),
        #[cfg(feature = "gui")]
        Bench::Draw(args) => draw::run(args, load),
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
    /// The input mesh, or a generated torus of about `torus` springs.
    fn load(input: &Input, load: &LoadArgs, torus: Option<usize>) -> Result<Base> {
        if let Some(springs) = torus {
            if springs > MAX_TORUS_SPRINGS {
                bail!("--torus: at most {MAX_TORUS_SPRINGS} springs, got {springs}");
            }
            return Ok(Base::torus(springs));
        }
        let (mesh, _, name) = load_mesh(input.mesh.as_deref(), load)?;
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

use puppet::stats::median_p95;

/// A bound a bench fails beyond (`--max-…`, `--min-…`): a finite number. A NaN would
/// compare false with every figure, and the bench could never fail; one no figure can meet
/// (a cost below −100 %) is allowed, and fails.
fn bound(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{s} is not a finite number")),
    }
}

/// Makes the folder `--images` names, if it does not exist yet.
fn image_folder(dir: Option<&PathBuf>) -> Result<()> {
    if let Some(dir) = dir {
        std::fs::create_dir_all(dir).map_err(|e| {
            super::FileError::new(dir.display().to_string(), format!("cannot create: {e}"))
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// Every bound flag of every bench mode (`--max-…`, `--min-…`) refuses what could
    /// never fail or never pass: NaN, infinity.
    #[test]
    fn every_bound_flag_refuses_nan() {
        let cli = crate::cli::Cli::command();
        let bench = cli.find_subcommand("bench").expect("bench");
        let mut checked = 0;
        for mode in bench.get_subcommands() {
            for arg in mode.get_arguments() {
                let Some(long) = arg.get_long() else {
                    continue;
                };
                if !(long.starts_with("max-") || long.starts_with("min-")) {
                    continue;
                }
                for bad in ["nan", "inf", "-inf"] {
                    let flag = format!("--{long}={bad}");
                    let parsed = crate::cli::Cli::command().try_get_matches_from([
                        "puppet",
                        "bench",
                        mode.get_name(),
                        flag.as_str(),
                    ]);
                    let err = parsed
                        .err()
                        .unwrap_or_else(|| panic!("bench {} {flag} was accepted", mode.get_name()));
                    assert!(
                        err.to_string().contains("is not a finite number"),
                        "bench {} {flag}: {err}",
                        mode.get_name()
                    );
                }
                checked += 1;
            }
        }
        assert!(checked >= 10, "{checked} bound flags");
    }
}
