//! Skinned glTF: the file's skin becomes the puppet's joints (its names, its hierarchy,
//! our roles beside them), its clips play through the puppet, and the puppet's surface
//! while a clip plays is held to the file's own linear-blend skinning, computed here
//! independently with the `gltf` crate's readers.

mod common;

use common::{ok, puppet, scratch, validate};
use glam::{DMat4, DQuat, DVec3};
use std::path::{Path, PathBuf};

fn figure() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf/skinned-figure.glb")
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = puppet(args);
    ok(&out);
    serde_json::from_slice(&out.stdout).unwrap()
}

/// `suggest` takes the skin's joints: the file's names and hierarchy, pivots at the
/// joints, our roles beside the names, the clips listed; `--ignore-skin` gives our own
/// suggestion instead.
#[test]
fn a_skinned_figure_is_rigged_by_its_skin() {
    let path = figure();
    let path = path.to_str().unwrap();
    let s = json(&["suggest", path, "--json"]);
    assert_eq!(s["joints_from"], "skin");
    let cuts = s["cuts"].as_array().unwrap();
    // 16 joints, the root one the root section: 15 cuts.
    assert_eq!(cuts.len(), 15, "{cuts:?}");
    let cut = |name: &str| cuts.iter().find(|c| c["name"] == name).unwrap();
    assert_eq!(cut("forearm.L")["parent"], "upper_arm.L");
    assert_eq!(cut("forearm.L")["role"], "forearm.L");
    assert_eq!(cut("thigh.R")["role"], "leg.R");
    assert_eq!(cut("thigh.R")["parent"], "spine");
    // The elbow's pivot where Blender's bone has it (z-up there, y-up in glTF).
    let pivot: Vec<f64> = cut("forearm.L")["pivot"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!((DVec3::from_slice(&pivot) - DVec3::new(0.48, 1.40, 0.0)).length() < 1e-4);
    for c in cuts {
        assert!(c["vertices"].as_u64().unwrap() > 20, "{c}");
    }
    let clips: Vec<&str> = s["skin"]["clips"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(clips, ["raise", "walk", "wave"]);
    // Mixamo's names, and its armature's 0.01 scale: the pivots in metres.
    let mixamo = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf/skinned-mixamo.glb");
    let m = json(&["suggest", mixamo.to_str().unwrap(), "--json"]);
    let cuts = m["cuts"].as_array().unwrap();
    let forearm = cuts
        .iter()
        .find(|c| c["name"] == "mixamorig:LeftForeArm")
        .unwrap();
    assert_eq!(forearm["role"], "forearm.L");
    assert_eq!(forearm["parent"], "mixamorig:LeftArm");
    let pivot: Vec<f64> = forearm["pivot"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!((DVec3::from_slice(&pivot) - DVec3::new(0.48, 1.40, 0.0)).length() < 1e-4);
    let ours = json(&["suggest", path, "--json", "--ignore-skin"]);
    assert_eq!(ours["joints_from"], "suggestion");
    assert!(ours["skin"]["joints"] == 16);
}

/// A downloaded wasp whose exporter wrote NaN for 6 vertices' skin weights keeps the
/// skeleton it came with: each of those vertices takes its nearest neighbour's joints, and
/// the load says so in one line (the whole skin was left out before, and its joints
/// suggested from the shape).
#[test]
fn a_skin_with_a_few_weights_that_are_not_numbers_is_kept() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf/wasp-nan-weights.glb");
    let out = puppet(&["suggest", path.to_str().unwrap(), "--json"]);
    ok(&out);
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(s["joints_from"], "skin");
    assert_eq!(s["skin"]["joints"], 29);
    assert_eq!(s["skin"]["clips"].as_array().unwrap().len(), 3);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("gave 6 vertices whose skin weights are not numbers the joints of the nearest vertex with weights"),
        "{stderr}"
    );
    assert!(!stderr.contains("left its skin out"), "{stderr}");
    let (mesh, _) = puppet::mesh::load(&path).unwrap();
    assert!(mesh.positions.iter().all(|p| p.is_finite()));
}

/// The rig file `suggest -o` writes from the skin loads back to the same sections.
#[test]
fn a_rig_written_from_a_skin_loads_back_the_same() {
    let dir = scratch("skin_rig");
    let rig = dir.join("figure.rig.toml");
    let path = figure();
    let first = json(&[
        "suggest",
        path.to_str().unwrap(),
        "--json",
        "-o",
        rig.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&rig).unwrap();
    assert!(text.contains("shape = \"skin\""), "{text}");
    let file = puppet::RigFile::load(&rig).unwrap();
    let (mesh, report) = puppet::mesh::load(&path).unwrap();
    let built = puppet::Puppet::build_loaded(mesh, Some(&report), file, puppet::progress::silent())
        .unwrap();
    let sections = built.joints.sections();
    for c in first["cuts"].as_array().unwrap() {
        let s = built.joints.find(c["name"].as_str().unwrap()).unwrap();
        assert_eq!(sections[s].vertices as u64, c["vertices"].as_u64().unwrap());
    }
}

/// A node's rest transform as translation, rotation, scale.
type Trs = (DVec3, DQuat, DVec3);

/// The file's own skinning of every vertex at time `t` of `clip`, computed with the
/// `gltf` crate's readers: node transforms (the clip's channels over the rest ones,
/// linear, rotations by slerp), `global · inverse bind` per joint, weights.
fn file_skinning(bytes: &[u8], clip: &str, t: f64) -> Vec<DVec3> {
    let gltf = gltf::Gltf::from_slice(bytes).unwrap();
    let blob = gltf.blob.clone().unwrap();
    let data = |_: gltf::Buffer| Some(blob.as_slice());
    let mut locals: Vec<Trs> = gltf
        .nodes()
        .map(|n| {
            let (t, r, s) = n.transform().decomposed();
            (
                glam::Vec3::from(t).as_dvec3(),
                glam::Quat::from_array(r).as_dquat(),
                glam::Vec3::from(s).as_dvec3(),
            )
        })
        .collect();
    let animation = gltf.animations().find(|a| a.name() == Some(clip)).unwrap();
    for channel in animation.channels() {
        let reader = channel.reader(data);
        let times: Vec<f32> = reader.read_inputs().unwrap().collect();
        let k = times
            .partition_point(|&x| (x as f64) <= t)
            .clamp(1, times.len() - 1);
        let s = ((t - times[k - 1] as f64) / (times[k] - times[k - 1]) as f64).clamp(0.0, 1.0);
        let node = channel.target().node().index();
        use gltf::animation::util::ReadOutputs;
        match reader.read_outputs().unwrap() {
            ReadOutputs::Translations(v) => {
                let v: Vec<DVec3> = v.map(|x| glam::Vec3::from(x).as_dvec3()).collect();
                locals[node].0 = v[k - 1].lerp(v[k], s);
            }
            ReadOutputs::Rotations(r) => {
                let r: Vec<DQuat> = r
                    .into_f32()
                    .map(|x| glam::Quat::from_array(x).as_dquat())
                    .collect();
                locals[node].1 = r[k - 1].slerp(r[k], s);
            }
            ReadOutputs::Scales(v) => {
                let v: Vec<DVec3> = v.map(|x| glam::Vec3::from(x).as_dvec3()).collect();
                locals[node].2 = v[k - 1].lerp(v[k], s);
            }
            ReadOutputs::MorphTargetWeights(_) => {}
        }
    }
    let mut parent = vec![None; locals.len()];
    for n in gltf.nodes() {
        for c in n.children() {
            parent[c.index()] = Some(n.index());
        }
    }
    let global = |mut n: usize| {
        let mut m = DMat4::IDENTITY;
        loop {
            let (t, r, s) = locals[n];
            m = DMat4::from_scale_rotation_translation(s, r, t) * m;
            match parent[n] {
                Some(p) => n = p,
                None => return m,
            }
        }
    };
    let mut out = Vec::new();
    for node in gltf.nodes() {
        let (Some(mesh), Some(skin)) = (node.mesh(), node.skin()) else {
            continue;
        };
        let ibm: Vec<DMat4> = skin
            .reader(data)
            .read_inverse_bind_matrices()
            .unwrap()
            .map(|m| glam::Mat4::from_cols_array_2d(&m).as_dmat4())
            .collect();
        let joints: Vec<DMat4> = skin
            .joints()
            .zip(&ibm)
            .map(|(j, ibm)| global(j.index()) * *ibm)
            .collect();
        for prim in mesh.primitives() {
            let reader = prim.reader(data);
            let positions = reader.read_positions().unwrap();
            let js = reader.read_joints(0).unwrap().into_u16();
            let ws = reader.read_weights(0).unwrap().into_f32();
            for ((p, j), w) in positions.zip(js).zip(ws) {
                let p = glam::Vec3::from(p).as_dvec3();
                out.push(
                    (0..4)
                        .map(|c| w[c] as f64 * joints[j[c] as usize].transform_point3(p))
                        .sum(),
                );
            }
        }
    }
    out
}

/// Each OBJ frame's vertices.
fn frame(path: &Path) -> Vec<DVec3> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|c| c.parse().unwrap()).collect();
            DVec3::new(v[0], v[1], v[2])
        })
        .collect()
}

/// The skinned characters of `tests/data/gltf` and their clips.
const CHARACTERS: [(&str, [&str; 3]); 3] = [
    ("skinned-figure.glb", ["walk", "wave", "raise"]),
    ("skinned-mixamo.glb", ["walk", "wave", "raise"]),
    ("skinned-dog.glb", ["trot", "wag", "look"]),
];

/// While each clip of each character plays, the puppet's surface stays within 2 % of the
/// character's height (RMS) of the file's own skinning at the same time, and equals it at
/// rest: the flesh lags and sways, the motion is the clip's. No edge (but slivers)
/// stretches past 2×, and the clip moves the character.
#[test]
fn every_clip_plays_through_the_puppet_as_the_file_skins_it() {
    for (name, clips) in CHARACTERS {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/gltf")
            .join(name);
        let bytes = std::fs::read(&path).unwrap();
        let (mesh, _) = puppet::mesh::load(&path).unwrap();
        // The file's vertex of each of ours, by rest position (welding merges duplicates).
        let rest = file_skinning(&bytes, clips[0], 0.0);
        let of: Vec<usize> = mesh
            .positions
            .iter()
            .map(|p| {
                (0..rest.len())
                    .min_by(|&a, &b| rest[a].distance(*p).total_cmp(&rest[b].distance(*p)))
                    .unwrap()
            })
            .collect();
        let (lo, hi) = mesh.positions.iter().fold(
            (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let height = (hi - lo).max_element();
        for (v, &f) in of.iter().enumerate() {
            assert!(
                rest[f].distance(mesh.positions[v]) < 1e-5 * height,
                "{name}: the rest differs at {v}"
            );
        }
        // Edges at least a quarter of the median edge; shorter ones (the metaball meshes'
        // slivers, whose length a millimetre's sway multiplies) are reported apart.
        let edges = puppet::mesh::unique_edges(&mesh.triangles);
        let length =
            |&(a, b): &(u32, u32)| mesh.positions[a as usize].distance(mesh.positions[b as usize]);
        let mut lengths: Vec<f64> = edges.iter().map(length).collect();
        lengths.sort_by(f64::total_cmp);
        let short = 0.25 * lengths[lengths.len() / 2];
        let longest = |x: &dyn Fn(usize) -> DVec3, slivers: bool| {
            edges
                .iter()
                .filter(|e| (length(e) < short) == slivers)
                .map(|&(a, b)| x(a as usize).distance(x(b as usize)) / length(&(a, b)))
                .fold(1.0, f64::max)
        };
        for clip in clips {
            let dir = scratch(&format!("skin_clip_{name}_{clip}"));
            let frames = dir.join("frames");
            ok(&puppet(&[
                "simulate",
                path.to_str().unwrap(),
                "--clip",
                clip,
                "--out-dir",
                &format!("{}/", frames.display()),
            ]));
            let (mut worst, mut moved): (f64, f64) = (0.0, 0.0);
            let (mut stretch, mut file_stretch, mut sliver): (f64, f64, f64) = (1.0, 1.0, 1.0);
            for k in (5..).step_by(5) {
                let file = frames.join(format!("frame_{k:05}.obj"));
                if !file.exists() {
                    break;
                }
                let ours = frame(&file);
                let theirs = file_skinning(&bytes, clip, k as f64 / 30.0);
                stretch = stretch.max(longest(&|v| ours[v], false));
                sliver = sliver.max(longest(&|v| ours[v], true));
                file_stretch = file_stretch.max(longest(&|v| theirs[of[v]], false));
                let sum: f64 = ours
                    .iter()
                    .zip(&of)
                    .map(|(p, &f)| p.distance_squared(theirs[f]))
                    .sum();
                worst = worst.max((sum / ours.len() as f64).sqrt() / height);
                let far = ours
                    .iter()
                    .zip(&mesh.positions)
                    .map(|(a, b)| a.distance(*b));
                moved = moved.max(far.fold(0.0, f64::max));
            }
            eprintln!(
                "{name} {clip}: worst RMS {:.3} % of the height; worst edge stretch \
                 {stretch:.2} (slivers {sliver:.2}), the file's skinning {file_stretch:.2}",
                worst * 100.0
            );
            assert!(worst <= 0.02, "{name} {clip}: RMS {worst:.3} of the height");
            assert!(
                stretch <= 2.0,
                "{name} {clip}: an edge stretched {stretch:.2}×"
            );
            // A still puppet would pass the bounds above only if the clip hardly moved.
            assert!(moved > 0.1 * height, "{name} {clip}: moved only {moved}");
        }
    }
}

/// The session plays a clip as the window does: a skinned file opened without cuts gets
/// its skin's joints, and `raise` turns the right arm 70° and holds it there.
#[test]
fn a_session_plays_a_clip_and_holds_its_last_pose() {
    let path = figure();
    let (mesh, report) = puppet::mesh::load(&path).unwrap();
    let loader = puppet::session::loader::Loader::build(
        mesh,
        "figure".into(),
        Some(path.clone()),
        Some(report),
        puppet::RigFile::default(),
        puppet::session::loader::AfterLoad {
            clip: Some("raise".into()),
            ..Default::default()
        },
    );
    let mut loader = loader;
    let start = std::time::Instant::now();
    let opened = loop {
        if let puppet::session::loader::Status::Done(r) = loader.poll() {
            break r.unwrap();
        }
        assert!(
            start.elapsed() < std::time::Duration::from_secs(120),
            "the loader did not finish within 120 s"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    assert!(opened.problems.is_empty(), "{:?}", opened.problems);
    let mut session = opened.session;
    assert_eq!(session.clips().len(), 3);
    for _ in 0..100 {
        session.advance(1.0 / 30.0, 10);
    }
    let arm = session.puppet.joints.find("upper_arm.R").unwrap();
    let degrees = session.local[arm]
        .rotation
        .angle_between(DQuat::IDENTITY)
        .to_degrees();
    assert!((degrees - 70.0).abs() < 5.0, "the arm turned {degrees}°");
}

/// A take baked from a clip is a glb the Khronos validator passes, with a morph target per
/// frame of the clip.
#[test]
fn a_take_baked_from_a_clip_is_valid_gltf() {
    let dir = scratch("skin_take");
    let take = dir.join("walk.glb");
    let path = figure();
    let out = json(&[
        "simulate",
        path.to_str().unwrap(),
        "--clip",
        "walk",
        "--out",
        take.to_str().unwrap(),
        "--json",
    ]);
    // 1.54 s at 30 fps.
    assert_eq!(out["exported_frames"], 47, "{out}");
    validate(&take);
    let gltf = gltf::Gltf::open(&take).unwrap();
    let targets = gltf.meshes().next().unwrap().primitives().next().unwrap();
    assert_eq!(targets.morph_targets().count(), 47);
}

/// Blender's glTF importer shows the baked take in time: at each of its frames the mesh is
/// our frames interpolated at that time (when Blender is installed; else not run).
#[test]
fn blender_shows_a_take_baked_from_a_clip_in_time() {
    if std::process::Command::new("blender")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("blender not installed: not run");
        return;
    }
    let dir = scratch("skin_take_blender");
    let (take, frames) = (dir.join("walk.glb"), dir.join("frames"));
    let path = figure();
    for out in [take.display().to_string(), format!("{}/", frames.display())] {
        ok(&puppet(&[
            "simulate",
            path.to_str().unwrap(),
            "--clip",
            "walk",
            "--out",
            &out,
        ]));
    }
    let shown = dir.join("shown.json");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/blender-take.py");
    let run = std::process::Command::new("blender")
        .args(["--background", "--factory-startup", "--python"])
        .arg(&script)
        .arg("--")
        .args([&take, &shown])
        .args(["13", "25", "37"])
        .output()
        .unwrap();
    common::ok(&run);
    let shown: serde_json::Value = serde_json::from_slice(&std::fs::read(&shown).unwrap()).unwrap();
    let fps = shown["fps"].as_f64().unwrap();
    for f in [13, 25, 37] {
        // Blender's frame f is f / fps seconds; our frame k is k / 30 s.
        let t = f as f64 / fps * 30.0;
        let k = t.floor() as usize;
        let w = t - k as f64;
        let (a, b) = (
            frame(&frames.join(format!("frame_{k:05}.obj"))),
            frame(&frames.join(format!("frame_{:05}.obj", k + 1))),
        );
        let blender = shown[f.to_string()].as_array().unwrap();
        assert_eq!(blender.len(), a.len());
        for (v, p) in blender.iter().enumerate() {
            let p = DVec3::new(
                p[0].as_f64().unwrap(),
                p[1].as_f64().unwrap(),
                p[2].as_f64().unwrap(),
            );
            let ours = a[v].lerp(b[v], w);
            assert!(
                p.distance(ours) < 1e-5,
                "frame {f}, vertex {v}: {p} in Blender, {ours} ours"
            );
        }
    }
}

/// `simulate` takes a skinned file's joints where the window does: with no rig, and with
/// a rig that has no cuts (a material only); a rig's cuts, or `--ignore-skin`, win.
#[test]
fn simulate_takes_the_skin_s_joints_where_the_window_does() {
    let dir = scratch("skin_simulate_joints");
    let rig = dir.join("water.rig.toml");
    std::fs::write(&rig, "material = \"water\"\n").unwrap();
    let path = figure();
    let from = |extra: &[&str]| {
        let mut args = vec![
            "simulate",
            path.to_str().unwrap(),
            "--frames",
            "2",
            "--json",
        ];
        args.extend_from_slice(extra);
        json(&args)["joints_from"].as_str().unwrap().to_string()
    };
    assert_eq!(from(&[]), "skin");
    assert_eq!(from(&["--rig", rig.to_str().unwrap()]), "skin");
    assert_eq!(from(&["--ignore-skin"]), "suggestion");
}
