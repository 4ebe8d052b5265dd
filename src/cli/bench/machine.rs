//! `puppet bench --machine`: what this machine can do, as yardsticks for the step.
//!
//! * **Copy bandwidth**: a 256 MiB `f32` buffer scaled into another (read + write counted),
//!   with one thread and with all, median of 7.
//! * **Plain spring loop**: the simplest single-threaded scalar loop of the step's force
//!   work on a 1024 × 768 torus grid (6 neighbours per vertex, row-major order, so every
//!   gather is local): per vertex the CSR neighbours, `(|d| − rest)/|d| · d` summed, one
//!   store. No bones, Verlet or constraint: a floor for what one core does per spring.

use super::median_p95;
use super::table;
use anyhow::Result;
use rayon::prelude::*;

#[derive(serde::Serialize)]
struct Report {
    copy_gb_per_second_1_thread: f64,
    copy_gb_per_second_all_threads: f64,
    threads: usize,
    plain_loop_vertices: usize,
    plain_loop_springs: usize,
    plain_loop_ms_median: f64,
    plain_loop_springs_per_second: f64,
}

fn copy_bandwidth(threads: usize) -> Result<f64> {
    let n = 64 << 20;
    let a: Vec<f32> = (0..n).map(|i| i as f32).collect();
    let mut b = vec![0f32; n];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let mut rates = Vec::new();
    pool.install(|| {
        for _ in 0..7 {
            let t = std::time::Instant::now();
            b.par_chunks_mut(1 << 16)
                .zip(a.par_chunks(1 << 16))
                .for_each(|(d, s)| d.iter_mut().zip(s).for_each(|(x, y)| *x = *y * 1.5));
            rates.push((n * 8) as f64 / t.elapsed().as_secs_f64() / 1e9);
        }
    });
    std::hint::black_box(&b);
    Ok(median_p95(rates).0)
}

/// (vertices, springs, median ms) of the plain loop.
fn plain_loop() -> (usize, usize, f64) {
    let (w, h) = (1024usize, 768usize);
    let n = w * h;
    let at = |i: isize, j: isize| {
        (j.rem_euclid(h as isize) as usize) * w + i.rem_euclid(w as isize) as usize
    };
    let x: Vec<f32> = (0..n).map(|k| (k % w) as f32 * 0.01).collect();
    let y: Vec<f32> = (0..n).map(|k| (k / w) as f32 * 0.01).collect();
    let z: Vec<f32> = (0..n)
        .map(|k| 0.002 * ((k % w) as f32 * 0.1).sin())
        .collect();
    let (mut start, mut nb, mut rest) = (vec![0u32], Vec::new(), Vec::new());
    for j in 0..h as isize {
        for i in 0..w as isize {
            let k = at(i, j);
            let mut v = [
                at(i + 1, j),
                at(i - 1, j),
                at(i, j + 1),
                at(i, j - 1),
                at(i + 1, j + 1),
                at(i - 1, j - 1),
            ];
            v.sort_unstable();
            for q in v {
                let d = [x[q] - x[k], y[q] - y[k], z[q] - z[k]];
                nb.push(q as u32);
                rest.push(0.9 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
            }
            start.push(nb.len() as u32);
        }
    }
    let mut out = vec![0f32; 3 * n];
    let mut ms = Vec::new();
    for _ in 0..7 {
        let t = std::time::Instant::now();
        for i in 0..n {
            let (px, py, pz) = (x[i], y[i], z[i]);
            let (mut fx, mut fy, mut fz) = (0f32, 0f32, 0f32);
            for s in start[i] as usize..start[i + 1] as usize {
                let q = nb[s] as usize;
                let (dx, dy, dz) = (x[q] - px, y[q] - py, z[q] - pz);
                let l = (dx * dx + dy * dy + dz * dz).sqrt();
                let f = if l > 0.0 { (l - rest[s]) / l } else { 0.0 };
                fx += f * dx;
                fy += f * dy;
                fz += f * dz;
            }
            out[3 * i] = px + 0.1 * fx;
            out[3 * i + 1] = py + 0.1 * fy;
            out[3 * i + 2] = pz + 0.1 * fz;
        }
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(&out);
    }
    // Springs counted as the step counts them: each edge once, plus 2 bone springs.
    (n, 3 * n + 2 * n, median_p95(ms).0)
}

/// `puppet bench machine`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &Args) -> Result<()> {
    let threads = rayon::current_num_threads();
    let one = copy_bandwidth(1)?;
    let all = copy_bandwidth(threads)?;
    let (vertices, springs, ms) = plain_loop();
    let r = Report {
        copy_gb_per_second_1_thread: one,
        copy_gb_per_second_all_threads: all,
        threads,
        plain_loop_vertices: vertices,
        plain_loop_springs: springs,
        plain_loop_ms_median: ms,
        plain_loop_springs_per_second: springs as f64 / (ms * 1e-3),
    };
    if args.json {
        table::json(&r)?;
    } else {
        println!(
            "copy bandwidth: {one:.1} GB/s with 1 thread, {all:.1} GB/s with {threads} (read + write, median of 7)"
        );
        println!(
            "plain scalar spring loop, 1 thread: {vertices} vertices, {springs} springs, {ms:.1} ms median of 7 = {:.2e} springs/s",
            r.plain_loop_springs_per_second
        );
    }
    Ok(())
}
