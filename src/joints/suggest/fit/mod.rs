//! Stage 6 of the suggestion: the named cuts fitted to the body.
//!
//! * **Pairs.** A left and a right cut that nearly mirror each other (`PAIRED`) are made to
//!   mirror each other exactly: at their mean, or, where that leaves a side empty, one as
//!   the other's image; a pair that cannot keeps its places, and the others are still
//!   mirrored (`pairs`).
//! * **Shoulders and hips.** Their cuts move toward the body while the mesh's slice around
//!   them stays within `ROUND` of the limb's width, up to where the limb meets the trunk (a
//!   left and a right one by the same distance: `body`, `slice`); each turns about the ball
//!   inside the trunk, `SOCKET` of a radius in from there.
//! * **A head on the shoulders.** A biped (arms hanging well above its legs) whose head
//!   nothing cuts, a head as wide as the chest it sits on (Homer's), is cut across up at the
//!   top of its shoulders, when what lies above is at least as tall as the slice there is
//!   wide and no taller than the character below it; the ears on it turn with it. A
//!   quadruped (forelegs standing well ahead of its hind legs) whose head nothing cuts (a
//!   wolf's, as thick as its chest all the way) is cut across its front a foreleg's width
//!   ahead of its shoulders: its `neck`, with the head and ears on it (`head`).

mod body;
mod head;
mod pairs;
mod slice;

use super::names::{other_side, Named};
use super::rules::SMALLEST;
use crate::joints::{Cut, Joints};
use crate::mesh::Mesh;
use glam::DVec3;

/// The cuts of `named` fitted to the body: `mesh` the whole mesh, `character` its shape
/// for naming (each rider where its host is), `points` its skeletal points, `blank` its
/// joints before any cut, `root` the root section's name.
pub(crate) fn fit(
    mesh: &Mesh,
    character: &Mesh,
    points: &[DVec3],
    blank: &Joints,
    root: &str,
    named: &Named,
) -> Vec<Cut> {
    let Named { cuts, frame, balls } = named;
    let mut cuts = cuts.clone();
    // Left and right mirror each other where they nearly do: at their mean; where that
    // leaves a side empty, the right as the left's image, or the left as the right's; else
    // each keeps its own place. (A cut that fails was moved, or a moved cut before it moved
    // its section: the nearest moved one tries its pair's next way.)
    let pairs = pairs::mirror_pairs(&cuts, frame, character);
    let mut way = vec![0usize; pairs.len()];
    // The joints with every cut applied, once a set of pairs is taken (the next step
    // measures the sections on them).
    let mut applied: Option<Joints> = None;
    loop {
        let mut trial = cuts.clone();
        for (p, pair) in pairs.iter().enumerate() {
            if let Some((a, b)) = pair.ways.get(way[p]) {
                trial[pair.left] = a.clone();
                trial[pair.right] = b.clone();
            }
        }
        if trial == cuts {
            break;
        }
        let mut check = blank.clone();
        if check.add_cuts_unbanded(trial.iter().cloned()).is_ok() {
            cuts = trial;
            applied = Some(check);
            break;
        }
        // The cut that failed: those before it applied.
        let bad = check.cuts().len();
        let Some(p) = (0..=bad)
            .rev()
            .filter(|&k| trial[k] != cuts[k])
            .find_map(|k| pairs.iter().position(|q| q.left == k || q.right == k))
        else {
            break;
        };
        way[p] += 1;
    }
    // A shoulder's or a hip's cut moves toward the body up to where the limb meets the
    // trunk; a left and a right one by the same distance.
    let smallest = (SMALLEST * points.len() as f64).max(12.0) as usize;
    cuts = body::to_the_body(mesh, blank, applied.as_ref(), cuts, balls, smallest);
    // A shoulder or a hip turns about the ball inside the trunk, past the cut; a left and a
    // right one by the same depth, so that a mirrored pair stays mirrored.
    for cut in &mut cuts {
        let Some(&(own, _)) = balls.get(&cut.name) else {
            continue;
        };
        let depth = other_side(&cut.name)
            .and_then(|o| balls.get(&o))
            .map_or(own, |&(o, _)| 0.5 * (own + o));
        *cut = Cut {
            pivot: cut.pivot.map(|p| p - cut.normal * depth),
            ..cut.clone()
        }
        .rounded();
    }
    // A biped's head on its body with no neck to cut at turns at the top of its shoulders;
    // a quadruped's head and neck that nothing cuts, ahead of them.
    head::on_the_shoulders(character, points, blank, root, cuts, frame, balls)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joints::suggest::fixture::Staged;
    use crate::mesh::orientation::image;

    #[test]
    fn pairs_mirror_exactly_and_shoulders_turn_inside_the_trunk() {
        let staged = Staged::human();
        let (mesh, skeleton, body, placed) =
            (staged.mesh, staged.skeleton, &staged.body, &staged.placed);
        let named = staged.named(None);
        let cuts = fit(
            mesh,
            &body.character,
            &skeleton.points,
            &placed.blank,
            "root",
            &named,
        );
        let find = |cuts: &[Cut], name: &str| {
            cuts.iter()
                .find(|c| c.name == name)
                .cloned()
                .unwrap_or_else(|| panic!("no {name}"))
        };
        let plane = named.frame.mirror.expect("mirrored");
        let size = mesh.longest_side();
        for (l, r) in [
            ("arm.L", "arm.R"),
            ("leg.L", "leg.R"),
            ("forearm.L", "forearm.R"),
        ] {
            let (a, b) = (find(&cuts, l), find(&cuts, r));
            let (pa, pb) = (a.pivot.unwrap_or(a.point), b.pivot.unwrap_or(b.point));
            assert!(
                pa.distance(image(plane, pb)) < 1e-6 * size,
                "{l}: {pa} {pb}"
            );
            assert!(a.point.distance(image(plane, b.point)) < 1e-6 * size, "{l}");
        }
        // A shoulder's and a hip's pivot moves into the trunk, past where it was named.
        for name in ["arm.L", "leg.R"] {
            let (before, after) = (find(&named.cuts, name), find(&cuts, name));
            let (Some(p0), Some(p1)) = (before.pivot, after.pivot) else {
                panic!("{name} has no pivot");
            };
            assert!((p1 - p0).dot(after.normal) < 0.0, "{name}: {p0} -> {p1}");
        }
        // Every fitted cut still applies to the blank joints.
        let mut joints = placed.blank.clone();
        assert!(joints.add_cuts_unbanded(cuts.iter().cloned()).is_ok());
    }
}
