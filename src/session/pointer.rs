//! The mouse as the puppeteer uses it: a press on a section selects it and starts turning
//! it, a press on the background orbits, the right or middle button pans, with the cut
//! tool on a press on the model places the plane, with the brush on a drag on the model
//! paints, and with *move pivots* on a drag from a cut's pivot moves it (on the cut's
//! plane; anywhere facing the view with Shift or Ctrl). The window maps its events onto
//! [`Pointer`]; nothing here needs one.

use super::{Camera, Session};
use glam::{DQuat, Vec2, Vec4Swizzles};

/// A mouse button.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Button {
    /// The primary button: select, turn, orbit, place a cut.
    Left,
    /// Pans the view.
    Right,
    /// Pans the view.
    Middle,
}

/// What a held mouse button is doing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Drag {
    /// No button held (or one that does nothing).
    #[default]
    None,
    /// Turning the camera about its target.
    Orbit,
    /// Moving the camera's target in the view plane.
    Pan,
    /// Turning the selected sections.
    Rotate,
    /// Painting with the brush.
    Paint,
    /// Moving the pivot of this section's cut.
    Pivot(usize),
}

/// The mouse: where it is, what a held button is doing, and whether a modifier that
/// toggles the selection (Shift or Ctrl) is held.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pointer {
    /// Cursor position in pixels from the top left of the viewport.
    pub cursor: Vec2,
    /// What the held button does.
    pub drag: Drag,
    /// Shift or Ctrl is held: a click toggles a section in the selection, a pivot moves
    /// off its cut's plane.
    pub toggle: bool,
}

/// How near (pixels) a press must be to a pivot to grab it.
pub const PIVOT_REACH: f32 = 12.0;

impl Pointer {
    /// A button went down at the cursor. With no session (still loading) a left press
    /// orbits.
    pub fn press(
        &mut self,
        button: Button,
        session: Option<&mut Session>,
        camera: &Camera,
        viewport: Vec2,
    ) {
        self.drag = match (button, session) {
            (Button::Right | Button::Middle, _) => Drag::Pan,
            (Button::Left, None) => Drag::Orbit,
            (Button::Left, Some(s)) => {
                let (origin, dir) = camera.ray(self.cursor, viewport);
                let grabbed = if s.cut_tool.move_pivots {
                    s.pivot_near(self.cursor, camera, viewport)
                } else {
                    None
                };
                if let Some(k) = grabbed {
                    s.select(Some(k), false);
                    s.checkpoint();
                    self.drag = Drag::Pivot(k);
                    return;
                }
                match s.pick(origin, dir) {
                    Some(h) if s.paint_tool.active => {
                        s.checkpoint();
                        s.paint_at(h.point);
                        Drag::Paint
                    }
                    Some(h) if s.cut_tool.active => {
                        let right = camera.view().row(0).truncate().as_dvec3();
                        let section = s.section_at(&h);
                        s.place_draft(section, h.point.as_dvec3(), s.cut_tool.axis.normal(right));
                        Drag::None
                    }
                    Some(h) => {
                        let section = s.section_at(&h);
                        if !s.selection.contains(&section) || self.toggle {
                            s.select(Some(section), self.toggle);
                        }
                        s.checkpoint();
                        Drag::Rotate
                    }
                    None => {
                        if !self.toggle {
                            s.select(None, false);
                        }
                        Drag::Orbit
                    }
                }
            }
        };
    }

    /// The cursor moved to `at`: orbits, pans or turns the selection by the drag. Returns
    /// true when something changed (the view or the pose).
    pub fn moved(
        &mut self,
        at: Vec2,
        session: Option<&mut Session>,
        camera: &mut Camera,
        viewport: Vec2,
    ) -> bool {
        let delta = at - self.cursor;
        self.cursor = at;
        match self.drag {
            Drag::None => return false,
            Drag::Orbit => camera.orbit(delta),
            Drag::Pan => camera.pan(delta, viewport.y),
            Drag::Rotate => {
                if let Some(s) = session {
                    s.rotate_selected(trackball(camera, delta, viewport.y));
                }
            }
            Drag::Pivot(k) => {
                if let Some(s) = session {
                    let (origin, dir) = camera.ray(at, viewport);
                    s.drag_pivot(k, origin.as_dvec3(), dir.as_dvec3(), self.toggle);
                }
            }
            Drag::Paint => {
                if let Some(s) = session {
                    let (origin, dir) = camera.ray(at, viewport);
                    if let Some(h) = s.pick(origin, dir) {
                        s.paint_at(h.point);
                    }
                }
            }
        }
        true
    }

    /// The held button went up.
    pub fn release(&mut self) {
        self.drag = Drag::None;
    }
}

/// The world rotation for a drag of `delta` pixels: about the screen axis perpendicular to
/// the drag, by an angle proportional to its length (a full viewport height ≈ 180°), so the
/// side facing the viewer follows the mouse.
pub fn trackball(camera: &Camera, delta: Vec2, height: f32) -> DQuat {
    let view = camera.view();
    let right = view.row(0).xyz();
    let up = view.row(1).xyz();
    let axis = (up * delta.x + right * delta.y).normalize_or_zero();
    let angle = delta.length() / height.max(1.0) * std::f32::consts::PI;
    if axis == glam::Vec3::ZERO || !angle.is_finite() {
        return DQuat::IDENTITY;
    }
    DQuat::from_axis_angle(axis.as_dvec3(), angle as f64)
}
