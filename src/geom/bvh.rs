//! A bounding volume hierarchy over triangles for nearest-hit ray casts (median split on the
//! widest centroid axis, flattened depth-first, leaves of at most four triangles stored
//! contiguously, boxes fitted bottom-up). Casts keep each pushed node's entry distance, so
//! no box is tested twice, and the slab test is conservative: a ray through a box's corner
//! or along its face still enters it.

use super::{max2, min2};
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
///
/// The vertices are renumbered in the order their triangles first appear in the leaves,
/// and their positions copied in that order: a leaf's corners lie close together in
/// memory, as with a copy of each triangle's corners, in a third of the memory (fresh
/// memory is slow to fault in).
pub struct Bvh {
    nodes: Vec<Node>,
    /// Input index of each triangle, in leaf order.
    order: Vec<u32>,
    /// Corners of each triangle as local vertex numbers, in leaf order (a leaf's
    /// triangles are contiguous).
    tris: Vec<[u32; 3]>,
    /// Position and input id of each local vertex.
    verts: Vec<DVec3>,
    input: Vec<u32>,
    /// Local number of each input vertex (`NO_VERTEX` for those of no triangle).
    local: Vec<u32>,
}

/// See [`Bvh::local`].
const NO_VERTEX: u32 = u32::MAX;

/// A ray hit: distance along the (unit or not) direction and the triangle index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the direction, in units of its length.
    pub t: f64,
    /// Index of the triangle hit.
    pub triangle: u32,
}

impl Bvh {
    /// Builds the hierarchy for `triangles` over `positions`.
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        Self::with_poll(positions, triangles, &|| {})
    }

    /// As [`Bvh::new`], calling `poll()` every few thousand triangles of the splitting and
    /// copying (most of the work), so that a caller sharing the thread can run more urgent
    /// work in between (the skeleton runs the tetrahedralization's second worker there).
    pub fn with_poll(positions: &[DVec3], triangles: &[[u32; 3]], poll: &dyn Fn()) -> Self {
        // Splits look only at centroids, kept small and contiguous (`f32` is plenty to
        // choose a split: the boxes themselves are exact, computed bottom-up from the
        // triangles).
        let mut prims: Vec<Prim> = triangles
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let c = (positions[t[0] as usize]
                    + positions[t[1] as usize]
                    + positions[t[2] as usize])
                    / 3.0;
                Prim {
                    c: c.as_vec3().to_array(),
                    i: i as u32,
                }
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * triangles.len() / 3 + 1);
        let mut bvh = Bvh {
            nodes: Vec::new(),
            order: Vec::new(),
            tris: Vec::with_capacity(triangles.len()),
            verts: Vec::new(),
            input: Vec::new(),
            local: vec![NO_VERTEX; positions.len()],
        };
        if !triangles.is_empty() {
            build(&mut nodes, &mut prims, 0, poll);
            bvh.order = prims.iter().map(|p| p.i).collect();
            drop(prims);
            let Bvh {
                order,
                tris,
                input,
                local,
                ..
            } = &mut bvh;
            for chunk in order.chunks(POLL_EVERY) {
                poll();
                tris.extend(chunk.iter().map(|&i| {
                    triangles[i as usize].map(|v| {
                        let l = &mut local[v as usize];
                        if *l == NO_VERTEX {
                            *l = input.len() as u32;
                            input.push(v);
                        }
                        *l
                    })
                }));
            }
            bvh.verts = bvh.input.iter().map(|&v| positions[v as usize]).collect();
            fit(&mut nodes, 0, &bvh);
        }
        bvh.nodes = nodes;
        bvh
    }

    /// The corners of the triangle in leaf slot `k`.
    #[inline(always)]
    fn corners(&self, k: usize) -> [DVec3; 3] {
        self.tris[k].map(|l| self.verts[l as usize])
    }

    /// The `n` vertices in the order their triangles first appear in the leaves, vertices of
    /// no triangle last: spatially coherent, so consecutive casts from them visit the same
    /// nodes (input order often is not coherent).
    pub fn vertex_order(&self, n: usize) -> Vec<u32> {
        let mut order = Vec::with_capacity(n);
        order.extend_from_slice(&self.input);
        let unused = |v: &u32| self.local.get(*v as usize).is_none_or(|&l| l == NO_VERTEX);
        order.extend((0..n as u32).filter(unused));
        order
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
        // Most rays have no zero direction component: their slab tests need no NaN care.
        let inv = dir.recip();
        if inv.is_finite() {
            self.traverse::<false>(origin, dir, inv, t_min, t_max, skip)
        } else {
            self.traverse::<true>(origin, dir, inv, t_min, t_max, skip)
        }
    }

    /// [`Bvh::cast_within`] with the slab test for an infinite component of `inv = 1 / dir`
    /// or not.
    fn traverse<const AXIAL: bool>(
        &self,
        origin: DVec3,
        dir: DVec3,
        inv: DVec3,
        t_min: f64,
        t_max: f64,
        skip: impl Fn(&[u32; 3]) -> bool,
    ) -> Option<Hit> {
        let best = Hit {
            t: t_max,
            triangle: u32::MAX,
        };
        // `traverse_from` sees local numbers; `skip` takes input ids.
        let skip = |t: &[u32; 3]| skip(&t.map(|l| self.input[l as usize]));
        let best = self.traverse_from::<AXIAL>(0, origin, dir, inv, t_min, best, skip);
        (best.triangle != u32::MAX).then_some(best)
    }

    /// As [`Bvh::traverse`], from node `start`, with `best` what an earlier part of the
    /// traversal found, and `skip` given the local vertex numbers.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn traverse_from<const AXIAL: bool>(
        &self,
        start: u32,
        origin: DVec3,
        dir: DVec3,
        inv: DVec3,
        t_min: f64,
        mut best: Hit,
        skip: impl Fn(&[u32; 3]) -> bool,
    ) -> Hit {
        // Nodes to visit with their entry distances (compared again when popped: the best
        // hit may have come closer since).
        let mut stack = [(0u32, 0.0f64); 64];
        stack[0] = (
            start,
            slab::<AXIAL>(&self.nodes[start as usize], origin, inv),
        );
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (idx, enter) = stack[sp];
            if enter >= best.t {
                continue;
            }
            let node = &self.nodes[idx as usize];
            if node.count > 0 {
                let s = node.start as usize;
                for k in s..s + node.count as usize {
                    if skip(&self.tris[k]) {
                        continue;
                    }
                    if let Some(t) = intersect(&self.corners(k), origin, dir) {
                        if t > t_min && t < best.t {
                            best = Hit {
                                t,
                                triangle: self.order[k],
                            };
                        }
                    }
                }
            } else {
                // Depth is at most log2(n) + 1 < 63, so two more slots always fit.
                let (l, r) = (idx + 1, node.start);
                let tl = slab::<AXIAL>(&self.nodes[l as usize], origin, inv);
                let tr = slab::<AXIAL>(&self.nodes[r as usize], origin, inv);
                let (near, far, tn, tf) = if tl <= tr {
                    (l, r, tl, tr)
                } else {
                    (r, l, tr, tl)
                };
                if tf < best.t {
                    stack[sp] = (far, tf);
                    sp += 1;
                }
                if tn < best.t {
                    stack[sp] = (near, tn);
                    sp += 1;
                }
            }
        }
        best
    }
}

/// One ray of a packet ([`Bvh::cast_packet`]): hits with `t_min < t < t_max` count, except on
/// triangles having `skip_vertex` as a corner.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Where it starts.
    pub origin: DVec3,
    /// Its direction (any length: distances are in its units).
    pub dir: DVec3,
    /// Hits at or before this distance are ignored.
    pub t_min: f64,
    /// Hits at or beyond this distance are ignored.
    pub t_max: f64,
    /// Triangles with this vertex as a corner are ignored (the ray's own vertex).
    pub skip_vertex: u32,
}

/// Most rays per packet.
pub const PACKET: usize = 8;

/// A node that only this many of a packet's rays enter is finished by the one-ray
/// traversal, which tests a box more cheaply than a packet tests all its lanes.
const SOLO: u32 = 1;

impl Bvh {
    /// The nearest hit of each of up to [`PACKET`] rays, as [`Bvh::cast_within`] would find
    /// it, in one traversal: a node is visited once for all the rays that enter its box,
    /// and its box is tested on all lanes at once. Worth it for coherent rays (nearby
    /// origins and directions), which visit nearly the same nodes. Compiled for AVX2 as
    /// well, used where the CPU has it (four lanes per instruction instead of two; the same
    /// IEEE operations, so the same results).
    ///
    /// # Panics
    /// When `rays` holds more than [`PACKET`] rays.
    pub fn cast_packet(&self, rays: &[Ray]) -> [Option<Hit>; PACKET] {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2.
            return unsafe { self.cast_packet_avx2(rays) };
        }
        self.cast_packet_impl(rays)
    }

    /// # Safety
    /// The CPU has AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn cast_packet_avx2(&self, rays: &[Ray]) -> [Option<Hit>; PACKET] {
        self.cast_packet_impl(rays)
    }

    #[inline(always)]
    fn cast_packet_impl(&self, rays: &[Ray]) -> [Option<Hit>; PACKET] {
        assert!(rays.len() <= PACKET, "at most {PACKET} rays per packet");
        let mut out = [None; PACKET];
        if self.nodes.is_empty() {
            return out;
        }
        // Lanes as arrays (so the box test runs on all of them at once); an empty lane has
        // `best = −∞` and enters no box.
        let mut o = [[0.0; PACKET]; 3];
        let mut inv = [[0.0; PACKET]; 3];
        let mut best = [f64::NEG_INFINITY; PACKET];
        let mut tri = [u32::MAX; PACKET];
        // The local number of each ray's skipped vertex.
        let mut skip = [NO_VERTEX; PACKET];
        for (r, ray) in rays.iter().enumerate() {
            skip[r] = self
                .local
                .get(ray.skip_vertex as usize)
                .copied()
                .unwrap_or(NO_VERTEX);
            let i = ray.dir.recip();
            if i.is_finite() {
                for k in 0..3 {
                    o[k][r] = ray.origin[k];
                    inv[k][r] = i[k];
                }
                best[r] = ray.t_max;
            } else {
                let skip = |t: &[u32; 3]| t.contains(&ray.skip_vertex);
                out[r] = self.cast_within(ray.origin, ray.dir, ray.t_min, ray.t_max, skip);
            }
        }
        let enters = |node: &Node, best: &[f64; PACKET]| enters(node, &o, &inv, best);
        let mut stack = [(0u32, 0u32); 64];
        let mut sp = 0;
        let root = enters(&self.nodes[0], &best);
        if root != 0 {
            stack[0] = (0, root);
            sp = 1;
        }
        while sp > 0 {
            sp -= 1;
            let (idx, mask) = stack[sp];
            if mask.count_ones() <= SOLO {
                let mut m = mask;
                while m != 0 {
                    let r = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let ray = &rays[r];
                    let i = DVec3::new(inv[0][r], inv[1][r], inv[2][r]);
                    let skip = |t: &[u32; 3]| t.contains(&skip[r]);
                    let b = Hit {
                        t: best[r],
                        triangle: tri[r],
                    };
                    let b = self
                        .traverse_from::<false>(idx, ray.origin, ray.dir, i, ray.t_min, b, skip);
                    best[r] = b.t;
                    tri[r] = b.triangle;
                }
                continue;
            }
            let node = &self.nodes[idx as usize];
            if node.count > 0 {
                let s = node.start as usize;
                for k in s..s + node.count as usize {
                    let ids = &self.tris[k];
                    let corners = self.corners(k);
                    let mut m = mask;
                    while m != 0 {
                        let r = m.trailing_zeros() as usize;
                        m &= m - 1;
                        let ray = &rays[r];
                        if ids.contains(&skip[r]) {
                            continue;
                        }
                        if let Some(t) = intersect(&corners, ray.origin, ray.dir) {
                            if t > ray.t_min && t < best[r] {
                                best[r] = t;
                                tri[r] = self.order[k];
                            }
                        }
                    }
                }
            } else {
                let (l, r) = (idx + 1, node.start);
                let ml = enters(&self.nodes[l as usize], &best) & mask;
                let mr = enters(&self.nodes[r as usize], &best) & mask;
                if mr != 0 {
                    stack[sp] = (r, mr);
                    sp += 1;
                }
                if ml != 0 {
                    stack[sp] = (l, ml);
                    sp += 1;
                }
            }
        }
        for r in 0..rays.len() {
            if tri[r] != u32::MAX {
                out[r] = Some(Hit {
                    t: best[r],
                    triangle: tri[r],
                });
            }
        }
        out
    }
}

/// Which lanes of a packet enter `node`'s box before their best hit (a bit per lane).
#[inline(always)]
fn enters(
    node: &Node,
    o: &[[f64; PACKET]; 3],
    inv: &[[f64; PACKET]; 3],
    best: &[f64; PACKET],
) -> u32 {
    let (lo, hi) = (node.lo.to_array(), node.hi.to_array());
    let mut enter = [0.0f64; PACKET];
    let mut exit = [f64::INFINITY; PACKET];
    for k in 0..3 {
        for r in 0..PACKET {
            let t0 = (lo[k] - o[k][r]) * inv[k][r];
            let t1 = (hi[k] - o[k][r]) * inv[k][r];
            enter[r] = max2(enter[r], min2(t0, t1));
            exit[r] = min2(exit[r], max2(t0, t1));
        }
    }
    let mut m = 0;
    for r in 0..PACKET {
        let hit = enter[r] <= exit[r] * (1.0 + 1e-15) && enter[r] < best[r];
        m |= u32::from(hit) << r;
    }
    m
}

/// Entry distance of the ray into a node's box, `INFINITY` when missed. Conservative: a
/// box the ray only grazes counts as hit.
///
/// `AXIAL`: some component of `inv` is infinite (a zero direction component). The slab then
/// gives ±∞ when the origin's coordinate is outside it, and NaN (0 · ∞) when the origin
/// lies in one of its planes, where the whole line lies in the closed slab: NaN means
/// unbounded. Without `AXIAL` no NaN can arise.
#[inline]
fn slab<const AXIAL: bool>(node: &Node, origin: DVec3, inv: DVec3) -> f64 {
    let mut t0 = (node.lo - origin) * inv;
    let mut t1 = (node.hi - origin) * inv;
    let (mut u0, mut u1) = (t0, t1);
    if AXIAL {
        let (n0, n1) = (t0.is_nan_mask(), t1.is_nan_mask());
        t0 = DVec3::select(n0, DVec3::NEG_INFINITY, t0);
        t1 = DVec3::select(n1, DVec3::NEG_INFINITY, t1);
        u0 = DVec3::select(n0, DVec3::INFINITY, u0);
        u1 = DVec3::select(n1, DVec3::INFINITY, u1);
    }
    // No NaN is left: plain comparisons (a third of the box test was `f64::min`'s NaN
    // handling).
    let (min, max) = (min2::<f64>, max2::<f64>);
    let tmin = [min(t0.x, t1.x), min(t0.y, t1.y), min(t0.z, t1.z)];
    let tmax = [max(u0.x, u1.x), max(u0.y, u1.y), max(u0.z, u1.z)];
    let enter = max(max(tmin[0], tmin[1]), max(tmin[2], 0.0));
    // Widened by a few ulps, the rounding of the products above: a ray through a corner or
    // an edge of the box (a vertex of the mesh) must not miss it.
    let exit = min(min(tmax[0], tmax[1]), tmax[2]) * (1.0 + 1e-15);
    if enter <= exit {
        enter
    } else {
        f64::INFINITY
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

/// Triangles of work between two calls of the `poll` of [`Bvh::with_poll`].
const POLL_EVERY: usize = 4096;

/// A triangle while building: its centroid and input index.
#[derive(Clone, Copy)]
struct Prim {
    c: [f32; 3],
    i: u32,
}

/// Splits `prims` (placed from `offset` on in the final order) at the median centroid along
/// the widest axis of the centroids, down to leaves of at most four; returns the node's
/// index. The boxes are left for [`fit`].
fn build(nodes: &mut Vec<Node>, prims: &mut [Prim], offset: u32, poll: &dyn Fn()) -> usize {
    let me = nodes.len();
    nodes.push(Node {
        lo: DVec3::ZERO,
        hi: DVec3::ZERO,
        start: offset,
        count: prims.len() as u32,
    });
    if prims.len() <= 4 {
        return me;
    }
    if prims.len() >= POLL_EVERY {
        poll();
    }
    // No centroid is NaN (those of finite positions may only overflow to ±∞ in `f32`).
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in prims.iter() {
        for k in 0..3 {
            lo[k] = min2(lo[k], p.c[k]);
            hi[k] = max2(hi[k], p.c[k]);
        }
    }
    let ext = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    if ext.iter().all(|&e| e <= 0.0) {
        return me;
    }
    let axis = if ext[0] >= ext[1] && ext[0] >= ext[2] {
        0
    } else if ext[1] >= ext[2] {
        1
    } else {
        2
    };
    let mid = prims.len() / 2;
    prims.select_nth_unstable_by(mid, |a, b| a.c[axis].total_cmp(&b.c[axis]));
    let (left, right) = prims.split_at_mut(mid);
    build(nodes, left, offset, poll);
    let r = build(nodes, right, offset + mid as u32, poll);
    nodes[me].start = r as u32;
    nodes[me].count = 0;
    me
}

/// Sets the boxes of the subtree at `idx` from the triangles of `bvh`, bottom-up; returns
/// the subtree's box.
fn fit(nodes: &mut [Node], idx: usize, bvh: &Bvh) -> (DVec3, DVec3) {
    let node = nodes[idx];
    let (lo, hi) = if node.count > 0 {
        let s = node.start as usize;
        (s..s + node.count as usize)
            .flat_map(|k| bvh.corners(k))
            .fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(p), hi.max(p)),
            )
    } else {
        let (al, ah) = fit(nodes, idx + 1, bvh);
        let (bl, bh) = fit(nodes, node.start as usize, bvh);
        (al.min(bl), ah.max(bh))
    };
    nodes[idx].lo = lo;
    nodes[idx].hi = hi;
    (lo, hi)
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

    /// Every vertex once, those of the first leaf triangle first, unused ones last.
    #[test]
    fn vertex_order_is_a_permutation_led_by_the_first_leaf() {
        let m = shapes::icosphere(1.0, 3);
        let n = m.positions.len();
        let bvh = Bvh::new(&m.positions, &m.triangles);
        // Two extra vertices that no triangle uses come last.
        let order = bvh.vertex_order(n + 2);
        assert_eq!(&order[n..], &[n as u32, n as u32 + 1]);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n as u32 + 2).collect::<Vec<_>>());
        assert_eq!(&order[..3], &m.triangles[bvh.order[0] as usize]);
    }

    /// A cube grid (axis-aligned faces) and an icosphere with randomly scaled radii.
    fn test_meshes(seed: u64) -> [crate::mesh::Mesh; 2] {
        let mut bumpy = shapes::icosphere(1.0, 3);
        let mut rng = crate::random::SplitMix(seed);
        let mut unit = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        for p in &mut bumpy.positions {
            *p *= 1.0 + 0.2 * unit();
        }
        [shapes::cube_grid(1.0, 4), bumpy]
    }

    /// The nearest hit over the hierarchy is the nearest over all triangles, for unbounded
    /// rays and segments, on a cube grid (axis-aligned faces, rays parallel to them and
    /// running in their planes: the slab test's 0 × ∞ case) and on a bumpy sphere.
    /// Regression: a ray lying in a plane of a box's face used to miss the box (NaN taken
    /// as a bound), so a ray along a grid line of a cube missed the opposite face.
    #[test]
    fn casts_match_brute_force() {
        for mesh in test_meshes(11) {
            let bvh = Bvh::new(&mesh.positions, &mesh.triangles);
            let tris: Vec<[DVec3; 3]> = mesh
                .triangles
                .iter()
                .map(|t| t.map(|i| mesh.positions[i as usize]))
                .collect();
            let mut rays: Vec<(DVec3, DVec3)> = Vec::new();
            for (i, &p) in mesh.positions.iter().enumerate() {
                for dir in [
                    DVec3::X,
                    -DVec3::Y,
                    DVec3::Z,
                    -p,
                    DVec3::new(1.0, 2.0, -0.5),
                ] {
                    rays.push((p, dir));
                    rays.push((p * (0.3 + 0.05 * (i % 7) as f64), dir));
                }
            }
            for (origin, dir) in rays {
                for t_max in [0.05, 0.4, f64::INFINITY] {
                    let expected = tris
                        .iter()
                        .filter_map(|t| intersect(t, origin, dir))
                        .filter(|&t| t > 1e-9 && t < t_max)
                        .fold(f64::INFINITY, f64::min);
                    let got = bvh
                        .cast_within(origin, dir, 1e-9, t_max, |_| false)
                        .map_or(f64::INFINITY, |h| h.t);
                    // Two triangles meeting where the ray crosses give hits that differ by
                    // rounding, and a box may prune the nearer one by an ulp.
                    assert!(
                        got == expected || (got - expected).abs() <= 1e-12 * expected,
                        "{origin} {dir} {t_max}: {got} against {expected}"
                    );
                }
            }
        }
    }

    /// A packet finds what each of its rays finds alone, whatever the packet's size, on
    /// both code paths (AVX2 where the CPU has it), with axis-parallel rays (which leave
    /// the packet for the one-ray traversal), segments, and rays ignoring the triangles of
    /// the vertex they start from.
    #[test]
    fn packets_match_single_casts() {
        for mesh in test_meshes(5) {
            let bvh = Bvh::new(&mesh.positions, &mesh.triangles);
            let mut rays = Vec::new();
            for (i, &p) in mesh.positions.iter().enumerate() {
                let dirs = [
                    -p,
                    DVec3::X,
                    DVec3::new(0.3, -1.0, 0.2),
                    -p + 0.1 * DVec3::new(p.y, p.z, p.x),
                ];
                for (k, dir) in dirs.into_iter().enumerate() {
                    let t_max = [f64::INFINITY, 0.3, 1.1, 2.0][(i + k) % 4];
                    let skip_vertex = if k % 2 == 0 { i as u32 } else { u32::MAX };
                    rays.push(Ray {
                        origin: p,
                        dir,
                        t_min: 1e-9,
                        t_max,
                        skip_vertex,
                    });
                }
            }
            let mut start = 0;
            let mut hits = 0;
            while start < rays.len() {
                let len = (1 + start % PACKET).min(rays.len() - start);
                let packet = &rays[start..start + len];
                let got = [bvh.cast_packet(packet), bvh.cast_packet_impl(packet)];
                for (j, ray) in packet.iter().enumerate() {
                    let skip = |t: &[u32; 3]| t.contains(&ray.skip_vertex);
                    let alone = bvh.cast_within(ray.origin, ray.dir, ray.t_min, ray.t_max, skip);
                    hits += usize::from(alone.is_some());
                    for got in &got {
                        let (a, b) = (got[j].map(|h| h.t), alone.map(|h| h.t));
                        let close =
                            matches!((a, b), (Some(a), Some(b)) if (a - b).abs() <= 1e-12 * b);
                        assert!(a == b || close, "ray {}: {a:?} against {b:?}", start + j);
                    }
                    assert!(got[0][len..].iter().all(Option::is_none));
                }
                start += len;
            }
            assert!(hits > rays.len() / 4, "{hits} of {}", rays.len());
        }
    }
}
