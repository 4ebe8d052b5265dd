//! The window test's synthetic drag (`--drive-test`): press on the section under the
//! window's centre column, move, release, all through the same handlers as the mouse.

use super::WindowState;
use crate::session::pointer::Button;
use glam::Vec2;

impl WindowState {
    /// One event of the synthetic drag per frame, once the puppet is built.
    pub fn drive_test(&mut self) {
        let Some(k) = self.hooks.drive else {
            return;
        };
        let Some(s) = &self.session else {
            return;
        };
        let size = self.viewport();
        // Aim at the pivot of the last section, or the model centre.
        let target = match s.puppet.joints.sections().len() {
            1 => s.puppet.sim.positions().get(0),
            n => s.pivot_world(n - 1).as_vec3(),
        };
        let Some(at) = self.camera.project(target, size) else {
            self.hooks.drive = None;
            return;
        };
        match k {
            0 => {
                self.cursor_moved(at);
                self.mouse_button(Button::Left, true);
            }
            1..=10 => self.cursor_moved(self.pointer.cursor + Vec2::new(0.0, 9.0)),
            11 => self.mouse_button(Button::Left, false),
            _ => {
                self.hooks.drive = None;
                return;
            }
        }
        self.hooks.drive = Some(k + 1);
    }
}
