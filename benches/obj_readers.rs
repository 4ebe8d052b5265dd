//! Our OBJ reader against tobj (the design card's) on the files users have, at about 50k
//! and 800k vertices: Spot Loop-subdivided twice and four times, written as OBJ text in
//! memory, each read by both in turn, alternating, median of seven
//! (`cargo bench --bench obj_readers`; ARCHITECTURE.md quotes it). Under `cargo test` it
//! reads the small Spot once with each and checks they agree.

use puppet::mesh::{parse_file_mesh, parse_obj, subdivide_loop, write_obj, Format};
use puppet::stats::median;
use std::hint::black_box;
use std::time::Instant;

fn tobj_read(text: &[u8]) -> usize {
    let options = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut std::io::Cursor::new(text), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .expect("tobj reads the file");
    models.iter().map(|m| m.mesh.indices.len() / 3).sum()
}

fn ours_read(text: &[u8]) -> usize {
    parse_file_mesh(text, Format::Obj)
        .expect("our reader reads the file")
        .triangles
        .len()
}

fn main() {
    let timing = std::env::args().any(|a| a == "--bench");
    let spot = parse_obj(include_bytes!("../assets/spot.obj"))
        .expect("Spot")
        .0;
    let levels: &[usize] = if timing { &[2, 4] } else { &[0] };
    if timing {
        println!("| input | vertices | MiB | ours ms | tobj ms | tobj / ours |");
        println!("|---|---:|---:|---:|---:|---:|");
    }
    for &level in levels {
        let mut mesh = spot.clone();
        for _ in 0..level {
            mesh = subdivide_loop(&mesh);
        }
        let mut text = Vec::new();
        write_obj(&mut text, &mesh.positions, &mesh.triangles, "spot").expect("OBJ text");
        assert_eq!(ours_read(&text), tobj_read(&text), "the same triangles");
        if !timing {
            continue;
        }
        let (mut ours, mut theirs) = (Vec::new(), Vec::new());
        for _ in 0..7 {
            let t = Instant::now();
            black_box(ours_read(black_box(&text)));
            ours.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            black_box(tobj_read(black_box(&text)));
            theirs.push(t.elapsed().as_secs_f64() * 1e3);
        }
        let (a, b) = (
            median(&mut ours).unwrap_or(f64::NAN),
            median(&mut theirs).unwrap_or(f64::NAN),
        );
        println!(
            "| Spot ×{} | {} | {:.1} | {a:.1} | {b:.1} | {:.2} |",
            4usize.pow(level as u32),
            mesh.positions.len(),
            text.len() as f64 / (1 << 20) as f64,
            b / a
        );
    }
}
