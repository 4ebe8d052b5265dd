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
