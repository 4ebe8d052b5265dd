use super::*;
use crate::geom::predicates::insphere;
use crate::mesh::shapes;
use crate::random::SplitMix;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Brute force: no input point strictly inside any finite tetrahedron's circumsphere.
fn assert_empty_spheres(dt: &Delaunay, pts: &[DVec3]) {
    for t in dt.finite_tets() {
        let [a, b, c, d] = t.map(|v| pts[v as usize]);
        for (i, &p) in pts.iter().enumerate() {
            assert!(
                insphere(a, b, c, d, p) <= 0.0,
                "point {i} strictly inside the circumsphere of {t:?}"
            );
        }
    }
}

fn volume(dt: &Delaunay, pts: &[DVec3]) -> f64 {
    dt.finite_tets()
        .iter()
        .map(|t| {
            let [a, b, c, d] = t.map(|v| pts[v as usize]);
            (b - a).dot((c - a).cross(d - a)) / 6.0
        })
        .sum()
}

fn random_points(n: usize, seed: u64) -> Vec<DVec3> {
    let mut rng = SplitMix(seed);
    let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    (0..n).map(|_| DVec3::new(u(), u(), u())).collect()
}

#[test]
fn random_points_satisfy_the_empty_sphere_property() {
    for seed in 0..3 {
        let pts = random_points(400, seed);
        let dt = Delaunay::new(&pts).unwrap();
        dt.check().unwrap();
        assert_empty_spheres(&dt, &pts);
    }
}

/// The `k × k × k` integer lattice: every cube's 8 corners are cospherical, faces coplanar.
fn lattice(k: u32) -> Vec<DVec3> {
    let mut pts = Vec::new();
    for x in 0..k {
        for y in 0..k {
            for z in 0..k {
                pts.push(DVec3::new(x as f64, y as f64, z as f64));
            }
        }
    }
    pts
}

#[test]
fn lattice_is_maximally_degenerate_and_still_exact() {
    let pts = lattice(6);
    let dt = Delaunay::new(&pts).unwrap();
    dt.check().unwrap();
    assert_empty_spheres(&dt, &pts);
    assert!(
        (volume(&dt, &pts) - 125.0).abs() < 1e-9,
        "volume {}",
        volume(&dt, &pts)
    );
}

#[test]
fn cube_grid_surface_points() {
    let m = shapes::cube_grid(2.0, 6);
    let dt = Delaunay::new(&m.positions).unwrap();
    dt.check().unwrap();
    assert_empty_spheres(&dt, &m.positions);
    assert!((volume(&dt, &m.positions) - 8.0).abs() < 1e-9);
}

#[test]
fn cospherical_uv_and_ico_spheres() {
    for m in [shapes::uv_sphere(1.0, 12, 24), shapes::icosphere(1.0, 2)] {
        let dt = Delaunay::new(&m.positions).unwrap();
        dt.check().unwrap();
        assert_empty_spheres(&dt, &m.positions);
    }
}

#[test]
fn exactly_cospherical_points() {
    // Points on the unit sphere with exactly representable coordinates (Pythagorean
    // triples), so the degeneracy is exact, not only up to rounding.
    let triples = [
        (3.0, 4.0, 0.0),
        (0.0, 3.0, 4.0),
        (4.0, 0.0, 3.0),
        (5.0, 0.0, 0.0),
    ];
    let mut pts = Vec::new();
    for &(x, y, z) in &triples {
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                for sz in [-1.0, 1.0] {
                    for p in [(x, y, z), (y, z, x), (z, x, y)] {
                        pts.push(DVec3::new(sx * p.0, sy * p.1, sz * p.2) / 5.0);
                    }
                }
            }
        }
    }
    pts.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
    pts.dedup();
    let dt = Delaunay::new(&pts).unwrap();
    dt.check().unwrap();
    assert_empty_spheres(&dt, &pts);
}

#[test]
fn duplicates_are_reported_not_inserted() {
    let mut pts = random_points(200, 9);
    pts.extend_from_within(..50);
    let dt = Delaunay::new(&pts).unwrap();
    dt.check().unwrap();
    let dups = (0..pts.len())
        .filter(|&i| dt.duplicate_of(i).is_some())
        .count();
    assert_eq!(dups, 50);
    for i in 0..pts.len() {
        if let Some(v) = dt.duplicate_of(i) {
            assert_eq!(pts[v as usize], pts[i]);
        }
    }
}

#[test]
fn flat_inputs_are_errors_not_panics() {
    let plane: Vec<DVec3> = (0..20)
        .map(|i| DVec3::new((i % 5) as f64, (i / 5) as f64, 0.0))
        .collect();
    assert_eq!(
        Delaunay::new(&plane).err(),
        Some(DelaunayError::Flat("coplanar"))
    );
    let line: Vec<DVec3> = (0..9).map(|i| DVec3::splat(i as f64)).collect();
    assert_eq!(
        Delaunay::new(&line).err(),
        Some(DelaunayError::Flat("collinear"))
    );
    assert_eq!(
        Delaunay::new(&[DVec3::ONE; 5]).err(),
        Some(DelaunayError::Flat("identical"))
    );
    assert_eq!(
        Delaunay::new(&[DVec3::ONE; 3]).err(),
        Some(DelaunayError::TooFew(3))
    );
    let mut nan = random_points(10, 1);
    nan[4].y = f64::NAN;
    assert_eq!(Delaunay::new(&nan).err(), Some(DelaunayError::NonFinite(4)));
}

#[test]
fn larger_random_set_is_locally_delaunay() {
    let pts = random_points(20_000, 42);
    let dt = Delaunay::new(&pts).unwrap();
    dt.check().unwrap();
    // Euler-type sanity: a random set in a cube has about 6.5 tetrahedra per point.
    let per_point = dt.finite_tets().len() as f64 / pts.len() as f64;
    assert!(
        (6.0..7.0).contains(&per_point),
        "{per_point} tets per point"
    );
}

/// Points on a sphere and far corners: a corner inserted after much of the sphere sees a
/// good part of its hull, a cavity boundary with more than LINK_MAX vertices.
fn sphere_and_far_corners() -> Vec<DVec3> {
    let mut pts: Vec<DVec3> = random_points(1000, 5)
        .into_iter()
        .map(|p| (p - DVec3::splat(0.5)).normalize())
        .collect();
    for x in [-1e3, 1e3] {
        for y in [-1e3, 1e3] {
            for z in [-1e3, 1e3] {
                pts.push(DVec3::new(x, y, z));
            }
        }
    }
    pts
}

#[test]
fn big_cavities_are_linked_by_sorting() {
    let pts = sphere_and_far_corners();
    let dt = Delaunay::new(&pts).unwrap();
    assert!(dt.sorted_links() > 0, "the sorting path was not exercised");
    dt.check().unwrap();
    assert_empty_spheres(&dt, &pts);
}

/// Tetrahedralizes with the parallel phases starting at insertion `first` on a pool of
/// `threads` threads.
fn phased(pts: &[DVec3], first: usize, threads: usize) -> Delaunay {
    phased_idle(pts, first, threads, &|| false)
}

/// As [`phased`], with an `idle` hook.
fn phased_idle(
    pts: &[DVec3],
    first: usize,
    threads: usize,
    idle: &(dyn Fn() -> bool + Sync),
) -> Delaunay {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| {
            Delaunay::with_phases_from(pts, idle, first, |_| ())
                .unwrap()
                .0
        })
}

/// The idle hook runs only while the other side of a phase runs on another thread: never
/// on one thread (where the other side runs after this one: running the hook until it
/// has no work left would delay it), at most once per phase when it has no work, and
/// whatever it does, the tetrahedra are the same.
#[test]
fn the_idle_hook_runs_only_while_the_other_side_works() {
    let pts = random_points(20_000, 3);
    let first = 40;
    // Phases double from `first`: at most this many.
    let phases = (pts.len() / first).ilog2() as usize + 1;
    let reference = canonical(&phased(&pts, first, 2));
    let calls = &AtomicUsize::new(0);
    let count = |more: bool| {
        calls.store(0, Ordering::Relaxed);
        move || {
            calls.fetch_add(1, Ordering::Relaxed);
            more
        }
    };
    let one = phased_idle(&pts, first, 1, &count(true));
    assert_eq!(calls.load(Ordering::Relaxed), 0, "called on one thread");
    assert_eq!(canonical(&one), reference);
    let two = phased_idle(&pts, first, 2, &count(false));
    let idle = calls.load(Ordering::Relaxed);
    assert!(idle <= phases, "{idle} calls with no work, {phases} phases");
    assert_eq!(canonical(&two), reference);
    // A hook that always has work is called until the other side is done.
    let busy = phased_idle(&pts, first, 2, &count(true));
    assert_eq!(canonical(&busy), reference);
}

/// The tetrahedra as a sorted list of rotated vertex quadruples: equal for equal
/// tetrahedralizations, whatever their memory layout.
fn canonical(dt: &Delaunay) -> Vec<[u32; 4]> {
    let mut tets: Vec<[u32; 4]> = dt
        .finite_tets()
        .into_iter()
        .map(|t| {
            // An even permutation putting the smallest id first keeps the orientation.
            // Even permutations: the smallest id first, then a rotation of the other three.
            let k = (0..4).min_by_key(|&i| t[i]).unwrap_or(0);
            let t = match k {
                0 => t,
                1 => [t[1], t[0], t[3], t[2]],
                2 => [t[2], t[3], t[0], t[1]],
                _ => [t[3], t[2], t[1], t[0]],
            };
            let mut rest = [t[1], t[2], t[3]];
            let r = (0..3).min_by_key(|&i| rest[i]).unwrap_or(0);
            rest.rotate_left(r);
            [t[0], rest[0], rest[1], rest[2]]
        })
        .collect();
    tets.sort_unstable();
    tets
}

/// Degenerate and generic inputs tetrahedralized in parallel phases from early on (so that
/// many insertions are deferred across the split plane) are Delaunay, the same on one
/// thread as on two (records included), and for generic input the same tetrahedra as the
/// serial insertion.
#[test]
fn parallel_phases_are_delaunay_and_do_not_depend_on_the_thread_count() {
    let mut with_duplicates = random_points(3000, 11);
    with_duplicates.extend_from_within(..300);
    let inputs = [
        ("random", random_points(4000, 7), true),
        ("lattice", lattice(9), false),
        ("cube grid", shapes::cube_grid(2.0, 12).positions, false),
        ("uv sphere", shapes::uv_sphere(1.0, 24, 48).positions, false),
        ("icosphere", shapes::icosphere(1.0, 3).positions, false),
        ("duplicates", with_duplicates, true),
    ];
    for (name, pts, generic) in inputs {
        for first in [40, pts.len() / 16] {
            let one = phased(&pts, first, 1);
            let two = phased(&pts, first, 2);
            // Local Delaunay everywhere and a valid triangulation: Delaunay.
            one.check()
                .unwrap_or_else(|e| panic!("{name}, from {first}: {e}"));
            assert!(
                one.deferred > 0 && one.deferred < pts.len() * 3 / 4,
                "{name}, from {first}: {} deferred",
                one.deferred
            );
            let records = |dt: &Delaunay| dt.cells.iter().map(|c| (c.v, c.n)).collect::<Vec<_>>();
            assert!(
                records(&one) == records(&two),
                "{name}: thread count matters"
            );
            for i in 0..pts.len() {
                assert_eq!(one.duplicate_of(i), two.duplicate_of(i));
                if let Some(v) = one.duplicate_of(i) {
                    assert_eq!(pts[v as usize], pts[i], "{name}");
                }
            }
            if generic {
                let serial = Delaunay::new(&pts).unwrap();
                assert!(
                    canonical(&one) == canonical(&serial),
                    "{name}: not the serial result"
                );
            }
        }
    }
}
