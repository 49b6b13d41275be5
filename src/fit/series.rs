//! The exponent `beta` of `M_r = s_r N^beta` (Eq. 28) from runs of one material pair at
//! several normal forces.
//!
//! Within one run the normal force varies by a few hundredths of a percent (Eq. 30), so
//! one run cannot tell `beta` from `s_r`: it measures the rolling-resistance torque at
//! its own normal force, `M_i = s_i N_i^beta_i` (its fitted `s_r` in its own law, at the
//! mean normal force `N_i` along the fitted motion). Runs at different normal forces
//! (other balls, other inclines) place these torques on the line
//! `ln M = ln s_r + beta ln N`, fitted by weighted least squares (weights `1 / u(ln M)^2`
//! from each run's combined standard uncertainty) for `s_r` and `beta` with their
//! covariance.
//!
//! The scatter about the line is judged as repeat runs are: `chi^2` and the Birge ratio
//! `R = sqrt(chi^2 / (n - 2))`. When `R > 1` the covariance is scaled by `R^2` and the
//! 95 % interval takes Student's `t` with `n - 2` degrees of freedom; otherwise the runs'
//! own uncertainties stand (coverage factor 1.96).

use crate::stats::student_t_quantile;
use serde::{Deserialize, Serialize};

/// One run of a series: its name, the mean normal force along its fitted motion, and the
/// rolling-resistance torque it measured there with its standard uncertainty.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SeriesRun {
    pub name: String,
    pub normal_force_n: f64,
    pub torque_nm: f64,
    pub u_torque_nm: f64,
}

impl SeriesRun {
    /// A run whose fit gave `s_r` (with standard uncertainty `u_s_r`) for the exponent
    /// `beta` at the mean normal force `n`.
    pub fn of(name: &str, s_r: f64, u_s_r: f64, beta: f64, n: f64) -> Self {
        let k = n.powf(beta);
        Self {
            name: name.to_string(),
            normal_force_n: n,
            torque_nm: s_r * k,
            u_torque_nm: u_s_r * k,
        }
    }
}

/// How one of the usual exponents fares against the series.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BetaTrial {
    pub beta: f64,
    /// `chi^2` of the runs about the best line of this slope.
    pub chi2: f64,
    /// Within the 95 % interval of the fitted `beta`.
    pub inside: bool,
}

/// `beta` and `s_r` fitted to a series of runs at several normal forces.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BetaSeries {
    /// The pair's name (the runs' `pair` key).
    pub pair: String,
    pub runs: Vec<SeriesRun>,
    pub beta: f64,
    /// Standard uncertainty of `beta` (scaled by the Birge ratio when it exceeds 1).
    pub u_beta: f64,
    pub beta_interval95: [f64; 2],
    /// `s_r` of the fitted law, m·N^(1-beta), and its standard uncertainty.
    pub s_r: f64,
    pub u_s_r: f64,
    /// Correlation between `ln s_r` and `beta`.
    pub correlation: f64,
    /// The torque's line at the runs' weighted mean `ln N`: `ln M = c + beta (ln N - x0)`.
    pub ln_n0: f64,
    pub ln_m0: f64,
    pub chi2: f64,
    /// `sqrt(chi^2 / (n - 2))` (`None` with two runs).
    pub birge_ratio: Option<f64>,
    /// `1 + 2 sqrt(2 / (n - 2))`, the limit the repeat runs use (two standard
    /// deviations of `R^2` for consistent runs, taken for `R`: lenient).
    pub birge_limit: Option<f64>,
    pub consistent: bool,
    /// The coverage factor of the interval.
    pub k: f64,
    /// `100 (N_max / N_min - 1)`: how far the normal forces reach, %.
    pub n_span_pct: f64,
    pub trials: Vec<BetaTrial>,
    /// One line: which law the data favour.
    pub verdict: String,
}

/// The usual exponents the verdict weighs: Coulomb-like (1), Hertzian hysteresis
/// (4/3), and 3/2.
pub const BETA_TRIALS: [f64; 3] = [1.0, 4.0 / 3.0, 1.5];

/// An exponent as the paper writes it: `1`, `4/3`, `3/2`, or its value to 3 decimals.
pub fn beta_name(b: f64) -> String {
    for (v, n) in [(1.0, "1"), (4.0 / 3.0, "4/3"), (1.5, "3/2")] {
        if (b - v).abs() < 1e-9 {
            return n.to_string();
        }
    }
    format!("{b:.3}")
}

/// Weighted least squares of `y = c + b (x - x0)`: `(x0, c, b, var_c, var_b, chi2)`
/// (`c` and `b` are uncorrelated about the weighted mean `x0`).
fn weighted_line(x: &[f64], y: &[f64], w: &[f64]) -> (f64, f64, f64, f64, f64, f64) {
    let sw: f64 = w.iter().sum();
    let x0 = x.iter().zip(w).map(|(x, w)| x * w).sum::<f64>() / sw;
    let y0 = y.iter().zip(w).map(|(y, w)| y * w).sum::<f64>() / sw;
    let sxx: f64 = x.iter().zip(w).map(|(x, w)| w * (x - x0).powi(2)).sum();
    let sxy: f64 = x
        .iter()
        .zip(y)
        .zip(w)
        .map(|((x, y), w)| w * (x - x0) * (y - y0))
        .sum();
    let b = sxy / sxx;
    let chi2 = x
        .iter()
        .zip(y)
        .zip(w)
        .map(|((x, y), w)| w * (y - y0 - b * (x - x0)).powi(2))
        .sum();
    (x0, y0, b, 1.0 / sw, 1.0 / sxx, chi2)
}

/// `chi^2` of the best line of slope `b` (its intercept fitted).
fn chi2_at_slope(x: &[f64], y: &[f64], w: &[f64], b: f64) -> f64 {
    let sw: f64 = w.iter().sum();
    let c = x
        .iter()
        .zip(y)
        .zip(w)
        .map(|((x, y), w)| w * (y - b * x))
        .sum::<f64>()
        / sw;
    x.iter()
        .zip(y)
        .zip(w)
        .map(|((x, y), w)| w * (y - c - b * x).powi(2))
        .sum()
}

/// Fit `beta` and `s_r` to the runs of the pair `pair`. `None` unless there are two
/// runs or more, each with a positive torque and uncertainty, at normal forces that
/// differ.
pub fn beta_series(pair: &str, runs: Vec<SeriesRun>) -> Option<BetaSeries> {
    let ok = |r: &SeriesRun| {
        r.torque_nm > 0.0
            && r.u_torque_nm > 0.0
            && r.normal_force_n > 0.0
            && r.torque_nm.is_finite()
            && r.u_torque_nm.is_finite()
    };
    if runs.len() < 2 || !runs.iter().all(ok) {
        return None;
    }
    let x: Vec<f64> = runs.iter().map(|r| r.normal_force_n.ln()).collect();
    let y: Vec<f64> = runs.iter().map(|r| r.torque_nm.ln()).collect();
    let w: Vec<f64> = runs
        .iter()
        .map(|r| (r.torque_nm / r.u_torque_nm).powi(2))
        .collect();
    let n_min = runs
        .iter()
        .map(|r| r.normal_force_n)
        .fold(f64::INFINITY, f64::min);
    let n_max = runs.iter().map(|r| r.normal_force_n).fold(0.0, f64::max);
    if n_max <= n_min * (1.0 + 1e-9) {
        return None;
    }
    let (x0, c, b, var_c, var_b, chi2) = weighted_line(&x, &y, &w);
    let dof = runs.len() - 2;
    let (birge, limit) = if dof > 0 {
        (
            Some((chi2 / dof as f64).sqrt()),
            Some(1.0 + 2.0 * (2.0 / dof as f64).sqrt()),
        )
    } else {
        (None, None)
    };
    let scale = birge.map_or(1.0, |r| r.max(1.0));
    let k = match birge {
        Some(r) if r > 1.0 => student_t_quantile(0.975, dof as f64),
        _ => 1.959_963_984_540_054,
    };
    let u_beta = var_b.sqrt() * scale;
    let half = k * u_beta;
    // ln s_r = c - b x0: var = var_c + x0^2 var_b (c and b uncorrelated about x0).
    let ln_s = c - b * x0;
    let var_ln_s = (var_c + x0 * x0 * var_b) * scale * scale;
    let cov = -x0 * var_b * scale * scale;
    let s_r = ln_s.exp();
    let trials: Vec<BetaTrial> = BETA_TRIALS
        .iter()
        .map(|&bt| BetaTrial {
            beta: bt,
            chi2: chi2_at_slope(&x, &y, &w, bt),
            inside: (bt - b).abs() <= half,
        })
        .collect();
    let consistent = match (birge, limit) {
        (Some(r), Some(l)) => r <= l,
        _ => true,
    };
    let n_span_pct = 100.0 * (n_max / n_min - 1.0);
    let name = |b: f64| beta_name(b);
    let inside: Vec<String> = trials
        .iter()
        .filter(|t| t.inside)
        .map(|t| name(t.beta))
        .collect();
    let outside: Vec<String> = trials
        .iter()
        .filter(|t| !t.inside)
        .map(|t| name(t.beta))
        .collect();
    let verdict = match inside.len() {
        0 => format!(
            "none of beta = {}: beta = {b:.3} +- {half:.3} (95 %)",
            outside.join(", ")
        ),
        1 => format!(
            "the data favour beta = {} ({} outside the 95 % interval {:.3} .. {:.3})",
            inside[0],
            outside.join(" and "),
            b - half,
            b + half
        ),
        _ => format!(
            "the data cannot tell beta = {} apart: the normal forces span {n_span_pct:.1} %, \
             the 95 % interval is {:.3} .. {:.3}",
            inside.join(" and "),
            b - half,
            b + half
        ),
    };
    Some(BetaSeries {
        pair: pair.to_string(),
        runs,
        beta: b,
        u_beta,
        beta_interval95: [b - half, b + half],
        s_r,
        u_s_r: s_r * var_ln_s.sqrt(),
        correlation: cov / (var_ln_s.sqrt() * u_beta),
        ln_n0: x0,
        ln_m0: c,
        chi2,
        birge_ratio: birge,
        birge_limit: limit,
        consistent,
        k,
        n_span_pct,
        trials,
        verdict,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(n: f64, m: f64, u_rel: f64) -> SeriesRun {
        SeriesRun {
            name: format!("N{n}"),
            normal_force_n: n,
            torque_nm: m,
            u_torque_nm: u_rel * m,
        }
    }

    #[test]
    fn an_exact_power_law_gives_its_exponent_and_coefficient() {
        // M = 2e-6 N^(4/3) at 2.5, 5, 10 and 20 N, each to 0.5 %.
        let law = |n: f64| 2e-6 * n.powf(4.0 / 3.0);
        let runs: Vec<_> = [2.5, 5.0, 10.0, 20.0]
            .iter()
            .map(|&n| run(n, law(n), 0.005))
            .collect();
        let s = beta_series("glass", runs).unwrap();
        assert!((s.beta - 4.0 / 3.0).abs() < 1e-12, "{}", s.beta);
        assert!((s.s_r / 2e-6 - 1.0).abs() < 1e-12);
        assert!(s.chi2 < 1e-20);
        // Equal weights: var(b) = u^2 / sum (x - x0)^2, x = ln N evenly spaced by ln 2.
        let sxx = (2f64.ln()).powi(2) * (2.25 + 0.25 + 0.25 + 2.25);
        assert!(
            (s.u_beta - 0.005 / sxx.sqrt()).abs() < 1e-12,
            "{}",
            s.u_beta
        );
        assert_eq!(s.k, 1.959_963_984_540_054);
        assert!(
            s.verdict.starts_with("the data favour beta = 4/3"),
            "{}",
            s.verdict
        );
        assert!((s.n_span_pct - 700.0).abs() < 1e-9);
        assert!(s.consistent);
    }

    #[test]
    fn runs_that_scatter_widen_the_interval_by_the_birge_ratio() {
        // Alternating 3 % errors against 0.5 % uncertainties.
        let runs: Vec<_> = [2.5, 5.0, 10.0, 20.0, 40.0]
            .iter()
            .enumerate()
            .map(|(i, &n)| run(n, 1e-6 * n * if i % 2 == 0 { 1.03 } else { 0.97 }, 0.005))
            .collect();
        let s = beta_series("pair", runs).unwrap();
        let r = s.birge_ratio.unwrap();
        assert!(r > 4.0, "{r}");
        assert!(!s.consistent);
        assert_eq!(s.k, student_t_quantile(0.975, 3.0));
        let unscaled = s.u_beta / r;
        assert!(s.beta_interval95[1] - s.beta > 3.0 * 1.96 * unscaled);
    }

    #[test]
    fn forces_too_close_cannot_tell_the_laws_apart() {
        // Four inclines of 3 to 12 deg change N by under 1 %.
        let runs: Vec<_> = [10.30, 10.33, 10.36, 10.39]
            .iter()
            .map(|&n: &f64| run(n, 3.7e-6 * n, 0.004))
            .collect();
        let s = beta_series("glass", runs).unwrap();
        assert!(s.u_beta > 0.3, "{}", s.u_beta);
        assert!(s.verdict.contains("cannot tell"), "{}", s.verdict);
        assert!(s.trials.iter().all(|t| t.inside));
    }

    #[test]
    fn a_single_force_or_a_zero_torque_is_no_series() {
        assert!(beta_series("a", vec![run(10.0, 1e-5, 0.01)]).is_none());
        assert!(beta_series("a", vec![run(10.0, 1e-5, 0.01), run(10.0, 1.1e-5, 0.01)]).is_none());
        assert!(beta_series("a", vec![run(5.0, 0.0, 0.01), run(10.0, 1e-5, 0.01)]).is_none());
    }
}
