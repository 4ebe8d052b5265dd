//! Stage 5 of the suggestion: names by role, within the frame found from the root's limbs
//! (`mesh::orientation::frame`: up, front and left beside the mirror plane).
//!
//! * **Roles.** The root's limbs off the mirror plane: pointing up from above the root's
//!   centre, ears, unless its root's mirror image lies by an arm's or a leg's, at most half
//!   as far as by another ear's (an arm raised higher than the other), and one above the
//!   centre whose root's mirror image lies by an ear's, at most half as far as by another
//!   limb's, is an ear too (the far ear of a head turned aside); of the others, when
//!   one pair stands on the ground ([`GROUND`]) and the rest do not, a biped: the standing
//!   pair are legs and the largest raised limb on each side an arm (arms held out or
//!   hanging down); when all stand, pairs from the front: arms (forelegs) and legs,
//!   numbered legs from three pairs on. A part on the plane hanging down with two or more
//!   off it (a pelvis the legs hang from, cut at a waist) is the `hips`, and those parts
//!   count as the root's limbs; so is the end of a chain of up to `WAIST` such parts, each
//!   the one part of the last (a shirt's hem, then the crotch), the ones above it the
//!   `waist`. On the plane, of those not growing from the back
//!   end and ending no thinner than any limb off the plane, the one whose far half is
//!   thickest (a head ends in a bulb, a tail in a point), leaning up, counted twice when it
//!   carries parts off the plane (ears, antennae), is the neck (or the head if nothing
//!   follows it); one pointing back or growing from the back end is the tail (a
//!   scorpion's, raised over its back), or the abdomen when it ends as thick as the head;
//!   with no head, a short one (a snout on a head not cut from the body) is no joint, and
//!   so is one with nothing of its own on a root that carries ears (the head is part of
//!   the body: a cat's or a wolf's muzzle, however thick it ends).
//!   Down a limb the names go on: `arm`, `forearm`, `hand`; `leg`, `shin`, `foot` (`leg`,
//!   `foot` where the joint below the hip points back: a hock, `HOCK`; a leg cut more
//!   often has its `foot` at the first part below the knee that points ahead); `neck`, `head`;
//!   four or five digits of a hand are `thumb`, `index`, `middle`, `ring`, `little` (the
//!   thumb the one turned most from the others), of a foot `toe1`…. A head's feelers are
//!   an insect's antennae; on a body whose legs are not numbered, ears.
//!   A neck's one short part with none of its own, thin beside it (a snout, a beak turned
//!   aside), is the head's end, no joint, and the neck is the `head`.
//!   A head's parts off the plane are ears; with two on a side, the one pointing most up
//!   is a horn; one long and round (`ANTENNA`) is an antenna.
//!   Side suffixes come from the side of the mirror plane; what fits no role keeps its
//!   number (`joint 3`). A role found twice stays with the one that mirrors the other
//!   side's, and the others are numbered on (`ear.2.L`, `hand.3.R`).
//!
//! * `naming`: what naming reads (the section tree, each subtree, the frame) and the root's
//!   limbs: ears, arms, legs, the neck, the tail;
//! * `chains`: down one limb (`arm`, `forearm`, `hand`…) and its digits.

mod chains;
mod naming;

use super::place::Placed;
use crate::joints::{Cut, Joints};
use crate::mesh::orientation::{frame, Cues, Frame, Given, Reach};
use crate::mesh::Mesh;
use naming::Naming;
use std::collections::HashMap;

/// Stage 5's output: the cuts named by role.
pub(crate) struct Named {
    /// The cuts renamed by role (each name once; a cut no role fits keeps its number), a
    /// section that is its parent's end (a snout) taken back.
    pub(crate) cuts: Vec<Cut>,
    /// The frame they were named in.
    pub(crate) frame: Frame,
    /// The shoulders' and hips' sockets and widths ([`Placed::sockets`]), by their final
    /// names.
    pub(crate) balls: HashMap<String, (f64, f64)>,
}

/// The cuts of `placed` named by role in the frame found from the root's limbs, on
/// `character` (each rider where its host is) of skeletal distances `radius`; up and front
/// as far as `given`; `cues`, the body's; `root`, the root section's name.
pub(crate) fn name(
    character: &Mesh,
    radius: &[f64],
    placed: &Placed,
    given: Given,
    cues: Cues,
    root: &str,
) -> Named {
    // Names by role, each given once ([`unique`]); a cut no role fits keeps its number.
    let mut roles = roles(character, radius, &placed.joints, given, cues);
    let pivots: Vec<glam::DVec3> = placed.joints.sections().iter().map(|s| s.pivot).collect();
    unique(&mut roles.names, &pivots, roles.frame.mirror);
    let mut cuts = placed.cuts.clone();
    let sockets = &placed.sockets;
    let frame = roles.frame;
    let mut renamed: HashMap<String, String> = HashMap::new();
    let mut taken: std::collections::HashSet<String> = Default::default();
    // The shoulders' and hips' sockets and widths, by their final names.
    let mut balls: HashMap<String, (f64, f64)> = HashMap::new();
    for (k, cut) in cuts.iter().enumerate() {
        if let Some(role) = roles.names.get(k + 1).cloned().flatten() {
            let is_ball = is_ball_joint(&role);
            if role != root && taken.insert(role.clone()) {
                renamed.insert(cut.name.clone(), role.clone());
                if is_ball {
                    balls.insert(role, sockets[k]);
                }
            } else if is_ball {
                balls.insert(cut.name.clone(), sockets[k]);
            }
        }
    }
    // A section that is its parent's end (a snout) is no joint: its cut is taken back
    // (it is a leaf, so nothing else moves).
    let ends: Vec<String> = roles
        .ends
        .iter()
        .filter_map(|&s| cuts.get(s.checked_sub(1)?))
        .filter(|end| !cuts.iter().any(|c| c.section == end.name))
        .map(|end| end.name.clone())
        .collect();
    cuts.retain(|c| !ends.contains(&c.name));
    for cut in &mut cuts {
        if let Some(name) = renamed.get(&cut.name) {
            cut.name = name.clone();
        }
        if let Some(section) = renamed.get(&cut.section) {
            cut.section = section.clone();
        }
    }
    Named { cuts, frame, balls }
}

/// The sections of a suggestion as [`roles`] reads them.
pub(crate) struct Roles {
    /// Per section, its name by role (index 0 is the root and keeps its name); `None`
    /// where no role fits.
    pub(crate) names: Vec<Option<String>>,
    /// The frame they were named in.
    pub(crate) frame: Frame,
    /// Sections that are the end of their parent, no joint (a head's snout): their cuts
    /// are taken back.
    pub(crate) ends: Vec<usize>,
}

/// Role names for the sections of `joints`, in the frame found for them. `radius` is each
/// vertex's skeletal distance, `cues` the body's mirror plane and flat base.
pub(crate) fn roles(
    mesh: &Mesh,
    radius: &[f64],
    joints: &Joints,
    given: Given,
    cues: Cues,
) -> Roles {
    let Cues { mirror, base, .. } = cues;
    let sections = joints.sections();
    let n = sections.len();
    let mut children = vec![Vec::new(); n];
    for (s, sec) in sections.iter().enumerate() {
        if let Some(p) = sec.parent {
            children[p].push(s);
        }
    }
    // Each section's subtree: the vertices in it and in what hangs from it.
    let mut within: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (v, &s) in joints.section_of().iter().enumerate() {
        let mut t = Some(s as usize);
        while let Some(at) = t {
            within[at].push(v);
            t = sections[at].parent;
        }
    }
    let mut naming = Naming {
        mesh,
        radius,
        sections,
        children,
        within,
        // The mirror plane first: a limb's reach says whether it carries parts off it.
        frame: Frame {
            mirror,
            ..Frame::default()
        },
        names: vec![None; n],
        ends: Vec::new(),
        size: mesh.longest_side().max(1e-12),
        base,
    };
    let limbs: Vec<(usize, Reach)> = naming.children[0]
        .iter()
        .map(|&s| (s, naming.reach(s)))
        .collect();
    let reaches: Vec<Reach> = limbs.iter().map(|l| l.1).collect();
    naming.frame = frame(&mesh.positions, cues, &reaches, given);
    naming.root(&limbs);
    naming.ears_unless_insect();
    Roles {
        names: naming.names,
        frame: naming.frame,
        ends: naming.ends,
    }
}

/// The name of the same role on the other side: `index.R.2` for `index.L.2`; `None` for a
/// name with no side.
pub fn other_side(name: &str) -> Option<String> {
    let words: Vec<&str> = name.split('.').collect();
    if !words.iter().any(|&w| w == "L" || w == "R") {
        return None;
    }
    let swapped: Vec<&str> = words
        .iter()
        .map(|&w| match w {
            "L" => "R",
            "R" => "L",
            w => w,
        })
        .collect();
    Some(swapped.join("."))
}

/// Is `role` a limb's root that turns in a ball joint: a shoulder (`arm.L`) or a hip
/// (`leg.R`, an insect's `leg2.L`)?
pub(crate) fn is_ball_joint(role: &str) -> bool {
    let base = role.split('.').next().unwrap_or("");
    base == "arm"
        || base
            .strip_prefix("leg")
            .is_some_and(|k| k.chars().all(|c| c.is_ascii_digit()))
}

/// Each role given once (`names` per section, `pivots` theirs): of the sections given one
/// name, the one nearest the mirror image (across `mirror`) of the section given the
/// other side's keeps it (the first where there is none); the others take the next
/// number of it (`ear.L` → `ear.2.L`, `hand.2.R` → `hand.3.R`, `finger1.L.2` →
/// `finger1.L.3`) not given yet. A hand found twice down one arm (`hand`, `hand.2`, then
/// a palm with a thumb beside it, `hand` again) is `hand.3` as its pair is, and a second
/// cut on one ear no longer leaves its pair unnamed.
fn unique(
    names: &mut [Option<String>],
    pivots: &[glam::DVec3],
    mirror: Option<(glam::DVec3, f64)>,
) {
    let mut given: std::collections::HashSet<String> = names.iter().flatten().cloned().collect();
    let n = names.len();
    for s in 1..n {
        let Some(name) = names[s].clone() else {
            continue;
        };
        let same: Vec<usize> = (1..n)
            .filter(|&t| names[t].as_deref() == Some(&name))
            .collect();
        if same.len() < 2 || same[0] != s {
            continue;
        }
        let image = mirror.zip(other_side(&name)).and_then(|(plane, other)| {
            let t = (1..n).find(|&t| names[t].as_deref() == Some(other.as_str()))?;
            Some(crate::mesh::orientation::image(plane, pivots[t]))
        });
        let keeper = match image {
            Some(at) => same
                .iter()
                .copied()
                .min_by(|&a, &b| pivots[a].distance(at).total_cmp(&pivots[b].distance(at)))
                .unwrap_or(s),
            None => s,
        };
        for &t in &same {
            if t == keeper {
                continue;
            }
            let mut next = name.clone();
            while given.contains(&next) {
                next = numbered_again(&next);
            }
            given.insert(next.clone());
            names[t] = Some(next);
        }
    }
}

/// `name` with its number one higher: the last part if it is a number, else the part
/// before its side (`ear.L` → `ear.2.L`, `hand.2.R` → `hand.3.R`), else `.2` added.
fn numbered_again(name: &str) -> String {
    let mut parts: Vec<String> = name.split('.').map(str::to_string).collect();
    let bump = |p: &str| p.parse::<u32>().ok().map(|k| (k + 1).to_string());
    if let Some((last, k)) = parts.last_mut().and_then(|p| bump(p).map(|k| (p, k))) {
        *last = k;
        return parts.join(".");
    }
    let sided = parts.last().is_some_and(|p| p == "L" || p == "R");
    if sided && parts.len() >= 2 {
        let at = parts.len() - 2;
        match bump(&parts[at]) {
            Some(k) if at > 0 => parts[at] = k,
            _ => parts.insert(at + 1, "2".into()),
        }
        return parts.join(".");
    }
    format!("{name}.2")
}

/// `base` with its side: `arm.L`; `tail` on the plane.
fn tagged(base: &str, tag: &str) -> String {
    if tag.is_empty() {
        base.to_string()
    } else {
        format!("{base}.{tag}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn a_name_numbered_again_counts_on_before_its_side() {
        assert_eq!(numbered_again("ear.L"), "ear.2.L");
        assert_eq!(numbered_again("hand.2.R"), "hand.3.R");
        assert_eq!(numbered_again("finger1.L.2"), "finger1.L.3");
        assert_eq!(numbered_again("tail"), "tail.2");
    }

    #[test]
    fn of_a_role_given_twice_the_one_mirroring_the_other_side_keeps_it() {
        let plane = (DVec3::X, 0.0);
        let pivots = [
            DVec3::ZERO,
            DVec3::new(-1.0, 2.0, 0.0),
            DVec3::new(1.0, 2.0, -0.5),
            DVec3::new(1.0, 2.0, 0.0),
        ];
        let mut names = vec![
            None,
            Some("ear.R".to_string()),
            Some("ear.L".to_string()),
            Some("ear.L".to_string()),
        ];
        unique(&mut names, &pivots, Some(plane));
        assert_eq!(names[2].as_deref(), Some("ear.2.L"));
        assert_eq!(names[3].as_deref(), Some("ear.L"));
    }

    #[test]
    fn a_side_s_name_has_its_other_side_and_a_shoulder_or_a_hip_is_a_ball() {
        assert_eq!(other_side("index.L.2").as_deref(), Some("index.R.2"));
        assert_eq!(other_side("leg1.R").as_deref(), Some("leg1.L"));
        for (role, ball) in [
            ("arm.L", true),
            ("leg", true),
            ("leg2.R", true),
            ("forearm.L", false),
            ("legs", false),
            ("ear.L", false),
            ("joint 2", false),
        ] {
            assert_eq!(is_ball_joint(role), ball, "{role}");
        }
        assert_eq!(other_side("tail.2"), None);
    }

    #[test]
    fn the_human_s_cuts_are_named_by_role_in_a_frame_facing_forward() {
        let staged = crate::joints::suggest::fixture::Staged::human();
        let count = staged.placed.cuts.len();
        let named = staged.named(None);
        assert_eq!(named.frame.up, DVec3::Y);
        assert_eq!(named.frame.front, DVec3::Z);
        assert_eq!(named.frame.left, DVec3::X);
        assert!(named.cuts.len() <= count);
        let names: Vec<&str> = named.cuts.iter().map(|c| c.name.as_str()).collect();
        for role in ["arm.L", "arm.R", "forearm.L", "leg.L", "leg.R", "shin.R"] {
            assert!(names.contains(&role), "{role} not in {names:?}");
        }
        assert!(
            names.contains(&"neck") || names.contains(&"head"),
            "{names:?}"
        );
        // Each name once; a cut's section is the root or another cut's name.
        let mut unique = names.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), names.len());
        for cut in &named.cuts {
            assert!(cut.section == "root" || names.contains(&cut.section.as_str()));
        }
        // The shoulders and hips keep their sockets under their names; nothing else.
        let mut balls: Vec<&str> = named.balls.keys().map(String::as_str).collect();
        balls.sort_unstable();
        assert_eq!(balls, ["arm.L", "arm.R", "leg.L", "leg.R"]);
        // Up given is up kept.
        let given = staged.named(Some(DVec3::Z));
        assert_eq!(given.frame.up, DVec3::Z);
    }
}
