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
//!
//! A camera in the hand moves the whole picture while the ball is held: a frame that
//! differs from the first is compared again where the camera's motion puts each pixel,
//! allowing for the motion's error at the first frame's edges ([`STILL_EDGE_PX`]), and
//! is still when it matches there (the motion one that moves the frame by more than
//! `MOVING_PX` and explains it: see `FirstLook::at`). A still camera's alignment, pulled after a ball just released, may explain the
//! frame too, and its still start would keep a frame or two more: so a look compares
//! under the camera's motion only when the look as it lies found the camera moving and
//! no wire (see `FirstLook::at`).

use crate::detect::steady::Motion;
use crate::detect::tuning::{
    MOVED_LEVELS, MOVED_SIGMAS, MOVING_MIN, STILL_EDGE_PX, STILL_MOVING_SHARE, STILL_SAMPLE_STEP,
};
use anyhow::Result;

/// Whether the scene has moved since the first frame (latched: once moving, always).
pub(super) struct Stillness {
    first: Vec<u8>,
    /// The first frame's gradient at each compared pixel, grey levels per px.
    gradient: Vec<f32>,
    /// The frame's width and height, px.
    size: (usize, usize),
    threshold: Option<u8>,
    /// The threshold of a frame compared under the camera's motion (its noise is the
    /// interpolated frame's).
    threshold_under: Option<f32>,
    moving: bool,
}

impl Stillness {
    /// Against `first`, the look's first frame of `width` px (brightness-normalised
    /// frames follow).
    pub(super) fn new(first: &[u8], width: usize) -> Self {
        let w = width.max(1);
        let h = first.len() / w;
        let at = |x: usize, y: usize| f32::from(first[y * w + x]);
        let gradient = (0..first.len())
            .step_by(STILL_SAMPLE_STEP)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let gx = at((x + 1).min(w - 1), y) - at(x.saturating_sub(1), y);
                let gy = at(x, (y + 1).min(h.max(1) - 1)) - at(x, y.saturating_sub(1));
                0.5 * gx.hypot(gy)
            })
            .collect();
        Self {
            first: first.iter().step_by(STILL_SAMPLE_STEP).copied().collect(),
            gradient,
            size: (w, h),
            threshold: None,
            threshold_under: None,
            moving: false,
        }
    }

    /// Whether the scene moved by `frame` (the first one asked about sets the noise).
    /// A frame that differs is compared again under the camera's motion against the
    /// first frame, when `camera` measures one (a frame still there is still).
    pub(super) fn moved(
        &mut self,
        frame: &[u8],
        camera: impl FnOnce() -> Result<Option<Motion>>,
    ) -> Result<bool> {
        if self.moving {
            return Ok(true);
        }
        let samples = frame.iter().step_by(STILL_SAMPLE_STEP);
        if samples.len() != self.first.len() || self.first.is_empty() {
            self.moving = true;
            return Ok(true);
        }
        let threshold = *self.threshold.get_or_insert_with(|| {
            let d: Vec<f32> = samples
                .clone()
                .zip(&self.first)
                .map(|(a, b)| f32::from(a.abs_diff(*b)))
                .collect();
            noise_threshold(d) as u8
        });
        let moved = samples
            .zip(&self.first)
            .filter(|(a, b)| a.abs_diff(**b) > threshold)
            .count();
        if moved <= self.most_still() {
            return Ok(false);
        }
        if let Some(m) = camera()? {
            if self.still_under(frame, m) {
                return Ok(false);
            }
        }
        self.moving = true;
        Ok(true)
    }

    /// The most compared pixels that may differ in a still frame.
    fn most_still(&self) -> usize {
        MOVING_MIN.max((STILL_MOVING_SHARE * self.first.len() as f64) as usize)
    }

    /// Whether `frame` matches the first frame where motion `m` puts each of its pixels
    /// (see [`Motion`]), within the noise and the motion's error at an edge.
    fn still_under(&mut self, frame: &[u8], m: Motion) -> bool {
        let (w, h) = self.size;
        if frame.len() != w * h || w < 2 || h < 2 {
            return false;
        }
        let (c, s) = (m.rot_rad.cos(), m.rot_rad.sin());
        let (cx, cy) = (0.5 * (w as f64 - 1.0), 0.5 * (h as f64 - 1.0));
        let px = |x: usize, y: usize| f32::from(frame[y * w + x]);
        // The difference at each compared pixel the frame shows (none off its edge).
        let diffs: Vec<(f32, f32)> = (0..w * h)
            .step_by(STILL_SAMPLE_STEP)
            .zip(self.first.iter().zip(&self.gradient))
            .filter_map(|(i, (&f, &g))| {
                let (x, y) = ((i % w) as f64 - cx, (i / w) as f64 - cy);
                let (u, v) = (cx + c * x - s * y + m.dx, cy + s * x + c * y + m.dy);
                if u < 0.0 || v < 0.0 || u > (w - 1) as f64 || v > (h - 1) as f64 {
                    return None;
                }
                let (x0, y0) = ((u as usize).min(w - 2), (v as usize).min(h - 2));
                let (a, b) = ((u - x0 as f64) as f32, (v - y0 as f64) as f32);
                let top = px(x0, y0) + a * (px(x0 + 1, y0) - px(x0, y0));
                let bottom = px(x0, y0 + 1) + a * (px(x0 + 1, y0 + 1) - px(x0, y0 + 1));
                let grey = top + b * (bottom - top);
                Some(((grey - f32::from(f)).abs(), g))
            })
            .collect();
        let threshold = *self
            .threshold_under
            .get_or_insert_with(|| noise_threshold(diffs.iter().map(|d| d.0).collect()) as f32);
        let edge = STILL_EDGE_PX as f32;
        let moved = diffs
            .iter()
            .filter(|(d, g)| *d > threshold + edge * g)
            .count();
        moved <= self.most_still()
    }
}

/// The difference over which a pixel moved, from the differences `d` of a frame's
/// compared pixels: [`MOVED_SIGMAS`] times their noise (1.4826 times the median absolute
/// difference is sigma for Gaussian noise), at least [`MOVED_LEVELS`] (a median of 0,
/// identical quantised pixels, leaves the floor).
fn noise_threshold(mut d: Vec<f32>) -> f64 {
    if d.is_empty() {
        return MOVED_LEVELS;
    }
    let mid = d.len() / 2;
    let median = f64::from(*d.select_nth_unstable_by(mid, f32::total_cmp).1);
    (MOVED_SIGMAS * 1.4826 * median).clamp(MOVED_LEVELS, 250.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// A noisy textured frame (grey levels 60..200, noise of a few levels from `seed`),
    /// with a dark disc of radius 12 at `x`.
    fn frame(seed: u64, x: f64) -> Vec<u8> {
        let (w, h) = (320usize, 240usize);
        let mut rng = Rng::new(seed);
        (0..w * h)
            .map(|i| {
                let noise = (rng.next_u64() % 7) as f64 - 3.0;
                let (px, py) = ((i % w) as f64, (i / w) as f64);
                if (px - x).hypot(py - 120.0) < 12.0 {
                    20
                } else {
                    (60.0 + ((i * 37) % 141) as f64 + noise) as u8
                }
            })
            .collect()
    }

    /// No camera motion measured.
    fn none() -> Result<Option<Motion>> {
        Ok(None)
    }

    /// A noisy frame of a smooth texture with strong edges (grey levels about 40..210)
    /// and a dark disc of radius 12 at `(x, 120)`, both as a camera moved by `m` shows
    /// them (see [`Motion`]).
    fn seen_under(seed: u64, x: f64, m: Motion) -> Vec<u8> {
        let (w, h) = (320usize, 240usize);
        let (cx, cy) = (0.5 * (w as f64 - 1.0), 0.5 * (h as f64 - 1.0));
        let (c, s) = (m.rot_rad.cos(), m.rot_rad.sin());
        let mut rng = Rng::new(seed);
        (0..w * h)
            .map(|i| {
                let noise = (rng.next_u64() % 5) as f64 - 2.0;
                // The first frame's point this pixel shows: p = c + R^T (q - c - t).
                let (qx, qy) = ((i % w) as f64 - cx - m.dx, (i / w) as f64 - cy - m.dy);
                let (px, py) = (cx + c * qx + s * qy, cy - s * qx + c * qy);
                if (px - x).hypot(py - 120.0) < 12.0 {
                    return 20;
                }
                // Stripes 16 px apart with edges a pixel or two wide, and a slow shading.
                let stripe = 85.0 * (1.0 + (0.4 * (px + 0.3 * py)).sin().tanh() * 1.3).min(2.0);
                (40.0 + stripe.clamp(0.0, 150.0) + 0.05 * py + noise).clamp(0.0, 255.0) as u8
            })
            .collect()
    }

    #[test]
    fn a_held_ball_is_still_under_a_moving_camera_and_a_moving_one_is_not() {
        let hand = Motion {
            dx: 1.7,
            dy: -1.2,
            rot_rad: 0.3f64.to_radians(),
        };
        let first = seen_under(1, 100.0, Motion::default());
        let mut s = Stillness::new(&first, 320);
        let still = seen_under(2, 100.0, Motion::default());
        assert!(!s.moved(&still, none).unwrap());
        // The camera moved: the frame differs from the first at its edges ...
        let moved_camera = seen_under(3, 100.0, hand);
        let mut raw = Stillness::new(&first, 320);
        raw.moved(&still, none).unwrap();
        assert!(
            raw.moved(&moved_camera, none).unwrap(),
            "the texture's edges moved"
        );
        // ... and matches it where the camera's motion puts each pixel.
        for seed in 4..8 {
            let f = seen_under(seed, 100.0, hand);
            assert!(
                !s.moved(&f, || Ok(Some(hand))).unwrap(),
                "held, frame {seed}"
            );
        }
        // The ball leaving its place moves the scene, the camera's motion or not.
        let gone = seen_under(9, 106.0, hand);
        assert!(s.moved(&gone, || Ok(Some(hand))).unwrap());
        assert!(s
            .moved(&seen_under(10, 100.0, hand), || Ok(Some(hand)))
            .unwrap());
    }

    #[test]
    fn a_held_ball_is_still_and_a_moving_one_is_not() {
        let mut s = Stillness::new(&frame(1, 100.0), 320);
        // Frames of the held ball differ by their noise only.
        for seed in 2..20 {
            assert!(
                !s.moved(&frame(seed, 100.0), none).unwrap(),
                "still frame {seed}"
            );
        }
        // The ball a few pixels on: moving, and latched.
        assert!(s.moved(&frame(30, 104.0), none).unwrap());
        assert!(s.moved(&frame(31, 100.0), none).unwrap());
    }

    #[test]
    fn a_frame_of_another_size_counts_as_motion() {
        let mut s = Stillness::new(&frame(1, 100.0), 320);
        assert!(s.moved(&[0u8; 100], none).unwrap());
    }
}
