//! The index's section on `beta` from runs at several normal forces: the experiments
//! that name the same `pair`, their torques against their normal forces (log-log) with
//! the fitted law and the lines of `beta` = 1, 4/3 and 3/2, and the verdict.

use super::plot::{render_svg, Chart, Rgb, Series};
use super::summary::Entry;
use crate::fit::{beta_name, beta_series, BetaSeries, SeriesRun};
use anyhow::Result;
use serde::Serialize;

/// The series of a build: the built experiments with a `pair`, grouped by it in the
/// manifest's order (a pair needs two runs or more at different normal forces).
pub fn series_of(entries: &[Entry]) -> Vec<BetaSeries> {
    let mut pairs: Vec<(String, Vec<SeriesRun>)> = Vec::new();
    for r in entries.iter().filter_map(|e| e.result.as_ref()) {
        let Some(pair) = &r.pair else { continue };
        let f = &r.results;
        let run = SeriesRun::of(
            &r.name,
            f.s_r_m,
            r.budget.u_c_m,
            f.beta,
            f.reactions.n_mean_n,
        );
        match pairs.iter_mut().find(|(p, _)| p == pair) {
            Some((_, runs)) => runs.push(run),
            None => pairs.push((pair.clone(), vec![run])),
        }
    }
    pairs
        .into_iter()
        .filter_map(|(p, runs)| beta_series(&p, runs))
        .collect()
}

/// The file name of a series' figure.
pub fn figure_file(index: usize) -> String {
    format!("beta-{}.svg", index + 1)
}

#[derive(Serialize)]
pub struct SeriesView {
    pair: String,
    figure: String,
    runs: Vec<RunView>,
    beta: String,
    s_r: String,
    birge: String,
    consistent: bool,
    trials: String,
    verdict: String,
}

#[derive(Serialize)]
struct RunView {
    name: String,
    n: String,
    torque: String,
}

/// The section's words and numbers for series `s`, the `index`-th.
pub fn series_view(index: usize, s: &BetaSeries) -> SeriesView {
    SeriesView {
        pair: s.pair.clone(),
        figure: figure_file(index),
        runs: s
            .runs
            .iter()
            .map(|r| RunView {
                name: r.name.clone(),
                n: format!("{:.4}", r.normal_force_n),
                torque: format!(
                    "{:.4e} ± {:.1e} N m ({:.2} %)",
                    r.torque_nm,
                    r.u_torque_nm,
                    100.0 * r.u_torque_nm / r.torque_nm
                ),
            })
            .collect(),
        beta: format!(
            "{:.3} ± {:.3} (u; 95 % {:.3} .. {:.3}, k = {:.2})",
            s.beta, s.u_beta, s.beta_interval95[0], s.beta_interval95[1], s.k
        ),
        s_r: format!(
            "{:.4e} ± {:.1e} m·N^(1-beta) (u; correlation with beta {:+.3})",
            s.s_r, s.u_s_r, s.correlation
        ),
        birge: match (s.birge_ratio, s.birge_limit) {
            (Some(r), Some(l)) => format!(
                "{r:.2} (limit {l:.2}; chi² {:.2} on {} dof)",
                s.chi2,
                s.runs.len() - 2
            ),
            _ => "- (two runs: no degrees of freedom left)".into(),
        },
        consistent: s.consistent,
        trials: s
            .trials
            .iter()
            .map(|t| {
                format!(
                    "beta = {}: chi² {:.2}{}",
                    beta_name(t.beta),
                    t.chi2,
                    if t.inside { " (inside)" } else { "" }
                )
            })
            .collect::<Vec<_>>()
            .join("; "),
        verdict: s.verdict.clone(),
    }
}

/// The series' figure: `log10 M` against `log10 N` with each run's 95 % bar, the fitted
/// law, and the lines of the usual exponents through the runs' weighted centre.
pub fn figure(s: &BetaSeries) -> Result<String> {
    let l10 = std::f64::consts::LN_10;
    let xs: Vec<f64> = s.runs.iter().map(|r| r.normal_force_n.log10()).collect();
    let (lo, hi) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let pad = 0.1 * (hi - lo).max(0.01);
    let (x0, x1) = (lo - pad, hi + pad);
    let line = |beta: f64| -> Vec<(f64, f64)> {
        [x0, x1]
            .iter()
            .map(|&x| (x, (s.ln_m0 + beta * (x * l10 - s.ln_n0)) / l10))
            .collect()
    };
    let mut c = Chart::new(
        &format!(
            "{}: rolling-resistance torque against the normal force",
            s.pair
        ),
        "log10 N (N)",
        "log10 M_r (N m)",
    )
    .with(Series::markers(
        "runs (torque at the mean normal force)",
        Rgb::RED,
        s.runs
            .iter()
            .map(|r| (r.normal_force_n.log10(), r.torque_nm.log10()))
            .collect(),
    ))
    .with(Series::line(
        "95 % of each run",
        Rgb::RED,
        s.runs
            .iter()
            .flat_map(|r| {
                let x = r.normal_force_n.log10();
                let h = 1.96 * r.u_torque_nm;
                [
                    // A bar reaching below zero is drawn down to a thousandth of M.
                    (x, (r.torque_nm - h).max(1e-3 * r.torque_nm).log10()),
                    (x, (r.torque_nm + h).log10()),
                    (f64::NAN, f64::NAN),
                ]
            })
            .collect(),
    ))
    .with(Series::line(
        &format!("fitted: beta = {:.3}", s.beta),
        Rgb::BLACK,
        line(s.beta),
    ));
    for (t, color) in s.trials.iter().zip([Rgb::BLUE, Rgb::GREEN, Rgb::PURPLE]) {
        c = c.with(Series::dashed(
            &format!("beta = {}", beta_name(t.beta)),
            color,
            line(t.beta),
        ));
    }
    c.x_range = Some((x0, x1));
    render_svg(&c)
}
