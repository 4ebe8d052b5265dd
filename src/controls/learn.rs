//! Learning and calibrating controls by moving them, as MIDI learn works in audio tools.
//!
//! * [`Learn`] watches every value that arrives, from any device, and names the one that
//!   moved: the source whose range so far is the widest against its size. Mapping it to a
//!   section ([`Learn::bind`]) adds a control to the file (or replaces the one that source
//!   drove), calibrated to the range it was seen moving over.
//! * [`Calibrate`] watches the file's own controls while the puppeteer moves each through
//!   its full range; [`Calibrate::finish`] sets each moved control's `min` and `max`.

use super::file::{Calibration, Control, ControlsFile, Source, Target, DEFAULT_SMOOTHING};
use super::live::Event;
use glam::DVec3;

/// Largest raw value taken (as the live controls do).
const MAX_RAW: f64 = 1e9;

/// A move is a range at least this fraction of the value's size (its largest magnitude,
/// at least 1): a tenth of a fader, of a 0..1 flex sensor, of half a stick.
const MOVED: f64 = 0.1;

/// The values an event carries, each with the source it comes from: one per numeric
/// argument of an OSC message, the 0..1 value of a MIDI message, a gamepad's value.
pub fn samples(event: &Event) -> Vec<(Source, f64)> {
    let ok = |x: f64| x.is_finite() && x.abs() <= MAX_RAW;
    match event {
        Event::Osc { address, args } => args
            .iter()
            .enumerate()
            .filter_map(|(arg, v)| {
                let v = (*v).filter(|&x| ok(x))?;
                Some((
                    Source::Osc {
                        address: address.clone(),
                        arg,
                    },
                    v,
                ))
            })
            .collect(),
        Event::MidiCc { channel, cc, value } => vec![(
            Source::MidiCc {
                channel: *channel,
                cc: *cc,
            },
            f64::from(*value) / 127.0,
        )],
        Event::MidiNote {
            channel,
            note,
            velocity,
        } => vec![(
            Source::MidiNote {
                channel: *channel,
                note: *note,
            },
            f64::from(*velocity) / 127.0,
        )],
        Event::Gamepad { name, value } if ok(*value) => {
            vec![(Source::Gamepad { name: name.clone() }, *value)]
        }
        Event::Gamepad { .. } => Vec::new(),
    }
}

/// The range a value was seen over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Smallest value seen.
    pub min: f64,
    /// Largest value seen.
    pub max: f64,
}

impl Range {
    fn new(x: f64) -> Range {
        Range { min: x, max: x }
    }

    fn take(&mut self, x: f64) {
        self.min = self.min.min(x);
        self.max = self.max.max(x);
    }

    /// How far it moved against its size (see [`MOVED`]).
    pub fn moved(&self) -> f64 {
        (self.max - self.min) / self.min.abs().max(self.max.abs()).max(1.0)
    }

    /// Whether it moved enough to count.
    pub fn is_move(&self) -> bool {
        self.moved() >= MOVED
    }
}

/// The learn step: which source moved, and mapping it to a section.
#[derive(Clone, Debug, Default)]
pub struct Learn {
    seen: Vec<(Source, Range)>,
}

impl Learn {
    /// Starts watching (nothing seen yet).
    pub fn new() -> Learn {
        Learn::default()
    }

    /// Takes in what an event carries.
    pub fn observe(&mut self, event: &Event) {
        for (source, x) in samples(event) {
            match self.seen.iter_mut().find(|(s, _)| *s == source) {
                Some((_, r)) => r.take(x),
                None => self.seen.push((source, Range::new(x))),
            }
        }
    }

    /// The source that moved most, with its range, once one moved enough to count.
    pub fn moved(&self) -> Option<(&Source, Range)> {
        self.seen
            .iter()
            .filter(|(_, r)| r.is_move())
            .max_by(|a, b| a.1.moved().total_cmp(&b.1.moved()))
            .map(|(s, r)| (s, *r))
    }

    /// Maps the source that moved to `section`: a control that turns it about `axis` by
    /// 0..90°, calibrated to the range seen, named after the section. A control the same
    /// source drove before is replaced (its axis and angles kept). Watching starts again
    /// for the next one. Returns the new control's index, or `None` when nothing moved.
    pub fn bind(&mut self, file: &mut ControlsFile, section: &str, axis: DVec3) -> Option<usize> {
        let (source, range) = self.moved().map(|(s, r)| (s.clone(), r))?;
        self.seen.clear();
        let calibration = Calibration {
            min: range.min,
            max: range.max,
            ..Calibration::default()
        };
        let before = file.controls.iter().position(|c| c.source == source);
        let (axis, angles, smoothing) = match before.map(|k| &file.controls[k]) {
            Some(Control {
                target: Target::Turn { axis, angles, .. },
                smoothing,
                ..
            }) => (*axis, *angles, *smoothing),
            _ => (axis, [0.0, 90.0], DEFAULT_SMOOTHING),
        };
        let control = Control {
            name: section.to_string(),
            source,
            calibration,
            target: Target::Turn {
                sections: vec![section.to_string()],
                axis,
                angles,
            },
            smoothing,
            line: 0,
        };
        Some(match before {
            Some(k) => {
                file.controls[k] = control;
                k
            }
            None => {
                file.controls.push(control);
                file.controls.len() - 1
            }
        })
    }
}

/// The calibrate step: each control's range while the puppeteer moves it end to end.
#[derive(Clone, Debug)]
pub struct Calibrate {
    /// Per control of the file: its range so far.
    seen: Vec<Option<Range>>,
}

impl Calibrate {
    /// Starts calibrating the controls of `file` (nothing seen yet).
    pub fn new(file: &ControlsFile) -> Calibrate {
        Calibrate {
            seen: vec![None; file.controls.len()],
        }
    }

    /// Takes in what an event carries for the controls of `file`.
    pub fn observe(&mut self, file: &ControlsFile, event: &Event) {
        for (source, x) in samples(event) {
            for (c, r) in file.controls.iter().zip(&mut self.seen) {
                if c.source == source {
                    match r {
                        Some(r) => r.take(x),
                        None => *r = Some(Range::new(x)),
                    }
                }
            }
        }
    }

    /// Each control's range so far (for the panel), in file order.
    pub fn ranges(&self) -> &[Option<Range>] {
        &self.seen
    }

    /// Sets `min` and `max` of every control that moved enough to count (buttons and
    /// orientations keep theirs); returns how many.
    pub fn finish(&self, file: &mut ControlsFile) -> usize {
        let mut done = 0;
        for (c, r) in file.controls.iter_mut().zip(&self.seen) {
            let Some(r) = r.filter(Range::is_move) else {
                continue;
            };
            if matches!(c.target, Target::Turn { .. }) {
                c.calibration.min = r.min;
                c.calibration.max = r.max;
                done += 1;
            }
        }
        done
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn osc(address: &str, args: &[f64]) -> Event {
        Event::Osc {
            address: address.into(),
            args: args.iter().map(|&x| Some(x)).collect(),
        }
    }

    #[test]
    fn the_control_that_moved_is_mapped_calibrated_to_its_range() {
        let mut learn = Learn::new();
        let mut file = ControlsFile::default();
        // Five flex values that jitter, the third bent from 0.2 to 0.8.
        for k in 0..=10 {
            let jitter = 0.01 * (k % 2) as f64;
            let third = 0.2 + 0.06 * k as f64;
            learn.observe(&osc("/glove/flex", &[jitter, jitter, third, jitter, 0.5]));
        }
        learn.observe(&Event::MidiCc {
            channel: 1,
            cc: 7,
            value: 64,
        });
        let (source, range) = learn.moved().unwrap();
        assert_eq!(
            *source,
            Source::Osc {
                address: "/glove/flex".into(),
                arg: 2
            }
        );
        assert!((range.min - 0.2).abs() < 1e-12 && (range.max - 0.8).abs() < 1e-12);
        assert_eq!(learn.bind(&mut file, "jaw", DVec3::X), Some(0));
        let c = &file.controls[0];
        assert_eq!(c.name, "jaw");
        assert!((c.calibration.apply(0.5) - 0.5).abs() < 1e-9);
        assert!(learn.moved().is_none(), "watching starts again");
        assert_eq!(
            learn.bind(&mut file, "head", DVec3::Z),
            None,
            "nothing moved since"
        );
        // The same source learned again replaces its control; a fader is a second one.
        for v in [0, 127] {
            learn.observe(&Event::MidiCc {
                channel: 1,
                cc: 7,
                value: v,
            });
        }
        assert_eq!(learn.bind(&mut file, "head", DVec3::Z), Some(1));
        for x in [0.0, 1.0] {
            learn.observe(&osc("/glove/flex", &[0.0, 0.0, x]));
        }
        assert_eq!(learn.bind(&mut file, "tail", DVec3::Y), Some(0));
        assert_eq!(file.controls.len(), 2);
        assert_eq!(file.controls[0].name, "tail");
        // What learning made is a file that saves and reads back.
        let back = ControlsFile::parse(&file.to_toml()).unwrap();
        assert_eq!(back.controls.len(), 2);
    }

    #[test]
    fn jitter_and_garbage_are_not_a_move() {
        let mut learn = Learn::new();
        for k in 0..100 {
            let x = 500.0 + (k % 7) as f64;
            learn.observe(&osc("/raw", &[x]));
            learn.observe(&Event::Gamepad {
                name: "LeftStickX".into(),
                value: if k % 2 == 0 { f64::NAN } else { 0.02 },
            });
            learn.observe(&Event::Osc {
                address: "/x".into(),
                args: vec![None, Some(f64::INFINITY)],
            });
        }
        assert!(learn.moved().is_none());
    }

    #[test]
    fn calibrate_sets_the_range_each_control_was_moved_over() {
        let mut file = ControlsFile::parse(
            r#"
[[control]]
osc = "/glove/flex"
arg = 1
section = "a"

[[control]]
gamepad = "LeftStickX"
section = "b"

[[control]]
gamepad = "South"
action = "record"
"#,
        )
        .unwrap();
        let mut cal = Calibrate::new(&file);
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            cal.observe(&file, &osc("/glove/flex", &[9.0, 120.0 + 800.0 * t]));
            cal.observe(
                &file,
                &Event::Gamepad {
                    name: "South".into(),
                    value: t.round(),
                },
            );
        }
        assert_eq!(cal.finish(&mut file), 1, "the stick never moved");
        let c = &file.controls[0].calibration;
        assert_eq!((c.min, c.max), (120.0, 920.0));
        assert_eq!(file.controls[1].calibration, Calibration::default());
        assert_eq!(file.controls[2].calibration, Calibration::default());
    }
}
