//! MIDI messages to [`Event`]s: control change (`0xBn cc value`), note on (`0x9n note
//! velocity`, velocity 0 meaning off) and note off (`0x8n`), channel `n + 1`. Everything
//! else (clock, sysex, pitch bend, a truncated or malformed message) is `None`.

use super::live::Event;

/// One MIDI message as an event.
pub fn event(bytes: &[u8]) -> Option<Event> {
    let (&status, data) = bytes.split_first()?;
    let channel = (status & 0x0F) + 1;
    let (a, b) = match data {
        [a, b, ..] if *a < 128 && *b < 128 => (*a, *b),
        _ => return None,
    };
    match status & 0xF0 {
        0xB0 => Some(Event::MidiCc {
            channel,
            cc: a,
            value: b,
        }),
        0x90 => Some(Event::MidiNote {
            channel,
            note: a,
            velocity: b,
        }),
        0x80 => Some(Event::MidiNote {
            channel,
            note: a,
            velocity: 0,
        }),
        _ => None,
    }
}

/// A gamepad axis or button by the name a controls file gives it (`LeftStickX`,
/// `South`…: the gilrs names), with its value.
pub fn gamepad(name: &str, value: f32) -> Event {
    Event::Gamepad {
        name: name.to_string(),
        value: f64::from(value),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_changes_and_notes_translate_and_the_rest_does_not() {
        assert_eq!(
            event(&[0xB1, 7, 100]),
            Some(Event::MidiCc {
                channel: 2,
                cc: 7,
                value: 100
            })
        );
        assert_eq!(
            event(&[0x90, 60, 64]),
            Some(Event::MidiNote {
                channel: 1,
                note: 60,
                velocity: 64
            })
        );
        assert_eq!(
            event(&[0x8F, 60, 64]),
            Some(Event::MidiNote {
                channel: 16,
                note: 60,
                velocity: 0
            })
        );
        for bad in [
            &[][..],
            &[0xB0],
            &[0xB0, 7],
            &[0xB0, 200, 1],
            &[0xF8],
            &[0xE0, 0, 64],
            &[0xF0, 1, 2, 0xF7],
        ] {
            assert_eq!(event(bad), None, "{bad:?}");
        }
        assert_eq!(
            gamepad("South", 1.0),
            Event::Gamepad {
                name: "South".into(),
                value: 1.0
            }
        );
    }

    #[test]
    fn midi_and_gamepad_events_drive_their_controls() {
        use super::super::{Controls, ControlsFile};
        let file = ControlsFile::parse(
            "[[control]]\nmidi = { channel = 1, cc = 21 }\nsection = \"a\"\nangles = [0, 60]\nmin_cutoff = 1000\n\
             [[control]]\nmidi = { channel = 10, note = 36 }\naction = \"reset\"\n\
             [[control]]\ngamepad = \"LeftStickX\"\nmin = -1\nsection = \"b\"\nmin_cutoff = 1000\n",
        )
        .unwrap();
        let mut c = Controls::new(file, &["root", "a", "b"]).unwrap();
        for (k, bytes) in [[0xB0u8, 21, 127], [0x99, 36, 100], [0x89, 36, 0]]
            .iter()
            .enumerate()
        {
            c.feed(&event(bytes).unwrap(), k as f64 * 0.01);
        }
        c.feed(&gamepad("LeftStickX", 0.0), 0.05);
        let mut local = vec![crate::joints::Local::default(); 3];
        assert_eq!(c.apply(&mut local), [1, 2]);
        let a = local[1].rotation.to_axis_angle().1.to_degrees();
        let b = local[2].rotation.to_axis_angle().1.to_degrees();
        assert!(
            (a - 60.0).abs() < 1e-6 && (b - 45.0).abs() < 1e-6,
            "{a} {b}"
        );
        assert_eq!(c.take_fired(), [super::super::Action::Reset]);
    }
}
