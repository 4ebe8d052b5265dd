//! The skeleton a file comes with: a glTF skin's joints, where they stand at rest, how much
//! of the surface each carries, and the file's clips as each joint's motion over time.
//!
//! A skinned file's surface is read at rest as the file's skinning puts it (each vertex by
//! its joints' rest transforms and its weights), and its skin becomes the puppet's joints
//! ([`crate::joints::skin`]) instead of a suggestion.

use glam::{DMat4, DVec3};
use std::collections::HashMap;

/// A vertex's four largest weights as (joint, weight), largest first, summing to 1;
/// `(u32::MAX, 0)` where it has fewer.
pub type Weights = [(u32, f32); 4];

/// The weights of a vertex no skin moves.
pub const NO_WEIGHTS: Weights = [(u32::MAX, 0.0); 4];

/// One joint of a skin.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinJoint {
    /// The file's name for it (its node's name, or `joint N`).
    pub name: String,
    /// The nearest ancestor that is a joint too.
    pub parent: Option<usize>,
    /// Its transform in the scene at rest (the nodes' own transforms, no clip).
    pub rest: DMat4,
    /// The weight it carries: the sum over every vertex of that vertex's weight for it.
    pub weight: f64,
}

/// A clip: each joint's transform in the scene at a fixed rate.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    /// The file's name for it (or `clip N`).
    pub name: String,
    /// Frames per second of `frames`.
    pub fps: f64,
    /// Its length in seconds (its last key's time).
    pub duration: f64,
    /// Per frame, every joint's transform in the scene (`frames[k][j]` at `k / fps` s).
    pub frames: Vec<Vec<DMat4>>,
    /// Channels that drive morph-target weights: not played (the puppet's surface is the
    /// simulation's), counted so the listing can say so.
    pub morph_channels: usize,
}

/// A file's skins, all joints in one list (several meshes may share them).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skin {
    /// Joints, parents before children.
    pub joints: Vec<SkinJoint>,
    /// The file's animations.
    pub clips: Vec<Clip>,
    /// Per vertex, the joint with its largest weight (`u32::MAX` for a vertex no skin
    /// moves): per vertex of the file as read, then of the loaded mesh ([`Skin::carry`]).
    pub vertex_joint: Vec<u32>,
    /// Per vertex, its four largest weights (as `vertex_joint`, per vertex of the file,
    /// then of the loaded mesh).
    pub weights: Vec<Weights>,
}

impl Skin {
    /// `weights` (and `vertex_joint`) of the file's vertices (at `positions`) carried to
    /// the loaded mesh's vertices by position, as the repairs left them: a vertex at the
    /// place of a file's vertex takes its weights, and one the repairs added (a hole's
    /// fill) those of a neighbour that has some, ring by ring.
    pub fn carry(&mut self, positions: &[DVec3], mesh: &super::Mesh) {
        let key = |p: DVec3| p.to_array().map(f64::to_bits);
        let at: HashMap<[u64; 3], Weights> = positions
            .iter()
            .zip(&self.weights)
            .map(|(p, &w)| (key(*p), w))
            .collect();
        let mut weights: Vec<Weights> = mesh
            .positions
            .iter()
            .map(|p| at.get(&key(*p)).copied().unwrap_or(NO_WEIGHTS))
            .collect();
        let (start, neighbours) =
            super::neighbours(weights.len(), &super::unique_edges(&mesh.triangles));
        loop {
            let mut changed = false;
            let before = weights.clone();
            for (v, w) in weights.iter_mut().enumerate() {
                if w[0].0 != u32::MAX {
                    continue;
                }
                let around = &neighbours[start[v] as usize..start[v + 1] as usize];
                if let Some(&n) = around
                    .iter()
                    .find(|&&n| before[n as usize][0].0 != u32::MAX)
                {
                    *w = before[n as usize];
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        self.vertex_joint = weights.iter().map(|w| w[0].0).collect();
        self.weights = weights;
    }

    /// Is joint `j` joint `ancestor` or below it?
    pub fn is_within(&self, mut j: usize, ancestor: usize) -> bool {
        for _ in 0..=self.joints.len() {
            if j == ancestor {
                return true;
            }
            match self.joints.get(j).and_then(|x| x.parent) {
                Some(p) => j = p,
                None => return false,
            }
        }
        false
    }

    /// The joint named `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }
}

/// Our role for a joint the file names (`mixamorig:LeftForeArm` → `forearm.L`), for the
/// names that Mixamo, Blender's Rigify and metarig, and most game exporters use; `None`
/// for a name it does not know.
pub fn role(name: &str) -> Option<String> {
    // The name without its rig's prefix ("mixamorig:", "Armature_", "DEF-"), in lower case.
    let bare = name
        .rsplit([':', '|'])
        .next()
        .unwrap_or(name)
        .trim_start_matches("DEF-")
        .trim_start_matches("ORG-");
    let lower = bare.to_ascii_lowercase();
    // Side: a Left/Right word, or a .L/_L/-L suffix.
    let (side, rest) = side_of(&lower);
    let compact: String = rest.chars().filter(|c| c.is_ascii_alphanumeric()).collect();
    // Numbered bones of one part (Blender's `spine.003`, `neck_01`) are that part.
    let word = compact.trim_end_matches(|c: char| c.is_ascii_digit());
    let part = match word {
        "hips" | "pelvis" | "root" => "hips",
        "spine" | "chest" | "upperchest" | "torso" => "spine",
        "neck" => "neck",
        "head" => "head",
        "shoulder" | "clavicle" | "collar" => "shoulder",
        "arm" | "upperarm" | "uparm" => "arm",
        "forearm" | "lowerarm" | "elbow" => "forearm",
        "hand" | "wrist" => "hand",
        "upleg" | "thigh" | "upperleg" | "hip" => "leg",
        "leg" | "calf" | "shin" | "lowerleg" | "knee" => "shin",
        "foot" | "ankle" => "foot",
        "toebase" | "toe" | "toes" | "ball" => "toe",
        "tail" => "tail",
        "jaw" => "jaw",
        _ => {
            // Fingers: Thumb1, index_01, LeftHandMiddle2 …
            let digits = compact.trim_start_matches("hand");
            let finger = ["thumb", "index", "middle", "ring", "pinky", "little"]
                .into_iter()
                .find(|f| digits.starts_with(f))?;
            let finger = if finger == "pinky" { "little" } else { finger };
            let number: String = digits[finger.len()..]
                .chars()
                .filter(char::is_ascii_digit)
                .collect();
            let k = number.trim_start_matches('0').parse::<u32>().unwrap_or(1);
            return Some(match (side, k) {
                (Some(s), 1) => format!("{finger}.{s}"),
                (Some(s), k) => format!("{finger}.{s}.{k}"),
                (None, 1) => finger.to_string(),
                (None, k) => format!("{finger}.{k}"),
            });
        }
    };
    Some(match side {
        Some(s) => format!("{part}.{s}"),
        None => part.to_string(),
    })
}

/// `Some("L")`/`Some("R")` and the name without its side, for `left…`, `right…`, `l_…`,
/// `…_l`, `….l`, `…-l` (already in lower case).
fn side_of(lower: &str) -> (Option<&'static str>, &str) {
    for (word, side) in [("left", "L"), ("right", "R")] {
        if let Some(rest) = lower.strip_prefix(word) {
            return (Some(side), rest);
        }
    }
    for (ends, side) in [
        ([".l", "_l", "-l", " l"], "L"),
        ([".r", "_r", "-r", " r"], "R"),
    ] {
        for e in ends {
            if let Some(rest) = lower.strip_suffix(e) {
                return (Some(side), rest);
            }
        }
    }
    for (starts, side) in [(["l_", "l."], "L"), (["r_", "r."], "R")] {
        for s in starts {
            if let Some(rest) = lower.strip_prefix(s) {
                return (Some(side), rest);
            }
        }
    }
    (None, lower)
}

#[cfg(test)]
mod tests {
    use super::role;

    #[test]
    fn roles_of_common_rig_names() {
        for (name, want) in [
            ("mixamorig:LeftForeArm", Some("forearm.L")),
            ("mixamorig:RightUpLeg", Some("leg.R")),
            ("mixamorig:RightLeg", Some("shin.R")),
            ("mixamorig:Hips", Some("hips")),
            ("mixamorig:Spine2", Some("spine")),
            ("mixamorig:LeftHandThumb2", Some("thumb.L.2")),
            ("mixamorig:RightHandPinky1", Some("little.R")),
            ("mixamorig:HeadTop_End", None),
            ("upper_arm.L", Some("arm.L")),
            ("DEF-forearm.R", Some("forearm.R")),
            ("thigh_l", Some("leg.L")),
            ("calf_r", Some("shin.R")),
            ("Head", Some("head")),
            ("Bone.001", None),
            ("spine.003", Some("spine")),
        ] {
            assert_eq!(role(name).as_deref(), want, "{name}");
        }
    }
}
