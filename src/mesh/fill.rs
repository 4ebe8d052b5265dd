//! Closing a hole with well-shaped triangles: the boundary loop is projected on its best
//! plane, triangulated there by a constrained Delaunay triangulation refined until the new
//! edges are about as long as the loop's (`spade`, Ruppert–Chew refinement that leaves the
//! loop's edges whole, so the patch meets the mesh edge for edge), and the new vertices are
//! then faired in 3D (a bi-Laplacian relaxation with the loop and the surface around it
//! held, so the patch continues the surface instead of lying flat). Where the loop's
//! projection folds (it crosses itself, or two of its vertices project onto one point),
//! the hole gets a fan around its centre instead.

use glam::{DVec2, DVec3};
use spade::{ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation};

/// A patch closing one hole: new vertices (appended after `base`, the mesh's vertex count)
/// and the triangles that close it.
pub(super) struct Patch {
    /// Positions of the new vertices, numbered from the `base` given.
    pub positions: Vec<DVec3>,
    /// The new triangles (loop vertices by their mesh index, new ones from `base`).
    pub triangles: Vec<[u32; 3]>,
    /// True when the loop's projection folded and the patch is a fan.
    pub fan: bool,
}

/// The unit normal of a closed polygon by Newell's method (its area vector), or zero.
fn newell(points: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for k in 0..points.len() {
        let (a, b) = (points[k], points[(k + 1) % points.len()]);
        n += a.cross(b);
    }
    n.normalize_or_zero()
}

/// Do two segments `a–b` and `c–d` of the plane cross (touching at an end excluded)?
fn cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let side = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let (d1, d2) = (side(a, b, c), side(a, b, d));
    let (d3, d4) = (side(c, d, a), side(c, d, b));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Is the polygon simple: no two non-adjacent edges cross, no two vertices at one point?
fn simple(poly: &[DVec2], tolerance: f64) -> bool {
    let n = poly.len();
    for i in 0..n {
        for j in i + 1..n {
            if poly[i].distance(poly[j]) <= tolerance {
                return false;
            }
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if !adjacent && cross(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]) {
                return false;
            }
        }
    }
    true
}

/// A fan of the loop around a new vertex at its centre (the new faces run against the
/// loop, `b → a`).
fn fan(lp: &[u32], positions: &[DVec3], base: u32) -> Patch {
    let centre = lp.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / lp.len() as f64;
    let triangles = (0..lp.len())
        .map(|k| [lp[(k + 1) % lp.len()], lp[k], base])
        .collect();
    Patch {
        positions: vec![centre],
        triangles,
        fan: true,
    }
}

/// The patch closing the boundary loop `lp` (in the direction of its faces' boundary edges,
/// `a → b`) of a mesh with `positions`; `neighbours(v)` lists a mesh vertex's neighbours
/// (the surface the fairing continues). New vertices are numbered from `base`.
pub(super) fn close(
    lp: &[u32],
    positions: &[DVec3],
    neighbours: &dyn Fn(u32) -> Vec<u32>,
    base: u32,
) -> Patch {
    let points: Vec<DVec3> = lp.iter().map(|&v| positions[v as usize]).collect();
    if lp.len() == 3 {
        return Patch {
            positions: Vec::new(),
            triangles: vec![[lp[0], lp[2], lp[1]]],
            fan: false,
        };
    }
    // The new faces run against the loop: seen from the side they face, the reversed loop
    // turns counter-clockwise, so the plane's axes are taken with u × v along its normal.
    let normal = -newell(&points);
    let mean_edge = (0..lp.len())
        .map(|k| points[k].distance(points[(k + 1) % lp.len()]))
        .sum::<f64>()
        / lp.len() as f64;
    if normal == DVec3::ZERO || mean_edge.is_nan() || mean_edge <= 0.0 {
        return fan(lp, positions, base);
    }
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let origin = points.iter().sum::<DVec3>() / points.len() as f64;
    let flat: Vec<DVec2> = points
        .iter()
        .map(|p| DVec2::new((*p - origin).dot(u), (*p - origin).dot(v)))
        .collect();
    if !simple(&flat, 1e-9 * mean_edge) {
        return fan(lp, positions, base);
    }
    // A chord of the loop that the surface already has as an edge (the loop runs round a
    // neck, and two of its vertices are neighbours across it) would be an edge of three
    // faces: each such chord gets a new vertex at its middle, which no triangulation can
    // pass through, and the hole is triangulated again.
    let joined = |a: u32, b: u32| neighbours(a).contains(&b) || neighbours(b).contains(&a);
    let slot: std::collections::HashMap<u32, usize> =
        lp.iter().enumerate().map(|(k, &v)| (v, k)).collect();
    let mut steiner: Vec<DVec2> = Vec::new();
    let mut patch = None;
    for _ in 0..4 {
        let Some((points, triangles)) = triangulate(lp, &flat, &steiner, mean_edge, base) else {
            return fan(lp, positions, base);
        };
        let before = steiner.len();
        for t in &triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let (Some(&i), Some(&j)) = (slot.get(&a), slot.get(&b)) else {
                    continue;
                };
                let consecutive = (i + 1) % lp.len() == j || (j + 1) % lp.len() == i;
                if a < b && !consecutive && joined(a, b) {
                    steiner.push((flat[i] + flat[j]) * 0.5);
                }
            }
        }
        if steiner.len() == before {
            patch = Some((points, triangles));
            break;
        }
    }
    let Some((mut new_positions, triangles)) = patch else {
        return fan(lp, positions, base);
    };
    // Lift the new vertices onto the plane, then fair them.
    for p in &mut new_positions {
        *p = origin + u * p.x + v * p.y;
    }
    // Fairing bends the patch to continue the surface; where that would turn a face over
    // (a rim that twists), the membrane is kept, or else the flat patch.
    let flat_positions = new_positions.clone();
    let membrane = fair(&mut new_positions, &triangles, positions, neighbours, base);
    let faces_up = |x: &[DVec3]| {
        triangles.iter().all(|t| {
            let [a, b, c] = t.map(|v| {
                if v >= base {
                    x[(v - base) as usize]
                } else {
                    positions[v as usize]
                }
            });
            (b - a).cross(c - a).dot(normal) > 0.0
        })
    };
    if !faces_up(&new_positions) {
        new_positions = match membrane {
            Some(m) if faces_up(&m) => m,
            _ => flat_positions,
        };
    }
    Patch {
        positions: new_positions,
        triangles,
        fan: false,
    }
}

/// The refined constrained Delaunay triangulation of the simple polygon `flat` (the loop
/// `lp`'s projection), through the `steiner` points inside it: new vertices as `(x, y, 0)` in the plane, and the triangles inside,
/// counter-clockwise. `None` where spade refuses the loop.
fn triangulate(
    lp: &[u32],
    flat: &[DVec2],
    steiner: &[DVec2],
    mean_edge: f64,
    base: u32,
) -> Option<(Vec<DVec3>, Vec<[u32; 3]>)> {
    // In units of the mean edge: spade's refinement has absolute limits, and a hole must
    // get the same patch at any scale.
    let unit = 1.0 / mean_edge;
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut handles = Vec::with_capacity(flat.len());
    for p in flat {
        handles.push(cdt.insert(Point2::new(p.x * unit, p.y * unit)).ok()?);
    }
    if cdt.num_vertices() != flat.len() {
        return None;
    }
    for p in steiner {
        cdt.insert(Point2::new(p.x * unit, p.y * unit)).ok()?;
    }
    for k in 0..handles.len() {
        let (a, b) = (handles[k], handles[(k + 1) % handles.len()]);
        if !cdt.can_add_constraint(a, b) {
            return None;
        }
        cdt.add_constraint(a, b);
    }
    // Triangles about as large as an equilateral one on the loop's mean edge.
    let area = 3f64.sqrt() / 4.0;
    let result = cdt.refine(
        RefinementParameters::<f64>::new()
            .exclude_outer_faces(true)
            .keep_constraint_edges()
            .with_max_allowed_area(area)
            .with_max_additional_vertices(20 * flat.len() + 1000),
    );
    let outer: std::collections::HashSet<_> = result.excluded_faces.into_iter().collect();
    // Mesh indices: the loop's own vertices, then new ones in the order met.
    let mut index: std::collections::HashMap<usize, u32> = handles
        .iter()
        .zip(lp)
        .map(|(h, &v)| (h.index(), v))
        .collect();
    let mut new_positions = Vec::new();
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        if outer.contains(&face.fix()) {
            continue;
        }
        let corners = face.vertices().map(|vh| {
            *index.entry(vh.fix().index()).or_insert_with(|| {
                let p = vh.position();
                new_positions.push(DVec3::new(p.x * mean_edge, p.y * mean_edge, 0.0));
                base + new_positions.len() as u32 - 1
            })
        });
        triangles.push(corners);
    }
    (!triangles.is_empty()).then_some((new_positions, triangles))
}

/// Fairs the new vertices: relaxes them towards the bi-Laplacian's zero over the patch and
/// the surface around it, the loop and the surface held, starting from the membrane (the
/// Laplacian's zero). The Laplacian weighs each neighbour by the inverse of its distance
/// (measured once, on the membrane), so a patch finer than the surface around it does not
/// overshoot it. Returns the membrane.
fn fair(
    new_positions: &mut [DVec3],
    triangles: &[[u32; 3]],
    positions: &[DVec3],
    neighbours: &dyn Fn(u32) -> Vec<u32>,
    base: u32,
) -> Option<Vec<DVec3>> {
    if new_positions.is_empty() {
        return None;
    }
    // Neighbourhoods: each vertex the patch touches, its mesh neighbours plus its patch ones.
    let mut ring: std::collections::BTreeMap<u32, Vec<(u32, f64)>> = Default::default();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            ring.entry(a).or_default().push((b, 1.0));
            ring.entry(b).or_default().push((a, 1.0));
        }
    }
    for (&v, r) in ring.iter_mut() {
        if v < base {
            r.extend(neighbours(v).into_iter().map(|w| (w, 1.0)));
        }
        r.sort_unstable_by_key(|&(w, _)| w);
        r.dedup_by_key(|&mut (w, _)| w);
    }
    let mut rings = Rings::new(&ring, positions, new_positions, base);
    let scale = new_positions
        .iter()
        .map(|p| p.length())
        .fold(1e-12, f64::max);
    // The membrane first (uniform weights: every weight is 1 until measured).
    rings.relax(scale, false);
    // Weights from the membrane, each row summing to 1.
    let snapshot = rings.x[..new_positions.len()].to_vec();
    rings.weigh(scale);
    rings.relax(scale, true);
    new_positions.copy_from_slice(&rings.x[..new_positions.len()]);
    Some(snapshot)
}

/// The neighbourhoods [`fair`] relaxes, packed flat: node `k`'s neighbours are
/// `nbr[start[k]..start[k + 1]]`, in the order of their vertex numbers. Nodes
/// `0..new` are the new vertices (`base + k`), the rest the surface's vertices they
/// reach, held.
struct Rings {
    /// Positions by node.
    x: Vec<DVec3>,
    /// Number of new vertices (the nodes that move).
    new: usize,
    /// Whether a node has a neighbourhood (the patch touches it).
    has: Vec<bool>,
    start: Vec<usize>,
    nbr: Vec<u32>,
    weight: Vec<f64>,
    /// Per node, the sum of its weights.
    total: Vec<f64>,
    /// Per entry `k → u`: `k`'s weight in `u`'s neighbourhood over `u`'s total (the
    /// coefficient of `x_k` in `Δx_u`).
    back: Vec<f64>,
}

impl Rings {
    fn new(
        ring: &std::collections::BTreeMap<u32, Vec<(u32, f64)>>,
        positions: &[DVec3],
        new_positions: &[DVec3],
        base: u32,
    ) -> Rings {
        let new = new_positions.len();
        let mut x = new_positions.to_vec();
        let mut node: std::collections::HashMap<u32, u32> = Default::default();
        let mut node_of = |v: u32, x: &mut Vec<DVec3>| -> u32 {
            if v >= base {
                return v - base;
            }
            *node.entry(v).or_insert_with(|| {
                x.push(positions[v as usize]);
                x.len() as u32 - 1
            })
        };
        let mut rows: Vec<Option<Vec<(u32, f64)>>> = vec![None; new];
        for (&v, r) in ring {
            let k = node_of(v, &mut x) as usize;
            let row: Vec<(u32, f64)> = r.iter().map(|&(u, w)| (node_of(u, &mut x), w)).collect();
            if rows.len() <= k {
                rows.resize(k + 1, None);
            }
            rows[k] = Some(row);
        }
        rows.resize(x.len(), None);
        let mut out = Rings {
            has: rows.iter().map(Option::is_some).collect(),
            start: Vec::with_capacity(x.len() + 1),
            nbr: Vec::new(),
            weight: Vec::new(),
            total: Vec::new(),
            back: Vec::new(),
            x,
            new,
        };
        out.start.push(0);
        for row in &rows {
            for &(u, w) in row.iter().flatten() {
                out.nbr.push(u);
                out.weight.push(w);
            }
            out.start.push(out.nbr.len());
        }
        out.totals();
        out
    }

    /// `total` and `back` from the weights.
    fn totals(&mut self) {
        let n = self.x.len();
        self.total = (0..n)
            .map(|k| self.weight[self.start[k]..self.start[k + 1]].iter().sum())
            .collect();
        self.back = vec![0.0; self.nbr.len()];
        for k in 0..n {
            for e in self.start[k]..self.start[k + 1] {
                let u = self.nbr[e] as usize;
                let row = self.start[u]..self.start[u + 1];
                self.back[e] = self.nbr[row.clone()]
                    .iter()
                    .position(|&m| m as usize == k)
                    .map_or(0.0, |i| self.weight[row.start + i] / self.total[u]);
            }
        }
    }

    /// Each neighbour weighed by the inverse of its distance now, each row summing to 1.
    fn weigh(&mut self, scale: f64) {
        for k in 0..self.x.len() {
            let row = self.start[k]..self.start[k + 1];
            let p = self.x[k];
            for e in row.clone() {
                self.weight[e] = 1.0 / p.distance(self.x[self.nbr[e] as usize]).max(1e-12 * scale);
            }
            let total: f64 = self.weight[row.clone()].iter().sum();
            self.weight[row].iter_mut().for_each(|w| *w /= total);
        }
        self.totals();
    }

    /// `Δx_k` (zero for a node with no neighbourhood).
    fn laplacian(&self, k: usize) -> DVec3 {
        if !self.has[k] {
            return DVec3::ZERO;
        }
        let row = self.start[k]..self.start[k + 1];
        let mean = self.nbr[row.clone()]
            .iter()
            .zip(&self.weight[row])
            .map(|(&u, &w)| self.x[u as usize] * w)
            .sum::<DVec3>()
            / self.total[k];
        mean - self.x[k]
    }

    /// Gauss–Seidel passes over the new vertices until they move less than `1e-10 ×
    /// scale`: towards the Laplacian's zero, or (`bi`) the bi-Laplacian's, `x_k` moving
    /// by `−Δ²x_k / c_k`, `c_k` the coefficient of `x_k` in `Δ²x_k`. The Laplacians are
    /// kept up to date as each vertex moves (a move of `x_k` changes `Δx_k` and its
    /// neighbours' by their weights), and taken afresh every [`FRESH`] passes, so a pass
    /// costs two visits of each neighbourhood rather than one per neighbour's.
    fn relax(&mut self, scale: f64, bi: bool) {
        /// Passes between Laplacians taken afresh (rounding does not build up).
        const FRESH: usize = 16;
        let n = self.x.len();
        // Per new vertex, `c_k` and each neighbour's share of `Δ²x_k`.
        let mut share = vec![0.0; self.nbr.len()];
        let mut coefficient = vec![1.0; self.new];
        for (k, c) in coefficient.iter_mut().enumerate() {
            let row = self.start[k]..self.start[k + 1];
            for (e, sh) in row.clone().zip(&mut share[row]) {
                *sh = self.weight[e] / self.total[k];
                if self.has[self.nbr[e] as usize] {
                    *c += *sh * self.back[e];
                }
            }
        }
        let mut lap = vec![DVec3::ZERO; n];
        for pass in 0..if bi { 400 } else { 200 } {
            if pass % FRESH == 0 {
                for (k, l) in lap.iter_mut().enumerate() {
                    *l = self.laplacian(k);
                }
            }
            let mut moved = 0.0f64;
            for k in 0..self.new {
                if !self.has[k] {
                    continue;
                }
                let row = self.start[k]..self.start[k + 1];
                let step = if bi {
                    let mut mean = DVec3::ZERO;
                    for e in row.clone() {
                        mean += lap[self.nbr[e] as usize] * share[e];
                    }
                    -(mean - lap[k]) / coefficient[k]
                } else {
                    lap[k]
                };
                if step.is_finite() {
                    self.x[k] += step;
                    lap[k] -= step;
                    for e in row {
                        lap[self.nbr[e] as usize] += step * self.back[e];
                    }
                    moved = moved.max(step.length());
                }
            }
            if moved <= 1e-10 * scale {
                break;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A regular `n`-gon of radius 1 in the plane z = 0, numbered 0..n counter-clockwise
    /// (seen from +z).
    fn ngon(n: usize) -> Vec<DVec3> {
        (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect()
    }

    /// A `side × side` grid in the plane, its border (numbered first, held) lifted onto a
    /// saddle and its inside (numbered from the returned base) flat: the rings of its
    /// 4-neighbourhoods as [`fair`] builds them.
    fn saddle(side: usize) -> Rings {
        let inside = |i: usize, j: usize| i > 0 && j > 0 && i + 1 < side && j + 1 < side;
        let mut border = Vec::new();
        let mut inner = Vec::new();
        for i in 0..side {
            for j in 0..side {
                let (x, y) = (i as f64 / side as f64, j as f64 / side as f64);
                if inside(i, j) {
                    inner.push((i, j, DVec3::new(x, y, 0.0)));
                } else {
                    border.push((i, j, DVec3::new(x, y, (x - 0.5) * (y - 0.5) * 2.0)));
                }
            }
        }
        let base = border.len() as u32;
        let number = |i: usize, j: usize| -> u32 {
            if inside(i, j) {
                base + inner
                    .iter()
                    .position(|&(a, b, _)| (a, b) == (i, j))
                    .unwrap_or(0) as u32
            } else {
                border
                    .iter()
                    .position(|&(a, b, _)| (a, b) == (i, j))
                    .unwrap_or(0) as u32
            }
        };
        let mut ring: std::collections::BTreeMap<u32, Vec<(u32, f64)>> = Default::default();
        for &(i, j, _) in border.iter().chain(&inner) {
            let near: Vec<(usize, usize)> = [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)]
                .iter()
                .map(|&(di, dj)| (i as i64 + di, j as i64 + dj))
                .filter(|&(a, b)| a >= 0 && b >= 0 && a < side as i64 && b < side as i64)
                .map(|(a, b)| (a as usize, b as usize))
                .collect();
            if !inside(i, j) && !near.iter().any(|&(a, b)| inside(a, b)) {
                continue;
            }
            let mut r: Vec<(u32, f64)> = near.iter().map(|&(a, b)| (number(a, b), 1.0)).collect();
            r.sort_unstable_by_key(|&(w, _)| w);
            ring.insert(number(i, j), r);
        }
        let positions: Vec<DVec3> = border.iter().map(|b| b.2).collect();
        let new: Vec<DVec3> = inner.iter().map(|b| b.2).collect();
        Rings::new(&ring, &positions, &new, base)
    }

    #[test]
    fn laplacians_kept_up_to_date_relax_as_laplacians_taken_afresh() {
        // The reference: Gauss–Seidel with every Laplacian taken afresh where it is used.
        fn plain(r: &mut Rings, bi: bool, passes: usize) {
            for _ in 0..passes {
                for k in 0..r.new {
                    let dv = r.laplacian(k);
                    let step = if bi {
                        let (mut mean, mut c) = (DVec3::ZERO, 1.0);
                        for e in r.start[k]..r.start[k + 1] {
                            let u = r.nbr[e] as usize;
                            let share = r.weight[e] / r.total[k];
                            mean += r.laplacian(u) * share;
                            if r.has[u] {
                                c += share * r.back[e];
                            }
                        }
                        -(mean - dv) / c
                    } else {
                        dv
                    };
                    r.x[k] += step;
                }
            }
        }
        let mut kept = saddle(14);
        let mut fresh = saddle(14);
        kept.relax(1.0, false);
        plain(&mut fresh, false, 200);
        kept.weigh(1.0);
        fresh.weigh(1.0);
        kept.relax(1.0, true);
        plain(&mut fresh, true, 400);
        let far = (0..kept.new)
            .map(|k| kept.x[k].distance(fresh.x[k]))
            .fold(0.0, f64::max);
        assert!(far < 1e-12, "{far}");
        // And the patch left the plane for the saddle: fairing did something.
        let lifted = (0..kept.new).map(|k| kept.x[k].z.abs()).fold(0.0, f64::max);
        assert!(lifted > 0.1, "{lifted}");
    }

    #[test]
    fn a_large_planar_hole_gets_well_shaped_triangles_facing_against_the_loop() {
        let points = ngon(80);
        let lp: Vec<u32> = (0..80).collect();
        let none = |_: u32| Vec::new();
        let patch = close(&lp, &points, &none, 80);
        assert!(!patch.fan);
        assert!(!patch.positions.is_empty(), "interior vertices added");
        let all: Vec<DVec3> = points.iter().chain(&patch.positions).copied().collect();
        let edge = points[0].distance(points[1]);
        let mut area = 0.0;
        for t in &patch.triangles {
            let [a, b, c] = t.map(|v| all[v as usize]);
            let n = (b - a).cross(c - a);
            // The loop runs counter-clockwise about +z: faces closing it face −z.
            assert!(n.z < 0.0, "{t:?}");
            area += n.length() / 2.0;
            for (p, q) in [(a, b), (b, c), (c, a)] {
                assert!(
                    p.distance(q) < 3.0 * edge,
                    "an edge of {} against {edge}",
                    p.distance(q)
                );
            }
        }
        let polygon = 0.5 * 80.0 * (std::f64::consts::TAU / 80.0).sin();
        assert!(
            (area - polygon).abs() < 1e-9 * polygon,
            "{area} vs {polygon}"
        );
        for p in &patch.positions {
            assert!(p.z.abs() < 1e-9, "a planar hole stays planar: {p}");
        }
    }

    #[test]
    fn a_folded_loop_gets_a_fan() {
        // A bow tie: its projection crosses itself.
        let points = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let none = |_: u32| Vec::new();
        let patch = close(&[0, 1, 2, 3], &points, &none, 4);
        assert!(patch.fan);
        assert_eq!(patch.triangles.len(), 4);
    }
}
