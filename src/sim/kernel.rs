//! The step's inner loop over one tile: stages 1–4 fused (bone transforms, spring forces,
//! Verlet, constraint), written so the compiler vectorizes the arithmetic.
//!
//! A tile is processed in three passes over small scratch arrays that stay in L1:
//! 1. per slot, the posed rest position, normal and bone points (one affine transform of the
//!    slot's section), and the spring vectors `x_j − x_i` of the springs it evaluates (the
//!    only gathers): a spring with both ends in the tile is evaluated once, at its lower slot
//!    ([`super::layout::Layout::eval_start`]);
//! 2. the spring forces `(|d| − rest) / |d| · d` over the evaluated springs of the tile: a
//!    straight loop of `sqrt` and `div` that compiles to 8-wide AVX2 (4-wide SSE2 without it);
//! 3. the force sum of each slot in CSR order, eight slots at a time, each term looked up
//!    through [`super::layout::Layout::term_lanes`] (negated for the upper end of a spring,
//!    which is bit for bit the term evaluated from that end: IEEE negation and
//!    `a − b = −(b − a)` are exact); then Verlet with velocity damping and the constraint.
//!
//! Only `+ − × ÷ √` are used, all correctly rounded in IEEE arithmetic, in the same order on
//! every path, so the AVX2 build of this code and the portable one give bit-identical results
//! (tested), whatever the thread count.

use super::layout::{len3, Layout, Soa};
use super::{Constraint, Params};
use glam::{Affine3A, Vec3};
use std::cell::RefCell;
use std::ops::Range;

/// Everything a tile reads.
pub(super) struct Ctx<'a> {
    pub layout: &'a Layout,
    pub cur: &'a Soa,
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

/// Per-thread scratch, grown once to the largest tile and then reused (no allocation per
/// step).
#[derive(Default)]
pub(super) struct Scratch {
    // Per spring of the tile.
    dx: Vec<f32>,
    dy: Vec<f32>,
    dz: Vec<f32>,
    // Per slot of the tile: posed rest position, normal, bone vectors and factors.
    rx: Vec<f32>,
    ry: Vec<f32>,
    rz: Vec<f32>,
    nx: Vec<f32>,
    ny: Vec<f32>,
    nz: Vec<f32>,
    ix: Vec<f32>,
    iy: Vec<f32>,
    iz: Vec<f32>,
    ox: Vec<f32>,
    oy: Vec<f32>,
    oz: Vec<f32>,
    fi: Vec<f32>,
    fo: Vec<f32>,
    // Per slot: the force sum, the squared displacement.
    gx: Vec<f32>,
    gy: Vec<f32>,
    gz: Vec<f32>,
    moved: Vec<f32>,
}

impl Scratch {
    fn reserve(&mut self, springs: usize, slots: usize) {
        for v in [&mut self.dx, &mut self.dy, &mut self.dz] {
            if v.len() < springs {
                v.resize(springs, 0.0);
            }
        }
        for v in [
            &mut self.rx,
            &mut self.ry,
            &mut self.rz,
            &mut self.nx,
            &mut self.ny,
            &mut self.nz,
            &mut self.ix,
            &mut self.iy,
            &mut self.iz,
            &mut self.ox,
            &mut self.oy,
            &mut self.oz,
            &mut self.fi,
            &mut self.fo,
            &mut self.gx,
            &mut self.gy,
            &mut self.gz,
            &mut self.moved,
        ] {
            if v.len() < slots {
                v.resize(slots, 0.0);
            }
        }
    }
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
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

/// Integrates the slots `range` (one tile). `px, py, pz` hold the tile's previous positions
/// on entry and its new positions on return. Returns the largest squared displacement of
/// the step in the tile.
pub(super) fn tile(
    ctx: &Ctx,
    range: Range<usize>,
    px: &mut [f32],
    py: &mut [f32],
    pz: &mut [f32],
) -> f32 {
    SCRATCH.with(|s| {
        let sc = &mut s.borrow_mut();
        #[cfg(target_arch = "x86_64")]
        if ctx.avx2 {
            // SAFETY: `ctx.avx2` is only set when `avx2_available()` said the CPU has AVX2.
            return unsafe { tile_avx2(ctx, range, px, py, pz, sc) };
        }
        tile_body(ctx, range, px, py, pz, sc)
    })
}

/// The kernel compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn tile_avx2(
    ctx: &Ctx,
    range: Range<usize>,
    px: &mut [f32],
    py: &mut [f32],
    pz: &mut [f32],
    sc: &mut Scratch,
) -> f32 {
    tile_body(ctx, range, px, py, pz, sc)
}

/// Spring factor `(|d| − rest) / |d|` (0 for a zero-length spring): the force of the
/// spring on its mass point is `factor × d`.
#[inline(always)]
fn factor(dx: f32, dy: f32, dz: f32, rest: f32) -> f32 {
    let len = len3(dx, dy, dz);
    if len > 0.0 {
        (len - rest) / len
    } else {
        0.0
    }
}

#[inline(always)]
fn tile_body(
    ctx: &Ctx,
    range: Range<usize>,
    px: &mut [f32],
    py: &mut [f32],
    pz: &mut [f32],
    sc: &mut Scratch,
) -> f32 {
    let l = ctx.layout;
    let cur = ctx.cur;
    let v0 = l.eval_start[range.start] as usize;
    let me = l.eval_start[range.end] as usize - v0;
    let nv = range.len();
    // One more spring entry than evaluated: the zero force that padded lanes point at.
    sc.reserve(me + 1, nv);

    // Pass 1: posed bones and spring vectors. Local slices: the compiler then keeps their
    // pointers in registers instead of reloading them after every store.
    let (cx, cy, cz) = (&cur.x[..], &cur.y[..], &cur.z[..]);
    let start = &l.start[range.start..=range.end];
    let neighbour = &l.eval_neighbour[v0..v0 + me];
    let (dx, dy, dz) = (&mut sc.dx[..me], &mut sc.dy[..me], &mut sc.dz[..me]);
    let out = Bones {
        rx: &mut sc.rx[..nv],
        ry: &mut sc.ry[..nv],
        rz: &mut sc.rz[..nv],
        nx: &mut sc.nx[..nv],
        ny: &mut sc.ny[..nv],
        nz: &mut sc.nz[..nv],
        ix: &mut sc.ix[..nv],
        iy: &mut sc.iy[..nv],
        iz: &mut sc.iz[..nv],
        ox: &mut sc.ox[..nv],
        oy: &mut sc.oy[..nv],
        oz: &mut sc.oz[..nv],
    };
    let tile_sections = l.sections_of_tile(range.start / l.tile);
    if let [section] = tile_sections {
        // One section (most tiles): one transform for the whole tile, a vector loop.
        let t = ctx.transform(*section);
        posed_bones(ctx, range.clone(), |_| t, out);
    } else {
        let sections = &l.slots.section[range.clone()];
        posed_bones(ctx, range.clone(), |j| ctx.transform(sections[j]), out);
    }
    // The spring vectors, in one flat loop over the tile's evaluated springs (a loop per
    // slot, with its varying trip count, mispredicted its exit about once per slot).
    let owner = &l.eval_owner[v0..v0 + me];
    let (tx, ty, tz) = (&cx[range.clone()], &cy[range.clone()], &cz[range.clone()]);
    for e in 0..me {
        let (q, o) = (neighbour[e] as usize, owner[e] as usize);
        dx[e] = cx[q] - tx[o];
        dy[e] = cy[q] - ty[o];
        dz[e] = cz[q] - tz[o];
    }

    // Pass 2: spring forces `factor × d`, in place over the spring vectors, vectorized
    // (every operand contiguous; with the rest lengths read from strided records this loop
    // stayed scalar). Entry `me` is the zero force of padded lanes.
    {
        let (dx, dy, dz) = (&mut sc.dx[..me], &mut sc.dy[..me], &mut sc.dz[..me]);
        let rest = &l.eval_rest[v0..v0 + me];
        for e in 0..me {
            let f = factor(dx[e], dy[e], dz[e], rest[e]);
            (dx[e], dy[e], dz[e]) = (f * dx[e], f * dy[e], f * dz[e]);
        }
        (sc.dx[me], sc.dy[me], sc.dz[me]) = (0.0, 0.0, 0.0);
        let (ix, iy, iz) = (&sc.ix[..nv], &sc.iy[..nv], &sc.iz[..nv]);
        let (ox, oy, oz) = (&sc.ox[..nv], &sc.oy[..nv], &sc.oz[..nv]);
        let (fi, fo) = (&mut sc.fi[..nv], &mut sc.fo[..nv]);
        let (ri, ro) = (
            &l.slots.inner_rest[range.clone()],
            &l.slots.outer_rest[range.clone()],
        );
        for j in 0..nv {
            fi[j] = factor(ix[j], iy[j], iz[j], ri[j]);
            fo[j] = factor(ox[j], oy[j], oz[j], ro[j]);
        }
    }

    // Pass 3a: force sums, 8 slots at a time through the transposed terms
    // ([`Layout::term_lanes`]): eight independent additions per row instead of one chain
    // per slot. Then the two bone springs.
    let groups = nv.div_ceil(Layout::LANES);
    let g0 = range.start / l.tile * l.groups_per_tile();
    let group_start = &l.group_start[g0..=g0 + groups];
    let lanes = &l.term_lanes[group_start[0] as usize..group_start[groups] as usize];
    let forces = [&sc.dx[..=me], &sc.dy[..=me], &sc.dz[..=me]];
    let sums = [&mut sc.gx[..nv], &mut sc.gy[..nv], &mut sc.gz[..nv]];
    force_sums(group_start, lanes, forces, sums);
    let (ix, iy, iz, fi) = (&sc.ix[..nv], &sc.iy[..nv], &sc.iz[..nv], &sc.fi[..nv]);
    let (ox, oy, oz, fo) = (&sc.ox[..nv], &sc.oy[..nv], &sc.oz[..nv], &sc.fo[..nv]);
    let (gx, gy, gz) = (&mut sc.gx[..nv], &mut sc.gy[..nv], &mut sc.gz[..nv]);
    for j in 0..nv {
        gx[j] = gx[j] + fi[j] * ix[j] + fo[j] * ox[j];
        gy[j] = gy[j] + fi[j] * iy[j] + fo[j] * oy[j];
        gz[j] = gz[j] + fi[j] * iz[j] + fo[j] * oz[j];
    }

    // Pass 3b: Verlet and the constraint. The circumsphere is a straight, branch-free loop
    // over slots (vectorized); the iterated spring reduction stays per slot.
    let (gx, gy, gz) = (&sc.gx[..nv], &sc.gy[..nv], &sc.gz[..nv]);
    let (rx, ry, rz) = (&sc.rx[..nv], &sc.ry[..nv], &sc.rz[..nv]);
    let (cx, cy, cz) = (&cx[range.clone()], &cy[range.clone()], &cz[range.clone()]);
    let lbs = &l.slots.bone_length[range.clone()];
    let moved = &mut sc.moved[..nv];
    let (px, py, pz) = (&mut px[..nv], &mut py[..nv], &mut pz[..nv]);
    let (damping, stiffness) = (ctx.damping, ctx.stiffness);
    let p = &ctx.params;
    match p.constraint {
        Constraint::Circumsphere => {
            let rho_factor = p.max_length - 1.0;
            for j in 0..nv {
                let inv_mass = 1.0 / (start[j + 1] - start[j] + 2) as f32;
                let k = stiffness * inv_mass;
                // The same expressions, in the same order, as Vec3 arithmetic would use.
                let (x, y, z) = (cx[j], cy[j], cz[j]);
                let yx = x + damping * (x - px[j]) + k * gx[j];
                let yy = y + damping * (y - py[j]) + k * gy[j];
                let yz = z + damping * (z - pz[j]) + k * gz[j];
                let (vx, vy, vz) = (yx - rx[j], yy - ry[j], yz - rz[j]);
                let d2 = vx * vx + vy * vy + vz * vz;
                let rho = rho_factor * lbs[j];
                let s = rho / d2.sqrt();
                let inside = d2 <= rho * rho;
                let nx = if inside { yx } else { rx[j] + vx * s };
                let ny = if inside { yy } else { ry[j] + vy * s };
                let nz = if inside { yz } else { rz[j] + vz * s };
                let (mx, my, mz) = (nx - x, ny - y, nz - z);
                moved[j] = mx * mx + my * my + mz * mz;
                (px[j], py[j], pz[j]) = (nx, ny, nz);
            }
        }
        Constraint::SpringReduction => {
            let (nx, ny, nz) = (&sc.nx[..nv], &sc.ny[..nv], &sc.nz[..nv]);
            for j in 0..nv {
                let inv_mass = 1.0 / (start[j + 1] - start[j] + 2) as f32;
                let f = Vec3::new(gx[j], gy[j], gz[j]);
                let x = Vec3::new(cx[j], cy[j], cz[j]);
                let before = Vec3::new(px[j], py[j], pz[j]);
                let y = x + damping * (x - before) + (stiffness * inv_mass) * f;
                let r = Vec3::new(rx[j], ry[j], rz[j]);
                let n = Vec3::new(nx[j], ny[j], nz[j]);
                let y = spring_reduction(y, r, n, lbs[j], p);
                moved[j] = (y - x).length_squared();
                (px[j], py[j], pz[j]) = (y.x, y.y, y.z);
            }
        }
    }
    moved.iter().fold(0.0f32, |w, &m| w.max(m))
}

/// The surface-spring force sum of every slot of a tile (see [`Layout::term_lanes`]):
/// `sums[axis][8 g + lane]` is the sum, in CSR order, of the signed forces
/// `forces[axis][term]` over row after row of group `g`. Padded terms add `+0`.
///
/// Scalar loads on purpose: the same loop with AVX2 gathers (`vgatherdps`) was slower on
/// this project's machine (3.7M springs, 4 alternating runs each: 26.5–36.2 ms with
/// gathers, 22.0–36.1 ms for this loop, 23.9–38.5 ms for the previous per-slot loop; perf
/// put the time on the instructions waiting for the gathers).
#[inline(always)]
fn force_sums(group_start: &[u32], lanes: &[u32], forces: [&[f32]; 3], sums: [&mut [f32]; 3]) {
    const L: usize = Layout::LANES;
    let base = group_start[0] as usize;
    let nv = sums[0].len();
    let [sx, sy, sz] = sums;
    for g in 0..group_start.len() - 1 {
        let rows = &lanes[group_start[g] as usize - base..group_start[g + 1] as usize - base];
        let (mut ax, mut ay, mut az) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
        for row in rows.chunks_exact(L) {
            for lane in 0..L {
                let term = row[lane];
                let c = (term & !Layout::NEGATE) as usize;
                let sign = term & Layout::NEGATE;
                // Exact negation: flip the sign bit.
                ax[lane] += f32::from_bits(forces[0][c].to_bits() ^ sign);
                ay[lane] += f32::from_bits(forces[1][c].to_bits() ^ sign);
                az[lane] += f32::from_bits(forces[2][c].to_bits() ^ sign);
            }
        }
        for lane in 0..L.min(nv - g * L) {
            let j = g * L + lane;
            (sx[j], sy[j], sz[j]) = (ax[lane], ay[lane], az[lane]);
        }
    }
}

/// Where [`posed_bones`] writes, per slot of the tile: the posed rest position `r` and
/// normal `n`, and the bone vectors `inner − x`, `outer − x`.
struct Bones<'a> {
    rx: &'a mut [f32],
    ry: &'a mut [f32],
    rz: &'a mut [f32],
    nx: &'a mut [f32],
    ny: &'a mut [f32],
    nz: &'a mut [f32],
    ix: &'a mut [f32],
    iy: &'a mut [f32],
    iz: &'a mut [f32],
    ox: &'a mut [f32],
    oy: &'a mut [f32],
    oz: &'a mut [f32],
}

/// Pass 1 of the kernel: the posed bones of every slot of `range`, slot `j` of the tile
/// posed by `transform(j)`. With a transform that does not depend on `j` this is a straight
/// vector loop over the struct-of-arrays constants. The arithmetic is glam's
/// `transform_point3` / `transform_vector3` written out in the same order (columns times
/// coordinates, added left to right, then the translation), so both loops agree bit for bit.
#[inline(always)]
fn posed_bones(ctx: &Ctx, range: Range<usize>, transform: impl Fn(usize) -> Affine3A, o: Bones) {
    let s = &ctx.layout.slots;
    let (px, py, pz) = (
        &s.rest.x[range.clone()],
        &s.rest.y[range.clone()],
        &s.rest.z[range.clone()],
    );
    let (mx, my, mz) = (
        &s.normal.x[range.clone()],
        &s.normal.y[range.clone()],
        &s.normal.z[range.clone()],
    );
    let lbs = &s.bone_length[range.clone()];
    let cur = ctx.cur;
    let (x, y, z) = (&cur.x[range.clone()], &cur.y[range.clone()], &cur.z[range]);
    let nv = x.len();
    for j in 0..nv {
        let t = transform(j);
        let (a, b, c, d) = (
            t.matrix3.x_axis,
            t.matrix3.y_axis,
            t.matrix3.z_axis,
            t.translation,
        );
        let (p0, p1, p2) = (px[j], py[j], pz[j]);
        let rx = a.x * p0 + b.x * p1 + c.x * p2 + d.x;
        let ry = a.y * p0 + b.y * p1 + c.y * p2 + d.y;
        let rz = a.z * p0 + b.z * p1 + c.z * p2 + d.z;
        let (m0, m1, m2) = (mx[j], my[j], mz[j]);
        let nx = a.x * m0 + b.x * m1 + c.x * m2;
        let ny = a.y * m0 + b.y * m1 + c.y * m2;
        let nz = a.z * m0 + b.z * m1 + c.z * m2;
        let lb = lbs[j];
        (o.rx[j], o.ry[j], o.rz[j]) = (rx, ry, rz);
        (o.nx[j], o.ny[j], o.nz[j]) = (nx, ny, nz);
        // inner = r − L n, outer = r + L n, as `bones` computes them.
        o.ix[j] = (rx - lb * nx) - x[j];
        o.iy[j] = (ry - lb * ny) - y[j];
        o.iz[j] = (rz - lb * nz) - z[j];
        o.ox[j] = (rx + lb * nx) - x[j];
        o.oy[j] = (ry + lb * ny) - y[j];
        o.oz[j] = (rz + lb * nz) - z[j];
    }
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
