//! `puppet bench --skeleton` (accuracy against analytic shapes) and `--skeleton-speed`
//! (time per stage on a mesh Loop-subdivided 0..=N times, with peak memory).

use crate::cli::load_mesh;
use anyhow::Result;
use puppet::mesh::{subdivide_loop, vertex_normals};
use puppet::skeleton::{self, truth, Method, SkeletonParams};

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
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

pub fn accuracy(args: &AccuracyArgs) -> Result<()> {
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

pub fn speed(args: &SpeedArgs) -> Result<()> {
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
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}
