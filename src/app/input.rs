//! Mouse state and the trackball mapping from a drag to a rotation.

use crate::render::Camera;
use glam::{DQuat, Vec2, Vec4Swizzles};

/// What a held mouse button is doing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Drag {
    #[default]
    None,
    Orbit,
    Pan,
    /// Turning the selected sections.
    Rotate,
}

#[derive(Default)]
pub struct Input {
    pub cursor: Vec2,
    pub drag: Drag,
    pub modifiers: winit::keyboard::ModifiersState,
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
