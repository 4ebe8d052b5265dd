//! Playing an animation file in the window: play, pause, restart, loop and scrub. Every
//! step samples the pose at `step × h` through [`crate::puppet::Puppet::step_animated`],
//! the same call `simulate` makes, from the same rest state, so what the window previews is
//! what `simulate` bakes, bit for bit.

use super::Session;
use crate::anim::{AnimError, Animation, Bound};
use crate::joints::Local;
use std::sync::Arc;

/// An animation bound to the puppet's sections, and where its playback is.
#[derive(Clone, Debug)]
pub struct Playback {
    /// The animation as loaded (saved back as it is; shared with the undo history).
    pub animation: Arc<Animation>,
    pub(super) bound: Bound,
    /// Steps played since the start.
    pub steps: u64,
    /// Stepping on.
    pub playing: bool,
    /// Plays only this part (seconds, from < to) over and over: at its end playback goes
    /// back to its start, re-simulated from rest (so each pass is what the bake shows
    /// there). Not saved with the animation.
    pub loop_range: Option<(f64, f64)>,
}

/// Longest scrub, in steps (a scrub re-simulates from the start).
const MAX_SCRUB_STEPS: u64 = 1_000_000;

impl Session {
    /// Loads an animation: bound to the sections by name, the puppet back at rest, playing
    /// from the start. On error nothing changes.
    pub fn set_animation(&mut self, animation: Animation) -> Result<(), AnimError> {
        self.set_shared_animation(Arc::new(animation))
    }

    /// [`Session::set_animation`] with an animation the undo history may share.
    pub(super) fn set_shared_animation(
        &mut self,
        animation: Arc<Animation>,
    ) -> Result<(), AnimError> {
        animation.check()?;
        let bound = animation.bind(&self.puppet.joints)?;
        self.playback = Some(Playback {
            animation,
            bound,
            steps: 0,
            playing: true,
            loop_range: None,
        });
        self.restart();
        Ok(())
    }

    /// The clips of the mesh file's skin, with their lengths in seconds (none without one).
    pub fn clips(&self) -> Vec<(String, f64)> {
        self.puppet
            .joints
            .skin()
            .map(|s| {
                s.clips
                    .iter()
                    .map(|c| (c.name.clone(), c.duration))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Plays the skin's clip `name` as the animation ([`crate::anim::clip`]): the sections
    /// named after its joints move as the clip moves them. On error nothing changes.
    pub fn play_clip(&mut self, name: &str) -> Result<(), AnimError> {
        let skin = self
            .puppet
            .joints
            .skin()
            .cloned()
            .ok_or_else(|| AnimError("the mesh file has no skin, so no clips".into()))?;
        let clip = skin
            .clips
            .iter()
            .find(|c| c.name == name)
            .ok_or_else(|| AnimError(format!("no clip named '{name}'")))?;
        let animation = crate::anim::clip::animation(clip, &skin, &self.puppet.joints);
        self.set_animation(animation)
    }

    /// Back to the start of the animation, the puppet at rest.
    pub fn restart(&mut self) {
        if let Some(p) = &mut self.playback {
            p.steps = 0;
            self.puppet.sim.reset();
            let mut local = Vec::new();
            p.bound.sample(0.0, &mut local);
            self.local = local;
            self.wake();
        }
    }

    /// Plays or pauses the animation.
    pub fn toggle_play(&mut self) {
        if let Some(p) = &mut self.playback {
            p.playing ^= true;
            self.wake();
        }
    }

    /// Seconds into the animation, and its duration.
    pub fn playback_time(&self) -> Option<(f64, f64)> {
        let p = self.playback.as_ref()?;
        let h = self.puppet.sim.params().solver.time_step as f64;
        Some((p.steps as f64 * h, p.animation.duration))
    }

    /// Jumps to `seconds`: the simulation runs from rest to there (a physical simulation
    /// has no shortcut), then holds, paused.
    pub fn scrub(&mut self, seconds: f64) {
        let h = self.puppet.sim.params().solver.time_step as f64;
        if self.playback.is_none() || !seconds.is_finite() {
            return;
        }
        let target = ((seconds.max(0.0) / h).round() as u64).min(MAX_SCRUB_STEPS);
        self.restart();
        self.play_steps(target);
        if let Some(p) = &mut self.playback {
            p.playing = false;
        }
    }

    /// Takes `n` steps of the animation.
    pub(super) fn play_steps(&mut self, n: u64) {
        let Some(p) = &mut self.playback else {
            return;
        };
        for _ in 0..n {
            p.steps += 1;
            self.puppet
                .step_animated(&p.bound, p.steps, &mut self.local, &mut self.scratch);
        }
        self.revision += 1;
    }

    /// True while an animation drives the pose.
    pub fn is_playing(&self) -> bool {
        self.playback.as_ref().is_some_and(|p| p.playing)
    }

    /// The pose the animation holds now, as played (with collision on, held back where a
    /// part met another): what a turn by hand starts from.
    pub fn animated_pose(&self) -> Option<Vec<Local>> {
        self.playback.as_ref()?;
        Some(self.local.clone())
    }
}

impl Session {
    /// Plays only `range` (seconds) over and over, or the whole animation with `None`. A
    /// range that is empty or not finite is ignored.
    pub fn set_loop_range(&mut self, range: Option<(f64, f64)>) {
        let Some(p) = &mut self.playback else {
            return;
        };
        p.loop_range = match range {
            Some((a, b)) if a.is_finite() && b.is_finite() && b > a.max(0.0) => {
                Some((a.max(0.0), b))
            }
            Some(_) => return,
            None => None,
        };
        self.wake();
    }

    /// At the end of the loop range: back to its start, still playing.
    pub(super) fn wrap_loop_range(&mut self) {
        let Some((t, _)) = self.playback_time() else {
            return;
        };
        let Some(p) = &self.playback else {
            return;
        };
        if let (Some((from, to)), true) = (p.loop_range, p.playing) {
            if t >= to {
                self.scrub(from);
                if let Some(p) = &mut self.playback {
                    p.playing = true;
                }
            }
        }
    }

    /// Loops the animation or not (kept in it, so saving writes it).
    pub fn set_looping(&mut self, looping: bool) {
        let joints = &self.puppet.joints;
        if let Some(p) = &mut self.playback {
            Arc::make_mut(&mut p.animation).looping = looping;
            if let Ok(bound) = p.animation.bind(joints) {
                p.bound = bound;
            }
            self.wake();
        }
    }
}

impl Session {
    /// Reads an animation file (TOML, or JSON by extension) and plays it; returns what the
    /// panel says. On error the puppet and any animation loaded stay as they were.
    pub fn open_animation(&mut self, path: &std::path::Path) -> Result<String, String> {
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into(),
        );
        let text = crate::files::read_text(path).map_err(|e| format!("{name}: {e}"))?;
        let animation = Animation::parse(&text, crate::files::Format::of(path))
            .map_err(|e| format!("{name}: {e}"))?;
        animation
            .bind(&self.puppet.joints)
            .map_err(|e| format!("{name}: {e}"))?;
        self.checkpoint();
        self.set_animation(animation)
            .map_err(|e| format!("{name}: {e}"))?;
        Ok(format!("playing {name}"))
    }

    /// Writes the loaded animation (TOML, or JSON by extension); returns what the panel
    /// says.
    pub fn save_animation(&self, path: &std::path::Path) -> Result<String, String> {
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into(),
        );
        let Some(p) = &self.playback else {
            return Err("no animation to save (open one first)".into());
        };
        let text = match crate::files::Format::of(path) {
            crate::files::Format::Json => {
                serde_json::to_string_pretty(&*p.animation).map_err(|e| e.to_string())?
            }
            crate::files::Format::Toml => p.animation.to_toml(),
        };
        std::fs::write(path, text)
            .map(|()| format!("saved {name}"))
            .map_err(|e| format!("{name}: cannot write: {}", crate::files::io_message(&e)))
    }
}

/// True when `path` holds an animation file (its text parses as one with tracks): what
/// a file dropped on the window is taken for before a rig.
pub fn is_animation_file(path: &std::path::Path) -> bool {
    crate::files::read_text(path).is_ok_and(|text| {
        Animation::parse(&text, crate::files::Format::of(path)).is_ok_and(|a| !a.track.is_empty())
    })
}
