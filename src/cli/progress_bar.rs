//! A progress bar on stderr for work that takes longer than about a second, drawn only when
//! stderr is a terminal (never in pipes, logs or CI output).

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Draws `stage [#####     ] 52%` lines in place after a one-second grace period.
pub struct ProgressBar {
    start: Instant,
    tty: bool,
    state: Mutex<(String, Instant, bool)>,
}

impl ProgressBar {
    pub fn new() -> Self {
        ProgressBar {
            start: Instant::now(),
            tty: std::io::stderr().is_terminal(),
            state: Mutex::new((String::new(), Instant::now(), false)),
        }
    }

    /// The library callback.
    pub fn update(&self, stage: &str, fraction: f64) {
        if !self.tty || self.start.elapsed() < Duration::from_secs(1) {
            return;
        }
        let Ok(mut st) = self.state.lock() else {
            return;
        };
        if st.0 == stage && st.1.elapsed() < Duration::from_millis(100) && fraction < 1.0 {
            return;
        }
        st.0 = stage.to_string();
        st.1 = Instant::now();
        st.2 = true;
        let filled = (fraction.clamp(0.0, 1.0) * 30.0) as usize;
        let mut err = std::io::stderr().lock();
        let _ = write!(
            err,
            "\r{stage:>16} [{}{}] {:3.0}%",
            "#".repeat(filled),
            " ".repeat(30 - filled),
            fraction * 100.0
        );
        let _ = err.flush();
    }

    /// Clears the bar if one was drawn.
    pub fn finish(&self) {
        if let Ok(st) = self.state.lock() {
            if st.2 {
                let _ = write!(std::io::stderr(), "\r{}\r", " ".repeat(60));
            }
        }
    }
}

impl Default for ProgressBar {
    fn default() -> Self {
        Self::new()
    }
}
