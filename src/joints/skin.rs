//! Joints from the skeleton a mesh file came with ([`crate::mesh::Skin`]): a section per
//! joint that is the largest weight of some vertex, hinged at the joint's rest place, with
//! the file's hierarchy and names. A joint that is no vertex's largest weight merges into
//! the nearest joint above it that is.
//!
//! # Mixes: the file's weights instead of bands
//! Skin cuts have no joint band. A vertex whose weights spread over several sections moves
//! with their transforms blended by its weights: a [`Mix`]. Weights are rounded to 1/64, so
//! vertices with the same sections and weights share one transform. The blend is of dual
//! quaternions ([`blend_rigid`]), not of matrices as the file's own linear blend skinning
//! is: a vertex's bone points must keep their spacing (the simulation's springs and
//! constraints hang on them), and a matrix blend shrinks where the sections turn apart (the
//! stress test found vertices whose constraint could not be met).

use super::{Cut, Joints, Shape};
use crate::mesh::Skin;
use glam::{DAffine3, DQuat, DVec3};
use std::collections::HashMap;

/// The rigid motions `parts` (each with its weight) blended as dual quaternions: rigid
/// whatever the weights (the identity when they sum to nothing).
pub fn blend_rigid<'a>(parts: impl Iterator<Item = (&'a DAffine3, f64)>) -> DAffine3 {
    let (mut real, mut dual) = (
        DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
        DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
    );
    let mut first: Option<DQuat> = None;
    for (m, w) in parts {
        let r = DQuat::from_mat3(&m.matrix3).normalize();
        // The same turn both ways round: on the side of the first.
        let pivot = *first.get_or_insert(r);
        let w = if r.dot(pivot) < 0.0 { -w } else { w };
        let t = m.translation;
        let d = DQuat::from_xyzw(t.x, t.y, t.z, 0.0) * r * 0.5;
        real += r * w;
        dual += d * w;
    }
    let norm = real.length();
    if norm.is_nan() || norm <= 1e-12 {
        return DAffine3::IDENTITY;
    }
    let (real, dual) = (real * (1.0 / norm), dual * (1.0 / norm));
    let t = dual * real.conjugate() * 2.0;
    DAffine3::from_rotation_translation(real, DVec3::new(t.x, t.y, t.z))
}

/// Steps a mix's weights are rounded to.
const MIX_STEPS: f32 = 64.0;

/// A blend of up to four sections' transforms by weight (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mix {
    /// (section, weight), the weights summing to 1; `count` of them are used.
    pub parts: [(u16, f32); 4],
    /// How many of `parts` are used.
    pub count: u8,
}

impl Joints {
    /// Gives every vertex whose skin weights spread over several sections a mix's
    /// transform, numbered from `next`; returns the next free transform. Nothing without
    /// a skin cut, or when the mixes would not fit under `max` transforms.
    pub(super) fn refresh_mixes(&mut self, next: usize, max: usize) -> usize {
        self.changing();
        self.mixes.clear();
        let Some(skin) = self.body.skin.clone() else {
            return next;
        };
        if !self.cuts.iter().any(|c| c.shape == Shape::Skin) {
            return next;
        }
        // Each joint's section: its own, or that of the nearest joint above it with one.
        let section_of_joint: Vec<Option<u16>> = (0..skin.joints.len())
            .map(|j| {
                let mut at = Some(j);
                for _ in 0..=skin.joints.len() {
                    let a = at?;
                    if let Some(s) = self.find(&skin.joints[a].name) {
                        return Some(s as u16);
                    }
                    at = skin.joints[a].parent;
                }
                None
            })
            .collect();
        let mut index: HashMap<[(u16, u16); 4], usize> = HashMap::new();
        let mut mixes = Vec::new();
        let mut assigned = Vec::new();
        for (v, weights) in skin.weights.iter().enumerate() {
            if self.body.is_rider(v) {
                continue;
            }
            // The weights by section, rounded.
            let mut parts: Vec<(u16, u16)> = Vec::with_capacity(4);
            for &(j, w) in weights {
                let Some(&Some(s)) = section_of_joint.get(j as usize) else {
                    continue;
                };
                let q = (w * MIX_STEPS).round() as u16;
                match parts.iter_mut().find(|p| p.0 == s) {
                    Some(p) => p.1 += q,
                    None => parts.push((s, q)),
                }
            }
            parts.retain(|p| p.1 > 0);
            let own = self.section_of[v];
            if parts.len() < 2 || !parts.iter().any(|p| p.0 == own) {
                continue;
            }
            parts.sort_unstable();
            let mut key = [(u16::MAX, 0u16); 4];
            key[..parts.len()].copy_from_slice(&parts);
            let k = *index.entry(key).or_insert_with(|| {
                let total: u16 = parts.iter().map(|p| p.1).sum();
                let mut mix = Mix {
                    parts: [(0, 0.0); 4],
                    count: parts.len() as u8,
                };
                for (slot, p) in mix.parts.iter_mut().zip(&parts) {
                    *slot = (p.0, p.1 as f32 / total as f32);
                }
                mixes.push(mix);
                mixes.len() - 1
            });
            assigned.push((v, k));
        }
        if next + mixes.len() > max {
            return next;
        }
        for (v, k) in assigned {
            self.transform_of[v] = (next + k) as u16;
        }
        let end = next + mixes.len();
        self.mixes = mixes;
        end
    }

    /// The joints of the skin the joints were given ([`joints`]), riders not counted.
    pub fn skin_joints(&self) -> Option<SkinJoints> {
        joints(self.body.skin.as_ref()?, |v| !self.body.is_rider(v))
    }

    /// The mixes (see the module docs), their transforms numbered after every other but
    /// the riders' twins.
    pub fn mixes(&self) -> &[Mix] {
        &self.mixes
    }
}

/// The joints a skin gives: the root section's name (the topmost joint that holds
/// vertices) and a skin cut per other joint that holds vertices, parents first.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinJoints {
    /// The root section's name.
    pub root: String,
    /// The cuts, parents first.
    pub cuts: Vec<Cut>,
}

/// The joints of `skin`; `None` when no joint holds a vertex. Only vertices for which
/// `counts` is true are held (riders, which go with their host, are not).
pub fn joints(skin: &Skin, counts: impl Fn(usize) -> bool) -> Option<SkinJoints> {
    let n = skin.joints.len();
    let mut holds = vec![0usize; n];
    for (v, &j) in skin.vertex_joint.iter().enumerate() {
        if let Some(h) = holds.get_mut(j as usize).filter(|_| counts(v)) {
            *h += 1;
        }
    }
    // The nearest joint above `j` that holds vertices.
    let holder_above = |j: usize| -> Option<usize> {
        let mut at = skin.joints[j].parent;
        for _ in 0..n {
            match at {
                Some(p) if holds[p] > 0 => return Some(p),
                Some(p) => at = skin.joints[p].parent,
                None => return None,
            }
        }
        None
    };
    let place = |j: usize| skin.joints[j].rest.w_axis.truncate();
    let held: Vec<usize> = (0..n).filter(|&j| holds[j] > 0).collect();
    let root = *held.iter().find(|&&j| holder_above(j).is_none())?;
    let cuts = held
        .iter()
        .filter(|&&j| j != root)
        .map(|&j| {
            let parent = holder_above(j).unwrap_or(root);
            let at = place(j);
            // The bone's direction: toward its children, else on from its parent, else
            // the joint's own y axis (the bone axis of Blender's and Mixamo's rigs).
            let children: Vec<DVec3> = (0..n)
                .filter(|&c| skin.joints[c].parent == Some(j))
                .map(place)
                .filter(|p| p.distance(at) > 0.0)
                .collect();
            let toward = if children.is_empty() {
                at - place(parent)
            } else {
                children.iter().sum::<DVec3>() / children.len() as f64 - at
            };
            let normal = toward
                .try_normalize()
                .or_else(|| skin.joints[j].rest.y_axis.truncate().try_normalize())
                .unwrap_or(DVec3::Y);
            Cut {
                name: skin.joints[j].name.clone(),
                section: skin.joints[parent].name.clone(),
                shape: Shape::Skin,
                point: at,
                normal,
                pivot: Some(at),
                connected: false,
                band: None,
                shared_pivot: false,
            }
        })
        .collect();
    Some(SkinJoints {
        root: skin.joints[root].name.clone(),
        cuts,
    })
}
