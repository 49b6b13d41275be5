//! From a sampled angle series to turning points, the equilibrium position and the
//! amplitude envelope (the paper's section 2.4, Eq. 38–39, with ERRATA §5 and §7).
//!
//! * Turning points are found half swing by half swing, then refined to sub-sample
//!   precision by fitting the neighbourhood of each extreme with a *different* curvature
//!   on each side (`psi''` jumps at a turning point because the rolling torque changes
//!   sign, ERRATA §7) and the next even terms of the swing's series (the quartic jumps
//!   with `psi''`, the sixth-order term is shared):
//!   `psi = p + c_± tau^2 + e_± tau^4 + f tau^6`, `tau = t - t_k`, `±` by the side of `t_k`.
//!   The odd terms vanish because `psi'(t_k) = 0` and `psi''' = -omega^2 cos(psi) psi'`
//!   is zero there too.
//! * Equilibrium by the paper's estimator (Eq. 38–39: the minimiser of
//!   `sum (psi_k - psi)^2`, the mean of the extremes) and by the joint fit of two
//!   symmetric envelopes `psi_k = psi_eq ± (A_0 - a t_k)` (ERRATA §5), which has no bias
//!   from the decay.
//! * Envelope slope `a` from the regression of `|psi_k - psi_eq|` on `t_k`.
//! * A held start (the ball held at its release angle before it is let go) is found
//!   by [`find_release`]: the release is the motion's first turning point, a start from
//!   rest with the hold on one side, not a cusp between two half swings.

use crate::numerics::{golden_section_min, linear_fit, median, upper_median, LineFit};
use crate::series::AngleSeries;
use anyhow::{bail, Result};
use nalgebra::{DMatrix, DVector, SMatrix, SVector};
use serde::{Deserialize, Serialize};

/// One extreme elongation of the measured signal.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Extreme {
    /// Time of the turning point, s.
    pub t: f64,
    /// Angle at the turning point, in the series' own frame (rad).
    pub angle: f64,
    /// +1 for a maximum of the series, -1 for a minimum.
    pub side: f64,
    /// RMS residual of the local fit, rad.
    pub fit_rms: f64,
    /// Samples used by the local fit.
    pub samples: usize,
    /// The release from rest that ends a held start ([`find_release`]): the motion's
    /// first turning point, with the hold on one side instead of a half swing.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub release: bool,
}

/// Per-sample noise of a smooth signal, from the median absolute second difference
/// (a second difference of white noise has standard deviation `sqrt(6) sigma`).
pub fn noise_sigma(y: &[f64]) -> f64 {
    if y.len() < 3 {
        return 0.0;
    }
    let mut d2: Vec<f64> = y
        .windows(3)
        .map(|w| (w[0] - 2.0 * w[1] + w[2]).abs())
        .collect();
    median(&mut d2) / (0.6745 * 6f64.sqrt())
}

/// Find and refine the turning points of a series.
///
/// A turning point is kept only when the signal moves away from it on both sides: the
/// release (the series begins at an extreme) and a final stop at an extreme are not
/// turning points of the free motion.
pub fn find_extremes(s: &AngleSeries) -> Result<Vec<Extreme>> {
    find_extremes_by(s, HalfSwing::EveryLobe)
}

/// Which lobes set the half swing that [`find_extremes_by`] seeks turning points over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HalfSwing {
    /// The median gap of every lobe; the swing's own ([`LOBE_GAP_SHARE`]) where that
    /// leaves the windows too short to hold a turning point's samples.
    EveryLobe,
    /// The swing's own lobes' ([`LOBE_GAP_SHARE`]), where at least three gaps lie
    /// between them (else as [`HalfSwing::EveryLobe`]).
    SwingLobes,
}

/// [`find_extremes`] with the half swing set as `by` says.
pub fn find_extremes_by(s: &AngleSeries, by: HalfSwing) -> Result<Vec<Extreme>> {
    let (t, y) = (&s.t, &s.angle);
    let n = y.len();
    if n < 8 {
        bail!("{} samples are too few to find turning points", n);
    }
    let sigma = noise_sigma(y);
    let center = median(&mut y.clone());
    let span = y.iter().fold(0.0f64, |m, v| m.max((v - center).abs()));
    if span <= 6.0 * sigma || span == 0.0 {
        bail!(
            "the angle never leaves its median by more than {:.4} deg (noise {:.4} deg): no swing to measure",
            span.to_degrees(),
            sigma.to_degrees()
        );
    }
    let h = (4.0 * sigma).max(1e-3 * span);

    let coarse = lobes(y, center, h);
    if coarse.len() < 3 {
        bail!(
            "found {} half swing(s); at least 3 are needed to measure turning points",
            coarse.len()
        );
    }
    let mut w = WINDOW_SHARE * median_gap(t, &coarse);
    // A window that cannot hold a turning point's samples: the lobes that set the half
    // swing are not the swing's (see `LOBE_GAP_SHARE`).
    let mut dt: Vec<f64> = t.windows(2).map(|p| p[1] - p[0]).collect();
    if by == HalfSwing::SwingLobes || 2.0 * w / median(&mut dt) + 1.0 < MIN_WINDOW_SAMPLES as f64 {
        if let Some(half) = swing_gap(t, y, center, &coarse) {
            w = WINDOW_SHARE * half;
        }
    }

    let mut out = Vec::new();
    for &(side, k) in &coarse {
        // The signal must move away from the extreme on both sides within the window.
        let (lo_t, hi_t) = (t[k] - w, t[k] + w);
        if lo_t < t[0] || hi_t > t[n - 1] {
            continue;
        }
        let lo = t.partition_point(|&v| v < lo_t);
        let hi = t.partition_point(|&v| v <= hi_t);
        let fall = |i: usize| side * (y[k] - y[i]);
        if fall(lo) < 1.5 * h || fall(hi - 1) < 1.5 * h || hi - lo < MIN_WINDOW_SAMPLES {
            continue;
        }
        if let Some(e) = refine(&t[lo..hi], &y[lo..hi], t[k], side, &s.t) {
            out.push(e);
        }
    }
    Ok(out)
}

/// The end of the motion: rolling friction brings the ball to rest once the linear
/// envelope of its turning points reaches zero, and the recording may run on. The angle
/// of a ball at rest still wanders (a flicker, a slow change of light, the codec), and
/// a few of its wanderings can pass [`find_extremes`]' tests for a turning point: on a
/// high-friction twin (glass fiber fabric, 40 s, at rest from 13 s) two such extremes,
/// 0.05 deg tall, turned a good fit into a bad one (s_r 10 % low, residual 0.41 deg).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Stop {
    /// When the envelope of the turning points before the stop reaches zero, s.
    pub t_s: f64,
    /// Extremes after it, dropped as the noise of the ball at rest.
    pub dropped: usize,
}

/// A gap between consecutive extremes longer than this many half swings (the median
/// gap before it) is where the free motion may have ended: its turning points follow
/// one another every half swing. A ball stops within about this many half swings of
/// its last turning point, too: the linear envelope's zero must lie there.
pub const STOP_GAP: f64 = 1.5;

/// After a gap, the linear envelope's zero may lie this many half swings after the last
/// turning point found: the ball's very last turning point, a fraction of a degree out,
/// can be lost in the angle's noise. A polycarbonate sweep twin (seed 53's scene 47,
/// 640x480, a drift steadied) lost its last, 0.46 deg from the equilibrium; the zero lay
/// 1.7 half swings after the last found, and the two wanderings of the ball at rest
/// 8.5 s later, 0.2 deg from the equilibrium, were fitted as turning points: `s_r`
/// 2.6 % low, the fit `suspect (residual, halves)`, its angles 0.012 deg RMS off the
/// truth. Out of rhythm, with no rest band to hold the extremes after it, the zero must
/// lie within [`STOP_GAP`].
pub const STOP_ZERO_AFTER_GAP: f64 = 2.5;

/// The extremes after a stop are the ball at rest, at one angle: they lie within this
/// share of the last turning point's amplitude of their median (and each nearer the
/// equilibrium than that amplitude: the ball cannot swing wider after it). The turning
/// points of a swing that goes on lie on both sides, nearly as far out as the last.
pub const STOP_REST_BAND: f64 = 0.25;

/// Drop the extremes after the motion's end ([`Stop`]): after the last turning point
/// of at least four whose linear envelope reaches zero within [`STOP_GAP`] half swings
/// after it (and no more than half a half swing before it), when what follows is the
/// ball at rest. That is told in one of two ways:
///
/// * **After a gap**: the next extreme comes more than [`STOP_GAP`] half swings later,
///   and every later one lies at the ball's rest ([`STOP_REST_BAND`]). The envelope's
///   zero may then lie up to [`STOP_ZERO_AFTER_GAP`] half swings after the last turning
///   point (the very last may be lost in the noise).
/// * **Out of rhythm**: only when the extremes as a whole are not one half swing apart
///   (the fit would refuse them, [`half_swings`]), at their own half swing or at the
///   swing's (the median gap of the first four), and no gap told the stop. The extremes
///   after the last turning point are not one half swing apart either, and each lies
///   nearer the equilibrium than the last turning point did (the ball cannot swing
///   wider after it). A camera that sways slowly makes the angle of a ball at rest
///   wander as far as the last turning points swung, every half to one and a half half
///   swings: a copper sweep twin (a tripod's sway of 0.8 px at 0.46 Hz) stopped at
///   22.7 s, 0.48 deg from its equilibrium, then wandered 0.24 deg either side of its
///   rest for 18 s, and the fit was refused. Where the wander outnumbers the swing's
///   turning points, their own half swing (the upper median gap) is the wander's, and
///   the whole may fall in its rhythm: a sweep twin (seed 2026's scene 36, a tripod's
///   sway of 0.07 deg at 0.39 Hz) swung five half swings of 1.6 s, then its ball at
///   rest wandered 0.3 deg every 0.8 to 1.1 s, 14 extremes; at 1.14 s the whole counted
///   as one rhythm, the stop was not looked for, and the fit refused the model's
///   turning points.
///
/// A turning point lost mid-motion leaves the envelope above zero; a convex decay (air,
/// a string) fitted with a line may reach zero there, but its later turning points
/// swing on both sides, one half swing apart: both are left whole.
pub fn drop_after_stop(extremes: &mut Vec<Extreme>) -> Option<Stop> {
    let n = extremes.len();
    if n < 5 {
        return None;
    }
    let stop_by =
        |rule: Rest| (3..n - 1).find_map(|i| stop_after(extremes, i, rule).map(|t| (i, t)));
    let (i, t_zero) = stop_by(Rest::AfterGap).or_else(|| {
        out_of_rhythm(extremes)
            .then(|| stop_by(Rest::OutOfRhythm))
            .flatten()
    })?;
    extremes.truncate(i + 1);
    Some(Stop {
        t_s: t_zero,
        dropped: n - i - 1,
    })
}

/// Whether the extremes as a whole are not one half swing apart, at their own half swing
/// ([`in_rhythm`]) or at the swing's: the median gap of the first four, which are the
/// swing's where a ball at rest wanders more often than the swing turned
/// ([`drop_after_stop`]).
fn out_of_rhythm(extremes: &[Extreme]) -> bool {
    let mut first: Vec<f64> = extremes
        .windows(2)
        .take(3)
        .map(|w| w[1].t - w[0].t)
        .collect();
    in_rhythm(extremes).is_none() || half_swings(extremes, median(&mut first)).is_none()
}

/// How [`drop_after_stop`] tells the ball at rest after a turning point.
#[derive(Clone, Copy, PartialEq)]
enum Rest {
    AfterGap,
    OutOfRhythm,
}

/// Each extreme's count of half swings from the first, `(t - t_0) / half` rounded,
/// when they follow one another one half swing apart (the counts rise); `None` when two
/// extremes fall on the same count or out of order.
pub fn half_swings(extremes: &[Extreme], half: f64) -> Option<Vec<usize>> {
    let t0 = extremes.first()?.t;
    let index: Vec<usize> = extremes
        .iter()
        .map(|e| ((e.t - t0) / half).round() as usize)
        .collect();
    index.windows(2).all(|w| w[1] > w[0]).then_some(index)
}

/// [`half_swings`] with the extremes' own half swing, the upper median of their gaps: the
/// counts the fit uses ([`crate::fit::from_extremes`]), `None` when it would refuse them.
pub fn in_rhythm(extremes: &[Extreme]) -> Option<Vec<usize>> {
    let mut gaps: Vec<f64> = extremes.windows(2).map(|w| w[1].t - w[0].t).collect();
    if gaps.is_empty() {
        // One extreme or none: nothing to be out of rhythm with.
        return Some(vec![0; extremes.len()]);
    }
    half_swings(extremes, upper_median(&mut gaps))
}

/// The time the motion stopped, when it stopped after extreme `i` as `rule` tells it
/// ([`drop_after_stop`]).
fn stop_after(ex: &[Extreme], i: usize, rule: Rest) -> Option<f64> {
    let before = &ex[..=i];
    let mut gaps: Vec<f64> = before.windows(2).map(|w| w[1].t - w[0].t).collect();
    let half = median(&mut gaps);
    if half.is_nan() || half <= 0.0 {
        return None;
    }
    let last = ex[i].t;
    let after = &ex[i + 1..];
    let parted = match rule {
        Rest::AfterGap => ex[i + 1].t - last > STOP_GAP * half,
        Rest::OutOfRhythm => {
            half_swings(before, half).is_some() && half_swings(&ex[i..], half).is_none()
        }
    };
    if !parted {
        return None;
    }
    let eq = equilibrium(before).ok()?.envelope;
    let t: Vec<f64> = before.iter().map(|e| e.t).collect();
    let amp: Vec<f64> = before.iter().map(|e| (e.angle - eq).abs()).collect();
    let line = linear_fit(&t, &amp);
    if line.slope.is_nan() || line.slope >= 0.0 {
        return None;
    }
    let t_zero = -line.intercept / line.slope;
    let reach = match rule {
        Rest::AfterGap => STOP_ZERO_AFTER_GAP,
        Rest::OutOfRhythm => STOP_GAP,
    };
    if t_zero.is_nan() || t_zero < last - 0.5 * half || t_zero > last + reach * half {
        return None;
    }
    let a_last = amp[i];
    let rest = median(&mut after.iter().map(|e| e.angle).collect::<Vec<_>>());
    after
        .iter()
        .all(|e| {
            (e.angle - eq).abs() < a_last
                && (rule == Rest::OutOfRhythm || (e.angle - rest).abs() < STOP_REST_BAND * a_last)
        })
        .then_some(t_zero)
}

/// A held start's departure is unseen when the samples after the hold begin more than
/// this share of a half swing after its last: the release's own fit reads the samples
/// within 0.3 of a half swing of it. (A hand that lets go hides the wire for a few
/// frames: on a sweep twin 0.6 s, a third of its half swing, and its release was still
/// fitted within a frame of the truth. A steadying lost for 2 s after the release of
/// another, over a half swing: its release was then fitted at the gap's end, and s_r
/// came out 3 % low.)
pub const RELEASE_GAP: f64 = 0.5;

/// A held start: the recording begins with the ball held at rest at its release angle
/// (by hand or a stop) and shows it being let go.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Release {
    /// When the ball was let go, s: between frames, from a fit of the departure.
    pub t_s: f64,
    /// Index of the first sample after the release; the samples before it are the hold,
    /// which is not fitted as motion.
    pub frame: usize,
    /// The held angle, in the series' own frame, rad: the start from rest.
    pub angle_rad: f64,
    /// How long the hold was recorded, s.
    pub held_s: f64,
}

/// Noise-band half-width of a hold, in multiples of the series' noise: the samples of a
/// hold stay within this of their mean.
pub const HOLD_NOISE_BAND: f64 = 5.0;
/// ... or within this fraction of the release amplitude, whichever is wider (a hand is
/// not a clamp: a tremor of a few percent of the swing is still a hold).
pub const HOLD_AMPLITUDE_BAND: f64 = 0.05;
/// A hold must last this many times longer than a turning point of the free motion stays
/// within the band (on both sides of it), so that a series which merely begins at or
/// near a turning point (the twins begin at the release) is not taken for a hold.
pub const HOLD_MARGIN: f64 = 2.0;

/// Find a held start: the series begins with a run of samples within its own noise of a
/// constant ([`HOLD_NOISE_BAND`], [`HOLD_AMPLITUDE_BAND`]), lasting longer than any turning point of the free motion could, away from
/// the centre of the swing, and ends by moving towards the centre. Returns the release
/// and its turning point, refined between frames.
///
/// From rest at `A`, the free motion is `A cos(omega tau)` (Eq. 33 at small angle,
/// ERRATA §2; `omega = pi / half swing`, measured from the motion after the hold),
/// so it leaves a band of half-width `b` after `acos(1 - b / A) / omega`; a turning
/// point of the free motion stays within the band twice that long. The release time is
/// then the `t_r` of the one-sided fit `y = p` before it and
/// `p + c tau^2 + e tau^4` after it (`tau = t - t_r`; the odd terms vanish, as at any
/// turning point, see the module documentation); the hold's side has no curvature.
pub fn find_release(s: &AngleSeries) -> Option<(Release, Extreme)> {
    let (t, y) = (&s.t, &s.angle);
    let n = y.len();
    if n < 16 {
        return None;
    }
    let sigma = noise_sigma(y);
    let center = median(&mut y.clone());
    let head = median(&mut y[..5].to_vec());
    let amp = (head - center).abs();
    if amp <= 6.0 * sigma || amp == 0.0 {
        return None;
    }
    let band = (HOLD_NOISE_BAND * sigma).max(HOLD_AMPLITUDE_BAND * amp);
    let run_of = |level: f64| y.iter().position(|v| (v - level).abs() > band).unwrap_or(n);
    let run = run_of(head);
    if run < 5 || run >= n {
        return None;
    }
    let level = y[..run].iter().sum::<f64>() / run as f64;
    let run = run_of(level);
    if run < 5 || run + 8 >= n {
        return None;
    }
    let side = (level - center).signum();
    let amp = (level - center).abs();
    // A release moves towards the centre.
    if side * (y[run] - level) >= 0.0 {
        return None;
    }
    // The half swing, from the motion after the hold.
    let sigma_m = noise_sigma(&y[run..]);
    let span = y[run..]
        .iter()
        .fold(0.0f64, |m, v| m.max((v - center).abs()));
    let coarse = lobes(&y[run..], center, (4.0 * sigma_m).max(1e-3 * span));
    if coarse.len() < 3 {
        return None;
    }
    let half = median_gap(&t[run..], &coarse);
    // The departure unseen (samples lost as the ball was let go: the hand in front, the
    // steadying of a moving camera lost for a while): when and from where it left is
    // not measured, and the first sample after the gap is no start from rest.
    if t[run] - t[run - 1] > RELEASE_GAP * half {
        return None;
    }
    let within = half / std::f64::consts::PI * (1.0 - band / amp).max(-1.0).acos();
    if t[run - 1] - t[0] < HOLD_MARGIN * 2.0 * within {
        return None;
    }
    // Sub-frame release time: the free motion crosses the band `within` after it.
    let dt = (t[run] - t[run - 1]).max(1e-12);
    let (lo_t, hi_t) = (t[run] - 2.0 * within - 2.0 * dt, t[run]);
    let guess = t[run] - within;
    let fit_lo = t.partition_point(|&v| v < guess - 0.3 * half);
    let fit_hi = t.partition_point(|&v| v <= guess + 0.3 * half);
    let (ft, fy) = (&t[fit_lo..fit_hi], &y[fit_lo..fit_hi]);
    let rss = |tr: f64| -> Option<(f64, f64)> {
        let basis = |ti: f64| {
            let tau = (ti - tr).max(0.0);
            let t2 = tau * tau;
            SVector::<f64, 3>::new(1.0, t2, t2 * t2)
        };
        let mut ata = SMatrix::<f64, 3, 3>::zeros();
        let mut atb = SVector::<f64, 3>::zeros();
        for (&ti, &yi) in ft.iter().zip(fy) {
            let row = basis(ti);
            ata += row * row.transpose();
            atb += row * yi;
        }
        let x = ata.cholesky()?.solve(&atb);
        let r = ft
            .iter()
            .zip(fy)
            .map(|(&ti, &yi)| (yi - basis(ti).dot(&x)).powi(2))
            .sum();
        Some((r, x[0]))
    };
    let grid = 32;
    let node = |g: usize| lo_t.max(t[0]) + (hi_t - lo_t.max(t[0])) * g as f64 / grid as f64;
    let step = (hi_t - lo_t.max(t[0])) / grid as f64;
    let (mut best_t, mut best) = (guess, f64::INFINITY);
    for g in 0..=grid {
        if let Some((r, _)) = rss(node(g)) {
            if r < best {
                (best_t, best) = (node(g), r);
            }
        }
    }
    let tol = 1e-6 * dt;
    let tr = golden_section_min(
        |x| rss(x).map(|r| r.0).ok_or(()),
        (best_t - step, best_t + step),
        tol,
    )
    .ok()?;
    let (r, p) = rss(tr)?;
    let frame = t.partition_point(|&v| v <= tr);
    Some((
        Release {
            t_s: tr,
            frame,
            angle_rad: p,
            held_s: tr - t[0],
        },
        Extreme {
            t: tr,
            angle: p,
            side,
            fit_rms: (r / ft.len() as f64).sqrt(),
            samples: ft.len(),
            release: true,
        },
    ))
}

/// Coarse turning points: the farthest sample of each lobe, `(side, index)`. A lobe is a
/// maximal run of samples beyond `center + h` or `center - h`; runs of the same side
/// separated only by the dead band are one lobe.
fn lobes(y: &[f64], center: f64, h: f64) -> Vec<(f64, usize)> {
    let mut runs: Vec<(f64, usize, usize)> = Vec::new(); // (side, first, last)
    for (i, v) in y.iter().enumerate() {
        let side = if v - center > h {
            1.0
        } else if v - center < -h {
            -1.0
        } else {
            continue;
        };
        match runs.last_mut() {
            Some(l) if l.0 == side => l.2 = i,
            _ => runs.push((side, i, i)),
        }
    }
    runs.iter()
        .map(|&(side, a, b)| {
            let k = (a..=b)
                .max_by(|&i, &j| (side * y[i]).total_cmp(&(side * y[j])))
                .expect("non-empty lobe");
            (side, k)
        })
        .collect()
}

/// The median time between consecutive coarse turning points: a half swing.
fn median_gap(t: &[f64], coarse: &[(f64, usize)]) -> f64 {
    let mut gaps: Vec<f64> = coarse.windows(2).map(|w| t[w[1].1] - t[w[0].1]).collect();
    median(&mut gaps)
}

/// [`find_extremes`] seeks a turning point within this share of a half swing either
/// side of a lobe's extreme ...
const WINDOW_SHARE: f64 = 0.3;

/// ... and refines it from at least this many samples there.
const MIN_WINDOW_SAMPLES: usize = 9;

/// When the median gap of every lobe leaves [`find_extremes`]' windows too short to hold
/// a turning point ([`MIN_WINDOW_SAMPLES`]), the half swing is the median gap between
/// consecutive lobes that both reach at least this share of the third tallest lobe's
/// height from the centre (the third: a misread frame or two, far out, would set the
/// tallest), when at least three such gaps are found. After an early stop, the ball at
/// rest wanders about the centre (a swaying camera's slow motion, the noise), crossing
/// it often and little, and a series may hold more of those lobes than of the swing's:
/// seed 1's sweep scene 11 (a sway of 1.7 px at 0.58 Hz, the camera not steadied; the
/// ball at rest from 23 s of 40) held 14 lobes of the swing, 1.6 to 1.7 s apart, and 43
/// of the ball at rest, their median gap 0.48 s; each turning point's window then held 7
/// samples, and none was found (the fit refused the video). Where the windows hold
/// their samples, the half swing is the median gap of every lobe, as it was, unless
/// those windows find too few turning points to fit: the fit then seeks them again over
/// the swing's own half swing ([`HalfSwing::SwingLobes`], `fit::measure::measure`).
pub const LOBE_GAP_SHARE: f64 = 0.1;

/// The half swing of the swing's own lobes ([`LOBE_GAP_SHARE`]), if at least three gaps
/// lie between them.
fn swing_gap(t: &[f64], y: &[f64], center: f64, coarse: &[(f64, usize)]) -> Option<f64> {
    let height = |k: usize| (y[k] - center).abs();
    let mut heights: Vec<f64> = coarse.iter().map(|&(_, k)| height(k)).collect();
    heights.sort_by(|a, b| b.total_cmp(a));
    let tall = LOBE_GAP_SHARE * *heights.get(2)?;
    let mut gaps: Vec<f64> = coarse
        .windows(2)
        .filter(|w| height(w[0].1) >= tall && height(w[1].1) >= tall)
        .map(|w| t[w[1].1] - t[w[0].1])
        .collect();
    (gaps.len() >= 3).then(|| median(&mut gaps))
}

/// Local cusp fit around a coarse extreme at `t_c`; see the module documentation.
fn refine(t: &[f64], y: &[f64], t_c: f64, side: f64, all_t: &[f64]) -> Option<Extreme> {
    let i = all_t.partition_point(|&v| v < t_c);
    let dt = if i + 1 < all_t.len() {
        all_t[i + 1] - all_t[i]
    } else {
        all_t[i] - all_t[i - 1]
    };
    let basis = |tau: f64| -> [f64; 6] {
        let t2 = tau * tau;
        let t4 = t2 * t2;
        let (l, r) = if tau < 0.0 { (1.0, 0.0) } else { (0.0, 1.0) };
        [1.0, l * t2, r * t2, l * t4, r * t4, t4 * t2]
    };
    let rss = |tk: f64| -> Option<(f64, f64)> {
        let mut ata = SMatrix::<f64, 6, 6>::zeros();
        let mut atb = SVector::<f64, 6>::zeros();
        for (&ti, &yi) in t.iter().zip(y) {
            let row = SVector::<f64, 6>::from(basis(ti - tk));
            ata += row * row.transpose();
            atb += row * yi;
        }
        let x = ata.cholesky()?.solve(&atb);
        let r: f64 = t
            .iter()
            .zip(y)
            .map(|(&ti, &yi)| {
                let b = basis(ti - tk);
                (yi - (0..6).map(|j| b[j] * x[j]).sum::<f64>()).powi(2)
            })
            .sum();
        Some((r, x[0]))
    };
    // Coarse grid over +-2 samples, then golden-section search around the best node.
    let grid = 16;
    let (mut best_t, mut best) = (t_c, f64::INFINITY);
    for g in 0..=grid {
        let tk = t_c - 2.0 * dt + 4.0 * dt * g as f64 / grid as f64;
        if let Some((r, _)) = rss(tk) {
            if r < best {
                best = r;
                best_t = tk;
            }
        }
    }
    let bracket = (
        best_t - 4.0 * dt / grid as f64,
        best_t + 4.0 * dt / grid as f64,
    );
    let tol = 1e-6 * dt.max(1e-12);
    let tk = golden_section_min(|x| rss(x).map(|r| r.0).ok_or(()), bracket, tol).ok()?;
    let (r, p) = rss(tk)?;
    Some(Extreme {
        t: tk,
        angle: p,
        side,
        fit_rms: (r / t.len() as f64).sqrt(),
        samples: t.len(),
        release: false,
    })
}

/// The equilibrium position by both estimators and the amplitude envelope.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Equilibrium {
    /// Eq. 38–39 as printed: the mean of the extreme elongations, rad.
    pub paper: f64,
    /// Joint symmetric-envelope fit (ERRATA §5), rad.
    pub envelope: f64,
    /// Envelope fit: amplitude at `t = 0`, rad.
    pub a0: f64,
    /// Envelope fit: amplitude decay rate, rad/s.
    pub a: f64,
    /// Envelope fit: RMS residual, rad.
    pub rms: f64,
}

/// Both equilibrium estimators on a list of extremes (at least three).
pub fn equilibrium(ex: &[Extreme]) -> Result<Equilibrium> {
    if ex.len() < 3 {
        bail!(
            "{} turning point(s) are too few for the equilibrium fit",
            ex.len()
        );
    }
    let paper = ex.iter().map(|e| e.angle).sum::<f64>() / ex.len() as f64;
    // psi_k = psi_eq + s_k A_0 - s_k a t_k : linear in (psi_eq, A_0, a).
    let m = ex.len();
    let a = DMatrix::from_fn(m, 3, |r, c| match c {
        0 => 1.0,
        1 => ex[r].side,
        _ => -ex[r].side * ex[r].t,
    });
    let b = DVector::from_iterator(m, ex.iter().map(|e| e.angle));
    let Some(x) = (a.transpose() * &a)
        .cholesky()
        .map(|c| c.solve(&(a.transpose() * &b)))
    else {
        bail!("the turning points do not alternate sides; cannot fit two envelopes");
    };
    let res = &b - &a * &x;
    Ok(Equilibrium {
        paper,
        envelope: x[0],
        a0: x[1],
        a: x[2],
        rms: (res.norm_squared() / m as f64).sqrt(),
    })
}

/// Amplitudes `|psi_k - psi_eq|` and the regression line of the paper's Fig. 14b/15:
/// `a` is minus its slope.
pub fn envelope_line(ex: &[Extreme], psi_eq: f64) -> (Vec<f64>, LineFit) {
    let amps: Vec<f64> = ex.iter().map(|e| (e.angle - psi_eq).abs()).collect();
    let ts: Vec<f64> = ex.iter().map(|e| e.t).collect();
    let line = linear_fit(&ts, &amps);
    (amps, line)
}

#[cfg(test)]
mod tests;
