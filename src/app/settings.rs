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
    /// Anti-aliasing as last chosen in the panel (`msaa`, `fxaa`, `off`; a version's
    /// `true` and `false` read as `msaa` and `off`); unset: the adapter's default (on a
    /// GPU 4 samples, on a software renderer FXAA).
    pub anti_aliasing: Option<crate::render::AntiAliasing>,
    /// The lighting as last chosen in the panel (`studio`, `clay`, `jelly`); unset: the
    /// studio's. `--lighting` overrides it for one run without changing it.
    pub lighting: Option<crate::session::Lighting>,
}

impl Settings {
    /// The settings a file's text says. A setting this version cannot read (another
    /// version's lighting, `anti_aliasing = "yes"`) reads as unset, with a warning naming
    /// it, and the others are kept: a save after a bad value must not lose the recent
    /// files. Text that is not TOML at all gives the defaults, with a warning.
    pub fn parse(text: &str, path: &Path) -> Settings {
        let table: toml::Table = match text.parse() {
            Ok(table) => table,
            Err(e) => {
                log::warn!("{}: ignored: {}", path.display(), e.message());
                return Settings::default();
            }
        };
        // Each entry alone, so that one bad value drops only itself.
        let readable: toml::Table = table
            .into_iter()
            .filter(|(key, value)| {
                let alone = toml::Table::from_iter([(key.clone(), value.clone())]);
                match toml::Value::Table(alone).try_into::<Settings>() {
                    Ok(_) => true,
                    Err(e) => {
                        log::warn!(
                            "{}: {key} = {value}: ignored: {}",
                            path.display(),
                            e.message()
                        );
                        false
                    }
                }
            })
            .collect();
        toml::Value::Table(readable).try_into().unwrap_or_default()
    }

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
            Ok(text) => Settings::parse(&text, &path),
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
    use crate::render::AntiAliasing;
    use crate::session::Lighting;

    /// The lighting is written by name and read back; a value this version cannot read,
    /// in any setting, is dropped alone, the recent files kept.
    #[test]
    fn settings_round_trip_and_a_bad_value_loses_nothing_else() {
        let kept = Settings {
            recent: vec![PathBuf::from("/a/b.obj")],
            hint_done: true,
            anti_aliasing: Some(AntiAliasing::Fxaa),
            lighting: Some(Lighting::Jelly),
        };
        let text = toml::to_string_pretty(&kept).unwrap();
        assert!(text.contains("lighting = \"jelly\""), "{text}");
        assert!(text.contains("anti_aliasing = \"fxaa\""), "{text}");
        // The switch of earlier versions.
        for (old, now) in [("true", AntiAliasing::Msaa), ("false", AntiAliasing::Off)] {
            let read = Settings::parse(&format!("anti_aliasing = {old}"), Path::new("s.toml"));
            assert_eq!(read.anti_aliasing, Some(now), "anti_aliasing = {old}");
        }
        assert_eq!(Settings::parse(&text, Path::new("s.toml")), kept);
        for (key, bad) in [
            ("lighting", "\"metal\""),
            ("lighting", "3"),
            ("anti_aliasing", "\"yes\""),
            ("hint_done", "[1]"),
        ] {
            let text = text
                .lines()
                .map(|l| {
                    if l.starts_with(key) {
                        format!("{key} = {bad}")
                    } else {
                        l.to_string()
                    }
                })
                .collect::<Vec<_>>()
                .join("\n");
            let read = Settings::parse(&text, Path::new("s.toml"));
            assert_eq!(read.recent, kept.recent, "{key} = {bad}");
            let unset = Settings::default();
            let expect = match key {
                "lighting" => Settings {
                    lighting: unset.lighting,
                    ..kept.clone()
                },
                "anti_aliasing" => Settings {
                    anti_aliasing: unset.anti_aliasing,
                    ..kept.clone()
                },
                _ => Settings {
                    hint_done: unset.hint_done,
                    ..kept.clone()
                },
            };
            assert_eq!(read, expect, "{key} = {bad}");
        }
        assert_eq!(
            Settings::parse("recent = [", Path::new("s.toml")),
            Settings::default()
        );
    }
}
