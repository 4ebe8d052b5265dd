//! The real window under Xvfb (installed by scripts/setup.sh): start the app with the frog
//! jaw rig, drag a section with synthetic mouse events through the same handlers the mouse
//! uses, take a screenshot, and check the model and the panel are in it.

mod common;

use puppet::render::Image;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How far the section `name` is turned in the app's report (degrees; 0 when it is not).
fn turned(r: &serde_json::Value, name: &str) -> f64 {
    let prefix = format!("{name}:");
    r["turned"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|t| t.as_str()?.strip_prefix(&prefix)?.parse().ok())
        .next()
        .unwrap_or(0.0)
}

/// Where the section `name` is drawn on screen, in the app's report (pixels).
fn target(r: &serde_json::Value, name: &str) -> [f64; 2] {
    let t = &r["targets"][name];
    [t[0].as_f64().unwrap(), t[1].as_f64().unwrap()]
}

#[test]
fn the_window_shows_the_puppet_and_panels_and_a_drag_turns_a_section() {
    let dir = common::scratch("window");
    let shot = dir.join("window.png");
    let runtime = common::runtime_dir(&dir);
    let rig = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/spot-jaw.rig.toml");
    let mut child = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_puppet"))
        .arg("--rig")
        .arg(&rig)
        .arg("--screenshot")
        .arg(&shot)
        .args(["--frames", "20", "--drive-test"])
        .env("XDG_RUNTIME_DIR", &runtime)
        .env("RUST_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("xvfb-run (scripts/setup.sh installs the xvfb package)");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > Duration::from_secs(180) {
            let _ = child.kill();
            panic!("the app did not exit within 180 s");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        status.success(),
        "exit {status}\nstdout: {stdout}\nstderr: {stderr}"
    );
    let report: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap_or(""))
        .unwrap_or_else(|e| panic!("{e}: {stdout}"));
    let selection = report["selection"].as_array().unwrap();
    assert_eq!(selection.len(), 1, "{report}");
    let turned = report["turned"].as_array().unwrap();
    assert_eq!(
        turned.len(),
        1,
        "exactly the dragged section turned: {report}"
    );
    let name = selection[0].as_str().unwrap();
    assert!(
        turned[0].as_str().unwrap().starts_with(&format!("{name}:")),
        "{report}"
    );

    let img = Image::load_png(&shot).unwrap();
    assert_eq!((img.width, img.height), (1280, 800));
    // The panel (left) is egui's grey with text; the model is to the right of it.
    let panel_rows: Vec<[u8; 4]> = (0..img.height)
        .step_by(4)
        .map(|y| img.pixel(40, y))
        .collect();
    let distinct: std::collections::HashSet<[u8; 4]> = (0..200)
        .flat_map(|x| (0..img.height).step_by(3).map(move |y| (x, y)))
        .map(|(x, y)| img.pixel(x, y))
        .collect();
    assert!(
        distinct.len() > 20,
        "the panel has text and widgets ({} colours)",
        distinct.len()
    );
    assert!(panel_rows.iter().any(|p| p[0] > 20), "the panel is drawn");
    let right = Image {
        width: 600,
        height: 800,
        rgba: (0..800u32)
            .flat_map(|y| (600..1200u32).map(move |x| (x, y)))
            .flat_map(|(x, y)| img.pixel(x, y))
            .collect(),
    };
    let coverage = right.coverage([12, 13, 14], 20);
    assert!(coverage > 0.05, "the model is visible ({coverage:.3})");
    // Keep the screenshot for the README when asked.
    if let Some(dst) = std::env::var_os("PUPPET_SCREENSHOT") {
        std::fs::copy(&shot, dst).unwrap();
    }
}

/// A settled window costs nothing: after the default cow settles, the process uses no CPU
/// while nobody touches it (a window that redraws when nothing changed would use a core).
#[test]
fn a_settled_window_uses_no_cpu() {
    let dir = common::scratch("window-idle");
    let w = common::Window::open(&dir, &[]);
    // Let the first frames' work (shader compilation, uploads) pass.
    std::thread::sleep(Duration::from_secs(2));
    let before = w.cpu_ticks();
    std::thread::sleep(Duration::from_secs(4));
    let used = w.cpu_ticks() - before;
    // At most 1 % of a core over 4 s (100 ticks a second).
    assert!(used <= 4, "{used} CPU ticks in 4 s of a settled window");
    assert!(w.quit().success());
}

/// The first five minutes, as a user meets them: the default cow opens with its suggested
/// joints and the first-run hint; a tap (press and release at once) on a part selects it;
/// a drag turns it and ends the hint for good; the cut tool places its plane on a tap too.
#[test]
fn taps_select_drags_turn_and_the_hint_goes_after_the_first_drag() {
    let dir = common::scratch("window-first");
    let mut w = common::Window::open(&dir, &[]);
    let r = w.state().unwrap();
    assert_eq!(r["hint"], true, "{r}");
    let sections = r["sections"].as_array().unwrap().len();
    assert!(
        sections >= 5,
        "the cow opens with its suggested joints: {r}"
    );
    let (name, at) = common::part_on_screen(&r);
    // Rest on the panel first (egui then thinks the pointer is its own), then tap the part.
    w.hover([120.0, 400.0]);
    std::thread::sleep(Duration::from_millis(300));
    w.click(at);
    w.wait(
        |r| r["selection"] == serde_json::json!([name]),
        "the tap to select",
    );
    // Drag it: it turns, and the hint is gone.
    w.drag(at, [0.0, 60.0]);
    let r = w.wait(
        |r| r["hint"] == false && !r["turned"].as_array().unwrap().is_empty(),
        "the drag to turn it",
    );
    assert!(
        r["turned"][0]
            .as_str()
            .unwrap()
            .starts_with(&format!("{name}:")),
        "{r}"
    );
    // The cut tool (C), then a tap on the body places its plane.
    w.key("c");
    w.wait(|r| r["cut_tool"] == true, "the cut tool");
    let body = w.state().unwrap()["targets"]["root"].clone();
    let body = [body[0].as_f64().unwrap(), body[1].as_f64().unwrap()];
    w.click(body);
    w.wait(|r| r["draft"] == true, "the tap to place the cut");
    let config = w.config.clone();
    assert!(w.quit().success());
    // The hint stays gone in the next run.
    let mut again = common::Window::open_with(&dir, &[], &config);
    assert_eq!(again.wait(|_| true, "a report")["hint"], false);
    assert!(again.quit().success());
}

/// The brush as a user meets it: B turns it on (painting the pinning at first), a drag on
/// the model paints instead of turning, Ctrl+Z takes the stroke back, and B again turns it
/// off so a drag turns the part again.
#[test]
fn the_brush_paints_pinning_with_a_drag_and_undo_takes_it_back() {
    let dir = common::scratch("window-brush");
    let mut w = common::Window::open(&dir, &[]);
    let r = w.state().unwrap();
    let at = r["targets"]["root"].clone();
    let at = [at[0].as_f64().unwrap(), at[1].as_f64().unwrap()];
    w.hover([120.0, 400.0]);
    std::thread::sleep(Duration::from_millis(300));
    w.key("b");
    w.wait(|r| r["brush"] == true, "the brush");
    w.drag(at, [40.0, 0.0]);
    let r = w.wait(
        |r| r["painted"].as_u64().unwrap() > 0 && r["pinned"].as_u64().unwrap() > 0,
        "the stroke to pin",
    );
    assert!(
        r["turned"].as_array().unwrap().is_empty(),
        "painting turns nothing: {r}"
    );
    w.key("ctrl+z");
    w.wait(|r| r["pinned"] == 0, "undo to take the stroke back");
    w.key("b");
    w.wait(|r| r["brush"] == false, "the brush off");
    assert!(w.quit().success());
}

/// An animation opened with the window plays at once; Space pauses it, → steps a frame,
/// Home goes back to the start.
#[test]
fn an_animation_plays_pauses_steps_and_restarts() {
    let dir = common::scratch("window-anim");
    let mut w = with_the_jaw_animation(&dir);
    // It plays from the start (it may have finished by the time the window is up).
    w.wait(
        |r| r["animation_time"].as_f64().is_some_and(|t| t > 0.0),
        "the animation to play",
    );
    w.hover([120.0, 400.0]);
    w.key("Home");
    w.wait(
        |r| r["animation_time"] == 0.0 && r["playing"] == false,
        "Home to go back to the start",
    );
    w.key("space");
    w.wait(|r| r["playing"] == true, "Space to play");
    w.key("space");
    let r = w.wait(|r| r["playing"] == false, "Space to pause");
    let paused_at = r["animation_time"].as_f64().unwrap();
    w.key("Right");
    w.wait(
        |r| r["animation_time"].as_f64().unwrap() > paused_at + 0.02,
        "→ to step a frame",
    );
    assert!(w.quit().success());
}

/// The window on Spot with the example rig and its jaw's animation playing.
fn with_the_jaw_animation(dir: &Path) -> common::Window {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples");
    let rig = root.join("spot-jaw.rig.toml");
    let anim = root.join("spot-jaw.anim.toml");
    common::Window::open(
        dir,
        &[
            "--rig",
            rig.to_str().unwrap(),
            "--anim",
            anim.to_str().unwrap(),
        ],
    )
}

/// The still frame: on this software renderer the window draws one sample a pixel while
/// anything moves (an animation playing), its edges smoothed after (FXAA, the default
/// here), and once nothing does (paused), the scene once more with 4 samples a pixel,
/// which the frames after copy until the view changes.
#[test]
fn a_still_view_has_4_samples_and_a_moving_one_is_smoothed() {
    let dir = common::scratch("window-still");
    let mut w = with_the_jaw_animation(&dir);
    w.hover([120.0, 400.0]);
    w.key("Home");
    let r = w.wait(
        |r| r["playing"] == false && r["drawn_samples"] == 4,
        "the still frame, anti-aliased",
    );
    assert_eq!(
        (&r["samples"], &r["anti_aliasing"]),
        (&serde_json::json!(1), &serde_json::json!("fxaa")),
        "the moving view is drawn with one sample and smoothed: {r}"
    );
    w.key("space");
    w.wait(
        |r| r["playing"] == true && r["drawn_samples"] == 1 && r["drawn_fxaa"] == true,
        "a frame of the animation drawn with one sample, smoothed",
    );
    w.key("space");
    w.wait(
        |r| r["playing"] == false && r["drawn_samples"] == 4,
        "paused, the still frame again",
    );
    assert!(w.quit().success());
}

/// Recording with the mouse: Ctrl+R records, a drag on a part turns it, Ctrl+R stops and
/// the take plays with a track for that part; Ctrl+Z takes the take back.
#[test]
fn a_take_is_recorded_with_the_mouse_plays_back_and_undo_takes_it_back() {
    let dir = common::scratch("window-record");
    let mut w = common::Window::open(&dir, &[]);
    let r = w.state().unwrap();
    let (name, at) = common::part_on_screen(&r);
    w.hover([120.0, 400.0]);
    std::thread::sleep(Duration::from_millis(300));
    w.key("ctrl+r");
    w.wait(|r| r["recording"] == true, "Ctrl+R to record");
    w.drag(at, [0.0, 60.0]);
    w.wait(
        |r| !r["turned"].as_array().unwrap().is_empty(),
        "the drag to turn the part",
    );
    w.hover([120.0, 400.0]);
    w.key("ctrl+r");
    let r = w.wait(|r| r["recording"] == false, "Ctrl+R to stop");
    let tracks = r["tracks"].as_array().unwrap();
    assert!(
        tracks.iter().any(|t| t.as_str() == Some(name.as_str())),
        "the take has a track for {name}: {r}"
    );
    assert!(r["animation_time"].is_number(), "the take plays: {r}");
    w.key("ctrl+z");
    w.wait(
        |r| r["animation_time"].is_null(),
        "undo to take the take back",
    );
    assert!(w.quit().success());
}

/// P turns *move pivots* on: the pivots show, a drag from one moves it (the section it
/// belongs to does not turn), and Ctrl+Z puts it back.
#[test]
fn a_pivot_is_dragged_with_the_mouse_and_undo_puts_it_back() {
    let dir = common::scratch("window-pivot");
    let mut w = common::Window::open(&dir, &[]);
    w.hover([120.0, 400.0]);
    std::thread::sleep(Duration::from_millis(300));
    w.key("p");
    let r = w.wait(
        |r| r["move_pivots"] == true && r["pivots"].as_object().is_some_and(|p| !p.is_empty()),
        "move pivots on",
    );
    // The pivot farthest right of the panel, so the drag stays in the view.
    let pivots = r["pivots"].as_object().unwrap();
    let xy = |v: &serde_json::Value| [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()];
    let (name, at) = pivots
        .iter()
        .map(|(n, v)| (n.clone(), xy(v)))
        .max_by(|a, b| a.1[0].total_cmp(&b.1[0]))
        .unwrap();
    // How far (pixels) the pivot is drawn from where the drag started.
    let off = |r: &serde_json::Value| {
        let now = xy(&r["pivots"][&name]);
        (now[0] - at[0]).hypot(now[1] - at[1])
    };
    w.drag(at, [-40.0, 0.0]);
    let r = w.wait(|r| off(r) > 5.0, "the pivot to move");
    assert!(
        r["turned"].as_array().unwrap().is_empty(),
        "moving a pivot turns nothing: {r}"
    );
    w.key("ctrl+z");
    w.wait(|r| off(r) < 0.5, "undo to put the pivot back");
    assert!(w.quit().success());
}

/// What loading repaired shows on the model: the cow with its head cut off opens with its
/// filled neck drawn in orange edges, and the panel's line says what was filled; the same
/// cow whole shows none of that orange.
#[test]
fn a_repaired_mesh_shows_its_filled_hole() {
    let dir = common::scratch("window-repairs");
    let runtime = common::runtime_dir(&dir);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shoot = |mesh: &Path, name: &str| {
        let shot = dir.join(format!("{name}.png"));
        let out = Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1280x800x24"])
            .arg(env!("CARGO_BIN_EXE_puppet"))
            .arg(mesh)
            .arg("--screenshot")
            .arg(&shot)
            .args(["--frames", "5"])
            .env("XDG_RUNTIME_DIR", &runtime)
            .env("RUST_LOG", "error")
            .output()
            .expect("xvfb-run (scripts/setup.sh installs the xvfb package)");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "{stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let report: serde_json::Value =
            serde_json::from_str(stdout.lines().last().unwrap_or("")).unwrap();
        let img = Image::load_png(&shot).unwrap();
        // Orange (the overlay's 1.0, 0.55, 0.1), right of the panel.
        let orange = (360..img.width)
            .flat_map(|x| (0..img.height).map(move |y| (x, y)))
            .map(|(x, y)| img.pixel(x, y))
            .filter(|p| {
                p[0] > 200 && p[1] > 110 && p[1] < 210 && (p[2] as i32) < (p[1] as i32) - 70
            })
            .count();
        (report, orange)
    };
    let (report, orange) = shoot(&root.join("tests/data/defects/open-neck.obj"), "open-neck");
    let message = report["message"].as_str().unwrap_or("");
    assert!(message.contains("filled 1 hole"), "{report}");
    let (_, whole) = shoot(&root.join("tests/data/meshes/spot-small.obj"), "whole");
    assert!(
        orange > 20 * whole.max(10),
        "{orange} orange pixels against {whole}"
    );
}

/// A glove over OSC drives the shipped hand: the test sends the messages a glove would
/// (`assets/examples/glove.toml`), the fingers curl (the report's turned sections), a
/// button records a take that holds the fingers' motion, and hostile packets are counted.
#[test]
fn a_glove_over_osc_curls_the_fingers_and_records_a_take() {
    use puppet::controls::{glove, osc};
    let dir = common::scratch("window-glove");
    let port = common::free_port();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples");
    let arg = |f: &str| root.join(f).display().to_string();
    let (hand, rig, controls) = (arg("hand.obj"), arg("hand.rig.toml"), arg("glove.toml"));
    let mut w = common::Window::open(
        &dir,
        &[
            &hand,
            "--rig",
            &rig,
            "--controls",
            &controls,
            "--listen",
            &port,
        ],
    );
    let socket = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    socket.connect(format!("127.0.0.1:{port}")).unwrap();
    let send = |address: &str, values: &[f32]| {
        socket.send(&osc::encode(address, values)).unwrap();
    };
    let angle = turned;
    // Every finger curled, then hostile packets: garbage, an unknown address, NaN.
    for _ in 0..30 {
        send("/glove/flex", &[1.0; 5]);
        std::thread::sleep(Duration::from_millis(10));
    }
    socket.send(b"not osc at all").unwrap();
    send("/nobody", &[1.0]);
    send("/glove/flex", &[f32::NAN; 5]);
    let r = w.wait(
        |r| angle(r, "index.3") > 60.0 && r["controls"]["bad_packets"] == 1,
        "the index finger to curl",
    );
    assert!(
        angle(&r, "middle") > 60.0 && angle(&r, "thumb") > 40.0,
        "{r}"
    );
    let c = &r["controls"];
    assert_eq!(
        (c["unknown"].as_u64(), c["ignored"].as_u64()),
        (Some(1), Some(5)),
        "{r}"
    );
    // The record button, a second of the synthetic performance, the button again.
    send("/glove/button", &[1.0]);
    send("/glove/button", &[0.0]);
    w.wait(|r| r["recording"] == true, "the button to start a take");
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(1) {
        for (address, values) in glove::performance(start.elapsed().as_secs_f64()) {
            send(address, &values);
        }
        std::thread::sleep(Duration::from_millis(16));
    }
    send("/glove/button", &[1.0]);
    send("/glove/button", &[0.0]);
    let r = w.wait(|r| r["recording"] == false, "the button to stop the take");
    let tracks: Vec<&str> = r["tracks"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|t| t.as_str())
        .collect();
    for name in ["index", "thumb.3", "wrist"] {
        assert!(
            tracks.contains(&name),
            "the take has a track for {name}: {r}"
        );
    }
    assert!(w.quit().success());
}

/// Learning a control as MIDI learn works: with the window listening and no controls yet,
/// L starts learning, a control that moves (OSC here) and a click on a part map one to the
/// other, and from then on the control turns that part.
#[test]
fn learn_maps_the_control_that_moved_to_the_part_clicked() {
    use puppet::controls::osc;
    let dir = common::scratch("window-learn");
    let port = common::free_port();
    let mut w = common::Window::open(&dir, &["--listen", &port]);
    let socket = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    socket.connect(format!("127.0.0.1:{port}")).unwrap();
    let send = |values: &[f32]| {
        socket.send(&osc::encode("/knob", values)).unwrap();
    };
    let r = w.state().unwrap();
    let (name, at) = common::part_on_screen(&r);
    w.hover([120.0, 400.0]);
    std::thread::sleep(Duration::from_millis(300));
    w.key("l");
    w.wait(
        |r| r["controls"]["learning"].is_string(),
        "L to start learning",
    );
    // The knob's second value sweeps; its first only jitters.
    for k in 0..=10 {
        send(&[0.5 + 0.001 * (k % 2) as f32, 0.1 * k as f32]);
        std::thread::sleep(Duration::from_millis(10));
    }
    w.wait(
        |r| {
            r["controls"]["learning"]
                .as_str()
                .is_some_and(|l| l.starts_with("moved: /knob 1"))
        },
        "the moved control to be named",
    );
    w.click(at);
    let r = w.wait(
        |r| {
            r["controls"]["values"]
                .as_array()
                .is_some_and(|v| !v.is_empty())
        },
        "the click to map the control",
    );
    assert_eq!(r["controls"]["values"][0][0], name.as_str(), "{r}");
    assert!(
        r["message"]
            .as_str()
            .unwrap_or("")
            .contains("learned: /knob 1"),
        "{r}"
    );
    w.key("l");
    w.wait(
        |r| r["controls"]["learning"].is_null(),
        "L to stop learning",
    );
    // The knob turned all the way is the part turned 90°.
    let angle = |r: &serde_json::Value| turned(r, &name);
    for _ in 0..30 {
        send(&[0.5, 1.0]);
        std::thread::sleep(Duration::from_millis(10));
    }
    w.wait(|r| angle(r) > 85.0, "the knob to turn the part");
    assert!(w.quit().success());
}

/// With collision on, an arm dragged into the body stops at it: the human's right arm,
/// dragged sideways so that it swings forward and across the chest, turns no further than
/// where it meets the body; the same drag with collision off swings it on through.
/// The human with its arms cut at the shoulders (`tests/data/human-arms.rig.toml`, collision
/// on), and the same rig with collision off written into `dir`.
fn human_arms(dir: &Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let on = root.join("tests/data/human-arms.rig.toml");
    let text = std::fs::read_to_string(&on).unwrap();
    let mesh = root.join("tests/data/meshes/human.obj");
    let off = dir.join("human-arms-off.rig.toml");
    std::fs::write(
        &off,
        text.replace("collision = true", "collision = false")
            .replace("meshes/human.obj", mesh.to_str().unwrap()),
    )
    .unwrap();
    (on, off)
}

#[test]
fn an_arm_dragged_into_the_body_stops_at_it() {
    let dir = common::scratch("window-collide");
    let (on, off) = human_arms(&dir);
    let drag = |rig: &Path, name: &str| -> f64 {
        let mut w = common::Window::open(&dir.join(name), &["--rig", rig.to_str().unwrap()]);
        let r = w.state().unwrap();
        let angle = |r: &serde_json::Value| turned(r, "right arm");
        let at = target(&r, "right arm");
        // A sideways drag swings the arm about the vertical through the shoulder: forward,
        // then across the chest (650 pixels of an 800-pixel view: about 146°).
        w.drag(at, [650.0, 0.0]);
        w.wait(|r| angle(r) > 30.0, "the drag to turn the arm");
        // Until it stops turning (an arm still turning after a minute fails).
        let mut last = -1.0;
        let start = Instant::now();
        loop {
            std::thread::sleep(Duration::from_millis(400));
            let now = angle(&w.state().unwrap());
            if (now - last).abs() < 0.05 {
                break;
            }
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "the arm still turns after 60 s: {last}° then {now}°"
            );
            last = now;
        }
        assert!(w.quit().success());
        last
    };
    let stopped = drag(&on, "on");
    let free = drag(&off, "off");
    assert!(
        free > stopped + 10.0,
        "with collision the arm stopped at {stopped}°, without it turned {free}°"
    );
}

/// An elbow bent with the mouse: the forearm, cut from the upper arm, turns, its band
/// bends as an arc (two limbs meet, `joints::band`), and the puppet settles to sleep.
#[test]
fn an_elbow_bent_with_the_mouse_bends_and_settles() {
    let dir = common::scratch("window-elbow");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("tests/data/human-arms.rig.toml")).unwrap();
    let mesh = root.join("tests/data/meshes/human.obj");
    let elbow = puppet::puppet::bend::JOINTS[0];
    let rig = dir.join("human-elbow.rig.toml");
    std::fs::write(
        &rig,
        format!(
            "{}\n[[cut]]\nname = \"right forearm\"\nsection = \"right arm\"\npoint = [{}, {}, {}]\nnormal = [{}, {}, {}]\nconnected = true\n",
            text.replace("meshes/human.obj", mesh.to_str().unwrap()),
            elbow.point.x,
            elbow.point.y,
            elbow.point.z,
            elbow.normal.x,
            elbow.normal.y,
            elbow.normal.z,
        ),
    )
    .unwrap();
    let spec = puppet::puppet::RigFile::load(&rig).unwrap();
    let (m, _) = puppet::mesh::load(&mesh).unwrap();
    let p = puppet::Puppet::build(m, spec, puppet::progress::silent()).unwrap();
    let k = p
        .joints
        .cuts()
        .iter()
        .position(|c| c.name == "right forearm");
    let band = k.and_then(|k| p.joints.bands()[k].clone()).expect("a band");
    assert!(band.arc, "{band:?}");

    let mut w = common::Window::open(&dir, &["--rig", rig.to_str().unwrap()]);
    let r = w.state().unwrap();
    let angle = |r: &serde_json::Value| turned(r, "right forearm");
    let at = target(&r, "right forearm");
    w.drag(at, [0.0, 200.0]);
    w.wait(|r| angle(r) > 20.0, "the drag to bend the elbow");
    let settled = w.wait(|r| r["state"] == "settled", "the bent puppet to settle");
    assert!(angle(&settled) > 20.0, "{settled}");
    assert!(w.quit().success());
}

/// A head nodded with the mouse keeps its skin whole: the human, opened without a rig, opens
/// with its suggested joints (the head's cut runs across the face), the head dragged about 45°, settled; no edge of
/// the surface stretches past 3× (without the bands blended over the surface,
/// `joints::blend`, the lips tear).
#[test]
fn a_head_nodded_with_the_mouse_keeps_its_skin_whole() {
    let dir = common::scratch("window-nod");
    let mesh = common::test_mesh("human.obj");
    // A mesh opened without a rig opens with its suggested joints.
    let mut w = common::Window::open(&dir, &[mesh.to_str().unwrap()]);
    let r = w.wait(
        |r| r["targets"]["head"].is_array(),
        "the head to be drawn with its suggested joints",
    );
    let at = target(&r, "head");
    w.drag(at, [0.0, 120.0]);
    w.wait(|r| turned(r, "head") > 20.0, "the drag to nod the head");
    let settled = w.wait(|r| r["state"] == "settled", "the nodded puppet to settle");
    let angle = turned(&settled, "head");
    assert!(angle > 20.0, "{settled}");
    let stretch = settled["stretch"].as_f64().unwrap();
    assert!(
        stretch <= 3.0,
        "nodded {angle:.0}°: an edge stretched {stretch:.2}×"
    );
    assert!(w.quit().success());
}

/// An animation that swings the right arm 120° down through the body: with collision on it
/// plays with the arm stopping at the body's side, as a drag does; off, it turns the whole
/// way.
#[test]
fn an_animation_that_swings_an_arm_through_the_body_stops_it_there() {
    let dir = common::scratch("window-anim-collide");
    let (on, off) = human_arms(&dir);
    let anim = dir.join("swing.anim.toml");
    std::fs::write(
        &anim,
        "duration = 1.5\n[[track]]\nsection = \"right arm\"\nease = \"smooth\"\nkey = [ { time = 0.0, axis = [0, 0, 1], angle = 0 }, { time = 1.0, axis = [0, 0, 1], angle = 120 } ]\n",
    )
    .unwrap();
    let play = |rig: &Path, name: &str| -> f64 {
        let mut w = common::Window::open(
            &dir.join(name),
            &[
                "--rig",
                rig.to_str().unwrap(),
                "--anim",
                anim.to_str().unwrap(),
            ],
        );
        let r = w.wait(
            |r| r["animation_time"].as_f64().is_some_and(|t| t >= 1.2),
            "the swing to end",
        );
        assert!(w.quit().success());
        turned(&r, "right arm")
    };
    let stopped = play(&on, "on");
    let free = play(&off, "off");
    assert!(
        stopped < 100.0 && free > 115.0,
        "with collision the arm stopped at {stopped}°, without it turned {free}°"
    );
}

/// A skinned glTF opens rigged by its skin (the file's joint names), lists its clips, and
/// plays one through the puppet: the arm the clip swings turns, and holds at the end.
#[test]
fn a_skinned_file_opens_with_its_joints_and_plays_a_clip() {
    let dir = common::scratch("window-skin");
    let figure = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf/skinned-figure.glb");
    let mut w = common::Window::open(&dir, &[figure.to_str().unwrap(), "--clip", "raise"]);
    let r = w.wait(
        |r| r["animation_time"].as_f64().is_some_and(|t| t >= 1.0),
        "the arm to be raised",
    );
    assert!(w.quit().success());
    let sections: Vec<&str> = r["sections"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    assert_eq!(sections[0], "spine");
    for name in ["upper_arm.R", "forearm.R", "hand.R", "thigh.L", "head"] {
        assert!(sections.contains(&name), "{name} in {sections:?}");
    }
    assert_eq!(r["clips"], serde_json::json!(["raise", "walk", "wave"]));
    assert!(
        r["tracks"].as_array().unwrap().len() >= 15,
        "{}",
        r["tracks"]
    );
    // The clip swings the right arm 70° forward and holds it there.
    let raised = turned(&r, "upper_arm.R");
    assert!((raised - 70.0).abs() < 5.0, "the arm turned {raised}°: {r}");
}

/// The window's look as a user meets it on this software renderer: the ground on and one
/// sample a pixel smoothed by FXAA by default (4 samples would cost two to three times the
/// frame here), and 4 samples when the settings say the user turned them on (an earlier
/// version's `anti_aliasing = true`); the studio's lights, the
/// matcap the settings remember, or the one `--lighting` names for one run.
#[test]
fn the_window_draws_the_ground_and_anti_aliases_when_the_user_asked() {
    let dir = common::scratch("window-look");
    let w = common::Window::open(&dir, &[]);
    let r = w.state().unwrap();
    assert_eq!(
        (r["samples"].as_u64(), r["ground"].as_bool()),
        (Some(1), Some(true)),
        "{r}"
    );
    assert_eq!(r["lighting"], "studio", "{r}");
    assert_eq!(r["anti_aliasing"], "fxaa", "{r}");
    let config = w.config.clone();
    assert!(w.quit().success());
    let settings = config.join("settings.toml");
    std::fs::write(&settings, "anti_aliasing = true\nlighting = \"clay\"\n").unwrap();
    let w = common::Window::open_with(&dir, &[], &config);
    let r = w.state().unwrap();
    assert_eq!(
        (r["samples"].as_u64(), r["lighting"].as_str()),
        (Some(4), Some("clay matcap")),
        "{r}"
    );
    assert!(w.quit().success());
    // `--lighting` for one run: the settings keep the panel's choice.
    let w = common::Window::open_with(&dir, &["--lighting", "jelly"], &config);
    assert_eq!(w.state().unwrap()["lighting"], "jelly matcap");
    assert!(w.quit().success());
    let kept = std::fs::read_to_string(&settings).unwrap();
    assert!(kept.contains("lighting = \"clay\""), "{kept}");
}
