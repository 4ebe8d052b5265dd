//! `puppet simulate [MESH.obj] --rig RIG --anim ANIM [--frames N] [--fps F]
//! [--out-dir DIR] [--out FINAL.obj | TAKE.glb | TAKE.pc2 | TAKE.mp4 | DIR/] [--gravity G]
//! [--floor H] [--friction F] [--collision] [--flesh F] [--json]`:
//! plays an animation through the full simulation, headless.
//!
//! A video (`TAKE.mp4`, `.webm`, `.mkv`, `.mov`) is the take drawn as the window draws it
//! when it opens the puppet (its camera, lighting, ground and shadow, anti-aliased; no
//! pivots), one picture per exported frame on the take's clock (`--fps` over
//! `--frame-step`), through `ffmpeg` when it is installed, else PNG frames beside it
//! ([`puppet::render::video`]).
//!
//! Frame `k` (1-based) shows time `k / fps`. The simulation runs on its own fixed step (the
//! rig's `time_step`); the pose is sampled from the animation at every step, not every
//! frame, so the result does not depend on `--fps`.

use super::progress_bar::ProgressBar;
use super::{load_mesh, FileError};
use anyhow::{bail, Result};
use puppet::anim::{Animation, Bound};
use puppet::export::{FileOrder, Kind, TakeFiles, TakeOptions};
use puppet::files::{self, Format};
use puppet::puppet::bake::{FrameRange, Player, MAX_FRAMES};
use puppet::session::Session;
use puppet::stats::median_p95;
use puppet::{Puppet, RigFile};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Mesh (OBJ, PLY, STL, glTF or glb); by default the rig's `mesh`, else the embedded Spot.
    pub mesh: Option<PathBuf>,
    /// Rig file (TOML or JSON): material, constraint, cuts. Default: the skin material and the
    /// mesh's suggested joints (a skinned file's own), as the window opens it.
    #[arg(long)]
    pub rig: Option<PathBuf>,
    /// Animation file (TOML or JSON). Default: the rest pose.
    #[arg(long)]
    pub anim: Option<PathBuf>,
    /// Play this clip of a skinned glTF (`puppet suggest` lists them) through the puppet:
    /// the skin's joints move as the clip moves them, the flesh follows elastically.
    /// Without cuts in the rig, the skin's joints are used.
    #[arg(long, conflicts_with = "anim")]
    pub clip: Option<String>,
    /// Suggest joints from the skeleton even when the file has a skin.
    #[arg(long)]
    pub ignore_skin: bool,
    /// Frames to play (default: the animation's duration, or 1 s without one).
    #[arg(long)]
    pub frames: Option<u64>,
    /// Frames per second of the output (the simulation step is the rig's).
    #[arg(long, default_value_t = 30.0)]
    pub fps: f64,
    /// Write every frame as DIR/frame_00001.obj, ...
    #[arg(long)]
    pub out_dir: Option<PathBuf>,
    /// `FINAL.obj`: the final surface (same vertex order as the welded input);
    /// `TAKE.glb`: every frame as a morph target with an animation of the weights (Blender
    /// shape keys, game engines); `TAKE.pc2`: a PC2 point cache and `TAKE.obj` beside it
    /// (Blender's Mesh Cache modifier, 3ds Max); `DIR/`: one OBJ per frame; `TAKE.mp4`
    /// (`.webm`, `.mkv`, `.mov`): the take drawn as the window draws it, through `ffmpeg`
    /// (else PNG frames in `TAKE-frames/`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// A video's size in pixels, `WIDTHxHEIGHT`, both even (with `--out TAKE.mp4`).
    #[arg(long, default_value = "1280x720")]
    pub video_size: String,
    /// How a video's surface is lit (with `--out TAKE.mp4`): the window's studio lights,
    /// or a matcap, light fixed to the camera (`clay`: matte; `jelly`: glossy).
    #[arg(long, value_enum, default_value_t = puppet::session::Lighting::Studio)]
    pub lighting: puppet::session::Lighting,
    /// Export every Nth frame (with `--out TAKE.glb | TAKE.pc2 | DIR/`).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub frame_step: u64,
    /// The first frame exported (with `--out TAKE.glb | TAKE.pc2 | DIR/`; the frames before
    /// it are simulated, not written).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub first_frame: u64,
    /// Write the `.glb`'s positions and morph targets as 16-bit integers
    /// (`KHR_mesh_quantization`, about two thirds of the size; error at most 1/32766 of the
    /// take's extent).
    #[arg(long)]
    pub quantize: bool,
    /// Replace the rig's cuts with the joints the skeleton suggests (see `puppet suggest`
    /// for their names); without `--rig` they are used anyway, as the window opens a mesh.
    #[arg(long)]
    pub suggest_joints: bool,
    /// Gravity in g pulling down (against the rig's `up`, or the one the suggestion finds;
    /// −y by default), over the rig's `gravity` (see `World::gravity`: 1 is 9.81 m/s² on a
    /// puppet one metre across).
    #[arg(long, allow_negative_numbers = true)]
    pub gravity: Option<f32>,
    /// A floor this high above the mesh's lowest rest point (mesh units), over the rig's.
    #[arg(long, allow_negative_numbers = true)]
    pub floor: Option<f32>,
    /// The floor's friction, 0..1 (over the rig's `floor_friction`); contacts between
    /// sections use it too.
    #[arg(long)]
    pub friction: Option<f32>,
    /// Sections collide (over the rig's `collision`): each point is kept out of the
    /// medial balls of the sections nearer the root.
    #[arg(long)]
    pub collision: bool,
    /// How far the flesh of a part nearer the root gives under a part pressed into it,
    /// 0..0.5 of its medial radius (over the rig's `flesh`; turns collision on).
    #[arg(long, allow_negative_numbers = true)]
    pub flesh: Option<f32>,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub json: bool,
}

/// What the command prints (`--json` prints exactly these fields).
#[derive(serde::Serialize)]
struct Summary {
    mesh: String,
    rig: Option<String>,
    anim: Option<String>,
    /// Where the joints come from: `rig` (its cuts), `suggestion`, `skin` (the file's
    /// own), or `none`.
    joints_from: puppet::puppet::JointsFrom,
    vertices: usize,
    springs: usize,
    sections: usize,
    method: &'static str,
    frames: u64,
    fps: f64,
    steps: u64,
    time_step: f32,
    ms_per_step_median: f64,
    ms_per_step_p95: f64,
    seconds_skeleton: f64,
    seconds_total: f64,
    /// Largest distance of a vertex from its posed rest position at the end, relative to
    /// the bounding-box diagonal.
    final_max_offset: f64,
    out: Option<String>,
    out_dir: Option<String>,
    /// Frames written to `--out` when it is a take (`.glb`, `.pc2`, a folder, a video).
    exported_frames: u64,
    /// Without `ffmpeg`, the folder a video's frames went to as PNG files, and the
    /// command that makes the video from them.
    video_frames_dir: Option<String>,
    video_command: Option<String>,
}

pub fn run(args: &Args, load: &super::LoadArgs) -> Result<()> {
    if !(args.fps.is_finite() && args.fps > 0.0 && args.fps <= 10_000.0) {
        bail!("--fps {} must be in (0, 10000]", args.fps);
    }
    let t_start = Instant::now();
    let spec = match &args.rig {
        Some(path) => {
            RigFile::load(path).map_err(|e| FileError::new(path.display().to_string(), e))?
        }
        None => RigFile::default(),
    };
    let anim = match &args.anim {
        Some(path) => {
            let text = files::read_text(path)
                .map_err(|e| FileError::new(path.display().to_string(), e))?;
            Some(
                Animation::parse(&text, Format::of(path))
                    .map_err(|e| FileError::new(path.display().to_string(), e))?,
            )
        }
        None => None,
    };
    let out = Out::of(args.out.as_deref())?;
    let mesh_path = args.mesh.clone().or_else(|| spec.mesh.clone());
    let (mesh, report, mesh_name) = load_mesh(mesh_path.as_deref(), load)?;
    // The skin's clip, named by `--clip`.
    let clip = match &args.clip {
        Some(name) => {
            let skin = report.skin.clone().ok_or_else(|| {
                FileError::new(&mesh_name, "--clip: the file has no skin, so no clips")
            })?;
            let k = skin
                .clips
                .iter()
                .position(|c| &c.name == name)
                .ok_or_else(|| {
                    let known: Vec<&str> = skin.clips.iter().map(|c| c.name.as_str()).collect();
                    FileError::new(
                        &mesh_name,
                        format!("no clip named '{name}' (clips: {})", known.join(", ")),
                    )
                })?;
            Some((skin, k))
        }
        None => None,
    };
    let duration = match (&anim, &clip) {
        (Some(a), _) => Some(a.duration),
        (None, Some((skin, k))) => Some(skin.clips[*k].duration.max(1.0 / args.fps)),
        (None, None) => None,
    };
    let frames = match (args.frames, duration) {
        (Some(n), _) => n,
        (None, Some(d)) => (d * args.fps).ceil().max(1.0) as u64,
        (None, None) => args.fps.ceil() as u64,
    };
    if frames == 0 || frames > MAX_FRAMES {
        bail!("--frames {frames} must be in 1..={MAX_FRAMES}");
    }
    let range = FrameRange {
        first: args.first_frame,
        last: frames,
        step: args.frame_step,
        fps: args.fps,
    };
    range
        .check()
        .map_err(|e| anyhow::anyhow!("--first-frame/--frames: {e}"))?;
    // Bad output paths fail now, not after the skeleton and the simulation.
    let mut take = match &out {
        Out::Take(path, kind) => {
            let order = match (kind, &mesh_path) {
                (Kind::Pc2, Some(file)) => FileOrder::of_file(file, &mesh)
                    .map_err(|e| FileError::new(file.display().to_string(), e))?,
                _ => None,
            };
            let options = TakeOptions {
                quantize: args.quantize,
                order,
            };
            Some(
                TakeFiles::create(
                    path,
                    *kind,
                    &mesh,
                    options,
                    args.fps,
                    range.first,
                    range.step,
                )
                .map_err(|e| FileError::new(e.path, e.message))?,
            )
        }
        _ => None,
    };
    let mut video = match &out {
        Out::Video(path) => Some(VideoTake::create(
            path,
            &args.video_size,
            args.lighting,
            args.fps / range.step as f64,
        )?),
        _ => None,
    };
    if let Some(dir) = &args.out_dir {
        std::fs::create_dir_all(dir).map_err(|e| {
            FileError::new(
                dir.display().to_string(),
                format!("cannot create folder: {e}"),
            )
        })?;
    }

    let bar = ProgressBar::new();
    let t_skeleton = Instant::now();
    let rig_name = args
        .rig
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| mesh_name.clone());
    let built = Puppet::build_loaded(mesh, Some(&report), spec, &|s, f| bar.update(s, f));
    let mut puppet = built.map_err(|e| match e {
        puppet::puppet::BuildError::Joints(e) => FileError::new(&rig_name, e),
        e @ puppet::puppet::BuildError::Regions(_) => FileError::new(&rig_name, e),
        e => FileError::new(&mesh_name, e),
    })?;
    bar.finish();
    puppet.ignore_skin = args.ignore_skin;
    // A mesh played without a rig has the joints the window opens it with: its suggested
    // ones (a skinned file's own), so an animation made in the window plays here; so has a
    // skinned file whose rig has no cuts.
    let uncut = puppet.joints.cuts().is_empty();
    let suggest = args.suggest_joints
        || args.rig.is_none()
        || (uncut && (clip.is_some() || puppet.skin_joints().is_some()));
    let mut suggested = false;
    if suggest {
        match puppet.suggest_joints() {
            Ok(_) => suggested = true,
            // Asked for, a failed suggestion is an error; taken by default, the puppet
            // plays without joints, as the window keeps it open.
            Err(e) if args.suggest_joints || clip.is_some() => {
                return Err(FileError::new(&mesh_name, e).into())
            }
            Err(e) => log::warn!("{mesh_name}: no suggested joints: {e}"),
        }
    }
    let joints_from = puppet.joints_from(suggested);
    let mut params = *puppet.sim.params();
    if let Some(g) = args.gravity {
        // Down is against the puppet's up (the rig's, or as the suggestion found it).
        params.world.gravity = (-g * puppet.sim.up().vector()).to_array();
    }
    if let Some(h) = args.floor {
        params.world.floor = true;
        params.world.floor_height = h;
    }
    if let Some(f) = args.friction {
        params.world.floor_friction = f;
    }
    if args.collision {
        params.world.collision = true;
    }
    if let Some(f) = args.flesh {
        params.world.collision = true;
        params.world.flesh = f;
    }
    params
        .check()
        .map_err(|e| anyhow::anyhow!("--gravity/--floor/--friction/--flesh: {e}"))?;
    puppet.sim.set_params(params);
    let seconds_skeleton = t_skeleton.elapsed().as_secs_f64();
    // What a video draws: the puppet as the window holds it.
    let mut session = Session::new(puppet, mesh_name.clone());
    let bound: Option<Bound> = match (&anim, &args.anim, &clip) {
        (Some(a), Some(path), _) => Some(
            a.bind(&session.puppet.joints)
                .map_err(|e| FileError::new(path.display().to_string(), e))?,
        ),
        (_, _, Some((skin, k))) => Some(
            puppet::anim::clip::animation(&skin.clips[*k], skin, &session.puppet.joints)
                .bind(&session.puppet.joints)
                .map_err(|e| FileError::new(&mesh_name, e))?,
        ),
        _ => None,
    };

    let h = session.puppet.sim.params().solver.time_step as f64;
    let mut player = Player::new(bound, args.fps);
    let mut step_ms = Vec::with_capacity(player.steps_by(h, frames).min(1 << 20) as usize);
    for frame in 1..=frames {
        let target = player.steps_by(h, frame);
        while player.steps() < target {
            let t = Instant::now();
            player.step(&mut session.puppet);
            step_ms.push(t.elapsed().as_secs_f64() * 1e3);
        }
        if let (Some(take), true) = (&mut take, range.keeps(frame)) {
            let x = session.puppet.sim.positions();
            take.add(frame, (0..x.len()).map(|i| x.get(i)).collect())
                .map_err(|e| FileError::new(e.path, e.message))?;
        }
        if let (Some(video), true) = (&mut video, range.keeps(frame)) {
            session.wake();
            video.add(&session)?;
            bar.update("drawing the video", frame as f64 / frames as f64);
        }
        if let Some(dir) = &args.out_dir {
            let path = dir.join(format!("frame_{frame:05}.obj"));
            write_surface(
                &session.puppet,
                &path,
                &format!("frame {frame}, t = {} s", frame as f64 / args.fps),
            )?;
        }
    }
    let steps = player.steps();
    if let Out::Final(path) = &out {
        write_surface(&session.puppet, path, &format!("final frame {frames}"))?;
    }
    if let Some(take) = take {
        take.finish()
            .map_err(|e| FileError::new(e.path, e.message))?;
    }
    let (video_frames_dir, video_command) = match video {
        Some(v) => {
            bar.finish();
            v.finish()?
        }
        None => (None, None),
    };

    let positions = session.puppet.sim.positions();
    let diagonal = session.puppet.mesh.diagonal().max(f64::MIN_POSITIVE);
    let final_max_offset = (0..positions.len())
        .map(|i| (positions.get(i) - session.puppet.sim.target(i)).length() as f64)
        .fold(0.0, f64::max)
        / diagonal;
    if !final_max_offset.is_finite() {
        bail!("{mesh_name}: the simulation produced non-finite positions (please report this)");
    }
    let (ms_median, ms_p95) = if step_ms.is_empty() {
        (0.0, 0.0)
    } else {
        median_p95(step_ms)
    };
    let summary = Summary {
        mesh: mesh_name,
        rig: args.rig.as_ref().map(|p| p.display().to_string()),
        anim: args.anim.as_ref().map(|p| p.display().to_string()),
        joints_from,
        vertices: session.puppet.mesh.positions.len(),
        springs: session.puppet.sim.rig().spring_count(),
        sections: session.puppet.joints.sections().len(),
        method: match session.puppet.sim.params().solver.constraint {
            puppet::sim::Constraint::Circumsphere => "circumsphere",
            puppet::sim::Constraint::SpringReduction => "spring-reduction",
        },
        frames,
        fps: args.fps,
        steps,
        time_step: session.puppet.sim.params().solver.time_step,
        ms_per_step_median: ms_median,
        ms_per_step_p95: ms_p95,
        seconds_skeleton,
        seconds_total: t_start.elapsed().as_secs_f64(),
        final_max_offset,
        out: args.out.as_ref().map(|p| p.display().to_string()),
        exported_frames: range.count(),
        out_dir: args.out_dir.as_ref().map(|p| p.display().to_string()),
        video_frames_dir,
        video_command,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        print_summary(&summary);
    }
    Ok(())
}

fn print_summary(s: &Summary) {
    println!(
        "mesh      {} ({} vertices, {} springs, {} sections; joints from: {})",
        s.mesh,
        s.vertices,
        s.springs,
        s.sections,
        s.joints_from.name()
    );
    println!(
        "played    {} frames at {} fps = {} steps of {:.2} ms ({})",
        s.frames,
        s.fps,
        s.steps,
        s.time_step * 1e3,
        s.method
    );
    println!(
        "step      {:.3} ms median, {:.3} ms p95; skeleton {:.2} s; total {:.2} s",
        s.ms_per_step_median, s.ms_per_step_p95, s.seconds_skeleton, s.seconds_total
    );
    println!(
        "final     largest offset from the posed rest shape: {:.2e} of the diagonal",
        s.final_max_offset
    );
    if let Some(d) = &s.out_dir {
        println!("frames    {d}/frame_00001.obj ..");
    }
    match (&s.video_frames_dir, &s.video_command, &s.out) {
        (Some(dir), Some(command), _) => {
            println!(
                "wrote     {} PNG frames to {dir}/ (ffmpeg not found)",
                s.exported_frames
            );
            println!("video     {command}");
        }
        (_, _, Some(o)) => println!("wrote     {o}"),
        _ => {}
    }
}

/// A take drawn into a video (see the module docs): [`puppet::render::video::TakeVideo`]
/// with the camera the window opens with.
#[cfg(feature = "gui")]
struct VideoTake(puppet::render::video::TakeVideo);

#[cfg(feature = "gui")]
impl VideoTake {
    /// Checks the size, finds the GPU and starts the video at `fps`.
    fn create(
        path: &Path,
        size: &str,
        lighting: puppet::session::Lighting,
        fps: f64,
    ) -> Result<VideoTake> {
        let size = video_size(size)?;
        let look = puppet::session::Overlays {
            lighting,
            ..Default::default()
        };
        puppet::render::video::TakeVideo::create(path, size, look, None, fps)
            .map(VideoTake)
            .map_err(|e| FileError::new(e.path, e.message).into())
    }

    /// Draws the session's puppet as the window would and adds it to the video.
    fn add(&mut self, session: &Session) -> Result<()> {
        self.0
            .add(session)
            .map_err(|e| FileError::new(e.path, e.message).into())
    }

    /// Ends the video; without `ffmpeg`, the frames' folder and the command that makes
    /// the video from them.
    fn finish(self) -> Result<(Option<String>, Option<String>)> {
        match self
            .0
            .finish()
            .map_err(|e| FileError::new(e.path, e.message))?
        {
            puppet::render::video::Written::Video(_) => Ok((None, None)),
            puppet::render::video::Written::Frames { dir, command } => {
                Ok((Some(dir.display().to_string()), Some(command)))
            }
        }
    }
}

/// Without a renderer, `--out TAKE.mp4` is refused before anything runs.
#[cfg(not(feature = "gui"))]
struct VideoTake;

#[cfg(not(feature = "gui"))]
impl VideoTake {
    fn create(path: &Path, size: &str, _: puppet::session::Lighting, _: f64) -> Result<VideoTake> {
        video_size(size)?;
        Err(FileError::new(
            path.display().to_string(),
            "this build draws no video (it was built without the gui feature)",
        )
        .into())
    }
    fn add(&mut self, _: &Session) -> Result<()> {
        Ok(())
    }
    fn finish(self) -> Result<(Option<String>, Option<String>)> {
        Ok((None, None))
    }
}

/// `WIDTHxHEIGHT`, both even and 16..=8192.
fn video_size(text: &str) -> Result<(u32, u32)> {
    let bad = || {
        anyhow::anyhow!(
            "--video-size: '{text}' is not WIDTHxHEIGHT with both even and within 16..8192"
        )
    };
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    let fits = |v: u32| (16..=8192).contains(&v) && v.is_multiple_of(2);
    if !(fits(w) && fits(h)) {
        return Err(bad());
    }
    Ok((w, h))
}

fn write_surface(puppet: &Puppet, path: &Path, header: &str) -> Result<()> {
    puppet
        .save_surface(path, &format!("puppet simulate: {header}"))
        .map_err(|e| FileError::new(path.display().to_string(), e))?;
    Ok(())
}

/// What `--out` asks for.
enum Out {
    None,
    /// The final surface as OBJ.
    Final(PathBuf),
    /// Every exported frame: `.glb`, `.pc2` or a folder of OBJ files.
    Take(PathBuf, Kind),
    /// Every exported frame drawn into a video.
    Video(PathBuf),
}

impl Out {
    fn of(path: Option<&Path>) -> Result<Out> {
        let Some(path) = path else {
            return Ok(Out::None);
        };
        if let Some(kind) = Kind::of(path) {
            return Ok(Out::Take(path.to_path_buf(), kind));
        }
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if ext.as_deref() == Some("obj") {
            return Ok(Out::Final(path.to_path_buf()));
        }
        if puppet::export::is_video(path) {
            return Ok(Out::Video(path.to_path_buf()));
        }
        Err(FileError::new(
            path.display().to_string(),
            "not a format simulate writes (FINAL.obj, TAKE.glb, TAKE.pc2, TAKE.mp4, or DIR/)",
        )
        .into())
    }
}
