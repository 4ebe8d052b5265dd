//! Meshes people actually have: holes, flipped faces, open seams, small separate parts, PLY
//! and STL files. What can be repaired loads with a warning that says what was done.
//!
//! The second half makes meshes as people have them from the test meshes, one defect each:
//! every one loads with the warning that says what was repaired, builds a puppet whose
//! skeletal points lie inside the repaired surface (the exact winding number), and survives
//! a violent pose without a non-finite or runaway point; what has no inside is refused in
//! one line. Then the defect corpus of `tests/data/defects/` (its README lists the files
//! and their sources), checked the same way and against the file's own triangles by the
//! generalized winding number.

mod common;

use common::{obj, ply_ascii, ply_binary, puppet, scratch, stl_ascii, stl_binary, test_mesh};
use glam::DVec3;
use puppet::geom::inside::InsideTest;
use puppet::geom::winding::Winding;
use puppet::joints::{Cut, Local, Shape};
use puppet::mesh::{self, shapes, Format, LoadOptions, Mesh};
use puppet::{Puppet, RigFile};
use std::path::{Path, PathBuf};

const TETRA: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// `puppet skeleton FILE --json ARGS`: (status, summary or null, stderr).
fn skeleton(path: &Path, args: &[&str]) -> (Option<i32>, serde_json::Value, String) {
    let mut all = vec!["skeleton", path.to_str().unwrap(), "--json"];
    all.extend_from_slice(args);
    let out = puppet(&all);
    let summary = serde_json::from_slice(&out.stdout).unwrap_or(serde_json::Value::Null);
    (
        out.status.code(),
        summary,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn holes_flipped_faces_and_seams_are_repaired_with_a_warning() {
    let dir = scratch("repairs");
    // A tetrahedron missing a face: a 3-edge hole.
    let open = write(&dir, "open.obj", TETRA.replace("f 2 3 4\n", "").as_bytes());
    let (code, v, err) = skeleton(&open, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("filled 1 hole with 1 new face"), "{err}");
    assert_eq!(v["faces"], 4);
    // One face turned the wrong way.
    let flipped = write(
        &dir,
        "flipped.obj",
        TETRA.replace("f 2 3 4", "f 2 4 3").as_bytes(),
    );
    let (code, v, err) = skeleton(&flipped, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("turned 1 face oriented against its neighbours"),
        "{err}"
    );
    assert_eq!(v["vertices"], 4);

    // A sphere without its north cap: a 40-edge hole, closed by default with well-shaped
    // triangles faired to continue the sphere; `--fill-holes` below its size refuses it.
    let mut sphere = shapes::uv_sphere(1.0, 12, 40);
    sphere.triangles.retain(|t| !t.contains(&0));
    let capless = write(&dir, "capless.obj", &obj(&sphere));
    let (code, _, err) = skeleton(&capless, &["--fill-holes", "32"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("1 hole larger than the 32 edges filled (the largest has 40: --fill-holes 40 closes it)"),
        "{err}"
    );
    let (code, v, err) = skeleton(&capless, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("filled 1 hole with "), "{err}");
    let added = v["vertices"].as_u64().unwrap() as usize + 1 - sphere.positions.len();
    assert!(
        added > 1,
        "new vertices inside the hole, not one fan centre: {err}"
    );
    assert!(
        err.contains(&format!(
            "{} new faces and {added} new vertices",
            2 * added + 38
        )),
        "a disc of {added} vertices in a 40-edge loop: {err}"
    );
    // The skeleton of the closed sphere: every skeletal point inside it.
    assert!(v["d_max"].as_f64().unwrap() <= 1.1, "{v}");

    // An open seam: one ring of the sphere duplicated a hair apart for half the faces.
    let mut seam = shapes::uv_sphere(1.0, 12, 24);
    let n = seam.positions.len() as u32;
    let ring: Vec<u32> = (1..=24).collect();
    for &v in &ring {
        let p = seam.positions[v as usize];
        seam.positions.push(p + DVec3::splat(1e-5));
    }
    for t in &mut seam.triangles {
        if t.iter().all(|&v| v != 0) && t.iter().any(|v| ring.contains(v)) {
            *t = t.map(|v| if ring.contains(&v) { v - 1 + n } else { v });
        }
    }
    let seamed = write(&dir, "seam.obj", &obj(&seam));
    let (code, v, err) = skeleton(&seamed, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("closed open seams by welding 24 vertex pairs"),
        "{err}"
    );
    assert_eq!(v["vertices"], n as usize);
}

#[test]
fn ply_and_stl_load_like_obj() {
    let dir = scratch("formats");
    let (spot, _) = mesh::load(&test_mesh("spot-small.obj")).unwrap();
    let (code, reference, err) = skeleton(&test_mesh("spot-small.obj"), &[]);
    assert_eq!(code, Some(0), "{err}");
    let files = [
        ("spot.ply", ply_ascii(&spot)),
        ("spot-binary.ply", ply_binary(&spot)),
        ("spot.stl", stl_ascii(&spot)),
        ("spot-binary.STL", stl_binary(&spot)),
        // Format by content when the name says nothing.
        ("spot-ply.mesh", ply_binary(&spot)),
        ("spot-stl.mesh", stl_binary(&spot)),
    ];
    for (name, bytes) in files {
        let path = write(&dir, name, &bytes);
        let (code, v, err) = skeleton(&path, &[]);
        assert_eq!(code, Some(0), "{name}: {err}");
        assert!(!err.contains("warn"), "{name}: a clean file: {err}");
        assert_eq!(v["vertices"], reference["vertices"], "{name}");
        assert_eq!(v["faces"], reference["faces"], "{name}");
        // f32 files hold the cow to 1e-7: the skeleton is the same to about that.
        let (a, b) = (
            v["d_median"].as_f64().unwrap(),
            reference["d_median"].as_f64().unwrap(),
        );
        assert!((a - b).abs() <= 1e-5 * b, "{name}: median d {a} vs {b}");
    }
    // Broken files: one error line each.
    let broken: [(&str, Vec<u8>); 4] = [
        ("cut.ply", ply_binary(&spot)[..2000].to_vec()),
        ("bad-header.ply", b"ply\nformat ascii 1.0\nelement vertex x\nend_header\n".to_vec()),
        ("no-faces.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n".to_vec()),
        ("cut.stl", stl_binary(&spot)[..1000].to_vec()),
    ];
    for (name, bytes) in broken {
        let path = write(&dir, name, &bytes);
        let (code, _, err) = skeleton(&path, &[]);
        assert_eq!(code, Some(2), "{name}: {err}");
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{name}: {err}");
        assert!(
            lines[0].starts_with(&format!("error: {}: ", path.display())),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{name}: {err}");
    }
    // A face naming a vertex that does not exist.
    let bad = String::from_utf8(ply_ascii(&spot))
        .unwrap()
        .replacen("\n3 ", "\n3 999999 ", 1);
    let path = write(&dir, "bad-index.ply", bad.as_bytes());
    let (code, _, err) = skeleton(&path, &[]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("names vertex 999999"), "{err}");
}

/// A capsule along y (an arm, radius 0.3, from -1.8 to 1.8) with two small beads: one
/// inside its upper end, one stuck on the outside near the bottom.
fn arm_with_beads() -> (Mesh, usize, [std::ops::Range<usize>; 2]) {
    let mut m = shapes::capsule(0.3, 1.5, 6, 36, 20);
    let body = m.positions.len();
    let mut ranges = Vec::new();
    for centre in [DVec3::new(0.0, 1.5, 0.0), DVec3::new(0.33, -1.4, 0.0)] {
        let bead = shapes::icosphere(0.05, 1);
        let off = m.positions.len() as u32;
        m.positions
            .extend(bead.positions.iter().map(|p| *p + centre));
        m.triangles
            .extend(bead.triangles.iter().map(|t| t.map(|v| v + off)));
        ranges.push(off as usize..m.positions.len());
    }
    (m, body, [ranges[0].clone(), ranges[1].clone()])
}

#[test]
fn small_separate_parts_ride_with_the_section_they_sit_in() {
    let (m, body, beads) = arm_with_beads();
    let dir = scratch("riders");
    let path = write(&dir, "arm.obj", &obj(&m));
    let (code, v, err) = skeleton(&path, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("2 small separate parts ride along with the body (no skeleton of their own)"),
        "{err}"
    );
    assert_eq!(v["riders"], beads[0].len() + beads[1].len());

    // The body's skeleton is the arm's alone, to the bit: the bead inside changes nothing.
    let (mesh, _) = mesh::load(&path).unwrap();
    let normals = mesh::vertex_normals(&mesh).unwrap();
    let params = puppet::skeleton::SkeletonParams::default();
    let silent = puppet::progress::silent();
    let sk = puppet::skeleton::build(&mesh, &normals, &params, silent).unwrap();
    let arm = shapes::capsule(0.3, 1.5, 6, 36, 20);
    let arm_sk =
        puppet::skeleton::build(&arm, &mesh::vertex_normals(&arm).unwrap(), &params, silent)
            .unwrap();
    assert_eq!(sk.distance[..body], arm_sk.distance[..]);
    for r in &beads {
        assert!(sk.distance[r.clone()].iter().all(|&d| d == 0.0));
    }

    // Cut the arm at its middle and turn the upper half: the bead inside it turns with it,
    // rigidly; the one below stays where it was.
    let spec = RigFile {
        cuts: vec![Cut {
            name: "upper".into(),
            section: "root".into(),
            point: DVec3::ZERO,
            normal: DVec3::Y,
            pivot: None,
            connected: false,
            band: None,
            shape: Shape::Plane,
            shared_pivot: false,
        }],
        ..RigFile::default()
    };
    let mut p = Puppet::build(mesh, spec, silent).unwrap();
    let upper = p.joints.find("upper").unwrap();
    let section_of = p.joints.section_of().to_vec();
    assert!(beads[0].clone().all(|v| section_of[v] as usize == upper));
    assert!(beads[1].clone().all(|v| section_of[v] == 0));
    let mut local = vec![Local::default(); p.joints.sections().len()];
    local[upper] = Local::axis_angle(DVec3::Z, 60.0);
    let pose = p.joints.pose(&local);
    for _ in 0..600 {
        p.sim.step(&pose);
    }
    let world = p.joints.world(&local);
    let x = p.sim.positions();
    for (r, section) in [(beads[0].clone(), upper), (beads[1].clone(), 0)] {
        for v in r {
            let want = world[section].transform_point3(p.mesh.positions[v]);
            let got = x.get(v).as_dvec3();
            assert!(
                got.distance(want) < 1e-4,
                "bead vertex {v}: {got} vs {want}"
            );
        }
    }
}

fn load(name: &str) -> Mesh {
    mesh::load(&test_mesh(name)).unwrap().0
}

/// Loads `bytes`, checks the warning, builds the puppet with its suggested joints and
/// turns every section hard for a second of steps.
fn survives(name: &str, bytes: &[u8], format: Format, warning: &str) {
    let (m, report) = mesh::parse(
        bytes,
        format,
        &LoadOptions::default(),
        puppet::progress::silent(),
    )
    .unwrap_or_else(|e| panic!("{name}: refused: {e}"));
    let warnings = report.warnings().join("; ");
    assert!(warnings.contains(warning), "{name}: {warnings}");
    let mut p = Puppet::build_loaded(
        m,
        Some(&report),
        RigFile::default(),
        puppet::progress::silent(),
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    // Skeletal points inside the surface the puppet is made of (riders have none).
    let inside = InsideTest::new(&p.mesh);
    let outside = p
        .skeleton
        .points
        .iter()
        .zip(&p.skeleton.distance)
        .filter(|&(s, &d)| d > 0.0 && !inside.contains(*s))
        .count();
    // None, by the winding number: the shipped human passes through itself at the toes
    // and the crotch, where the parity of a ray's crossings put 35 of its points outside.
    assert_eq!(outside, 0, "{name}: skeletal points outside");
    shake(name, &mut p);
}

/// Builds the suggested joints and turns every section hard (120°, each about its own
/// axis) for a second of steps: no point may become non-finite or run further from where
/// its bones hold it than its own medial radius (the constraint keeps it within a few
/// hundredths of one: at most 0.05 on every mesh here; the bound was a whole diagonal).
fn shake(name: &str, p: &mut Puppet) {
    let _ = p.suggest_joints();
    let sections = p.joints.sections().len();
    let size = p.mesh.diagonal();
    let local: Vec<Local> = (0..sections)
        .map(|k| Local::axis_angle(DVec3::new(1.0, k as f64, 0.5), 120.0))
        .collect();
    let pose = p.joints.pose(&local);
    for _ in 0..60 {
        p.sim.step(&pose);
    }
    let x = p.sim.positions();
    for i in 0..x.len() {
        let y = x.get(i);
        assert!(y.is_finite(), "{name}: vertex {i} not finite");
        let drift = (y - p.sim.target(i)).length() as f64;
        let radius = p.skeleton.distance[i].max(1e-4 * size);
        assert!(
            drift <= radius,
            "{name}: vertex {i} ran {drift} from its target, beyond its medial radius {radius}"
        );
    }
}

#[test]
fn open_meshes_are_closed_and_become_puppets() {
    // A scan's open base: the bunny's lowest faces gone (a large hole).
    let bunny = load("bunny.obj");
    let lo = bunny.positions.iter().map(|p| p.y).fold(f64::MAX, f64::min);
    let hi = bunny.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
    let mut base = bunny.clone();
    base.triangles.retain(|t| {
        t.iter()
            .any(|&v| bunny.positions[v as usize].y > lo + 0.04 * (hi - lo))
    });
    survives("open base", &obj(&base), Format::Obj, "filled 1 hole");
    // A character's open neck: the human's head gone.
    let human = load("human.obj");
    let lo = human.positions.iter().map(|p| p.y).fold(f64::MAX, f64::min);
    let hi = human.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
    let mut neck = human.clone();
    neck.triangles.retain(|t| {
        t.iter()
            .all(|&v| human.positions[v as usize].y < lo + 0.87 * (hi - lo))
    });
    survives("open neck", &obj(&neck), Format::Obj, "filled 1 hole");
    // Several holes at once: every tenth face of the small Spot gone where they do not touch.
    let spot = load("spot-small.obj");
    let mut holes = spot.clone();
    let mut used = vec![false; spot.positions.len()];
    holes.triangles.retain(|t| {
        if t.iter().any(|&v| used[v as usize]) {
            return true;
        }
        t.iter().for_each(|&v| used[v as usize] = true);
        false
    });
    survives("many holes", &obj(&holes), Format::Obj, "holes with");
}

#[test]
fn touching_sheets_and_duplicates_become_puppets() {
    // Two copies of the small Spot touching at one vertex (a pinch): the second turned
    // half a turn about that vertex.
    let spot = load("spot-small.obj");
    let pin = spot.positions[0];
    let n = spot.positions.len() as u32;
    let mut pinched = spot.clone();
    pinched.positions.extend(spot.positions.iter().map(|p| {
        let d = *p - pin;
        pin + DVec3::new(-d.x, -d.y, d.z)
    }));
    pinched.triangles.extend(
        spot.triangles
            .iter()
            .map(|t| t.map(|v| if v == 0 { 0 } else { v + n })),
    );
    // (The turned copy overlaps the first: what the skeleton sees as inside is their union.)
    let (m, report) = mesh::parse(
        &obj(&pinched),
        Format::Obj,
        &LoadOptions::default(),
        puppet::progress::silent(),
    )
    .expect("the pinched pair loads");
    assert!(
        report
            .warnings()
            .join("; ")
            .contains("its own copy of 1 vertex"),
        "{:?}",
        report.warnings()
    );
    assert_eq!(m.triangles.len(), 2 * spot.triangles.len());
    // Duplicate faces: every face written twice, once each way round (welding and the
    // sheet split leave a closed surface or refuse it in one line).
    let mut twice = spot.clone();
    twice
        .triangles
        .extend(spot.triangles.iter().map(|t| [t[0], t[1], t[2]]));
    let r = mesh::parse(
        &obj(&twice),
        Format::Obj,
        &LoadOptions::default(),
        puppet::progress::silent(),
    );
    if let Err(e) = r {
        assert!(!e.to_string().contains('\n'), "{e}");
    }
    // A soup closed only up to a tolerance: every vertex written once per face, moved by
    // a millionth of the size: welded back into the small Spot.
    let mut soup = Mesh {
        positions: Vec::new(),
        triangles: Vec::new(),
    };
    let size = spot.diagonal();
    for t in &spot.triangles {
        let base = soup.positions.len() as u32;
        for &v in t {
            soup.positions
                .push(spot.positions[v as usize] + DVec3::splat(1e-9 * size));
        }
        soup.triangles.push([base, base + 1, base + 2]);
    }
    survives("soup", &obj(&soup), Format::Obj, "welded");
}

#[test]
fn triangle_strips_and_flipped_parts_become_puppets() {
    let hand = load("hand.obj");
    // As one triangle strip per face (a PLY tristrips element).
    let mut ply = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n",
        hand.positions.len()
    );
    for p in &hand.positions {
        ply += &format!("{} {} {}\n", p.x, p.y, p.z);
    }
    let strip: Vec<String> = hand
        .triangles
        .iter()
        .flat_map(|t| [t[0] as i64, t[1] as i64, t[2] as i64, -1])
        .map(|v| v.to_string())
        .collect();
    ply += &format!("{} {}\n", strip.len(), strip.join(" "));
    let (m, _) = mesh::parse(
        ply.as_bytes(),
        Format::Ply,
        &LoadOptions::default(),
        puppet::progress::silent(),
    )
    .expect("strips read");
    assert_eq!(
        m.triangles, hand.triangles,
        "the same triangles as the faces"
    );
    // The whole hand inside out.
    let mut flipped = hand.clone();
    flipped.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    survives("inside out", &obj(&flipped), Format::Obj, "was inside out");
}

// ---------------------------------------------------------------------------------------
// The defect corpus: `tests/data/defects/`, one file per defect, listed with what loading
// must say in `corpus.toml` (written with the files by `regenerate_the_defect_corpus`).

/// The corpus folder.
fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/defects")
}

/// One corpus file as `corpus.toml` lists it.
#[derive(Debug, serde::Deserialize, serde::Serialize)]
struct Defect {
    /// File name in the corpus folder.
    file: String,
    /// What is wrong with it, in words.
    defect: String,
    /// What it was made from (see the folder's README for credits).
    source: String,
    /// Lines loading must warn (each a part of one warning).
    #[serde(default)]
    warns: Vec<String>,
    /// The groups the file names, when it names some.
    #[serde(default)]
    groups: Vec<String>,
    /// A part of the one-line refusal, for what has no inside.
    #[serde(default)]
    refused: Option<String>,
}

#[derive(Debug, serde::Deserialize, serde::Serialize)]
struct Corpus {
    defect: Vec<Defect>,
}

/// Every corpus file loads as its entry says: refused in one line, or repaired with the
/// warnings it lists, its groups named, then a puppet whose every skeletal point is inside
/// the mesh *as the file has it* by the generalized winding number (holes and all), which
/// survives a violent pose without a non-finite or runaway point.
#[test]
fn every_mesh_of_the_defect_corpus_becomes_a_puppet_or_is_refused_in_one_line() {
    let text = std::fs::read_to_string(corpus_dir().join("corpus.toml")).unwrap();
    let corpus: Corpus = toml::from_str(&text).unwrap();
    assert!(corpus.defect.len() >= 25, "{} files", corpus.defect.len());
    // The list, the folder and its README agree.
    let readme = std::fs::read_to_string(corpus_dir().join("README.md")).unwrap();
    let mut files: Vec<String> = std::fs::read_dir(corpus_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|f| f != "README.md" && f != "corpus.toml")
        .collect();
    files.sort();
    let mut listed: Vec<String> = corpus.defect.iter().map(|d| d.file.clone()).collect();
    listed.sort();
    assert_eq!(
        files, listed,
        "files in tests/data/defects against corpus.toml"
    );
    for f in &listed {
        assert!(
            readme.contains(&format!("`{f}`")),
            "README.md does not list {f}"
        );
    }
    let mut worst = Vec::new();
    for d in &corpus.defect {
        let path = corpus_dir().join(&d.file);
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", d.file));
        let format = Format::of(Some(&path), &bytes);
        let loaded = mesh::parse(
            &bytes,
            format,
            &LoadOptions::default(),
            puppet::progress::silent(),
        );
        if let Some(why) = &d.refused {
            let e = loaded.expect_err(&d.file).to_string();
            assert!(
                !e.contains('\n') && e.contains(why.as_str()),
                "{}: {e}",
                d.file
            );
            continue;
        }
        let (m, report) = loaded.unwrap_or_else(|e| panic!("{}: refused: {e}", d.file));
        let warnings = report.warnings().join("; ");
        for w in &d.warns {
            assert!(warnings.contains(w.as_str()), "{}: {warnings}", d.file);
        }
        assert_eq!(report.groups.names, d.groups, "{}", d.file);
        let mut p = Puppet::build_loaded(
            m,
            Some(&report),
            RigFile::default(),
            puppet::progress::silent(),
        )
        .unwrap_or_else(|e| panic!("{}: {e}", d.file));
        // Inside the file's own triangles, as given.
        let given = mesh::parse_file_mesh(&bytes, format).unwrap();
        let winding = Winding::new(&given.positions, &given.triangles);
        let exact = InsideTest::new(&p.mesh);
        let (mut least, mut below, mut total, mut outside) = (f64::INFINITY, 0, 0, 0);
        for (s, &dist) in p.skeleton.points.iter().zip(&p.skeleton.distance) {
            if dist > 0.0 {
                outside += usize::from(!exact.contains(*s));
                let w = winding.at(*s).abs();
                least = least.min(w);
                below += usize::from(w < 0.5);
                total += 1;
            }
        }
        // Inside the repaired surface, exactly; inside the file's own triangles by the
        // generalized winding number, which holes and faces turned the wrong way pull
        // towards 0.5 near them: all points clear of outside (0.3), 90 % past 0.5 (a tube
        // open at both ends has 6 % of its points near its open ends, below 0.5).
        if outside > 0 {
            let fit =
                puppet::mesh::fit_surface(&p.mesh, &puppet::mesh::vertex_normals(&p.mesh).unwrap());
            for (i, (s, &dist)) in p
                .skeleton
                .points
                .iter()
                .zip(&p.skeleton.distance)
                .enumerate()
            {
                if dist > 0.0 && !exact.contains(*s) {
                    let n = (p.mesh.positions[i] - *s) / dist;
                    eprintln!(
                        "{i} (of {}): p {:.3} d {dist:.4} n {n:.3} fitted {} new? {}",
                        p.mesh.positions.len(),
                        p.mesh.positions[i],
                        fit.fitted[i],
                        report
                            .marks
                            .hole_faces
                            .iter()
                            .any(|&f| p.mesh.triangles[f as usize].contains(&(i as u32)))
                    );
                }
            }
        }
        assert_eq!(
            outside, 0,
            "{}: skeletal points outside the repaired mesh",
            d.file
        );
        assert!(
            least >= 0.3 && below * 10 <= total,
            "{}: winding number {least:.2} at least, {below} of {total} points below 0.5",
            d.file
        );
        worst.push(format!(
            "{} {least:.2} ({below} of {total} below 0.5)",
            d.file
        ));
        shake(&d.file, &mut p);
    }
    eprintln!(
        "least winding number of a skeletal point:\n{}",
        worst.join("\n")
    );
}

/// Writes the corpus and its list. Run by hand (`cargo test --release --test repair --
/// --ignored regenerate`) after changing what it makes; the files are committed.
#[test]
#[ignore]
fn regenerate_the_defect_corpus() {
    let dir = corpus_dir();
    std::fs::create_dir_all(&dir).unwrap();
    let list = std::cell::RefCell::new(Vec::new());
    let add = |file: &str, bytes: Vec<u8>, defect: &str, source: &str, warns: &[&str]| {
        std::fs::write(dir.join(file), bytes).unwrap();
        list.borrow_mut().push(Defect {
            file: file.into(),
            defect: defect.into(),
            source: source.into(),
            warns: warns.iter().map(|w| w.to_string()).collect(),
            groups: Vec::new(),
            refused: None,
        });
    };
    let spot = load("spot-small.obj");
    let bunny = load("bunny.obj");
    let (spot_src, bunny_src, made) = ("spot-small", "bunny", "generated");
    let join = |a: &Mesh, b: &Mesh| {
        let mut m = a.clone();
        let n = m.positions.len() as u32;
        m.positions.extend(&b.positions);
        m.triangles
            .extend(b.triangles.iter().map(|t| t.map(|v| v + n)));
        m
    };
    let moved = |m: &Mesh, f: &dyn Fn(DVec3) -> DVec3| Mesh {
        positions: m.positions.iter().map(|&p| f(p)).collect(),
        triangles: m.triangles.clone(),
    };
    let keep = |m: &Mesh, f: &dyn Fn(DVec3) -> bool| Mesh {
        positions: m.positions.clone(),
        triangles: m
            .triangles
            .iter()
            .filter(|t| {
                let c = t.iter().map(|&v| m.positions[v as usize]).sum::<DVec3>() / 3.0;
                f(c)
            })
            .copied()
            .collect(),
    };
    let (lo, hi) = spot.bounds();
    let at = |axis: usize, f: f64| lo[axis] + f * (hi[axis] - lo[axis]);

    // Touching sheets.
    let pin = spot.positions[0];
    let turned = moved(&spot, &|p| {
        let d = p - pin;
        pin + DVec3::new(-d.x, -d.y, d.z)
    });
    add("pinch-cows.obj", obj(&join(&spot, &turned)), "two cows touching at one vertex, the second turned half a turn about it (their volumes overlap)", spot_src, &["its own copy of 1 vertex"]);
    let ball = shapes::uv_sphere(1.0, 8, 16);
    let above = moved(&ball, &|p| p + DVec3::new(0.0, 2.0, 0.0));
    add(
        "pinch-balls.obj",
        obj(&join(&ball, &above)),
        "two balls touching at a pole (a classic pinched vertex)",
        made,
        &["its own copy of 1 vertex"],
    );
    let huge = moved(&join(&ball, &above), &|p| p * 1e4);
    add(
        "pinch-balls-huge.obj",
        obj(&huge),
        "the pinched balls, 40,000 units tall",
        made,
        &["its own copy of 1 vertex"],
    );
    let cube = shapes::cube_grid(1.0, 2);
    let beside = moved(&cube, &|p| p + DVec3::new(1.0, 1.0, 0.0));
    add(
        "bowtie-edge.obj",
        obj(&join(&cube, &beside)),
        "two boxes sharing one edge (a bowtie: edges of four faces)",
        made,
        &["opening 2 edges shared by more than two faces"],
    );

    // Holes.
    add(
        "open-hooves.obj",
        obj(&keep(&spot, &|c| c.y > at(1, 0.06))),
        "the cow with its hooves cut off: four holes",
        spot_src,
        &["filled 4 holes"],
    );
    add(
        "open-neck.obj",
        obj(&keep(&spot, &|c| c.z > at(2, 0.3))),
        "the cow with its head cut off: one large hole",
        spot_src,
        &["filled 1 hole"],
    );
    let tiny = moved(&keep(&spot, &|c| c.z > at(2, 0.3)), &|p| p * 1e-4);
    add(
        "open-neck-tiny.obj",
        obj(&tiny),
        "the headless cow a ten-thousandth of its size",
        spot_src,
        &["filled 1 hole"],
    );
    let (blo, bhi) = bunny.bounds();
    add(
        "open-base-scan.obj",
        obj(&keep(&bunny, &|c| c.y > blo.y + 0.04 * (bhi.y - blo.y))),
        "a scan's open base: the bunny's lowest faces gone",
        bunny_src,
        &["filled 1 hole"],
    );
    let tube = keep(&shapes::capsule(0.4, 1.0, 6, 8, 20), &|c| c.y.abs() < 1.0);
    add(
        "open-tube.obj",
        obj(&tube),
        "a tube open at both ends",
        made,
        &["filled 2 holes"],
    );
    let mut used = vec![false; spot.positions.len()];
    let mut holes = spot.clone();
    holes.triangles.retain(|t| {
        if t.iter().any(|&v| used[v as usize]) {
            return true;
        }
        t.iter().for_each(|&v| used[v as usize] = true);
        false
    });
    add(
        "many-holes.obj",
        obj(&holes),
        "the cow with a face missing wherever one can go without touching another hole",
        spot_src,
        &["holes with"],
    );
    // Two holes sharing a vertex: two adjacent faces of a ball's fan gone... apart at the
    // pole's opposite corners: they meet at the pole only.
    let north = (0..ball.positions.len())
        .max_by(|&a, &b| ball.positions[a].y.total_cmp(&ball.positions[b].y))
        .unwrap() as u32;
    let fan: Vec<usize> = (0..ball.triangles.len())
        .filter(|&f| ball.triangles[f].contains(&north))
        .collect();
    let mut touching = ball.clone();
    let gone = [fan[0], fan[fan.len() / 2]];
    touching.triangles = ball
        .triangles
        .iter()
        .enumerate()
        .filter(|(f, _)| !gone.contains(f))
        .map(|(_, t)| *t)
        .collect();
    add(
        "holes-touching.obj",
        obj(&touching),
        "two holes that meet at one vertex (split there, they are one loop)",
        made,
        &["its own copy of 1 vertex", "filled 1 hole"],
    );
    // A T-junction: a vertex in the middle of an edge, used by the face on one side of it
    // only (that face split in two, the face across the edge left whole).
    let mut tj = shapes::cube_grid(1.0, 4);
    let [ea, eb, ec] = tj.triangles[20];
    let mid = (tj.positions[ea as usize] + tj.positions[eb as usize]) * 0.5;
    tj.positions.push(mid);
    let m = (tj.positions.len() - 1) as u32;
    tj.triangles[20] = [ea, m, ec];
    tj.triangles.push([m, eb, ec]);
    let tj = obj(&tj);
    add(
        "t-junction.obj",
        tj,
        "a T-junction: a vertex on an edge that the face across it does not use",
        made,
        &["filled 1 hole"],
    );

    // Parts.
    let head = shapes::icosphere(1.0, 3);
    let eye = shapes::icosphere(0.2, 2);
    let eyes = join(
        &moved(&eye, &|p| p + DVec3::new(0.85, 0.3, 0.35)),
        &moved(&eye, &|p| p + DVec3::new(0.85, 0.3, -0.35)),
    );
    add(
        "loose-eyes.obj",
        obj(&join(&head, &eyes)),
        "a head with two loose eyes pushed halfway into it",
        made,
        &["2 small separate parts ride"],
    );
    let arm = shapes::capsule(0.3, 0.8, 8, 8, 16);
    let arm = moved(&arm, &|p| DVec3::new(p.y + 1.0, -p.x, p.z));
    add(
        "arm-in-body.obj",
        obj(&join(&head, &arm)),
        "an arm modelled apart and pushed into the body",
        made,
        &[],
    );
    let palm = shapes::ellipsoid(1.0, 0.3, 0.8, 12, 24);
    let finger = shapes::capsule(0.15, 0.6, 6, 6, 12);
    let tilt = |a: f64| {
        move |p: DVec3| {
            let (s, c) = a.sin_cos();
            DVec3::new(c * p.x - s * p.y, s * p.x + c * p.y, p.z) + DVec3::new(1.0, 0.0, 0.0)
        }
    };
    let crossed = join(
        &join(&palm, &moved(&finger, &tilt(-1.2))),
        &moved(&finger, &|p| tilt(-1.9)(p) + DVec3::new(0.0, 0.0, 0.05)),
    );
    add(
        "crossed-fingers.obj",
        obj(&crossed),
        "two fingers crossed through each other and through the palm (separate parts)",
        made,
        &[],
    );
    let inner = moved(&shapes::icosphere(0.3, 2), &|p| {
        p + DVec3::new(0.2, 0.0, 0.0)
    });
    add(
        "nested-ball.obj",
        obj(&join(&head, &inner)),
        "a small ball inside the body, facing out (a modelling leftover)",
        made,
        &["1 small separate part rides"],
    );

    // Self-intersection in one piece: a long finger curled more than a full turn, its tip
    // through its own base. Bent smoothly about a circle wider than the finger is thick,
    // so the surface does not fold; the turn climbs a little so the tip overlaps the base.
    let long = shapes::capsule(0.2, 1.5, 8, 40, 16);
    let curl = |p: DVec3| {
        let (centre, s) = (0.45, p.y + 1.7);
        let turn = s / centre;
        let r = centre + p.x;
        DVec3::new(
            r * turn.cos(),
            r * turn.sin(),
            p.z + 0.15 * turn / std::f64::consts::TAU,
        )
    };
    let curled = moved(&long, &curl);
    let crossing =
        puppet::geom::intersect::intersecting_faces(&curled.positions, &curled.triangles);
    assert!(
        crossing.iter().filter(|&&c| c).count() > 20,
        "the curl crosses itself"
    );
    add("curled-finger.obj", obj(&curled), "a finger curled more than a full turn, its tip through its own base (one surface crossing itself)", made, &[]);

    // Orientation.
    let flipped = |m: &Mesh| Mesh {
        positions: m.positions.clone(),
        triangles: m.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
    };
    add(
        "inside-out.stl",
        stl_binary(&flipped(&spot)),
        "the cow inside out, as binary STL",
        spot_src,
        &["was inside out"],
    );
    let far = moved(&head, &|p| p + DVec3::new(3.0, 0.0, 0.0));
    add(
        "inside-out-part.obj",
        obj(&join(&head, &flipped(&far))),
        "two balls, one of them inside out",
        made,
        &["1 of its 2 parts was inside out"],
    );
    let mut some = spot.clone();
    for t in some.triangles.iter_mut().step_by(7) {
        t.swap(1, 2);
    }
    add(
        "flipped-faces.obj",
        obj(&some),
        "every seventh face of the cow turned against its neighbours",
        spot_src,
        &["turned"],
    );

    // Duplicates, soups, strips and leftovers.
    let mut dup = spot.clone();
    dup.triangles
        .extend(spot.triangles.iter().step_by(5).copied());
    add(
        "duplicate-faces.obj",
        obj(&dup),
        "every fifth face of the cow written twice",
        spot_src,
        &["duplicate faces over the same corners"],
    );
    let mut back = spot.clone();
    back.triangles
        .extend(spot.triangles.iter().step_by(5).map(|t| [t[0], t[2], t[1]]));
    add(
        "duplicate-faces-reversed.obj",
        obj(&back),
        "every fifth face of the cow written again the other way round",
        spot_src,
        &["duplicate faces over the same corners"],
    );
    // A two-sided flap, as the famous monkey head has: a triangle written both ways round,
    // hanging off an edge of the surface by a vertex of its own.
    let mut flap = spot.clone();
    let [fa, fb, fc] = spot.triangles[0];
    let tip = (spot.positions[fa as usize] + spot.positions[fb as usize]) * 0.5
        + (spot.positions[fa as usize] - spot.positions[fc as usize]);
    flap.positions.push(tip);
    let t = (flap.positions.len() - 1) as u32;
    flap.triangles.push([fa, fb, t]);
    flap.triangles.push([fb, fa, t]);
    add(
        "flap.obj",
        obj(&flap),
        "the cow with a two-sided flap (one triangle written both ways round) on an edge",
        spot_src,
        &["removed 2 duplicate faces", "removed 1 unused vertices"],
    );
    // An old Blender's PLY: its comment line written bare, with no `comment` keyword.
    let bare = String::from_utf8(ply_ascii(&spot)).unwrap().replacen(
        "format ascii 1.0\n",
        "format ascii 1.0\nCreated by Blender 2.49 - www.blender.org, source file: ''\n",
        1,
    );
    add(
        "bare-comment.ply",
        bare.into_bytes(),
        "the cow as ASCII PLY whose header has a comment line without the `comment` keyword, as an old Blender wrote it",
        spot_src,
        &["read 1 line of the PLY header without a keyword as comments"],
    );
    // A fin: one triangle hanging off an edge of the surface (three faces on that edge),
    // and a flap of two such triangles, as a modeller's leftover.
    let mut fin = spot.clone();
    fin.positions.push(tip);
    let t = (fin.positions.len() - 1) as u32;
    fin.triangles.push([fb, fa, t]);
    add(
        "fin.obj",
        obj(&fin),
        "the cow with a fin (one triangle hanging off an edge of its surface)",
        spot_src,
        &[
            "dropped 1 fin face hanging off an edge",
            "removed 1 unused vertices",
        ],
    );
    let mut fins = fin.clone();
    fins.positions
        .push(tip + (spot.positions[fa as usize] - spot.positions[fb as usize]));
    fins.triangles.push([fa, t + 1, t]);
    add(
        "fin-flap.obj",
        obj(&fins),
        "the cow with a flap of two triangles hanging off an edge of its surface",
        spot_src,
        &[
            "dropped 2 fin faces hanging off an edge",
            "removed 2 unused vertices",
        ],
    );
    let mut soup = Mesh {
        positions: Vec::new(),
        triangles: Vec::new(),
    };
    let size = spot.diagonal();
    for (k, t) in spot.triangles.iter().enumerate() {
        let base = soup.positions.len() as u32;
        for (c, &v) in t.iter().enumerate() {
            let wobble = ((k * 3 + c) % 7) as f64 - 3.0;
            soup.positions
                .push(spot.positions[v as usize] + DVec3::splat(1e-9 * size * wobble));
        }
        soup.triangles.push([base, base + 1, base + 2]);
    }
    add(
        "soup.obj",
        obj(&soup),
        "a triangle soup: every face with its own corners, off by up to 3e-9 of the size",
        spot_src,
        &["welded"],
    );
    add(
        "soup-ascii.stl",
        stl_ascii(&bunny),
        "the bunny as ASCII STL (a soup of single-precision corners, which the STL reader joins)",
        bunny_src,
        &[],
    );
    // Strips: the torus ring by ring, one strip per ring.
    let torus = shapes::torus(1.0, 0.35, 24, 10);
    let (nu, nv) = (24usize, 10usize);
    let mut strips: Vec<String> = Vec::new();
    for i in 0..nu {
        let mut s = Vec::new();
        for j in 0..=nv {
            s.push(((i % nu) * nv + j % nv).to_string());
            s.push((((i + 1) % nu) * nv + j % nv).to_string());
        }
        strips.push(s.join(" "));
    }
    let mut ply = format!(
        "ply\nformat ascii 1.0\ncomment a torus as triangle strips\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n",
        torus.positions.len()
    );
    for p in &torus.positions {
        ply += &format!("{} {} {}\n", p.x as f32, p.y as f32, p.z as f32);
    }
    let joined = strips.join(" -1 ");
    ply += &format!("{} {joined}\n", joined.split(' ').count());
    add(
        "strips.ply",
        ply.into_bytes(),
        "a torus as triangle strips (a PLY tristrips element, -1 between rings), turned inwards",
        made,
        &["was inside out"],
    );
    let mut extra = String::from_utf8(obj(&spot)).unwrap();
    for k in 0..50 {
        extra += &format!("v {k} 1e30 -7\n");
    }
    add(
        "unused-vertices.obj",
        extra.into_bytes(),
        "the cow with 50 vertices no face uses (one of them absurdly far)",
        spot_src,
        &["removed 50 unused vertices"],
    );
    let mut degenerate = String::from_utf8(obj(&spot)).unwrap();
    degenerate += "f 1 1 2\nf 3 4 3\nf 5 5 5\n";
    add(
        "degenerate-faces.obj",
        degenerate.into_bytes(),
        "the cow with three faces that repeat a corner",
        spot_src,
        &["dropped 3 degenerate faces"],
    );
    let mut seam = shapes::uv_sphere(1.0, 12, 24);
    // The meridian at +x written twice, the copy off by a millionth: an open seam.
    let n = seam.positions.len() as u32;
    let on_seam: Vec<u32> = (0..n)
        .filter(|&v| {
            let p = seam.positions[v as usize];
            p.z.abs() < 1e-12 && p.x > 1e-9
        })
        .collect();
    for (k, &v) in on_seam.iter().enumerate() {
        seam.positions
            .push(seam.positions[v as usize] + DVec3::new(0.0, 0.0, 1e-6));
        let copy = n + k as u32;
        for t in seam.triangles.iter_mut() {
            let c = t.iter().map(|&u| seam.positions[u as usize]).sum::<DVec3>() / 3.0;
            if c.z > 0.0 {
                for u in t.iter_mut().filter(|u| **u == v) {
                    *u = copy;
                }
            }
        }
    }
    add(
        "open-seam.obj",
        obj(&seam),
        "a ball whose seam is written twice, a millionth apart",
        made,
        &["closed open seams"],
    );
    let mut quads = String::new();
    let grid = shapes::cube_grid(1.0, 3);
    for p in &grid.positions {
        quads += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    // Pairs of triangles written as quads where they make one, and one square left out.
    let mut k = 0;
    while k + 1 < grid.triangles.len() {
        let (a, b) = (grid.triangles[k], grid.triangles[k + 1]);
        if k == 4 {
            k += 2;
            continue;
        }
        // The edge of `a` that `b` runs the other way, if any: then one quad.
        let shared = (0..3).find(|&i| {
            let (p, q) = (a[i], a[(i + 1) % 3]);
            (0..3).any(|j| b[j] == q && b[(j + 1) % 3] == p)
        });
        let d = b.iter().find(|v| !a.contains(v)).copied();
        match (shared, d) {
            (Some(i), Some(d)) => {
                let q = [a[(i + 1) % 3], a[(i + 2) % 3], a[i], d];
                quads += &format!("f {} {} {} {}\n", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
            }
            _ => {
                for t in [a, b] {
                    quads += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
                }
            }
        }
        k += 2;
    }
    add(
        "quads-with-a-hole.obj",
        quads.into_bytes(),
        "a box written as quads, one square missing",
        made,
        &["filled 1 hole"],
    );

    // Groups: the open-necked cow in two materials, and a head with eyes in glTF.
    let headless = keep(&spot, &|c| c.z > at(2, 0.3));
    let mut grouped = String::from("# the cow in two materials\n");
    for p in &headless.positions {
        grouped += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    let mut current = "";
    for t in &headless.triangles {
        let c = t
            .iter()
            .map(|&v| headless.positions[v as usize])
            .sum::<DVec3>()
            / 3.0;
        let m = if c.y < at(1, 0.35) { "legs" } else { "hide" };
        if m != current {
            grouped += &format!("usemtl {m}\n");
            current = m;
        }
        grouped += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    add(
        "materials-open-neck.obj",
        grouped.into_bytes(),
        "the headless cow in two materials (usemtl hide, legs)",
        spot_src,
        &["filled 1 hole"],
    );
    list.borrow_mut().last_mut().unwrap().groups = vec!["legs".into(), "hide".into()];
    add(
        "eyes-and-skin.gltf",
        gltf(&[("skin", &keep(&head, &|c| c.y > -0.8)), ("eyes", &eyes)]),
        "an open-necked head and two loose eyes, as glTF primitives with two materials",
        made,
        &["filled 1 hole", "2 small separate parts ride"],
    );
    list.borrow_mut().last_mut().unwrap().groups = vec!["skin".into(), "eyes".into()];

    // What has no inside.
    let mut sheet = String::new();
    for j in 0..5 {
        for i in 0..5 {
            sheet += &format!("v {i} {j} 0\n");
        }
    }
    for j in 0..4 {
        for i in 0..4 {
            let a = j * 5 + i + 1;
            sheet += &format!("f {a} {} {}\nf {a} {} {}\n", a + 1, a + 6, a + 6, a + 5);
        }
    }
    add(
        "flat-sheet.obj",
        sheet.into_bytes(),
        "a flat sheet: nothing inside",
        made,
        &[],
    );
    list.borrow_mut().last_mut().unwrap().refused = Some("encloses no volume".into());
    let corpus = Corpus {
        defect: list.into_inner(),
    };
    std::fs::write(
        dir.join("corpus.toml"),
        format!(
            "# Written by `regenerate_the_defect_corpus` (tests/repair.rs); see README.md.\n\n{}",
            toml::to_string(&corpus).unwrap()
        ),
    )
    .unwrap();
}

/// A `.gltf` with its buffer embedded: one primitive per named part, each with a material
/// of that name.
fn gltf(parts: &[(&str, &Mesh)]) -> Vec<u8> {
    let mut buffer: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut prims, mut materials) = (vec![], vec![], vec![], vec![]);
    for (k, (name, m)) in parts.iter().enumerate() {
        let (lo, hi) = m.bounds();
        let start = buffer.len();
        for p in &m.positions {
            for x in p.to_array() {
                buffer.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        let istart = buffer.len();
        for t in &m.triangles {
            for v in t {
                buffer.extend_from_slice(&v.to_le_bytes());
            }
        }
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{start},"byteLength":{}}}"#,
            istart - start
        ));
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{istart},"byteLength":{}}}"#,
            buffer.len() - istart
        ));
        let lo = lo.as_vec3();
        let hi = hi.as_vec3();
        accessors.push(format!(r#"{{"bufferView":{},"componentType":5126,"count":{},"type":"VEC3","min":[{},{},{}],"max":[{},{},{}]}}"#, 2 * k, m.positions.len(), lo.x, lo.y, lo.z, hi.x, hi.y, hi.z));
        accessors.push(format!(
            r#"{{"bufferView":{},"componentType":5125,"count":{},"type":"SCALAR"}}"#,
            2 * k + 1,
            3 * m.triangles.len()
        ));
        prims.push(format!(
            r#"{{"attributes":{{"POSITION":{}}},"indices":{},"material":{k}}}"#,
            2 * k,
            2 * k + 1
        ));
        materials.push(format!(r#"{{"name":"{name}"}}"#));
    }
    let data = base64(&buffer);
    format!(
        r#"{{"asset":{{"version":"2.0","generator":"puppet tests"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{}]}}],"materials":[{}],"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{data}"}}],"bufferViews":[{}],"accessors":[{}]}}"#,
        prims.join(","),
        materials.join(","),
        buffer.len(),
        views.join(","),
        accessors.join(",")
    )
    .into_bytes()
}

fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * k)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A rig file's region names a group of the mesh file (its materials): the puppet simulates
/// with it under gravity, and the legs, made of water, sag further than the hide in skin;
/// a group the file does not have is one line naming the region and the groups there are.
#[test]
fn a_rig_file_region_gives_a_file_group_its_material() {
    let dir = scratch("groups");
    let mesh = corpus_dir().join("materials-open-neck.obj");
    let mesh = mesh.to_str().unwrap();
    let run = |rig: &str, name: &str| {
        let rig_path = write(&dir, &format!("{name}.rig.toml"), rig.as_bytes());
        let out = dir.join(format!("{name}.obj"));
        let o = puppet(&[
            "simulate",
            mesh,
            "--rig",
            rig_path.to_str().unwrap(),
            "--frames",
            "30",
            "--gravity",
            "1",
            "--out",
            out.to_str().unwrap(),
        ]);
        (o, out)
    };
    let (o, plain) = run("material = \"skin\"\n", "plain");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rig = "material = \"skin\"\n[[region]]\nname = \"wobbly legs\"\nmaterial = \"water\"\ngroups = [\"legs\"]\n";
    let (o, legs) = run(rig, "legs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let read = |p: &Path| mesh::file_mesh(p).unwrap().positions;
    let (a, b) = (read(&plain), read(&legs));
    let (lo, hi) = mesh::file_mesh(Path::new(mesh)).unwrap().bounds();
    let low = |p: &DVec3| p.y < lo.y + 0.3 * (hi.y - lo.y);
    let moved = |pick: &dyn Fn(&DVec3) -> bool| {
        a.iter()
            .zip(&b)
            .filter(|(p, _)| pick(p))
            .map(|(p, q)| p.distance(*q))
            .fold(0.0, f64::max)
    };
    // The water legs move away from the skin run; the top of the back barely.
    let (legs_moved, back_moved) = (moved(&low), moved(&|p| p.y > lo.y + 0.8 * (hi.y - lo.y)));
    assert!(
        legs_moved > 3.0 * back_moved && legs_moved > 1e-3,
        "{legs_moved} {back_moved}"
    );
    let bad = "[[region]]\nname = \"eyes\"\nmaterial = \"water\"\ngroups = [\"eyes\"]\n";
    let (o, _) = run(bad, "bad");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.lines().filter(|l| l.starts_with("error:")).count() == 1
            && err.contains("region 'eyes': no group 'eyes' (the mesh file's groups: legs, hide)"),
        "{err}"
    );
}
