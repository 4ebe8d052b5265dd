//! Loading a mesh and building its puppet on a background thread, with progress, so the
//! window stays responsive and the current puppet stays until the new one is ready. What
//! follows a load (suggested joints, an animation to play) happens here too, on the same
//! thread: the window only shows the session it gets and the message it says.

use super::Session;
use crate::anim::Animation;
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

/// What to do with a puppet once it is built, before anyone sees it.
#[derive(Debug, Default)]
pub struct AfterLoad {
    /// Replace the rig's cuts with the suggested joints ([`Session::suggest_joints`]); the
    /// session starts from them (nothing to undo).
    pub suggest: bool,
    /// Play this animation ([`Session::set_animation`]).
    pub animation: Option<Animation>,
    /// Play this clip of the mesh file's skin ([`Session::play_clip`]).
    pub clip: Option<String>,
}

/// A session on a puppet built by a [`Loader`].
pub struct Opened {
    /// The session, named after the file, with [`AfterLoad`] done.
    pub session: Box<Session>,
    /// The file's full path, when it came from a file.
    pub source: Option<PathBuf>,
    /// What reading the file did (repairs, riders) and how long each stage took.
    pub report: Option<LoadReport>,
    /// Seconds from the file to the puppet: reading (when the report says) and building.
    pub seconds: f64,
    /// What went wrong after the load (a suggestion or an animation that did not apply);
    /// the puppet opened all the same.
    pub problems: Vec<String>,
}

impl Opened {
    /// Does what `after` asks, keeping what fails as a problem.
    fn then(mut self, after: AfterLoad) -> Opened {
        if after.suggest {
            if let Err(e) = self.session.suggest_joints() {
                self.problems.push(e.to_string());
            }
            self.session.clear_history();
        }
        if let Some(animation) = after.animation {
            if let Err(e) = self.session.set_animation(animation) {
                self.problems.push(format!("animation: {e}"));
            }
        }
        if let Some(clip) = after.clip {
            if let Err(e) = self.session.play_clip(&clip) {
                self.problems.push(format!("clip: {e}"));
            }
        }
        self
    }

    /// The line to show: how long opening took and what reading the file repaired, or what
    /// went wrong after it (`true`: an error).
    pub fn message(&self) -> (String, bool) {
        if !self.problems.is_empty() {
            return (self.problems.join("; "), true);
        }
        let name = &self.session.name;
        let warnings = self
            .report
            .as_ref()
            .map(|r| r.warnings())
            .unwrap_or_default();
        let said = if warnings.is_empty() {
            format!("opened {name} in {:.1} s", self.seconds)
        } else {
            format!(
                "opened {name} in {:.1} s: {}",
                self.seconds,
                warnings.join("; ")
            )
        };
        (said, false)
    }
}

/// A finished load.
pub type Loaded = Result<Opened, LoadError>;

enum Message {
    Progress(String, f32),
    Done(Box<Loaded>),
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
    Done(Box<Loaded>),
}

impl Loader {
    /// Reads, repairs, validates and builds `path` (errors name the file as given), then
    /// does what `after` asks.
    pub fn open(
        path: PathBuf,
        rig_file: RigFile,
        options: LoadOptions,
        after: AfterLoad,
    ) -> Loader {
        Loader::spawn(after, move |progress| {
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
            let mut opened = build(mesh, Some(&report), given, rig_file, progress)?;
            opened.session.name = name;
            opened.session.repairs = report.marks.clone();
            opened.source = source;
            opened.seconds += report.seconds.iter().map(|s| s.1).sum::<f64>();
            opened.report = Some(report);
            Ok(opened)
        })
    }

    /// Builds the puppet of an already validated mesh named `name`, from `source`, then does
    /// what `after` asks; `report` says how the mesh was read, when it was.
    pub fn build(
        mesh: Mesh,
        name: String,
        source: Option<PathBuf>,
        report: Option<LoadReport>,
        rig_file: RigFile,
        after: AfterLoad,
    ) -> Loader {
        Loader::spawn(after, move |progress| {
            let mut opened = build(mesh, report.as_ref(), name, rig_file, progress)?;
            opened.source = source;
            if let Some(r) = &report {
                opened.seconds += r.total_seconds();
                opened.session.repairs = r.marks.clone();
            }
            opened.report = report;
            Ok(opened)
        })
    }

    fn spawn(
        after: AfterLoad,
        work: impl FnOnce(&(dyn Fn(&str, f64) + Sync)) -> Loaded + Send + 'static,
    ) -> Loader {
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let progress_tx = tx.clone();
            let progress = move |stage: &str, f: f64| {
                let _ = progress_tx.send(Message::Progress(stage.to_string(), f as f32));
            };
            let result = work(&progress).map(|opened| opened.then(after));
            let _ = tx.send(Message::Done(Box::new(result)));
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
                    return Status::Done(Box::new(Err(LoadError::Stopped)))
                }
            }
        }
    }
}

fn build(
    mesh: Mesh,
    report: Option<&LoadReport>,
    name: String,
    rig_file: RigFile,
    progress: &(dyn Fn(&str, f64) + Sync),
) -> Loaded {
    let start = std::time::Instant::now();
    match Puppet::build_loaded(mesh, report, rig_file, progress) {
        Ok(mut puppet) => Ok(Opened {
            // A skinned file without cuts in its rig opens with its skin's joints.
            session: {
                if puppet.joints.cuts().is_empty() && puppet.skin_joints().is_some() {
                    if let Err(e) = puppet.suggest_joints() {
                        log::warn!("{name}: the skin's joints: {e}");
                    }
                }
                Box::new(Session::new(puppet, name))
            },
            seconds: start.elapsed().as_secs_f64(),
            source: None,
            report: None,
            problems: Vec::new(),
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
                return *r;
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
        let err = wait(Loader::open(
            bad.clone(),
            RigFile::default(),
            options,
            AfterLoad::default(),
        ))
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
            AfterLoad::default(),
        ))
        .unwrap();
        assert_eq!(opened.session.name, "ball");
        assert_eq!(opened.session.puppet.joints.sections().len(), 1);
        let (said, error) = opened.message();
        assert!(said.starts_with("opened ball in ") && !error, "{said}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn after_a_load_the_joints_are_suggested_and_an_animation_that_fails_is_said() {
        let spot = include_bytes!("../../assets/spot.obj");
        let options = LoadOptions::default();
        let (mesh, _) =
            crate::mesh::parse(spot, mesh::Format::Obj, &options, crate::progress::silent())
                .unwrap();
        let mut expected = Puppet::build(mesh.clone(), RigFile::default(), &|_, _| {}).unwrap();
        let joints = expected.suggest_joints().unwrap();
        let animation = Animation::parse(
            "duration = 1.0\n[[track]]\nsection = \"no such section\"\nkey = [{ time = 0.0, axis = [1, 0, 0], angle = 0 }]\n",
            crate::files::Format::Toml,
        )
        .unwrap();
        let after = AfterLoad {
            suggest: true,
            animation: Some(animation),
            clip: None,
        };
        let opened = wait(Loader::build(
            mesh,
            "spot".into(),
            None,
            None,
            RigFile::default(),
            after,
        ))
        .unwrap();
        let s = &opened.session;
        assert_eq!(s.puppet.joints.cuts().len(), joints);
        assert_eq!(s.puppet.joints.cuts(), expected.joints.cuts());
        assert!(
            !s.can_undo(),
            "the suggestion is where the puppeteer starts"
        );
        assert!(s.playback.is_none(), "the animation did not bind");
        let (said, error) = opened.message();
        assert!(error && said.starts_with("animation: "), "{said}");
    }
}
