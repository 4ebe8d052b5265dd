//! Quadric-error decimation by half-edge collapses (Garland & Heckbert's error, but each
//! edge collapses into one of its ends, so every vertex left is one of the input's: a
//! decimated analytic shape keeps its vertices exactly on the surface). Used for the
//! uneven test shapes of `bench::truth`: its triangles are as uneven as those of a
//! decimated scan or a game character.

use crate::mesh::Mesh;
use glam::DVec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A symmetric 4×4 quadric `vᵀ Q v`, stored as its upper triangle.
#[derive(Clone, Copy, Default)]
struct Quadric([f64; 10]);

impl Quadric {
    /// The squared distance to the plane `n·x + d = 0`, weighted.
    fn plane(n: DVec3, d: f64, w: f64) -> Quadric {
        let p = [n.x, n.y, n.z, d];
        let mut q = [0.0; 10];
        let mut k = 0;
        for i in 0..4 {
            for j in i..4 {
                q[k] = w * p[i] * p[j];
                k += 1;
            }
        }
        Quadric(q)
    }

    fn add(&mut self, o: &Quadric) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }

    fn error(&self, v: DVec3) -> f64 {
        let p = [v.x, v.y, v.z, 1.0];
        let mut e = 0.0;
        let mut k = 0;
        for i in 0..4 {
            for j in i..4 {
                let f = if i == j { 1.0 } else { 2.0 };
                e += f * self.0[k] * p[i] * p[j];
                k += 1;
            }
        }
        e
    }
}

/// A candidate collapse of `from` into `to`, cheapest first.
struct Candidate {
    cost: f64,
    from: u32,
    to: u32,
    stamp: (u32, u32),
}

impl PartialEq for Candidate {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Candidate {
    fn cmp(&self, o: &Self) -> Ordering {
        o.cost
            .total_cmp(&self.cost)
            .then(o.from.cmp(&self.from))
            .then(o.to.cmp(&self.to))
    }
}

/// Collapses edges of a closed manifold mesh, cheapest quadric error first, until at most
/// `target` vertices are left (or no collapse keeps the mesh a manifold without flipped
/// faces). The vertices left keep their positions; their order is the input's.
pub fn decimate(mesh: &Mesh, target: usize) -> Mesh {
    let n = mesh.positions.len();
    let pos = &mesh.positions;
    let mut faces: Vec<[u32; 3]> = mesh.triangles.clone();
    let mut alive_face = vec![true; faces.len()];
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut quadric = vec![Quadric::default(); n];
    for (f, t) in faces.iter().enumerate() {
        let (a, b, c) = (pos[t[0] as usize], pos[t[1] as usize], pos[t[2] as usize]);
        let cross = (b - a).cross(c - a);
        let area = 0.5 * cross.length();
        let nrm = cross.normalize_or_zero();
        let q = Quadric::plane(nrm, -nrm.dot(a), area);
        for &v in t {
            quadric[v as usize].add(&q);
            around[v as usize].push(f as u32);
        }
    }
    let mut alive = vec![true; n];
    let mut stamp = vec![0u32; n];
    let mut left = n;
    let mut heap = BinaryHeap::new();
    let neighbours = |around: &[Vec<u32>], faces: &[[u32; 3]], v: u32| -> Vec<u32> {
        let mut out: Vec<u32> = around[v as usize]
            .iter()
            .flat_map(|&f| faces[f as usize])
            .filter(|&w| w != v)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    };
    let push =
        |heap: &mut BinaryHeap<Candidate>, quadric: &[Quadric], stamp: &[u32], u: u32, v: u32| {
            let mut q = quadric[u as usize];
            q.add(&quadric[v as usize]);
            heap.push(Candidate {
                cost: q.error(pos[v as usize]),
                from: u,
                to: v,
                stamp: (stamp[u as usize], stamp[v as usize]),
            });
        };
    for t in &faces {
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            push(&mut heap, &quadric, &stamp, u, v);
            push(&mut heap, &quadric, &stamp, v, u);
        }
    }
    while left > target.max(4) {
        let Some(c) = heap.pop() else { break };
        let (u, v) = (c.from, c.to);
        if !alive[u as usize]
            || !alive[v as usize]
            || c.stamp != (stamp[u as usize], stamp[v as usize])
        {
            continue;
        }
        // The link condition: u and v share exactly the two vertices opposite their edge.
        let nu = neighbours(&around, &faces, u);
        let nv = neighbours(&around, &faces, v);
        if !nu.contains(&v) {
            continue;
        }
        let common = nu.iter().filter(|w| nv.binary_search(w).is_ok()).count();
        let shared: Vec<u32> = around[u as usize]
            .iter()
            .copied()
            .filter(|&f| faces[f as usize].contains(&v))
            .collect();
        if common != 2 || shared.len() != 2 || nu.len() <= 3 || nv.len() <= 3 {
            continue;
        }
        // No face around u may flip or become a needle when u moves to v.
        let keeps_shape = around[u as usize].iter().all(|&f| {
            let t = faces[f as usize];
            if t.contains(&v) {
                return true;
            }
            let p = |w: u32| {
                if w == u {
                    pos[v as usize]
                } else {
                    pos[w as usize]
                }
            };
            let old = (pos[t[1] as usize] - pos[t[0] as usize])
                .cross(pos[t[2] as usize] - pos[t[0] as usize]);
            let new = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            new.dot(old) > 0.5 * old.length() * new.length() && new.length() > 1e-12
        });
        if !keeps_shape {
            continue;
        }
        for &f in &shared {
            alive_face[f as usize] = false;
        }
        let moved: Vec<u32> = around[u as usize]
            .iter()
            .copied()
            .filter(|&f| alive_face[f as usize])
            .collect();
        for &f in &moved {
            for w in &mut faces[f as usize] {
                if *w == u {
                    *w = v;
                }
            }
        }
        for w in faces[shared[0] as usize]
            .into_iter()
            .chain(faces[shared[1] as usize])
        {
            around[w as usize].retain(|&f| alive_face[f as usize]);
        }
        around[v as usize].extend(moved);
        around[u as usize].clear();
        alive[u as usize] = false;
        left -= 1;
        let q = quadric[u as usize];
        quadric[v as usize].add(&q);
        stamp[v as usize] += 1;
        for w in neighbours(&around, &faces, v) {
            stamp[w as usize] += 1;
        }
        for w in neighbours(&around, &faces, v) {
            for x in neighbours(&around, &faces, w) {
                push(&mut heap, &quadric, &stamp, w, x);
                push(&mut heap, &quadric, &stamp, x, w);
            }
        }
    }
    let mut index = vec![u32::MAX; n];
    let mut positions = Vec::with_capacity(left);
    for v in 0..n {
        if alive[v] {
            index[v] = positions.len() as u32;
            positions.push(pos[v]);
        }
    }
    let triangles = faces
        .iter()
        .zip(&alive_face)
        .filter(|(_, &a)| a)
        .map(|(t, _)| t.map(|v| index[v as usize]))
        .collect();
    Mesh {
        positions,
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{shapes, validate};

    #[test]
    fn a_decimated_sphere_is_a_closed_manifold_on_the_sphere() {
        let sphere = shapes::icosphere(1.0, 4);
        let mut m = decimate(&sphere, 500);
        assert!(m.positions.len() <= 500 && m.positions.len() > 400);
        for p in &m.positions {
            assert!((p.length() - 1.0).abs() < 1e-12);
        }
        assert!(validate(&mut m).is_ok());
        assert!(m.signed_volume() > 0.9 * 4.0 / 3.0 * std::f64::consts::PI * 0.8);
    }
}
