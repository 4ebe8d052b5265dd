//! A puppet put together: mesh → skeleton → rig → simulation, with its joints, as a
//! [`RigFile`] describes it.
//!
//! * this file: building it, suggesting joints, holding a pose back where parts meet;
//! * `rig_file`: the rig file, TOML or JSON;
//! * `paint`: painted weights of material regions and the pinning;
//! * `bake`: playing an animation on the fixed step and keeping chosen frames;
//! * `bend`, `press`, `poses`: measured bends, presses and random poses (what the benches
//!   and tests hold the puppet to).

pub mod bake;
pub mod bend;
pub mod paint;
pub mod poses;
pub mod press;
mod rig_file;

pub use paint::Paint;
pub use rig_file::{Region, RigError, RigFile};

use crate::anim::Bound;
use crate::files;
use crate::joints::{JointError, Joints, Local, PoseScratch};
use crate::mesh::orientation::Up;
use crate::mesh::{self, Groups, LoadReport, Mesh, MeshError};
use crate::progress::Progress;
use crate::rig::Rig;
use crate::sim::{Layer, Regions, Simulation};
use crate::skeleton::{self, Skeleton, SkeletonError, SkeletonParams};
use glam::DVec3;
use std::path::Path;

/// Why a puppet could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The mesh has no usable normals.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The skeleton could not be built.
    #[error(transparent)]
    Skeleton(#[from] SkeletonError),
    /// A cut of the rig file is impossible on this skeleton.
    #[error(transparent)]
    Joints(#[from] JointError),
    /// A region or the pinning of the rig file does not fit this mesh or these sections.
    #[error("{0}")]
    Regions(String),
}

/// A file could not be written; the message says why in words.
#[derive(Debug, thiserror::Error)]
#[error("cannot write: {}", files::io_message(.0))]
pub struct WriteError(#[from] pub std::io::Error);

/// A live puppet: the mesh, its skeleton, joints and simulation.
#[derive(Clone)]
pub struct Puppet {
    /// The validated mesh.
    pub mesh: Mesh,
    /// Its medial skeleton.
    pub skeleton: Skeleton,
    /// Sections, cuts and pivots.
    pub joints: Joints,
    /// The mass points and their state.
    pub sim: Simulation,
    /// The rig file it was built from (preset name, skeleton method, mesh path).
    pub rig_file: RigFile,
    /// The mesh file's named groups (its materials), which regions may name.
    pub groups: Groups,
    /// The sections' balls for the pose limit, built when first needed (and again after
    /// the cuts change).
    balls: Option<std::sync::Arc<crate::joints::collide::Balls>>,
    /// The pose limit's pairs of balls near each other, kept from move to move
    /// ([`crate::joints::collide::Near`]).
    near: crate::joints::collide::Near,
    /// Where the last move [`Puppet::hold_back`] stopped short ended, and the pose it was
    /// going to: the same move asked again (a pose held against the body, step after
    /// step) stays where it is without being tested again.
    stopped: Option<(Vec<Local>, Vec<Local>)>,
    /// Whether the pose collision came on in was looked at for parts already pressing
    /// each other ([`Puppet::hold_back`]).
    pressing_found: bool,
    /// Up, front and left, as the last suggestion found them.
    frame: Option<crate::mesh::orientation::Frame>,
    /// The axes the mesh file's format declares (glTF's +y up and +z front, by its
    /// specification): up taken as given where the rig file gives none, the front where
    /// up is the file's ([`crate::mesh::orientation::Axes::given`]).
    format_axes: Option<crate::mesh::orientation::Axes>,
    /// Suggest joints from the skeleton even when the mesh file has a skin.
    pub ignore_skin: bool,
    /// Where the mesh's separate parts meet ([`crate::mesh::attachments`]), found once
    /// when it is built: its joints join the parts there, and the suggestion walks them.
    attachments: Vec<(u32, u32)>,
}

/// Where a puppet's joints come from, as `suggest` and `simulate` report it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum JointsFrom {
    /// The rig file's cuts.
    Rig,
    /// The suggestion from the skeleton.
    Suggestion,
    /// The mesh file's skin.
    Skin,
    /// None: one rigid section.
    None,
}

impl JointsFrom {
    /// Its name as `--json` writes it.
    pub fn name(self) -> &'static str {
        match self {
            JointsFrom::Rig => "rig",
            JointsFrom::Suggestion => "suggestion",
            JointsFrom::Skin => "skin",
            JointsFrom::None => "none",
        }
    }
}

impl Puppet {
    /// Builds the skeleton, rig, simulation and joints of a validated mesh.
    pub fn build(mesh: Mesh, rig_file: RigFile, progress: Progress) -> Result<Puppet, BuildError> {
        Puppet::build_loaded(mesh, None, rig_file, progress)
    }

    /// [`Puppet::build`] for a mesh as loading left it (`report`): the file's groups, which
    /// the rig file's regions may name, and where a hole was filled or a vertex split, every
    /// skeletal point held inside ([`Skeleton::keep_inside`]).
    pub fn build_loaded(
        mesh: Mesh,
        report: Option<&LoadReport>,
        rig_file: RigFile,
        progress: Progress,
    ) -> Result<Puppet, BuildError> {
        let normals = mesh::vertex_normals(&mesh)?;
        let params = SkeletonParams {
            method: rig_file.method,
            ..SkeletonParams::default()
        };
        let mut skeleton = skeleton::cache::build_cached(&mesh, &normals, &params, progress)?;
        let groups = report.map(|r| r.groups.clone()).unwrap_or_default();
        let parts = mesh::Parts::of(&mesh);
        let repaired = report.is_some_and(|r| !r.marks.is_empty());
        let moved = skeleton.hold_inside(&mesh, &parts, repaired);
        if moved > 0 {
            log::debug!("{moved} skeletal points moved back inside the mesh");
        }
        // Riders go with the section of the body vertex nearest to them.
        let hosts = if skeleton.riders > 0 {
            parts.hosts(&mesh.positions)
        } else {
            Vec::new()
        };
        let mut uncut =
            Joints::with_mesh(&skeleton.points, &mesh.triangles, &hosts, &rig_file.root);
        let attachments = parts.attachments(&mesh);
        uncut.attach_parts(&attachments);
        uncut.set_surface(&mesh.positions, &skeleton.distance);
        uncut.set_skin(report.and_then(|r| r.skin.clone()));
        let joints = rig_file.joints(uncut)?;
        let rig = Rig::new(
            &mesh,
            &normals,
            &skeleton.distance,
            rig_file.params.material.bone_distance,
        );
        let mut sim = Simulation::new(rig, rig_file.params);
        sim.set_sections(joints.transform_of().to_vec());
        sim.set_joint_sections(joints.joint_sections());
        let mut puppet = Puppet {
            mesh,
            skeleton,
            joints,
            sim,
            rig_file,
            groups,
            balls: None,
            near: Default::default(),
            stopped: None,
            pressing_found: false,
            frame: None,
            format_axes: report
                .is_some_and(|r| r.format == mesh::Format::Gltf)
                .then_some(crate::mesh::orientation::Axes::GLTF),
            ignore_skin: false,
            attachments,
        };
        let regions = puppet.regions(true).map_err(BuildError::Regions)?;
        puppet.sim.set_regions(regions);
        puppet.sim.set_up(puppet.up().as_vec3());
        Ok(puppet)
    }

    /// The rig file's regions and pinning resolved on the current sections. `strict`: an
    /// unknown section or painted weights for another vertex count are errors (see
    /// [`Paint::resolve`]).
    pub fn regions(&self, strict: bool) -> Result<Regions, String> {
        let mut out = Regions::default();
        for r in &self.rig_file.regions {
            out.layers.push(Layer {
                material: r.material,
                weight: r
                    .paint
                    .resolve(&self.joints, &self.groups, strict)
                    .map_err(|e| format!("region '{}': {e}", r.name))?,
            });
        }
        out.pin = self
            .rig_file
            .pin
            .resolve(&self.joints, &self.groups, strict)
            .map_err(|e| format!("pin: {e}"))?;
        Ok(out)
    }

    /// Builds the pose limit's balls now rather than on the first move with collision on
    /// (a downloaded statue's take tens of milliseconds), and looks for parts pressing
    /// each other at rest ([`Puppet::hold_back`]): what a window holds once a part has
    /// been dragged, and what `bench poses` times.
    pub fn ready_pose_limit(&mut self) {
        let rest = vec![Local::default(); self.joints.sections().len()];
        self.pressing_found = true;
        if let Some(back) = self.back_off(&rest) {
            self.stopped = Some((back, rest));
        }
    }

    /// Once after collision comes on (or the cuts change), for the pose `pose` the puppet
    /// holds: when parts of it press each other (posed with collision off, then turned
    /// on), the pose they would have stopped in, reached from rest as a move is held back
    /// ([`crate::joints::collide::Balls::hold`]), and the contacts act between them. No
    /// move of a pose that already presses meets anything new, so its parts would stay
    /// through each other. `None` when none press.
    fn back_off(&mut self, pose: &[Local]) -> Option<Vec<Local>> {
        let balls = self.pose_balls();
        let mut met = balls.pressing_sections(&self.joints.world(pose));
        if met.is_empty() {
            return None;
        }
        let rest = vec![Local::default(); pose.len()];
        let back = balls.hold(&self.joints, &rest, pose, &mut met, &mut self.near);
        let sections = self.joints.sections().len();
        self.sim.contacts_between(sections, &met);
        back
    }

    /// The sections' balls for the pose limit, built when first needed, letting parts
    /// overlap by the flesh's give ([`crate::joints::collide::Balls::set_squash`]).
    fn pose_balls(&mut self) -> std::sync::Arc<crate::joints::collide::Balls> {
        let joints = &self.joints;
        let squash = f64::from(self.sim.params().world.flesh);
        let balls = self
            .balls
            .get_or_insert_with(|| std::sync::Arc::new(joints.balls()));
        if balls.squash() != squash {
            std::sync::Arc::make_mut(balls).set_squash(squash);
        }
        balls.clone()
    }

    /// Gives the simulation the current sections, and the regions and pinning resolved on
    /// them ([`Puppet::sync_regions`]). Call after any change of cuts.
    pub fn sync_sections(&mut self) {
        self.balls = None;
        self.near = Default::default();
        self.stopped = None;
        self.pressing_found = false;
        self.sim.contacts_everywhere();
        self.sim.set_sections(self.joints.transform_of().to_vec());
        self.sim.set_joint_sections(self.joints.joint_sections());
        self.sync_regions();
    }

    /// Gives the simulation the rig file's regions and pinning, resolved on the current
    /// sections (a region naming a section that no longer exists skips it). Call after a
    /// change of regions or paint.
    pub fn sync_regions(&mut self) {
        if let Ok(regions) = self.regions(false) {
            self.sim.set_regions(regions);
        }
    }

    /// Writes the current simulated surface as an OBJ file (the welded input's vertex order
    /// and faces).
    pub fn save_surface(&self, path: &Path, header: &str) -> Result<(), WriteError> {
        let x = self.sim.positions();
        let points: Vec<DVec3> = (0..x.len()).map(|i| x.get(i).as_dvec3()).collect();
        let mut file = std::fs::File::create(path).map_err(WriteError::from)?;
        mesh::write_obj(&mut file, &points, &self.mesh.triangles, header).map_err(WriteError::from)
    }

    /// Replaces the cuts with the joints suggested by the skeleton
    /// ([`crate::joints::suggest`]), or, when the mesh file came with a skin (and
    /// [`Puppet::ignore_skin`] is off), the skin's joints ([`crate::joints::skin`]);
    /// returns how many. On error nothing changes.
    pub fn suggest_joints(&mut self) -> Result<usize, JointError> {
        let mut root = self.joints.sections()[0].name.clone();
        let given = crate::mesh::orientation::Axes::given(
            self.format_axes,
            self.rig_file.up,
            self.rig_file.front,
        );
        let (mut cuts, frame) = crate::joints::suggest::suggest(
            &self.mesh,
            &self.skeleton,
            &self.attachments,
            &root,
            given,
        );
        self.frame = Some(frame);
        let mut skinned = false;
        if let Some(skin) = self.skin_joints() {
            root = skin.root;
            cuts = skin.cuts;
            skinned = true;
        }
        // The floor lies across the up the suggestion found (unless the rig gives one).
        self.sim.set_up(self.up().as_vec3());
        let mut joints = self.joints.without_cuts(&root);
        if skinned {
            joints.add_cuts(cuts)?;
        } else {
            // The suggestion weighs its cuts on the sections before parts of the mesh go
            // whole (see `joints::whole`), then the puppet takes them whole.
            joints.set_parts_whole(false);
            crate::joints::suggest::seams::add(&mut joints, cuts);
            joints.set_parts_whole(true);
        }
        let count = joints.cuts().len();
        self.joints = joints;
        self.sync_sections();
        Ok(count)
    }

    /// Where its joints come from: after [`Puppet::suggest_joints`] (`suggested`) the skin
    /// when it gives them, else the suggestion; otherwise the rig's cuts, or none.
    pub fn joints_from(&self, suggested: bool) -> JointsFrom {
        match (suggested, self.skin_joints().is_some()) {
            (true, true) => JointsFrom::Skin,
            (true, false) => JointsFrom::Suggestion,
            _ if self.joints.cuts().is_empty() => JointsFrom::None,
            _ => JointsFrom::Rig,
        }
    }

    /// The joints the mesh file's skin gives, unless [`Puppet::ignore_skin`] is on.
    pub fn skin_joints(&self) -> Option<crate::joints::skin::SkinJoints> {
        if self.ignore_skin {
            return None;
        }
        self.joints.skin_joints()
    }

    /// Sets aside the axes the mesh file's format declares ([`Puppet::up`] and the next
    /// suggestion find up and front from the shape alone): what the suggestion's own cues
    /// do on a glTF file.
    pub fn ignore_format_axes(&mut self) {
        self.format_axes = None;
        self.sim.set_up(self.up().as_vec3());
    }

    /// Up, front and left as the last suggestion found them (`None` before one).
    pub fn frame(&self) -> Option<crate::mesh::orientation::Frame> {
        self.frame
    }

    /// The mesh's up direction: the rig file's, or the file format's (glTF's +y), or as the
    /// last suggestion found it, or +y.
    pub fn up(&self) -> DVec3 {
        match (
            self.rig_file.up.or(self.format_axes.map(|a| a.up)),
            self.frame,
        ) {
            (Some(u), _) => u.vector(),
            (None, Some(f)) => f.up,
            (None, None) => DVec3::Y,
        }
    }

    /// With collision on, takes the move from the pose `before` to the pose in `local`
    /// only as far as no part presses into another, each turn as far as it can
    /// ([`crate::joints::collide::Balls::hold`]): `local` becomes the pose reached, and the
    /// contacts act between the parts that met. Every path that poses a section goes
    /// through it (a drag, a glove, an animation, a recorded take, `simulate`), so a part
    /// stops at the body the same way whatever moves it. A `before` shorter than `local`
    /// is at rest beyond its end. The first call after collision comes on (or the cuts
    /// change) takes a `before` whose parts already press each other back to where they
    /// meet first, reached from rest (see `Puppet::back_off`).
    pub fn hold_back(&mut self, before: &[Local], local: &mut Vec<Local>) {
        if !self.sim.params().world.collision {
            self.pressing_found = false;
            return;
        }
        let backed;
        let mut before = before;
        if !self.pressing_found {
            self.pressing_found = true;
            if let Some(back) = self.back_off(before) {
                backed = back;
                before = &backed;
            }
        }
        if let Some((at, wanted)) = &self.stopped {
            if at.as_slice() == before && wanted == local {
                local.clear();
                local.extend_from_slice(before);
                return;
            }
        }
        let mut met = Vec::new();
        let got = self
            .pose_balls()
            .hold(&self.joints, before, local, &mut met, &mut self.near);
        // The contacts act between the parts that met (`sim::contact::Pairs`).
        let sections = self.joints.sections().len();
        self.sim.contacts_between(sections, &met);
        if let Some(reached) = got {
            let wanted = std::mem::replace(local, reached);
            self.stopped = Some((local.clone(), wanted));
        } else {
            self.stopped = None;
        }
    }

    /// One step toward the pose `wanted`: the move from the pose played last (`local`,
    /// empty at rest) held back where parts meet ([`Puppet::hold_back`]), then one
    /// simulation step in the pose reached, which `local` becomes.
    pub fn step_toward(
        &mut self,
        wanted: &[Local],
        local: &mut Vec<Local>,
        scratch: &mut PoseScratch,
    ) {
        if self.sim.params().world.collision {
            let before = std::mem::replace(local, wanted.to_vec());
            self.hold_back(&before, local);
        } else {
            self.pressing_found = false;
            // Nothing to hold back: no allocation in the step.
            local.clear();
            local.extend_from_slice(wanted);
        }
        let pose = self.joints.pose_into(local, scratch);
        self.sim.step(pose);
    }

    /// Step `step` (1-based) of an animation: the pose at `step × h`, reached from the
    /// pose played last (`local`) as [`Puppet::step_toward`] does, then one simulation
    /// step. `simulate` and the window's playback both play animations through this, so a
    /// take previewed in the window and baked by `simulate` give the same positions bit
    /// for bit (same fixed step, same pose sampling); and an animation that swings a limb
    /// into the body stops it there, as a drag does.
    pub fn step_animated(
        &mut self,
        animation: &Bound,
        step: u64,
        local: &mut Vec<Local>,
        scratch: &mut PoseScratch,
    ) {
        let h = self.sim.params().solver.time_step as f64;
        // The sample goes into the scratch's buffer (kept from step to step).
        let mut wanted = std::mem::take(&mut scratch.wanted);
        animation.sample(step as f64 * h, &mut wanted);
        self.step_toward(&wanted, local, scratch);
        scratch.wanted = wanted;
    }

    /// The rig file of the puppet as it is now (parameters, and cuts with resolved pivots).
    pub fn current_rig_file(&self) -> RigFile {
        // An up found other than +y is written, so the rig opens the mesh standing.
        let found = Up::nearest(self.up());
        RigFile {
            params: *self.sim.params(),
            cuts: self.joints.cuts().to_vec(),
            root: self.joints.sections()[0].name.clone(),
            up: self.rig_file.up.or((found != Up::PosY).then_some(found)),
            ..self.rig_file.clone()
        }
    }
}
