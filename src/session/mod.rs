//! What the puppeteer works on, without any window: the puppet, its pose, the selection,
//! undo/redo, the cut tool, when the simulation has settled, and what to draw. The window
//! (`app`, behind the `gui` feature) turns mouse and keys into calls here; tests call the
//! same functions.
//!
//! * [`camera`]: the orbit camera and rays through the cursor;
//! * [`pointer`]: a mouse button's press, moves and release as clicks and drags;
//! * [`pick`]: rays against the current surface;
//! * [`undo`]: snapshots of cuts and pose;
//! * [`cut_tool`]: the cut being placed, applying and removing cuts;
//! * [`paint_tool`]: the brush that paints material regions and pinning;
//! * [`playback`]: playing an animation file (what `simulate` bakes, bit for bit);
//! * [`recording`]: recording a take from the puppeteer's hands;
//! * [`export`]: baking the animation to `.glb`, `.pc2`, OBJ files or a video (through a
//!   [`TakeWriter`] the shell gives) on a thread;
//! * [`view`]: what a renderer draws (surface colours, overlay lines) and when it changed;
//! * [`loader`]: reading a mesh and building its puppet on a background thread;
//! * [`live`]: live controls (a glove, MIDI, a gamepad) turning sections.

pub mod camera;
pub mod cut_tool;
pub mod export;
pub mod live;
pub mod loader;
pub mod paint_tool;
pub mod pick;
pub mod playback;
pub mod pointer;
pub mod recording;
pub mod undo;
pub mod view;

pub use camera::Camera;
pub use cut_tool::{CutAxis, CutDraft, CutTool, ShapeKind};
pub use export::{ExportJob, ExportSettings, TakeWriter};
pub use paint_tool::PaintTool;
pub use pick::Hit;
pub use playback::Playback;
pub use recording::Recorder;
pub use view::{Ground, Lighting, Line, Overlays, View};

use crate::joints::{Local, PoseScratch};
use crate::mesh::RepairMarks;
use crate::puppet::Puppet;
use crate::sim::{Material, Params};
use glam::{DQuat, DVec3};
use std::sync::atomic::{AtomicU64, Ordering};

/// The puppet has settled when no vertex moved more than this fraction of the model's
/// bounding-box diagonal in the last step (invisible at any zoom that shows the whole
/// model) and the pose did not change.
pub const SETTLED_MOTION: f64 = 1e-6;

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// The working state of the app.
pub struct Session {
    /// Unique per session (render caches key on it).
    pub id: u64,
    /// The puppet being played.
    pub puppet: Puppet,
    /// Mesh name shown in the title and messages.
    pub name: String,
    /// Local pose of every section.
    pub local: Vec<Local>,
    /// Selected sections.
    pub selection: Vec<usize>,
    /// The cut tool's settings.
    pub cut_tool: CutTool,
    /// The cut tool's plane, once placed.
    pub draft: Option<CutDraft>,
    /// The brush's settings.
    pub paint_tool: PaintTool,
    /// The animation loaded, if any, and where its playback is.
    pub playback: Option<Playback>,
    /// Recording settings and the take being recorded.
    pub recorder: Recorder,
    /// What *Export animation* writes.
    pub export_settings: ExportSettings,
    /// The export running, if any.
    export: Option<ExportJob>,
    /// Simulation paused by the user ([`Session::set_paused`]).
    paused: bool,
    /// The regions and pinning as undo keeps them.
    regions_state: paint_tool::RegionsState,
    undo: undo::History,
    scratch: PoseScratch,
    /// No step needed: pose unchanged and motion died out.
    settled: bool,
    /// Bumped whenever the surface or anything drawn changes (render caches key on it).
    pub revision: u64,
    /// Bumped when sections, selection or cuts change (colours, overlays).
    pub layout_revision: u64,
    /// Where loading repaired the mesh (filled holes, split vertices), for the overlay.
    pub repairs: RepairMarks,
}

impl Session {
    /// A session on a freshly built puppet, at rest, nothing selected.
    pub fn new(puppet: Puppet, name: impl Into<String>) -> Session {
        let sections = puppet.joints.sections().len();
        let regions_state = paint_tool::RegionsState::of(
            puppet.rig_file.regions.clone(),
            puppet.rig_file.pin.clone(),
        );
        Session {
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            puppet,
            name: name.into(),
            local: vec![Local::default(); sections],
            selection: Vec::new(),
            cut_tool: CutTool::default(),
            draft: None,
            paint_tool: PaintTool::default(),
            playback: None,
            recorder: Recorder::default(),
            export_settings: ExportSettings::default(),
            export: None,
            paused: false,
            regions_state,
            undo: undo::History::default(),
            scratch: PoseScratch::default(),
            settled: false,
            revision: 0,
            layout_revision: 0,
            repairs: RepairMarks::default(),
        }
    }

    /// True when the puppet has settled (see [`SETTLED_MOTION`]): stepping would change
    /// nothing until something else does.
    pub fn is_settled(&self) -> bool {
        self.settled
    }

    /// True when the simulation needs steps: neither settled nor paused. When it does not,
    /// the window stops stepping and drawing until the next input.
    pub fn is_running(&self) -> bool {
        !self.settled && !self.paused
    }

    /// True when the user paused the simulation.
    pub fn is_paused(&self) -> bool {
        self.paused
    }

    /// Pauses or resumes the simulation; resumed, it steps again (and the window draws
    /// the change either way).
    pub fn set_paused(&mut self, paused: bool) {
        if self.paused != paused {
            self.paused = paused;
            self.wake();
        }
    }

    /// What Space does: plays or pauses the animation playing, else pauses or resumes
    /// the simulation.
    pub fn toggle_pause(&mut self) {
        if self.playback.is_some() {
            self.toggle_play();
        } else {
            self.set_paused(!self.paused);
        }
    }

    /// Something changed: simulate again.
    pub fn wake(&mut self) {
        self.settled = false;
        self.revision += 1;
    }

    /// Runs the simulation for `seconds` of wall time (at most `max_steps` fixed steps).
    /// Returns the steps taken; none when not running.
    pub fn advance(&mut self, seconds: f32, max_steps: u32) -> u32 {
        if !self.is_running() {
            return 0;
        }
        if self.is_recording() {
            return self.record_steps(seconds, max_steps);
        }
        if self.is_playing() {
            let due = self.puppet.sim.steps_due(seconds, max_steps);
            self.play_steps(due as u64);
            self.wrap_loop_range();
            // A finished animation that does not loop holds its last pose.
            let time = self.playback_time();
            if let (Some(p), Some((t, duration))) = (&mut self.playback, time) {
                if !p.animation.looping && t >= duration {
                    p.playing = false;
                }
            }
            return due;
        }
        let pose = self.puppet.joints.pose_into(&self.local, &mut self.scratch);
        let steps = self.puppet.sim.advance(pose, seconds, max_steps);
        if steps > 0 {
            self.revision += 1;
            let limit = SETTLED_MOTION * self.puppet.mesh.diagonal();
            if self.puppet.sim.is_static()
                || self.puppet.sim.largest_motion() as f64 <= limit * limit
            {
                self.settled = true;
            }
        }
        steps
    }

    /// Selects `section` (or clears the selection with `None`); `toggle` adds it to the
    /// selection or takes it out (Shift/Ctrl+click) instead of replacing the selection.
    pub fn select(&mut self, section: Option<usize>, toggle: bool) {
        match section {
            Some(s) if s < self.local.len() => {
                if toggle {
                    if let Some(k) = self.selection.iter().position(|&x| x == s) {
                        self.selection.remove(k);
                    } else {
                        self.selection.push(s);
                    }
                } else {
                    self.selection = vec![s];
                }
            }
            _ if !toggle => self.selection.clear(),
            _ => {}
        }
        self.layout_revision += 1;
        self.revision += 1;
    }

    /// Rotates every selected section by `rotation` (world space) about its current pivot.
    /// A section whose ancestor is also selected is carried by it, not turned twice.
    pub fn rotate_selected(&mut self, rotation: DQuat) {
        if !rotation.is_finite() || self.selection.is_empty() {
            return;
        }
        let world = self.puppet.joints.world(&self.local);
        let before = self.local.clone();
        let sel = self.selection.clone();
        for &s in &sel {
            if sel
                .iter()
                .any(|&a| a != s && self.puppet.joints.hangs_from(s, a))
            {
                continue;
            }
            self.touch(&[s]);
            // W_s' = T(p) Q T(-p) W_s  ⇔  R_local' = R_parent⁻¹ Q R_parent R_local, the
            // parent's frame as it carries the section.
            let frame = self.puppet.joints.parent_frame(s, &world, &self.local);
            let parent = DQuat::from_mat3(&frame.matrix3);
            let l = &mut self.local[s];
            l.rotation = (parent.inverse() * rotation * parent * l.rotation).normalize();
            if !l.rotation.is_finite() {
                l.rotation = DQuat::IDENTITY;
            }
        }
        self.hold_back(&before);
        self.wake();
    }

    /// With collision on, takes the move from `before` to the pose now in `local` only as
    /// far as no part presses into another (see [`crate::joints::collide`]): a limb
    /// dragged into the body stops at it, however fast the drag.
    pub fn hold_back(&mut self, before: &[Local]) {
        self.puppet.hold_back(before, &mut self.local);
    }

    /// Every section back to rest.
    pub fn reset_pose(&mut self) {
        self.checkpoint();
        self.local.iter_mut().for_each(|l| *l = Local::default());
        self.wake();
    }

    /// World position of the point a section turns about, in the current pose (at the end
    /// of an arc band, where the bent band carries its cut's pivot).
    pub fn pivot_world(&self, section: usize) -> DVec3 {
        let world = self.puppet.joints.world(&self.local);
        let p = self.puppet.joints.sections()[section].pivot;
        let carrier = self
            .puppet
            .joints
            .pivot_carrier(section, &world, &self.local);
        carrier.transform_point3(p)
    }

    /// Sets simulation parameters from the panel (sanitized: a slider cannot break it).
    pub fn set_params(&mut self, params: Params) {
        if params != *self.puppet.sim.params() {
            self.puppet.sim.set_params(params);
            self.wake();
        }
    }

    /// Sets the base material from the panel (sanitized); the rig's preset name becomes
    /// "custom" where the material is no longer its preset's.
    pub fn set_material(&mut self, material: Material) {
        let params = Params {
            material,
            ..*self.puppet.sim.params()
        };
        self.set_params(params);
        let now = self.puppet.sim.params().material;
        if Material::preset(&self.puppet.rig_file.preset) != Some(now) {
            self.puppet.rig_file.preset = "custom".into();
        }
    }

    /// Gives the base material a preset by name (see [`crate::sim::material`] for what a
    /// preset changes: the whole material, nothing else); returns false for an unknown
    /// name, and "custom" keeps the material as it is.
    pub fn set_preset(&mut self, name: &str) -> bool {
        if name == "custom" {
            self.puppet.rig_file.preset = name.into();
            return true;
        }
        let Some(material) = Material::preset(name) else {
            return false;
        };
        self.puppet.rig_file.preset = name.into();
        self.set_params(Params {
            material,
            ..*self.puppet.sim.params()
        });
        true
    }

    /// Gives region `k` a preset by name, by the same rule as [`Session::set_preset`];
    /// returns false for an unknown name or region.
    pub fn set_region_preset(&mut self, k: usize, name: &str) -> bool {
        let mut regions = self.puppet.rig_file.regions.clone();
        let Some(region) = regions.get_mut(k) else {
            return false;
        };
        if name != "custom" {
            let Some(material) = Material::preset(name) else {
                return false;
            };
            region.material = material;
        }
        region.preset = name.into();
        let pin = self.puppet.rig_file.pin.clone();
        self.set_regions(regions, pin);
        true
    }
}

#[cfg(test)]
mod tests;
