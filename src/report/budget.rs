//! The uncertainty budget on an experiment's page: its rows, its total and the Monte
//! Carlo check's comparison, formatted.

use super::{figures, kv, Kv};
use crate::uncertainty::{Budget, Distribution, MonteCarlo};
use serde::Serialize;

/// `s_r +- U` of the budget, as the pages and Table 1 show it.
pub fn fmt_expanded(b: &Budget) -> String {
    format!(
        "{:.4e} ± {:.2e} m (k = {:.2}, {:.2} %)",
        b.s_r_m,
        b.expanded_m,
        b.k,
        100.0 * b.expanded_m / b.s_r_m.abs()
    )
}

/// The budget's rows: one per input, then the angles' parts.
pub(super) fn budget_rows(b: &Budget) -> Vec<BudgetRow> {
    b.components
        .iter()
        .map(|c| BudgetRow {
            quantity: c.quantity.clone(),
            key: c.key.clone(),
            value: if c.adds_to_s_r() {
                format!("{:.4e} m", c.value)
            } else {
                format!("{} {}", figures::trim(c.value), c.unit)
            },
            u: format!("{:.2e} {}", c.u, c.unit),
            distribution: match c.distribution {
                Distribution::Rectangular => "rectangular",
                Distribution::Normal => "normal",
                Distribution::Student => "Student t",
            },
            source: c.source.clone(),
            sensitivity: if c.adds_to_s_r() {
                "1".to_string()
            } else {
                format!("{:.3e} m/{}", c.sensitivity, c.unit)
            },
            contribution: format!("{:.2e}", c.contribution_m),
            share: format!("{:.1} %", 100.0 * (c.contribution_m / b.u_c_m).powi(2)),
            dof: figures::dof(c.dof),
        })
        .collect()
}

pub(super) fn budget_total(b: &Budget) -> Vec<Kv> {
    vec![
        kv(
            "combined standard uncertainty u_c",
            format!(
                "{:.3e} m ({:.3} %)",
                b.u_c_m,
                100.0 * b.u_c_m / b.s_r_m.abs()
            ),
        ),
        kv(
            "effective degrees of freedom (Welch-Satterthwaite)",
            figures::dof(b.nu_eff),
        ),
        kv("coverage factor k (95 %)", format!("{:.3}", b.k)),
        kv(
            "expanded uncertainty U = k u_c",
            format!("{:.3e} m", b.expanded_m),
        ),
        kv(
            "s_r ± U",
            format!(
                "{} ({:.4e} .. {:.4e} m)",
                fmt_expanded(b),
                b.interval95_m[0],
                b.interval95_m[1]
            ),
        ),
    ]
}

pub(super) fn monte_carlo_rows(mc: &MonteCarlo, b: &Budget) -> Vec<Kv> {
    let rel = |v: f64| 100.0 * v / b.s_r_m.abs();
    let interval = |label: &str, [lo, hi]: [f64; 2]| {
        kv(
            label,
            format!(
                "{lo:.4e} .. {hi:.4e} m ({:+.3} % .. {:+.3} %)",
                rel(lo - b.s_r_m),
                rel(hi - b.s_r_m)
            ),
        )
    };
    vec![
        kv("draws (seed)", format!("{} ({})", mc.draws, mc.seed)),
        kv(
            "standard deviation of the draws / u_c",
            format!(
                "{:.3e} m / {:.3e} m = {:.3} ({:+.1} %)",
                mc.u_m,
                b.u_c_m,
                mc.u_ratio,
                100.0 * (mc.u_ratio - 1.0)
            ),
        ),
        interval(
            "95 % interval: Monte Carlo (2.5 %, 97.5 % quantiles)",
            mc.interval95_m,
        ),
        interval("95 % interval: the budget (s_r ± U)", b.interval95_m),
        kv(
            "agreement (JCGM 101 §8: within 10 % of u_c)",
            if (mc.u_ratio - 1.0).abs() <= 0.1 {
                "the budget's u_c is within 10 % of the Monte Carlo's".to_string()
            } else {
                "the budget's u_c differs from the Monte Carlo's by more than 10 %: the \
                 linearisation does not hold; use the Monte Carlo interval"
                    .to_string()
            },
        ),
    ]
}

#[derive(Serialize)]
pub(super) struct BudgetRow {
    quantity: String,
    key: String,
    value: String,
    u: String,
    distribution: &'static str,
    source: String,
    sensitivity: String,
    contribution: String,
    share: String,
    dof: String,
}
