//! The system's file dialog (rfd: an XDG desktop portal, or zenity), on a thread of its
//! own so the window keeps drawing. Where there is neither, the panel's path field, the
//! recent files and dropping a file on the window do the same.

use crate::ui::FilePurpose;
use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver, TryRecvError};

/// A dialog being shown.
pub struct Dialog {
    /// What the file is for.
    pub purpose: FilePurpose,
    rx: Receiver<Option<PathBuf>>,
}

/// Is there a dialog backend at all (a D-Bus session for the portal, or zenity)?
pub fn available() -> bool {
    let zenity = std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join("zenity").is_file()));
    zenity || std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some()
}

impl Dialog {
    /// Shows the dialog for `purpose`, starting in `dir`.
    pub fn show(purpose: FilePurpose, dir: Option<PathBuf>) -> Dialog {
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut d = rfd::FileDialog::new();
            if let Some(dir) = dir {
                d = d.set_directory(dir);
            }
            let picked = match purpose {
                FilePurpose::OpenMesh => d
                    .set_title("Open a mesh")
                    .add_filter(
                        "meshes",
                        &[
                            "obj", "ply", "stl", "glb", "gltf", "OBJ", "PLY", "STL", "GLB", "GLTF",
                        ],
                    )
                    .pick_file(),
                FilePurpose::LoadRig => d
                    .set_title("Load a rig")
                    .add_filter("rig files", &["toml", "json"])
                    .pick_file(),
                FilePurpose::SaveRig => d
                    .set_title("Save the rig")
                    .add_filter("rig files", &["toml", "json"])
                    .set_file_name("puppet.rig.toml")
                    .save_file(),
                FilePurpose::ExportSurface => d
                    .set_title("Export the surface")
                    .add_filter("OBJ", &["obj"])
                    .set_file_name("puppet.obj")
                    .save_file(),
                FilePurpose::OpenAnimation => d
                    .set_title("Open an animation")
                    .add_filter("animation files", &["toml", "json"])
                    .pick_file(),
                FilePurpose::ExportAnimation => d
                    .set_title("Export the animation")
                    .add_filter("glTF binary (shape keys)", &["glb"])
                    .add_filter("PC2 point cache", &["pc2"])
                    .add_filter("video (ffmpeg)", &crate::export::VIDEO_EXTENSIONS)
                    .set_file_name("take.glb")
                    .save_file(),
                FilePurpose::SaveAnimation => d
                    .set_title("Save the animation")
                    .add_filter("animation files", &["toml", "json"])
                    .set_file_name("puppet.anim.toml")
                    .save_file(),
                FilePurpose::LoadControls => d
                    .set_title("Load controls")
                    .add_filter("controls files", &["toml"])
                    .pick_file(),
                FilePurpose::SaveControls => d
                    .set_title("Save the controls")
                    .add_filter("controls files", &["toml"])
                    .set_file_name("controls.toml")
                    .save_file(),
            };
            let _ = tx.send(picked);
        });
        Dialog { purpose, rx }
    }

    /// The answer once there is one: `Some(None)` when it was cancelled.
    pub fn poll(&mut self) -> Option<Option<PathBuf>> {
        match self.rx.try_recv() {
            Ok(answer) => Some(answer),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(None),
        }
    }
}
