//! The dynamics (paper §3.2–3.3): position Verlet with velocity damping on the rig's mass
//! points, then the circumsphere or the spring-reduction constraint.
//!
//! # Units: what `D` and `C_vd` mean
//! The simulation runs on a fixed step `h` (default and maximum [`REFERENCE_STEP`] = 1/60 s),
//! decoupled from the render rate ([`Simulation::advance`] accumulates frame time). Every
//! vertex has a lumped mass equal to its number of springs (`deg_i + 2`), and
//! * `D` (stiffness, dimensionless) is the spring constant in units of that mass per
//!   reference step squared: one step moves a vertex by `D (h/h₀)² / (deg_i + 2)` times the
//!   sum of its spring stretch vectors. For this degree-normalised system the explicit step
//!   is stable for `D ≤ 1` at any `h ≤ h₀`, which is why the paper's `D = 1` is the top of
//!   the UI range ([`MAX_STIFFNESS`]).
//! * `C_vd` (damping) is the share of velocity kept per reference step; a step of `h` keeps
//!   `C_vd^(h/h₀)`.
//!
//! With both scaled by `h/h₀`, a preset behaves the same at any step size or frame rate.
//!
//! # The constraints
//! * circumsphere: after integration a mass point farther than `ρ_i = (f_max − 1) L_i` from
//!   its rest position (moved with its section) is put back on that sphere. We read the
//!   paper's `ρ = f_max L` as `(f_max − 1) L` (see `shared/paper/READING.md`): only then does
//!   `sl_max = 1` mean "no elastic movement" as Table 1 says.
//! * spring reduction (Provot): each bone spring is clamped into `[f_min L, f_max L]` by
//!   moving its mass-point end, alternating inner and outer spring, at most
//!   `reduction_iterations` times, stopping as soon as nothing is violated. If the budget runs
//!   out, the point is pulled towards its rest position until both springs are within bounds,
//!   so the constraint holds after every step.

mod kernel;
mod lanes;
pub mod layout;
mod material;

pub use material::{
    check_params, parse_materials, presets, write_materials, Material, MaterialError,
};

use crate::rig::Rig;
use glam::{Affine3A, Vec3};
use layout::{Layout, Packed};
use rayon::prelude::*;
use std::time::Instant;

/// The reference step `h₀` that `D` and `C_vd` are defined at (seconds).
pub const REFERENCE_STEP: f32 = 1.0 / 60.0;
/// Largest stiffness the UI and the parameter checks allow (the stability limit).
pub const MAX_STIFFNESS: f32 = 1.0;
/// Smallest accepted time step (seconds).
pub const MIN_STEP: f32 = 1.0 / 2000.0;

/// Which constraint keeps the mass points near their bones.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Constraint {
    Circumsphere,
    SpringReduction,
}

/// Every simulation parameter, with the paper's names.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Params {
    /// `C_vd`: share of velocity kept per reference step, 0..1 (0.99 jelly, 0.7 dull).
    pub damping: f32,
    /// `D`: dimensionless spring constant, 0..[`MAX_STIFFNESS`] (see module docs).
    pub stiffness: f32,
    /// `d_B` = `f_bd`: bone distance factor, 0..1 (0 puts the bones on the surface).
    pub bone_distance: f32,
    /// `sl_max` = `f_max`: maximum bone-spring length factor, 1..3.
    pub max_length: f32,
    /// `f_min`: minimum bone-spring length factor, 0..1 (spring reduction only).
    pub min_length: f32,
    /// Which constraint.
    pub constraint: Constraint,
    /// Spring-reduction passes per step, 1..64.
    pub reduction_iterations: u32,
    /// Fixed simulation step `h` in seconds, [`MIN_STEP`]..[`REFERENCE_STEP`].
    pub time_step: f32,
}

impl Default for Params {
    /// The "skin" preset of Table 1 with the circumsphere constraint at 60 steps/s.
    fn default() -> Self {
        Params {
            damping: 0.85,
            stiffness: 1.0,
            bone_distance: 0.2,
            max_length: 1.25,
            min_length: 0.8,
            constraint: Constraint::Circumsphere,
            reduction_iterations: 4,
            time_step: REFERENCE_STEP,
        }
    }
}

impl Params {
    /// The same parameters clamped into their valid ranges (NaN takes the default), so no
    /// slider position or file value can make the step unstable.
    pub fn sanitized(&self) -> Params {
        let d = Params::default();
        let clamp =
            |v: f32, lo: f32, hi: f32, def: f32| if v.is_nan() { def } else { v.clamp(lo, hi) };
        Params {
            damping: clamp(self.damping, 0.0, 1.0, d.damping),
            stiffness: clamp(self.stiffness, 0.0, MAX_STIFFNESS, d.stiffness),
            bone_distance: clamp(self.bone_distance, 0.0, 1.0, d.bone_distance),
            max_length: clamp(self.max_length, 1.0, 3.0, d.max_length),
            min_length: clamp(self.min_length, 0.0, 1.0, d.min_length),
            constraint: self.constraint,
            reduction_iterations: self.reduction_iterations.clamp(1, 64),
            time_step: clamp(self.time_step, MIN_STEP, REFERENCE_STEP, d.time_step),
        }
    }

    /// True when the parameters leave no room for elastic movement (Table 1's "plastic"):
    /// bones on the surface or `sl_max = 1`. Such a rig is not integrated at all.
    pub fn is_static(&self) -> bool {
        self.bone_distance <= 0.0 || self.max_length <= 1.0
    }
}

/// A pose: one rigid transform per joint section (section 0 is the whole object until joints
/// cut it).
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    pub transforms: Vec<Affine3A>,
}

impl Pose {
    /// Every section at rest.
    pub fn rest(sections: usize) -> Pose {
        Pose {
            transforms: vec![Affine3A::IDENTITY; sections.max(1)],
        }
    }
}

/// Mass-point positions, read through the rig's vertex numbering (the solver stores them in
/// its own order, see [`layout`]).
#[derive(Clone, Copy, Debug)]
pub struct Positions<'a> {
    points: &'a Packed,
    slot: &'a [u32],
}

impl Positions<'_> {
    /// Position of rig vertex `i`.
    ///
    /// # Panics
    /// If `i` is not a vertex of the rig.
    #[inline]
    pub fn get(&self, i: usize) -> Vec3 {
        self.points.get(self.slot[i] as usize)
    }

    /// Number of mass points.
    pub fn len(&self) -> usize {
        self.slot.len()
    }

    /// True for a rig without vertices.
    pub fn is_empty(&self) -> bool {
        self.slot.is_empty()
    }

    /// All positions in vertex order.
    pub fn to_vec(&self) -> Vec<Vec3> {
        (0..self.len()).map(|i| self.get(i)).collect()
    }
}

impl PartialEq for Positions<'_> {
    /// Same positions for every vertex (exact `f32` equality).
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && (0..self.len()).all(|i| self.get(i) == other.get(i))
    }
}

/// Solver options that change cost, not physics (beyond the sleeping error, which
/// `puppet bench --skip` measures).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Let still tiles sleep (see the module docs).
    pub sleeping: bool,
    /// A tile whose every mass point moved less than this fraction of the rig's bounding-box
    /// diagonal per step, for [`QUIET_STEPS`] steps in a row, with no moving neighbour and no
    /// pose change, sleeps.
    pub sleep_threshold: f32,
    /// Slots per tile (at least 1).
    pub tile: usize,
    /// Use the AVX2 build of the kernel where the CPU has it (results are bit-identical).
    pub simd: bool,
}

/// Steps a tile must stay still before it sleeps.
pub const QUIET_STEPS: u16 = 8;

impl Default for Options {
    /// Values chosen by measurement: BENCHMARKS.md, "Skipping what does not move".
    fn default() -> Self {
        Options {
            sleeping: true,
            sleep_threshold: 1e-6,
            tile: 256,
            simd: true,
        }
    }
}

/// Time spent per stage of the last step (seconds).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Stage 0: which sections moved, which tiles wake.
    pub wake: f64,
    /// Stages 1–4 fused in one pass over the awake tiles: bone transforms, forces, Verlet,
    /// constraint.
    pub fused: f64,
    /// Stage 5: tiles that stopped moving go to sleep, moving tiles wake their neighbours.
    pub sleep: f64,
}

impl StageTimes {
    /// The whole step.
    pub fn total(&self) -> f64 {
        self.wake + self.fused + self.sleep
    }
}

/// A simulated puppet: rig, parameters, state and scratch.
pub struct Simulation {
    rig: Rig,
    params: Params,
    options: Options,
    layout: Layout,
    /// Section of each rig vertex (all 0 until joints cut the skeleton).
    section_of: Vec<u16>,
    /// Transform of each section in the last step.
    transforms: Vec<Affine3A>,
    /// Current and previous positions by slot (the step writes the new positions over the
    /// previous ones, then swaps).
    cur: Packed,
    prev: Packed,
    /// Sleeping state per tile.
    awake: Vec<bool>,
    quiet: Vec<u16>,
    motion: Vec<f32>,
    /// Scratch: sections whose transform changed, tiles to wake.
    changed: Vec<bool>,
    to_wake: Vec<bool>,
    wake_all: bool,
    /// Squared absolute sleep threshold.
    still2: f32,
    diagonal: f32,
    steps: u64,
    awake_tiles: usize,
    time_debt: f32,
    last_times: StageTimes,
}

impl Simulation {
    /// A simulation at rest, with the default [`Options`].
    pub fn new(rig: Rig, params: Params) -> Simulation {
        Simulation::with_options(rig, params, Options::default())
    }

    /// A simulation at rest.
    pub fn with_options(mut rig: Rig, params: Params, options: Options) -> Simulation {
        let params = params.sanitized();
        if rig.bone_distance != params.bone_distance {
            rig.set_bone_distance(params.bone_distance);
        }
        let n = rig.len();
        let layout = Layout::new(&rig, options.tile);
        let cur = layout.rest_positions();
        let (lo, hi) = rig.rest.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let diagonal = if n > 0 { (hi - lo).length() } else { 0.0 };
        let tiles = layout.tiles();
        let mut sim = Simulation {
            section_of: vec![0; n],
            transforms: vec![Affine3A::IDENTITY],
            prev: cur.clone(),
            cur,
            awake: vec![true; tiles],
            quiet: vec![0; tiles],
            motion: vec![0.0; tiles],
            changed: vec![false; 1],
            to_wake: vec![false; tiles],
            wake_all: true,
            still2: 0.0,
            diagonal,
            steps: 0,
            awake_tiles: tiles,
            time_debt: 0.0,
            last_times: StageTimes::default(),
            layout,
            rig,
            params,
            options,
        };
        sim.set_options(options);
        sim
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The parameters in force (sanitized).
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The solver options in force.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Changes the solver options (a new tile size renumbers nothing but re-cuts the
    /// tiles). Every tile wakes.
    pub fn set_options(&mut self, options: Options) {
        let tile = options.tile.max(1);
        if tile != self.layout.tile {
            self.layout = Layout::new(&self.rig, tile);
            self.layout.set_sections(&self.section_of);
            let tiles = self.layout.tiles();
            self.awake = vec![true; tiles];
            self.quiet = vec![0; tiles];
            self.motion = vec![0.0; tiles];
            self.to_wake = vec![false; tiles];
        }
        let threshold = if options.sleep_threshold.is_finite() {
            options.sleep_threshold.max(0.0)
        } else {
            0.0
        };
        self.options = Options {
            tile,
            sleep_threshold: threshold,
            simd: options.simd && kernel::avx2_available(),
            ..options
        };
        self.still2 = (threshold * self.diagonal).powi(2);
        self.wake_all = true;
    }

    /// Changes parameters; they take effect on the next step and wake every tile. A new
    /// bone distance moves the bone points in O(n) without touching the skeleton.
    pub fn set_params(&mut self, params: Params) {
        let params = params.sanitized();
        if params == self.params {
            return;
        }
        self.params = params;
        if self.params.bone_distance != self.rig.bone_distance {
            self.rig.set_bone_distance(self.params.bone_distance);
            self.layout.set_bone_length(&self.rig);
        }
        self.wake_all = true;
    }

    /// Assigns vertices to joint sections (used by the joints module). Every tile wakes.
    ///
    /// # Panics
    /// If `section_of` does not have one entry per vertex.
    pub fn set_sections(&mut self, section_of: Vec<u16>) {
        assert_eq!(section_of.len(), self.rig.len(), "one section per vertex");
        self.layout.set_sections(&section_of);
        let sections = section_of
            .iter()
            .map(|&s| s as usize + 1)
            .max()
            .unwrap_or(1);
        self.section_of = section_of;
        self.transforms.resize(sections, Affine3A::IDENTITY);
        self.changed.resize(sections, false);
        self.wake_all = true;
    }

    /// Current positions.
    pub fn positions(&self) -> Positions<'_> {
        Positions {
            points: &self.cur,
            slot: &self.layout.slot,
        }
    }

    /// Previous positions (velocity = current − previous).
    pub fn previous_positions(&self) -> Positions<'_> {
        Positions {
            points: &self.prev,
            slot: &self.layout.slot,
        }
    }

    /// Rest position of vertex `i` in the pose of the last step.
    pub fn target(&self, i: usize) -> Vec3 {
        self.transform_of(i).transform_point3(self.rig.rest[i])
    }

    /// Inner and outer bone point of vertex `i` in the pose of the last step.
    pub fn bone_points(&self, i: usize) -> (Vec3, Vec3) {
        let t = self.transform_of(i);
        let (s, k) = (&self.layout.slots, self.layout.slot[i] as usize);
        kernel::bones(
            t.transform_point3(s.rest.get(k)),
            t.transform_vector3(s.normal.get(k)),
            s.bone_length[k],
        )
    }

    fn transform_of(&self, i: usize) -> Affine3A {
        self.transforms
            .get(self.section_of[i] as usize)
            .copied()
            .unwrap_or(Affine3A::IDENTITY)
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Stage times of the last step.
    pub fn last_times(&self) -> StageTimes {
        self.last_times
    }

    /// Entries of the kernel's spring rows: one per half-spring (every spring is evaluated
    /// from both ends) plus the padding of slots with fewer springs than the largest valence
    /// of their group of 8.
    pub fn lane_entries(&self) -> usize {
        self.layout.lane_offsets().len()
    }

    /// Tiles in all, and tiles integrated by the last step.
    pub fn tiles(&self) -> (usize, usize) {
        (self.layout.tiles(), self.awake_tiles)
    }

    /// True when every tile sleeps: the next step with the same pose does nothing.
    pub fn is_asleep(&self) -> bool {
        !self.wake_all && self.awake.iter().all(|a| !a)
    }

    /// Sum of squared per-step displacements (proportional to kinetic energy).
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.cur.len())
            .map(|k| (self.cur.get(k) - self.prev.get(k)).length_squared() as f64)
            .sum()
    }

    /// Runs as many fixed steps as `dt` seconds of frame time hold (at most `max_steps`;
    /// the rest of the time is dropped so a slow frame cannot snowball). Returns the steps
    /// taken.
    pub fn advance(&mut self, pose: &Pose, dt: f32, max_steps: u32) -> u32 {
        if dt.is_finite() && dt > 0.0 {
            self.time_debt += dt;
        }
        let h = self.params.time_step;
        let mut taken = 0;
        while self.time_debt >= h && taken < max_steps {
            self.step(pose);
            self.time_debt -= h;
            taken += 1;
        }
        if taken == max_steps {
            self.time_debt = 0.0;
        }
        taken
    }

    /// One simulation step of `h = params.time_step`.
    ///
    /// 0. **Wake**: sections whose transform differs from the last step wake the tiles that
    ///    hold their vertices (a parameter or section change wakes all).
    /// 1. **Bone transforms**: each slot's rest position, normal and bone points are moved
    ///    rigidly with its section's transform.
    /// 2. **Forces**: each mass point gathers its surface springs (CSR neighbours) and its
    ///    two bone springs (Hooke, `stretch × direction`).
    /// 3. **Verlet** with velocity damping:
    ///    `x' = x + C_vd^(h/h₀) (x − x_prev) + D (h/h₀)² / (deg + 2) · F`.
    /// 4. **Constraint**: circumsphere projection, or iterated spring reduction.
    /// 5. **Sleep**: a tile that moved less than the threshold for [`QUIET_STEPS`] steps,
    ///    with still neighbours, stops (its velocity is set to zero); a tile that moved wakes
    ///    its neighbours for the next step.
    ///
    /// Stages 1–4 are fused into one parallel pass over the awake tiles (`kernel`) that
    /// reads the current positions and writes the new ones over the previous ones, so the
    /// result does not depend on the number of threads and nothing is allocated. A static
    /// material (see [`Params::is_static`]) skips 2–4: the surface just follows the bones.
    pub fn step(&mut self, pose: &Pose) {
        let t0 = Instant::now();
        self.wake(pose);
        let t1 = Instant::now();
        if self.params.is_static() {
            self.follow_bones();
        } else if self.awake_tiles > 0 {
            self.integrate();
        }
        let t2 = Instant::now();
        self.settle();
        self.steps += 1;
        self.last_times = StageTimes {
            wake: (t1 - t0).as_secs_f64(),
            fused: (t2 - t1).as_secs_f64(),
            sleep: t2.elapsed().as_secs_f64(),
        };
    }

    /// Stage 0.
    fn wake(&mut self, pose: &Pose) {
        let mut any = false;
        for (s, (old, changed)) in self
            .transforms
            .iter_mut()
            .zip(self.changed.iter_mut())
            .enumerate()
        {
            let new = pose
                .transforms
                .get(s)
                .copied()
                .unwrap_or(Affine3A::IDENTITY);
            *changed = new != *old;
            if *changed {
                *old = new;
                any = true;
            }
        }
        let all = self.wake_all || !self.options.sleeping;
        self.wake_all = false;
        for t in 0..self.awake.len() {
            let woken = all
                || (any
                    && self
                        .layout
                        .sections_of_tile(t)
                        .iter()
                        .any(|&s| self.changed[s as usize]));
            if woken {
                self.awake[t] = true;
                self.quiet[t] = 0;
            }
        }
        self.awake_tiles = self.awake.iter().filter(|&&a| a).count();
    }

    /// Stages 1–4 for a static material: awake tiles take their posed rest positions.
    fn follow_bones(&mut self) {
        let layout = &self.layout;
        for t in 0..layout.tiles() {
            if !self.awake[t] {
                continue;
            }
            for k in layout.tile_range(t) {
                let s = &layout.slots;
                let r = self.transforms[s.section[k] as usize].transform_point3(s.rest.get(k));
                self.cur.set(k, r);
                self.prev.set(k, r);
            }
            self.motion[t] = 0.0;
        }
    }

    /// Stages 1–4: the fused kernel over every awake tile.
    fn integrate(&mut self) {
        let p = self.params;
        let ratio = p.time_step / REFERENCE_STEP;
        let ctx = kernel::Ctx {
            layout: &self.layout,
            cur: &self.cur,
            transforms: &self.transforms,
            params: p,
            stiffness: p.stiffness * ratio * ratio,
            damping: p.damping.powf(ratio),
            avx2: self.options.simd,
        };
        let tile = self.layout.tile;
        let awake = &self.awake;
        let prev = &mut self.prev;
        prev.0
            .par_chunks_mut(tile)
            .zip(self.motion.par_iter_mut())
            .enumerate()
            .for_each(|(t, (points, motion))| {
                if awake[t] {
                    *motion = kernel::tile(&ctx, ctx.layout.tile_range(t), points);
                }
            });
        std::mem::swap(&mut self.prev, &mut self.cur);
    }

    /// Stage 5.
    fn settle(&mut self) {
        if !self.options.sleeping {
            return;
        }
        let layout = &self.layout;
        self.to_wake.fill(false);
        for t in 0..layout.tiles() {
            if !self.awake[t] {
                continue;
            }
            if self.motion[t] > self.still2 {
                self.quiet[t] = 0;
                for &u in layout.neighbours_of_tile(t) {
                    self.to_wake[u as usize] = true;
                }
            } else {
                self.quiet[t] = self.quiet[t].saturating_add(1);
            }
        }
        let static_material = self.params.is_static();
        for t in 0..layout.tiles() {
            if self.to_wake[t] {
                if !self.awake[t] {
                    self.awake[t] = true;
                    self.quiet[t] = 0;
                }
            } else if self.awake[t] && (static_material || self.quiet[t] >= QUIET_STEPS) {
                // Asleep with zero velocity: both buffers hold the same positions.
                self.awake[t] = false;
                self.prev.copy_range(&self.cur, layout.tile_range(t));
            }
        }
    }
}
