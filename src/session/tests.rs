use super::*;
use crate::anim::Animation;
use crate::joints::{Cut, Shape};
use crate::mesh::shapes;
use crate::puppet::RigFile;
use crate::session::recording::BLEND_BACK;
use crate::sim;
use glam::{Vec2, Vec3};

fn session() -> Session {
    let mesh = shapes::capsule(0.3, 1.0, 4, 12, 12);
    let spec = RigFile {
        cuts: vec![
            Cut {
                name: "arm".into(),
                section: "root".into(),
                point: DVec3::new(0.0, 0.0, 0.0),
                normal: DVec3::Y,
                pivot: None,
                connected: false,
                band: None,
                shape: Shape::Plane,
                shared_pivot: false,
            },
            Cut {
                name: "hand".into(),
                section: "arm".into(),
                point: DVec3::new(0.0, 0.8, 0.0),
                normal: DVec3::Y,
                pivot: None,
                connected: false,
                band: None,
                shape: Shape::Plane,
                shared_pivot: false,
            },
        ],
        ..RigFile::default()
    };
    let puppet = Puppet::build(mesh, spec, crate::progress::silent()).unwrap();
    Session::new(puppet, "capsule")
}

#[test]
fn selection_replaces_toggles_and_clears() {
    let mut s = session();
    s.select(Some(1), false);
    assert_eq!(s.selection, vec![1]);
    s.select(Some(2), true);
    assert_eq!(s.selection, vec![1, 2]);
    s.select(Some(1), true);
    assert_eq!(s.selection, vec![2]);
    s.select(None, true);
    assert_eq!(
        s.selection,
        vec![2],
        "a modifier click on nothing keeps the selection"
    );
    s.select(None, false);
    assert!(s.selection.is_empty());
    s.select(Some(99), false);
    assert!(s.selection.is_empty(), "no such section");
}

#[test]
fn a_world_rotation_turns_the_section_about_its_current_pivot() {
    let mut s = session();
    // A hinge turns about its pivot; a joint band also carries the section along the
    // bent limb (below).
    for k in 0..s.puppet.joints.cuts().len() {
        let name = s.puppet.joints.cuts()[k].name.clone();
        s.puppet.joints.set_band(&name, Some(0.0));
    }
    s.select(Some(1), false);
    s.rotate_selected(DQuat::from_rotation_z(0.7));
    s.select(Some(2), false);
    let before = s.puppet.joints.world(&s.local)[2];
    let pivot = s.pivot_world(2);
    let q = DQuat::from_rotation_x(0.4);
    s.rotate_selected(q);
    let after = s.puppet.joints.world(&s.local)[2];
    let p = DVec3::new(0.1, 1.2, 0.05);
    let expected = pivot + q * (before.transform_point3(p) - pivot);
    assert!((after.transform_point3(p) - expected).length() < 1e-12);
}

#[test]
fn a_world_rotation_turns_a_section_at_a_joint_band_by_it() {
    let mut s = session();
    assert!(s.puppet.joints.bands().iter().any(Option::is_some));
    s.select(Some(2), false);
    s.rotate_selected(DQuat::from_rotation_z(0.3));
    let before = s.puppet.joints.world(&s.local)[2];
    let q = DQuat::from_rotation_x(0.4);
    s.rotate_selected(q);
    let after = s.puppet.joints.world(&s.local)[2];
    let turned = DQuat::from_mat3(&after.matrix3) * DQuat::from_mat3(&before.matrix3).inverse();
    assert!(turned.dot(q).abs() > 1.0 - 1e-12, "{turned:?}");
}

#[test]
fn a_selected_child_of_a_selected_parent_is_carried_not_turned_twice() {
    let mut s = session();
    s.select(Some(1), false);
    s.select(Some(2), true);
    s.rotate_selected(DQuat::from_rotation_z(0.5));
    assert_eq!(s.local[2], Local::default());
    assert_ne!(s.local[1], Local::default());
}

#[test]
fn undo_and_redo_pose_changes_and_cuts() {
    let mut s = session();
    assert!(!s.can_undo());
    s.select(Some(1), false);
    s.checkpoint();
    s.rotate_selected(DQuat::from_rotation_z(0.5));
    let turned = s.local.clone();
    s.draft = Some(CutDraft {
        shape: Shape::Plane,
        section: 0,
        point: DVec3::new(0.0, -0.6, 0.0),
        normal: -DVec3::Y,
        pivot: None,
        connected: false,
        name: s.fresh_section_name(),
    });
    s.apply_draft().unwrap();
    assert_eq!(s.puppet.joints.sections().len(), 4);
    assert_eq!(s.selection, vec![3]);
    s.undo();
    assert_eq!(s.puppet.joints.sections().len(), 3);
    assert_eq!(s.local, turned);
    s.undo();
    assert!(s.local.iter().all(|l| *l == Local::default()));
    assert!(!s.can_undo());
    s.redo();
    assert_eq!(s.local, turned);
    s.redo();
    assert_eq!(s.puppet.joints.sections().len(), 4);
    assert_eq!(s.puppet.sim.rig().len(), s.puppet.joints.section_of().len());
    assert!(!s.can_redo());
    s.remove_cut("section 1").unwrap();
    assert_eq!(s.puppet.joints.sections().len(), 3);
    s.undo();
    assert_eq!(s.puppet.joints.sections().len(), 4);
}

#[test]
fn a_refused_cut_changes_nothing() {
    let mut s = session();
    s.draft = Some(CutDraft {
        shape: Shape::Plane,
        section: 0,
        point: DVec3::new(0.0, -5.0, 0.0),
        normal: -DVec3::Y,
        pivot: None,
        connected: false,
        name: "x".into(),
    });
    assert!(s.apply_draft().is_err());
    assert_eq!(s.puppet.joints.sections().len(), 3);
    assert!(!s.can_undo());
}

#[test]
fn sliders_are_sanitized_and_presets_apply() {
    let mut s = session();
    s.set_material(Material {
        damping: 5.0,
        stiffness: f32::NAN,
        ..Material::default()
    });
    let m = s.puppet.sim.params().material;
    assert_eq!(
        (m.damping, m.stiffness),
        (1.0, Material::default().stiffness)
    );
    assert_eq!(s.puppet.rig_file.preset, "custom", "no longer skin");
    assert!(s.set_preset("water"));
    assert_eq!(s.puppet.sim.params().material.max_length, 1.4);
    assert_eq!(s.puppet.rig_file.preset, "water");
    assert!(!s.set_preset("rubber"));
    assert_eq!(
        s.puppet.rig_file.preset, "water",
        "an unknown name changes nothing"
    );
}

/// One rule for what a preset changes, for the base material and a region alike: the whole
/// material (stiffening included), and neither the solver nor the world.
#[test]
fn a_preset_replaces_the_material_and_nothing_else() {
    let mut s = session();
    let custom = Material {
        damping: 0.5,
        stiffening: 3,
        ..Material::default()
    };
    let mut params = *s.puppet.sim.params();
    params.material = custom;
    params.solver.constraint = sim::Constraint::SpringReduction;
    params.solver.time_step = 1.0 / 120.0;
    params.world.gravity = [0.0, -2.0, 0.0];
    params.world.floor = true;
    s.set_params(params);
    s.set_regions(
        vec![crate::puppet::Region {
            name: "belly".into(),
            preset: "custom".into(),
            material: custom,
            paint: crate::puppet::Paint::default(),
        }],
        crate::puppet::Paint::default(),
    );
    let water = Material::preset("water").unwrap();
    assert!(s.set_preset("water"));
    assert!(s.set_region_preset(0, "water"));
    let after = *s.puppet.sim.params();
    let region = &s.puppet.rig_file.regions[0];
    assert_eq!(
        after.material, water,
        "base: the whole material, stiffening too"
    );
    assert_eq!(region.material, water, "region: the same");
    assert_eq!((after.solver, after.world), (params.solver, params.world));
    assert_eq!(region.preset, "water");
    assert!(!s.set_region_preset(0, "rubber") && !s.set_region_preset(5, "water"));
    assert!(s.set_region_preset(0, "custom"));
    assert_eq!(
        s.puppet.rig_file.regions[0].material, water,
        "custom keeps it"
    );
}

#[test]
fn the_simulation_sleeps_when_settled_and_wakes_on_a_change() {
    let mut s = session();
    s.advance(1.0 / 60.0, 4);
    assert!(s.is_settled(), "a rig at rest is settled after one step");
    assert_eq!(s.advance(1.0, 4), 0);
    s.select(Some(2), false);
    s.rotate_selected(DQuat::from_rotation_z(0.5));
    assert!(!s.is_settled());
    let mut steps = 0;
    while !s.is_settled() && steps < 100_000 {
        steps += s.advance(1.0 / 60.0, 1);
    }
    assert!(s.is_settled(), "settles again");
    assert!(steps > 10, "the motion took {steps} steps to die out");
}

#[test]
fn pausing_stops_the_steps_and_resuming_wakes_them() {
    let mut s = session();
    s.select(Some(2), false);
    s.rotate_selected(DQuat::from_rotation_z(0.5));
    let revision = s.revision;
    s.toggle_pause();
    assert!(s.is_paused() && !s.is_running());
    assert!(s.revision > revision, "the window draws the paused state");
    assert_eq!(s.advance(1.0, 4), 0, "paused, nothing steps");
    s.set_paused(false);
    assert!(!s.is_paused() && s.is_running());
    assert!(s.advance(1.0 / 60.0, 4) > 0, "resumed, it steps again");
}

#[test]
fn picking_hits_the_nearest_surface() {
    let s = session();
    let hit = s
        .pick(Vec3::new(0.0, 0.5, 5.0), Vec3::new(0.0, 0.0, -1.0))
        .unwrap();
    assert!((hit.point.z - 0.3).abs() < 0.02, "{hit:?}");
    assert_eq!(s.section_at(&hit), 1);
    assert!(s
        .pick(Vec3::new(3.0, 0.5, 5.0), Vec3::new(0.0, 0.0, -1.0))
        .is_none());
}

#[test]
fn the_brush_paints_blends_erases_and_undoes() {
    let mut s = session();
    s.set_regions(
        vec![crate::puppet::Region {
            name: "jelly".into(),
            preset: "water".into(),
            material: Material::preset("water").unwrap(),
            paint: crate::puppet::Paint::default(),
        }],
        crate::puppet::Paint::default(),
    );
    s.paint_tool = PaintTool {
        active: true,
        target: Some(0),
        radius: 0.4,
        falloff: 0.5,
        erase: false,
    };
    let tip = s
        .puppet
        .mesh
        .positions
        .iter()
        .map(|p| p.y)
        .fold(f64::MIN, f64::max);
    s.checkpoint();
    s.paint_at(Vec3::new(0.0, tip as f32, 0.0));
    let w = s.puppet.rig_file.regions[0].paint.weights.clone();
    let painted = w.iter().filter(|&&w| w > 0.0).count();
    assert!(painted > 0 && w.contains(&1.0), "a hard core");
    assert!(w.iter().any(|&w| w > 0.0 && w < 1.0), "a soft edge");
    assert!(s.puppet.sim.regions().is_mixed());
    // Erasing with a larger hard brush takes it all away; undo brings the paint back.
    s.checkpoint();
    s.paint_tool.erase = true;
    s.paint_tool.falloff = 0.0;
    s.paint_tool.radius = 0.5;
    s.paint_at(Vec3::new(0.0, tip as f32, 0.0));
    assert!(s.puppet.rig_file.regions[0]
        .paint
        .weights
        .iter()
        .all(|&w| w == 0.0));
    assert!(!s.puppet.sim.regions().is_mixed());
    s.undo();
    assert_eq!(s.puppet.rig_file.regions[0].paint.weights, w);
    assert!(s.puppet.sim.regions().is_mixed());
    // Pinning by the brush, and removing the region, keep the simulation in step.
    s.paint_tool = PaintTool {
        target: None,
        erase: false,
        radius: 0.4,
        ..s.paint_tool
    };
    s.paint_at(Vec3::new(0.0, tip as f32, 0.0));
    assert!(s.puppet.sim.regions().is_pinned());
    s.set_regions(Vec::new(), s.puppet.rig_file.pin.clone());
    assert!(!s.puppet.sim.regions().is_mixed());
    assert!(s.paint_tool.target.is_none());
}

#[test]
fn animations_open_save_and_bad_ones_change_nothing() {
    let mut s = session();
    let dir = std::env::temp_dir().join(format!("puppet-anim-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("wave.anim.toml");
    std::fs::write(
        &good,
        "duration = 1\n[[track]]\nsection = \"arm\"\nkey = [{ time = 0, axis = [0, 0, 1], angle = 0 }, { time = 1, axis = [0, 0, 1], angle = 45 }]\n",
    )
    .unwrap();
    assert_eq!(s.open_animation(&good).unwrap(), "playing wave.anim.toml");
    assert!(s.is_playing());
    assert!(crate::session::playback::is_animation_file(&good));
    s.advance(0.5, 100);
    assert!(s.playback_time().unwrap().0 > 0.4);
    // Bad files: one message naming the file; what plays stays.
    let bad = dir.join("bad.anim.toml");
    std::fs::write(&bad, "duration = 1\n[[track]]\nsection = \"tail\"\nkey = [{ time = 0, axis = [0, 0, 1], angle = 0 }]\n").unwrap();
    let e = s.open_animation(&bad).unwrap_err();
    assert!(
        e.starts_with("bad.anim.toml: ") && e.contains("tail"),
        "{e}"
    );
    assert!(s.open_animation(&dir.join("missing.toml")).is_err());
    assert_eq!(
        s.playback.as_ref().unwrap().animation.track[0].section,
        "arm"
    );
    // Saved as TOML and as JSON, both read back the same.
    for name in ["saved.anim.toml", "saved.anim.json"] {
        let path = dir.join(name);
        s.save_animation(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let back = crate::anim::Animation::parse(&text, crate::files::Format::of(&path)).unwrap();
        assert_eq!(back, *s.playback.as_ref().unwrap().animation);
    }
    assert!(s.save_animation(&dir.join("no/such/dir/a.toml")).is_err());
    assert!(!crate::session::playback::is_animation_file(
        &dir.join("missing.toml")
    ));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_recorded_take_plays_back_what_the_hands_did() {
    let mut s = session();
    s.select(Some(1), false);
    s.start_recording();
    assert!(s.is_recording());
    // Turn the arm a little every frame for a second, then hold for half a second.
    for frame in 0..90 {
        if frame < 60 {
            s.rotate_selected(DQuat::from_rotation_z(1.5f64.to_radians()));
        }
        s.advance(1.0 / 60.0, 8);
    }
    let held = s.local[1].rotation;
    let said = s.stop_recording().unwrap();
    assert!(said.starts_with("recorded 1.5 s"), "{said}");
    let p = s.playback.as_ref().unwrap();
    assert_eq!(p.animation.track.len(), 1, "only the arm moved");
    assert_eq!(p.animation.track[0].section, "arm");
    let keys = p.animation.track[0].key.len();
    assert!((2..=10).contains(&keys), "{keys} keys for 90 samples");
    assert!(s.is_playing());
    // Played to the end, the arm holds what the hands left it at (within the tolerance).
    s.scrub(1.5);
    let end = s.animated_pose().unwrap()[1].rotation;
    assert!(end.angle_between(held).to_degrees() <= s.recorder.tolerance + 1e-9);
    // A take in which nothing moved is no take.
    s.start_recording();
    s.advance(0.5, 100);
    assert!(s.stop_recording().is_err());
    assert!(!s.is_recording());
    // Slow motion: half speed records half the simulated time.
    s.recorder.speed = 0.5;
    s.start_recording();
    s.rotate_selected(DQuat::from_rotation_z(0.3));
    s.advance(1.0, 1000);
    assert!(
        (s.recorded_seconds() - 0.5).abs() < 0.02,
        "{}",
        s.recorded_seconds()
    );
}

#[test]
fn a_take_over_an_animation_replaces_only_what_the_hands_turned_over_its_range() {
    let mut s = session();
    // The arm swings 0° → 60° over 2 s.
    let text = "duration = 2.0\n[[track]]\nsection = \"arm\"\nkey = [\n  { time = 0.0, axis = [0, 0, 1], angle = 0 },\n  { time = 2.0, axis = [0, 0, 1], angle = 60 },\n]\n";
    let anim = Animation::parse(text, crate::files::Format::Toml).unwrap();
    s.set_animation(anim.clone()).unwrap();
    s.scrub(0.5);
    // Over 0.5 s .. 1.0 s the hand is turned; the arm goes on swinging meanwhile.
    s.select(Some(2), false);
    s.start_recording();
    for _ in 0..30 {
        s.rotate_selected(DQuat::from_rotation_x(1.0f64.to_radians()));
        s.advance(1.0 / 60.0, 8);
    }
    let arm_at_stop = s.local[1].rotation;
    let said = s.stop_recording().unwrap();
    assert!(said.contains("over 0.5"), "{said}");
    let deg = |q: DQuat| q.to_axis_angle().1.to_degrees();
    assert!(
        (deg(arm_at_stop) - 30.0).abs() < 1.0,
        "the arm kept playing"
    );
    let p = s.playback.as_ref().unwrap();
    let arm = p
        .animation
        .track
        .iter()
        .find(|t| t.section == "arm")
        .unwrap();
    assert_eq!(arm, &anim.track[0], "the untouched track is as it was");
    assert!(p.animation.track.iter().any(|t| t.section == "hand"));
    assert_eq!(p.animation.duration, 2.0);
    // The hand: at rest before the take, turned in it, back to rest after the blend.
    let at = |s: &mut Session, t: f64| {
        s.scrub(t);
        deg(s.animated_pose().unwrap()[2].rotation)
    };
    assert!(at(&mut s, 0.4) < 1.0);
    assert!((at(&mut s, 0.98) - 29.0).abs() < 2.0);
    assert!(at(&mut s, 1.0 + BLEND_BACK + 0.05) < 1.0);
    // One undo takes the take back; redo brings it again.
    s.undo();
    let p = s.playback.as_ref().unwrap();
    assert_eq!(*p.animation, anim);
    s.redo();
    assert!(s.playback.as_ref().unwrap().animation.track.len() == 2);
}

#[test]
fn a_loop_range_plays_its_part_over_and_over_as_the_bake_shows_it() {
    let mut s = session();
    let text = "duration = 2.0\n[[track]]\nsection = \"arm\"\nkey = [\n  { time = 0.0, axis = [0, 0, 1], angle = 0 },\n  { time = 2.0, axis = [0, 0, 1], angle = 60 },\n]\n";
    s.set_animation(Animation::parse(text, crate::files::Format::Toml).unwrap())
        .unwrap();
    s.set_loop_range(Some((0.5, 1.0)));
    // Bad ranges change nothing.
    s.set_loop_range(Some((1.0, 0.5)));
    s.set_loop_range(Some((f64::NAN, 1.0)));
    assert_eq!(s.playback.as_ref().unwrap().loop_range, Some((0.5, 1.0)));
    // The surface at the range's start, as playing from rest gives it.
    s.scrub(0.5);
    let start = s.puppet.sim.positions().to_vec();
    s.restart();
    s.toggle_play();
    let mut wraps = 0;
    let mut last = 0.0;
    for _ in 0..200 {
        s.advance(1.0 / 60.0, 8);
        let t = s.playback_time().unwrap().0;
        assert!(t <= 1.0 + 1e-6, "never past the range: {t}");
        if t < last {
            wraps += 1;
            assert!((t - 0.5).abs() < 1e-6, "back to the range's start: {t}");
            assert!(
                s.puppet.sim.positions().to_vec() == start,
                "as the bake has it"
            );
        }
        last = t;
    }
    assert!(wraps >= 3, "{wraps} passes");
    assert!(s.is_playing());
    s.set_loop_range(None);
    assert_eq!(s.playback.as_ref().unwrap().loop_range, None);
}

#[test]
fn a_pivot_dragged_with_the_mouse_stays_on_its_plane_and_undoes() {
    use crate::session::pointer::{Button, Drag, Pointer};
    let mut s = session();
    let camera = Camera::default();
    let viewport = Vec2::new(800.0, 600.0);
    let before = s.puppet.joints.cuts()[1].pivot.unwrap();
    let at = camera
        .project(s.pivot_world(2).as_vec3(), viewport)
        .unwrap();
    // Without *move pivots* the press turns the section instead.
    let mut pointer = Pointer {
        cursor: at,
        ..Pointer::default()
    };
    pointer.press(Button::Left, Some(&mut s), &camera, viewport);
    assert_ne!(pointer.drag, Drag::Pivot(2));
    pointer.release();
    s.cut_tool.move_pivots = true;
    pointer.press(Button::Left, Some(&mut s), &camera, viewport);
    assert_eq!(pointer.drag, Drag::Pivot(2));
    assert_eq!(s.selection, vec![2]);
    for _ in 0..5 {
        pointer.moved(
            pointer.cursor + Vec2::new(6.0, 3.0),
            Some(&mut s),
            &mut Camera::default(),
            viewport,
        );
    }
    pointer.release();
    let moved = s.puppet.joints.cuts()[1].pivot.unwrap();
    assert!(moved.distance(before) > 0.01, "{before} -> {moved}");
    assert!(
        (moved.y - before.y).abs() < 1e-9,
        "kept on the plane y = 0.8"
    );
    assert_eq!(s.puppet.joints.sections()[2].pivot, moved);
    // Shift (toggle) frees it from the plane.
    pointer.cursor = camera
        .project(s.pivot_world(2).as_vec3(), viewport)
        .unwrap();
    pointer.toggle = true;
    pointer.press(Button::Left, Some(&mut s), &camera, viewport);
    pointer.moved(
        pointer.cursor + Vec2::new(0.0, -20.0),
        Some(&mut s),
        &mut Camera::default(),
        viewport,
    );
    pointer.release();
    let free = s.puppet.joints.cuts()[1].pivot.unwrap();
    assert!((free.y - moved.y).abs() > 0.01, "{moved} -> {free}");
    s.undo();
    assert_eq!(s.puppet.joints.cuts()[1].pivot.unwrap(), moved);
    s.undo();
    assert_eq!(s.puppet.joints.cuts()[1].pivot.unwrap(), before);
    assert_eq!(s.puppet.joints.sections()[2].pivot, before);
    s.redo();
    assert_eq!(s.puppet.joints.cuts()[1].pivot.unwrap(), moved);
}

#[test]
fn a_shared_pivot_is_set_from_the_session_and_undoes() {
    let mut s = session();
    let own = s.puppet.joints.sections()[1].pivot;
    let hand = s.puppet.joints.cuts()[1].pivot.unwrap();
    s.set_shared_pivot("hand", true);
    assert_eq!(s.puppet.joints.sections()[1].pivot, hand);
    s.undo();
    assert_eq!(s.puppet.joints.sections()[1].pivot, own);
    assert!(!s.puppet.joints.cuts()[1].shared_pivot);
}

#[test]
fn the_cut_tool_places_and_applies_a_sphere() {
    let mut s = session();
    s.cut_tool.shape = ShapeKind::Sphere;
    // The capsule's lower cap, in the root.
    s.place_draft(0, DVec3::new(0.0, -0.7, 0.0), DVec3::Y);
    let d = s.draft.clone().unwrap();
    assert!(matches!(d.shape, Shape::Sphere { radius } if radius > 0.0));
    if let Some(CutDraft {
        shape: Shape::Sphere { radius },
        ..
    }) = &mut s.draft
    {
        *radius = 0.35;
    }
    s.apply_draft().unwrap();
    let k = s.puppet.joints.sections().len() - 1;
    let points = s.puppet.joints.points();
    for (i, &sec) in s.puppet.joints.section_of().iter().enumerate() {
        if sec as usize == k {
            assert!(points[i].distance(DVec3::new(0.0, -0.7, 0.0)) < 0.35);
        }
    }
    assert!(s.puppet.joints.sections()[k].vertices > 0);
}

/// A file that needed repairs shows them: the open-necked cow's filled holes as orange
/// edges (each once) and nothing else; a clean file shows none.
#[test]
fn the_repairs_overlay_draws_the_filled_holes() {
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/defects/open-neck.obj"
    ))
    .unwrap();
    let (mesh, report) = crate::mesh::parse(
        &bytes,
        crate::mesh::Format::Obj,
        &crate::mesh::LoadOptions::default(),
        crate::progress::silent(),
    )
    .unwrap();
    assert_eq!(report.marks.hole_faces.len(), report.hole_faces);
    let puppet = Puppet::build(mesh, RigFile::default(), crate::progress::silent()).unwrap();
    let mut s = Session::new(puppet, "open neck");
    let overlays = Overlays {
        repairs: true,
        pivots: false,
        ..Overlays::default()
    };
    let (mut lines, mut top) = (Vec::new(), Vec::new());
    s.view(overlays).lines(&mut lines, &mut top);
    assert!(lines.is_empty() && top.is_empty(), "nothing marked yet");
    s.repairs = report.marks.clone();
    s.view(overlays).lines(&mut lines, &mut top);
    // Every edge of the patches once: (3 F + the loop's edges) / 2 of them.
    let faces = report.hole_faces;
    assert!(
        lines.len() > 3 * faces / 2 && lines.len() < 2 * faces,
        "{} lines for {faces} faces",
        lines.len()
    );
    assert!(lines.iter().all(|l| l.color == [1.0, 0.55, 0.1, 0.9]));
    assert!(top.is_empty(), "no split vertices");
}

/// Live controls turn sections as the mouse does: a take recorded with an OSC button
/// holds the motion the controls made, and hostile messages change nothing.
#[test]
fn live_controls_turn_sections_and_record_a_take() {
    use crate::controls::{Controls, ControlsFile, Event};
    let mut s = session();
    let file = ControlsFile::parse(
        "[[control]]\nosc = \"/bend\"\nsection = \"arm\"\nangles = [0, 80]\nmin_cutoff = 1000\n\
         [[control]]\nosc = \"/rec\"\naction = \"record\"\n",
    )
    .unwrap();
    let mut c = Controls::new(file, &s.section_names()).unwrap();
    let osc = |address: &str, x: f64| Event::Osc {
        address: address.into(),
        args: vec![Some(x)],
    };
    c.feed(&osc("/rec", 1.0), 0.0);
    assert_eq!(s.drive(&mut c), None);
    assert!(s.is_recording());
    for k in 0..30 {
        c.feed(&osc("/bend", k as f64 / 29.0), k as f64 / 30.0);
        s.drive(&mut c);
        s.advance(1.0 / 30.0, 10);
    }
    let angle = s.local[1]
        .rotation
        .angle_between(DQuat::IDENTITY)
        .to_degrees();
    assert!((angle - 80.0).abs() < 1.0, "{angle}");
    c.feed(&osc("/rec", 0.0), 1.0);
    c.feed(&osc("/rec", 1.0), 1.1);
    let said = s.drive(&mut c).expect("the take stops");
    assert!(!s.is_recording(), "{said}");
    let take = s.playback.as_ref().expect("the take plays back");
    let tracks: Vec<&str> = take
        .animation
        .track
        .iter()
        .map(|t| t.section.as_str())
        .collect();
    assert!(tracks.contains(&"arm"), "{tracks:?}");
    c.feed(&osc("/nobody", 1.0), 2.0);
    c.feed(&osc("/bend", f64::NAN), 2.0);
    assert_eq!((c.unknown, c.ignored), (1, 1));
}

#[test]
fn a_learned_control_bends_its_section_towards_the_viewer() {
    let s = session();
    let arm = s.section_names().iter().position(|&n| n == "arm").unwrap();
    // Seen from +z, the arm (along +y) bends about +x: its tip comes towards the camera.
    let axis = s.bend_axis(arm, DVec3::NEG_Z);
    assert!(axis.distance(DVec3::X) < 0.02, "{axis}");
    let tip = DQuat::from_axis_angle(axis, 0.5) * DVec3::Y;
    assert!(tip.z > 0.4, "{tip}");
    // Seen along the arm there is no such axis: +z.
    assert_eq!(s.bend_axis(arm, DVec3::NEG_Y), DVec3::Z);
    assert_eq!(s.bend_axis(99, DVec3::NEG_Z), DVec3::Z);
}

/// A device unplugged while a take records: its controls stop (they are dropped, as the
/// window's are when the device goes), the take goes on, and stopping it keeps what the
/// device did.
#[test]
fn a_take_survives_its_device_going_away() {
    use crate::controls::{Controls, ControlsFile, Event};
    let mut s = session();
    let file = ControlsFile::parse(
        "[[control]]\nmidi = { channel = 1, cc = 1 }\nsection = \"arm\"\nmin_cutoff = 1000\n",
    )
    .unwrap();
    let mut c = Controls::new(file, &s.section_names()).unwrap();
    s.start_recording();
    for k in 0..20 {
        c.feed(
            &Event::MidiCc {
                channel: 1,
                cc: 1,
                value: (k * 6) as u8,
            },
            k as f64 / 30.0,
        );
        s.drive(&mut c);
        s.advance(1.0 / 30.0, 10);
    }
    drop(c);
    for _ in 0..10 {
        s.advance(1.0 / 30.0, 10);
    }
    assert!(s.is_recording());
    let said = s.stop_recording().expect("the take stops");
    let take = s.playback.as_ref().expect("the take plays back");
    assert!(
        take.animation.track.iter().any(|t| t.section == "arm"),
        "{said}"
    );
}

/// The cut tool and the brush are one at a time, a draft goes with the cut tool, and
/// the axis and shape buttons reshape a draft on the model: the session keeps these, so
/// a key, a panel or a test all get the same.
#[test]
fn tools_keep_their_rules_whoever_switches_them() {
    use super::cut_tool::{CutAxis, ShapeKind};
    let mut s = session();
    let revision = s.revision;
    s.set_cut_tool(true);
    assert!(s.cut_tool.active && s.revision > revision);
    s.place_draft(0, DVec3::ZERO, DVec3::Y);
    s.set_cut_axis(CutAxis::X);
    assert_eq!(s.draft.as_ref().map(|d| d.normal), Some(DVec3::X));
    s.set_cut_axis(CutAxis::View);
    assert_eq!(s.draft.as_ref().map(|d| d.normal), Some(DVec3::X));
    s.set_cut_shape(ShapeKind::Sphere);
    assert!(matches!(
        s.draft.as_ref().map(|d| d.shape),
        Some(crate::joints::Shape::Sphere { .. })
    ));
    // The brush turns the cut tool off and drops the draft; the cut tool the brush.
    s.set_brush(None, true);
    assert!(s.paint_tool.active && !s.cut_tool.active && s.draft.is_none());
    s.set_cut_tool(true);
    assert!(s.cut_tool.active && !s.paint_tool.active);
    s.place_draft(0, DVec3::ZERO, DVec3::Y);
    s.cancel_draft();
    assert!(!s.cut_tool.active && s.draft.is_none());
    s.set_move_pivots(true);
    assert!(s.cut_tool.move_pivots);
    s.select(Some(1), false);
    s.set_cut_tool(true);
    s.escape();
    assert!(!s.cut_tool.active && !s.paint_tool.active && s.selection.is_empty());
}

#[test]
fn the_ground_lies_under_the_rest_mesh_or_at_the_floor_and_goes_when_hidden() {
    let mut s = session();
    let ground = s
        .view(Overlays::default())
        .ground()
        .expect("shown by default");
    let lowest = s
        .puppet
        .mesh
        .positions
        .iter()
        .map(|p| p.y)
        .fold(f64::INFINITY, f64::min) as f32;
    assert_eq!(ground.up, Vec3::Y);
    assert!((ground.centre.y - lowest).abs() < 1e-5, "{ground:?}");
    for a in ground.across {
        assert!(a.dot(Vec3::Y).abs() < 1e-6 && (a.length() - 1.0).abs() < 1e-6);
    }
    assert!(ground.across[0].dot(ground.across[1]).abs() < 1e-6);
    assert!((ground.spacing * view::GRID_LINES as f32 - ground.half).abs() < 1e-6);
    // The floor on: the ground is the floor, whatever the puppet does.
    let mut params = *s.puppet.sim.params();
    params.world.floor = true;
    s.set_params(params);
    let height = s.puppet.sim.floor_height().expect("the floor is on");
    let floor = s.view(Overlays::default()).ground().unwrap();
    assert!((floor.centre.y - height).abs() < 1e-5, "{floor:?}");
    let hidden = Overlays {
        ground: false,
        ..Overlays::default()
    };
    assert_eq!(s.view(hidden).ground(), None);
}

#[test]
fn a_video_keeps_the_windows_look_and_drops_the_marks_for_editing() {
    let shown = Overlays {
        wireframe: true,
        skeleton: true,
        bone_points: true,
        bone_springs: true,
        cuts: true,
        pivots: true,
        repairs: true,
        ground: false,
        occlusion: false,
        lighting: Lighting::Jelly,
    };
    let video = shown.for_video();
    assert_eq!(
        (
            video.wireframe,
            video.ground,
            video.occlusion,
            video.lighting
        ),
        (true, false, false, Lighting::Jelly)
    );
    assert!(
        !(video.skeleton
            || video.bone_points
            || video.bone_springs
            || video.cuts
            || video.pivots
            || video.repairs)
    );
}
