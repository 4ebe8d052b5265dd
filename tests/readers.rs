//! Readers that never panic: thousands of mutated copies of valid files (OBJ, PLY ASCII and
//! binary, STL ASCII and binary, glb, rig, animation) go through each reader; every one is
//! read or refused with one line, none panics, none takes long. `cargo fuzz` targets in
//! `fuzz/` run the same readers for longer.

mod common;

use common::{example, ply_ascii, ply_binary, stl_ascii, stl_binary, test_mesh};
use puppet::anim::Animation;
use puppet::files::Format as TextFormat;
use puppet::mesh::{self, Format, LoadOptions, Mesh};
use puppet::random::SplitMix;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::time::{Duration, Instant};

/// Mutations of each file per run.
const MUTATIONS: usize = 1500;

/// The small Spot, the valid starting point of every mesh format.
fn spot() -> Mesh {
    mesh::load(&test_mesh("spot-small.obj")).unwrap().0
}

fn glb(m: &Mesh) -> Vec<u8> {
    let rest: Vec<glam::Vec3> = m.positions.iter().map(|p| p.as_vec3()).collect();
    let normals = mesh::vertex_normals(m).unwrap();
    let take = puppet::export::Frames {
        triangles: m.triangles.clone(),
        rest: rest.clone(),
        normals: normals.iter().map(|n| n.as_vec3()).collect(),
        frames: vec![rest.clone(), rest.iter().map(|p| *p * 1.01).collect()],
        fps: 30.0,
        first: 1,
        step: 1,
    };
    puppet::export::glb::write(&take).unwrap()
}

/// One random change: a byte replaced, inserted or removed, a run of bytes copied over
/// another place, the end cut off, or a number's digit changed.
fn mutate(data: &[u8], rng: &mut SplitMix) -> Vec<u8> {
    let mut d = data.to_vec();
    let mut below = |n: usize| (rng.next_u64() % n.max(1) as u64) as usize;
    for _ in 0..1 + below(3) {
        let len = d.len().max(1);
        match below(9) {
            0 => {
                let at = below(len);
                if at < d.len() {
                    d[at] = below(256) as u8;
                }
            }
            1 => {
                let at = below(len + 1).min(d.len());
                d.insert(at, below(256) as u8);
            }
            2 => {
                if !d.is_empty() {
                    let at = below(d.len());
                    d.remove(at);
                }
            }
            3 => {
                let (from, to, n) = (below(len), below(len), 1 + below(64));
                let run: Vec<u8> = d.iter().skip(from).take(n).copied().collect();
                for (k, b) in run.into_iter().enumerate() {
                    if to + k < d.len() {
                        d[to + k] = b;
                    }
                }
            }
            4 => d.truncate(below(len)),
            5 => {
                // A digit or a sign, where text has numbers.
                let at = below(len);
                if at < d.len() {
                    d[at] = b"0123456789-.eE+"[below(15)];
                }
            }
            7 | 8 => {
                // One digit of the text changed: a count, an index, a coordinate (in a glb,
                // its JSON's accessor and buffer view numbers).
                let digits: Vec<usize> = (0..d.len()).filter(|&i| d[i].is_ascii_digit()).collect();
                if !digits.is_empty() {
                    let at = digits[below(digits.len())];
                    d[at] = b'0' + below(10) as u8;
                }
            }
            _ => {
                // A 32-bit field set to an extreme (binary counts and indices).
                let at = below(len) & !3;
                let v: u32 = [0, 1, u32::MAX, 0x7fff_ffff, 0x8000_0000][below(5)];
                for (k, b) in v.to_le_bytes().into_iter().enumerate() {
                    if at + k < d.len() {
                        d[at + k] = b;
                    }
                }
            }
        }
    }
    d
}

/// Runs `read` on `MUTATIONS` mutations of `data`: no panic, no read longer than two
/// seconds, every refusal one non-empty line. Returns how many were refused.
fn survive(
    name: &str,
    data: &[u8],
    seed: u64,
    read: impl Fn(&[u8]) -> Result<(), String>,
) -> usize {
    assert!(
        read(data).is_ok(),
        "{name}: the valid file reads: {:?}",
        read(data)
    );
    let mut rng = SplitMix(seed);
    let mut refused = 0;
    for k in 0..MUTATIONS {
        let bad = mutate(data, &mut rng);
        let start = Instant::now();
        let result = catch_unwind(AssertUnwindSafe(|| read(&bad)));
        let took = start.elapsed();
        let Ok(result) = result else {
            let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("panic-{name}-{k}"));
            let _ = std::fs::write(&path, &bad);
            panic!(
                "{name}: mutation {k} panicked the reader (input saved to {})",
                path.display()
            );
        };
        assert!(
            took < Duration::from_secs(2),
            "{name}: mutation {k} took {took:?}"
        );
        if let Err(e) = result {
            refused += 1;
            assert!(
                !e.trim().is_empty() && !e.contains('\n'),
                "{name}: mutation {k}: {e:?}"
            );
            // A crate bug the guard had to catch: check for it in the reader instead
            // (src/mesh/gltf/mod.rs has the two known ones), so the message can say what is wrong.
            assert!(
                !e.contains("the reader failed"),
                "{name}: mutation {k}: a crate panicked: {e}"
            );
        }
    }
    refused
}

fn read_mesh(format: Format) -> impl Fn(&[u8]) -> Result<(), String> {
    move |bytes| {
        mesh::parse(
            bytes,
            format,
            &LoadOptions::default(),
            puppet::progress::silent(),
        )
        .map(|_| ())
        .map_err(|e| e.to_string())
    }
}

#[test]
fn mesh_readers_never_panic() {
    let m = spot();
    let obj = std::fs::read(test_mesh("spot-small.obj")).unwrap();
    for (k, (name, data, format)) in [
        ("obj", obj, Format::Obj),
        ("ply-ascii", ply_ascii(&m), Format::Ply),
        ("ply-binary", ply_binary(&m), Format::Ply),
        ("stl-ascii", stl_ascii(&m), Format::Stl),
        ("stl-binary", stl_binary(&m), Format::Stl),
        ("glb", glb(&m), Format::Gltf),
        (
            "glb-quantized",
            gltf_file("spot-quantized.glb"),
            Format::Gltf,
        ),
        ("glb-meshopt", gltf_file("spot-meshopt.glb"), Format::Gltf),
        ("glb-skinned", gltf_file("skinned-figure.glb"), Format::Gltf),
    ]
    .into_iter()
    .enumerate()
    {
        let refused = survive(name, &data, 17 + k as u64, read_mesh(format));
        assert!(refused > 0, "{name}: some mutations must be refused");
    }
    // The glb's JSON, where its indices, counts and offsets are: digits changed in place
    // (the chunk keeps its length), so the crate gets past the container to them. The
    // compressed file's digits include its meshopt strides, counts and lengths.
    for (seed, good) in [
        (99, glb(&m)),
        (100, gltf_file("spot-quantized.glb")),
        (101, gltf_file("spot-meshopt.glb")),
        (102, gltf_file("skinned-figure.glb")),
    ] {
        survive_json_digits(&good, seed);
    }
}

/// A glTF file of `tests/data/gltf`.
fn gltf_file(name: &str) -> Vec<u8> {
    std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/gltf")
            .join(name),
    )
    .unwrap()
}

/// `MUTATIONS` copies of the glb `good` with one or two digits of its JSON changed: none
/// panics (nor aborts: a meshopt decoder asserting its sizes would end the process), and
/// a tenth at least are refused with one line.
fn survive_json_digits(good: &[u8], seed: u64) {
    let json_len = u32::from_le_bytes(good[12..16].try_into().unwrap()) as usize;
    let json = 20..20 + json_len;
    let digits: Vec<usize> = json.filter(|&i| good[i].is_ascii_digit()).collect();
    let mut rng = SplitMix(seed);
    let read = read_mesh(Format::Gltf);
    let mut refused = 0;
    for k in 0..MUTATIONS {
        let mut bad = good.to_vec();
        for _ in 0..1 + rng.next_u64() % 2 {
            let at = digits[(rng.next_u64() % digits.len() as u64) as usize];
            bad[at] = b'0' + (rng.next_u64() % 10) as u8;
        }
        let result = catch_unwind(AssertUnwindSafe(|| read(&bad)));
        let Ok(result) = result else {
            let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("panic-glb-json-{k}"));
            let _ = std::fs::write(&path, &bad);
            panic!(
                "glb JSON mutation {k} panicked the reader (saved to {})",
                path.display()
            );
        };
        if let Err(e) = result {
            refused += 1;
            assert!(!e.contains('\n'), "{e}");
            assert!(
                !e.contains("the reader failed"),
                "glb JSON mutation {k}: a crate panicked: {e}"
            );
        }
    }
    assert!(refused > MUTATIONS / 10, "only {refused} refused");
}

/// What gltfpack (1.3, npm) writes, quantized (`KHR_mesh_quantization`) and compressed
/// (`EXT_meshopt_compression`, `-c`), reads as the OBJ it was made from: the same faces
/// on the same vertices, each within the 14-bit grid gltfpack rounds positions to. It
/// reorders vertices and faces, so they are matched by position.
#[test]
fn gltfpack_output_reads_as_the_mesh_it_was_made_from() {
    let source = spot();
    let (lo, hi) = source.positions.iter().fold(
        (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let step = (hi - lo).max_element() / 16383.0;
    for name in ["spot-quantized.glb", "spot-meshopt.glb"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/gltf")
            .join(name);
        let (packed, _) = mesh::load(&path).unwrap();
        assert_eq!(packed.positions.len(), source.positions.len(), "{name}");
        assert_eq!(packed.triangles.len(), source.triangles.len(), "{name}");
        // Each source vertex's nearest packed vertex, within the grid.
        let to: Vec<u32> = source
            .positions
            .iter()
            .map(|p| {
                let (k, d) = packed
                    .positions
                    .iter()
                    .map(|q| q.distance(*p))
                    .enumerate()
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .unwrap();
                assert!(
                    d <= step,
                    "{name}: a vertex {d} from its source, grid {step}"
                );
                k as u32
            })
            .collect();
        let key = |t: [u32; 3]| {
            let k = t
                .iter()
                .position(|&v| v == *t.iter().min().unwrap())
                .unwrap();
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        };
        let mut mapped: Vec<[u32; 3]> = source
            .triangles
            .iter()
            .map(|t| key([to[t[0] as usize], to[t[1] as usize], to[t[2] as usize]]))
            .collect();
        let mut theirs: Vec<[u32; 3]> = packed.triangles.iter().map(|&t| key(t)).collect();
        mapped.sort_unstable();
        theirs.sort_unstable();
        assert_eq!(mapped, theirs, "{name}: the same faces, the same way round");
    }
}

#[test]
fn rig_animation_controls_and_osc_readers_never_panic() {
    let rig = std::fs::read(example("spot-mouth.rig.toml")).unwrap();
    survive("rig", &rig, 3, |bytes| {
        let text = std::str::from_utf8(bytes).map_err(|e| e.to_string())?;
        puppet::RigFile::parse(text, TextFormat::Toml, Path::new("."))
            .map(|_| ())
            .map_err(|e| e.to_string())
    });
    let anim = std::fs::read(example("spot-mouth.anim.toml")).unwrap();
    survive("anim", &anim, 4, |bytes| {
        let text = std::str::from_utf8(bytes).map_err(|e| e.to_string())?;
        Animation::parse(text, TextFormat::Toml)
            .and_then(|a| a.check().map(|()| a))
            .map(|_| ())
            .map_err(|e| e.to_string())
    });
    // The controls file, and OSC packets: mutated copies of a glove's message.
    let controls = std::fs::read(example("glove.toml")).unwrap();
    survive("controls", &controls, 5, |bytes| {
        let text = std::str::from_utf8(bytes).map_err(|e| e.to_string())?;
        puppet::controls::ControlsFile::parse(text)
            .map(|_| ())
            .map_err(|e| e.to_string())
    });
    let packet = puppet::controls::osc::encode("/glove/flex", &[0.1, 0.2, 0.3, 0.4, 0.5]);
    survive("osc", &packet, 6, |bytes| {
        puppet::controls::osc::decode(bytes)
            .map(|_| ())
            .ok_or_else(|| "not OSC".to_string())
    });
}

/// gltf-json 1.4.1 panics validating a primitive whose POSITION names a missing accessor
/// (`src/mesh/gltf/mod.rs` says where); the reader refuses it with one line instead.
#[test]
fn a_glb_naming_a_missing_position_accessor_is_an_error() {
    let good = glb(&spot());
    let at = good
        .windows(11)
        .position(|w| w == b"\"POSITION\":")
        .unwrap()
        + 11;
    let mut bad = good[..at].to_vec();
    bad.push(b'9');
    bad.extend_from_slice(&good[at..]);
    // Keep the chunk's length: drop one character of the mesh's name.
    let name = bad
        .windows(15)
        .position(|w| w == b"\"name\":\"puppet\"")
        .unwrap();
    bad.remove(name + 13);
    assert_eq!(bad.len(), good.len());
    let e = read_mesh(Format::Gltf)(&bad).unwrap_err();
    assert!(
        e.starts_with("glTF: mesh 0 primitive 0: POSITION is accessor 9"),
        "{e}"
    );
    // And through the command line: one error line, exit status 2.
    let dir = common::scratch("readers_glb");
    let path = dir.join("bad.glb");
    std::fs::write(&path, &bad).unwrap();
    let out = common::puppet(&["skeleton", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with(&format!("error: {}: glTF: ", path.display())),
        "{err}"
    );
}

/// gltf 1.4.1 reaches `unreachable!()` reading indices whose accessor is not of unsigned
/// integers (`src/mesh/gltf/mod.rs` says where); the reader refuses them with one line instead.
#[test]
fn a_glb_with_float_indices_is_an_error() {
    let good = glb(&spot());
    let json_len = u32::from_le_bytes(good[12..16].try_into().unwrap()) as usize;
    let json = std::str::from_utf8(&good[20..20 + json_len]).unwrap();
    // The indices accessor: the primitive's "indices" number, then its "componentType".
    let root: serde_json::Value = serde_json::from_str(json.trim_end()).unwrap();
    let index = root["meshes"][0]["primitives"][0]["indices"]
        .as_u64()
        .unwrap() as usize;
    let kind = root["accessors"][index]["componentType"].as_u64().unwrap();
    assert_eq!(kind, 5125, "unsigned 32-bit indices");
    let mut root = root;
    root["accessors"][index]["componentType"] = 5126.into();
    let mut text = serde_json::to_string(&root).unwrap().into_bytes();
    assert!(text.len() <= json_len);
    text.resize(json_len, b' ');
    let mut bad = good.clone();
    bad[20..20 + json_len].copy_from_slice(&text);
    let e = read_mesh(Format::Gltf)(&bad).unwrap_err();
    assert!(e.contains("indices"), "{e}");
    assert!(
        !e.contains("reader failed"),
        "refused before the crate reads: {e}"
    );
}

/// The triangles of an OBJ as corner coordinates, by tobj (the design card's reader).
fn tobj_triangles(bytes: &[u8]) -> Result<Vec<[[f32; 3]; 3]>, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _) = tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for m in models {
        let p = &m.mesh.positions;
        let corner = |i: u32| -> Result<[f32; 3], String> {
            let i = i as usize * 3;
            p.get(i..i + 3)
                .map(|c| [c[0], c[1], c[2]])
                .ok_or_else(|| "index out of range".to_string())
        };
        for t in m.mesh.indices.chunks(3) {
            out.push([corner(t[0])?, corner(t[1])?, corner(t[2])?]);
        }
    }
    Ok(out)
}

/// The triangles of an OBJ as corner coordinates, by our reader (the file's mesh, before
/// welding).
fn our_triangles(bytes: &[u8]) -> Result<Vec<[[f32; 3]; 3]>, String> {
    let m = mesh::parse_file_mesh(bytes, Format::Obj).map_err(|e| e.to_string())?;
    let p = |v: u32| m.positions[v as usize].as_vec3().to_array();
    Ok(m.triangles
        .iter()
        .map(|t| [p(t[0]), p(t[1]), p(t[2])])
        .collect())
}

/// Our OBJ reader and tobj read every test mesh to the same triangles, in the same order;
/// on malformed files ours refuses with one line where tobj guesses or refuses.
#[test]
fn our_obj_reader_and_tobj_agree_on_every_test_mesh() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![dir.join("assets/spot.obj")];
    for e in std::fs::read_dir(dir.join("tests/data/meshes"))
        .unwrap()
        .flatten()
    {
        if e.path().extension().is_some_and(|x| x == "obj") {
            files.push(e.path());
        }
    }
    assert!(files.len() >= 6);
    for f in &files {
        let bytes = std::fs::read(f).unwrap();
        let (ours, theirs) = (
            our_triangles(&bytes).unwrap(),
            tobj_triangles(&bytes).unwrap(),
        );
        assert_eq!(ours.len(), theirs.len(), "{}", f.display());
        for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
            for c in 0..3 {
                for x in 0..3 {
                    let (p, q) = (a[c][x], b[c][x]);
                    assert!(
                        (p - q).abs() <= 1e-6 * p.abs().max(1.0),
                        "{}: triangle {k}: {a:?} vs {b:?}",
                        f.display()
                    );
                }
            }
        }
    }
    // Polygons, negative indices, v/vt/vn forms, groups: the same triangles.
    let forms = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng a\nf 1/1/1 2/1/1 3/1/1 4/1/1\ng b\nf -4//1 -2//1 -1//1\n";
    assert_eq!(
        our_triangles(forms.as_bytes()),
        tobj_triangles(forms.as_bytes())
    );
    // Malformed files: ours refuses each with one line; tobj's answer is recorded beside it.
    for (bad, tobj_refuses) in [
        ("v 0 0 0\nv 1 0 0\nf 1 2 3\n", true), // an index past the vertices
        ("v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", true), // a vertex with two coordinates
        ("v 0 0 x\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", true), // not a number
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", true), // index 0
        ("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", false), // tobj reads NaN
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", false), // tobj drops a two-corner face
    ] {
        let ours = mesh::parse(
            bad.as_bytes(),
            Format::Obj,
            &LoadOptions::default(),
            puppet::progress::silent(),
        );
        let e = ours.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(
            !e.is_empty() && !e.contains('\n'),
            "ours must refuse {bad:?} in one line: {e:?}"
        );
        let theirs = tobj_triangles(bad.as_bytes());
        assert_eq!(theirs.is_err(), tobj_refuses, "tobj on {bad:?}: {theirs:?}");
    }
}
