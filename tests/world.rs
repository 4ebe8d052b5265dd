//! Gravity, the floor, several materials on one puppet, pinning and stiffening bone
//! springs (paper §3.2 and §5): what each promises, and that rigs written before them
//! behave exactly as before.

mod common;
use common::{example, ok, puppet, scratch};
use glam::{Affine3A, Quat, Vec3};
use puppet::sim::{Material, Pose, Regions, Simulation};
use puppet::{Puppet, RigFile};
use std::path::Path;

/// FNV-1a over the vertex lines of an OBJ file (the header names paths and versions).
fn vertex_hash(obj: &Path) -> u64 {
    let text = std::fs::read_to_string(obj).unwrap();
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for line in text.lines().filter(|l| l.starts_with("v ")) {
        for b in line.bytes().chain([b'\n']) {
            h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

/// The example rig and animation through `puppet simulate`, with `extra` appended to the
/// rig; the hash of the final surface.
fn simulate_hash(test: &str, extra: &str) -> u64 {
    let dir = scratch(test);
    let rig = dir.join("rig.toml");
    let text = std::fs::read_to_string(example("spot-jaw.rig.toml"))
        .unwrap()
        .replace("mesh = \"../spot.obj\"\n", "")
        // Hinges, as every cut was then (joint bands came later and change the bend).
        .replace("[[cut]]\n", "[[cut]]\nband = 0.0\n");
    std::fs::write(&rig, format!("{text}{extra}")).unwrap();
    let out_obj = dir.join("final.obj");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/spot.obj");
    let out = puppet(&[
        "simulate",
        mesh.to_str().unwrap(),
        "--rig",
        rig.to_str().unwrap(),
        "--anim",
        &example("spot-jaw.anim.toml"),
        "--frames",
        "45",
        "--out",
        out_obj.to_str().unwrap(),
    ]);
    ok(&out);
    vertex_hash(&out_obj)
}

#[test]
fn rigs_written_before_gravity_behave_exactly_as_before() {
    // The hashes were taken with the code before gravity, floors, materials, pinning and
    // stiffening existed (commit ffd865a): the same rig files gave the same surface, bit
    // for bit, on both constraints, until whole sections (`joints::whole`): the plain
    // plane at Spot's neck left a piece of 9 body vertices inside the head, which now
    // turns with it (the final surface moves by up to 1.8 % of the diagonal). Taken
    // again then, and again when a surface spring's stiffness became the mean rest length
    // over its own (`rig::stiffness`: the final surfaces moved by at most 0.16 %, 0.68 %
    // and 0.71 % of the diagonal, median 0.004–0.04 %); nothing since may change them.
    assert_eq!(
        simulate_hash("before_circumsphere", ""),
        0x1fcc_8c85_bea3_4955
    );
    let water = "\n[params]\ndamping = 0.99\nbone_distance = 1.0\nmax_length = 1.4\n";
    let reduction = water.replace("[params]\n", "[params]\nmin_length = 0.7\n");
    assert_eq!(simulate_hash("before_water", water), 0x4008_fe1d_bca9_fef8);
    let text = format!("{reduction}reduction_iterations = 3\n");
    let hash = simulate_hash(
        "before_reduction",
        &text.replace(
            "\n[params]",
            "\n[params]\nconstraint = \"spring-reduction\"",
        ),
    );
    assert_eq!(hash, 0x22a2_cff2_bcfb_b218);
}

/// A capsule along y from −1.8 to 1.8 (an arm), radius 0.3, cut at y = 0 into "root" and
/// "arm", built from a rig file's text (appended to a cut).
fn arm(extra: &str) -> Result<Puppet, String> {
    let mesh = puppet::mesh::shapes::capsule(0.3, 1.5, 6, 36, 20);
    let text = format!("{extra}\n[[cut]]\nname = \"arm\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\n");
    let spec = RigFile::parse(&text, puppet::files::Format::Toml, Path::new("."))
        .map_err(|e| e.to_string())?;
    Puppet::build(mesh, spec, puppet::progress::silent()).map_err(|e| e.to_string())
}

/// Runs until every tile sleeps (at most `limit` steps); the largest vertex distance from
/// its posed rest position.
fn settle(sim: &mut Simulation, pose: &Pose, limit: usize) -> f32 {
    for _ in 0..limit {
        sim.step(pose);
        if sim.is_asleep() {
            break;
        }
    }
    let x = sim.positions();
    (0..x.len())
        .map(|i| (x.get(i) - sim.target(i)).length())
        .fold(0.0, f32::max)
}

#[test]
fn gravity_sags_within_the_constraint_and_not_a_static_material() {
    let mut p = arm("[params]\ngravity = [0, -1, 0]\n").unwrap();
    let pose = Pose::rest(2);
    let sag = settle(&mut p.sim, &pose, 3000);
    assert!(p.sim.is_asleep(), "settles");
    let rho = (p.sim.params().material.max_length - 1.0)
        * p.sim.rig().bone_length.iter().copied().fold(0.0, f32::max);
    assert!(sag > 0.2 * rho && sag <= rho * 1.0001, "sag {sag}, ρ {rho}");
    // Every vertex moved down, none up.
    let x = p.sim.positions();
    assert!((0..x.len()).all(|i| x.get(i).y <= p.sim.rig().rest[i].y + 1e-6));
    let mut plastic = arm("material = \"plastic\"\n[params]\ngravity = [0, -10, 0]\n").unwrap();
    assert_eq!(settle(&mut plastic.sim, &pose, 100), 0.0);
}

#[test]
fn gravity_does_not_depend_on_the_step() {
    let at = |h: f32| {
        let mut p = arm(&format!(
            "material = \"water\"\n[params]\ngravity = [0, -1, 0]\ntime_step = {h}\n"
        ))
        .unwrap();
        let pose = Pose::rest(2);
        for _ in 0..(2.0 / h) as usize {
            p.sim.step(&pose);
        }
        let x = p.sim.positions();
        (0..x.len())
            .map(|i| p.sim.rig().rest[i].y - x.get(i).y)
            .sum::<f32>()
            / x.len() as f32
    };
    let (a, b) = (at(1.0 / 60.0), at(1.0 / 240.0));
    assert!(
        a > 0.0 && (a - b).abs() <= 0.1 * a,
        "mean sag after 2 s: {a} vs {b}"
    );
}

#[test]
fn a_section_posed_into_the_floor_squashes_against_it() {
    let mut p = arm("[params]\nfloor = true\nfloor_height = 0.5\nfloor_friction = 1.0\n").unwrap();
    let floor = p.sim.floor_height().unwrap();
    assert_eq!(floor, -1.8 + 0.5, "0.5 above the lowest rest point");
    // Push the arm down into the floor by a third of its length.
    let pose = Pose {
        transforms: vec![
            Affine3A::IDENTITY,
            Affine3A::from_translation(Vec3::new(0.0, -1.2, 0.0)),
        ],
    };
    let mut squashed = 0;
    for _ in 0..240 {
        p.sim.step(&pose);
        let x = p.sim.positions();
        for i in 0..x.len() {
            assert!(x.get(i).y >= floor, "vertex {i} below the floor");
        }
        squashed = (0..x.len()).filter(|&i| x.get(i).y == floor).count();
    }
    assert!(squashed > 10, "{squashed} vertices on the floor");
    // A turned pose too, and gravity in any direction: still nothing below it.
    let mut q = *p.sim.params();
    q.world.gravity = [3.0, -5.0, 2.0];
    p.sim.set_params(q);
    let pose = Pose {
        transforms: vec![
            Affine3A::IDENTITY,
            Affine3A::from_quat(Quat::from_rotation_z(2.5)),
        ],
    };
    for _ in 0..120 {
        p.sim.step(&pose);
    }
    let x = p.sim.positions();
    assert!((0..x.len()).all(|i| x.get(i).y >= floor && x.get(i).is_finite()));
}

#[test]
fn regions_and_pinning_by_section_and_painted() {
    // The arm is water, the root pinned: under gravity the arm sags, the root does not.
    let mut p = arm("[params]\ngravity = [0, -2, 0]\n\
         [[region]]\nname = \"jelly\"\nmaterial = \"water\"\nsections = [\"arm\"]\n\
         [region.params]\nstiffening = 2\n\
         [pin]\nsections = [\"root\"]\n")
    .unwrap();
    let sections = p.joints.section_of().to_vec();
    let pose = Pose::rest(2);
    for _ in 0..600 {
        p.sim.step(&pose);
    }
    let x = p.sim.positions();
    let moved = |s: u16| {
        (0..x.len())
            .filter(|&i| sections[i] == s)
            .map(|i| (x.get(i) - p.sim.target(i)).length())
            .fold(0.0, f32::max)
    };
    assert!(moved(0) < 1e-5, "pinned root moved {}", moved(0));
    assert!(moved(1) > 1e-3, "water arm sagged {}", moved(1));
    let arm_vertex = sections.iter().position(|&s| s == 1).unwrap();
    let water = p
        .sim
        .regions()
        .material_of(arm_vertex, &p.sim.params().material);
    assert_eq!((water.damping, water.stiffening), (0.99, 2));

    // The rig written and read back gives the same regions (painted weights included).
    let mut spec = p.current_rig_file();
    let n = p.mesh.positions.len();
    spec.regions[0].paint.weights = (0..n)
        .map(|i| if i % 7 == 0 { 128.0 / 255.0 } else { 0.0 })
        .collect();
    let text = spec.to_toml(None);
    assert!(text.contains("painted = \"128 0*6 128"), "{text}");
    let back = RigFile::parse(&text, puppet::files::Format::Toml, Path::new(".")).unwrap();
    assert_eq!(back.regions, spec.regions);
    assert_eq!(back.pin, spec.pin);
}

#[test]
fn bad_regions_say_which_and_where() {
    let err = |extra: &str| arm(extra).err().unwrap();
    assert!(err("[[region]]\nname = \"a\"\nsections = [\"leg\"]\n")
        .contains("region 'a': no section 'leg'"));
    assert!(err("[[region]]\nname = \"a\"\npainted = \"255*3\"\n")
        .contains("painted weights are for 3 vertices"));
    assert!(err("[[region]]\nname = \"a\"\npainted = \"255*x\"\n")
        .contains("region 1 ('a'): painted: run 1"));
    assert!(err("[[region]]\nname = \"a\"\nmaterial = \"rubber\"\n").contains("not a preset"));
    assert!(
        err("[[region]]\nname = \"a\"\n[region.params]\ndamping = 3\n")
            .contains("region 1 ('a'): params: damping = 3")
    );
    assert!(err("[pin]\nsections = [\"leg\"]\n").contains("pin: no section 'leg'"));
    assert!(err("[params]\nstiffening = 9\n").contains("stiffening"));
    assert!(err("[params]\ngravity = [0, 1]\n").starts_with("params"));
}

#[test]
fn stiffening_softens_near_rest() {
    // A small pull: stiffening springs give way more than Hooke's.
    let pulled = |stiffening: u32| {
        let mut p = arm(&format!(
            "[params]\ngravity = [0, -0.05, 0]\nstiffening = {stiffening}\nmax_length = 3.0\n"
        ))
        .unwrap();
        settle(&mut p.sim, &Pose::rest(2), 3000)
    };
    let (hooke, soft) = (pulled(0), pulled(2));
    assert!(soft > 1.5 * hooke, "{soft} vs {hooke}");
}

#[test]
fn simulate_takes_gravity_and_the_floor() {
    let dir = scratch("simulate_gravity");
    let out_obj = dir.join("final.obj");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/spot.obj");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "simulate",
            mesh.to_str().unwrap(),
            "--frames",
            "30",
            "--json",
        ];
        args.extend_from_slice(extra);
        puppet(&args)
    };
    let out = run(&[
        "--gravity",
        "2",
        "--floor",
        "0.05",
        "--friction",
        "0.3",
        "--out",
        out_obj.to_str().unwrap(),
    ]);
    ok(&out);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(report["final_max_offset"].as_f64().unwrap() > 1e-3);
    let bad = run(&["--gravity", "11"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.starts_with("error: ") && err.contains("gravity[1]"),
        "{err}"
    );
}

#[test]
fn uniform_regions_change_nothing() {
    // Every vertex given the base material explicitly (weight 0 layers, pin 0): bit for
    // bit the plain simulation.
    let run = |regions: Option<Regions>| {
        let mut p = arm("[params]\ngravity = [0, -1, 0]\n").unwrap();
        if let Some(r) = regions {
            p.sim.set_regions(r);
        }
        let pose = Pose {
            transforms: vec![
                Affine3A::IDENTITY,
                Affine3A::from_quat(Quat::from_rotation_x(0.7)),
            ],
        };
        for _ in 0..100 {
            p.sim.step(&pose);
        }
        p.sim.positions().to_vec()
    };
    let n = arm("").unwrap().mesh.positions.len();
    let zero = Regions {
        layers: vec![puppet::sim::Layer {
            material: Material::default(),
            weight: vec![0.0; n],
        }],
        pin: vec![0.0; n],
    };
    assert_eq!(run(None), run(Some(zero)));
}

/// A character modelled z-up (the cow turned so its up is +z, `up = "+z"` in its rig):
/// `--gravity` pulls it along −z, and the floor lies across z under its lowest point; no
/// vertex passes it.
#[test]
fn gravity_and_the_floor_follow_the_character_s_up() {
    let dir = scratch("z_up");
    let (cow, _) =
        puppet::mesh::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/spot.obj")).unwrap();
    let turned: Vec<glam::DVec3> = cow
        .positions
        .iter()
        .map(|p| glam::DVec3::new(p.x, -p.z, p.y))
        .collect();
    let mesh = dir.join("cow-z-up.obj");
    let mut file = std::fs::File::create(&mesh).unwrap();
    puppet::mesh::write_obj(&mut file, &turned, &cow.triangles, "").unwrap();
    drop(file);
    let rig = dir.join("rig.toml");
    std::fs::write(&rig, "up = \"+z\"\n").unwrap();
    let out_obj = dir.join("final.obj");
    let out = puppet(&[
        "simulate",
        mesh.to_str().unwrap(),
        "--rig",
        rig.to_str().unwrap(),
        "--frames",
        "30",
        "--gravity",
        "3",
        "--floor",
        "0",
        "--out",
        out_obj.to_str().unwrap(),
    ]);
    ok(&out);
    let (now, _) = puppet::mesh::load(&out_obj).unwrap();
    let lowest = turned.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    let mean = |v: &[glam::DVec3]| v.iter().copied().sum::<glam::DVec3>() / v.len() as f64;
    let moved = mean(&now.positions) - mean(&turned);
    let size = 1.0; // The cow is about a unit across.
    assert!(moved.z < -1e-3 * size, "it sags along −z: {moved}");
    assert!(moved.y.abs() < 0.2 * moved.z.abs(), "not along y: {moved}");
    let below = now
        .positions
        .iter()
        .map(|p| lowest - p.z)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(below <= 1e-5, "a vertex {below} below the floor");
}
