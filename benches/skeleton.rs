//! Micro-benchmarks of the skeleton stages on the embedded Spot (2,930 vertices) and on
//! Spot Loop-subdivided twice (46,850 vertices). `cargo bench --bench skeleton`.

use criterion::{criterion_group, criterion_main, Criterion};
use puppet::delaunay::Delaunay;
use puppet::geom::bvh::Bvh;
use puppet::geom::inside::InsideTest;
use puppet::mesh::{parse_obj, subdivide_loop, vertex_normals, Mesh};
use puppet::skeleton::{build, SkeletonParams};
use std::hint::black_box;

fn spot() -> Mesh {
    parse_obj(include_bytes!("../assets/spot.obj"))
        .expect("embedded mesh")
        .0
}

fn stages(c: &mut Criterion) {
    let small = spot();
    let large = subdivide_loop(&subdivide_loop(&small));
    for (name, mesh) in [("spot", &small), ("spot-x16", &large)] {
        let normals = vertex_normals(mesh).expect("normals");
        let mut g = c.benchmark_group(name);
        g.sample_size(10);
        g.bench_function("delaunay", |b| {
            b.iter(|| Delaunay::new(black_box(&mesh.positions)).expect("dt"))
        });
        g.bench_function("inside_oracle_build", |b| {
            b.iter(|| InsideTest::new(black_box(mesh)))
        });
        g.bench_function("bvh_build", |b| {
            b.iter(|| Bvh::new(black_box(&mesh.positions), &mesh.triangles))
        });
        let oracle = InsideTest::new(mesh);
        let centroid = mesh.positions.iter().sum::<glam::DVec3>() / mesh.positions.len() as f64;
        g.bench_function("inside_query_x1000", |b| {
            b.iter(|| {
                (0..1000)
                    .filter(|&i| oracle.contains(centroid + glam::DVec3::splat(i as f64 * 1e-4)))
                    .count()
            })
        });
        g.bench_function("skeleton_total", |b| {
            b.iter(|| {
                build(
                    mesh,
                    &normals,
                    &SkeletonParams::default(),
                    puppet::progress::silent(),
                )
                .expect("skeleton")
            })
        });
        g.finish();
    }
}

criterion_group!(benches, stages);
criterion_main!(benches);
