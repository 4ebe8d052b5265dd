//! A bounding volume hierarchy over triangles for nearest-hit ray casts (median split on the
//! widest centroid axis, flattened depth-first, leaves of at most four triangles).

use glam::DVec3;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: first triangle in `order`; inner: index of the second child (first is next).
    start: u32,
    /// Leaf: number of triangles (> 0); inner: 0.
    count: u32,
}

/// BVH over a triangle soup (positions are copied, so the BVH owns its data).
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
    tris: Vec<[DVec3; 3]>,
    ids: Vec<[u32; 3]>,
}

/// A ray hit: distance along the (unit or not) direction and the triangle index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f64,
    pub triangle: u32,
}

impl Bvh {
    /// Builds the hierarchy for `triangles` over `positions`.
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let tris: Vec<[DVec3; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| positions[i as usize]))
            .collect();
        let centroids: Vec<DVec3> = tris.iter().map(|t| (t[0] + t[1] + t[2]) / 3.0).collect();
        let mut order: Vec<u32> = (0..tris.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * tris.len() / 3 + 1);
        if !tris.is_empty() {
            build(&mut nodes, &mut order, 0, &tris, &centroids);
        }
        Bvh {
            nodes,
            order,
            tris,
            ids: triangles.to_vec(),
        }
    }

    /// Nearest hit with `t > t_min`, skipping triangles for which `skip(vertex ids)` holds.
    pub fn cast(
        &self,
        origin: DVec3,
        dir: DVec3,
        t_min: f64,
        skip: impl Fn(&[u32; 3]) -> bool,
    ) -> Option<Hit> {
        self.cast_within(origin, dir, t_min, f64::INFINITY, skip)
    }

    /// As [`Bvh::cast`], but only hits with `t < t_max` count: a segment query, which prunes
    /// every node beyond `t_max` and is much cheaper when `t_max` is local.
    pub fn cast_within(
        &self,
        origin: DVec3,
        dir: DVec3,
        t_min: f64,
        t_max: f64,
        skip: impl Fn(&[u32; 3]) -> bool,
    ) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = dir.recip();
        let mut best = Hit {
            t: t_max,
            triangle: u32::MAX,
        };
        let mut stack = [0u32; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let idx = stack[sp] as usize;
            let node = &self.nodes[idx];
            if slab(node, origin, inv) >= best.t {
                continue;
            }
            if node.count > 0 {
                let s = node.start as usize;
                for &ti in &self.order[s..s + node.count as usize] {
                    if skip(&self.ids[ti as usize]) {
                        continue;
                    }
                    if let Some(t) = intersect(&self.tris[ti as usize], origin, dir) {
                        if t > t_min && t < best.t {
                            best = Hit { t, triangle: ti };
                        }
                    }
                }
            } else {
                // Depth is at most log2(n) + 1 < 63, so two more slots always fit.
                let (l, r) = (idx as u32 + 1, node.start);
                let tl = slab(&self.nodes[l as usize], origin, inv);
                let tr = slab(&self.nodes[r as usize], origin, inv);
                let (near, far, tn, tf) = if tl <= tr {
                    (l, r, tl, tr)
                } else {
                    (r, l, tr, tl)
                };
                if tf < best.t {
                    stack[sp] = far;
                    sp += 1;
                }
                if tn < best.t {
                    stack[sp] = near;
                    sp += 1;
                }
            }
        }
        (best.triangle != u32::MAX).then_some(best)
    }
}

/// Entry distance of the ray into a node's box, `INFINITY` when missed.
#[inline]
fn slab(node: &Node, origin: DVec3, inv: DVec3) -> f64 {
    let t0 = (node.lo - origin) * inv;
    let t1 = (node.hi - origin) * inv;
    let tmin = t0.min(t1);
    let tmax = t0.max(t1);
    // 0 * inf gives NaN for rays parallel to a slab through its plane: ignore that axis.
    let enter = fmax(fmax(tmin.x, tmin.y), fmax(tmin.z, 0.0));
    let exit = fmin(fmin(tmax.x, tmax.y), tmax.z);
    if enter <= exit {
        enter
    } else {
        f64::INFINITY
    }
}

#[inline]
fn fmax(a: f64, b: f64) -> f64 {
    if a > b || b.is_nan() {
        a
    } else {
        b
    }
}

#[inline]
fn fmin(a: f64, b: f64) -> f64 {
    if a < b || b.is_nan() {
        a
    } else {
        b
    }
}

/// Möller–Trumbore, both sides; returns the ray parameter of the hit (may be negative:
/// callers keep the range they need).
#[inline]
pub fn intersect(tri: &[DVec3; 3], origin: DVec3, dir: DVec3) -> Option<f64> {
    let e1 = tri[1] - tri[0];
    let e2 = tri[2] - tri[0];
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - tri[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(e2.dot(q) * inv)
}

fn build(
    nodes: &mut Vec<Node>,
    order: &mut [u32],
    offset: u32,
    tris: &[[DVec3; 3]],
    centroids: &[DVec3],
) -> usize {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let (mut clo, mut chi) = (lo, hi);
    for &i in order.iter() {
        for p in tris[i as usize] {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let c = centroids[i as usize];
        clo = clo.min(c);
        chi = chi.max(c);
    }
    let me = nodes.len();
    nodes.push(Node {
        lo,
        hi,
        start: offset,
        count: order.len() as u32,
    });
    let ext = chi - clo;
    if order.len() <= 4 || ext.max_element() == 0.0 {
        return me;
    }
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |a, b| {
        centroids[*a as usize][axis].total_cmp(&centroids[*b as usize][axis])
    });
    let (left, right) = order.split_at_mut(mid);
    build(nodes, left, offset, tris, centroids);
    let r = build(nodes, right, offset + mid as u32, tris, centroids);
    nodes[me].start = r as u32;
    nodes[me].count = 0;
    me
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn ray_through_sphere_hits_far_side() {
        let m = shapes::icosphere(1.0, 3);
        let bvh = Bvh::new(&m.positions, &m.triangles);
        let hit = bvh
            .cast(DVec3::new(0.01, 0.02, 0.0), DVec3::X, 0.0, |_| false)
            .unwrap();
        assert!((hit.t - 0.99).abs() < 0.02, "t = {}", hit.t);
        let from_out = bvh
            .cast(DVec3::new(-3.0, 0.01, 0.02), DVec3::X, 0.0, |_| false)
            .unwrap();
        assert!((from_out.t - 2.0).abs() < 0.02);
        assert!(bvh
            .cast(DVec3::new(-3.0, 5.0, 0.0), DVec3::X, 0.0, |_| false)
            .is_none());
    }
}
