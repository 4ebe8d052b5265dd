//! Subdivision, used to build large benchmark inputs from the shipped meshes.

use super::Mesh;
use glam::DVec3;
use std::collections::HashMap;

/// Splits every triangle into four at its edge midpoints (shape unchanged, flat patches).
pub fn subdivide_midpoint(mesh: &Mesh) -> Mesh {
    split(mesh, |_, _, _| None).0
}

/// One step of Loop subdivision: a smooth surface with four times the faces. Original
/// vertices keep their indices; edge vertices follow.
pub fn subdivide_loop(mesh: &Mesh) -> Mesh {
    subdivide_loop_with_parents(mesh).0
}

/// [`subdivide_loop`], and per-vertex values carried along: an original vertex keeps its
/// value, an edge vertex takes the mean of its edge's ends. Used to give subdivided
/// benchmark meshes plausible skeletal distances without recomputing the skeleton.
///
/// # Panics
/// If `values` does not have one entry per vertex.
pub fn subdivide_loop_values(mesh: &Mesh, values: &[f64]) -> (Mesh, Vec<f64>) {
    assert_eq!(values.len(), mesh.positions.len(), "one value per vertex");
    let (out, parents) = subdivide_loop_with_parents(mesh);
    let mut v = values.to_vec();
    v.extend(
        parents
            .iter()
            .map(|&(a, b)| 0.5 * (values[a as usize] + values[b as usize])),
    );
    (out, v)
}

fn subdivide_loop_with_parents(mesh: &Mesh) -> (Mesh, Vec<(u32, u32)>) {
    let n = mesh.positions.len();
    // Neighbour sums for the vertex rule.
    let mut nsum = vec![DVec3::ZERO; n];
    let mut valence = vec![0u32; n];
    for &(a, b) in &super::unique_edges(&mesh.triangles) {
        nsum[a as usize] += mesh.positions[b as usize];
        nsum[b as usize] += mesh.positions[a as usize];
        valence[a as usize] += 1;
        valence[b as usize] += 1;
    }
    let (mut out, parents) = split(mesh, |a, b, opp: [DVec3; 2]| {
        Some(0.375 * (a + b) + 0.125 * (opp[0] + opp[1]))
    });
    for i in 0..n {
        let k = valence[i] as f64;
        if k < 3.0 {
            continue;
        }
        let beta = if valence[i] == 3 {
            3.0 / 16.0
        } else {
            3.0 / (8.0 * k)
        };
        out.positions[i] = (1.0 - k * beta) * mesh.positions[i] + beta * nsum[i];
    }
    (out, parents)
}

/// Shared 1-to-4 split; `edge_point(a, b, [opposite corners])` gives the new edge vertex
/// (None = midpoint). Also returns the edge each new vertex was made from.
fn split(
    mesh: &Mesh,
    edge_point: impl Fn(DVec3, DVec3, [DVec3; 2]) -> Option<DVec3>,
) -> (Mesh, Vec<(u32, u32)>) {
    let p = &mesh.positions;
    // Opposite corners per undirected edge.
    let mut opposite: HashMap<(u32, u32), Vec<u32>> =
        HashMap::with_capacity(mesh.triangles.len() * 2);
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            opposite
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push(t[(k + 2) % 3]);
        }
    }
    let mut positions = p.clone();
    let mut parents = Vec::with_capacity(opposite.len());
    let mut mid: HashMap<(u32, u32), u32> = HashMap::with_capacity(opposite.len());
    let mut triangles = Vec::with_capacity(mesh.triangles.len() * 4);
    for t in &mesh.triangles {
        let mut m = [0u32; 3];
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            m[k] = *mid.entry(key).or_insert_with(|| {
                let (pa, pb) = (p[a as usize], p[b as usize]);
                let opp = &opposite[&key];
                let pt = if opp.len() == 2 {
                    edge_point(pa, pb, [p[opp[0] as usize], p[opp[1] as usize]])
                } else {
                    None
                };
                positions.push(pt.unwrap_or(0.5 * (pa + pb)));
                parents.push(key);
                (positions.len() - 1) as u32
            });
        }
        triangles.push([t[0], m[0], m[2]]);
        triangles.push([t[1], m[1], m[0]]);
        triangles.push([t[2], m[2], m[1]]);
        triangles.push([m[0], m[1], m[2]]);
    }
    (
        Mesh {
            positions,
            triangles,
        },
        parents,
    )
}
