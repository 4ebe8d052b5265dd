//! `puppet bench poses`: a population of characters, each with its suggested joints, put in
//! seeded random poses (see `puppet::puppet::poses`), settled, and the surface measured
//! against its rest shape: the worst edge stretch, the shares of edges over 1.5× and 2×,
//! new crossing faces, each section's volume change, NaN, and the time. Fails when a pose
//! misses a target given on the command line.

use super::table::{self, Column, Table};
use crate::cli::LoadArgs;
use anyhow::{anyhow, bail, Result};
use puppet::joints::Local;
use puppet::puppet::poses::{self, Spread, Surface};
use puppet::random::SplitMix;
use puppet::stats::{median, quantile};
use puppet::{Puppet, RigFile};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `puppet bench poses`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Meshes, or folders whose meshes (`.obj`, `.ply`, `.stl`, `.gltf`, `.glb`) to pose;
    /// the shipped ones when omitted (the embedded cow, `tests/data/meshes`,
    /// `tests/data/characters`, `tests/data/poses`).
    paths: Vec<PathBuf>,
    /// Only the characters whose name contains this.
    #[arg(long)]
    only: Option<String>,
    /// Random poses per character.
    #[arg(long, default_value_t = 20)]
    poses: usize,
    /// The seed of the first pose (pose k of every character uses seed + k).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Largest turn of a joint whose parent is not the root (degrees either way).
    #[arg(long, default_value_t = Spread::default().limb)]
    limb: f64,
    /// Largest turn of a joint hanging from the root (degrees either way).
    #[arg(long, default_value_t = Spread::default().root)]
    root: f64,
    /// Turn one joint a pose, drawn among them, the rest at rest: what a mouse drag turns
    /// (by default every joint turns at once, as an animation may).
    #[arg(long)]
    drag: bool,
    /// Pose with collision on.
    #[arg(long)]
    collision: bool,
    /// Suggest joints from the skeleton even for a file with a skin (a skinned glTF's own
    /// joints are posed by default).
    #[arg(long)]
    ignore_skin: bool,
    /// Pose each character with collision off and on, and compare: the poses where on
    /// crosses more faces than off, stretches an edge more, or leaves a vertex farther
    /// behind.
    #[arg(long, conflicts_with_all = ["collision", "targets"])]
    compare: bool,
    /// With `--compare`: fail when collision on is worse than off on some pose.
    #[arg(long, requires = "compare")]
    never_worse: bool,
    /// With `--compare`: fail when a character's step with collision on, held or while
    /// the joints turn (medians over its poses), costs more than this share (%) over the
    /// same step off, and more than `--max-collision-ms` over it.
    #[arg(long, requires = "compare", value_parser = super::bound)]
    max_collision_cost: Option<f64>,
    /// With `--max-collision-cost`: what the step with collision on may cost over the
    /// step off whatever the share, in ms (on a small mesh a share of a fraction of a
    /// millisecond is noise).
    #[arg(long, default_value_t = 0.3, requires = "max_collision_cost", value_parser = super::bound)]
    max_collision_ms: f64,
    /// Fail when a pose's worst edge stretch is above this.
    #[arg(long, value_parser = super::bound)]
    max_stretch: Option<f64>,
    /// Fail when a pose has more than this share (%) of its edges stretched over 1.5×.
    #[arg(long, value_parser = super::bound)]
    max_over: Option<f64>,
    /// Fail when a section's volume changes by more than this (%) in a pose (naming the
    /// sections that change most).
    #[arg(long, value_parser = super::bound)]
    max_volume: Option<f64>,
    /// Fail when a character takes longer than this (s) to open: read, repaired,
    /// skeleton, rig and suggested joints, as the window opens it.
    #[arg(long, value_parser = super::bound)]
    max_open: Option<f64>,
    /// Measure where the bones hold the surface (the rig's targets) instead of settling
    /// the simulation: fast, and the rig's own share of the stretch.
    #[arg(long)]
    targets: bool,
    /// Print one JSON record per pose instead of a Markdown table per character.
    #[arg(long)]
    json: bool,
}

/// One pose of one character, measured.
#[derive(serde::Serialize)]
struct Row {
    character: String,
    seed: u64,
    joints: usize,
    collision: bool,
    #[serde(flatten)]
    surface: Surface,
    /// The sections whose volume changes the least and the most (empty where none
    /// holds a volume).
    volume_sections: [String; 2],
    /// The sections of the two ends of the most stretched edge (empty where none).
    worst_sections: [String; 2],
    /// Where that edge lies at rest: its midpoint (mesh units; absent where none).
    #[serde(skip_serializing_if = "Option::is_none")]
    worst_at: Option<[f64; 3]>,
    /// How many vertices the part of the mesh holding that edge has (0 where
    /// none): the body's, or a separate part's (a backpack, a boot).
    worst_part: usize,
    /// The mesh's vertices.
    vertices: usize,
    /// Median step time while settling (ms).
    step_ms: f64,
    /// The pose limit's time in a step (ms): its median over the steps that reach the pose
    /// (while it moves; held, it costs nothing), and its largest.
    limit_ms: [f64; 2],
    /// A whole step while the pose moves (ms): the median over the steps that reach the
    /// pose of the pose limit and the step together, what a frame of a drag costs.
    moving_ms: f64,
    /// How much of the pose asked for the settled pose reached ([`reached`]): 1 with
    /// collision off, less where parts stopped at each other.
    reached: f64,
    /// With `--compare`, on the row with collision on: whether it is worse than off
    /// ([`Worse`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    worse: Option<Worse>,
    /// How long the character took to open, from its file to its suggested joints (s).
    open_s: f64,
}

/// Whether a pose is worse with collision on than off ([`worse`]), and what makes it so.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
enum Worse {
    /// Not worse.
    Not,
    /// Worse than off at the pose asked for, but not than the pose it reached settled with
    /// collision off: the pose its parts stopped at crosses or stretches as much without
    /// collision (a bent joint's crease), not the contacts.
    Pose,
    /// Worse also than off at the pose it reached.
    Collision,
}

/// `base` settled into `target` with collision on or off ([`poses::settle`]): each step's
/// times, the surface measured, and the pose reached.
fn settled(
    base: &Puppet,
    collision: bool,
    target: &[Local],
) -> (Vec<[f64; 2]>, Surface, Vec<Local>) {
    let mut p = base.clone();
    let mut params = *p.sim.params();
    params.world.collision = collision;
    p.sim.set_params(params);
    let (times, got) = poses::settle(&mut p, target);
    let surface = poses::measure(&p, &got);
    (times, surface, got)
}

/// The median over the first `steps` of `times` (each a step's time and its pose
/// limit's) of the two together (0 when none).
fn moving(times: &[[f64; 2]], steps: usize) -> f64 {
    let mut v: Vec<f64> = times.iter().take(steps).map(|t| t[0] + t[1]).collect();
    median(&mut v).unwrap_or(0.0)
}

/// How much of the pose `asked` the pose `got` reached: over the sections asked to turn
/// more than a degree, the mean of the share of each one's turn it got (1 when none is).
/// A part that stops at the body reaches less; a character that cannot move at all, 0.
fn reached(asked: &[Local], got: &[Local]) -> f64 {
    let angle = |l: &Local| 2.0 * l.rotation.w.abs().min(1.0).acos();
    let shares: Vec<f64> = asked
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(_, a)| angle(a) > 1f64.to_radians())
        .map(|(s, a)| (got.get(s).map_or(0.0, angle) / angle(a)).clamp(0.0, 1.0))
        .collect();
    if shares.is_empty() {
        1.0
    } else {
        shares.iter().sum::<f64>() / shares.len() as f64
    }
}

/// When collision on counts as worse than off on a pose: more new crossing faces; an edge
/// stretched over [`TORN`] and more than [`WORSE_STRETCH`] times off's worst (the held pose
/// is another pose, its edges a little other lengths); a vertex farther than [`BEHIND`]
/// of its own medial radii (at least the median) from where its bones hold it, and
/// farther than off's.
const TORN: f64 = 1.5;
const WORSE_STRETCH: f64 = 1.1;
const BEHIND: f64 = 1.0;

/// The summary counts the poses where a section's volume changes by more than this share
/// (the pose issue's bound).
const VOLUME: f64 = 0.05;

/// The summary counts the poses whose worst edge stretches more than this (the pose
/// issue's bound).
const STRETCH: f64 = 3.0;

/// Collision on is worse than off on this pose: what is worse, in words.
fn worse(off: &Surface, on: &Surface) -> Vec<String> {
    let mut out = Vec::new();
    if on.nan && !off.nan {
        out.push("NaN".into());
    }
    if on.crossing > off.crossing {
        out.push(format!(
            "{} crossing faces against {}",
            on.crossing, off.crossing
        ));
    }
    if on.worst > TORN && on.worst > off.worst * WORSE_STRETCH {
        out.push(format!(
            "worst stretch {:.2} against {:.2}",
            on.worst, off.worst
        ));
    }
    if on.behind > BEHIND && on.behind > off.behind {
        out.push(format!(
            "a vertex {:.2} medial radii behind against {:.2}",
            on.behind, off.behind
        ));
    }
    out
}

/// The extensions read from a folder.
const MESH_FILES: [&str; 5] = ["obj", "ply", "stl", "gltf", "glb"];

/// The population: `(name, path)`, `None` for the embedded cow.
fn population(paths: &[PathBuf]) -> Result<Vec<(String, Option<PathBuf>)>> {
    let defaults = [
        PathBuf::from("tests/data/meshes"),
        PathBuf::from("tests/data/characters"),
        PathBuf::from("tests/data/poses"),
    ];
    let mut out = Vec::new();
    if paths.is_empty() {
        out.push(("cow".to_string(), None));
    }
    for path in if paths.is_empty() {
        &defaults[..]
    } else {
        paths
    } {
        if path.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(|e| anyhow!("{}: {e}", path.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.extension()
                        .and_then(|e| e.to_str())
                        .is_some_and(|e| MESH_FILES.contains(&e.to_ascii_lowercase().as_str()))
                })
                .collect();
            files.sort();
            out.extend(files.into_iter().map(|p| (stem(&p), Some(p))));
        } else if path.is_file() {
            out.push((stem(path), Some(path.clone())));
        } else {
            bail!("{}: no such file or folder", path.display());
        }
    }
    Ok(out)
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

pub fn run(args: &Args, load: &LoadArgs) -> Result<()> {
    for (name, v) in [("--limb", args.limb), ("--root", args.root)] {
        if !(v.is_finite() && (0.0..=180.0).contains(&v)) {
            bail!("{name}: {v} is outside 0..180");
        }
    }
    let spread = Spread {
        limb: args.limb,
        root: args.root,
    };
    let characters = population(&args.paths)?;
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    // The table's head, printed with its first row: a file that fails to load before it
    // leaves only its error line.
    let mut table = Table::new(if args.compare {
        &COMPARISON
    } else {
        &CHARACTER
    });
    for (name, path) in characters {
        if args
            .only
            .as_ref()
            .is_some_and(|o| !name.contains(o.as_str()))
        {
            continue;
        }
        let opening = Instant::now();
        let (mesh, report, file) = crate::cli::load_mesh(path.as_deref(), load)?;
        let mut params = puppet::sim::Params::default();
        params.world.collision = args.collision;
        let rig = RigFile {
            params,
            ..RigFile::default()
        };
        let mut base = Puppet::build_loaded(mesh, Some(&report), rig, puppet::progress::silent())
            .map_err(|e| anyhow!("{file}: {e}"))?;
        base.ignore_skin = args.ignore_skin;
        base.suggest_joints().map_err(|e| anyhow!("{file}: {e}"))?;
        let open_s = opening.elapsed().as_secs_f64();
        if args.compare || args.collision {
            base.ready_pose_limit();
        }
        if let Some(m) = args.max_open.filter(|&m| beyond(open_s, m)) {
            failures.push(format!("{name}: opens in {open_s:.2} s > {m} s"));
        }
        let joints = base.joints.cuts().len();
        // Each vertex's part, and each part's size: where the worst edge lies.
        let parts = puppet::mesh::Parts::of(&base.mesh);
        let mut part_size = vec![0usize; parts.len()];
        for &p in &parts.part_of {
            part_size[p as usize] += 1;
        }
        let mut mine = Vec::new();
        let runs: &[bool] = if args.compare {
            &[false, true]
        } else {
            &[args.collision]
        };
        for k in 0..args.poses as u64 {
            let seed = args.seed + k;
            let mut rng = SplitMix(seed);
            let mut target = poses::random_pose(&base.joints, spread, &mut rng);
            if args.drag {
                poses::one_turned(&mut target, &mut rng);
            }
            let mut pair: Vec<Surface> = Vec::new();
            for &collision in runs {
                let start = Instant::now();
                let (times, surface, posed) = if args.targets {
                    let now = poses::targets(&base, &target);
                    (Vec::new(), poses::measure_at(&base, &now, &target), None)
                } else {
                    let (times, surface, got) = settled(&base, collision, &target);
                    (times, surface, Some(got))
                };
                let got = posed.as_deref().map_or(1.0, |g| reached(&target, g));
                let seconds = start.elapsed().as_secs_f64();
                let median = |k: usize, steps: usize| {
                    let mut v: Vec<f64> = times.iter().take(steps).map(|t| t[k]).collect();
                    median(&mut v).unwrap_or(0.0)
                };
                let ramp = (poses::RAMP / f64::from(base.sim.params().solver.time_step)).ceil();
                let mut row = Row {
                    character: name.clone(),
                    seed,
                    joints,
                    collision,
                    surface,
                    volume_sections: surface.volume_sections.map(|s| {
                        s.and_then(|s| base.joints.sections().get(s))
                            .map_or_else(String::new, |s| s.name.clone())
                    }),
                    worst_sections: std::array::from_fn(|k| {
                        surface
                            .worst_edge
                            .and_then(|e| base.joints.section_of().get(e[k]))
                            .and_then(|&s| base.joints.sections().get(usize::from(s)))
                            .map_or_else(String::new, |s| s.name.clone())
                    }),
                    worst_at: surface.worst_edge.and_then(|[a, b]| {
                        let p = &base.mesh.positions;
                        Some(((*p.get(a)? + *p.get(b)?) * 0.5).to_array())
                    }),
                    worst_part: surface
                        .worst_edge
                        .and_then(|[a, _]| parts.part_of.get(a))
                        .map_or(0, |&p| part_size[p as usize]),
                    vertices: base.mesh.positions.len(),
                    step_ms: median(0, times.len()),
                    limit_ms: [
                        median(1, ramp as usize),
                        times.iter().map(|t| t[1]).fold(0.0, f64::max),
                    ],
                    moving_ms: moving(&times, ramp as usize),
                    reached: got,
                    worse: None,
                    open_s,
                };
                pair.push(surface);
                if let [off, on] = pair[..] {
                    let w = worse(&off, &on);
                    if !w.is_empty() {
                        // Is it collision, or the pose it stopped at? That pose settled
                        // with collision off.
                        let there = posed.as_deref().map(|g| settled(&base, false, g).1);
                        row.worse = Some(if there.is_none_or(|t| !worse(&t, &on).is_empty()) {
                            Worse::Collision
                        } else {
                            Worse::Pose
                        });
                        if args.never_worse {
                            let there = there.map_or_else(String::new, |t| {
                                format!(
                                    " (off at the pose reached: {} crossing faces, worst stretch {:.2})",
                                    t.crossing, t.worst
                                )
                            });
                            failures.push(format!(
                                "{name} seed {seed}: collision on: {}{there}",
                                w.join(", ")
                            ));
                        }
                    } else {
                        row.worse = Some(Worse::Not);
                    }
                }
                let s = &row.surface;
                let mut missed = Vec::new();
                if s.nan {
                    missed.push("NaN".to_string());
                }
                if let Some(m) = args.max_stretch.filter(|&m| beyond(s.worst, m)) {
                    missed.push(format!("worst stretch {:.2} > {m}", s.worst));
                }
                if let Some(m) = args.max_over.filter(|&m| beyond(100.0 * s.over_1_5, m)) {
                    missed.push(format!(
                        "{:.2} % of edges over 1.5× > {m} %",
                        100.0 * s.over_1_5
                    ));
                }
                if let Some(m) = args
                    .max_volume
                    .filter(|&m| beyond(100.0 * s.volume[0].abs().max(s.volume[1].abs()), m))
                {
                    missed.push(format!(
                        "a section's volume {:+.1} % ({}) … {:+.1} % ({}) beyond ±{m} %",
                        100.0 * s.volume[0],
                        row.volume_sections[0],
                        100.0 * s.volume[1],
                        row.volume_sections[1]
                    ));
                }
                if !missed.is_empty() {
                    failures.push(format!("{name} seed {seed}: {}", missed.join(", ")));
                }
                if args.json {
                    table::json(&row)?;
                }
                mine.push((row, seconds));
            }
        }
        if let Some(m) = args.max_collision_cost {
            let step = |on: bool, of: &dyn Fn(&Row) -> f64| {
                let mut v: Vec<f64> = mine
                    .iter()
                    .filter(|(r, _)| r.collision == on)
                    .map(|(r, _)| of(r))
                    .collect();
                median(&mut v).unwrap_or(0.0)
            };
            let held = |r: &Row| r.step_ms;
            let moving = |r: &Row| r.moving_ms;
            for (what, of) in [("held", &held as &dyn Fn(&Row) -> f64), ("moving", &moving)] {
                let (off, on) = (step(false, of), step(true, of));
                let ms = args.max_collision_ms;
                if beyond(on, (off * (1.0 + m / 100.0)).max(off + ms)) {
                    failures.push(format!(
                        "{name}: the step with collision on ({what}) costs {on:.3} ms against \
                         {off:.3} off, more than {m} % and {ms} ms over"
                    ));
                }
            }
        }
        if !args.json && !mine.is_empty() {
            table.row(&if args.compare {
                comparison_cells(&name, joints, &mine)
            } else {
                character_cells(&name, joints, &mine)
            });
        }
        rows.extend(mine.into_iter().map(|(r, _)| r));
    }
    if !args.json && rows.len() > 1 {
        let mut worst: Vec<f64> = rows.iter().map(|r| r.surface.worst).collect();
        let beyond_volume = rows
            .iter()
            .filter(|r| r.surface.volume[0] < -VOLUME || r.surface.volume[1] > VOLUME)
            .count();
        // The largest change, and where.
        let most = rows
            .iter()
            .flat_map(|r| (0..2).map(move |k| (r.surface.volume[k], r, k)))
            .filter(|(v, _, _)| v.is_finite())
            .max_by(|a, b| a.0.abs().total_cmp(&b.0.abs()));
        println!(
            "\n{} poses of {} characters: worst stretch median {:.2}, 90th percentile {:.2}, max {:.2}; a section's volume beyond ±{:.0} % in {beyond_volume}",
            rows.len(),
            {
                let mut c: Vec<&str> = rows.iter().map(|r| r.character.as_str()).collect();
                c.dedup();
                c.len()
            },
            median(&mut worst).unwrap_or(f64::NAN),
            quantile(&mut worst, 0.9).unwrap_or(f64::NAN),
            quantile(&mut worst, 1.0).unwrap_or(f64::NAN),
            100.0 * VOLUME,
        );
        let over = rows.iter().filter(|r| r.surface.worst > STRETCH).count();
        if let Some(r) = rows
            .iter()
            .max_by(|a, b| a.surface.worst.total_cmp(&b.surface.worst))
        {
            let [a, b] = &r.worst_sections;
            let between = if a == b {
                format!("within {a}")
            } else {
                format!("between {a} and {b}")
            };
            let at = r.worst_at.map_or_else(String::new, |[x, y, z]| {
                format!(
                    ", at ({x:.3}, {y:.3}, {z:.3}) on a part of {} of its {} vertices",
                    r.worst_part, r.vertices
                )
            });
            println!(
                "The most stretched edge: {:.2}× ({}'s, {between}{at}, seed {}); {over} poses past {STRETCH}×",
                r.surface.worst, r.character, r.seed
            );
        }
        if let Some((v, r, k)) = most {
            println!(
                "A section's largest volume change: {:+.1} % ({}'s {}, seed {})",
                100.0 * v,
                r.character,
                r.volume_sections[k],
                r.seed
            );
        }
        if let Some(slowest) = rows.iter().max_by(|a, b| a.open_s.total_cmp(&b.open_s)) {
            println!(
                "Each opens (file to suggested joints) in at most {:.2} s ({})",
                slowest.open_s, slowest.character
            );
        }
    }
    if !failures.is_empty() {
        // (With `--compare`, each pose is a row off and a row on.)
        let poses = rows.len() / if args.compare { 2 } else { 1 };
        bail!(
            "{} missed over {poses} poses:\n  {}",
            match failures.len() {
                1 => "1 target".to_string(),
                n => format!("{n} targets"),
            },
            failures.join("\n  ")
        );
    }
    Ok(())
}

/// `value` misses the bound `limit` (above it, or not a number).
fn beyond(value: f64, limit: f64) -> bool {
    value.is_nan() || value > limit
}

/// A character's cells in the table per character.
fn character_cells(name: &str, joints: usize, rows: &[(Row, f64)]) -> Vec<String> {
    let at = |q: f64, f: &dyn Fn(&Row) -> f64| {
        let mut v: Vec<f64> = rows.iter().map(|(r, _)| f(r)).collect();
        quantile(&mut v, q).unwrap_or(f64::NAN)
    };
    let worst = |r: &Row| r.surface.worst;
    let crossing = |r: &Row| r.surface.crossing as f64;
    let max = |f: &dyn Fn(&Row) -> f64| rows.iter().map(|(r, _)| f(r)).fold(0.0, f64::max);
    let lo = rows
        .iter()
        .map(|(r, _)| r.surface.volume[0])
        .fold(f64::INFINITY, f64::min);
    let hi = rows
        .iter()
        .map(|(r, _)| r.surface.volume[1])
        .fold(f64::NEG_INFINITY, f64::max);
    let mut secs: Vec<f64> = rows.iter().map(|(_, s)| *s).collect();
    let min_max = |f: &dyn Fn(&Row) -> f64| {
        rows.iter()
            .map(|(r, _)| f(r))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
    };
    let whole = min_max(&|r| r.surface.whole);
    vec![
        name.to_string(),
        joints.to_string(),
        rows.len().to_string(),
        format!("{:.2} … {:.2}", at(0.5, &worst), at(1.0, &worst)),
        format!("{:.2}", max(&|r| r.surface.p99)),
        format!("{:.2}", 100.0 * max(&|r| r.surface.over_1_5)),
        format!("{:.2}", 100.0 * max(&|r| r.surface.over_2)),
        format!("{:.0} … {:.0}", at(0.5, &crossing), at(1.0, &crossing)),
        format!("{:+.1} … {:+.1}", 100.0 * lo, 100.0 * hi),
        format!("{:+.1} … {:+.1}", 100.0 * whole.0, 100.0 * whole.1),
        rows.iter()
            .filter(|(r, _)| r.surface.nan)
            .count()
            .to_string(),
        format!("{:.3}", at(0.5, &|r| r.step_ms)),
        format!("{:.2}", median(&mut secs).unwrap_or(f64::NAN)),
        format!("{:.2}", rows.first().map_or(f64::NAN, |(r, _)| r.open_s)),
    ]
}

/// A character's cells in the table with collision off and on, from its poses (rows
/// alternate: off, on).
fn comparison_cells(name: &str, joints: usize, rows: &[(Row, f64)]) -> Vec<String> {
    let side = |on: bool| -> Vec<&Row> {
        rows.iter()
            .map(|(r, _)| r)
            .filter(|r| r.collision == on)
            .collect()
    };
    let (off, on) = (side(false), side(true));
    let median = |rows: &[&Row], f: &dyn Fn(&Row) -> f64| {
        let mut v: Vec<f64> = rows.iter().map(|r| f(r)).collect();
        median(&mut v).unwrap_or(0.0)
    };
    let max =
        |rows: &[&Row], f: &dyn Fn(&Row) -> f64| rows.iter().map(|r| f(r)).fold(0.0, f64::max);
    let crossing = |r: &Row| r.surface.crossing as f64;
    let count = |w: &[Worse]| {
        on.iter()
            .filter(|r| r.worse.is_some_and(|x| w.contains(&x)))
            .count()
    };
    let worse_poses = count(&[Worse::Pose, Worse::Collision]);
    let worse_there = count(&[Worse::Collision]);
    vec![
        name.to_string(),
        joints.to_string(),
        off.len().to_string(),
        format!(
            "{:.0} → {:.0}; {:.0} → {:.0}",
            median(&off, &crossing),
            median(&on, &crossing),
            max(&off, &crossing),
            max(&on, &crossing)
        ),
        format!(
            "{:.2} → {:.2}",
            max(&off, &|r| r.surface.worst),
            max(&on, &|r| r.surface.worst)
        ),
        format!(
            "{:.2} → {:.2}",
            max(&off, &|r| r.surface.behind),
            max(&on, &|r| r.surface.behind)
        ),
        format!("{worse_poses} ({worse_there})"),
        format!(
            "{:.0}; {:.0}",
            100.0 * median(&on, &|r| r.reached),
            100.0 * on.iter().map(|r| r.reached).fold(1.0, f64::min)
        ),
        format!(
            "{:.3} → {:.3}",
            median(&off, &|r| r.step_ms),
            median(&on, &|r| r.step_ms)
        ),
        format!(
            "{:.3} → {:.3}",
            median(&off, &|r| r.moving_ms),
            median(&on, &|r| r.moving_ms)
        ),
        format!(
            "{:.3}; {:.2}",
            median(&on, &|r| r.limit_ms[0]),
            max(&on, &|r| r.limit_ms[1])
        ),
    ]
}

/// The columns of the table per character.
const CHARACTER: [Column; 14] = [
    Column::Text("character"),
    Column::Figure("joints"),
    Column::Figure("poses"),
    Column::Figure("worst stretch (median … max)"),
    Column::Figure("p99 stretch (max)"),
    Column::Figure("edges over 1.5× (max %)"),
    Column::Figure("edges over 2× (max %)"),
    Column::Figure("new crossing faces (median … max)"),
    Column::Figure("section volume (% min … max)"),
    Column::Figure("whole volume (% min … max)"),
    Column::Figure("NaN"),
    Column::Figure("step (ms)"),
    Column::Figure("pose (s)"),
    Column::Figure("open (s)"),
];

/// The columns of the table per character with collision off and on (`--compare`).
const COMPARISON: [Column; 11] = [
    Column::Text("character"),
    Column::Figure("joints"),
    Column::Figure("poses"),
    Column::Figure("new crossing faces off → on (median; max)"),
    Column::Figure("worst stretch off → on (max)"),
    Column::Figure("farthest behind off → on (max, medial radii)"),
    Column::Figure("poses worse on (also than off at the pose reached)"),
    Column::Figure("turn reached on (median; least %)"),
    Column::Figure("step off → on (median ms)"),
    Column::Figure("step while moving off → on, pose limit included (median ms)"),
    Column::Figure("pose limit while moving (median; max ms)"),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// What counts as collision on being worse than off, each bound on its own.
    #[test]
    fn worse_names_each_way_collision_on_can_be_worse() {
        let off = Surface {
            worst: 1.4,
            crossing: 3,
            behind: 0.2,
            ..Surface::default()
        };
        assert!(worse(&off, &off).is_empty());
        let more = |f: &dyn Fn(&mut Surface)| {
            let mut on = off;
            f(&mut on);
            worse(&off, &on)
        };
        assert_eq!(more(&|s| s.crossing = 4).len(), 1);
        // Stretch: worse only past a tear and past a tenth more than off.
        assert!(more(&|s| s.worst = 1.49).is_empty());
        assert_eq!(more(&|s| s.worst = 1.6).len(), 1);
        assert!(more(&|s| s.behind = 0.9).is_empty());
        assert_eq!(more(&|s| s.behind = 1.2).len(), 1);
        assert_eq!(more(&|s| s.nan = true).len(), 1);
    }

    /// A step while the pose moves is the pose limit and the step together, over the
    /// ramp's steps only (the held steps after it cost no pose limit).
    #[test]
    fn a_moving_step_counts_the_pose_limit_over_the_ramp() {
        let times = [[1.0, 0.5], [2.0, 0.1], [0.5, 3.0], [0.1, 0.0], [0.1, 0.0]];
        assert_eq!(moving(&times, 3), 2.1);
        assert_eq!(moving(&times, 0), 0.0);
    }

    /// The share of a pose reached: the mean share of each turned section's turn; the root
    /// and sections asked to stay do not count.
    #[test]
    fn reached_is_the_mean_share_of_each_turn() {
        let turn = |deg: f64| Local {
            rotation: glam::DQuat::from_rotation_x(deg.to_radians()),
            translation: glam::DVec3::ZERO,
        };
        let asked = [turn(30.0), turn(90.0), turn(40.0), turn(0.0)];
        assert!((reached(&asked, &asked) - 1.0).abs() < 1e-9);
        let got = [turn(0.0), turn(45.0), turn(0.0), turn(10.0)];
        assert!((reached(&asked, &got) - 0.25).abs() < 1e-9);
        assert_eq!(reached(&[turn(30.0)], &[]), 1.0);
        assert_eq!(reached(&asked, &[]), 0.0);
    }
}
