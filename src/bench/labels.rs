//! A labelled character: where a puppeteer would put its joints, written by hand (or, for
//! a generated character, where its bones meet), and how a suggestion scores against it.
//! `puppet bench suggest` reads the set in `tests/data/characters`.
//!
//! The file (TOML) names its mesh (relative to the file), and lists:
//! * `[[joint]]`: `role` (the section the joint starts: `arm.L` at the shoulder), `at`, and
//!   `required`: a suggestion must find it (limb roots, the neck, elbows, knees) or may
//!   (wrists, ankles, ears, a tail's root);
//! * `[[free]]`: a stretch (`along`, a polyline) where any cut is a fair joint (a tail, a
//!   scorpion's leg).
//!
//! A cut matches a joint when its pivot lies within [`TOLERANCE`] of the character's
//! height (the longest side of its bounding box, so a lying lizard is measured by its
//! length), each joint matching at most one cut, nearest pairs first. A cut that matches no
//! joint and lies on no free stretch is spurious.

use glam::DVec3;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A match is within this share of the character's height.
pub const TOLERANCE: f64 = 0.05;

/// A labelled character: its mesh and joints (see the module docs).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Labels {
    /// The mesh, relative to the labels file.
    pub mesh: PathBuf,
    /// What it is (`humanoid`, `quadruped`, `toy`…).
    pub kind: String,
    /// The up direction it is modelled with (`+y`, `+z`), when it says.
    #[serde(default)]
    pub up: Option<crate::mesh::orientation::Up>,
    /// The direction it faces (`+z`, glTF's), when it says.
    #[serde(default)]
    pub front: Option<crate::mesh::orientation::Up>,
    /// Which half of the population it is in: rules are chosen on the development half
    /// only, and the held-out half checks that they carry over.
    #[serde(default)]
    pub half: Half,
    /// Where the mesh comes from and its licence, for meshes not generated here.
    #[serde(default)]
    pub credit: Option<String>,
    /// The joints (`[[joint]]`).
    #[serde(default, rename = "joint")]
    pub joints: Vec<Joint>,
    /// The stretches where any cut is fair (`[[free]]`).
    #[serde(default)]
    pub free: Vec<Free>,
}

/// A half of the labelled population, fixed once.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, serde::Serialize, clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Half {
    /// Where rules and thresholds are chosen (the labelled set the suggestion grew on is
    /// all in it).
    #[default]
    Development,
    /// Never looked at while choosing: a change that helps one half and hurts the other
    /// is not kept.
    HeldOut,
}

impl Half {
    /// As written in a labels file.
    pub fn name(self) -> &'static str {
        match self {
            Half::Development => "development",
            Half::HeldOut => "held-out",
        }
    }
}

/// A labelled joint.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Joint {
    /// The section the joint starts (`arm.L`, `neck`…).
    pub role: String,
    /// Where it is, in the mesh's frame.
    pub at: [f64; 3],
    /// A suggestion must find it.
    #[serde(default)]
    pub required: bool,
}

/// A stretch where any cut is fair.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Free {
    /// What it is (`tail`).
    pub role: String,
    /// A polyline through it.
    pub along: Vec<[f64; 3]>,
}

/// A suggestion against a labelled character.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Score {
    /// Required joints.
    pub required: usize,
    /// Required joints a cut matched.
    pub found: usize,
    /// Suggested cuts.
    pub cuts: usize,
    /// Cuts that matched no joint and lie on no free stretch.
    pub spurious: usize,
    /// Matched cuts whose name is the joint's role.
    pub named: usize,
    /// Cuts that matched a joint.
    pub matched: usize,
    /// The mean distance from each joint to the nearest cut and from each cut to the
    /// nearest joint, averaged (RigNet's CD-J2J), in % of the height.
    pub j2j: f64,
    /// The required joints no cut matched, each with the distance to the nearest cut in %
    /// of the height.
    pub missed: Vec<String>,
    /// The spurious cuts' names.
    pub extra: Vec<String>,
}

impl Labels {
    /// Reads a labels file; the error is one line.
    pub fn read(path: &Path) -> Result<Labels, String> {
        let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
        toml::from_str(&text).map_err(|e| e.message().to_string())
    }

    /// The mesh's path, given the labels file's.
    pub fn mesh_path(&self, file: &Path) -> PathBuf {
        file.parent().unwrap_or(Path::new(".")).join(&self.mesh)
    }

    /// The labels of the character turned by `turn` about the origin: each joint, each
    /// free stretch, up and front turned with it.
    pub fn turned(&self, turn: glam::DQuat) -> Labels {
        let at = |p: [f64; 3]| (turn * DVec3::from_array(p)).to_array();
        let axis = |u: crate::mesh::orientation::Up| {
            crate::mesh::orientation::Up::nearest(turn * u.vector())
        };
        Labels {
            up: Some(axis(self.up.unwrap_or(crate::mesh::orientation::Up::PosY))),
            front: self.front.map(axis),
            joints: self
                .joints
                .iter()
                .map(|j| Joint {
                    at: at(j.at),
                    ..j.clone()
                })
                .collect(),
            free: self
                .free
                .iter()
                .map(|f| Free {
                    along: f.along.iter().map(|&p| at(p)).collect(),
                    ..f.clone()
                })
                .collect(),
            ..self.clone()
        }
    }

    /// Scores suggested cuts (`name`, pivot) on a character `height` tall.
    pub fn score(&self, cuts: &[(String, DVec3)], height: f64) -> Score {
        let tolerance = TOLERANCE * height;
        let at: Vec<DVec3> = self
            .joints
            .iter()
            .map(|j| DVec3::from_array(j.at))
            .collect();
        // Nearest pairs first, each joint and each cut at most once.
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (j, &p) in at.iter().enumerate() {
            for (c, (_, q)) in cuts.iter().enumerate() {
                let d = p.distance(*q);
                if d <= tolerance {
                    pairs.push((d, j, c));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut joint_of = vec![None; cuts.len()];
        let mut taken = vec![false; at.len()];
        for (_, j, c) in pairs {
            if !taken[j] && joint_of[c].is_none() {
                taken[j] = true;
                joint_of[c] = Some(j);
            }
        }
        let on_free = |q: DVec3| {
            self.free.iter().any(|f| {
                f.along
                    .windows(2)
                    .any(|w| segment_distance(q, w[0].into(), w[1].into()) <= tolerance)
            })
        };
        let mut score = Score {
            required: self.joints.iter().filter(|j| j.required).count(),
            cuts: cuts.len(),
            ..Score::default()
        };
        for (j, joint) in self.joints.iter().enumerate() {
            if joint.required {
                if taken[j] {
                    score.found += 1;
                } else {
                    // With how far the nearest cut is, in % of the height.
                    let nearest = cuts
                        .iter()
                        .map(|c| c.1.distance(at[j]))
                        .fold(f64::INFINITY, f64::min);
                    score.missed.push(format!(
                        "{} ({:.0} %)",
                        joint.role,
                        100.0 * nearest / height
                    ));
                }
            }
        }
        for (c, (name, q)) in cuts.iter().enumerate() {
            match joint_of[c] {
                Some(j) => {
                    score.matched += 1;
                    if *name == self.joints[j].role {
                        score.named += 1;
                    }
                }
                None if on_free(*q) => {}
                None => {
                    score.spurious += 1;
                    score.extra.push(name.clone());
                }
            }
        }
        let nearest = |p: DVec3, set: &mut dyn Iterator<Item = DVec3>| {
            set.map(|q| p.distance(q)).fold(f64::INFINITY, f64::min)
        };
        if !at.is_empty() && !cuts.is_empty() {
            let to_cuts: f64 = at
                .iter()
                .map(|&p| nearest(p, &mut cuts.iter().map(|c| c.1)))
                .sum::<f64>()
                / at.len() as f64;
            let to_joints: f64 = cuts
                .iter()
                .map(|c| nearest(c.1, &mut at.iter().copied()))
                .sum::<f64>()
                / cuts.len() as f64;
            score.j2j = 100.0 * 0.5 * (to_cuts + to_joints) / height;
        }
        score
    }
}

/// The distance from `p` to the segment `a`–`b`.
fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels() -> Labels {
        toml::from_str(
            r#"
            mesh = "x.obj"
            kind = "humanoid"
            [[joint]]
            role = "arm.L"
            at = [1, 0, 0]
            required = true
            [[joint]]
            role = "hand.L"
            at = [2, 0, 0]
            [[free]]
            role = "tail"
            along = [[0, -1, 0], [0, -3, 0]]
            "#,
        )
        .unwrap()
    }

    #[test]
    fn cuts_match_the_nearest_joint_once_and_free_stretches_are_no_spurious_cuts() {
        let r = labels();
        let cuts = vec![
            ("arm.L".to_string(), DVec3::new(1.02, 0.0, 0.0)),
            ("joint 2".to_string(), DVec3::new(1.04, 0.0, 0.0)),
            ("tail".to_string(), DVec3::new(0.05, -2.0, 0.0)),
            ("joint 4".to_string(), DVec3::new(5.0, 0.0, 0.0)),
        ];
        let s = r.score(&cuts, 2.0);
        assert_eq!((s.required, s.found, s.named, s.matched), (1, 1, 1, 1));
        // The second cut near the shoulder is within reach of no unmatched joint.
        assert_eq!(s.spurious, 2);
        assert_eq!(s.extra, vec!["joint 2", "joint 4"]);
        assert!(s.j2j > 0.0);
    }

    #[test]
    fn a_missing_required_joint_is_named() {
        let s = labels().score(&[("x".into(), DVec3::new(2.0, 0.0, 0.0))], 2.0);
        assert_eq!(
            (s.found, s.missed.clone()),
            (0, vec!["arm.L (50 %)".to_string()])
        );
        assert_eq!(s.spurious, 0);
    }
}
