//! Spatial insertion order: 3D Hilbert curve keys and BRIO (biased randomized insertion
//! order, Amenta–Choi–Rote): random rounds of doubling size, each sorted along the Hilbert
//! curve. This keeps point location walks short while keeping the expected cost of
//! randomized incremental construction. The random source is seeded, so the order (and the
//! tetrahedralization) is deterministic.

use glam::DVec3;

/// Hilbert index of a point with `bits`-bit integer coordinates (Skilling's transpose
/// algorithm), `3 * bits <= 63`.
pub fn hilbert_index(mut x: [u32; 3], bits: u32) -> u64 {
    let m = 1u32 << (bits - 1);
    // Inverse undo excess work.
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
    // Gray encode.
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

/// A small deterministic PRNG (SplitMix64).
#[derive(Clone, Debug)]
pub struct SplitMix(pub u64);

impl SplitMix {
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
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
    let q = quantizer(points, BITS);
    by_key(
        points
            .iter()
            .enumerate()
            .map(|(i, p)| (hilbert_index(q(*p), BITS), i as u32))
            .collect(),
    )
}

/// BRIO order of `points`: indices into `points`. The keys are computed and sorted on all
/// cores (the order does not depend on how many).
pub fn brio_order(points: &[DVec3], seed: u64) -> Vec<u32> {
    use rayon::prelude::*;
    const BITS: u32 = 16;
    const MAX_ROUND: u32 = 12;
    let q = quantizer(points, BITS);
    let mut rng = SplitMix(seed);
    // Round r (0 = last, biggest) with probability 2^-(r+1); earlier rounds first.
    let rounds: Vec<u8> = (0..points.len())
        .map(|_| rng.next_u64().trailing_ones().min(MAX_ROUND) as u8)
        .collect();
    by_key(
        points
            .par_iter()
            .zip(rounds.par_iter())
            .enumerate()
            .map(|(i, (p, &round))| {
                let key = ((MAX_ROUND - round as u32) as u64) << 48 | hilbert_index(q(*p), BITS);
                (key, i as u32)
            })
            .collect(),
    )
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
