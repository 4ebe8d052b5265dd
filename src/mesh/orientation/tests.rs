//! The orientation cues and frame on small figures made to show each rule.

use super::frame::toes;
use super::*;

#[test]
fn up_reads_and_writes_as_an_axis() {
    for text in ["+x", "-x", "+y", "-y", "+z", "-z"] {
        let up: Up = text.parse().unwrap();
        assert_eq!(up.to_string(), text);
    }
    assert_eq!("Z".parse::<Up>().unwrap(), Up::PosZ);
    assert_eq!(Up::nearest(DVec3::new(0.1, -0.2, -0.9)), Up::NegZ);
    assert!("up".parse::<Up>().is_err());
}

#[test]
fn a_bust_with_no_limbs_stands_on_its_flat_base() {
    // A ball cut flat below, modelled z-up: a bust's base at its far end along -z.
    let mut bust = crate::mesh::shapes::icosphere(1.0, 3);
    for p in &mut bust.positions {
        p.z = p.z.max(-0.6);
    }
    assert_eq!(flat_base(&bust), Some(DVec3::NEG_Z));
    // Round all over, or flat where it is not at the far end, there is none.
    assert_eq!(flat_base(&crate::mesh::shapes::icosphere(1.0, 3)), None);
    let (n, o) = mirror_plane(&bust.positions, &bust.triangles, None).unwrap();
    assert!(n.dot(DVec3::Z).abs() < 0.5, "{n}");
    // Its cues: the plane along the axis, the base below.
    let cues = Cues::of(&bust, None);
    assert_eq!(cues.base, Some(DVec3::NEG_Z));
    assert_eq!(cues.mirror, Some((n, o)));
    let f = frame(&bust.positions, cues, &[], Given::default());
    assert_eq!(f.up, DVec3::Z);
    // A given up wins, and with nothing flat the convention stays.
    let given = frame(&bust.positions, cues, &[], Given::with_up(DVec3::X));
    assert_eq!(given.up, DVec3::X);
    assert_eq!(
        frame(
            &bust.positions,
            Cues {
                base: None,
                flat: [0.0; 6],
                ..cues
            },
            &[],
            Given::default()
        )
        .up,
        DVec3::Y
    );
}

#[test]
fn legs_hanging_along_an_axis_make_the_other_way_up() {
    let plane = crate::mesh::mirror::tests::figure(false);
    // Four legs off the plane hanging along -z: z is up, front across it and x.
    let leg = |x: f64, y: f64| Reach {
        pivot: DVec3::new(x, y, 0.0),
        tip: DVec3::new(x, y, -1.0),
        end: 0.1,
        carried: None,
    };
    let limbs = [leg(0.5, 0.2), leg(1.5, 0.2), leg(0.5, 1.8), leg(1.5, 1.8)];
    let cues = Cues {
        mirror: mirror_plane(&plane, &[], None),
        base: None,
        flat: [0.0; 6],
        bulk: None,
        detail: [0.0; 3],
    };
    let f = frame(&plane, cues, &limbs, Given::default());
    assert_eq!(f.up, DVec3::Z);
    assert!(f.front.dot(DVec3::Y).abs() > 0.99);
    assert!((f.left - f.up.cross(f.front)).length() < 1e-12);
    // Given, up is kept.
    assert_eq!(
        frame(&plane, cues, &limbs, Given::with_up(DVec3::Y)).up,
        DVec3::Y
    );
    // Sprawled legs say little: +y stays.
    let sprawl = |x: f64, y: f64, s: f64| Reach {
        pivot: DVec3::new(x, y, 0.0),
        tip: DVec3::new(x + s, y, -0.3),
        end: 0.1,
        carried: None,
    };
    let limbs = [sprawl(0.5, 0.2, -1.0), sprawl(1.5, 0.2, 1.0)];
    assert_eq!(frame(&plane, cues, &limbs, Given::default()).up, DVec3::Y);
}

/// A leg hanging straight down from (x, 0.5, z) to the ground, its far half `end` thick.
fn hanging(x: f64, z: f64, end: f64) -> Reach {
    Reach {
        pivot: DVec3::new(x, 0.5, z),
        tip: DVec3::new(x, 0.0, z),
        end,
        carried: None,
    }
}

/// Two legs standing either side of the mirror plane x = 0, their tips (the heels)
/// a little behind (−z), and the cues that plane gives.
fn standing_legs() -> ([Reach; 2], Cues) {
    let leg = |x: f64| Reach {
        pivot: DVec3::new(x, 0.9, 0.0),
        tip: DVec3::new(x, 0.0, -0.05),
        end: 0.05,
        carried: None,
    };
    let cues = Cues {
        mirror: Some((DVec3::X, 0.0)),
        base: None,
        flat: [0.0; 6],
        bulk: None,
        detail: [0.0; 3],
    };
    ([leg(0.1), leg(-0.1)], cues)
}

/// A standing figure whose legs' tips (the heels, farthest from the hips) lie behind:
/// its soles, reaching forward of its shins, tell the front (+z); without soles ahead
/// of the shins the limbs' tips do (−z).
#[test]
fn soles_ahead_of_the_shins_tell_the_front_of_a_standing_figure() {
    let figure = |soles: bool| {
        let mut p = Vec::new();
        for i in 0..=170 {
            let y = i as f64 * 0.01;
            for x in [-0.1, 0.1] {
                p.push(DVec3::new(x, y, 0.0));
                if soles && y <= 0.05 {
                    for k in 1..=6 {
                        p.push(DVec3::new(x, y, 0.025 * k as f64));
                    }
                }
            }
        }
        p
    };
    let (limbs, cues) = standing_legs();
    let with = figure(true);
    assert!(toes(&with, DVec3::Y, DVec3::Z) > TOES * 1.7);
    assert_eq!(
        frame(&with, cues, &limbs, Given::with_up(DVec3::Y)).front,
        DVec3::Z
    );
    let without = figure(false);
    assert_eq!(toes(&without, DVec3::Y, DVec3::Z), 0.0);
    assert_eq!(
        frame(&without, cues, &limbs, Given::with_up(DVec3::Y)).front,
        DVec3::NEG_Z
    );
}

/// The front a file declares wins over the cues where it lies across up and the
/// mirror plane (the figure's limbs say −z; a glTF file says +z), and not where it lies
/// along the plane's normal (a model facing across its own mirror plane): there the
/// cues decide. Taken only with the file's own up.
#[test]
fn a_front_the_file_declares_is_taken_along_the_line_the_cues_allow() {
    let (limbs, cues) = standing_legs();
    let figure: Vec<DVec3> = (0..=170)
        .flat_map(|i| [-0.1, 0.1].map(|x| DVec3::new(x, i as f64 * 0.01, 0.0)))
        .collect();
    let found = frame(&figure, cues, &limbs, Given::with_up(DVec3::Y));
    assert_eq!(found.front, DVec3::NEG_Z);
    let gltf = Axes::given(Some(Axes::GLTF), None, None);
    assert_eq!(gltf.up, Some(DVec3::Y));
    let declared = frame(&figure, cues, &limbs, gltf);
    assert_eq!(declared.front, DVec3::Z);
    assert_eq!(declared.left, DVec3::X);
    let across = Given {
        front: Some(DVec3::X),
        ..gltf
    };
    assert_eq!(frame(&figure, cues, &limbs, across).front, DVec3::NEG_Z);
    // A rig's own up sets the file's front aside; the file's up again keeps it.
    let rig = Axes::given(Some(Axes::GLTF), Some(Up::PosZ), None);
    assert_eq!((rig.up, rig.front), (Some(DVec3::Z), None));
    assert_eq!(Axes::given(Some(Axes::GLTF), Some(Up::PosY), None), gltf);
    assert_eq!(Axes::given(None, None, None), Given::default());
    // A rig's front over the file's.
    let turned = Axes::given(Some(Axes::GLTF), None, Some(Up::NegZ));
    assert_eq!(frame(&figure, cues, &limbs, turned).front, DVec3::NEG_Z);
    assert_eq!(
        Axes::given(None, Some(Up::PosZ), Some(Up::PosX)).front,
        Some(DVec3::X)
    );
}

/// A four-legged figure with one part on its mirror plane, reaching back along -z: thin
/// (a rat's tail, a tenth of the legs' ends), it is a tail and the figure faces +z;
/// ending as thick as the legs (a head on a long neck), the figure faces where it leans.
#[test]
fn a_lone_thin_part_on_the_plane_is_a_tail_that_leans_back() {
    let positions: Vec<DVec3> = (0..=20)
        .flat_map(|i| {
            let z = -1.6 + 0.12 * i as f64;
            [DVec3::new(-0.4, 0.0, z), DVec3::new(0.4, 1.0, z)]
        })
        .collect();
    let leg = |x: f64, z: f64| hanging(x, z, 0.2);
    let part = |end: f64| Reach {
        pivot: DVec3::new(0.0, 0.6, -0.8),
        tip: DVec3::new(0.0, 0.7, -1.6),
        end,
        carried: None,
    };
    let cues = Cues {
        mirror: Some((DVec3::X, 0.0)),
        base: None,
        flat: [0.0; 6],
        bulk: None,
        detail: [0.0; 3],
    };
    let legs = [
        leg(0.3, 0.5),
        leg(-0.3, 0.5),
        leg(0.3, -0.5),
        leg(-0.3, -0.5),
    ];
    let with = |end: f64| {
        let limbs: Vec<Reach> = legs.iter().copied().chain([part(end)]).collect();
        frame(&positions, cues, &limbs, Given::with_up(DVec3::Y)).front
    };
    assert_eq!(with(0.02), DVec3::Z);
    assert_eq!(with(TAIL_END * 0.2 * 1.1), DVec3::NEG_Z);
    assert_eq!(with(0.2), DVec3::NEG_Z);
}

/// Of two parts on the mirror plane about as thick and leaning up alike, the one carrying
/// parts that point up (ears) is the head; carrying parts that hang (a dog's hind legs
/// on its hindquarters), it is not: the other, carrying nothing, is.
#[test]
fn a_part_carrying_legs_is_no_head_and_one_carrying_ears_is() {
    let part = |z: f64, end: f64, carried: Option<DVec3>| Reach {
        pivot: DVec3::new(0.0, 1.0, z),
        tip: DVec3::new(0.0, 1.8, 2.0 * z),
        end,
        carried,
    };
    let with = |carried| {
        let (a, b) = (part(0.5, 0.3, None), part(-0.5, 0.29, carried));
        head_of(&[&a, &b], 0.0, DVec3::Y)
    };
    assert_eq!(with(Some(DVec3::NEG_Y)), Some(0));
    assert_eq!(with(Some(DVec3::new(0.7, 0.7, 0.0))), Some(1));
}

/// A face is modelled finer than a rump: [`detail`] reads how much finer one half of
/// a mesh is made along each axis. Where legs hang from a long body, the finer end is
/// its front, before the head's place (a tail thicker than the head, taken for one);
/// an upright figure's finer back is not.
#[test]
fn a_long_bodys_finer_end_is_its_front_and_an_upright_ones_is_not() {
    let ball = crate::mesh::shapes::icosphere(1.0, 3);
    assert!(
        detail(&ball).iter().all(|d| d.abs() < 0.2),
        "{:?}",
        detail(&ball)
    );
    // Each triangle of the +z half split in four at its edges' midpoints.
    let mut fine = ball.clone();
    fine.triangles.clear();
    for t in &ball.triangles {
        let p = t.map(|v| ball.positions[v as usize]);
        if (p[0] + p[1] + p[2]).z <= 0.0 {
            fine.triangles.push(*t);
            continue;
        }
        let mut mid = |a: usize, b: usize| {
            fine.positions.push((p[a] + p[b]) * 0.5);
            (fine.positions.len() - 1) as u32
        };
        let (ab, bc, ca) = (mid(0, 1), mid(1, 2), mid(2, 0));
        let [a, b, c] = *t;
        fine.triangles
            .extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    let d = detail(&fine);
    assert!((d[2] - 4f64.ln()).abs() < 0.3 && d[0].abs() < 0.2, "{d:?}");
    // Four legs hanging from a body twice as long (z) as it is tall (y), a thick part
    // on the plane at its back (-z) that reads as a head.
    let body = |length: f64| -> Vec<DVec3> {
        (0..=20)
            .flat_map(|i| {
                let z = length * (i as f64 / 20.0 - 0.5);
                [DVec3::new(0.0, 0.0, z), DVec3::new(0.0, 1.0, z)]
            })
            .collect()
    };
    let leg = |x: f64, z: f64| hanging(x, z, 0.05);
    let tail = |length: f64| Reach {
        pivot: DVec3::new(0.0, 0.6, -0.4 * length),
        tip: DVec3::new(0.0, 0.7, -0.5 * length),
        end: 0.3,
        carried: None,
    };
    let cues = |finer: f64| Cues {
        mirror: Some((DVec3::X, 0.0)),
        base: None,
        flat: [0.0; 6],
        bulk: None,
        detail: [0.0, 0.0, finer],
    };
    let front = |length: f64, finer: f64| {
        let limbs = [
            leg(0.2, 0.3 * length),
            leg(-0.2, 0.3 * length),
            leg(0.2, -0.3 * length),
            leg(-0.2, -0.3 * length),
            tail(length),
        ];
        let given = Given::with_up(DVec3::Y);
        frame(&body(length), cues(finer), &limbs, given).front
    };
    assert_eq!(
        front(2.0, 0.0),
        DVec3::NEG_Z,
        "the thick part reads as a head"
    );
    assert_eq!(front(2.0, DETAIL.ln() * 1.1), DVec3::Z);
    assert_eq!(front(2.0, -DETAIL.ln() * 1.1), DVec3::NEG_Z);
    assert_eq!(
        front(2.0, DETAIL.ln() * 0.9),
        DVec3::NEG_Z,
        "not finer enough"
    );
    // Standing as deep as a person (0.3 of its height): its finer end says nothing,
    // either way.
    let upright = front(0.3, 0.0);
    assert_eq!(front(0.3, DETAIL.ln() * 2.0), upright);
    assert_eq!(front(0.3, -DETAIL.ln() * 2.0), upright);
}

/// Three feet on the ground one way, standing apart, make it down whatever the other
/// limbs say: a bull whose hindquarters are cut as limbs, thick, one reaching back and
/// up, stands on its front legs and a hind hoof (the limbs' thickness-weighted reach
/// says −z). Its hind hoof raised, it is no stance. (Feet side by side are none either:
/// `tests/suggest.rs`, a creature with its ears up and an arm raised high.)
#[test]
fn three_feet_apart_on_the_ground_say_down() {
    let body = box_corners(4.5, 3.0);
    let limb = |pivot: DVec3, tip: DVec3, end: f64| Reach {
        pivot,
        tip,
        end,
        carried: None,
    };
    let frame_of = |front_feet: [DVec3; 2], hind_hoof: DVec3| {
        let hip = |x: f64| DVec3::new(x, 2.0, -1.9);
        let limbs = [
            limb(DVec3::new(0.8, 2.1, 1.9), front_feet[0], 0.19),
            limb(DVec3::new(-0.8, 2.1, 1.9), front_feet[1], 0.19),
            limb(hip(0.5), DVec3::new(0.5, 4.3, -2.9), 0.86),
            limb(hip(-0.6), hind_hoof, 0.84),
        ];
        let cues = Cues {
            mirror: Some((DVec3::X, 0.0)),
            base: None,
            flat: [0.0; 6],
            bulk: None,
            detail: [0.0; 3],
        };
        frame(&body, cues, &limbs, Given::default()).up
    };
    let apart = [DVec3::new(0.8, 0.0, 2.3), DVec3::new(-0.8, 0.0, 2.3)];
    assert_eq!(frame_of(apart, DVec3::new(-0.6, 0.0, -2.9)), DVec3::Y);
    assert_ne!(frame_of(apart, DVec3::new(-0.6, 0.5, -2.9)), DVec3::Y);
}

/// Two ears hanging up from a root that is all head say "down is +y"; soles at the −y end
/// (and none on top) turn that round. Flat at both ends, or too little flat to be soles
/// ([`SOLES`]), the limbs keep their say.
#[test]
fn soles_at_the_end_the_ears_put_on_top_make_it_down() {
    let body = box_corners(4.0, 1.0);
    let ear = |x: f64| Reach {
        pivot: DVec3::new(x, 3.4, 0.0),
        tip: DVec3::new(x, 4.0, 0.0),
        end: 0.2,
        carried: None,
    };
    let up_with = |bottom: f64, top: f64| {
        let mut flat = [0.0; 6];
        flat[2] = top;
        flat[3] = bottom;
        let cues = Cues {
            mirror: Some((DVec3::X, 0.0)),
            base: None,
            flat,
            bulk: None,
            detail: [0.0; 3],
        };
        frame(&body, cues, &[ear(0.6), ear(-0.6)], Given::default()).up
    };
    assert_eq!(up_with(0.0, 0.0), DVec3::NEG_Y);
    assert_eq!(up_with(0.004, 0.0), DVec3::NEG_Y);
    // Soles at the bottom (y = 0), the ears' end round.
    assert_eq!(up_with(0.006, 0.0), DVec3::Y);
    assert_eq!(up_with(0.006, 0.0015), DVec3::Y);
    // Flat at both ends alike: no soles.
    assert_eq!(up_with(0.006, 0.004), DVec3::NEG_Y);
    // With no limb to read, soles at one end along the plane say down whatever axis
    // that is; none, the convention (+y).
    let up_of = |k: usize| {
        let mut flat = [0.0; 6];
        flat[k] = 0.01;
        let cues = Cues {
            mirror: Some((DVec3::X, 0.0)),
            flat,
            ..Cues::default()
        };
        frame(&body, cues, &[], Given::default()).up
    };
    assert_eq!(up_of(5), DVec3::Z);
    assert_eq!(up_of(4), DVec3::NEG_Z);
    assert_eq!(up_of(2), DVec3::NEG_Y);
    // Across the plane (x) it says nothing.
    assert_eq!(up_of(1), DVec3::Y);
    // With no plane at all, soles at one end only say down; at two, nothing does.
    let no_plane = |flat: [f64; 6]| {
        let cues = Cues {
            flat,
            ..Cues::default()
        };
        frame(&body, cues, &[], Given::default()).up
    };
    assert_eq!(soles(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.01]), Some(DVec3::NEG_Z));
    assert_eq!(no_plane([0.0, 0.0, 0.0, 0.0, 0.0, 0.01]), DVec3::Z);
    assert_eq!(soles(&[0.01, 0.0, 0.0, 0.0, 0.0, 0.01]), None);
    assert_eq!(no_plane([0.01, 0.0, 0.0, 0.0, 0.0, 0.01]), DVec3::Y);
}

/// A long body with nothing hanging from it (a fish) faces the end its bulk lies toward:
/// thickest near the head, tapering to the tail, whichever end that is.
#[test]
fn a_body_with_nothing_hanging_faces_where_its_bulk_lies() {
    // A ball stretched along z to six times its height, tapering to half its width at
    // one end.
    let fish = |thick_end: f64| {
        let mut m = crate::mesh::shapes::icosphere(1.0, 3);
        for p in &mut m.positions {
            let s = 0.75 + 0.25 * p.z * thick_end;
            *p = DVec3::new(p.x * s, p.y * s, 3.0 * p.z);
        }
        m
    };
    for thick_end in [1.0, -1.0] {
        let m = fish(thick_end);
        let centre = bulk(&m).unwrap();
        assert!(centre.z * thick_end > 0.2, "{centre}");
        let cues = Cues {
            mirror: Some((DVec3::X, 0.0)),
            bulk: Some(centre),
            ..Cues::default()
        };
        let f = frame(&m.positions, cues, &[], Given::default());
        assert_eq!(f.up, DVec3::Y);
        assert_eq!(f.front, DVec3::Z * thick_end);
    }
    // Nothing enclosed (a sheet seen from both sides), no bulk.
    let sheet = crate::mesh::Mesh {
        positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
        triangles: vec![[0, 1, 2], [0, 2, 1]],
    };
    assert_eq!(bulk(&sheet), None);
}

/// The corners of a box from x = −1 to 1, y = 0 to `height`, z = −`half_depth` to
/// `half_depth`: a body's extent, for the rules that read only that.
fn box_corners(height: f64, half_depth: f64) -> Vec<DVec3> {
    let mut corners = Vec::new();
    for x in [-1.0, 1.0] {
        for y in [0.0, height] {
            for z in [-half_depth, half_depth] {
                corners.push(DVec3::new(x, y, z));
            }
        }
    }
    corners
}
