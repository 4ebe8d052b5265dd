use super::*;

/// Skeletal points on the y axis from 0 to 3 (an arm: shoulder at 1, elbow at 2).
fn line() -> Vec<DVec3> {
    (0..=30)
        .map(|k| DVec3::new(0.0, k as f64 * 0.1, 0.0))
        .collect()
}

fn cut(name: &str, section: &str, y: f64) -> Cut {
    Cut {
        name: name.into(),
        section: section.into(),
        point: DVec3::new(0.0, y, 0.0),
        normal: DVec3::Y,
        pivot: None,
        connected: false,
        band: None,
    }
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn a_cut_moves_the_positive_side_to_a_new_section() {
    let mut j = Joints::new(&line(), ROOT);
    let arm = j.add_cut(cut("arm", ROOT, 1.05)).unwrap();
    assert_eq!(arm, 1);
    for (i, &s) in j.section_of().iter().enumerate() {
        assert_eq!(s as usize, usize::from(i > 10), "vertex {i}");
    }
    assert_eq!(j.sections()[0].vertices, 11);
    assert_eq!(j.sections()[1].vertices, 20);
    // Default pivot: centroid of the nearest skeletal points, projected onto the plane.
    assert!(close(j.sections()[1].pivot, DVec3::new(0.0, 1.05, 0.0)));
}

#[test]
fn bad_cuts_are_refused_and_change_nothing() {
    let mut j = Joints::new(&line(), ROOT);
    let before = j.clone();
    let mut c = cut("a", ROOT, 1.0);
    c.normal = DVec3::ZERO;
    assert_eq!(j.add_cut(c), Err(JointError::ZeroNormal("a".into())));
    let mut c = cut("a", ROOT, 1.0);
    c.point.x = f64::NAN;
    assert!(matches!(j.add_cut(c), Err(JointError::NotFinite { .. })));
    assert!(matches!(
        j.add_cut(cut("a", ROOT, 5.0)),
        Err(JointError::EmptySide { .. })
    ));
    assert!(matches!(
        j.add_cut(cut("a", "nope", 1.0)),
        Err(JointError::UnknownSection { .. })
    ));
    assert!(matches!(
        j.add_cut(cut("", ROOT, 1.0)),
        Err(JointError::EmptyName(_))
    ));
    assert_eq!(j, before);
    j.add_cut(cut("a", ROOT, 1.0)).unwrap();
    assert_eq!(
        j.add_cut(cut("a", ROOT, 2.0)),
        Err(JointError::DuplicateName("a".into()))
    );
}

#[test]
fn rotations_compose_down_the_tree() {
    // arm (pivot y=1) -> forearm (pivot y=2) -> hand (pivot y=2.5).
    let mut j = Joints::new(&line(), ROOT);
    let arm = j.add_cut(cut("arm", ROOT, 1.0)).unwrap();
    let fore = j.add_cut(cut("forearm", "arm", 2.0)).unwrap();
    let hand = j.add_cut(cut("hand", "forearm", 2.5)).unwrap();
    assert_eq!(j.sections()[hand].parent, Some(fore));
    let mut local = vec![Local::default(); 4];
    local[arm] = Local::axis_angle(DVec3::Z, 90.0);
    let w = j.world(&local);
    // The arm's rotation carries forearm and hand: the fingertip (y=3) swings to x=-2.
    let tip = DVec3::new(0.0, 3.0, 0.0);
    for s in [arm, fore, hand] {
        assert!(close(
            w[s].transform_point3(tip),
            DVec3::new(-2.0, 1.0, 0.0)
        ));
    }
    assert!(close(w[0].transform_point3(tip), tip));
    // The forearm's own rotation is about the elbow as carried by the arm.
    local[fore] = Local::axis_angle(DVec3::Z, 90.0);
    let w = j.world(&local);
    assert!(close(
        w[hand].transform_point3(tip),
        DVec3::new(-1.0, 0.0, 0.0)
    ));
    assert!(close(
        w[arm].transform_point3(tip),
        DVec3::new(-2.0, 1.0, 0.0)
    ));
    // Several sections at once: the hand turns back, about the carried wrist (-1, 0.5).
    local[hand] = Local::axis_angle(DVec3::Z, -90.0);
    let w = j.world(&local);
    assert!(close(
        w[hand].transform_point3(tip),
        DVec3::new(-1.5, 0.5, 0.0)
    ));
}

#[test]
fn a_later_cut_adopts_the_children_on_its_side() {
    // Elbow first, then shoulder: the forearm becomes a child of the upper arm.
    let mut j = Joints::new(&line(), ROOT);
    let fore = j.add_cut(cut("forearm", ROOT, 2.0)).unwrap();
    let arm = j.add_cut(cut("arm", ROOT, 1.0)).unwrap();
    assert_eq!(j.sections()[fore].parent, Some(arm));
    assert_eq!(j.sections()[arm].parent, Some(0));
    assert_eq!(j.order[0], 0);
    let pos = |s: usize| j.order.iter().position(|&x| x == s).unwrap();
    assert!(pos(arm) < pos(fore));
}

#[test]
fn removing_a_cut_collapses_the_tree() {
    let mut j = Joints::new(&line(), ROOT);
    j.add_cut(cut("arm", ROOT, 1.0)).unwrap();
    j.add_cut(cut("forearm", "arm", 2.0)).unwrap();
    j.remove_cut("arm").unwrap();
    // Same as cutting only the forearm from the root.
    let mut only = Joints::new(&line(), ROOT);
    only.add_cut(cut("forearm", ROOT, 2.0)).unwrap();
    assert_eq!(j, only);
    j.remove_cut("forearm").unwrap();
    assert_eq!(j, Joints::new(&line(), ROOT));
    assert_eq!(
        j.remove_cut("forearm"),
        Err(JointError::NoSuchCut("forearm".into()))
    );
}

#[test]
fn the_pose_in_single_precision_matches() {
    let mut j = Joints::new(&line(), ROOT);
    let arm = j.add_cut(cut("arm", ROOT, 1.0)).unwrap();
    let mut local = vec![Local::default(); 2];
    local[arm] = Local::axis_angle(DVec3::X, 40.0);
    let pose = j.pose(&local);
    let w = j.world(&local);
    let p = DVec3::new(0.0, 2.5, 0.3);
    let a = pose.transforms[arm]
        .transform_point3(p.as_vec3())
        .as_dvec3();
    assert!((a - w[arm].transform_point3(p)).length() < 1e-6);
}
