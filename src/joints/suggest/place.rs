//! Stage 4 of the suggestion: the limbs applied as cuts, numbered by their place in the
//! tree (`joint 1`, `joint 1.2`).
//!
//! Each cut is a connected plane through the ring's centre, across the
//! limb's axis there, its pivot on the axis; cuts apply parent-first, and one that would
//! leave a section of fewer than `SMALLEST` of the vertices, or whose plane takes more
//! than twice what lies past it in the join tree (it slipped past the limb into the
//! body), is dropped; a limb's root plane that slips so first tries the mirror image of
//! its partner's on the other side (an arm hanging closer to the body on one side), and
//! a plane that leaves its parent nothing on the other side (a leg's plane along the
//! crotch) tries its sibling's image (the other leg's from the same hips). A limb's root
//! plane that reaches through the body across its mirror plane is turned toward the
//! limb's side (by [`TURNS`]) where that leaves nothing across.

use super::limbs::Limb;
use super::rules::{MATCHED, PAIRED, SMALLEST, TURNS};
use crate::joints::{Cut, Joints, Shape};
use crate::mesh::Mesh;
use crate::skeleton::Skeleton;
use glam::DVec3;
use std::collections::HashMap;

/// Stage 4's output: the cuts that applied, and the joints they make.
pub(crate) struct Placed {
    /// The joints of the whole mesh before any cut (its edges found once), to try sets of
    /// cuts on.
    pub(crate) blank: Joints,
    /// The joints with every cut applied.
    pub(crate) joints: Joints,
    /// The cuts that applied, parent-first, numbered by their place in the tree.
    pub(crate) cuts: Vec<Cut>,
    /// Per cut, its limb's socket and width ([`Limb::socket`], [`Limb::width`]).
    pub(crate) sockets: Vec<(f64, f64)>,
}

/// `limbs` applied in order as cuts to the joints of `mesh` (its skeleton `skeleton`, its
/// riders going with `hosts`, its separate parts meeting at `attachments`) under the root
/// section `root`; `mirror`, the body's mirror plane. One that cannot apply (a side left empty) is dropped, and what hangs from it
/// hangs from its parent instead.
pub(crate) fn place(
    mesh: &Mesh,
    skeleton: &Skeleton,
    hosts: &[Option<u32>],
    attachments: &[(u32, u32)],
    root: &str,
    limbs: &[Limb],
    mirror: Option<(DVec3, f64)>,
) -> Placed {
    let mut joints = Joints::with_mesh(&skeleton.points, &mesh.triangles, hosts, root);
    joints.attach_parts(attachments);
    let blank = joints.clone();
    let mut applied: Vec<Option<String>> = Vec::with_capacity(limbs.len());
    let mut count: HashMap<String, usize> = Default::default();
    let mut cuts = Vec::new();
    // Each applied cut's limb's `socket` and width.
    let mut sockets = Vec::new();
    for limb in limbs {
        // The nearest ancestor that applied, or the root.
        let mut parent = limb.parent;
        let section = loop {
            match parent {
                Some(p) => match &applied[p] {
                    Some(name) => break name.clone(),
                    None => parent = limbs[p].parent,
                },
                None => break root.to_string(),
            }
        };
        let k = count.entry(section.clone()).or_default();
        *k += 1;
        let name = if section == root {
            format!("joint {k}")
        } else {
            format!("{section}.{k}")
        };
        let plane = |point: DVec3, normal: DVec3, pivot: DVec3| {
            Cut {
                name: name.clone(),
                section: section.clone(),
                point,
                normal,
                pivot: Some(pivot),
                connected: true,
                band: None,
                shape: Shape::Plane,
                shared_pivot: false,
            }
            .rounded()
        };
        // Too small a piece, or too little left, is no joint worth a section.
        let smallest = (SMALLEST * skeleton.points.len() as f64).max(12.0) as usize;
        let big_enough_for = |joints: &Joints, cut: &Cut, expected: usize| {
            joints.find(&cut.section).is_some_and(|s| {
                let taken = joints.preview(s, cut).iter().filter(|&&t| t).count();
                taken >= smallest
                    && joints.sections()[s].vertices - taken >= smallest
                    && taken <= 2 * expected + smallest
            })
        };
        // Its partner's plane mirrored, its partner within `within` of the mesh's size.
        let mirrored = |joints: &Joints, within: f64| {
            let m = mirror?;
            let o = partner(limbs, limb, m, within * mesh.longest_side())?;
            let image = |p: DVec3| crate::mesh::orientation::image(m, p);
            let cut = plane(
                image(o.point),
                crate::mesh::orientation::reflect(m.0, o.normal),
                image(o.pivot),
            );
            big_enough_for(joints, &cut, o.expected).then_some(cut)
        };
        // A root limb's plane that slips past it into the body (an arm hanging close to
        // it) may take the mirror image of its partner's (within `PAIRED`) instead.
        let mut cut = plane(limb.point, limb.normal, limb.pivot);
        let mut big_enough = big_enough_for(&joints, &cut, limb.expected);
        if !big_enough && limb.parent.is_none() {
            if let Some(m) = mirrored(&joints, PAIRED) {
                cut = m;
                big_enough = true;
            }
        }
        // A limb's root plane that reaches through the body across its mirror plane (a
        // shoulder's plane tilted up through the collar takes the head with the arm) is
        // turned toward the limb's side by the first of `TURNS` that leaves nothing
        // across, takes less, and still leaves both sections big enough.
        if let (true, None, Some(mirror)) = (big_enough, limb.parent, mirror) {
            let reach = |c: &Cut| {
                let s = joints.find(&c.section)?;
                let taken = joints.preview(s, c);
                let pivot = c.pivot.unwrap_or(limb.pivot);
                let across = across(mirror, pivot, 0.5 * limb.width, &skeleton.points, &taken);
                Some((taken.iter().filter(|&&t| t).count(), across))
            };
            if let Some((before, true)) = reach(&cut) {
                let pivot = cut.pivot.unwrap_or(limb.pivot);
                let side = mirror.0 * (pivot.dot(mirror.0) - mirror.1).signum();
                let turned = TURNS.iter().find_map(|&t| {
                    let normal = cut.normal.normalize_or_zero().lerp(side, t);
                    let turned = plane(cut.point, normal.normalize_or_zero(), pivot);
                    let (after, across) = reach(&turned)?;
                    (normal != DVec3::ZERO
                        && !across
                        && after < before
                        && big_enough_for(&joints, &turned, limb.expected))
                    .then_some(turned)
                });
                if let Some(turned) = turned {
                    log::debug!("suggested joint {} turned toward its side", cut.name);
                    cut = turned;
                }
            }
        }
        if !big_enough {
            *count.entry(cut.section).or_default() -= 1;
            applied.push(None);
            continue;
        }
        // One whose plane leaves nothing on the other side (a leg's plane tilted along
        // the crotch, which the hips would not keep) takes its partner's image
        // (within `MATCHED`: the legs as they hang from the hips).
        let added = match joints.add_cut_unbanded(cut.clone()) {
            Err(e) => match mirrored(&joints, MATCHED).filter(|m| *m != cut) {
                Some(m) => {
                    log::debug!(
                        "suggested joint {}: {e}; its partner's image instead",
                        cut.name
                    );
                    cut = m;
                    joints.add_cut_unbanded(cut.clone())
                }
                None => Err(e),
            },
            added => added,
        };
        match added {
            Ok(_) => {
                applied.push(Some(name));
                cuts.push(cut);
                sockets.push((limb.socket, limb.width));
            }
            Err(e) => {
                log::debug!("suggested joint dropped: {e}");
                *count.entry(cut.section).or_default() -= 1;
                applied.push(None);
            }
        }
    }
    Placed {
        blank,
        joints,
        cuts,
        sockets,
    }
}

/// Whether `taken` (per skeletal point of `points`, what a plane through `pivot` takes)
/// reaches across the mirror plane `mirror` by more than `radius`
/// ([`crate::mesh::mirror::reaches_across`]).
fn across(
    mirror: (DVec3, f64),
    pivot: DVec3,
    radius: f64,
    points: &[DVec3],
    taken: &[bool],
) -> bool {
    let taken = points
        .iter()
        .zip(taken)
        .filter(|(_, &t)| t)
        .map(|(p, _)| *p);
    crate::mesh::mirror::reaches_across(mirror, pivot, radius, taken)
}

/// The sibling of `limb` (a limb hanging from the same cut, or like it from the root)
/// whose pivot's mirror image (through `mirror`) lies nearest `limb`'s pivot, no farther
/// than `within`: two legs from the hips, two arms from the body. `None` for one nearest
/// its own image.
fn partner<'a>(
    limbs: &'a [Limb],
    limb: &Limb,
    mirror: (DVec3, f64),
    within: f64,
) -> Option<&'a Limb> {
    limbs
        .iter()
        .filter(|o| o.parent == limb.parent)
        .map(|o| {
            (
                o,
                crate::mesh::orientation::image(mirror, o.pivot).distance(limb.pivot),
            )
        })
        .filter(|&(_, d)| d <= within)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(o, _)| o)
        // (A limb on the mirror plane is its own image: it has no partner.)
        .filter(|o| !std::ptr::eq(*o, limb))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joints::suggest::fixture::Staged;

    #[test]
    fn each_limb_that_leaves_a_section_big_enough_is_a_numbered_cut() {
        let Staged {
            mesh,
            skeleton,
            body,
            limbs,
            placed,
        } = Staged::human();
        assert!(placed.blank.cuts().is_empty());
        assert_eq!(placed.joints.cuts(), &placed.cuts[..]);
        assert_eq!(placed.sockets.len(), placed.cuts.len());
        assert!(placed.cuts.len() <= limbs.len() && placed.cuts.len() >= 9);
        // Numbered by place: `joint k` on the root, `<section>.k` below it.
        for cut in &placed.cuts {
            if cut.section == "root" {
                assert!(cut.name.starts_with("joint "), "{}", cut.name);
            } else {
                assert!(
                    cut.name.starts_with(&format!("{}.", cut.section)),
                    "{}",
                    cut.name
                );
            }
        }
        let smallest = (SMALLEST * skeleton.points.len() as f64).max(12.0) as usize;
        for s in placed.joints.sections() {
            assert!(s.vertices >= smallest, "{}: {}", s.name, s.vertices);
        }
        // A limb past every vertex (nothing left beside it) is no cut.
        let mut whole = limbs[0];
        whole.point -= whole.normal * 10.0 * mesh.longest_side();
        whole.parent = None;
        let none = place(
            mesh,
            skeleton,
            &body.hosts,
            &crate::mesh::attachments(mesh),
            "root",
            &[whole],
            None,
        );
        assert!(none.cuts.is_empty());
    }

    #[test]
    fn a_shoulder_plane_reaching_through_the_body_turns_toward_its_side() {
        // The spacesuit's shoulder planes, tilted up through its collar, reach across its
        // mirror plane (they took its head and chest with an arm); placed, none does.
        let Staged {
            skeleton,
            body,
            limbs,
            placed,
            ..
        } = Staged::of("tests/data/population/man-spacesuit.glb");
        let mirror = body.cues.mirror.expect("the spacesuit is mirrored");
        let reaches = |cut: &Cut, width: f64| {
            let taken = placed.blank.preview(0, cut);
            let pivot = cut.pivot.expect("a suggested cut has its pivot");
            across(mirror, pivot, 0.5 * width, &skeleton.points, &taken)
        };
        let planes = limbs.iter().filter(|l| l.parent.is_none()).filter(|l| {
            let cut = Cut {
                pivot: Some(l.pivot),
                connected: true,
                ..Cut::plane("limb", "root", l.point, l.normal)
            };
            reaches(&cut, l.width)
        });
        assert!(planes.count() >= 1);
        for (cut, &(_, width)) in placed.cuts.iter().zip(&placed.sockets) {
            if cut.section == "root" {
                assert!(!reaches(cut, width), "{} reaches across", cut.name);
            }
        }
    }

    #[test]
    fn a_leg_plane_that_leaves_nothing_beside_it_takes_its_partners_image() {
        // Woman-casual's right leg: its plane from stage 3 runs along the crotch and
        // leaves the hips no skeletal point on their side, so the cut would not apply
        // and the leg would turn only at the knee. Both legs hang from the hips, mirror
        // images of each other.
        let Staged { body, placed, .. } = Staged::of("tests/data/population/woman-casual.glb");
        let mirror = body.cues.mirror.expect("woman-casual is mirrored");
        let image = |p: DVec3| crate::mesh::orientation::image(mirror, p);
        let nested = |c: &&Cut| c.section != "root";
        let paired = placed.cuts.iter().filter(nested).any(|a| {
            let (pa, qa) = (a.pivot.unwrap_or(a.point), a.point);
            placed.cuts.iter().filter(nested).any(|b| {
                let pb = b.pivot.unwrap_or(b.point);
                b.name != a.name
                    && b.section == a.section
                    && image(pa).distance(pb) < 1e-3
                    && image(qa).distance(b.point) < 1e-3
                    && (pa - pb).length() > 0.1
            })
        });
        assert!(paired, "{:#?}", placed.cuts);
    }
}
