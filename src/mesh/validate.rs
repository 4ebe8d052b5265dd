//! Validation: is the mesh a closed, consistently oriented 2-manifold the skeleton can use?
//! Refusals say what is wrong and how much ("37 boundary edges, e.g. 4–9").

use super::{Mesh, MeshError};

/// Facts found by [`validate`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Topology {
    /// Unique edges.
    pub edges: usize,
    /// Connected components (by shared edges).
    pub components: usize,
    /// Faces of exactly zero area (kept: they close the surface).
    pub zero_area_faces: usize,
    /// The mesh was inside out and its faces were flipped.
    pub flipped: bool,
}

/// Checks that `mesh` is a closed, consistently oriented 2-manifold, flips it if it is
/// inside out, and reports what it found.
///
/// # Errors
/// [`MeshError::Topology`] naming boundary, non-manifold and inconsistently oriented edges
/// and non-manifold vertices with counts and an example; [`MeshError::Empty`] or
/// [`MeshError::Degenerate`] for meshes without volume.
pub fn validate(mesh: &mut Mesh) -> Result<Topology, MeshError> {
    if mesh.triangles.is_empty() {
        return Err(MeshError::Empty {
            vertices: mesh.positions.len(),
        });
    }
    // Directed edges sorted by undirected key.
    let mut edges: Vec<(u32, u32, bool)> = Vec::with_capacity(mesh.triangles.len() * 3);
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.push((a.min(b), a.max(b), a < b));
        }
    }
    edges.sort_unstable();
    let (mut boundary, mut nonmanifold, mut flipped_edges, mut unique) = (0, 0, 0, 0);
    let mut examples: [Option<(u32, u32)>; 3] = [None; 3];
    let mut i = 0;
    while i < edges.len() {
        let mut j = i;
        while j < edges.len() && edges[j].0 == edges[i].0 && edges[j].1 == edges[i].1 {
            j += 1;
        }
        unique += 1;
        let key = (edges[i].0 + 1, edges[i].1 + 1);
        match j - i {
            1 => {
                boundary += 1;
                examples[0].get_or_insert(key);
            }
            2 if edges[i].2 == edges[i + 1].2 => {
                flipped_edges += 1;
                examples[2].get_or_insert(key);
            }
            2 => {}
            _ => {
                nonmanifold += 1;
                examples[1].get_or_insert(key);
            }
        }
        i = j;
    }
    let mut problems = Vec::new();
    let eg = |e: Option<(u32, u32)>| {
        e.map(|(a, b)| format!(" (e.g. {a}-{b})"))
            .unwrap_or_default()
    };
    if boundary > 0 {
        problems.push(format!("{boundary} boundary edges{}", eg(examples[0])));
    }
    if nonmanifold > 0 {
        problems.push(format!(
            "{nonmanifold} non-manifold edges shared by more than two faces{}",
            eg(examples[1])
        ));
    }
    if flipped_edges > 0 {
        problems.push(format!(
            "{flipped_edges} edges between inconsistently oriented faces{}",
            eg(examples[2])
        ));
    }
    if !problems.is_empty() {
        return Err(MeshError::Topology(problems.join(", ")));
    }
    let bad_vertices = nonmanifold_vertices(mesh);
    if let Some(&first) = bad_vertices.first() {
        return Err(MeshError::Topology(format!(
            "{} non-manifold vertices where separate surface sheets touch (e.g. vertex {})",
            bad_vertices.len(),
            first + 1
        )));
    }
    let components = count_components(mesh);
    let zero_area_faces = mesh
        .triangles
        .iter()
        .filter(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            (b - a).cross(c - a) == glam::DVec3::ZERO
        })
        .count();
    let volume = mesh.signed_volume();
    let scale = mesh.diagonal();
    if volume.is_nan() || volume.abs() <= 1e-12 * scale * scale * scale {
        return Err(MeshError::Degenerate(format!(
            "it encloses no volume (signed volume {volume:e})"
        )));
    }
    let flipped = volume < 0.0;
    if flipped {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    Ok(Topology {
        edges: unique,
        components,
        zero_area_faces,
        flipped,
    })
}

/// Vertices whose faces do not form a single fan (edges must already be manifold).
fn nonmanifold_vertices(mesh: &Mesh) -> Vec<u32> {
    let n = mesh.positions.len();
    // CSR of the "opposite edges" of each vertex's faces: for face (v, a, b): a -> b.
    let mut start = vec![0u32; n + 1];
    for t in &mesh.triangles {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut opp = vec![(0u32, 0u32); mesh.triangles.len() * 3];
    for t in &mesh.triangles {
        for k in 0..3 {
            let v = t[k] as usize;
            opp[fill[v] as usize] = (t[(k + 1) % 3], t[(k + 2) % 3]);
            fill[v] += 1;
        }
    }
    let mut bad = Vec::new();
    for v in 0..n {
        let fan = &mut opp[start[v] as usize..start[v + 1] as usize];
        if fan.is_empty() {
            continue;
        }
        fan.sort_unstable();
        // Follow a -> b from the first edge; a single fan visits every edge once.
        let first = fan[0].0;
        let mut cur = first;
        let mut steps = 0;
        while let Ok(k) = fan.binary_search_by_key(&cur, |e| e.0) {
            cur = fan[k].1;
            steps += 1;
            if cur == first || steps > fan.len() {
                break;
            }
        }
        if steps != fan.len() || cur != first {
            bad.push(v as u32);
        }
    }
    bad
}

fn count_components(mesh: &Mesh) -> usize {
    let n = mesh.positions.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for t in &mesh.triangles {
        let r0 = find(&mut parent, t[0]);
        for &v in &t[1..] {
            let r = find(&mut parent, v);
            if r != r0 {
                parent[r as usize] = r0;
            }
        }
    }
    (0..n as u32).filter(|&v| find(&mut parent, v) == v).count()
}
