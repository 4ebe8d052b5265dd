use puppet::mesh::*;
fn main() {
    let (mut m, _) = load_obj(std::path::Path::new("../shared/meshes/spot.obj")).unwrap();
    let levels: usize = std::env::args().nth(1).unwrap().parse().unwrap();
    for _ in 0..levels { m = subdivide_loop(&m); }
    let t = std::time::Instant::now();
    let dt = puppet::delaunay::Delaunay::new(&m.positions).unwrap();
    eprintln!("{} pts: {:.3}s, {} tets", m.positions.len(), t.elapsed().as_secs_f64(), dt.tet_count());
}
