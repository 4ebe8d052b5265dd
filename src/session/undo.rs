//! Undo and redo: snapshots of everything a puppeteer changes by hand (the cuts with their
//! pivots, the pose, the regions and pinning), taken once before each change.

use super::paint_tool::RegionsState;
use super::Session;
use crate::joints::{Cut, Local};
use glam::DVec3;

/// How many undo steps are kept.
pub const UNDO_DEPTH: usize = 200;

/// Everything undo restores: the cuts (with pivots), the pose, and the material regions
/// and pinning.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Snapshot {
    cuts: Vec<Cut>,
    root_pivot: DVec3,
    local: Vec<Local>,
    regions: RegionsState,
}

/// The undo and redo stacks.
#[derive(Clone, Debug, Default)]
pub(super) struct History {
    undo: Vec<Snapshot>,
    redo: Vec<Snapshot>,
}

impl Session {
    fn snapshot(&self) -> Snapshot {
        Snapshot {
            cuts: self.puppet.joints.cuts().to_vec(),
            root_pivot: self.puppet.joints.sections()[0].pivot,
            local: self.local.clone(),
            regions: self.regions_state.clone(),
        }
    }

    /// Records the current state for undo; call once before a change (at the start of a
    /// drag, not on every mouse move).
    pub fn checkpoint(&mut self) {
        let s = self.snapshot();
        if self.undo.undo.last() != Some(&s) {
            self.undo.undo.push(s);
            if self.undo.undo.len() > UNDO_DEPTH {
                self.undo.undo.remove(0);
            }
        }
        self.undo.redo.clear();
    }

    /// Forgets the last checkpoint (a change that was refused).
    pub(super) fn drop_checkpoint(&mut self) {
        self.undo.undo.pop();
    }

    /// True when undo would change something.
    pub fn can_undo(&self) -> bool {
        let now = self.snapshot();
        self.undo.undo.iter().any(|s| *s != now)
    }

    /// True when there is something to redo.
    pub fn can_redo(&self) -> bool {
        !self.undo.redo.is_empty()
    }

    /// Undoes the last pose or cut change.
    pub fn undo(&mut self) {
        let current = self.snapshot();
        while let Some(s) = self.undo.undo.pop() {
            if s != current {
                self.undo.redo.push(current);
                self.restore(s);
                return;
            }
        }
    }

    /// Redoes what undo undid.
    pub fn redo(&mut self) {
        if let Some(s) = self.undo.redo.pop() {
            let now = self.snapshot();
            self.undo.undo.push(now);
            self.restore(s);
        }
    }

    fn restore(&mut self, s: Snapshot) {
        if s.cuts != self.puppet.joints.cuts() {
            let mut rig_file = self.puppet.current_rig_file();
            rig_file.cuts = s.cuts.clone();
            // Replaying cuts that were valid before cannot fail; keep the current state if
            // it somehow does.
            if let Ok(mut joints) = rig_file.joints(self.puppet.joints.clone()) {
                joints.set_pivot(0, s.root_pivot);
                self.puppet.joints = joints;
                self.puppet.sync_sections();
            }
        }
        if s.regions != self.regions_state {
            let (regions, pin) = (*s.regions.data).clone();
            self.regions_state = s.regions;
            self.apply_regions(regions, pin);
        }
        self.local = s.local;
        self.local
            .resize(self.puppet.joints.sections().len(), Local::default());
        let count = self.local.len();
        self.selection.retain(|&x| x < count);
        self.layout_revision += 1;
        self.wake();
    }
}
