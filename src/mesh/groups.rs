//! Groups: the faces a file names together. An OBJ file's `usemtl` materials (or, in a file
//! without any, its `g` groups and `o` objects), a glTF file's primitives with their
//! materials. Artists already split a character this way (eyes, teeth, skin, shell), so a
//! group is offered as a region the user can give its own material (see
//! `puppet::Paint::groups`).
//!
//! The file names faces; what the puppet needs is a weight per welded vertex, after every
//! repair has renumbered, split and added vertices. So the groups are carried by position:
//! each file vertex's exact position collects the groups of the faces around it, and each
//! vertex of the repaired mesh takes the shares of the faces at its position (a vertex on
//! the seam between eyes and skin is half of each). Vertices no file face had (the inside
//! of a filled hole, a weld that moved one) take the mean of their neighbours, ring by ring.

use super::Mesh;
use std::collections::HashMap;

/// The faces of a file grouped by name, as a parser gives them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceGroups {
    /// Group names, in order of first use.
    pub names: Vec<String>,
    /// Group of each face of the soup (an index into `names`).
    pub of_face: Vec<u32>,
}

impl FaceGroups {
    /// Groups from a name per face (`None`: a face before any name, in a group of its own
    /// named `unnamed`). `None` when fewer than two groups remain: one group is the whole
    /// mesh, nothing to tell apart.
    pub fn from_names<'a>(names: impl Iterator<Item = Option<&'a str>>) -> Option<FaceGroups> {
        let mut index: HashMap<&str, u32> = HashMap::new();
        let mut out = FaceGroups::default();
        for name in names {
            let name = name.map_or("unnamed", str::trim);
            let name = if name.is_empty() { "unnamed" } else { name };
            let k = *index.entry(name).or_insert_with(|| {
                out.names.push(name.to_string());
                (out.names.len() - 1) as u32
            });
            out.of_face.push(k);
        }
        (out.names.len() > 1).then_some(out)
    }
}

/// Named groups of a loaded mesh: for each, a weight 0..1 per vertex.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Groups {
    /// Group names, in the file's order.
    pub names: Vec<String>,
    /// Per group, per vertex of the mesh: the share of the vertex's faces in the group.
    #[serde(skip)]
    pub weights: Vec<Vec<f32>>,
}

impl Groups {
    /// True when the file named no groups (or only one).
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// The weights of the group called `name`.
    pub fn weights_of(&self, name: &str) -> Option<&[f32]> {
        let k = self.names.iter().position(|n| n == name)?;
        self.weights.get(k).map(Vec::as_slice)
    }

    /// The groups of `faces` over the soup's `positions` and `triangles`, carried to the
    /// vertices of the repaired `mesh` by position.
    pub fn carry(
        faces: &FaceGroups,
        positions: &[glam::DVec3],
        triangles: &[[u32; 3]],
        mesh: &Mesh,
    ) -> Groups {
        let g = faces.names.len();
        let key = |p: glam::DVec3| p.to_array().map(f64::to_bits);
        // Per position: face count per group.
        let mut at: HashMap<[u64; 3], Vec<u32>> = HashMap::new();
        for (t, &k) in triangles.iter().zip(&faces.of_face) {
            for &v in t {
                let Some(&p) = positions.get(v as usize) else {
                    continue;
                };
                at.entry(key(p)).or_insert_with(|| vec![0; g])[k as usize] += 1;
            }
        }
        let n = mesh.positions.len();
        let mut weights = vec![vec![0.0f32; n]; g];
        let mut known = vec![false; n];
        for (v, p) in mesh.positions.iter().enumerate() {
            if let Some(counts) = at.get(&key(*p)) {
                let total: u32 = counts.iter().sum();
                for (w, &c) in weights.iter_mut().zip(counts) {
                    w[v] = c as f32 / total.max(1) as f32;
                }
                known[v] = true;
            }
        }
        spread(mesh, &mut weights, &mut known);
        Groups {
            names: faces.names.clone(),
            weights,
        }
    }
}

/// Gives every vertex not `known` the mean weights of its known neighbours, ring by ring
/// out from the known ones (vertices of a part with no known vertex stay at 0).
fn spread(mesh: &Mesh, weights: &mut [Vec<f32>], known: &mut [bool]) {
    if known.iter().all(|&k| k) {
        return;
    }
    let edges = super::unique_edges(&mesh.triangles);
    let (start, adj) = super::neighbours(mesh.positions.len(), &edges);
    loop {
        let ring: Vec<usize> = (0..known.len())
            .filter(|&v| {
                !known[v]
                    && adj[start[v] as usize..start[v + 1] as usize]
                        .iter()
                        .any(|&u| known[u as usize])
            })
            .collect();
        if ring.is_empty() {
            return;
        }
        for &v in &ring {
            let around: Vec<usize> = adj[start[v] as usize..start[v + 1] as usize]
                .iter()
                .map(|&u| u as usize)
                .filter(|&u| known[u])
                .collect();
            for w in weights.iter_mut() {
                w[v] = around.iter().map(|&u| w[u]).sum::<f32>() / around.len() as f32;
            }
        }
        for v in ring {
            known[v] = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn names_per_face_become_groups_and_one_name_is_none() {
        let g =
            FaceGroups::from_names([None, Some("skin"), Some(" eyes "), Some("skin")].into_iter())
                .unwrap();
        assert_eq!(g.names, ["unnamed", "skin", "eyes"]);
        assert_eq!(g.of_face, [0, 1, 2, 1]);
        assert!(FaceGroups::from_names([Some("a"), Some("a")].into_iter()).is_none());
        assert!(FaceGroups::from_names(std::iter::empty()).is_none());
    }

    #[test]
    fn weights_follow_positions_through_renumbering_and_fill_new_vertices() {
        // Two triangles of a quad in two groups, then the "repaired" mesh: renumbered, with
        // a new vertex in the middle of the quad.
        let positions = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let triangles = [[0, 1, 2], [0, 2, 3]];
        let faces = FaceGroups::from_names([Some("a"), Some("b")].into_iter()).unwrap();
        let mesh = Mesh {
            positions: vec![
                positions[3],
                positions[2],
                positions[1],
                positions[0],
                DVec3::new(0.5, 0.5, 0.0),
            ],
            triangles: vec![[3, 2, 4], [2, 1, 4], [1, 0, 4], [0, 3, 4]],
        };
        let g = Groups::carry(&faces, &positions, &triangles, &mesh);
        assert_eq!(g.names, ["a", "b"]);
        let a = g.weights_of("a").unwrap();
        assert_eq!(&a[..4], &[0.0, 0.5, 1.0, 0.5]);
        assert!((a[4] - 0.5).abs() < 1e-6);
        assert!(g.weights_of("c").is_none());
    }
}
