//! Comparisons of a reproduced value with an expected one, and the consistency verdict
//! on every result.
//!
//! A check's verdict is always recomputed from its numbers ([`Check::verdict`]), so a
//! summary edited by hand cannot claim a pass its numbers do not support.
//!
//! A result is `ok` only when the data agree with the physics it was fitted with
//! ([`assess`]): the period measured against the geometry's, the fit's residual against
//! the angle series' own noise, the envelope's shape (linear for rolling friction,
//! exponential for viscous damping), the earlier and the later turning points' `s_r`
//! against each other, the width of the interval on `s_r`, the turning points the fit
//! dropped as outliers, and, for angles measured in a video, the pivot
//! against the wire's own direction and the swing's scale through a lens or a plate
//! calibration. Each disagreement is a named [`Warning`]; a result
//! with any is `suspect`.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The value a result is compared with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Against {
    /// A published value (the experiment's `reference.source`, `reference` if unnamed).
    Reference(String),
    /// The `s_r` the digital twin was rendered with.
    SyntheticTruth,
}

impl Against {
    const TRUTH: &'static str = "synthetic truth";

    pub fn as_str(&self) -> &str {
        match self {
            Against::Reference(s) => s,
            Against::SyntheticTruth => Self::TRUTH,
        }
    }
}

impl Serialize for Against {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for Against {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        Ok(if s == Self::TRUTH {
            Against::SyntheticTruth
        } else {
            Against::Reference(s)
        })
    }
}

/// The quantity a check compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Quantity {
    /// The rolling-friction coefficient, m.
    #[serde(rename = "s_r")]
    SR,
    /// The dimensionless coefficient `s_r N_0^(beta-1) / r`.
    #[serde(rename = "mu_r")]
    MuR,
    /// The envelope slope, rad/s.
    #[serde(rename = "a")]
    A,
}

impl Quantity {
    pub fn as_str(&self) -> &'static str {
        match self {
            Quantity::SR => "s_r",
            Quantity::MuR => "mu_r",
            Quantity::A => "a",
        }
    }
}

/// One comparison of a reproduced value with an expected one.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Check {
    pub quantity: Quantity,
    pub against: Against,
    pub value: f64,
    pub expected: f64,
    pub tolerance_rel: f64,
    pub deviation_rel: f64,
    pub pass: bool,
}

impl Check {
    pub fn new(quantity: Quantity, against: Against, value: f64, expected: f64, tol: f64) -> Self {
        let dev = (value - expected) / expected;
        Self {
            quantity,
            against,
            value,
            expected,
            tolerance_rel: tol,
            deviation_rel: dev,
            pass: dev.abs() <= tol,
        }
    }

    /// Recompute the verdict from the numbers (a summary's `pass` is not trusted).
    pub fn verdict(&self) -> bool {
        let dev = (self.value - self.expected) / self.expected;
        dev.is_finite() && dev.abs() <= self.tolerance_rel
    }
}

/// The limits of the consistency checks (an experiment's `tolerances:`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Largest `|d_period - d| / d`.
    pub period_rel: f64,
    /// Largest ratio of the amplitude residual RMS to the amplitude scatter the angle
    /// noise explains.
    pub residual_factor: f64,
    /// Largest AICc advantage of an exponential envelope over a linear one.
    pub envelope_aicc: f64,
    /// Largest relative difference between the `s_r` of the earlier and of the later
    /// half of the turning points.
    pub halves_rel: f64,
    /// Largest relative half-width of the 95 % interval on `s_r`.
    pub interval_rel: f64,
    /// Turning points the fit may drop as outliers without a warning.
    pub outliers: usize,
    /// Largest `|swing_scale - 1|`.
    pub pivot_rel: f64,
    /// Largest relative standard uncertainty of `s_r` from the swing's scale (a lens, a
    /// plate calibration).
    pub scale_rel: f64,
}

/// The check names, in the order they are run.
pub use crate::config::CHECKS;

/// One failed consistency check.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Warning {
    /// `period`, `residual`, `envelope`, `halves`, `interval`, `outliers`, `pivot`,
    /// `scale` or `detection`.
    pub check: String,
    pub value: f64,
    pub limit: f64,
    /// One line: what disagrees with what.
    pub reason: String,
    /// The experiment file's written reason for accepting it, if it does.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accepted: Option<String>,
}

/// `ok` or `suspect`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    #[default]
    Ok,
    Suspect,
}

impl Status {
    pub fn as_str(&self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Suspect => "suspect",
        }
    }
}

/// A result's verdict: `suspect` when any consistency check failed.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    #[serde(default)]
    pub verdict: Status,
    #[serde(default)]
    pub warnings: Vec<Warning>,
}

impl Verdict {
    /// The verdict of a list of warnings.
    pub fn of(warnings: Vec<Warning>) -> Self {
        Self {
            verdict: if warnings.is_empty() {
                Status::Ok
            } else {
                Status::Suspect
            },
            warnings,
        }
    }

    /// Mark the warnings an experiment accepts, `(check, reason)`.
    pub fn accept<'a>(&mut self, accepted: impl IntoIterator<Item = (&'a str, &'a str)>) {
        for (check, reason) in accepted {
            for w in self.warnings.iter_mut().filter(|w| w.check == check) {
                w.accepted = Some(reason.to_string());
            }
        }
    }

    /// Recomputed from the warnings (a stale `verdict` field is not trusted).
    pub fn status(&self) -> Status {
        if self.warnings.is_empty() {
            Status::Ok
        } else {
            Status::Suspect
        }
    }

    /// The warnings no written reason accepts.
    pub fn open(&self) -> impl Iterator<Item = &Warning> {
        self.warnings.iter().filter(|w| w.accepted.is_none())
    }

    /// Suspect, with a warning nobody accepted.
    pub fn blocks(&self) -> bool {
        self.open().next().is_some()
    }

    /// `ok`, `suspect (period, envelope)` or `suspect, accepted (period)`.
    pub fn label(&self) -> String {
        if self.warnings.is_empty() {
            return "ok".into();
        }
        let names = |acc: bool| {
            self.warnings
                .iter()
                .filter(|w| w.accepted.is_some() == acc)
                .map(|w| w.check.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let (open, acc) = (names(false), names(true));
        match (open.is_empty(), acc.is_empty()) {
            (false, true) => format!("suspect ({open})"),
            (true, false) => format!("suspect, accepted ({acc})"),
            _ => format!("suspect ({open}; accepted: {acc})"),
        }
    }
}

/// What the consistency checks look at.
#[derive(Clone, Debug)]
pub struct Evidence<'a> {
    /// Pendulum length `d` of the geometry, m.
    pub d_m: f64,
    /// The length the measured period implies, m.
    pub d_from_period_m: f64,
    /// Per-frame noise of the angle series, rad.
    pub frame_noise_rad: f64,
    /// Samples behind each measured amplitude (its local fit's window).
    pub samples: &'a [usize],
    /// Times of the turning points, s, and their amplitudes, rad.
    pub t: &'a [f64],
    pub amplitudes: &'a [f64],
    /// RMS residual of the model fit to the amplitudes, rad.
    pub residual_rms_rad: f64,
    pub s_r: f64,
    pub s_r_ci95: [f64; 2],
    /// The `s_r` of the earlier and of the later half of the turning points, each
    /// fitted alone (`crate::uncertainty::AngleUncertainty::halves_m`); `None` with
    /// fewer than six turning points.
    pub s_r_halves: Option<[f64; 2]>,
    /// Times of the turning points dropped from the fit as outliers, s.
    pub outliers_dropped: &'a [f64],
    /// Times of the outliers found beyond the cap and kept in the fit, s.
    pub outliers_kept: &'a [f64],
    /// The most turning points the fit may drop (a tenth of them).
    pub outlier_cap: usize,
    /// Of angles measured in a video: how much more the wire's own direction turns than
    /// its angle about the pivot (the detector's `swing_scale`; 1 when the pivot lies
    /// on the wire's line).
    pub swing_scale: Option<f64>,
    /// Of angles measured through a lens or a plate calibration: the relative standard
    /// uncertainty the swing's scale puts on `s_r` (the budget's lens and calibration
    /// components, combined).
    pub scale_u_rel: Option<f64>,
}

/// Residual sum of squares of the best linear envelope `A0 - a t`.
pub fn linear_rss(t: &[f64], y: &[f64]) -> f64 {
    let n = t.len() as f64;
    let (mt, my) = (t.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = t.iter().map(|x| (x - mt).powi(2)).sum();
    let sxy: f64 = t.iter().zip(y).map(|(x, v)| (x - mt) * (v - my)).sum();
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    t.iter()
        .zip(y)
        .map(|(x, v)| (v - my - b * (x - mt)).powi(2))
        .sum()
}

/// Residual sum of squares of the best exponential envelope `A0 exp(-k t)` (`k >= 0`
/// profiled: `A0` is linear given `k`) and its `k`, 1/s.
pub fn exponential_rss(t: &[f64], y: &[f64]) -> (f64, f64) {
    let t0 = t.first().copied().unwrap_or(0.0);
    let rss_at = |k: f64| {
        let e: Vec<f64> = t.iter().map(|x| (-k * (x - t0)).exp()).collect();
        let ee: f64 = e.iter().map(|v| v * v).sum();
        let ey: f64 = e.iter().zip(y).map(|(a, b)| a * b).sum();
        let a0 = if ee > 0.0 { ey / ee } else { 0.0 };
        e.iter()
            .zip(y)
            .map(|(a, b)| (b - a0 * a).powi(2))
            .sum::<f64>()
    };
    let span = (t.last().copied().unwrap_or(t0) - t0).max(1e-9);
    // Rates from no decay to a thousandfold over the recording, on a log grid, then a
    // golden-section polish around the best.
    let grid: Vec<f64> = std::iter::once(0.0)
        .chain((0..=120).map(|i| 1e-4 * 10f64.powf(i as f64 / 20.0) / span))
        .collect();
    let (mut best_k, mut best) = (0.0, rss_at(0.0));
    for &k in &grid {
        let r = rss_at(k);
        if r < best {
            (best_k, best) = (k, r);
        }
    }
    let (mut lo, mut hi) = (best_k / 1.13, best_k * 1.13);
    if best_k > 0.0 {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..60 {
            let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if rss_at(x1) < rss_at(x2) {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        let k = 0.5 * (lo + hi);
        let r = rss_at(k);
        if r < best {
            (best_k, best) = (k, r);
        }
    }
    (best, best_k)
}

/// The `residual` check's ratio: the amplitudes' RMS residual about the model against
/// the scatter the per-frame noise alone explains (each amplitude averages its window's
/// frames, so about `sigma_frame / sqrt(samples)`), and the mean window it assumed.
pub fn residual_ratio(
    residual_rms_rad: f64,
    frame_noise_rad: f64,
    samples: &[usize],
) -> (f64, f64) {
    let n = samples.len().max(1) as f64;
    let mean_samples = (samples.iter().sum::<usize>() as f64 / n).max(1.0);
    let expected = (frame_noise_rad / mean_samples.sqrt()).max(1e-5);
    (residual_rms_rad / expected, mean_samples)
}

/// `v <= limit`, false when either is NaN (a NaN never passes a check).
fn within(v: f64, limit: f64) -> bool {
    v <= limit
}

/// The consistency checks of one fit (the `inputs` check refuses a result instead, in
/// the pipeline: see [`degrees_suspected`]).
pub fn assess(e: &Evidence, lim: &Limits) -> Verdict {
    let mut w = Vec::new();
    // period: ERRATA §2's small-angle period 2 pi sqrt(7 L / (5 g sin(alpha))) turned
    // into the length it implies.
    let dev = (e.d_from_period_m - e.d_m) / e.d_m;
    if !within(dev.abs(), lim.period_rel) {
        w.push(Warning {
            check: "period".into(),
            value: dev.abs(),
            limit: lim.period_rel,
            reason: format!(
                "the measured period implies d = {:.4} m, the geometry says {:.4} m ({:+.1} %): \
                 the YAML's geometry does not describe this pendulum",
                e.d_from_period_m,
                e.d_m,
                100.0 * dev
            ),
            accepted: None,
        });
    }
    let (ratio, mean_samples) = residual_ratio(e.residual_rms_rad, e.frame_noise_rad, e.samples);
    if !within(ratio, lim.residual_factor) {
        w.push(Warning {
            check: "residual".into(),
            value: ratio,
            limit: lim.residual_factor,
            reason: format!(
                "the amplitudes scatter about the model by {:.4} deg RMS, {ratio:.1} times what \
                 the angle noise ({:.4} deg per frame over ~{mean_samples:.0} frames) explains: \
                 a turning point is wrong or the model does not fit",
                e.residual_rms_rad.to_degrees(),
                e.frame_noise_rad.to_degrees()
            ),
            accepted: None,
        });
    }
    // envelope: linear (rolling friction, Eq. 33) against exponential (viscous or air
    // damping), both with two parameters, by their AICc difference n ln(RSS_lin/RSS_exp).
    let k = e.amplitudes.len();
    if k >= 4 {
        let lin = linear_rss(e.t, e.amplitudes).max(1e-300);
        let (exp, rate) = exponential_rss(e.t, e.amplitudes);
        let gain = k as f64 * (lin / exp.max(1e-300)).ln();
        if gain > lim.envelope_aicc {
            w.push(Warning {
                check: "envelope".into(),
                value: gain,
                limit: lim.envelope_aicc,
                reason: format!(
                    "the amplitudes decay exponentially (time constant {:.1} s), not linearly: \
                     viscous or air damping, not rolling friction, dominates (AICc favours the \
                     exponential by {gain:.1})",
                    1.0 / rate
                ),
                accepted: None,
            });
        }
    }
    // halves: rolling friction's s_r is one number for the whole recording (Eq. 33's
    // linear envelope, or the beta law's); when the earlier and the later turning points,
    // each fitted alone, disagree by more than the limit, the envelope bends in a way the
    // model does not: a damping that weakens with the swing (air, viscous: the envelope
    // check's exponential, caught here before it is clearly preferred), a friction that
    // changes with the amplitude, an equilibrium off, or a detector scale that changes
    // with the swing (a shadow or a second edge followed instead of the wire, a camera's
    // perspective).
    // (An s_r of zero has no finite relative difference: the interval check speaks for
    // it.)
    if let Some([early, late]) = e.s_r_halves {
        let dev = (early - late) / e.s_r.abs();
        if dev.is_finite() && !within(dev.abs(), lim.halves_rel) {
            w.push(Warning {
                check: "halves".into(),
                value: dev.abs(),
                limit: lim.halves_rel,
                reason: format!(
                    "the earlier half of the turning points gives s_r = {early:.4e} m, the later \
                     half {late:.4e} m ({:.1} % apart): one s_r does not describe the whole \
                     recording (a damping that weakens with the swing, as air's does, a \
                     friction that changes with the amplitude, an equilibrium off, or a \
                     detector scale that changes with the swing)",
                    100.0 * dev.abs()
                ),
                accepted: None,
            });
        }
    }
    // interval: s_r resolved from zero, and not wider than the limit.
    let [lo, hi] = e.s_r_ci95;
    let half = 0.5 * (hi - lo) / e.s_r.abs();
    if !within(f64::MIN_POSITIVE, lo) {
        w.push(Warning {
            check: "interval".into(),
            value: lo,
            limit: 0.0,
            reason: format!(
                "the 95 % interval on s_r ({lo:.3e} .. {hi:.3e} m) includes zero: s_r is not \
                 resolved"
            ),
            accepted: None,
        });
    } else if !within(half, lim.interval_rel) {
        w.push(Warning {
            check: "interval".into(),
            value: half,
            limit: lim.interval_rel,
            reason: format!(
                "the 95 % interval on s_r is +/- {:.1} % wide (limit {:.1} %)",
                100.0 * half,
                100.0 * lim.interval_rel
            ),
            accepted: None,
        });
    }
    // outliers: every turning point found to be an outlier is said, dropped or not, beyond
    // the allowance; more than the cap always.
    let (dropped, kept) = (e.outliers_dropped, e.outliers_kept);
    let found = dropped.len() + kept.len();
    let limit = lim.outliers.min(e.outlier_cap);
    if found > limit {
        let times = |ts: &[f64]| {
            ts.iter()
                .map(|t| format!("{t:.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let points = |n: usize| {
            if n == 1 {
                "1 turning point".to_string()
            } else {
                format!("{n} turning points")
            }
        };
        let is = |n: usize| if n == 1 { "is" } else { "are" };
        let mut reason = String::new();
        if !dropped.is_empty() {
            reason = format!(
                "{} dropped as {} (t = {} s)",
                points(dropped.len()),
                if dropped.len() == 1 {
                    "an outlier"
                } else {
                    "outliers"
                },
                times(dropped)
            );
        }
        if !kept.is_empty() {
            let more = if reason.is_empty() { "" } else { "; and" };
            reason = format!(
                "{reason}{more}{}{} {} outlying (t = {} s) but kept in the fit: at most {} \
                 may be dropped (a tenth of the turning points)",
                if more.is_empty() { "" } else { " " },
                points(kept.len()),
                is(kept.len()),
                times(kept),
                e.outlier_cap
            );
        }
        w.push(Warning {
            check: "outliers".into(),
            value: found as f64,
            limit: limit as f64,
            reason,
            accepted: None,
        });
    }
    // pivot: a pivot off along the wire by delta (at a mean radius R) leaves each frame's
    // free line where it is but turns the line through the pivot by R / (R + delta) of
    // its angle: the measured swing, and s_r with the envelope slope, shrink or grow by
    // about that.
    if let Some(scale) = e.swing_scale {
        let dev = scale - 1.0;
        if !within(dev.abs(), lim.pivot_rel) {
            w.push(Warning {
                check: "pivot".into(),
                value: dev.abs(),
                limit: lim.pivot_rel,
                reason: format!(
                    "the wire's own direction swings {:.1} % {} than its angle about the pivot: \
                     the pivot is off along the wire, which scales the measured swing, and s_r, \
                     by about as much; give `video.pivot`",
                    100.0 * dev.abs(),
                    if dev > 0.0 { "more" } else { "less" }
                ),
                accepted: None,
            });
        }
    }
    // scale: the swing's scale through a lens (or a plate calibration) known so loosely
    // that it alone spreads s_r beyond the limit. The interval says it too, but among
    // every other share; a lens fitted from a sheet whose lines were too few or too
    // faint is the cause to name (its s_r can be a percent off and `ok` otherwise).
    if let Some(u) = e.scale_u_rel {
        if !within(u, lim.scale_rel) {
            w.push(Warning {
                check: "scale".into(),
                value: u,
                limit: lim.scale_rel,
                reason: format!(
                    "the swing's scale through the lens or the plate's calibration is known to \
                     +/- {:.2} % only, and s_r with it (limit {:.2} %): fit the lens from a \
                     sheet with more, sharper lines (`rollfric lens`), or calibrate with more \
                     points",
                    100.0 * u,
                    100.0 * lim.scale_rel
                ),
                accepted: None,
            });
        }
    }
    Verdict::of(w)
}

/// Why an angle series (rad) looks like degrees, if it does: the wire's angle is a
/// direction (within a turn of zero) and the pendulum swings less than 90 degrees from
/// its equilibrium (`center`, e.g. the series' median).
pub fn degrees_suspected(angles: &[f64], center: f64) -> Option<String> {
    let (lo, hi) = angles
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let tau = std::f64::consts::TAU;
    let swing = (hi - center).max(center - lo);
    if hi - lo > tau {
        Some(format!(
            "the angles span {:.3} rad, more than a full turn: are these degrees? \
             (`angle_rad` is in radians)",
            hi - lo
        ))
    } else if swing > std::f64::consts::FRAC_PI_2 {
        Some(format!(
            "the angle swings {:.3} rad ({:.1} deg) from its equilibrium, beyond 90 deg: \
             are these degrees? (`angle_rad` is in radians)",
            swing,
            swing.to_degrees()
        ))
    } else if center.abs() > tau {
        Some(format!(
            "the equilibrium angle is {} rad, beyond a full turn: are these degrees? \
             (`angle_rad` is in radians)",
            crate::config::shown((center * 1e3).round() / 1e3)
        ))
    } else {
        None
    }
}

#[cfg(test)]
mod tests;
