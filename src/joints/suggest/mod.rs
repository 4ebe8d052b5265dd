//! Joints suggested from the skeleton: cuts where the protrusions of a mesh (limbs, neck,
//! tail, ears, fingers) leave the body and where they narrow, organised as a section tree
//! (shoulder → elbow → wrist) and named by role.
//!
//! [`suggest`] runs one character through six stages, each a module with its own type in
//! and out; every threshold they use is in `rules`:
//!
//! 1. **Orientation** (`body`, [`Body::of`]): the body apart from its riders, and its cues,
//!    the mirror plane and the flat base ([`crate::mesh::orientation::Cues`]).
//! 2. **The tree** (`body`, [`Body::tree`]): the root, the body's core, the distance `g`
//!    from it in local radii, and the join tree of `g`: protrusions hanging from forks
//!    (`body::Tree`).
//! 3. **Limbs** (`limbs`): which protrusions are limbs and where each is cut (a `Limb`
//!    per cut, parent-first).
//! 4. **Cuts** (`place`): the limbs applied as cuts, numbered by their place in the tree;
//!    one that leaves too small a section or slips into the body is dropped (`Placed`).
//! 5. **Names** (`names`): up, front and left from how the root's limbs hang
//!    ([`crate::mesh::orientation::frame`]), then names by role: `arm.L`, `neck`, `tail`…
//!    (`Named`).
//! 6. **Fit** (`fit`): left and right made to mirror each other, shoulders and hips moved
//!    to the body and turned about their balls, a head with no neck cut at the shoulders.
//!
//! Then, once the cuts apply to the puppet (`Puppet` calls [`seams::add`]):
//! **Seams.** With its sections whole over the surface, a section that meets one it neither hangs from, nor carries, nor sits beside over
//! `FOREIGN` of its seam loses its cut (`seams`): the two would turn apart with no band
//! between them. A section that meets its parent along two loops (`TWICE`: a statue's
//! hind legs standing on its pedestal, met at the hips and across the pedestal) loses
//! its cut too: turned about one, it tears the other. Then the joints are turned through
//! `TRIALS` random poses; a section
//! whose skin tears there (an edge past `TEAR` times its length where the bones hold
//! it: a body standing on a pedestal by four legs, turned about one) loses its cut. Last,
//! a joint that, turned alone, changes its section's volume or its parent's by more than
//! `BALLOON` of its size (a pivot far off its seam) loses its cut
//! (`balloon`).
//!
//! Two or more characters in one file (bodies apart from each other) each run the stages
//! on their own (`characters`). `puppet bench suggest` scores the suggestion against the
//! labelled characters of `tests/data/characters` and `tests/data/population`
//! (`crate::bench::labels`).
//!
//! # Where things are
//! * `rules`: the thresholds, in one place;
//! * `body`: stages 1–2 (`graph`: shortest paths in local radii; `tree`: the join tree);
//! * `limbs`: stage 3 (`find`: the walk over the tree; `profile`: cuts inside a part;
//!   `trunk`: a cut across the core);
//! * `place`: stage 4;
//! * `names`: stage 5 (`naming`: the root's limbs; `chains`: down a limb, and digits);
//! * `fit`: stage 6 (`pairs`, `body` and `slice`, `head`);
//! * `seams`: the cuts applied, and those that would tear taken back;
//! * `balloon`: those whose turn would balloon a section taken back;
//! * `characters`: two or more characters in one file;
//! * `union_find`: the sweep's sets, a slice's loops;
//! * `fixture` (tests only): the repository's characters the stages' unit tests run on.

mod balloon;
mod body;
pub mod characters;
mod fit;
mod limbs;
mod names;
mod place;
mod rules;
pub mod seams;
mod union_find;

#[cfg(test)]
pub(crate) mod fixture;

pub use names::other_side;

use crate::joints::Cut;
use crate::mesh::orientation::{Frame, Given};
use crate::mesh::Mesh;
use crate::skeleton::Skeleton;
use body::Body;

/// Cuts where the protrusions of `mesh` narrow, organised parent-first as a section tree
/// under the root section `root`, named by role where one fits, and the frame (up, front,
/// left) they were named in: up and front as far as `given`, the rest found. Every cut
/// applies, in order, to joints without cuts. Two or more characters in the file (body parts apart from each
/// other) each get their own cuts, the largest's names as they are and the others' with
/// `.001`, `.002`… (see `characters`); the frame is the largest's. `attachments`: where
/// the mesh's separate parts meet ([`crate::mesh::attachments`]), found once by the
/// caller (the puppet's build joins its parts there too) for every stage that walks them.
pub fn suggest(
    mesh: &Mesh,
    skeleton: &Skeleton,
    attachments: &[(u32, u32)],
    root: &str,
    given: Given,
) -> (Vec<Cut>, Frame) {
    let whole = Input {
        mesh,
        skeleton,
        attachments,
    };
    let Some(characters) = characters::of(mesh, skeleton, attachments) else {
        return suggest_one(whole, root, given);
    };
    let mut all = Vec::new();
    let mut first = None;
    for (k, c) in characters.iter().enumerate() {
        let attachments = crate::mesh::attachments(&c.mesh);
        let one = Input {
            mesh: &c.mesh,
            skeleton: &c.skeleton,
            attachments: &attachments,
        };
        let (cuts, frame) = suggest_one(one, root, given);
        first.get_or_insert(frame);
        let named = |n: &str| characters::name(n, k, root);
        all.extend(cuts.into_iter().map(|cut| Cut {
            name: named(&cut.name),
            section: named(&cut.section),
            ..cut
        }));
    }
    match first {
        Some(frame) => (all, frame),
        None => suggest_one(whole, root, given),
    }
}

/// What the stages read of one character: its mesh, its skeleton, and where its separate
/// parts meet ([`crate::mesh::attachments`]).
#[derive(Clone, Copy)]
struct Input<'a> {
    mesh: &'a Mesh,
    skeleton: &'a Skeleton,
    attachments: &'a [(u32, u32)],
}

/// [`suggest`] for one character: the six stages of the module docs.
fn suggest_one(input: Input<'_>, root: &str, given: Given) -> (Vec<Cut>, Frame) {
    let Input {
        mesh,
        skeleton,
        attachments,
    } = input;
    // 1. Orientation: the body apart from its riders, its mirror plane and flat base.
    let body = Body::of(mesh, skeleton, attachments, given.up);
    let mirror = body.cues.mirror;
    // 2. The tree of the body's protrusions.
    let tree = body.tree();
    // 3. Limbs: where each protrusion is cut.
    let limbs = limbs::of(&tree, mirror);
    // 4. Cuts: the limbs applied to the whole mesh's joints, riders going with their hosts.
    let placed = place::place(
        mesh,
        skeleton,
        &body.hosts,
        attachments,
        root,
        &limbs,
        mirror,
    );
    // 5. Names by role, in the frame the root's limbs give.
    let named = names::name(
        &body.character,
        &skeleton.distance,
        &placed,
        given,
        body.cues,
        root,
    );
    // 6. Fit: pairs mirrored, shoulders and hips to the body, a head on the shoulders.
    let cuts = fit::fit(
        mesh,
        &body.character,
        &skeleton.points,
        &placed.blank,
        root,
        &named,
    );
    (cuts, named.frame)
}

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};

    /// The suggestion's modules (a file or a folder of `joints/suggest/`) and, for each,
    /// the sibling modules its code names (`super::x` from a file or a folder's `mod.rs`,
    /// `super::super::x` from a folder's other files, or `crate::joints::suggest::x`).
    fn imports() -> BTreeMap<String, BTreeSet<String>> {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/joints/suggest");
        let mut files = Vec::new();
        for entry in std::fs::read_dir(&dir).expect("the folder reads").flatten() {
            let path = entry.path();
            if path.is_dir() {
                for inner in std::fs::read_dir(&path).expect("a stage reads").flatten() {
                    // A folder's `mod.rs` names its siblings as a file does.
                    let nested = inner.path().file_stem().is_some_and(|s| s != "mod");
                    files.push((path.clone(), inner.path(), nested));
                }
            } else {
                files.push((path.clone(), path, false));
            }
        }
        let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (module, file, nested) in files {
            let name = module.file_stem().map(|s| s.to_string_lossy().to_string());
            let Some(name) = name.filter(|n| n != "mod") else {
                continue;
            };
            let text = std::fs::read_to_string(&file).unwrap_or_default();
            let code: String = text
                .lines()
                .map(|l| l.split("//").next().unwrap_or(""))
                .collect::<Vec<_>>()
                .join("\n");
            let prefixes: &[&str] = if nested {
                &["super::super::", "crate::joints::suggest::"]
            } else {
                &["super::", "crate::joints::suggest::"]
            };
            let used = out.entry(name.clone()).or_default();
            for prefix in prefixes {
                for part in code.split(prefix).skip(1) {
                    let word: String = part
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    if word != name && !word.is_empty() && word.chars().all(|c| !c.is_uppercase()) {
                        used.insert(word);
                    }
                }
            }
        }
        // Only the modules count (not a function called through `super::`), and not the
        // tests' `fixture`, which runs the stages for them.
        out.remove("fixture");
        let modules: BTreeSet<String> = out.keys().cloned().collect();
        for used in out.values_mut() {
            used.retain(|m| modules.contains(m));
        }
        out
    }

    /// No module of the suggestion names one that names it back, directly or through
    /// others: the stages run one way (the module docs' order).
    #[test]
    fn the_stages_import_each_other_one_way() {
        let imports = imports();
        for stage in ["body", "limbs", "place", "names", "fit", "rules", "seams"] {
            assert!(
                imports.contains_key(stage),
                "{stage} not found: {imports:?}"
            );
        }
        // Depth-first from each module: reaching itself again is a circle.
        for start in imports.keys() {
            let mut stack: Vec<&String> = imports[start].iter().collect();
            let mut seen = BTreeSet::new();
            while let Some(m) = stack.pop() {
                assert_ne!(
                    m, start,
                    "{start} imports itself through others: {imports:?}"
                );
                if seen.insert(m) {
                    stack.extend(imports.get(m).into_iter().flatten());
                }
            }
        }
        // Each stage reads earlier stages only.
        let order = ["body", "limbs", "place", "names", "fit"];
        for (k, stage) in order.iter().enumerate() {
            for later in &order[k + 1..] {
                assert!(
                    !imports[*stage].contains(*later),
                    "{stage} reads the later stage {later}"
                );
            }
        }
    }
}
