//! Joints from the skeleton a mesh file came with ([`crate::mesh::Skin`]): a section per
//! joint that is the largest weight of some vertex, hinged at the joint's rest place, with
//! the file's hierarchy and names. A joint that is no vertex's largest weight merges into
//! the nearest joint above it that is.

use super::{Cut, Shape};
use crate::mesh::Skin;
use glam::DVec3;

/// The joints a skin gives: the root section's name (the topmost joint that holds
/// vertices) and a skin cut per other joint that holds vertices, parents first.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinJoints {
    /// The root section's name.
    pub root: String,
    /// The cuts, parents first.
    pub cuts: Vec<Cut>,
}

/// The joints of `skin`; `None` when no joint holds a vertex.
pub fn joints(skin: &Skin) -> Option<SkinJoints> {
    let n = skin.joints.len();
    let mut holds = vec![0usize; n];
    for &j in &skin.vertex_joint {
        if let Some(h) = holds.get_mut(j as usize) {
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
