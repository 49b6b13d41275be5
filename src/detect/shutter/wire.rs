//! A rolling shutter and the wire's own motion, with the camera still: each row is read
//! at its own time, so a wire that turns while the rows are read is seen at a different
//! angle on each row. Two things follow. The wire's image bows, and its angle is the
//! angle of some time after or before the frame's own (the middle row's), by where on
//! the picture the wire lies: a lag of up to half the readout, which the angles carry
//! as an error of the lag times the wire's angular velocity (a 1920x1080 sweep twin read
//! out over 0.83 of a 30 fps interval, its wire in the upper part of the picture: 2.8 ms,
//! most of its 0.020 deg RMS).
//!
//! The bow gives the readout. A point at radius `r` along the wire (direction `d`, from
//! the pivot `P`) lies on row `y = P_y + r d_y`, read `T (y - y_c) / H` after the middle
//! row `y_c` (`T` the readout, first row to last, `H` the rows); while the wire turns at
//! `w` it is seen `r w T (y - y_c) / H` across the wire's line. The part in `r^2`,
//! `w T d_y / H r^2`, bows the strip: its middle lies `response w T d_y L^2 / (4 H)` to
//! the left of the chord (`L` the chord's length, [`Bowed::mid_px`](crate::lens::bow::Bowed::mid_px), `response` the
//! share of an offset the strip shows). A lens bows the wire too, but by where it lies,
//! not how fast it turns: each frame's bow is taken against the other frames' at the
//! same angle (bins of [`WIRE_READOUT_BIN_DEG`]), the wire passing each angle both
//! ways, and the readout fitted by least squares to what is left. The rows are taken to
//! be the sensor's: a sensor read across the picture's columns (a phone filmed upright,
//! its video turned) bows the wire by `d_x` instead, which one small swing cannot tell
//! apart (`d_x` and `d_y` keep their ratio).
//!
//! The angle, fitted about the pivot to the far strip's pixels, is that of the strip's
//! effective radius (`R = 3/4 (r1^4 - r0^4) / (r1^3 - r0^3)`, the fit's moment ratio),
//! whose row is read `tau = T (P_y + R d_y - y_c) / H` after the middle row's: each
//! angle is taken back by its angular velocity times `tau`, to the frame's time.

use crate::detect::line::unwrap_near;
use crate::detect::tuning::{
    FREE_STRIP_FROM, MAX_READOUT, WIRE_READOUT_BIN_DEG, WIRE_READOUT_BLOCKS,
    WIRE_READOUT_MIN_FRAMES, WIRE_READOUT_MIN_RESPONSE, WIRE_READOUT_SIGNIFICANCE,
};
use crate::detect::{AngleRow, Pt, Status};

/// A rolling shutter's readout fitted to the wire's bows and taken out of the angles.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WireReadout {
    /// Rows read out over this, top to bottom, ms.
    pub rows_ms: f64,
    /// Its standard uncertainty (the jackknife), ms.
    pub u_rows_ms: f64,
    /// The largest time an angle was taken back by, ms.
    pub max_lag_ms: f64,
}

impl WireReadout {
    /// In words: "its rows read out over 30.2 +- 0.2 ms (fitted to how the moving wire
    /// bows); each angle taken to its frame's time, the middle row's, by up to 3.2 ms".
    pub fn describe(&self) -> String {
        format!(
            "its rows read out over {:.1} +- {:.1} ms (fitted to how the moving wire bows); \
             each angle taken to its frame's time, the middle row's, by up to {:.1} ms",
            self.rows_ms, self.u_rows_ms, self.max_lag_ms
        )
    }
}

/// One frame's bow against the readout: `mid_px = c(bin) + T g`.
struct Seen {
    bin: i64,
    g: f64,
    mid: f64,
}

/// The angular velocity of each row, rad/s: the central difference of its neighbours'
/// angles, one-sided where only one neighbour has one. Called after the fill: every
/// angle not missing is a found one or a flagged frame's filled one, so that a run of
/// filled frames is taken back as its neighbours are.
fn velocities(rows: &[AngleRow]) -> Vec<Option<f64>> {
    let at = |i: Option<usize>| -> Option<(f64, f64)> {
        let r = rows.get(i?)?;
        Some((r.t_s, r.angle_rad.filter(|_| r.status != Status::Missing)?))
    };
    (0..rows.len())
        .map(|i| {
            let own = rows[i].angle_rad.map(|a| (rows[i].t_s, a));
            let (a, b) = match (at(i.checked_sub(1)), at(Some(i + 1))) {
                (Some(a), Some(b)) => (a, b),
                (Some(a), None) => (a, own?),
                (None, Some(b)) => (own?, b),
                (None, None) => return None,
            };
            let dt = b.0 - a.0;
            (dt > 0.0).then(|| (unwrap_near(b.1, a.1) - a.1) / dt)
        })
        .collect()
}

/// The readout `T` (s) that best explains `seen`'s bows, each bin's own mean taken
/// out, by least squares.
fn fit(seen: &[&Seen]) -> Option<f64> {
    let mut by_bin = std::collections::HashMap::<i64, (f64, f64, f64)>::new();
    for s in seen {
        let e = by_bin.entry(s.bin).or_default();
        *e = (e.0 + 1.0, e.1 + s.g, e.2 + s.mid);
    }
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for s in seen {
        let (n, g, m) = by_bin[&s.bin];
        let x = s.g - g / n;
        sxx += x * x;
        sxy += x * (s.mid - m / n);
    }
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Fits a rolling shutter's readout to the bows of `rows`' found frames (see the
/// module's text) and takes each angle back to its frame's time, when a readout stands
/// clear of noise within the frame's `interval` (s); `None` otherwise, the angles
/// untouched. `pivot` in full-frame px; `frame` the picture's width and height.
pub(in crate::detect) fn take_out(
    rows: &mut [AngleRow],
    pivot: Pt,
    frame: [f64; 2],
    interval: f64,
) -> Option<WireReadout> {
    let omega = velocities(rows);
    let bin_w = WIRE_READOUT_BIN_DEG.to_radians();
    let mut radii = (Vec::new(), Vec::new());
    let seen: Vec<Seen> = rows
        .iter()
        .zip(&omega)
        .filter(|(r, _)| r.status == Status::Ok && r.flag.is_none())
        .filter_map(|(r, w)| {
            let b = r
                .moments
                .as_ref()?
                .bow
                .filter(|b| b.usable(WIRE_READOUT_MIN_RESPONSE))?;
            let (w, a) = ((*w)?, r.angle_rad?);
            let [e0, e1] = b.ends;
            let (dx, dy) = (e1[0] - e0[0], e1[1] - e0[1]);
            let l = dx.hypot(dy);
            radii.0.push((e0[0] - pivot.x).hypot(e0[1] - pivot.y));
            radii.1.push((e1[0] - pivot.x).hypot(e1[1] - pivot.y));
            // w d_y L^2 / (4 H) with d_y = dy / L.
            let k = b.response * w * l / 4.0;
            Some(Seen {
                bin: (a / bin_w).floor() as i64,
                g: k * dy / frame[1],
                mid: b.mid_px,
            })
        })
        .collect();
    if seen.len() < WIRE_READOUT_MIN_FRAMES {
        return None;
    }
    let all: Vec<&Seen> = seen.iter().collect();
    let t = fit(&all)?;
    // The jackknife over contiguous blocks.
    let n = seen.len();
    let mut outs = Vec::with_capacity(WIRE_READOUT_BLOCKS);
    for k in 0..WIRE_READOUT_BLOCKS {
        let (lo, hi) = (
            k * n / WIRE_READOUT_BLOCKS,
            (k + 1) * n / WIRE_READOUT_BLOCKS,
        );
        let rest: Vec<&Seen> = seen[..lo].iter().chain(&seen[hi..]).collect();
        outs.push(fit(&rest)?);
    }
    let u = crate::numerics::jackknife_u(&outs);
    let z = t.abs() / u;
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "shutter: the wire's bow gives a readout of {:.2} +- {:.2} ms ({z:.1} standard \
             errors; {n} frames; a frame's interval {:.2} ms)",
            1e3 * t,
            1e3 * u,
            1e3 * interval
        );
    }
    // Rows read top to bottom within the interval: a readout fitted the other way is
    // taken for something else that bows with the swing's speed.
    if z < WIRE_READOUT_SIGNIFICANCE || t <= 0.0 || t > MAX_READOUT * interval {
        return None;
    }
    // The far strip's effective radius, from the strips' typical ends.
    let r1 = crate::numerics::median(&mut radii.1);
    let r0 = crate::numerics::median(&mut radii.0).max(FREE_STRIP_FROM * r1);
    let reff = 0.75 * (r1.powi(4) - r0.powi(4)) / (r1.powi(3) - r0.powi(3));
    if !reff.is_finite() {
        return None;
    }
    let c = pivot.y - 0.5 * (frame[1] - 1.0);
    let mut max_lag: f64 = 0.0;
    for (r, w) in rows.iter_mut().zip(&omega) {
        if let (Some(a), Some(w), true) = (&mut r.angle_rad, w, r.status != Status::Missing) {
            let tau = t * (c + reff * a.sin()) / frame[1];
            max_lag = max_lag.max(tau.abs());
            *a -= w * tau;
        }
    }
    Some(WireReadout {
        rows_ms: 1e3 * t,
        u_rows_ms: 1e3 * u,
        max_lag_ms: 1e3 * max_lag,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::row::KeptMoments;
    use crate::lens::bow::Bowed;
    use crate::rng::Rng;

    const FPS: f64 = 30.0;
    const W: f64 = 1280.0;
    const H: f64 = 720.0;
    const PIVOT: [f64; 2] = [640.0, -30.0];
    const R0: f64 = 60.0;
    const R1: f64 = 420.0;

    /// A wire hanging from above the frame, swinging 8 deg about 80 deg for 40 s, filmed
    /// at 30 fps with its rows read out over `readout_s`, through a lens that bows it
    /// by `lens_px` times the swing's distance `s` from its middle (radians) and 10 times
    /// `s^2`, with 0.004 deg
    /// of noise on the angles and 0.1 px on the bows: the rows, and the true angles.
    ///
    /// Each angle is the fit through the pivot of the far strip's points (radii from a
    /// quarter of the outer one out, every pixel), each seen where its own row's time put
    /// it; each bow the middle's offset from the chord over the whole strip, as the
    /// parabola `w T d_y r^2 / H` across the line gives it, at a response of 0.8.
    fn filmed(readout_s: f64, lens_px: f64) -> (Vec<AngleRow>, Vec<f64>) {
        let mut rng = Rng::new(11);
        let (mut rows, mut truth) = (Vec::new(), Vec::new());
        let tau = std::f64::consts::TAU;
        let theta = |t: f64| (80.0 + 8.0 * (tau * t / 1.4).cos() * (-t / 60.0).exp()).to_radians();
        for k in 0..(40.0 * FPS) as u64 {
            let t = k as f64 / FPS;
            let th = theta(t);
            let w = (theta(t + 1e-4) - theta(t - 1e-4)) / 2e-4;
            let (dx, dy) = (th.cos(), th.sin());
            // The far strip's fit through the pivot: each point `r` off the line by
            // `r w T (y - y_c) / H`, the slope sum(r q) / sum(r^2).
            let (mut srq, mut srr) = (0.0, 0.0);
            let mut r = 0.25 * R1;
            while r <= R1 {
                let y = PIVOT[1] + r * dy;
                let q = r * w * readout_s * (y - 0.5 * (H - 1.0)) / H;
                srq += r * q;
                srr += r * r;
                r += 1.0;
            }
            let seen = th + srq / srr + 0.004f64.to_radians() * rng.normal();
            let l = R1 - R0;
            let mid = 0.8 * w * readout_s * dy * l * l / (4.0 * H)
                + lens_px * (th - 80f64.to_radians())
                + 10.0 * lens_px * (th - 80f64.to_radians()).powi(2)
                + 0.1 * rng.normal();
            let end = |r: f64| [PIVOT[0] + r * dx, PIVOT[1] + r * dy];
            truth.push(th);
            rows.push(AngleRow {
                frame: k,
                t_s: t,
                angle_rad: Some(seen),
                status: Status::Ok,
                quality: 1.0,
                flag: None,
                moments: Some(KeptMoments {
                    moments: [[0.0; 6]; 2],
                    free: [true; 2],
                    bow: Some(Bowed {
                        ends: [end(R0), end(R1)],
                        mid_px: mid,
                        response: 0.8,
                    }),
                    plate: None,
                }),
            });
        }
        (rows, truth)
    }

    fn rms_deg(rows: &[AngleRow], truth: &[f64]) -> f64 {
        let s: f64 = rows
            .iter()
            .zip(truth)
            .map(|(r, t)| (r.angle_rad.unwrap() - t).powi(2))
            .sum();
        (s / truth.len() as f64).sqrt().to_degrees()
    }

    fn taken_out(rows: &mut [AngleRow]) -> Option<WireReadout> {
        take_out(rows, Pt::new(PIVOT[0], PIVOT[1]), [W, H], 1.0 / FPS)
    }

    #[test]
    fn a_rolling_shutter_is_fitted_to_the_wire_s_bow_and_the_angles_taken_to_the_frame_s_time() {
        // Read out over 0.8 of the interval, through a lens that bows the wire 2 px per
        // radian of swing.
        let readout = 0.8 / FPS;
        let (mut rows, truth) = filmed(readout, 2.0);
        let before = rms_deg(&rows, &truth);
        let got = taken_out(&mut rows).expect("a readout fitted");
        let after = rms_deg(&rows, &truth);
        assert!(
            (got.rows_ms - 1e3 * readout).abs() < 0.05 * 1e3 * readout,
            "{got:?}"
        );
        assert!(got.u_rows_ms < 0.1 * got.rows_ms, "{got:?}");
        // The wire lies in the frame's upper half: its angles lag, 0.05 deg RMS here.
        assert!(before > 0.04, "{before}");
        assert!(after < 0.006, "{before} -> {after}");
        assert!(
            got.max_lag_ms > 3.0 && got.max_lag_ms < 0.5 * 1e3 * readout,
            "{got:?}"
        );
    }

    #[test]
    fn a_global_shutter_s_angles_are_left_as_they_are_whatever_the_lens_bows() {
        for lens_px in [0.0, 2.0, -5.0] {
            let (mut rows, truth) = filmed(0.0, lens_px);
            let before: Vec<Option<f64>> = rows.iter().map(|r| r.angle_rad).collect();
            assert_eq!(taken_out(&mut rows), None, "lens {lens_px}");
            let after: Vec<Option<f64>> = rows.iter().map(|r| r.angle_rad).collect();
            assert_eq!(before, after);
            assert!(rms_deg(&rows, &truth) < 0.006);
        }
    }

    #[test]
    fn a_readout_fitted_bottom_to_top_is_not_taken() {
        // Rows read bottom to top bow the wire the other way: fitted negative, which the
        // bar takes for something else that bows with the swing's speed.
        let (mut rows, _) = filmed(-0.8 / FPS, 0.0);
        let before: Vec<Option<f64>> = rows.iter().map(|r| r.angle_rad).collect();
        assert_eq!(taken_out(&mut rows), None);
        assert_eq!(before, rows.iter().map(|r| r.angle_rad).collect::<Vec<_>>());
    }

    #[test]
    fn a_run_of_filled_frames_is_taken_back_as_its_neighbours_are() {
        // Frames 300 to 305 flagged and filled (their angles as found here), as the fill
        // leaves them: their angular velocity comes from the filled neighbours too.
        let readout = 0.8 / FPS;
        let (mut rows, truth) = filmed(readout, 0.0);
        for r in &mut rows[300..306] {
            r.flag = Some(crate::detect::Flag::Pulled);
            r.status = Status::Corrected;
        }
        taken_out(&mut rows).expect("a readout fitted");
        let run: Vec<AngleRow> = rows[300..306].to_vec();
        assert!(
            rms_deg(&run, &truth[300..306]) < 0.01,
            "{}",
            rms_deg(&run, &truth[300..306])
        );
    }

    #[test]
    fn a_lens_s_bow_is_not_taken_for_a_readout_when_frames_are_lost_one_way_of_the_swing() {
        // A global shutter through a lens that bows the wire 5 px per radian of swing (and
        // 50 px per radian squared), the frames swinging one way lost on one side of the
        // swing (a wire blurred by its speed loses its strip more one way than the other,
        // and where it passes something): without each bin's own mean taken out, the
        // frames left each way lie on different parts of the lens's bow, which then
        // follows the speed's sign and reads as a readout.
        let (mut rows, _) = filmed(0.0, 5.0);
        let omega = velocities(&rows);
        for (r, w) in rows.iter_mut().zip(omega) {
            if w.is_some_and(|w| w > 0.0) && r.angle_rad.is_some_and(|a| a < 80f64.to_radians()) {
                r.moments = None;
            }
        }
        let before: Vec<Option<f64>> = rows.iter().map(|r| r.angle_rad).collect();
        assert_eq!(taken_out(&mut rows), None);
        assert_eq!(before, rows.iter().map(|r| r.angle_rad).collect::<Vec<_>>());
    }
}
