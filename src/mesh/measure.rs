//! Measures of a deformed surface over a set of faces: how sharply it folds (the largest
//! dihedral angle) and how much volume it encloses seen from a point.

use glam::DVec3;
use std::collections::HashMap;

/// The largest angle, in degrees, between the normals of two faces that share an edge, over
/// the edges whose two faces are both in `region` (0: flat, 180: folded flat onto itself).
/// Degenerate faces (no normal) are skipped.
///
/// # Panics
/// If `region` is not one flag per triangle, or a triangle names a vertex beyond
/// `positions`.
pub fn largest_dihedral(positions: &[DVec3], triangles: &[[u32; 3]], region: &[bool]) -> f64 {
    let mut largest: f64 = 0.0;
    for_each_edge(triangles, region, |f, g| {
        if let Some(x) = dihedral(positions, triangles, f, g) {
            largest = largest.max(x);
        }
    });
    largest
}

/// The largest rise of a dihedral angle over its rest angle, in degrees: per edge whose
/// two faces are both in `region`, the angle between their normals in `now` less the
/// angle in `rest`, the largest. Unlike [`largest_dihedral`] against the rest mesh's
/// largest, a crease cannot hide behind a sharper feature elsewhere in the region.
/// Degenerate faces (no normal) are skipped.
///
/// # Panics
/// If `region` is not one flag per triangle, or a triangle names a vertex beyond `rest`
/// or `now`.
pub fn largest_crease(
    rest: &[DVec3],
    now: &[DVec3],
    triangles: &[[u32; 3]],
    region: &[bool],
) -> f64 {
    let mut largest: f64 = 0.0;
    for_each_edge(triangles, region, |f, g| {
        let bent = dihedral(now, triangles, f, g);
        if let (Some(x), Some(y)) = (bent, dihedral(rest, triangles, f, g)) {
            largest = largest.max(x - y);
        }
    });
    largest
}

/// Calls `visit(f, g)` for each edge shared by two faces `f`, `g` of `region`.
///
/// # Panics
/// If `region` is not one flag per triangle.
fn for_each_edge(triangles: &[[u32; 3]], region: &[bool], mut visit: impl FnMut(usize, usize)) {
    assert_eq!(region.len(), triangles.len(), "one flag per triangle");
    let mut first: HashMap<(u32, u32), usize> = HashMap::new();
    for (f, t) in triangles.iter().enumerate().filter(|(f, _)| region[*f]) {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let key = (a.min(b), a.max(b));
            match first.remove(&key) {
                Some(g) => visit(f, g),
                None => {
                    first.insert(key, f);
                }
            }
        }
    }
}

/// The angle between the normals of faces `f` and `g` (degrees); `None` when one is
/// degenerate.
fn dihedral(positions: &[DVec3], triangles: &[[u32; 3]], f: usize, g: usize) -> Option<f64> {
    let normal = |f: usize| {
        let [a, b, c] = triangles[f].map(|i| positions[i as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    };
    let (n, m) = (normal(f), normal(g));
    (n != DVec3::ZERO && m != DVec3::ZERO).then(|| n.dot(m).clamp(-1.0, 1.0).acos().to_degrees())
}

/// The volume of the cones from `apex` to the faces in `region` (signed, positive for
/// outward faces): the region's share of the enclosed volume. A rotation about `apex`
/// leaves it unchanged; only a deformation of the region's surface changes it. Over every
/// face of a closed mesh it is the enclosed volume, whatever the apex.
///
/// # Panics
/// If `region` is not one flag per triangle, or a triangle names a vertex beyond
/// `positions`.
pub fn cone_volume(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    region: &[bool],
    apex: DVec3,
) -> f64 {
    assert_eq!(region.len(), triangles.len(), "one flag per triangle");
    triangles
        .iter()
        .zip(region)
        .filter(|(_, &r)| r)
        .map(|(t, _)| {
            let [a, b, c] = t.map(|i| positions[i as usize] - apex);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// The volume the faces in `region` enclose once each of the region's boundary loops is
/// closed by a fan from its vertices' centroid (signed, positive for outward faces). Unlike
/// [`cone_volume`] it depends on no apex: any rigid motion of the region leaves it
/// unchanged, so it measures a region whose parts move apart (a limb whose far part turns
/// about a point the bend moves). Over every face of a closed mesh it is the enclosed
/// volume.
///
/// # Panics
/// If `region` is not one flag per triangle, or a triangle names a vertex beyond
/// `positions`.
pub fn capped_volume(positions: &[DVec3], triangles: &[[u32; 3]], region: &[bool]) -> f64 {
    Capped::new(triangles, region).volume(positions)
}

/// The gradient of [`capped_volume`] over the region made of `faces` (the caps'
/// centroids spread over their loops' vertices): how its capped volume changes as each
/// vertex moves, to first order. Pairs (vertex, gradient), each vertex of the faces once,
/// by vertex.
///
/// # Panics
/// If a face names a vertex beyond `positions`.
pub fn capped_volume_gradient(positions: &[DVec3], faces: &[[u32; 3]]) -> Vec<(u32, DVec3)> {
    Capped::from_faces(faces.to_vec()).volume_gradient(positions)
}

/// A region's faces and the loops of its boundary, each closed by a cap (see
/// [`capped_volume`]): found once, its volume measured for any positions.
#[derive(Clone, Debug, PartialEq)]
pub struct Capped {
    faces: Vec<[u32; 3]>,
    /// Boundary edges (a, b) with their loop.
    boundary: Vec<(u32, u32, usize)>,
    /// Each boundary vertex's loop, by vertex.
    loop_of_vertex: Vec<(u32, usize)>,
    /// Per loop, its vertex count.
    loops: Vec<usize>,
}

impl Capped {
    fn new(triangles: &[[u32; 3]], region: &[bool]) -> Capped {
        assert_eq!(region.len(), triangles.len(), "one flag per triangle");
        Capped::from_faces(
            triangles
                .iter()
                .zip(region)
                .filter(|(_, &r)| r)
                .map(|(t, _)| *t)
                .collect(),
        )
    }

    /// The gradient of its capped volume ([`capped_volume_gradient`]) at `positions`.
    ///
    /// # Panics
    /// If a face names a vertex beyond `positions`.
    pub fn volume_gradient(&self, positions: &[DVec3]) -> Vec<(u32, DVec3)> {
        let Some(origin) = self.faces.first().map(|t| positions[t[0] as usize]) else {
            return Vec::new();
        };
        let at = |i: u32| positions[i as usize] - origin;
        let vertices = self
            .faces
            .iter()
            .flatten()
            .max()
            .map_or(0, |&v| v as usize + 1);
        let mut gradient = vec![DVec3::ZERO; vertices];
        // d(a·(b×c))/da = b×c, and cyclically.
        let mut add = |v: u32, g: DVec3| gradient[v as usize] += g / 6.0;
        for t in &self.faces {
            let [a, b, c] = t.map(at);
            add(t[0], b.cross(c));
            add(t[1], c.cross(a));
            add(t[2], a.cross(b));
        }
        let centres: Vec<DVec3> = self
            .centres(positions)
            .into_iter()
            .map(|c| c - origin)
            .collect();
        let mut at_centre = vec![DVec3::ZERO; centres.len()];
        for &(a, b, l) in &self.boundary {
            // The cap's triangle (b, a, centre).
            let (pb, pa, c) = (at(b), at(a), centres[l]);
            add(b, pa.cross(c));
            add(a, c.cross(pb));
            at_centre[l] += pb.cross(pa);
        }
        for &(v, l) in &self.loop_of_vertex {
            add(v, at_centre[l] / self.loops[l] as f64);
        }
        let mut used: Vec<u32> = self.faces.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        used.into_iter()
            .map(|v| (v, gradient[v as usize]))
            .collect()
    }

    /// The region made of `faces`.
    pub fn from_faces(faces: Vec<[u32; 3]>) -> Capped {
        // Directed edges, sorted: one whose reverse no face has runs along the boundary.
        let key = |a: u32, b: u32| (u64::from(a) << 32) | u64::from(b);
        let mut edges: Vec<u64> = faces
            .iter()
            .flat_map(|t| [key(t[0], t[1]), key(t[1], t[2]), key(t[2], t[0])])
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let boundary: Vec<(u32, u32)> = edges
            .iter()
            .map(|&e| ((e >> 32) as u32, e as u32))
            .filter(|&(a, b)| edges.binary_search(&key(b, a)).is_err())
            .collect();
        // Loops: the boundary's vertices joined along its edges.
        let vertices = faces.iter().flatten().max().map_or(0, |&v| v as usize + 1);
        let mut index = vec![u32::MAX; vertices];
        let mut count = 0;
        for &(a, b) in &boundary {
            for v in [a, b] {
                if index[v as usize] == u32::MAX {
                    index[v as usize] = count;
                    count += 1;
                }
            }
        }
        let joined: Vec<[u32; 3]> = boundary
            .iter()
            .map(|&(a, b)| [index[a as usize], index[b as usize], index[b as usize]])
            .collect();
        let loop_of = super::parts::components(count as usize, &joined);
        let loop_count = loop_of.iter().map(|&l| l as usize + 1).max().unwrap_or(0);
        let mut loops = vec![0; loop_count];
        // In vertex order, so the caps' centroids add up alike on every run.
        let loop_of_vertex: Vec<(u32, usize)> = (0..vertices as u32)
            .filter(|&v| index[v as usize] != u32::MAX)
            .map(|v| (v, loop_of[index[v as usize] as usize] as usize))
            .collect();
        for &(_, l) in &loop_of_vertex {
            loops[l] += 1;
        }
        Capped {
            boundary: boundary
                .into_iter()
                .map(|(a, b)| (a, b, loop_of[index[a as usize] as usize] as usize))
                .collect(),
            faces,
            loop_of_vertex,
            loops,
        }
    }

    /// The region's volume with its vertices at `positions` (indexed by vertex), each
    /// boundary loop closed by a fan from its centroid ([`capped_volume`]).
    ///
    /// # Panics
    /// If a face names a vertex beyond `positions`.
    pub fn volume(&self, positions: &[DVec3]) -> f64 {
        let apex = self
            .faces
            .first()
            .map_or(DVec3::ZERO, |t| positions[t[0] as usize]);
        self.volume_from(positions, apex)
    }

    /// The faces and caps of the region that touch a vertex for which `moved` holds:
    /// moving only those vertices changes this part's [`Capped::volume_from`] a fixed
    /// apex by as much as it changes the whole region's volume, for less work.
    pub fn around(&self, moved: impl Fn(u32) -> bool) -> Capped {
        let mut touched = vec![false; self.loops.len()];
        for &(v, l) in &self.loop_of_vertex {
            touched[l] |= moved(v);
        }
        Capped {
            faces: self
                .faces
                .iter()
                .filter(|t| t.iter().any(|&v| moved(v)))
                .copied()
                .collect(),
            boundary: self
                .boundary
                .iter()
                .filter(|b| touched[b.2])
                .copied()
                .collect(),
            loop_of_vertex: self
                .loop_of_vertex
                .iter()
                .filter(|p| touched[p.1])
                .copied()
                .collect(),
            loops: self.loops.clone(),
        }
    }

    /// The sum of the cones from `apex` over the region's faces and caps: its volume for
    /// any apex when the region is the whole ([`Capped::volume`]).
    ///
    /// # Panics
    /// If a face names a vertex beyond `positions`.
    pub fn volume_from(&self, positions: &[DVec3], apex: DVec3) -> f64 {
        let cone = |a: DVec3, b: DVec3, c: DVec3| (a - apex).dot((b - apex).cross(c - apex)) / 6.0;
        let centres = self.centres(positions);
        let surface: f64 = self
            .faces
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                cone(a, b, c)
            })
            .sum();
        let caps: f64 = self
            .boundary
            .iter()
            .map(|&(a, b, l)| cone(positions[b as usize], positions[a as usize], centres[l]))
            .sum();
        surface + caps
    }

    /// Each loop's centroid.
    fn centres(&self, positions: &[DVec3]) -> Vec<DVec3> {
        let mut sum = vec![DVec3::ZERO; self.loops.len()];
        for &(v, l) in &self.loop_of_vertex {
            sum[l] += positions[v as usize];
        }
        sum.iter()
            .zip(&self.loops)
            .map(|(s, &count)| *s / count.max(1) as f64)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn a_fine_sphere_is_smooth_and_its_cones_add_up_to_its_volume_from_any_apex() {
        let m = shapes::uv_sphere(1.0, 64, 48);
        let all = vec![true; m.triangles.len()];
        assert!(largest_dihedral(&m.positions, &m.triangles, &all) < 10.0);
        for apex in [DVec3::ZERO, DVec3::new(0.3, -0.2, 0.5)] {
            let v = cone_volume(&m.positions, &m.triangles, &all, apex);
            assert!((v - m.signed_volume()).abs() < 1e-9, "{v}");
        }
        // A cube's edges are right angles.
        let c = shapes::cube_grid(1.0, 2);
        let all = vec![true; c.triangles.len()];
        assert!((largest_dihedral(&c.positions, &c.triangles, &all) - 90.0).abs() < 1e-9);
    }

    #[test]
    fn a_crease_is_measured_against_its_own_rest_angle() {
        // Two faces hinged on the edge 0–1, flat at rest.
        let rest = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, 1.0, 0.0),
            DVec3::new(0.5, -1.0, 0.0),
        ];
        let triangles = [[0, 1, 2], [1, 0, 3]];
        let both = [true, true];
        assert_eq!(largest_crease(&rest, &rest, &triangles, &both), 0.0);
        // Folded by 40° about the edge: a 40° crease, whether or not a sharper feature
        // elsewhere dominates the largest dihedral angle.
        let a = 40f64.to_radians();
        let mut now = rest;
        now[3] = DVec3::new(0.5, -a.cos(), a.sin());
        let crease = largest_crease(&rest, &now, &triangles, &both);
        assert!((crease - 40.0).abs() < 1e-9, "{crease}");
        assert_eq!(largest_crease(&rest, &now, &triangles, &[true, false]), 0.0);
    }

    /// One flag per face of `m`: whether all three of its vertices satisfy `inside`.
    fn faces_where(m: &crate::mesh::Mesh, inside: impl Fn(DVec3) -> bool) -> Vec<bool> {
        m.triangles
            .iter()
            .map(|t| t.iter().all(|&i| inside(m.positions[i as usize])))
            .collect()
    }

    /// A piece of a tube bent as an arc (every ring square to the bent centre line, which
    /// keeps its length: by Pappus the piece holds what it held) keeps its capped volume,
    /// while its cone from the near cut's centre gains: the far cut, tilted, lies nearer.
    #[test]
    fn a_tube_bent_as_an_arc_keeps_its_capped_volume_but_not_its_cone() {
        let m = shapes::capsule(0.2, 1.0, 8, 40, 48);
        let piece = faces_where(&m, |p| p.y.abs() <= 0.5 + 1e-9);
        let bend = 60f64.to_radians();
        let radius = 1.0 / bend;
        let now: Vec<DVec3> = m
            .positions
            .iter()
            .map(|&p| {
                let s = (p.y + 0.5).clamp(0.0, 1.0);
                let past = p.y + 0.5 - s;
                let a = bend * s;
                let centre = DVec3::new(radius * (1.0 - a.cos()), -0.5 + radius * a.sin(), 0.0);
                let along = DVec3::new(a.sin(), a.cos(), 0.0);
                let across = DVec3::new(a.cos(), -a.sin(), 0.0);
                centre + along * past + across * p.x + DVec3::Z * p.z
            })
            .collect();
        let pivot = DVec3::new(0.0, -0.5, 0.0);
        let change = |a: f64, b: f64| b / a - 1.0;
        let capped = change(
            capped_volume(&m.positions, &m.triangles, &piece),
            capped_volume(&now, &m.triangles, &piece),
        );
        let cone = change(
            cone_volume(&m.positions, &m.triangles, &piece, pivot),
            cone_volume(&now, &m.triangles, &piece, pivot),
        );
        assert!(capped.abs() < 0.01, "capped {capped}");
        assert!(cone > 0.05, "cone {cone}");
    }

    /// The gradient is the capped volume's: moving one vertex a little (a vertex of the
    /// surface, one on the cut, which moves the cap's centre too) changes the volume by
    /// the gradient's dot the move, to second order.
    #[test]
    fn the_capped_volume_gradient_matches_small_moves() {
        let m = shapes::capsule(0.2, 1.0, 8, 40, 48);
        let piece = faces_where(&m, |p| p.y <= 0.25);
        let faces: Vec<[u32; 3]> = m
            .triangles
            .iter()
            .zip(&piece)
            .filter(|(_, &r)| r)
            .map(|(t, _)| *t)
            .collect();
        let gradient = capped_volume_gradient(&m.positions, &faces);
        let v0 = capped_volume(&m.positions, &m.triangles, &piece);
        // Every vertex on the cut (the last ring under y = 0.25), and a sample of the rest.
        let on_cut = |v: u32| (m.positions[v as usize].y - 0.25).abs() < 0.05;
        let checked: Vec<(u32, DVec3)> = gradient
            .iter()
            .enumerate()
            .filter(|&(k, &(v, _))| on_cut(v) || k % 37 == 0)
            .map(|(_, &x)| x)
            .collect();
        assert!(checked.iter().filter(|&&(v, _)| on_cut(v)).count() >= 8);
        let h = 1e-6;
        for &(v, g) in &checked {
            for d in [DVec3::X, DVec3::Y, DVec3::Z] {
                let mut moved = m.positions.clone();
                moved[v as usize] += d * h;
                let dv = (capped_volume(&moved, &m.triangles, &piece) - v0) / h;
                assert!(
                    (dv - g.dot(d)).abs() < 1e-6,
                    "vertex {v}: {dv} against {}",
                    g.dot(d)
                );
            }
        }
    }
}
