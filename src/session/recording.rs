//! Recording a take: while recording, what the puppeteer does to the sections is sampled
//! at every simulation step; stopping thins the samples to keys
//! ([`crate::anim::record`]) and plays the take back (then *Save animation* keeps it and
//! `simulate` bakes it exactly as the window plays it).
//!
//! With an animation loaded, a take is recorded **over** it from where playback stands:
//! the animation goes on playing every section the puppeteer has not touched, and on stop
//! only the touched sections' keys are replaced over the take's time range (the old
//! motion takes over again with a short blend after it). Each take is one undo step.

use super::Session;
use crate::anim::record::{self, Samples};
use crate::anim::{Animation, Bound};
use crate::joints::Local;
use std::sync::Arc;

/// After a take recorded over an animation, the old motion comes back over this long
/// (seconds), not with a jump.
pub const BLEND_BACK: f64 = 0.25;

/// Recording settings and the take being recorded.
#[derive(Clone, Debug)]
pub struct Recorder {
    /// The take so far (`None`: not recording).
    pub take: Option<Samples>,
    /// The animation the take is recorded over, if any.
    over: Option<Over>,
    /// Keys are kept where playback would otherwise miss the take by more than this
    /// (degrees).
    pub tolerance: f64,
    /// Simulated time per wall-clock time while recording (below 1: record in slow
    /// motion, play back at normal speed).
    pub speed: f32,
    /// What the last stop said (shown under the button).
    pub said: Option<String>,
}

/// A take recorded over an animation.
#[derive(Clone, Debug)]
struct Over {
    /// The animation as it was.
    animation: Arc<Animation>,
    bound: Bound,
    /// Where the take starts in it (seconds).
    start: f64,
    /// Sections the puppeteer turned during the take.
    touched: Vec<bool>,
}

impl Default for Recorder {
    fn default() -> Self {
        Recorder {
            take: None,
            over: None,
            tolerance: 1.0,
            speed: 1.0,
            said: None,
        }
    }
}

impl Session {
    /// Starts recording from the current pose. With an animation loaded the take is
    /// recorded over it from the current playback time (see the module docs).
    pub fn start_recording(&mut self) {
        let h = self.puppet.sim.params().solver.time_step as f64;
        self.recorder.over = self.playback.as_mut().map(|p| {
            p.playing = false;
            Over {
                animation: p.animation.clone(),
                bound: p.bound.clone(),
                start: p.steps as f64 * h,
                touched: vec![false; self.local.len()],
            }
        });
        self.recorder.take = Some(Samples {
            times: vec![0.0],
            poses: vec![self.local.clone()],
        });
        self.wake();
    }

    /// True while recording.
    pub fn is_recording(&self) -> bool {
        self.recorder.take.is_some()
    }

    /// Seconds recorded so far.
    pub fn recorded_seconds(&self) -> f64 {
        self.recorder
            .take
            .as_ref()
            .and_then(|t| t.times.last().copied())
            .unwrap_or(0.0)
    }

    /// Marks sections turned by hand during a take recorded over an animation.
    pub(super) fn touch(&mut self, sections: &[usize]) {
        if let (Some(over), true) = (&mut self.recorder.over, self.recorder.take.is_some()) {
            for &s in sections {
                if let Some(t) = over.touched.get_mut(s) {
                    *t = true;
                }
            }
        }
    }

    /// Stops recording: the take becomes the animation (or goes into it, when recorded
    /// over one) and plays from the start; one undo step takes it back. Returns what the
    /// panel says; a take in which nothing moved is dropped with a message.
    pub fn stop_recording(&mut self) -> Result<String, String> {
        let Some(take) = self.recorder.take.take() else {
            return Err("not recording".into());
        };
        let over = self.recorder.over.take();
        let names: Vec<String> = self
            .puppet
            .joints
            .sections()
            .iter()
            .map(|s| s.name.clone())
            .collect();
        let size = self.puppet.mesh.diagonal();
        let tolerance = self.recorder.tolerance;
        let (animation, tracks) = match &over {
            None => {
                let a = take.to_animation(&names, tolerance, size);
                let n = a.track.len();
                (a, n)
            }
            Some(over) => merge(over, &take, &names, tolerance, size),
        };
        if tracks == 0 {
            if let (Some(p), Some(_)) = (&mut self.playback, &over) {
                p.playing = true;
            }
            return Err("nothing moved while recording: no take".into());
        }
        let keys: usize = animation.track.iter().map(|t| t.key.len()).sum();
        let said = match &over {
            None => format!(
                "recorded {:.1} s: {} keys in {} tracks (from {} samples)",
                animation.duration,
                keys,
                animation.track.len(),
                take.times.len()
            ),
            Some(o) => format!(
                "recorded {:.1} s over {:.1}–{:.1} s: {} tracks replaced there",
                take.times.last().copied().unwrap_or(0.0),
                o.start,
                o.start + take.times.last().copied().unwrap_or(0.0),
                tracks
            ),
        };
        self.checkpoint();
        self.set_animation(animation).map_err(|e| e.to_string())?;
        Ok(said)
    }

    /// Takes the frame's steps while recording: each step samples the pose (sections not
    /// touched in a take over an animation play it).
    pub(super) fn record_steps(&mut self, seconds: f32, max_steps: u32) -> u32 {
        let speed = if self.recorder.speed.is_finite() {
            self.recorder.speed.clamp(0.05, 1.0)
        } else {
            1.0
        };
        let due = self.puppet.sim.steps_due(seconds * speed, max_steps);
        let h = self.puppet.sim.params().solver.time_step as f64;
        let mut played = Vec::new();
        for _ in 0..due {
            let t = self.recorder.take.as_ref().map_or(0, |t| t.times.len()) as f64 * h;
            if let Some(over) = &self.recorder.over {
                over.bound.sample(over.start + t, &mut played);
                let before = self.local.clone();
                for (s, l) in self.local.iter_mut().enumerate() {
                    if !over.touched.get(s).copied().unwrap_or(true) {
                        *l = played.get(s).copied().unwrap_or_default();
                    }
                }
                self.puppet.hold_back(&before, &mut self.local);
            }
            let pose = self.puppet.joints.pose_into(&self.local, &mut self.scratch);
            self.puppet.sim.step(pose);
            if let Some(take) = &mut self.recorder.take {
                take.times.push(t);
                take.poses.push(self.local.clone());
            }
        }
        if due > 0 {
            self.revision += 1;
        }
        due
    }
}

/// The animation with a take recorded over it: the touched sections' motion is the take's
/// over its range, the animation's before it, and blends back to the animation's over
/// [`BLEND_BACK`] after it; each is thinned again to `tolerance`. Untouched sections keep
/// their tracks as they were. Returns the animation and how many tracks changed.
fn merge(
    over: &Over,
    take: &Samples,
    names: &[String],
    tolerance: f64,
    size: f64,
) -> (Animation, usize) {
    let mut animation = (*over.animation).clone();
    if !over.touched.contains(&true) {
        return (animation, 0);
    }
    let length = take.times.last().copied().unwrap_or(0.0);
    let end = over.start + length;
    let h = if take.times.len() > 1 {
        take.times[1] - take.times[0]
    } else {
        1.0 / 60.0
    };
    let duration = animation.duration.max(end);
    let count = (duration / h).ceil() as usize + 1;
    let times: Vec<f64> = (0..count).map(|k| (k as f64 * h).min(duration)).collect();
    let mut changed = 0;
    // What the animation played, at every time, once for all touched sections.
    let played: Vec<Vec<Local>> = times
        .iter()
        .map(|&t| {
            let mut pose = Vec::new();
            over.bound.sample(t, &mut pose);
            pose
        })
        .collect();
    for (s, name) in names.iter().enumerate() {
        if !over.touched.get(s).copied().unwrap_or(false) {
            continue;
        }
        let recorded = |k: usize| take.poses.get(k).and_then(|p| p.get(s)).copied();
        let last = recorded(take.poses.len().saturating_sub(1)).unwrap_or_default();
        let mut locals = Vec::with_capacity(count);
        for (&t, pose) in times.iter().zip(&played) {
            let old = pose.get(s).copied().unwrap_or_default();
            let l = if t < over.start - 1e-9 {
                old
            } else if t <= end + 1e-9 {
                let k = ((t - over.start) / h).round() as usize;
                recorded(k.min(take.poses.len() - 1)).unwrap_or(old)
            } else {
                let w = ((t - end) / BLEND_BACK).clamp(0.0, 1.0);
                blend(&last, &old, w * w * (3.0 - 2.0 * w))
            };
            locals.push(l);
        }
        animation.track.retain(|t| &t.section != name);
        let still = locals.iter().all(|l| *l == Local::default());
        if !still {
            animation
                .track
                .push(record::thin(&times, name, &locals, tolerance, size));
        }
        changed += 1;
    }
    animation.duration = duration;
    (animation, changed)
}

/// From `a` to `b` by `w` (rotation by slerp, translation linearly).
fn blend(a: &Local, b: &Local, w: f64) -> Local {
    Local {
        rotation: a.rotation.slerp(b.rotation, w).normalize(),
        translation: a.translation.lerp(b.translation, w),
    }
}
