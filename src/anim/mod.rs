//! Animations: keyframes per named section, read from TOML or JSON, sampled at any time.
//!
//! ```toml
//! duration = 2.0            # seconds; after it the last pose holds (or `looping = true`)
//! [[track]]
//! section = "jaw"           # a section of the rig
//! ease = "smooth"           # "linear" (default) or "smooth" (ease in and out per segment)
//! key = [
//!   { time = 0.0, axis = [1, 0, 0], angle = 0 },
//!   { time = 1.0, axis = [1, 0, 0], angle = 40 },   # degrees about the axis
//!   { time = 2.0, axis = [1, 0, 0], angle = 0, translation = [0, 0, 0] },
//! ]
//! ```
//!
//! Each key is the section's local rotation about its pivot (see [`crate::joints`]). Between
//! keys the rotation is interpolated by slerp; when both keys share an axis the angle is
//! interpolated instead, which is the same path for turns under 180° and keeps the turn
//! the file asks for beyond it (0° → 270° turns three quarters, not a quarter back).
//! Translations are interpolated linearly. Before the first key the first holds.
//!
//! Files: this one (the format, checking, binding to sections, sampling); `record`
//! (a take thinned to keys); `clip` (a skinned glTF's clip as an animation).

pub mod clip;
pub mod record;

use crate::files::{self, Format};
use crate::joints::{Joints, Local};
use glam::{DQuat, DVec3};

/// Interpolation between keys.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Ease {
    /// Constant angular speed within a segment.
    #[default]
    Linear,
    /// Smoothstep in time: starts and stops at rest at every key.
    Smooth,
}

/// One keyframe.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Key {
    /// Seconds from the start, in `[0, duration]`, increasing within a track.
    pub time: f64,
    /// Rotation axis (any non-zero length; ignored when `angle` is 0).
    #[serde(default = "default_axis")]
    pub axis: [f64; 3],
    /// Rotation angle in degrees.
    #[serde(default)]
    pub angle: f64,
    /// Translation after the rotation (mostly for the root).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translation: Option<[f64; 3]>,
}

fn default_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

/// The keys of one section.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Track {
    /// The section the keys turn.
    pub section: String,
    /// How the keys are interpolated.
    #[serde(default)]
    pub ease: Ease,
    /// The keys, in time order.
    pub key: Vec<Key>,
}

/// An animation file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Animation {
    /// Length in seconds (> 0).
    pub duration: f64,
    /// Start over after `duration` instead of holding the last pose.
    #[serde(default)]
    pub looping: bool,
    /// One track per posed section.
    #[serde(default)]
    pub track: Vec<Track>,
}

/// What is wrong with an animation; the message says where.
#[derive(Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct AnimError(pub String);

impl Animation {
    /// Parses and checks an animation (sections are checked by [`Animation::bind`]).
    pub fn parse(text: &str, format: Format) -> Result<Animation, AnimError> {
        let anim: Animation = files::parse(text, format).map_err(|e| AnimError(e.to_string()))?;
        anim.check()?;
        Ok(anim)
    }

    /// Checks values: finite numbers, a positive duration, keys in time order inside it,
    /// non-zero axes, one track per section.
    pub fn check(&self) -> Result<(), AnimError> {
        let err = |m: String| Err(AnimError(m));
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return err(format!(
                "duration = {} must be a positive number of seconds",
                self.duration
            ));
        }
        for (t, track) in self.track.iter().enumerate() {
            let name = &track.section;
            if self.track[..t].iter().any(|o| &o.section == name) {
                return err(format!("section '{name}' has more than one track"));
            }
            if track.key.is_empty() {
                return err(format!("track '{name}' has no keys"));
            }
            for (k, key) in track.key.iter().enumerate() {
                let at = format!("track '{name}', key {}", k + 1);
                let finite = key.time.is_finite()
                    && key.angle.is_finite()
                    && key.axis.iter().all(|v| v.is_finite())
                    && key
                        .translation
                        .is_none_or(|v| v.iter().all(|c| c.is_finite()));
                if !finite {
                    return err(format!("{at}: every value must be a finite number"));
                }
                if !(0.0..=self.duration).contains(&key.time) {
                    return err(format!(
                        "{at}: time {} is outside 0..{} (the duration)",
                        key.time, self.duration
                    ));
                }
                if k > 0 && key.time <= track.key[k - 1].time {
                    return err(format!(
                        "{at}: time {} is not after the previous key's {} (keys must be in time order)",
                        key.time,
                        track.key[k - 1].time
                    ));
                }
                if key.angle != 0.0 && DVec3::from(key.axis) == DVec3::ZERO {
                    return err(format!("{at}: the rotation axis is zero"));
                }
            }
        }
        Ok(())
    }

    /// Writes the animation as TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_default()
    }

    /// Resolves section names against `joints`.
    pub fn bind(&self, joints: &Joints) -> Result<Bound, AnimError> {
        let mut tracks = Vec::with_capacity(self.track.len());
        for track in &self.track {
            let section = joints.find(&track.section).ok_or_else(|| {
                let known: Vec<&str> = joints.sections().iter().map(|s| s.name.as_str()).collect();
                AnimError(format!(
                    "track '{}': unknown section (the rig has: {})",
                    track.section,
                    known.join(", ")
                ))
            })?;
            tracks.push((section, track.clone()));
        }
        Ok(Bound {
            sections: joints.sections().len(),
            duration: self.duration,
            looping: self.looping,
            tracks,
        })
    }
}

/// An animation whose tracks are bound to section indices.
#[derive(Clone, Debug)]
pub struct Bound {
    sections: usize,
    duration: f64,
    looping: bool,
    tracks: Vec<(usize, Track)>,
}

impl Bound {
    /// Writes the local pose of every section at time `t` (seconds) into `local` (resized
    /// to the number of sections; sections without a track are at rest).
    pub fn sample(&self, t: f64, local: &mut Vec<Local>) {
        local.clear();
        local.resize(self.sections, Local::default());
        let t = if self.looping && t > self.duration {
            t.rem_euclid(self.duration)
        } else {
            t.clamp(0.0, self.duration)
        };
        for (section, track) in &self.tracks {
            local[*section] = sample_track(track, t);
        }
    }
}

fn key_local(k: &Key) -> (DVec3, f64, DVec3) {
    (
        DVec3::from(k.axis).normalize_or_zero(),
        k.angle,
        k.translation.map(DVec3::from).unwrap_or(DVec3::ZERO),
    )
}

fn sample_track(track: &Track, t: f64) -> Local {
    let keys = &track.key;
    let next = keys.partition_point(|k| k.time <= t);
    if next == 0 || next == keys.len() {
        let k = &keys[if next == 0 { 0 } else { keys.len() - 1 }];
        let (axis, angle, translation) = key_local(k);
        return Local {
            translation,
            ..Local::axis_angle(axis, angle)
        };
    }
    let (a, b) = (&keys[next - 1], &keys[next]);
    let mut u = (t - a.time) / (b.time - a.time);
    if track.ease == Ease::Smooth {
        u = u * u * (3.0 - 2.0 * u);
    }
    let (axis_a, angle_a, ta) = key_local(a);
    let (axis_b, angle_b, tb) = key_local(b);
    let translation = ta.lerp(tb, u);
    let same_axis = axis_a.dot(axis_b) > 1.0 - 1e-12 || angle_a == 0.0 || angle_b == 0.0;
    let rotation = if same_axis {
        let axis = if angle_a == 0.0 { axis_b } else { axis_a };
        Local::axis_angle(axis, angle_a + (angle_b - angle_a) * u).rotation
    } else {
        let qa = Local::axis_angle(axis_a, angle_a).rotation;
        let qb = Local::axis_angle(axis_b, angle_b).rotation;
        qa.slerp(qb, u)
    };
    Local {
        rotation: normalize(rotation),
        translation,
    }
}

fn normalize(q: DQuat) -> DQuat {
    let q = q.normalize();
    if q.is_finite() {
        q
    } else {
        DQuat::IDENTITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joints::{Cut, Shape, ROOT};

    const JAW: &str = r#"
duration = 2.0
[[track]]
section = "jaw"
key = [
  { time = 0.0, axis = [1, 0, 0], angle = 0 },
  { time = 1.0, axis = [1, 0, 0], angle = 40 },
  { time = 2.0, axis = [1, 0, 0], angle = 300 },
]
"#;

    fn joints() -> Joints {
        let pts: Vec<DVec3> = (0..10).map(|k| DVec3::new(0.0, k as f64, 0.0)).collect();
        let mut j = Joints::new(&pts, ROOT);
        j.add_cut(Cut {
            name: "jaw".into(),
            section: ROOT.into(),
            point: DVec3::new(0.0, 4.5, 0.0),
            normal: DVec3::Y,
            pivot: None,
            connected: false,
            band: None,
            shape: Shape::Plane,
            shared_pivot: false,
        })
        .unwrap();
        j
    }

    /// Is `l` a rotation of `deg` degrees about x (quaternions up to sign)?
    fn about_x(l: &Local, deg: f64) -> bool {
        let q = DQuat::from_axis_angle(DVec3::X, deg.to_radians());
        l.rotation.abs_diff_eq(q, 1e-12) || l.rotation.abs_diff_eq(-q, 1e-12)
    }

    #[test]
    fn samples_interpolate_angles_and_hold_at_the_ends() {
        let anim = Animation::parse(JAW, Format::Toml).unwrap();
        let bound = anim.bind(&joints()).unwrap();
        let mut local = Vec::new();
        bound.sample(0.5, &mut local);
        assert_eq!(local.len(), 2);
        assert_eq!(local[0], Local::default());
        assert!(about_x(&local[1], 20.0));
        bound.sample(1.5, &mut local);
        // 40 -> 300 about the same axis goes the long way, as written: 170 degrees.
        assert!(about_x(&local[1], 170.0));
        bound.sample(10.0, &mut local);
        assert!(about_x(&local[1], 300.0));
        bound.sample(-1.0, &mut local);
        assert!(about_x(&local[1], 0.0));
    }

    #[test]
    fn different_axes_slerp_and_smooth_eases() {
        let text = r#"
duration = 1
[[track]]
section = "jaw"
ease = "smooth"
key = [{ time = 0, axis = [1, 0, 0], angle = 90 }, { time = 1, axis = [0, 1, 0], angle = 90 }]
"#;
        let bound = Animation::parse(text, Format::Toml)
            .unwrap()
            .bind(&joints())
            .unwrap();
        let mut local = Vec::new();
        bound.sample(0.5, &mut local);
        let qa = DQuat::from_axis_angle(DVec3::X, 90f64.to_radians());
        let qb = DQuat::from_axis_angle(DVec3::Y, 90f64.to_radians());
        assert!(local[1].rotation.abs_diff_eq(qa.slerp(qb, 0.5), 1e-12));
        bound.sample(0.25, &mut local);
        // smoothstep(0.25) = 0.15625
        assert!(local[1].rotation.abs_diff_eq(qa.slerp(qb, 0.15625), 1e-12));
    }

    #[test]
    fn bad_animations_say_what_and_where() {
        let bad = |text: &str| Animation::parse(text, Format::Toml).unwrap_err().0;
        let track =
            |keys: &str| format!("duration = 2\n[[track]]\nsection = \"jaw\"\nkey = [{keys}]\n");
        assert!(
            bad(&track("{ time = 1 }, { time = 0.5 }")).contains("key 2: time 0.5 is not after")
        );
        assert!(bad(&track("{ time = 3 }")).contains("outside 0..2"));
        assert!(bad(&track("{ time = nan }")).contains("finite"));
        assert!(bad(&track("{ time = 0, axis = [0, 0, 0], angle = 5 }")).contains("axis is zero"));
        assert!(bad(&track("")).contains("no keys"));
        assert!(bad(&track("{ time = 0, angel = 5 }")).contains("unknown field `angel`"));
        assert!(bad("duration = 0\n").contains("positive"));
        assert!(bad("duration = 1\n[[track]]\nsection = \"a\"\nkey = [{time = 0}]\n[[track]]\nsection = \"a\"\nkey = [{time = 0}]\n").contains("more than one track"));
        let e = Animation::parse(&track("{ time = 0 }").replace("jaw", "tail"), Format::Toml)
            .unwrap()
            .bind(&joints())
            .unwrap_err();
        assert_eq!(
            e.0,
            "track 'tail': unknown section (the rig has: root, jaw)"
        );
    }

    #[test]
    fn toml_and_json_round_trip() {
        let anim = Animation::parse(JAW, Format::Toml).unwrap();
        assert_eq!(
            Animation::parse(&anim.to_toml(), Format::Toml).unwrap(),
            anim
        );
        let json = serde_json::to_string(&anim).unwrap();
        assert_eq!(Animation::parse(&json, Format::Json).unwrap(), anim);
    }
}
