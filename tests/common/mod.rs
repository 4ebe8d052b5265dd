//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh scratch directory under the target dir, named after the test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// Runs the `puppet` binary.
pub fn puppet(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_puppet"))
        .args(args)
        .env("RUST_LOG", "warn")
        .output()
        .expect("run puppet")
}

/// A file of `assets/examples` (the example rig and animation), as a path string.
pub fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/examples")
        .join(name)
        .display()
        .to_string()
}

/// Asserts that a command exited with status 0 (showing its stderr otherwise).
pub fn ok(out: &Output) {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A test mesh from `tests/data/meshes` (credits in its README).
pub fn test_mesh(name: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/meshes")
        .join(name);
    assert!(
        p.exists(),
        "test mesh {} is missing (tests/data/meshes)",
        p.display()
    );
    p
}

/// Approximate equality with a relative tolerance.
pub fn approx(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
}

/// A part other than the root with a visible pixel in a window report: its name and where
/// to click it.
pub fn part_on_screen(report: &serde_json::Value) -> (String, [f64; 2]) {
    report["targets"]
        .as_object()
        .expect("targets in the report")
        .iter()
        .find(|(n, _)| n.as_str() != "root")
        .map(|(n, a)| (n.clone(), [a[0].as_f64().unwrap(), a[1].as_f64().unwrap()]))
        .expect("a part on screen")
}

/// The real window under Xvfb, driven with xdotool the way a user would, its state read
/// from the app's `--report` file.
pub struct Window {
    child: std::process::Child,
    /// Where the app writes what it shows.
    pub report: PathBuf,
    /// The app's settings folder (a fresh one per test).
    pub config: PathBuf,
    display: String,
    xauthority: Option<String>,
    pid: u32,
    window: String,
}

/// `DIR/xdg`, made private to its owner as `XDG_RUNTIME_DIR` must be, for a window run in
/// `dir`.
pub fn runtime_dir(dir: &Path) -> PathBuf {
    let runtime = dir.join("xdg");
    std::fs::create_dir_all(&runtime).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&runtime, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
    runtime
}

impl Window {
    /// Starts `puppet ARGS` in a virtual X server in `dir` and waits until its puppet is
    /// built and settled.
    pub fn open(dir: &Path, args: &[&str]) -> Window {
        runtime_dir(dir);
        let config = dir.join("config");
        std::fs::create_dir_all(&config).unwrap();
        Window::open_with(dir, args, &config)
    }

    /// As [`Window::open`], with the settings in `config`.
    pub fn open_with(dir: &Path, args: &[&str], config: &Path) -> Window {
        let report = dir.join("report.json");
        let _ = std::fs::remove_file(&report);
        let child = Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1280x800x24"])
            .arg(env!("CARGO_BIN_EXE_puppet"))
            .args(args)
            .arg("--report")
            .arg(&report)
            .env("XDG_RUNTIME_DIR", dir.join("xdg"))
            .env("PUPPET_CONFIG_DIR", config)
            .env("RUST_LOG", "warn")
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("xvfb-run (scripts/setup.sh installs it)");
        let mut w = Window {
            child,
            report,
            config: config.to_path_buf(),
            display: String::new(),
            xauthority: None,
            pid: 0,
            window: String::new(),
        };
        let r = w.wait(|r| r["state"] == "settled", "the puppet to settle");
        w.display = r["display"].as_str().unwrap_or(":99").to_string();
        w.xauthority = r["xauthority"].as_str().map(str::to_string);
        w.pid = r["pid"].as_u64().unwrap() as u32;
        let found = w.xdo(&["search", "--sync", "--pid", &w.pid.to_string()]);
        w.window = found.lines().last().unwrap_or("").trim().to_string();
        assert!(!w.window.is_empty(), "no window of pid {}", w.pid);
        w
    }

    /// The app's last report.
    pub fn state(&self) -> Option<serde_json::Value> {
        let text = std::fs::read_to_string(&self.report).ok()?;
        serde_json::from_str(&text).ok()
    }

    /// Waits (at most 60 s) until the report satisfies `ok`; returns it.
    pub fn wait(
        &mut self,
        ok: impl Fn(&serde_json::Value) -> bool,
        what: &str,
    ) -> serde_json::Value {
        let start = std::time::Instant::now();
        loop {
            if let Some(r) = self.state() {
                if ok(&r) {
                    return r;
                }
            }
            if let Ok(Some(status)) = self.child.try_wait() {
                panic!("the app exited ({status}) while waiting for {what}");
            }
            assert!(
                start.elapsed() < std::time::Duration::from_secs(60),
                "timed out waiting for {what}: {:?}",
                self.state()
            );
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
    }

    /// Runs xdotool on the window's display; returns its output.
    pub fn xdo(&self, args: &[&str]) -> String {
        let mut cmd = Command::new("xdotool");
        cmd.args(args).env("DISPLAY", &self.display);
        if let Some(a) = &self.xauthority {
            cmd.env("XAUTHORITY", a);
        }
        let out = cmd
            .output()
            .expect("xdotool (scripts/setup.sh installs it)");
        assert!(
            out.status.success(),
            "xdotool {args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// Moves the pointer to a pixel of the window.
    pub fn hover(&self, at: [f64; 2]) {
        let (x, y) = (format!("{}", at[0].round()), format!("{}", at[1].round()));
        self.xdo(&["mousemove", "--window", &self.window, &x, &y]);
    }

    /// A click (press and release at once, as a tap) at a pixel of the window.
    pub fn click(&self, at: [f64; 2]) {
        let (x, y) = (format!("{}", at[0].round()), format!("{}", at[1].round()));
        self.xdo(&["mousemove", "--window", &self.window, &x, &y, "click", "1"]);
    }

    /// A drag with the left button from a pixel, by `(dx, dy)`, in a few moves.
    pub fn drag(&self, at: [f64; 2], by: [f64; 2]) {
        let p = |k: f64| {
            [
                format!("{}", (at[0] + by[0] * k).round()),
                format!("{}", (at[1] + by[1] * k).round()),
            ]
        };
        let [x, y] = p(0.0);
        self.xdo(&[
            "mousemove",
            "--window",
            &self.window,
            &x,
            &y,
            "mousedown",
            "1",
        ]);
        for k in 1..=5 {
            let [x, y] = p(k as f64 / 5.0);
            self.xdo(&["mousemove", "--window", &self.window, &x, &y]);
            std::thread::sleep(std::time::Duration::from_millis(30));
        }
        self.xdo(&["mouseup", "1"]);
    }

    /// Keys, as xdotool names them (`c`, `ctrl+q`), to the window. Under load the X server
    /// now and then loses a synthetic key press; the report counts the presses the window
    /// got, so a press that did not arrive within a few seconds is sent again.
    pub fn key(&self, keys: &str) {
        let presses = keys.split('+').count() as u64;
        let before = self.state().and_then(|r| r["keys"].as_u64());
        for _ in 0..3 {
            self.xdo(&["windowfocus", "--sync", &self.window]);
            self.xdo(&["key", keys]);
            let Some(before) = before else {
                return;
            };
            let start = std::time::Instant::now();
            while start.elapsed() < std::time::Duration::from_secs(5) {
                let got = self.state().and_then(|r| r["keys"].as_u64());
                if got.is_none_or(|k| k >= before + presses) {
                    return;
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            eprintln!("the window did not get {keys}: sending it again");
        }
    }

    /// The app's CPU time so far, in clock ticks (user + system).
    pub fn cpu_ticks(&self) -> u64 {
        let stat = std::fs::read_to_string(format!("/proc/{}/stat", self.pid)).unwrap();
        // The fields after the command name (which may hold spaces) start after the last ')'.
        let rest = &stat[stat.rfind(')').unwrap() + 2..];
        let fields: Vec<&str> = rest.split_whitespace().collect();
        fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap()
    }

    /// Closes the window with Ctrl+Q and waits for the app to exit; its status.
    pub fn quit(mut self) -> std::process::ExitStatus {
        self.key("ctrl+q");
        let start = std::time::Instant::now();
        loop {
            if let Some(s) = self.child.try_wait().unwrap() {
                return s;
            }
            assert!(
                start.elapsed() < std::time::Duration::from_secs(30),
                "the app did not quit"
            );
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
    }
}

impl Drop for Window {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            if self.pid != 0 {
                let _ = Command::new("kill").arg(self.pid.to_string()).status();
            }
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// A mesh as OBJ text.
pub fn obj(mesh: &puppet::mesh::Mesh) -> Vec<u8> {
    let mut out = Vec::new();
    puppet::mesh::write_obj(&mut out, &mesh.positions, &mesh.triangles, "test").unwrap();
    out
}

/// ASCII and little-endian binary PLY of a mesh (with a normal property and a quad-free
/// face list), and ASCII and binary STL.
pub fn ply_ascii(m: &puppet::mesh::Mesh) -> Vec<u8> {
    let mut s = format!(
        "ply\nformat ascii 1.0\ncomment test\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        m.positions.len(),
        m.triangles.len()
    );
    for p in &m.positions {
        s.push_str(&format!(
            "{} {} {} 0 0 1\n",
            p.x as f32, p.y as f32, p.z as f32
        ));
    }
    for t in &m.triangles {
        s.push_str(&format!("3 {} {} {}\n", t[0], t[1], t[2]));
    }
    s.into_bytes()
}

pub fn ply_binary(m: &puppet::mesh::Mesh) -> Vec<u8> {
    let mut b = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\nelement face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        m.positions.len(),
        m.triangles.len()
    )
    .into_bytes();
    for p in &m.positions {
        for x in p.to_array() {
            b.extend_from_slice(&x.to_le_bytes());
        }
    }
    for t in &m.triangles {
        b.push(3);
        for v in t {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }
    b
}

pub fn stl_ascii(m: &puppet::mesh::Mesh) -> Vec<u8> {
    let mut s = String::from("solid test\n");
    for t in &m.triangles {
        s.push_str(" facet normal 0 0 0\n  outer loop\n");
        for &v in t {
            let p = m.positions[v as usize];
            s.push_str(&format!(
                "   vertex {} {} {}\n",
                p.x as f32, p.y as f32, p.z as f32
            ));
        }
        s.push_str("  endloop\n endfacet\n");
    }
    s.push_str("endsolid test\n");
    s.into_bytes()
}

pub fn stl_binary(m: &puppet::mesh::Mesh) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&(m.triangles.len() as u32).to_le_bytes());
    for t in &m.triangles {
        b.extend_from_slice(&[0u8; 12]);
        for &v in t {
            for x in m.positions[v as usize].to_array() {
                b.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        b.extend_from_slice(&[0, 0]);
    }
    b
}

/// A UDP port free on this machine now (for a window to listen on).
pub fn free_port() -> String {
    std::net::UdpSocket::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
        .to_string()
}

/// Whether the tests run under CI (`CI` set, as CI services and `.ci/run`'s callers set
/// it): there a tool a check needs must be here.
pub fn under_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| !v.is_empty() && v != "false" && v != "0")
}

/// The Khronos validator, when Node and the validator (`scripts/setup.sh`) are here: no
/// error and no warning. Under CI a missing validator fails the test.
pub fn validate(glb: &Path) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let modules = root.join("target/npm/node_modules");
    let node = std::process::Command::new("node").arg("--version").output();
    if node.is_err() || !modules.join("gltf-validator").exists() {
        assert!(
            !under_ci(),
            "gltf-validator not installed: scripts/setup.sh installs Node and the validator"
        );
        eprintln!("gltf-validator not installed (scripts/setup.sh installs it): not run");
        return;
    }
    let out = std::process::Command::new("node")
        .arg(root.join("tests/data/gltf-validate.js"))
        .arg(glb)
        .env("NODE_PATH", &modules)
        .output()
        .unwrap();
    ok(&out);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["errors"], 0, "{report}");
    assert_eq!(report["warnings"], 0, "{report}");
}

/// The OBJ files of `tests/data/<folder>`, sorted.
pub fn data_objs(folder: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(folder);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    files.sort();
    files
}

/// The mesh at `path` loaded as the app loads it, built into a puppet with its suggested
/// joints.
pub fn suggested(path: &Path) -> puppet::Puppet {
    let mut p = built(path);
    p.suggest_joints().expect("suggested joints");
    p
}

/// As [`suggested`], the joints suggested from the skeleton even where the file has a
/// skin (`--ignore-skin`, as `bench poses` poses the downloads).
pub fn suggested_from_shape(path: &Path) -> puppet::Puppet {
    let mut p = built(path);
    p.ignore_skin = true;
    p.suggest_joints().expect("suggested joints");
    p
}

/// The puppet of the mesh at `path`, loaded and repaired as the window opens it.
fn built(path: &Path) -> puppet::Puppet {
    let (mesh, report) = puppet::mesh::load_with(
        path,
        &puppet::mesh::LoadOptions::default(),
        puppet::progress::silent(),
    )
    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    puppet::Puppet::build_loaded(
        mesh,
        Some(&report),
        puppet::RigFile::default(),
        puppet::progress::silent(),
    )
    .expect("a puppet")
}

/// Frame `k` (1-based) of `video`, decoded by `ffmpeg` into `png` and read back.
#[cfg(feature = "gui")]
#[allow(dead_code)]
pub fn decoded_frame(video: &Path, k: usize, png: &Path) -> puppet::render::Image {
    ok(&Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-i"])
        .arg(video)
        .args([
            "-vf",
            &format!("select=eq(n\\,{})", k - 1),
            "-frames:v",
            "1",
        ])
        .arg(png)
        .output()
        .expect("run ffmpeg"));
    puppet::render::Image::load_png(png).expect("a decoded frame")
}

/// What `ffprobe` reads of `video`'s first video stream: frames counted, width, height,
/// duration (JSON, as `ffprobe` writes it).
#[allow(dead_code)]
pub fn probed(video: &Path) -> serde_json::Value {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=nb_read_frames,width,height,duration",
        ])
        .args(["-of", "json"])
        .arg(video)
        .output()
        .expect("run ffprobe");
    ok(&out);
    let probe: serde_json::Value = serde_json::from_slice(&out.stdout).expect("ffprobe's JSON");
    probe["streams"][0].clone()
}
