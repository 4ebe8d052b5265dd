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

mod material;

pub use material::{
    check_params, parse_materials, presets, write_materials, Material, MaterialError,
};

use crate::rig::Rig;
use glam::{Affine3A, Vec3};
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

/// Mass-point positions as struct-of-arrays.
#[derive(Clone, Debug, PartialEq)]
pub struct Positions {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
}

impl Positions {
    fn from_points(points: &[Vec3]) -> Self {
        Positions {
            x: points.iter().map(|p| p.x).collect(),
            y: points.iter().map(|p| p.y).collect(),
            z: points.iter().map(|p| p.z).collect(),
        }
    }

    #[inline(always)]
    pub fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    fn set_all(&mut self, points: &[Vec3]) {
        for (i, p) in points.iter().enumerate() {
            (self.x[i], self.y[i], self.z[i]) = (p.x, p.y, p.z);
        }
    }

    /// All positions as vectors.
    pub fn to_vec(&self) -> Vec<Vec3> {
        (0..self.x.len()).map(|i| self.get(i)).collect()
    }
}

/// The kinematic targets of the current pose: rest positions and bone points in world space.
#[derive(Clone, Debug)]
struct BoneFrame {
    rest: Vec<Vec3>,
    inner: Vec<Vec3>,
    outer: Vec<Vec3>,
    /// Unit normals in world space (for the direction of a zero-length bone spring).
    normal: Vec<Vec3>,
    /// The pose and bone distance this frame was computed for.
    pose: Option<Pose>,
    bone_distance: f32,
}

/// Time spent per stage of the last step (seconds).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Stage 1, bone transforms (zero when the pose did not change).
    pub bones: f64,
    /// Stages 2–4 fused in one pass: forces, Verlet, constraint.
    pub springs_verlet_constraint: f64,
}

/// A simulated puppet: rig, parameters, state and scratch.
pub struct Simulation {
    rig: Rig,
    params: Params,
    /// Section of each vertex (all 0 until joints cut the skeleton).
    section_of: Vec<u16>,
    inv_mass: Vec<f32>,
    frame: BoneFrame,
    /// Current, previous and scratch positions (rotated each step, never reallocated).
    cur: Positions,
    prev: Positions,
    next: Positions,
    steps: u64,
    time_debt: f32,
    last_times: StageTimes,
}

impl Simulation {
    /// A simulation at rest.
    pub fn new(mut rig: Rig, params: Params) -> Simulation {
        let params = params.sanitized();
        if rig.bone_distance != params.bone_distance {
            rig.set_bone_distance(params.bone_distance);
        }
        let n = rig.len();
        let inv_mass = (0..n)
            .map(|i| 1.0 / (rig.start[i + 1] - rig.start[i] + 2) as f32)
            .collect();
        let cur = Positions::from_points(&rig.rest);
        let frame = BoneFrame {
            rest: rig.rest.clone(),
            inner: rig.inner.clone(),
            outer: rig.outer.clone(),
            normal: rig.normals.clone(),
            pose: Some(Pose::rest(1)),
            bone_distance: rig.bone_distance,
        };
        Simulation {
            section_of: vec![0; n],
            inv_mass,
            frame,
            prev: cur.clone(),
            next: cur.clone(),
            cur,
            rig,
            params,
            steps: 0,
            time_debt: 0.0,
            last_times: StageTimes::default(),
        }
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The parameters in force (sanitized).
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Changes parameters; they take effect on the next step. A new bone distance moves the
    /// bone points in O(n) without touching the skeleton.
    pub fn set_params(&mut self, params: Params) {
        self.params = params.sanitized();
        if self.params.bone_distance != self.rig.bone_distance {
            self.rig.set_bone_distance(self.params.bone_distance);
        }
    }

    /// Assigns vertices to joint sections (used by the joints module).
    ///
    /// # Panics
    /// If `section_of` does not have one entry per vertex.
    pub fn set_sections(&mut self, section_of: Vec<u16>) {
        assert_eq!(section_of.len(), self.rig.len(), "one section per vertex");
        self.section_of = section_of;
        self.frame.pose = None;
    }

    /// Current positions.
    pub fn positions(&self) -> &Positions {
        &self.cur
    }

    /// Previous positions (velocity = current − previous).
    pub fn previous_positions(&self) -> &Positions {
        &self.prev
    }

    /// Rest position of vertex `i` in the pose of the last step.
    pub fn target(&self, i: usize) -> Vec3 {
        self.frame.rest[i]
    }

    /// Inner and outer bone point of vertex `i` in the pose of the last step.
    pub fn bone_points(&self, i: usize) -> (Vec3, Vec3) {
        (self.frame.inner[i], self.frame.outer[i])
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Stage times of the last step.
    pub fn last_times(&self) -> StageTimes {
        self.last_times
    }

    /// Sum of squared per-step displacements (proportional to kinetic energy).
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.rig.len())
            .map(|i| (self.cur.get(i) - self.prev.get(i)).length_squared() as f64)
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
    /// 1. **Bone transforms**: rest positions and bone points of every vertex are moved
    ///    rigidly with their section's transform (skipped when neither the pose nor the bone
    ///    distance changed since the last step).
    /// 2. **Forces**: each vertex gathers its surface springs (CSR neighbours) and its two
    ///    bone springs (Hooke, `stretch × direction`).
    /// 3. **Verlet** with velocity damping:
    ///    `x' = x + C_vd^(h/h₀) (x − x_prev) + D (h/h₀)² / (deg + 2) · F`.
    /// 4. **Constraint**: circumsphere projection, or iterated spring reduction.
    ///
    /// Stages 2–4 are fused into one parallel pass over vertices that reads the current
    /// positions and writes the next ones, so the result does not depend on the number of
    /// threads and nothing is allocated. A static material (see [`Params::is_static`]) skips
    /// 2–4: the surface just follows the bones.
    pub fn step(&mut self, pose: &Pose) {
        let t0 = Instant::now();
        self.update_frame(pose);
        let t1 = Instant::now();
        let p = self.params;
        if p.is_static() {
            self.prev.set_all(&self.frame.rest);
            self.cur.set_all(&self.frame.rest);
        } else {
            self.integrate();
        }
        self.steps += 1;
        self.last_times = StageTimes {
            bones: (t1 - t0).as_secs_f64(),
            springs_verlet_constraint: t1.elapsed().as_secs_f64(),
        };
    }

    fn update_frame(&mut self, pose: &Pose) {
        let same_pose = self.frame.pose.as_ref() == Some(pose);
        if same_pose && self.frame.bone_distance == self.rig.bone_distance {
            return;
        }
        let rig = &self.rig;
        let sections = &self.section_of;
        let transforms = &pose.transforms;
        let f = &mut self.frame;
        (
            f.rest.par_iter_mut(),
            f.inner.par_iter_mut(),
            f.outer.par_iter_mut(),
            f.normal.par_iter_mut(),
        )
            .into_par_iter()
            .enumerate()
            .for_each(|(i, (r, bi, bo, n))| {
                let t = transforms
                    .get(sections[i] as usize)
                    .copied()
                    .unwrap_or(Affine3A::IDENTITY);
                *r = t.transform_point3(rig.rest[i]);
                *bi = t.transform_point3(rig.inner[i]);
                *bo = t.transform_point3(rig.outer[i]);
                *n = t.transform_vector3(rig.normals[i]);
            });
        f.pose = Some(pose.clone());
        f.bone_distance = rig.bone_distance;
    }

    fn integrate(&mut self) {
        const CHUNK: usize = 1024;
        let p = self.params;
        let ratio = p.time_step / REFERENCE_STEP;
        let k = p.stiffness * ratio * ratio;
        let c = p.damping.powf(ratio);
        let rig = &self.rig;
        let frame = &self.frame;
        let inv_mass = &self.inv_mass;
        let (cur, prev) = (&self.cur, &self.prev);
        let next = &mut self.next;
        next.x
            .par_chunks_mut(CHUNK)
            .zip(next.y.par_chunks_mut(CHUNK))
            .zip(next.z.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(chunk, ((nx, ny), nz))| {
                let base = chunk * CHUNK;
                for local in 0..nx.len() {
                    let i = base + local;
                    let x = cur.get(i);
                    // 2. Forces.
                    let mut force = Vec3::ZERO;
                    for s in rig.start[i] as usize..rig.start[i + 1] as usize {
                        force += stretch(
                            cur.get(rig.neighbour[s] as usize) - x,
                            rig.neighbour_rest[s],
                        );
                    }
                    force += stretch(frame.inner[i] - x, rig.inner_rest[i]);
                    force += stretch(frame.outer[i] - x, rig.outer_rest[i]);
                    // 3. Verlet with velocity damping.
                    let mut y = x + c * (x - prev.get(i)) + (k * inv_mass[i]) * force;
                    // 4. Constraint.
                    y = match p.constraint {
                        Constraint::Circumsphere => circumsphere(
                            y,
                            frame.rest[i],
                            (p.max_length - 1.0) * rig.bone_length[i],
                        ),
                        Constraint::SpringReduction => {
                            spring_reduction(y, frame, i, rig.bone_length[i], &p)
                        }
                    };
                    (nx[local], ny[local], nz[local]) = (y.x, y.y, y.z);
                }
            });
        // Rotate buffers: prev <- cur, cur <- next, next <- old prev.
        std::mem::swap(&mut self.prev, &mut self.cur);
        std::mem::swap(&mut self.cur, &mut self.next);
    }
}

/// Hooke's stretch vector of a spring from the mass point along `d` (to the other end).
#[inline(always)]
fn stretch(d: Vec3, rest: f32) -> Vec3 {
    let len = d.length();
    if len > 0.0 {
        d * ((len - rest) / len)
    } else {
        Vec3::ZERO
    }
}

/// Projects `y` onto the ball of radius `rho` around `centre`.
#[inline(always)]
fn circumsphere(y: Vec3, centre: Vec3, rho: f32) -> Vec3 {
    let v = y - centre;
    let d2 = v.length_squared();
    if d2 <= rho * rho {
        y
    } else {
        centre + v * (rho / d2.sqrt())
    }
}

/// Is `y` within both bone-spring bounds (with a relative slack for rounding)?
#[inline(always)]
fn reduction_ok(y: Vec3, frame: &BoneFrame, i: usize, lo: f32, hi: f32) -> bool {
    let slack = 1e-6 * hi.max(1e-30);
    [frame.inner[i], frame.outer[i]].iter().all(|b| {
        let len = (y - *b).length();
        len >= lo - slack && len <= hi + slack
    })
}

/// Iterated clamping of both bone springs into `[f_min L, f_max L]` (see module docs).
#[inline(always)]
fn spring_reduction(mut y: Vec3, frame: &BoneFrame, i: usize, l: f32, p: &Params) -> Vec3 {
    let (lo, hi) = (p.min_length * l, p.max_length * l);
    for _ in 0..p.reduction_iterations {
        let mut violated = false;
        for (b, away) in [
            (frame.inner[i], frame.normal[i]),
            (frame.outer[i], -frame.normal[i]),
        ] {
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
    if reduction_ok(y, frame, i, lo, hi) {
        return y;
    }
    // Budget spent: pull towards the rest position (where both springs have length L,
    // always feasible) until feasible, by bisection on the segment.
    let r = frame.rest[i];
    let (mut feasible, mut infeasible) = (0.0f32, 1.0f32);
    for _ in 0..20 {
        let s = 0.5 * (feasible + infeasible);
        if reduction_ok(r + (y - r) * s, frame, i, lo, hi) {
            feasible = s;
        } else {
            infeasible = s;
        }
    }
    r + (y - r) * feasible
}
