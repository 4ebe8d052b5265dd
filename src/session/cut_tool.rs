//! The cut tool: a plane placed on the model, moved and turned, then applied as a cut; and
//! removing cuts again.

use super::Session;
use crate::joints::{Cut, JointError, Local};
use glam::DVec3;

/// How a new cut plane is oriented.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CutAxis {
    /// Normal along +x.
    X,
    /// Normal along +y.
    #[default]
    Y,
    /// Normal along +z.
    Z,
    /// Perpendicular to the screen's horizontal: the plane is seen edge-on as a vertical line.
    View,
}

impl CutAxis {
    /// The unit normal of a new plane, given the camera's right vector.
    pub fn normal(self, camera_right: DVec3) -> DVec3 {
        match self {
            CutAxis::X => DVec3::X,
            CutAxis::Y => DVec3::Y,
            CutAxis::Z => DVec3::Z,
            CutAxis::View => camera_right.normalize_or(DVec3::X),
        }
    }
}

/// The cut tool's settings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CutTool {
    /// The tool is on: the next press on the model places the plane.
    pub active: bool,
    /// How a new plane is oriented.
    pub axis: CutAxis,
}

/// A cut being placed with the cut tool.
#[derive(Clone, Debug, PartialEq)]
pub struct CutDraft {
    /// Section the cut will split (where the plane was placed).
    pub section: usize,
    /// Point on the plane (a picked surface point, then moved along the normal).
    pub point: DVec3,
    /// Plane normal, pointing into the new section.
    pub normal: DVec3,
    /// Pivot; `None` takes the default.
    pub pivot: Option<DVec3>,
    /// Only the piece connected to the point (the limb picked, not every limb beyond the
    /// plane).
    pub connected: bool,
    /// Name the new section will get.
    pub name: String,
}

impl Session {
    /// Places the cut tool's plane through `point` on `section`, oriented by `normal`.
    pub fn place_draft(&mut self, section: usize, point: DVec3, normal: DVec3) {
        self.draft = Some(CutDraft {
            section,
            point,
            normal,
            pivot: None,
            connected: true,
            name: self.fresh_section_name(),
        });
        self.revision += 1;
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
            connected: d.connected,
            band: None,
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
                self.drop_checkpoint();
                Err(e)
            }
        }
    }

    /// Sets the joint band of cut `name` (half-width in local medial radii; 0 a hinge).
    /// `checkpoint`: record it for undo (once per drag of the slider).
    pub fn set_band(&mut self, name: &str, band: f64, checkpoint: bool) {
        if checkpoint {
            self.checkpoint();
        }
        if self.puppet.joints.set_band(name, Some(band)) {
            self.puppet.sync_sections();
            self.layout_revision += 1;
            self.wake();
        }
    }

    /// Removes the cut that made section `name`.
    pub fn remove_cut(&mut self, name: &str) -> Result<(), JointError> {
        let k = self.puppet.joints.find(name);
        self.checkpoint();
        if let Err(e) = self.puppet.joints.remove_cut(name) {
            self.drop_checkpoint();
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
        self.puppet.sync_sections();
        self.layout_revision += 1;
        self.wake();
    }

    /// Replaces the cuts with the joints the skeleton suggests (undoable); returns how
    /// many. On error nothing changes.
    pub fn suggest_joints(&mut self) -> Result<usize, JointError> {
        self.checkpoint();
        match self.puppet.suggest_joints() {
            Ok(n) => {
                self.local.clear();
                self.selection.clear();
                self.after_cut_change();
                Ok(n)
            }
            Err(e) => {
                self.drop_checkpoint();
                Err(e)
            }
        }
    }

    /// A name for the next cut that no section has yet.
    pub fn fresh_section_name(&self) -> String {
        (1..)
            .map(|k| format!("section {k}"))
            .find(|n| self.puppet.joints.find(n).is_none())
            .unwrap_or_default()
    }
}
