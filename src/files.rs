//! Reading the project's text files (rigs, animations): TOML or JSON chosen by extension,
//! with syntax errors shortened to one line that says where.

use glam::DVec3;
use serde::de::DeserializeOwned;
use std::path::Path;

/// The serialization of a file, by extension: `.json` is JSON, anything else TOML.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// TOML (any extension but `.json`).
    Toml,
    /// JSON.
    Json,
}

impl Format {
    /// The format of `path` by its extension.
    pub fn of(path: &Path) -> Format {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("json") => Format::Json,
            _ => Format::Toml,
        }
    }
}

/// Why a text file could not be read; the message is one line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TextError {
    /// The file cannot be read (why, in words).
    #[error("cannot read file: {0}")]
    Read(String),
    /// Binary, or not UTF-8.
    #[error("not a text file (invalid UTF-8)")]
    NotText,
    /// Not valid TOML or JSON for what it should hold, with the line and column.
    #[error("{0}")]
    Syntax(String),
}

/// `v` at the precision files write: the `f64` of the shortest decimal that reads back to
/// `v`'s `f32` (`0.20000000298023224` → `0.2`). Exact for every `f32` (it reads back to
/// the same one), idempotent, and a file holding it reads back to the same `f64`; the
/// simulation runs on `f32`, so nothing it shows is lost. Non-finite values stay as they
/// are.
pub fn shortest(v: f64) -> f64 {
    if !v.is_finite() {
        return v;
    }
    let single = v as f32;
    if !single.is_finite() {
        return v;
    }
    single.to_string().parse().unwrap_or(v)
}

/// [`shortest`] of each coordinate.
pub fn shortest3(v: DVec3) -> DVec3 {
    DVec3::new(shortest(v.x), shortest(v.y), shortest(v.z))
}

/// Parses `text`; the error is one line naming the line and column.
pub fn parse<T: DeserializeOwned>(text: &str, format: Format) -> Result<T, TextError> {
    match format {
        Format::Toml => toml::from_str(text).map_err(|e| TextError::Syntax(one_line_toml(&e))),
        Format::Json => serde_json::from_str(text).map_err(|e| TextError::Syntax(e.to_string())),
    }
}

/// `TOML parse error at line 3, column 5: missing field `time``.
fn one_line_toml(e: &toml::de::Error) -> String {
    let text = e.to_string();
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let first = lines.next().unwrap_or("invalid TOML").trim().to_string();
    // The message is the last line after the source excerpt (`  |` lines).
    let message = text
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty() && !l.trim_start().starts_with('|') && !l.contains(" | "))
        .unwrap_or("")
        .trim();
    if message.is_empty() || message == first {
        first
    } else {
        format!("{first}: {message}")
    }
}

/// An I/O error in a few words ("no such file", "permission denied").
pub fn io_message(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => e.to_string(),
    }
}

/// Reads a whole text file; the error says why in words.
pub fn read_text(path: &Path) -> Result<String, TextError> {
    if path.is_dir() {
        return Err(TextError::Read("is a directory".into()));
    }
    let bytes = std::fs::read(path).map_err(|e| TextError::Read(io_message(&e)))?;
    String::from_utf8(bytes).map_err(|_| TextError::NotText)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize, Debug)]
    #[allow(dead_code)]
    struct T {
        a: f64,
    }

    #[test]
    fn toml_errors_are_one_line_with_a_position() {
        let e = parse::<T>("b = 1\n", Format::Toml).unwrap_err().to_string();
        assert!(!e.contains('\n'), "{e}");
        assert!(e.contains("line 1"), "{e}");
        assert!(e.contains("missing field `a`"), "{e}");
        let e = parse::<T>("{\"a\": \"x\"}", Format::Json)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1"), "{e}");
    }

    #[test]
    fn shortest_reads_back_to_the_same_single_and_is_short() {
        assert_eq!(shortest(0.2f32 as f64), 0.2);
        assert_eq!(shortest(0.8500000238418579), 0.85);
        assert_eq!(shortest(1.0 / 3.0).to_string(), "0.33333334");
        for v in [
            0.1f32,
            1e-30,
            3.4e38,
            -7.25,
            16_777_217.0,
            f32::MIN_POSITIVE,
        ] {
            let s = shortest(v as f64);
            assert_eq!(s as f32, v, "{v}");
            assert_eq!(shortest(s), s, "idempotent: {v}");
        }
        assert!(shortest(f64::NAN).is_nan());
        assert_eq!(shortest(1e300), 1e300, "beyond f32: as it is");
    }
}
