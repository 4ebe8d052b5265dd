//! The `puppet` binary. Errors are one line, `error: <file>: <problem>`, with exit status 2.

mod cli;

use clap::Parser;
use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    // A reader that stops early (`puppet suggest … | head`) ends the program quietly, as
    // for other command-line tools; Rust's default would panic in `println!`.
    #[cfg(unix)]
    // SAFETY: restoring a signal's default disposition at startup, before any thread runs.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("warn,winit=error,sctk_adwaita=error"),
    )
    .format(|buf, record| {
        let level = record.level().as_str().to_lowercase();
        writeln!(buf, "{level}: {}", record.args())
    })
    .init();
    let cli = cli::Cli::parse();
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
