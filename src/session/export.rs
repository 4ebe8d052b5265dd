//! *Export animation*: the loaded animation baked from rest on a copy of the puppet, on a
//! thread of its own (the window keeps playing), with its progress and a cancel. It plays
//! through [`crate::puppet::bake`] like `simulate --out`, so the window's export and
//! `simulate`'s give the same frames.

use super::Session;
use crate::anim::Bound;
use crate::export::{FileOrder, Kind, TakeFiles, TakeOptions};
use crate::puppet::bake::{self, BakeError, FrameRange};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

/// The frames and format an export writes (the panel edits them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExportSettings {
    /// Frames per second.
    pub fps: f64,
    /// First and last frame (1-based; `last` 0: to the end of the animation).
    pub first: u64,
    /// Last frame; 0 is the animation's end.
    pub last: u64,
    /// Every `step`th frame.
    pub step: u64,
    /// `.glb`: 16-bit positions and targets.
    pub quantize: bool,
}

impl Default for ExportSettings {
    fn default() -> Self {
        ExportSettings {
            fps: 30.0,
            first: 1,
            last: 0,
            step: 1,
            quantize: false,
        }
    }
}

/// An export running on its own thread.
pub struct ExportJob {
    /// Where it writes.
    pub path: PathBuf,
    /// Frames it keeps.
    pub frames: u64,
    done: Arc<AtomicU64>,
    cancel: Arc<AtomicBool>,
    thread: JoinHandle<Result<String, String>>,
}

/// Progress is kept in millionths.
const SCALE: f64 = 1e6;

/// Writes an export's frames from the session baking them (a video draws each as the
/// window does: `render::video::TakeVideo`); the kinds [`Kind`] names write through
/// [`Session::start_export`] instead.
pub trait TakeWriter: Send {
    /// Adds the next frame: `session`'s puppet as it is now.
    ///
    /// # Errors
    /// A message when the frame cannot be written.
    fn add(&mut self, session: &Session) -> Result<(), String>;

    /// Ends the file once every frame is in: what the export says (`exported 9 frames to
    /// take.mp4`). A writer dropped without it (a cancel, a failed frame) leaves no file.
    ///
    /// # Errors
    /// A message when the file cannot be finished.
    fn finish(self: Box<Self>) -> Result<String, String>;
}

impl AsMut<crate::Puppet> for Session {
    fn as_mut(&mut self) -> &mut crate::Puppet {
        &mut self.puppet
    }
}

impl ExportJob {
    /// The fraction done, 0..1.
    pub fn progress(&self) -> f64 {
        self.done.load(Ordering::Relaxed) as f64 / SCALE
    }
}

impl Session {
    /// The frames an export with these settings plays, for the loaded animation.
    pub fn export_range(&self) -> Option<FrameRange> {
        let p = self.playback.as_ref()?;
        let s = &self.export_settings;
        let whole = FrameRange::of_duration(p.animation.duration, s.fps);
        Some(FrameRange {
            first: s.first,
            last: if s.last == 0 { whole.last } else { s.last },
            step: s.step,
            fps: s.fps,
        })
    }

    /// Starts exporting the loaded animation to `path` (`.glb`, `.pc2` or a folder);
    /// `source` is the mesh file (a point cache follows its vertex order). The files are
    /// created now, so a bad path is an error at once; the take being recorded and what
    /// plays are not touched.
    pub fn start_export(&mut self, path: &Path, source: Option<&Path>) -> Result<String, String> {
        let name = path.display().to_string();
        let (range, bound) = self.export_plan()?;
        let Some(kind) = Kind::of(path) else {
            return Err(format!(
                "{name}: choose a .glb, a .pc2, a video (.mp4, .webm, .mkv, .mov) or a folder (ending in /) to export to"
            ));
        };
        let order = match (kind, source) {
            (Kind::Pc2, Some(src)) => FileOrder::of_file(src, &self.puppet.mesh)
                .map_err(|e| format!("{}: {e}", src.display()))?,
            _ => None,
        };
        let options = TakeOptions {
            quantize: self.export_settings.quantize,
            order,
        };
        let mut take = TakeFiles::create(
            path,
            kind,
            &self.puppet.mesh,
            options,
            range.fps,
            range.first,
            range.step,
        )
        .map_err(|e| e.to_string())?;
        let mut puppet = self.puppet.clone();
        let target = path.to_path_buf();
        Ok(self.spawn_export(path, range.count(), move |go| {
            let mut sink = |frame: u64, p: &crate::Puppet| {
                let x = p.sim.positions();
                take.add(frame, (0..x.len()).map(|i| x.get(i)).collect())
                    .map_err(|e| e.to_string())
            };
            let shown = target.display().to_string();
            match bake::bake(&mut puppet, Some(bound), &range, &mut sink, go) {
                Ok(()) => {
                    let frames = take.frames_added();
                    let bytes = take.finish().map_err(|e| e.to_string())?;
                    Ok(if bytes > 0 {
                        format!(
                            "exported {frames} frames to {shown} ({:.1} MB)",
                            bytes as f64 / 1e6
                        )
                    } else {
                        format!("exported {frames} frames to {shown}")
                    })
                }
                Err(BakeError::Cancelled) => {
                    drop(take);
                    if kind != Kind::Sequence {
                        let _ = std::fs::remove_file(&target);
                        if kind == Kind::Pc2 {
                            let _ = std::fs::remove_file(target.with_extension("obj"));
                        }
                    }
                    Err(format!("export to {shown} cancelled"))
                }
                Err(e) => Err(e.to_string()),
            }
        }))
    }

    /// Starts exporting the loaded animation to `path` through the writer `make` gives for
    /// the frames' rate (a video), on a copy of this session baking it from rest: the
    /// window's camera and look are the writer's, the frames those of
    /// [`Session::start_export`]. The writer is made once the export can start (none
    /// running, an animation loaded, a valid range); the take being recorded and what
    /// plays are not touched.
    pub fn start_export_with(
        &mut self,
        path: &Path,
        make: impl FnOnce(f64) -> Result<Box<dyn TakeWriter>, String>,
    ) -> Result<String, String> {
        let (range, bound) = self.export_plan()?;
        let mut writer = make(range.fps / range.step as f64)?;
        let mut copy = Session::new(self.puppet.clone(), self.name.clone());
        let shown = path.display().to_string();
        Ok(self.spawn_export(path, range.count(), move |go| {
            // Each frame drawn anew: the view uploads what the session's revision says moved.
            let mut sink = |_: u64, s: &mut Session| {
                s.wake();
                writer.add(s)
            };
            match bake::bake_in(&mut copy, Some(bound), &range, &mut sink, go) {
                Ok(()) => writer.finish(),
                Err(BakeError::Cancelled) => Err(format!("export to {shown} cancelled")),
                Err(e) => Err(e.to_string()),
            }
        }))
    }

    /// What an export plays, once none is running: its frames and the loaded animation
    /// bound to the joints.
    fn export_plan(&self) -> Result<(FrameRange, Bound), String> {
        if self.export.is_some() {
            return Err("an export is running (cancel it first)".into());
        }
        let Some(playback) = &self.playback else {
            return Err("no animation to export: open or record one first".into());
        };
        let range = self.export_range().ok_or("no animation")?;
        range.check().map_err(|e| format!("export: {e}"))?;
        let bound = playback
            .animation
            .bind(&self.puppet.joints)
            .map_err(|e| e.to_string())?;
        Ok((range, bound))
    }

    /// Runs `work` on a thread of its own as the export to `path` of `frames` frames:
    /// `work` bakes with the `go` it is given (the progress bar's fraction, and false once
    /// the puppeteer cancels) and says what it wrote.
    fn spawn_export(
        &mut self,
        path: &Path,
        frames: u64,
        work: impl FnOnce(&mut dyn FnMut(f64) -> bool) -> Result<String, String> + Send + 'static,
    ) -> String {
        let done = Arc::new(AtomicU64::new(0));
        let cancel = Arc::new(AtomicBool::new(false));
        let (d, c) = (done.clone(), cancel.clone());
        let thread = std::thread::spawn(move || {
            work(&mut |f: f64| {
                d.store((f * SCALE) as u64, Ordering::Relaxed);
                !c.load(Ordering::Relaxed)
            })
        });
        self.export = Some(ExportJob {
            path: path.to_path_buf(),
            frames,
            done,
            cancel,
            thread,
        });
        format!("exporting {frames} frames to {}", path.display())
    }

    /// The running export, if any.
    pub fn export_job(&self) -> Option<&ExportJob> {
        self.export.as_ref()
    }

    /// Asks the running export to stop (its partial files are removed).
    pub fn cancel_export(&mut self) {
        if let Some(job) = &self.export {
            job.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// What the export said once it ended (`None` while it runs or when there is none).
    pub fn poll_export(&mut self) -> Option<Result<String, String>> {
        let job = self.export.as_ref()?;
        if !job.thread.is_finished() {
            return None;
        }
        self.wait_export()
    }

    /// Waits for the running export to end and returns what it said.
    pub fn wait_export(&mut self) -> Option<Result<String, String>> {
        let job = self.export.take()?;
        Some(
            job.thread
                .join()
                .unwrap_or_else(|_| Err("the export failed (please report this)".into())),
        )
    }
}
