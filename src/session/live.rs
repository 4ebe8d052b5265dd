//! Live controls driving the session: what a glove, a MIDI controller or a gamepad did
//! since the last frame becomes section rotations and actions, exactly as the mouse's
//! would (recording keeps them; see [`crate::controls`]).

use super::Session;
use crate::controls::{Action, Controls};
use glam::DVec3;

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
            let before = self.local.clone();
            let touched = controls.apply(&mut self.local);
            self.hold_back(&before);
            if !touched.is_empty() {
                self.touch(&touched);
                self.wake();
            }
        }
        said
    }

    /// The axis a learned control turns `section` about, seen along `view` (the camera's
    /// direction): across the section's length and the line of sight, so that the part
    /// bends towards the viewer as a finger curls, whichever way it points on screen.
    /// Falls back to +z where the section points along the view.
    pub fn bend_axis(&self, section: usize, view: DVec3) -> DVec3 {
        let Some(pivot) = self.puppet.joints.sections().get(section).map(|s| s.pivot) else {
            return DVec3::Z;
        };
        let (mut sum, mut n) = (DVec3::ZERO, 0usize);
        for (p, &k) in self
            .puppet
            .mesh
            .positions
            .iter()
            .zip(self.puppet.joints.section_of())
        {
            if usize::from(k) == section {
                sum += *p;
                n += 1;
            }
        }
        let along = if n > 0 {
            sum / n as f64 - pivot
        } else {
            DVec3::ZERO
        };
        view.cross(along)
            .try_normalize()
            .filter(|_| {
                along
                    .normalize_or_zero()
                    .dot(view.normalize_or_zero())
                    .abs()
                    < 0.95
            })
            .unwrap_or(DVec3::Z)
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
