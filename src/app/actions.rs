//! Keys and the panels' actions: opening meshes and rigs (in the background; the current
//! puppet stays until the new one is ready), saving, exporting, undo, framing, suggesting
//! joints.

use super::dialog::{self, Dialog};
use super::WindowState;
use crate::puppet::RigFile;
use crate::session::loader::{AfterLoad, Loader};
use crate::ui::{Action, FilePurpose};
use std::path::{Path, PathBuf};
use winit::keyboard::{Key, NamedKey};

/// A video exported from the window is this many pixels (`simulate --video-size`'s
/// default).
const VIDEO_SIZE: (u32, u32) = (1280, 720);

/// What a key asks of the event loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeyOutcome {
    /// Nothing more.
    Handled,
    /// Close the window (Ctrl+Q).
    Quit,
}

impl WindowState {
    /// Starts loading a mesh (or the current one with a new rig) in the background; the
    /// current puppet stays until the new one is ready. A mesh opened without a rig opens
    /// ready to play: with its suggested joints (a skinned file's own), as the embedded cow
    /// does.
    pub fn start_loading(&mut self, path: Option<PathBuf>, rig_file: Option<RigFile>) {
        let after = AfterLoad {
            suggest: rig_file.is_none(),
            ..AfterLoad::default()
        };
        let rig_file = rig_file.unwrap_or_else(|| {
            let mut rig_file = self
                .session
                .as_ref()
                .map(|s| s.puppet.current_rig_file())
                .unwrap_or_default();
            rig_file.cuts.clear();
            rig_file.root = crate::joints::ROOT.into();
            rig_file
        });
        match path {
            Some(p) => {
                self.settings.opened(&p);
                self.panel.recent = self.settings.recent.clone();
                self.loader = Some(Loader::open(p, rig_file, self.load, after));
            }
            None => {
                if let Some(s) = &self.session {
                    let (mesh, name) = (s.puppet.mesh.clone(), s.name.clone());
                    let source = self.panel.source.clone();
                    self.loader = Some(Loader::build(
                        mesh,
                        name,
                        source,
                        None,
                        rig_file,
                        AfterLoad::default(),
                    ));
                }
            }
        }
        self.panel.message = None;
        self.window.request_redraw();
    }

    /// A key went down.
    pub fn key(&mut self, key: &Key) -> KeyOutcome {
        let ctrl = self.modifiers.control_key();
        let shift = self.modifiers.shift_key();
        match key {
            Key::Character(c) => match (c.to_lowercase().as_str(), ctrl) {
                ("q", true) => return KeyOutcome::Quit,
                ("o", true) => self.act(Action::Browse(FilePurpose::OpenMesh)),
                ("f", false) => self.frame_model(),
                ("w", false) => self.panel.overlays.wireframe ^= true,
                ("p", false) => {
                    if let Some(s) = &mut self.session {
                        s.set_move_pivots(!s.cut_tool.move_pivots);
                    }
                }
                ("c", false) => {
                    if let Some(s) = &mut self.session {
                        s.set_cut_tool(!s.cut_tool.active);
                    }
                }
                ("b", false) => {
                    if let Some(s) = &mut self.session {
                        s.toggle_brush();
                    }
                }
                ("l", false) => self.toggle_learn(),
                ("r", false) => {
                    if let Some(s) = &mut self.session {
                        s.reset_pose();
                    }
                }
                ("r", true) => {
                    if let Some(s) = &mut self.session {
                        if s.is_recording() {
                            let said = s.stop_recording();
                            s.recorder.said = Some(said.clone().unwrap_or_else(|e| e));
                            self.panel.message = Some(match said {
                                Ok(m) => (m, false),
                                Err(m) => (m, true),
                            });
                        } else {
                            s.start_recording();
                        }
                    }
                }
                ("z", true) if shift => self.redo(),
                ("z", true) => self.undo(),
                ("y", true) => self.redo(),
                _ => {}
            },
            Key::Named(NamedKey::Space) => {
                if let Some(s) = &mut self.session {
                    s.toggle_pause();
                }
            }
            Key::Named(
                key @ (NamedKey::ArrowLeft | NamedKey::ArrowRight | NamedKey::Home | NamedKey::End),
            ) => {
                if let Some(s) = &mut self.session {
                    if let Some((t, duration)) = s.playback_time() {
                        // A frame at the timeline's rate (the export's).
                        let frame = 1.0 / s.export_settings.fps.clamp(1.0, 240.0);
                        match key {
                            NamedKey::ArrowLeft => s.scrub(t - frame),
                            NamedKey::ArrowRight => s.scrub(t + frame),
                            NamedKey::Home => {
                                s.restart();
                                if s.is_playing() {
                                    s.toggle_play();
                                }
                            }
                            _ => s.scrub(duration),
                        }
                    }
                }
            }
            Key::Named(NamedKey::Escape) => {
                if let Some(s) = &mut self.session {
                    s.escape();
                }
            }
            _ => {}
        }
        self.window.request_redraw();
        KeyOutcome::Handled
    }

    fn undo(&mut self) {
        if let Some(s) = &mut self.session {
            s.undo();
        }
    }

    fn redo(&mut self) {
        if let Some(s) = &mut self.session {
            s.redo();
        }
    }

    fn frame_model(&mut self) {
        if let Some(s) = &self.session {
            let (lo, hi) = s.puppet.mesh.bounds();
            self.camera.frame(lo.as_vec3(), hi.as_vec3());
            self.camera.up = s.puppet.up().as_vec3();
        }
    }

    /// Carries out what a panel asked for; the outcome goes to the panel's message line.
    pub fn act(&mut self, action: Action) {
        match action {
            Action::Frame => self.frame_model(),
            Action::SuggestJoints => {
                if let Some(s) = &mut self.session {
                    let message = match s.suggest_joints() {
                        Ok(0) => ("no joints found on this shape".to_string(), false),
                        Ok(n) => (format!("suggested {n} joints"), false),
                        Err(e) => (e.to_string(), true),
                    };
                    self.panel.message = Some(message);
                }
            }
            Action::Browse(purpose) => {
                if !dialog::available() {
                    self.panel.message = Some((
                        "no file dialog on this system (install zenity or an XDG desktop portal): type the path under \"Type a path\", pick a recent file, or drop the file on the window".into(),
                        true,
                    ));
                    return;
                }
                let dir = self
                    .panel
                    .source
                    .as_deref()
                    .and_then(Path::parent)
                    .map(Path::to_path_buf);
                self.dialog = Some(Dialog::show(purpose, dir));
            }
            Action::File(purpose, path) => self.use_file(purpose, path),
            Action::Learn => self.toggle_learn(),
            Action::Calibrate => {
                if let Some(live) = &mut self.live {
                    live.start_calibrating();
                }
            }
            Action::CalibrateDone(keep) => {
                if let Some(said) = self.live.as_mut().and_then(|l| l.finish_calibrating(keep)) {
                    self.panel.message = Some((said, false));
                }
            }
        }
        self.window.request_redraw();
    }

    /// Starts or stops learning controls (starting the live input, with no controls yet,
    /// where there is none).
    fn toggle_learn(&mut self) {
        let Some(s) = &mut self.session else {
            return;
        };
        let live = self.live.get_or_insert_with(|| {
            super::live::Live::start(
                super::LiveOptions {
                    file: crate::controls::ControlsFile::default(),
                    socket: None,
                },
                self.proxy.clone(),
            )
        });
        self.panel.message = Some(live.toggle_learn(s));
        self.panel.live = Some(live.counts());
    }

    /// Uses a controls file loaded from the panel: a bad one is a line in the panel and
    /// the controls in use stay.
    fn load_controls(&mut self, path: &Path) -> Result<String, String> {
        let shown = crate::ui::file_name(path);
        let file =
            crate::controls::ControlsFile::load(path).map_err(|e| format!("{shown}: {e}"))?;
        let n = file.controls.len();
        let osc = file
            .controls
            .iter()
            .any(|c| matches!(c.source, crate::controls::Source::Osc { .. }));
        let live = match &mut self.live {
            Some(live) => {
                live.set_file(file);
                live
            }
            None => self.live.insert(super::live::Live::start(
                super::LiveOptions { file, socket: None },
                self.proxy.clone(),
            )),
        };
        let warning = if osc { live.ensure_osc() } else { None };
        self.panel.live = Some(live.counts());
        match warning {
            Some(w) => Err(format!("loaded {shown} ({n} controls); {w}")),
            None => Ok(format!("loaded {shown}: {n} controls")),
        }
    }

    /// What a file is for, done: open, load, save or export.
    pub fn use_file(&mut self, purpose: FilePurpose, path: PathBuf) {
        let shown = crate::ui::file_name(&path);
        let result: Result<String, String> = match purpose {
            FilePurpose::OpenMesh => {
                self.start_loading(Some(path), None);
                return;
            }
            FilePurpose::LoadRig => match RigFile::load(&path) {
                Ok(rig_file) => {
                    self.settings.opened(&path);
                    self.panel.recent = self.settings.recent.clone();
                    let mesh = rig_file.mesh.clone();
                    self.start_loading(mesh, Some(rig_file));
                    return;
                }
                Err(e) => Err(format!("{shown}: {e}")),
            },
            // The mesh it was opened from, written relative to the rig file.
            FilePurpose::SaveRig => match self.session() {
                Some(s) => std::fs::write(&path, {
                    let mut rig = s.puppet.current_rig_file();
                    rig.mesh = self.panel.source.clone();
                    rig.text_for(&path)
                })
                .map(|_| format!("saved {shown}"))
                .map_err(|e| format!("{shown}: cannot write: {}", crate::files::io_message(&e))),
                None => return,
            },
            FilePurpose::OpenAnimation => match &mut self.session {
                Some(s) => s.open_animation(&path),
                None => return,
            },
            FilePurpose::ExportAnimation => {
                let source = self.panel.source.clone();
                let (camera, look) = (self.camera, self.panel.overlays);
                match &mut self.session {
                    // A video draws what the window shows: its camera and look.
                    Some(s) if crate::export::is_video(&path) => {
                        s.start_export_with(&path, |fps| {
                            crate::render::video::TakeVideo::create(
                                &path,
                                VIDEO_SIZE,
                                look,
                                Some(camera),
                                fps,
                            )
                            .map(|video| Box::new(video) as Box<dyn crate::session::TakeWriter>)
                            .map_err(|e| e.to_string())
                        })
                    }
                    Some(s) => s.start_export(&path, source.as_deref()),
                    None => return,
                }
            }
            FilePurpose::SaveAnimation => match self.session() {
                Some(s) => s.save_animation(&path),
                None => return,
            },
            FilePurpose::LoadControls => self.load_controls(&path),
            FilePurpose::SaveControls => match &self.live {
                Some(live) => live
                    .file()
                    .save(&path)
                    .map(|_| format!("saved {shown}"))
                    .map_err(|e| format!("{shown}: cannot write: {e}")),
                None => Err("no controls to save yet: learn some, or load a file".into()),
            },
            FilePurpose::ExportSurface => match self.session() {
                Some(s) => s
                    .puppet
                    .save_surface(&path, "exported by puppet")
                    .map(|_| format!("exported {shown}"))
                    .map_err(|e| format!("{shown}: {e}")),
                None => return,
            },
        };
        self.panel.message = Some(match result {
            Ok(m) => (m, false),
            Err(m) => (m, true),
        });
    }
}
