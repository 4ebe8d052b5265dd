//! Separating surface sheets that touch: a vertex where two fans of faces meet (a pinched
//! vertex: a classic cow's, a teapot's once its holes are closed) and an edge shared by
//! more than two faces (two sheets along one edge) each become as many vertices as there
//! are sheets there, all at the same place. Across an edge of two faces the faces are one
//! sheet; around an edge of four or more, each face is paired with the neighbour across
//! the solid wedge beside it (the side its outward normal does not point to), found by the
//! faces' angles about the edge. The skeleton treats the copies as any duplicated position.

use super::Mesh;
use glam::DVec3;
use std::collections::HashMap;

/// What [`split_sheets`] changed.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct Split {
    /// Vertices where separate sheets met, each now one per sheet.
    pub vertices: usize,
    /// Edges of more than two faces, opened into one edge per pair of faces.
    pub edges: usize,
    /// The split vertices and their copies.
    pub marked: Vec<u32>,
}

/// Union-find with path halving, over corners (`face × 3 + k`).
fn find(parent: &mut [u32], mut x: usize) -> usize {
    while parent[x] as usize != x {
        parent[x] = parent[parent[x] as usize];
        x = parent[x] as usize;
    }
    x
}

fn union(parent: &mut [u32], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb) as u32;
    }
}

/// The corner of face `f` at vertex `v`.
fn corner(triangles: &[[u32; 3]], f: u32, v: u32) -> usize {
    let t = triangles[f as usize];
    f as usize * 3 + t.iter().position(|&x| x == v).unwrap_or(0)
}

/// The faces around the edge `a`–`b` (`a < b`) paired across the solid wedge between
/// neighbours, or `None` where the faces' sides do not pair up (an inconsistent fold).
pub(super) fn pair_around(
    mesh: &Mesh,
    a: u32,
    b: u32,
    faces: &[(u32, bool)],
) -> Option<Vec<(u32, u32)>> {
    let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
    let axis = (pb - pa).normalize_or_zero();
    if axis == DVec3::ZERO {
        return None;
    }
    let u = axis.any_orthonormal_vector();
    let w = axis.cross(u);
    // Each face's angle about the edge, and whether the solid lies ahead of it (towards
    // larger angles): its outward normal points back.
    let mut around: Vec<(f64, u32, bool)> = Vec::with_capacity(faces.len());
    for &(f, _) in faces {
        let t = mesh.triangles[f as usize];
        let c = *t.iter().find(|&&x| x != a && x != b)?;
        let d = mesh.positions[c as usize] - pa;
        let d = (d - axis * axis.dot(d)).normalize_or_zero();
        let [p0, p1, p2] = t.map(|v| mesh.positions[v as usize]);
        let normal = (p1 - p0).cross(p2 - p0);
        let ahead = normal.dot(axis.cross(d)) < 0.0;
        around.push((d.dot(w).atan2(d.dot(u)), f, ahead));
    }
    around.sort_by(|x, y| x.0.total_cmp(&y.0));
    let n = around.len();
    let mut pairs = Vec::with_capacity(n / 2);
    for k in 0..n {
        let (_, f, ahead) = around[k];
        if ahead {
            let (_, g, g_ahead) = around[(k + 1) % n];
            if g_ahead {
                return None;
            }
            pairs.push((f, g));
        }
    }
    (pairs.len() * 2 == n).then_some(pairs)
}

/// Gives every sheet that touches another at a vertex or along an edge its own copies of
/// the vertices they share (new vertices appended, at the same positions). Edges that are
/// boundaries, inconsistently oriented, or of faces that cannot be paired are left.
pub(super) fn split_sheets(mesh: &mut Mesh) -> Split {
    let mut edges: HashMap<(u32, u32), Vec<(u32, bool)>> = HashMap::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((f as u32, a < b));
        }
    }
    let mut parent: Vec<u32> = (0..mesh.triangles.len() as u32 * 3).collect();
    let mut split = Split::default();
    let mut keys: Vec<(u32, u32)> = edges.keys().copied().collect();
    keys.sort_unstable();
    for (a, b) in keys {
        let faces = &edges[&(a, b)];
        let forward = faces.iter().filter(|f| f.1).count();
        let paired = match faces.len() {
            2 if forward == 1 => Some(vec![(faces[0].0, faces[1].0)]),
            n if n > 2 && n % 2 == 0 && forward * 2 == n => pair_around(mesh, a, b, faces),
            _ => None,
        };
        let pairs = match paired {
            Some(p) => {
                split.edges += usize::from(faces.len() > 2);
                p
            }
            // A fin (an odd number of faces), faces that do not pair, or two running the
            // same way (a surface that cannot be oriented): kept together, so the check
            // names the edge instead of a sheet cut loose.
            None if faces.len() > 1 => faces.windows(2).map(|w| (w[0].0, w[1].0)).collect(),
            None => continue,
        };
        for (f, g) in pairs {
            for v in [a, b] {
                let (cf, cg) = (corner(&mesh.triangles, f, v), corner(&mesh.triangles, g, v));
                union(&mut parent, cf, cg);
            }
        }
    }
    // Each vertex keeps its first sheet; every other sheet gets a copy.
    let n = mesh.positions.len();
    let mut first: Vec<u32> = vec![u32::MAX; n];
    let mut copy: HashMap<usize, u32> = HashMap::new();
    let mut split_vertex = vec![false; n];
    for c in 0..parent.len() {
        let v = mesh.triangles[c / 3][c % 3] as usize;
        let root = find(&mut parent, c) as u32;
        if first[v] == u32::MAX {
            first[v] = root;
        } else if first[v] != root {
            let new = *copy.entry(root as usize).or_insert_with(|| {
                mesh.positions.push(mesh.positions[v]);
                (mesh.positions.len() - 1) as u32
            });
            split_vertex[v] = true;
            mesh.triangles[c / 3][c % 3] = new;
        }
    }
    split.vertices = split_vertex.iter().filter(|&&s| s).count();
    split.marked = (0..n as u32)
        .filter(|&v| split_vertex[v as usize])
        .chain(n as u32..mesh.positions.len() as u32)
        .collect();
    split
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::edges::HalfEdges;
    use crate::mesh::shapes;

    fn tetra(offset: DVec3) -> Mesh {
        Mesh {
            positions: [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z]
                .map(|p| p + offset)
                .to_vec(),
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        }
    }

    /// Two meshes in one, the second's vertices renumbered by `map`.
    fn join(a: &Mesh, b: &Mesh, map: impl Fn(u32) -> u32) -> Mesh {
        let mut m = a.clone();
        let n = m.positions.len() as u32;
        m.positions.extend(b.positions.iter().copied());
        m.triangles.extend(
            b.triangles
                .iter()
                .map(|t| t.map(|v| if map(v) < n { map(v) } else { v + n })),
        );
        m
    }

    #[test]
    fn two_tetrahedra_touching_at_a_vertex_get_one_each() {
        // The second tetrahedron mirrored through the first's vertex 0: they touch there.
        let a = tetra(DVec3::ZERO);
        let mut b = tetra(DVec3::ZERO);
        for p in &mut b.positions {
            *p = -*p;
        }
        for t in &mut b.triangles {
            t.swap(1, 2);
        }
        let mut m = join(&a, &b, |v| if v == 0 { 0 } else { u32::MAX });
        assert!(!HalfEdges::new(m.positions.len(), &m.triangles).is_closed_manifold());
        let s = split_sheets(&mut m);
        assert_eq!(
            s,
            Split {
                vertices: 1,
                edges: 0,
                marked: vec![0, 8]
            }
        );
        assert!(HalfEdges::new(m.positions.len(), &m.triangles).is_closed_manifold());
        assert_eq!(
            m.positions.len(),
            9,
            "a copy of the shared vertex (the join left one unused)"
        );
    }

    #[test]
    fn two_tetrahedra_sharing_an_edge_are_opened_along_it() {
        // The second turned half a turn about the z axis: they share the edge 0–3 and
        // nothing else.
        let a = tetra(DVec3::ZERO);
        let mut b = tetra(DVec3::ZERO);
        for p in &mut b.positions {
            *p = DVec3::new(-p.x, -p.y, p.z);
        }
        let mut m = join(&a, &b, |v| match v {
            0 => 0,
            3 => 3,
            _ => u32::MAX,
        });
        let half = HalfEdges::new(m.positions.len(), &m.triangles);
        assert_eq!(half.census(&|_| true).nonmanifold, 1);
        let s = split_sheets(&mut m);
        assert_eq!(
            s,
            Split {
                vertices: 2,
                edges: 1,
                marked: vec![0, 3, 8, 9]
            }
        );
        assert!(HalfEdges::new(m.positions.len(), &m.triangles).is_closed_manifold());
    }

    #[test]
    fn a_closed_manifold_is_left_alone() {
        let mut m = shapes::icosphere(1.0, 2);
        let before = m.clone();
        assert_eq!(split_sheets(&mut m), Split::default());
        assert_eq!(m, before);
    }
}
