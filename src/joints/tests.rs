use super::*;

/// Skeletal points on the y axis from 0 to 3 (an arm: shoulder at 1, elbow at 2).
fn line() -> Vec<DVec3> {
    (0..=30)
        .map(|k| DVec3::new(0.0, k as f64 * 0.1, 0.0))
        .collect()
}

fn cut(name: &str, section: &str, y: f64) -> Cut {
    Cut::plane(name, section, DVec3::new(0.0, y, 0.0), DVec3::Y)
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

/// A chain root → arm → forearm: each hangs from those above it, not from itself nor
/// from those below, and moves with them.
#[test]
fn a_section_hangs_from_every_section_above_it() {
    let mut j = Joints::new(&line(), ROOT);
    let arm = j.add_cut(cut("arm", ROOT, 1.05)).unwrap();
    let forearm = j.add_cut(cut("forearm", "arm", 2.05)).unwrap();
    assert!(j.hangs_from(forearm, arm) && j.hangs_from(forearm, 0) && j.hangs_from(arm, 0));
    assert!(!j.hangs_from(arm, forearm) && !j.hangs_from(arm, arm) && !j.hangs_from(0, arm));
    assert_eq!(j.moves_with(arm), vec![false, true, true]);
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

/// A pose asked for again of the same joints is the one made last; the joints changed
/// (a pivot moved, a cut added, a band set), or another pose, or another clone changed
/// apart, it is made again: each reads what `pose` makes from scratch.
#[test]
fn a_pose_is_made_again_when_the_joints_or_the_pose_change() {
    let mut j = Joints::new(&line(), ROOT);
    let arm = j.add_cut(cut("arm", ROOT, 1.0)).unwrap();
    let mut local = vec![Local::default(); 2];
    local[arm] = Local::axis_angle(DVec3::X, 40.0);
    let mut scratch = PoseScratch::default();
    let first = j.pose_into(&local, &mut scratch).clone();
    assert_eq!(first, j.pose(&local));
    assert_eq!(*j.pose_into(&local, &mut scratch), first, "asked again");
    j.set_pivot(arm, DVec3::new(0.0, 1.2, 0.5));
    let moved = j.pose_into(&local, &mut scratch).clone();
    assert_ne!(moved, first, "a moved pivot turns the arm about it");
    assert_eq!(moved, j.pose(&local));
    local[arm] = Local::axis_angle(DVec3::X, 20.0);
    assert_eq!(*j.pose_into(&local, &mut scratch), j.pose(&local));
    let mut other = j.clone();
    other.set_pivot(arm, DVec3::new(0.0, 0.8, -0.5));
    assert_eq!(*other.pose_into(&local, &mut scratch), other.pose(&local));
    j.set_pivot(arm, DVec3::new(0.0, 1.2, 0.9));
    assert_eq!(
        *j.pose_into(&local, &mut scratch),
        j.pose(&local),
        "clones apart"
    );
    let hand = j.add_cut(cut("hand", "arm", 2.0)).unwrap();
    local.resize(3, Local::default());
    local[hand] = Local::axis_angle(DVec3::Z, 30.0);
    assert_eq!(*j.pose_into(&local, &mut scratch), j.pose(&local));
    assert!(j.set_band("hand", Some(0.2)));
    assert_eq!(
        *j.pose_into(&local, &mut scratch),
        j.pose(&local),
        "a band set"
    );
}

/// A 9×9×9 grid of skeletal points in [−1, 1]³, with the edges between grid neighbours.
fn cube() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let at = |k: usize| -1.0 + k as f64 * 0.25;
    let index = |x: usize, y: usize, z: usize| (x * 81 + y * 9 + z) as u32;
    let mut points = Vec::new();
    for x in 0..9 {
        for y in 0..9 {
            for z in 0..9 {
                points.push(DVec3::new(at(x), at(y), at(z)));
            }
        }
    }
    // Degenerate triangles carry the grid's edges (connected cuts only need the edges).
    let mut triangles = Vec::new();
    for x in 0..9 {
        for y in 0..9 {
            for z in 0..9 {
                let i = index(x, y, z);
                for (dx, dy, dz) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                    if x + dx < 9 && y + dy < 9 && z + dz < 9 {
                        triangles.push([i, index(x + dx, y + dy, z + dz), i]);
                    }
                }
            }
        }
    }
    (points, triangles)
}

#[test]
fn spheres_and_boxes_take_what_is_inside() {
    let (points, triangles) = cube();
    let mut j = Joints::with_mesh(&points, &triangles, &[], ROOT);
    let centre = DVec3::new(0.5, 0.5, 0.5);
    let ball = j
        .add_cut(Cut {
            shape: Shape::Sphere { radius: 0.3 },
            point: centre,
            connected: true,
            ..cut("ball", ROOT, 0.0)
        })
        .unwrap();
    for (i, p) in points.iter().enumerate() {
        let inside = p.distance(centre) < 0.3;
        assert_eq!(j.section_of()[i] as usize == ball, inside, "{p}");
    }
    // The seam's centroid: the ball is whole inside the cube, so its seam is all of it.
    assert!(close(j.sections()[ball].pivot, centre));
    // A box with normal +z is axis-aligned; turned about z by its normal it is not.
    let b = j
        .add_cut(Cut {
            shape: Shape::Box {
                size: DVec3::new(0.6, 1.1, 0.6),
            },
            point: DVec3::new(-0.5, -0.5, -0.5),
            normal: DVec3::Z,
            ..cut("box", ROOT, 0.0)
        })
        .unwrap();
    let inside = |p: DVec3| {
        let v = (p - DVec3::new(-0.5, -0.5, -0.5)).abs();
        v.x < 0.3 && v.y < 0.55 && v.z < 0.3
    };
    for (i, &p) in points.iter().enumerate() {
        assert_eq!(j.section_of()[i] as usize == b, inside(p), "{p}");
    }
    assert_eq!(j.sections()[b].vertices, 3 * 5 * 3);
    // Bad sizes are refused and change nothing.
    let before = j.clone();
    for shape in [
        Shape::Sphere { radius: 0.0 },
        Shape::Sphere { radius: f64::NAN },
        Shape::Box {
            size: DVec3::new(1.0, -1.0, 1.0),
        },
    ] {
        let refused = j.add_cut(Cut {
            shape,
            ..cut("bad", ROOT, 0.0)
        });
        assert!(matches!(refused, Err(JointError::BadSize(..))), "{shape:?}");
    }
    assert_eq!(j, before);
}

#[test]
fn a_shared_pivot_turns_both_sides_about_one_hinge() {
    // A mouth: the lower jaw below y = 1.5 is cut from the head, hinged at (0, 1.5, 0).
    let mut j = Joints::new(&line(), ROOT);
    let mut jaw = cut("jaw", ROOT, 1.5);
    jaw.normal = -DVec3::Y;
    let k = j.add_cut(jaw).unwrap();
    let hinge = j.cuts()[0].pivot.unwrap();
    let centroid = j.root_pivot();
    assert!(close(j.sections()[0].pivot, centroid));
    assert!(j.set_shared_pivot("jaw", true));
    assert!(close(j.sections()[0].pivot, hinge));
    // Head up 20°, jaw down 20° relative: the hinge stays where it is for both.
    let mut local = vec![Local::default(); 2];
    local[0] = Local::axis_angle(DVec3::Z, 20.0);
    local[k] = Local::axis_angle(DVec3::Z, -40.0);
    let world = j.world(&local);
    assert!(close(world[0].transform_point3(hinge), hinge));
    assert!(close(world[k].transform_point3(hinge), hinge));
    // Moving the pivot moves the point both turn about; the root's own pivot stays.
    let moved = hinge + DVec3::new(0.3, 0.0, 0.0);
    j.set_pivot(k, moved);
    assert!(close(j.sections()[0].pivot, moved));
    assert!(close(j.sections()[k].pivot, moved));
    assert!(close(j.root_pivot(), centroid));
    // A section turns about one point: a second sharing cut is refused, and sharing
    // another cut's pivot stops the first.
    let mut nose = cut("nose", ROOT, 2.5);
    nose.shared_pivot = true;
    assert!(matches!(
        j.add_cut(nose.clone()),
        Err(JointError::SharedPivot { .. })
    ));
    nose.shared_pivot = false;
    let n = j.add_cut(nose).unwrap();
    assert!(j.set_shared_pivot("nose", true));
    assert!(!j.cuts()[0].shared_pivot);
    assert!(close(j.sections()[0].pivot, j.sections()[n].pivot));
    assert!(j.set_shared_pivot("nose", false));
    assert!(close(j.sections()[0].pivot, centroid));
    assert!(!j.set_shared_pivot("root", true));
}

#[test]
fn removing_a_cut_keeps_one_shared_pivot_per_section() {
    // root -> arm -> hand (shared with the arm), root -> leg (shared with the root).
    // Removing the arm makes the hand a cut of the root too: the first keeps its shared
    // pivot.
    let mut j = Joints::new(&line(), ROOT);
    j.add_cut(cut("arm", ROOT, 1.0)).unwrap();
    j.add_cut(cut("hand", "arm", 2.5)).unwrap();
    let mut leg = cut("leg", ROOT, 0.5);
    leg.normal = -DVec3::Y;
    j.add_cut(leg).unwrap();
    assert!(j.set_shared_pivot("hand", true));
    assert!(j.set_shared_pivot("leg", true));
    j.remove_cut("arm").unwrap();
    let shared: Vec<&str> = j
        .cuts()
        .iter()
        .filter(|c| c.shared_pivot)
        .map(|c| c.name.as_str())
        .collect();
    assert_eq!(shared, ["hand"]);
    assert_eq!(j.sections()[0].pivot, j.cuts()[0].pivot.unwrap());
}

/// A band along +y, `±4` about the origin, bent as an arc.
fn arc_band() -> Band {
    Band {
        child: 1,
        parent: 0,
        width: 4.0,
        child_width: 4.0,
        radius: 1.0,
        pivot: DVec3::ZERO,
        normal: DVec3::Y,
        first_level: 2,
        arc: true,
        ..Band::default()
    }
}

#[test]
fn an_arc_band_bends_its_centre_line_without_shortening_it() {
    use glam::{DAffine3, DQuat};
    let band = arc_band();
    // At rest and twisted about its own axis nothing moves but the twist.
    assert!(close(
        band.shift(DQuat::IDENTITY, Slide::default()),
        DVec3::ZERO
    ));
    assert!(close(
        band.shift(DQuat::from_rotation_y(1.0), Slide::default()),
        DVec3::ZERO
    ));
    let rest = DAffine3::IDENTITY;
    for k in 0..=8 {
        let m = band.motion(DQuat::IDENTITY, &rest, k as f64 / 8.0);
        assert!(m.abs_diff_eq(DAffine3::IDENTITY, 1e-12), "{m:?}");
    }
    // Bent 90° about z: the child turns about the pivot and moves by the shift.
    let turn = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    let child =
        DAffine3::from_translation(band.shift(turn, Slide::default())) * DAffine3::from_quat(turn);
    let steps = 256;
    let centre = |k: usize| {
        let w = k as f64 / steps as f64;
        band.motion(turn, &child, w)
            .transform_point3(DVec3::new(0.0, -4.0 + 8.0 * w, 0.0))
    };
    let mut length = 0.0;
    for k in 1..=steps {
        let w = (k as f64 - 0.5) / steps as f64;
        let step = centre(k) - centre(k - 1);
        length += step.length();
        // Each level stays square to the centre line.
        let tangent = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2 * w) * DVec3::Y;
        assert!(step.normalize().dot(tangent) > 1.0 - 1e-6, "{k}");
    }
    // (Chords of 256 steps fall short of the arc by about 1e-5.)
    assert!((length - 8.0).abs() < 1e-4, "{length}");
    // A quarter circle of radius 8 / (π/2) from (0, −4) turning towards −x.
    let r = 8.0 / std::f64::consts::FRAC_PI_2;
    assert!(close(centre(steps), DVec3::new(-r, -4.0 + r, 0.0)));
    // The band's child end is where the child's own motion takes it.
    let end = band.motion(turn, &child, 1.0);
    assert!(end.abs_diff_eq(child, 1e-12), "{end:?} against {child:?}");
}

/// A sheet of `w × rows` vertices (row `r`, column `c` at index `r w + c`), each with its
/// skeletal point and position from `at`, triangulated between neighbouring rows (and the
/// last row to the first when `closed`); the joints have its surface.
fn sheet(
    w: usize,
    rows: usize,
    closed: bool,
    at: impl Fn(usize, usize) -> (DVec3, DVec3),
) -> Joints {
    let index = |r: usize, c: usize| ((r % rows) * w + c) as u32;
    let (mut points, mut positions) = (Vec::new(), Vec::new());
    for r in 0..rows {
        for c in 0..w {
            let (p, x) = at(r, c);
            points.push(p);
            positions.push(x);
        }
    }
    let mut triangles = Vec::new();
    for r in 0..if closed { rows } else { rows - 1 } {
        for c in 0..w - 1 {
            triangles.push([index(r, c), index(r, c + 1), index(r + 1, c + 1)]);
            triangles.push([index(r, c), index(r + 1, c + 1), index(r + 1, c)]);
        }
    }
    let mut j = Joints::with_mesh(&points, &triangles, &[], ROOT);
    j.set_surface(&positions, &vec![0.05; positions.len()]);
    j
}

/// A flat strip of `w × 31` vertices 0.1 apart (row `r`, column `c` at `(0.1 c, 0.1 r)`,
/// index `31 … w`), each vertex's skeletal point on the y axis at its own height unless
/// `point` says otherwise; the joints have its surface.
fn strip(w: usize, point: impl Fn(usize, usize) -> f64) -> Joints {
    sheet(w, 31, false, |r, c| {
        (
            DVec3::new(0.0, point(r, c), 0.0),
            DVec3::new(0.1 * c as f64, 0.1 * r as f64, 0.0),
        )
    })
}

#[test]
fn a_patch_of_the_parent_inside_a_child_turns_with_the_child() {
    // Rows 20–21 of columns 1–2 have skeletal points down at the body's (y = 0.5): by
    // its skeletal points, an island of the root inside the arm.
    let island = |r: usize, c: usize| (20..=21).contains(&r) && (1..=2).contains(&c);
    let point = |r: usize, c: usize| if island(r, c) { 0.5 } else { 0.1 * r as f64 };
    let mut j = strip(5, point);
    let arm = j.add_cut(cut("arm", ROOT, 1.05)).unwrap();
    for r in 0..31 {
        for c in 0..5 {
            let want = usize::from(r > 10);
            assert_eq!(
                usize::from(j.section_of()[r * 5 + c]),
                want,
                "row {r} column {c}"
            );
        }
    }
    assert_eq!(j.sections()[arm].vertices, 20 * 5);
    // Turning the arm carries the patch: no edge of it stays behind.
    let mut local = vec![Local::default(); 2];
    local[arm] = Local::axis_angle(DVec3::Z, 60.0);
    let pose = j.pose(&local);
    let moved = |i: usize| {
        let t = pose.transforms[usize::from(j.transform_of()[i])];
        t.transform_point3(DVec3::new(0.1 * (i % 5) as f64, 0.1 * (i / 5) as f64, 0.0).as_vec3())
    };
    assert!(moved(20 * 5 + 1).distance(moved(20 * 5)) < 0.11);
    // Joints without a surface (the suggestion's) keep the skeleton's sections.
    let mut bare = Joints::with_mesh(
        &(0..31 * 5)
            .map(|i| DVec3::new(0.0, point(i / 5, i % 5), 0.0))
            .collect::<Vec<_>>(),
        &[],
        &[],
        ROOT,
    );
    bare.add_cut(cut("arm", ROOT, 1.05)).unwrap();
    assert_eq!(bare.section_of()[20 * 5 + 1], 0);
}

#[test]
fn two_pieces_that_each_hang_from_the_parent_stay_one_section() {
    // Column 2 above row 20 has skeletal points at the bottom: one plane at y = 2.05
    // takes two legs, columns 0–1 and 3–4, each on the root.
    let mut j = strip(5, |r, c| {
        if c == 2 && r > 20 {
            0.0
        } else {
            0.1 * r as f64
        }
    });
    let legs = j.add_cut(cut("legs", ROOT, 2.05)).unwrap();
    for r in 21..31 {
        for c in 0..5 {
            assert_eq!(
                usize::from(j.section_of()[r * 5 + c]),
                if c == 2 { 0 } else { legs },
                "row {r} column {c}"
            );
        }
    }
}

/// A ring of 5 × 61 vertices (the strip's last row joined to its first), cut at y = 1.05:
/// with `arch`, rows 11–49 have skeletal points above the cut and the rest below, so the
/// cut takes an arch joined to the root at both ends (a body standing on a pedestal by
/// two legs); without, a strip whose top hangs from the cut alone.
fn arch_or_strip(arch: bool) -> Joints {
    let mut j = sheet(5, 61, arch, |r, c| {
        let y = if arch && r >= 50 { 0.0 } else { 0.1 * r as f64 };
        (
            DVec3::new(0.0, y, 0.0),
            DVec3::new(0.1 * c as f64, 0.1 * r as f64, 0.0),
        )
    });
    j.add_cut(cut("arm", ROOT, 1.05)).unwrap();
    assert_eq!(j.sections()[1].vertices, if arch { 195 } else { 250 });
    j
}

#[test]
fn a_section_joined_to_its_parent_in_two_places_loses_its_cut() {
    // Turned about one end, the arch tears at the other.
    let mut j = arch_or_strip(true);
    let removed = super::suggest::seams::keep_whole(&mut j);
    assert_eq!(removed, vec!["arm".to_string()]);
    assert_eq!(j.sections().len(), 1);
    // The same cut on a strip whose top hangs from it alone keeps it.
    let mut j = arch_or_strip(false);
    assert!(super::suggest::seams::keep_whole(&mut j).is_empty());
    assert_eq!(j.sections().len(), 2);
}

#[test]
fn a_section_meeting_its_parent_along_two_loops_is_joined_twice() {
    // The arch meets the root along two seams of equal length: joined twice, whether or
    // not a pose would tear it past `TEAR` (a squat arch does not).
    let j = arch_or_strip(true);
    assert_eq!(super::suggest::seams::joined_twice(&j), Some("arm".into()));
    let mut bare = j.uncut();
    let removed = super::suggest::seams::add(&mut bare, j.cuts().to_vec());
    assert_eq!(removed, vec!["arm".to_string()]);
    // The strip meets it along one.
    assert_eq!(
        super::suggest::seams::joined_twice(&arch_or_strip(false)),
        None
    );
}

#[test]
fn a_suggested_cut_that_does_not_fit_is_taken_back_and_its_cuts_go_to_its_section() {
    // On the strip: `hand` leaves the side its normal points to empty; `finger`, cut
    // from it, goes to `arm`, the section `hand` would have cut.
    let mut bare = arch_or_strip(false).uncut();
    let cuts = vec![
        cut("arm", ROOT, 1.05),
        cut("hand", "arm", 99.0),
        cut("finger", "hand", 4.05),
    ];
    let removed = super::suggest::seams::add(&mut bare, cuts);
    assert_eq!(removed, vec!["hand".to_string()]);
    let names: Vec<&str> = bare.sections().iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, [ROOT, "arm", "finger"]);
    assert_eq!(bare.sections()[2].parent, Some(1));
}

#[test]
fn a_later_connected_cut_adopts_the_children_it_carries_wherever_their_pivots_lie() {
    // A tail: rows 0–20 rise along y, rows 21–30 curl back down and out along z. Its tip
    // (rows 26–30) is cut first, from the root; then the body (rows 11–25) by a tilted
    // connected plane behind which the tip's pivot lies. The tip hangs from the body it
    // touches, not from the root it no longer meets.
    let curl = |r: usize| {
        if r <= 20 {
            DVec3::new(0.0, 0.1 * r as f64, 0.0)
        } else {
            let k = (r - 20) as f64;
            DVec3::new(0.0, 2.0 - 0.1 * k, 0.1 * k)
        }
    };
    let w = 5;
    let mut j = sheet(w, 31, false, |r, c| {
        (curl(r), curl(r) + DVec3::new(0.1 * c as f64, 0.0, 0.0))
    });
    let connected = |name: &str, point: DVec3, normal: DVec3| Cut {
        connected: true,
        ..Cut::plane(name, ROOT, point, normal)
    };
    let tip = j
        .add_cut(connected("tip", DVec3::new(0.0, 1.45, 0.55), -DVec3::Y))
        .unwrap();
    assert_eq!(j.sections()[tip].vertices, 5 * w);
    let a = 40f64.to_radians();
    let tilted = DVec3::new(0.0, a.cos(), -a.sin());
    let body = j
        .add_cut(connected("body", DVec3::new(0.0, 1.05, 0.0), tilted))
        .unwrap();
    assert!(tilted.dot(j.sections()[tip].pivot - DVec3::new(0.0, 1.05, 0.0)) < 0.0);
    assert_eq!(j.sections()[body].vertices, 15 * w);
    assert_eq!(j.sections()[tip].parent, Some(body));
}

/// The joints between two sections: up from each to the section both hang from, that
/// one left out; none between a section and itself.
#[test]
fn the_path_between_two_sections_runs_through_the_section_both_hang_from() {
    // Two arms on a line of points: arm -> forearm -> hand above y = 1, leg below y = 0.5.
    let mut j = Joints::new(&line(), ROOT);
    let arm = j.add_cut(cut("arm", ROOT, 1.0)).unwrap();
    let fore = j.add_cut(cut("forearm", "arm", 2.0)).unwrap();
    let hand = j.add_cut(cut("hand", "forearm", 2.5)).unwrap();
    let leg = j
        .add_cut(Cut::plane(
            "leg",
            ROOT,
            DVec3::new(0.0, 0.5, 0.0),
            -DVec3::Y,
        ))
        .unwrap();
    let sorted = |mut v: Vec<usize>| {
        v.sort_unstable();
        v
    };
    assert_eq!(
        sorted(j.path(hand, leg)),
        sorted(vec![hand, fore, arm, leg])
    );
    assert_eq!(sorted(j.path(hand, arm)), sorted(vec![hand, fore]));
    assert_eq!(sorted(j.path(0, fore)), sorted(vec![fore, arm]));
    assert!(j.path(hand, hand).is_empty());
}

/// Bands compose in slot order, but a carrier before the section it carries: without
/// carries the order is the slots', and a carried band moves after its carriers.
#[test]
fn carriers_compose_first_and_the_rest_keep_slot_order() {
    use super::carry::carriers_first;
    assert_eq!(carriers_first(4, &[]), vec![0, 1, 2, 3]);
    // Slot 3 carries slot 1; slot 2 carries slot 0.
    let place = carriers_first(4, &[(3, 1), (2, 0)]);
    assert!(place[3] < place[1] && place[2] < place[0]);
    assert_eq!(place, vec![1, 3, 0, 2]);
}

/// A fan's slide profile (`slide`): nothing up to the seam, then evenly along the band to
/// the whole slide at the child's end; `along` inverts the band's weight at every level
/// and between.
#[test]
fn a_fans_slide_rises_evenly_from_its_seam_to_its_child_end() {
    use super::band::{weight, LEVELS};
    use super::slide::{along, profile};
    for k in 0..=4 * LEVELS {
        let x = k as f64 / (4 * LEVELS) as f64;
        assert!((along(weight(x)) - x).abs() < 1e-12, "{x}");
    }
    let at_cut = 0.6;
    assert_eq!(profile(at_cut, 0.0), 0.0);
    assert_eq!(profile(at_cut, 0.5), 0.0);
    assert!(profile(at_cut, at_cut).abs() < 1e-12);
    assert!((profile(at_cut, 0.8) - 0.5).abs() < 1e-12);
    assert!((profile(at_cut, 1.0) - 1.0).abs() < 1e-12);
}

#[test]
fn a_limb_curling_back_to_its_cut_turns_whole_where_it_comes_back() {
    // Rows 26–30 of the arm (cut at y = 1.05) have skeletal points just above the cut, as
    // a spider's leg whose tip comes back beside its hip: by their skeletal points inside
    // the band, but joined to the seam only through the arm beyond it.
    let curled = |r: usize| r >= 26;
    let mut j = strip(5, |r, _| if curled(r) { 1.1 } else { 0.1 * r as f64 });
    let arm = j.add_cut(cut("arm", ROOT, 1.05)).unwrap();
    let sections = j.sections().len();
    let transform = |r: usize, c: usize| usize::from(j.transform_of()[r * 5 + c]);
    // The band still bends the arm at its seam …
    assert!((0..5).all(|c| transform(11, c) >= sections));
    // … and the curled tip turns with the arm, not by a level of the band.
    for r in (0..31).filter(|&r| curled(r)) {
        for c in 0..5 {
            assert_eq!(transform(r, c), arm, "row {r} column {c}");
        }
    }
}

#[test]
fn bands_found_on_one_thread_or_many_pose_alike() {
    // The bands are found cut by cut in parallel and numbered in the cuts' order, so the
    // number of threads changes nothing: the human with its suggested cuts, posed at random.
    let puppet = crate::joints::suggest::fixture::suggested_human();
    let banded = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        pool.install(|| {
            let mut joints = puppet.joints.clone();
            joints.refresh_bands();
            joints
        })
    };
    let (one, many) = (banded(1), banded(4));
    assert!(one.bands().iter().flatten().count() >= 9);
    let differ = (one.transform_of().iter())
        .zip(many.transform_of())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differ, 0, "vertices whose transform differs");
    for seed in 0..4 {
        let pose = |joints: &Joints| {
            let local = crate::joints::spread::random_pose(
                joints,
                crate::joints::spread::Spread::default(),
                &mut crate::random::SplitMix(seed),
            );
            joints
                .pose_into(&local, &mut PoseScratch::default())
                .transforms
                .clone()
        };
        assert_eq!(pose(&one), pose(&many), "seed {seed}");
    }
}

/// The slides a pose's world transforms read, each section's turn and each band's slide
/// found once per pose (`Joints::slides_into`), are those each band gives on its own
/// (`Joints::slide`, its cross terms turning their two sections each time), to the bit,
/// on the suggested human in random poses: finding them once changes no pose.
#[test]
fn slides_found_once_per_pose_are_each_band_s_own() {
    let puppet = crate::joints::suggest::fixture::suggested_human();
    let joints = &puppet.joints;
    let (mut turns, mut slides) = (Vec::new(), Vec::new());
    let (mut crossed, mut slid) = (0, 0);
    for seed in 1..=10 {
        let mut rng = crate::random::SplitMix(seed);
        let local = super::spread::random_pose(joints, Default::default(), &mut rng);
        joints.slides_into(&local, &mut turns, &mut slides);
        assert_eq!(slides.len(), joints.sections().len());
        for (s, &once) in slides.iter().enumerate() {
            let own = joints
                .band_ending_in(s)
                .map_or_else(Default::default, |band| {
                    crossed += usize::from(!band.cross.is_empty());
                    joints.slide(band, |k| {
                        local.get(k).map_or(DQuat::IDENTITY, |l| l.rotation)
                    })
                });
            assert_eq!(once, own, "seed {seed}, section {s}");
            slid += usize::from(own != Default::default());
        }
    }
    assert!(
        crossed > 0 && slid > 0,
        "no band with cross terms, or none slides"
    );
}

/// Skeletal points of a body along x from -1 to 1 at y = 0 and a head on it from y = 0.1
/// to 1 at x = ±0.1: mirrored about x = 0.
fn body_and_head() -> Vec<DVec3> {
    (0..=20)
        .map(|k| DVec3::new(-1.0 + k as f64 * 0.1, 0.0, 0.0))
        .chain((1..=10).flat_map(|k| [-0.1, 0.1].map(|x| DVec3::new(x, k as f64 * 0.1, 0.0))))
        .collect()
}

#[test]
fn a_limb_cut_through_the_head_reaches_across_the_mirror_plane() {
    let mirror = (DVec3::X, 0.0);
    // Square across the arm: the arm alone.
    let mut square = Joints::new(&body_and_head(), ROOT);
    square
        .add_cut(Cut::plane(
            "arm.L",
            ROOT,
            DVec3::new(0.55, 0.0, 0.0),
            DVec3::X,
        ))
        .unwrap();
    assert!(square.across_mirror(mirror).is_empty());
    // Tilted up through the head: the head's far side comes with the arm.
    let mut tilted = Joints::new(&body_and_head(), ROOT);
    let up = DVec3::new(0.6, 0.8, 0.0);
    tilted
        .add_cut(Cut::plane("arm.L", ROOT, DVec3::new(0.55, 0.0, 0.0), up))
        .unwrap();
    let across = tilted.across_mirror(mirror);
    assert_eq!(across, [tilted.find("arm.L").unwrap()]);
    // A section on the plane (a neck) is no limb on one side.
    let mut neck = Joints::new(&body_and_head(), ROOT);
    let at = DVec3::new(0.0, 0.45, 0.0);
    neck.add_cut(Cut {
        pivot: Some(at),
        ..Cut::plane("neck", ROOT, at, DVec3::Y)
    })
    .unwrap();
    assert!(neck.across_mirror(mirror).is_empty());
    // No plane, nothing.
    assert!(tilted.across_mirror((DVec3::ZERO, 0.0)).is_empty());
    assert!(tilted.across_mirror((DVec3::X, f64::NAN)).is_empty());
}
