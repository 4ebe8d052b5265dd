//! The command line: argument parsing, the `error: <file>: <problem>` convention (exit
//! status 2), and a file per command: `skeleton`, `suggest`, `simulate`, `send_osc` (a
//! synthetic glove), `bench` (a folder, a file per mode); `progress_bar` draws progress on
//! a terminal, and `docs` tests that the docs name and quote the commands as they are.
//! Only this module and `main.rs` print.

pub mod bench;
pub mod progress_bar;
pub mod send_osc;
pub mod simulate;
pub mod skeleton;
pub mod suggest;

#[cfg(test)]
mod docs;

use anyhow::Result;
use clap::{Parser, Subcommand};
use puppet::mesh::{self, LoadReport, Mesh};
use std::path::{Path, PathBuf};

/// The embedded default mesh (Spot the cow, public domain; see `assets/CREDITS.md`).
pub const DEFAULT_MESH: &[u8] = include_bytes!("../../assets/spot.obj");
/// How the embedded mesh is named in messages.
pub const DEFAULT_MESH_NAME: &str = "spot.obj (embedded)";

#[derive(Parser, Debug)]
#[command(
    name = "puppet",
    version,
    about = "A character mesh as an elastic puppet, in real time, with no rigging by hand"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Mesh to open (OBJ, PLY, STL or glTF); the embedded Spot when omitted.
    pub mesh: Option<PathBuf>,
    /// How meshes are read (for the window and every command).
    #[command(flatten)]
    pub load: LoadArgs,
    /// Rig file to open with it (material, constraint, cuts).
    #[arg(long)]
    pub rig: Option<PathBuf>,
    /// Animation file to play in the window (the format `simulate --anim` reads).
    #[arg(long)]
    pub anim: Option<PathBuf>,
    /// Play this clip of a skinned glTF (`puppet suggest` lists them) in the window.
    #[arg(long, conflicts_with = "anim")]
    pub clip: Option<String>,
    /// Suggest joints from the skeleton even when the file has a skin.
    #[arg(long)]
    pub ignore_skin: bool,
    /// Save a screenshot of the window (PNG) after --frames frames, then exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Frames to draw before the screenshot.
    #[arg(long, default_value_t = 30)]
    pub frames: u32,
    /// How the surface is lit: the studio's lights, or a matcap, light fixed to the camera
    /// (`clay`: matte; `jelly`: glossy); without it, as last chosen in the panel's Show
    /// section.
    #[arg(long, value_enum)]
    pub lighting: Option<puppet::session::Lighting>,
    /// Test hook: drag the last section with synthetic mouse events before the screenshot.
    #[arg(long, hide = true)]
    pub drive_test: bool,
    /// Open with the joints the skeleton suggests, or a skinned file's own, even over a
    /// rig's cuts (the default when no rig is given).
    #[arg(long)]
    pub suggest_joints: bool,
    /// Write what the window shows (JSON) to this file whenever the puppet settles and when
    /// the window closes: for tests and scripts that drive the window.
    #[arg(long, hide = true)]
    pub report: Option<PathBuf>,
    /// Controls file: live devices (a glove or tracker over OSC) mapped to sections.
    #[arg(long)]
    pub controls: Option<PathBuf>,
    /// UDP port to receive OSC on (default 9000 where the controls file reads OSC); alone,
    /// it listens with no controls yet, for the Controls panel's Learn.
    #[arg(long)]
    pub listen: Option<u16>,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Build the medial skeleton of a mesh and write the skeletal mesh S (M = S + dN).
    Skeleton(skeleton::Args),
    /// Suggest joints: print the cuts where the mesh's protrusions narrow, and write them
    /// as a rig file.
    Suggest(suggest::Args),
    /// Play an animation file through the simulation and write the take: OBJ frames, a glb, a PC2 point cache (headless).
    Simulate(simulate::Args),
    /// Stream a synthetic glove performance as OSC (try `--controls` without a glove).
    SendOsc(send_osc::Args),
    /// Measure (every figure in BENCHMARKS.md and docs/engine-benchmarks.md): throughput,
    /// accuracy, stress, skip, sag, export, joints, collide, poses, suggest, skeleton,
    /// skeleton-speed, skeleton-change, machine, controls, draw.
    #[command(arg_required_else_help = false)]
    Bench {
        /// What to measure.
        #[command(subcommand)]
        mode: bench::Bench,
    },
}

/// Options for reading a mesh, accepted by the window and every command.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct LoadArgs {
    /// Close holes of up to this many boundary edges (0: close none; by default every hole
    /// is closed).
    #[arg(long, global = true, value_name = "EDGES")]
    pub fill_holes: Option<usize>,
}

impl LoadArgs {
    /// The library's options.
    pub fn options(&self) -> mesh::LoadOptions {
        mesh::LoadOptions {
            fill_holes: self.fill_holes.unwrap_or(mesh::FILL_HOLES),
        }
    }
}

/// A failure that names the file it concerns: printed as `error: <file>: <message>`.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {message}")]
pub struct FileError {
    pub file: String,
    pub message: String,
}

impl FileError {
    pub fn new(file: impl Into<String>, message: impl std::fmt::Display) -> Self {
        FileError {
            file: file.into(),
            message: message.to_string(),
        }
    }
}

/// How a mesh is named in the window: its file's name (the embedded one's own name).
#[cfg(feature = "gui")]
pub fn display_name(path: Option<&Path>) -> String {
    match path {
        Some(p) => p.file_name().map_or_else(
            || p.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        ),
        None => DEFAULT_MESH_NAME.to_string(),
    }
}

/// Loads `path` (or the embedded default), logging load warnings.
pub fn load_mesh(path: Option<&Path>, load: &LoadArgs) -> Result<(Mesh, LoadReport, String)> {
    let options = load.options();
    let silent = puppet::progress::silent();
    let (name, result) = match path {
        Some(p) => (
            p.display().to_string(),
            mesh::load_with(p, &options, silent),
        ),
        None => (
            DEFAULT_MESH_NAME.to_string(),
            mesh::parse(DEFAULT_MESH, mesh::Format::Obj, &options, silent),
        ),
    };
    let (mesh, report) = result.map_err(|e| FileError::new(&name, e))?;
    for w in report.warnings() {
        log::warn!("{name}: {w}");
    }
    Ok((mesh, report, name))
}

impl Cli {
    /// The command line as meant: a mesh named before a command that reads one is that
    /// command's (`puppet hero.glb suggest` suggests for `hero.glb`, not for the embedded
    /// mesh). Exits with a usage error (status 2) where a command is given with what only
    /// the window reads, or with two meshes.
    /// True when the command pipes frames into another program (`simulate --out
    /// TAKE.mp4` into `ffmpeg`): a broken pipe must then be an error to report, not the
    /// signal that ends the program quietly.
    pub fn pipes_to_programs(&self) -> bool {
        matches!(&self.command, Some(Command::Simulate(a)) if a.out.as_deref().is_some_and(puppet::export::is_video))
    }

    pub fn settled(mut self) -> Cli {
        use clap::CommandFactory;
        let Some(command) = &mut self.command else {
            return self;
        };
        let usage = |message: String| -> ! {
            Cli::command()
                .error(clap::error::ErrorKind::ArgumentConflict, message)
                .exit()
        };
        let name = match command {
            Command::Skeleton(_) => "skeleton",
            Command::Suggest(_) => "suggest",
            Command::Simulate(_) => "simulate",
            Command::SendOsc(_) => "send-osc",
            Command::Bench { .. } => "bench",
        };
        if let Some(mesh) = self.mesh.take() {
            let slot = match command {
                Command::Skeleton(a) => Some(&mut a.mesh),
                Command::Suggest(a) => Some(&mut a.mesh),
                Command::Simulate(a) => Some(&mut a.mesh),
                Command::SendOsc(_) | Command::Bench { .. } => None,
            };
            match slot {
                Some(slot @ None) => *slot = Some(mesh),
                Some(Some(other)) => usage(format!(
                    "two meshes, '{}' and '{}': `puppet {name}` reads one",
                    mesh.display(),
                    other.display()
                )),
                None => usage(format!(
                    "'{}' before `puppet {name}`, which reads no mesh there",
                    mesh.display()
                )),
            }
        }
        let window = [
            ("--rig", self.rig.is_some()),
            ("--anim", self.anim.is_some()),
            ("--clip", self.clip.is_some()),
            ("--screenshot", self.screenshot.is_some()),
            ("--suggest-joints", self.suggest_joints),
            ("--controls", self.controls.is_some()),
            ("--listen", self.listen.is_some()),
            ("--report", self.report.is_some()),
            ("--drive-test", self.drive_test),
        ];
        if let Some((flag, _)) = window.iter().find(|(_, given)| *given) {
            usage(format!(
                "{flag} before `puppet {name}` is an option of the window (see `puppet {name} --help` for the command's own)"
            ));
        }
        if let Some(lighting) = self.lighting {
            match command {
                Command::Simulate(a) => a.lighting = lighting,
                _ => usage(format!(
                    "--lighting before `puppet {name}` is an option of the window (`puppet simulate` lights its video with it)"
                )),
            }
        }
        if self.ignore_skin {
            match command {
                Command::Suggest(a) => a.ignore_skin = true,
                Command::Simulate(a) => a.ignore_skin = true,
                _ => usage(format!(
                    "--ignore-skin before `puppet {name}`, which has no skin to ignore"
                )),
            }
        }
        self
    }
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match &cli.command {
        Some(Command::Skeleton(args)) => skeleton::run(args, &cli.load),
        Some(Command::Simulate(args)) => simulate::run(args, &cli.load),
        Some(Command::SendOsc(args)) => send_osc::run(args),
        Some(Command::Suggest(args)) => suggest::run(args, &cli.load),
        Some(Command::Bench { mode }) => bench::run(mode, &cli.load),
        None => open(&cli),
    }
}

/// `puppet [MESH] [--rig RIG]`: the interactive window. The mesh (and rig) are read and
/// validated first, so a bad file is an `error:` line and exit status 2 before any window
/// opens; the skeleton is then built in the background while the window shows progress.
/// With `--screenshot`, prints one JSON line saying what the screenshot shows.
#[cfg(feature = "gui")]
fn open(cli: &Cli) -> Result<()> {
    let rig_file = match &cli.rig {
        Some(path) => puppet::RigFile::load(path)
            .map_err(|e| FileError::new(path.display().to_string(), e))?,
        None => puppet::RigFile::default(),
    };
    let animation = match &cli.anim {
        Some(path) => {
            let text = puppet::files::read_text(path)
                .map_err(|e| FileError::new(path.display().to_string(), e))?;
            Some(
                puppet::anim::Animation::parse(&text, puppet::files::Format::of(path))
                    .map_err(|e| FileError::new(path.display().to_string(), e))?,
            )
        }
        None => None,
    };
    let live = match (&cli.controls, cli.listen) {
        (Some(path), listen) => {
            let name = path.display().to_string();
            let file =
                puppet::controls::ControlsFile::load(path).map_err(|e| FileError::new(&name, e))?;
            // A UDP port only where the file reads OSC (or --listen asks for one).
            let osc = file
                .controls
                .iter()
                .any(|c| matches!(c.source, puppet::controls::Source::Osc { .. }));
            let socket = if osc || listen.is_some() {
                let port = listen.unwrap_or(puppet::app::DEFAULT_PORT);
                Some(std::net::UdpSocket::bind(("0.0.0.0", port)).map_err(|e| {
                    FileError::new(&name, format!("cannot listen on UDP port {port}: {e}"))
                })?)
            } else {
                None
            };
            Some(puppet::app::LiveOptions { file, socket })
        }
        // Listening with no controls yet: the panel's Learn maps what arrives.
        (None, Some(port)) => {
            let socket = std::net::UdpSocket::bind(("0.0.0.0", port)).map_err(|e| {
                anyhow::anyhow!(
                    "cannot listen on UDP port {port}: {}",
                    puppet::files::io_message(&e)
                )
            })?;
            Some(puppet::app::LiveOptions {
                file: puppet::controls::ControlsFile::default(),
                socket: Some(socket),
            })
        }
        (None, None) => None,
    };
    let mesh_path = cli.mesh.clone().or_else(|| rig_file.mesh.clone());
    let (mesh, mut load_report, mesh_name) = load_mesh(mesh_path.as_deref(), &cli.load)?;
    if let Some(name) = &cli.clip {
        let clips: Vec<&str> = load_report
            .skin
            .iter()
            .flat_map(|s| s.clips.iter().map(|c| c.name.as_str()))
            .collect();
        if !clips.contains(&name.as_str()) {
            return Err(FileError::new(
                &mesh_name,
                format!("no clip named '{name}' (clips: {})", clips.join(", ")),
            )
            .into());
        }
    }
    if cli.ignore_skin {
        // The window then knows nothing of the skin: our own suggestion, no clips.
        load_report.skin = None;
    }
    // A mesh opened without a rig opens ready to play: with its suggested joints (a skinned
    // file's own), as the embedded cow does.
    let suggest = cli.suggest_joints || cli.rig.is_none();
    let report = puppet::app::run(puppet::app::Options {
        mesh,
        load_report: Some(load_report),
        load: cli.load.options(),
        name: display_name(mesh_path.as_deref()),
        source: mesh_path.map(|p| p.canonicalize().unwrap_or(p)),
        rig_file,
        after: puppet::session::loader::AfterLoad {
            suggest,
            animation,
            clip: cli.clip.clone(),
        },
        hooks: puppet::app::TestHooks::new(
            cli.screenshot.clone(),
            cli.frames,
            cli.drive_test,
            cli.report.clone(),
        ),
        live,
        lighting: cli.lighting,
    })?;
    if let Some(report) = report {
        println!("{}", serde_json::to_string(&report)?);
    }
    Ok(())
}

/// Without the `gui` feature there is no window.
#[cfg(not(feature = "gui"))]
fn open(_cli: &Cli) -> Result<()> {
    anyhow::bail!(
        "this build of puppet has no window (built without the `gui` feature); the headless commands are `puppet skeleton`, `puppet suggest`, `puppet simulate` and `puppet bench`"
    )
}
