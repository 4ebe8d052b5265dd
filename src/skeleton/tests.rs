//! The skeleton's unit tests.

use super::build::{build_with, Overlap};
use super::thickness::ring_bounds;
use super::*;
use crate::mesh::{shapes, Mesh};

/// A 1.5:1:0.5 ellipsoid whose vertices are pushed out by up to 3 % at random, so that
/// balls are limited by the far side, by the local curvature and by the bumps.
fn bumpy_ellipsoid(seed: u64) -> Mesh {
    let mut mesh = shapes::ellipsoid(1.5, 1.0, 0.5, 24, 48);
    let mut rng = crate::random::SplitMix(seed);
    for p in &mut mesh.positions {
        *p *= 1.0 + 0.03 * ((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64);
    }
    mesh
}

/// The default method, checked against its definition by brute force over all vertices
/// (no Delaunay edges): every ball is no larger than its start (the fitted curvature
/// radius) and empty of the vertices off its patch, and unless the thickness clamp
/// shrank it by more than 1 %, it is the largest such ball: its start, or some vertex
/// off the patch lies on it. On a bumpy ellipsoid, where balls are limited by the far
/// side, by the local curvature and by the bumps.
#[test]
fn fitted_ball_is_the_largest_tangent_ball_empty_off_its_patch() {
    let mesh = bumpy_ellipsoid(3);
    let normals = crate::mesh::vertex_normals(&mesh).unwrap();
    let none = |_: &str, _: f64| {};
    let sk = build(&mesh, &normals, &SkeletonParams::default(), &none).unwrap();
    assert_eq!(sk.fallback, 0);
    let start = crate::mesh::fit_surface(&mesh, &normals).fitted_radius;
    let brute = crate::bench::truth::fitted_balls_by_brute_force(&mesh, &normals);
    let pts = &mesh.positions;
    let (mut largest, mut started) = (0, 0);
    for (i, (&d, &brute)) in sk.distance.iter().zip(&brute).enumerate() {
        assert!(
            d > 0.0 && d <= brute * (1.0 + 1e-12),
            "vertex {i}: {d} > {brute}"
        );
        // A clamp of less than 1 % is not counted as one.
        largest += usize::from(d >= brute * 0.99);
        started += usize::from(brute == start[i]);
    }
    // Only clamped balls may be smaller than the largest one.
    assert!(
        largest + sk.clamped >= pts.len(),
        "{largest} + {}",
        sk.clamped
    );
    // Both limits occur: the curvature and a vertex.
    assert!(started > 0 && started < pts.len(), "{started} started");
}

/// Two balls modelled apart and pushed into each other (the second one a capsule, as an
/// arm pushed into a body): each part's skeleton is its own, as if the other were not
/// there, and every skeletal point is inside by the winding number.
#[test]
fn overlapping_parts_each_get_their_own_skeleton() {
    let ball = shapes::icosphere(1.0, 3);
    let arm = shapes::capsule(0.3, 0.8, 8, 8, 16);
    let mut mesh = ball.clone();
    let n = mesh.positions.len() as u32;
    let shift = DVec3::new(1.0, 0.0, 0.0);
    // The capsule lies along z: turn it to lie along x, its far end out of the ball.
    mesh.positions.extend(
        arm.positions
            .iter()
            .map(|p| DVec3::new(p.z, p.y, -p.x) + shift),
    );
    mesh.triangles
        .extend(arm.triangles.iter().map(|t| t.map(|i| i + n)));
    let normals = crate::mesh::vertex_normals(&mesh).unwrap();
    let none = |_: &str, _: f64| {};
    let params = SkeletonParams::default();
    let sk = build(&mesh, &normals, &params, &none).unwrap();
    assert_eq!(sk.riders, 0);
    let alone = |m: &Mesh| build(m, &crate::mesh::vertex_normals(m).unwrap(), &params, &none);
    let ball_alone = alone(&ball).unwrap();
    assert_eq!(&sk.distance[..n as usize], &ball_alone.distance[..]);
    let inside = crate::geom::inside::InsideTest::new(&mesh);
    for (v, p) in sk.points.iter().enumerate() {
        assert!(inside.contains(*p), "skeletal point {v} outside");
    }
    // The ball's points near the arm are not pulled to the surface by the arm's
    // buried vertices: every ball vertex keeps most of its radius.
    let least = sk.distance[..n as usize]
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    assert!(least > 0.8, "{least}");
}

/// The mesh-neighbour bound that shortens the thickness rays cast during the
/// tetrahedralization holds (twice every shrinking-ball radius), and is not loose
/// everywhere (or the shortcut would be worthless), on a bumpy ellipsoid.
#[test]
fn ring_bounds_bound_the_shrinking_ball() {
    let mesh = bumpy_ellipsoid(5);
    let normals = crate::mesh::vertex_normals(&mesh).unwrap();
    let none = |_: &str, _: f64| {};
    for method in [Method::ShrinkingBall, Method::FittedBall] {
        let params = SkeletonParams {
            method,
            ..SkeletonParams::default()
        };
        let sk = build(&mesh, &normals, &params, &none).unwrap();
        // The bound is taken over the tangents the balls use.
        let tangents = match method {
            Method::FittedBall => Tangent::fitted(&crate::mesh::fit_surface(&mesh, &normals)),
            _ => normals.iter().map(|&n| Tangent::plain(n)).collect(),
        };
        let bound = ring_bounds(&mesh.positions, &tangents, &mesh.triangles, &|| {});
        let mut tight = 0;
        for (i, (&d, &b)) in sk.distance.iter().zip(&bound).enumerate() {
            assert!(2.0 * d <= b, "{method} vertex {i}: 2d = {} > {b}", 2.0 * d);
            tight += usize::from(b < 6.0 * d);
        }
        // The bounded radius is within 3 times the radius for most vertices.
        assert!(
            tight > sk.distance.len() / 2,
            "{method}: {tight} tight bounds"
        );
    }
}

/// A repeated position (possible without welding) is never inserted in the
/// tetrahedralization: it takes its twin's distance and is no fallback, in every method.
#[test]
fn a_duplicated_position_shares_its_twins_distance() {
    let mut mesh = shapes::cube_grid(1.0, 3);
    let mut normals = crate::mesh::vertex_normals(&mesh).unwrap();
    mesh.positions.push(mesh.positions[5]);
    normals.push(normals[5]);
    let none = |_: &str, _: f64| {};
    for method in Method::ALL {
        let params = SkeletonParams {
            method,
            ..SkeletonParams::default()
        };
        let sk = build(&mesh, &normals, &params, &none).unwrap();
        let last = mesh.positions.len() - 1;
        assert_eq!(sk.fallback, 0, "{method}");
        assert!(sk.distance[5] > 0.0, "{method}");
        assert_eq!(sk.distance[last], sk.distance[5], "{method}");
    }
}

/// The thickness of a vertex is measured either alongside the tetrahedralization
/// (unbounded ray) or after it (a segment of length 2d): the skeleton must not depend on
/// which, nor on how many vertices the overlap reached.
#[test]
fn thickness_measured_early_or_late_gives_the_same_skeleton() {
    // A long thin box, where the thickness clamp matters.
    let mut mesh = shapes::cube_grid(1.0, 6);
    for p in &mut mesh.positions {
        p.x *= 6.0;
        p.y *= 0.5;
    }
    let normals = crate::mesh::vertex_normals(&mesh).unwrap();
    let none = |_: &str, _: f64| {};
    for method in Method::ALL {
        let params = SkeletonParams {
            method,
            ..SkeletonParams::default()
        };
        let late = build_with(&mesh, &normals, &params, &none, Overlap::Nothing).unwrap();
        let early = build_with(&mesh, &normals, &params, &none, Overlap::Everything).unwrap();
        let real = build(&mesh, &normals, &params, &none).unwrap();
        assert_eq!(late.distance, early.distance, "{method}");
        assert_eq!(late.distance, real.distance, "{method}");
        assert_eq!(late.clamped, early.clamped, "{method}");
        // The shrinking ball already fits the local thickness; the others need clamping.
        if !method.is_ball() {
            assert!(late.clamped > 0, "{method}: the clamp was not exercised");
        }
    }
}
