//! Welding: merge vertices closer than a tolerance relative to the bounding box, drop the
//! faces that collapse, and drop vertices no face uses. Vertex order is kept (the earliest
//! vertex of a group survives), so indices stay comparable with the input file.
//!
//! The vertices are sorted by a grid cell much larger than the tolerance (then by `x`), so
//! that close pairs are found by a short sweep inside a cell; a neighbouring cell is looked
//! at only for the rare vertex within the tolerance of its cell's face. The search runs in
//! parallel; the merge is a pass in file order, so the result does not depend on threads.

use super::soup::used_vertices;
use super::Mesh;
use glam::DVec3;
use rayon::prelude::*;

/// What [`weld`] changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WeldStats {
    /// Vertices merged into an earlier one.
    pub merged: usize,
    /// Faces dropped because two of their corners became the same vertex.
    pub dropped_faces: usize,
    /// Vertices removed in all (merged ones and unreferenced ones).
    pub removed_vertices: usize,
}

/// Welds `mesh` in place with tolerance `rel_tol` times the bounding-box diagonal of the
/// vertices that faces use.
pub fn weld(mesh: &mut Mesh, rel_tol: f64) -> WeldStats {
    let n = mesh.positions.len();
    let used = used_vertices(n, &mesh.triangles);
    let (lo, hi) = used_bounds(&mesh.positions, &used);
    let tol = rel_tol * (hi - lo).length();
    let mut rep: Vec<u32> = (0..n as u32).collect();
    let mut merged = 0;
    if tol == 0.0 {
        // Every used vertex is at one place: they are all one vertex.
        if let Some(first) = used.iter().position(|&u| u) {
            for i in first + 1..n {
                if used[i] {
                    rep[i] = first as u32;
                    merged += 1;
                }
            }
        }
    } else if tol.is_finite() {
        let pairs = close_pairs(&mesh.positions, &used, lo, hi, tol);
        // In file order: a vertex joins the earliest surviving vertex within reach.
        for &(i, j) in &pairs {
            if rep[i as usize] == i && rep[j as usize] == j {
                rep[i as usize] = j;
                merged += 1;
            }
        }
    }
    let stats = remap(mesh, &rep);
    WeldStats { merged, ..stats }
}

/// Replaces every vertex by `rep[v]`, drops the faces that collapse and the vertices no face
/// uses (keeping order). `merged` is left 0 for the caller.
pub(super) fn remap(mesh: &mut Mesh, rep: &[u32]) -> WeldStats {
    let n = mesh.positions.len();
    let before = mesh.triangles.len();
    let identity = rep.iter().enumerate().all(|(i, &r)| r as usize == i);
    if !identity {
        mesh.triangles = mesh
            .triangles
            .par_iter()
            .map(|t| t.map(|v| rep[v as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
    } else if mesh
        .triangles
        .iter()
        .any(|t| t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
    {
        mesh.triangles
            .retain(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    }
    let dropped_faces = before - mesh.triangles.len();
    let used = used_vertices(n, &mesh.triangles);
    if used.iter().all(|&u| u) {
        return WeldStats {
            dropped_faces,
            ..WeldStats::default()
        };
    }
    let mut new_index = vec![u32::MAX; n];
    let mut positions = Vec::with_capacity(n);
    for i in 0..n {
        if used[i] {
            new_index[i] = positions.len() as u32;
            positions.push(mesh.positions[i]);
        }
    }
    mesh.triangles
        .par_iter_mut()
        .for_each(|t| *t = t.map(|v| new_index[v as usize]));
    let removed_vertices = n - positions.len();
    mesh.positions = positions;
    WeldStats {
        merged: 0,
        dropped_faces,
        removed_vertices,
    }
}

/// Bounding box of the used points (`(0, 0)` when none).
fn used_bounds(points: &[DVec3], used: &[bool]) -> (DVec3, DVec3) {
    let (lo, hi) = points
        .par_iter()
        .zip(used)
        .filter(|(_, &u)| u)
        .map(|(p, _)| (*p, *p))
        .reduce(
            || (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    if lo.x > hi.x {
        (DVec3::ZERO, DVec3::ZERO)
    } else {
        (lo, hi)
    }
}

/// Pairs `(i, j)`, `j < i`, of used points within `tol` of each other, sorted.
fn close_pairs(points: &[DVec3], used: &[bool], lo: DVec3, hi: DVec3, tol: f64) -> Vec<(u32, u32)> {
    // Cells far larger than the tolerance (a point or two each), at most 2^20 per axis.
    let cell = (tol * 1024.0).max((hi - lo).max_element() / f64::from(1u32 << 20));
    let inv = 1.0 / cell;
    let coord = |x: f64, o: f64| (((x - o) * inv).floor().max(0.0) as u64).min((1 << 21) - 1);
    let key_of = |c: [u64; 3]| (c[0] << 42) | (c[1] << 21) | c[2];
    let cell_of = |p: DVec3| [coord(p.x, lo.x), coord(p.y, lo.y), coord(p.z, lo.z)];
    // Each used point's cell, and a flag (the top bit) when it is within reach of a face
    // of its cell, computed in file order so that the search touches no point it need not.
    const NEAR: u32 = 1 << 31;
    let reach_of = |p: DVec3, c: [u64; 3]| {
        [0, 1, 2].map(|a| {
            let t = (p[a] - lo[a]) * inv - c[a] as f64;
            (
                if t * cell <= tol && c[a] > 0 {
                    -1i64
                } else {
                    0
                },
                if (1.0 - t) * cell <= tol { 1i64 } else { 0 },
            )
        })
    };
    let mut order: Vec<(u64, u32)> = points
        .par_iter()
        .zip(used)
        .enumerate()
        .filter(|(_, (_, &u))| u)
        .map(|(i, (p, _))| {
            let c = cell_of(*p);
            let near = reach_of(*p, c).iter().any(|&r| r != (0, 0));
            (key_of(c), i as u32 | if near { NEAR } else { 0 })
        })
        .collect();
    order.par_sort_unstable();
    let tol2 = tol * tol;
    let close = |i: u32, j: u32| points[i as usize].distance_squared(points[j as usize]) <= tol2;
    let pair = |i: u32, j: u32| (i.max(j), i.min(j));
    // The points of cell `key`.
    let run_of = |key: u64| -> &[(u64, u32)] {
        let from = order.partition_point(|e| e.0 < key);
        let to = from + order[from..].iter().take_while(|e| e.0 == key).count();
        &order[from..to]
    };
    const CHUNK: usize = 1 << 14;
    let found: Vec<Vec<(u32, u32)>> = (0..order.len().div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let mut out = Vec::new();
            // The runs that start in this chunk.
            let mut s = chunk * CHUNK;
            while s > 0 && s < order.len() && order[s - 1].0 == order[s].0 {
                s += 1;
            }
            let end = ((chunk + 1) * CHUNK).min(order.len());
            while s < end {
                let key = order[s].0;
                let e = s + order[s..].iter().take_while(|x| x.0 == key).count();
                let run = &order[s..e];
                within_cell(run, points, tol, &mut out);
                // Neighbouring cells, only for points within reach of a face.
                for &(_, flagged) in run {
                    if flagged & NEAR == 0 {
                        continue;
                    }
                    let i = flagged & !NEAR;
                    let p = points[i as usize];
                    let c = cell_of(p);
                    let reach = reach_of(p, c);
                    for dx in reach[0].0..=reach[0].1 {
                        for dy in reach[1].0..=reach[1].1 {
                            for dz in reach[2].0..=reach[2].1 {
                                if (dx, dy, dz) == (0, 0, 0) {
                                    continue;
                                }
                                let nc = [
                                    (c[0] as i64 + dx) as u64,
                                    (c[1] as i64 + dy) as u64,
                                    (c[2] as i64 + dz) as u64,
                                ];
                                for &(_, j) in run_of(key_of(nc)) {
                                    let j = j & !NEAR;
                                    if close(i, j) {
                                        out.push(pair(i, j));
                                    }
                                }
                            }
                        }
                    }
                }
                s = e;
            }
            out
        })
        .collect();
    let mut pairs: Vec<(u32, u32)> = found.concat();
    // Flags off.
    debug_assert!(pairs.iter().all(|&(i, j)| i & NEAR == 0 && j & NEAR == 0));
    pairs.par_sort_unstable();
    pairs.dedup();
    pairs
}

/// Close pairs inside one cell's run: every pair for the usual point or two, a sweep along
/// `x` for a crowded cell.
fn within_cell(run: &[(u64, u32)], points: &[DVec3], tol: f64, out: &mut Vec<(u32, u32)>) {
    let index = |e: &(u64, u32)| e.1 & !(1 << 31);
    let pair = |i: u32, j: u32| (i.max(j), i.min(j));
    let close =
        |i: u32, j: u32| points[i as usize].distance_squared(points[j as usize]) <= tol * tol;
    if run.len() <= 32 {
        for (k, a) in run.iter().enumerate() {
            for b in &run[k + 1..] {
                if close(index(a), index(b)) {
                    out.push(pair(index(a), index(b)));
                }
            }
        }
        return;
    }
    // Crowded: sorted by x, each point meets only those within reach along x.
    let mut by_x: Vec<u32> = run.iter().map(index).collect();
    by_x.sort_unstable_by(|&a, &b| points[a as usize].x.total_cmp(&points[b as usize].x));
    for (k, &i) in by_x.iter().enumerate() {
        let x = points[i as usize].x;
        for &j in &by_x[k + 1..] {
            if points[j as usize].x > x + tol {
                break;
            }
            if close(i, j) {
                out.push(pair(i, j));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule, the slow way: every vertex joins the earliest surviving vertex within reach.
    fn reference(points: &[DVec3], tol: f64) -> Vec<u32> {
        let mut rep: Vec<u32> = (0..points.len() as u32).collect();
        for i in 0..points.len() {
            for j in 0..i {
                if rep[j] == j as u32 && points[j].distance_squared(points[i]) <= tol * tol {
                    rep[i] = j as u32;
                    break;
                }
            }
        }
        rep
    }

    #[test]
    fn same_as_the_quadratic_rule() {
        // Clusters straddling cell faces, exact duplicates, near misses.
        let mut rng = 12345u64;
        let mut rand = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut points = Vec::new();
        for _ in 0..400 {
            let c = DVec3::new(rand(), rand(), rand());
            for _ in 0..3 {
                let jitter = DVec3::new(rand(), rand(), rand()) - 0.5;
                points.push(c + jitter * 2e-7);
            }
            points.push(c);
        }
        // A crowded cell: a hundred points within a few tolerances.
        let c = DVec3::splat(0.5);
        for _ in 0..100 {
            points.push(c + (DVec3::new(rand(), rand(), rand()) - 0.5) * 1e-6);
        }
        points.push(DVec3::ZERO);
        points.push(DVec3::ONE);
        let tol = 1e-7 * (DVec3::ONE).length();
        let used = vec![true; points.len()];
        let (lo, hi) = used_bounds(&points, &used);
        let pairs = close_pairs(&points, &used, lo, hi, tol);
        let mut rep: Vec<u32> = (0..points.len() as u32).collect();
        for &(i, j) in &pairs {
            if rep[i as usize] == i && rep[j as usize] == j {
                rep[i as usize] = j;
            }
        }
        assert_eq!(rep, reference(&points, tol));
        assert!(
            rep.iter()
                .enumerate()
                .filter(|(i, &r)| r as usize != *i)
                .count()
                > 400
        );
    }

    #[test]
    fn a_duplicate_across_a_cell_face_is_found() {
        // Cell size is 1024 tol: put a pair on either side of a face.
        let tol = 1e-7 * 3f64.sqrt();
        let cell = tol * 1024.0;
        let x = 3.0 * cell;
        let points = vec![
            DVec3::ZERO,
            DVec3::ONE,
            DVec3::new(x - 0.2 * tol, 0.5, 0.5),
            DVec3::new(x + 0.2 * tol, 0.5, 0.5),
        ];
        let used = vec![true; 4];
        let (lo, hi) = used_bounds(&points, &used);
        assert_eq!(close_pairs(&points, &used, lo, hi, tol), vec![(3, 2)]);
    }
}
