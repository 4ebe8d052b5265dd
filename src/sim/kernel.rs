//! The step's inner loop over one tile: stages 1–4 fused (bone transforms, spring forces,
//! Verlet, constraint), eight slots at a time.
//!
//! The slots of a tile are taken in groups of eight ([`LANES`]), one slot per lane, and each
//! group is carried through every stage in registers before the next starts: nothing is
//! written back to memory but the new positions. For a group:
//! 1. the surface-spring forces, row after row of [`Layout::lane_offset`]: row `r` holds
//!    each lane's `r`-th neighbour (CSR order), so one row is eight springs, one per lane,
//!    evaluated together: gather the neighbours' positions, `d = x_j − x_i`, the factor
//!    `(|d| − rest) / |d|` (zero for a zero-length spring, which is what padded lanes hold:
//!    their neighbour is the slot itself) and `sum += factor × d`;
//! 2. the posed rest position, normal and bone points (one affine transform per lane, the
//!    same for all lanes of a single-section tile) and the two bone-spring forces;
//! 3. Verlet with velocity damping;
//! 4. the constraint: the circumsphere projection in lanes, or the iterated spring reduction
//!    lane by lane.
//!
//! Every spring is evaluated from both of its ends; the two evaluations are exact negations
//! of each other (`a − b = −(b − a)` and IEEE negation are exact), so this is bit for bit what
//! evaluating it once and adding the negated force at the other end gives (an earlier kernel
//! did that, through per-tile scratch arrays that cost more than the second evaluation).
//!
//! The code is generic over [`Lanes`] and compiled twice: with AVX2 registers ([`Avx`],
//! chosen at run time) and with plain arrays ([`Portable`]). Only `+ − × ÷ √`, comparisons
//! and selects are used, each correctly rounded, in the same order on both, so the two builds
//! give bit-identical results (tested), whatever the thread count.

#[cfg(target_arch = "x86_64")]
use super::lanes::Avx;
use super::lanes::{Lanes, Portable, LANES};
use super::layout::{Layout, Packed};
use super::{Constraint, Params};
use glam::{Affine3A, Vec3};
use std::ops::Range;

/// Everything a tile reads.
pub(super) struct Ctx<'a> {
    pub layout: &'a Layout,
    pub cur: &'a Packed,
    pub transforms: &'a [Affine3A],
    pub params: Params,
    /// `D (h/h₀)²` and `C_vd^(h/h₀)`.
    pub stiffness: f32,
    pub damping: f32,
    /// Use the AVX2 build of the kernel.
    pub avx2: bool,
}

impl Ctx<'_> {
    #[inline(always)]
    pub fn transform(&self, section: u16) -> Affine3A {
        self.transforms
            .get(section as usize)
            .copied()
            .unwrap_or(Affine3A::IDENTITY)
    }
}

/// Is the AVX2 build usable on this CPU?
pub(super) fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Integrates the slots `range` (one tile). `points` holds the tile's previous positions on
/// entry and its new positions on return. Returns the largest squared displacement of
/// the step in the tile.
pub(super) fn tile(ctx: &Ctx, range: Range<usize>, points: &mut [[f32; 4]]) -> f32 {
    #[cfg(target_arch = "x86_64")]
    if ctx.avx2 {
        // SAFETY: `ctx.avx2` is only set when `avx2_available()` said the CPU has AVX2.
        return unsafe { tile_avx2(ctx, range, points) };
    }
    tile_body::<Portable>(ctx, range, points)
}

/// The kernel compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn tile_avx2(ctx: &Ctx, range: Range<usize>, points: &mut [[f32; 4]]) -> f32 {
    tile_body::<Avx>(ctx, range, points)
}

/// Spring factor `(|d| − rest) / |d|` in lanes, 0 where `|d| = 0`: the force of the spring
/// on its mass point is `factor × d`.
#[inline(always)]
fn factor<V: Lanes>(dx: V, dy: V, dz: V, rest: V) -> V {
    let len = (dx * dx + dy * dy + dz * dz).sqrt();
    len.positive_or_zero((len - rest) / len)
}

/// A vector in lanes.
#[derive(Clone, Copy)]
struct V3<V> {
    x: V,
    y: V,
    z: V,
}

#[inline(always)]
fn tile_body<V: Lanes>(ctx: &Ctx, range: Range<usize>, points: &mut [[f32; 4]]) -> f32 {
    let l = ctx.layout;
    let cur = &ctx.cur.0[..];
    let s = &l.slots;
    let g0 = range.start / l.tile * l.groups_per_tile();
    let single = match l.sections_of_tile(range.start / l.tile) {
        [section] => {
            let t = ctx.transform(*section);
            Some(columns::<V>(|_| t))
        }
        _ => None,
    };
    // The transforms of the slots `k0 + lane`, lanes clamped to `n` slots.
    let transform = |k0: usize, n: usize| match &single {
        Some(t) => *t,
        None => columns::<V>(|lane| ctx.transform(s.section[k0 + lane.min(n - 1)])),
    };
    // Every neighbour slot of the tile's spring rows, checked once here so the gathers
    // need no bounds checks.
    let groups = range.len().div_ceil(LANES);
    let span = l.group_start[g0] as usize..l.group_start[g0 + groups] as usize;
    let largest = l.lane_offset[span].iter().fold(0, |m, &q| m.max(q));
    assert!(
        largest as usize + 4 <= 4 * cur.len(),
        "spring rows past the last slot"
    );
    let rows = |gi: usize| l.group_start[g0 + gi] as usize..l.group_start[g0 + gi + 1] as usize;

    let mut moved_max = V::splat(0.0);
    // Set once per tile: zeroing it per group was a `memset` call per group.
    let mut buf = [[V::splat(0.0); 4]; CHUNK];
    let full = range.len() / LANES;
    for gi in 0..full {
        let (k0, j0) = (range.start + gi * LANES, gi * LANES);
        let g = Group {
            x: v3(V::load3(cur, k0)),
            before: v3(V::load3(points, j0)),
            t: transform(k0, LANES),
            rows: rows(gi),
        };
        // SAFETY: the tile's neighbours were checked against `cur.len()` above.
        let (new, moved) = unsafe { group(ctx, cur, g, |a| V::load(a, k0), LANES, &mut buf) };
        moved_max = moved.max(moved_max);
        V::store3([new.x, new.y, new.z], points, j0);
    }
    if full < groups {
        // The short last group: lanes past its end repeat its last slot (their `moved` is
        // that slot's), and only its own lanes are written back.
        let (k0, j0, n) = (
            range.start + full * LANES,
            full * LANES,
            range.len() % LANES,
        );
        let (mut own, mut local) = ([0u32; LANES], [0u32; LANES]);
        for lane in 0..LANES {
            own[lane] = (k0 + lane.min(n - 1)) as u32;
            local[lane] = (j0 + lane.min(n - 1)) as u32;
        }
        let g = Group {
            x: v3(V::gather3(cur, &own)),
            before: v3(V::gather3(points, &local)),
            t: transform(k0, n),
            rows: rows(full),
        };
        // SAFETY: the tile's neighbours were checked against `cur.len()` above.
        let (new, moved) = unsafe { group(ctx, cur, g, |a| V::gather(a, &own), n, &mut buf) };
        moved_max = moved.max(moved_max);
        let [nx, ny, nz] = arrays(new);
        for (l, q) in points[j0..j0 + n].iter_mut().enumerate() {
            *q = [nx[l], ny[l], nz[l], 0.0];
        }
    }
    let moved = moved_max.to_array();
    moved[1..]
        .iter()
        .fold(moved[0], |w, &m| if m > w { m } else { w })
}

/// Rows of springs per phase of [`group`]'s two-phase loop.
const CHUNK: usize = 8;

/// What [`group`] starts from: the current and previous positions of its slots, their
/// transforms ([`columns`]) and the span of its spring rows.
struct Group<V> {
    x: V3<V>,
    before: V3<V>,
    t: [V; 12],
    rows: Range<usize>,
}

/// Stages 1–4 for one group of eight slots: returns their new positions and squared
/// displacements. `load` reads a per-slot constant array in lanes; only the first `n`
/// lanes are live (the spring reduction skips the others). `buf` is scratch.
///
/// # Safety
/// Every neighbour in the group's spring rows must be less than `cur.len()`.
#[inline(always)]
unsafe fn group<V: Lanes>(
    ctx: &Ctx,
    cur: &[[f32; 4]],
    Group { x, before, t, rows }: Group<V>,
    load: impl Fn(&[f32]) -> V,
    n: usize,
    buf: &mut [[V; 4]; CHUNK],
) -> (V3<V>, V) {
    let l = ctx.layout;
    let s = &l.slots;
    let p = &ctx.params;

    // Stage 2a: surface springs, one row (eight springs, one per lane) at a time.
    let zero = V::splat(0.0);
    let mut f = V3 {
        x: zero,
        y: zero,
        z: zero,
    };
    // In two phases per chunk of rows: first the gathers and squared lengths, then the
    // square roots, divisions and sums. Fused in one loop, each row was one long dependency
    // chain (gather, √, ÷, sum) of about 50 instructions, and the out-of-order window held
    // too few rows to keep the divider busy.
    let (neighbours, rests) = (&l.lane_offset[rows.clone()], &l.lane_rest[rows]);
    for (idx, rest) in neighbours
        .chunks(LANES * CHUNK)
        .zip(rests.chunks(LANES * CHUNK))
    {
        for (b, idx) in buf.iter_mut().zip(idx.chunks_exact(LANES)) {
            let Some(idx) = idx.first_chunk::<LANES>() else {
                break;
            };
            // SAFETY: the caller promises every neighbour is less than `cur.len()`.
            let [qx, qy, qz] = unsafe { V::gather3_unchecked(cur, idx) };
            let (dx, dy, dz) = (qx - x.x, qy - x.y, qz - x.z);
            *b = [dx, dy, dz, dx * dx + dy * dy + dz * dz];
        }
        for (&[dx, dy, dz, len2], rest) in buf.iter().zip(rest.chunks_exact(LANES)) {
            let len = len2.sqrt();
            let k = len.positive_or_zero((len - V::load(rest, 0)) / len);
            f.x = f.x + k * dx;
            f.y = f.y + k * dy;
            f.z = f.z + k * dz;
        }
    }

    // Stage 1: posed rest position and normal, glam's `transform_point3` /
    // `transform_vector3` written out in the same order (columns times coordinates, added
    // left to right, then the translation).
    let (p0, p1, p2) = (load(&s.rest.x), load(&s.rest.y), load(&s.rest.z));
    let r = V3 {
        x: t[0] * p0 + t[3] * p1 + t[6] * p2 + t[9],
        y: t[1] * p0 + t[4] * p1 + t[7] * p2 + t[10],
        z: t[2] * p0 + t[5] * p1 + t[8] * p2 + t[11],
    };
    let (m0, m1, m2) = (load(&s.normal.x), load(&s.normal.y), load(&s.normal.z));
    let nrm = V3 {
        x: t[0] * m0 + t[3] * m1 + t[6] * m2,
        y: t[1] * m0 + t[4] * m1 + t[7] * m2,
        z: t[2] * m0 + t[5] * m1 + t[8] * m2,
    };
    // Stage 2b: bone springs. inner = r − L n, outer = r + L n, as `bones` computes them.
    let lb = load(&s.bone_length);
    let i = V3 {
        x: (r.x - lb * nrm.x) - x.x,
        y: (r.y - lb * nrm.y) - x.y,
        z: (r.z - lb * nrm.z) - x.z,
    };
    let o = V3 {
        x: (r.x + lb * nrm.x) - x.x,
        y: (r.y + lb * nrm.y) - x.y,
        z: (r.z + lb * nrm.z) - x.z,
    };
    let fi = factor(i.x, i.y, i.z, load(&s.inner_rest));
    let fo = factor(o.x, o.y, o.z, load(&s.outer_rest));
    let g = V3 {
        x: f.x + fi * i.x + fo * o.x,
        y: f.y + fi * i.y + fo * o.y,
        z: f.z + fi * i.z + fo * o.z,
    };

    // Stage 3: Verlet, `x + C_vd (x − x_prev) + D / m · F` (same order as Vec3 code).
    let (damping, k) = (
        V::splat(ctx.damping),
        V::splat(ctx.stiffness) * load(&s.inv_mass),
    );
    let y = V3 {
        x: x.x + damping * (x.x - before.x) + k * g.x,
        y: x.y + damping * (x.y - before.y) + k * g.y,
        z: x.z + damping * (x.z - before.z) + k * g.z,
    };

    // Stage 4: the constraint.
    let new = match p.constraint {
        Constraint::Circumsphere => {
            let v = V3 {
                x: y.x - r.x,
                y: y.y - r.y,
                z: y.z - r.z,
            };
            let d2 = v.x * v.x + v.y * v.y + v.z * v.z;
            let rho = V::splat(p.max_length - 1.0) * lb;
            let sc = rho / d2.sqrt();
            let rho2 = rho * rho;
            V3 {
                x: d2.le_select(rho2, y.x, r.x + v.x * sc),
                y: d2.le_select(rho2, y.y, r.y + v.y * sc),
                z: d2.le_select(rho2, y.z, r.z + v.z * sc),
            }
        }
        Constraint::SpringReduction => {
            let (y, r, nrm, lb) = (arrays(y), arrays(r), arrays(nrm), lb.to_array());
            let mut out = [[0.0f32; LANES]; 3];
            for lane in 0..n {
                let at = |a: &[[f32; LANES]; 3]| Vec3::new(a[0][lane], a[1][lane], a[2][lane]);
                let q = spring_reduction(at(&y), at(&r), at(&nrm), lb[lane], p);
                (out[0][lane], out[1][lane], out[2][lane]) = (q.x, q.y, q.z);
            }
            V3 {
                x: V::from_array(out[0]),
                y: V::from_array(out[1]),
                z: V::from_array(out[2]),
            }
        }
    };
    let (mx, my, mz) = (new.x - x.x, new.y - x.y, new.z - x.z);
    (new, mx * mx + my * my + mz * mz)
}

/// The twelve coefficients of each lane's transform: the matrix columns, then the
/// translation.
#[inline(always)]
fn columns<V: Lanes>(transform: impl Fn(usize) -> Affine3A) -> [V; 12] {
    // Plain loops, no `array::from_fn`: its closures were not inlined into the AVX2 build,
    // and neither were the intrinsics inside them (perf showed `_mm256_loadu_ps` calls).
    let mut t = [[0.0f32; LANES]; 12];
    for lane in 0..LANES {
        let m = transform(lane);
        let (a, b, c, d) = (
            m.matrix3.x_axis,
            m.matrix3.y_axis,
            m.matrix3.z_axis,
            m.translation,
        );
        let coefficients = [a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, d.x, d.y, d.z];
        for (row, v) in t.iter_mut().zip(coefficients) {
            row[lane] = v;
        }
    }
    let mut out = [V::splat(0.0); 12];
    for (o, row) in out.iter_mut().zip(t) {
        *o = V::from_array(row);
    }
    out
}

#[inline(always)]
fn arrays<V: Lanes>(v: V3<V>) -> [[f32; LANES]; 3] {
    [v.x.to_array(), v.y.to_array(), v.z.to_array()]
}

#[inline(always)]
fn v3<V: Lanes>([x, y, z]: [V; 3]) -> V3<V> {
    V3 { x, y, z }
}

/// Bone points of a posed rest position `r` with unit normal `n` and bone length `lb`.
#[inline(always)]
pub(super) fn bones(r: Vec3, n: Vec3, lb: f32) -> (Vec3, Vec3) {
    (r - lb * n, r + lb * n)
}

/// Is `y` within both bone-spring bounds (with a relative slack for rounding)?
#[inline(always)]
fn reduction_ok(y: Vec3, inner: Vec3, outer: Vec3, lo: f32, hi: f32) -> bool {
    let slack = 1e-6 * hi.max(1e-30);
    [inner, outer].iter().all(|b| {
        let len = (y - *b).length();
        len >= lo - slack && len <= hi + slack
    })
}

/// Iterated clamping of both bone springs of a mass point into `[f_min L, f_max L]`
/// (see the module docs of `sim`). `r` is the posed rest position, `n` the posed normal.
#[inline(always)]
pub(super) fn spring_reduction(mut y: Vec3, r: Vec3, n: Vec3, lb: f32, p: &Params) -> Vec3 {
    let (inner, outer) = bones(r, n, lb);
    let (lo, hi) = (p.min_length * lb, p.max_length * lb);
    for _ in 0..p.reduction_iterations {
        let mut violated = false;
        for (b, away) in [(inner, n), (outer, -n)] {
            let v = y - b;
            let len = v.length();
            if len > hi {
                y = b + v * (hi / len);
                violated = true;
            } else if len < lo {
                y = if len > 0.0 {
                    b + v * (lo / len)
                } else {
                    b + away * lo
                };
                violated = true;
            }
        }
        if !violated {
            return y;
        }
    }
    if reduction_ok(y, inner, outer, lo, hi) {
        return y;
    }
    // Budget spent: pull towards the rest position (where both springs have length L,
    // always feasible) until feasible, by bisection on the segment.
    let (mut feasible, mut infeasible) = (0.0f32, 1.0f32);
    for _ in 0..20 {
        let s = 0.5 * (feasible + infeasible);
        if reduction_ok(r + (y - r) * s, inner, outer, lo, hi) {
            feasible = s;
        } else {
            infeasible = s;
        }
    }
    r + (y - r) * feasible
}
