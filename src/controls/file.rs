//! The controls file: which control drives which section, and how.
//!
//! ```toml
//! [filter]                 # One Euro smoothing for every control (optional)
//! min_cutoff = 1.0         # Hz: lower, less jitter at rest
//! beta = 0.05              # higher, less lag when moving
//!
//! [[control]]
//! name = "index"           # what the panel shows (default: the source)
//! osc = "/glove/flex"      # the source: an OSC address and its argument (from 0),
//! arg = 1                  # or midi = { channel = 1, cc = 21 } (or note = 60),
//!                          # or gamepad = "LeftStickX" (an axis or a button)
//! min = 0.1                # calibration: the raw value taken as 0 and as 1,
//! max = 0.9                # invert = true, dead_zone = 0.05 (of the range, at 0)
//! curl = ["index.1", "index.2", "index.3"]  # the target: sections bent together,
//!                          # or section = "jaw"; or orientation = "hand" (an OSC
//!                          # quaternion w x y z from `arg`); or action = "record"
//! axis = [0, 0, 1]         # the rotation's axis in the section's frame (default +z)
//! angles = [0, 90]         # degrees at 0 and at 1
//! ```
//!
//! Every error names its line: `line 12: control 'index': no section 'index.4'`.

use glam::DVec3;
use serde::Deserialize;
use toml::Spanned;

/// A controls file that cannot be used, with its line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ControlsError(pub String);

/// Where a control's value comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// An OSC address and which of its arguments (from 0).
    Osc {
        /// The address, as `/glove/flex`.
        address: String,
        /// The argument.
        arg: usize,
    },
    /// A MIDI control change on a channel (1–16).
    MidiCc {
        /// Channel, 1–16.
        channel: u8,
        /// Controller number, 0–127.
        cc: u8,
    },
    /// A MIDI note's velocity on a channel (note off: 0).
    MidiNote {
        /// Channel, 1–16.
        channel: u8,
        /// Note number, 0–127.
        note: u8,
    },
    /// A gamepad axis or button, by its name (`LeftStickX`, `South`…).
    Gamepad {
        /// The axis or button.
        name: String,
    },
}

impl std::fmt::Display for Source {
    /// As the panel shows it: `/glove/flex 2`, `midi 1 cc 7`, `midi 1 note 60`,
    /// `gamepad LeftStickX`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Source::Osc { address, arg } => write!(f, "{address} {arg}"),
            Source::MidiCc { channel, cc } => write!(f, "midi {channel} cc {cc}"),
            Source::MidiNote { channel, note } => write!(f, "midi {channel} note {note}"),
            Source::Gamepad { name } => write!(f, "gamepad {name}"),
        }
    }
}

/// What a button does instead of turning a section.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Action {
    /// Start or stop recording a take.
    Record,
    /// Every section back to rest.
    Reset,
    /// Play or pause the animation.
    Play,
}

/// What a control drives.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// Sections turned about `axis` (their own frame) by an angle from `angles[0]` at 0 to
    /// `angles[1]` at 1 (degrees): one section, or a chain curled together.
    Turn {
        /// The sections, by name.
        sections: Vec<String>,
        /// Unit axis.
        axis: DVec3,
        /// Degrees at 0 and 1.
        angles: [f64; 2],
    },
    /// A section's rotation from an OSC quaternion (`w x y z` from the control's argument).
    Orientation {
        /// The section.
        section: String,
    },
    /// A button: the action fires when the value rises past one half.
    Action(Action),
}

/// A control's calibration: the raw values taken as 0 and 1, whether it runs the other
/// way, and the part of the range near 0 that counts as 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibration {
    /// Raw value read as 0.
    pub min: f64,
    /// Raw value read as 1.
    pub max: f64,
    /// 1 at `min`, 0 at `max`.
    pub invert: bool,
    /// Values below this (of the range) read 0; the rest is stretched over 0..1.
    pub dead_zone: f64,
}

impl Default for Calibration {
    fn default() -> Self {
        Calibration {
            min: 0.0,
            max: 1.0,
            invert: false,
            dead_zone: 0.0,
        }
    }
}

impl Calibration {
    /// The raw value as 0..1 (NaN stays NaN).
    pub fn apply(&self, raw: f64) -> f64 {
        let mut v = ((raw - self.min) / (self.max - self.min)).clamp(0.0, 1.0);
        if self.invert {
            v = 1.0 - v;
        }
        if v < self.dead_zone {
            0.0
        } else {
            (v - self.dead_zone) / (1.0 - self.dead_zone)
        }
    }
}

/// One control of the file.
#[derive(Clone, Debug, PartialEq)]
pub struct Control {
    /// What the panel shows.
    pub name: String,
    /// Where its value comes from.
    pub source: Source,
    /// Raw value to 0..1.
    pub calibration: Calibration,
    /// What it drives.
    pub target: Target,
    /// Its One Euro filter's `min_cutoff` (Hz) and `beta`.
    pub smoothing: (f64, f64),
    /// Its line in the file (from 1).
    pub line: usize,
}

/// A controls file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ControlsFile {
    /// The controls in file order.
    pub controls: Vec<Control>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileEntry {
    #[serde(default)]
    filter: Option<FilterEntry>,
    #[serde(default)]
    control: Vec<Spanned<ControlEntry>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct FilterEntry {
    min_cutoff: Option<f64>,
    beta: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MidiEntry {
    channel: u8,
    cc: Option<u8>,
    note: Option<u8>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ControlEntry {
    name: Option<String>,
    osc: Option<String>,
    arg: Option<usize>,
    midi: Option<MidiEntry>,
    gamepad: Option<String>,
    min: Option<f64>,
    max: Option<f64>,
    #[serde(default)]
    invert: bool,
    dead_zone: Option<f64>,
    section: Option<String>,
    #[serde(default)]
    curl: Vec<String>,
    orientation: Option<String>,
    action: Option<Action>,
    axis: Option<[f64; 3]>,
    angles: Option<[f64; 2]>,
    min_cutoff: Option<f64>,
    beta: Option<f64>,
}

/// Default One Euro parameters: steady at rest, quick when moving, for 0..1 values.
pub const DEFAULT_SMOOTHING: (f64, f64) = (1.0, 0.05);

impl ControlsFile {
    /// Reads a controls file's text.
    ///
    /// # Errors
    /// [`ControlsError`] naming the line: TOML syntax, an unknown key, a control with no
    /// source or two, no target or two, or a value out of range.
    pub fn parse(text: &str) -> Result<ControlsFile, ControlsError> {
        let entry: FileEntry = toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|s| format!("line {}: ", line_of(text, s.start)))
                .unwrap_or_default();
            ControlsError(format!("{line}{}", e.message().trim()))
        })?;
        let filter = entry.filter.unwrap_or(FilterEntry {
            min_cutoff: None,
            beta: None,
        });
        let mut controls = Vec::new();
        for (k, spanned) in entry.control.into_iter().enumerate() {
            let line = line_of(text, spanned.span().start);
            let c = spanned.into_inner();
            let name = c.name.clone().unwrap_or_else(|| format!("{}", k + 1));
            let at = |what: &str| ControlsError(format!("line {line}: control '{name}': {what}"));
            controls.push(control(c, filter, line, &at)?);
        }
        Ok(ControlsFile { controls })
    }

    /// Reads a controls file.
    ///
    /// # Errors
    /// As [`ControlsFile::parse`], or the file cannot be read.
    pub fn load(path: &std::path::Path) -> Result<ControlsFile, ControlsError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| ControlsError(crate::files::io_message(&e)))?;
        ControlsFile::parse(&text)
    }

    /// The sections the controls name, each once, in file order.
    pub fn sections(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for c in &self.controls {
            let names: Vec<&str> = match &c.target {
                Target::Turn { sections, .. } => sections.iter().map(String::as_str).collect(),
                Target::Orientation { section } => vec![section.as_str()],
                Target::Action(_) => Vec::new(),
            };
            for n in names {
                if !out.contains(&n) {
                    out.push(n);
                }
            }
        }
        out
    }
}

impl ControlsFile {
    /// The file as TOML that [`ControlsFile::parse`] reads back to the same controls
    /// (their lines aside): one `[[control]]` table each, keys left out where they hold
    /// the default, numbers in their shortest form.
    pub fn to_toml(&self) -> String {
        let mut out = String::from(
            "# Live controls for puppet: `puppet MESH --rig R --controls THIS_FILE`.\n",
        );
        for c in &self.controls {
            out.push_str("\n[[control]]\n");
            line(&mut out, "name", &quoted(&c.name));
            match &c.source {
                Source::Osc { address, arg } => {
                    line(&mut out, "osc", &quoted(address));
                    if *arg != 0 {
                        line(&mut out, "arg", &arg.to_string());
                    }
                }
                Source::MidiCc { channel, cc } => {
                    line(
                        &mut out,
                        "midi",
                        &format!("{{ channel = {channel}, cc = {cc} }}"),
                    );
                }
                Source::MidiNote { channel, note } => line(
                    &mut out,
                    "midi",
                    &format!("{{ channel = {channel}, note = {note} }}"),
                ),
                Source::Gamepad { name } => line(&mut out, "gamepad", &quoted(name)),
            }
            let k = &c.calibration;
            let default = Calibration::default();
            if k.min != default.min || k.max != default.max {
                line(&mut out, "min", &number(k.min));
                line(&mut out, "max", &number(k.max));
            }
            if k.invert {
                line(&mut out, "invert", "true");
            }
            if k.dead_zone != 0.0 {
                line(&mut out, "dead_zone", &number(k.dead_zone));
            }
            match &c.target {
                Target::Turn {
                    sections,
                    axis,
                    angles,
                } => {
                    if let [one] = sections.as_slice() {
                        line(&mut out, "section", &quoted(one));
                    } else {
                        let names: Vec<String> = sections.iter().map(|s| quoted(s)).collect();
                        line(&mut out, "curl", &format!("[{}]", names.join(", ")));
                    }
                    if *axis != DVec3::Z {
                        line(&mut out, "axis", &vector(&axis.to_array()));
                    }
                    if *angles != [0.0, 90.0] {
                        line(&mut out, "angles", &vector(angles));
                    }
                }
                Target::Orientation { section } => {
                    line(&mut out, "orientation", &quoted(section));
                }
                Target::Action(a) => {
                    let name = match a {
                        Action::Record => "record",
                        Action::Reset => "reset",
                        Action::Play => "play",
                    };
                    line(&mut out, "action", &quoted(name));
                }
            }
            if c.smoothing != DEFAULT_SMOOTHING {
                line(&mut out, "min_cutoff", &number(c.smoothing.0));
                line(&mut out, "beta", &number(c.smoothing.1));
            }
        }
        out
    }

    /// Writes the file (as [`ControlsFile::to_toml`]).
    ///
    /// # Errors
    /// The file cannot be written, in words.
    pub fn save(&self, path: &std::path::Path) -> Result<(), ControlsError> {
        std::fs::write(path, self.to_toml())
            .map_err(|e| ControlsError(crate::files::io_message(&e)))
    }
}

fn line(out: &mut String, key: &str, value: &str) {
    out.push_str(key);
    out.push_str(" = ");
    out.push_str(value);
    out.push('\n');
}

/// A TOML string.
fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// The shortest text that reads back to `x`.
fn number(x: f64) -> String {
    format!("{x}")
}

fn vector(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|&x| number(x)).collect();
    format!("[{}]", parts.join(", "))
}

/// Whether the file at `path` reads as a controls file (it has a `[[control]]` table), so
/// a file dropped on the window goes where it belongs.
pub fn is_controls_file(path: &std::path::Path) -> bool {
    std::fs::read_to_string(path).is_ok_and(|text| text.lines().any(|l| l.trim() == "[[control]]"))
}

/// The line (from 1) of byte `at` of `text`.
fn line_of(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// One control entry checked.
fn control(
    c: ControlEntry,
    filter: FilterEntry,
    line: usize,
    at: &dyn Fn(&str) -> ControlsError,
) -> Result<Control, ControlsError> {
    let finite = |x: f64, what: &str| {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(at(&format!("{what} must be a finite number")))
        }
    };
    let mut sources = Vec::new();
    if let Some(address) = &c.osc {
        if !address.starts_with('/') || address.contains(char::is_whitespace) {
            return Err(at(&format!(
                "osc = '{address}' is not an OSC address (it starts with / and has no spaces)"
            )));
        }
        let arg = c.arg.unwrap_or(0);
        if arg > 255 {
            return Err(at(&format!("arg = {arg} is too large (0..255)")));
        }
        sources.push(Source::Osc {
            address: address.clone(),
            arg,
        });
    } else if c.arg.is_some() {
        return Err(at("arg is for an OSC source (osc = \"/address\")"));
    }
    if let Some(m) = &c.midi {
        if !(1..=16).contains(&m.channel) {
            return Err(at(&format!("midi channel {} is not 1..16", m.channel)));
        }
        match (m.cc, m.note) {
            (Some(cc), None) if cc < 128 => sources.push(Source::MidiCc {
                channel: m.channel,
                cc,
            }),
            (None, Some(note)) if note < 128 => sources.push(Source::MidiNote {
                channel: m.channel,
                note,
            }),
            (Some(_), Some(_)) | (None, None) => {
                return Err(at("midi needs one of cc or note"));
            }
            _ => return Err(at("midi cc and note numbers are 0..127")),
        }
    }
    if let Some(name) = &c.gamepad {
        if name.trim().is_empty() {
            return Err(at("gamepad names an axis or a button"));
        }
        sources.push(Source::Gamepad { name: name.clone() });
    }
    let source = match sources.len() {
        1 => sources.remove(0),
        0 => return Err(at("no source: give osc, midi or gamepad")),
        _ => return Err(at("more than one source: give one of osc, midi or gamepad")),
    };
    let calibration = Calibration {
        min: finite(c.min.unwrap_or(0.0), "min")?,
        max: finite(c.max.unwrap_or(1.0), "max")?,
        invert: c.invert,
        dead_zone: finite(c.dead_zone.unwrap_or(0.0), "dead_zone")?,
    };
    if calibration.min == calibration.max {
        return Err(at("min and max are the same value"));
    }
    if !(0.0..0.9).contains(&calibration.dead_zone) {
        return Err(at("dead_zone must be at least 0 and below 0.9"));
    }
    let mut targets = Vec::new();
    let turn = |sections: Vec<String>| -> Result<Target, ControlsError> {
        let axis = c.axis.map_or(DVec3::Z, DVec3::from_array);
        if !axis.is_finite() || axis.length() < 1e-9 {
            return Err(at("axis must be a non-zero vector"));
        }
        let angles = c.angles.unwrap_or([0.0, 90.0]);
        for a in angles {
            finite(a, "angles")?;
            if a.abs() > 720.0 {
                return Err(at("angles are degrees within ±720"));
            }
        }
        Ok(Target::Turn {
            sections,
            axis: axis.normalize(),
            angles,
        })
    };
    if let Some(s) = &c.section {
        targets.push(turn(vec![s.clone()])?);
    }
    if !c.curl.is_empty() {
        targets.push(turn(c.curl.clone())?);
    }
    if let Some(s) = &c.orientation {
        if !matches!(source, Source::Osc { .. }) {
            return Err(at("orientation reads an OSC quaternion: give osc"));
        }
        targets.push(Target::Orientation { section: s.clone() });
    }
    if let Some(a) = c.action {
        targets.push(Target::Action(a));
    }
    let target = match targets.len() {
        1 => targets.remove(0),
        0 => return Err(at("no target: give section, curl, orientation or action")),
        _ => {
            return Err(at(
                "more than one target: give one of section, curl, orientation or action",
            ))
        }
    };
    if !matches!(target, Target::Turn { .. }) && (c.axis.is_some() || c.angles.is_some()) {
        return Err(at("axis and angles are for section or curl"));
    }
    let min_cutoff = finite(
        c.min_cutoff
            .or(filter.min_cutoff)
            .unwrap_or(DEFAULT_SMOOTHING.0),
        "min_cutoff",
    )?;
    let beta = finite(
        c.beta.or(filter.beta).unwrap_or(DEFAULT_SMOOTHING.1),
        "beta",
    )?;
    if min_cutoff <= 0.0 || beta < 0.0 {
        return Err(at("min_cutoff must be above 0 and beta at least 0"));
    }
    let name = c.name.clone().unwrap_or_else(|| match &source {
        Source::Gamepad { name } => name.clone(),
        other => other.to_string(),
    });
    Ok(Control {
        name,
        source,
        calibration,
        target,
        smoothing: (min_cutoff, beta),
        line,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GLOVE: &str = r#"
[filter]
beta = 0.1

[[control]]
name = "index"
osc = "/glove/flex"
arg = 1
min = 0.1
max = 0.9
curl = ["index.1", "index.2"]
angles = [0, 80]

[[control]]
midi = { channel = 2, cc = 7 }
invert = true
section = "jaw"
axis = [1, 0, 0]

[[control]]
osc = "/glove/wrist"
orientation = "hand"

[[control]]
gamepad = "South"
action = "record"
"#;

    #[test]
    fn a_file_reads_into_sources_targets_and_calibrations() {
        let f = ControlsFile::parse(GLOVE).unwrap();
        assert_eq!(f.controls.len(), 4);
        let c = &f.controls[0];
        assert_eq!(c.name, "index");
        assert_eq!(c.line, 5);
        assert_eq!(
            c.source,
            Source::Osc {
                address: "/glove/flex".into(),
                arg: 1
            }
        );
        assert_eq!(c.smoothing, (1.0, 0.1));
        assert!((c.calibration.apply(0.5) - 0.5).abs() < 1e-12);
        assert_eq!(c.calibration.apply(0.0), 0.0);
        assert_eq!(c.calibration.apply(2.0), 1.0);
        assert_eq!(f.controls[1].name, "midi 2 cc 7");
        assert_eq!(f.controls[1].calibration.apply(0.0), 1.0);
        assert!(matches!(
            &f.controls[1].target,
            Target::Turn { axis, angles, .. } if *axis == DVec3::X && *angles == [0.0, 90.0]
        ));
        assert_eq!(f.controls[3].target, Target::Action(Action::Record));
        assert_eq!(f.sections(), ["index.1", "index.2", "jaw", "hand"]);
    }

    #[test]
    fn a_file_written_reads_back_to_the_same_controls() {
        let mut f = ControlsFile::parse(GLOVE).unwrap();
        f.controls[0].calibration.dead_zone = 0.125;
        f.controls[0].smoothing = (0.3, 0.7);
        f.controls.push(Control {
            name: "a \"quoted\" name".into(),
            source: Source::MidiNote {
                channel: 16,
                note: 60,
            },
            calibration: Calibration {
                min: -1.0,
                max: 0.1 + 0.2,
                ..Calibration::default()
            },
            target: Target::Turn {
                sections: vec!["jaw".into()],
                axis: DVec3::new(0.6, 0.8, 0.0),
                angles: [-12.5, 1e-3],
            },
            smoothing: DEFAULT_SMOOTHING,
            line: 0,
        });
        let text = f.to_toml();
        let back = ControlsFile::parse(&text).unwrap();
        let unlined = |f: &ControlsFile| {
            let mut f = f.clone();
            for c in &mut f.controls {
                c.line = 0;
            }
            f
        };
        assert_eq!(unlined(&back), unlined(&f), "{text}");
        assert_eq!(back.to_toml(), text, "saving again gives the same bytes");
        assert!(text.contains("curl = [\"index.1\", \"index.2\"]"), "{text}");
    }

    #[test]
    fn every_error_names_its_line() {
        let bad = [
            (
                "[[control]]\nsection = \"jaw\"\n",
                "line 1: control '1': no source",
            ),
            (
                "[[control]]\nosc = \"/a\"\n",
                "line 1: control '1': no target",
            ),
            (
                "\n[[control]]\nosc = \"a\"\nsection = \"jaw\"\n",
                "line 2: control '1': osc = 'a' is not an OSC address",
            ),
            (
                "[[control]]\nosc = \"/a\"\ngamepad = \"South\"\nsection = \"x\"\n",
                "more than one source",
            ),
            (
                "[[control]]\nosc = \"/a\"\nsection = \"x\"\naction = \"play\"\n",
                "more than one target",
            ),
            (
                "[[control]]\nmidi = { channel = 17, cc = 1 }\nsection = \"x\"\n",
                "channel 17",
            ),
            (
                "[[control]]\nosc = \"/a\"\nsection = \"x\"\nmin = 1\nmax = 1\n",
                "same value",
            ),
            (
                "[[control]]\nosc = \"/a\"\nsection = \"x\"\nangles = [0, 1e9]\n",
                "within ±720",
            ),
            (
                "[[control]]\nosc = \"/a\"\nsection = \"x\"\naxis = [0, 0, 0]\n",
                "non-zero",
            ),
            (
                "[[control]]\ngamepad = \"X\"\norientation = \"hand\"\n",
                "OSC quaternion",
            ),
            (
                "[[control]]\nosc = \"/a\"\nsection = \"x\"\nspeed = 3\n",
                "line 4: unknown field `speed`",
            ),
            ("[[control]\n", "line 1:"),
            (
                "[[control]]\nosc = \"/a\"\naction = \"dance\"\n",
                "line 3: unknown variant `dance`",
            ),
        ];
        for (text, want) in bad {
            let e = ControlsFile::parse(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
            assert!(!e.contains('\n'), "{e}");
        }
    }
}
