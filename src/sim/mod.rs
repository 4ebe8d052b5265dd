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
//!   paper's `ρ = f_max L` as `(f_max − 1) L` (see `docs/paper.md`): only then does
//!   `sl_max = 1` mean "no elastic movement" as Table 1 says.
//! * spring reduction (Provot): each bone spring is clamped into `[f_min L, f_max L]` by
//!   moving its mass-point end, alternating inner and outer spring, at most
//!   `reduction_iterations` times, stopping as soon as nothing is violated. If the budget runs
//!   out, the point is pulled towards its rest position until both springs are within bounds,
//!   so the constraint holds after every step.

//! # Where things are
//! * [`params`]: [`Params`] (the base [`Material`], the [`Solver`] and the [`World`]) and
//!   [`Constraint`];
//! * [`material`]: [`Material`] (what a region may change), Table 1's presets and materials
//!   files;
//! * `range`: a parameter's range, its clamp and its [`ParamError`];
//! * [`regions`]: several materials on one puppet (layers with a weight per vertex) and
//!   pinning;
//! * [`pose`]: the [`Pose`] a step takes and the [`Positions`] it leaves;
//! * [`options`]: run [`Options`] (sleeping, tile size, SIMD: a step's cost, not its physics);
//! * [`contact`]: sections colliding through their medial balls (stage 4c), and the floor;
//! * `step`: [`Simulation::step`], its numbered stages, and sleeping;
//! * [`layout`]: the solver's Hilbert-ordered slots and tiles;
//! * `kernel`, `lanes`: the fused pass over a tile, eight slots per register.

pub mod contact;
mod kernel;
mod lanes;
pub mod layout;
pub mod material;
pub mod options;
pub mod params;
pub mod pose;
mod range;
pub mod regions;
mod step;

pub use material::{
    parse_materials, presets, write_materials, Material, MaterialError, Preset, MAX_STIFFENING,
};
pub use options::{Options, SLEEP_AFTER};
pub use params::{Constraint, ParamError, Params, Solver, World, MAX_GRAVITY, STANDARD_GRAVITY};
pub use pose::{Pose, Positions};
pub use regions::{Layer, Regions};

use crate::rig::Rig;
use glam::{Affine3A, Vec3};
use layout::{Layout, Packed};
use regions::PerSlot;

/// The reference step `h₀` that `D` and `C_vd` are defined at (seconds).
pub const REFERENCE_STEP: f32 = 1.0 / 60.0;
/// Largest stiffness the UI and the parameter checks allow (the stability limit).
pub const MAX_STIFFNESS: f32 = 1.0;
/// Smallest accepted time step (seconds).
pub const MIN_STEP: f32 = 1.0 / 2000.0;

/// Time spent per stage of the last step (seconds).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Stage 0: which sections moved, which tiles wake.
    pub wake: f64,
    /// Stages 1–4 fused in one pass over the awake tiles: bone transforms, forces, Verlet,
    /// constraint.
    pub fused: f64,
    /// Stage 4c: contacts between sections (zero when collision is off).
    pub contact: f64,
    /// Stage 5: tiles that stopped moving go to sleep, moving tiles wake their neighbours.
    pub sleep: f64,
}

impl StageTimes {
    /// The whole step.
    pub fn total(&self) -> f64 {
        self.wake + self.fused + self.contact + self.sleep
    }
}

/// What a simulation remembers from one step to the next.
#[derive(Clone, Debug)]
struct State {
    /// Current and previous positions by slot (the step writes the new positions over the
    /// previous ones, then swaps).
    cur: Packed,
    prev: Packed,
    /// Section of each rig vertex (all 0 until joints cut the skeleton).
    section_of: Vec<u16>,
    /// Transform of each section in the last step, as the kernel reads (and, in tiles
    /// that mix sections, gathers) it.
    transforms: Vec<kernel::Rows>,
    /// Per tile: integrated by the next step, and how many steps in a row it stayed under
    /// the sleep threshold.
    awake: Vec<bool>,
    steps_under_threshold: Vec<u16>,
    /// Every tile wakes at the next step (a parameter, option or section change).
    wake_all: bool,
    /// Steps taken.
    steps: u64,
    /// Frame time not yet simulated ([`Simulation::advance`]).
    time_debt: f32,
}

/// Buffers one step fills and the next overwrites; nothing in them survives a step.
#[derive(Clone, Debug, Default)]
struct Scratch {
    /// Per tile: the largest squared displacement of the step.
    motion: Vec<f32>,
    /// Per section: its transform changed this step.
    changed: Vec<bool>,
    /// Per tile: woken by a moving neighbour.
    to_wake: Vec<bool>,
    /// Per section: its transform this step (for the contacts).
    affine: Vec<Affine3A>,
}

/// What the contacts need of the joints (`Joints::joint_sections`), per vertex and per
/// section. The transforms of [`Simulation::set_sections`] split a section into its band
/// levels; contacts go by whole sections.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct JointSections {
    /// Each vertex's joint section: a point never collides with its own section's balls,
    /// whichever band level moves it.
    pub section: Vec<u16>,
    /// Each section's rank: a point yields only to the balls of sections of lower rank
    /// (a limb to the body it is pressed into).
    pub rank: Vec<u32>,
    /// Each vertex's joint flesh: 1 + the index of the joint it lies at, 0 for none. A
    /// point is never pushed out of a ball of its own joint's flesh that it lay near at
    /// rest; two parts that merely rest against each other do collide. Empty: every pair
    /// near at rest is a joint's flesh.
    pub flesh: Vec<u16>,
}

/// A simulated puppet: rig, parameters, options, state and scratch.
#[derive(Clone)]
pub struct Simulation {
    rig: Rig,
    params: Params,
    options: Options,
    layout: Layout,
    state: State,
    scratch: Scratch,
    /// Material and pin weight per vertex, and what the kernel reads of them by slot
    /// (`None` when every vertex has the parameters' material / nothing is pinned).
    regions: Regions,
    per_slot: Option<PerSlot>,
    pin: Option<Vec<f32>>,
    /// Every vertex's material is static: the surface just follows the bones.
    all_static: bool,
    /// The medial balls sections collide with, built at the first step with collision on
    /// (and again after the sections change).
    contacts: Option<contact::Colliders>,
    /// The pairs of sections the contacts act between (`None`: every pair), and whether
    /// they changed since the contacts last took them.
    pairs: Option<contact::Pairs>,
    pairs_changed: bool,
    /// The joint sections, for contacts (empty: the transforms').
    joint: JointSections,
    /// The sleep threshold as a squared distance.
    sleep_threshold2: f32,
    diagonal: f32,
    /// Which way is up (the floor's normal), and the rest mesh's lowest height along it
    /// (the floor's origin).
    up: contact::Up,
    lowest: f32,
    /// What the last step did.
    awake_tiles: usize,
    largest_motion: f32,
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
        if rig.bone_distance != params.material.bone_distance {
            rig.set_bone_distance(params.material.bone_distance);
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
            state: State {
                section_of: vec![0; n],
                transforms: vec![kernel::IDENTITY_ROWS],
                prev: cur.clone(),
                cur,
                awake: vec![true; tiles],
                steps_under_threshold: vec![0; tiles],
                wake_all: true,
                steps: 0,
                time_debt: 0.0,
            },
            scratch: Scratch {
                motion: vec![0.0; tiles],
                changed: vec![false; 1],
                to_wake: vec![false; tiles],
                affine: Vec::new(),
            },
            contacts: None,
            pairs: None,
            pairs_changed: false,
            joint: JointSections::default(),
            regions: Regions::default(),
            per_slot: None,
            pin: None,
            all_static: params.is_static(),
            sleep_threshold2: 0.0,
            diagonal,
            up: contact::Up::default(),
            lowest: if n > 0 { lo.y } else { 0.0 },
            awake_tiles: tiles,
            largest_motion: 0.0,
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

    /// The run options in force.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Changes the run options (a new tile size renumbers nothing but re-cuts the
    /// tiles). Every tile wakes.
    pub fn set_options(&mut self, options: Options) {
        let tile = options.tile.max(1);
        if tile != self.layout.tile {
            self.layout = Layout::new(&self.rig, tile);
            self.layout.set_sections(&self.state.section_of);
            self.contacts = None;
            let tiles = self.layout.tiles();
            self.state.awake = vec![true; tiles];
            self.state.steps_under_threshold = vec![0; tiles];
            self.scratch.motion = vec![0.0; tiles];
            self.scratch.to_wake = vec![false; tiles];
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
        self.sleep_threshold2 = (threshold * self.diagonal).powi(2);
        self.state.wake_all = true;
    }

    /// Changes parameters; they take effect on the next step and wake every tile. A new
    /// bone distance moves the bone points in O(n) without touching the skeleton.
    pub fn set_params(&mut self, params: Params) {
        let params = params.sanitized();
        if params == self.params {
            return;
        }
        self.params = params;
        if self.regions.is_mixed() {
            self.refresh_regions();
        } else {
            if self.params.material.bone_distance != self.rig.bone_distance {
                self.rig
                    .set_bone_distance(self.params.material.bone_distance);
                self.layout.set_bone_length(&self.rig);
            }
            self.all_static = self.params.is_static();
        }
        self.state.wake_all = true;
    }

    /// Sets which way is up: the axis direction nearest `up` (the puppet's, found or
    /// given). The floor lies across it, under the rest mesh's lowest point along it.
    pub fn set_up(&mut self, up: Vec3) {
        let up = contact::Up::nearest(up);
        if up == self.up {
            return;
        }
        self.up = up;
        self.lowest = self
            .rig
            .rest
            .iter()
            .map(|&p| up.height(p))
            .fold(f32::INFINITY, f32::min);
        if !self.lowest.is_finite() {
            self.lowest = 0.0;
        }
        self.state.wake_all = true;
    }

    /// Which way is up (see [`Simulation::set_up`]).
    pub fn up(&self) -> contact::Up {
        self.up
    }

    /// Gives vertices their own materials and pin weights (see [`Regions`]); every tile
    /// wakes. Weights missing at the end count as 0; extra ones are dropped.
    pub fn set_regions(&mut self, mut regions: Regions) {
        let n = self.rig.len();
        for layer in &mut regions.layers {
            layer.weight.resize(n, 0.0);
        }
        regions.pin.resize(n, 0.0);
        if regions == self.regions {
            return;
        }
        self.regions = regions;
        self.refresh_regions();
        self.state.wake_all = true;
    }

    /// The materials and pin weights in force.
    pub fn regions(&self) -> &Regions {
        &self.regions
    }

    /// Rebuilds the per-slot constants and the bone points from the regions.
    fn refresh_regions(&mut self) {
        let (regions, base) = (&self.regions, self.params);
        if regions.is_mixed() {
            let of_vertex: Vec<Material> = (0..self.rig.len())
                .map(|i| regions.material_of(i, &base.material))
                .collect();
            self.rig
                .set_bone_distances(base.material.bone_distance, |i| of_vertex[i].bone_distance);
            self.per_slot = Some(PerSlot::new(
                &of_vertex,
                base.solver.time_step,
                &self.layout.order,
            ));
            self.all_static = of_vertex.iter().all(Material::is_static);
        } else {
            self.rig.set_bone_distance(base.material.bone_distance);
            self.per_slot = None;
            self.all_static = base.is_static();
        }
        self.layout.set_bone_length(&self.rig);
        self.pin = regions.is_pinned().then(|| {
            self.layout
                .order
                .iter()
                .map(|&v| regions.pin_of(v as usize))
                .collect()
        });
    }

    /// True when no vertex is integrated: every material is static.
    pub fn is_static(&self) -> bool {
        self.all_static
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
        self.state.section_of = section_of;
        self.state
            .transforms
            .resize(sections, kernel::IDENTITY_ROWS);
        self.scratch.changed.resize(sections, false);
        self.contacts = None;
        self.state.wake_all = true;
    }

    /// Lets the contacts act only between pairs of sections the pose limit stopped against
    /// each other ([`contact::Pairs`]), adding the pairs `met` (sections of `sections`). A
    /// puppet calls it on every move it holds back (`Puppet::hold_back`); until then,
    /// every pair.
    pub fn contacts_between(&mut self, sections: usize, met: &[(usize, usize)]) {
        let pairs = match &mut self.pairs {
            Some(p) if p.sections() == sections => p,
            _ => {
                self.pairs_changed = true;
                self.pairs.insert(contact::Pairs::new(sections))
            }
        };
        for &(a, b) in met {
            self.pairs_changed |= pairs.add(a, b);
        }
    }

    /// Lets the contacts act between every pair of sections again (the sections changed).
    pub fn contacts_everywhere(&mut self) {
        self.pairs_changed |= self.pairs.take().is_some();
    }

    /// Gives the joint sections the contacts go by ([`JointSections`]). Without them, each
    /// transform of [`Simulation::set_sections`] counts as a section, ranked by its index,
    /// and every pair near at rest is a joint's flesh.
    pub fn set_joint_sections(&mut self, joint: JointSections) {
        if joint.section.len() == self.rig.len() && joint != self.joint {
            self.joint = joint;
            self.contacts = None;
        }
    }

    /// Current positions.
    pub fn positions(&self) -> Positions<'_> {
        Positions {
            points: &self.state.cur,
            slot: &self.layout.slot,
        }
    }

    /// Previous positions (velocity = current − previous).
    pub fn previous_positions(&self) -> Positions<'_> {
        Positions {
            points: &self.state.prev,
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
            t.transform_vector3(s.normal.get(k)).normalize_or_zero(),
            s.bone_length[k],
        )
    }

    fn transform_of(&self, i: usize) -> Affine3A {
        self.state
            .transforms
            .get(self.state.section_of[i] as usize)
            .map_or(Affine3A::IDENTITY, kernel::affine_of)
    }

    /// The vertices a contact holds: the last step that tested them put them out of
    /// another section's ball (they may be outside their constraint: a contact wins over
    /// it, as the floor does).
    pub fn in_contact(&self) -> Vec<usize> {
        self.contacts.as_ref().map_or_else(Vec::new, |c| {
            c.held()
                .iter()
                .enumerate()
                .filter(|(_, &h)| h)
                .map(|(k, _)| self.layout.order[k] as usize)
                .collect()
        })
    }

    /// Forgets the contacts' kept lists of the balls near each tile, so that the next step
    /// gathers them all again: what the stage finds does not depend on them (a test
    /// compares).
    #[doc(hidden)]
    pub fn forget_contact_lists(&mut self) {
        if let Some(c) = &mut self.contacts {
            c.forget_lists();
        }
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.state.steps
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
        !self.state.wake_all && self.state.awake.iter().all(|a| !a)
    }

    /// The largest squared distance any mass point moved in the last step.
    pub fn largest_motion(&self) -> f32 {
        self.largest_motion
    }

    /// Sum of squared per-step displacements (proportional to kinetic energy).
    pub fn kinetic_energy(&self) -> f64 {
        let s = &self.state;
        (0..s.cur.len())
            .map(|k| (s.cur.get(k) - s.prev.get(k)).length_squared() as f64)
            .sum()
    }
}
