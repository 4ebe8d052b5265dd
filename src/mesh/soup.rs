//! A triangle soup: positions and triangles as a file gave them, before welding, repairs
//! and validation make a [`Mesh`] of them.

use super::groups::FaceGroups;
use super::{Mesh, MeshError, MAX_COORDINATE};
use glam::DVec3;
use rayon::prelude::*;

/// Positions and triangles as read, in the file's order (indices are in range).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Soup {
    /// Vertex positions, unchecked.
    pub positions: Vec<DVec3>,
    /// Triangles (polygons already split), corners as the file wrote them.
    pub triangles: Vec<[u32; 3]>,
    /// Objects or groups in the file (at least 1).
    pub objects: usize,
    /// The faces' named groups, where the file has two or more.
    pub groups: Option<FaceGroups>,
    /// Header lines read as comments though they lack the `comment` keyword (PLY files
    /// some exporters write).
    pub loose_comments: usize,
    /// The skeleton the file comes with (a glTF skin), joints and clips.
    pub skin: Option<super::Skin>,
    /// Why the file's skin was left out, where it has one that cannot be read.
    pub unread_skin: Option<String>,
    /// Skinned vertices whose weights were not numbers, given their nearest neighbour's.
    pub borrowed_weights: usize,
}

impl Soup {
    /// Checks the coordinates of the vertices that faces use and makes a mesh of them (still
    /// to be welded and validated). Unused vertices may hold anything: they are dropped.
    ///
    /// # Errors
    /// [`MeshError::Empty`] without triangles; [`MeshError::NonFinite`] or
    /// [`MeshError::TooLarge`] naming the first bad used vertex (from 1, as files count).
    pub fn into_mesh(self) -> Result<(Mesh, Vec<bool>), MeshError> {
        if self.triangles.is_empty() {
            return Err(MeshError::Empty {
                vertices: self.positions.len(),
            });
        }
        let used = used_vertices(self.positions.len(), &self.triangles);
        let bad = self
            .positions
            .par_iter()
            .zip(&used)
            .enumerate()
            .filter(|(_, (p, &u))| u && !p.to_array().iter().all(|x| x.abs() <= MAX_COORDINATE))
            .map(|(i, (p, _))| (i, *p))
            .min_by_key(|&(i, _)| i);
        if let Some((i, p)) = bad {
            let arr = p.to_array();
            if let Some(&value) = arr.iter().find(|x| !x.is_finite()) {
                return Err(MeshError::NonFinite {
                    vertex: i + 1,
                    value,
                });
            }
            let value = arr
                .iter()
                .copied()
                .find(|x| x.abs() > MAX_COORDINATE)
                .unwrap_or(f64::NAN);
            return Err(MeshError::TooLarge {
                vertex: i + 1,
                value,
                max: MAX_COORDINATE,
            });
        }
        Ok((
            Mesh {
                positions: self.positions,
                triangles: self.triangles,
            },
            used,
        ))
    }
}

/// Which of `n` vertices the triangles use.
pub(super) fn used_vertices(n: usize, triangles: &[[u32; 3]]) -> Vec<bool> {
    let mut used = vec![false; n];
    for t in triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    used
}
