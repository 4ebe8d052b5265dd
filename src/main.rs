//! The `puppet` binary. Errors are one line, `error: <file>: <problem>`, with exit status 2.

mod cli;

use clap::Parser;
use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    // A reader that stops early (`puppet suggest … | head`) ends the program quietly, as
    // for other command-line tools; Rust's default would panic in `println!`. Not while
    // frames are piped into `ffmpeg`: its early exit is an error to report.
    #[cfg(unix)]
    if !cli.pipes_to_programs() {
        // SAFETY: restoring a signal's default disposition at startup, before any thread
        // runs (parsing the command line starts none).
        unsafe {
            libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        }
    }
    #[cfg(unix)]
    private_runtime_dir();
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("warn,winit=error,sctk_adwaita=error"),
    )
    .format(|buf, record| {
        let level = record.level().as_str().to_lowercase();
        writeln!(buf, "{level}: {}", record.args())
    })
    .init();
    let cli = cli.settled();
    match cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the chain joined, the file first when the error names one.
            let msg = e
                .chain()
                .map(|c| c.to_string())
                .collect::<Vec<_>>()
                .join(": ");
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
    }
}

/// Mesa (the software renderer, and some GPU drivers) prints `error: XDG_RUNTIME_DIR is
/// invalid or not set` when the session has none (a container, `ssh`, CI), on runs that
/// succeed. Without a usable one, the process gets a private directory of its own (mode
/// 0700, under the temporary folder, per user) before any thread or adapter exists; when
/// that cannot be made, nothing changes.
#[cfg(unix)]
fn private_runtime_dir() {
    use std::os::unix::fs::{DirBuilderExt, MetadataExt, PermissionsExt};
    let usable = |p: &std::path::Path| {
        std::fs::metadata(p).is_ok_and(|m| {
            // SAFETY: `getuid` has no preconditions and cannot fail.
            m.is_dir()
                && m.uid() == unsafe { libc::getuid() }
                && m.permissions().mode() & 0o077 == 0
        })
    };
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| usable(std::path::Path::new(&d))) {
        return;
    }
    // SAFETY: as above.
    let uid = unsafe { libc::getuid() };
    let dir = std::env::temp_dir().join(format!("puppet-runtime-{uid}"));
    let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
    if usable(&dir) {
        // Single-threaded here: nothing reads the environment concurrently.
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
}
