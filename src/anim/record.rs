//! A recorded take as keys: the pose of every section sampled at each simulation step,
//! thinned to a tolerance so a take stays small and editable.
//!
//! Thinning is greedy: from the last key kept, a key is added only where the animation's
//! own interpolation between the last key and a later sample would miss some sample in
//! between by more than the tolerance (in degrees of rotation, and that share of the
//! model's size in translation). The check uses the sampler that plays the file, so what
//! plays back is within the tolerance of what was recorded.

use super::{sample_track, Animation, Ease, Key, Track};
use crate::joints::Local;
use glam::DVec3;

/// Samples of one take: times (seconds from its start) and every section's local pose.
#[derive(Clone, Debug, Default)]
pub struct Samples {
    /// Sample times, increasing.
    pub times: Vec<f64>,
    /// Per sample, the local pose of every section.
    pub poses: Vec<Vec<Local>>,
}

/// The key of a local pose at `time`.
fn key_of(time: f64, l: &Local) -> Key {
    let q = l.rotation.normalize();
    let (axis, angle) = q.to_axis_angle();
    let (axis, angle) = if angle.is_finite() && axis.is_finite() && angle.abs() > 1e-12 {
        (axis, angle.to_degrees())
    } else {
        (DVec3::Z, 0.0)
    };
    Key {
        time,
        axis: axis.to_array(),
        angle,
        translation: (l.translation != DVec3::ZERO).then(|| l.translation.to_array()),
    }
}

/// How far apart two local poses are: degrees of rotation, and translation over `size`
/// counted in the same units (1° per `size / 360`).
fn miss(a: &Local, b: &Local, size: f64) -> f64 {
    let angle = a.rotation.angle_between(b.rotation).to_degrees();
    let moved = (a.translation - b.translation).length() / size.max(1e-300) * 360.0;
    angle.max(moved)
}

impl Samples {
    /// The take as an animation: one track per section that is not at rest throughout
    /// (`names` by section; a section held turned needs its one key, since sections without
    /// a track play at rest), keys thinned to `tolerance` degrees; `size` is the model's
    /// size (for translations). No track at all when nothing moved during the take.
    pub fn to_animation(&self, names: &[String], tolerance: f64, size: f64) -> Animation {
        let tolerance = if tolerance.is_finite() {
            tolerance.max(0.0)
        } else {
            0.0
        };
        let duration = self.times.last().copied().unwrap_or(0.0).max(1e-6);
        let mut track = Vec::new();
        // A take in which no section moved is empty (a held pose is not a performance).
        let first = self.poses.first();
        let moved = self.poses.iter().any(|p| Some(p) != first);
        if !moved {
            return Animation {
                duration,
                looping: false,
                track,
            };
        }
        for (s, name) in names.iter().enumerate() {
            let locals: Vec<Local> = self
                .poses
                .iter()
                .map(|p| p.get(s).copied().unwrap_or_default())
                .collect();
            let still = locals
                .iter()
                .all(|l| miss(l, &Local::default(), size) == 0.0);
            if locals.is_empty() || still {
                continue;
            }
            track.push(thin(&self.times, name, &locals, tolerance, size));
        }
        Animation {
            duration,
            looping: false,
            track,
        }
    }
}

/// One section's samples (`locals` at `times`) as a linear track thinned greedily to
/// `tolerance` degrees (see the module docs); `size` is the model's size (translations).
///
/// # Panics
/// When `times` or `locals` is empty.
pub fn thin(times: &[f64], name: &str, locals: &[Local], tolerance: f64, size: f64) -> Track {
    let mut keys = vec![key_of(times[0], &locals[0])];
    let mut last = 0;
    let n = locals.len().min(times.len());
    let mut j = 1;
    while j < n {
        // Can the segment from `last` reach `j + 1` and still pass every sample?
        let fits = |end: usize| {
            let t = Track {
                section: name.into(),
                ease: Ease::Linear,
                key: vec![
                    keys[keys.len() - 1].clone(),
                    key_of(times[end], &locals[end]),
                ],
            };
            (last + 1..end)
                .all(|k| miss(&sample_track(&t, times[k]), &locals[k], size) <= tolerance)
        };
        if j + 1 < n && fits(j + 1) {
            j += 1;
            continue;
        }
        keys.push(key_of(times[j], &locals[j]));
        last = j;
        j += 1;
    }
    Track {
        section: name.into(),
        ease: Ease::Linear,
        key: keys,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_steady_turn_thins_to_its_ends_and_a_turn_back_keeps_its_corner() {
        let h = 1.0 / 60.0;
        let mut s = Samples::default();
        for k in 0..=120 {
            let t = k as f64 * h;
            // 0° to 90° over 1 s about x, then back to 45° over the next second.
            let deg = if t <= 1.0 {
                90.0 * t
            } else {
                90.0 - 45.0 * (t - 1.0)
            };
            s.times.push(t);
            s.poses
                .push(vec![Local::default(), Local::axis_angle(DVec3::X, deg)]);
        }
        let names = vec!["root".to_string(), "arm".to_string()];
        let a = s.to_animation(&names, 0.5, 1.0);
        assert_eq!(a.track.len(), 1, "the still root has no track");
        let keys = &a.track[0].key;
        assert!(keys.len() <= 4, "{} keys", keys.len());
        assert!(a.check().is_ok());
        // Played back, every sample is within the tolerance.
        for (k, t) in s.times.iter().enumerate() {
            let got = sample_track(&a.track[0], *t);
            assert!(miss(&got, &s.poses[k][1], 1.0) <= 0.5 + 1e-9, "sample {k}");
        }
        // Tolerance 0 keeps what it must (a straight line still thins).
        assert!(s.to_animation(&names, 0.0, 1.0).track[0].key.len() < 121);
    }
}
