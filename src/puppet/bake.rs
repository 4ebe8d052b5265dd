//! Baking a take: playing an animation (or the rest pose) on the fixed step from rest and
//! keeping the surface at chosen frames. `simulate` and the window's *Export animation*
//! both play through [`Player`], so they give the same frames bit for bit; the window's
//! playback steps through [`Puppet::step_animated`] like [`Player::step`] does.

use super::Puppet;
use crate::anim::Bound;
use crate::joints::{Local, PoseScratch};

/// Plays an animation (or holds the rest pose) one fixed step at a time, counting steps
/// and frames as `simulate` does: frame `k` (1-based) shows time `k / fps`.
pub struct Player {
    bound: Option<Bound>,
    fps: f64,
    steps: u64,
    local: Vec<Local>,
    scratch: PoseScratch,
}

impl Player {
    /// A player at the start (the puppet is expected at rest: see
    /// [`crate::sim::Simulation::reset`]).
    pub fn new(bound: Option<Bound>, fps: f64) -> Player {
        Player {
            bound,
            fps,
            steps: 0,
            local: Vec::new(),
            scratch: PoseScratch::default(),
        }
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Steps done by the end of frame `frame` on a step of `h` seconds (the tolerance
    /// absorbs the rounding of an `f32` step: 1/60 is not exact).
    pub fn steps_by(&self, h: f64, frame: u64) -> u64 {
        (frame as f64 / self.fps / h + 1e-4).floor() as u64
    }

    /// One simulation step.
    pub fn step(&mut self, puppet: &mut Puppet) {
        self.steps += 1;
        match &self.bound {
            Some(b) => puppet.step_animated(b, self.steps, &mut self.local, &mut self.scratch),
            None => {
                self.local.clear();
                let pose = puppet.joints.pose_into(&self.local, &mut self.scratch);
                puppet.sim.step(pose);
            }
        }
    }

    /// Steps until frame `frame` is done.
    pub fn play_to(&mut self, puppet: &mut Puppet, frame: u64) {
        let target = self.steps_by(puppet.sim.params().solver.time_step as f64, frame);
        while self.steps < target {
            self.step(puppet);
        }
    }
}

/// Which frames a bake keeps: `first`, `first + step`, … up to `last` (1-based, at `fps`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRange {
    /// First kept frame (≥ 1).
    pub first: u64,
    /// Last frame played (≥ `first`).
    pub last: u64,
    /// Every `step`th frame from `first` is kept (≥ 1).
    pub step: u64,
    /// Frames per second.
    pub fps: f64,
}

/// Frames beyond this are refused (a typo, not a render).
pub const MAX_FRAMES: u64 = 10_000_000;

impl FrameRange {
    /// Every frame of `seconds` at `fps` (at least one).
    pub fn of_duration(seconds: f64, fps: f64) -> FrameRange {
        let last = (seconds * fps).ceil();
        let last = if last.is_finite() {
            (last as u64).clamp(1, MAX_FRAMES)
        } else {
            1
        };
        FrameRange {
            first: 1,
            last,
            step: 1,
            fps,
        }
    }

    /// Says what is wrong with the range, if anything.
    pub fn check(&self) -> Result<(), String> {
        if !(self.fps.is_finite() && self.fps > 0.0 && self.fps <= 10_000.0) {
            return Err(format!(
                "{} frames per second must be in (0, 10000]",
                self.fps
            ));
        }
        if self.last == 0 || self.last > MAX_FRAMES {
            return Err(format!(
                "last frame {} must be in 1..={MAX_FRAMES}",
                self.last
            ));
        }
        if self.first == 0 || self.first > self.last {
            return Err(format!(
                "first frame {} must be in 1..={} (the last frame)",
                self.first, self.last
            ));
        }
        if self.step == 0 {
            return Err("the frame step must be at least 1".into());
        }
        Ok(())
    }

    /// True when frame `frame` is kept.
    pub fn keeps(&self, frame: u64) -> bool {
        frame >= self.first && frame <= self.last && (frame - self.first).is_multiple_of(self.step)
    }

    /// How many frames are kept.
    pub fn count(&self) -> u64 {
        if self.first == 0 || self.first > self.last || self.step == 0 {
            return 0;
        }
        (self.last - self.first) / self.step + 1
    }
}

/// Why a bake stopped.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum BakeError {
    /// The range is not valid (the message says why).
    #[error("{0}")]
    Range(String),
    /// The caller cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The frame sink failed (a file could not be written).
    #[error("{0}")]
    Sink(String),
}

/// Plays `bound` (or the rest pose) from rest through `range.last` frames and hands every
/// kept frame's puppet to `sink` with the frame's number. After every frame `go` gets the
/// fraction done and returns false to cancel. The puppet is reset to rest first and left
/// at the last frame.
///
/// # Errors
/// [`BakeError`]: a bad range, a cancel, or the sink's error.
pub fn bake(
    puppet: &mut Puppet,
    bound: Option<Bound>,
    range: &FrameRange,
    sink: &mut dyn FnMut(u64, &Puppet) -> Result<(), String>,
    go: &mut dyn FnMut(f64) -> bool,
) -> Result<(), BakeError> {
    bake_in(
        puppet,
        bound,
        range,
        &mut |f, p: &mut Puppet| sink(f, p),
        go,
    )
}

/// [`bake`] of the puppet `owner` holds, handing `sink` the owner (a session, whose view
/// a video draws, woken for it).
///
/// # Errors
/// As [`bake`].
pub fn bake_in<T: AsMut<Puppet>>(
    owner: &mut T,
    bound: Option<Bound>,
    range: &FrameRange,
    sink: &mut dyn FnMut(u64, &mut T) -> Result<(), String>,
    go: &mut dyn FnMut(f64) -> bool,
) -> Result<(), BakeError> {
    range.check().map_err(BakeError::Range)?;
    owner.as_mut().sim.reset();
    let mut player = Player::new(bound, range.fps);
    for frame in 1..=range.last {
        player.play_to(owner.as_mut(), frame);
        if range.keeps(frame) {
            sink(frame, owner).map_err(BakeError::Sink)?;
        }
        if !go(frame as f64 / range.last as f64) {
            return Err(BakeError::Cancelled);
        }
    }
    Ok(())
}

impl AsMut<Puppet> for Puppet {
    fn as_mut(&mut self) -> &mut Puppet {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges() {
        let r = FrameRange {
            first: 3,
            last: 10,
            step: 3,
            fps: 30.0,
        };
        assert!(r.check().is_ok());
        assert_eq!(r.count(), 3);
        let kept: Vec<u64> = (1..=12).filter(|&f| r.keeps(f)).collect();
        assert_eq!(kept, vec![3, 6, 9]);
        for bad in [
            FrameRange { first: 0, ..r },
            FrameRange { first: 11, ..r },
            FrameRange { step: 0, ..r },
            FrameRange { fps: f64::NAN, ..r },
            FrameRange {
                last: MAX_FRAMES + 1,
                ..r
            },
        ] {
            assert!(bad.check().is_err(), "{bad:?}");
        }
        assert_eq!(FrameRange::of_duration(2.0, 30.0).last, 60);
        assert_eq!(FrameRange::of_duration(f64::INFINITY, 30.0).last, 1);
    }
}
