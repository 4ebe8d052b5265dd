//! The One Euro filter (Casiez, Roussel and Vogel 2012, *1€ Filter: A Simple Speed-based
//! Low-pass Filter for Noisy Input in Interactive Systems*): a low-pass filter whose cutoff
//! rises with the signal's speed, so a still hand does not jitter and a fast one does not
//! lag. Two parameters: `min_cutoff` (Hz; lower: less jitter at rest) and `beta` (higher:
//! less lag when moving).

use std::f64::consts::TAU;

/// One signal's One Euro filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneEuro {
    /// Cutoff frequency at rest (Hz).
    pub min_cutoff: f64,
    /// How fast the cutoff rises with speed.
    pub beta: f64,
    /// Cutoff of the speed's own smoothing (Hz).
    pub d_cutoff: f64,
    /// Last output, last smoothed speed and the time of the last sample.
    state: Option<(f64, f64, f64)>,
}

impl OneEuro {
    /// A filter with these parameters and no history.
    pub fn new(min_cutoff: f64, beta: f64) -> OneEuro {
        OneEuro {
            min_cutoff,
            beta,
            d_cutoff: 1.0,
            state: None,
        }
    }

    /// The smoothing factor of a first-order low-pass at `cutoff` over `dt` seconds.
    fn alpha(cutoff: f64, dt: f64) -> f64 {
        let tau = 1.0 / (TAU * cutoff.max(1e-6));
        1.0 / (1.0 + tau / dt)
    }

    /// Filters `x`, sampled at `time` (seconds). The first sample passes unchanged; a
    /// sample no later than the last one replaces it without smoothing; a non-finite
    /// sample is ignored (the last output is returned).
    pub fn filter(&mut self, x: f64, time: f64) -> f64 {
        let Some((last, speed, t0)) = self.state else {
            if x.is_finite() && time.is_finite() {
                self.state = Some((x, 0.0, time));
            }
            return x;
        };
        if !x.is_finite() || !time.is_finite() {
            return last;
        }
        let dt = time - t0;
        if dt <= 0.0 {
            self.state = Some((x, speed, t0));
            return x;
        }
        let raw_speed = (x - last) / dt;
        let speed = speed + Self::alpha(self.d_cutoff, dt) * (raw_speed - speed);
        let cutoff = self.min_cutoff + self.beta * speed.abs();
        let out = last + Self::alpha(cutoff, dt) * (x - last);
        self.state = Some((out, speed, time));
        out
    }

    /// The last output, if any sample came.
    pub fn value(&self) -> Option<f64> {
        self.state.map(|s| s.0)
    }

    /// Forgets the history.
    pub fn reset(&mut self) {
        self.state = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jitter_at_rest_is_smoothed_and_a_fast_move_is_followed() {
        let mut f = OneEuro::new(1.0, 0.5);
        // At rest with ±0.05 noise at 100 Hz: the output stays within a fifth of it.
        let mut worst: f64 = 0.0;
        for k in 0..200 {
            let noise = if k % 2 == 0 { 0.05 } else { -0.05 };
            let y = f.filter(0.5 + noise, k as f64 / 100.0);
            if k > 50 {
                worst = worst.max((y - 0.5).abs());
            }
        }
        assert!(worst < 0.01, "{worst}");
        // A step to 1: followed to within 5 % in a tenth of a second.
        let mut y = 0.0;
        for k in 200..210 {
            y = f.filter(1.0, k as f64 / 100.0);
        }
        assert!(y > 0.95, "{y}");
        // With beta 0 the same step lags far behind: the speed term is what follows it.
        let mut slow = OneEuro::new(1.0, 0.0);
        slow.filter(0.5, 0.0);
        let mut z = 0.0;
        for k in 1..=10 {
            z = slow.filter(1.0, k as f64 / 100.0);
        }
        assert!(z < 0.8, "{z}");
    }

    #[test]
    fn hostile_samples_change_nothing() {
        let mut f = OneEuro::new(1.0, 0.1);
        assert_eq!(f.filter(0.3, 0.0), 0.3);
        assert_eq!(f.filter(f64::NAN, 0.01), 0.3);
        assert_eq!(f.filter(0.4, f64::INFINITY), 0.3);
        // Time going backwards: taken as it is, no division by a negative step.
        assert_eq!(f.filter(0.6, -5.0), 0.6);
        assert!(f.filter(0.6, 0.02).is_finite());
        f.reset();
        assert_eq!(f.value(), None);
    }
}
