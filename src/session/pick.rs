//! Picking: a ray from the camera against the current (simulated) surface.

use super::Session;
use glam::Vec3;

/// Result of a ray cast against the current surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The triangle hit.
    pub triangle: usize,
    /// Vertex of the triangle nearest the hit point.
    pub vertex: usize,
    /// The hit point.
    pub point: Vec3,
    /// Distance along the ray.
    pub distance: f32,
}

impl Session {
    /// Casts a ray (unit `dir`) against the current (simulated) surface; the nearest hit in
    /// front of `origin`.
    pub fn pick(&self, origin: Vec3, dir: Vec3) -> Option<Hit> {
        let x = self.puppet.sim.positions();
        let mut best: Option<Hit> = None;
        for (t, tri) in self.puppet.mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| x.get(i as usize));
            if let Some(d) = ray_triangle(origin, dir, a, b, c) {
                if best.is_none_or(|h| d < h.distance) {
                    let p = origin + dir * d;
                    let vertex = *tri
                        .iter()
                        .min_by(|&&i, &&j| {
                            let di = (x.get(i as usize) - p).length_squared();
                            let dj = (x.get(j as usize) - p).length_squared();
                            di.total_cmp(&dj)
                        })
                        .unwrap_or(&tri[0]) as usize;
                    best = Some(Hit {
                        triangle: t,
                        vertex,
                        point: p,
                        distance: d,
                    });
                }
            }
        }
        best
    }

    /// Section of the vertex a hit landed nearest to.
    pub fn section_at(&self, hit: &Hit) -> usize {
        self.puppet.joints.section_of()[hit.vertex] as usize
    }
}

/// Distance along the unit `d` from `o` to the triangle, if hit in front.
fn ray_triangle(o: Vec3, d: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    let tri = [a.as_dvec3(), b.as_dvec3(), c.as_dvec3()];
    let t = crate::geom::bvh::intersect(&tri, o.as_dvec3(), d.as_dvec3())?;
    (t > 0.0).then_some(t as f32)
}
