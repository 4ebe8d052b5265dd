//! A character as a smooth union of tapered capsules, meshed by surface nets: closed,
//! manifold, with near-even triangles, so the labelled set's generated characters look
//! like what a sculpting tool exports.

use glam::DVec3;

/// A tapered capsule from `a` (radius `ra`) to `b` (radius `rb`).
#[derive(Clone, Copy, Debug)]
pub struct Bone {
    pub a: DVec3,
    pub b: DVec3,
    pub ra: f64,
    pub rb: f64,
    /// Bones of one group (a limb's chain) join without a blend, as sphere-swept
    /// capsules do: a blend would swell every knee and elbow.
    pub group: usize,
}

impl Bone {
    fn field(&self, p: DVec3) -> f64 {
        let ba = self.b - self.a;
        let t = ((p - self.a).dot(ba) / ba.length_squared().max(1e-12)).clamp(0.0, 1.0);
        (p - self.a - ba * t).length() - (self.ra + (self.rb - self.ra) * t)
    }
}

/// The polynomial smooth minimum of width `k`.
fn smooth_min(d: f64, e: f64, k: f64) -> f64 {
    if !d.is_finite() {
        return e;
    }
    let h = (k - (d - e).abs()).max(0.0) / k;
    d.min(e) - h * h * k * 0.25
}

/// The implicit body: the smooth minimum (blend width `blend`) of its bones' fields.
pub struct Body {
    pub bones: Vec<Bone>,
    pub blend: f64,
}

impl Body {
    pub fn field(&self, p: DVec3) -> f64 {
        let k = self.blend;
        let groups = self.bones.iter().map(|b| b.group + 1).max().unwrap_or(0);
        // Within a group, a blend a quarter as wide: enough to round the crease inside a
        // bent knee, too little to swell it.
        let mut per = vec![f64::INFINITY; groups];
        for b in &self.bones {
            per[b.group] = smooth_min(per[b.group], b.field(p), 0.25 * k);
        }
        per.into_iter()
            .fold(f64::INFINITY, |d, e| smooth_min(d, e, k))
    }

    fn gradient(&self, p: DVec3, h: f64) -> DVec3 {
        let f = |d: DVec3| self.field(p + d) - self.field(p - d);
        DVec3::new(f(DVec3::X * h), f(DVec3::Y * h), f(DVec3::Z * h)) / (2.0 * h)
    }

    /// Surface nets on a grid of cell `cell`: one vertex per cell the surface crosses,
    /// pulled onto the surface, and two triangles per grid edge it crosses.
    pub fn mesh(&self, cell: f64, offset: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for b in &self.bones {
            let r = b.ra.max(b.rb);
            lo = lo.min(b.a.min(b.b) - DVec3::splat(r));
            hi = hi.max(b.a.max(b.b) + DVec3::splat(r));
        }
        // A grid offset of a fraction of a cell keeps grid points off the bones' axes.
        lo -= DVec3::splat(2.0 * cell) + DVec3::splat(cell * offset);
        hi += DVec3::splat(2.0 * cell);
        let n = ((hi - lo) / cell).ceil().as_uvec3() + 1;
        let (nx, ny, nz) = (n.x as usize, n.y as usize, n.z as usize);
        let at =
            |i: usize, j: usize, k: usize| lo + DVec3::new(i as f64, j as f64, k as f64) * cell;
        let idx = |i: usize, j: usize, k: usize| (k * ny + j) * nx + i;
        let mut f = vec![0.0; nx * ny * nz];
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let v = self.field(at(i, j, k));
                    // Never exactly on the surface.
                    f[idx(i, j, k)] = if v == 0.0 { 1e-9 } else { v };
                }
            }
        }
        // One vertex per crossed cell (indexed by its lowest corner).
        let mut vertex = vec![u32::MAX; nx * ny * nz];
        let mut positions = Vec::new();
        for k in 0..nz - 1 {
            for j in 0..ny - 1 {
                for i in 0..nx - 1 {
                    let mut sum = DVec3::ZERO;
                    let mut count = 0;
                    let corner = |c: usize| (i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                    for c in 0..8 {
                        for axis in 0..3 {
                            if c & (1 << axis) != 0 {
                                continue;
                            }
                            let (a, b) = (corner(c), corner(c | (1 << axis)));
                            let (fa, fb) = (f[idx(a.0, a.1, a.2)], f[idx(b.0, b.1, b.2)]);
                            if (fa < 0.0) != (fb < 0.0) {
                                let t = fa / (fa - fb);
                                let pa = at(a.0, a.1, a.2);
                                sum += pa + (at(b.0, b.1, b.2) - pa) * t;
                                count += 1;
                            }
                        }
                    }
                    if count == 0 {
                        continue;
                    }
                    let mut p = sum / count as f64;
                    let g = self.gradient(p, cell * 0.1);
                    if g.length_squared() > 1e-12 {
                        p -= g * self.field(p) / g.length_squared();
                    }
                    let box_lo = at(i, j, k);
                    // Inside its cell, off its walls: no two vertices meet.
                    p = p.clamp(
                        box_lo + DVec3::splat(0.05 * cell),
                        box_lo + DVec3::splat(0.95 * cell),
                    );
                    vertex[idx(i, j, k)] = positions.len() as u32;
                    positions.push(p);
                }
            }
        }
        // A quad around each crossed grid edge, from the four cells that share it.
        let mut triangles = Vec::new();
        for k in 1..nz - 1 {
            for j in 1..ny - 1 {
                for i in 1..nx - 1 {
                    let f0 = f[idx(i, j, k)];
                    for axis in 0..3 {
                        let (i1, j1, k1) = match axis {
                            0 => (i + 1, j, k),
                            1 => (i, j + 1, k),
                            _ => (i, j, k + 1),
                        };
                        if i1 >= nx || j1 >= ny || k1 >= nz {
                            continue;
                        }
                        let f1 = f[idx(i1, j1, k1)];
                        if (f0 < 0.0) == (f1 < 0.0) {
                            continue;
                        }
                        // The four cells around the edge, in order around the axis.
                        let cells: [(usize, usize, usize); 4] = match axis {
                            0 => [(i, j - 1, k - 1), (i, j, k - 1), (i, j, k), (i, j - 1, k)],
                            1 => [(i - 1, j, k - 1), (i - 1, j, k), (i, j, k), (i, j, k - 1)],
                            _ => [(i - 1, j - 1, k), (i, j - 1, k), (i, j, k), (i - 1, j, k)],
                        };
                        let q = cells.map(|(a, b, c)| vertex[idx(a, b, c)]);
                        if q.contains(&u32::MAX) {
                            continue;
                        }
                        // Inside at the low end: the surface faces +axis.
                        let q = if f0 < 0.0 {
                            q
                        } else {
                            [q[3], q[2], q[1], q[0]]
                        };
                        let d02 = positions[q[0] as usize].distance(positions[q[2] as usize]);
                        let d13 = positions[q[1] as usize].distance(positions[q[3] as usize]);
                        if d02 <= d13 {
                            triangles.push([q[0], q[1], q[2]]);
                            triangles.push([q[0], q[2], q[3]]);
                        } else {
                            triangles.push([q[0], q[1], q[3]]);
                            triangles.push([q[1], q[2], q[3]]);
                        }
                    }
                }
            }
        }
        (positions, triangles)
    }
}

/// Is the surface closed and manifold: every edge in two faces of opposite direction, and
/// the faces around every vertex one fan?
pub fn manifold(triangles: &[[u32; 3]], vertices: usize) -> bool {
    use std::collections::HashMap;
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    if edges
        .iter()
        .any(|(&(a, b), &n)| n != 1 || edges.get(&(b, a)) != Some(&1))
    {
        return false;
    }
    // Around each vertex: the next corner of each face, followed from one to the next.
    let mut next: Vec<Vec<(u32, u32)>> = vec![Vec::new(); vertices];
    for t in triangles {
        for k in 0..3 {
            next[t[k] as usize].push((t[(k + 1) % 3], t[(k + 2) % 3]));
        }
    }
    next.iter().all(|fan| {
        let Some(&(start, _)) = fan.first() else {
            return true;
        };
        let mut at = start;
        let mut seen = 0;
        loop {
            let Some(&(_, b)) = fan.iter().find(|&&(a, _)| a == at) else {
                return false;
            };
            seen += 1;
            at = b;
            if at == start || seen > fan.len() {
                break;
            }
        }
        seen == fan.len()
    })
}
