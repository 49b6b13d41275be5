//! The rolling-friction coefficient from measured turning points (the paper's
//! section 2.4: "the value of s_r is found imposing the condition that the theoretical
//! curve passes as closely as possible to the experimental points").
//!
//! The model's turning amplitudes come from integrating Eq. 33 ([`crate::physics::ode`])
//! from a turning point of amplitude `A` (the first measured one). Both `s_r` and `A`
//! are fitted by Gauss–Newton (Levenberg-damped) least squares on the amplitudes
//! `|psi_k - psi_eq|`, so noise on the first extreme does not pin the whole model
//! (the starting amplitude is profiled out). The 95 % interval on `s_r` is Student's t
//! on the linearised covariance `sigma^2 (J^T J)^-1`.
//!
//! Derived results: `mu_r = s_r N_0^(beta-1) / r` (Eq. 40; `s_r / r` for `beta = 1`),
//! the pendulum length implied by the measured period (a geometry cross-check), and the
//! reactions along the fitted motion: `N(t)` (Eq. 30, Fig. 17) and `|T| / N` (Eq. 31,
//! 34, Fig. 18).
//!
//! One bad turning point (a spoiled frame at the extreme, a hand in the picture) must not
//! drag `s_r`: [`fit_robust`] drops turning points whose residual is an outlier against
//! the residuals' robust scale and far above the angle noise, one at a time, refitting
//! after each, and names them (at most a tenth of them; beyond that the verdict says so
//! instead of dropping more).

use crate::numerics::{golden_section_min, linear_fit, median};
use crate::physics::ode::{integrate, OdeOptions};
pub use crate::physics::BetaChoice;
use crate::physics::{FrictionLaw, Pendulum};
pub use crate::signal::{Release, Stop};
use crate::stats::student_t_quantile;
use anyhow::{bail, Context, Result};
use serde::Serialize;

mod air;
mod measure;
mod reactions;
mod series;

pub use air::{fit_drag_scale, AirShare, MAX_DRAG_SCALE};
pub use measure::{analyze, from_extremes, measure, refine, Measurement, MIN_EXTREMES};
pub use reactions::{reactions, Reactions};
pub use series::{beta_name, beta_series, BetaSeries, BetaTrial, SeriesRun, BETA_TRIALS};

/// Model turning amplitudes `|psi_j|`, `j = 0..=j_max`, starting from a turning point of
/// amplitude `a0` (`j = 0`). After the model stops, its amplitude stays at the last one.
pub fn model_amplitudes(
    p: &Pendulum,
    law: &FrictionLaw,
    a0: f64,
    j_max: usize,
    rtol: f64,
) -> Vec<f64> {
    let opts = OdeOptions {
        rtol,
        // Angles and rates are of order 0.1 rad and 0.1 rad/s.
        atol: rtol * 0.1,
        max_turns: j_max,
        ..OdeOptions::default()
    };
    let tr = integrate(p, law, 0.0, [a0, 0.0], &opts);
    let mut amps = Vec::with_capacity(j_max + 1);
    amps.push(a0);
    amps.extend(tr.turns.iter().map(|tp| tp.psi.abs()));
    while amps.len() <= j_max {
        amps.push(*amps.last().expect("non-empty"));
    }
    amps
}

/// One candidate exponent in the model comparison.
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize, PartialEq)]
pub struct BetaCandidate {
    pub beta: f64,
    pub s_r: f64,
    /// Residual sum of squares of the amplitudes, rad^2.
    pub rss: f64,
    /// Small-sample Akaike criterion (lower is better; differences below ~2 mean the
    /// data cannot tell the exponents apart).
    pub aicc: f64,
}

/// The complete result of one fit.
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct FitResult {
    pub s_r_m: f64,
    pub s_r_se_m: f64,
    /// The least-squares 95 % interval (the turning points taken as independent).
    pub s_r_ci95_m: [f64; 2],
    /// The angles' standard uncertainty of `s_r`: statistics with correlated
    /// neighbours, drift and the detector's scale (`crate::uncertainty`; the geometry
    /// taken as exact, its share is in the budget), m. Set by the pipeline.
    #[serde(default)]
    pub s_r_u_m: f64,
    /// `s_r +- k s_r_u_m` (95 %), m. How both were made up: the budget's `angles`.
    #[serde(default)]
    pub s_r_interval95_m: [f64; 2],
    pub beta: f64,
    /// Fitted amplitude at the first measured turning point, rad.
    pub a_start_rad: f64,
    pub mu_r: f64,
    /// Envelope slope `a` from the measured amplitudes, rad/s.
    pub a_rad_s: f64,
    /// Envelope slope of the fitted model's turning points, rad/s.
    pub a_model_rad_s: f64,
    /// Equilibrium by the symmetric-envelope fit (used for the amplitudes), rad.
    pub psi_eq_rad: f64,
    /// Equilibrium by Eq. 38–39 as printed (mean of the extremes), rad.
    pub psi_eq_paper_rad: f64,
    pub n_extremes: usize,
    pub period_s: f64,
    pub d_from_period_m: f64,
    pub max_t_over_n: f64,
    pub reactions: Reactions,
    /// Amplitude residuals `measured - model`, rad.
    pub residuals_rad: Vec<f64>,
    pub residual_rms_rad: f64,
    pub iterations: usize,
    pub beta_comparison: Vec<BetaCandidate>,
    /// The held start, when the recording begins with the ball held at its release
    /// angle: the fit starts there from rest, and the frames before `t_s` (`frame` of
    /// them) are not fitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub release: Option<Release>,
    /// The motion's end, when the recording runs on after the ball has stopped and
    /// extremes of the ball at rest were dropped ([`crate::signal::drop_after_stop`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<Stop>,
    /// Turning points found to be outliers ([`fit_robust`]), in time order: dropped from
    /// the fit, or kept in it when more than the cap were found.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outliers: Vec<Outlier>,
    /// The air's share, when the pendulum moves through air: `s_r` without it, the
    /// correction, the share of the energy.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub air: Option<AirShare>,
}

/// A turning point whose amplitude residual is an outlier.
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize, PartialEq)]
pub struct Outlier {
    pub t_s: f64,
    /// Angle at the turning point (the series' frame), rad.
    pub angle_rad: f64,
    /// Its measured amplitude, rad.
    pub amplitude_rad: f64,
    /// Its residual (measured - model) in the fit it was found in, rad.
    pub residual_rad: f64,
    /// That residual's distance from the residuals' median in robust standard
    /// deviations (`1.4826 MAD`).
    pub robust_z: f64,
    /// Dropped from the fit; `false` when found beyond the cap and kept.
    pub dropped: bool,
}

/// A residual is an outlier beyond this many robust standard deviations
/// (`1.4826 * MAD`, the standard deviation for Gaussian residuals) from the residuals'
/// median: five, which a Gaussian residual exceeds once in three million.
pub const OUTLIER_ROBUST_Z: f64 = 5.0;
/// ... and only when it is also larger than this many times the scatter the angle noise
/// alone gives one amplitude (`sigma / sqrt(frames behind it)`, the `residual` check's
/// unit): the noise floor, so that a clean fit, whose residuals may be far below any
/// real error, drops nothing. The clean digital twins' largest residuals reach 10 of
/// these (their errors are not white: blur, compression, lighting drift), some with a
/// robust z above 5; a spoiled turning point is hundreds.
pub const OUTLIER_NOISE_FACTOR: f64 = 30.0;
/// At most this fraction of the turning points may be dropped (rounded down, and never
/// below the fit's minimum); more outliers than that is not one bad turning point.
pub const OUTLIER_MAX_FRACTION: f64 = 0.1;

/// How many of `n` turning points [`fit_robust`] may drop.
pub fn outlier_cap(n: usize) -> usize {
    ((OUTLIER_MAX_FRACTION * n as f64).floor() as usize).min(n.saturating_sub(MIN_EXTREMES))
}

/// The residuals that are outliers: `(position, robust z)`. `samples[i]` is the number
/// of frames behind turning point `i`, `frame_noise_rad` the series' per-frame noise.
fn outlying(residuals: &[f64], samples: &[usize], frame_noise_rad: f64) -> Vec<(usize, f64)> {
    if residuals.len() < 3 {
        return Vec::new();
    }
    let med = median(&mut residuals.to_vec());
    let mut dev: Vec<f64> = residuals.iter().map(|r| (r - med).abs()).collect();
    let scale = 1.4826 * median(&mut dev);
    residuals
        .iter()
        .zip(samples)
        .enumerate()
        .filter_map(|(i, (&r, &n))| {
            let z = (r - med).abs() / scale;
            let floor = (frame_noise_rad / (n.max(1) as f64).sqrt()).max(1e-5);
            (z > OUTLIER_ROBUST_Z && r.abs() > OUTLIER_NOISE_FACTOR * floor).then_some((i, z))
        })
        .collect()
}

/// Options of a fit.
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    pub beta: BetaChoice,
    /// Also fit `beta` = 1, 4/3 and 3/2 and report their figures of merit.
    pub compare_betas: bool,
    /// Relative tolerance of the model integration.
    pub rtol: f64,
    /// The standard error of the drag's scale, when it was fitted
    /// ([`fit_drag_scale`]) into the pendulum's air.
    pub drag_scale_se: Option<f64>,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            beta: BetaChoice::Fixed(1.0),
            compare_betas: false,
            rtol: 1e-7,
            drag_scale_se: None,
        }
    }
}

struct Core {
    s_r: f64,
    a0: f64,
    se: f64,
    rss: f64,
    residuals: Vec<f64>,
    iterations: usize,
    dof: usize,
}

/// Amplitude residuals `measured - model` of `(s_r, A)` for a fixed `beta`.
fn residuals(p: &Pendulum, m: &Measurement, beta: f64, rtol: f64, s_r: f64, a0: f64) -> Vec<f64> {
    let j_max = *m.index.last().expect("non-empty");
    let model = model_amplitudes(p, &FrictionLaw::new(s_r, beta), a0, j_max, rtol);
    m.index
        .iter()
        .zip(&m.amplitudes)
        .map(|(&j, &y)| y - model[j])
        .collect()
}

/// The model amplitudes' derivatives in `s_r` and `A` at `(s_r, a0)` (forward
/// differences, the steps [`fit`] uses), one column each: the linearisation behind the
/// interval's error model ([`crate::uncertainty`]).
pub fn jacobian(
    p: &Pendulum,
    m: &Measurement,
    beta: f64,
    s_r: f64,
    a0: f64,
    rtol: f64,
) -> [Vec<f64>; 2] {
    let r = residuals(p, m, beta, rtol, s_r, a0);
    // Derivatives of the model: minus those of the residuals.
    residual_jacobian(p, m, beta, rtol, s_r, a0, &r).map(|c| c.iter().map(|v| -v).collect())
}

/// The residuals' derivatives in `s_r` and `A` at `(s_r, a0)`, whose residuals are `r`:
/// forward differences (two integrations), one column each.
fn residual_jacobian(
    p: &Pendulum,
    m: &Measurement,
    beta: f64,
    rtol: f64,
    s_r: f64,
    a0: f64,
    r: &[f64],
) -> [Vec<f64>; 2] {
    let hs = 1e-3 * s_r.abs().max(1e-9);
    let ha = 1e-4 * a0.abs().max(1e-3);
    let rs = residuals(p, m, beta, rtol, s_r + hs, a0);
    let ra = residuals(p, m, beta, rtol, s_r, a0 + ha);
    [
        rs.iter().zip(r).map(|(b, a)| (b - a) / hs).collect(),
        ra.iter().zip(r).map(|(b, a)| (b - a) / ha).collect(),
    ]
}

/// `(s_r, A)` fitted again to the same turning points for another pendulum (the
/// uncertainty budget's sensitivity coefficients and Monte Carlo draws), started from
/// `start` (a nearby solution) with `beta` fixed.
pub fn refit(
    p: &Pendulum,
    m: &Measurement,
    beta: f64,
    start: [f64; 2],
    rtol: f64,
) -> Result<[f64; 2]> {
    let c = fit_core_from(p, m, beta, rtol, Some(start))?;
    Ok([c.s_r, c.a0])
}

/// Gauss–Newton with Levenberg damping on `(s_r, A)` for a fixed `beta`.
fn fit_core(p: &Pendulum, m: &Measurement, beta: f64, rtol: f64) -> Result<Core> {
    fit_core_from(p, m, beta, rtol, None)
}

/// [`fit_core`] from `start`, or (`None`) from the closed-form small-angle relation
/// between the envelope slope and `s_r` (ERRATA §2).
fn fit_core_from(
    p: &Pendulum,
    m: &Measurement,
    beta: f64,
    rtol: f64,
    start: Option<[f64; 2]>,
) -> Result<Core> {
    let n = m.amplitudes.len();
    let resid = |s_r: f64, a0: f64| -> Vec<f64> { residuals(p, m, beta, rtol, s_r, a0) };
    let ss = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    let (mut s_r, mut a0) = match start {
        Some([s, a]) => (s.max(1e-12), a),
        None => {
            let unit = FrictionLaw::new(1.0, beta);
            let per_unit = p.envelope_slope(&unit);
            (
                (m.envelope.slope.abs() / per_unit).max(1e-12),
                m.amplitudes[0],
            )
        }
    };
    let mut r = resid(s_r, a0);
    let mut rss = ss(&r);
    let mut lambda = 1e-6;
    let mut iterations = 0;
    let mut jac = [Vec::new(), Vec::new()];
    for it in 1..=60 {
        iterations = it;
        // Forward-difference Jacobian, computed at the start only (a chord iteration:
        // the amplitudes are nearly linear in s_r and A, so it converges in a few steps
        // at one integration each).
        if it == 1 {
            jac = residual_jacobian(p, m, beta, rtol, s_r, a0, &r);
        }
        let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
        let (j00, j01, j11) = (
            dot(&jac[0], &jac[0]),
            dot(&jac[0], &jac[1]),
            dot(&jac[1], &jac[1]),
        );
        let (g0, g1) = (dot(&jac[0], &r), dot(&jac[1], &r));
        let mut accepted = false;
        let mut converged = false;
        for _ in 0..8 {
            let (a, c) = (j00 * (1.0 + lambda), j11 * (1.0 + lambda));
            let det = a * c - j01 * j01;
            if det <= 0.0 || !det.is_finite() {
                lambda *= 10.0;
                continue;
            }
            let ds = -(c * g0 - j01 * g1) / det;
            let da = -(a * g1 - j01 * g0) / det;
            let s_new = (s_r + ds).max(0.0);
            let a_new = a0 + da;
            // Steps this small are below the integration's own noise.
            converged = (s_new - s_r).abs() <= 1e-7 * s_r.abs().max(1e-12)
                && da.abs() <= 1e-10 * a0.abs().max(1e-3);
            let r_new = resid(s_new, a_new);
            let rss_new = ss(&r_new);
            if rss_new <= rss * (1.0 + 1e-12) {
                converged |= rss - rss_new <= 1e-10 * rss;
                s_r = s_new;
                a0 = a_new;
                r = r_new;
                rss = rss_new;
                lambda = (lambda / 10.0).max(1e-12);
                accepted = true;
                break;
            }
            if converged {
                break;
            }
            lambda *= 10.0;
        }
        if !accepted || converged {
            break;
        }
    }
    let dof = n.saturating_sub(2).max(1);
    let sigma2 = rss / dof as f64;
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
    let (j00, j01, j11) = (
        dot(&jac[0], &jac[0]),
        dot(&jac[0], &jac[1]),
        dot(&jac[1], &jac[1]),
    );
    let det = j00 * j11 - j01 * j01;
    let var = if det > 0.0 {
        sigma2 * j11 / det
    } else {
        f64::INFINITY
    };
    Ok(Core {
        s_r,
        a0,
        se: var.sqrt(),
        rss,
        residuals: r,
        iterations,
        dof,
    })
}

fn aicc(rss: f64, n: usize, k: usize) -> f64 {
    let nf = n as f64;
    let kf = k as f64;
    let corr = if n > k + 1 {
        2.0 * kf * (kf + 1.0) / (nf - kf - 1.0)
    } else {
        f64::INFINITY
    };
    nf * (rss.max(1e-300) / nf).ln() + 2.0 * kf + corr
}

/// The longest span of turning points the model is integrated over, in small-angle
/// periods of the pendulum (an hour of a 0.7 s pendulum): the integration's steps are
/// bounded by this before it starts.
pub const MAX_MODEL_PERIODS: f64 = 5000.0;

/// Fit `s_r` (and optionally `beta`) to a measurement.
pub fn fit(p: &Pendulum, m: &Measurement, opts: &FitOptions) -> Result<FitResult> {
    let n = m.amplitudes.len();
    if n < MIN_EXTREMES {
        bail!("only {n} turning point(s); the fit needs at least {MIN_EXTREMES}");
    }
    let beta = match opts.beta {
        BetaChoice::Fixed(b) => b,
        BetaChoice::Free => {
            // Golden-section search of the profiled residual over beta.
            let f = |b: f64| fit_core(p, m, b, opts.rtol).map(|c| c.rss);
            golden_section_min(f, (0.5, 2.0), 1e-3)?
        }
    };
    let core = fit_core(p, m, beta, opts.rtol).context("fitting s_r")?;
    let k_params = if opts.beta == BetaChoice::Free { 3 } else { 2 };
    let mut beta_comparison = Vec::new();
    if opts.compare_betas || opts.beta == BetaChoice::Free {
        for b in [1.0, 4.0 / 3.0, 1.5] {
            let c = fit_core(p, m, b, opts.rtol)?;
            beta_comparison.push(BetaCandidate {
                beta: b,
                s_r: c.s_r,
                rss: c.rss,
                aicc: aicc(c.rss, n, 2),
            });
        }
        if opts.beta == BetaChoice::Free {
            beta_comparison.push(BetaCandidate {
                beta,
                s_r: core.s_r,
                rss: core.rss,
                aicc: aicc(core.rss, n, k_params),
            });
        }
    }
    let tq = student_t_quantile(0.975, core.dof as f64);
    let law = FrictionLaw::new(core.s_r, beta);
    let n0 = p.rest_normal_force();
    let t_first = m.extremes[0].t;
    let t_last = m.extremes.last().expect("non-empty").t;
    let period = p.small_angle_period();
    let span = t_last - t_first;
    if span.is_nan() || span > MAX_MODEL_PERIODS * period {
        bail!(
            "the turning points span {:.6e} s, over {MAX_MODEL_PERIODS} periods of the pendulum \
             ({period:.4} s for d = {:.4} m, r = {:.4} m): check `geometry.pendulum` and \
             `geometry.ball`, and the times' units",
            span,
            p.d,
            p.r
        );
    }
    let model = integrate(
        p,
        &law,
        t_first,
        [core.a0, 0.0],
        &OdeOptions {
            t_end: t_last,
            rtol: 1e-9,
            atol: 1e-10,
            ..OdeOptions::default()
        },
    );
    let reactions = reactions(&model, t_first, t_last);
    let (mt, ma): (Vec<f64>, Vec<f64>) = std::iter::once((t_first, core.a0))
        .chain(model.turns.iter().map(|tp| (tp.t, tp.psi.abs())))
        .unzip();
    let a_model = if mt.len() >= 2 {
        -linear_fit(&mt, &ma).slope
    } else {
        f64::NAN
    };
    let air = air::air_share(
        p,
        m,
        beta,
        opts.rtol,
        [core.s_r, core.a0],
        &model,
        opts.drag_scale_se,
    )?;
    let mean_amp = m.amplitudes.iter().sum::<f64>() / n as f64;
    // Finite-amplitude correction of the period (T = T_0 (1 + A^2/16 + ...)).
    let t0 = m.period_s / (1.0 + mean_amp * mean_amp / 16.0);
    Ok(FitResult {
        s_r_m: core.s_r,
        s_r_se_m: core.se,
        s_r_ci95_m: [core.s_r - tq * core.se, core.s_r + tq * core.se],
        s_r_u_m: f64::NAN,
        s_r_interval95_m: [f64::NAN; 2],
        beta,
        a_start_rad: core.a0,
        mu_r: core.s_r * n0.powf(beta - 1.0) / p.r,
        a_rad_s: -m.envelope.slope,
        a_model_rad_s: a_model,
        psi_eq_rad: m.equilibrium.envelope,
        psi_eq_paper_rad: m.equilibrium.paper,
        n_extremes: n,
        period_s: m.period_s,
        d_from_period_m: p.d_from_period(t0),
        max_t_over_n: reactions.max_t_over_n,
        reactions,
        residual_rms_rad: (core.rss / n as f64).sqrt(),
        residuals_rad: core.residuals,
        iterations: core.iterations,
        beta_comparison,
        release: m.release,
        stop: m.stop,
        outliers: Vec::new(),
        air,
    })
}

/// [`fit`], robust to outlying turning points: while a residual is an outlier (more than
/// [`OUTLIER_ROBUST_Z`] robust standard deviations from the residuals' median and more
/// than [`OUTLIER_NOISE_FACTOR`] times the noise floor of its amplitude), the worst one
/// is dropped and the fit redone, up to [`outlier_cap`] of them. Returns the measurement
/// that was fitted (without the dropped turning points) and the fit, whose `outliers`
/// name every one found: those dropped and those beyond the cap, kept. With none found,
/// this is exactly [`fit`].
pub fn fit_robust(
    p: &Pendulum,
    m: &Measurement,
    opts: &FitOptions,
    frame_noise_rad: f64,
) -> Result<(Measurement, FitResult)> {
    let cap = outlier_cap(m.amplitudes.len());
    let mut cur = m.clone();
    let mut f = fit(p, &cur, opts)?;
    let mut outliers = Vec::new();
    let outlier = |m: &Measurement, f: &FitResult, (k, z): (usize, f64), dropped: bool| Outlier {
        t_s: m.extremes[k].t,
        angle_rad: m.extremes[k].angle,
        amplitude_rad: m.amplitudes[k],
        residual_rad: f.residuals_rad[k],
        robust_z: z,
        dropped,
    };
    loop {
        let samples: Vec<usize> = cur.extremes.iter().map(|e| e.samples).collect();
        let found = outlying(&f.residuals_rad, &samples, frame_noise_rad);
        let Some(&worst) = found.iter().max_by(|a, b| a.1.total_cmp(&b.1)) else {
            break;
        };
        let dropped = outliers.len() < cap;
        let refit = if dropped {
            cur.without(worst.0)
                .and_then(|m2| fit(p, &m2, opts).map(|f2| (m2, f2)))
                .ok()
        } else {
            None
        };
        let Some((m2, f2)) = refit else {
            // Beyond the cap (or the fit cannot do without it): named, kept.
            outliers.extend(found.iter().map(|&o| outlier(&cur, &f, o, false)));
            break;
        };
        outliers.push(outlier(&cur, &f, worst, true));
        (cur, f) = (m2, f2);
    }
    outliers.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    f.outliers = outliers;
    Ok((cur, f))
}

#[cfg(test)]
mod tests;
