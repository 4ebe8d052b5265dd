//! A character made of many pieces is one puppet: the suggestion sees the pieces where
//! they meet (`mesh::contacts`) and cuts the limbs they make; every piece turns with its
//! limb.

use glam::DVec3;
use puppet::mesh::{shapes, Mesh};
use puppet::{Puppet, RigFile};

/// `piece` moved by `at`, its axis (y) turned to `axis`, added to `mesh` as a part of its own.
fn add(mesh: &mut Mesh, piece: &Mesh, axis: DVec3, at: DVec3) {
    let turn = glam::DQuat::from_rotation_arc(DVec3::Y, axis.normalize());
    let off = mesh.positions.len() as u32;
    mesh.positions
        .extend(piece.positions.iter().map(|&p| turn * p + at));
    mesh.triangles
        .extend(piece.triangles.iter().map(|t| t.map(|v| v + off)));
}

/// A mannequin in nine pieces, each pushed a little into the one it hangs from: a torso,
/// a head, upper and lower arms held out sideways, and two legs.
fn mannequin() -> Mesh {
    let mut m = Mesh::default();
    let torso = shapes::capsule(0.35, 0.45, 8, 8, 24);
    let head = shapes::uv_sphere(0.25, 12, 24);
    let limb = shapes::capsule(0.1, 0.3, 6, 6, 16);
    let leg = shapes::capsule(0.13, 0.55, 6, 10, 16);
    add(&mut m, &torso, DVec3::Y, DVec3::ZERO);
    add(&mut m, &head, DVec3::Y, DVec3::new(0.0, 1.0, 0.0));
    for side in [-1.0, 1.0] {
        add(&mut m, &limb, DVec3::X, DVec3::new(side * 0.65, 0.5, 0.0));
        add(&mut m, &limb, DVec3::X, DVec3::new(side * 1.3, 0.5, 0.0));
        add(&mut m, &leg, DVec3::Y, DVec3::new(side * 0.18, -1.2, 0.0));
    }
    m
}

#[test]
fn a_mannequin_in_pieces_gets_its_arms_legs_and_head() {
    let mesh = mannequin();
    let parts = puppet::mesh::Parts::of(&mesh);
    assert_eq!(parts.len(), 8, "{:?}", parts.area);
    assert_eq!(parts.riders(), 0);
    assert!(!puppet::mesh::contacts(&mesh).is_empty());
    let mut p =
        Puppet::build(mesh, RigFile::default(), puppet::progress::silent()).expect("a puppet");
    p.suggest_joints().expect("joints");
    let names: Vec<&str> = p.joints.cuts().iter().map(|c| c.name.as_str()).collect();
    for want in ["arm.L", "arm.R", "leg.L", "leg.R"] {
        assert!(names.contains(&want), "{want} in {names:?}");
    }
    assert!(
        names.iter().any(|n| *n == "neck" || *n == "head"),
        "a neck or a head in {names:?}"
    );
}
