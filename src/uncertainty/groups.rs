//! Repeat runs: the experiments of a manifest that name the same `material`, their
//! mean with its uncertainty, their spread and the Birge ratio of the spread against
//! the runs' own uncertainties.

use super::{coverage_factor, sd, welch_satterthwaite};
use serde::{Deserialize, Serialize};

/// One run of a group: an experiment's `s_r`, its angles' standard uncertainty (what
/// differs from run to run) and its budget's combined one.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Run {
    pub name: String,
    pub d_m: f64,
    pub s_r_m: f64,
    pub u_angles_m: f64,
    pub u_c_m: f64,
}

/// Repeat runs of one material (the experiments of a manifest that name the same
/// `material`): their mean and spread, and whether the spread agrees with the runs'
/// own uncertainties.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Group {
    pub material: String,
    pub runs: Vec<Run>,
    /// Arithmetic mean, m.
    pub mean_m: f64,
    /// Standard deviation of the runs, m.
    pub sd_m: f64,
    /// Standard uncertainty of the mean from the spread, `sd / sqrt(n)` (Type A, `n - 1`
    /// degrees of freedom), m.
    pub u_mean_m: f64,
    /// The runs' geometry share (the RMS over runs of `sqrt(u_c^2 - u_angles^2)`): the
    /// rig's rulers and balance, not averaged away by repeating, m.
    pub u_geometry_m: f64,
    /// Combined standard uncertainty of the mean, `sqrt(u_mean^2 + u_geometry^2)`, m.
    pub u_c_m: f64,
    pub nu_eff: Option<f64>,
    pub k: f64,
    /// Expanded uncertainty of the mean (95 %), m.
    pub expanded_m: f64,
    /// `chi^2 = sum ((s_i - mean_w) / u_i)^2` about the weighted mean, with each run's
    /// angles' uncertainty `u_i`, and the Birge ratio `sqrt(chi^2 / (n - 1))`.
    pub chi2: f64,
    pub birge_ratio: f64,
    /// The Birge ratio's limit: `1 + 2 sqrt(2 / (n - 1))` (two of its standard
    /// deviations for consistent runs).
    pub birge_limit: f64,
    /// The spread is within the runs' uncertainties (`birge_ratio <= birge_limit`).
    pub consistent: bool,
}

/// The statistics of a group of at least two runs.
pub fn group(material: &str, runs: Vec<Run>) -> Group {
    let n = runs.len() as f64;
    let mean = runs.iter().map(|r| r.s_r_m).sum::<f64>() / n;
    let s: Vec<f64> = runs.iter().map(|r| r.s_r_m).collect();
    let sd = sd(&s);
    let u_mean = sd / n.sqrt();
    let u_geometry = (runs
        .iter()
        .map(|r| (r.u_c_m.powi(2) - r.u_angles_m.powi(2)).max(0.0))
        .sum::<f64>()
        / n)
        .sqrt();
    let u_c = (u_mean.powi(2) + u_geometry.powi(2)).sqrt();
    let nu_eff = welch_satterthwaite(u_c, &[(u_mean, Some(n - 1.0)), (u_geometry, None)]);
    let k = coverage_factor(nu_eff);
    let w: Vec<f64> = runs.iter().map(|r| 1.0 / r.u_angles_m.powi(2)).collect();
    let mean_w = runs.iter().zip(&w).map(|(r, w)| w * r.s_r_m).sum::<f64>() / w.iter().sum::<f64>();
    let chi2: f64 = runs
        .iter()
        .map(|r| ((r.s_r_m - mean_w) / r.u_angles_m).powi(2))
        .sum();
    let birge_ratio = (chi2 / (n - 1.0)).sqrt();
    let birge_limit = 1.0 + 2.0 * (2.0 / (n - 1.0)).sqrt();
    Group {
        material: material.to_string(),
        runs,
        mean_m: mean,
        sd_m: sd,
        u_mean_m: u_mean,
        u_geometry_m: u_geometry,
        u_c_m: u_c,
        nu_eff,
        k,
        expanded_m: k * u_c,
        chi2,
        birge_ratio,
        birge_limit,
        consistent: birge_ratio <= birge_limit,
    }
}
