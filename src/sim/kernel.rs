//! The step's inner loop over one tile: stages 1–4 fused (bone transforms, spring forces,
//! Verlet, constraint), eight slots at a time.
//!
//! The slots of a tile are taken in groups of eight ([`LANES`]), one slot per lane, and each
//! group is carried through every stage in registers before the next starts: nothing is
//! written back to memory but the new positions. For a group:
//! 1. the surface-spring forces, row after row of [`Layout::lane_offsets`]: row `r` holds
//!    each lane's `r`-th neighbour (CSR order), so one row is eight springs, one per lane,
//!    evaluated together: gather the neighbours' positions, `d = x_j − x_i`, the factor
//!    `(|d| − rest) / |d|` (zero for a zero-length spring, which is what padded lanes hold:
//!    their neighbour is the slot itself) and `sum += factor × d`, in two phases per chunk
//!    of rows (gathers and squared lengths, then roots, divisions and sums) so that the
//!    divider always has independent work;
//! 2. the posed rest position, normal (made unit again in a tile whose transforms
//!    include one that scales, a trunk's swell) and bone points (one affine transform per
//!    lane, the same for all lanes of a single-section tile) and the two bone-spring
//!    forces;
//! 3. Verlet with velocity damping;
//! 4. the constraint: the circumsphere projection or the iterated spring reduction, both in
//!    lanes.
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

use super::contact::Floor;
#[cfg(target_arch = "x86_64")]
use super::lanes::Avx;
use super::lanes::{Lanes, Portable, LANES, V3};
use super::layout::{Layout, Packed};
use super::regions::PerSlot;
use super::{Constraint, Params};
use glam::{Affine3A, Vec3};
use std::ops::Range;

/// Everything a tile reads.
pub(super) struct Ctx<'a> {
    pub layout: &'a Layout,
    pub cur: &'a Packed,
    /// Each section's transform as four rows of four floats ([`Rows`]), one after another.
    pub transforms: &'a [[f32; 4]],
    pub params: Params,
    /// `D (h/h₀)²` and `C_vd^(h/h₀)`.
    pub stiffness: f32,
    pub damping: f32,
    /// Use the AVX2 build of the kernel.
    pub avx2: bool,
    /// Gravity's displacement per step, `g (h)²` (`None`: off).
    pub gravity: Option<[f32; 3]>,
    /// The floor (`None`: none).
    pub floor: Option<Floor>,
    /// Per-slot materials (`None`: every slot has `params`).
    pub mixed: Option<&'a PerSlot>,
    /// Per-slot pin weights (`None`: nothing pinned).
    pub pin: Option<&'a [f32]>,
}

impl Ctx<'_> {
    /// True when the step needs more than the paper's machinery: gravity, a floor, several
    /// materials, pinning or stiffening bone springs. Without them the kernel is compiled
    /// without those stages (a scene that does not use them pays nothing).
    pub fn extras(&self) -> bool {
        self.gravity.is_some()
            || self.floor.is_some()
            || self.mixed.is_some()
            || self.pin.is_some()
            || self.params.material.stiffening > 0
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
    if ctx.extras() {
        tile_body::<Portable, true>(ctx, range, points)
    } else {
        tile_body::<Portable, false>(ctx, range, points)
    }
}

/// The kernel compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn tile_avx2(ctx: &Ctx, range: Range<usize>, points: &mut [[f32; 4]]) -> f32 {
    if ctx.extras() {
        tile_body::<Avx, true>(ctx, range, points)
    } else {
        tile_body::<Avx, false>(ctx, range, points)
    }
}

/// Spring factor `(|d| − rest) / |d|` in lanes, 0 where `|d| = 0`: the force of the spring
/// on its mass point is `factor × d`.
#[inline(always)]
fn factor<V: Lanes>(dx: V, dy: V, dz: V, rest: V) -> V {
    let len = (dx * dx + dy * dy + dz * dz).sqrt();
    len.positive_or_zero((len - rest) / len)
}

/// A surface spring's factor from its squared length `|d|²`, its stiffness `c` and the
/// mean rest length `unit`: `c (|d| − rest) / |d| = c − unit / |d|` (`c · rest = unit`,
/// see [`crate::rig`]), 0 where `|d| = 0`. At rest it is exactly 0: `c` is `unit / rest`
/// rounded as this division rounds.
#[inline(always)]
fn surface_factor<V: Lanes>(len2: V, c: V, unit: V) -> V {
    let len = len2.sqrt();
    len.positive_or_zero(c - unit / len)
}

#[inline(always)]
fn tile_body<V: Lanes, const EXTRAS: bool>(
    ctx: &Ctx,
    range: Range<usize>,
    points: &mut [[f32; 4]],
) -> f32 {
    let l = ctx.layout;
    let cur = &ctx.cur.0[..];
    let g0 = range.start / l.tile * l.groups_per_tile();
    let tile_transforms = TileTransforms::<V>::of(ctx, range.start / l.tile);
    let scaled = scaled(ctx, range.start / l.tile);
    // The layout keeps every neighbour offset + 4 ≤ 4 × `l.len()` (its invariant), so with
    // this the gathers need no bounds checks (and no scan of the offsets every step).
    assert_eq!(cur.len(), l.len(), "positions and layout disagree");
    let groups = range.len().div_ceil(LANES);
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
            t: transform(ctx, &tile_transforms, k0, LANES),
            scaled,
            rows: rows(gi),
        };
        // SAFETY: `cur.len() == l.len()` (asserted above) and the layout's invariant.
        let (new, moved) = unsafe { group::<V, EXTRAS>(ctx, cur, g, Lanes8::Run(k0), &mut buf) };
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
            t: transform(ctx, &tile_transforms, k0, n),
            scaled,
            rows: rows(full),
        };
        // SAFETY: `cur.len() == l.len()` (asserted above) and the layout's invariant.
        let (new, moved) = unsafe { group::<V, EXTRAS>(ctx, cur, g, Lanes8::Slots(own), &mut buf) };
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

/// The slots of a group's lanes: eight in a row from the first, or listed.
#[derive(Clone, Copy)]
enum Lanes8 {
    Run(usize),
    Slots([u32; LANES]),
}

impl Lanes8 {
    /// A per-slot constant array in lanes. A method, not a closure: closures were not
    /// inlined into the AVX2 build, and neither were the intrinsics inside them.
    #[inline(always)]
    fn load<V: Lanes>(self, a: &[f32]) -> V {
        match self {
            Lanes8::Run(k0) => V::load(a, k0),
            Lanes8::Slots(own) => V::gather(a, &own),
        }
    }
}

/// Rows of springs per phase of [`group`]'s two-phase loop.
const CHUNK: usize = 8;

/// A transform whose first column's squared length is within `√RIGID` of 1 is rigid (a
/// swell, `joints::slide::MAX_SWELL` at most, scales one by far more where it matters):
/// the normals it moves are not normalised again.
const RIGID: f32 = 1e-12;

/// What [`group`] starts from: the current and previous positions of its slots, their
/// transforms ([`TileTransforms`]), whether one of the tile's transforms scales
/// ([`scaled`]) and the span of its spring rows.
struct Group<V> {
    x: V3<V>,
    before: V3<V>,
    t: [V; 12],
    scaled: bool,
    rows: Range<usize>,
}

/// Stages 1–4 for one group of eight slots: returns their new positions and squared
/// displacements. `buf` is scratch.
///
/// # Safety
/// Every neighbour in the group's spring rows must be less than `cur.len()`.
#[inline(always)]
unsafe fn group<V: Lanes, const EXTRAS: bool>(
    ctx: &Ctx,
    cur: &[[f32; 4]],
    Group {
        x,
        before,
        t,
        scaled,
        rows,
    }: Group<V>,
    slots: Lanes8,
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
    let (neighbours, stiffness) = (&l.lane_offsets()[rows.clone()], &l.lane_stiffness[rows]);
    let unit = V::splat(l.spring_length);
    for (idx, stiffness) in neighbours
        .chunks(LANES * CHUNK)
        .zip(stiffness.chunks(LANES * CHUNK))
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
        for (&[dx, dy, dz, len2], c) in buf.iter().zip(stiffness.chunks_exact(LANES)) {
            let k = surface_factor(len2, V::load(c, 0), unit);
            f.x = f.x + k * dx;
            f.y = f.y + k * dy;
            f.z = f.z + k * dz;
        }
    }

    // Stage 1: posed rest position and normal, glam's `transform_point3` /
    // `transform_vector3` written out in the same order (columns times coordinates, added
    // left to right, then the translation).
    let (p0, p1, p2) = (
        slots.load::<V>(&s.rest.x),
        slots.load::<V>(&s.rest.y),
        slots.load::<V>(&s.rest.z),
    );
    let r = V3 {
        x: t[0] * p0 + t[3] * p1 + t[6] * p2 + t[9],
        y: t[1] * p0 + t[4] * p1 + t[7] * p2 + t[10],
        z: t[2] * p0 + t[5] * p1 + t[8] * p2 + t[11],
    };
    let (m0, m1, m2) = (
        slots.load::<V>(&s.normal.x),
        slots.load::<V>(&s.normal.y),
        slots.load::<V>(&s.normal.z),
    );
    let nrm = V3 {
        x: t[0] * m0 + t[3] * m1 + t[6] * m2,
        y: t[1] * m0 + t[4] * m1 + t[7] * m2,
        z: t[2] * m0 + t[5] * m1 + t[8] * m2,
    };
    // Kept unit where a transform scales: a trunk's swollen level scales its slots
    // (`joints::slide`), and bone points spread by the scale would leave no rest position
    // within a strict material's bone-spring bounds. Only in a tile that holds such a
    // level (the root and division cost 7–20 % of an in-cache step), and a normal a rigid
    // transform moved is left as it is there too (unit to rounding).
    let nrm = if scaled {
        let nn = nrm.x * nrm.x + nrm.y * nrm.y + nrm.z * nrm.z;
        let off = nn - V::splat(1.0);
        let unit = (off * off).le_select(V::splat(RIGID), V::splat(1.0), V::splat(1.0) / nn.sqrt());
        V3 {
            x: nrm.x * unit,
            y: nrm.y * unit,
            z: nrm.z * unit,
        }
    } else {
        nrm
    };
    // Stage 2b: bone springs. inner = r − L n, outer = r + L n, as `bones` computes them.
    let lb = slots.load::<V>(&s.bone_length);
    let inner = V3 {
        x: r.x - lb * nrm.x,
        y: r.y - lb * nrm.y,
        z: r.z - lb * nrm.z,
    };
    let outer = V3 {
        x: r.x + lb * nrm.x,
        y: r.y + lb * nrm.y,
        z: r.z + lb * nrm.z,
    };
    let i = V3 {
        x: inner.x - x.x,
        y: inner.y - x.y,
        z: inner.z - x.z,
    };
    let o = V3 {
        x: outer.x - x.x,
        y: outer.y - x.y,
        z: outer.z - x.z,
    };
    let m = material::<V, EXTRAS>(ctx, slots);
    let mut fi = factor(i.x, i.y, i.z, slots.load::<V>(&s.inner_rest));
    let mut fo = factor(o.x, o.y, o.z, slots.load::<V>(&s.outer_rest));
    if EXTRAS && m.max_exponent > 0 {
        let rho = m.reach * lb;
        fi = fi * stiffening(i, slots.load::<V>(&s.inner_rest), rho, &m);
        fo = fo * stiffening(o, slots.load::<V>(&s.outer_rest), rho, &m);
    }
    let g = V3 {
        x: f.x + fi * i.x + fo * o.x,
        y: f.y + fi * i.y + fo * o.y,
        z: f.z + fi * i.z + fo * o.z,
    };

    // Stage 3: Verlet, `x + C_vd (x − x_prev) + D / m · F` (same order as Vec3 code).
    let (damping, k) = (m.damping, m.stiffness * slots.load::<V>(&s.inv_mass));
    let mut y = V3 {
        x: x.x + damping * (x.x - before.x) + k * g.x,
        y: x.y + damping * (x.y - before.y) + k * g.y,
        z: x.z + damping * (x.z - before.z) + k * g.z,
    };
    // Gravity, then pinning (a pinned point is drawn to its posed rest position).
    if let (true, Some([gx, gy, gz])) = (EXTRAS, ctx.gravity) {
        y = V3 {
            x: y.x + V::splat(gx),
            y: y.y + V::splat(gy),
            z: y.z + V::splat(gz),
        };
    }
    if let (true, Some(pin)) = (EXTRAS, ctx.pin) {
        let w = slots.load::<V>(pin);
        y = V3 {
            x: y.x + (r.x - y.x) * w,
            y: y.y + (r.y - y.y) * w,
            z: y.z + (r.z - y.z) * w,
        };
    }

    // The floor's friction: a point that would pass the floor keeps only part of its
    // sliding motion (before the constraint, so friction never holds a point away from
    // its bones).
    if let (true, Some(floor)) = (EXTRAS, ctx.floor) {
        y = floor.slide(y, x);
    }

    // Stage 4: the constraint.
    let new = match p.solver.constraint {
        Constraint::Circumsphere => {
            let v = V3 {
                x: y.x - r.x,
                y: y.y - r.y,
                z: y.z - r.z,
            };
            let d2 = v.x * v.x + v.y * v.y + v.z * v.z;
            let rho = m.reach * lb;
            let sc = rho / d2.sqrt();
            let rho2 = rho * rho;
            V3 {
                x: d2.le_select(rho2, y.x, r.x + v.x * sc),
                y: d2.le_select(rho2, y.y, r.y + v.y * sc),
                z: d2.le_select(rho2, y.z, r.z + v.z * sc),
            }
        }
        Constraint::SpringReduction => {
            let bounds = (m.min_length * lb, m.max_length * lb);
            spring_reduction_lanes(
                y,
                r,
                nrm,
                inner,
                outer,
                bounds,
                p.solver.reduction_iterations,
            )
        }
    };
    // Stage 4b: the floor, which no point passes: it wins over the constraint, so a section
    // posed into the floor squashes against it.
    let new = match (EXTRAS, ctx.floor) {
        (true, Some(floor)) => floor.hold(new),
        _ => new,
    };
    let (mx, my, mz) = (new.x - x.x, new.y - x.y, new.z - x.z);
    (new, mx * mx + my * my + mz * mz)
}

/// The transforms of the slots `k0 + lane` (lanes clamped to `n` slots), each as its
/// matrix columns, then its translation.
#[inline(always)]
fn transform<V: Lanes>(ctx: &Ctx, tile: &TileTransforms<V>, k0: usize, n: usize) -> [V; 12] {
    let section = &ctx.layout.slots.section;
    match tile {
        TileTransforms::Single(t) => *t,
        TileTransforms::Gathered => {
            let mut offsets = [[0u32; LANES]; 4];
            for lane in 0..LANES {
                let row = 4 * section[k0 + lane.min(n - 1)] as u32;
                for (c, o) in offsets.iter_mut().enumerate() {
                    o[lane] = 4 * (row + c as u32);
                }
            }
            let mut out = [V::splat(0.0); 12];
            for (c, o) in offsets.iter().enumerate() {
                // SAFETY: `TileTransforms::of` checked that every section of the tile has
                // its four rows in `ctx.transforms`, so each offset + 4 is at most
                // 4 × `ctx.transforms.len()`.
                let [x, y, z] = unsafe { V::gather3_unchecked(ctx.transforms, o) };
                out[3 * c] = x;
                out[3 * c + 1] = y;
                out[3 * c + 2] = z;
            }
            out
        }
    }
}

/// Whether a transform of tile `t`'s sections scales (its [`Rows`]' flag, [`rows_of`]).
#[inline(always)]
fn scaled(ctx: &Ctx, t: usize) -> bool {
    ctx.layout.sections_of_tile(t).iter().any(|&s| {
        ctx.transforms
            .get(4 * s as usize)
            .is_some_and(|r| r[3] != 0.0)
    })
}

/// How a tile's groups get their lanes' transforms.
enum TileTransforms<V> {
    /// One section in the whole tile: its coefficients, splatted once.
    Single([V; 12]),
    /// Several: gathered from `Ctx::transforms` lane by lane.
    Gathered,
}

impl<V: Lanes> TileTransforms<V> {
    /// # Panics
    /// If a section of tile `t` has no transform (the simulation keeps one per section).
    #[inline(always)]
    fn of(ctx: &Ctx, t: usize) -> TileTransforms<V> {
        let sections = ctx.layout.sections_of_tile(t);
        let rows = ctx.transforms.len() / 4;
        assert!(
            sections.iter().all(|&s| (s as usize) < rows),
            "a section without a transform"
        );
        match sections {
            &[section] => {
                let rows = &ctx.transforms[4 * section as usize..][..4];
                let mut out = [V::splat(0.0); 12];
                for (c, row) in rows.iter().enumerate() {
                    for i in 0..3 {
                        out[3 * c + i] = V::splat(row[i]);
                    }
                }
                TileTransforms::Single(out)
            }
            _ => TileTransforms::Gathered,
        }
    }
}

/// A transform as the kernel gathers it: its matrix columns, then its translation, each
/// as four floats (the fourth 0 but the first row's, whether it scales: [`rows_of`]).
pub(super) type Rows = [[f32; 4]; 4];

/// The identity as [`Rows`]: a section that has not moved.
pub(super) const IDENTITY_ROWS: Rows = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 0.0],
];

/// `t` as [`Rows`]; the first row's fourth float is 1 where `t` scales (not rigid to
/// [`RIGID`]), else 0.
pub(super) fn rows_of(t: &Affine3A) -> Rows {
    let (a, b, c, d) = (
        t.matrix3.x_axis,
        t.matrix3.y_axis,
        t.matrix3.z_axis,
        t.translation,
    );
    let off = a.length_squared() - 1.0;
    let scales = if off * off > RIGID { 1.0 } else { 0.0 };
    [
        [a.x, a.y, a.z, scales],
        [b.x, b.y, b.z, 0.0],
        [c.x, c.y, c.z, 0.0],
        [d.x, d.y, d.z, 0.0],
    ]
}

/// The transform of [`Rows`].
pub(super) fn affine_of(r: &Rows) -> Affine3A {
    let v = |i: usize| glam::Vec3::new(r[i][0], r[i][1], r[i][2]);
    Affine3A::from_cols(v(0).into(), v(1).into(), v(2).into(), v(3).into())
}

#[inline(always)]
fn arrays<V: Lanes>(v: V3<V>) -> [[f32; LANES]; 3] {
    [v.x.to_array(), v.y.to_array(), v.z.to_array()]
}

#[inline(always)]
fn v3<V: Lanes>([x, y, z]: [V; 3]) -> V3<V> {
    V3 { x, y, z }
}

/// The iterated spring reduction (`spring_reduction` in this module's tests) in lanes: the
/// same operations in the same order, lane by lane, so the results are the same bit for
/// bit. `inner` and `outer` are the bone points `r ∓ lb n`, `(lo, hi)` the bounds
/// `(f_min lb, sl_max lb)`. All lanes iterate until none is
/// violated (a lane with no violation is not changed by further iterations, so this is the
/// per-lane early exit); lanes still violated after the last iteration take the fallback,
/// also in lanes.
#[inline(always)]
fn spring_reduction_lanes<V: Lanes>(
    mut y: V3<V>,
    r: V3<V>,
    n: V3<V>,
    inner: V3<V>,
    outer: V3<V>,
    (lo, hi): (V, V),
    iterations: u32,
) -> V3<V> {
    let away_outer = V3 {
        x: n.x.neg(),
        y: n.y.neg(),
        z: n.z.neg(),
    };
    let zero = V::splat(0.0);
    let mut violated = V::mask(true);
    for _ in 0..iterations {
        violated = V::mask(false);
        for (b, away) in [(inner, n), (outer, away_outer)] {
            let v = V3 {
                x: y.x - b.x,
                y: y.y - b.y,
                z: y.z - b.z,
            };
            let len = (v.x * v.x + v.y * v.y + v.z * v.z).sqrt();
            let over = len.gt(hi);
            let under = over.and_not(len.lt(lo));
            let s = over.select(hi, lo) / len;
            // Too short and of zero length: pushed out along the normal instead.
            let pushed = len.gt(zero).and_not(under);
            let hit = over.or(under);
            y = V3 {
                x: hit.select(pushed.select(b.x + away.x * lo, b.x + v.x * s), y.x),
                y: hit.select(pushed.select(b.y + away.y * lo, b.y + v.y * s), y.y),
                z: hit.select(pushed.select(b.z + away.z * lo, b.z + v.z * s), y.z),
            };
            violated = violated.or(hit);
        }
        if !violated.any() {
            return y;
        }
    }
    // Lanes violated in the last iteration: the check and fallback of `spring_reduction`
    // after its loop, in lanes.
    let need = reduction_ok_lanes(y, inner, outer, lo, hi).and_not(violated);
    if !need.any() {
        return y;
    }
    // Bisection on the segment from the rest position `r` (where both springs have length
    // L, always feasible) to `y`.
    let (mut feasible, mut infeasible) = (zero, V::splat(1.0));
    for _ in 0..20 {
        let s = V::splat(0.5) * (feasible + infeasible);
        let ok = reduction_ok_lanes(along(r, y, s), inner, outer, lo, hi);
        feasible = ok.select(s, feasible);
        infeasible = ok.select(infeasible, s);
    }
    let fallback = along(r, y, feasible);
    V3 {
        x: need.select(fallback.x, y.x),
        y: need.select(fallback.y, y.y),
        z: need.select(fallback.z, y.z),
    }
}

/// The material constants of a group's lanes.
struct Material<V> {
    /// `C_vd^(h/h₀)` and `D (h/h₀)²`.
    damping: V,
    stiffness: V,
    /// `sl_max − 1`, `f_min`, `sl_max`.
    reach: V,
    min_length: V,
    max_length: V,
    /// Stiffening exponent per lane, and the largest of any slot (0: Hooke everywhere).
    exponent: V,
    max_exponent: u32,
}

/// The lanes' material: the parameters' (the same for every slot) or each slot's own.
#[inline(always)]
fn material<V: Lanes, const EXTRAS: bool>(ctx: &Ctx, slots: Lanes8) -> Material<V> {
    let p = &ctx.params;
    match (EXTRAS, ctx.mixed) {
        (false, _) | (true, None) => Material {
            damping: V::splat(ctx.damping),
            stiffness: V::splat(ctx.stiffness),
            reach: V::splat(p.material.max_length - 1.0),
            min_length: V::splat(p.material.min_length),
            max_length: V::splat(p.material.max_length),
            exponent: V::splat(p.material.stiffening as f32),
            max_exponent: p.material.stiffening,
        },
        (true, Some(m)) => Material {
            damping: slots.load(&m.damping),
            stiffness: slots.load(&m.stiffness),
            reach: slots.load(&m.reach),
            min_length: slots.load(&m.min_length),
            max_length: slots.load(&m.max_length),
            exponent: slots.load(&m.exponent),
            max_exponent: m.max_exponent,
        },
    }
}

/// The stiffening of a bone spring `d` (from the mass point to the bone point) of rest
/// length `rest`: `min(|(|d| − rest)| / ρ, 1)^e` (1 where `ρ = 0`).
#[inline(always)]
fn stiffening<V: Lanes>(d: V3<V>, rest: V, rho: V, m: &Material<V>) -> V {
    let one = V::splat(1.0);
    let stretch = (d.x * d.x + d.y * d.y + d.z * d.z).sqrt() - rest;
    let size = stretch.max(stretch.neg()) / rho;
    let s = rho
        .gt(V::splat(0.0))
        .select(size.lt(one).select(size, one), one);
    let mut out = one;
    for e in 0..m.max_exponent {
        out = m.exponent.gt(V::splat(e as f32)).select(out * s, out);
    }
    out
}

/// `r + (y − r) s`.
#[inline(always)]
fn along<V: Lanes>(r: V3<V>, y: V3<V>, s: V) -> V3<V> {
    V3 {
        x: r.x + (y.x - r.x) * s,
        y: r.y + (y.y - r.y) * s,
        z: r.z + (y.z - r.z) * s,
    }
}

/// `reduction_ok` in lanes (a mask). Helper functions, not closures: closures were not
/// inlined into the AVX2 build, and neither were the intrinsics inside them.
#[inline(always)]
fn reduction_ok_lanes<V: Lanes>(y: V3<V>, inner: V3<V>, outer: V3<V>, lo: V, hi: V) -> V {
    let slack = V::splat(1e-6) * hi.max(V::splat(1e-30));
    let (lo, hi) = (lo - slack, hi + slack);
    within(y, inner, lo, hi).and(within(y, outer, lo, hi))
}

/// `lo <= |y − b| <= hi` (false for NaN, as in the scalar code).
#[inline(always)]
fn within<V: Lanes>(y: V3<V>, b: V3<V>, lo: V, hi: V) -> V {
    let (vx, vy, vz) = (y.x - b.x, y.y - b.y, y.z - b.z);
    let len = (vx * vx + vy * vy + vz * vz).sqrt();
    lo.le(len).and(len.le(hi))
}

/// Bone points of a posed rest position `r` with unit normal `n` and bone length `lb`.
#[inline(always)]
pub(super) fn bones(r: Vec3, n: Vec3, lb: f32) -> (Vec3, Vec3) {
    (r - lb * n, r + lb * n)
}

/// Is `y` within both bone-spring bounds (with a relative slack for rounding)?
#[cfg(test)]
fn reduction_ok(y: Vec3, inner: Vec3, outer: Vec3, lo: f32, hi: f32) -> bool {
    let slack = 1e-6 * hi.max(1e-30);
    [inner, outer].iter().all(|b| {
        let len = (y - *b).length();
        len >= lo - slack && len <= hi + slack
    })
}

/// Iterated clamping of both bone springs of a mass point into `[f_min L, f_max L]`
/// (see the module docs of `sim`). `r` is the posed rest position, `n` the posed normal.
/// The specification of [`spring_reduction_lanes`], which the kernel runs (tested equal
/// bit for bit).
#[cfg(test)]
fn spring_reduction(mut y: Vec3, r: Vec3, n: Vec3, lb: f32, p: &Params) -> Vec3 {
    let (inner, outer) = bones(r, n, lb);
    let (lo, hi) = (p.material.min_length * lb, p.material.max_length * lb);
    for _ in 0..p.solver.reduction_iterations {
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
    reduction_fallback(y, r, inner, outer, lo, hi)
}

/// The end of `spring_reduction` when its iterations ran out: `y` if it is feasible, else
/// the feasible point nearest to it on the segment towards the rest position `r`.
#[cfg(test)]
fn reduction_fallback(y: Vec3, r: Vec3, inner: Vec3, outer: Vec3, lo: f32, hi: f32) -> Vec3 {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Points around a bone pair in every regime the reduction has: inside, too far, too
    /// close, exactly on a bone point (zero length), NaN, and budgets from 0 to 4 (with
    /// budget 0 or 1 many end in the fallback).
    fn cases() -> Vec<(Vec3, Vec3, Vec3, f32)> {
        let mut state = 0x2545_f491_u32;
        let mut rand = move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        let mut out = Vec::new();
        for k in 0..4000 {
            let r = Vec3::new(rand(), rand(), rand()) * 3.0;
            let n = Vec3::new(rand(), rand(), rand()).normalize_or(Vec3::Z);
            let lb = 0.01 + rand().abs();
            let y = match k % 5 {
                0 => r + Vec3::new(rand(), rand(), rand()) * lb * 4.0,
                1 => r + Vec3::new(rand(), rand(), rand()) * lb * 0.3,
                2 => r - lb * n,
                3 => r + lb * n + Vec3::new(rand(), rand(), rand()) * 1e-3,
                _ if k % 50 == 4 => Vec3::NAN,
                _ => r + Vec3::new(rand(), rand(), rand()) * lb * 20.0,
            };
            out.push((y, r, n, lb));
        }
        out
    }

    fn check<V: Lanes>() {
        for iterations in 0..=4 {
            for (min, max) in [(0.8, 1.2), (0.5, 1.5), (1.0, 1.0), (0.99, 1.01)] {
                let mut p = Params::default();
                (p.material.min_length, p.material.max_length) = (min, max);
                p.solver.reduction_iterations = iterations;
                for group in cases().chunks_exact(LANES) {
                    let lane = |f: &dyn Fn(usize) -> f32| V::from_array(std::array::from_fn(f));
                    let v3 = |f: &dyn Fn(usize) -> Vec3| V3 {
                        x: lane(&|l| f(l).x),
                        y: lane(&|l| f(l).y),
                        z: lane(&|l| f(l).z),
                    };
                    let bone = |l: usize| bones(group[l].1, group[l].2, group[l].3);
                    let lb = lane(&|l| group[l].3);
                    let got = spring_reduction_lanes(
                        v3(&|l| group[l].0),
                        v3(&|l| group[l].1),
                        v3(&|l| group[l].2),
                        v3(&|l| bone(l).0),
                        v3(&|l| bone(l).1),
                        (
                            V::splat(p.material.min_length) * lb,
                            V::splat(p.material.max_length) * lb,
                        ),
                        p.solver.reduction_iterations,
                    );
                    let got = arrays(got);
                    for (l, &(y, r, n, lb)) in group.iter().enumerate() {
                        let want = spring_reduction(y, r, n, lb, &p);
                        for c in 0..3 {
                            assert_eq!(
                                got[c][l].to_bits(),
                                want[c].to_bits(),
                                "lane {l} axis {c}: {y} {r} {n} {lb} with {p:?}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn spring_reduction_in_lanes_is_the_scalar_one_bit_for_bit() {
        check::<Portable>();
        #[cfg(target_arch = "x86_64")]
        if avx2_available() {
            #[target_feature(enable = "avx2")]
            fn avx() {
                check::<Avx>();
            }
            // SAFETY: the CPU has AVX2 (checked just above).
            unsafe { avx() };
        }
    }

    /// The identity's rows are the identity's, and rows convert back to the transform.
    #[test]
    fn rows_round_trip() {
        assert_eq!(IDENTITY_ROWS, rows_of(&Affine3A::IDENTITY));
        let t = Affine3A::from_scale_rotation_translation(
            glam::Vec3::new(1.0, 2.0, 0.5),
            glam::Quat::from_rotation_y(0.7),
            glam::Vec3::new(3.0, -1.0, 2.0),
        );
        assert_eq!(affine_of(&rows_of(&t)), t);
    }
}
