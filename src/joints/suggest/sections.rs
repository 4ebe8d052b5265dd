//! Step 4 of the module docs: the cuts found, numbered by their place in the tree and
//! applied parent-first; one that leaves too small a section, or slips past its limb, is
//! dropped. Then (step 5, `anatomy`) they are named by role.

use super::cuts::Limb;
use super::frame::Frame;
use super::rules::{PAIRED, SMALLEST, STANDING};
use super::tree::Tree;
use crate::joints::{Cut, Joints, Shape};
use crate::mesh::Mesh;
use crate::skeleton::Skeleton;
use glam::DVec3;
use std::collections::HashMap;

/// The cuts' places, from what stands on a flat base ([`STANDING`]), else from the root
/// found, or from the body when that root is a big head on it ([`Tree::body_elsewhere`]).
fn limbs_of(
    mesh: &Mesh,
    skeleton: &Skeleton,
    mirror: Option<(DVec3, f64)>,
    base: Option<DVec3>,
) -> Vec<Limb> {
    if let Some(root) = base.and_then(|down| on_the_base(mesh, &skeleton.distance, down)) {
        return Tree::rooted(mesh, skeleton, Some(root)).limbs(mirror);
    }
    let tree = Tree::new(mesh, skeleton);
    let limbs = tree.limbs(mirror);
    let Some((root, body)) = tree.body_elsewhere(&limbs) else {
        return limbs;
    };
    let mut out = Tree::rooted(mesh, skeleton, Some(root)).limbs(mirror);
    // The head the tree was first rooted in turns at the cut that hung the body from it,
    // the other way round, unless a cut from the body near there already takes it; what
    // hangs from the body past that cut hangs from the head.
    let head = tree.core.0;
    let past = |l: &Limb, p: DVec3| (p - l.point).dot(l.normal) > 0.0;
    if out.iter().any(|l| {
        l.parent.is_none() && past(l, head) && l.point.distance(body.point) < 2.0 * body.width
    }) {
        return out;
    }
    let neck = Limb {
        parent: None,
        normal: -body.normal,
        expected: mesh
            .positions
            .iter()
            .filter(|&&p| (p - body.point).dot(body.normal) < 0.0)
            .count(),
        past: None,
        socket: 0.0,
        ..body
    };
    super::cuts::put_first(&mut out, neck);
    out
}

/// The vertex with the largest skeletal distance `radius` within [`STANDING`] of the mesh's
/// height above its flat base, whose outward normal is `down`.
fn on_the_base(mesh: &Mesh, radius: &[f64], down: DVec3) -> Option<usize> {
    let height = |v: usize| -mesh.positions[v].dot(down);
    let (low, high) = (0..mesh.positions.len())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(height(v)), hi.max(height(v)))
        });
    let top = low + STANDING * (high - low);
    (0..radius.len().min(mesh.positions.len()))
        .filter(|&v| height(v) <= top)
        .max_by(|&a, &b| radius[a].total_cmp(&radius[b]))
}

/// The root limb whose pivot's mirror image (through `mirror`) lies nearest root limb
/// `limb`'s pivot, within [`PAIRED`] of the mesh's `size`; `None` for a nested limb and
/// for one nearest its own image.
fn partner<'a>(
    limbs: &'a [Limb],
    limb: &Limb,
    mirror: (DVec3, f64),
    size: f64,
) -> Option<&'a Limb> {
    if limb.parent.is_some() {
        return None;
    }
    limbs
        .iter()
        .filter(|o| o.parent.is_none())
        .map(|o| (o, super::frame::image(mirror, o.pivot).distance(limb.pivot)))
        .filter(|&(_, d)| d <= PAIRED * size)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(o, _)| o)
        // (A limb on the mirror plane is its own image: it has no partner.)
        .filter(|o| !std::ptr::eq(*o, limb))
}

/// Cuts where the protrusions of `mesh` narrow, organised parent-first as a section tree
/// under the root section `root`, named by role where one fits, and the frame (up, front,
/// left) they were named in: `up` when given, else found. Every cut applies, in order, to
/// joints without cuts. Two or more characters in the file (body parts apart from each
/// other) each get their own cuts, the largest's names as they are and the others' with
/// `.001`, `.002`… (see `characters`); the frame is the largest's.
pub fn suggest(
    mesh: &Mesh,
    skeleton: &Skeleton,
    root: &str,
    up: Option<DVec3>,
) -> (Vec<Cut>, Frame) {
    let Some(characters) = super::characters::of(mesh, skeleton) else {
        return suggest_one(mesh, skeleton, root, up);
    };
    let mut all = Vec::new();
    let mut first = None;
    for (k, c) in characters.iter().enumerate() {
        let (cuts, frame) = suggest_one(&c.mesh, &c.skeleton, root, up);
        first.get_or_insert(frame);
        let named = |n: &str| super::characters::name(n, k, root);
        all.extend(cuts.into_iter().map(|cut| Cut {
            name: named(&cut.name),
            section: named(&cut.section),
            ..cut
        }));
    }
    match first {
        Some(frame) => (all, frame),
        None => suggest_one(mesh, skeleton, root, up),
    }
}

/// [`suggest`] for one character.
fn suggest_one(
    mesh: &Mesh,
    skeleton: &Skeleton,
    root: &str,
    up: Option<DVec3>,
) -> (Vec<Cut>, Frame) {
    // The mirror plane and the flat base, once: the cuts copy across the plane, the tree
    // stands on the base, and the names take their sides and up from both. (The body's: a
    // prop riding apart from it says nothing of its symmetry.)
    let riders = (skeleton.riders > 0).then(|| {
        let parts = crate::mesh::Parts::of(mesh);
        let (body, old) = parts.body(mesh);
        (parts, body, old)
    });
    let shape = riders.as_ref().map_or(mesh, |(_, body, _)| body);
    let mirror = super::frame::mirror_plane(&shape.positions);
    let base = super::frame::flat_base(shape);
    // Riders have no skeleton: the limbs are the body's, and riders go with their hosts.
    let (limbs, hosts) = if let Some((parts, body, old)) = riders {
        let body_skeleton = Skeleton {
            distance: old.iter().map(|&v| skeleton.distance[v as usize]).collect(),
            points: old.iter().map(|&v| skeleton.points[v as usize]).collect(),
            riders: 0,
            ..skeleton.clone()
        };
        let limbs = limbs_of(&body, &body_skeleton, mirror, base);
        (limbs, parts.hosts(&mesh.positions))
    } else {
        (limbs_of(mesh, skeleton, mirror, base), Vec::new())
    };
    // The character's shape for naming: each rider where its host is (a prop lying apart
    // from the body would stretch its size and move its centre).
    let character = if hosts.iter().any(Option::is_some) {
        std::borrow::Cow::Owned(Mesh {
            positions: (0..mesh.positions.len())
                .map(|v| mesh.positions[hosts[v].map_or(v, |h| h as usize)])
                .collect(),
            triangles: mesh.triangles.clone(),
        })
    } else {
        std::borrow::Cow::Borrowed(mesh)
    };
    let character: &Mesh = &character;
    // Apply them in order; one that cannot apply (a side left empty) is dropped and what
    // hangs from it hangs from its parent instead.
    let mut joints = Joints::with_mesh(&skeleton.points, &mesh.triangles, &hosts, root);
    joints.attach_parts(&crate::mesh::attachments(mesh));
    // The joints before any cut, to try sets of cuts on (its mesh's edges found once).
    let blank = joints.clone();
    let mut applied: Vec<Option<String>> = Vec::with_capacity(limbs.len());
    let mut count: HashMap<String, usize> = Default::default();
    let mut cuts = Vec::new();
    // Each applied cut's limb's `socket` and width.
    let mut sockets = Vec::new();
    for limb in &limbs {
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
        let big_enough_for = |cut: &Cut, expected: usize| {
            joints.find(&cut.section).is_some_and(|s| {
                let taken = joints.preview(s, cut).iter().filter(|&&t| t).count();
                taken >= smallest
                    && joints.sections()[s].vertices - taken >= smallest
                    && taken <= 2 * expected + smallest
            })
        };
        // A limb's root plane that slips past it into the body (an arm hanging close to
        // it) may take the mirror image of its partner's on the other side instead.
        let mut cut = plane(limb.point, limb.normal, limb.pivot);
        let mut big_enough = big_enough_for(&cut, limb.expected);
        if let (false, Some(m)) = (big_enough, mirror) {
            if let Some(o) = partner(&limbs, limb, m, mesh.longest_side()) {
                let image = |p: DVec3| super::frame::image(m, p);
                let mirrored = plane(
                    image(o.point),
                    super::frame::reflect(m.0, o.normal),
                    image(o.pivot),
                );
                if big_enough_for(&mirrored, o.expected) {
                    cut = mirrored;
                    big_enough = true;
                }
            }
        }
        if !big_enough {
            *count.entry(cut.section).or_default() -= 1;
            applied.push(None);
            continue;
        }
        match joints.add_cut_unbanded(cut.clone()) {
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
    // Names by role; a name taken twice, and a cut no role fits, keep their numbers.
    let roles = super::anatomy::roles(character, &skeleton.distance, &joints, up, mirror, base);
    let frame = roles.frame;
    let mut renamed: HashMap<String, String> = HashMap::new();
    let mut taken: std::collections::HashSet<String> = Default::default();
    // The shoulders' and hips' sockets and widths, by their final names.
    let mut ball: HashMap<String, (f64, f64)> = HashMap::new();
    for (k, cut) in cuts.iter().enumerate() {
        if let Some(role) = roles.names.get(k + 1).cloned().flatten() {
            let is_ball = super::anatomy::is_ball_joint(&role);
            if role != root && taken.insert(role.clone()) {
                renamed.insert(cut.name.clone(), role.clone());
                if is_ball {
                    ball.insert(role, sockets[k]);
                }
            } else if is_ball {
                ball.insert(cut.name.clone(), sockets[k]);
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
    // Left and right mirror each other where they nearly do: at their mean; where that
    // leaves a side empty, the right as the left's image, or the left as the right's; else
    // each keeps its own place. (A cut that fails was moved, or a moved cut before it moved
    // its section: the nearest moved one tries its pair's next way.)
    let pairs = mirror_pairs(&cuts, &frame, character);
    let mut way = vec![0usize; pairs.len()];
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
        let Some(bad) = trial
            .iter()
            .position(|c| check.add_cut_unbanded(c.clone()).is_err())
        else {
            cuts = trial;
            break;
        };
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
    let smallest = (SMALLEST * skeleton.points.len() as f64).max(12.0) as usize;
    cuts = to_the_body(mesh, &blank, cuts, &ball, smallest);
    // A shoulder or a hip turns about the ball inside the trunk, past the cut; a left and a
    // right one by the same depth, so that a mirrored pair stays mirrored.
    for cut in &mut cuts {
        let Some(&(own, _)) = ball.get(&cut.name) else {
            continue;
        };
        let depth = super::anatomy::other_side(&cut.name)
            .and_then(|o| ball.get(&o))
            .map_or(own, |&(o, _)| 0.5 * (own + o));
        *cut = Cut {
            pivot: cut.pivot.map(|p| p - cut.normal * depth),
            ..cut.clone()
        }
        .rounded();
    }
    // A biped's head on its body with no neck to cut at turns at the top of its shoulders.
    let cuts = super::head::on_the_shoulders(
        character,
        &skeleton.points,
        &blank,
        root,
        cuts,
        frame.up,
        &ball,
    );
    (cuts, frame)
}

/// `cuts` with each shoulder's and hip's (`ball`: its socket and width, by name) moved
/// toward the body along its normal as far as [`super::slice::Slicer::toward_body`] allows, a left
/// and a right one by the lesser of their two distances; one that then takes more than
/// twice its section's vertices (it slipped into the body) or cannot apply stays. `blank`:
/// the mesh's joints before any cut, which the cuts are tried on.
fn to_the_body(
    mesh: &Mesh,
    blank: &Joints,
    cuts: Vec<Cut>,
    ball: &HashMap<String, (f64, f64)>,
    smallest: usize,
) -> Vec<Cut> {
    if !cuts.iter().any(|c| ball.contains_key(&c.name)) {
        return cuts;
    }
    let slicer = super::slice::Slicer::new(mesh);
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
    let sizes = |cuts: &[Cut]| -> Option<Vec<usize>> {
        let mut joints = blank.clone();
        joints.add_cuts_unbanded(cuts.iter().cloned()).ok()?;
        cuts.iter()
            .map(|c| Some(joints.sections()[joints.find(&c.name)?].vertices))
            .collect()
    };
    let Some(before) = sizes(&cuts) else {
        return cuts;
    };
    let moved = |skip: &[&str]| -> Vec<Cut> {
        cuts.iter()
            .map(|c| {
                let Some(&t) = far.get(c.name.as_str()) else {
                    return c.clone();
                };
                let partner = super::anatomy::other_side(&c.name);
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

/// A left and a right cut that nearly mirror each other, and the ways to make them mirror
/// each other exactly, in order of preference.
struct Pair {
    left: usize,
    right: usize,
    ways: Vec<(Cut, Cut)>,
}

/// The pairs of cuts named alike but for `L` and `R` whose pivots already lie within
/// [`PAIRED`] of the mesh's size of each other's mirror image; each can be moved to the
/// mean of the one and the other's image, or one to the other's image.
fn mirror_pairs(cuts: &[Cut], frame: &Frame, mesh: &Mesh) -> Vec<Pair> {
    let Some((n, o)) = frame.mirror else {
        return Vec::new();
    };
    let point = |p: DVec3| super::frame::image((n, o), p);
    let vector = |v: DVec3| super::frame::reflect(n, v);
    let size = mesh.longest_side();
    let index: HashMap<&str, usize> = cuts
        .iter()
        .enumerate()
        .map(|(k, c)| (c.name.as_str(), k))
        .collect();
    // `a` moved to (point, normal, pivot), and `b` to its image.
    let placed = |a: &Cut, b: &Cut, at: DVec3, normal: DVec3, pivot: DVec3| {
        (
            Cut {
                point: at,
                normal,
                pivot: Some(pivot),
                ..a.clone()
            }
            .rounded(),
            Cut {
                point: point(at),
                normal: vector(normal),
                pivot: Some(point(pivot)),
                ..b.clone()
            }
            .rounded(),
        )
    };
    let mut out = Vec::new();
    for (i, a) in cuts.iter().enumerate() {
        if !a.name.split('.').any(|w| w == "L") {
            continue;
        }
        let Some(other) = super::anatomy::other_side(&a.name) else {
            continue;
        };
        let Some(&j) = index.get(other.as_str()) else {
            continue;
        };
        let b = &cuts[j];
        let (pa, pb) = (a.pivot.unwrap_or(a.point), b.pivot.unwrap_or(b.point));
        if pa.distance(point(pb)) > PAIRED * size {
            continue;
        }
        let mean = placed(
            a,
            b,
            0.5 * (a.point + point(b.point)),
            (a.normal + vector(b.normal)).normalize_or(a.normal),
            0.5 * (pa + point(pb)),
        );
        let left = placed(a, b, a.point, a.normal, pa);
        let (b2, a2) = placed(b, a, b.point, b.normal, pb);
        out.push(Pair {
            left: i,
            right: j,
            ways: vec![mean, left, (a2, b2)],
        });
    }
    out
}
