//! Skeletons cached by mesh content, so reopening a mesh (a second `open` of the same file
//! in the window, a reload after a failed edit, a rig file pointing at the same mesh) never
//! recomputes its skeleton. Changing the bone distance never needs the skeleton at all
//! (`rig::Rig::set_bone_distance` is O(n)).
//!
//! The key is a 128-bit content hash (two independent FNV-1a-64 streams) of the welded
//! positions (exact bits), the triangles and the skeleton parameters; the process keeps
//! the [`CAPACITY`] most recently used skeletons.

use super::{build, Skeleton, SkeletonError, SkeletonParams};
use crate::mesh::Mesh;
use crate::progress::Progress;
use glam::DVec3;
use std::sync::Mutex;

/// Skeletons kept in memory.
pub const CAPACITY: usize = 4;

static CACHE: Mutex<Vec<(u128, Skeleton)>> = Mutex::new(Vec::new());

/// Content key of a mesh and skeleton parameters.
pub fn key(mesh: &Mesh, params: &SkeletonParams) -> u128 {
    struct Fnv(u64);
    impl Fnv {
        fn eat(&mut self, bytes: &[u8]) {
            for &b in bytes {
                self.0 ^= b as u64;
                self.0 = self.0.wrapping_mul(0x0000_0100_0000_01B3);
            }
        }
    }
    let (mut a, mut b) = (Fnv(0xcbf2_9ce4_8422_2325), Fnv(0x6c62_272e_07bb_0142));
    let mut eat = |bytes: &[u8]| {
        a.eat(bytes);
        b.eat(bytes);
        b.eat(&[0x5a]);
    };
    eat(&(mesh.positions.len() as u64).to_le_bytes());
    for p in &mesh.positions {
        for c in p.to_array() {
            eat(&c.to_bits().to_le_bytes());
        }
    }
    eat(&(mesh.triangles.len() as u64).to_le_bytes());
    for t in &mesh.triangles {
        for v in t {
            eat(&v.to_le_bytes());
        }
    }
    eat(&[params.method as u8]);
    eat(&params.sliver_ratio.to_bits().to_le_bytes());
    (a.0 as u128) << 64 | b.0 as u128
}

/// [`build`], or the cached skeleton of the same mesh and parameters.
pub fn build_cached(
    mesh: &Mesh,
    normals: &[DVec3],
    params: &SkeletonParams,
    progress: Progress,
) -> Result<Skeleton, SkeletonError> {
    let k = key(mesh, params);
    if let Some(sk) = take(k) {
        log::info!("skeleton: cached ({} vertices)", mesh.positions.len());
        progress("skeleton (cached)", 1.0);
        return Ok(sk);
    }
    let sk = build(mesh, normals, params, progress)?;
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    cache.retain(|(c, _)| *c != k);
    cache.push((k, sk.clone()));
    if cache.len() > CAPACITY {
        cache.remove(0);
    }
    Ok(sk)
}

/// The cached skeleton for `k`, moved to the most recently used place.
fn take(k: u128) -> Option<Skeleton> {
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    let at = cache.iter().position(|(c, _)| *c == k)?;
    let entry = cache.remove(at);
    let sk = entry.1.clone();
    cache.push(entry);
    Some(sk)
}

/// Forgets every cached skeleton.
pub fn clear() {
    CACHE.lock().unwrap_or_else(|e| e.into_inner()).clear();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{shapes, vertex_normals};

    #[test]
    fn reopening_the_same_mesh_uses_the_cache_and_changes_do_not() {
        let mesh = shapes::icosphere(1.0, 2);
        let normals = vertex_normals(&mesh).unwrap();
        let params = SkeletonParams::default();
        let first = build_cached(&mesh, &normals, &params, crate::progress::silent()).unwrap();
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let count = |_: &str, _: f64| {
            calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        };
        let again = build_cached(&mesh, &normals, &params, &count).unwrap();
        assert_eq!(first.distance, again.distance);
        // A cache hit reports one "done" and runs no stage.
        assert_eq!(calls.load(std::sync::atomic::Ordering::Relaxed), 1);
        assert!(again.seconds == first.seconds);
        // Any change of content or parameters is a different key.
        let mut moved = mesh.clone();
        moved.positions[0].x += 1e-12;
        assert_ne!(key(&mesh, &params), key(&moved, &params));
        let other = SkeletonParams {
            method: crate::skeleton::Method::Pole,
            ..params
        };
        assert_ne!(key(&mesh, &params), key(&mesh, &other));
    }
}
