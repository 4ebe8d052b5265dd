//! Seams, once the suggested cuts apply: a section that meets a section it is not related to (neither its
//! parent, nor its child, nor a sibling) over a large share of its seam loses its cut.
//! Two such sections turn each on its own with no band between them, and the skin where
//! they meet tears: a lion statue's chain of "jaws" each touching the body (93×), toes
//! meeting a shin past the foot (13×). Measured on the sections as the puppet has them
//! (whole over the surface, with the mesh's attachments), once the cuts apply.
//!
//! Next, a section that meets its parent along two loops rather than one ([`TWICE`]: a
//! lion statue's hind legs standing on its pedestal) loses its cut: turned about one
//! loop, it tears the other, however far a random pose turns it.
//!
//! Then, **tears** ([`keep_whole`]): the joints are turned through [`TRIALS`] random poses
//! (the spread `puppet bench poses` uses, other seeds) and the surface is taken where the
//! bones would hold it (each vertex moved by its transform). An edge stretched past
//! [`TEAR`] is torn, not bent: two sections joined in two places (a body standing on a
//! pedestal by four legs, turned about one), or a section whose seam lies far from the
//! band that should blend it. Each torn edge counts against the deeper of its two
//! sections; the section with the most loses its cut, and the poses are drawn again until
//! none tears.
//!
//! Last, **balloons** ([`super::balloon`]): a joint that, turned alone, changes its own
//! section's volume or its parent's by more than [`super::rules::BALLOON`] of its size
//! loses its cut, the largest first.

use super::rules::{FOREIGN, TEAR, TRIALS, TWICE};
use crate::joints::spread::{random_pose, Spread};
use crate::joints::{Cut, JointError, Joints, PoseScratch};
use crate::random::SplitMix;
use glam::DVec3;

/// Adds the suggested `cuts` to `joints`, then takes back, one at a time, the cut of the
/// deeper section of the unrelated pair with the largest shared seam at or above
/// [`FOREIGN`], then of each section joined to its parent twice ([`TWICE`]), then those
/// [`keep_whole`] removes, and then those that balloon ([`super::balloon`]); returns the
/// names taken back.
/// The bands are worked out once the seams are settled (those need only the sections),
/// then again for each cut a tear or a balloon takes back. A cut that does not fit (a
/// side left empty: a character of a file with several, fitted on its own mesh) is taken
/// back first, and the cuts of the section it would have made go to the section it cuts:
/// a suggestion always applies.
pub fn add(joints: &mut Joints, cuts: Vec<Cut>) -> Vec<String> {
    let mut removed = Vec::new();
    let mut instead: std::collections::HashMap<String, String> = Default::default();
    for mut cut in cuts {
        if let Some(section) = instead.get(&cut.section) {
            cut.section = section.clone();
        }
        if joints.add_cut_unbanded(cut.clone()).is_err() {
            instead.insert(cut.name.clone(), cut.section);
            removed.push(cut.name);
        }
    }
    log_taken_back("it does not fit", &removed);
    let foreign = remove_while(joints, foreign, Joints::remove_cut_unbanded);
    let twice = remove_while(joints, joined_twice, Joints::remove_cut_unbanded);
    log_taken_back("it meets a section it is not joined to", &foreign);
    log_taken_back("it meets its parent twice", &twice);
    removed.extend(foreign);
    removed.extend(twice);
    joints.refresh_bands();
    let torn = keep_whole(joints);
    log_taken_back("its skin tears in random poses", &torn);
    removed.extend(torn);
    let ballooned = remove_while(joints, super::balloon::ballooned, Joints::remove_cut);
    log_taken_back("turned, a section's volume balloons", &ballooned);
    removed.extend(ballooned);
    removed
}

/// Says at debug level which suggested cuts were taken back, and why.
fn log_taken_back(why: &str, names: &[String]) {
    if !names.is_empty() {
        log::debug!("suggested joints taken back ({why}): {names:?}");
    }
}

/// The name of the section that loses its cut next, if any.
fn foreign(joints: &Joints) -> Option<String> {
    let sections = joints.sections();
    let of = joints.section_of();
    let parent = |s: usize| sections[s].parent;
    let related = |a: usize, b: usize| {
        parent(a) == Some(b)
            || parent(b) == Some(a)
            || (parent(a).is_some() && parent(a) == parent(b))
    };
    let depth = |mut s: usize| {
        let mut d = 0;
        while let Some(p) = parent(s) {
            d += 1;
            s = p;
        }
        d
    };
    let mut seam = vec![0usize; sections.len()];
    let mut shared: std::collections::HashMap<(usize, usize), usize> = Default::default();
    for a in 0..of.len() {
        for &b in joints.body.neighbours(a) {
            let b = b as usize;
            let (sa, sb) = (of[a] as usize, of[b] as usize);
            if a >= b || sa == sb {
                continue;
            }
            seam[sa] += 1;
            seam[sb] += 1;
            if !related(sa, sb) {
                *shared.entry((sa.min(sb), sa.max(sb))).or_default() += 1;
            }
        }
    }
    let ((a, b), share) = shared
        .into_iter()
        .map(|(pair, n)| {
            (
                pair,
                n as f64 / seam[pair.0].min(seam[pair.1]).max(1) as f64,
            )
        })
        .filter(|&(_, share)| share >= FOREIGN)
        .max_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)))?;
    let deeper = if (depth(b), b) > (depth(a), a) { b } else { a };
    log::debug!(
        "'{}' and '{}' meet over {:.0} % of the shorter seam",
        sections[a].name,
        sections[b].name,
        100.0 * share
    );
    // The root has no cut to lose (it is never the deeper of an unrelated pair).
    parent(deeper).map(|_| sections[deeper].name.clone())
}

/// The seed of the first trial pose: far from `puppet bench poses`'s (1 on), so the bench
/// measures poses this check never saw.
const FIRST_SEED: u64 = 1 << 32;

/// Removes, one at a time, the cut of the section that the most torn edges count against
/// (see the module docs); returns the names of the cuts removed. Without rest positions
/// or mesh edges it removes nothing.
pub fn keep_whole(joints: &mut Joints) -> Vec<String> {
    remove_while(joints, torn, Joints::remove_cut)
}

/// Removes the cut `next` names by `remove`, one at a time, while it names one (at most
/// as many as there are cuts); returns the names removed.
fn remove_while(
    joints: &mut Joints,
    next: fn(&Joints) -> Option<String>,
    remove: fn(&mut Joints, &str) -> Result<(), JointError>,
) -> Vec<String> {
    let mut removed = Vec::new();
    for _ in 0..joints.cuts().len() {
        let Some(name) = next(joints) else {
            break;
        };
        if remove(joints, &name).is_err() {
            break;
        }
        removed.push(name);
    }
    removed
}

/// The name of the section that loses its cut next for tearing, if any.
fn torn(joints: &Joints) -> Option<String> {
    let body = &joints.body;
    let rest = &body.rest;
    let of = joints.section_of();
    let n = of.len();
    if rest.len() != n || joints.cuts().is_empty() {
        return None;
    }
    let rank = joints.contact_ranks();
    let mut blame = vec![0usize; joints.sections().len()];
    let mut scratch = PoseScratch::first_order();
    let mut now = vec![DVec3::ZERO; n];
    for trial in 0..TRIALS {
        let local = random_pose(joints, Spread::default(), &mut SplitMix(FIRST_SEED + trial));
        now.copy_from_slice(rest);
        joints.held_surface(&local, &mut scratch, &mut now);
        for a in 0..n {
            for &b in body.neighbours(a) {
                let b = b as usize;
                let r = rest[a].distance(rest[b]);
                if b > a && r > 0.0 && now[a].distance(now[b]) > TEAR * r {
                    // The deeper section (by depth, then index) of the two.
                    let s = if rank[usize::from(of[b])] > rank[usize::from(of[a])] {
                        of[b]
                    } else {
                        of[a]
                    };
                    blame[usize::from(s)] += 1;
                }
            }
        }
    }
    // The root has no cut to lose.
    let worst = (1..blame.len()).max_by_key(|&s| (blame[s], s))?;
    (blame[worst] > 0).then(|| joints.sections()[worst].name.clone())
}

/// The name of the section joined to its parent in two places ([`TWICE`]) that loses its
/// cut next, if any: the one with the largest second loop, by share.
pub fn joined_twice(joints: &Joints) -> Option<String> {
    let sections = joints.sections();
    let of = joints.section_of();
    let mut loops = super::union_find::UnionFind::new(of.len());
    // Each seam edge between a section and its parent: the section and one end.
    let mut seam = Vec::new();
    for a in 0..of.len() {
        for &b in joints.body.neighbours(a) {
            let b = b as usize;
            let (sa, sb) = (usize::from(of[a]), usize::from(of[b]));
            let child = if sections[sa].parent == Some(sb) {
                sa
            } else if sections[sb].parent == Some(sa) {
                sb
            } else {
                continue;
            };
            if a < b {
                // Each end's neighbours too: a ring crossing a vertex of a third section
                // stays one loop.
                for &c in joints
                    .body
                    .neighbours(a)
                    .iter()
                    .chain(joints.body.neighbours(b))
                {
                    loops.union(a, c as usize);
                }
                loops.union(a, b);
                seam.push((child, a));
            }
        }
    }
    // The mesh's pieces: a cut across two pieces meets its parent along a loop on each,
    // and is joined once on each (counted over the whole seam, a witch in the population
    // lost a cut across two pieces).
    let mut pieces = super::union_find::UnionFind::new(of.len());
    for t in &joints.body.triangles {
        pieces.union(t[0] as usize, t[1] as usize);
        pieces.union(t[1] as usize, t[2] as usize);
    }
    let mut edges: std::collections::HashMap<(usize, usize, usize), usize> = Default::default();
    for (s, a) in seam {
        *edges.entry((s, pieces.find(a), loops.find(a))).or_default() += 1;
    }
    let mut per_piece: std::collections::HashMap<(usize, usize), Vec<usize>> = Default::default();
    for ((s, piece, _), n) in edges {
        per_piece.entry((s, piece)).or_default().push(n);
    }
    let share = |loops: &mut Vec<usize>| {
        loops.sort_unstable_by(|a, b| b.cmp(a));
        let all: usize = loops.iter().sum();
        loops
            .get(1)
            .map_or(0.0, |&second| second as f64 / all as f64)
    };
    let ((worst, _), twice) = per_piece
        .iter_mut()
        .map(|(&key, l)| (key, share(l)))
        .max_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)))?;
    // The root has no parent, hence no seam of its own: it never comes out here.
    (twice >= TWICE && sections[worst].parent.is_some()).then(|| sections[worst].name.clone())
}
