//! `puppet bench export`: time and file size of a take in each export format.
//!
//! The standard scenario on the mesh Loop-subdivided `--subdivisions` times (Spot twice:
//! 46,850 vertices) plays `--frames` frames at 30 fps; each format then writes every frame
//! to a scratch folder (removed afterwards), timed from the frames in memory to the file
//! closed.

use super::table::{self, Column, Table};
use super::{Base, Input};
use crate::cli::LoadArgs;
use anyhow::{Context, Result};
use puppet::export::{glb, pc2, Frames};
use puppet::sim::{Params, Simulation};
use std::io::Write;
use std::time::Instant;

/// `puppet bench export`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Loop subdivisions of the mesh.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(0..=4))]
    subdivisions: u8,
    /// Frames in the take.
    #[arg(long, default_value_t = 300, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    frames: u64,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct Row {
    format: &'static str,
    seconds: f64,
    bytes: u64,
    files: usize,
    /// The largest distance of a written position from the simulated one, as a share of
    /// the mesh's diagonal (0: exact).
    largest_error: f64,
}

#[derive(serde::Serialize)]
struct Report {
    mesh: String,
    vertices: usize,
    frames: u64,
    rows: Vec<Row>,
}

pub fn run(args: &Args, load: &LoadArgs) -> Result<()> {
    let base = Base::load(&args.input, load, None)?;
    let scenario = base.scenario(args.subdivisions as usize, 1.0)?;
    let params = Params::default();
    let mut sim = Simulation::new(scenario.rig(params.material.bone_distance), params);
    sim.set_sections(scenario.joints.section_of().to_vec());
    let fps = 30.0;
    let h = params.solver.time_step as f64;
    let mut frames = Vec::with_capacity(args.frames as usize);
    let mut steps = 0u64;
    for k in 1..=args.frames {
        while (steps as f64) * h < k as f64 / fps - 1e-9 {
            steps += 1;
            sim.step(&scenario.pose(steps as f64 * h));
        }
        let x = sim.positions();
        frames.push((0..x.len()).map(|i| x.get(i)).collect());
    }
    let normals = puppet::mesh::vertex_normals(&scenario.mesh)?;
    let take = Frames {
        triangles: scenario.mesh.triangles.clone(),
        rest: scenario
            .mesh
            .positions
            .iter()
            .map(|p| p.as_vec3())
            .collect(),
        normals: normals.iter().map(|n| n.as_vec3()).collect(),
        frames,
        fps,
        first: 1,
        step: 1,
    };
    let dir = std::env::temp_dir().join(format!("puppet-bench-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| dir.display().to_string())?;
    let write = |name: &str, bytes: &[u8]| -> Result<u64> {
        let path = dir.join(name);
        let mut f = std::fs::File::create(&path).with_context(|| path.display().to_string())?;
        f.write_all(bytes)?;
        f.sync_all()?;
        Ok(bytes.len() as u64)
    };
    let diagonal = scenario.mesh.diagonal();
    // The largest distance of a decoded position from the simulated one, of the diagonal.
    let largest = |decoded: &mut dyn Iterator<Item = glam::Vec3>| -> f64 {
        let mut worst = 0.0f64;
        let mut count = 0;
        for (d, p) in decoded.zip(take.frames.iter().flatten()) {
            let e = d.as_dvec3().distance(p.as_dvec3());
            worst = if e.is_nan() {
                f64::INFINITY
            } else {
                worst.max(e)
            };
            count += 1;
        }
        if count == take.frames.len() * take.rest.len() {
            worst / diagonal
        } else {
            f64::INFINITY
        }
    };
    let mut rows = Vec::new();
    let t = Instant::now();
    let bytes = write("take.glb", &glb::write(&take)?)?;
    let seconds = t.elapsed().as_secs_f64();
    // What a reader decodes: the rest position plus the frame's morph target.
    let n = take.rest.len();
    let mut decoded = take
        .frames
        .iter()
        .flat_map(|f| f.iter().zip(&take.rest).map(|(p, r)| *r + (*p - *r)))
        .take(take.frames.len() * n);
    rows.push(Row {
        format: "glTF binary (.glb)",
        seconds,
        bytes,
        files: 1,
        largest_error: largest(&mut decoded),
    });
    let t = Instant::now();
    let bytes = write("take16.glb", &glb::write_with(&take, true)?)?;
    let seconds = t.elapsed().as_secs_f64();
    // What a reader decodes: the grid point through the node's transform.
    let grid = glb::Grid::of(&take);
    let largest_16 = take
        .frames
        .iter()
        .flatten()
        .map(|&p| {
            let q = glam::IVec3::from_array(grid.point(p)).as_vec3();
            (grid.center + q * grid.scale - p).length()
        })
        .fold(0.0f32, f32::max);
    rows.push(Row {
        format: "glTF binary, 16-bit (`--quantize`)",
        seconds,
        bytes,
        files: 1,
        largest_error: largest_16 as f64 / diagonal,
    });
    let t = Instant::now();
    let rest: Vec<glam::DVec3> = take.rest.iter().map(|p| p.as_dvec3()).collect();
    let mut obj = Vec::new();
    puppet::mesh::write_obj(&mut obj, &rest, &take.triangles, "base")?;
    let cache = pc2::write(&take)?;
    let bytes = write("take.obj", &obj)? + write("take.pc2", &cache)?;
    let seconds = t.elapsed().as_secs_f64();
    // What a reader decodes: the little-endian floats after the 32-byte header.
    let floats: Vec<f32> = cache
        .get(32..)
        .unwrap_or_default()
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let mut decoded = floats
        .chunks_exact(3)
        .map(|c| glam::Vec3::new(c[0], c[1], c[2]));
    rows.push(Row {
        format: "PC2 + base OBJ",
        seconds,
        bytes,
        files: 2,
        largest_error: largest(&mut decoded),
    });
    let mut bytes = 0;
    let mut seconds = 0.0;
    let mut worst = 0.0f64;
    for (k, frame) in take.frames.iter().enumerate() {
        let t = Instant::now();
        let points: Vec<glam::DVec3> = frame.iter().map(|p| p.as_dvec3()).collect();
        let mut obj = Vec::new();
        puppet::mesh::write_obj(&mut obj, &points, &take.triangles, "frame")?;
        bytes += write(&format!("frame_{:05}.obj", k + 1), &obj)?;
        seconds += t.elapsed().as_secs_f64();
        // What a reader decodes (untimed): each `v` line's numbers as single floats.
        let text = String::from_utf8_lossy(&obj);
        let decoded: Vec<glam::Vec3> = text
            .lines()
            .filter_map(|l| l.strip_prefix("v "))
            .map(|l| {
                let c: Vec<f32> = l
                    .split_whitespace()
                    .map(|x| x.parse().unwrap_or(f32::NAN))
                    .collect();
                let at = |k: usize| c.get(k).copied().unwrap_or(f32::NAN);
                glam::Vec3::new(at(0), at(1), at(2))
            })
            .collect();
        worst = worst.max(if decoded.len() == frame.len() {
            decoded
                .iter()
                .zip(frame)
                .map(|(d, p)| d.as_dvec3().distance(p.as_dvec3()))
                .fold(
                    0.0,
                    |a: f64, e| if e.is_nan() { f64::INFINITY } else { a.max(e) },
                )
        } else {
            f64::INFINITY
        });
    }
    rows.push(Row {
        format: "OBJ sequence",
        seconds,
        bytes,
        files: take.frames.len(),
        largest_error: worst / diagonal,
    });
    let _ = std::fs::remove_dir_all(&dir);
    let report = Report {
        mesh: base.name.clone(),
        vertices: take.rest.len(),
        frames: args.frames,
        rows,
    };
    if args.json {
        return table::json(&report);
    }
    println!(
        "{} Loop-subdivided {}x ({} vertices), {} frames",
        report.mesh, args.subdivisions, report.vertices, report.frames
    );
    println!();
    let mut table = Table::new(&[
        Column::Text("format"),
        Column::Figure("seconds"),
        Column::Figure("MB"),
        Column::Figure("files"),
        Column::Figure("largest error (of the diagonal)"),
    ]);
    table.start();
    for r in &report.rows {
        table.row(&[
            r.format.to_string(),
            format!("{:.2}", r.seconds),
            format!("{:.1}", r.bytes as f64 / 1e6),
            r.files.to_string(),
            if r.largest_error == 0.0 {
                "exact".to_string()
            } else {
                format!("{:.1e}", r.largest_error)
            },
        ]);
    }
    Ok(())
}
