//! A clip of the mesh file's skin ([`crate::mesh::skin::Clip`]) as an animation of the
//! puppet's sections: a section named after a skin joint moves as that joint moves
//! (`G(t) · G(rest)⁻¹`, its transform in the scene at time `t` against at rest), written as
//! its rotation about its pivot and a translation, relative to its parent section, one key
//! per frame of the clip. Sections named after no joint stay at rest against their parent.

use super::{Animation, Ease, Key, Track};
use crate::joints::Joints;
use crate::mesh::skin::{Clip, Skin};
use glam::{DAffine3, DMat4};

/// `clip` of `skin` as an animation of the sections of `joints`.
pub fn animation(clip: &Clip, skin: &Skin, joints: &Joints) -> Animation {
    let sections = joints.sections();
    let joint: Vec<Option<usize>> = sections.iter().map(|s| skin.find(&s.name)).collect();
    let affine = |m: DMat4| DAffine3::from_mat4(m);
    // Per section, its track (sections named after a joint).
    let mut tracks: Vec<Track> = Vec::new();
    let track_of: Vec<Option<usize>> = sections
        .iter()
        .zip(&joint)
        .map(|(s, j)| {
            j.map(|_| {
                tracks.push(Track {
                    section: s.name.clone(),
                    ease: Ease::Linear,
                    key: Vec::with_capacity(clip.frames.len()),
                });
                tracks.len() - 1
            })
        })
        .collect();
    let mut world = vec![DAffine3::IDENTITY; sections.len()];
    let mut motion = world.clone();
    let mut turned = vec![crate::joints::Local::default(); sections.len()];
    let last = clip.frames.len().saturating_sub(1);
    for (k, frame) in clip.frames.iter().enumerate() {
        let time = if k == last {
            clip.duration
        } else {
            (k as f64 / clip.fps).min(clip.duration)
        };
        // Every section's motion relative to its parent first: a band's slide depends on
        // the turns of the sections around it.
        for &s in joints.parents_first() {
            let parent = sections[s].parent.map_or(DAffine3::IDENTITY, |p| world[p]);
            world[s] = match joint[s] {
                Some(j) => affine(frame[j]) * affine(skin.joints[j].rest).inverse(),
                None => parent,
            };
            motion[s] = parent.inverse() * world[s];
            turned[s].rotation = motion[s].to_scale_rotation_translation().1.normalize();
        }
        for &s in joints.parents_first() {
            let (Some(_), Some(t)) = (joint[s], track_of[s]) else {
                continue;
            };
            let local = joints.local_for(s, &motion[s], &turned);
            let (axis, angle) = local.rotation.to_axis_angle();
            tracks[t].key.push(Key {
                time,
                axis: axis.to_array(),
                angle: angle.to_degrees(),
                translation: Some(local.translation.to_array()),
            });
        }
    }
    Animation {
        duration: clip.duration.max(1.0 / clip.fps),
        looping: false,
        track: tracks,
    }
}
