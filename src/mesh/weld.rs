//! Welding: merge vertices closer than a tolerance relative to the bounding box, drop the
//! faces that collapse, and drop vertices no face uses. Vertex order is kept (first
//! occurrence wins), so indices stay comparable with the input file.

use super::Mesh;
use std::collections::HashMap;

/// What [`weld`] changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WeldStats {
    /// Vertices merged into an earlier one.
    pub merged: usize,
    /// Faces dropped because two of their corners became the same vertex.
    pub dropped_faces: usize,
    /// Vertices removed in all (merged ones and unreferenced ones).
    pub removed_vertices: usize,
}

/// Welds `mesh` in place with tolerance `rel_tol` times the bounding-box diagonal.
pub fn weld(mesh: &mut Mesh, rel_tol: f64) -> WeldStats {
    let n = mesh.positions.len();
    let tol = rel_tol * mesh.diagonal();
    let mut rep: Vec<u32> = (0..n as u32).collect();
    let mut merged = 0;
    if tol > 0.0 && tol.is_finite() {
        let inv = 1.0 / tol;
        let cell = |x: f64| (x * inv).floor() as i64;
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::with_capacity(n);
        for (i, &p) in mesh.positions.iter().enumerate() {
            let c = [cell(p.x), cell(p.y), cell(p.z)];
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                            for &j in list {
                                if mesh.positions[j as usize].distance_squared(p) <= tol * tol {
                                    found = Some(j);
                                    break 'search;
                                }
                            }
                        }
                    }
                }
            }
            match found {
                Some(j) => {
                    rep[i] = j;
                    merged += 1;
                }
                None => grid.entry(c).or_default().push(i as u32),
            }
        }
    }
    let before = mesh.triangles.len();
    mesh.triangles = mesh
        .triangles
        .iter()
        .map(|t| t.map(|v| rep[v as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .collect();
    let dropped_faces = before - mesh.triangles.len();

    // Compact: keep referenced vertices in their original order.
    let mut used = vec![false; n];
    for t in &mesh.triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let mut new_index = vec![u32::MAX; n];
    let mut positions = Vec::with_capacity(n);
    for i in 0..n {
        if used[i] {
            new_index[i] = positions.len() as u32;
            positions.push(mesh.positions[i]);
        }
    }
    for t in &mut mesh.triangles {
        *t = t.map(|v| new_index[v as usize]);
    }
    let removed_vertices = n - positions.len();
    mesh.positions = positions;
    WeldStats {
        merged,
        dropped_faces,
        removed_vertices,
    }
}
