//! Every bad input is one `error: <file>: <problem>` line and exit status 2, never a panic;
//! good but messy input is repaired with a warning.

mod common;
use common::{puppet, scratch};
use puppet::mesh::{LoadReport, Mesh};
use std::path::Path;

const TETRA: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// Writes `bytes` to a file and runs `puppet skeleton` on it; returns (status, stderr, path).
fn run_on(dir: &Path, name: &str, bytes: &[u8]) -> (Option<i32>, String, String) {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    let p = path.to_str().unwrap().to_string();
    let out = puppet(&["skeleton", &p]);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        p,
    )
}

fn assert_refused(name: &str, bytes: &[u8], expect: &str) {
    let dir = scratch(&format!("refuse-{name}"));
    let (code, err, path) = run_on(&dir, name, bytes);
    assert_eq!(code, Some(2), "{name}: exit status, stderr: {err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.starts_with("warn")).collect();
    assert_eq!(lines.len(), 1, "{name}: one error line, got: {err}");
    assert!(
        lines[0].starts_with(&format!("error: {path}: ")),
        "{name}: names the file: {err}"
    );
    assert!(
        lines[0].contains(expect),
        "{name}: expected '{expect}' in: {err}"
    );
    assert!(!err.contains("panicked"), "{name}: panic: {err}");
}

#[test]
fn missing_file_and_directory() {
    let out = puppet(&["skeleton", "/nonexistent/cow.obj"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.trim(),
        "error: /nonexistent/cow.obj: cannot read file: no such file"
    );
    let dir = scratch("dir-input");
    let out = puppet(&["skeleton", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is a directory"));
}

#[test]
fn empty_and_binary_files() {
    assert_refused("empty.obj", b"", "empty");
    assert_refused("blank.obj", b"\n  \n\t\n", "empty");
    let mut garbage: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    garbage[10] = 0;
    assert_refused("garbage.obj", &garbage, "not a text OBJ file");
    assert_refused("latin1.obj", b"v 0 0 0\n# caf\xe9\n", "invalid UTF-8");
}

#[test]
fn malformed_lines_are_named() {
    assert_refused(
        "short-vertex.obj",
        b"v 0 0 0\nv 1 0\n",
        "line 2: vertex has 2 coordinates",
    );
    assert_refused(
        "word.obj",
        b"v 0 zero 0\n",
        "line 1: 'zero' is not a number",
    );
    let truncated = &TETRA.as_bytes()[..TETRA.len() - 4]; // "f 2 3 4" cut to "f 2 "
    assert_refused("truncated.obj", truncated, "line 8: face has 1 vertices");
    assert_refused(
        "two-vertex-face.obj",
        b"v 0 0 0\nv 1 0 0\nf 1 2\n",
        "face has 2 vertices",
    );
    assert_refused(
        "bad-index.obj",
        b"v 0 0 0\nf 1 x 2\n",
        "'x' is not a vertex index",
    );
}

#[test]
fn out_of_range_indices() {
    assert_refused(
        "big-index.obj",
        format!("{TETRA}f 1 2 99\n").as_bytes(),
        "line 9: vertex index 99 is out of range",
    );
    assert_refused(
        "zero-index.obj",
        format!("{TETRA}f 0 1 2\n").as_bytes(),
        "vertex index 0 is out of range",
    );
    assert_refused(
        "neg-index.obj",
        b"v 0 0 0\nv 1 0 0\nf -1 -2 -3\n",
        "vertex index -3 is out of range",
    );
}

#[test]
fn non_finite_and_huge_coordinates() {
    assert_refused(
        "nan.obj",
        TETRA.replacen("v 1 0 0", "v NaN 0 0", 1).as_bytes(),
        "vertex 2 has a non-finite coordinate",
    );
    assert_refused(
        "inf.obj",
        TETRA.replacen("v 0 1 0", "v 0 inf 0", 1).as_bytes(),
        "vertex 3 has a non-finite coordinate",
    );
    assert_refused(
        "huge.obj",
        TETRA.replacen("v 0 0 1", "v 0 0 1e30", 1).as_bytes(),
        "beyond the supported range",
    );
}

#[test]
fn no_faces() {
    assert_refused(
        "points.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\n",
        "no triangles: the file holds 3 vertices",
    );
}

#[test]
fn what_cannot_be_repaired_is_refused() {
    // With hole filling off, an open mesh is refused, and the message says so.
    let open = TETRA.replace("f 2 3 4\n", "");
    let dir = scratch("refuse-open-nofill");
    let path = dir.join("open.obj");
    std::fs::write(&path, &open).unwrap();
    let out = puppet(&["skeleton", path.to_str().unwrap(), "--fill-holes", "0"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.trim()
            .ends_with("3 boundary edges (e.g. 2-3); 1 hole (hole filling is off)"),
        "{err}"
    );
    // Three equal sheets on one edge (a book of three single-face pages): no piece is
    // the surface a fin hangs off, so nothing is dropped; the message says what to look
    // for. (A fin off a closed surface is dropped: `tests/data/defects/fin.obj`.)
    let book = "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 0 0 1\nv -1 0 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
    assert_refused("book.obj", book.as_bytes(), "non-manifold edges");
    assert_refused(
        "book.obj",
        book.as_bytes(),
        "Select > All by Trait > Non Manifold",
    );
    // A Möbius-like twist cannot be oriented: a strip of quads closed with a half turn.
    let mut mobius = String::new();
    let n = 12;
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let (c, s) = (a.cos(), a.sin());
        let (tc, ts) = ((a / 2.0).cos() * 0.3, (a / 2.0).sin() * 0.3);
        mobius.push_str(&format!("v {} {} {}\n", c * (1.0 + tc), s * (1.0 + tc), ts));
        mobius.push_str(&format!(
            "v {} {} {}\n",
            c * (1.0 - tc),
            s * (1.0 - tc),
            -ts
        ));
    }
    for k in 0..n {
        let (a, b) = (2 * k + 1, 2 * k + 2);
        let (c, d) = if k + 1 < n {
            (2 * k + 3, 2 * k + 4)
        } else {
            (2, 1)
        };
        mobius.push_str(&format!("f {a} {b} {d}\nf {a} {d} {c}\n"));
    }
    assert_refused("mobius.obj", mobius.as_bytes(), "not a closed 2-manifold");
}

#[test]
fn degenerate_meshes() {
    // Two copies of one triangle, back to back: closed and manifold but no volume.
    assert_refused(
        "sheet.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n",
        "encloses no volume",
    );
    // Everything welds into one point.
    assert_refused(
        "collapsed.obj",
        b"v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n",
        "no triangles",
    );
}

#[test]
fn messy_but_valid_input_is_repaired() {
    let dir = scratch("messy");
    // A cube written as 6 quads with its own vertices per face (24 vertices, like many
    // exporters), objects, v/vt/vn forms, negative indices and an unused vertex.
    let mut obj = String::from("# cube\nvt 0 0\nvn 0 0 1\nv 9 9 9\n");
    let faces: [[[i32; 3]; 4]; 6] = [
        [[0, 0, 0], [0, 1, 0], [1, 1, 0], [1, 0, 0]],
        [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
        [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]],
        [[0, 1, 0], [0, 1, 1], [1, 1, 1], [1, 1, 0]],
        [[0, 0, 0], [0, 0, 1], [0, 1, 1], [0, 1, 0]],
        [[1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 0, 1]],
    ];
    for (k, f) in faces.iter().enumerate() {
        obj.push_str(&format!("o side{k}\n"));
        for c in f {
            obj.push_str(&format!("v {} {} {}\n", c[0], c[1], c[2]));
        }
        if k % 2 == 0 {
            obj.push_str("f -4/1/1 -3/1/1 -2/1/1 -1/1/1\n");
        } else {
            let n = 1 + 4 * k as i32 + 1;
            obj.push_str(&format!(
                "f {}//1 {}//1 {}//1 {}//1\n",
                n,
                n + 1,
                n + 2,
                n + 3
            ));
        }
    }
    let path = dir.join("cube.obj");
    std::fs::write(&path, obj).unwrap();
    let out = puppet(&["skeleton", path.to_str().unwrap(), "--json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.contains("welded 16 duplicate vertices"), "{err}");
    assert!(err.contains("removed 1 unused vertices"), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["vertices"], 8);
    assert_eq!(v["faces"], 12);
    // Corner normals are diagonal: the thickness along -n is the cube's diagonal, so the
    // clamp bounds d by half of it (and the skeletal point lands at the centre, inside).
    let d_max = v["d_max"].as_f64().unwrap();
    assert!(d_max <= 0.5 * 3f64.sqrt() + 1e-9, "d_max {d_max}");
}

#[test]
fn inside_out_mesh_is_flipped_with_a_warning() {
    let dir = scratch("inside-out");
    let inverted: String = TETRA
        .lines()
        .map(|l| {
            if let Some(rest) = l.strip_prefix("f ") {
                let v: Vec<&str> = rest.split_whitespace().collect();
                format!("f {} {} {}\n", v[0], v[2], v[1])
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let (code, err, _) = run_on(&dir, "inverted.obj", inverted.as_bytes());
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("inside out"), "{err}");
}

#[test]
fn vertex_order_of_the_file_is_kept() {
    // tobj renumbers by first use; the face order here uses vertex 4 first.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 4 2 3\nf 1 3 2\nf 1 2 4\nf 1 4 3\n";
    let (mesh, _) = puppet::mesh::parse_obj(obj.as_bytes()).unwrap();
    assert_eq!(mesh.positions[0], glam::DVec3::ZERO);
    assert_eq!(mesh.positions[3], glam::DVec3::Z);
    assert_eq!(mesh.triangles[0], [3, 1, 2]);
}

#[test]
fn unknown_method_is_a_usage_error() {
    let out = puppet(&["skeleton", "--method", "magic"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: invalid value 'magic'"), "{err}");
    assert!(err.contains("mean, pole, shrinking-ball"), "{err}");
}

/// Sheets that touch (two solids sharing one vertex, or one edge) are given their own
/// copies of what they share, with a warning, and the puppet builds.
#[test]
fn touching_sheets_are_separated() {
    let dir = scratch("touching-sheets");
    // Two tetrahedra sharing only vertex 1 (a pinched vertex: a bowtie).
    let bowtie =
        format!("{TETRA}v -1 0 0\nv 0 -1 0\nv 0 0 -1\nf 1 5 6\nf 1 7 5\nf 1 6 7\nf 5 7 6\n");
    // Two tetrahedra sharing the edge 1-4: the second is the first turned half a turn
    // about the z axis through vertex 1.
    let edge = format!("{TETRA}v -1 0 0\nv 0 -1 0\nf 1 6 5\nf 1 5 4\nf 1 4 6\nf 5 6 4\n");
    for (name, text, says) in [
        (
            "bowtie.obj",
            bowtie,
            "its own copy of 1 vertex where sheets touched",
        ),
        (
            "edge.obj",
            edge,
            "its own copy of 2 vertices where sheets touched, opening 1 edge",
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, &text).unwrap();
        let out = puppet(&["skeleton", path.to_str().unwrap(), "--json"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["faces"], 8, "{name}");
    }
}

/// The ring of a 12 × 16 ball's vertices at y = −0.5, in order around it.
fn ring_of(m: &Mesh) -> Vec<u32> {
    let mut ring: Vec<u32> = (0..m.positions.len() as u32)
        .filter(|&v| (m.positions[v as usize].y + 0.5).abs() < 1e-9)
        .collect();
    assert_eq!(ring.len(), 16);
    ring.sort_by(|&a, &b| {
        let (p, q) = (m.positions[a as usize], m.positions[b as usize]);
        p.z.atan2(p.x).total_cmp(&q.z.atan2(q.x))
    });
    ring
}

/// Writes `m` as an OBJ and loads it: the mesh and the warnings, one a line.
fn written_and_loaded(m: &Mesh, name: &str) -> (Mesh, LoadReport, String) {
    let path = scratch(name).join(format!("{name}.obj"));
    std::fs::write(&path, common::obj(m)).unwrap();
    let (mesh, report) = puppet::mesh::load(&path).expect("it loads");
    let warnings = report.warnings().join("\n");
    (mesh, report, warnings)
}

/// A closed piece set into a ring of the surface (a low-poly eye's buried half, a cone
/// from a ring of a ball to a point inside it: every ring edge has three faces and no
/// piece there has an edge of one face) gets its own copies and closes on its own: the
/// ball stays whole, two parts load where the file was refused.
#[test]
fn a_closed_piece_set_into_a_ring_goes_its_own_way() {
    let mut m = puppet::mesh::shapes::uv_sphere(1.0, 12, 16);
    let faces = m.triangles.len();
    let ring = ring_of(&m);
    let apex = m.positions.len() as u32;
    m.positions.push(glam::DVec3::new(0.0, 0.2, 0.0));
    for k in 0..16 {
        m.triangles.push([ring[(k + 1) % 16], ring[k], apex]);
    }
    let (mesh, _, warnings) = written_and_loaded(&m, "buried-cone");
    assert!(
        warnings.contains("gave 1 piece meeting a larger one"),
        "{warnings}"
    );
    assert_eq!(puppet::mesh::Parts::of(&mesh).len(), 2, "{warnings}");
    assert!(mesh.triangles.len() >= faces + 16);
}

/// A large open piece hanging off an edge the surface shares (a skirt sewn to a body at
/// its waist, as game characters are exported) is kept: it gets its own copies of the
/// vertices there, its hole is filled, and it is a part of the puppet; a flap of a few
/// faces is still dropped.
#[test]
fn a_skirt_on_the_waist_is_kept_apart_not_dropped() {
    let body = puppet::mesh::shapes::uv_sphere(1.0, 12, 16);
    let mut m = body.clone();
    // An open cone of 32 faces below the sphere, its rim on one ring of the sphere's
    // vertices: each rim edge is the sphere's and the cone's (three faces).
    let ring = ring_of(&m);
    let hem0 = m.positions.len() as u32;
    for &v in &ring {
        let p = m.positions[v as usize];
        m.positions
            .push(glam::DVec3::new(1.6 * p.x, -2.0, 1.6 * p.z));
    }
    for k in 0..16u32 {
        let (a, b) = (ring[k as usize], ring[((k + 1) % 16) as usize]);
        let (c, d) = (hem0 + k, hem0 + (k + 1) % 16);
        m.triangles.push([a, b, d]);
        m.triangles.push([a, d, c]);
    }
    let (mesh, report, warnings) = written_and_loaded(&m, "skirt");
    assert!(
        warnings.contains("gave 1 piece meeting a larger one"),
        "{warnings}"
    );
    assert!(!warnings.contains("fin"), "{warnings}");
    assert_eq!(puppet::mesh::Parts::of(&mesh).len(), 2);
    assert!(mesh.triangles.len() >= body.triangles.len() + 32);
    puppet::Puppet::build_loaded(
        mesh,
        Some(&report),
        puppet::RigFile::default(),
        puppet::progress::silent(),
    )
    .expect("a puppet");
}
