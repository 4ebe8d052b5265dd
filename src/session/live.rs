//! Live controls driving the session: what a glove, a MIDI controller or a gamepad did
//! since the last frame becomes section rotations and actions, exactly as the mouse's
//! would (recording keeps them; see [`crate::controls`]).

use super::Session;
use crate::controls::{Action, Controls};

impl Session {
    /// Applies what `controls` took in since the last call: fired actions first (record
    /// starts or stops a take, reset, play), then the rotations of the sections whose
    /// controls moved. Returns what a stopped take says, for the panel.
    pub fn drive(&mut self, controls: &mut Controls) -> Option<String> {
        let mut said = None;
        for action in controls.take_fired() {
            match action {
                Action::Record if self.is_recording() => {
                    said = Some(self.stop_recording().unwrap_or_else(|e| e));
                }
                Action::Record => self.start_recording(),
                Action::Reset => self.reset_pose(),
                Action::Play => self.toggle_play(),
            }
        }
        if controls.take_changed() {
            let touched = controls.apply(&mut self.local);
            if !touched.is_empty() {
                self.touch(&touched);
                self.wake();
            }
        }
        said
    }

    /// The names of the sections, in order (what a controls file names).
    pub fn section_names(&self) -> Vec<&str> {
        self.puppet
            .joints
            .sections()
            .iter()
            .map(|s| s.name.as_str())
            .collect()
    }
}
