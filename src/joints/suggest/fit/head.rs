//! A biped's head that sits on its body with no neck to cut at (Homer's, as wide as his
//! chest; a cartoon's cylinder of a head) turns at the top of its shoulders; a
//! quadruped's head and neck that nothing cuts (a wolf's, as thick as its chest all the
//! way) turn at the front of its shoulders.

use crate::joints::suggest::rules::{GROUND, RAISED, SMALLEST};
use crate::joints::{Cut, Joints, Shape};
use crate::mesh::orientation::Frame;
use crate::mesh::Mesh;
use glam::DVec3;
use std::collections::HashMap;

/// `cuts` (named by role, parent-first) with a cut across the body at the top of a biped's
/// shoulders when no cut turns its head: where `arm.L` and `arm.R` hang from the root, and
/// `leg.L` and `leg.R` from the root or from its `hips` (a pelvis cut at a waist), the arms
/// [`RAISED`] widths above the legs, and none is named `neck` or `head`. The plane lies across `up` at the top of the higher arm's ring (its cut's point
/// plus its width, from `width` by name), its pivot at the centre of the body's slice
/// there. The part above must be at least as tall as the slice is wide (a head, not the
/// top of a chest the arms leave from), and no taller than the character below it (the
/// shoulders of one standing lie above its middle).
/// The root's cuts above the plane (ears) hang from the head; with two or more it is the
/// `head`, else the `neck` (as for a head cut where it narrows).
/// A quadruped's the same way along its front (`frame`, with a mirror plane): where its
/// forelegs stand on the ground ([`GROUND`]) [`RAISED`] widths ahead of its hind legs, the
/// plane lies across the front a foreleg's width ahead of the foremost foreleg's ring, and
/// the part ahead, its `neck` with the head and ears on it, must reach at least as far as
/// the slice is wide and no farther than the body behind it. `points` are the skeletal
/// points, `blank` the joints before any cut.
pub(super) fn on_the_shoulders(
    mesh: &Mesh,
    points: &[DVec3],
    blank: &Joints,
    root: &str,
    cuts: Vec<Cut>,
    frame: &Frame,
    width: &HashMap<String, (f64, f64)>,
) -> Vec<Cut> {
    let up = frame.up;
    let smallest = (SMALLEST * points.len() as f64).max(12.0) as usize;
    let find = |name: &str, from: &[&str]| {
        cuts.iter()
            .find(|c| c.name == name && from.contains(&c.section.as_str()))
    };
    // The legs hang from the root, or from a pelvis cut from it at a waist (`hips`, below
    // a `waist` or not).
    let below: Vec<&str> = std::iter::once(root)
        .chain(
            cuts.iter()
                .filter(|c| c.name == "hips" || c.name == "waist")
                .map(|c| c.name.as_str()),
        )
        .collect();
    let (Some(arm_l), Some(arm_r), Some(leg_l), Some(leg_r)) = (
        find("arm.L", &[root]),
        find("arm.R", &[root]),
        find("leg.L", &below),
        find("leg.R", &below),
    ) else {
        return cuts;
    };
    if cuts.iter().any(|c| {
        let base = c.name.split('.').next().unwrap_or("");
        base == "neck" || base == "head"
    }) {
        return cuts;
    }
    let height = |c: &Cut| c.pivot.unwrap_or(c.point).dot(up);
    let arm_width = |c: &Cut| width.get(&c.name).map_or(0.0, |&(_, w)| w);
    let arms = 0.5 * (arm_width(arm_l) + arm_width(arm_r));
    if arms <= 0.0 {
        return cuts;
    }
    let mut joints = blank.clone();
    if joints.add_cuts_unbanded(cuts.iter().cloned()).is_err() {
        return cuts;
    }
    // A quadruped's forelegs stand on the ground ([`GROUND`]) ahead of its hind legs: its
    // head and neck reach ahead of its shoulders (a wolf's, cut nowhere else: no narrowing
    // between them). A biped's arms hang well above its legs: its head sits on top of its
    // shoulders.
    let section_of = joints.section_of();
    let sections = joints.sections();
    let (floor, top) = mesh
        .positions
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.dot(up)), hi.max(p.dot(up)))
        });
    let stands = |arm: &Cut| {
        let Some(a) = joints.find(&arm.name) else {
            return false;
        };
        let within = |mut s: usize| loop {
            if s == a {
                return true;
            }
            match sections.get(s).and_then(|x| x.parent) {
                Some(p) => s = p,
                None => return false,
            }
        };
        (0..mesh.positions.len().min(section_of.len()))
            .filter(|&v| within(section_of[v] as usize))
            .any(|v| mesh.positions[v].dot(up) <= floor + GROUND * (top - floor))
    };
    let ahead = |c: &Cut| c.pivot.unwrap_or(c.point).dot(frame.front);
    let forelegs = frame.mirror.is_some()
        && stands(arm_l)
        && stands(arm_r)
        && 0.5 * (ahead(arm_l) + ahead(arm_r) - ahead(leg_l) - ahead(leg_r)) >= RAISED * arms;
    let raised =
        0.5 * (height(arm_l) + height(arm_r) - height(leg_l) - height(leg_r)) >= RAISED * arms;
    let axis = if forelegs {
        frame.front
    } else if raised {
        up
    } else {
        return cuts;
    };
    let top_of = |c: &Cut| c.point.dot(axis) + arm_width(c);
    // A quadruped's plane a foreleg's width further ahead: at the rings' front it runs
    // through the shoulders the forelegs' bands blend, and a neck cut there swells when
    // it and a foreleg turn together.
    let at = top_of(arm_l).max(top_of(arm_r)) + if forelegs { arms } else { 0.0 };
    let Some(body) = joints.find(root) else {
        return cuts;
    };
    let of_body: Vec<DVec3> = (0..mesh.positions.len())
        .filter(|&v| section_of[v] as usize == body)
        .map(|v| mesh.positions[v])
        .collect();
    // The body's slice at the top of the shoulders: its centre, and its mean distance
    // from it across `up` (half its width).
    let ring: Vec<DVec3> = of_body
        .iter()
        .copied()
        .filter(|p| (at..=at + arms).contains(&p.dot(axis)))
        .collect();
    if ring.len() < 3 {
        return cuts;
    }
    let centre = ring.iter().copied().sum::<DVec3>() / ring.len() as f64;
    let centre = centre + axis * (at - centre.dot(axis));
    let half = ring
        .iter()
        .map(|&p| {
            let d = p - centre;
            (d - axis * d.dot(axis)).length()
        })
        .sum::<f64>()
        / ring.len() as f64;
    let top = of_body
        .iter()
        .map(|p| p.dot(axis))
        .fold(f64::NEG_INFINITY, f64::max);
    let bottom = mesh
        .positions
        .iter()
        .map(|p| p.dot(axis))
        .fold(f64::INFINITY, f64::min);
    if top - at < 2.0 * half || top - at > at - bottom {
        return cuts;
    }
    // The root's cuts above the plane (ears on the head) hang from it, and so does what
    // hangs from them.
    let above: Vec<bool> = cuts
        .iter()
        .map(|c| c.section == root && c.point.dot(axis) > at && !c.name.starts_with("arm"))
        .collect();
    // A quadruped's part ahead of its shoulders is its neck with its head on it.
    let name = if !forelegs && above.iter().filter(|&&a| a).count() >= 2 {
        "head"
    } else {
        "neck"
    };
    let neck = Cut {
        name: name.to_string(),
        section: root.to_string(),
        shape: Shape::Plane,
        point: centre,
        normal: axis,
        pivot: Some(centre),
        connected: true,
        band: None,
        shared_pivot: false,
    }
    .rounded();
    let taken = joints.preview(body, &neck).iter().filter(|&&t| t).count();
    let rest = joints.sections()[body].vertices.saturating_sub(taken);
    if taken < smallest || rest < smallest {
        return cuts;
    }
    // Parent-first: what does not hang from the head, the head, then what does.
    let mut on_head: Vec<String> = Vec::new();
    let (mut before, mut after) = (Vec::new(), Vec::new());
    for (c, &up_there) in cuts.iter().zip(&above) {
        if up_there {
            on_head.push(c.name.clone());
            after.push(Cut {
                section: name.to_string(),
                ..c.clone()
            });
        } else if on_head.contains(&c.section) {
            on_head.push(c.name.clone());
            after.push(c.clone());
        } else {
            before.push(c.clone());
        }
    }
    let out: Vec<Cut> = before
        .into_iter()
        .chain(std::iter::once(neck))
        .chain(after)
        .collect();
    let mut check = blank.clone();
    if check.add_cuts_unbanded(out.iter().cloned()).is_err() {
        return cuts;
    }
    out
}
