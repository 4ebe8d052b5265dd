//! The generated characters of the labelled set (`tests/data/characters`): each is a few
//! tapered capsules blended into one closed surface, with its joints written down where its
//! bones meet. `cargo test --release --test characters -- --ignored` writes them again; the
//! other test checks that the files in the repository are what this file makes.

mod mesher;

use glam::DVec3;
use mesher::{Body, Bone};
use std::fmt::Write as _;
use std::path::Path;

/// A labelled joint: the section it starts (`arm.L` at the shoulder), where, and
/// whether a suggestion must find it (limb roots, neck, elbows, knees) or may (wrists,
/// ankles, ears, tail).
struct Joint {
    role: String,
    at: DVec3,
    required: bool,
    /// A limb's root: the direction its bone leaves the trunk, and its radius there.
    limb: Option<(DVec3, f64)>,
}

/// A stretch along which any cut is a fair joint (a tail, a long flexible limb).
struct Free {
    role: String,
    along: Vec<DVec3>,
}

#[derive(Default)]
struct Character {
    name: &'static str,
    kind: &'static str,
    what: &'static str,
    /// Grid cell of the mesher.
    cell: f64,
    blend: f64,
    bones: Vec<Bone>,
    joints: Vec<Joint>,
    free: Vec<Free>,
    /// Modelled Z-up (front -Y), as CAD and some DCC tools export: written rotated.
    z_up: bool,
    /// The trunk's bones (those made before the limbs).
    trunk: Option<usize>,
}

fn v(p: [f64; 3]) -> DVec3 {
    DVec3::from_array(p)
}

impl Character {
    fn bone(&mut self, a: [f64; 3], b: [f64; 3], ra: f64, rb: f64) {
        let group = self.bones.len();
        self.grouped(a, b, ra, rb, group);
    }

    fn grouped(&mut self, a: [f64; 3], b: [f64; 3], ra: f64, rb: f64, group: usize) {
        self.bones.push(Bone {
            a: v(a),
            b: v(b),
            ra,
            rb,
            group,
        });
    }

    /// Bones from point to point, `radii` at each point, joined without a blend.
    fn chain(&mut self, points: &[[f64; 3]], radii: &[f64]) {
        let group = self.bones.len();
        for k in 1..points.len() {
            self.grouped(points[k - 1], points[k], radii[k - 1], radii[k], group);
        }
    }

    fn joint(&mut self, role: &str, at: [f64; 3], required: bool) {
        self.joints.push(Joint {
            role: role.into(),
            at: v(at),
            required,
            limb: None,
        });
    }

    /// A limb's root: where the bone from `at` towards `toward` (radius `r`) leaves the
    /// trunk, half its radius in: where a puppeteer puts the ball of a shoulder or a hip.
    fn root(&mut self, role: &str, at: [f64; 3], toward: [f64; 3], r: f64) {
        self.joints.push(Joint {
            role: role.into(),
            at: v(at),
            required: true,
            limb: Some(((v(toward) - v(at)).normalize(), r)),
        });
    }

    /// Where joint `j` is: a limb's root is found on the trunk's surface.
    fn place(&self, j: &Joint) -> DVec3 {
        let Some((dir, r)) = j.limb else {
            return j.at;
        };
        let trunk = Body {
            bones: self.bones[..self.trunk.unwrap_or(self.bones.len())].to_vec(),
            blend: self.blend,
        };
        let step = r * 0.01;
        let mut p = j.at;
        for _ in 0..10_000 {
            if trunk.field(p) > 0.0 {
                break;
            }
            p += dir * step;
        }
        p - dir * 0.5 * r
    }

    /// A stubby limb from `root` to `tip` (radii `r`), its joint where it leaves the trunk,
    /// any cut along it fair: a toy's arm.
    fn stub(&mut self, role: &str, root: [f64; 3], tip: [f64; 3], r: [f64; 2]) {
        self.bone(root, tip, r[0], r[1]);
        self.root(role, root, tip, r[0]);
        self.free(role, &[root, tip]);
    }

    /// A leg from the hip to the ankle and a foot on to the toe (radii at the hip, the
    /// ankle's two and the toe), its joint where it leaves the trunk, any cut along it fair.
    fn leg_with_foot(&mut self, role: &str, [hip, ankle, toe]: [[f64; 3]; 3], r: [f64; 4]) {
        self.bone(hip, ankle, r[0], r[1]);
        self.bone(ankle, toe, r[2], r[3]);
        self.root(role, hip, ankle, r[0]);
        self.free(role, &[hip, ankle, toe]);
    }

    fn free(&mut self, role: &str, along: &[[f64; 3]]) {
        self.free.push(Free {
            role: role.into(),
            along: along.iter().map(|&p| v(p)).collect(),
        });
    }

    /// Runs `side` for the character's left (x > 0, suffix `L`) and right.
    fn both(&mut self, side: impl Fn(&mut Character, f64, &str)) {
        self.trunk.get_or_insert(self.bones.len());
        side(self, 1.0, "L");
        side(self, -1.0, "R");
    }

    fn body(&self) -> Body {
        Body {
            bones: self.bones.clone(),
            blend: self.blend,
        }
    }

    /// Y-up (the model's frame) to the file's frame.
    fn out(&self, p: DVec3) -> DVec3 {
        if self.z_up {
            DVec3::new(p.x, -p.z, p.y)
        } else {
            p
        }
    }

    fn obj(&self) -> String {
        // The first grid offset that gives a manifold surface (surface nets can pinch
        // where two sheets pass within a cell).
        let body = self.body();
        let (positions, mut triangles) =
            [0.33, 0.21, 0.47, 0.12, 0.39, 0.05, 0.27, 0.43, 0.15, 0.36]
                .iter()
                .map(|&o| body.mesh(self.cell, o))
                .find(|(p, t)| mesher::manifold(t, p.len()) && distinct(p))
                .unwrap_or_else(|| panic!("{}: no manifold surface at any offset", self.name));
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                a.dot(b.cross(c))
            })
            .sum();
        if volume < 0.0 {
            for t in &mut triangles {
                t.swap(1, 2);
            }
        }
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# {}: {} (generated by tests/characters, CC0)",
            self.name, self.what
        );
        for p in &positions {
            let p = self.out(*p);
            let _ = writeln!(s, "v {} {} {}", r4(p.x), r4(p.y), r4(p.z));
        }
        for t in &triangles {
            let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
    }

    fn labels(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# {}: {}. Generated with its mesh by tests/characters (CC0): the joints are\n\
             # where its bones meet.",
            self.name, self.what
        );
        let _ = writeln!(s, "mesh = \"{}.obj\"", self.name);
        let _ = writeln!(s, "kind = \"{}\"", self.kind);
        let _ = writeln!(s, "up = \"{}\"", if self.z_up { "+z" } else { "+y" });
        for j in &self.joints {
            let p = self.out(self.place(j));
            let _ = writeln!(
                s,
                "\n[[joint]]\nrole = \"{}\"\nat = [{}, {}, {}]\nrequired = {}",
                j.role,
                r3(p.x),
                r3(p.y),
                r3(p.z),
                j.required
            );
        }
        for f in &self.free {
            let along: Vec<String> = f
                .along
                .iter()
                .map(|&p| {
                    let p = self.out(p);
                    format!("[{}, {}, {}]", r3(p.x), r3(p.y), r3(p.z))
                })
                .collect();
            let _ = writeln!(
                s,
                "\n[[free]]\nrole = \"{}\"\nalong = [{}]",
                f.role,
                along.join(", ")
            );
        }
        s
    }
}

/// No two vertices the same once written with four decimals.
fn distinct(positions: &[DVec3]) -> bool {
    let mut seen = std::collections::HashSet::new();
    positions
        .iter()
        .all(|p| seen.insert([r4(p.x), r4(p.y), r4(p.z)]))
}

fn r4(x: f64) -> String {
    format!("{}", (x * 1e4).round() / 1e4 + 0.0)
}

fn r3(x: f64) -> String {
    format!("{}", (x * 1e3).round() / 1e3 + 0.0)
}

/// A slender humanoid in A-pose.
fn robot() -> Character {
    let mut c = Character {
        name: "robot",
        kind: "humanoid",
        what: "a slender humanoid in A-pose",
        cell: 0.032,
        blend: 0.04,
        ..Default::default()
    };
    c.bone([0.0, 0.95, 0.0], [0.0, 1.32, 0.0], 0.15, 0.17);
    c.bone([0.0, 1.4, 0.0], [0.0, 1.58, 0.0], 0.055, 0.055);
    c.bone([0.0, 1.68, 0.01], [0.0, 1.76, 0.01], 0.11, 0.1);
    c.joint("neck", [0.0, 1.48, 0.0], true);
    c.joint("head", [0.0, 1.58, 0.0], false);
    c.both(|c, s, lr| {
        let (sh, el, wr, tip) = (
            [0.2 * s, 1.42, 0.0],
            [0.38 * s, 1.15, 0.0],
            [0.52 * s, 0.9, 0.02],
            [0.58 * s, 0.78, 0.04],
        );
        c.chain(&[sh, el, wr, tip], &[0.055, 0.045, 0.035, 0.03]);
        c.root(&format!("arm.{lr}"), sh, el, 0.055);
        c.joint(&format!("forearm.{lr}"), el, true);
        c.joint(&format!("hand.{lr}"), wr, false);
        let (hip, knee, ankle, toe) = (
            [0.1 * s, 0.9, 0.0],
            [0.12 * s, 0.5, 0.01],
            [0.13 * s, 0.09, 0.0],
            [0.13 * s, 0.04, 0.16],
        );
        c.chain(&[hip, knee, ankle], &[0.08, 0.06, 0.042]);
        c.bone(ankle, toe, 0.045, 0.035);
        c.root(&format!("leg.{lr}"), hip, knee, 0.08);
        c.joint(&format!("shin.{lr}"), knee, true);
        c.joint(&format!("foot.{lr}"), ankle, false);
    });
    c
}

/// A cartoon man: a big head on a thick neck, a pear-shaped body with a belly, short
/// limbs, and bumps for eyes and a nose that are no joints.
fn cartoon() -> Character {
    let mut c = Character {
        name: "cartoon",
        kind: "cartoon",
        what: "a cartoon man with a big head, eyes, a nose and a belly",
        cell: 0.022,
        blend: 0.05,
        ..Default::default()
    };
    c.bone([0.0, 0.45, 0.0], [0.0, 0.72, 0.0], 0.26, 0.2);
    c.bone([0.0, 0.5, 0.12], [0.0, 0.5, 0.14], 0.14, 0.14);
    c.bone([0.0, 0.82, 0.0], [0.0, 0.95, 0.01], 0.12, 0.12);
    c.bone([0.0, 1.02, 0.02], [0.0, 1.1, 0.02], 0.17, 0.16);
    c.bone([0.0, 1.02, 0.17], [0.0, 1.0, 0.23], 0.035, 0.035);
    for s in [1.0, -1.0] {
        c.bone(
            [0.065 * s, 1.09, 0.15],
            [0.065 * s, 1.09, 0.16],
            0.045,
            0.045,
        );
    }
    c.joint("neck", [0.0, 0.86, 0.0], true);
    c.both(|c, s, lr| {
        let (sh, el, wr, tip) = (
            [0.2 * s, 0.8, 0.0],
            [0.36 * s, 0.62, 0.04],
            [0.44 * s, 0.46, 0.08],
            [0.46 * s, 0.4, 0.1],
        );
        c.chain(&[sh, el, wr], &[0.062, 0.05, 0.042]);
        c.bone(wr, tip, 0.055, 0.05);
        c.root(&format!("arm.{lr}"), sh, el, 0.062);
        c.joint(&format!("forearm.{lr}"), el, true);
        c.joint(&format!("hand.{lr}"), wr, false);
        let (hip, knee, ankle, toe) = (
            [0.12 * s, 0.3, 0.0],
            [0.13 * s, 0.17, 0.02],
            [0.13 * s, 0.06, 0.0],
            [0.13 * s, 0.045, 0.12],
        );
        c.chain(&[hip, knee, ankle], &[0.085, 0.07, 0.055]);
        c.bone(ankle, toe, 0.06, 0.05);
        c.root(&format!("leg.{lr}"), hip, knee, 0.085);
        c.joint(&format!("shin.{lr}"), knee, false);
        c.joint(&format!("foot.{lr}"), ankle, false);
    });
    c
}

/// A toy bear with big round ears, a big head on a round body, and stubby limbs.
fn teddy() -> Character {
    let mut c = Character {
        name: "teddy",
        kind: "toy",
        what: "a toy bear with big ears and stubby limbs",
        cell: 0.018,
        blend: 0.04,
        ..Default::default()
    };
    c.bone([0.0, 0.33, 0.0], [0.0, 0.52, 0.0], 0.2, 0.17);
    c.bone([0.0, 0.78, 0.0], [0.0, 0.79, 0.0], 0.2, 0.2);
    c.bone([0.0, 0.74, 0.17], [0.0, 0.73, 0.22], 0.07, 0.06);
    c.joint("head", [0.0, 0.63, 0.0], true);
    c.both(|c, s, lr| {
        c.bone([0.16 * s, 0.92, 0.0], [0.24 * s, 1.0, -0.01], 0.06, 0.1);
        c.joint(&format!("ear.{lr}"), [0.16 * s, 0.92, 0.0], false);
        let arm = ([0.16 * s, 0.52, 0.0], [0.32 * s, 0.4, 0.07]);
        c.stub(&format!("arm.{lr}"), arm.0, arm.1, [0.07, 0.06]);
        let leg = [
            [0.1 * s, 0.22, 0.0],
            [0.12 * s, 0.07, 0.03],
            [0.12 * s, 0.06, 0.12],
        ];
        c.leg_with_foot(&format!("leg.{lr}"), leg, [0.085, 0.075, 0.065, 0.06]);
    });
    c
}

/// A dog: a quadruped with a neck, a snout, ears and a tail.
fn dog() -> Character {
    let mut c = Character {
        name: "dog",
        kind: "quadruped",
        what: "a dog with a snout, ears and a tail",
        cell: 0.017,
        blend: 0.03,
        ..Default::default()
    };
    c.bone([0.0, 0.45, -0.28], [0.0, 0.47, 0.25], 0.13, 0.14);
    c.bone([0.0, 0.5, 0.3], [0.0, 0.62, 0.42], 0.07, 0.065);
    c.bone([0.0, 0.66, 0.45], [0.0, 0.64, 0.52], 0.09, 0.08);
    c.bone([0.0, 0.63, 0.55], [0.0, 0.61, 0.66], 0.045, 0.04);
    c.joint("neck", [0.0, 0.52, 0.32], true);
    c.joint("head", [0.0, 0.62, 0.42], false);
    let tail = [[0.0, 0.5, -0.4], [0.0, 0.58, -0.52], [0.0, 0.64, -0.64]];
    c.chain(&tail, &[0.035, 0.028, 0.02]);
    c.joint("tail", tail[0], false);
    c.free("tail", &tail);
    c.both(|c, s, lr| {
        let ear = [[0.06 * s, 0.72, 0.43], [0.1 * s, 0.8, 0.41]];
        c.bone(ear[0], ear[1], 0.032, 0.02);
        c.joint(&format!("ear.{lr}"), ear[0], false);
        let (sh, el, wr, paw) = (
            [0.08 * s, 0.4, 0.22],
            [0.09 * s, 0.24, 0.24],
            [0.09 * s, 0.07, 0.23],
            [0.09 * s, 0.035, 0.29],
        );
        c.chain(&[sh, el, wr], &[0.05, 0.036, 0.03]);
        c.bone(wr, paw, 0.034, 0.03);
        c.root(&format!("arm.{lr}"), sh, el, 0.05);
        c.joint(&format!("forearm.{lr}"), el, true);
        c.joint(&format!("hand.{lr}"), wr, false);
        let (hip, knee, hock, paw) = (
            [0.08 * s, 0.42, -0.25],
            [0.09 * s, 0.26, -0.2],
            [0.09 * s, 0.13, -0.31],
            [0.09 * s, 0.035, -0.27],
        );
        c.chain(&[hip, knee, hock, paw], &[0.058, 0.04, 0.03, 0.03]);
        c.root(&format!("leg.{lr}"), hip, knee, 0.058);
        c.joint(&format!("shin.{lr}"), knee, true);
        c.joint(&format!("foot.{lr}"), hock, false);
    });
    c
}

/// A horse modelled Z-up (front -Y), with a long neck and a tail.
fn horse() -> Character {
    let mut c = Character {
        name: "horse",
        kind: "quadruped",
        what: "a horse modelled Z-up, with a long neck and a tail",
        cell: 0.044,
        blend: 0.06,
        z_up: true,
        ..Default::default()
    };
    c.bone([0.0, 1.2, -0.6], [0.0, 1.25, 0.55], 0.3, 0.32);
    c.bone([0.0, 1.35, 0.7], [0.0, 1.75, 1.0], 0.15, 0.12);
    c.bone([0.0, 1.8, 1.05], [0.0, 1.55, 1.35], 0.11, 0.08);
    c.joint("neck", [0.0, 1.38, 0.72], true);
    c.joint("head", [0.0, 1.75, 1.0], false);
    let tail = [[0.0, 1.3, -0.85], [0.0, 1.05, -1.0], [0.0, 0.8, -1.05]];
    c.chain(&tail, &[0.06, 0.05, 0.04]);
    c.joint("tail", tail[0], false);
    c.free("tail", &tail);
    c.both(|c, s, lr| {
        c.bone([0.06 * s, 1.9, 1.0], [0.07 * s, 2.0, 0.98], 0.035, 0.025);
        c.joint(&format!("ear.{lr}"), [0.06 * s, 1.9, 1.0], false);
        let (sh, carpus, fetlock, hoof) = (
            [0.15 * s, 1.0, 0.5],
            [0.15 * s, 0.55, 0.52],
            [0.15 * s, 0.2, 0.5],
            [0.15 * s, 0.05, 0.56],
        );
        c.chain(&[sh, carpus, fetlock], &[0.09, 0.06, 0.045]);
        c.bone(fetlock, hoof, 0.045, 0.055);
        c.root(&format!("arm.{lr}"), sh, carpus, 0.09);
        c.joint(&format!("forearm.{lr}"), carpus, true);
        c.joint(&format!("hand.{lr}"), fetlock, false);
        let (hip, stifle, hock, fetlock, hoof) = (
            [0.16 * s, 1.1, -0.55],
            [0.16 * s, 0.75, -0.45],
            [0.16 * s, 0.5, -0.7],
            [0.16 * s, 0.18, -0.65],
            [0.16 * s, 0.05, -0.6],
        );
        c.chain(&[hip, stifle, hock, fetlock], &[0.13, 0.085, 0.06, 0.045]);
        c.bone(fetlock, hoof, 0.045, 0.055);
        c.root(&format!("leg.{lr}"), hip, stifle, 0.13);
        c.joint(&format!("shin.{lr}"), stifle, true);
        c.joint(&format!("foot.{lr}"), hock, false);
        c.free(&format!("foot.{lr}"), &[hock, fetlock, hoof]);
    });
    c
}

/// A lizard: sprawled legs and a long tail curling to one side.
fn lizard() -> Character {
    let mut c = Character {
        name: "lizard",
        kind: "creature with a tail",
        what: "a lizard with sprawled legs and a long tail",
        cell: 0.0104,
        blend: 0.015,
        ..Default::default()
    };
    c.bone([0.0, 0.08, -0.15], [0.0, 0.08, 0.15], 0.07, 0.075);
    c.bone([0.0, 0.09, 0.2], [0.0, 0.09, 0.26], 0.042, 0.042);
    c.bone([0.0, 0.09, 0.3], [0.0, 0.08, 0.38], 0.052, 0.035);
    c.joint("neck", [0.0, 0.09, 0.21], true);
    let tail = [
        [0.0, 0.08, -0.2],
        [0.0, 0.07, -0.4],
        [0.05, 0.06, -0.6],
        [0.12, 0.05, -0.75],
    ];
    c.chain(&tail, &[0.05, 0.035, 0.022, 0.012]);
    c.joint("tail", tail[0], false);
    c.free("tail", &tail);
    c.both(|c, s, lr| {
        let (sh, el, wr, foot) = (
            [0.07 * s, 0.08, 0.12],
            [0.17 * s, 0.09, 0.16],
            [0.19 * s, 0.025, 0.2],
            [0.2 * s, 0.018, 0.25],
        );
        c.chain(&[sh, el, wr, foot], &[0.028, 0.022, 0.018, 0.016]);
        c.root(&format!("arm.{lr}"), sh, el, 0.028);
        c.joint(&format!("forearm.{lr}"), el, true);
        c.joint(&format!("hand.{lr}"), wr, false);
        let (hip, knee, ankle, foot) = (
            [0.07 * s, 0.08, -0.13],
            [0.18 * s, 0.09, -0.12],
            [0.2 * s, 0.025, -0.17],
            [0.22 * s, 0.018, -0.23],
        );
        c.chain(&[hip, knee, ankle, foot], &[0.032, 0.024, 0.02, 0.016]);
        c.root(&format!("leg.{lr}"), hip, knee, 0.032);
        c.joint(&format!("shin.{lr}"), knee, true);
        c.joint(&format!("foot.{lr}"), ankle, false);
    });
    c
}

/// A two-legged dinosaur: big legs, tiny arms, a head held forward and a long tail.
fn dino() -> Character {
    let mut c = Character {
        name: "dino",
        kind: "creature with a tail",
        what: "a two-legged dinosaur with tiny arms and a long tail",
        cell: 0.028,
        blend: 0.05,
        ..Default::default()
    };
    c.bone([0.0, 1.0, -0.2], [0.0, 1.1, 0.25], 0.22, 0.2);
    c.bone([0.0, 1.2, 0.35], [0.0, 1.35, 0.45], 0.11, 0.1);
    c.bone([0.0, 1.42, 0.5], [0.0, 1.38, 0.78], 0.12, 0.08);
    c.joint("neck", [0.0, 1.22, 0.36], true);
    let tail = [[0.0, 1.0, -0.35], [0.0, 0.95, -0.8], [0.0, 0.9, -1.3]];
    c.chain(&tail, &[0.15, 0.08, 0.025]);
    c.joint("tail", tail[0], false);
    c.free("tail", &tail);
    c.both(|c, s, lr| {
        let (sh, el, tip) = (
            [0.15 * s, 1.05, 0.3],
            [0.2 * s, 0.95, 0.42],
            [0.21 * s, 0.98, 0.5],
        );
        c.chain(&[sh, el, tip], &[0.04, 0.032, 0.025]);
        c.root(&format!("arm.{lr}"), sh, el, 0.04);
        c.free(&format!("arm.{lr}"), &[sh, el, tip]);
        let (hip, knee, ankle, toe) = (
            [0.14 * s, 0.95, -0.1],
            [0.18 * s, 0.6, 0.08],
            [0.18 * s, 0.2, -0.12],
            [0.18 * s, 0.045, 0.08],
        );
        c.chain(&[hip, knee, ankle], &[0.13, 0.09, 0.06]);
        c.bone(ankle, toe, 0.055, 0.045);
        c.root(&format!("leg.{lr}"), hip, knee, 0.13);
        c.joint(&format!("shin.{lr}"), knee, true);
        c.joint(&format!("foot.{lr}"), ankle, false);
    });
    c
}

/// An ant: head, thorax and abdomen joined at narrow waists, six sprawled legs from the
/// thorax and two antennae.
fn ant() -> Character {
    let mut c = Character {
        name: "ant",
        kind: "insect",
        what: "an ant with a narrow waist, six legs and antennae",
        cell: 0.007,
        blend: 0.012,
        ..Default::default()
    };
    c.bone([0.0, 0.2, 0.0], [0.0, 0.22, 0.19], 0.055, 0.05);
    c.bone([0.0, 0.2, -0.07], [0.0, 0.2, -0.03], 0.025, 0.025);
    c.bone([0.0, 0.2, -0.22], [0.0, 0.22, -0.12], 0.09, 0.07);
    c.bone([0.0, 0.23, 0.22], [0.0, 0.24, 0.24], 0.022, 0.022);
    c.bone([0.0, 0.25, 0.3], [0.0, 0.24, 0.34], 0.065, 0.06);
    c.joint("head", [0.0, 0.235, 0.24], true);
    c.joint("abdomen", [0.0, 0.2, -0.06], true);
    c.both(|c, s, lr| {
        let antenna = [
            [0.03 * s, 0.3, 0.36],
            [0.09 * s, 0.38, 0.38],
            [0.14 * s, 0.4, 0.46],
        ];
        c.chain(&antenna, &[0.026, 0.024, 0.022]);
        c.joint(&format!("antenna.{lr}"), antenna[0], false);
        c.free(&format!("antenna.{lr}"), &antenna);
        for (k, z) in [(1, 0.17), (2, 0.09), (3, 0.01)] {
            let spread = (z - 0.1) * 2.0;
            let (hip, knee, foot) = (
                [0.04 * s, 0.2, z],
                [0.2 * s, 0.3, z + spread],
                [0.32 * s, 0.02, z + 1.6 * spread],
            );
            c.chain(&[hip, knee, foot], &[0.034, 0.03, 0.026]);
            c.root(&format!("leg{k}.{lr}"), hip, knee, 0.034);
            c.joint(&format!("shin{k}.{lr}"), knee, true);
            c.free(&format!("shin{k}.{lr}"), &[knee, foot]);
        }
    });
    c
}

/// A toy whose head is bigger than its body, with big flat ears (the kind of a
/// well-known big-eared toy): the body is where the arms and legs hang, not the head.
fn bigears() -> Character {
    let mut c = Character {
        name: "bigears",
        kind: "toy",
        what: "a toy with a head bigger than its body and big flat ears",
        cell: 0.012,
        blend: 0.03,
        ..Default::default()
    };
    c.bone([0.0, 0.3, 0.0], [0.0, 0.5, 0.0], 0.11, 0.1);
    c.bone([0.0, 0.77, 0.0], [0.0, 0.78, 0.0], 0.19, 0.19);
    c.joint("head", [0.0, 0.6, 0.0], true);
    c.both(|c, s, lr| {
        // A flat ear: capsules fanning out from the head to one round rim, one surface.
        let group = c.bones.len();
        for dy in [-0.06, -0.03, 0.0, 0.03, 0.06] {
            let (base, rim) = (
                [0.17 * s, 0.8 + 0.5 * dy, 0.0],
                [0.31 * s, 0.81 + dy, -0.02],
            );
            c.grouped(base, rim, 0.022, 0.05, group);
        }
        c.joint(&format!("ear.{lr}"), [0.17 * s, 0.8, 0.0], false);
        let arm = ([0.09 * s, 0.47, 0.0], [0.22 * s, 0.32, 0.05]);
        c.stub(&format!("arm.{lr}"), arm.0, arm.1, [0.04, 0.035]);
        let leg = [
            [0.06 * s, 0.28, 0.0],
            [0.07 * s, 0.07, 0.01],
            [0.07 * s, 0.05, 0.12],
        ];
        c.leg_with_foot(&format!("leg.{lr}"), leg, [0.05, 0.045, 0.045, 0.05]);
    });
    c
}

/// A monkey's head modelled on its own (the kind of Blender's Suzanne): a skull, a muzzle
/// and eyes in front, and flat ears out to the sides. The ears are its only limbs, so
/// finding them is required; the face is no neck.
fn monkey() -> Character {
    let mut c = Character {
        name: "monkey",
        kind: "head",
        what: "a monkey's head on its own, with a muzzle, eyes and flat ears",
        cell: 0.014,
        blend: 0.04,
        ..Default::default()
    };
    c.bone([0.0, 1.0, -0.05], [0.0, 1.06, -0.05], 0.3, 0.28);
    c.bone([0.0, 0.88, 0.14], [0.0, 0.62, 0.2], 0.19, 0.15);
    for s in [1.0, -1.0] {
        c.bone([0.11 * s, 1.05, 0.2], [0.11 * s, 1.05, 0.23], 0.07, 0.07);
    }
    c.both(|c, s, lr| {
        // A flat ear: capsules fanning out from the side of the skull to one round rim.
        let group = c.bones.len();
        for dy in [-0.06, -0.03, 0.0, 0.03, 0.06] {
            let (base, rim) = (
                [0.26 * s, 1.0 + 0.5 * dy, -0.05],
                [0.42 * s, 1.01 + dy, -0.1],
            );
            c.grouped(base, rim, 0.04, 0.06, group);
        }
        c.joint(&format!("ear.{lr}"), [0.3 * s, 1.0, -0.05], true);
    });
    c
}

fn characters() -> Vec<Character> {
    vec![
        robot(),
        cartoon(),
        teddy(),
        bigears(),
        dog(),
        horse(),
        lizard(),
        dino(),
        ant(),
        monkey(),
    ]
}

fn folder() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/characters")
}

#[test]
#[ignore = "writes tests/data/characters; run it after changing a character"]
fn write_the_generated_characters() {
    let dir = folder();
    std::fs::create_dir_all(&dir).unwrap();
    for c in characters() {
        std::fs::write(dir.join(format!("{}.obj", c.name)), c.obj()).unwrap();
        std::fs::write(dir.join(format!("{}.toml", c.name)), c.labels()).unwrap();
    }
}

#[test]
fn the_generated_characters_are_what_this_file_makes() {
    for c in characters() {
        let labels = std::fs::read_to_string(folder().join(format!("{}.toml", c.name)))
            .expect("the labels are in tests/data/characters");
        assert_eq!(labels, c.labels(), "{}.toml is stale", c.name);
    }
}
