//! Meshes people actually have: holes, flipped faces, open seams, small separate parts, PLY
//! and STL files. What can be repaired loads with a warning that says what was done.

mod common;

use common::{obj, ply_ascii, ply_binary, puppet, scratch, stl_ascii, stl_binary, test_mesh};
use glam::DVec3;
use puppet::joints::{Cut, Local, Shape};
use puppet::mesh::{self, shapes, Mesh};
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
