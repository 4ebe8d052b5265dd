//! A take rendered to a video: frames drawn offscreen ([`super::render_image`]) and piped
//! into `ffmpeg` when it is installed (the Debian package), else written as numbered PNG
//! files in a folder beside where the video would have gone, with the `ffmpeg` line that
//! makes the video from them. `ffmpeg` writes beside the video (`take.partial.mp4`) and the
//! file takes the video's name once it is finished, so a video that is not finished (an
//! error, a cancel) leaves no file behind and a video already there stays until then.

use super::{Gpu, Image, SceneRenderer};
use crate::session::{Camera, Overlays, Session, TakeWriter};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// Why a video could not be written: the file and the problem.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct VideoError {
    /// The file or folder.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

impl VideoError {
    fn new(path: &Path, message: impl Into<String>) -> VideoError {
        VideoError {
            path: path.display().to_string(),
            message: message.into(),
        }
    }
}

/// Where the frames go.
enum Sink {
    /// `ffmpeg` encoding what comes on its standard input into the video.
    Ffmpeg(Child),
    /// Numbered PNG files in a folder.
    Frames(PathBuf),
}

/// What a finished video is.
#[derive(Clone, Debug, PartialEq)]
pub enum Written {
    /// The video file, encoded by `ffmpeg`.
    Video(PathBuf),
    /// No `ffmpeg`: the frames as PNG files in this folder, and the command that makes
    /// the video from them.
    Frames {
        /// The folder of `frame_00001.png`, …
        dir: PathBuf,
        /// The `ffmpeg` line that makes the video from them.
        command: String,
    },
}

/// A video being written, frame by frame (see the module docs).
pub struct Video {
    path: PathBuf,
    /// Where `ffmpeg` writes until the video is finished.
    partial: PathBuf,
    sink: Option<Sink>,
    width: u32,
    height: u32,
    fps: f64,
    frames: usize,
}

/// The `ffmpeg` to run: `$PUPPET_FFMPEG` when set (empty: none, as if not installed),
/// else `ffmpeg` if it runs.
fn ffmpeg() -> Option<PathBuf> {
    let program = match std::env::var_os("PUPPET_FFMPEG") {
        Some(p) if p.is_empty() => return None,
        Some(p) => PathBuf::from(p),
        None => PathBuf::from("ffmpeg"),
    };
    let runs = Command::new(&program)
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    runs.then_some(program)
}

/// Where `ffmpeg` writes `path` until it is finished: `take.mp4` → `take.partial.mp4`.
fn partial_path(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = path
        .extension()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!("{stem}.partial.{ext}"))
}

/// The folder the frames go to when there is no `ffmpeg`: `take.mp4` → `take-frames`.
pub fn frames_dir(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "take".into());
    path.with_file_name(format!("{stem}-frames"))
}

impl Video {
    /// Starts a video of `width × height` pixels (both even) at `fps` frames a second at
    /// `path`: `ffmpeg` if it runs, else a folder of PNG frames ([`frames_dir`]).
    pub fn create(path: &Path, width: u32, height: u32, fps: f64) -> Result<Video, VideoError> {
        if width == 0 || height == 0 || !width.is_multiple_of(2) || !height.is_multiple_of(2) {
            return Err(VideoError::new(
                path,
                format!("the frame size {width}x{height} must be even on both sides"),
            ));
        }
        if !(fps.is_finite() && fps > 0.0) {
            return Err(VideoError::new(path, format!("{fps} frames a second")));
        }
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            if !parent.is_dir() {
                return Err(VideoError::new(path, "its folder does not exist"));
            }
        }
        let partial = partial_path(path);
        let sink = match ffmpeg() {
            Some(program) => {
                let child = Command::new(program)
                    .args(["-hide_banner", "-loglevel", "error", "-y"])
                    .args(["-f", "rawvideo", "-pix_fmt", "rgba"])
                    .args(["-s", &format!("{width}x{height}")])
                    .args(["-framerate", &format!("{fps}")])
                    .args(["-i", "-", "-an", "-pix_fmt", "yuv420p"])
                    .arg(&partial)
                    .stdin(Stdio::piped())
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .spawn()
                    .map_err(|e| VideoError::new(path, format!("cannot run ffmpeg: {e}")))?;
                Sink::Ffmpeg(child)
            }
            None => {
                let dir = frames_dir(path);
                std::fs::create_dir_all(&dir)
                    .map_err(|e| VideoError::new(&dir, format!("cannot create folder: {e}")))?;
                Sink::Frames(dir)
            }
        };
        Ok(Video {
            path: path.to_path_buf(),
            partial,
            sink: Some(sink),
            width,
            height,
            fps,
            frames: 0,
        })
    }

    /// Adds the next frame (of the video's size).
    pub fn add(&mut self, image: &Image) -> Result<(), VideoError> {
        if (image.width, image.height) != (self.width, self.height) {
            return Err(VideoError::new(
                &self.path,
                format!(
                    "a frame of {}x{} in a video of {}x{}",
                    image.width, image.height, self.width, self.height
                ),
            ));
        }
        self.frames += 1;
        match &mut self.sink {
            Some(Sink::Ffmpeg(child)) => {
                let written = child
                    .stdin
                    .as_mut()
                    .map(|stdin| stdin.write_all(&image.rgba));
                if !matches!(written, Some(Ok(()))) {
                    let message = self.ffmpeg_failed();
                    return Err(VideoError::new(&self.path, message));
                }
                Ok(())
            }
            Some(Sink::Frames(dir)) => {
                let file = dir.join(format!("frame_{:05}.png", self.frames));
                image
                    .save_png(&file)
                    .map_err(|e| VideoError::new(&file, format!("cannot write: {e}")))
            }
            None => Err(VideoError::new(&self.path, "already finished")),
        }
    }

    /// Ends the video: waits for `ffmpeg` to finish the file.
    pub fn finish(mut self) -> Result<Written, VideoError> {
        match self.sink.take() {
            Some(Sink::Ffmpeg(mut child)) => {
                drop(child.stdin.take());
                let out = child
                    .wait_with_output()
                    .map_err(|e| VideoError::new(&self.path, format!("ffmpeg: {e}")))?;
                if !out.status.success() {
                    let _ = std::fs::remove_file(&self.partial);
                    return Err(VideoError::new(
                        &self.path,
                        format!("ffmpeg failed: {}", first_line(&out.stderr)),
                    ));
                }
                std::fs::rename(&self.partial, &self.path).map_err(|e| {
                    let _ = std::fs::remove_file(&self.partial);
                    VideoError::new(&self.path, format!("cannot write: {e}"))
                })?;
                Ok(Written::Video(self.path.clone()))
            }
            Some(Sink::Frames(dir)) => {
                let command = format!(
                    "ffmpeg -framerate {} -i {}/frame_%05d.png -pix_fmt yuv420p {}",
                    self.fps,
                    dir.display(),
                    self.path.display()
                );
                Ok(Written::Frames { dir, command })
            }
            None => Err(VideoError::new(&self.path, "already finished")),
        }
    }

    /// Stops `ffmpeg` after a failed write and says why it stopped.
    fn ffmpeg_failed(&mut self) -> String {
        if let Some(Sink::Ffmpeg(mut child)) = self.sink.take() {
            drop(child.stdin.take());
            let _ = child.kill();
            if let Ok(out) = child.wait_with_output() {
                let _ = std::fs::remove_file(&self.partial);
                let said = first_line(&out.stderr);
                if !said.is_empty() {
                    return format!("ffmpeg failed: {said}");
                }
            }
        }
        let _ = std::fs::remove_file(&self.partial);
        "ffmpeg stopped taking frames".into()
    }
}

impl Drop for Video {
    /// A video not finished leaves nothing behind: `ffmpeg` is stopped and its partial
    /// file removed, or the frames written so far (and their folder, when that leaves it
    /// empty).
    fn drop(&mut self) {
        match self.sink.take() {
            Some(Sink::Ffmpeg(mut child)) => {
                drop(child.stdin.take());
                let _ = child.kill();
                let _ = child.wait();
                let _ = std::fs::remove_file(&self.partial);
            }
            Some(Sink::Frames(dir)) => {
                for k in 1..=self.frames {
                    let _ = std::fs::remove_file(dir.join(format!("frame_{k:05}.png")));
                }
                let _ = std::fs::remove_dir(dir);
            }
            None => {}
        }
    }
}

/// A take drawn into a video as the window draws the puppet (its look, no marks for
/// editing: [`Overlays::for_video`]), frame by frame: `simulate --out TAKE.mp4` with the
/// camera and look the window opens with, the window's *Export animation* with its own.
pub struct TakeVideo {
    gpu: Gpu,
    renderer: SceneRenderer,
    look: Overlays,
    /// `None`: framed on the puppet's bounds at the first frame, as the window opens.
    camera: Option<Camera>,
    video: Video,
    size: (u32, u32),
}

impl TakeVideo {
    /// Finds a GPU (a headless one of its own: it draws on the export's thread) and
    /// starts the video of `size` pixels (both even) at `fps` frames a second.
    ///
    /// # Errors
    /// No GPU, or a video that cannot start (a bad size, a folder that cannot be written).
    pub fn create(
        path: &Path,
        size: (u32, u32),
        look: Overlays,
        camera: Option<Camera>,
        fps: f64,
    ) -> Result<TakeVideo, VideoError> {
        let gpu = Gpu::headless().map_err(|e| VideoError::new(path, e.to_string()))?;
        let renderer = SceneRenderer::new(&gpu, super::OFFSCREEN_FORMAT);
        let video = Video::create(path, size.0, size.1, fps)?;
        Ok(TakeVideo {
            gpu,
            renderer,
            look: look.for_video(),
            camera,
            video,
            size,
        })
    }

    /// Draws the session's puppet as the window would and adds it to the video.
    ///
    /// # Errors
    /// The picture could not be drawn, or the video took no more frames.
    pub fn add(&mut self, session: &Session) -> Result<(), VideoError> {
        let puppet = &session.puppet;
        let camera = self.camera.get_or_insert_with(|| {
            let (lo, hi) = puppet.mesh.bounds();
            let mut c = Camera {
                up: puppet.up().as_vec3(),
                ..Default::default()
            };
            c.frame(lo.as_vec3(), hi.as_vec3());
            c
        });
        let image = super::render_image(
            &self.gpu,
            &mut self.renderer,
            &session.view(self.look),
            camera,
            self.size.0,
            self.size.1,
        )
        .map_err(|e| VideoError::new(&self.video.path, e.to_string()))?;
        self.video.add(&image)
    }

    /// Ends the video (see [`Video::finish`]).
    ///
    /// # Errors
    /// As [`Video::finish`].
    pub fn finish(self) -> Result<Written, VideoError> {
        self.video.finish()
    }
}

impl TakeWriter for TakeVideo {
    fn add(&mut self, session: &Session) -> Result<(), String> {
        TakeVideo::add(self, session).map_err(|e| e.to_string())
    }

    fn finish(self: Box<Self>) -> Result<String, String> {
        let frames = self.video.frames;
        match TakeVideo::finish(*self).map_err(|e| e.to_string())? {
            Written::Video(path) => Ok(format!("exported {frames} frames to {}", path.display())),
            Written::Frames { dir, command } => Ok(format!(
                "no ffmpeg: {frames} frames written as PNG files in {}; make the video with: {command}",
                dir.display()
            )),
        }
    }
}

/// The first non-empty line of what a program printed.
fn first_line(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes)
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("")
        .to_string()
}
