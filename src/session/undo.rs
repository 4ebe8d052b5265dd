//! Undo and redo: snapshots of everything a puppeteer changes by hand (the cuts with their
//! pivots, the pose, the regions and pinning, the animation a take or a file replaced),
//! taken once before each change.

use super::paint_tool::RegionsState;
use super::Session;
use crate::anim::Animation;
use crate::joints::{Cut, Local};
use std::sync::Arc;

/// The animation loaded, shared (a snapshot costs a pointer; two are the same animation
/// when they share it).
#[derive(Clone, Debug, Default)]
pub(super) struct AnimationState(Option<Arc<Animation>>);

impl PartialEq for AnimationState {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        }
    }
}

/// How many undo steps are kept.
pub const UNDO_DEPTH: usize = 200;

/// Everything undo restores: the cuts (with pivots), the pose, and the material regions
/// and pinning.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Snapshot {
    cuts: Vec<Cut>,
    local: Vec<Local>,
    regions: RegionsState,
    animation: AnimationState,
}

/// The undo and redo stacks.
#[derive(Clone, Debug, Default)]
pub(super) struct History {
    undo: Vec<Snapshot>,
    redo: Vec<Snapshot>,
}

impl Session {
    fn animation_state(&self) -> AnimationState {
        AnimationState(self.playback.as_ref().map(|p| p.animation.clone()))
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot {
            cuts: self.puppet.joints.cuts().to_vec(),
            local: self.local.clone(),
            regions: self.regions_state.clone(),
            animation: self.animation_state(),
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

    /// Forgets every undo and redo step: what is there now is where the puppeteer starts
    /// (a puppet just opened, its suggested joints included).
    pub fn clear_history(&mut self) {
        self.undo = History::default();
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
            if let Ok(joints) = rig_file.joints(self.puppet.joints.clone()) {
                self.puppet.joints = joints;
                self.puppet.sync_sections();
            }
        }
        if s.regions != self.regions_state {
            let (regions, pin) = (*s.regions.data).clone();
            self.regions_state = s.regions;
            self.apply_regions(regions, pin);
        }
        if s.animation != self.animation_state() {
            match s.animation.0 {
                // It played on these sections before; keep what plays if it somehow cannot.
                Some(a) => {
                    let _ = self.set_shared_animation(a);
                }
                None => self.playback = None,
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
}
