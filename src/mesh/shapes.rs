//! Analytic test shapes whose vertices lie exactly on known surfaces, so the skeleton can be
//! compared with the true medial radius (see `bench::truth`). Also a cube grid: the
//! coplanar, cocircular worst case for Delaunay code.

use super::Mesh;
use glam::DVec3;
use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

/// Flips all faces if the mesh is inside out.
fn outward(mut m: Mesh) -> Mesh {
    if m.signed_volume() < 0.0 {
        for t in &mut m.triangles {
            t.swap(1, 2);
        }
    }
    m
}

/// Surface of revolution about +y from a profile of `(radius, y)` pairs running from the
/// north pole (radius 0) to the south pole (radius 0).
fn revolve(profile: &[(f64, f64)], segments: usize) -> Mesh {
    let angles: Vec<f64> = (0..segments)
        .map(|j| TAU * j as f64 / segments as f64)
        .collect();
    revolve_at(profile, &angles)
}

/// [`revolve`] with the ring vertices at the given angles (increasing, in `[0, 2π)`).
fn revolve_at(profile: &[(f64, f64)], angles: &[f64]) -> Mesh {
    let segments = angles.len();
    let rings = &profile[1..profile.len() - 1];
    let mut positions = vec![DVec3::new(0.0, profile[0].1, 0.0)];
    for &(r, y) in rings {
        for &phi in angles {
            positions.push(DVec3::new(r * phi.cos(), y, r * phi.sin()));
        }
    }
    let south = positions.len() as u32;
    positions.push(DVec3::new(0.0, profile[profile.len() - 1].1, 0.0));
    let ring = |k: usize, j: usize| (1 + k * segments + j % segments) as u32;
    let mut triangles = Vec::new();
    for j in 0..segments {
        triangles.push([0, ring(0, j + 1), ring(0, j)]);
    }
    for k in 0..rings.len() - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (
                ring(k, j),
                ring(k, j + 1),
                ring(k + 1, j),
                ring(k + 1, j + 1),
            );
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    let last = rings.len() - 1;
    for j in 0..segments {
        triangles.push([south, ring(last, j), ring(last, j + 1)]);
    }
    outward(Mesh {
        positions,
        triangles,
    })
}

/// Latitude–longitude sphere: `rings` latitude bands, `segments` longitudes. All vertices
/// are exactly cospherical up to rounding, with many cocircular quadruples.
pub fn uv_sphere(radius: f64, rings: usize, segments: usize) -> Mesh {
    let profile: Vec<(f64, f64)> = (0..=rings.max(2))
        .map(|k| {
            let theta = PI * k as f64 / rings.max(2) as f64;
            let (r, y) = if k == 0 {
                (0.0, radius)
            } else if k == rings.max(2) {
                (0.0, -radius)
            } else {
                (radius * theta.sin(), radius * theta.cos())
            };
            (r, y)
        })
        .collect();
    revolve(&profile, segments.max(3))
}

/// Ellipsoid with semi-axes `a` (x), `b` (y), `c` (z): a UV sphere scaled per axis.
pub fn ellipsoid(a: f64, b: f64, c: f64, rings: usize, segments: usize) -> Mesh {
    let mut m = uv_sphere(1.0, rings, segments);
    for p in &mut m.positions {
        *p *= DVec3::new(a, b, c);
    }
    m
}

/// Capsule along y: a cylinder of `radius` and half-length `half` capped by hemispheres.
/// `rings` bands per hemisphere, `len_rings` bands along the cylinder.
pub fn capsule(radius: f64, half: f64, rings: usize, len_rings: usize, segments: usize) -> Mesh {
    revolve(
        &capsule_profile(radius, half, rings, len_rings),
        segments.max(3),
    )
}

/// A [`capsule`] whose ring vertices alternate a short and a long gap (2 : 4 of the mean,
/// `segments` even): every vertex on the capsule, every fan uneven, so angle-weighted
/// normals tilt by a few degrees around the tube.
pub fn uneven_capsule(
    radius: f64,
    half: f64,
    rings: usize,
    len_rings: usize,
    segments: usize,
) -> Mesh {
    let segments = segments.max(4) & !1;
    let gap = TAU / segments as f64;
    let angles: Vec<f64> = (0..segments)
        .map(|j| gap * (j as f64 - if j % 2 == 1 { 1.0 / 3.0 } else { 0.0 }))
        .collect();
    revolve_at(&capsule_profile(radius, half, rings, len_rings), &angles)
}

fn capsule_profile(radius: f64, half: f64, rings: usize, len_rings: usize) -> Vec<(f64, f64)> {
    let rings = rings.max(1);
    let mut profile = vec![(0.0, half + radius)];
    for k in 1..=rings {
        let theta = 0.5 * PI * k as f64 / rings as f64;
        profile.push((radius * theta.sin(), half + radius * theta.cos()));
    }
    for k in 1..len_rings.max(1) {
        profile.push((
            radius,
            half - 2.0 * half * k as f64 / len_rings.max(1) as f64,
        ));
    }
    for k in 0..rings {
        let theta = 0.5 * PI * k as f64 / rings as f64;
        profile.push((radius * theta.cos(), -half - radius * theta.sin()));
    }
    profile.push((0.0, -half - radius));
    profile
}

/// An [`icosphere`] scaled to the ellipsoid with semi-axes `axes`, each vertex first moved
/// along the unit sphere by up to `jitter` of the mean edge length in a random direction
/// (seeded): every vertex stays exactly on the surface while its fan becomes uneven.
pub fn jittered_ellipsoid(axes: DVec3, levels: usize, jitter: f64, seed: u64) -> Mesh {
    let mut m = icosphere(1.0, levels);
    let mean = m.mean_edge_length();
    let mut rng = crate::random::SplitMix(seed);
    let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    for p in &mut m.positions {
        let n = p.normalize();
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        let (angle, amount) = (TAU * unit(), jitter * mean * unit());
        *p = (n + (u * angle.cos() + v * angle.sin()) * amount).normalize() * axes;
    }
    outward(m)
}

/// `mesh` with every vertex moved by up to `share` of the mean edge length, in a direction
/// and by an amount drawn uniformly from a ball (seeded): a rough surface, as a scan or a
/// mesh written with few digits has, where [`jittered_ellipsoid`] keeps every vertex on
/// the surface. The triangles are the same.
pub fn roughen(mesh: &Mesh, share: f64, seed: u64) -> Mesh {
    let mean = mesh.mean_edge_length();
    let mut rng = crate::random::SplitMix(seed);
    let mut unit = || 2.0 * ((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64) - 1.0;
    let positions = mesh
        .positions
        .iter()
        .map(|&p| loop {
            let d = DVec3::new(unit(), unit(), unit());
            if d.length_squared() <= 1.0 {
                break p + d * share * mean;
            }
        })
        .collect();
    Mesh {
        positions,
        triangles: mesh.triangles.clone(),
    }
}

/// Torus around y: major radius `major`, tube radius `minor`.
pub fn torus(major: f64, minor: f64, n_major: usize, n_minor: usize) -> Mesh {
    let (nu, nv) = (n_major.max(3), n_minor.max(3));
    let mut positions = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let u = TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let v = TAU * j as f64 / nv as f64;
            let r = major + minor * v.cos();
            positions.push(DVec3::new(r * u.cos(), minor * v.sin(), r * u.sin()));
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + j % nv) as u32;
    let mut triangles = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i, j + 1), id(i + 1, j + 1));
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    outward(Mesh {
        positions,
        triangles,
    })
}

/// Geodesic sphere: an icosahedron split `levels` times, projected onto the sphere.
pub fn icosphere(radius: f64, levels: usize) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let v = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ];
    let f: [[u32; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut m = Mesh {
        positions: v.iter().map(|&(x, y, z)| DVec3::new(x, y, z)).collect(),
        triangles: f.to_vec(),
    };
    for _ in 0..levels {
        m = super::subdivide_midpoint(&m);
    }
    for p in &mut m.positions {
        *p = p.normalize() * radius;
    }
    outward(m)
}

/// Axis-aligned cube of edge `size` centred at the origin, each face an `n`×`n` grid of
/// squares split into two triangles: exactly coplanar and cocircular vertices.
pub fn cube_grid(size: f64, n: usize) -> Mesh {
    let n = n.max(1) as i64;
    let mut index: HashMap<[i64; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut id = |c: [i64; 3]| {
        *index.entry(c).or_insert_with(|| {
            positions.push(DVec3::new(
                size * (c[0] as f64 / n as f64 - 0.5),
                size * (c[1] as f64 / n as f64 - 0.5),
                size * (c[2] as f64 / n as f64 - 0.5),
            ));
            (positions.len() - 1) as u32
        })
    };
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: i64, dj: i64| {
                        let mut c = [0i64; 3];
                        c[axis] = side;
                        c[(axis + 1) % 3] = i + di;
                        c[(axis + 2) % 3] = j + dj;
                        c
                    };
                    let (a, b, c, d) = (
                        id(corner(0, 0)),
                        id(corner(1, 0)),
                        id(corner(0, 1)),
                        id(corner(1, 1)),
                    );
                    if side == n {
                        triangles.push([a, b, d]);
                        triangles.push([a, d, c]);
                    } else {
                        triangles.push([a, d, b]);
                        triangles.push([a, c, d]);
                    }
                }
            }
        }
    }
    outward(Mesh {
        positions,
        triangles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_roughened_mesh_moves_each_vertex_within_its_share_and_repeats_by_seed() {
        let sphere = icosphere(1.0, 3);
        let mean = sphere.mean_edge_length();
        let rough = roughen(&sphere, 0.1, 7);
        assert_eq!(rough.triangles, sphere.triangles);
        let moved: Vec<f64> = rough
            .positions
            .iter()
            .zip(&sphere.positions)
            .map(|(a, b)| a.distance(*b))
            .collect();
        assert!(moved.iter().all(|&d| d <= 0.1 * mean + 1e-12));
        assert!(moved.iter().any(|&d| d > 0.05 * mean));
        assert_eq!(roughen(&sphere, 0.1, 7).positions, rough.positions);
        assert_ne!(roughen(&sphere, 0.1, 8).positions, rough.positions);
    }
}
