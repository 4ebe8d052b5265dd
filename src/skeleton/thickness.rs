//! Stage 4: the thickness `t_i` along `−n_i` of every vertex, by rays cast in packets of
//! eight neighbours against a BVH, partly while the tetrahedralization runs; and the clamp
//! `d_i ≤ t_i / 2`.

use super::Tangent;
use crate::geom::bvh::{Bvh, Ray, PACKET};
use glam::DVec3;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

/// The thickness rays: the BVH, the order they are cast in, how far each looks in stage 1,
/// and what stage 1 measured. Packets are claimed in order by whichever thread is free
/// (the BVH's thread between its other jobs, the tetrahedralizing thread while it waits
/// for its other worker), so the measured ones are always a prefix of the order.
pub(super) struct Rays<'a> {
    bvh: Bvh,
    pts: &'a [DVec3],
    normals: &'a [DVec3],
    /// Hits closer than this are ignored.
    t_min: f64,
    /// The vertices in the BVH's leaf order: neighbours cast nearly the same rays.
    pub order: Vec<u32>,
    /// How far the ray of each vertex looks in stage 1 (twice a bound on `d`, by
    /// [`ring_bounds`]); everywhere infinite without it.
    reach: Option<Vec<f64>>,
    /// The next packet to claim.
    next: AtomicUsize,
    /// The thickness of `order[k]` as `f64` bits, for `k` below [`Rays::measured`].
    thickness: Vec<AtomicU64>,
}

impl<'a> Rays<'a> {
    pub fn new(
        bvh: Bvh,
        pts: &'a [DVec3],
        normals: &'a [DVec3],
        t_min: f64,
        reach: Option<Vec<f64>>,
    ) -> Self {
        // Rays in a spatially coherent order share the nodes they visit.
        let order = bvh.vertex_order(pts.len());
        let thickness = order.iter().map(|_| AtomicU64::new(0)).collect();
        Rays {
            bvh,
            pts,
            normals,
            t_min,
            order,
            reach,
            next: AtomicUsize::new(0),
            thickness,
        }
    }

    /// How far stage 1 looks from vertex `v`.
    pub fn reach(&self, v: u32) -> f64 {
        self.reach.as_ref().map_or(f64::INFINITY, |r| r[v as usize])
    }

    /// Claims the next packet and measures it up to its reach; false when none is left.
    pub fn cast_next(&self) -> bool {
        let n = self.order.len();
        let k = self.next.fetch_add(1, Ordering::Relaxed) * PACKET;
        if k >= n {
            return false;
        }
        let verts = &self.order[k..(k + PACKET).min(n)];
        let mut far = [0.0; PACKET];
        for (f, &v) in far.iter_mut().zip(verts) {
            *f = self.reach(v);
        }
        let m = verts.len();
        let mut th = [f64::INFINITY; PACKET];
        self.cast(verts, &far[..m], &mut th[..m]);
        for (slot, t) in self.thickness[k..k + m].iter().zip(th) {
            slot.store(t.to_bits(), Ordering::Relaxed);
        }
        true
    }

    /// How many vertices (a prefix of the order) stage 1 measured. Only once no thread
    /// casts any more (every claimed packet is then finished).
    pub fn measured(&self) -> usize {
        (self.next.load(Ordering::Relaxed) * PACKET).min(self.order.len())
    }

    /// The thickness stage 1 measured for `order[k]`, `k` below [`Rays::measured`].
    pub fn known(&self, k: usize) -> f64 {
        f64::from_bits(self.thickness[k].load(Ordering::Relaxed))
    }

    /// The thickness along `−n` of each of `verts` (at most [`PACKET`], neighbours in the
    /// order), looking as far as `far` (no cast where that is 0: `th` is kept): one packet
    /// of rays, each ignoring its own vertex's triangles. Infinite where nothing is hit.
    pub fn cast(&self, verts: &[u32], far: &[f64], th: &mut [f64]) {
        let mut rays = [Ray {
            origin: DVec3::ZERO,
            dir: DVec3::ZERO,
            t_min: self.t_min,
            t_max: 0.0,
            skip_vertex: u32::MAX,
        }; PACKET];
        let mut lane = [0; PACKET];
        let mut m = 0;
        for (j, (&v, &f)) in verts.iter().zip(far).enumerate() {
            if f > 0.0 {
                let i = v as usize;
                rays[m] = Ray {
                    origin: self.pts[i],
                    dir: -self.normals[i],
                    t_min: self.t_min,
                    t_max: f,
                    skip_vertex: v,
                };
                lane[m] = j;
                m += 1;
            }
        }
        if m == 0 {
            return;
        }
        let hits = self.bvh.cast_packet(&rays[..m]);
        for (&j, hit) in lane[..m].iter().zip(hits) {
            th[j] = hit.map_or(f64::INFINITY, |h| h.t);
        }
    }
}

/// For every vertex, twice an upper bound on its shrinking-ball radius, slightly widened:
/// the ball is empty of every vertex, so it is no larger than the ball that any one vertex
/// limits, here its mesh neighbours (infinite where none lies on the inner side). It is
/// usually close to the radius, so a thickness ray cast before the radius is known can stop
/// there instead of crossing the model. Calls `poll()` every few thousand triangles.
pub(super) fn ring_bounds(
    pts: &[DVec3],
    tangents: &[Tangent],
    triangles: &[[u32; 3]],
    poll: &dyn Fn(),
) -> Vec<f64> {
    let mut bound: Vec<f64> = tangents.iter().map(|t| t.start).collect();
    for chunk in triangles.chunks(4096) {
        poll();
        for tri in chunk {
            for k in 0..3 {
                let a = tri[k] as usize;
                for q in [tri[(k + 1) % 3], tri[(k + 2) % 3]] {
                    tangents[a].lower(&mut bound[a], pts[a], pts[q as usize], || true);
                }
            }
        }
    }
    // The radius's own expression, but the radius may come from another neighbour that
    // rounds differently: a margin far above rounding keeps the bound safe.
    for b in &mut bound {
        *b *= 2.0 * (1.0 + 1e-9);
    }
    bound
}

/// Limits `d` to half the thickness `th` (skipping `d = 0`, the fallback); true when that
/// was a real correction, not a rounding-level one (a sphere's centre is at exactly half
/// the thickness).
pub(super) fn clamp(d: &mut f64, th: f64) -> bool {
    if *d == 0.0 || th * 0.5 >= *d {
        return false;
    }
    let significant = th * 0.5 < *d * 0.99;
    *d = th * 0.5;
    significant
}
