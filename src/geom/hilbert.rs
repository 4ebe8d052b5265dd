//! Spatial insertion order: 3D Hilbert curve keys and BRIO (biased randomized insertion
//! order, Amenta–Choi–Rote): random rounds of doubling size, each sorted along the Hilbert
//! curve. This keeps point location walks short while keeping the expected cost of
//! randomized incremental construction. The random source is seeded, so the order (and the
//! tetrahedralization) is deterministic.

use crate::random::SplitMix;
use glam::DVec3;

/// Hilbert index of a point with `bits`-bit integer coordinates (Skilling's transpose
/// algorithm), `1 <= bits` and `3 * bits <= 63`.
pub fn hilbert_index(x: [u32; 3], bits: u32) -> u64 {
    hilbert_lanes(x.map(|c| [c]), bits)[0]
}

/// How many points [`hilbert_lanes`] takes at once where many keys are wanted.
const LANES: usize = 8;

/// [`hilbert_index`] of `L` points at once, coordinate-major (`x[axis][lane]`).
///
/// Skilling's loop is one long chain of dependent steps per point. Here each step is
/// done for all lanes together, so the chains of different points overlap (and
/// vectorize), and without the textbook loop's branches on the coordinate bits. The
/// tests check it against the textbook loop.
// Each loop over the lanes indexes several coordinate rows at once.
#[allow(clippy::needless_range_loop)]
fn hilbert_lanes<const L: usize>(mut x: [[u32; L]; 3], bits: u32) -> [u64; L] {
    let m = 1u32 << (bits - 1);
    // Inverse undo excess work: where bit q of x[i] is set, invert the low bits of x[0];
    // elsewhere exchange the low bits of x[0] and x[i].
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..3 {
            for l in 0..L {
                let set = 0u32.wrapping_sub(u32::from(x[i][l] & q != 0));
                let t = (x[0][l] ^ x[i][l]) & p & !set;
                x[0][l] ^= (p & set) | t;
                x[i][l] ^= t;
            }
        }
        q >>= 1;
    }
    // Gray encode.
    let mut t = [0u32; L];
    for l in 0..L {
        x[1][l] ^= x[0][l];
        x[2][l] ^= x[1][l];
        q = m;
        while q > 1 {
            t[l] ^= (q - 1) & 0u32.wrapping_sub(u32::from(x[2][l] & q != 0));
            q >>= 1;
        }
    }
    // Interleave: bit b of x[0], x[1], x[2] becomes bit 3b + 2, 3b + 1, 3b of the index.
    let mask = (1u64 << bits) - 1;
    let mut h = [0u64; L];
    for l in 0..L {
        let [a, b, c] = [0, 1, 2].map(|i| spread3(u64::from(x[i][l] ^ t[l]) & mask));
        h[l] = (a << 2) | (b << 1) | c;
    }
    h
}

/// Moves bit `k` of `v` (below 2²¹) to bit `3k`.
fn spread3(mut v: u64) -> u64 {
    v = (v | v << 32) & 0x001F_0000_0000_FFFF;
    v = (v | v << 16) & 0x001F_0000_FF00_00FF;
    v = (v | v << 8) & 0x100F_00F0_0F00_F00F;
    v = (v | v << 4) & 0x10C3_0C30_C30C_30C3;
    (v | v << 2) & 0x1249_2492_4924_9249
}

/// `(key, index)` for every point: its Hilbert index on a `bits`-bit grid over the
/// bounding box, plus `high(index)` (bits above the index), on all cores.
fn hilbert_keys(
    points: &[DVec3],
    bits: u32,
    high: impl Fn(usize) -> u64 + Sync,
) -> Vec<(u64, u32)> {
    use rayon::prelude::*;
    let q = quantizer(points, bits);
    let mut keys = vec![(0, 0); points.len()];
    keys.par_chunks_mut(LANES)
        .zip(points.par_chunks(LANES))
        .enumerate()
        .for_each(|(c, (keys, pts))| {
            let mut x = [[0; LANES]; 3];
            for (l, p) in pts.iter().enumerate() {
                let [a, b, z] = q(*p);
                [x[0][l], x[1][l], x[2][l]] = [a, b, z];
            }
            let h = hilbert_lanes(x, bits);
            for (l, key) in keys.iter_mut().enumerate() {
                let i = c * LANES + l;
                *key = (high(i) | h[l], i as u32);
            }
        });
    keys
}

/// Maps points to `bits`-bit integer coordinates over their bounding box.
fn quantizer(points: &[DVec3], bits: u32) -> impl Fn(DVec3) -> [u32; 3] {
    let (lo, hi) = crate::mesh::bounds(points);
    let ext = (hi - lo).max_element();
    let scale = if ext > 0.0 {
        ((1u32 << bits) - 1) as f64 / ext
    } else {
        0.0
    };
    move |p| ((p - lo) * scale).to_array().map(|c| c as u32)
}

/// The indices of `(key, index)` pairs in key order, sorted on all cores (the pairs are
/// distinct, so the order does not depend on how many).
fn by_key(mut keys: Vec<(u64, u32)>) -> Vec<u32> {
    use rayon::prelude::*;
    keys.par_sort_unstable();
    keys.into_iter().map(|(_, i)| i).collect()
}

/// Points sorted along the 3D Hilbert curve of their bounding box: indices into `points`.
/// Consecutive indices are close in space, so data laid out in this order is read with few
/// cache misses by anything that visits mesh neighbours (the simulation step).
pub fn hilbert_order(points: &[DVec3]) -> Vec<u32> {
    const BITS: u32 = 21;
    by_key(hilbert_keys(points, BITS, |_| 0))
}

/// BRIO order of `points`: indices into `points`. The keys are computed and sorted on all
/// cores (the order does not depend on how many).
pub fn brio_order(points: &[DVec3], seed: u64) -> Vec<u32> {
    const BITS: u32 = 16;
    const MAX_ROUND: u32 = 12;
    let mut rng = SplitMix(seed);
    // Round r (0 = last, biggest) with probability 2^-(r+1); earlier rounds first.
    let rounds: Vec<u8> = (0..points.len())
        .map(|_| rng.next_u64().trailing_ones().min(MAX_ROUND) as u8)
        .collect();
    by_key(hilbert_keys(points, BITS, |i| {
        u64::from(MAX_ROUND - u32::from(rounds[i])) << 48
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hilbert_is_a_bijection_with_unit_steps() {
        let bits = 3;
        let side = 1u32 << bits;
        let mut cells = vec![[0u32; 3]; (side * side * side) as usize];
        for x in 0..side {
            for y in 0..side {
                for z in 0..side {
                    let h = hilbert_index([x, y, z], bits) as usize;
                    cells[h] = [x, y, z];
                }
            }
        }
        for w in cells.windows(2) {
            let d: u32 = (0..3).map(|k| w[0][k].abs_diff(w[1][k])).sum();
            assert_eq!(d, 1, "consecutive Hilbert cells must be face neighbours");
        }
    }

    /// Skilling's loop as published, branching on every bit.
    fn hilbert_index_textbook(mut x: [u32; 3], bits: u32) -> u64 {
        let m = 1u32 << (bits - 1);
        let mut q = m;
        while q > 1 {
            let p = q - 1;
            for i in 0..3 {
                if x[i] & q != 0 {
                    x[0] ^= p;
                } else {
                    let t = (x[0] ^ x[i]) & p;
                    x[0] ^= t;
                    x[i] ^= t;
                }
            }
            q >>= 1;
        }
        x[1] ^= x[0];
        x[2] ^= x[1];
        let mut t = 0;
        q = m;
        while q > 1 {
            if x[2] & q != 0 {
                t ^= q - 1;
            }
            q >>= 1;
        }
        for v in &mut x {
            *v ^= t;
        }
        let mut h = 0u64;
        for b in (0..bits).rev() {
            for v in x {
                h = (h << 1) | ((v >> b) & 1) as u64;
            }
        }
        h
    }

    #[test]
    fn branch_free_hilbert_index_matches_the_textbook_loop() {
        let mut rng = SplitMix(11);
        for bits in [1, 2, 3, 5, 16, 21] {
            let top = (1u64 << bits) - 1;
            for k in 0..20_000 {
                let x = [0; 3].map(|_| match k % 4 {
                    // Corners and edges of the cube as well as random cells.
                    0 => (rng.next_u64() & 1) as u32 * top as u32,
                    _ => (rng.next_u64() & top) as u32,
                });
                assert_eq!(
                    hilbert_index(x, bits),
                    hilbert_index_textbook(x, bits),
                    "{x:?} at {bits} bits"
                );
            }
        }
    }

    #[test]
    fn eight_lane_keys_match_one_point_keys() {
        // 1,001 points: the last chunk of eight is partly empty.
        let mut rng = SplitMix(5);
        let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let pts: Vec<DVec3> = (0..1001).map(|_| DVec3::new(u(), u(), u())).collect();
        let q = quantizer(&pts, 21);
        let mut expected: Vec<(u64, u32)> = (0..pts.len())
            .map(|i| (hilbert_index(q(pts[i]), 21), i as u32))
            .collect();
        expected.sort_unstable();
        let expected: Vec<u32> = expected.into_iter().map(|(_, i)| i).collect();
        assert_eq!(hilbert_order(&pts), expected);
    }

    #[test]
    fn brio_is_a_deterministic_permutation() {
        let pts: Vec<DVec3> = (0..1000)
            .map(|i| DVec3::new((i % 10) as f64, (i / 10 % 10) as f64, (i / 100) as f64))
            .collect();
        let a = brio_order(&pts, 7);
        let mut sorted = a.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..1000).collect::<Vec<u32>>());
        assert_eq!(a, brio_order(&pts, 7));
    }
}
