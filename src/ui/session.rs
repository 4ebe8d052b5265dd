//! What the puppeteer works on, without any window: the puppet, its pose, the selection,
//! undo/redo, the cut being placed, and when the simulation may sleep. The window
//! (`app`) turns mouse and keys into calls here; tests call the same functions.

use crate::joints::{Cut, JointError, Local, PoseScratch};
use crate::scene::Puppet;
use crate::sim::{self, Params};
use glam::{DQuat, DVec3, Vec3};
use std::sync::atomic::{AtomicU64, Ordering};

/// How many undo steps are kept.
pub const UNDO_DEPTH: usize = 200;

/// Everything undo restores: the cuts (with pivots) and the pose.
#[derive(Clone, Debug, PartialEq)]
struct Snapshot {
    cuts: Vec<Cut>,
    root_pivot: DVec3,
    local: Vec<Local>,
}

/// A cut being placed with the cut tool.
#[derive(Clone, Debug, PartialEq)]
pub struct CutDraft {
    /// Section the cut will split (where the plane was placed).
    pub section: usize,
    /// Point on the plane (a picked surface point, then moved along the normal).
    pub point: DVec3,
    pub normal: DVec3,
    /// Pivot; `None` takes the default.
    pub pivot: Option<DVec3>,
    /// Name the new section will get.
    pub name: String,
}

/// Result of a ray cast against the current surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub triangle: usize,
    /// Vertex of the triangle nearest the hit point.
    pub vertex: usize,
    pub point: Vec3,
    pub distance: f32,
}

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// The working state of the app.
pub struct Session {
    /// Unique per session (render caches key on it).
    pub id: u64,
    pub puppet: Puppet,
    /// Mesh name shown in the title and messages.
    pub name: String,
    /// Local pose of every section.
    pub local: Vec<Local>,
    /// Selected sections.
    pub selection: Vec<usize>,
    /// The cut tool's plane, when the tool is active.
    pub draft: Option<CutDraft>,
    /// Simulation paused by the user.
    pub paused: bool,
    undo: Vec<Snapshot>,
    redo: Vec<Snapshot>,
    scratch: PoseScratch,
    /// No step needed: pose unchanged and motion died out.
    settled: bool,
    /// Bumped whenever the surface or anything drawn changes (render caches key on it).
    pub revision: u64,
    /// Bumped when sections, selection or cuts change (colours, overlays).
    pub layout_revision: u64,
}

impl Session {
    pub fn new(puppet: Puppet, name: impl Into<String>) -> Session {
        let sections = puppet.joints.sections().len();
        Session {
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            puppet,
            name: name.into(),
            local: vec![Local::default(); sections],
            selection: Vec::new(),
            draft: None,
            paused: false,
            undo: Vec::new(),
            redo: Vec::new(),
            scratch: PoseScratch::default(),
            settled: false,
            revision: 0,
            layout_revision: 0,
        }
    }

    /// True when stepping would change nothing (the app then stops stepping and drawing).
    pub fn is_idle(&self) -> bool {
        self.settled || self.paused
    }

    /// Something changed: simulate again.
    pub fn wake(&mut self) {
        self.settled = false;
        self.revision += 1;
    }

    /// Runs the simulation for `dt` seconds of wall time (at most `max_steps` fixed steps).
    /// Returns the steps taken; none when idle.
    pub fn advance(&mut self, dt: f32, max_steps: u32) -> u32 {
        if self.is_idle() {
            return 0;
        }
        let pose = self.puppet.joints.pose_into(&self.local, &mut self.scratch);
        let steps = self.puppet.sim.advance(pose, dt, max_steps);
        if steps > 0 {
            self.revision += 1;
            // Settled when the largest per-step motion is below 1e-6 of the model size
            // (invisible at any zoom that shows the whole model).
            let n = self.puppet.sim.rig().len().max(1) as f64;
            let size = self.puppet.mesh.diagonal();
            let threshold = (1e-6 * size).powi(2) * n;
            if self.puppet.sim.params().is_static() || self.puppet.sim.kinetic_energy() <= threshold
            {
                self.settled = true;
            }
        }
        steps
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot {
            cuts: self.puppet.joints.cuts().to_vec(),
            root_pivot: self.puppet.joints.sections()[0].pivot,
            local: self.local.clone(),
        }
    }

    /// Records the current state for undo; call once before a change (at the start of a
    /// drag, not on every mouse move).
    pub fn checkpoint(&mut self) {
        let s = self.snapshot();
        if self.undo.last() != Some(&s) {
            self.undo.push(s);
            if self.undo.len() > UNDO_DEPTH {
                self.undo.remove(0);
            }
        }
        self.redo.clear();
    }

    pub fn can_undo(&self) -> bool {
        self.undo.iter().any(|s| *s != self.snapshot())
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Undoes the last pose or cut change.
    pub fn undo(&mut self) {
        let current = self.snapshot();
        while let Some(s) = self.undo.pop() {
            if s != current {
                self.redo.push(current);
                self.restore(s);
                return;
            }
        }
    }

    /// Redoes what undo undid.
    pub fn redo(&mut self) {
        if let Some(s) = self.redo.pop() {
            self.undo.push(self.snapshot());
            self.restore(s);
        }
    }

    fn restore(&mut self, s: Snapshot) {
        if s.cuts != self.puppet.joints.cuts() {
            let mut spec = self.puppet.current_spec();
            spec.cuts = s.cuts.clone();
            // Replaying cuts that were valid before cannot fail; keep the current state if
            // it somehow does.
            if let Ok(mut joints) = spec.joints(&self.puppet.skeleton.points) {
                joints.set_pivot(0, s.root_pivot);
                self.puppet.joints = joints;
                self.puppet
                    .sim
                    .set_sections(self.puppet.joints.section_of().to_vec());
            }
        }
        self.local = s.local;
        self.local
            .resize(self.puppet.joints.sections().len(), Local::default());
        let count = self.local.len();
        self.selection.retain(|&x| x < count);
        self.layout_revision += 1;
        self.wake();
    }

    /// Selects `section` (or clears the selection with `None`); `additive` toggles it in a
    /// multiple selection.
    pub fn select(&mut self, section: Option<usize>, additive: bool) {
        match section {
            Some(s) if s < self.local.len() => {
                if additive {
                    if let Some(k) = self.selection.iter().position(|&x| x == s) {
                        self.selection.remove(k);
                    } else {
                        self.selection.push(s);
                    }
                } else {
                    self.selection = vec![s];
                }
            }
            _ if !additive => self.selection.clear(),
            _ => {}
        }
        self.layout_revision += 1;
        self.revision += 1;
    }

    fn is_ancestor(&self, a: usize, mut s: usize) -> bool {
        let sections = self.puppet.joints.sections();
        while let Some(p) = sections[s].parent {
            if p == a {
                return true;
            }
            s = p;
        }
        false
    }

    /// Rotates every selected section by `rotation` (world space) about its current pivot.
    /// A section whose ancestor is also selected is carried by it, not turned twice.
    pub fn rotate_selected(&mut self, rotation: DQuat) {
        if !rotation.is_finite() || self.selection.is_empty() {
            return;
        }
        let world = self.puppet.joints.world(&self.local);
        let sel = self.selection.clone();
        for &s in &sel {
            if sel.iter().any(|&a| a != s && self.is_ancestor(a, s)) {
                continue;
            }
            // W_s' = T(p) Q T(-p) W_s  ⇔  R_local' = R_parent⁻¹ Q R_parent R_local.
            let parent = match self.puppet.joints.sections()[s].parent {
                Some(p) => DQuat::from_mat3(&world[p].matrix3),
                None => DQuat::IDENTITY,
            };
            let l = &mut self.local[s];
            l.rotation = (parent.inverse() * rotation * parent * l.rotation).normalize();
            if !l.rotation.is_finite() {
                l.rotation = DQuat::IDENTITY;
            }
        }
        self.wake();
    }

    /// Every section back to rest.
    pub fn reset_pose(&mut self) {
        self.checkpoint();
        self.local.iter_mut().for_each(|l| *l = Local::default());
        self.wake();
    }

    /// World position of a section's pivot in the current pose.
    pub fn pivot_world(&self, section: usize) -> DVec3 {
        let world = self.puppet.joints.world(&self.local);
        let p = self.puppet.joints.sections()[section].pivot;
        world[section].transform_point3(p)
    }

    /// Applies the cut draft; the new section is selected. On error nothing changes.
    pub fn apply_draft(&mut self) -> Result<(), JointError> {
        let Some(d) = self.draft.clone() else {
            return Ok(());
        };
        let section = self.puppet.joints.sections()[d.section].name.clone();
        self.checkpoint();
        let before = self.puppet.joints.clone();
        let result = self.puppet.joints.add_cut(Cut {
            name: d.name.clone(),
            section,
            point: d.point,
            normal: d.normal,
            pivot: d.pivot,
        });
        match result {
            Ok(index) => {
                self.after_cut_change();
                self.selection = vec![index];
                self.draft = None;
                Ok(())
            }
            Err(e) => {
                self.puppet.joints = before;
                self.undo.pop();
                Err(e)
            }
        }
    }

    /// Removes the cut that made section `name`.
    pub fn remove_cut(&mut self, name: &str) -> Result<(), JointError> {
        let k = self.puppet.joints.find(name);
        self.checkpoint();
        if let Err(e) = self.puppet.joints.remove_cut(name) {
            self.undo.pop();
            return Err(e);
        }
        if let Some(k) = k {
            if k < self.local.len() {
                self.local.remove(k);
            }
        }
        self.after_cut_change();
        Ok(())
    }

    fn after_cut_change(&mut self) {
        let n = self.puppet.joints.sections().len();
        self.local.resize(n, Local::default());
        self.selection.retain(|&s| s < n);
        self.puppet
            .sim
            .set_sections(self.puppet.joints.section_of().to_vec());
        self.layout_revision += 1;
        self.wake();
    }

    /// A name for the next cut that no section has yet.
    pub fn fresh_section_name(&self) -> String {
        (1..)
            .map(|k| format!("section {k}"))
            .find(|n| self.puppet.joints.find(n).is_none())
            .unwrap_or_default()
    }

    /// Sets simulation parameters from the panel (sanitized: a slider cannot break it).
    pub fn set_params(&mut self, params: Params) {
        if params != *self.puppet.sim.params() {
            self.puppet.sim.set_params(params);
            self.wake();
        }
    }

    /// Applies a Table 1 preset by name; returns false for an unknown name.
    pub fn set_preset(&mut self, name: &str) -> bool {
        match sim::presets().into_iter().find(|m| m.name == name) {
            Some(m) => {
                let constraint = self.puppet.sim.params().constraint;
                let iterations = self.puppet.sim.params().reduction_iterations;
                self.puppet.spec.material = m.name;
                self.set_params(Params {
                    constraint,
                    reduction_iterations: iterations,
                    ..m.params
                });
                true
            }
            None => false,
        }
    }

    /// Casts a ray against the current (simulated) surface.
    pub fn pick(&self, origin: Vec3, dir: Vec3) -> Option<Hit> {
        let x = self.puppet.sim.positions();
        let mut best: Option<Hit> = None;
        for (t, tri) in self.puppet.mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| x.get(i as usize));
            if let Some(d) = ray_triangle(origin, dir, a, b, c) {
                if best.is_none_or(|h| d < h.distance) {
                    let p = origin + dir * d;
                    let vertex = *tri
                        .iter()
                        .min_by(|&&i, &&j| {
                            let di = (x.get(i as usize) - p).length_squared();
                            let dj = (x.get(j as usize) - p).length_squared();
                            di.total_cmp(&dj)
                        })
                        .unwrap_or(&tri[0]) as usize;
                    best = Some(Hit {
                        triangle: t,
                        vertex,
                        point: p,
                        distance: d,
                    });
                }
            }
        }
        best
    }

    /// Section of the vertex a hit landed nearest to.
    pub fn section_at(&self, hit: &Hit) -> usize {
        self.puppet.joints.section_of()[hit.vertex] as usize
    }
}

/// Distance along the unit `d` from `o` to the triangle, if hit in front.
fn ray_triangle(o: Vec3, d: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    let tri = [a.as_dvec3(), b.as_dvec3(), c.as_dvec3()];
    let t = crate::geom::bvh::intersect(&tri, o.as_dvec3(), d.as_dvec3())?;
    (t > 0.0).then_some(t as f32)
}

#[cfg(test)]
mod tests;
