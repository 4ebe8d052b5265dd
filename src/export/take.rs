//! A take's output files: created before anything is simulated (so a bad path fails at
//! once), fed frame by frame, written at the end. `simulate --out` and the window's
//! *Export animation* both write through this.

use super::{glb, pc2, FileOrder, Frames};
use crate::files::io_message;
use crate::mesh::{vertex_normals, write_obj, Mesh};
use glam::{DVec3, Vec3};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The formats a take is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// glTF binary with a morph target per frame.
    Glb,
    /// PC2 point cache and its base OBJ beside it.
    Pc2,
    /// One OBJ per frame in a folder.
    Sequence,
}

impl Kind {
    /// The format a path asks for: `.glb`, `.pc2`, or a folder (a path ending in `/` or an
    /// existing folder). `None` for anything else.
    pub fn of(path: &Path) -> Option<Kind> {
        let text = path.to_string_lossy();
        if text.ends_with('/') || text.ends_with(std::path::MAIN_SEPARATOR) || path.is_dir() {
            return Some(Kind::Sequence);
        }
        match path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .as_deref()
        {
            Some("glb") => Some(Kind::Glb),
            Some("pc2") => Some(Kind::Pc2),
            _ => None,
        }
    }
}

/// The extensions a take is drawn into as a video (`render::video`, behind `gui`).
pub const VIDEO_EXTENSIONS: [&str; 4] = ["mp4", "webm", "mkv", "mov"];

/// True when `path` names a video by its extension ([`VIDEO_EXTENSIONS`]).
pub fn is_video(path: &Path) -> bool {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .is_some_and(|e| VIDEO_EXTENSIONS.contains(&e.as_str()))
}

/// How a take is written.
#[derive(Clone, Debug, Default)]
pub struct TakeOptions {
    /// `.glb` only: 16-bit positions and morph targets (`KHR_mesh_quantization`).
    pub quantize: bool,
    /// `.pc2` only: the file's vertex order (see [`FileOrder`]); `None` writes the welded
    /// mesh's order (the same for a file without duplicates).
    pub order: Option<FileOrder>,
}

/// A file that could not be written, and why.
#[derive(Debug, PartialEq, thiserror::Error)]
#[error("{path}: {message}")]
pub struct TakeError {
    /// The file.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

fn failed(path: &Path, message: impl std::fmt::Display) -> TakeError {
    TakeError {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// A take being written.
pub struct TakeFiles {
    kind: Kind,
    path: PathBuf,
    file: Option<std::fs::File>,
    base: Option<(PathBuf, std::fs::File)>,
    options: TakeOptions,
    frames: Frames,
    /// Base frames per second (OBJ headers give the time of each frame).
    fps: f64,
    written: usize,
}

impl TakeFiles {
    /// Creates the files for a take of `mesh` (its rest surface and normals are the base)
    /// at `path`: frames numbered from `first`, `fps` frames per second before `step`
    /// thins them.
    ///
    /// # Errors
    /// [`TakeError`] naming the file or folder that cannot be created (or the mesh when it
    /// has no normals: it was not validated).
    pub fn create(
        path: &Path,
        kind: Kind,
        mesh: &Mesh,
        options: TakeOptions,
        fps: f64,
        first: u64,
        step: u64,
    ) -> Result<TakeFiles, TakeError> {
        let normals = vertex_normals(mesh).map_err(|e| failed(path, e))?;
        let create = |p: &Path| {
            std::fs::File::create(p)
                .map_err(|e| failed(p, format!("cannot write: {}", io_message(&e))))
        };
        let (file, base) = match kind {
            Kind::Glb => (Some(create(path)?), None),
            Kind::Pc2 => {
                let base = path.with_extension("obj");
                let base_file = create(&base)?;
                (Some(create(path)?), Some((base, base_file)))
            }
            Kind::Sequence => {
                std::fs::create_dir_all(path).map_err(|e| {
                    failed(path, format!("cannot create folder: {}", io_message(&e)))
                })?;
                (None, None)
            }
        };
        Ok(TakeFiles {
            kind,
            path: path.to_path_buf(),
            file,
            base,
            options,
            frames: Frames {
                triangles: mesh.triangles.clone(),
                rest: mesh.positions.iter().map(|p| p.as_vec3()).collect(),
                normals: normals.iter().map(|n| n.as_vec3()).collect(),
                frames: Vec::new(),
                fps,
                first,
                step: step.max(1),
            },
            fps,
            written: 0,
        })
    }

    /// Adds frame `frame` (1-based): the welded mesh's positions. A sequence writes its
    /// OBJ now; the other formats keep the frame until [`TakeFiles::finish`].
    ///
    /// # Errors
    /// [`TakeError`] when a frame's OBJ cannot be written.
    pub fn add(&mut self, frame: u64, positions: Vec<Vec3>) -> Result<(), TakeError> {
        self.written += 1;
        if self.kind != Kind::Sequence {
            self.frames.frames.push(positions);
            return Ok(());
        }
        let path = self.path.join(format!("frame_{frame:05}.obj"));
        let points: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
        let header = format!("puppet: frame {frame}, t = {} s", frame as f64 / self.fps);
        let mut file = std::fs::File::create(&path)
            .map_err(|e| failed(&path, format!("cannot write: {}", io_message(&e))))?;
        write_obj(&mut file, &points, &self.frames.triangles, &header)
            .map_err(|e| failed(&path, format!("cannot write: {}", io_message(&e))))
    }

    /// Frames added so far.
    pub fn frames_added(&self) -> usize {
        self.written
    }

    /// Writes the `.glb` or the `.pc2` and its base OBJ; returns the bytes written.
    ///
    /// # Errors
    /// [`TakeError`] naming the file.
    pub fn finish(self) -> Result<u64, TakeError> {
        let bytes = match self.kind {
            Kind::Sequence => return Ok(0),
            Kind::Glb => glb::write_with(&self.frames, self.options.quantize)
                .map_err(|e| failed(&self.path, e))?,
            Kind::Pc2 => {
                let mut take = self.frames;
                // The base OBJ: the file's vertices and faces, or the welded mesh's.
                let (rest, triangles): (Vec<DVec3>, _) = match &self.options.order {
                    Some(order) => {
                        take.frames = take.frames.iter().map(|f| order.frame(f)).collect();
                        take.rest = order.positions.iter().map(|p| p.as_vec3()).collect();
                        (order.positions.clone(), &order.triangles)
                    }
                    None => (
                        take.rest.iter().map(|p| p.as_dvec3()).collect(),
                        &take.triangles,
                    ),
                };
                if let Some((base, mut file)) = self.base {
                    let mut text = Vec::new();
                    write_obj(
                        &mut text,
                        &rest,
                        triangles,
                        "puppet: the rest surface of the PC2 point cache beside it",
                    )
                    .and_then(|()| file.write_all(&text))
                    .and_then(|()| file.flush())
                    .map_err(|e| failed(&base, format!("cannot write: {}", io_message(&e))))?;
                }
                pc2::write(&take).map_err(|e| failed(&self.path, e))?
            }
        };
        let mut file = self.file.ok_or_else(|| failed(&self.path, "not open"))?;
        file.write_all(&bytes)
            .and_then(|()| file.flush())
            .map_err(|e| failed(&self.path, format!("cannot write: {}", io_message(&e))))?;
        Ok(bytes.len() as u64)
    }
}
