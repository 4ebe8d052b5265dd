//! A synthetic glove performance, for trying the controls without hardware
//! (`puppet send-osc`) and for tests: five fingers curling and opening, each at its own
//! pace, and the wrist turning a little, as the OSC messages `assets/examples/glove.toml`
//! reads.

use glam::DQuat;
use std::f64::consts::TAU;

/// The messages a glove sends at `t` seconds: `/glove/flex` with five flex values (0
/// straight, 1 curled) and `/glove/wrist` with a quaternion `w x y z`.
pub fn performance(t: f64) -> Vec<(&'static str, Vec<f32>)> {
    let flex: Vec<f32> = (0..5)
        .map(|k| {
            let period = 2.0 + 0.35 * k as f64;
            (0.5 - 0.5 * (TAU * t / period + 0.6 * k as f64).cos()) as f32
        })
        .collect();
    let q = DQuat::from_rotation_z(0.35 * (TAU * t / 5.0).sin())
        * DQuat::from_rotation_x(0.2 * (TAU * t / 3.0).sin());
    vec![
        ("/glove/flex", flex),
        (
            "/glove/wrist",
            vec![q.w as f32, q.x as f32, q.y as f32, q.z as f32],
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_performance_reads_through_the_example_glove() {
        let text = include_str!("../../assets/examples/glove.toml");
        let file = super::super::ControlsFile::parse(text).unwrap();
        let names = [
            "root", "wrist", "forearm", "thumb", "thumb.2", "thumb.3", "little", "little.2",
            "little.3", "ring", "ring.2", "ring.3", "index", "index.2", "index.3", "middle",
            "middle.2", "middle.3",
        ];
        let mut c = super::super::Controls::new(file, &names).unwrap();
        for k in 0..120 {
            let t = k as f64 / 60.0;
            for (address, args) in performance(t) {
                let bytes = super::super::osc::encode(address, &args);
                for e in super::super::osc::decode(&bytes).unwrap() {
                    c.feed(&e, t);
                }
            }
        }
        assert_eq!((c.unknown, c.ignored), (0, 0));
        let mut local = vec![crate::joints::Local::default(); names.len()];
        let touched = c.apply(&mut local);
        assert_eq!(touched.len(), 16, "five fingers of three and the wrist");
        assert!(local.iter().all(|l| l.rotation.is_finite()));
    }
}
