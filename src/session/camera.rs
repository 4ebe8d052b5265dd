//! The orbit camera: yaw and pitch about a target, a distance, perspective projection with
//! wgpu's 0..1 depth range, and rays through the cursor for picking.

use glam::{Mat4, Vec2, Vec3, Vec4Swizzles};

/// An orbit camera looking at `target` from `distance` away.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The point looked at (and orbited about).
    pub target: Vec3,
    /// Radians about +y.
    pub yaw: f32,
    /// Radians above the horizon, kept inside ±89°.
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
    /// Vertical field of view in radians.
    pub fov_y: f32,
    /// The world's up (the mesh's: +y unless it is modelled otherwise); yaw turns about
    /// it and pitch rises towards it.
    pub up: Vec3,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            target: Vec3::ZERO,
            yaw: -2.2,
            pitch: 0.25,
            distance: 3.0,
            fov_y: 40f32.to_radians(),
            up: Vec3::Y,
        }
    }
}

const PITCH_LIMIT: f32 = 1.55;

impl Camera {
    /// Frames a bounding box: target at its centre, the whole box in view.
    pub fn frame(&mut self, lo: Vec3, hi: Vec3) {
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        self.target = (lo + hi) * 0.5;
        self.distance = radius / (self.fov_y * 0.5).sin() * 1.05;
    }

    /// Camera position.
    pub fn eye(&self) -> Vec3 {
        let dir = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        self.target + self.tilt() * dir * self.distance
    }

    /// The rotation from +y up to the world's up (+z up: the front view looks along +y,
    /// at a character facing −y, Blender's front).
    fn tilt(&self) -> glam::Quat {
        glam::Quat::from_rotation_arc(Vec3::Y, self.up.try_normalize().unwrap_or(Vec3::Y))
    }

    /// The view matrix (world to camera).
    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, self.tilt() * Vec3::Y)
    }

    /// The perspective projection for a viewport of `aspect` = width / height.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let near = (self.distance * 0.01).max(1e-6);
        let far = self.distance * 100.0 + 1.0;
        // wgpu: depth 0..1, NDC y up (the "directx" convention).
        glam::camera::rh::proj::directx::perspective(self.fov_y, aspect.max(1e-3), near, far)
    }

    /// Projection times view.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// Turns the camera by a mouse drag of `delta` pixels.
    pub fn orbit(&mut self, delta: Vec2) {
        self.yaw -= delta.x * 0.008;
        self.pitch = (self.pitch + delta.y * 0.008).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Moves the target in the view plane by a drag of `delta` pixels in a viewport
    /// `height` pixels tall (the point under the cursor follows it).
    pub fn pan(&mut self, delta: Vec2, height: f32) {
        let view = self.view();
        let right = view.row(0).xyz();
        let up = view.row(1).xyz();
        let scale = 2.0 * self.distance * (self.fov_y * 0.5).tan() / height.max(1.0);
        self.target += (-right * delta.x + up * delta.y) * scale;
    }

    /// Zooms by `steps` wheel notches (positive: closer).
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * 0.9f32.powf(steps)).clamp(1e-4, 1e6);
    }

    /// The ray through a pixel (`cursor` in pixels from the top left of a `size` viewport):
    /// origin and unit direction.
    pub fn ray(&self, cursor: Vec2, size: Vec2) -> (Vec3, Vec3) {
        let ndc = Vec2::new(
            2.0 * cursor.x / size.x.max(1.0) - 1.0,
            1.0 - 2.0 * cursor.y / size.y.max(1.0),
        );
        let inv = self.view_proj(size.x / size.y.max(1.0)).inverse();
        let near = inv.project_point3(ndc.extend(0.0));
        let far = inv.project_point3(ndc.extend(1.0));
        (near, (far - near).normalize_or_zero())
    }

    /// Pixel position of a world point (`None` behind the camera).
    pub fn project(&self, p: Vec3, size: Vec2) -> Option<Vec2> {
        let clip = self.view_proj(size.x / size.y.max(1.0)) * p.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.xy() / clip.w;
        Some(Vec2::new(
            (ndc.x + 1.0) * 0.5 * size.x,
            (1.0 - ndc.y) * 0.5 * size.y,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ray_through_a_projected_point_hits_it() {
        let mut c = Camera::default();
        c.frame(Vec3::splat(-1.0), Vec3::splat(1.0));
        let size = Vec2::new(800.0, 600.0);
        let p = Vec3::new(0.3, -0.2, 0.5);
        let px = c.project(p, size).unwrap();
        let (o, d) = c.ray(px, size);
        let closest = o + d * (p - o).dot(d);
        assert!((closest - p).length() < 1e-4);
        // The centre pixel looks at the target.
        let (o, d) = c.ray(size * 0.5, size);
        assert!((o + d * (c.target - o).dot(d) - c.target).length() < 1e-4);
    }

    #[test]
    fn orbit_keeps_the_pitch_inside_the_poles() {
        let mut c = Camera::default();
        c.orbit(Vec2::new(0.0, 1e6));
        assert!(c.pitch <= PITCH_LIMIT);
        assert!(c.eye().is_finite());
    }
}
