//! Joints (paper §3.4): cutting the skeleton with planes into sections, the pivot of each
//! cut, and how the rotations of a pose compose down the section tree.
//!
//! # Sections and cuts
//! Section 0, the *root*, is the whole object. A [`Cut`] is a plane (point + unit normal)
//! applied to one existing section: every vertex of that section whose **skeletal point**
//! `sp_i` lies strictly on the side the normal points to moves to a new section named after
//! the cut; the rest stay. Cutting by skeletal points rather than surface positions keeps
//! thin features whole (the surface of a bent arm can cross the plane where its medial axis
//! does not). The cuts form a binary tree: each cut splits one section in two.
//!
//! # The joint hierarchy and how rotations compose
//! The new section is the *child* of the section it was cut from, hinged at the cut's
//! **pivot** (by default the centroid of the skeletal points of the cut section nearest the
//! plane, projected onto the plane; editable). When a later cut splits a section that
//! already has children, a child whose pivot lies on the new side is handed to the new
//! section: cutting the shoulder after the elbow makes the forearm a child of the upper arm.
//!
//! A pose gives every section a local [`Local`] rotation about its own pivot (plus an
//! optional translation, used for the root). World transforms compose from the root down:
//!
//! `W(s) = W(parent(s)) · T(pivot_s + t_s) · R_s · T(−pivot_s)`
//!
//! so rotating the upper arm carries the forearm and the hand with it, and the forearm's own
//! rotation is about its elbow *as carried by the upper arm*. Every section can be posed at
//! once (both jaws of a mouth).
//!
//! # Removing cuts
//! Removing a cut merges its section back into the section it was cut from; its children
//! and the cuts applied to it move to that section. The assignment is replayed from the
//! remaining cuts (O(vertices × cuts)); the skeleton is never recomputed.

use crate::sim::Pose;
use glam::{Affine3A, DAffine3, DQuat, DVec3};

/// Most sections a rig may have (the simulation stores a `u16` section per vertex).
pub const MAX_SECTIONS: usize = 4096;

/// Name of the root section unless a rig file says otherwise.
pub const ROOT: &str = "root";

/// A cut as written by a user or a file: which section it splits, the plane, the pivot.
#[derive(Clone, Debug, PartialEq)]
pub struct Cut {
    /// Name of the new section (the side the normal points to).
    pub name: String,
    /// Name of the section this cut splits.
    pub section: String,
    /// A point on the plane.
    pub point: DVec3,
    /// Plane normal, pointing into the new section (any non-zero length).
    pub normal: DVec3,
    /// Rotation point; `None` takes the default (see module docs).
    pub pivot: Option<DVec3>,
}

/// A section: a node of the joint hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// Its name (the cut's, or the root's).
    pub name: String,
    /// Parent section (`None` for the root).
    pub parent: Option<usize>,
    /// Rotation point (for the root, the centroid of all skeletal points).
    pub pivot: DVec3,
    /// Number of vertices in this section.
    pub vertices: usize,
}

/// A section's pose relative to its parent: a rotation about its pivot, then a translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Local {
    /// Rotation about the section's pivot.
    pub rotation: DQuat,
    /// Translation after the rotation.
    pub translation: DVec3,
}

impl Default for Local {
    fn default() -> Self {
        Local {
            rotation: DQuat::IDENTITY,
            translation: DVec3::ZERO,
        }
    }
}

impl Local {
    /// A rotation of `degrees` about `axis` (no translation). A zero or non-finite axis
    /// gives the identity.
    pub fn axis_angle(axis: DVec3, degrees: f64) -> Local {
        let axis = axis.normalize_or_zero();
        if axis == DVec3::ZERO || !degrees.is_finite() {
            return Local::default();
        }
        Local {
            rotation: DQuat::from_axis_angle(axis, degrees.to_radians()),
            translation: DVec3::ZERO,
        }
    }
}

/// Why a cut or a removal was refused. Nothing changes when one is returned.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum JointError {
    /// The cut names a section that does not exist.
    #[error("cut '{cut}': unknown section '{section}' (known: {known})")]
    UnknownSection {
        /// The cut.
        cut: String,
        /// The section it names.
        section: String,
        /// The sections there are, comma-separated.
        known: String,
    },
    /// The cut's name is empty.
    #[error("cut '{0}': the name is empty")]
    EmptyName(String),
    /// A section of that name exists.
    #[error("cut '{0}': a section with this name already exists")]
    DuplicateName(String),
    /// A point, normal or pivot with a NaN or infinite coordinate.
    #[error("cut '{cut}': {what} is not a finite vector")]
    NotFinite {
        /// The cut.
        cut: String,
        /// Which vector.
        what: &'static str,
    },
    /// The plane normal has zero length.
    #[error("cut '{0}': the plane normal is zero")]
    ZeroNormal(String),
    /// The plane leaves one side of the section without a skeletal point.
    #[error("cut '{cut}': leaves {side} of section '{section}' empty (no skeletal point on that side of the plane)")]
    EmptySide {
        /// The cut.
        cut: String,
        /// The section it cuts.
        section: String,
        /// Which side is empty.
        side: &'static str,
    },
    /// More than [`MAX_SECTIONS`] sections.
    #[error("too many sections (at most {MAX_SECTIONS})")]
    TooMany,
    /// No cut of that name to remove.
    #[error("no cut named '{0}'")]
    NoSuchCut(String),
}

/// The joints of one puppet: cuts, the sections they make and each vertex's section.
#[derive(Clone, Debug, PartialEq)]
pub struct Joints {
    /// Skeletal point of each vertex.
    points: Vec<DVec3>,
    /// Cuts in the order applied, with resolved pivots.
    cuts: Vec<Cut>,
    sections: Vec<Section>,
    section_of: Vec<u16>,
    /// Sections parents-first (for composing transforms).
    order: Vec<usize>,
}

impl Joints {
    /// One root section named `root` holding every vertex; `skeleton_points` are the
    /// skeletal points `sp_i`.
    pub fn new(skeleton_points: &[DVec3], root: &str) -> Joints {
        let n = skeleton_points.len().max(1) as f64;
        let centroid = skeleton_points.iter().copied().sum::<DVec3>() / n;
        Joints {
            points: skeleton_points.to_vec(),
            cuts: Vec::new(),
            sections: vec![Section {
                name: root.to_string(),
                parent: None,
                pivot: centroid,
                vertices: skeleton_points.len(),
            }],
            section_of: vec![0; skeleton_points.len()],
            order: vec![0],
        }
    }

    /// The sections; index 0 is the root.
    pub fn sections(&self) -> &[Section] {
        &self.sections
    }

    /// The cuts in the order applied, with their pivots resolved.
    pub fn cuts(&self) -> &[Cut] {
        &self.cuts
    }

    /// Section index of each vertex.
    pub fn section_of(&self) -> &[u16] {
        &self.section_of
    }

    /// Index of the section named `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.sections.iter().position(|s| s.name == name)
    }

    /// Applies a cut; returns the new section's index. On error nothing changes.
    pub fn add_cut(&mut self, cut: Cut) -> Result<usize, JointError> {
        let name = cut.name.clone();
        if name.trim().is_empty() {
            return Err(JointError::EmptyName(name));
        }
        if self.find(&name).is_some() {
            return Err(JointError::DuplicateName(name));
        }
        if self.sections.len() >= MAX_SECTIONS {
            return Err(JointError::TooMany);
        }
        let parent = self
            .find(&cut.section)
            .ok_or_else(|| JointError::UnknownSection {
                cut: name.clone(),
                section: cut.section.clone(),
                known: self
                    .sections
                    .iter()
                    .map(|s| s.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })?;
        for (what, v) in [
            ("point", Some(cut.point)),
            ("normal", Some(cut.normal)),
            ("pivot", cut.pivot),
        ] {
            if v.is_some_and(|v| !v.is_finite()) {
                return Err(JointError::NotFinite {
                    cut: name.clone(),
                    what,
                });
            }
        }
        let normal = cut.normal.normalize_or_zero();
        if normal == DVec3::ZERO || !normal.is_finite() {
            return Err(JointError::ZeroNormal(name));
        }
        let side = |p: DVec3| (p - cut.point).dot(normal);
        let (mut inside, mut outside) = (0usize, 0usize);
        for (i, &s) in self.section_of.iter().enumerate() {
            if s as usize == parent {
                if side(self.points[i]) > 0.0 {
                    inside += 1;
                } else {
                    outside += 1;
                }
            }
        }
        for (count, side) in [
            (inside, "the side the normal points to"),
            (outside, "the other side"),
        ] {
            if count == 0 {
                return Err(JointError::EmptySide {
                    cut: name,
                    section: cut.section.clone(),
                    side,
                });
            }
        }
        let pivot = match cut.pivot {
            Some(p) => p,
            None => self.default_pivot(parent, cut.point, normal),
        };
        let index = self.sections.len();
        for (i, s) in self.section_of.iter_mut().enumerate() {
            if *s as usize == parent && side(self.points[i]) > 0.0 {
                *s = index as u16;
            }
        }
        // Children of the split section whose pivot is on the new side follow it.
        for s in &mut self.sections {
            if s.parent == Some(parent) && side(s.pivot) > 0.0 {
                s.parent = Some(index);
            }
        }
        self.sections[parent].vertices = outside;
        self.sections.push(Section {
            name,
            parent: Some(parent),
            pivot,
            vertices: inside,
        });
        self.cuts.push(Cut {
            pivot: Some(pivot),
            ..cut
        });
        self.order = parents_first(&self.sections);
        Ok(index)
    }

    /// Removes the cut that made section `name`: the section merges back into the one it was
    /// cut from, and cuts that split it now split that one. The skeleton is not touched. On
    /// error (the replay of the remaining cuts fails) nothing changes.
    pub fn remove_cut(&mut self, name: &str) -> Result<(), JointError> {
        let k = self
            .cuts
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| JointError::NoSuchCut(name.to_string()))?;
        let mut cuts = self.cuts.clone();
        let removed = cuts.remove(k);
        for c in &mut cuts {
            if c.section == removed.name {
                c.section = removed.section.clone();
            }
        }
        let mut rebuilt = Joints::new(&self.points, &self.sections[0].name);
        rebuilt.sections[0].pivot = self.sections[0].pivot;
        for c in cuts {
            rebuilt.add_cut(c)?;
        }
        *self = rebuilt;
        Ok(())
    }

    /// Moves the pivot of section `index` (for the root too).
    pub fn set_pivot(&mut self, index: usize, pivot: DVec3) {
        if !pivot.is_finite() || index >= self.sections.len() {
            return;
        }
        self.sections[index].pivot = pivot;
        if index > 0 {
            self.cuts[index - 1].pivot = Some(pivot);
        }
    }

    /// The pivot a cut gets by default: the centroid of the skeletal points of `section`
    /// nearest the plane (the `max(4, √m)` nearest of its `m` points), projected onto the
    /// plane.
    fn default_pivot(&self, section: usize, point: DVec3, normal: DVec3) -> DVec3 {
        let mut near: Vec<(f64, DVec3)> = self
            .section_of
            .iter()
            .zip(&self.points)
            .filter(|(s, _)| **s as usize == section)
            .map(|(_, p)| ((*p - point).dot(normal).abs(), *p))
            .collect();
        let k = ((near.len() as f64).sqrt().ceil() as usize)
            .max(4)
            .min(near.len());
        if k == 0 {
            return point;
        }
        near.select_nth_unstable_by(k - 1, |a, b| a.0.total_cmp(&b.0));
        let centroid = near[..k].iter().map(|(_, p)| *p).sum::<DVec3>() / k as f64;
        centroid - normal * (centroid - point).dot(normal)
    }

    /// World transform of every section for the given local poses (one per section; missing
    /// entries are at rest), composed from the root down (see module docs).
    pub fn world(&self, local: &[Local]) -> Vec<DAffine3> {
        let mut world = Vec::new();
        self.world_into(local, &mut world);
        world
    }

    /// [`Joints::world`] into existing storage.
    pub fn world_into(&self, local: &[Local], world: &mut Vec<DAffine3>) {
        world.clear();
        world.resize(self.sections.len(), DAffine3::IDENTITY);
        for &s in &self.order {
            let l = local.get(s).copied().unwrap_or_default();
            let pivot = self.sections[s].pivot;
            let own = DAffine3::from_translation(pivot + l.translation)
                * DAffine3::from_quat(l.rotation)
                * DAffine3::from_translation(-pivot);
            world[s] = match self.sections[s].parent {
                Some(p) => world[p] * own,
                None => own,
            };
        }
    }

    /// The simulation's pose (single precision) for the given local poses.
    pub fn pose(&self, local: &[Local]) -> Pose {
        let mut scratch = PoseScratch::default();
        self.pose_into(local, &mut scratch);
        scratch.pose
    }

    /// [`Joints::pose`] reusing `scratch` (nothing allocated once it has grown).
    pub fn pose_into<'a>(&self, local: &[Local], scratch: &'a mut PoseScratch) -> &'a Pose {
        self.world_into(local, &mut scratch.world);
        scratch.pose.transforms.clear();
        scratch
            .pose
            .transforms
            .extend(scratch.world.iter().map(to_f32));
        &scratch.pose
    }
}

/// Storage for [`Joints::pose_into`].
#[derive(Clone, Debug)]
pub struct PoseScratch {
    world: Vec<DAffine3>,
    pose: Pose,
}

impl Default for PoseScratch {
    fn default() -> Self {
        PoseScratch {
            world: Vec::new(),
            pose: Pose::rest(1),
        }
    }
}

/// An f64 affine transform in f32.
pub fn to_f32(t: &DAffine3) -> Affine3A {
    Affine3A::from_cols_array(&t.to_cols_array().map(|v| v as f32))
}

/// Section indices ordered so every parent precedes its children.
fn parents_first(sections: &[Section]) -> Vec<usize> {
    let mut children = vec![Vec::new(); sections.len()];
    let mut roots = Vec::new();
    for (i, s) in sections.iter().enumerate() {
        match s.parent {
            Some(p) => children[p].push(i),
            None => roots.push(i),
        }
    }
    let mut order = Vec::with_capacity(sections.len());
    let mut stack = roots;
    while let Some(s) = stack.pop() {
        order.push(s);
        stack.extend(children[s].iter().rev());
    }
    order
}

#[cfg(test)]
mod tests;
