//! Loading a mesh and building its puppet on a background thread, with progress.

use crate::mesh::{self, Mesh};
use crate::scene::{Puppet, RigSpec};
use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver, TryRecvError};

enum Message {
    Progress(String, f32),
    Done(Result<(Box<Puppet>, String), String>),
}

/// A build in progress.
pub struct Loader {
    rx: Receiver<Message>,
    stage: (String, f32),
}

pub enum Status {
    Working(String, f32),
    Done(Result<(Box<Puppet>, String), String>),
}

impl Loader {
    /// Reads, validates and builds `path` (errors name the file).
    pub fn open(path: PathBuf, rig: RigSpec) -> Loader {
        Loader::spawn(move |progress| {
            let name = path.display().to_string();
            progress("reading", 0.0);
            let (mesh, report) = mesh::load_obj(&path).map_err(|e| format!("{name}: {e}"))?;
            for w in report.warnings() {
                log::warn!("{name}: {w}");
            }
            build(mesh, name, rig, progress)
        })
    }

    /// Builds the puppet of an already validated mesh.
    pub fn build(mesh: Mesh, name: String, rig: RigSpec) -> Loader {
        Loader::spawn(move |progress| build(mesh, name, rig, progress))
    }

    fn spawn(
        work: impl FnOnce(&(dyn Fn(&str, f64) + Sync)) -> Result<(Box<Puppet>, String), String>
            + Send
            + 'static,
    ) -> Loader {
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
                Err(TryRecvError::Disconnected) => {
                    return Status::Done(Err("the loading thread stopped unexpectedly".into()))
                }
            }
        }
    }
}

fn build(
    mesh: Mesh,
    name: String,
    rig: RigSpec,
    progress: &(dyn Fn(&str, f64) + Sync),
) -> Result<(Box<Puppet>, String), String> {
    let puppet = Puppet::build(mesh, rig, progress).map_err(|e| format!("{name}: {e}"))?;
    Ok((Box::new(puppet), name))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait(mut l: Loader) -> Result<(Box<Puppet>, String), String> {
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
        let err = wait(Loader::open(bad.clone(), RigSpec::default()))
            .err()
            .unwrap();
        assert!(err.starts_with(&bad.display().to_string()), "{err}");
        assert!(err.contains("boundary edges"), "{err}");
        let good = crate::mesh::shapes::icosphere(1.0, 2);
        let (p, name) = wait(Loader::build(good, "ball".into(), RigSpec::default())).unwrap();
        assert_eq!(name, "ball");
        assert_eq!(p.joints.sections().len(), 1);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
