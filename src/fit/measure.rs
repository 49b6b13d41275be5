//! The measured side of a fit: turning points, equilibrium, envelope and period of an
//! angle series, first model-free, then refined with the model's own shape.
//!
//! A recording that begins with the ball held at its release angle ([`signal::find_release`])
//! is measured from the release on: the hold is not motion, and the release is the first
//! turning point, a start from rest (`psi = psi_0`, `psi' = 0`), which is exactly how the
//! model is integrated from a turning point.

use super::BetaChoice;
use crate::numerics::{linear_fit, upper_median, LineFit};
use crate::physics::ode::{integrate, OdeOptions};
use crate::physics::{FrictionLaw, Pendulum};
use crate::series::AngleSeries;
use crate::signal::{self, envelope_line, Equilibrium, Extreme, Release, Stop};
use anyhow::{bail, Result};
use serde::Serialize;

/// The measured side: turning points, equilibrium and envelope of one angle series.
#[derive(Clone, Debug, Serialize)]
pub struct Measurement {
    pub extremes: Vec<Extreme>,
    pub equilibrium: Equilibrium,
    /// `|psi_k - psi_eq|` about the envelope-fit equilibrium, rad.
    pub amplitudes: Vec<f64>,
    /// Regression of the amplitudes on time (its slope is `-a`).
    pub envelope: LineFit,
    /// Half-swing index of each extreme, counted from the first (gaps allowed).
    pub index: Vec<usize>,
    /// Measured period (twice the half-swing time, by regression of `t_k` on index), s.
    pub period_s: f64,
    /// The held start, when the series begins with one: the samples before the release
    /// are not measured as motion.
    pub release: Option<Release>,
    /// The motion's end, when extremes after it (the ball at rest) were dropped.
    pub stop: Option<Stop>,
}

/// Minimum number of turning points for a fit with two parameters and a residual.
pub const MIN_EXTREMES: usize = 4;

/// A turning point is refitted with the model's shape ([`refine`]) only when each side
/// of its window that moves (after a release, only the side after it) holds at least
/// this share of the samples a gap-free side would: a side cut short by a gap (the wire
/// lost for a while) leaves the amplitude and the local equilibrium to be told apart by
/// the curvature of a short stretch, and the model-free turning point is kept. With the
/// angle noise of a sweep twin (0.017 deg a frame at 60 fps), a release whose motion is
/// seen for 0.35, 0.5, 0.7 or 1.1 s of the window's 1.35 s gave refitted amplitudes up to
/// 0.28, 0.12, 0.05 and 0.015 deg off (s_r up to 2.3 % off), the model-free one 0.007.
pub const REFINE_MIN_SIDE_SHARE: f64 = 0.75;

/// Extremes, equilibrium and envelope of an angle series (model-free: the turning
/// points come from local cusp fits, [`signal::find_extremes`]).
///
/// Where the windows the median gap of every lobe sets find too few turning points to
/// fit, they are sought again over the swing's own half swing
/// ([`signal::HalfSwing::SwingLobes`]): after an early stop the ball at rest may wander
/// across the centre a few times a second, and its many small lobes halve the half
/// swing while leaving the windows long enough to hold their samples. Seed 1205's sweep
/// scene 33 (1280x720 at 25 frames/s, hand-held and steadied, copper, the ball at rest
/// from 22 s of 40) gave a median gap of 0.84 s against the swing's 1.68, and 10 of its
/// 12 turning points saw too little fall on one side of windows half as wide as the
/// swing's: 2 were found and the fit was refused. Only a refusal is tried again: where
/// the first windows find enough, the swing's can set turning points out of rhythm (a
/// swaying camera's ball at rest, `tests/release_outliers.rs`).
pub fn measure(series: &AngleSeries) -> Result<Measurement> {
    let first = motion(series, signal::HalfSwing::EveryLobe)?;
    let found = if first.extremes.len() < MIN_EXTREMES {
        match motion(series, signal::HalfSwing::SwingLobes) {
            Ok(wider) if wider.extremes.len() > first.extremes.len() => wider,
            _ => first,
        }
    } else {
        first
    };
    let mut m = from_extremes(found.extremes)?;
    m.release = found.release;
    m.stop = found.stop;
    Ok(m)
}

/// The motion's turning points, those after its stop dropped
/// ([`signal::drop_after_stop`]), and its release and stop.
struct Motion {
    extremes: Vec<Extreme>,
    release: Option<Release>,
    stop: Option<Stop>,
}

/// The turning points of the motion ([`Motion`]), sought with the half swing `by` sets.
fn motion(series: &AngleSeries, by: signal::HalfSwing) -> Result<Motion> {
    let Some((release, start)) = signal::find_release(series) else {
        let mut extremes = signal::find_extremes_by(series, by)?;
        let stop = signal::drop_after_stop(&mut extremes);
        return Ok(Motion {
            extremes,
            release: None,
            stop,
        });
    };
    // Turning points are sought in the motion only, from the release on: there the
    // release leaves its lobe on one side only and is not taken for one.
    let moving = AngleSeries::new(
        series.t[release.frame..].to_vec(),
        series.angle[release.frame..].to_vec(),
    );
    let mut extremes = signal::find_extremes_by(&moving, by)?;
    // Nothing within half a half swing of the release is a turning point.
    let mut gaps: Vec<f64> = extremes.windows(2).map(|w| w[1].t - w[0].t).collect();
    if !gaps.is_empty() {
        let half = upper_median(&mut gaps);
        extremes.retain(|e| e.t - start.t > 0.5 * half);
    }
    extremes.insert(0, start);
    let stop = signal::drop_after_stop(&mut extremes);
    Ok(Motion {
        extremes,
        release: Some(release),
        stop,
    })
}

/// Equilibrium, envelope, half-swing indices and period of a list of turning points.
pub fn from_extremes(extremes: Vec<Extreme>) -> Result<Measurement> {
    if extremes.len() < MIN_EXTREMES {
        bail!(
            "only {} turning point(s) in the angle series; the fit needs at least {MIN_EXTREMES}",
            extremes.len()
        );
    }
    let equilibrium = signal::equilibrium(&extremes)?;
    let (amplitudes, envelope) = envelope_line(&extremes, equilibrium.envelope);
    let Some(index) = signal::in_rhythm(&extremes) else {
        bail!("turning points are not one half swing apart; the series is too irregular to fit");
    };
    let idx: Vec<f64> = index.iter().map(|&i| i as f64).collect();
    let ts: Vec<f64> = extremes.iter().map(|e| e.t).collect();
    let period_s = 2.0 * linear_fit(&idx, &ts).slope;
    Ok(Measurement {
        extremes,
        equilibrium,
        amplitudes,
        envelope,
        index,
        period_s,
        release: None,
        stop: None,
    })
}

impl Measurement {
    /// The measurement without turning point `k` (an outlier): equilibrium, envelope and
    /// period from the others, half-swing indices counted from the new first one. The
    /// amplitudes are kept as measured (each about its own equilibrium, after
    /// [`refine`]).
    pub fn without(&self, k: usize) -> Result<Measurement> {
        let mut extremes = self.extremes.clone();
        let mut amplitudes = self.amplitudes.clone();
        let mut index = self.index.clone();
        extremes.remove(k);
        amplitudes.remove(k);
        index.remove(k);
        if extremes.len() < MIN_EXTREMES {
            bail!(
                "only {} turning point(s) would be left; the fit needs at least {MIN_EXTREMES}",
                extremes.len()
            );
        }
        let i0 = index[0];
        index.iter_mut().for_each(|i| *i -= i0);
        let equilibrium = signal::equilibrium(&extremes)?;
        let ts: Vec<f64> = extremes.iter().map(|e| e.t).collect();
        let idx: Vec<f64> = index.iter().map(|&i| i as f64).collect();
        Ok(Measurement {
            envelope: linear_fit(&ts, &amplitudes),
            period_s: 2.0 * linear_fit(&idx, &ts).slope,
            extremes,
            equilibrium,
            amplitudes,
            index,
            release: self.release,
            stop: self.stop,
        })
    }
}

/// Second pass over the turning points: "fit the model itself around the extreme"
/// (ERRATA §7). Each turning point is refitted over most of the two half swings that
/// meet at it with the model's own shape: forward in time, the motion from rest at the
/// turning amplitude `A`; backward in time, the same with the friction's sign reversed
/// (the time reversal of Eq. 33). The unknowns are `A`, the turning time and the local
/// equilibrium `e`: `y(t) = e + side psi(t - t_k; A)`. `A` is then measured about a
/// local equilibrium, which no drift of the camera or error of the global equilibrium
/// can bias, and averages about three times as many samples as the local polynomial.
/// The shape uses `s_r` from the closed-form slope relation (ERRATA §2; its residual
/// effect on the shape is second order) and a pendulum whose length reproduces the
/// measured period, so that its time scale is the recording's own.
pub fn refine(
    series: &AngleSeries,
    m: &Measurement,
    p: &Pendulum,
    beta: f64,
    passes: usize,
) -> Result<Measurement> {
    let n = m.amplitudes.len() as f64;
    let mean_amp = m.amplitudes.iter().sum::<f64>() / n;
    let d = p.d_from_swing_period(m.period_s, mean_amp);
    let ps = Pendulum::new(p.r, p.m, p.j_z, d.max(1.001 * p.r), p.alpha, p.g)?;
    let s_r = (m.envelope.slope.abs() / ps.envelope_slope(&FrictionLaw::new(1.0, beta))).max(0.0);
    let (fwd_law, bwd_law) = (FrictionLaw::new(s_r, beta), FrictionLaw::new(-s_r, beta));
    let half = 0.5 * m.period_s;
    let w = 0.8 * half;
    let opts = OdeOptions {
        rtol: 1e-8,
        atol: 1e-9,
        t_end: 0.9 * half,
        ..OdeOptions::default()
    };
    // psi(tau; A) and psi'(tau; A) on both sides of a turning point at tau = 0; before a
    // release, the ball is at rest at A.
    let shape = |amp: f64, release: bool| {
        let fwd = integrate(&ps, &fwd_law, 0.0, [amp, 0.0], &opts);
        let bwd = (!release).then(|| integrate(&ps, &bwd_law, 0.0, [amp, 0.0], &opts));
        move |tau: f64| -> (f64, f64) {
            match &bwd {
                _ if tau >= 0.0 => {
                    let [x, v] = fwd.state(tau);
                    (x, v)
                }
                Some(bwd) => {
                    let [x, v] = bwd.state(-tau);
                    (x, -v)
                }
                None => (amp, 0.0),
            }
        }
    };
    let (t, y) = (&series.t, &series.angle);
    // The samples a gap-free side of a window holds, at the series' typical interval
    // (within the series: its own ends are no gap).
    let mut steps: Vec<f64> = t.windows(2).map(|p| p[1] - p[0]).collect();
    let step = upper_median(&mut steps);
    let (first, last) = (t[0], t[t.len() - 1]);
    let short = |n: usize, span: f64| (n as f64) < REFINE_MIN_SIDE_SHARE * span / step;
    let mut out = Vec::with_capacity(m.extremes.len());
    let mut amps = Vec::with_capacity(m.extremes.len());
    for (e, &a_first) in m.extremes.iter().zip(&m.amplitudes) {
        let lo = t.partition_point(|&v| v < e.t - w);
        let hi = t.partition_point(|&v| v <= e.t + w);
        let mid = t.partition_point(|&v| v <= e.t);
        if hi - lo < 12
            || short(hi - mid, w.min(last - e.t))
            || (!e.release && short(mid - lo, w.min(e.t - first)))
        {
            out.push(*e);
            amps.push(a_first);
            continue;
        }
        let (mut amp, mut tk, mut eq) = (a_first, e.t, e.angle - e.side * a_first);
        let mut rss = 0.0;
        // Outer passes integrate the shape at the current amplitude; inner Gauss–Newton
        // steps scale it (psi(tau; A) ~ psi(tau; A_s) A / A_s, exact to O(A^2 dA), and
        // the next pass removes even that).
        for _pass in 0..passes {
            let a_s = amp;
            let cur = shape(a_s, e.release);
            for _ in 0..8 {
                let scale = amp / a_s;
                let mut ata = nalgebra::Matrix3::<f64>::zeros();
                let mut atr = nalgebra::Vector3::<f64>::zeros();
                rss = 0.0;
                for i in lo..hi {
                    let (x, v) = cur(t[i] - tk);
                    let r = y[i] - eq - e.side * x * scale;
                    let g = nalgebra::Vector3::new(e.side * x / a_s, -e.side * v * scale, 1.0);
                    ata += g * g.transpose();
                    atr += g * r;
                    rss += r * r;
                }
                let Some(step) = ata.cholesky().map(|c| c.solve(&atr)) else {
                    break;
                };
                amp += step[0];
                tk += step[1].clamp(-0.05 * half, 0.05 * half);
                eq += step[2];
                // Far below the noise of any recording (1e-8 rad, 1e-6 of a half swing).
                if step[0].abs() < 1e-8 && step[1].abs() < 1e-6 * half {
                    break;
                }
            }
        }
        out.push(Extreme {
            t: tk,
            angle: eq + e.side * amp,
            side: e.side,
            fit_rms: (rss / (hi - lo) as f64).sqrt(),
            samples: hi - lo,
            release: e.release,
        });
        amps.push(amp);
    }
    let release = match (m.release, out.first()) {
        (Some(_), Some(e)) if e.release => Some(Release {
            t_s: e.t,
            frame: t.partition_point(|&v| v <= e.t),
            angle_rad: e.angle,
            held_s: e.t - t[0],
        }),
        (r, _) => r,
    };
    let mut refined = from_extremes(out)?;
    refined.release = release;
    refined.stop = m.stop;
    // The amplitudes about each turning point's own equilibrium.
    refined.envelope = linear_fit(
        &refined.extremes.iter().map(|e| e.t).collect::<Vec<_>>(),
        &amps,
    );
    refined.amplitudes = amps;
    Ok(refined)
}

/// The whole measurement: model-free turning points, then their model refinement.
pub fn analyze(p: &Pendulum, series: &AngleSeries, beta: BetaChoice) -> Result<Measurement> {
    let first = measure(series)?;
    let b = match beta {
        BetaChoice::Fixed(b) => b,
        BetaChoice::Free => 1.0,
    };
    // Twice: the second pass takes the period and slope from the better turning points
    // of the first, so the shape's time scale matches the recording's to ~1e-5.
    let second = refine(series, &first, p, b, 1)?;
    refine(series, &second, p, b, 2)
}
