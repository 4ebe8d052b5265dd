//! Validation: is the mesh's body a closed, consistently oriented 2-manifold the skeleton can
//! use? Refusals say what is wrong and how much ("37 boundary edges, e.g. 4–9"). Riders
//! (small separate parts, see `parts`) are not held to it: they only ride along.

use super::edges::{target, EdgeCensus, HalfEdges};
use super::parts::{Measures, Parts};
use super::{Mesh, MeshError};
use glam::DVec3;
use rayon::prelude::*;

/// Facts found by [`validate`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Topology {
    /// Unique edges.
    pub edges: usize,
    /// Connected components (by shared vertices).
    pub components: usize,
    /// Components that ride along (see `parts`).
    pub riders: usize,
    /// Faces of exactly zero area (kept: they close the surface).
    pub zero_area_faces: usize,
    /// Some part was inside out and its faces were flipped.
    pub flipped: bool,
    /// How many parts were flipped.
    pub flipped_parts: usize,
}

/// Checks that `mesh`'s body is a closed, consistently oriented 2-manifold, turns every
/// closed part that is inside out, and reports what it found.
///
/// # Errors
/// [`MeshError::Topology`] naming boundary, non-manifold and inconsistently oriented edges
/// and non-manifold vertices with counts and an example; [`MeshError::Empty`] or
/// [`MeshError::Degenerate`] for meshes without volume.
pub fn validate(mesh: &mut Mesh) -> Result<Topology, MeshError> {
    let half = HalfEdges::new(mesh.positions.len(), &mesh.triangles);
    validate_with(mesh, &half, None, None)
}

/// [`validate`] with the half-edges of `mesh` already made; `closed` when
/// [`HalfEdges::is_closed_manifold`] was asked (and what it said), and the measured parts
/// when they were taken.
pub(super) fn validate_with(
    mesh: &mut Mesh,
    half: &HalfEdges,
    closed: Option<bool>,
    measured: Option<(Parts, Measures)>,
) -> Result<Topology, MeshError> {
    if mesh.triangles.is_empty() {
        return Err(MeshError::Empty {
            vertices: mesh.positions.len(),
        });
    }
    let (parts, measures) = measured.unwrap_or_else(|| Parts::measured(mesh));
    let body = |v: u32| !parts.is_rider_vertex(v as usize);
    // The whole mesh a closed manifold (the usual case): nothing to look into.
    let manifold = closed.unwrap_or_else(|| half.is_closed_manifold());
    let census = if manifold {
        EdgeCensus {
            edges: half.len() / 2,
            ..EdgeCensus::default()
        }
    } else {
        let census = half.census(&body);
        problems(&census)?;
        let bad_vertices = nonmanifold_vertices(mesh, half, &parts);
        if let Some(&first) = bad_vertices.first() {
            return Err(MeshError::Topology(format!(
                "{} non-manifold vertices where separate surface sheets touch (e.g. vertex {})",
                bad_vertices.len(),
                first + 1
            )));
        }
        census
    };
    // Riders count only when closed.
    let closed = closed_parts(half, &parts);
    let volume = measures.volume;
    let mut lo = vec![DVec3::splat(f64::INFINITY); parts.len()];
    let mut hi = vec![DVec3::splat(f64::NEG_INFINITY); parts.len()];
    for (v, p) in mesh.positions.iter().enumerate() {
        let k = parts.part_of[v] as usize;
        lo[k] = lo[k].min(*p);
        hi[k] = hi[k].max(*p);
    }
    let mut flip = vec![false; parts.len()];
    for k in 0..parts.len() {
        let scale = (hi[k] - lo[k]).length();
        let flat = volume[k].is_nan() || volume[k].abs() <= 1e-12 * scale * scale * scale;
        if !parts.rider[k] && flat {
            return Err(MeshError::Degenerate(format!(
                "it encloses no volume (signed volume {:e}): a flat sheet, or an open surface around nothing, has no inside to simulate",
                volume[k]
            )));
        }
        flip[k] = closed[k] && !flat && volume[k] < 0.0;
    }
    let flipped_parts = flip.iter().filter(|&&f| f).count();
    if flipped_parts > 0 {
        mesh.triangles.par_iter_mut().for_each(|t| {
            if flip[parts.part_of[t[0] as usize] as usize] {
                t.swap(1, 2);
            }
        });
    }
    Ok(Topology {
        edges: if manifold || parts.riders() == 0 {
            census.edges
        } else {
            census.edges + half.census(&|v| !body(v)).edges
        },
        components: parts.len(),
        riders: parts.riders(),
        zero_area_faces: measures.zero_area_faces,
        flipped: flipped_parts > 0,
        flipped_parts,
    })
}

/// The refusal for a census with problems.
fn problems(census: &EdgeCensus) -> Result<(), MeshError> {
    let eg = |e: Option<(u32, u32)>| {
        e.map(|(a, b)| format!(" (e.g. {}-{})", a + 1, b + 1))
            .unwrap_or_default()
    };
    let mut problems = Vec::new();
    if census.boundary > 0 {
        problems.push(format!(
            "{} boundary edges{}",
            census.boundary,
            eg(census.examples[0])
        ));
    }
    if census.nonmanifold > 0 {
        problems.push(format!(
            "{} non-manifold edges shared by more than two faces{} (fins, or sheets meeting along an edge: delete the extra faces in a modeller, e.g. Blender's Select > All by Trait > Non Manifold)",
            census.nonmanifold,
            eg(census.examples[1])
        ));
    }
    if census.inconsistent > 0 {
        problems.push(format!(
            "{} edges between inconsistently oriented faces{}",
            census.inconsistent,
            eg(census.examples[2])
        ));
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(MeshError::Topology(problems.join(", ")))
    }
}

/// Body vertices whose faces do not form a single fan (edges must already be manifold and
/// consistent).
fn nonmanifold_vertices(mesh: &Mesh, half: &HalfEdges, parts: &Parts) -> Vec<u32> {
    (0..mesh.positions.len() as u32)
        .into_par_iter()
        .filter(|&v| !parts.is_rider_vertex(v as usize) && !half.single_fan(v))
        .collect()
}

/// Whether each part is closed and consistently oriented (every edge of two faces running
/// opposite ways). Body parts are, once [`problems`] passed; riders are checked here.
fn closed_parts(half: &HalfEdges, parts: &Parts) -> Vec<bool> {
    let mut closed = vec![true; parts.len()];
    if parts.riders() == 0 {
        return closed;
    }
    for a in 0..half.vertices() as u32 {
        let k = parts.part_of[a as usize] as usize;
        if !parts.rider[k] || !closed[k] {
            continue;
        }
        let row = half.row(a);
        for (i, &e) in row.iter().enumerate() {
            let b = target(e);
            let repeated = i + 1 < row.len() && target(row[i + 1]) == b;
            if repeated || half.count(b, a) != 1 {
                closed[k] = false;
                break;
            }
        }
    }
    closed
}
