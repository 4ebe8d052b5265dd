//! Step 6, seams: a section that meets a section it is not related to (neither its
//! parent, nor its child, nor a sibling) over a large share of its seam loses its cut.
//! Two such sections turn each on its own with no band between them, and the skin where
//! they meet tears: a lion statue's chain of "jaws" each touching the body (93×), toes
//! meeting a shin past the foot (13×). Measured on the sections as the puppet has them
//! (whole over the surface, with the mesh's attachments), once the cuts apply.

use crate::joints::Joints;

/// A seam between two unrelated sections, as a share of the shorter of their two seams
/// (mesh edges to other sections), at or above which the deeper of the two loses its
/// cut. No shipped or labelled character has any such seam. Chosen on the six men of
/// `tests/data/pieces`, where every value from 0.2 to 0.3 removes the same cuts; on the
/// rest of the population the seams it removes share 29.7–100 %, and those it keeps at
/// most 14 % (a thumb's base and its tip, a koala's ear and its body)
/// (`docs/performance-log.md`).
pub const FOREIGN: f64 = 0.25;

/// Removes, one at a time, the cut of the deeper section of the unrelated pair with the
/// largest shared seam at or above [`FOREIGN`]; returns the names of the cuts removed.
pub fn keep_related(joints: &mut Joints) -> Vec<String> {
    let mut removed = Vec::new();
    for _ in 0..joints.cuts().len() {
        let Some(name) = foreign(joints) else {
            break;
        };
        if joints.remove_cut(&name).is_err() {
            break;
        }
        removed.push(name);
    }
    removed
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
    let ((a, b), _) = shared
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
    // The root has no cut to lose (it is never the deeper of an unrelated pair).
    parent(deeper).map(|_| sections[deeper].name.clone())
}
