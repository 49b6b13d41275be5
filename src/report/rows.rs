//! Rows of an experiment page's tables in words: the air's share of the fit, the
//! torsion check (Appendix A), and the notes on what was not fitted.

use super::{figures, kv, Kv};
use crate::physics::torsion::TorsionCheck;
use crate::pipeline::ExperimentResult;

/// The air's rows of the fit table: the drag modelled, `s_r` without it, the
/// correction and its share of the budget (or that the air is left out).
pub fn air_rows(r: &ExperimentResult) -> Vec<Kv> {
    let Some(a) = &r.results.air else {
        return vec![kv(
            "the air",
            "not modelled (`air.model: none`): the paper's equation of motion, in a vacuum".into(),
        )];
    };
    let scale = match a.drag_scale_se {
        Some(se) => format!("; drag scale fitted: {:.3} +- {:.3}", a.drag_scale, se),
        None => String::new(),
    };
    let u2: f64 = r
        .budget
        .components
        .iter()
        .filter(|c| c.key.starts_with("air."))
        .map(|c| c.contribution_m * c.contribution_m)
        .sum();
    let share = if r.budget.u_c_m > 0.0 {
        100.0 * u2 / (r.budget.u_c_m * r.budget.u_c_m)
    } else {
        0.0
    };
    vec![
        kv(
            "the air (drag of a sphere, docs/air.md)",
            format!(
                "rho = {:.4} kg/m^3, mu = {:.4e} Pa s, wall factor {}{scale}; Reynolds number up \
                 to {:.0}; the air takes {:.3} % of the energy lost",
                a.density_kg_m3,
                a.viscosity_pa_s,
                figures::trim(a.wall_factor),
                a.reynolds_max,
                a.energy_share_pct
            ),
        ),
        kv(
            "s_r without the air (the paper's model)",
            format!(
                "{:.4e} m: modelling the air changes s_r by {:+.3} %; the air's inputs give \
                 {:.3e} m of u ({:.2} % of u_c^2)",
                a.s_r_without_air_m,
                a.correction_pct,
                u2.sqrt(),
                share
            ),
        ),
    ]
}

/// The Appendix A table's rows, label and formatted value (the text table and the
/// report pages both show these).
pub fn torsion_rows(c: &TorsionCheck, s_r_from: &str) -> Vec<(&'static str, String)> {
    vec![
        ("torsion period T", format!("{:.1} s", c.period_s)),
        ("wire length", format!("{:.3} m", c.wire_length_m)),
        (
            "k_t = 4 pi^2 J_z / T^2 (A5)",
            format!("{:.3e} N m/rad", c.k_t_n_m_per_rad),
        ),
        (
            "psi_0 -> phi_0 = psi_0 / sin(delta)",
            format!(
                "{:.1} deg -> {:.3} rad ({:.1} deg)",
                c.psi0_rad.to_degrees(),
                c.phi0_rad,
                c.phi0_rad.to_degrees()
            ),
        ),
        ("M_t,max = k_t phi_0", format!("{:.3e} N m", c.m_t_max_n_m)),
        (
            "M_r = s_r m g",
            format!("{:.3e} N m (s_r from {s_r_from})", c.m_r_n_m),
        ),
        (
            "M_r = s_r N_0^beta (model)",
            format!("{:.3e} N m", c.m_r_model_n_m),
        ),
        ("100 M_t,max / M_r", format!("{:.2} %", c.ratio_pct)),
    ]
}

/// The page's lines on what was not fitted: the frames of a held start before the
/// release, and the turning points dropped as outliers (or found beyond the cap).
pub(super) fn fit_notes(f: &crate::fit::FitResult) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(r) = &f.release {
        out.push(format!(
            "{} frames before the release at t = {:.3} s are not fitted: the recording begins \
             with the ball held at {:.4} deg for {:.2} s. The fit starts at the release, from \
             rest (turning point 0).",
            r.frame,
            r.t_s,
            r.angle_rad.to_degrees(),
            r.held_s
        ));
    }
    if let Some(s) = &f.stop {
        out.push(format!(
            "The ball stops at about t = {:.3} s (the turning points' envelope reaches zero): \
             the {} extreme(s) the recording shows after it, the noise of the ball at rest, \
             are not fitted.",
            s.t_s, s.dropped
        ));
    }
    let list = |dropped: bool| {
        f.outliers
            .iter()
            .filter(|o| o.dropped == dropped)
            .map(|o| {
                format!(
                    "t = {:.3} s (residual {:+.4} deg, {:.0} robust standard deviations)",
                    o.t_s,
                    o.residual_rad.to_degrees(),
                    o.robust_z
                )
            })
            .collect::<Vec<_>>()
    };
    let (dropped, kept) = (list(true), list(false));
    if !dropped.is_empty() {
        out.push(format!(
            "{} dropped as {} and not fitted (marked in Figures 14a, 15 and 16): {}.",
            if dropped.len() == 1 {
                "1 turning point".to_string()
            } else {
                format!("{} turning points", dropped.len())
            },
            if dropped.len() == 1 {
                "an outlier"
            } else {
                "outliers"
            },
            dropped.join("; ")
        ));
    }
    if !kept.is_empty() {
        out.push(format!(
            "{} also outlying but kept in the fit, as at most {} may be dropped (a tenth of \
             the turning points): {}.",
            if kept.len() == 1 {
                "1 turning point is".to_string()
            } else {
                format!("{} turning points are", kept.len())
            },
            crate::fit::outlier_cap(f.n_extremes + dropped.len()),
            kept.join("; ")
        ));
    }
    out
}
