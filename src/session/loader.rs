//! Loading a mesh and building its puppet on a background thread, with progress, so the
//! window stays responsive and the current puppet stays until the new one is ready.

use crate::mesh::{self, LoadOptions, LoadReport, Mesh, MeshError};
use crate::puppet::{BuildError, Puppet, RigFile};
use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver, TryRecvError};

/// Why loading failed; the message names the file first.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The mesh file could not be read or is not a usable mesh.
    #[error("{name}: {error}")]
    Mesh {
        /// The file as shown to the user.
        name: String,
        /// What is wrong.
        error: MeshError,
    },
    /// The skeleton, rig or joints could not be built.
    #[error("{name}: {error}")]
    Build {
        /// The file as shown to the user.
        name: String,
        /// What is wrong.
        error: BuildError,
    },
    /// The loading thread ended without an answer (it panicked).
    #[error("the loading thread stopped unexpectedly")]
    Stopped,
}

/// A puppet built by a [`Loader`].
pub struct Opened {
    /// The puppet.
    pub puppet: Box<Puppet>,
    /// The name to show: the file's name.
    pub name: String,
    /// The file's full path, when it came from a file.
    pub source: Option<PathBuf>,
    /// What reading the file did (repairs, riders) and how long each stage took.
    pub report: Option<LoadReport>,
    /// Seconds from the file to the puppet: reading (when the report says) and building.
    pub seconds: f64,
}

/// A finished load.
pub type Loaded = Result<Opened, LoadError>;

enum Message {
    Progress(String, f32),
    Done(Loaded),
}

/// A build in progress.
pub struct Loader {
    rx: Receiver<Message>,
    stage: (String, f32),
}

/// Where a [`Loader`] is.
pub enum Status {
    /// Still working: the stage and the fraction of it done.
    Working(String, f32),
    /// Finished.
    Done(Loaded),
}

impl Loader {
    /// Reads, repairs, validates and builds `path` (errors name the file as given).
    pub fn open(path: PathBuf, rig_file: RigFile, options: LoadOptions) -> Loader {
        Loader::spawn(move |progress| {
            let given = path.display().to_string();
            let (mesh, report) =
                mesh::load_with(&path, &options, progress).map_err(|error| LoadError::Mesh {
                    name: given.clone(),
                    error,
                })?;
            for w in report.warnings() {
                log::warn!("{given}: {w}");
            }
            let name = path
                .file_name()
                .map_or(given.clone(), |n| n.to_string_lossy().into_owned());
            let source = Some(path.canonicalize().unwrap_or(path));
            let mut opened = build(mesh, given, rig_file, progress)?;
            opened.name = name;
            opened.source = source;
            opened.seconds += report.seconds.iter().map(|s| s.1).sum::<f64>();
            opened.report = Some(report);
            Ok(opened)
        })
    }

    /// Builds the puppet of an already validated mesh named `name`, from `source`; `report`
    /// says how the mesh was read, when it was.
    pub fn build(
        mesh: Mesh,
        name: String,
        source: Option<PathBuf>,
        report: Option<LoadReport>,
        rig_file: RigFile,
    ) -> Loader {
        Loader::spawn(move |progress| {
            let mut opened = build(mesh, name, rig_file, progress)?;
            opened.source = source;
            if let Some(r) = &report {
                opened.seconds += r.total_seconds();
            }
            opened.report = report;
            Ok(opened)
        })
    }

    fn spawn(work: impl FnOnce(&(dyn Fn(&str, f64) + Sync)) -> Loaded + Send + 'static) -> Loader {
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let progress_tx = tx.clone();
            let progress = move |stage: &str, f: f64| {
                let _ = progress_tx.send(Message::Progress(stage.to_string(), f as f32));
            };
            let result = work(&progress);
            let _ = tx.send(Message::Done(result));
        });
        Loader {
            rx,
            stage: ("starting".into(), 0.0),
        }
    }

    /// Drains messages: the latest progress, or the result.
    pub fn poll(&mut self) -> Status {
        loop {
            match self.rx.try_recv() {
                Ok(Message::Progress(s, f)) => self.stage = (s, f),
                Ok(Message::Done(r)) => return Status::Done(r),
                Err(TryRecvError::Empty) => {
                    return Status::Working(self.stage.0.clone(), self.stage.1)
                }
                Err(TryRecvError::Disconnected) => return Status::Done(Err(LoadError::Stopped)),
            }
        }
    }
}

fn build(
    mesh: Mesh,
    name: String,
    rig_file: RigFile,
    progress: &(dyn Fn(&str, f64) + Sync),
) -> Loaded {
    let start = std::time::Instant::now();
    match Puppet::build(mesh, rig_file, progress) {
        Ok(puppet) => Ok(Opened {
            puppet: Box::new(puppet),
            name,
            source: None,
            report: None,
            seconds: start.elapsed().as_secs_f64(),
        }),
        Err(error) => Err(LoadError::Build { name, error }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait(mut l: Loader) -> Loaded {
        loop {
            if let Status::Done(r) = l.poll() {
                return r;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
    }

    #[test]
    fn a_bad_file_fails_with_its_name_and_a_good_one_builds() {
        let dir = std::env::temp_dir().join(format!("puppet-loader-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bad = dir.join("open.obj");
        std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let options = LoadOptions { fill_holes: 0 };
        let err = wait(Loader::open(bad.clone(), RigFile::default(), options))
            .err()
            .unwrap()
            .to_string();
        assert!(err.starts_with(&bad.display().to_string()), "{err}");
        assert!(err.contains("boundary edges"), "{err}");
        let good = crate::mesh::shapes::icosphere(1.0, 2);
        let opened = wait(Loader::build(
            good,
            "ball".into(),
            None,
            None,
            RigFile::default(),
        ))
        .unwrap();
        assert_eq!(opened.name, "ball");
        assert_eq!(opened.puppet.joints.sections().len(), 1);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
