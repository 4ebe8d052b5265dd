//! `puppet simulate --out TAKE.glb | TAKE.pc2 | DIR/`: a take in the formats other tools
//! read. The `.glb` is read back with the `gltf` crate and checked by the Khronos
//! validator when Node and the validator are installed (`scripts/setup.sh`); every format
//! gives the same positions as the OBJ frames.

mod common;
use common::{example, ok, puppet, scratch, validate};
use std::path::{Path, PathBuf};

/// The example take (45 frames at 30 fps) written to `out`.
fn simulate(out: &Path, extra: &[&str]) {
    let mut args = vec![
        "simulate".to_string(),
        "--rig".into(),
        example("spot-jaw.rig.toml"),
        "--anim".into(),
        example("spot-jaw.anim.toml"),
        "--frames".into(),
        "45".into(),
        "--out".into(),
        out.display().to_string(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    ok(&puppet(&args));
}

/// Vertex positions of an OBJ frame.
fn obj_vertices(path: &Path) -> Vec<[f32; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f32> = l.split_whitespace().map(|c| c.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    (0..3).all(|c| (a[c] - b[c]).abs() <= 1e-5)
}

fn frames_dir(test: &str) -> PathBuf {
    let dir = scratch(test).join("frames");
    simulate(&PathBuf::from(format!("{}/", dir.display())), &[]);
    dir
}

#[test]
fn glb_reads_back_with_one_target_per_frame_and_the_frames_positions() {
    let dir = scratch("export_glb");
    let glb = dir.join("take.glb");
    simulate(&glb, &["--frame-step", "4"]);
    let bytes = std::fs::read(&glb).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).expect("a valid glTF binary");
    let blob = gltf.blob.clone().expect("a BIN chunk");
    let mesh = gltf.meshes().next().expect("a mesh");
    let prim = mesh.primitives().next().unwrap();
    let reader = prim.reader(|_| Some(&blob));
    let rest: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    let targets: Vec<Vec<[f32; 3]>> = reader
        .read_morph_targets()
        .map(|(p, _, _)| p.unwrap().collect())
        .collect();
    // Frames 1, 5, ..., 45: 12 targets, and an animation of their weights (the rest
    // surface at 0, then one key per frame).
    assert_eq!(targets.len(), 12);
    assert_eq!(gltf.animations().count(), 1);
    let sampler = gltf.animations().next().unwrap().samplers().next().unwrap();
    assert_eq!(sampler.input().count(), 13);
    assert_eq!(sampler.output().count(), 13 * 12);
    // Frame 45 (the last target) is the OBJ frame 45 of the same take.
    let frames = frames_dir("export_glb_frames");
    let obj = obj_vertices(&frames.join("frame_00045.obj"));
    assert_eq!(obj.len(), rest.len());
    for (i, o) in obj.iter().enumerate() {
        let d = targets[11][i];
        let p = [rest[i][0] + d[0], rest[i][1] + d[1], rest[i][2] + d[2]];
        assert!(close(p, *o), "vertex {i}: {p:?} vs {o:?}");
    }
    validate(&glb);
    // And it opens as a mesh (glTF input): the same welded vertices and triangles.
    let (mesh, report) = puppet::mesh::load(&glb).expect("the .glb opens as a mesh");
    assert_eq!(report.format, puppet::mesh::Format::Gltf);
    assert_eq!(mesh.positions.len(), rest.len());
    let (spot, _) =
        puppet::mesh::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/spot.obj")).unwrap();
    assert_eq!(mesh.triangles, spot.triangles);
}

/// The key times of a `.glb`'s animation and each key's weights, read back with the `gltf`
/// crate.
fn glb_keys(glb: &Path) -> (Vec<f32>, Vec<Vec<f32>>) {
    let bytes = std::fs::read(glb).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).expect("a valid glTF binary");
    let blob = gltf.blob.clone().expect("a BIN chunk");
    let animation = gltf.animations().next().expect("an animation");
    let channel = animation.channels().next().expect("a channel");
    let reader = channel.reader(|_| Some(&blob));
    let times: Vec<f32> = reader.read_inputs().expect("key times").collect();
    let weights: Vec<f32> = match reader.read_outputs().expect("weights") {
        gltf::animation::util::ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
        _ => panic!("the channel animates morph target weights"),
    };
    let targets = weights.len() / times.len();
    (
        times,
        weights.chunks(targets).map(<[f32]>::to_vec).collect(),
    )
}

/// The time an OBJ frame's header gives (`puppet: frame K, t = T s`).
fn header_time(obj: &Path) -> f64 {
    let text = std::fs::read_to_string(obj).unwrap();
    let line = text.lines().next().unwrap();
    let t = line.split("t = ").nth(1).unwrap().trim_end_matches(" s");
    t.parse().unwrap()
}

/// glTF time t shows the state at animation time t: the rest surface at 0, frame k at
/// k / fps (its OBJ's header time), and `--first-frame N` starts the clip at N / fps; the
/// PC2's start frame and sample rate count the same frames.
#[test]
fn a_take_keeps_the_animation_s_clock() {
    let dir = scratch("export_clock");
    let frames = frames_dir("export_clock_frames");
    let glb = dir.join("take.glb");
    simulate(&glb, &["--frame-step", "4"]);
    let (times, weights) = glb_keys(&glb);
    assert_eq!(times.len(), 13);
    assert_eq!(times[0], 0.0);
    assert!(
        weights[0].iter().all(|&w| w == 0.0),
        "the rest surface at 0"
    );
    for (j, k) in (1..=45).step_by(4).enumerate() {
        let header = header_time(&frames.join(format!("frame_{k:05}.obj")));
        assert_eq!(times[j + 1], header as f32, "frame {k}");
        assert_eq!(
            times[j + 1],
            (k as f64 / 30.0) as f32,
            "frame {k} at k / fps"
        );
        assert_eq!(weights[j + 1][j], 1.0);
        assert_eq!(weights[j + 1].iter().sum::<f32>(), 1.0);
    }
    let late = dir.join("late.glb");
    simulate(&late, &["--first-frame", "10", "--frame-step", "5"]);
    let (times, _) = glb_keys(&late);
    let numbers: Vec<u64> = (10..=45).step_by(5).collect();
    assert_eq!(
        times.len(),
        numbers.len(),
        "no rest key: the clip starts at frame 10"
    );
    for (t, k) in times.iter().zip(&numbers) {
        let header = header_time(&frames.join(format!("frame_{k:05}.obj")));
        assert_eq!(*t, header as f32, "frame {k}");
    }
    validate(&late);
    let pc2 = dir.join("late.pc2");
    simulate(&pc2, &["--first-frame", "10", "--frame-step", "5"]);
    let b = std::fs::read(&pc2).unwrap();
    let f = |at: usize| f32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    let i = |at: usize| i32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    assert_eq!((f(20), f(24), i(28)), (10.0, 5.0, numbers.len() as i32));
}

#[test]
fn pc2_holds_every_frame_in_vertex_order_beside_its_base_obj() {
    let dir = scratch("export_pc2");
    let pc2 = dir.join("take.pc2");
    simulate(&pc2, &[]);
    let b = std::fs::read(&pc2).unwrap();
    assert_eq!(&b[..12], b"POINTCACHE2\0");
    let i = |at: usize| i32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    let f = |at: usize| f32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    let (points, samples) = (i(16) as usize, i(28) as usize);
    assert_eq!(samples, 45);
    assert_eq!(b.len(), 32 + points * samples * 12);
    let base = obj_vertices(&dir.join("take.obj"));
    assert_eq!(base.len(), points, "the base OBJ has the cache's points");
    let frames = frames_dir("export_pc2_frames");
    for k in [1usize, 20, 45] {
        let obj = obj_vertices(&frames.join(format!("frame_{k:05}.obj")));
        for (v, o) in obj.iter().enumerate() {
            let at = 32 + ((k - 1) * points + v) * 12;
            let p = [f(at), f(at + 4), f(at + 8)];
            assert!(close(p, *o), "frame {k} vertex {v}: {p:?} vs {o:?}");
        }
    }
}

#[test]
fn bad_export_paths_are_one_error_line_before_simulating() {
    let dir = scratch("export_bad");
    // A .pc2's base OBJ is created first: its error names it.
    let pc2 = puppet(&[
        "simulate",
        "--frames",
        "2",
        "--out",
        "/nonexistent/take.pc2",
    ]);
    assert_eq!(pc2.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&pc2.stderr)
        .starts_with("error: /nonexistent/take.obj: cannot write"));
    for (out, says) in [
        ("/nonexistent/take.glb", "cannot write"),
        ("/nonexistent/take.obj", "cannot write"),
        ("take.fbx", "not a format simulate writes"),
    ] {
        let target = if out.starts_with('/') {
            out.to_string()
        } else {
            dir.join(out).display().to_string()
        };
        let o = puppet(&["simulate", "--frames", "2", "--out", &target]);
        assert_eq!(o.status.code(), Some(2), "{out}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.starts_with(&format!("error: {target}: ")) && err.contains(says),
            "{err}"
        );
    }
}

/// The bake equals the preview: the example animation played in a session the way the
/// window plays it (uneven frame times, several steps in a long frame) and baked by
/// `simulate` into a PC2 give the same positions bit for bit.
#[test]
fn the_bake_equals_the_preview_bit_for_bit() {
    let dir = scratch("export_bake");
    let pc2 = dir.join("take.pc2");
    simulate(&pc2, &[]);
    let b = std::fs::read(&pc2).unwrap();
    let points = i32::from_le_bytes(b[16..20].try_into().unwrap()) as usize;

    let rig = puppet::RigFile::load(Path::new(&example("spot-jaw.rig.toml"))).unwrap();
    let (mesh, _) = puppet::mesh::load(rig.mesh.as_ref().unwrap()).unwrap();
    let built = puppet::Puppet::build(mesh, rig, puppet::progress::silent()).unwrap();
    let mut session = puppet::session::Session::new(built, "spot");
    let text = std::fs::read_to_string(example("spot-jaw.anim.toml")).unwrap();
    let anim = puppet::anim::Animation::parse(&text, puppet::files::Format::Toml).unwrap();
    session.set_animation(anim).unwrap();
    // Frame `f` of the cache (30 fps) is step `2 (f + 1)` at 60 steps/s: every frame is
    // compared, reached in window frames of uneven length.
    let samples = i32::from_le_bytes(b[28..32].try_into().unwrap()) as usize;
    assert_eq!(samples, 45);
    let frames = [1.0 / 37.0, 1.0 / 90.0, 0.1, 1.0 / 60.0, 0.031];
    let mut k = 0;
    let mut x = Vec::new();
    for f in 0..samples {
        let step = 2 * (f as u64 + 1);
        while (session.puppet.sim.steps() as u64) < step {
            let left = (step - session.puppet.sim.steps() as u64) as u32;
            session.advance(frames[k % frames.len()], left.min(8));
            k += 1;
        }
        assert_eq!(session.puppet.sim.steps() as u64, step);
        x = session.puppet.sim.positions().to_vec();
        assert_eq!(x.len(), points);
        for (v, p) in x.iter().enumerate() {
            let at = 32 + (f * points + v) * 12;
            for c in 0..3 {
                let baked = f32::from_le_bytes(b[at + 4 * c..at + 4 * c + 4].try_into().unwrap());
                assert_eq!(
                    p[c].to_bits(),
                    baked.to_bits(),
                    "frame {f} vertex {v} axis {c}"
                );
            }
        }
    }
    // Restart and a scrub back to the same time give the same surface again.
    session.scrub(1.5);
    assert_eq!(session.puppet.sim.steps(), 90);
    let again = session.puppet.sim.positions();
    assert!((0..points).all(|v| again.get(v) == x[v]));
}

/// The PC2 cache of a file with duplicate and unused vertices is in the file's vertex
/// order: every file vertex, a duplicate moving with the vertex it was welded into, an
/// unused one staying, and the base OBJ holding the file's vertices.
#[test]
fn pc2_follows_the_files_vertex_order_when_welding_merged_duplicates() {
    let dir = scratch("export_pc2_order");
    let spot = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/spot.obj");
    let text = std::fs::read_to_string(&spot).unwrap();
    let vertices: Vec<&str> = text.lines().filter(|l| l.starts_with("v ")).collect();
    let n = vertices.len();
    // Vertex n+1 duplicates vertex 1 and the first face uses it; vertex n+2 is unused.
    let mut out = String::new();
    let mut first_face = true;
    for line in text.lines() {
        if let (Some(face), true) = (line.strip_prefix("f "), first_face) {
            first_face = false;
            let corners: Vec<String> = face
                .split_whitespace()
                .map(|c| {
                    let v = c.split('/').next().unwrap();
                    if v == "1" {
                        (n + 1).to_string()
                    } else {
                        v.to_string()
                    }
                })
                .collect();
            out.push_str(&format!("f {}\n", corners.join(" ")));
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out.push_str(vertices[0]);
    out.push('\n');
    out.push_str("v 5 5 5\n");
    let mesh = dir.join("spot-dup.obj");
    std::fs::write(&mesh, out).unwrap();
    let pc2 = dir.join("take.pc2");
    let o = puppet(&[
        "simulate",
        &mesh.display().to_string(),
        "--rig",
        &example("spot-jaw.rig.toml"),
        "--anim",
        &example("spot-jaw.anim.toml"),
        "--frames",
        "20",
        "--out",
        &pc2.display().to_string(),
    ]);
    ok(&o);
    let b = std::fs::read(&pc2).unwrap();
    let i = |at: usize| i32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    let f = |at: usize| f32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    let (points, samples) = (i(16) as usize, i(28) as usize);
    assert_eq!(
        (points, samples),
        (n + 2, 20),
        "every file vertex, in order"
    );
    let base = obj_vertices(&dir.join("take.obj"));
    assert_eq!(base.len(), n + 2, "the base OBJ has the file's vertices");
    let at = |frame: usize, v: usize| {
        let k = 32 + (frame * points + v) * 12;
        [f(k), f(k + 4), f(k + 8)]
    };
    let mut moved = false;
    for frame in 0..samples {
        assert_eq!(
            at(frame, n),
            at(frame, 0),
            "the duplicate moves with vertex 1"
        );
        assert_eq!(at(frame, n + 1), [5.0, 5.0, 5.0], "the unused vertex stays");
        moved |= !close(at(frame, 0), base[0]);
    }
    assert!(moved, "vertex 1 moves in the take");
}

/// `--quantize`: 16-bit positions and targets (KHR_mesh_quantization) that decode, through
/// the node's transform, to the float take within half a grid step, in a smaller file the
/// validator accepts, and that puppet reads back: the float take's rest surface, face for
/// face, within a grid step.
#[test]
fn a_quantized_glb_decodes_to_the_take_and_is_smaller() {
    let dir = scratch("export_glb_quantized");
    let (full, small) = (dir.join("full.glb"), dir.join("small.glb"));
    simulate(&full, &["--frame-step", "4"]);
    simulate(&small, &["--frame-step", "4", "--quantize"]);
    let (a, b) = (
        std::fs::metadata(&full).unwrap().len(),
        std::fs::metadata(&small).unwrap().len(),
    );
    assert!(b * 10 < a * 8, "{b} bytes quantized vs {a}");
    validate(&small);
    let (ours, _) = puppet::mesh::load(&small).unwrap();
    let (float, _) = puppet::mesh::load(&full).unwrap();
    assert_eq!(ours.triangles, float.triangles);
    let extent = float
        .positions
        .iter()
        .fold(0.0f64, |e, p| e.max(p.abs().max_element()));
    for (a, b) in ours.positions.iter().zip(&float.positions) {
        assert!(
            a.distance(*b) <= 2.0 * extent / 32766.0,
            "{a} read back as {b}"
        );
    }
    // The gltf crate does not implement the extension: read it without its checks.
    let gltf = gltf::Gltf::from_slice_without_validation(&std::fs::read(&small).unwrap()).unwrap();
    assert!(gltf
        .extensions_required()
        .any(|e| e == "KHR_mesh_quantization"));
    let blob = gltf.blob.clone().unwrap();
    let node = gltf.nodes().next().unwrap();
    let (t, _, s) = node.transform().decomposed();
    let prim = gltf.meshes().next().unwrap().primitives().next().unwrap();
    // Reads a VEC3 of i16 accessor.
    let shorts = |a: gltf::Accessor| -> Vec<[f32; 3]> {
        assert_eq!(a.data_type(), gltf::accessor::DataType::I16);
        let view = a.view().unwrap();
        let stride = view.stride().unwrap_or(6);
        let start = view.offset() + a.offset();
        (0..a.count())
            .map(|k| {
                let at = start + k * stride;
                let c = |j: usize| {
                    i16::from_le_bytes(blob[at + 2 * j..at + 2 * j + 2].try_into().unwrap()) as f32
                };
                [c(0), c(1), c(2)]
            })
            .collect()
    };
    let rest = shorts(prim.get(&gltf::Semantic::Positions).unwrap());
    let last = prim.morph_targets().last().unwrap();
    let delta = shorts(last.positions().unwrap());
    // Frame 45 (the last target) against the float take's OBJ frame.
    let frames = frames_dir("export_glb_quantized_frames");
    let obj = obj_vertices(&frames.join("frame_00045.obj"));
    let step = s[0];
    for (v, o) in obj.iter().enumerate() {
        for c in 0..3 {
            let decoded = t[c] + s[c] * (rest[v][c] + delta[v][c]);
            assert!(
                (decoded - o[c]).abs() <= step * 0.5 + 1e-5,
                "vertex {v}: {decoded} vs {}",
                o[c]
            );
        }
    }
}

/// A session of the jaw example with its animation loaded and played a little (an export
/// starts from rest whatever the window shows), exporting with `settings`; and the mesh
/// file it was opened from.
fn jaw_session(settings: puppet::session::ExportSettings) -> (puppet::session::Session, PathBuf) {
    let rig = puppet::RigFile::load(Path::new(&example("spot-jaw.rig.toml"))).unwrap();
    let source = rig.mesh.clone().unwrap();
    let (mesh, _) = puppet::mesh::load(&source).unwrap();
    let built = puppet::Puppet::build(mesh, rig, puppet::progress::silent()).unwrap();
    let mut session = puppet::session::Session::new(built, "spot");
    let text = std::fs::read_to_string(example("spot-jaw.anim.toml")).unwrap();
    let anim = puppet::anim::Animation::parse(&text, puppet::files::Format::Toml).unwrap();
    session.set_animation(anim).unwrap();
    session.advance(0.3, 20);
    session.export_settings = settings;
    (session, source)
}

/// *Export animation* in a session gives the bytes `simulate` writes for the same range,
/// a bad path is a message that leaves the take being recorded alone, and a cancel
/// removes the partial file.
#[test]
fn the_windows_export_equals_simulates_and_can_be_cancelled() {
    let dir = scratch("export_session");
    let cli = dir.join("cli.pc2");
    simulate(&cli, &["--first-frame", "5", "--frame-step", "5"]);
    let (mut session, source) = jaw_session(puppet::session::ExportSettings {
        fps: 30.0,
        first: 5,
        last: 45,
        step: 5,
        quantize: false,
    });
    let win = dir.join("window.pc2");
    session.start_export(&win, Some(&source)).unwrap();
    let said = session.wait_export().unwrap().unwrap();
    assert!(said.contains("exported 9 frames"), "{said}");
    assert_eq!(std::fs::read(&win).unwrap(), std::fs::read(&cli).unwrap());
    assert_eq!(
        std::fs::read(dir.join("window.obj")).unwrap().len(),
        std::fs::read(dir.join("cli.obj")).unwrap().len()
    );

    // A bad path: a message, and the take being recorded goes on.
    session.start_recording();
    let bad = session.start_export(Path::new("/nonexistent/take.glb"), None);
    assert!(bad.unwrap_err().contains("cannot write"));
    let bad = session.start_export(&dir.join("take.fbx"), None);
    assert!(bad.unwrap_err().contains("choose a .glb"));
    assert!(session.is_recording());
    let _ = session.stop_recording();

    // Cancelled: no partial file left.
    session.export_settings.last = 2000;
    session.export_settings.step = 1;
    let long = dir.join("long.glb");
    session.start_export(&long, None).unwrap();
    assert!(session.export_job().is_some());
    session.cancel_export();
    let said = session.wait_export().unwrap();
    assert!(said.unwrap_err().contains("cancelled"));
    assert!(!long.exists());
}

/// Records a take in `session` turning section `section` about x by `degrees` a frame for
/// the first `turning` of `frames` frames (60 a second), saves it, exports it from the
/// session as a `.pc2` against `source`, bakes the saved file with `simulate` (`args`, then
/// `--anim` and `--out`), and asserts the two files are the same, byte for byte, with
/// several frames of `vertices` points.
fn take_bakes_as_exported(
    mut session: puppet::session::Session,
    section: usize,
    (frames, turning, degrees): (usize, usize, f64),
    source: &Path,
    dir: &Path,
    args: &[&str],
    vertices: usize,
) {
    session.select(Some(section), false);
    session.start_recording();
    for frame in 0..frames {
        if frame < turning {
            session.rotate_selected(glam::DQuat::from_rotation_x(degrees.to_radians()));
        }
        session.advance(1.0 / 60.0, 8);
    }
    session.stop_recording().unwrap();
    let anim = dir.join("take.anim.toml");
    session.save_animation(&anim).unwrap();
    let win = dir.join("window.pc2");
    session.start_export(&win, Some(source)).unwrap();
    session.wait_export().unwrap().unwrap();
    let cli = dir.join("cli.pc2");
    let mut all = vec!["simulate"];
    all.extend_from_slice(args);
    let (anim, out) = (anim.display().to_string(), cli.display().to_string());
    all.extend_from_slice(&["--anim", &anim, "--out", &out]);
    ok(&puppet(&all));
    let (a, b) = (std::fs::read(&win).unwrap(), std::fs::read(&cli).unwrap());
    assert!(a.len() > 32 + 12 * vertices, "several frames");
    assert!(a == b, "the window's export and simulate's bake differ");
}

/// The bake equals the preview for a take recorded by hand: recorded in a session, saved,
/// exported from the session, and the saved file baked by `simulate`, byte for byte.
#[test]
fn a_recorded_take_exports_as_simulate_bakes_its_saved_file() {
    let dir = scratch("export_recorded");
    let rig_path = example("spot-jaw.rig.toml");
    let rig = puppet::RigFile::load(Path::new(&rig_path)).unwrap();
    let source = rig.mesh.clone().unwrap();
    let (mesh, _) = puppet::mesh::load(&source).unwrap();
    let built = puppet::Puppet::build(mesh, rig, puppet::progress::silent()).unwrap();
    let session = puppet::session::Session::new(built, "spot");
    let args = ["--rig", rig_path.as_str()];
    take_bakes_as_exported(session, 1, (50, 30, 0.7), &source, &dir, &args, 2930);
}

/// *Export animation* to a video draws what `simulate --out TAKE.mp4` draws, frame by
/// frame (with the window's camera where it has one: here the one the window opens with),
/// and a cancelled one leaves no file: no video, no partial video, no frames' folder.
#[cfg(feature = "gui")]
#[test]
fn the_windows_video_export_draws_simulates_frames_and_can_be_cancelled() {
    use puppet::render::video::TakeVideo;
    use puppet::render::Image;
    let dir = scratch("export_video");
    // `simulate`'s frames, as PNG files (no `ffmpeg` for it).
    let cli = dir.join("cli.mp4");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_puppet"))
        .args(["simulate", "--rig", &example("spot-jaw.rig.toml")])
        .args(["--anim", &example("spot-jaw.anim.toml"), "--frames", "30"])
        .args(["--video-size", "160x120", "--out", cli.to_str().unwrap()])
        .env("PUPPET_FFMPEG", "")
        .output()
        .unwrap();
    ok(&out);
    let cli_frame =
        |k: usize| Image::load_png(&dir.join(format!("cli-frames/frame_{k:05}.png"))).unwrap();

    let (mut session, _) = jaw_session(puppet::session::ExportSettings {
        fps: 30.0,
        first: 1,
        last: 30,
        step: 1,
        quantize: false,
    });
    let look = puppet::session::Overlays::default();
    let video = |path: PathBuf| {
        move |fps: f64| {
            assert_eq!(fps, 30.0);
            TakeVideo::create(&path, (160, 120), look, None, fps)
                .map(|v| Box::new(v) as Box<dyn puppet::session::TakeWriter>)
                .map_err(|e| e.to_string())
        }
    };
    let win = dir.join("window.mp4");
    session.start_export_with(&win, video(win.clone())).unwrap();
    let said = session.wait_export().unwrap().unwrap();
    // With `ffmpeg` the video, each frame decoded; without it, the frames as PNG files.
    let frame = |k: usize| -> Image {
        if win.exists() {
            common::decoded_frame(&win, k, &dir.join(format!("window_{k}.png")))
        } else {
            Image::load_png(&dir.join(format!("window-frames/frame_{k:05}.png"))).unwrap()
        }
    };
    assert!(said.contains("30 frames"), "{said}");
    if win.exists() {
        // As long as the take, a picture a frame (`ffprobe` comes with `ffmpeg`).
        let stream = common::probed(&win);
        assert_eq!(stream["nb_read_frames"], "30", "{stream}");
        let duration: f64 = stream["duration"].as_str().unwrap().parse().unwrap();
        assert!((duration - 1.0).abs() < 1e-3, "{duration} s");
    }
    for k in [1, 15, 30] {
        let d = frame(k).mean_abs_diff(&cli_frame(k)).unwrap();
        assert!(d < 3.0, "frame {k} differs from simulate's by {d:.2}");
    }
    assert!(
        frame(30).mean_abs_diff(&frame(1)).unwrap() > 0.5,
        "the jaw moves"
    );

    // Cancelled: nothing left.
    session.export_settings.last = 2000;
    let long = dir.join("long.mp4");
    session
        .start_export_with(&long, video(long.clone()))
        .unwrap();
    // While it runs another is refused before its writer is made (no second `ffmpeg`).
    let refused = session.start_export_with(&dir.join("other.mp4"), |_| -> Result<_, _> {
        panic!("a writer made for an export that cannot start")
    });
    assert!(refused.unwrap_err().contains("an export is running"));
    session.cancel_export();
    let said = session.wait_export().unwrap();
    assert!(said.unwrap_err().contains("cancelled"));
    for gone in ["long.mp4", "long.partial.mp4", "long-frames"] {
        assert!(!dir.join(gone).exists(), "{gone} left behind");
    }
}

/// The bake equals the preview for a mesh opened without a rig: the window opens it with
/// its suggested joints, a take is recorded turning one of them (the human's left leg),
/// and `simulate` bakes the saved take on the same mesh, no rig given, byte for byte.
#[test]
fn a_take_on_a_mesh_opened_without_a_rig_bakes_the_same_without_one() {
    let dir = scratch("export_no_rig");
    let source = common::test_mesh("human.obj");
    let (mesh, _) = puppet::mesh::load(&source).unwrap();
    let mut built =
        puppet::Puppet::build(mesh, puppet::RigFile::default(), puppet::progress::silent())
            .unwrap();
    // What the window does with a mesh opened without a rig.
    built.suggest_joints().unwrap();
    let leg = built.joints.find("leg.L").expect("a suggested leg");
    let session = puppet::session::Session::new(built, "human");
    let args = [source.to_str().unwrap()];
    take_bakes_as_exported(session, leg, (40, 25, -2.0), &source, &dir, &args, 6890);
}
