//! `puppet bench skeleton` (accuracy against analytic shapes) and `skeleton-speed` (the
//! time from a file to its skeleton, per stage, on a mesh Loop-subdivided 0..=N times, the
//! time to write the skeletal OBJ against the disk's own speed, and peak memory).

use super::table::{self, Column, Table};
use crate::cli::{load_mesh, FileError, LoadArgs};
use anyhow::{bail, Result};
use puppet::bench::truth;
use puppet::mesh::{self, subdivide_loop, vertex_normals, write_obj};
use puppet::skeleton::{self, Method, SkeletonParams};
use puppet::stats::median;
use std::time::Instant;

/// `puppet bench skeleton`.
#[derive(clap::Args, Debug)]
pub struct AccuracyArgs {
    /// Resolutions per shape (1 to 3).
    #[arg(long, default_value_t = 3)]
    levels: usize,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

/// `puppet bench skeleton-speed`.
#[derive(clap::Args, Debug)]
pub struct SpeedArgs {
    /// Mesh to measure on; the embedded Spot when omitted.
    mesh: Option<std::path::PathBuf>,
    /// Loop subdivision steps (each quadruples the faces; at most 6).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(0..=6))]
    subdivisions: u8,
    /// Runs per size; the median is reported.
    #[arg(long, default_value_t = 3)]
    runs: usize,
    /// Fail (exit status 2) when reading a file of 100k vertices or more (read, parse,
    /// weld, repair, check) takes longer than this fraction of its skeleton.
    #[arg(long, value_parser = super::bound)]
    max_load_ratio: Option<f64>,
    /// Fail when writing the skeletal OBJ is slower than this fraction of writing the same
    /// number of bytes straight to the same disk.
    #[arg(long, value_parser = super::bound)]
    min_write_speed: Option<f64>,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

pub fn accuracy(args: &AccuracyArgs) -> Result<()> {
    let cases = truth::cases(args.levels);
    let rows = truth::accuracy(&cases, &Method::ALL, SkeletonParams::default().sliver_ratio);
    if args.json {
        return table::json(&rows);
    }
    let mut table = Table::new(&[
        Column::Text("shape"),
        Column::Text("resolution"),
        Column::Figure("vertices"),
        Column::Text("method"),
        Column::Figure("median rel. error"),
        Column::Figure("p95 rel. error"),
        Column::Figure("fallback"),
        Column::Figure("clamped"),
    ]);
    table.start();
    for r in &rows {
        table.row(&[
            r.shape.to_string(),
            r.resolution.to_string(),
            r.vertices.to_string(),
            r.method.to_string(),
            format!("{:.4}", r.median_rel_error),
            format!("{:.4}", r.p95_rel_error),
            r.fallback.to_string(),
            r.clamped.to_string(),
        ]);
    }
    Ok(())
}

#[derive(serde::Serialize)]
struct SpeedRow {
    vertices: usize,
    faces: usize,
    file_mib: f64,
    runs: usize,
    /// From the file to the skeleton: load, normals, skeleton.
    seconds_median: f64,
    /// Read, parse, weld, (repair,) check.
    load_median: f64,
    skeleton_median: f64,
    load_ratio: f64,
    stages_median: Vec<(String, f64)>,
    /// Writing the skeletal OBJ, and the same bytes written straight to the same disk.
    write_median: f64,
    raw_write_median: f64,
    peak_rss_mib: Option<f64>,
}

/// Files of the measurement, removed when it ends.
struct Scratch(std::path::PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Median of each stage over runs (stages in the order of the first run).
fn stage_medians(runs: &[Vec<(String, f64)>]) -> Vec<(String, f64)> {
    runs[0]
        .iter()
        .map(|(stage, _)| {
            let mut values: Vec<f64> = runs
                .iter()
                .filter_map(|r| r.iter().find(|(s, _)| s == stage).map(|x| x.1))
                .collect();
            (stage.clone(), median(&mut values).unwrap_or(f64::NAN))
        })
        .collect()
}

pub fn speed(args: &SpeedArgs, load: &LoadArgs) -> Result<()> {
    let (mut mesh, _, name) = load_mesh(args.mesh.as_deref(), load)?;
    let dir = std::env::temp_dir().join(format!("puppet-skeleton-speed-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let scratch = Scratch(dir);
    let options = load.options();
    let mut rows = Vec::new();
    let runs = args.runs.max(1);
    for level in 0..=args.subdivisions as usize {
        // The input file itself, then each subdivision written as an OBJ file.
        let file = match (level, &args.mesh) {
            (0, Some(path)) => path.clone(),
            _ => {
                if level > 0 {
                    mesh = subdivide_loop(&mesh);
                }
                let path = scratch.0.join(format!("level-{level}.obj"));
                let mut out = std::io::BufWriter::new(std::fs::File::create(&path)?);
                write_obj(
                    &mut out,
                    &mesh.positions,
                    &mesh.triangles,
                    "skeleton-speed input",
                )?;
                path
            }
        };
        let file_bytes = std::fs::metadata(&file)?.len();
        let mut totals = Vec::new();
        let mut loads = Vec::new();
        let mut skeletons = Vec::new();
        let mut stages: Vec<Vec<(String, f64)>> = Vec::new();
        let mut writes = Vec::new();
        let mut raw_writes = Vec::new();
        let (mut vertices, mut faces) = (0, 0);
        for _ in 0..runs {
            let t = Instant::now();
            let (m, report) = mesh::load_with(&file, &options, puppet::progress::silent())
                .map_err(|e| FileError::new(file.display().to_string(), e))?;
            let load_seconds = report.total_seconds();
            let t_normals = Instant::now();
            let normals = vertex_normals(&m)?;
            let normals_seconds = t_normals.elapsed().as_secs_f64();
            let t_skeleton = Instant::now();
            let sk = skeleton::build(
                &m,
                &normals,
                &SkeletonParams::default(),
                puppet::progress::silent(),
            )?;
            // The whole call, riders' bookkeeping included.
            let sk_total = t_skeleton.elapsed().as_secs_f64();
            totals.push(t.elapsed().as_secs_f64());
            loads.push(load_seconds);
            skeletons.push(sk_total);
            let mut st: Vec<(String, f64)> = report
                .seconds
                .iter()
                .map(|(k, v)| (k.to_string(), *v))
                .collect();
            st.push(("normals".into(), normals_seconds));
            st.extend(
                sk.seconds
                    .iter()
                    .filter(|s| s.0 != "total")
                    .map(|(k, v)| (k.to_string(), *v)),
            );
            stages.push(st);
            // Writing the skeletal mesh, then as many bytes written plainly.
            let out = scratch.0.join("skeletal.obj");
            let t = Instant::now();
            let mut w = std::io::BufWriter::new(std::fs::File::create(&out)?);
            write_obj(&mut w, &sk.points, &m.triangles, "skeletal mesh")?;
            drop(w);
            writes.push(t.elapsed().as_secs_f64());
            let size = std::fs::metadata(&out)?.len() as usize;
            let bytes = vec![b'x'; size];
            let t = Instant::now();
            std::fs::write(scratch.0.join("raw.bin"), &bytes)?;
            raw_writes.push(t.elapsed().as_secs_f64());
            (vertices, faces) = (m.positions.len(), m.triangles.len());
        }
        let load_median = median(&mut loads).unwrap_or(f64::NAN);
        let skeleton_median = median(&mut skeletons).unwrap_or(f64::NAN);
        rows.push(SpeedRow {
            vertices,
            faces,
            file_mib: file_bytes as f64 / (1024.0 * 1024.0),
            runs,
            seconds_median: median(&mut totals).unwrap_or(f64::NAN),
            load_median,
            skeleton_median,
            load_ratio: load_median / skeleton_median.max(1e-12),
            stages_median: stage_medians(&stages),
            write_median: median(&mut writes).unwrap_or(f64::NAN),
            raw_write_median: median(&mut raw_writes).unwrap_or(f64::NAN),
            peak_rss_mib: peak_rss_mib(),
        });
    }
    drop(scratch);
    if args.json {
        table::json(&rows)?;
    } else {
        print_speed(&name, runs, &rows);
    }
    for r in &rows {
        if let Some(max) = args.max_load_ratio {
            if r.vertices >= 100_000 && r.load_ratio > max {
                bail!(
                    "reading {} vertices took {:.2} of the skeleton's time (at most {max})",
                    r.vertices,
                    r.load_ratio
                );
            }
        }
        if let Some(min) = args.min_write_speed {
            let speed = r.raw_write_median / r.write_median.max(1e-12);
            if r.vertices >= 100_000 && speed < min {
                bail!(
                    "writing the skeletal OBJ of {} vertices ran at {speed:.2} of the disk's speed (at least {min})",
                    r.vertices
                );
            }
        }
    }
    Ok(())
}

fn print_speed(name: &str, runs: usize, rows: &[SpeedRow]) {
    println!(
        "from file to skeleton on {name} (Loop-subdivided, each size read from an OBJ file), default parameters, median of {runs} runs"
    );
    println!();
    let mut table = Table::new(&[
        Column::Figure("vertices"),
        Column::Figure("file MiB"),
        Column::Figure("total ms"),
        Column::Figure("load ms"),
        Column::Figure("skeleton ms"),
        Column::Figure("load / skeleton"),
        Column::Text("stages (ms)"),
        Column::Figure("write ms (disk ms)"),
        Column::Figure("peak RSS MiB"),
    ]);
    table.start();
    for r in rows {
        let st: Vec<String> = r
            .stages_median
            .iter()
            .map(|(s, v)| format!("{s} {:.1}", v * 1e3))
            .collect();
        table.row(&[
            r.vertices.to_string(),
            format!("{:.1}", r.file_mib),
            format!("{:.1}", r.seconds_median * 1e3),
            format!("{:.1}", r.load_median * 1e3),
            format!("{:.1}", r.skeleton_median * 1e3),
            format!("{:.2}", r.load_ratio),
            st.join(", "),
            format!(
                "{:.1} ({:.1})",
                r.write_median * 1e3,
                r.raw_write_median * 1e3
            ),
            r.peak_rss_mib
                .map(|m| format!("{m:.0}"))
                .unwrap_or_else(|| "?".into()),
        ]);
    }
}

/// Peak resident memory of this process so far (Linux), in MiB.
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// `puppet bench skeleton-change`.
#[derive(clap::Args, Debug)]
pub struct ChangeArgs {
    /// Meshes to compare on; the embedded Spot when none is given.
    meshes: Vec<std::path::PathBuf>,
    /// The method compared against.
    #[arg(long, value_enum, default_value_t = Method::ShrinkingBall)]
    from: Method,
    /// The method compared (default: the default method).
    #[arg(long, value_enum)]
    to: Option<Method>,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

/// One mesh's row of `skeleton-change`.
#[derive(serde::Serialize)]
struct ChangeRow {
    mesh: String,
    vertices: usize,
    /// Skeletal points that moved by more than 1e-9 of the bounding-box diagonal.
    moved: usize,
    /// Median, 95th percentile and largest move of the moved points, relative to the
    /// point's skeletal distance under `from`.
    median_rel_move: f64,
    p95_rel_move: f64,
    max_rel_move: f64,
    /// Largest move relative to the bounding-box diagonal.
    max_move_of_diagonal: f64,
    /// Skeletal points of `to` (with a positive distance) outside the mesh.
    outside: usize,
    /// Of those, the ones whose point under `from` is inside (where a mesh intersects
    /// itself, a point can be "outside" under every method).
    newly_outside: usize,
}

/// How far each skeletal point moves from one method to another on real meshes, and whether
/// every one of the new points is still inside. Fails (exit status 2) if one that was
/// inside is not.
pub fn change(args: &ChangeArgs, load: &LoadArgs) -> Result<()> {
    let to = args.to.unwrap_or_default();
    let inputs: Vec<Option<&std::path::Path>> = if args.meshes.is_empty() {
        vec![None]
    } else {
        args.meshes.iter().map(|m| Some(m.as_path())).collect()
    };
    let mut rows = Vec::new();
    for input in inputs {
        let (mesh, _, name) = load_mesh(input, load)?;
        let normals = vertex_normals(&mesh).map_err(|e| FileError::new(&name, e))?;
        let none = puppet::progress::silent();
        let build = |method| {
            let params = SkeletonParams {
                method,
                ..SkeletonParams::default()
            };
            skeleton::build(&mesh, &normals, &params, none).map_err(|e| FileError::new(&name, e))
        };
        let (old, new) = (build(args.from)?, build(to)?);
        let (lo, hi) = mesh.bounds();
        let diagonal = (hi - lo).length().max(f64::MIN_POSITIVE);
        let mut rel: Vec<f64> = Vec::new();
        let mut largest: f64 = 0.0;
        for ((a, b), d) in old.points.iter().zip(&new.points).zip(&old.distance) {
            let moved = a.distance(*b);
            if moved > 1e-9 * diagonal {
                rel.push(moved / d.max(1e-12 * diagonal));
                largest = largest.max(moved);
            }
        }
        rel.sort_by(f64::total_cmp);
        let at = |q: f64| {
            rel.get(((rel.len() as f64 - 1.0) * q).round() as usize)
                .copied()
                .unwrap_or(0.0)
        };
        let inside = puppet::geom::inside::InsideTest::new(&mesh);
        let out = |sk: &skeleton::Skeleton, v: usize| {
            sk.distance[v] > 0.0 && !inside.contains(sk.points[v])
        };
        let outside: Vec<usize> = (0..mesh.positions.len())
            .filter(|&v| out(&new, v))
            .collect();
        let newly_outside = outside.iter().filter(|&&v| !out(&old, v)).count();
        rows.push(ChangeRow {
            mesh: name,
            vertices: mesh.positions.len(),
            moved: rel.len(),
            median_rel_move: at(0.5),
            p95_rel_move: at(0.95),
            max_rel_move: rel.last().copied().unwrap_or(0.0),
            max_move_of_diagonal: largest / diagonal,
            outside: outside.len(),
            newly_outside,
        });
    }
    if args.json {
        table::json(&rows)?;
    } else {
        println!("{} -> {to}", args.from);
        println!();
        let mut table = Table::new(&[
            Column::Text("mesh"),
            Column::Figure("vertices"),
            Column::Figure("points moved"),
            Column::Figure("median move / d"),
            Column::Figure("p95 move / d"),
            Column::Figure("largest move / d"),
            Column::Figure("largest move / diagonal"),
            Column::Figure("outside (newly)"),
        ]);
        table.start();
        for r in &rows {
            table.row(&[
                r.mesh.to_string(),
                r.vertices.to_string(),
                format!(
                    "{} ({:.1} %)",
                    r.moved,
                    100.0 * r.moved as f64 / r.vertices.max(1) as f64
                ),
                format!("{:.4}", r.median_rel_move),
                format!("{:.4}", r.p95_rel_move),
                format!("{:.3}", r.max_rel_move),
                format!("{:.5}", r.max_move_of_diagonal),
                format!("{} ({})", r.outside, r.newly_outside),
            ]);
        }
    }
    let outside: usize = rows.iter().map(|r| r.newly_outside).sum();
    if outside > 0 {
        bail!(
            "{outside} skeletal points of {to} lie outside their mesh where those of {} do not",
            args.from
        );
    }
    Ok(())
}
