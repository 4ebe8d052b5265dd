//! The cut tool: a plane, a sphere or a box placed on the model, moved, turned and sized,
//! then applied as a cut; an applied cut's pivot moved and shared; removing cuts again.

use super::{Camera, Session};
use crate::joints::{Cut, JointError, Local, Shape};
use glam::{DVec3, Vec2};

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
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CutTool {
    /// The tool is on: the next press on the model places the plane.
    pub active: bool,
    /// How a new plane is oriented.
    pub axis: CutAxis,
    /// The shape a new cut takes (a sphere's or a box's size is a tenth of the model's
    /// diagonal until changed).
    pub shape: ShapeKind,
    /// Moving pivots: the cuts' pivots are drawn and a drag from one moves it.
    pub move_pivots: bool,
}

/// Which shape the cut tool places.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShapeKind {
    /// A plane (a limb).
    #[default]
    Plane,
    /// A sphere (a tail tip, an ear, a nose).
    Sphere,
    /// A box.
    Box,
}

impl ShapeKind {
    /// The shape of this kind for a model of diagonal `size`.
    pub fn shape(self, size: f64) -> Shape {
        match self {
            ShapeKind::Plane => Shape::Plane,
            ShapeKind::Sphere => Shape::Sphere { radius: 0.1 * size },
            ShapeKind::Box => Shape::Box {
                size: DVec3::splat(0.2 * size),
            },
        }
    }
}

/// A cut being placed with the cut tool.
#[derive(Clone, Debug, PartialEq)]
pub struct CutDraft {
    /// Section the cut will split (where the plane was placed).
    pub section: usize,
    /// Plane, sphere or box.
    pub shape: Shape,
    /// Point on the plane, or the centre (a picked surface point, then moved).
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

impl CutDraft {
    /// The cut this draft makes of the section named `section`.
    pub fn cut(&self, section: String) -> Cut {
        Cut {
            name: self.name.clone(),
            section,
            shape: self.shape,
            point: self.point,
            normal: self.normal,
            pivot: self.pivot,
            connected: self.connected,
            band: None,
            shared_pivot: false,
        }
        .rounded()
    }
}

impl Session {
    /// Turns the cut tool on or off. On, the brush goes off (one tool at a time); off,
    /// a draft not applied goes away.
    pub fn set_cut_tool(&mut self, on: bool) {
        self.cut_tool.active = on;
        if on {
            self.paint_tool.active = false;
        } else {
            self.draft = None;
        }
        self.revision += 1;
    }

    /// Shows the cuts' pivots for dragging, or hides them.
    pub fn set_move_pivots(&mut self, on: bool) {
        self.cut_tool.move_pivots = on;
        self.revision += 1;
    }

    /// Orients new cut planes along `axis`; a draft on the model turns to it (`View` keeps
    /// the draft's normal: the view's right is the window's to know).
    pub fn set_cut_axis(&mut self, axis: CutAxis) {
        self.cut_tool.axis = axis;
        if let Some(d) = &mut self.draft {
            if axis != CutAxis::View {
                d.normal = axis.normal(d.normal);
            }
        }
        self.revision += 1;
    }

    /// Makes new cuts `kind`; a draft on the model takes the shape, at a tenth of the
    /// model's diagonal.
    pub fn set_cut_shape(&mut self, kind: ShapeKind) {
        self.cut_tool.shape = kind;
        let size = self.puppet.mesh.diagonal();
        if let Some(d) = &mut self.draft {
            d.shape = kind.shape(size);
        }
        self.revision += 1;
    }

    /// Drops the draft and turns the cut tool off.
    pub fn cancel_draft(&mut self) {
        self.set_cut_tool(false);
    }

    /// What Escape does: every tool off, the draft dropped, nothing selected.
    pub fn escape(&mut self) {
        self.set_cut_tool(false);
        self.paint_tool.active = false;
        self.select(None, false);
    }

    /// Places the cut tool's shape at `point` on `section`, oriented by `normal`.
    pub fn place_draft(&mut self, section: usize, point: DVec3, normal: DVec3) {
        self.draft = Some(CutDraft {
            section,
            shape: self.cut_tool.shape.shape(self.puppet.mesh.diagonal()),
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
        let result = self.puppet.joints.add_cut(d.cut(section));
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

    /// Moves the pivot of the cut that made `section` to where the ray from `origin` along
    /// `dir` (world space) meets the plane it may move in: the cut's plane through the
    /// pivot (a sphere's or a box's tangent plane there), or with `free` the plane through
    /// it facing the ray. Posed, the pivot moves in its parent's frame, where the cut is.
    /// Call [`Session::checkpoint`] once before a drag; a ray that misses changes nothing.
    pub fn drag_pivot(&mut self, section: usize, origin: DVec3, dir: DVec3, free: bool) {
        let joints = &self.puppet.joints;
        let Some(cut) = section
            .checked_sub(1)
            .and_then(|k| joints.cuts().get(k))
            .filter(|_| {
                joints
                    .sections()
                    .get(section)
                    .is_some_and(|s| s.parent.is_some())
            })
        else {
            return;
        };
        let Some(pivot) = cut.pivot else {
            return;
        };
        let world = joints.world(&self.local);
        let carrier = joints.cut_carrier(section, &world, &self.local);
        let frame = carrier.unwrap_or_else(|| joints.parent_frame(section, &world, &self.local));
        let to_rest = frame.inverse();
        let (o, d) = (
            to_rest.transform_point3(origin),
            to_rest.transform_vector3(dir),
        );
        let normal = if free {
            d.normalize_or_zero()
        } else {
            cut.normal_near(pivot)
        };
        let along = d.dot(normal);
        if along.abs() < 1e-9 * d.length() || !along.is_finite() {
            return;
        }
        let t = (pivot - o).dot(normal) / along;
        let moved = crate::files::shortest3(o + d * t);
        if t > 0.0 && moved.is_finite() && moved != pivot {
            self.puppet.joints.set_pivot(section, moved);
            self.puppet.sync_sections();
            self.layout_revision += 1;
            self.wake();
        }
    }

    /// Each cut's section and the pixel its pivot is drawn at, as posed (cuts whose pivot
    /// is behind the camera left out).
    pub fn pivots_on_screen(&self, camera: &Camera, viewport: Vec2) -> Vec<(usize, Vec2)> {
        let joints = &self.puppet.joints;
        let world = joints.world(&self.local);
        (1..joints.sections().len())
            .filter_map(|section| {
                let pivot = joints.cuts()[section - 1].pivot?;
                let at = joints
                    .pivot_carrier(section, &world, &self.local)
                    .transform_point3(pivot)
                    .as_vec3();
                Some((section, camera.project(at, viewport)?))
            })
            .collect()
    }

    /// The section whose cut's pivot is drawn within [`super::pointer::PIVOT_REACH`]
    /// pixels of `cursor` (the nearest), if any.
    pub fn pivot_near(&self, cursor: Vec2, camera: &Camera, viewport: Vec2) -> Option<usize> {
        self.pivots_on_screen(camera, viewport)
            .into_iter()
            .map(|(k, at)| (k, at.distance(cursor)))
            .filter(|&(_, d)| d <= super::pointer::PIVOT_REACH)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    }

    /// Lets the section that cut `name` splits turn about that cut's pivot too (`shared`),
    /// or about its own again (undoable; see [`crate::joints`]).
    pub fn set_shared_pivot(&mut self, name: &str, shared: bool) {
        self.checkpoint();
        if self.puppet.joints.set_shared_pivot(name, shared) {
            self.layout_revision += 1;
            self.wake();
        } else {
            self.drop_checkpoint();
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
