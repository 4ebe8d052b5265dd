//! What scripts and tests ask of the window beyond what a person does: a screenshot after
//! some frames (then exit), a synthetic drag, a report file written as the window changes.
//! One small type, so the window's own state holds none of it.

use std::path::PathBuf;

/// The test hooks of a window (none, by default).
#[derive(Debug, Default)]
pub struct TestHooks {
    /// Save a screenshot here and exit, after `exit_after` frames.
    pub(super) screenshot: Option<PathBuf>,
    pub(super) exit_after: Option<u32>,
    /// The synthetic drag's next event (`None`: no drag, or done).
    pub(super) drive: Option<u32>,
    /// Where the report goes (`--report`).
    pub(super) report: Option<PathBuf>,
    /// Key presses the window received (the report says how many, so a test driving it
    /// knows a key arrived).
    pub(super) keys: u64,
}

impl TestHooks {
    /// Hooks for a run: save a screenshot to `screenshot` after `frames` frames and exit;
    /// `drive`: first drag the section under the window centre the way a mouse would;
    /// `report`: write what the window shows to this file (JSON) whenever the puppet
    /// settles and when the window closes.
    pub fn new(
        screenshot: Option<PathBuf>,
        frames: u32,
        drive: bool,
        report: Option<PathBuf>,
    ) -> TestHooks {
        TestHooks {
            exit_after: screenshot.is_some().then_some(frames.max(1)),
            screenshot,
            drive: drive.then_some(0),
            report,
            keys: 0,
        }
    }

    /// True while a hook needs frames drawn whether or not anything moves (a screenshot
    /// to take, a drag to make).
    pub(super) fn busy(&self) -> bool {
        self.screenshot.is_some() || self.drive.is_some()
    }
}
