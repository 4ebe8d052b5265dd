//! The file's vertex order: a point cache must have the vertices of the mesh the user
//! imports, in its order, while the simulation runs on the welded mesh (duplicates
//! merged, unused vertices dropped). Each file vertex follows the welded vertex at its
//! place (the one welding merged it into), offset by the difference of their rest
//! positions; a vertex no face uses stays where the file has it.

use crate::mesh::{Mesh, MeshError};
use glam::{DVec3, Vec3};
use std::collections::HashMap;
use std::path::Path;

/// How far a file vertex may be from the welded vertex it follows, as a share of the
/// diagonal (the weld tolerance and a repaired seam's gap are far below it).
pub const FILE_ORDER_TOLERANCE: f64 = 1e-3;

/// The file's vertices and faces, and the welded vertex each follows.
#[derive(Clone, Debug, PartialEq)]
pub struct FileOrder {
    /// The file's vertices (non-finite unused ones at the origin).
    pub positions: Vec<DVec3>,
    /// The file's triangles.
    pub triangles: Vec<[u32; 3]>,
    /// Per file vertex, the welded vertex it follows (`None`: it stays).
    follows: Vec<Option<u32>>,
    /// Per file vertex, its rest offset from the welded vertex it follows.
    offset: Vec<Vec3>,
}

impl FileOrder {
    /// The order of the mesh file at `path` for `welded`, the mesh loaded from it
    /// ([`crate::mesh::file_mesh`] reads the file again without welding). `None` when the
    /// file's vertices are the welded ones already.
    ///
    /// # Errors
    /// [`MeshError`] when the file cannot be read or parsed again.
    pub fn of_file(path: &Path, welded: &Mesh) -> Result<Option<FileOrder>, MeshError> {
        let file = crate::mesh::file_mesh(path)?;
        Ok(FileOrder::new(
            &file,
            &welded.positions,
            FILE_ORDER_TOLERANCE * welded.diagonal(),
        ))
    }

    /// Matches `file`'s vertices to the welded mesh's rest positions `welded`: an exact
    /// match first, else the nearest welded vertex within `tolerance` (mesh units; the weld
    /// and seam tolerances). `None` when the two are the same vertex list already.
    pub fn new(file: &Mesh, welded: &[DVec3], tolerance: f64) -> Option<FileOrder> {
        if file.positions == welded {
            return None;
        }
        let key = |p: DVec3| p.to_array().map(f64::to_bits);
        let exact: HashMap<[u64; 3], u32> = welded
            .iter()
            .enumerate()
            .rev()
            .map(|(i, &p)| (key(p), i as u32))
            .collect();
        let cell = tolerance.max(f64::MIN_POSITIVE);
        let cell_of = |p: DVec3| (p / cell).floor().as_i64vec3().to_array();
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let mut follows = Vec::with_capacity(file.positions.len());
        let mut offset = Vec::with_capacity(file.positions.len());
        let mut positions = Vec::with_capacity(file.positions.len());
        for &p in &file.positions {
            let p = if p.is_finite() { p } else { DVec3::ZERO };
            positions.push(p);
            let found = exact.get(&key(p)).copied().or_else(|| {
                if grid.is_empty() {
                    for (i, &w) in welded.iter().enumerate() {
                        grid.entry(cell_of(w)).or_default().push(i as u32);
                    }
                }
                let c = cell_of(p);
                let mut best: Option<(f64, u32)> = None;
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let near = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]);
                            for &i in near.into_iter().flatten() {
                                let d = welded[i as usize].distance_squared(p);
                                if d <= tolerance * tolerance && best.is_none_or(|b| d < b.0) {
                                    best = Some((d, i));
                                }
                            }
                        }
                    }
                }
                best.map(|b| b.1)
            });
            follows.push(found);
            offset.push(found.map_or(Vec3::ZERO, |w| (p - welded[w as usize]).as_vec3()));
        }
        Some(FileOrder {
            positions,
            triangles: file.triangles.clone(),
            follows,
            offset,
        })
    }

    /// A frame of the welded mesh in the file's order.
    pub fn frame(&self, welded: &[Vec3]) -> Vec<Vec3> {
        self.follows
            .iter()
            .zip(&self.offset)
            .zip(&self.positions)
            .map(|((f, &o), &p)| match f {
                Some(w) => welded.get(*w as usize).map_or(p.as_vec3(), |&x| x + o),
                None => p.as_vec3(),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duplicates_follow_their_welded_vertex_and_unused_ones_stay() {
        // A file with vertex 3 a duplicate of 0, vertex 4 unused and vertex 5 a near one.
        let file = Mesh {
            positions: vec![
                DVec3::ZERO,
                DVec3::X,
                DVec3::Y,
                DVec3::ZERO,
                DVec3::splat(9.0),
                DVec3::new(1e-9, 1.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [3, 1, 5]],
        };
        let welded = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let order = FileOrder::new(&file, &welded, 1e-6).unwrap();
        let moved = [
            Vec3::ONE,
            Vec3::new(2.0, 1.0, 1.0),
            Vec3::new(1.0, 2.0, 1.0),
        ];
        let f = order.frame(&moved);
        assert_eq!(f.len(), 6);
        assert_eq!(f[0], Vec3::ONE);
        assert_eq!(f[3], Vec3::ONE);
        assert_eq!(f[4], Vec3::splat(9.0));
        assert!((f[5] - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-6);
        // Already in order: nothing to do.
        let same = Mesh {
            positions: welded.to_vec(),
            triangles: vec![[0, 1, 2]],
        };
        assert!(FileOrder::new(&same, &welded, 1e-6).is_none());
    }
}
