//! Triangle meshes: reading files, welding, repairing and validating them, angle-weighted
//! normals, analytic test shapes and subdivision.
//!
//! Everything downstream (skeleton, rig, simulation) takes a [`Mesh`] that passed
//! [`validate`]: a welded mesh whose body is a closed, consistently and outwardly oriented
//! 2-manifold (small separate parts may ride along, see [`Parts`]), with the vertex order
//! of the input file (vertices added to close holes come last).
//!
//! Files, in the order a load runs them:
//! * `obj`, `ply`, `stl`, `gltf`: parsing into a `soup` (positions and triangles as the file
//!   has them); `guard`: the crates' readers held to one error line;
//! * `weld`: one vertex where the file has several at the same place;
//! * `edges`: the half-edges by vertex and the edge census that repairs and checks read;
//! * `repair`: open seams, faces turned against their neighbours, holes (closed by `fill`:
//!   a refined constrained Delaunay patch, faired);
//! * `split`: sheets that touch at a vertex or along an edge, each given its own copies;
//! * `parts`: the connected pieces, body and riders; `attachments`: where body parts meet;
//! * `grid`: the nearest-point grid riders, attachments and the mirror plane query;
//! * `validate`: the checks, and turning inside-out parts;
//! * `load`: the pipeline, its options and its report;
//! * `normals`, `fit`: angle-weighted vertex normals, and the local surface fit that
//!   sharpens them for the skeleton;
//! * `skin`: the skeleton and clips a file comes with (a glTF skin);
//! * `shapes`, `subdivide`: test shapes, refinement;
//! * `groups`: the file's named groups (materials), carried to the loaded vertices;
//! * `measure`: areas, volumes and extents of a surface;
//! * `orientation`: a character's flat base, up, front and left; `mirror`: its mirror plane.

mod attachments;
mod edges;
mod fill;
mod fit;
mod gltf;
mod grid;
mod groups;
mod guard;
mod load;
pub mod measure;
pub mod mirror;
mod normals;
mod obj;
pub mod orientation;
mod parts;
mod ply;
mod repair;
pub mod shapes;
pub mod skin;
mod soup;
mod split;
mod stl;
mod subdivide;
mod validate;
mod weld;

pub use attachments::attachments;
pub use fit::{fit_surface, SurfaceFit};
pub use groups::{FaceGroups, Groups};
pub use load::{
    file_mesh, load, load_with, parse, parse_file_mesh, parse_obj, Format, LoadOptions, LoadReport,
    RepairMarks, FILL_HOLES, WELD_TOLERANCE,
};
pub use normals::{area_normals_into, vertex_normals};
pub use obj::write as write_obj;
pub(crate) use parts::components;
pub use parts::{Parts, RIDER_AREA};
pub use skin::Skin;
pub use subdivide::{subdivide_loop, subdivide_loop_values, subdivide_midpoint};
pub use validate::{validate, Topology};
pub use weld::weld;

use glam::DVec3;

/// Largest coordinate magnitude accepted from a file. Beyond it, squared distances lose the
/// precision the skeleton and the simulation need; such values are almost always a broken
/// export, so they are refused instead of silently producing garbage.
pub const MAX_COORDINATE: f64 = 1e12;

/// An indexed triangle mesh in double precision.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// What can be wrong with a mesh. The message never names the file: the caller adds it.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file cannot be read (why, in words).
    #[error("cannot read file: {0}")]
    Io(String),
    /// Binary or not UTF-8.
    #[error("not a text OBJ file: {0}")]
    NotText(String),
    /// A malformed line.
    #[error("line {line}: {message}")]
    Syntax {
        /// Line number, from 1.
        line: usize,
        /// What is wrong with it.
        message: String,
    },
    /// The parser refused the file.
    #[error("{0}")]
    Parse(String),
    /// No faces.
    #[error("no triangles: the file holds {vertices} vertices and no faces")]
    Empty {
        /// Vertices in the file.
        vertices: usize,
    },
    /// A NaN or infinite coordinate.
    #[error("vertex {vertex} has a non-finite coordinate ({value})")]
    NonFinite {
        /// The vertex, from 1 (as the file counts).
        vertex: usize,
        /// The coordinate.
        value: f64,
    },
    /// A coordinate beyond [`MAX_COORDINATE`].
    #[error("vertex {vertex} has coordinate {value:e}, beyond the supported range ±{max:e}")]
    TooLarge {
        /// The vertex, from 1.
        vertex: usize,
        /// The coordinate.
        value: f64,
        /// The largest accepted magnitude.
        max: f64,
    },
    /// No volume, or a vertex without a normal.
    #[error("the mesh is degenerate: {0}")]
    Degenerate(String),
    /// Not a closed, consistently oriented 2-manifold (what, how many, an example).
    #[error("not a closed 2-manifold: {0}")]
    Topology(String),
}

impl Mesh {
    /// Axis-aligned bounding box `(min, max)`; `(0, 0)` for an empty mesh.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        bounds(&self.positions)
    }

    /// The longest side of the bounding box (a character's height, whichever way it is
    /// modelled up).
    pub fn longest_side(&self) -> f64 {
        longest_side(&self.positions)
    }

    /// Length of the bounding-box diagonal.
    pub fn diagonal(&self) -> f64 {
        let (lo, hi) = self.bounds();
        (hi - lo).length()
    }

    /// Number of unique undirected edges.
    pub fn edge_count(&self) -> usize {
        unique_edges(&self.triangles).len()
    }

    /// The mean length of its unique edges (0 without any).
    pub fn mean_edge_length(&self) -> f64 {
        let edges = unique_edges(&self.triangles);
        edges
            .iter()
            .map(|&(a, b)| self.positions[a as usize].distance(self.positions[b as usize]))
            .sum::<f64>()
            / edges.len().max(1) as f64
    }

    /// The centroid of the volume the mesh encloses (of its vertices where it encloses
    /// none): unlike the vertices' mean, not pulled towards a finely meshed face.
    pub fn volume_centroid(&self) -> DVec3 {
        let mut sum = DVec3::ZERO;
        let mut volume = 0.0;
        let origin = self.positions.first().copied().unwrap_or_default();
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.positions[i as usize] - origin);
            let v = a.dot(b.cross(c)) / 6.0;
            sum += (a + b + c) / 4.0 * v;
            volume += v;
        }
        if volume.abs() > f64::MIN_POSITIVE && (sum / volume).is_finite() {
            origin + sum / volume
        } else {
            self.positions.iter().sum::<DVec3>() / self.positions.len().max(1) as f64
        }
    }

    /// Is the surface closed, every edge shared by two faces running opposite ways, with
    /// every part turned outward (positive volume)? Seen from outside, such a surface
    /// shows only the faces turned towards the eye: a renderer may skip the others (see
    /// `render::SceneRenderer`). An open sheet, a hole left open (`--fill-holes 0`) or a
    /// part inside out says no.
    pub fn is_closed_outward(&self) -> bool {
        if self.triangles.is_empty() {
            return false;
        }
        let half = edges::HalfEdges::new(self.positions.len(), &self.triangles);
        half.is_closed_manifold()
            && parts::Parts::measured(self)
                .1
                .volume
                .iter()
                .all(|&v| v > 0.0)
    }

    /// Signed volume (positive for an outward-oriented closed mesh).
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }
}

/// A message from another crate on one line (errors are one line each).
fn one_line(message: &str) -> String {
    let words: Vec<&str> = message.split_whitespace().collect();
    let line = words.join(" ");
    // A parser's internal state says nothing to a user.
    let line = line.split(" Error: ParseError").next().unwrap_or(&line);
    line.replace(". Error:", ":")
}

/// The longest side of the bounding box of a point set; 0 when empty.
pub fn longest_side(points: &[DVec3]) -> f64 {
    let (lo, hi) = bounds(points);
    (hi - lo).max_element()
}

/// Bounding box of a point set; `(0, 0)` when empty.
pub fn bounds(points: &[DVec3]) -> (DVec3, DVec3) {
    if points.is_empty() {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

/// Each vertex's neighbours over `edges` (as [`unique_edges`] gives them) as a CSR: the
/// neighbours of `v` are `to[start[v]..start[v + 1]]`, in the order of `edges`.
pub fn neighbours(n: usize, edges: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; n + 1];
    for &(a, b) in edges {
        start[a as usize + 1] += 1;
        start[b as usize + 1] += 1;
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut to = vec![0u32; 2 * edges.len()];
    for &(a, b) in edges {
        for (from, other) in [(a, b), (b, a)] {
            to[fill[from as usize] as usize] = other;
            fill[from as usize] += 1;
        }
    }
    (start, to)
}

/// Unique undirected edges `(a, b)` with `a < b`, sorted.
///
/// A counting sort on `a` (a bucket per vertex), then each small bucket sorted on `b`:
/// linear in the faces, where sorting all `3F` pairs was the larger part of building a rig.
pub fn unique_edges(triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let n = triangles
        .iter()
        .flat_map(|t| t.iter())
        .max()
        .map_or(0, |&m| m as usize + 1);
    let mut start = vec![0u32; n + 1];
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            start[a.min(b) as usize + 1] += 1;
        }
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut other = vec![0u32; triangles.len() * 3];
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let slot = &mut fill[a.min(b) as usize];
            other[*slot as usize] = a.max(b);
            *slot += 1;
        }
    }
    let mut edges = Vec::with_capacity(triangles.len() * 3 / 2 + 1);
    for a in 0..n {
        let bucket = &mut other[start[a] as usize..start[a + 1] as usize];
        bucket.sort_unstable();
        let mut last = None;
        for &b in bucket.iter() {
            if last != Some(b) {
                edges.push((a as u32, b));
                last = Some(b);
            }
        }
    }
    edges
}

#[cfg(test)]
mod tests {
    use super::unique_edges;
    use glam::DVec3;

    #[test]
    fn closed_outward_means_no_boundary_and_every_part_turned_out() {
        let sphere = super::shapes::uv_sphere(1.0, 8, 12);
        assert!(sphere.is_closed_outward());
        let mut two = sphere.clone();
        let far = super::shapes::uv_sphere(0.5, 6, 8);
        let n = two.positions.len() as u32;
        two.positions
            .extend(far.positions.iter().map(|&p| p + 3.0 * DVec3::X));
        two.triangles
            .extend(far.triangles.iter().map(|t| t.map(|v| v + n)));
        assert!(two.is_closed_outward(), "two closed parts");
        // The small part inside out: the whole volume stays positive, the part's is not.
        let k = sphere.triangles.len();
        two.triangles[k..].iter_mut().for_each(|t| t.swap(1, 2));
        assert!(!two.is_closed_outward(), "a part inside out");
        let mut open = sphere.clone();
        open.triangles.pop();
        assert!(!open.is_closed_outward(), "a hole");
        assert!(!super::Mesh::default().is_closed_outward(), "nothing");
    }

    #[test]
    fn the_volume_centroid_is_a_cubes_centre_however_meshed_and_wherever_it_is() {
        let mut m = super::shapes::cube_grid(2.0, 1);
        let fine = super::shapes::cube_grid(2.0, 8);
        assert!(fine.volume_centroid().length() < 1e-12);
        m.positions.iter_mut().for_each(|p| *p += DVec3::X);
        assert!((m.volume_centroid() - DVec3::X).length() < 1e-12);
        assert_eq!(
            super::Mesh::default().volume_centroid(),
            DVec3::ZERO,
            "an empty mesh"
        );
    }

    #[test]
    fn unique_edges_are_the_sorted_deduplicated_pairs() {
        // Any triangles, repeated vertices and faces included.
        let mut state = 7u64;
        let mut next = |m: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) % m) as u32
        };
        let triangles: Vec<[u32; 3]> = (0..500).map(|_| [next(60), next(60), next(60)]).collect();
        let mut naive: Vec<(u32, u32)> = triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
            .collect();
        naive.sort_unstable();
        naive.dedup();
        assert_eq!(unique_edges(&triangles), naive);
        assert!(unique_edges(&[]).is_empty());
    }
}
