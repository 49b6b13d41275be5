//! A still start: the paper's operator holds the ball at its release angle for about a
//! second before letting it go. A first look spent on a held ball sees little of the
//! swing (its sweep, its pivot and its region come out poor, or no moving wire at
//! all), so the look keeps only the last few frames of a still start and begins its
//! clock there: its frames span the first seconds of the motion.
//!
//! A frame is still when it matches the look's first frame (both brought to the same
//! brightness) within the sensor's noise at all but a few pixels. The noise is read
//! from the first two frames: the wire and the ball cover a minority of the pixels, so
//! the median difference is the noise's whether or not they move.

use crate::detect::tuning::{
    MOVED_LEVELS, MOVED_SIGMAS, MOVING_MIN, STILL_MOVING_SHARE, STILL_SAMPLE_STEP,
};

/// Whether the scene has moved since the first frame (latched: once moving, always).
pub(super) struct Stillness {
    first: Vec<u8>,
    threshold: Option<u8>,
    moving: bool,
}

impl Stillness {
    /// Against `first`, the look's first frame (brightness-normalised frames follow).
    pub(super) fn new(first: &[u8]) -> Self {
        Self {
            first: first.iter().step_by(STILL_SAMPLE_STEP).copied().collect(),
            threshold: None,
            moving: false,
        }
    }

    /// Whether the scene moved by `frame` (the first one asked about sets the noise).
    pub(super) fn moved(&mut self, frame: &[u8]) -> bool {
        if self.moving {
            return true;
        }
        let samples = frame.iter().step_by(STILL_SAMPLE_STEP);
        if samples.len() != self.first.len() || self.first.is_empty() {
            self.moving = true;
            return true;
        }
        let threshold = *self.threshold.get_or_insert_with(|| {
            let mut d: Vec<u8> = samples
                .clone()
                .zip(&self.first)
                .map(|(a, b)| a.abs_diff(*b))
                .collect();
            let mid = d.len() / 2;
            let median = *d.select_nth_unstable(mid).1 as f64;
            // 1.4826 MAD is sigma for Gaussian noise; a median of 0 (identical
            // quantised pixels) leaves the floor.
            (MOVED_SIGMAS * 1.4826 * median).clamp(MOVED_LEVELS, 250.0) as u8
        });
        let moved = samples
            .zip(&self.first)
            .filter(|(a, b)| a.abs_diff(**b) > threshold)
            .count();
        self.moving =
            moved > MOVING_MIN.max((STILL_MOVING_SHARE * self.first.len() as f64) as usize);
        self.moving
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A noisy textured frame (grey levels 60..200, noise of a few levels from `seed`),
    /// with a dark disc of radius 12 at `x`.
    fn frame(seed: u64, x: f64) -> Vec<u8> {
        let (w, h) = (320usize, 240usize);
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
        (0..w * h)
            .map(|i| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let noise = ((s >> 33) % 7) as f64 - 3.0;
                let (px, py) = ((i % w) as f64, (i / w) as f64);
                if (px - x).hypot(py - 120.0) < 12.0 {
                    20
                } else {
                    (60.0 + ((i * 37) % 141) as f64 + noise) as u8
                }
            })
            .collect()
    }

    #[test]
    fn a_held_ball_is_still_and_a_moving_one_is_not() {
        let mut s = Stillness::new(&frame(1, 100.0));
        // Frames of the held ball differ by their noise only.
        for seed in 2..20 {
            assert!(!s.moved(&frame(seed, 100.0)), "still frame {seed}");
        }
        // The ball a few pixels on: moving, and latched.
        assert!(s.moved(&frame(30, 104.0)));
        assert!(s.moved(&frame(31, 100.0)));
    }

    #[test]
    fn a_frame_of_another_size_counts_as_motion() {
        let mut s = Stillness::new(&frame(1, 100.0));
        assert!(s.moved(&[0u8; 100]));
    }
}
