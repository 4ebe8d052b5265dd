//! A shoulder's or a hip's cut moved toward the body, up to where the limb meets the trunk.

use super::other_side;
use super::slice::Slicer;
use crate::joints::{Cut, Joints};
use crate::mesh::Mesh;
use std::collections::HashMap;

/// `cuts` with each shoulder's and hip's (`ball`: its socket and width, by name) moved
/// toward the body along its normal as far as [`Slicer::toward_body`] allows, a left
/// and a right one by the lesser of their two distances; one that then takes more than
/// twice its section's vertices (it slipped into the body) or cannot apply stays. `blank`:
/// the mesh's joints before any cut, which the cuts are tried on; `applied`, those joints
/// with `cuts` applied, when the caller has them.
pub(super) fn to_the_body(
    mesh: &Mesh,
    blank: &Joints,
    applied: Option<&Joints>,
    cuts: Vec<Cut>,
    ball: &HashMap<String, (f64, f64)>,
    smallest: usize,
) -> Vec<Cut> {
    if !cuts.iter().any(|c| ball.contains_key(&c.name)) {
        return cuts;
    }
    let slicer = Slicer::new(mesh);
    let far: HashMap<&str, f64> = cuts
        .iter()
        .filter_map(|c| {
            let &(_, width) = ball.get(&c.name)?;
            let t = slicer.toward_body(c.point, c.normal, width);
            (t > 0.0).then_some((c.name.as_str(), t))
        })
        .collect();
    if far.is_empty() {
        return cuts;
    }
    // Each cut's section's vertices, once all apply.
    let sizes_on = |joints: &Joints, cuts: &[Cut]| -> Option<Vec<usize>> {
        cuts.iter()
            .map(|c| Some(joints.sections()[joints.find(&c.name)?].vertices))
            .collect()
    };
    let sizes = |cuts: &[Cut]| -> Option<Vec<usize>> {
        let mut joints = blank.clone();
        joints.add_cuts_unbanded(cuts.iter().cloned()).ok()?;
        sizes_on(&joints, cuts)
    };
    let before = match applied {
        Some(joints) => sizes_on(joints, &cuts),
        None => sizes(&cuts),
    };
    let Some(before) = before else {
        return cuts;
    };
    let moved = |skip: &[&str]| -> Vec<Cut> {
        cuts.iter()
            .map(|c| {
                let Some(&t) = far.get(c.name.as_str()) else {
                    return c.clone();
                };
                let partner = other_side(&c.name);
                let t = match partner.as_deref() {
                    Some(o) if ball.contains_key(o) => t.min(far.get(o).copied().unwrap_or(0.0)),
                    _ => t,
                };
                if t <= 0.0
                    || skip.contains(&c.name.as_str())
                    || partner.as_deref().is_some_and(|o| skip.contains(&o))
                {
                    return c.clone();
                }
                Cut {
                    point: c.point - c.normal * t,
                    pivot: c.pivot.map(|p| p - c.normal * t),
                    ..c.clone()
                }
                .rounded()
            })
            .collect()
    };
    // Moves that slip into the body stay where they were, one at a time.
    let mut skip: Vec<&str> = Vec::new();
    loop {
        let trial = moved(&skip);
        let bad = sizes(&trial).map_or_else(
            || trial.iter().zip(&cuts).position(|(a, b)| a != b),
            |after| {
                (0..trial.len())
                    .find(|&k| trial[k] != cuts[k] && after[k] > 2 * before[k] + smallest)
            },
        );
        match bad {
            None => return trial,
            Some(k) if !skip.contains(&cuts[k].name.as_str()) => skip.push(cuts[k].name.as_str()),
            Some(_) => return cuts,
        }
    }
}
