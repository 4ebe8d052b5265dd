//! `puppet skeleton MESH.obj [--method M] [-o SKELETON.obj] [--json]`.

use super::progress_bar::ProgressBar;
use super::{load_mesh, FileError};
use anyhow::Result;
use puppet::mesh::{vertex_normals, write_obj};
use puppet::skeleton::{self, Method, SkeletonParams};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Mesh (OBJ, PLY, STL, glTF or glb); the embedded Spot when omitted.
    pub mesh: Option<PathBuf>,
    /// How the skeletal distance is taken (default: fitted-ball).
    #[arg(long, value_enum)]
    pub method: Option<Method>,
    /// Write the skeletal mesh S here (same vertex order and faces as the welded input).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub json: bool,
}

/// Summary printed by the command (`--json` prints exactly these fields).
#[derive(serde::Serialize)]
struct Summary<'a> {
    file: &'a str,
    vertices: usize,
    faces: usize,
    method: Method,
    tetrahedra: usize,
    inside_voronoi_vertices: usize,
    fallback: usize,
    clamped: usize,
    riders: usize,
    /// Skeletal points moved back inside the mesh ([`skeleton::Skeleton::hold_inside`]).
    moved_inside: usize,
    d_min: f64,
    d_median: f64,
    d_max: f64,
    seconds: serde_json::Map<String, serde_json::Value>,
    output: Option<String>,
}

pub fn run(args: &Args, load: &super::LoadArgs) -> Result<()> {
    let (mesh, report, name) = load_mesh(args.mesh.as_deref(), load)?;
    let t_load = std::time::Instant::now();
    let normals = vertex_normals(&mesh).map_err(|e| FileError::new(&name, e))?;
    let t_normals = t_load.elapsed().as_secs_f64();
    let params = SkeletonParams {
        method: args.method.unwrap_or(SkeletonParams::default().method),
        ..SkeletonParams::default()
    };
    let bar = ProgressBar::new();
    let mut sk = skeleton::build(&mesh, &normals, &params, &|s, f| bar.update(s, f))
        .map_err(|e| FileError::new(&name, e))?;
    // The skeleton the puppet uses: held inside a repaired mesh, and a mesh in pieces.
    let parts = puppet::mesh::Parts::of(&mesh);
    let moved_inside = sk.hold_inside(&mesh, &parts, !report.marks.is_empty());
    bar.finish();
    let mut t_written = None;
    if let Some(out) = &args.output {
        let file = std::fs::File::create(out)
            .map_err(|e| FileError::new(out.display().to_string(), format!("cannot write: {e}")))?;
        let t_write = std::time::Instant::now();
        let header = format!(
            "skeletal mesh of {name} by puppet {} (method {}): vertex i is p_i - d_i n_i",
            env!("CARGO_PKG_VERSION"),
            params.method
        );
        write_obj(&mut &file, &sk.points, &mesh.triangles, &header)
            .map_err(|e| FileError::new(out.display().to_string(), format!("cannot write: {e}")))?;
        t_written = Some(t_write.elapsed().as_secs_f64());
    }
    let (d_min, d_median, d_max) = min_median_max(&sk.distance);
    let mut seconds = serde_json::Map::new();
    for (stage, s) in &report.seconds {
        seconds.insert((*stage).into(), (*s).into());
    }
    seconds.insert("normals".into(), t_normals.into());
    // `total` is the whole run, from reading the file (its repairs too) to writing the
    // skeleton; the skeleton's own stages sum to `skeleton`.
    let mut total = report.total_seconds() + t_normals;
    for (stage, s) in &sk.seconds {
        if *stage == "total" {
            seconds.insert("skeleton".into(), (*s).into());
            total += s;
        } else {
            seconds.insert((*stage).into(), (*s).into());
        }
    }
    if let Some(w) = t_written {
        seconds.insert("write".into(), w.into());
        total += w;
    }
    seconds.insert("total".into(), total.into());
    let summary = Summary {
        file: &name,
        vertices: mesh.positions.len(),
        faces: mesh.triangles.len(),
        method: params.method,
        tetrahedra: sk.tetrahedra,
        inside_voronoi_vertices: sk.inside_voronoi_vertices,
        fallback: sk.fallback,
        clamped: sk.clamped,
        riders: sk.riders,
        moved_inside,
        d_min,
        d_median,
        d_max,
        seconds,
        output: args.output.as_ref().map(|p| p.display().to_string()),
    };
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
        return Ok(());
    }
    println!(
        "{}: {} vertices, {} faces",
        name, summary.vertices, summary.faces
    );
    println!(
        "skeleton ({}): d min {:.4}  median {:.4}  max {:.4}; {} fallback (sp = p), {} clamped to thickness, {} moved back inside",
        params.method, d_min, d_median, d_max, sk.fallback, sk.clamped, moved_inside
    );
    let stages: Vec<String> = summary
        .seconds
        .iter()
        .map(|(k, v)| format!("{k} {:.1} ms", v.as_f64().unwrap_or(0.0) * 1e3))
        .collect();
    println!("time: {}", stages.join(", "));
    if let Some(out) = &summary.output {
        println!("wrote {out}");
    }
    Ok(())
}

/// Minimum, median and maximum (zeros for an empty slice).
pub fn min_median_max(v: &[f64]) -> (f64, f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    (s[0], s[s.len() / 2], s[s.len() - 1])
}
