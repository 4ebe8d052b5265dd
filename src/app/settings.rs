//! What the app remembers between runs: recent files, whether the first-run hint was
//! followed, anti-aliasing turned on or off, and the lighting chosen. Kept in `settings.toml` under `$PUPPET_CONFIG_DIR`, else
//! `$XDG_CONFIG_HOME/puppet`, else `~/.config/puppet`; best effort (a settings file that
//! cannot be read or written is logged and otherwise ignored).

use std::path::{Path, PathBuf};

/// How many recent files are kept.
pub const RECENT: usize = 8;

/// The remembered settings.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Meshes and rigs opened, the latest first.
    pub recent: Vec<PathBuf>,
    /// The puppeteer has turned a section once: no more first-run hint.
    pub hint_done: bool,
    /// Anti-aliasing as last set in the panel; unset: the adapter's default (on a GPU,
    /// off on a software renderer).
    pub anti_aliasing: Option<bool>,
    /// The lighting as last chosen in the panel (`studio`, `clay`, `jelly`); unset: the
    /// studio's. `--lighting` overrides it for one run without changing it. A value this
    /// version does not know (another version's lighting) reads as unset, with a warning,
    /// instead of losing the rest of the file.
    #[serde(deserialize_with = "known_lighting")]
    pub lighting: Option<crate::session::Lighting>,
}

/// A lighting by its name, or none for a value that names no lighting here.
fn known_lighting<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<crate::session::Lighting>, D::Error> {
    use clap::ValueEnum;
    let value = <Option<toml::Value> as serde::Deserialize>::deserialize(d)?;
    Ok(value.and_then(|v| {
        let known = v
            .as_str()
            .and_then(|s| crate::session::Lighting::from_str(s, true).ok());
        if known.is_none() {
            log::warn!("settings.toml: lighting = {v}: not a lighting here, ignored");
        }
        known
    }))
}

impl Settings {
    /// The folder the settings live in, if one can be named.
    fn dir() -> Option<PathBuf> {
        let var = |k: &str| {
            std::env::var_os(k)
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
        };
        var("PUPPET_CONFIG_DIR")
            .or_else(|| var("XDG_CONFIG_HOME").map(|d| d.join("puppet")))
            .or_else(|| var("HOME").map(|d| d.join(".config/puppet")))
    }

    /// Reads the settings (defaults when there are none or they cannot be read).
    pub fn load() -> Settings {
        let Some(path) = Self::dir().map(|d| d.join("settings.toml")) else {
            return Settings::default();
        };
        match std::fs::read_to_string(&path) {
            Ok(text) => toml::from_str(&text).unwrap_or_else(|e| {
                log::warn!("{}: ignored: {}", path.display(), e.message());
                Settings::default()
            }),
            Err(_) => Settings::default(),
        }
    }

    /// Writes the settings (a failure is logged).
    pub fn save(&self) {
        let Some(dir) = Self::dir() else {
            return;
        };
        let path = dir.join("settings.toml");
        let result = std::fs::create_dir_all(&dir)
            .and_then(|()| std::fs::write(&path, toml::to_string_pretty(self).unwrap_or_default()));
        if let Err(e) = result {
            log::warn!("{}: cannot write: {e}", path.display());
        }
    }

    /// Puts `path` first in the recent files (once) and saves.
    pub fn opened(&mut self, path: &Path) {
        let path = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        self.recent.retain(|p| *p != path);
        self.recent.insert(0, path);
        self.recent.truncate(RECENT);
        self.save();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::Lighting;

    /// The lighting is written by name and read back; one this version does not know is
    /// dropped alone, the recent files kept.
    #[test]
    fn the_lighting_round_trips_and_an_unknown_one_loses_nothing_else() {
        let kept = Settings {
            recent: vec![PathBuf::from("/a/b.obj")],
            lighting: Some(Lighting::Jelly),
            ..Settings::default()
        };
        let text = toml::to_string_pretty(&kept).unwrap();
        assert!(text.contains("lighting = \"jelly\""), "{text}");
        assert_eq!(toml::from_str::<Settings>(&text).unwrap(), kept);
        for other in ["\"metal\"", "3"] {
            let read: Settings =
                toml::from_str(&format!("recent = [\"/a/b.obj\"]\nlighting = {other}\n")).unwrap();
            assert_eq!(read.lighting, None, "{other}");
            assert_eq!(read.recent, kept.recent, "{other}");
        }
    }
}
