//! Keys and the panels' actions: opening meshes and rigs (in the background; the current
//! puppet stays until the new one is ready), saving, exporting, undo, framing.

use super::window::WindowState;
use crate::puppet::RigFile;
use crate::session::loader::Loader;
use crate::ui::Action;
use std::path::{Path, PathBuf};
use winit::keyboard::{Key, NamedKey};

impl WindowState {
    /// Starts loading a mesh (or the current one with a new rig) in the background; the
    /// current puppet stays until the new one is ready.
    pub fn start_loading(&mut self, path: Option<PathBuf>, rig_file: Option<RigFile>) {
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
            Some(p) => self.loader = Some(Loader::open(p, rig_file)),
            None => {
                if let Some(s) = &self.session {
                    let (mesh, name) = (s.puppet.mesh.clone(), s.name.clone());
                    self.loader = Some(Loader::build(mesh, name, rig_file));
                }
            }
        }
        self.panel.message = None;
        self.window.request_redraw();
    }

    /// A key went down.
    pub fn key(&mut self, key: &Key) {
        let ctrl = self.modifiers.control_key();
        let shift = self.modifiers.shift_key();
        match key {
            Key::Character(c) => match (c.to_lowercase().as_str(), ctrl) {
                ("f", false) => self.frame_model(),
                ("w", false) => self.panel.overlays.wireframe ^= true,
                ("r", false) => {
                    if let Some(s) = &mut self.session {
                        s.reset_pose();
                    }
                }
                ("z", true) if shift => self.redo(),
                ("z", true) => self.undo(),
                ("y", true) => self.redo(),
                _ => {}
            },
            Key::Named(NamedKey::Space) => {
                if let Some(s) = &mut self.session {
                    s.paused ^= true;
                    s.wake();
                }
            }
            Key::Named(NamedKey::Escape) => {
                if let Some(s) = &mut self.session {
                    s.cut_tool.active = false;
                    s.draft = None;
                    s.select(None, false);
                }
            }
            _ => {}
        }
        self.window.request_redraw();
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
        }
    }

    /// Carries out what a panel asked for; the outcome goes to the panel's message line.
    pub fn act(&mut self, action: Action) {
        let result: Result<String, String> = match action {
            Action::OpenMesh(path) => {
                self.start_loading(Some(PathBuf::from(path)), None);
                return;
            }
            Action::Frame => {
                self.frame_model();
                return;
            }
            Action::LoadRig(path) => match RigFile::load(Path::new(&path)) {
                Ok(rig_file) => {
                    let mesh = rig_file.mesh.clone();
                    self.start_loading(mesh, Some(rig_file));
                    return;
                }
                Err(e) => Err(format!("{path}: {e}")),
            },
            Action::SaveRig(path) => match self.session() {
                Some(s) => std::fs::write(&path, s.puppet.current_rig_file().to_toml(None))
                    .map(|_| format!("saved {path}"))
                    .map_err(|e| format!("{path}: cannot write: {e}")),
                None => return,
            },
            Action::ExportObj(path) => match self.session() {
                Some(s) => s
                    .puppet
                    .save_surface(Path::new(&path), "exported by puppet")
                    .map(|_| format!("exported {path}"))
                    .map_err(|e| format!("{path}: {e}")),
                None => return,
            },
        };
        self.panel.message = Some(match result {
            Ok(m) => (m, false),
            Err(m) => (m, true),
        });
    }
}
