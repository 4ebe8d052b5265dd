//! One step and its stages (see [`Simulation::step`]), and the fixed-step clock
//! ([`Simulation::advance`]).

use super::contact::{Floor, Touched};
use super::{kernel, Pose, Simulation, StageTimes, REFERENCE_STEP, SLEEP_AFTER, STANDARD_GRAVITY};
use glam::Affine3A;
use rayon::prelude::*;
use std::time::Instant;

impl Simulation {
    /// Runs as many fixed steps as `seconds` of frame time hold (at most `max_steps`; the
    /// rest of the time is dropped so a slow frame cannot snowball). Returns the steps
    /// taken.
    pub fn advance(&mut self, pose: &Pose, seconds: f32, max_steps: u32) -> u32 {
        let due = self.steps_due(seconds, max_steps);
        for _ in 0..due {
            self.step(pose);
        }
        due
    }

    /// The fixed steps `seconds` of frame time hold (with the time not yet simulated, at
    /// most `max_steps`; the rest is dropped so a slow frame cannot snowball). The caller
    /// takes them (with a pose per step: an animation's playback).
    pub fn steps_due(&mut self, seconds: f32, max_steps: u32) -> u32 {
        if seconds.is_finite() && seconds > 0.0 {
            self.state.time_debt += seconds;
        }
        let h = self.params.solver.time_step;
        let mut due = 0;
        while self.state.time_debt >= h && due < max_steps {
            self.state.time_debt -= h;
            due += 1;
        }
        if due == max_steps {
            self.state.time_debt = 0.0;
        }
        due
    }

    /// Back to rest: every mass point at its rest position with no velocity, every section
    /// at rest, no step taken (what a freshly built simulation is).
    pub fn reset(&mut self) {
        let s = &mut self.state;
        s.cur = self.layout.rest_positions();
        s.prev = s.cur.clone();
        s.transforms.fill(kernel::IDENTITY_ROWS);
        s.awake.fill(true);
        s.steps_under_threshold.fill(0);
        s.wake_all = true;
        if let Some(c) = &mut self.contacts {
            // (The points jumped: what the contacts kept of them is forgotten.)
            c.forget_lists();
        }
        s.steps = 0;
        s.time_debt = 0.0;
        self.largest_motion = 0.0;
    }

    /// One simulation step of `h = params.solver.time_step`.
    ///
    /// 0. **Wake**: sections whose transform differs from the last step wake the tiles that
    ///    hold their vertices (a parameter or section change wakes all).
    /// 1. **Bone transforms**: each slot's rest position, normal and bone points are moved
    ///    with its section's transform (rigid, but for a trunk's swell: `joints::slide`).
    /// 2. **Forces**: each mass point gathers its surface springs (CSR neighbours) and its
    ///    two bone springs (Hooke, `stretch × direction`).
    /// 3. **Verlet** with velocity damping:
    ///    `x' = x + C_vd^(h/h₀) (x − x_prev) + D (h/h₀)² / (deg + 2) · F`, plus gravity
    ///    `g h²`; a pinned point is then drawn to its posed rest position by its weight, and
    ///    (3b) one that would pass the floor loses part of its sliding motion (friction).
    /// 4. **Constraint**: circumsphere projection, or iterated spring reduction; then (4b)
    ///    the floor lifts any point below it onto it (3b and 4b: [`super::contact::Floor`]).
    ///    With collision on, (4c) every point of a section is put out of the other
    ///    sections' medial balls ([`super::contact`]), and off the floor.
    /// 5. **Sleep**: a tile that moved less than the threshold for [`SLEEP_AFTER`] steps,
    ///    with still neighbours, stops (its velocity is set to zero); a tile that moved wakes
    ///    its neighbours for the next step.
    ///
    /// With several materials ([`super::Regions`]) stages 2–4 take each vertex's own
    /// parameters; the stiffening exponent shapes the bone springs of stage 2.
    ///
    /// Stages 1–4 are fused into one parallel pass over the awake tiles (`kernel`) that
    /// reads the current positions and writes the new ones over the previous ones, so the
    /// result does not depend on the number of threads and nothing is allocated. A static
    /// material everywhere (see [`super::Params::is_static`]) skips 2–4: the surface just
    /// follows the bones (and the floor).
    pub fn step(&mut self, pose: &Pose) {
        let t0 = Instant::now();
        self.wake(pose);
        let t1 = Instant::now();
        if self.is_static() {
            self.follow_bones();
        } else if self.awake_tiles > 0 {
            self.integrate();
        } else {
            self.largest_motion = 0.0;
        }
        let t2 = Instant::now();
        if self.params.world.collision && !self.is_static() {
            self.collide();
        } else if let Some(c) = &mut self.contacts {
            c.clear();
        }
        let t3 = Instant::now();
        self.sleep();
        self.state.steps += 1;
        self.last_times = StageTimes {
            wake: (t1 - t0).as_secs_f64(),
            fused: (t2 - t1).as_secs_f64(),
            contact: (t3 - t2).as_secs_f64(),
            sleep: t3.elapsed().as_secs_f64(),
        };
    }

    /// Stage 4c: contacts between sections (see [`super::contact`]). A tile's motion is
    /// measured again from where its points ended (a contact held in place is none), and
    /// a sleeping tile a contact moved wakes.
    fn collide(&mut self) {
        let (floor, keep) = (self.floor(), self.keep());
        let rig = &self.rig;
        let built = self.contacts.is_none();
        let contacts = self.contacts.get_or_insert_with(|| {
            let centers: Vec<glam::Vec3> = (0..rig.len())
                .map(|i| rig.rest[i] - rig.normals[i] * rig.skeletal_distance[i])
                .collect();
            let transform_of = &self.state.section_of;
            let joint = &self.joint;
            let section_of = if joint.section.is_empty() {
                transform_of
            } else {
                &joint.section
            };
            let mut c = super::contact::Colliders::new(
                &centers,
                &rig.skeletal_distance,
                section_of,
                transform_of,
                &joint.flesh,
            );
            c.bind(
                &self.layout,
                section_of,
                &joint.rank,
                &rig.skeletal_distance,
                &joint.flesh,
            );
            c
        });
        if built || self.pairs_changed {
            contacts.set_pairs(self.pairs.clone());
            self.pairs_changed = false;
        }
        let (state, scratch) = (&mut self.state, &mut self.scratch);
        scratch.affine.clear();
        scratch
            .affine
            .extend(state.transforms.iter().map(kernel::affine_of));
        let p = &self.params;
        let stage = super::contact::Stage {
            layout: &self.layout,
            transforms: &scratch.affine,
            changed: &scratch.changed,
            margin: p.world.collision_margin * self.diagonal,
            flesh: p.world.flesh,
            tile_motion: &scratch.motion,
            keep,
            floor,
        };
        let touched = contacts.resolve(&stage, &mut state.cur, &mut state.prev, &state.awake);
        for Touched {
            tile: t,
            motion,
            released,
        } in touched
        {
            if !state.awake[t] && (motion.is_some_and(|m| m > self.sleep_threshold2) || released) {
                state.awake[t] = true;
                state.steps_under_threshold[t] = 0;
                self.awake_tiles += 1;
            }
            // (A tile only let go of keeps the kernel's motion.)
            if let Some(motion) = motion {
                scratch.motion[t] = motion;
                self.largest_motion = self.largest_motion.max(motion);
            }
        }
    }

    /// Stage 0.
    fn wake(&mut self, pose: &Pose) {
        let (state, scratch) = (&mut self.state, &mut self.scratch);
        let mut any = false;
        for (s, (old, changed)) in state
            .transforms
            .iter_mut()
            .zip(scratch.changed.iter_mut())
            .enumerate()
        {
            let new = kernel::rows_of(pose.transforms.get(s).unwrap_or(&Affine3A::IDENTITY));
            *changed = new != *old;
            if *changed {
                *old = new;
                any = true;
            }
        }
        let all = state.wake_all || !self.options.sleeping;
        state.wake_all = false;
        for t in 0..state.awake.len() {
            let woken = all
                || (any
                    && self
                        .layout
                        .sections_of_tile(t)
                        .iter()
                        .any(|&s| scratch.changed[s as usize]));
            if woken {
                state.awake[t] = true;
                state.steps_under_threshold[t] = 0;
            }
        }
        self.awake_tiles = state.awake.iter().filter(|&&a| a).count();
    }

    /// Stages 1–4 for a static material: awake tiles take their posed rest positions.
    fn follow_bones(&mut self) {
        let floor = self.floor();
        let (layout, state) = (&self.layout, &mut self.state);
        let mut largest = 0.0f32;
        for t in 0..layout.tiles() {
            if !state.awake[t] {
                continue;
            }
            for k in layout.tile_range(t) {
                let s = &layout.slots;
                let mut r = kernel::affine_of(&state.transforms[s.section[k] as usize])
                    .transform_point3(s.rest.get(k));
                if let Some(lifted) = floor.and_then(|f| f.lift(r)) {
                    r = lifted;
                }
                largest = largest.max((r - state.cur.get(k)).length_squared());
                state.cur.set(k, r);
                state.prev.set(k, r);
            }
            self.scratch.motion[t] = 0.0;
        }
        self.largest_motion = largest;
    }

    /// Stages 1–4: the fused kernel over every awake tile.
    fn integrate(&mut self) {
        let p = self.params;
        let ratio = p.solver.time_step / REFERENCE_STEP;
        let (gravity, floor) = (self.gravity_per_step(), self.floor());
        let state = &mut self.state;
        let ctx = kernel::Ctx {
            layout: &self.layout,
            cur: &state.cur,
            transforms: state.transforms.as_flattened(),
            params: p,
            stiffness: p.material.stiffness * ratio * ratio,
            damping: p.material.damping.powf(ratio),
            avx2: self.options.simd,
            gravity,
            floor,
            mixed: self.per_slot.as_ref(),
            pin: self.pin.as_deref(),
        };
        let tile = self.layout.tile;
        let awake = &state.awake;
        state
            .prev
            .0
            .par_chunks_mut(tile)
            .zip(self.scratch.motion.par_iter_mut())
            .enumerate()
            .for_each(|(t, (points, motion))| {
                if awake[t] {
                    *motion = kernel::tile(&ctx, ctx.layout.tile_range(t), points);
                }
            });
        std::mem::swap(&mut state.prev, &mut state.cur);
        self.largest_motion = (0..awake.len())
            .filter(|&t| awake[t])
            .map(|t| self.scratch.motion[t])
            .fold(0.0, f32::max);
    }

    /// Gravity's displacement in one step, `g h²` (`None` when off or static).
    fn gravity_per_step(&self) -> Option<[f32; 3]> {
        let p = &self.params;
        if !p.world.has_gravity() {
            return None;
        }
        let scale = STANDARD_GRAVITY * self.diagonal * p.solver.time_step * p.solver.time_step;
        Some(p.world.gravity.map(|g| g * scale))
    }

    /// The floor's height along up ([`Simulation::up`]) when there is one.
    pub fn floor_height(&self) -> Option<f32> {
        self.floor().map(|f| f.height)
    }

    /// The floor, when the world has one.
    pub(super) fn floor(&self) -> Option<Floor> {
        let p = &self.params;
        p.world.floor.then(|| Floor {
            up: self.up,
            height: self.lowest + p.world.floor_height,
            keep: self.keep(),
        })
    }

    /// The share of its sliding motion a touching point keeps per step (the floor's and
    /// the balls' friction).
    fn keep(&self) -> f32 {
        let p = &self.params;
        (1.0 - p.world.floor_friction).powf(p.solver.time_step / REFERENCE_STEP)
    }

    /// Stage 5.
    fn sleep(&mut self) {
        if !self.options.sleeping {
            return;
        }
        let static_material = self.is_static();
        let (layout, state, scratch) = (&self.layout, &mut self.state, &mut self.scratch);
        scratch.to_wake.fill(false);
        for t in 0..layout.tiles() {
            if !state.awake[t] {
                continue;
            }
            if scratch.motion[t] > self.sleep_threshold2 {
                state.steps_under_threshold[t] = 0;
                for &u in layout.neighbours_of_tile(t) {
                    scratch.to_wake[u as usize] = true;
                }
            } else {
                state.steps_under_threshold[t] = state.steps_under_threshold[t].saturating_add(1);
            }
        }
        for t in 0..layout.tiles() {
            if scratch.to_wake[t] {
                if !state.awake[t] {
                    state.awake[t] = true;
                    state.steps_under_threshold[t] = 0;
                }
            } else if state.awake[t]
                && (static_material || state.steps_under_threshold[t] >= SLEEP_AFTER)
            {
                // Asleep with zero velocity: both buffers hold the same positions.
                state.awake[t] = false;
                state.prev.copy_range(&state.cur, layout.tile_range(t));
            }
        }
    }
}
