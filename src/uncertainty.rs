//! The uncertainty of `s_r`: the angles' share (their statistics and the detector's
//! systematic behaviour), and the uncertainty budget that adds the geometry's inputs
//! (GUM, JCGM 100:2008) with its Monte Carlo check (JCGM 101:2008).
//!
//! **The angles' share** ([`angle_uncertainty`]) is what the video measures, the geometry
//! taken as exact:
//!
//! - *statistical*, from the turning points' residuals by a circular block bootstrap over
//!   half swings ([`BLOCK_BOOTSTRAP_DRAWS`] draws, blocks of `ceil(n^(1/3))` turning
//!   points, residuals rescaled for the two fitted parameters), each draw solved on the
//!   fit's linearisation. Blocks keep the correlation between neighbouring extremes that
//!   the least-squares interval (which treats them as independent) leaves out; the larger
//!   of the two is kept;
//! - *drift*: the turning points split into their earlier and later halves, each fitted
//!   (linearised) alone. A detector error that grows or shrinks with the amplitude bends
//!   the envelope, and the halves then disagree; half their difference is the drift
//!   component (it also holds some of the statistics again, which errs on the safe
//!   side);
//! - *scale*: a detector that measures every swing a little too large or too small scales
//!   `s_r` by the same factor, and no residual shows it. Its relative standard
//!   uncertainty is [`DETECTOR_SCALE_REL`] (the detector's validation on randomised twins),
//!   combined with the swing scale's own departure from 1 when the video's pivot check
//!   measured one (read as the half-width of a rectangular distribution).
//!
//! They combine in quadrature into `s_r_u_m`, with Welch–Satterthwaite degrees of freedom
//! (the statistical part has `n - 2`, the others are Type B with infinitely many), and
//! `s_r_interval95_m = s_r +- k u` with `k` Student's 97.5 % quantile.
//!
//! **The budget** ([`budget`]) adds every geometry input (`h`, `l` or `alpha`, `d` or
//! `L`, `r`, `m` or `rho`, `g`) with its standard uncertainty (given, or the default of
//! its instrument's resolution, [`crate::config::InputUncertainty`]). Each sensitivity
//! coefficient `c_i = ds_r/dx_i` is a central difference of two re-fits of the same
//! turning points with `x_i +- u_i` (the model integrated again: no small-angle formula).
//! Contributions `|c_i| u_i`, combined `u_c`, effective degrees of freedom, coverage
//! factor `k` and expanded uncertainty `U = k u_c` follow JCGM 100 §5–6 and Annex G.
//!
//! **The Monte Carlo check** ([`monte_carlo`]) draws every input from its distribution
//! (rectangular for the defaults, normal for given values; the angles' statistical part
//! Student's t, its scale and drift normal), re-fits `s_r` for each draw, and compares
//! the distribution's standard deviation and 95 % probabilistically symmetric interval
//! with the budget's (JCGM 101 §8).

use crate::config::Experiment;
use crate::fit::{self, FitResult, Measurement};
use crate::physics::Pendulum;
use crate::rng::Rng;
use crate::stats::student_t_quantile;
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

mod groups;
mod inputs;
mod monte_carlo;

pub use groups::{group, Group, Run};
use inputs::{inputs, pendulum_with, Setting};
pub use monte_carlo::{monte_carlo, Histogram, MonteCarlo, HISTOGRAM_BINS};

/// Draws of the block bootstrap of the angles' statistical uncertainty.
pub const BLOCK_BOOTSTRAP_DRAWS: usize = 2000;

/// Relative standard uncertainty of the detector's angle scale: how much larger or
/// smaller than the truth it measures every swing of a video. A Type B value from the
/// detector's validation: the smallest that lets the 95 % interval hold the truth in
/// at least 90 % of the randomised robustness sweep's twins (`make coverage`, seed 1;
/// docs/uncertainty.md gives the figures). Its main source is a pivot
/// found a pixel or two off along the wire, which scales every swing alike and which
/// no residual shows.
pub const DETECTOR_SCALE_REL: f64 = 0.0013;

/// Relative tolerance of the budget's re-fits (the fit's own).
const RTOL: f64 = 1e-7;

/// The angles' share of the uncertainty of `s_r` (the geometry taken as exact).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct AngleUncertainty {
    /// Statistical standard uncertainty (block bootstrap, or the least-squares one when
    /// larger), m.
    pub u_stat_m: f64,
    /// Its degrees of freedom (`n - 2`).
    pub dof_stat: f64,
    /// The block length of the bootstrap, turning points.
    pub block: usize,
    /// Drift between the earlier and later turning points, m.
    pub u_drift_m: f64,
    /// The `s_r` of the earlier and of the later half of the turning points, each
    /// fitted alone (on the fit's linearisation), m; `None` with fewer than six.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub halves_m: Option<[f64; 2]>,
    /// The detector's angle scale: relative standard uncertainty, and in m.
    pub scale_rel: f64,
    pub u_scale_m: f64,
    /// Combined standard uncertainty, m.
    pub u_m: f64,
    /// Effective degrees of freedom (`None`: infinitely many).
    pub dof: Option<f64>,
    /// Coverage factor for 95 %.
    pub k: f64,
    /// `s_r +- k u`, m.
    pub interval95_m: [f64; 2],
}

/// The least-squares solution of the linearised model for residuals `r`: the change of
/// `(s_r, A)`.
fn solve(j: &[Vec<f64>; 2], r: &[f64], rows: impl Iterator<Item = usize> + Clone) -> [f64; 2] {
    let (mut a, mut b, mut c, mut g0, mut g1) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in rows {
        a += j[0][i] * j[0][i];
        b += j[0][i] * j[1][i];
        c += j[1][i] * j[1][i];
        g0 += j[0][i] * r[i];
        g1 += j[1][i] * r[i];
    }
    let det = a * c - b * b;
    if det.abs() <= f64::MIN_POSITIVE {
        return [f64::NAN, f64::NAN];
    }
    [(c * g0 - b * g1) / det, (a * g1 - b * g0) / det]
}

fn sd(v: &[f64]) -> f64 {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt()
}

/// The coverage factor for 95 % at `dof` degrees of freedom (`None`: the normal one).
pub fn coverage_factor(dof: Option<f64>) -> f64 {
    match dof {
        Some(nu) if nu.is_finite() => student_t_quantile(0.975, nu.max(1.0)),
        _ => 1.959_963_984_540_054,
    }
}

/// Welch–Satterthwaite (JCGM 100 G.4.1): effective degrees of freedom of a combined
/// `u_c` from contributions `(u_i, nu_i)` (`None`: infinitely many).
pub fn welch_satterthwaite(u_c: f64, parts: &[(f64, Option<f64>)]) -> Option<f64> {
    let s: f64 = parts
        .iter()
        .filter_map(|&(u, nu)| nu.map(|nu| u.powi(4) / nu))
        .sum();
    (s > 0.0).then(|| u_c.powi(4) / s)
}

/// The angles' share of the uncertainty of the fitted `s_r` of `m` ([`fit::fit`]'s
/// result `f`), with the detector's swing scale when the angles come from a video.
pub fn angle_uncertainty(
    p: &Pendulum,
    m: &Measurement,
    f: &FitResult,
    swing_scale: Option<f64>,
) -> AngleUncertainty {
    let n = m.amplitudes.len();
    let j = fit::jacobian(p, m, f.beta, f.s_r_m, f.a_start_rad, RTOL);
    let r = &f.residuals_rad;
    // Residuals of a two-parameter fit are smaller than the errors behind them.
    let inflate = (n as f64 / (n as f64 - 2.0).max(1.0)).sqrt();
    let block = ((n as f64).cbrt().ceil() as usize).clamp(1, n);
    let mut rng = Rng::new(0x5EED_B10C);
    let mut draws = Vec::with_capacity(BLOCK_BOOTSTRAP_DRAWS);
    let mut rs = vec![0.0; n];
    for _ in 0..BLOCK_BOOTSTRAP_DRAWS {
        let mut i = 0;
        while i < n {
            let start = ((rng.uniform() * n as f64) as usize).min(n - 1);
            for k in 0..block {
                if i + k >= n {
                    break;
                }
                rs[i + k] = inflate * r[(start + k) % n];
            }
            i += block;
        }
        draws.push(solve(&j, &rs, 0..n)[0]);
    }
    let u_boot = sd(&draws);
    let u_stat = if u_boot.is_finite() {
        u_boot.max(f.s_r_se_m)
    } else {
        f.s_r_se_m
    };
    let dof_stat = (n as f64 - 2.0).max(1.0);
    // Drift: the earlier and the later half fitted alone, on the same linearisation.
    let half = n / 2;
    // Their changes of s_r from the whole fit's.
    let moves = (half >= 3)
        .then(|| [solve(&j, r, 0..half)[0], solve(&j, r, half..n)[0]])
        .filter(|h| (h[0] - h[1]).is_finite());
    // Half their difference, whole: subtracting what statistics alone would give
    // covered fewer of the validation twins (see DETECTOR_SCALE_REL).
    let u_drift = moves.map_or(0.0, |[early, late]| (early - late).abs() / 2.0);
    let halves = moves.map(|m| m.map(|d| f.s_r_m + d));
    let scale_rel = match swing_scale {
        Some(s) if s.is_finite() => (DETECTOR_SCALE_REL.powi(2) + (s - 1.0).powi(2) / 3.0).sqrt(),
        _ => DETECTOR_SCALE_REL,
    };
    let u_scale = scale_rel * f.s_r_m.abs();
    let u = (u_stat.powi(2) + u_drift.powi(2) + u_scale.powi(2)).sqrt();
    let dof = welch_satterthwaite(
        u,
        &[(u_stat, Some(dof_stat)), (u_drift, None), (u_scale, None)],
    );
    let k = coverage_factor(dof);
    AngleUncertainty {
        u_stat_m: u_stat,
        dof_stat,
        block,
        u_drift_m: u_drift,
        halves_m: halves,
        scale_rel,
        u_scale_m: u_scale,
        u_m: u,
        dof,
        k,
        interval95_m: [f.s_r_m - k * u, f.s_r_m + k * u],
    }
}

/// How an input's value is distributed about its estimate.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Distribution {
    /// Half-width `sqrt(3) u` (an instrument's resolution).
    Rectangular,
    Normal,
    /// Student's t with the component's degrees of freedom.
    Student,
}

/// One line of the budget.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Component {
    /// The quantity's symbol, e.g. `d`.
    pub quantity: String,
    /// Where its value comes from: the experiment file's key, `angles`, or
    /// `video.calibration` or `video.lens` (the plate calibration's or the lens's
    /// share).
    pub key: String,
    /// Its estimate, in `unit` (`s_r` itself for the angles' parts).
    pub value: f64,
    pub unit: String,
    /// Standard uncertainty, in `unit`.
    pub u: f64,
    pub distribution: Distribution,
    /// Why this `u`: given, or the default's instrument.
    pub source: String,
    /// Sensitivity coefficient `ds_r/dx`, m per `unit`.
    pub sensitivity: f64,
    /// `|c| u`, m.
    pub contribution_m: f64,
    /// Degrees of freedom (`None`: infinitely many).
    pub dof: Option<f64>,
}

impl Component {
    /// A part that adds to `s_r` itself (the angles' parts, the plate calibration),
    /// rather than an input of the geometry or of the air with a sensitivity
    /// coefficient.
    pub fn adds_to_s_r(&self) -> bool {
        !self.key.starts_with("geometry.") && !self.key.starts_with("air.")
    }
}

/// The uncertainty budget of `s_r` (JCGM 100).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Budget {
    pub s_r_m: f64,
    /// The angles' share, as `s_r_u_m` and `s_r_interval95_m` report it.
    pub angles: AngleUncertainty,
    pub components: Vec<Component>,
    /// Combined standard uncertainty `u_c`, m.
    pub u_c_m: f64,
    /// Effective degrees of freedom (`None`: infinitely many).
    pub nu_eff: Option<f64>,
    /// Coverage factor for 95 %.
    pub k: f64,
    /// Expanded uncertainty `U = k u_c`, m.
    pub expanded_m: f64,
    /// `s_r +- U`, m.
    pub interval95_m: [f64; 2],
}

/// The uncertainty budget of the fitted `s_r` (result `f` of the turning points `m`),
/// with the angles' share `a`.
pub fn budget(
    exp: &Experiment,
    m: &Measurement,
    f: &FitResult,
    a: AngleUncertainty,
    calibration: Option<&PlaneScale>,
    lens: Option<&LensScale>,
) -> Result<Budget> {
    let start = [f.s_r_m, f.a_start_rad];
    let mut components = Vec::new();
    let base = Setting::of(exp, f);
    for i in inputs(exp, f) {
        let (u, distribution, source) = match i.given {
            Some(u) => (u, Distribution::Normal, "given".to_string()),
            None => (
                i.default_u,
                Distribution::Rectangular,
                format!("default: {}", i.default_why),
            ),
        };
        if i.ratio && u >= i.value.abs() {
            bail!(
                "`{}` = {} {unit}: its standard uncertainty ({:.3e} {unit}, {source}) is as \
                 large as the value itself; check the value's units, or give its uncertainty",
                i.key,
                crate::config::shown(i.value),
                u,
                unit = i.unit
            );
        }
        let sensitivity = if u > 0.0 {
            let s_at = |x: f64| -> Result<f64> {
                let p = pendulum_with(&base, &i, x, u)?;
                Ok(fit::refit(&p, m, f.beta, start, RTOL)
                    .with_context(|| format!("re-fitting with `{}` = {x}", i.key))?[0])
            };
            (s_at(i.value + u)? - s_at(i.value - u)?) / (2.0 * u)
        } else {
            0.0
        };
        components.push(Component {
            quantity: i.quantity.to_string(),
            key: i.key.to_string(),
            value: i.value,
            unit: i.unit.to_string(),
            u,
            distribution,
            source,
            sensitivity,
            contribution_m: (sensitivity * u).abs(),
            dof: None,
        });
    }
    let angles = |quantity: &str, u: f64, distribution, source: &str, dof| Component {
        quantity: quantity.to_string(),
        key: "angles".to_string(),
        value: f.s_r_m,
        unit: "m".to_string(),
        u,
        distribution,
        source: source.to_string(),
        sensitivity: 1.0,
        contribution_m: u,
        dof,
    };
    components.push(angles(
        "s_r (statistics)",
        a.u_stat_m,
        Distribution::Student,
        &format!(
            "block bootstrap of the turning points' residuals (blocks of {})",
            a.block
        ),
        Some(a.dof_stat),
    ));
    components.push(angles(
        "s_r (drift)",
        a.u_drift_m,
        Distribution::Normal,
        "the earlier and later turning points fitted apart",
        None,
    ));
    components.push(angles(
        "s_r (detector scale)",
        a.u_scale_m,
        Distribution::Normal,
        &format!(
            "the detector's angle scale, {:.2} % (validated on randomised twins)",
            100.0 * a.scale_rel
        ),
        None,
    ));
    if let Some(c) = calibration {
        let u = c.u_rel * f.s_r_m.abs();
        components.push(Component {
            quantity: "s_r (plate calibration)".to_string(),
            key: "video.calibration".to_string(),
            value: f.s_r_m,
            unit: "m".to_string(),
            u,
            distribution: if c.dof.is_some() {
                Distribution::Student
            } else {
                Distribution::Normal
            },
            source: format!(
                "the swing's scale through the homography of {} points, each to {:.2} px ({}): {:.3} %",
                c.points,
                c.point_u_px,
                c.point_u_why,
                100.0 * c.u_rel
            ),
            sensitivity: 1.0,
            contribution_m: u,
            dof: c.dof,
        });
    }
    if let Some(l) = lens {
        let u = l.u_rel * f.s_r_m.abs();
        components.push(Component {
            quantity: "s_r (lens distortion)".to_string(),
            key: "video.lens".to_string(),
            value: f.s_r_m,
            unit: "m".to_string(),
            u,
            distribution: Distribution::Normal,
            source: format!(
                "the swing's scale through the lens, k1 = {} +- {}: {:.3} %",
                l.k1,
                l.u_k1,
                100.0 * l.u_rel
            ),
            sensitivity: 1.0,
            contribution_m: u,
            dof: None,
        });
    }
    let u_c = components
        .iter()
        .map(|c| c.contribution_m.powi(2))
        .sum::<f64>()
        .sqrt();
    let parts: Vec<(f64, Option<f64>)> = components
        .iter()
        .map(|c| (c.contribution_m, c.dof))
        .collect();
    let nu_eff = welch_satterthwaite(u_c, &parts);
    let k = coverage_factor(nu_eff);
    Ok(Budget {
        s_r_m: f.s_r_m,
        angles: a,
        components,
        u_c_m: u_c,
        nu_eff,
        k,
        expanded_m: k * u_c,
        interval95_m: [f.s_r_m - k * u_c, f.s_r_m + k * u_c],
    })
}

/// What a plate calibration adds to the budget: the relative standard uncertainty of
/// the swing's scale ([`crate::plane::Calibration::scale_u_rel`]), which `s_r` follows.
#[derive(Clone, Debug, PartialEq)]
pub struct PlaneScale {
    pub u_rel: f64,
    pub points: usize,
    pub point_u_px: f64,
    /// Where the points' uncertainty comes from, in words.
    pub point_u_why: &'static str,
    /// Degrees of freedom (`2 n - 8` when the residual estimated the points'
    /// uncertainty; `None`: a given or default value).
    pub dof: Option<f64>,
}

impl PlaneScale {
    /// The scale uncertainty of `c` for a wire through the image point `pivot` swinging
    /// `amp` about the plate angle `rest` (rad).
    pub fn of(c: &crate::plane::Calibration, pivot: [f64; 2], rest: f64, amp: f64) -> Self {
        Self {
            u_rel: c.scale_u_rel(pivot, rest, amp),
            points: c.image.len(),
            point_u_px: c.point_u_px,
            point_u_why: c.point_u_source.describe(),
            dof: (c.point_u_source == crate::plane::PointUSource::Residual).then_some(c.dof as f64),
        }
    }
}

/// What a lens's distortion (`video.lens`) adds to the budget: the relative standard
/// uncertainty `u_k1` puts on the swing's scale ([`crate::lens::Lens::scale_u_rel`]),
/// which `s_r` follows.
#[derive(Clone, Debug, PartialEq)]
pub struct LensScale {
    pub u_rel: f64,
    pub k1: f64,
    pub u_k1: f64,
}

impl LensScale {
    /// The scale uncertainty of `l` for a wire through the image point `pivot`, seen
    /// over the radii `band` (px), swinging `amp` about the image angle `rest` (rad).
    pub fn of(l: &crate::lens::Lens, pivot: [f64; 2], band: [f64; 2], rest: f64, amp: f64) -> Self {
        Self {
            u_rel: l.scale_u_rel(pivot, rest, amp, band),
            k1: l.k1,
            u_k1: l.u_k1,
        }
    }
}

#[cfg(test)]
mod tests;
