//! The bench command's contract: usage errors exit 2, `--json` carries the documented fields.

mod common;
use common::puppet;

#[test]
fn bench_needs_something_to_measure() {
    let out = puppet(&["bench"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: nothing to measure"));
}

#[test]
fn subdivisions_are_capped() {
    let out = puppet(&["bench", "--sim", "--subdivisions", "9"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--subdivisions"));
}

#[test]
fn sim_bench_json_has_the_documented_fields() {
    let out = puppet(&[
        "bench",
        "--sim",
        "--subdivisions",
        "0",
        "--steps",
        "5",
        "--json",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let row = &rows[0];
    for key in [
        "vertices",
        "springs",
        "steps",
        "ms_per_step_median",
        "ms_per_step_p95",
        "springs_per_second",
        "method",
    ] {
        assert!(row.get(key).is_some(), "missing {key}: {row}");
    }
    assert_eq!(row["vertices"], 2930);
    assert_eq!(row["steps"], 5);
    assert_eq!(row["method"], "circumsphere");
}
