//! The rig (paper §3.2): what the simulation needs from mesh + skeleton, in `f32`.
//!
//! * one mass point per vertex, its rest position `p_i` and unit normal `n_i`;
//! * surface springs: the unique mesh edges, rest length = edge length at load, stored flat
//!   as [`Spring`] `(a, b, rest, stiffness)` and, for the solver, as a CSR adjacency (each
//!   vertex gathers its own forces, so the step has no write races and no order
//!   dependence). A spring's stiffness is `ℓ̄ / rest` ([`stiffness`], `ℓ̄` the mean rest
//!   length): its force is `ℓ̄ ε` for a strain `ε`, so the surface stretches like one sheet
//!   of material whatever its triangles. With equal springs (the paper's reading) a short
//!   edge takes the same extension as a long one, so several times its strain: among the
//!   posed characters of `puppet bench poses` an edge a ninth of the mean length settled
//!   at 4.4× while its bones held it at 1.0×. The mass of a point is the sum of its
//!   springs' stiffnesses (two bone springs of stiffness 1 included), so the step stays a
//!   weighted average that is stable for any stiffnesses;
//! * per vertex an inner and an outer bone point `p_i ∓ f_bd d_i n_i` with bone springs of
//!   rest length `L_i = f_bd d_i`. Changing `f_bd` ([`Rig::set_bone_distance`]) is O(n) and
//!   never recomputes the skeleton.

use crate::mesh::Mesh;
use glam::{DVec3, Vec3};

/// A spring between two mass points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    /// One end (a vertex).
    pub a: u32,
    /// The other end.
    pub b: u32,
    /// Rest length.
    pub rest: f32,
    /// Stiffness relative to a spring of the mean rest length ([`stiffness`]).
    pub stiffness: f32,
}

/// The largest spring stiffness: a spring shorter than `ℓ̄ / MAX_STIFFNESS` (two vertices
/// at one place) pulls toward that length instead of its own.
pub const MAX_STIFFNESS: f32 = 1e4;

/// The stiffness of a surface spring of rest length `rest` among springs of mean rest
/// length `mean`: `mean / rest`, at most [`MAX_STIFFNESS`] (see the module docs).
pub fn stiffness(rest: f32, mean: f32) -> f32 {
    if rest > 0.0 && mean > 0.0 {
        (mean / rest).min(MAX_STIFFNESS)
    } else {
        MAX_STIFFNESS
    }
}

/// Mass points, springs and bone points for one bone distance.
#[derive(Clone, Debug)]
pub struct Rig {
    /// Rest positions `p_i`.
    pub rest: Vec<Vec3>,
    /// Unit outward normals `n_i`.
    pub normals: Vec<Vec3>,
    /// Skeletal distances `d_i`.
    pub skeletal_distance: Vec<f32>,
    /// Unique edges.
    pub springs: Vec<Spring>,
    /// CSR: the neighbours of vertex `i` are `neighbour[start[i]..start[i+1]]`.
    pub start: Vec<u32>,
    /// Neighbours by vertex (see `start`).
    pub neighbour: Vec<u32>,
    /// Stiffness of the spring to each neighbour ([`stiffness`]).
    pub neighbour_stiffness: Vec<f32>,
    /// The surface springs' mean rest length `ℓ̄`.
    pub spring_length: f32,
    /// Bone distance factor `f_bd` (0..1).
    pub bone_distance: f32,
    /// `L_i = f_bd d_i`.
    pub bone_length: Vec<f32>,
    /// Inner bone points `p_i − L_i n_i` in the rest pose.
    pub inner: Vec<Vec3>,
    /// Outer bone points `p_i + L_i n_i` in the rest pose.
    pub outer: Vec<Vec3>,
    /// Rest lengths of the inner and outer bone springs as the solver measures them (equal
    /// to `L_i` up to rounding; taken from the same f32 arithmetic, so a rig at rest has
    /// exactly zero force).
    pub inner_rest: Vec<f32>,
    /// As `inner_rest`, for the outer bone springs.
    pub outer_rest: Vec<f32>,
}

impl Rig {
    /// Builds the rig from a validated mesh, its unit normals and skeletal distances.
    ///
    /// # Panics
    /// If `normals` or `distance` do not have one entry per vertex.
    pub fn new(mesh: &Mesh, normals: &[DVec3], distance: &[f64], bone_distance: f32) -> Rig {
        let n = mesh.positions.len();
        assert_eq!(normals.len(), n, "one normal per vertex");
        assert_eq!(distance.len(), n, "one skeletal distance per vertex");
        let rest: Vec<Vec3> = mesh.positions.iter().map(|p| p.as_vec3()).collect();
        let mut springs: Vec<Spring> = crate::mesh::unique_edges(&mesh.triangles)
            .into_iter()
            .map(|(a, b)| Spring {
                a,
                b,
                rest: (rest[b as usize] - rest[a as usize]).length(),
                stiffness: 1.0,
            })
            .collect();
        let spring_length = (springs.iter().map(|s| f64::from(s.rest)).sum::<f64>()
            / springs.len().max(1) as f64) as f32;
        for s in &mut springs {
            s.stiffness = stiffness(s.rest, spring_length);
        }
        let mut start = vec![0u32; n + 1];
        for s in &springs {
            start[s.a as usize + 1] += 1;
            start[s.b as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut neighbour = vec![0u32; 2 * springs.len()];
        let mut neighbour_stiffness = vec![0f32; 2 * springs.len()];
        for s in &springs {
            for (from, to) in [(s.a, s.b), (s.b, s.a)] {
                let k = fill[from as usize] as usize;
                neighbour[k] = to;
                neighbour_stiffness[k] = s.stiffness;
                fill[from as usize] += 1;
            }
        }
        let mut rig = Rig {
            rest,
            normals: normals.iter().map(|v| v.as_vec3()).collect(),
            skeletal_distance: distance.iter().map(|&d| d as f32).collect(),
            springs,
            start,
            neighbour,
            neighbour_stiffness,
            spring_length,
            bone_distance: 0.0,
            bone_length: vec![0.0; n],
            inner: vec![Vec3::ZERO; n],
            outer: vec![Vec3::ZERO; n],
            inner_rest: vec![0.0; n],
            outer_rest: vec![0.0; n],
        };
        rig.set_bone_distance(bone_distance);
        rig
    }

    /// Number of mass points.
    pub fn len(&self) -> usize {
        self.rest.len()
    }

    /// True for a rig without vertices.
    pub fn is_empty(&self) -> bool {
        self.rest.is_empty()
    }

    /// Surface springs plus two bone springs per vertex.
    pub fn spring_count(&self) -> usize {
        self.springs.len() + 2 * self.len()
    }

    /// Moves the bone points for a new bone distance factor (clamped to 0..1), in O(n).
    pub fn set_bone_distance(&mut self, f_bd: f32) {
        self.set_bone_distances(f_bd, |_| f_bd);
    }

    /// Moves the bone points for a bone distance factor per vertex (`of(i)`, clamped to
    /// 0..1; several materials on one puppet), in O(n). `base` is recorded as
    /// [`Rig::bone_distance`].
    pub fn set_bone_distances(&mut self, base: f32, of: impl Fn(usize) -> f32) {
        let clamp = |f: f32| {
            if f.is_finite() {
                f.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        self.bone_distance = clamp(base);
        for i in 0..self.len() {
            let l = clamp(of(i)) * self.skeletal_distance[i];
            let (p, n) = (self.rest[i], self.normals[i]);
            self.bone_length[i] = l;
            self.inner[i] = p - l * n;
            self.outer[i] = p + l * n;
            self.inner_rest[i] = (self.inner[i] - p).length();
            self.outer_rest[i] = (self.outer[i] - p).length();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spring_is_as_stiff_as_the_mean_rest_length_over_its_own() {
        assert_eq!(stiffness(0.5, 0.5), 1.0);
        assert_eq!(stiffness(0.1, 0.5), 5.0);
        assert_eq!(stiffness(1.0, 0.5), 0.5);
        // Two vertices at one place: the stiffest spring, no infinity.
        assert_eq!(stiffness(0.0, 0.5), MAX_STIFFNESS);
        assert_eq!(stiffness(1e-9, 0.5), MAX_STIFFNESS);
    }

    #[test]
    fn each_neighbour_gets_its_springs_stiffness() {
        let mesh = crate::mesh::shapes::capsule(0.3, 1.5, 6, 36, 20);
        let n = mesh.positions.len();
        let rig = Rig::new(&mesh, &vec![DVec3::Y; n], &vec![0.1; n], 0.5);
        let mean = rig.springs.iter().map(|s| s.rest).sum::<f32>() / rig.springs.len() as f32;
        assert!((rig.spring_length - mean).abs() <= 1e-5 * mean);
        for s in &rig.springs {
            assert_eq!(s.stiffness, stiffness(s.rest, rig.spring_length));
            for (from, to) in [(s.a, s.b), (s.b, s.a)] {
                let row = rig.start[from as usize] as usize..rig.start[from as usize + 1] as usize;
                let k = row
                    .clone()
                    .find(|&k| rig.neighbour[k] == to)
                    .expect("in the CSR");
                assert_eq!(rig.neighbour_stiffness[k], s.stiffness);
            }
        }
    }
}
