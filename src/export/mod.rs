//! Taking a performance to other tools: a sequence of simulated surfaces (a **take**'s
//! frames) written as glTF binary with morph targets ([`glb`]), as a PC2 point cache
//! ([`pc2`]), or as one OBJ per frame.
//!
//! The `.glb` and the OBJ sequence hold the welded mesh (the file's vertex order for a
//! file without duplicate vertices: welding keeps the earliest of a group); the PC2 point
//! cache can be written in the file's own vertex order ([`FileOrder`]), which is what
//! Blender's Mesh Cache modifier needs on the mesh the user imported. [`TakeFiles`]
//! creates the files before a take is simulated and writes them at its end.
//!
//! Files: `glb`, `pc2` (the formats), `order` (the file's vertex order), `take` (a take's
//! output files, fed frame by frame).

pub mod glb;
mod order;
pub mod pc2;
mod take;

pub use order::{FileOrder, FILE_ORDER_TOLERANCE};
pub use take::{is_video, Kind, TakeError, TakeFiles, TakeOptions, VIDEO_EXTENSIONS};

use glam::Vec3;

/// The frames of a take: the surface at each exported frame, on one mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frames {
    /// The mesh's triangles.
    pub triangles: Vec<[u32; 3]>,
    /// The rest surface (the base of morph targets and of the PC2's OBJ).
    pub rest: Vec<Vec3>,
    /// Unit vertex normals of the rest surface.
    pub normals: Vec<Vec3>,
    /// Per exported frame, every vertex's position.
    pub frames: Vec<Vec<Vec3>>,
    /// The take's frames per second: frame `k` is the state at `k / fps` s.
    pub fps: f64,
    /// The number of the first exported frame (1-based, as `simulate` counts).
    pub first: u64,
    /// Frames between two exported ones (1: every frame).
    pub step: u64,
}

/// Why a take could not be exported.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// Nothing to export.
    #[error("no frames to export")]
    Empty,
    /// A frame with another vertex count than the mesh, or a non-finite position.
    #[error("frame {0} does not fit the mesh (vertex count or a non-finite position)")]
    BadFrame(usize),
    /// The file would pass a format's size limit.
    #[error("{0}")]
    TooLarge(String),
    /// The glTF JSON could not be written.
    #[error("glTF: {0}")]
    Gltf(String),
}

impl Frames {
    /// The frame number of exported frame `j` (0-based): `first + j × step`.
    pub fn number(&self, j: usize) -> u64 {
        self.first + j as u64 * self.step.max(1)
    }

    /// The animation time of exported frame `j`, in seconds: its number over the frame
    /// rate (the state it holds; 30 frames per second where the rate is not a positive
    /// number).
    pub fn time(&self, j: usize) -> f64 {
        let fps = if self.fps.is_finite() && self.fps > 0.0 {
            self.fps
        } else {
            30.0
        };
        self.number(j) as f64 / fps
    }

    /// Checks that every frame fits the mesh.
    pub fn check(&self) -> Result<(), ExportError> {
        if self.frames.is_empty() || self.rest.is_empty() {
            return Err(ExportError::Empty);
        }
        for (k, f) in self.frames.iter().enumerate() {
            if f.len() != self.rest.len() || !f.iter().all(|p| p.is_finite()) {
                return Err(ExportError::BadFrame(k));
            }
        }
        Ok(())
    }
}
