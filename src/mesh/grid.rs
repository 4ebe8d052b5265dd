//! A uniform grid of points for nearest-point queries: each cell's points as one slice of
//! a flat list indexed by cell, so a query reads cells and hashes nothing. Riders find the
//! body vertex nearest them ([`Grid::nearest_within`], growing shells of cells until
//! nothing beyond can be nearer), attachments their partner on another piece, and the
//! mirror plane each vertex's image's partner within a cell or two
//! ([`Grid::nearest_around`], the 27 cells around it only).

use glam::DVec3;

/// A uniform grid of some points, for nearest-point queries.
pub(crate) struct Grid {
    lo: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// Cell of each entry of `points`, sorted: `start[c]..start[c + 1]`.
    start: Vec<u32>,
    points: Vec<u32>,
}

impl Grid {
    /// A grid of the points `which` (of `positions`) with about two points per cell.
    pub(crate) fn new(positions: &[DVec3], which: &[u32]) -> Grid {
        let ps: Vec<DVec3> = which.iter().map(|&v| positions[v as usize]).collect();
        let (lo, hi) = super::bounds(&ps);
        let extent = (hi - lo).max(DVec3::splat(1e-300));
        // About two points per cell, at most 2^21 cells.
        let cells = (which.len() as f64 / 2.0).clamp(1.0, f64::from(1u32 << 21));
        let cell = (extent.x * extent.y * extent.z / cells)
            .cbrt()
            .max(extent.max_element() / 128.0);
        Grid::build(&ps, which, lo, hi, cell)
    }

    /// A grid of the points `which` (of `positions`) whose cells are cubes of side `cell`
    /// (at most 1,024 along an axis), from the points' lowest corner.
    pub(crate) fn with_cell(positions: &[DVec3], which: &[u32], cell: f64) -> Grid {
        let ps: Vec<DVec3> = which.iter().map(|&v| positions[v as usize]).collect();
        let (lo, hi) = super::bounds(&ps);
        Grid::build(&ps, which, lo, hi, cell)
    }

    /// The grid of the points `ps` (the positions of `which`) within `lo..=hi`, each cell
    /// listing its points in the order of `which`.
    fn build(ps: &[DVec3], which: &[u32], lo: DVec3, hi: DVec3, cell: f64) -> Grid {
        let extent = (hi - lo).max(DVec3::splat(1e-300));
        let dims = [0, 1, 2].map(|k| ((extent[k] / cell) as usize + 1).min(1 << 10));
        let cell_of = |p: DVec3| {
            let c = [0, 1, 2].map(|k| (((p[k] - lo[k]) / cell).max(0.0) as usize).min(dims[k] - 1));
            (c[2] * dims[1] + c[1]) * dims[0] + c[0]
        };
        let total = dims[0] * dims[1] * dims[2];
        let mut start = vec![0u32; total + 1];
        for p in ps {
            start[cell_of(*p) + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut points = vec![0u32; which.len()];
        for (k, p) in ps.iter().enumerate() {
            let c = cell_of(*p);
            points[fill[c] as usize] = which[k];
            fill[c] += 1;
        }
        Grid {
            lo,
            cell,
            dims,
            start,
            points,
        }
    }

    /// The place in `start` of the cell at `c` (in cells from `lo`), if it is in the grid.
    fn cell_id(&self, c: [i64; 3]) -> Option<usize> {
        let inside = (0..3).all(|k| (0..self.dims[k] as i64).contains(&c[k]));
        inside
            .then(|| (c[2] as usize * self.dims[1] + c[1] as usize) * self.dims[0] + c[0] as usize)
    }

    /// The nearest point to `q` nearer than `reach` among the 27 cells around `q`'s
    /// (those in the grid; none when `q`'s own lies outside it and no neighbour is in),
    /// and its distance; of two as near, the one listed first, cell by cell. A quick
    /// look where only a near point matters (a mirror image's partner): a point within
    /// a cell of `q` is always found, one farther perhaps not.
    pub(crate) fn nearest_around(
        &self,
        positions: &[DVec3],
        q: DVec3,
        reach: f64,
    ) -> Option<(f64, u32)> {
        let key = [0, 1, 2].map(|k| ((q[k] - self.lo[k]) / self.cell).floor() as i64);
        let mut best = (reach, u32::MAX);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(id) = self.cell_id([key[0] + dx, key[1] + dy, key[2] + dz]) else {
                        continue;
                    };
                    for &v in &self.points[self.start[id] as usize..self.start[id + 1] as usize] {
                        let d = positions[v as usize].distance(q);
                        if d < best.0 {
                            best = (d, v);
                        }
                    }
                }
            }
        }
        (best.1 != u32::MAX).then_some(best)
    }

    /// The nearest grid point to `q` and its squared distance (of two as near, the lower
    /// index).
    pub(crate) fn nearest(&self, positions: &[DVec3], q: DVec3) -> Option<(f64, u32)> {
        self.nearest_within(positions, q, f64::INFINITY)
    }

    /// [`Grid::nearest`] among the points whose squared distance to `q` is at most
    /// `limit`: `None` when there is none. A search with a limit stops at the cells that
    /// lie farther, where one without searches on until it finds a point.
    pub(crate) fn nearest_within(
        &self,
        positions: &[DVec3],
        q: DVec3,
        limit: f64,
    ) -> Option<(f64, u32)> {
        if self.points.is_empty() {
            return None;
        }
        let c = [0, 1, 2].map(|k| {
            (((q[k] - self.lo[k]) / self.cell).floor() as i64).clamp(0, self.dims[k] as i64 - 1)
        });
        let mut best = (f64::INFINITY, u32::MAX);
        let visit = |cc: [i64; 3], best: &mut (f64, u32)| {
            let Some(id) = self.cell_id(cc) else {
                return;
            };
            for &v in &self.points[self.start[id] as usize..self.start[id + 1] as usize] {
                let d = positions[v as usize].distance_squared(q);
                if d <= limit && (d < best.0 || (d == best.0 && v < best.1)) {
                    *best = (d, v);
                }
            }
        };
        // Grow shells of cells until the best is closer than anything beyond the shell.
        let max_r = self.dims.iter().max().copied().unwrap_or(1) as i64;
        for r in 0..=max_r {
            // Every cell of shell r lies at least r - 1 cells from q.
            let gap = (r - 1).max(0) as f64 * self.cell;
            if gap * gap > limit {
                break;
            }
            // The shell's cells only: all of its two faces across z and y, and the two
            // ends across x of the rows between.
            for dz in -r..=r {
                for dy in -r..=r {
                    if dz.abs() == r || dy.abs() == r {
                        for dx in -r..=r {
                            visit([c[0] + dx, c[1] + dy, c[2] + dz], &mut best);
                        }
                    } else {
                        visit([c[0] - r, c[1] + dy, c[2] + dz], &mut best);
                        if r > 0 {
                            visit([c[0] + r, c[1] + dy, c[2] + dz], &mut best);
                        }
                    }
                }
            }
            // Everything outside shell r is at least r cells away from q's cell.
            let reach = r as f64 * self.cell;
            if best.1 != u32::MAX && best.0 <= reach * reach {
                break;
            }
        }
        (best.1 != u32::MAX).then_some(best)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn nearest_matches_brute_force() {
        let m = shapes::uv_sphere(1.0, 30, 15);
        let all: Vec<u32> = (0..m.positions.len() as u32).collect();
        let grid = Grid::new(&m.positions, &all);
        for k in 0..50 {
            let q = DVec3::new(
                (k as f64 * 0.37).sin() * 1.7,
                (k as f64).cos() * 0.3,
                0.1 * k as f64 - 2.5,
            );
            let brute = all
                .iter()
                .map(|&v| (m.positions[v as usize].distance_squared(q), v))
                .fold((f64::INFINITY, u32::MAX), |a, b| {
                    if b.0 < a.0 || (b.0 == a.0 && b.1 < a.1) {
                        b
                    } else {
                        a
                    }
                });
            assert_eq!(grid.nearest(&m.positions, q), Some(brute));
            // Within a bound: the same point when it is that near, else none.
            for limit in [0.0, 0.01, 0.1, 0.5, 2.0, 10.0] {
                let within = grid.nearest_within(&m.positions, q, limit);
                assert_eq!(within, (brute.0 <= limit).then_some(brute), "{q} {limit}");
            }
        }
    }

    #[test]
    fn the_grid_finds_the_nearest_vertex_within_its_reach() {
        let points: Vec<DVec3> = (0..2000)
            .map(|i| {
                let t = i as f64;
                DVec3::new((t * 0.37).sin(), (t * 0.11).cos() * 2.0, (t * 0.013).sin())
            })
            .collect();
        let (lo, hi) = crate::mesh::bounds(&points);
        let cell = (hi - lo).max_element() / 48.0;
        let all: Vec<u32> = (0..points.len() as u32).collect();
        let grid = Grid::with_cell(&points, &all, cell);
        // Queries inside the bounds and past them (a mirror image can fall outside).
        for i in 0..500 {
            let t = i as f64;
            let p = DVec3::new(
                (t * 0.7).sin() * 1.3,
                (t * 0.3).cos() * 2.4,
                (t * 0.05).cos(),
            );
            let (q, d) = grid
                .nearest_around(&points, p, 2.0 * cell)
                .map_or((p, 2.0 * cell), |(d, v)| (points[v as usize], d));
            let brute = points
                .iter()
                .map(|x| x.distance(p))
                .fold(f64::INFINITY, f64::min);
            if brute < cell {
                // Within a cell the nearest vertex is always among the 27 cells searched.
                assert_eq!(d, brute, "{p}");
                assert_eq!(q.distance(p), d);
            } else {
                // Farther: a vertex no nearer than the nearest, or none and two cells.
                let none = q == p && d == 2.0 * cell;
                assert!(
                    none || (d >= brute && d < 2.0 * cell),
                    "{p}: {d} vs {brute}"
                );
            }
        }
    }
}
