//! The command line: argument parsing, the `error: <file>: <problem>` convention (exit
//! status 2), progress bars and the `skeleton` and `bench` commands. Only this module and
//! `main.rs` print.

pub mod bench;
pub mod progress_bar;
pub mod simulate;
pub mod skeleton;

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
    about = "Any closed triangle mesh as an elastic puppet"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Mesh to open (OBJ); the embedded Spot when omitted.
    pub mesh: Option<PathBuf>,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Build the medial skeleton of a mesh and write the skeletal mesh S (M = S + dN).
    Skeleton(skeleton::Args),
    /// Play an animation file through the simulation and write OBJ frames (headless).
    Simulate(simulate::Args),
    /// Measure: skeleton accuracy against analytic shapes, skeleton speed.
    Bench(bench::Args),
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

/// Loads `path` (or the embedded default), logging load warnings.
pub fn load_mesh(path: Option<&Path>) -> Result<(Mesh, LoadReport, String)> {
    let (name, result) = match path {
        Some(p) => (p.display().to_string(), mesh::load_obj(p)),
        None => (DEFAULT_MESH_NAME.to_string(), mesh::parse_obj(DEFAULT_MESH)),
    };
    let (mesh, report) = result.map_err(|e| FileError::new(&name, e))?;
    for w in report.warnings() {
        log::warn!("{name}: {w}");
    }
    Ok((mesh, report, name))
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Some(Command::Skeleton(args)) => skeleton::run(&args),
        Some(Command::Simulate(args)) => simulate::run(&args),
        Some(Command::Bench(args)) => bench::run(&args),
        None => open(cli.mesh.as_deref()),
    }
}

/// `puppet [MESH]`: the puppet for a mesh. The interactive window is not built yet
/// (issue "The interactive puppet app"); until then this loads the mesh, builds its
/// skeleton and prints the summary a user would see in the window's stats panel.
fn open(path: Option<&Path>) -> Result<()> {
    let args = skeleton::Args {
        mesh: path.map(Path::to_path_buf),
        method: None,
        output: None,
        json: false,
    };
    skeleton::run(&args)?;
    println!("(the interactive window is not part of this build yet; see README.md)");
    Ok(())
}
