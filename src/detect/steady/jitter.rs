//! The steadying's own noise in the angles. Each frame's motion is measured against the
//! first frame on the static scene, and a scene with little texture (a plain wall, a
//! plate seen obliquely) fixes it to a few hundredths of a pixel and a few ten-thousandths
//! of a radian, differently in every frame. A frame warped back by a shift a little off
//! moves the wire across the pivot held in the plate's frame, and its angle errs by that
//! shift over the wire's radius: on a hand-held sweep twin (960x540 at 60 fps, a plain
//! room) the angles' frame-to-frame error followed the motions' frame-to-frame part
//! (a correlation of 0.84) and was most of its 0.0295 deg RMS.
//!
//! A camera moves smoothly from frame to frame, the measurement's noise does not: each
//! motion's departure from the cubic fitted to its window of [`JITTER_FRAMES`] frames (a
//! Savitzky-Golay smoothing) is mostly the noise. A longer window holds more of the
//! noise, and more of a true shake too, which dilutes the regression (a twin shaking
//! at 3 Hz, at 60 fps: its angles err 0.0164 deg RMS, 0.0098 corrected over 9 frames,
//! 0.0154 over 15). The angles' own departures are
//! regressed on the three motions' (shift across, shift down, turn), and what the
//! regression explains is taken out of the angles when it stands clear of chance
//! ([`JITTER_SIGNIFICANCE`], the coefficients' uncertainty a jackknife over
//! [`JITTER_BLOCKS`] contiguous blocks of frames). The pendulum's swing is a cubic over
//! a few frames to a few ten-thousandths of a degree, so the regression learns nothing
//! of it and takes nothing of it out; and a motion the steadying follows truly leaves
//! no error in the angles to regress on, so its coefficients stay within chance and
//! nothing is taken.

use super::Steadied;
use crate::detect::tuning::{
    JITTER_BLOCKS, JITTER_FRAMES, JITTER_MIN_FRAMES, JITTER_MIN_SHARE, JITTER_SIGNIFICANCE,
};
use crate::detect::{AngleRow, Flag, Status};

/// What was taken out of the angles: the RMS of the correction over the frames
/// corrected, deg, and the largest of the coefficients' standard scores.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jitter {
    pub rms_deg: f64,
    pub z: f64,
}

/// The weights of the middle value of the cubic fitted by least squares to `n` (odd)
/// evenly spaced values.
fn cubic_middle(n: usize) -> Vec<f64> {
    let m = (n / 2) as f64;
    // For a cubic (and so a quadratic: the odd powers do not reach the middle) over
    // `-m..=m`, the middle weights are `(3 (3 m^2 + 3 m - 1) - 15 k^2) / ((2 m - 1)
    // (2 m + 1) (2 m + 3))`.
    let d = (2.0 * m - 1.0) * (2.0 * m + 1.0) * (2.0 * m + 3.0);
    (0..n)
        .map(|i| {
            let k = i as f64 - m;
            (3.0 * (3.0 * m * m + 3.0 * m - 1.0) - 15.0 * k * k) / d
        })
        .collect()
}

/// Each row's departure from the cubic fitted to its window of [`JITTER_FRAMES`] rows
/// (the row in the middle), of a quantity known by row: `None` where any of the window
/// is unknown (and at the ends).
fn departures(x: &[Option<f64>]) -> Vec<Option<f64>> {
    let w = cubic_middle(JITTER_FRAMES);
    let half = JITTER_FRAMES / 2;
    (0..x.len())
        .map(|i| {
            let own = x[i]?;
            if i < half || i + half >= x.len() {
                return None;
            }
            let mut fitted = 0.0;
            for (v, w) in x[i - half..=i + half].iter().zip(&w) {
                fitted += w * (*v)?;
            }
            Some(own - fitted)
        })
        .collect()
}

/// The least-squares coefficients of `y` on the three columns of `x`, through the
/// origin; `None` when they are not fixed.
fn fit(x: &[[f64; 3]], y: &[f64]) -> Option<[f64; 3]> {
    crate::numerics::least_squares3(x.iter().copied().zip(y.iter().copied()))
}

/// Takes the steadying's noise out of the angles of `rows` (see the module's text):
/// `steadied` in frame order. What was taken out, or `None` (the angles untouched).
pub(in crate::detect) fn take_out(rows: &mut [AngleRow], steadied: &[Steadied]) -> Option<Jitter> {
    if steadied.len() < JITTER_MIN_FRAMES {
        return None;
    }
    let motion = |r: &AngleRow| {
        let i = steadied.binary_search_by_key(&r.frame, |s| s.index).ok()?;
        let s = &steadied[i];
        s.measured
            .then_some([s.motion.dx, s.motion.dy, s.motion.rot_rad])
    };
    let motions: Vec<Option<[f64; 3]>> = rows.iter().map(motion).collect();
    let cols: Vec<Vec<Option<f64>>> = (0..3)
        .map(|j| {
            let x: Vec<Option<f64>> = motions.iter().map(|m| m.map(|m| m[j])).collect();
            departures(&x)
        })
        .collect();
    // The fit reads windows of frames the pass took whole.
    let taken: Vec<Option<f64>> = rows
        .iter()
        .map(|r| {
            r.angle_rad
                .filter(|_| r.flag.is_none() && r.status == Status::Ok)
        })
        .collect();
    let angle_off = departures(&taken);
    let mut x = Vec::new();
    let mut y = Vec::new();
    for (i, a) in angle_off.iter().enumerate() {
        if let (Some(a), Some(d0), Some(d1), Some(d2)) = (a, cols[0][i], cols[1][i], cols[2][i]) {
            x.push([d0, d1, d2]);
            y.push(*a);
        }
    }
    if y.len() < JITTER_MIN_FRAMES {
        return None;
    }
    let c = fit(&x, &y)?;
    // The jackknife over contiguous blocks (the departures of neighbouring frames share
    // frames, so they are not independent).
    let n = y.len();
    let blocks = JITTER_BLOCKS;
    let mut leave: Vec<[f64; 3]> = Vec::with_capacity(blocks);
    for k in 0..blocks {
        let (lo, hi) = (k * n / blocks, (k + 1) * n / blocks);
        let xs: Vec<[f64; 3]> = x[..lo].iter().chain(&x[hi..]).copied().collect();
        let ys: Vec<f64> = y[..lo].iter().chain(&y[hi..]).copied().collect();
        leave.push(fit(&xs, &ys)?);
    }
    let z = (0..3)
        .map(|j| {
            let u = crate::numerics::jackknife_u(&leave.iter().map(|c| c[j]).collect::<Vec<_>>());
            (c[j] / u.max(f64::MIN_POSITIVE)).abs()
        })
        .fold(0.0, f64::max);
    // The share of the angles' departures the motions explain.
    let before: f64 = y.iter().map(|v| v * v).sum();
    let after: f64 = x
        .iter()
        .zip(&y)
        .map(|(x, y)| (y - (0..3).map(|j| c[j] * x[j]).sum::<f64>()).powi(2))
        .sum();
    let explained = 1.0 - after / before.max(f64::MIN_POSITIVE);
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "steady: the angles' departures on the motions' over {n} frames: {c:?}, \
             {z:.1} standard errors, {:.0} % explained",
            100.0 * explained
        );
    }
    if z < JITTER_SIGNIFICANCE || explained < JITTER_MIN_SHARE {
        return None;
    }
    let (mut sum2, mut count) = (0.0, 0usize);
    for (i, r) in rows.iter_mut().enumerate() {
        let (Some(a), Some(d0), Some(d1), Some(d2)) =
            (&mut r.angle_rad, cols[0][i], cols[1][i], cols[2][i])
        else {
            continue;
        };
        if r.status == Status::Missing || r.flag == Some(Flag::Flash) {
            continue;
        }
        let d = c[0] * d0 + c[1] * d1 + c[2] * d2;
        *a -= d;
        sum2 += d * d;
        count += 1;
    }
    (count > 0).then(|| Jitter {
        rms_deg: (sum2 / count as f64).sqrt().to_degrees(),
        z,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::steady::Motion;
    use crate::rng::Rng;

    const FPS: f64 = 60.0;

    /// A wire swinging 10 deg about hanging, 300 px from the pivot, with 0.005 deg of its
    /// own noise, under a camera shaking (2 px at 3 Hz across, 1 px at 2.2 Hz down, 0.2
    /// deg at 2.7 Hz) whose motion is measured with `noise_px` of noise across (and a
    /// fifth of it down and in the turn): each frame warped back by the measured motion,
    /// so the angle errs by the shift's noise over the radius. The angles, the truth and
    /// the motions as measured.
    fn filmed(noise_px: f64, seconds: f64) -> (Vec<AngleRow>, Vec<f64>, Vec<Steadied>) {
        let mut rng = Rng::new(11);
        let (mut rows, mut truth, mut steadied) = (Vec::new(), Vec::new(), Vec::new());
        let tau = std::f64::consts::TAU;
        for k in 0..(seconds * FPS) as u64 {
            let t = k as f64 / FPS;
            let theta = (90.0 + 10.0 * (tau * t / 1.6).cos()).to_radians();
            let true_motion = Motion {
                dx: 2.0 * (tau * 3.0 * t).sin(),
                dy: (tau * 2.2 * t + 1.0).sin(),
                rot_rad: 0.2f64.to_radians() * (tau * 2.7 * t + 2.0).sin(),
            };
            let (ex, ey, er) = (
                noise_px * rng.normal(),
                0.2 * noise_px * rng.normal(),
                0.2 * noise_px / 300.0 * rng.normal(),
            );
            // A shift across the hanging wire (along x) of `ex` turns it by `-ex / 300`.
            let err = -ex / 300.0 + er;
            let own = 0.005f64.to_radians() * rng.normal();
            truth.push(theta);
            rows.push(AngleRow::found(k, t, theta + err + own));
            let measured = Motion {
                dx: true_motion.dx + ex,
                dy: true_motion.dy + ey,
                rot_rad: true_motion.rot_rad - er,
            };
            steadied.push(Steadied::measured(k, t, measured));
        }
        (rows, truth, steadied)
    }

    fn rms_off_deg(rows: &[AngleRow], truth: &[f64]) -> f64 {
        let e: Vec<f64> = rows
            .iter()
            .zip(truth)
            .map(|(r, t)| (r.angle_rad.unwrap() - t).to_degrees())
            .collect();
        let m = e.iter().sum::<f64>() / e.len() as f64;
        (e.iter().map(|v| (v - m).powi(2)).sum::<f64>() / e.len() as f64).sqrt()
    }

    #[test]
    fn the_steadying_s_noise_is_taken_out_of_the_angles() {
        let (mut rows, truth, steadied) = filmed(0.08, 20.0);
        let before = rms_off_deg(&rows, &truth);
        let j = take_out(&mut rows, &steadied).expect("taken out");
        let after = rms_off_deg(&rows, &truth);
        assert!(before > 0.015, "{before} deg RMS before");
        assert!(after < 0.6 * before, "{before} -> {after} deg RMS");
        assert!(j.z >= JITTER_SIGNIFICANCE && j.rms_deg > 0.005, "{j:?}");
    }

    #[test]
    fn a_motion_followed_truly_leaves_the_angles_as_they_are() {
        // The camera shakes as before, measured without noise: the angles hold only the
        // wire's own noise, which the motions do not explain.
        let (mut rows, _, steadied) = filmed(0.0, 20.0);
        let angles = |rows: &[AngleRow]| rows.iter().map(|r| r.angle_rad).collect::<Vec<_>>();
        let before = angles(&rows);
        assert_eq!(take_out(&mut rows, &steadied), None);
        assert_eq!(angles(&rows), before);
    }

    #[test]
    fn the_swing_is_not_taken_for_the_steadying_s_noise() {
        // The measured shift across follows the swing itself (a ball pulling the
        // alignment), with no noise in the angles: the swing departs from the cubic of
        // its window by almost nothing, and nothing is taken out. (From a plain mean of
        // the window it departs by a tenth of a degree at its turns, which the pull's
        // departures would explain, and take out.)
        let (mut rows, truth, mut steadied) = filmed(0.0, 20.0);
        for (s, t) in steadied.iter_mut().zip(&truth) {
            s.motion.dx = 30.0 * (t - std::f64::consts::FRAC_PI_2);
        }
        let before: Vec<_> = rows.iter().map(|r| r.angle_rad).collect();
        let taken = take_out(&mut rows, &steadied);
        let after: Vec<_> = rows.iter().map(|r| r.angle_rad).collect();
        assert!(taken.is_none() && after == before, "{taken:?}");
    }
}
