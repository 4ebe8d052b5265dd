//! The controls at run time: events from devices in, each control's calibrated and
//! filtered value, the sections' rotations and the actions out.
//!
//! Hostile input changes nothing and is counted: a message for an address no control
//! reads, an argument that is missing, not a number, non-finite or beyond 1e9, a
//! quaternion of zero length. A flood is fine: each event costs a lookup per control.

use super::file::{Action, Control, ControlsError, ControlsFile, Source, Target};
use super::filter::OneEuro;
use crate::joints::Local;
use glam::DQuat;

/// What a device said, with the time it arrived (seconds, any origin).
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// An OSC message: its address and its arguments as numbers (`None` where an argument
    /// is not a number).
    Osc {
        /// The address.
        address: String,
        /// The arguments.
        args: Vec<Option<f64>>,
    },
    /// A MIDI control change: channel 1–16, controller, value 0–127.
    MidiCc {
        /// Channel, 1–16.
        channel: u8,
        /// Controller.
        cc: u8,
        /// Value, 0–127.
        value: u8,
    },
    /// A MIDI note on (velocity) or off (velocity 0).
    MidiNote {
        /// Channel, 1–16.
        channel: u8,
        /// Note.
        note: u8,
        /// Velocity, 0–127.
        velocity: u8,
    },
    /// A gamepad axis (−1..1) or button (0..1) by name.
    Gamepad {
        /// Axis or button.
        name: String,
        /// Its value.
        value: f64,
    },
}

/// Largest raw value taken (beyond it the sample is ignored as garbage).
const MAX_RAW: f64 = 1e9;

/// One control's state.
#[derive(Clone, Debug)]
struct State {
    /// Sections it turns (indices into the puppet's sections).
    sections: Vec<usize>,
    /// Filtered 0..1 value.
    filter: OneEuro,
    /// Orientation: one filter per quaternion component, and the last quaternion.
    quat: Option<([OneEuro; 4], DQuat)>,
    /// A button's last state (for the rising edge).
    pressed: bool,
}

/// Live controls bound to a puppet's sections.
#[derive(Clone, Debug)]
pub struct Controls {
    file: ControlsFile,
    state: Vec<State>,
    /// Messages that reached a control.
    pub used: usize,
    /// Messages no control reads (an unknown address, channel or name).
    pub unknown: usize,
    /// Samples ignored as malformed (missing, not a number, non-finite, huge).
    pub ignored: usize,
    fired: Vec<Action>,
    changed: bool,
}

impl Controls {
    /// The controls of `file` for a puppet whose sections are `sections` (by name).
    ///
    /// # Errors
    /// [`ControlsError`] naming the control's line and the missing section.
    pub fn new(file: ControlsFile, sections: &[&str]) -> Result<Controls, ControlsError> {
        let mut state = Vec::with_capacity(file.controls.len());
        for c in &file.controls {
            let names: Vec<&String> = match &c.target {
                Target::Turn { sections, .. } => sections.iter().collect(),
                Target::Orientation { section } => vec![section],
                Target::Action(_) => Vec::new(),
            };
            let mut found = Vec::new();
            for n in names {
                match sections.iter().position(|s| s == n) {
                    Some(k) => found.push(k),
                    None => {
                        return Err(ControlsError(format!(
                            "line {}: control '{}': no section '{n}' (the puppet has: {})",
                            c.line,
                            c.name,
                            sections.join(", ")
                        )))
                    }
                }
            }
            let (min_cutoff, beta) = c.smoothing;
            state.push(State {
                sections: found,
                filter: OneEuro::new(min_cutoff, beta),
                quat: None,
                pressed: false,
            });
        }
        Ok(Controls {
            file,
            state,
            used: 0,
            unknown: 0,
            ignored: 0,
            fired: Vec::new(),
            changed: false,
        })
    }

    /// The controls, in file order.
    pub fn controls(&self) -> &[Control] {
        &self.file.controls
    }

    /// Each control's name and current 0..1 value (for the panel).
    pub fn values(&self) -> Vec<(&str, Option<f64>)> {
        self.file
            .controls
            .iter()
            .zip(&self.state)
            .map(|(c, s)| (c.name.as_str(), s.filter.value()))
            .collect()
    }

    /// Takes in one event that arrived at `time` (seconds).
    pub fn feed(&mut self, event: &Event, time: f64) {
        let mut reached = false;
        for k in 0..self.state.len() {
            let sample = match (&self.file.controls[k].source, event) {
                (Source::Osc { address, arg }, Event::Osc { address: a, args }) if a == address => {
                    if let Target::Orientation { .. } = self.file.controls[k].target {
                        reached = true;
                        self.orientation(k, args.get(*arg..*arg + 4), time);
                        continue;
                    }
                    Some(args.get(*arg).copied().flatten())
                }
                (
                    Source::MidiCc { channel, cc },
                    Event::MidiCc {
                        channel: ch,
                        cc: c,
                        value,
                    },
                ) if ch == channel && c == cc => Some(Some(f64::from(*value) / 127.0)),
                (
                    Source::MidiNote { channel, note },
                    Event::MidiNote {
                        channel: ch,
                        note: n,
                        velocity,
                    },
                ) if ch == channel && n == note => Some(Some(f64::from(*velocity) / 127.0)),
                (Source::Gamepad { name }, Event::Gamepad { name: n, value }) if n == name => {
                    Some(Some(*value))
                }
                _ => None,
            };
            let Some(sample) = sample else {
                continue;
            };
            reached = true;
            match sample.filter(|x| x.is_finite() && x.abs() <= MAX_RAW) {
                Some(raw) => self.take(k, raw, time),
                None => self.ignored += 1,
            }
        }
        if reached {
            self.used += 1;
        } else {
            self.unknown += 1;
        }
    }

    /// A raw sample of control `k`.
    fn take(&mut self, k: usize, raw: f64, time: f64) {
        let c = &self.file.controls[k];
        let s = &mut self.state[k];
        let v = c.calibration.apply(raw);
        if let Target::Action(a) = c.target {
            let pressed = v > 0.5;
            if pressed && !s.pressed {
                self.fired.push(a);
            }
            s.pressed = pressed;
            return;
        }
        s.filter.filter(v, time);
        self.changed = true;
    }

    /// An OSC quaternion `w x y z` for control `k`.
    fn orientation(&mut self, k: usize, wxyz: Option<&[Option<f64>]>, time: f64) {
        let q = wxyz
            .and_then(|a| {
                let v: Option<Vec<f64>> = a.iter().copied().collect();
                v
            })
            .map(|v| DQuat::from_xyzw(v[1], v[2], v[3], v[0]))
            .filter(|q| q.is_finite() && q.length() > 1e-6 && q.length() < MAX_RAW);
        let Some(q) = q else {
            self.ignored += 1;
            return;
        };
        let mut q = q.normalize();
        let (min_cutoff, beta) = self.file.controls[k].smoothing;
        let s = &mut self.state[k];
        let (filters, last) = s
            .quat
            .get_or_insert_with(|| ([OneEuro::new(min_cutoff, beta); 4], q));
        // q and −q are the same turn: keep the sign nearest the last one, so the filter
        // does not pass through zero.
        if q.dot(*last) < 0.0 {
            q = -q;
        }
        let mut out = [0.0; 4];
        for ((o, f), x) in out.iter_mut().zip(filters.iter_mut()).zip(q.to_array()) {
            *o = f.filter(x, time);
        }
        let filtered = DQuat::from_array(out);
        if filtered.length() > 1e-6 {
            *last = filtered.normalize();
        }
        self.changed = true;
    }

    /// Whether any section's value changed since the last call (and clears it).
    pub fn take_changed(&mut self) -> bool {
        std::mem::take(&mut self.changed)
    }

    /// The actions fired since the last call, in order.
    pub fn take_fired(&mut self) -> Vec<Action> {
        std::mem::take(&mut self.fired)
    }

    /// Sets the rotation of every section a control has a value for; returns those
    /// sections. Sections keep their offset; a chain of a curl turns each of its sections
    /// by the same angle.
    pub fn apply(&self, local: &mut [Local]) -> Vec<usize> {
        let mut touched = Vec::new();
        for (c, s) in self.file.controls.iter().zip(&self.state) {
            let rotation = match &c.target {
                Target::Turn { axis, angles, .. } => {
                    let Some(v) = s.filter.value() else {
                        continue;
                    };
                    let degrees = angles[0] + (angles[1] - angles[0]) * v.clamp(0.0, 1.0);
                    DQuat::from_axis_angle(*axis, degrees.to_radians())
                }
                Target::Orientation { .. } => match &s.quat {
                    Some((_, q)) => *q,
                    None => continue,
                },
                Target::Action(_) => continue,
            };
            for &k in &s.sections {
                if let Some(l) = local.get_mut(k) {
                    l.rotation = rotation;
                    touched.push(k);
                }
            }
        }
        touched
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn controls() -> Controls {
        let file = ControlsFile::parse(
            r#"
[[control]]
name = "index"
osc = "/glove/flex"
arg = 1
curl = ["a", "b"]
angles = [0, 90]
min_cutoff = 1000

[[control]]
midi = { channel = 1, cc = 7 }
section = "c"
axis = [1, 0, 0]
angles = [-45, 45]
min_cutoff = 1000

[[control]]
osc = "/glove/wrist"
orientation = "c"

[[control]]
gamepad = "South"
action = "record"
"#,
        )
        .unwrap();
        Controls::new(file, &["root", "a", "b", "c"]).unwrap()
    }

    #[test]
    fn events_turn_their_sections_and_buttons_fire_once_per_press() {
        let mut c = controls();
        let mut local = vec![Local::default(); 4];
        assert!(
            c.apply(&mut local).is_empty(),
            "nothing before a value comes"
        );
        c.feed(
            &Event::Osc {
                address: "/glove/flex".into(),
                args: vec![Some(0.0), Some(1.0)],
            },
            0.0,
        );
        let touched = c.apply(&mut local);
        assert_eq!(touched, [1, 2]);
        let angle = local[1]
            .rotation
            .angle_between(DQuat::IDENTITY)
            .to_degrees();
        assert!((angle - 90.0).abs() < 1e-9, "{angle}");
        assert_eq!(local[1].rotation, local[2].rotation);
        c.feed(
            &Event::MidiCc {
                channel: 1,
                cc: 7,
                value: 127,
            },
            0.01,
        );
        c.apply(&mut local);
        let (axis, a) = local[3].rotation.to_axis_angle();
        assert!((a.to_degrees() - 45.0).abs() < 1e-6 && (axis.x - 1.0).abs() < 1e-9);
        // A button fires on the press, not while held, and again after a release.
        for (t, v) in [(0.0, 1.0), (0.1, 1.0), (0.2, 0.0), (0.3, 1.0)] {
            c.feed(
                &Event::Gamepad {
                    name: "South".into(),
                    value: v,
                },
                t,
            );
        }
        assert_eq!(c.take_fired(), [Action::Record, Action::Record]);
        assert!(c.take_fired().is_empty());
        assert_eq!(c.unknown, 0);
        assert!(c.take_changed());
        assert!(!c.take_changed());
    }

    #[test]
    fn a_quaternion_sets_a_rotation() {
        let mut c = controls();
        let q = DQuat::from_rotation_y(0.7);
        let wxyz = [q.w, q.x, q.y, q.z].map(Some).to_vec();
        c.feed(
            &Event::Osc {
                address: "/glove/wrist".into(),
                args: wxyz,
            },
            0.0,
        );
        let mut local = vec![Local::default(); 4];
        c.apply(&mut local);
        assert!(local[3].rotation.angle_between(q) < 1e-9);
    }

    #[test]
    fn hostile_input_is_counted_and_changes_nothing() {
        let mut c = controls();
        let mut local = vec![Local::default(); 4];
        let bad = [
            Event::Osc {
                address: "/nobody".into(),
                args: vec![Some(1.0)],
            },
            Event::Osc {
                address: "/glove/flex".into(),
                args: vec![Some(0.0)],
            },
            Event::Osc {
                address: "/glove/flex".into(),
                args: vec![Some(0.0), None],
            },
            Event::Osc {
                address: "/glove/flex".into(),
                args: vec![Some(0.0), Some(f64::NAN)],
            },
            Event::Osc {
                address: "/glove/flex".into(),
                args: vec![Some(0.0), Some(1e300)],
            },
            Event::Osc {
                address: "/glove/wrist".into(),
                args: vec![Some(0.0); 4],
            },
            Event::Osc {
                address: "/glove/wrist".into(),
                args: vec![Some(1.0); 2],
            },
            Event::MidiCc {
                channel: 2,
                cc: 7,
                value: 3,
            },
            Event::Gamepad {
                name: "North".into(),
                value: f64::INFINITY,
            },
        ];
        for (k, e) in bad.iter().enumerate() {
            c.feed(e, k as f64);
        }
        assert!(c.apply(&mut local).is_empty());
        assert!(local.iter().all(|l| *l == Local::default()));
        assert_eq!((c.unknown, c.ignored, c.used), (3, 6, 6));
        // A flood of ten thousand good messages: the last value wins, filtered.
        for k in 0..10_000 {
            c.feed(
                &Event::Osc {
                    address: "/glove/flex".into(),
                    args: vec![Some(0.0), Some((k % 2) as f64)],
                },
                10.0 + k as f64 * 1e-4,
            );
        }
        c.apply(&mut local);
        assert!(local[1].rotation.is_finite());
    }
}
