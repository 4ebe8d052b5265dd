//! Poses a puppeteer makes keep the skin whole: shipped characters with their suggested
//! joints, every joint turned at once in seeded random poses (`puppet::puppet::poses`:
//! ±60°, ±90° at the root), settled, the surface measured against its rest shape. The
//! full population is `puppet bench poses` (`BENCHMARKS.md`); this is its sample.

mod common;

use common::{data_objs, ok, puppet, suggested};
use puppet::puppet::poses::{self, Spread};
use puppet::random::SplitMix;
use puppet::Puppet;
use std::path::Path;

fn mesh(name: &str) -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    match name {
        "spot.obj" => root.join("assets/spot.obj"),
        _ => root.join("tests/data/meshes").join(name),
    }
}

/// The worst stretch and share of edges over 1.5× over seeds `1..=seeds`, settled (and
/// where the bones alone hold the surface).
fn worst(p: &Puppet, seeds: u64) -> (f64, f64, f64) {
    let (mut stretch, mut over, mut bones) = (0.0f64, 0.0f64, 0.0f64);
    for seed in 1..=seeds {
        let target = poses::random_pose(&p.joints, Spread::default(), &mut SplitMix(seed));
        let mut posed = p.clone();
        poses::settle(&mut posed, &target);
        let s = poses::measure(&posed, &target);
        assert!(!s.nan, "seed {seed}: NaN");
        stretch = stretch.max(s.worst);
        over = over.max(s.over_1_5);
        let b = poses::measure_at(p, &poses::targets(p, &target), &target);
        bones = bones.max(b.worst);
    }
    (stretch, over, bones)
}

/// The guide's claim: on the shipped cow, hand and human, no edge of a settled random
/// pose stretches past 3×, and at most 2 % of the edges past 1.5×.
#[test]
fn random_poses_of_the_shipped_characters_keep_the_skin_whole() {
    for name in ["spot.obj", "hand.obj", "human.obj"] {
        let p = suggested(&mesh(name));
        let (stretch, over, bones) = worst(&p, 5);
        assert!(
            stretch <= 3.0 && bones <= 3.0,
            "{name}: an edge stretched {stretch:.2}× (bones alone {bones:.2}×)"
        );
        assert!(
            over <= 0.02,
            "{name}: {:.2} % of edges over 1.5×",
            100.0 * over
        );
    }
}

/// BENCHMARKS' claim: every one of the 500 poses of `bench poses` (the 25 shipped
/// characters, 20 seeds each, settled) keeps its worst edge within 3×, with no NaN, at
/// most 2 change a section's volume by more than 5 %, and 18 characters keep 99 % of
/// their edges within 1.5× on every pose (what each change did to these figures:
/// `docs/performance-log.md`). The bench itself fails off the stretch bound; a minute in
/// CI.
#[test]
fn every_pose_of_the_shipped_population_stays_within_three_times() {
    let out = puppet(&["bench", "poses", "--max-stretch", "3"]);
    ok(&out);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("500 poses of 25 characters"), "{table}");
    let beyond = beyond_volume(&table);
    assert!(
        beyond <= 2,
        "{beyond} poses with a section's volume beyond ±5 %"
    );
    // Each character's row: `| name | joints | poses | worst | p99 (max) | …`.
    let within = table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| character"))
        .filter_map(|l| l.split('|').map(str::trim).nth(5)?.parse::<f64>().ok())
        .filter(|&p99| p99 <= 1.5)
        .count();
    assert!(
        within >= 18,
        "{within} characters keep 99 % of their edges within 1.5×"
    );
}

/// How many poses the summary of `bench poses` counts with a section's volume beyond
/// ±5 %.
fn beyond_volume(table: &str) -> usize {
    table
        .split("a section's volume beyond ±5 % in ")
        .nth(1)
        .and_then(|tail| tail.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count of poses beyond ±5 % in {table}"))
}

/// BENCHMARKS' claims on the 45 downloads of `tests/data/population` (20 seeds each,
/// settled, the joints suggested from the skeleton): no pose gives a NaN, no edge
/// stretches past 3× (the adventurer's, 2.98×), all 45 characters stay within 3× on
/// every pose, and at most 67 poses change a section's volume by more than 5 % (what
/// each change did to that count: `docs/performance-log.md`). Half a minute in CI.
#[test]
fn the_downloads_poses_hold_what_benchmarks_says() {
    holds("tests/data/population", 45, 3.0, 0, 45, 67);
}

/// BENCHMARKS' claims on the 12 characters in pieces of `tests/data/pieces` (20 seeds
/// each, settled): no NaN, no edge past 3× (the man on the beach, 2.85×), all 12
/// characters within 3× on every pose, and at most 13 poses change a
/// section's volume by more than 5 %.
#[test]
fn the_pieces_poses_hold_what_benchmarks_says() {
    holds("tests/data/pieces", 12, 3.0, 0, 12, 13);
}

/// BENCHMARKS' claim on collision over the 12 characters in pieces, which nobody tuned it
/// on: with collision on, no pose of three is worse than off (`--never-worse` fails the
/// command when one is).
#[test]
fn collision_on_the_pieces_is_never_worse() {
    let out = puppet(&[
        "bench",
        "poses",
        "--compare",
        "--never-worse",
        "--poses",
        "3",
        "--ignore-skin",
        "tests/data/pieces",
    ]);
    ok(&out);
}

/// BENCHMARKS' claim on collision over the 45 downloads (6 seeds each): at most 7 of the
/// 270 poses worse with collision on than off, and at most 3 of them still worse against
/// the pose they reached settled with collision off (the JSON's `worse`: `pose` or
/// `collision`).
#[test]
fn collision_on_the_downloads_is_worse_on_few_poses() {
    let out = puppet(&[
        "bench",
        "poses",
        "--compare",
        "--poses",
        "6",
        "--json",
        "--ignore-skin",
        "tests/data/population",
    ]);
    ok(&out);
    let rows = json_rows(&out);
    assert_eq!(rows.len(), 540);
    let on: Vec<&serde_json::Value> = rows.iter().filter(|r| r["collision"] == true).collect();
    let poses = |what: &str| -> Vec<String> {
        on.iter()
            .filter(|r| r["worse"] == what)
            .map(|r| format!("{} {}", r["character"], r["seed"]))
            .collect()
    };
    let (not, pose, collision) = (poses("not"), poses("pose"), poses("collision"));
    assert_eq!(not.len() + pose.len() + collision.len(), 270);
    assert!(
        pose.len() + collision.len() <= 7 && collision.len() <= 3,
        "worse on than off: {pose:?} (as much off at the pose reached), {collision:?}"
    );
}

/// BENCHMARKS' claim on drags: one joint turned a pose (`--drag`, as a mouse drag turns
/// it), none of the 250 poses of the shipped characters is worse with collision on than
/// off, and crossing faces go to 0 on most characters.
#[test]
fn collision_on_a_drag_is_never_worse() {
    let out = puppet(&[
        "bench",
        "poses",
        "--compare",
        "--drag",
        "--never-worse",
        "--poses",
        "10",
        "--json",
    ]);
    ok(&out);
    let rows = json_rows(&out);
    assert_eq!(rows.len(), 500);
    // Per character, the most faces a pose crosses with collision on.
    let mut most = std::collections::BTreeMap::new();
    for r in rows.iter().filter(|r| r["collision"] == true) {
        let m = most
            .entry(r["character"].as_str().unwrap().to_string())
            .or_insert(0);
        *m = r["crossing"].as_u64().unwrap().max(*m);
    }
    let none = most.values().filter(|&&m| m == 0).count();
    assert!(none >= 16, "{most:?}");
}

/// The records of a `--json` run, one a line.
fn json_rows(out: &std::process::Output) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// Runs `bench poses --ignore-skin` on `folder`'s `characters` and holds it to its
/// figures: no NaN, no edge past `stretch`, at most `past` poses past 3×, at least
/// `within` characters within 3× on every pose, at most `beyond` poses with a section's
/// volume beyond ±5 %.
fn holds(folder: &str, characters: usize, stretch: f64, past: usize, within: usize, beyond: usize) {
    let bound = stretch.to_string();
    let out = puppet(&[
        "bench",
        "poses",
        "--ignore-skin",
        "--max-stretch",
        &bound,
        folder,
    ]);
    ok(&out);
    let table = String::from_utf8_lossy(&out.stdout);
    let poses = 20 * characters;
    assert!(
        table.contains(&format!("{poses} poses of {characters} characters")),
        "{table}"
    );
    let passed: usize = table
        .split(" poses past 3×")
        .next()
        .and_then(|head| head.rsplit("; ").next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("no count of poses past 3× in {table}"));
    assert!(passed <= past, "{passed} poses past 3×");
    let changed = beyond_volume(&table);
    assert!(
        changed <= beyond,
        "{changed} poses with a section's volume beyond ±5 %"
    );
    // Each character's row: `| name | joints | poses | median … max | … | NaN | …`.
    let rows: Vec<Vec<&str>> = table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| character"))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect();
    assert_eq!(rows.len(), characters, "{table}");
    let kept = rows
        .iter()
        .filter(|r| {
            r[4].rsplit(' ')
                .next()
                .and_then(|m| m.parse::<f64>().ok())
                .is_some_and(|m| m <= 3.0)
        })
        .count();
    assert!(
        kept >= within,
        "{kept} of {characters} within 3× on every pose"
    );
    assert!(rows.iter().all(|r| r[11] == "0"), "a NaN: {table}");
}

/// The pose issue's first case: the human's head nodded 45° forward about its suggested
/// cut, which crossed the face at the mouth and tore it open (46× at the lips).
#[test]
fn the_human_nods_without_tearing_its_face() {
    let p = suggested(&mesh("human.obj"));
    let head = p.joints.find("head").expect("a head cut");
    let cut = p
        .joints
        .cuts()
        .iter()
        .find(|c| c.name == "head")
        .expect("the head's cut");
    let left = glam::DVec3::X.cross(cut.normal).cross(cut.normal);
    let axis = cut.normal.cross(left).normalize();
    let mut target = vec![puppet::joints::Local::default(); p.joints.sections().len()];
    target[head] = puppet::joints::Local::axis_angle(axis, 45.0);
    let bones = poses::measure_at(&p, &poses::targets(&p, &target), &target);
    let mut posed = p.clone();
    poses::settle(&mut posed, &target);
    let settled = poses::measure(&posed, &target);
    assert!(
        bones.worst <= 2.0 && settled.worst <= 2.0,
        "bones {bones:?}, settled {settled:?}"
    );
}

/// Settling never stretches the skin past what its bones do (`rig::stiffness`: a surface
/// spring's force is proportional to its strain). With equal springs a short edge took
/// the same extension as its long neighbours, so several times their strain: the ant,
/// the stuffed toy and the monkey settled 1.46–1.92× past their bones in these poses
/// (an edge a ninth of the mean length at 4.4× where the bones held it at 1.0×); over
/// all of `bench poses` now at most 1.04×.
#[test]
fn settling_stretches_no_edge_past_its_bones() {
    for name in ["ant.obj", "teddy.obj", "monkey.obj"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/characters")
            .join(name);
        let p = suggested(&path);
        for seed in 1..=8 {
            let target = poses::random_pose(&p.joints, Spread::default(), &mut SplitMix(seed));
            let mut posed = p.clone();
            poses::settle(&mut posed, &target);
            let settled = poses::measure(&posed, &target).worst;
            let bones = poses::measure_at(&p, &poses::targets(&p, &target), &target).worst;
            assert!(
                settled <= 1.05 * bones,
                "{name} seed {seed}: settled {settled:.2}×, bones alone {bones:.2}×"
            );
        }
    }
}

/// A band's short edges keep their ends on one level (`joints::levels`): with each vertex
/// rounded to its own, the SMPL-X human's neck, edges a twentieth of the mean length where
/// neighbouring vertices fell on neighbouring levels, tore to 5.0× with the bones alone and
/// 4.7× settled over 20 poses.
#[test]
fn short_edges_turn_on_one_level() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/poses/human_neutral.obj");
    let p = suggested(&path);
    let (stretch, _, bones) = worst(&p, 10);
    assert!(
        stretch <= 3.0 && bones <= 3.5,
        "an edge stretched {stretch:.2}× (bones alone {bones:.2}×)"
    );
}

/// Every mesh in the pose population but the embedded cow (`puppet bench poses`).
fn population() -> Vec<std::path::PathBuf> {
    ["meshes", "characters", "poses"]
        .into_iter()
        .flat_map(data_objs)
        .collect()
}

/// Sections are whole (`joints::whole`): on every character of the population, each
/// piece of a section's surface (joined by mesh edges between its own vertices) is its
/// largest, or touches its parent, or touches no other section. Before, a patch of the
/// scorpion's body lay inside each claw, the penguin's inside its head, a stuffed toy's
/// and a lion statue's inside theirs, and tore open when the part turned.
#[test]
fn every_section_of_every_character_is_whole() {
    let mut checked = 0;
    for path in population() {
        let p = suggested(&path);
        let of = p.joints.section_of();
        let sections = p.joints.sections();
        let n = of.len();
        let mut near = vec![Vec::new(); n];
        for t in &p.mesh.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                near[a as usize].push(b as usize);
                near[b as usize].push(a as usize);
            }
        }
        // Pieces: (section, size, the sections they touch).
        let mut piece = vec![usize::MAX; n];
        let mut pieces: Vec<(u16, usize, Vec<u16>)> = Vec::new();
        for seed in 0..n {
            if piece[seed] != usize::MAX {
                continue;
            }
            let k = pieces.len();
            piece[seed] = k;
            let (mut stack, mut size, mut touches) = (vec![seed], 0, Vec::new());
            while let Some(v) = stack.pop() {
                size += 1;
                for &w in &near[v] {
                    if of[w] != of[seed] {
                        touches.push(of[w]);
                    } else if piece[w] == usize::MAX {
                        piece[w] = k;
                        stack.push(w);
                    }
                }
            }
            pieces.push((of[seed], size, touches));
        }
        for (k, (s, size, touches)) in pieces.iter().enumerate() {
            let largest = pieces.iter().filter(|q| q.0 == *s).all(|q| q.1 <= *size);
            let parent = sections[usize::from(*s)].parent;
            let hangs = touches.iter().any(|&t| Some(usize::from(t)) == parent);
            assert!(
                largest || hangs || touches.is_empty(),
                "{}: a piece of {} vertices of {} (piece {k}) touches only {:?}",
                path.display(),
                size,
                sections[usize::from(*s)].name,
                touches
                    .iter()
                    .map(|&t| sections[usize::from(t)].name.as_str())
                    .collect::<std::collections::BTreeSet<_>>()
            );
        }
        checked += 1;
    }
    assert!(checked >= 21, "{checked} characters");
}

/// A joint's targets follow its angle continuously: on every character of the population,
/// every joint turned by a hundredth of a degree (about two axes across its cut, each way)
/// moves no vertex's target farther than a thousandth of the mesh's diagonal (a rigid turn
/// moves a point at most 0.0002 of it). Before, a parent's vertex that lay across a
/// rounded cut's plane at rest was pushed back over it at the first degree of bend: 2.7
/// edges on the horse's hip, and each hip, shoulder and leg of the horse, the dino, the
/// koala and the goat's head tore 3.0–3.9× in random poses.
#[test]
fn a_joint_turned_a_little_moves_its_skin_a_little() {
    let mut checked = 0;
    for path in population() {
        let p = suggested(&path);
        let rest = &p.mesh.positions;
        let (lo, hi) = rest.iter().fold(
            (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN)),
            |(lo, hi), x| (lo.min(*x), hi.max(*x)),
        );
        let diagonal = lo.distance(hi);
        let n = p.joints.sections().len();
        for cut in p.joints.cuts() {
            let Some(j) = p.joints.find(&cut.name) else {
                continue;
            };
            let a = cut.normal.any_orthonormal_vector();
            for axis in [a, cut.normal.cross(a)] {
                for degrees in [0.01, -0.01] {
                    let mut local = vec![puppet::joints::Local::default(); n];
                    local[j] = puppet::joints::Local::axis_angle(axis, degrees);
                    let now = poses::targets(&p, &local);
                    let (far, v) = now
                        .iter()
                        .zip(rest)
                        .enumerate()
                        .map(|(i, (x, r))| (x.distance(*r), i))
                        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
                    assert!(
                        far <= 1e-3 * diagonal,
                        "{}: {} turned {degrees}° moves vertex {v} by {:.4} of the diagonal",
                        path.display(),
                        cut.name,
                        far / diagonal
                    );
                }
            }
        }
        checked += 1;
    }
    assert!(checked >= 21, "{checked} characters");
}

/// The scorpion's claws fold against its body, and a patch of the body's skin lay inside
/// each (by their skeletal points): turned in random poses, the skin between tore 8–15×.
/// Whole sections carry the patch with the claw (2.1–3.0× over `bench poses`' 20 seeds).
#[test]
fn a_claw_folded_against_the_body_turns_without_tearing() {
    let p = suggested(&mesh("scorpion.obj"));
    let (stretch, over, bones) = worst(&p, 3);
    assert!(
        stretch <= 3.5 && bones <= 3.5,
        "an edge stretched {stretch:.2}× (bones alone {bones:.2}×)"
    );
    assert!(over <= 0.01, "{:.2} % of edges over 1.5×", 100.0 * over);
}

/// The suggestion's step 6 (`joints::suggest::seams`): on every character of the
/// population and of the characters in pieces, no section meets one it is not related to
/// (neither its parent, its child nor a sibling) over a quarter of the shorter of their
/// seams (mesh edges to other sections), as the guide and BENCHMARKS say.
#[test]
fn no_section_meets_one_it_is_not_related_to() {
    let mut files = population();
    files.extend(data_objs("pieces"));
    for path in &files {
        let p = suggested(path);
        let sections = p.joints.sections();
        let of = p.joints.section_of();
        let parent = |s: usize| sections[s].parent;
        let related = |a: usize, b: usize| {
            parent(a) == Some(b)
                || parent(b) == Some(a)
                || (parent(a).is_some() && parent(a) == parent(b))
        };
        let mut seam = vec![0usize; sections.len()];
        let mut shared = std::collections::BTreeMap::new();
        let edges: std::collections::BTreeSet<(u32, u32)> = p
            .mesh
            .triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        for (a, b) in edges {
            let (sa, sb) = (usize::from(of[a as usize]), usize::from(of[b as usize]));
            if sa != sb {
                seam[sa] += 1;
                seam[sb] += 1;
                if !related(sa, sb) {
                    *shared.entry((sa.min(sb), sa.max(sb))).or_insert(0usize) += 1;
                }
            }
        }
        for ((a, b), n) in shared {
            let share = n as f64 / seam[a].min(seam[b]) as f64;
            assert!(
                share < 0.25,
                "{}: {} and {} share {:.0} % of a seam",
                path.display(),
                sections[a].name,
                sections[b].name,
                100.0 * share
            );
        }
    }
    assert!(files.len() >= 36, "{} characters", files.len());
}

/// Sections that met unrelated ones turned apart with no band between them: the lion
/// statue's chain of "jaws", each touching its body, tore 44–93×, the beach man's toes,
/// which met his shin past his foot, 13–17×. Their cuts go (step 6). A section joined to
/// the rest in two places tore where it was not turned: the lion's hind legs with half its
/// pedestal, meeting the body at the hips and across the pedestal, 3.8× over `bench
/// poses`' 20 seeds, the mech's 16×; a section that meets its parent along two loops
/// loses its cut (`rules::TWICE`), and the tear check takes the others: the lion at most
/// 2.6× over all 20 seeds, the others 2.4× at most over the first three.
#[test]
fn sections_that_met_unrelated_ones_or_tore_no_longer_tear() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (file, seeds, most) in [
        ("tests/data/poses/lionstatue.obj", 20, 3.0),
        ("tests/data/pieces/man-beach.obj", 3, 3.0),
        ("tests/data/pieces/mech-george.obj", 3, 3.0),
    ] {
        let p = suggested(&root.join(file));
        let (stretch, _, _) = worst(&p, seeds);
        assert!(stretch <= most, "{file}: an edge stretched {stretch:.2}×");
    }
}

/// A seam reaches into the parent as far as it lies from the pivot's line (`joints::blend`):
/// on a coarse scan, the goat's head, whose ears' seams are wide and flat, every one of
/// `bench poses`' 20 seeds stays within 3× settled (3.03× when every seam vertex reached
/// only as far as the median's).
#[test]
fn a_wide_flat_seam_bends_over_a_strip_as_wide() {
    let p = suggested(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/poses/goathead.obj"));
    let (stretch, _, _) = worst(&p, 20);
    assert!(stretch <= 3.0, "an edge stretched {stretch:.2}×");
}

/// Asserts that where the bones hold the surface of each file (its suggested joints) over
/// `bench poses`' 20 seeds, no edge stretches past the file's bound.
fn bones_within(cases: &[(&str, f64)]) {
    bones_within_of(cases, suggested);
}

/// [`bones_within`], each puppet opened by `open`.
fn bones_within_of(cases: &[(&str, f64)], open: fn(&Path) -> Puppet) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for &(name, most) in cases {
        let p = open(&root.join(name));
        let bones = (1..=20)
            .map(|seed| {
                let target = poses::random_pose(&p.joints, Spread::default(), &mut SplitMix(seed));
                poses::measure_at(&p, &poses::targets(&p, &target), &target).worst
            })
            .fold(0.0f64, f64::max);
        assert!(
            bones <= most,
            "{name}: an edge stretched {bones:.2}× by the bones"
        );
    }
}

/// A band's weight steps no steeper than `joints::blend::SLOPE` allows: where the bones
/// hold the surface in `bench poses`' 20 seeds, the penguin's flipper root stays within 3×
/// (4.23× without the bound: a seam vertex of the body at share 0.68 beside one of the
/// flipper at 0.84 over a short edge) and the SWAT man of the pieces within 4.5× (6.97×).
/// Against a fixed weight too: the downloaded deer's neck, beside its hindquarters' band,
/// stays within the slope of its head, which that band does not move (5.03× when the
/// bound only halved the step there; 4.11× with it). And against a section hanging from
/// the band's child: a thumb at the end of a palm the wrist's band covers turns whole
/// with the hand, and the palm's skin next to it is held as a jump (the downloaded
/// formal woman 5.61× where the thumb's root lay beside palm skin at 49 of 64 of the
/// wrist's turn, 2.59× now; the soldier of the pieces 4.08×, 2.11× now). A first guess
/// steeper than the slope allows far from the pivot is smoothed as a jump: a fish's tail
/// fin, its tip far off the pivot's line (5.66× held to the limb's ramp, 2.33× now).
#[test]
fn a_band_weight_steps_no_steeper_than_its_slope() {
    bones_within(&[
        ("tests/data/meshes/penguin.obj", 3.0),
        ("tests/data/pieces/man-swat.obj", 4.5),
        ("tests/data/population/deer.glb", 4.5),
        ("tests/data/population/woman-formal.glb", 3.0),
        ("tests/data/pieces/woman-soldier.obj", 3.0),
        ("tests/data/population/fish3.glb", 3.0),
    ]);
}

/// Where bands overlap on their parent's side, their slopes are bounded together
/// (`joints::blend`: *Where bands overlap*): the downloaded king's armpit, which his arm's,
/// his neck's and his waist's bands each move partly, stays within 3× where the bones
/// hold the surface in `bench poses`' 20 seeds (3.48× with each band's own bound, 2.72×
/// now).
#[test]
fn bands_that_overlap_share_their_slope() {
    bones_within_of(
        &[("tests/data/population/man-king.glb", 3.0)],
        common::suggested_from_shape,
    );
}

/// A part of the mesh that a cut splits beside the limb goes whole to the section it hangs
/// from (`joints::whole`): the downloaded adventurer's backpack, a part of 99 vertices
/// that his waist's cut crosses behind his back, lies in one section, and where the bones
/// hold the surface in `bench poses`' 20 seeds no edge of his stretches past 3.5× (4.04×
/// with the backpack's halves in two sections). A band's width is measured on the
/// sections as they were before parts moved: the spacesuit's shoulder, whose cut crosses
/// its helmet, stays within 3× (2.94×; measured without the helmet its band narrowed:
/// 3.99×, and settled 3.69×).
#[test]
fn a_part_beside_a_cut_turns_whole() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/population");
    let p = common::suggested_from_shape(&root.join("man-adventurer.glb"));
    let positions = &p.mesh.positions;
    let parts = puppet::mesh::Parts::of(&p.mesh);
    let at = glam::DVec3::new(0.05845, 1.39935, -0.20160);
    let nearest = (0..positions.len())
        .min_by(|&a, &b| {
            positions[a]
                .distance(at)
                .total_cmp(&positions[b].distance(at))
        })
        .expect("a vertex");
    let backpack: Vec<usize> = (0..positions.len())
        .filter(|&v| parts.part_of[v] == parts.part_of[nearest])
        .collect();
    assert_eq!(backpack.len(), 99, "the backpack's part");
    let sections: std::collections::BTreeSet<u16> =
        backpack.iter().map(|&v| p.joints.section_of()[v]).collect();
    assert_eq!(sections.len(), 1, "the backpack in sections {sections:?}");
    bones_within_of(
        &[
            ("tests/data/population/man-adventurer.glb", 3.5),
            ("tests/data/population/man-spacesuit.glb", 3.0),
        ],
        common::suggested_from_shape,
    );
}

/// The parent's side of a band reaches `SEAM_REACH` seam radii into it (`joints::blend`),
/// more where the seam moves with more than half the turn (a fan's): a thick joint bends
/// over a strip as wide as it is thick. Where the bones hold the surface in `bench poses`'
/// 20 seeds, the arm of bigears beside its neckless head's band stays within 3× (3.32×
/// with a reach of 0.75 radii) and the penguin's flipper root within 4.5× (5.36×; 4.80×
/// with the reach not widened for a fan).
#[test]
fn a_thick_seam_bends_over_a_strip_as_wide_as_it_is_thick() {
    bones_within(&[
        ("tests/data/characters/bigears.obj", 3.0),
        ("tests/data/meshes/penguin.obj", 4.5),
    ]);
}

/// The capped volume change of every section of `p` but `turned`, its parent and its
/// children, where the bones hold the surface with only `turned` turned by `degrees` about
/// `axes` axes across its cut: the largest, in %, with the section's name.
/// Section `s`'s faces (every vertex in it) and the volume they hold at rest, each cut
/// across them closed (`capped_volume`).
fn section_region(p: &Puppet, s: usize) -> (Vec<bool>, f64) {
    let section_of = p.joints.section_of();
    let faces: Vec<bool> = p
        .mesh
        .triangles
        .iter()
        .map(|t| t.iter().all(|&i| usize::from(section_of[i as usize]) == s))
        .collect();
    let rest = puppet::mesh::measure::capped_volume(&p.mesh.positions, &p.mesh.triangles, &faces);
    (faces, rest)
}

fn others_volume(p: &Puppet, turned: usize, degrees: f64, axes: usize) -> (f64, String) {
    use puppet::mesh::measure::capped_volume;
    let sections = p.joints.sections();
    let normal = p
        .joints
        .cuts()
        .get(turned - 1)
        .expect("a cut made the section")
        .normal;
    let across = normal.any_orthonormal_vector();
    let triangles = &p.mesh.triangles;
    let mut worst = (0.0f64, String::new());
    for s in 0..sections.len() {
        if s == turned || sections[turned].parent == Some(s) || sections[s].parent == Some(turned) {
            continue;
        }
        let (faces, rest) = section_region(p, s);
        if rest.abs() < 1e-12 {
            continue;
        }
        for k in 0..axes {
            let turn = glam::DQuat::from_axis_angle(
                normal,
                std::f64::consts::TAU * k as f64 / axes as f64,
            );
            let mut target = vec![puppet::joints::Local::default(); sections.len()];
            target[turned] = puppet::joints::Local::axis_angle(turn * across, degrees);
            let now = poses::targets(p, &target);
            let change = 100.0 * (capped_volume(&now, triangles, &faces) - rest) / rest.abs();
            if change.abs() > worst.0.abs() {
                worst = (change, sections[s].name.clone());
            }
        }
    }
    worst
}

/// A section beside a band rides on it whole (`joints::band`: *carried*): a neckless
/// head's band blends the trunk's skin over a strip as wide as the head is thick, which
/// reaches the shoulders, and an arm whose seam moved with a share of the nod while its
/// far end stayed was sheared. The head of the stuffed toy and of bigears turned 45°
/// about eight axes across its cut: every section but the head, its parent and its
/// children keeps its volume within 5 % (0.0 % and 0.1 %; riding on the parent, the arms
/// changed by up to +26.0 % and +19.9 %), the head is among the joints that stop when an
/// arm meets a leg, and the arm, turned with the mouse while it rides on a nod, turns by
/// the hand's turn (0.011 off on bigears in its parent's own frame), its pivot moving no
/// more than its fan's slide.
#[test]
fn a_section_beside_a_band_rides_on_it_whole() {
    for name in ["bigears.obj", "teddy.obj"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/characters")
            .join(name);
        let p = suggested(&path);
        let head = p.joints.find("head").expect("a head");
        let (change, section) = others_volume(&p, head, 45.0, 8);
        assert!(
            change.abs() <= 5.0,
            "{name}: {section} changed by {change:+.1} %"
        );
        // A nod moves the arm, so the pose limit stops the nod where the arm meets a leg.
        let (arm, leg) = (p.joints.find("arm.L"), p.joints.find("leg.L"));
        let (arm, leg) = arm.zip(leg).expect("an arm and a leg");
        assert!(p.joints.path(arm, leg).contains(&head), "{name}");
        // Turned with the mouse while it rides on a nod, the arm turns by what the hand
        // does, about where its pivot is now.
        let mut s = puppet::session::Session::new(p, name);
        s.select(Some(head), false);
        s.rotate_selected(glam::DQuat::from_rotation_x(0.6));
        s.select(Some(arm), false);
        let before = s.puppet.joints.world(&s.local)[arm];
        let pivot = s.pivot_world(arm);
        let q = glam::DQuat::from_rotation_z(0.5);
        s.rotate_selected(q);
        let after = s.puppet.joints.world(&s.local)[arm];
        let turn = after.matrix3 - glam::DMat3::from_quat(q) * before.matrix3;
        assert!(
            turn.to_cols_array().iter().all(|x| x.abs() < 1e-9),
            "{name}: the arm turned off the hand's turn by {turn:?}"
        );
        // Its pivot stays where it was but for the fan's slide (`joints::slide`).
        let band = s
            .puppet
            .joints
            .bands()
            .iter()
            .flatten()
            .find(|b| b.child == arm);
        // Each side of its fan slides at most `MAX_SLIDE` radii.
        let reach = band.map_or(0.0, |b| 2.0 * puppet::joints::MAX_SLIDE * b.radius);
        let x = pivot + glam::DVec3::new(0.1, -0.2, 0.05);
        let expected = pivot + q * (before.transform_point3(x) - pivot);
        let off = (after.transform_point3(x) - expected).length();
        assert!(
            off <= reach + 1e-9,
            "{name}: the arm moved {off} off the hand's turn"
        );
    }
}

/// A fan keeps both sides' volumes as it turns (`joints::slide`): turned alone by ±30°
/// about four axes across its cut, each fan's child (the koala's head, ears and limbs,
/// the dog's, the stuffed toy's) and the parent it turns on (but a trunk, which does not
/// slide) change their capped volumes by at most 2 % oddly, the part that changes sign
/// with the turn (1.6 %, the koala's ear, since a band's slope is held against fixed
/// weights and far from its pivot; 0.7 % on a parent, its head).
#[test]
fn a_fan_keeps_both_sides_volumes_either_way_it_turns() {
    let mut worst = Worst::default();
    let checked = fan_turns(
        30.0,
        |_| true,
        |path, p, band, [plus, minus]| {
            // A trunk (the root) does not slide: its side is not held.
            let mut sides = vec![band.child];
            if p.joints.sections()[band.parent].parent.is_some() {
                sides.push(band.parent);
            }
            for side in sides {
                if section_region(p, side).1.abs() < 1e-12 {
                    continue;
                }
                let change = |now: &[glam::DVec3]| volume_change(p, side, now);
                let odd = 0.5 * (change(plus) - change(minus));
                worst.see(odd, || {
                    format!(
                        "{}'s {} (turning {})",
                        stem(path),
                        p.joints.sections()[side].name,
                        p.joints.sections()[band.child].name
                    )
                });
            }
        },
    );
    assert!(checked >= 40, "only {checked} turns");
    assert!(
        worst.0.abs() <= 2.0,
        "{} changed by {:+.1} % oddly",
        worst.1,
        worst.0
    );
}

/// A trunk keeps its volume as a limb turns on it (`joints::slide`, *A trunk's side*):
/// turned alone by ±60° about four axes across its cut, each fan hanging from the root
/// whose trunk side swells (the penguin's, the cat's, the lizard's, the scorpion's and
/// the goat's head's limbs, heads, ears and tails) changes the trunk's capped volume by
/// 0.001 % oddly at the median turn, 0.91 % at the worst (the goat's ear, its swell held
/// at `joints::slide::MAX_SWELL`); without the swell 0.096 % and 1.00 % (the penguin's
/// head).
#[test]
fn a_trunk_swells_to_keep_its_volume_as_a_limb_turns() {
    let files = [
        "tests/data/meshes/penguin.obj",
        "tests/data/meshes/cat.obj",
        "tests/data/characters/lizard.obj",
        "tests/data/meshes/scorpion.obj",
        "tests/data/poses/goathead.obj",
    ];
    let mut worst = Worst::default();
    let mut odd = Vec::new();
    let checked = fan_turns_of(
        &files,
        60.0,
        |band| band.swell != glam::DVec3::ZERO,
        |path, p, band, [plus, minus]| {
            let change = |now: &[glam::DVec3]| volume_change(p, band.parent, now);
            let o = 0.5 * (change(plus) - change(minus));
            odd.push(o.abs());
            worst.see(o, || {
                format!(
                    "{}'s trunk (turning {})",
                    stem(path),
                    p.joints.sections()[band.child].name
                )
            });
        },
    );
    odd.sort_by(f64::total_cmp);
    let median = odd.get(odd.len() / 2).copied().unwrap_or(0.0);
    assert!(checked >= 60, "only {checked} turns");
    assert!(
        worst.0.abs() <= 0.95 && median <= 0.01,
        "{} changed by {:+.2} % oddly, the median turn {median:.3} % ({checked} turns)",
        worst.1,
        worst.0
    );
}

/// A fan turned far keeps its child's volume (`joints::slide`): each side slides along
/// the normal turned with its share of the turn, the way a neck lengthens along itself.
/// Turned alone by ±80° about four axes across its cut, each sliding fan's child (the
/// koala's head, ears and limbs, the dog's, the stuffed toy's) changes its capped volume
/// by at most 15 % (11.9 %, the koala's ear, where the first order is far off); sliding
/// along the parent's unturned normal, which at a right angle moves the child sideways
/// instead, 24.6 %.
#[test]
fn a_fan_turned_far_keeps_its_childs_volume() {
    let mut worst = Worst::default();
    let sliding = |band: &puppet::joints::Band| band.slide != glam::DVec3::ZERO;
    let checked = fan_turns(80.0, sliding, |path, p, band, turned| {
        for now in turned {
            let change = volume_change(p, band.child, now);
            worst.see(change, || {
                format!("{}'s {}", stem(path), p.joints.sections()[band.child].name)
            });
        }
    });
    assert!(checked >= 40, "only {checked} turns");
    assert!(
        worst.0.abs() <= 15.0,
        "{} changed by {:+.1} %",
        worst.1,
        worst.0
    );
}

/// The largest change seen (in %), with what changed.
#[derive(Default)]
struct Worst(f64, String);

impl Worst {
    fn see(&mut self, change: f64, what: impl FnOnce() -> String) {
        if change.abs() > self.0.abs() {
            *self = Worst(change, what());
        }
    }
}

/// A file's name without its folder or extension.
fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|x| x.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Section `s`'s capped volume change (%) with the surface at `now`, against its rest.
fn volume_change(p: &Puppet, s: usize, now: &[glam::DVec3]) -> f64 {
    let (faces, rest) = section_region(p, s);
    100.0 * (puppet::mesh::measure::capped_volume(now, &p.mesh.triangles, &faces) - rest)
        / rest.abs()
}

/// Turns each fan of the koala, the dog and the stuffed toy that `keep` accepts alone by
/// ±`degrees` about four axes across its cut, and calls `visit` with the file, the
/// puppet, the band and where its bones hold the surface turned either way; returns how
/// many turns. Fans whose child holds no volume at rest are left out.
fn fan_turns(
    degrees: f64,
    keep: impl Fn(&puppet::joints::Band) -> bool,
    visit: impl FnMut(&Path, &Puppet, &puppet::joints::Band, [&[glam::DVec3]; 2]),
) -> usize {
    let files = [
        "tests/data/poses/koala_low_resolution.obj",
        "tests/data/characters/dog.obj",
        "tests/data/characters/teddy.obj",
    ];
    fan_turns_of(&files, degrees, keep, visit)
}

/// [`fan_turns`] on the characters of `files` (paths in the repository).
fn fan_turns_of(
    files: &[&str],
    degrees: f64,
    keep: impl Fn(&puppet::joints::Band) -> bool,
    mut visit: impl FnMut(&Path, &Puppet, &puppet::joints::Band, [&[glam::DVec3]; 2]),
) -> usize {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut checked = 0;
    for path in files.iter().map(|f| root.join(f)) {
        let p = suggested(&path);
        for band in p.joints.bands().iter().flatten() {
            if band.arc || !keep(band) || section_region(&p, band.child).1.abs() < 1e-12 {
                continue;
            }
            let across = band.normal.any_orthonormal_vector();
            for k in 0..4 {
                let axis = glam::DQuat::from_axis_angle(
                    band.normal,
                    std::f64::consts::FRAC_PI_4 * k as f64,
                ) * across;
                let turned = |degrees: f64| {
                    let mut target =
                        vec![puppet::joints::Local::default(); p.joints.sections().len()];
                    target[band.child] = puppet::joints::Local::axis_angle(axis, degrees);
                    poses::targets(&p, &target)
                };
                let (plus, minus) = (turned(degrees), turned(-degrees));
                visit(&path, &p, band, [&plus, &minus]);
                checked += 1;
            }
        }
    }
    checked
}

/// Which sides of a fan slide (`joints::slide`): a limb's side under a turning child does
/// (the dog's thighs under their hind feet, turned at the hock), a trunk's does not (the dog's body under its legs
/// and head), nor the head's under the example's frog jaw, hinged at its cut's rim.
#[test]
fn a_limbs_side_slides_a_trunks_and_a_rim_hinges_do_not() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dog = suggested(&root.join("tests/data/characters/dog.obj"));
    let band = |p: &Puppet, name: &str| {
        let s = p.joints.find(name).expect(name);
        let band = p.joints.bands().iter().flatten().find(|b| b.child == s);
        band.expect("a band").clone()
    };
    for foot in ["foot.L", "foot.R"] {
        let b = band(&dog, foot);
        assert!(!b.arc && b.parent_slide.length() > 0.0, "{foot}: {}", b.arc);
    }
    for on_trunk in ["leg.L", "leg.R", "head"] {
        let b = band(&dog, on_trunk);
        assert!(!b.arc && b.slide.length() > 0.0, "{on_trunk}: {}", b.arc);
        assert_eq!(b.parent_slide, glam::DVec3::ZERO, "{on_trunk}");
    }
    let spec = puppet::RigFile::load(&root.join("assets/examples/spot-jaw.rig.toml"))
        .expect("example rig");
    let (mesh, _) = puppet::mesh::load(spec.mesh.as_deref().expect("a mesh")).expect("spot");
    let spot = Puppet::build(mesh, spec, puppet::progress::silent()).expect("a puppet");
    let jaw = band(&spot, "jaw");
    assert_eq!(jaw.parent_slide, glam::DVec3::ZERO, "the jaw's hinge slid");
}

/// Two bends on one short section keep its volume together (`joints::slide`: the cross
/// term): where a fan's band and its child's band overlap (the lizard's, the ant's and
/// the dog's thighs, upper arms and tails between two joints), the two bent by 60° about
/// axes across their cuts, four ways and either sign, change the section's capped volume
/// by at most 10 %, and by more than 5 % in at most a tenth of the turns (measured: 8.2 %,
/// the dog's tail; 10 of 176; median 0.7 %). Without the cross term, 15.2 %, 104 of 176,
/// median 5.8 %.
#[test]
fn two_bends_on_one_short_section_keep_its_volume_together() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut worst = Worst::default();
    let (mut checked, mut beyond) = (0, 0);
    for path in [
        root.join("tests/data/characters/lizard.obj"),
        root.join("tests/data/characters/ant.obj"),
        root.join("tests/data/characters/dog.obj"),
    ] {
        let p = suggested(&path);
        let bands: Vec<&puppet::joints::Band> = p.joints.bands().iter().flatten().collect();
        for band in &bands {
            if band.cross.is_empty() || section_region(&p, band.child).1.abs() < 1e-12 {
                continue;
            }
            for below in bands.iter().filter(|b| b.parent == band.child) {
                for k in 0..4 {
                    let turn = |b: &puppet::joints::Band, k: usize| {
                        let across = b.normal.any_orthonormal_vector();
                        glam::DQuat::from_axis_angle(
                            b.normal,
                            std::f64::consts::FRAC_PI_2 * k as f64,
                        ) * across
                    };
                    for (sa, sb) in [(1.0, 1.0), (1.0, -1.0)] {
                        let mut target =
                            vec![puppet::joints::Local::default(); p.joints.sections().len()];
                        target[band.child] =
                            puppet::joints::Local::axis_angle(turn(band, k), 60.0 * sa);
                        target[below.child] =
                            puppet::joints::Local::axis_angle(turn(below, k), 60.0 * sb);
                        let now = poses::targets(&p, &target);
                        let change = volume_change(&p, band.child, &now);
                        worst.see(change, || {
                            format!("{}'s {}", stem(&path), p.joints.sections()[band.child].name)
                        });
                        checked += 1;
                        beyond += usize::from(change.abs() > 5.0);
                    }
                }
            }
        }
    }
    assert!(checked >= 100, "only {checked} turns");
    assert!(
        worst.0.abs() <= 10.0,
        "{} changed by {:+.1} %",
        worst.1,
        worst.0
    );
    assert!(
        beyond * 10 <= checked,
        "{beyond} of {checked} turns changed a section by more than 5 %"
    );
}

/// An arc's child side slides along the bend by what keeps the child's volume
/// (`joints::slide`, *Arcs*): each of the 46 arcs of the lizard, the dino, the horse and
/// the scorpion turned alone by ±60° about four axes across its cut, where its bones hold
/// the surface, changes its child's volume by at most 2 % at the median arc and 12 % at
/// the worst (the horse's hoof, its slide held at `joints::slide::MAX_SLIDE`).
#[test]
fn an_arc_turned_alone_keeps_its_childs_volume() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut worst = Worst::default();
    let mut per_arc: Vec<f64> = Vec::new();
    let mut checked = 0;
    for file in [
        "tests/data/characters/lizard.obj",
        "tests/data/characters/dino.obj",
        "tests/data/characters/horse.obj",
        "tests/data/meshes/scorpion.obj",
    ] {
        let path = root.join(file);
        let p = suggested(&path);
        for band in p.joints.bands().iter().flatten() {
            if !band.arc || section_region(&p, band.child).1.abs() < 1e-12 {
                continue;
            }
            let across = band.normal.any_orthonormal_vector();
            let mut this = 0.0f64;
            for k in 0..4 {
                let axis = glam::DQuat::from_axis_angle(
                    band.normal,
                    std::f64::consts::FRAC_PI_4 * k as f64,
                ) * across;
                for degrees in [60.0, -60.0] {
                    let mut target =
                        vec![puppet::joints::Local::default(); p.joints.sections().len()];
                    target[band.child] = puppet::joints::Local::axis_angle(axis, degrees);
                    let change = volume_change(&p, band.child, &poses::targets(&p, &target));
                    worst.see(change, || {
                        format!("{}'s {}", stem(&path), p.joints.sections()[band.child].name)
                    });
                    this = this.max(change.abs());
                    checked += 1;
                }
            }
            per_arc.push(this);
        }
    }
    assert!(per_arc.len() >= 40, "only {} arcs", per_arc.len());
    assert_eq!(checked, 8 * per_arc.len());
    let median = puppet::stats::median(&mut per_arc).unwrap_or(0.0);
    assert!(median <= 2.0, "the median arc changed by {median:.1} %");
    assert!(
        worst.0.abs() <= 12.0,
        "{} changed by {:+.1} %",
        worst.1,
        worst.0
    );
}

/// A pose gives back what the slides leave of each section's volume (`joints::volume`):
/// on five downloads of four kinds (two men in clothes, a trex, a triceratops, an
/// alpaca), where the bones hold the surface in seeded random poses, at most a third as
/// many poses have a section beyond ±5 % with the bands swollen as with the slides alone
/// (`PoseScratch::first_order`), and no pose's most changed section changes more than 1
/// point further. As `bench poses` measures: each
/// section's capped volume, against a hundredth of the whole's at least.
#[test]
fn a_pose_gives_back_the_volume_its_slides_leave() {
    use puppet::joints::PoseScratch;
    use puppet::puppet::press::section_volumes;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/population");
    let (mut kept_beyond, mut first_beyond) = (0, 0);
    for name in ["man-farmer", "man-casual2", "trex", "triceratops", "alpaca"] {
        let p = common::suggested_from_shape(&root.join(format!("{name}.glb")));
        let transform_of = p.joints.transform_of().to_vec();
        for seed in 1..=10 {
            let local = poses::random_pose(&p.joints, Spread::default(), &mut SplitMix(seed));
            let at = |mut scratch: PoseScratch| -> f64 {
                let pose = p.joints.pose_into(&local, &mut scratch);
                let now: Vec<glam::DVec3> = (p.mesh.positions.iter().zip(&transform_of))
                    .map(|(&x, &t)| {
                        let m = pose.transforms[usize::from(t)];
                        m.transform_point3(x.as_vec3()).as_dvec3()
                    })
                    .collect();
                let [lo, hi] = section_volumes(&p, &now);
                lo.abs().max(hi.abs())
            };
            let kept = at(PoseScratch::default());
            let first = at(PoseScratch::first_order());
            assert!(
                kept <= first + 0.01,
                "{name} seed {seed}: {:.1} % against {:.1} % by the slides alone",
                100.0 * kept,
                100.0 * first
            );
            kept_beyond += usize::from(kept > 0.05);
            first_beyond += usize::from(first > 0.05);
        }
    }
    assert!(
        first_beyond >= 10 && kept_beyond * 3 <= first_beyond,
        "poses beyond ±5 %: {kept_beyond} kept, {first_beyond} by the slides alone"
    );
}

/// A rider (an eye, a crown, a backpack) rides on its host's motion made rigid about
/// the host (`joints::band::Twin`): where the band its host moves with swells to keep a
/// section's volume, the rider keeps its shape and stays on its host. The downloads
/// whose riders' hosts lie in swelling bands (the king, the adventurer, a mech), 10
/// random poses each: every rider edge keeps its length (within 10⁻⁵ of the diagonal:
/// single precision), each host lands
/// where its own transform puts it, and in some pose of each a host's transform scales
/// by more than 1 % (the rider, on that transform, would have scaled with it).
#[test]
fn riders_keep_their_shape_where_their_hosts_swell() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/population");
    for name in ["man-king", "man-adventurer", "mech-george"] {
        let p = common::suggested_from_shape(&root.join(format!("{name}.glb")));
        let rest = &p.mesh.positions;
        let hosts = puppet::mesh::Parts::of(&p.mesh).hosts(rest);
        let transform_of = p.joints.transform_of();
        let edges: Vec<(usize, usize)> = puppet::mesh::unique_edges(&p.mesh.triangles)
            .into_iter()
            .map(|(a, b)| (a as usize, b as usize))
            .filter(|&(a, b)| hosts[a].is_some() && hosts[b].is_some())
            .collect();
        assert!(!edges.is_empty(), "{name}: riders");
        let (mut worst, mut scaled, mut off) = (0.0f64, 0.0f64, 0.0f64);
        for seed in 1..=10 {
            let local = poses::random_pose(&p.joints, Spread::default(), &mut SplitMix(seed));
            let pose = p.joints.pose(&local);
            let at = |v: usize, t: u16| {
                pose.transforms[usize::from(t)]
                    .transform_point3(rest[v].as_vec3())
                    .as_dvec3()
            };
            for &(a, b) in &edges {
                let r = rest[a].distance(rest[b]);
                if r > 0.0 {
                    let now = at(a, transform_of[a]).distance(at(b, transform_of[b]));
                    worst = worst.max((now - r).abs());
                }
            }
            for (v, h) in hosts.iter().enumerate() {
                let Some(h) = h.map(|h| h as usize) else {
                    continue;
                };
                let host = pose.transforms[usize::from(transform_of[h])];
                let m = glam::Mat3::from(host.matrix3);
                let strain = (m.transpose() * m - glam::Mat3::IDENTITY).abs();
                let s = strain.to_cols_array().into_iter().fold(0.0f32, f32::max);
                scaled = scaled.max(f64::from(s));
                // The rider's transform puts the host where the host's own does.
                let twin = pose.transforms[usize::from(transform_of[v])];
                let x = rest[h].as_vec3();
                off = off.max(f64::from(
                    twin.transform_point3(x).distance(host.transform_point3(x)),
                ));
            }
        }
        let diagonal = p.mesh.diagonal();
        assert!(
            worst < 1e-5 * diagonal,
            "{name}: a rider's edge changed by {worst:.2e}"
        );
        assert!(
            off < 1e-4 * diagonal,
            "{name}: a rider {off:.2e} off its host"
        );
        assert!(scaled > 0.01, "{name}: no host swelled ({scaled:.4})");
    }
}

/// Creases shaded on every shipped character (`geom::occlusion`), at rest and in a
/// settled random pose: every vertex's occlusion is a number in `0..=1`, and most of the
/// skin stays open (the downloads measured: at most 41 % of vertices past one half, a mech
/// of overlapping plates; median 7 % at rest).
#[test]
fn creases_are_shaded_on_every_shipped_character_without_darkening_it_whole() {
    use glam::Vec3;
    use puppet::geom::occlusion::Occluders;
    for path in population() {
        let p = suggested(&path);
        let mut occluders = Occluders::new(
            &p.mesh.positions,
            &p.mesh.triangles,
            &p.skeleton.points,
            &p.skeleton.distance,
            p.joints.section_of(),
        );
        let target = poses::random_pose(&p.joints, Spread::default(), &mut SplitMix(1));
        let mut posed = p.clone();
        poses::settle(&mut posed, &target);
        for (when, puppet) in [("at rest", &p), ("posed", &posed)] {
            let x = puppet.sim.positions();
            let positions: Vec<Vec3> = (0..x.len()).map(|i| x.get(i)).collect();
            let mut normals = Vec::new();
            puppet::mesh::area_normals_into(&positions, &p.mesh.triangles, &mut normals);
            let mut out = Vec::new();
            occluders.shade(&positions, &normals, &mut out);
            let name = path.display();
            assert_eq!(out.len(), positions.len(), "{name} {when}");
            assert!(
                out.iter().all(|o| (0.0..=1.0).contains(o)),
                "{name} {when}: an occlusion outside 0..=1"
            );
            let dark = out.iter().filter(|&&o| o > 0.5).count();
            assert!(
                dark * 2 < out.len(),
                "{name} {when}: {dark} of {} vertices past one half",
                out.len()
            );
        }
    }
}
