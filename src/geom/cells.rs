//! Grids of balls keyed by cell: the hash their maps use.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A grid cell's hash: its three coordinates mixed by multiplication (the standard
/// library's SipHash, made for untrusted keys, took a third of the contact stage and most
/// of the pose limit).
#[derive(Default)]
pub struct CellHasher(u64);

const MIX: u64 = 0x51_7c_c1_b7_27_22_0a_95;

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(5) ^ u64::from(b)).wrapping_mul(MIX);
        }
    }

    fn write_i32(&mut self, i: i32) {
        self.0 = (self.0.rotate_left(5) ^ (i as u32 as u64)).wrapping_mul(MIX);
    }

    fn write_i64(&mut self, i: i64) {
        self.0 = (self.0.rotate_left(5) ^ (i as u64)).wrapping_mul(MIX);
    }

    fn write_usize(&mut self, _: usize) {}
}

/// A map from grid cells to what lies in them.
pub type Cells<K, V> = HashMap<K, V, BuildHasherDefault<CellHasher>>;

/// A grid of indices sorted by cell (x, then y, then z): built once, then read a row of
/// cells at a time. A grid looked up in thousands of boxes per move reads each row of a
/// box with one binary search and a contiguous scan, where a map hashes every cell and
/// allocates a list per cell (the pose limit's broad phase: `docs/performance-log.md`).
#[derive(Clone, Debug, Default)]
pub struct SortedCells {
    entries: Vec<([i64; 3], u32)>,
}

impl SortedCells {
    /// The grid of `entries` (a cell and what lies in it; one index may lie in several).
    pub fn new(mut entries: Vec<([i64; 3], u32)>) -> SortedCells {
        entries.sort_unstable();
        SortedCells { entries }
    }

    /// What lies in cells `x`, `y`, `z0..=z1`, by cell, then index.
    pub fn row(&self, x: i64, y: i64, z0: i64, z1: i64) -> &[([i64; 3], u32)] {
        let start = self.entries.partition_point(|e| e.0 < [x, y, z0]);
        let len = self.entries[start..].partition_point(|e| e.0 <= [x, y, z1]);
        &self.entries[start..start + len]
    }

    /// Calls `f` with each index in the cells from `lo` to `hi` (inclusive, every axis).
    pub fn each_in(&self, lo: [i64; 3], hi: [i64; 3], mut f: impl FnMut(u32)) {
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                self.row(x, y, lo[2], hi[2]).iter().for_each(|e| f(e.1));
            }
        }
    }

    /// The runs of indices that share a cell, with their cell.
    pub fn runs(&self) -> impl Iterator<Item = ([i64; 3], &[([i64; 3], u32)])> {
        self.entries
            .chunk_by(|a, b| a.0 == b.0)
            .map(|run| (run[0].0, run))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sorted grid finds in a box what a map of cells finds, and its runs are the map's
    /// lists.
    #[test]
    fn a_sorted_grid_finds_what_a_map_finds() {
        let mut rng = crate::random::SplitMix(5);
        let mut cell = || (rng.next_u64() % 7) as i64 - 3;
        let entries: Vec<([i64; 3], u32)> =
            (0..300).map(|i| ([cell(), cell(), cell()], i)).collect();
        let mut map: Cells<[i64; 3], Vec<u32>> = Cells::default();
        for &(k, i) in &entries {
            map.entry(k).or_default().push(i);
        }
        let grid = SortedCells::new(entries);
        for (lo, hi) in [
            ([-1, -2, 0], [2, 1, 2]),
            ([-3; 3], [3; 3]),
            ([0; 3], [0; 3]),
            ([2, 2, 2], [1, 5, 5]),
        ] {
            let mut found = Vec::new();
            grid.each_in(lo, hi, |i| found.push(i));
            let mut want: Vec<u32> = map
                .iter()
                .filter(|(k, _)| (0..3).all(|d| lo[d] <= k[d] && k[d] <= hi[d]))
                .flat_map(|(_, v)| v.iter().copied())
                .collect();
            found.sort_unstable();
            want.sort_unstable();
            assert_eq!(found, want, "{lo:?}..{hi:?}");
        }
        assert_eq!(grid.runs().count(), map.len());
        for (k, run) in grid.runs() {
            let mut ids: Vec<u32> = run.iter().map(|e| e.1).collect();
            let mut want = map[&k].clone();
            ids.sort_unstable();
            want.sort_unstable();
            assert_eq!(ids, want);
        }
    }
}
