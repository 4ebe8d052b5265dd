//! Live controls: hardware a puppeteer holds (a data glove or hand tracker sending OSC, a
//! MIDI controller, a gamepad) mapped to the sections, as the paper's data glove was.
//!
//! * [`file`]: the controls file (`controls.toml`): which control drives what, each
//!   control's calibration and smoothing; errors name the line.
//! * [`filter`]: the One Euro filter (Casiez et al. 2012) that smooths each control.
//! * [`live`]: the controls at run time: events in, filtered values, section rotations
//!   and actions out, with counts of what was ignored.
//! * [`learn`]: *Learn* (move a control, click a section) and *Calibrate* (move each
//!   control end to end) for the window's Controls panel.
//! * [`osc`]: OSC packets (UDP) to events, hostile input counted, never a panic.
//! * [`midi`]: MIDI messages (and gamepad axes and buttons) to events.
//! * [`glove`]: a synthetic glove performance (`puppet send-osc`), to try it without one.
//!
//! Devices themselves (sockets, ports) are the shell's: the core sees only [`Event`]s, so
//! mapping, calibration and filtering are tested with synthetic events.

pub mod file;
pub mod filter;
pub mod glove;
pub mod learn;
pub mod live;
pub mod midi;
pub mod osc;

pub use file::{Action, Calibration, Control, ControlsError, ControlsFile, Source, Target};
pub use filter::OneEuro;
pub use learn::{Calibrate, Learn};
pub use live::{Controls, Event};
