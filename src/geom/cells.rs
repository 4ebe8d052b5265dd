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
