//! A rolling shutter under a moving camera: a phone reads its rows one after another
//! over most of a frame's interval, so while the camera moves each row sees it further
//! on, and the wire, which spans many rows, leans by the camera's motion over its rows'
//! readout. Steadying warps each frame back by one shift and turn (the middle row's,
//! near enough) and leaves the lean in the angle: a hand-held twin at 5 Hz read out
//! over 0.8 of a 30 fps frame's interval was measured 0.13 deg RMS off.
//!
//! The lean follows from the camera's velocity, which the steadied frames' motions give
//! (their differences from frame to frame), and from one unknown: how long the readout
//! takes. A wire at image angle `theta` (direction `d`), in a camera moving at `V` (px/s)
//! whose rows are read out over `T` s of a picture `H` rows high, leans by
//!
//! `T / H * d_y * (d x V)`
//!
//! (`d x V` the cross product: each row's time is `T (y - c_row) / H` from the middle
//! row's, and the motion in that time shears the picture along the rows). `T` is fitted
//! by least squares to the angles' fourth differences (the pendulum's smooth swing leaves
//! none, a shaking camera's lean a good deal), and the angles corrected when it stands
//! clear of noise ([`READOUT_SIGNIFICANCE`]) within one frame's interval
//! ([`MAX_READOUT`]): a global shutter's angles do not move with the lean, and are left
//! as they are. On a hand-held twin (640x480, 30 fps, 2.5 px and 0.3 deg at 5 Hz, read
//! out over 0.8 of the interval) the angles' error falls from 0.134 to 0.047 deg RMS, the
//! readout fitted at 19.6 ms of the 26.7 (the steadying's turn takes up part of the
//! shear); the same twin with a global shutter fits 0.1 ms, 0.2 standard errors from
//! none, and is left as it is. The turn's own rate leans the wire too (each row turned
//! as at its own time); as a second term of the same readout it fitted worse (0.049 deg),
//! and is left out.

mod wire;

pub(super) use wire::take_out as take_out_wire_lag;
pub use wire::WireReadout;

use super::judge::{paired_fourth_differences, slope_through_origin};
use super::steady::{Motion, Steadied};
use super::tuning::{MAX_READOUT, READOUT_SIGNIFICANCE};
use super::{AngleRow, Status};

/// The lean per second of readout (see the module's text) of each row with an angle,
/// by row; `None` where the steadied frames do not give the camera's velocity.
fn leans(rows: &[AngleRow], steadied: &[Steadied], height: f64) -> Vec<Option<f64>> {
    rows.iter()
        .map(|r| {
            let theta = r.angle_rad?;
            let i = steadied.binary_search_by_key(&r.frame, |s| s.index).ok()?;
            let get = |k: usize| steadied.get(k);
            let (a2, a1, b1, b2) = (
                get(i.checked_sub(2)?)?,
                get(i - 1)?,
                get(i + 1)?,
                get(i + 2)?,
            );
            let dt = Some(b1.t_s - a1.t_s).filter(|dt| *dt > 0.0)?;
            // The five-point derivative (a camera shaking at 5 Hz, filmed at 30 fps, is
            // a sixth too slow by the three-point one).
            let rate = |f: fn(&Motion) -> f64| {
                let d = |b: &Steadied, a: &Steadied| f(&b.motion) - f(&a.motion);
                (8.0 * d(b1, a1) - d(b2, a2)) / (6.0 * dt)
            };
            let (vx, vy) = (rate(|m| m.dx), rate(|m| m.dy));
            let (dx, dy) = (theta.cos(), theta.sin());
            Some(dy * (dx * vy - dy * vx) / height)
        })
        .collect()
}

/// Fits the readout of a rolling shutter to the angles of `rows` (see the module's
/// text) and takes the lean out of them, when it stands clear of noise within a frame's
/// interval: the readout, first row to last, s, or `None` (the angles untouched).
/// `steadied` in frame order, their motions in full-frame px; `height` the picture's
/// rows.
pub(super) fn take_out(rows: &mut [AngleRow], steadied: &[Steadied], height: f64) -> Option<f64> {
    if steadied.len() < 5 {
        return None;
    }
    let lean = leans(rows, steadied, height);
    let pairs = paired_fourth_differences(rows, &lean);
    if pairs.len() < 20 {
        return None;
    }
    let (k, z) = slope_through_origin(&pairs)?;
    // The frame interval, s: the median of the steadied frames' steps.
    let mut steps: Vec<f64> = steadied.windows(2).map(|w| w[1].t_s - w[0].t_s).collect();
    let mid = steps.len() / 2;
    let interval = *steps.select_nth_unstable_by(mid, f64::total_cmp).1;
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "shutter: readout {:.2} ms ({z:.1} standard errors; a frame's interval {:.2} ms)",
            1e3 * k,
            1e3 * interval
        );
    }
    if z < READOUT_SIGNIFICANCE || k > MAX_READOUT * interval {
        return None;
    }
    for (r, g) in rows.iter_mut().zip(&lean) {
        if let (Some(a), Some(g), true) = (&mut r.angle_rad, g, r.status != Status::Missing) {
            *a -= k * g;
        }
    }
    Some(k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    const FPS: f64 = 30.0;
    const H: f64 = 480.0;

    /// A wire swinging 10 deg about hanging (90 deg) with 0.005 deg of noise, filmed by a
    /// camera shaking sideways (3 px at 5 Hz and 2 px at 3.1 Hz), its rows read out over
    /// `readout_s`: the angles, leaning by `T / H * d_y * (d x V)`, and the motions.
    fn filmed(readout_s: f64) -> (Vec<AngleRow>, Vec<f64>, Vec<Steadied>) {
        let mut rng = Rng::new(3);
        let (mut rows, mut truth, mut steadied) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..(12.0 * FPS) as u64 {
            let t = k as f64 / FPS;
            let tau = std::f64::consts::TAU;
            let theta = (90.0 + 10.0 * (tau * t / 1.6).cos()).to_radians();
            let dx = 3.0 * (tau * 5.0 * t).sin() + 2.0 * (tau * 3.1 * t + 1.0).sin();
            let vx = 3.0 * tau * 5.0 * (tau * 5.0 * t).cos()
                + 2.0 * tau * 3.1 * (tau * 3.1 * t + 1.0).cos();
            let lean = readout_s / H * theta.sin() * (-theta.sin() * vx);
            let noise = 0.005f64.to_radians() * rng.normal();
            truth.push(theta);
            rows.push(AngleRow::found(k, t, theta + lean + noise));
            let motion = Motion {
                dx,
                ..Motion::default()
            };
            steadied.push(Steadied::measured(k, t, motion));
        }
        (rows, truth, steadied)
    }

    #[test]
    fn a_rolling_shutter_s_lean_is_fitted_and_taken_out() {
        let (mut rows, truth, steadied) = filmed(0.025);
        let before = rms_off_deg(&rows, &truth);
        let r = take_out(&mut rows, &steadied, H).expect("a readout");
        assert!((r - 0.025).abs() < 0.001, "{r} s");
        let after = rms_off_deg(&rows, &truth);
        // The five-point derivative of a 5 Hz shake at 30 fps is 3.5 % slow.
        assert!(before > 0.2 && after < 0.015, "{before} -> {after} deg RMS");
    }

    #[test]
    fn a_global_shutter_s_angles_are_left_as_they_are() {
        let (mut rows, _, steadied) = filmed(0.0);
        let angles = |rows: &[AngleRow]| rows.iter().map(|r| r.angle_rad).collect::<Vec<_>>();
        let before = angles(&rows);
        assert_eq!(take_out(&mut rows, &steadied, H), None);
        assert_eq!(angles(&rows), before);
        // A readout longer than the frame's interval is not a rolling shutter's.
        let (mut rows, _, steadied) = filmed(0.05);
        assert_eq!(take_out(&mut rows, &steadied, H), None);
    }

    /// The RMS of `rows`' angles off `truth`, deg, away from the ends (whose velocity the
    /// motions do not give).
    fn rms_off_deg(rows: &[AngleRow], truth: &[f64]) -> f64 {
        let e: Vec<f64> = rows[2..rows.len() - 2]
            .iter()
            .zip(&truth[2..])
            .map(|(r, t)| (r.angle_rad.unwrap() - t).to_degrees())
            .collect();
        (e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64).sqrt()
    }
}
