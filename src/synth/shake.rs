//! The camera's own motion (`synthetic.shake`): the whole picture shifted and turned
//! about its centre along a smooth random path, zero at the first frame.

use super::plan::stream;
use crate::config::Shake;
use crate::rng::Rng;
use anyhow::Result;
use opencv::core::{self, Mat, Scalar};
use opencv::imgproc;
use opencv::prelude::*;

/// Each axis (x, y, turn) is a sum of sines at these multiples of `shake.hz`.
const MULTIPLES: [f64; 4] = [0.6, 0.85, 1.15, 1.4];

pub(super) struct ShakePath {
    /// Per axis (x px, y px, turn rad), per sine: amplitude, frequency (Hz), phase.
    sines: [[(f64, f64, f64); 4]; 3],
    /// The drift's velocity, px/s.
    drift: (f64, f64),
}

impl ShakePath {
    /// The path of `k` from `seed`, for a recording `duration_s` long.
    pub(super) fn new(k: &Shake, seed: u64, duration_s: f64) -> Self {
        let mut rng = Rng::new(stream(seed, 7));
        // The RMS of four sines of amplitude a is a sqrt(2): a shift of RMS `px` splits
        // into two axes of RMS px / sqrt(2) each.
        let amp = [0.5 * k.px, 0.5 * k.px, k.deg.to_radians() / 2f64.sqrt()];
        let mut sines = [[(0.0, 0.0, 0.0); 4]; 3];
        for (axis, a) in sines.iter_mut().zip(amp) {
            for (s, m) in axis.iter_mut().zip(MULTIPLES) {
                let f = k.hz * m * (1.0 + 0.1 * (rng.uniform() - 0.5));
                *s = (a, f, std::f64::consts::TAU * rng.uniform());
            }
        }
        let dir = std::f64::consts::TAU * rng.uniform();
        let v = k.drift_px / duration_s.max(1e-9);
        Self {
            sines,
            drift: (v * dir.cos(), v * dir.sin()),
        }
    }

    /// The picture's shift (px) and turn (rad) at time `t`, s: a point of the first
    /// frame at `p` is seen at `c + R (p - c) + shift` (`c` the frame's centre).
    pub(super) fn at(&self, t: f64) -> (f64, f64, f64) {
        let axis = |k: usize| {
            self.sines[k]
                .iter()
                .map(|&(a, f, ph)| a * ((std::f64::consts::TAU * f * t + ph).sin() - ph.sin()))
                .sum::<f64>()
        };
        (
            axis(0) + self.drift.0 * t,
            axis(1) + self.drift.1 * t,
            axis(2),
        )
    }
}

/// `frame` as the camera moved by `m` (see [`ShakePath::at`]) sees it, via `tmp`; the
/// border the move uncovers repeats the picture mirrored.
pub(super) fn apply(frame: &mut Mat, m: (f64, f64, f64), tmp: &mut Mat) -> Result<()> {
    let (dx, dy, rot) = m;
    if dx == 0.0 && dy == 0.0 && rot == 0.0 {
        return Ok(());
    }
    warp_rows(frame, m, 0, frame.rows(), tmp)?;
    std::mem::swap(frame, tmp);
    Ok(())
}

/// Rows `y0..y1` of `frame` as the camera moved by `m` sees them, into `out` (those rows
/// only: `y1 - y0` rows, as wide as the frame).
pub(super) fn warp_rows(
    frame: &Mat,
    (dx, dy, rot): (f64, f64, f64),
    y0: i32,
    y1: i32,
    out: &mut Mat,
) -> Result<()> {
    let (c, s) = (rot.cos(), rot.sin());
    let cx = 0.5 * (f64::from(frame.cols()) - 1.0);
    let cy = 0.5 * (f64::from(frame.rows()) - 1.0);
    // Forward: q = R (p - c) + c + d, then q's row counted from `y0`.
    let a = Mat::from_slice_2d(&[
        [c, -s, cx - c * cx + s * cy + dx],
        [s, c, cy - s * cx - c * cy + dy - f64::from(y0)],
    ])?;
    imgproc::warp_affine(
        frame,
        out,
        &a,
        core::Size::new(frame.cols(), y1 - y0),
        imgproc::INTER_LINEAR,
        core::BORDER_REFLECT_101,
        Scalar::default(),
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_starts_still_and_has_the_asked_rms() {
        let k = Shake {
            px: 2.0,
            deg: 0.3,
            hz: 5.0,
            drift_px: 0.0,
        };
        let p = ShakePath::new(&k, 3, 60.0);
        assert_eq!(p.at(0.0), (0.0, 0.0, 0.0));
        let n = 60_000;
        let (mut s2, mut r2) = (0.0, 0.0);
        for i in 0..n {
            let (x, y, r) = p.at(i as f64 * 1e-3);
            s2 += x * x + y * y;
            r2 += r * r;
        }
        // About the path's own mean, which the start's offset shifts: within a fifth.
        let rms = (s2 / n as f64).sqrt();
        let deg = (r2 / n as f64).sqrt().to_degrees();
        assert!((rms / 2.0 - 1.0).abs() < 0.5, "{rms}");
        assert!((deg / 0.3 - 1.0).abs() < 0.5, "{deg}");
        let d = ShakePath::new(
            &Shake {
                px: 0.0,
                deg: 0.0,
                hz: 5.0,
                drift_px: 6.0,
            },
            3,
            60.0,
        );
        let (x, y, _) = d.at(60.0);
        assert!((x.hypot(y) - 6.0).abs() < 1e-9);
    }
}
