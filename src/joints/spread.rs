//! Random poses of the joints: every section but the root turned about a random axis across
//! its cut (square to the cut's normal) by an angle drawn evenly within ±[`Spread::limb`]
//! degrees, or ±[`Spread::root`] for a section hanging from the root (a head, a hip, a
//! shoulder). What `puppet bench poses`, the pose tests, the stress test and the
//! suggestion's tear check ([`super::suggest::seams`]) turn a character through.

use super::{Joints, Local};
use crate::random::SplitMix;
use glam::DVec3;

/// How far the joints of a random pose turn (degrees either way).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Spread {
    /// A section whose parent is not the root (an elbow, a knee, a finger's joint).
    pub limb: f64,
    /// A section hanging from the root (a head, a hip, a shoulder).
    pub root: f64,
}

impl Default for Spread {
    /// The pose issue's population: ±60° on limbs, ±90° at the root.
    fn default() -> Self {
        Spread {
            limb: 60.0,
            root: 90.0,
        }
    }
}

/// Two unit axes across section `s`'s cut (square to its normal), and how far `spread`
/// turns it either way: [`Spread::root`] for a section hanging from the root, else
/// [`Spread::limb`]. `None` for the root, which has no cut.
pub fn across(joints: &Joints, s: usize, spread: Spread) -> Option<(DVec3, DVec3, f64)> {
    let parent = joints.sections().get(s)?.parent?;
    let cut = joints.cuts().get(s.checked_sub(1)?)?;
    let (a, b) = cut.normal.normalize_or(DVec3::Y).any_orthonormal_pair();
    let limit = if parent == 0 {
        spread.root
    } else {
        spread.limb
    };
    Some((a, b, limit))
}

/// A random pose of `joints` (one [`Local`] per section, the root at rest), drawn from
/// `rng` (see the module docs).
pub fn random_pose(joints: &Joints, spread: Spread, rng: &mut SplitMix) -> Vec<Local> {
    let sections = joints.sections();
    let mut local = vec![Local::default(); sections.len()];
    for cut in joints.cuts() {
        let Some(s) = joints.find(&cut.name) else {
            continue;
        };
        let Some((a, b, limit)) = across(joints, s, spread) else {
            continue;
        };
        let turn = std::f64::consts::TAU * unit(rng);
        let axis = a * turn.cos() + b * turn.sin();
        local[s] = Local::axis_angle(axis, limit * (2.0 * unit(rng) - 1.0));
    }
    local
}

/// Keeps one of `pose`'s turned sections, drawn from `rng`, and puts the rest at rest:
/// what a mouse drag turns (the sections past it follow it). A pose with none turned
/// stays as it is.
pub fn one_turned(pose: &mut [Local], rng: &mut SplitMix) {
    let turned: Vec<usize> = (0..pose.len())
        .filter(|&s| pose[s] != Local::default())
        .collect();
    if turned.is_empty() {
        return;
    }
    let keep = turned[(rng.next_u64() % turned.len() as u64) as usize];
    for (s, l) in pose.iter_mut().enumerate() {
        if s != keep {
            *l = Local::default();
        }
    }
}

/// A number in `0..1` from `rng`.
fn unit(rng: &mut SplitMix) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_random_pose_turns_across_each_cut_within_its_spread() {
        // A line of skeletal points cut at y = 1 (from the root) and y = 2 (from that).
        let points: Vec<DVec3> = (0..=30)
            .map(|k| DVec3::new(0.0, k as f64 * 0.1, 0.0))
            .collect();
        let mut joints = Joints::new(&points, super::super::ROOT);
        for (name, section, y) in [("arm", super::super::ROOT, 1.0), ("forearm", "arm", 2.0)] {
            joints
                .add_cut(super::super::Cut::plane(
                    name,
                    section,
                    DVec3::new(0.0, y, 0.0),
                    DVec3::Y,
                ))
                .expect("a cut");
        }
        let mut rng = SplitMix(7);
        let spread = Spread::default();
        for _ in 0..50 {
            let pose = random_pose(&joints, spread, &mut rng);
            assert_eq!(pose[0], Local::default());
            for cut in joints.cuts() {
                let s = joints.find(&cut.name).expect("section");
                let (axis, angle) = pose[s].rotation.to_axis_angle();
                let limit = if joints.sections()[s].parent == Some(0) {
                    spread.root
                } else {
                    spread.limb
                };
                assert!(angle.to_degrees() <= limit + 1e-9);
                if angle > 1e-6 {
                    assert!(axis.dot(cut.normal.normalize()).abs() < 1e-9);
                }
            }
        }
    }

    #[test]
    fn a_drag_keeps_one_turned_section_of_a_pose() {
        let turned = |a: f64| Local::axis_angle(DVec3::X, a);
        let pose = vec![
            Local::default(),
            turned(10.0),
            Local::default(),
            turned(20.0),
            turned(30.0),
        ];
        let mut kept = std::collections::BTreeSet::new();
        for seed in 0..40 {
            let mut one = pose.clone();
            one_turned(&mut one, &mut SplitMix(seed));
            let moved: Vec<usize> = (0..one.len())
                .filter(|&s| one[s] != Local::default())
                .collect();
            assert_eq!(moved.len(), 1, "{one:?}");
            assert_eq!(one[moved[0]], pose[moved[0]]);
            kept.insert(moved[0]);
        }
        // Each turned section is drawn, none at rest.
        assert_eq!(kept.into_iter().collect::<Vec<_>>(), vec![1, 3, 4]);
        let mut rest = vec![Local::default(); 3];
        one_turned(&mut rest, &mut SplitMix(1));
        assert_eq!(rest, vec![Local::default(); 3]);
    }
}
