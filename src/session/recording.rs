//! Recording a take: while recording, what the puppeteer does to the sections is sampled
//! at every simulation step; stopping thins the samples to keys
//! ([`crate::anim::record`]) and plays the take back (then *Save animation* keeps it and
//! `simulate` bakes it exactly as the window plays it).

use super::Session;
use crate::anim::record::Samples;

/// Recording settings and the take being recorded.
#[derive(Clone, Debug)]
pub struct Recorder {
    /// The take so far (`None`: not recording).
    pub take: Option<Samples>,
    /// Keys are kept where playback would otherwise miss the take by more than this
    /// (degrees).
    pub tolerance: f64,
    /// Simulated time per wall-clock time while recording (below 1: record in slow
    /// motion, play back at normal speed).
    pub speed: f32,
    /// What the last stop said (shown under the button).
    pub said: Option<String>,
}

impl Default for Recorder {
    fn default() -> Self {
        Recorder {
            take: None,
            tolerance: 1.0,
            speed: 1.0,
            said: None,
        }
    }
}

impl Session {
    /// Starts recording from the current pose (an animation playing stops: the take
    /// replaces it when recording stops).
    pub fn start_recording(&mut self) {
        if let Some(p) = &mut self.playback {
            p.playing = false;
        }
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

    /// Stops recording: the take becomes the animation and plays from the start. Returns
    /// what the panel says; a take in which nothing moved is dropped with a message.
    pub fn stop_recording(&mut self) -> Result<String, String> {
        let Some(take) = self.recorder.take.take() else {
            return Err("not recording".into());
        };
        let names: Vec<String> = self
            .puppet
            .joints
            .sections()
            .iter()
            .map(|s| s.name.clone())
            .collect();
        let size = self.puppet.mesh.diagonal();
        let animation = take.to_animation(&names, self.recorder.tolerance, size);
        if animation.track.is_empty() {
            return Err("nothing moved while recording: no take".into());
        }
        let keys: usize = animation.track.iter().map(|t| t.key.len()).sum();
        let said = format!(
            "recorded {:.1} s: {} keys in {} tracks (from {} samples)",
            animation.duration,
            keys,
            animation.track.len(),
            take.times.len()
        );
        self.set_animation(animation).map_err(|e| e.to_string())?;
        Ok(said)
    }

    /// Takes the frame's steps while recording: each step samples the pose.
    pub(super) fn record_steps(&mut self, seconds: f32, max_steps: u32) -> u32 {
        let speed = if self.recorder.speed.is_finite() {
            self.recorder.speed.clamp(0.05, 1.0)
        } else {
            1.0
        };
        let due = self.puppet.sim.steps_due(seconds * speed, max_steps);
        let h = self.puppet.sim.params().time_step as f64;
        for _ in 0..due {
            let pose = self.puppet.joints.pose_into(&self.local, &mut self.scratch);
            self.puppet.sim.step(pose);
            if let Some(take) = &mut self.recorder.take {
                let t = take.times.len() as f64 * h;
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
