//! One experiment's page (HTML and Markdown) and its figures.

use super::budget::{budget_rows, budget_total, fmt_expanded, monte_carlo_rows, BudgetRow};
use super::rows::{air_rows, fit_notes, torsion_rows};
use super::{figures, fmt_pct, fmt_sci, kv, render_pair, Kv, OutputFile};
use crate::config::Experiment;
use crate::detect::summary::ReviewPicture;
use crate::fit::Measurement;
use crate::pipeline::{Analysis, ExperimentResult};
use crate::series::AngleRow;
use crate::verdict::Check;
use anyhow::Result;
use serde::Serialize;

/// The files of one experiment's report: its figures under `<name>/`, Figure 11 (the
/// detector's PNG, when given), the review page and its pictures (when the detector
/// kept them: `review`), then `<name>.html` and `<name>.md`.
pub fn experiment_pages(
    exp: &Experiment,
    a: &Analysis,
    r: &ExperimentResult,
    rows: &[AngleRow],
    fig11_png: Option<&[u8]>,
    review: Option<&[(ReviewPicture, Vec<u8>)]>,
) -> Result<Vec<OutputFile>> {
    let f = &a.fit;
    // Figure 16 shows s_r changed by the larger of 15 % and three times the CI.
    let ci_rel = (f.s_r_ci95_m[1] - f.s_r_m) / f.s_r_m;
    let dropped: Vec<(f64, f64)> = f
        .outliers
        .iter()
        .filter(|o| o.dropped)
        .map(|o| (o.t_s, o.angle_rad))
        .collect();
    let figs = figures::experiment_figures(&figures::Inputs {
        name: &exp.name,
        rows,
        m: &a.measurement,
        p: &exp.pendulum,
        law: a.law,
        a_start: f.a_start_rad,
        delta_rel: (3.0 * ci_rel).max(0.15),
        mu: a.sliding_mu,
        release: f.release.map(|r| (r.t_s, r.angle_rad)),
        dropped: &dropped,
    })?;
    let mut files: Vec<OutputFile> = figs
        .into_iter()
        .map(|fg| OutputFile::new(format!("{}/{}", exp.name, fg.file), fg.svg))
        .collect();
    let has_fig11 = r.detection.is_some() && fig11_png.is_some();
    if let (true, Some(png)) = (has_fig11, fig11_png) {
        files.push(OutputFile::new(format!("{}/fig11.png", exp.name), png));
    }
    let has_review = match (&r.detection, review) {
        (Some(d), Some(pictures)) => {
            files.extend(super::review::review_files(
                exp,
                &r.inputs.experiment_file,
                d,
                f,
                rows,
                pictures,
            )?);
            true
        }
        _ => false,
    };
    if let Some(mc) = &r.monte_carlo {
        let fg = figures::monte_carlo_figure(&exp.name, mc, &r.budget)?;
        files.push(OutputFile::new(format!("{}/{}", exp.name, fg.file), fg.svg));
    }
    let mut view = experiment_view(r, &a.measurement, has_fig11);
    view.has_review = has_review;
    files.extend(render_pair("experiment", &exp.name, &view)?);
    Ok(files)
}

fn s_r_expanded(r: &ExperimentResult) -> Kv {
    kv(
        "s_r ± U (95 %, the uncertainty budget)",
        fmt_expanded(&r.budget),
    )
}

#[derive(Serialize)]
struct ExperimentView {
    name: String,
    material: String,
    notes: String,
    synthetic: bool,
    angles: String,
    tool: &'static str,
    inputs: Vec<Kv>,
    geometry: Vec<Kv>,
    detection: Vec<Kv>,
    flagged: Vec<Kv>,
    flagged_more: usize,
    has_detection: bool,
    has_fig11: bool,
    /// A review page (`<name>/review.html`) was written.
    has_review: bool,
    fit: Vec<Kv>,
    /// What was not fitted: the hold before a release, dropped outliers (one line each).
    fit_notes: Vec<String>,
    checks: Vec<CheckView>,
    extremes: Vec<ExtremeView>,
    torsion: Vec<Kv>,
    rolling: String,
    pass: bool,
    /// `pass`, `fail` or `measured` (the CSS class of the standing).
    standing_class: &'static str,
    standing: &'static str,
    /// Nothing to compare with: the Results table lists the measured values.
    measured: Vec<Kv>,
    verdict: String,
    suspect: bool,
    /// `ok`, `suspect`, or `accepted` (suspect, every warning accepted): the banner's class.
    verdict_class: &'static str,
    warnings: Vec<WarningView>,
    /// The tolerances wider than their defaults (`key value (default d)`), and why.
    widened: String,
    widened_reason: String,
    budget: Vec<BudgetRow>,
    budget_total: Vec<Kv>,
    /// The budget's Monte Carlo check (`<name>/mc.svg` and its rows), when run.
    has_monte_carlo: bool,
    monte_carlo: Vec<Kv>,
}

#[derive(Serialize)]
struct WarningView {
    check: String,
    value: String,
    limit: String,
    reason: String,
    accepted: String,
}

#[derive(Serialize)]
struct CheckView {
    quantity: String,
    against: String,
    value: String,
    expected: String,
    deviation: String,
    tolerance: String,
    pass: bool,
}

#[derive(Serialize)]
struct ExtremeView {
    /// The index among the fitted turning points (`0 (release)` for a release from
    /// rest), or `dropped` for an outlier.
    k: String,
    t: String,
    angle: String,
    amplitude: String,
    residual: String,
}

fn check_view(c: &Check) -> CheckView {
    CheckView {
        quantity: c.quantity.as_str().to_string(),
        against: c.against.as_str().to_string(),
        value: fmt_sci(c.value, 4),
        expected: fmt_sci(c.expected, 4),
        deviation: fmt_pct(c.deviation_rel),
        tolerance: format!("{:.1} %", 100.0 * c.tolerance_rel),
        pass: c.verdict(),
    }
}

fn experiment_view(r: &ExperimentResult, m: &Measurement, has_fig11: bool) -> ExperimentView {
    let g = &r.geometry;
    let f = &r.results;
    let mut geometry = Vec::new();
    if let (Some(h), Some(l)) = (g.h_m, g.l_m) {
        geometry.push(kv(
            "inclination alpha = asin(h / l) (Eq. 36)",
            format!("asin({h} / {l}) = {:.4} deg", g.alpha_deg),
        ));
    } else {
        geometry.push(kv("inclination alpha", format!("{:.4} deg", g.alpha_deg)));
    }
    geometry.extend([
        kv(
            "pendulum length d (fulcrum to ball centre)",
            format!("{:.4} m", g.d_m),
        ),
        kv(
            "L = sqrt(d^2 - r^2), fulcrum to contact (Eq. 37)",
            format!("{:.4} m", g.contact_length_m),
        ),
        kv("delta = asin(r / d)", format!("{:.3} deg", g.delta_deg)),
        kv("ball radius r", format!("{:.5} m", g.r_m)),
        kv("ball mass m", format!("{:.4} kg", g.m_kg)),
        kv("J_z = 2/5 m r^2", format!("{:.4e} kg m^2", g.j_z_kg_m2)),
        kv(
            "normal force at rest N_0 = m g (cos(alpha) + sin(alpha) tan(delta))",
            format!("{:.4} N", g.n0_n),
        ),
        kv(
            "small-angle period (model)",
            format!("{:.4} s", g.period_small_angle_s),
        ),
    ]);
    let mut detection = Vec::new();
    let mut flagged = Vec::new();
    let mut flagged_more = 0;
    if let Some(d) = &r.detection {
        detection.extend([
            kv("video", d.video.clone()),
            kv("decoder", d.decoder.clone()),
            kv("frames", d.frames.to_string()),
            kv(
                "ok / corrected / manual / missing",
                format!("{} / {} / {} / {}", d.ok, d.corrected, d.manual, d.missing),
            ),
            kv(
                "pivot",
                format!("({:.1}, {:.1}) px", d.pivot_px[0], d.pivot_px[1]),
            ),
            kv("region of interest [x, y, w, h]", format!("{:?} px", d.roi)),
            kv(
                "wire",
                if d.dark_wire {
                    "darker than the background"
                } else {
                    "lighter than the background"
                }
                .into(),
            ),
            kv("Figure 11 frame", d.figure11_frame.to_string()),
        ]);
        if let Some(v) = &d.verdict {
            detection.push(kv("detection verdict", v.label()));
            detection.push(kv("what the detector saw", v.seen.describe()));
            if let Some(p) = v.seen.period_s {
                detection.push(kv(
                    "period seen / the geometry's d implies (small-angle)",
                    format!(
                        "{p:.4} s / {:.4} s ({:+.1} %)",
                        g.period_small_angle_s,
                        100.0 * (p / g.period_small_angle_s - 1.0)
                    ),
                ));
            }
            for c in v.failed() {
                detection.push(kv(
                    &format!("detection check `{}`", c.check),
                    c.reason.clone(),
                ));
            }
        }
        if let Some(s) = d.swing_scale {
            detection.push(kv(
                "swing of the wire's own direction / of its angle about the pivot",
                format!("{s:.4} (1 when the pivot lies on the wire's line)"),
            ));
        }
        detection.push(kv(
            "camera",
            match &d.camera {
                Some(c) => format!(
                    "moved ({}): {}, and angles, pivot and region are the first frame's",
                    c.describe(),
                    c.steadied()
                ),
                None => "still".into(),
            },
        ));
        if let Some(s) = &d.shutter {
            detection.push(kv("rolling shutter", s.describe()));
        }
        match &d.calibration {
            Some(c) => detection.push(kv(
                "angles measured in",
                format!(
                    "the plate's plane, through the homography of {} calibration points \
                     (`video.calibration`; residual {:.3} px RMS, {} degrees of freedom; \
                     each image point to {:.3} px, {})",
                    c.points,
                    c.residual_rms_px,
                    c.dof,
                    c.point_u_px,
                    c.point_u_source.describe()
                ),
            )),
            None => detection.push(kv(
                "angles measured in",
                match &d.lens {
                    Some(l) => format!(
                        "the undistorted view, through the lens's radial distortion \
                         (`video.lens`: k1 = {} +- {})",
                        l.lens.k1, l.lens.u_k1
                    ),
                    None => {
                        "the image (no `video.calibration`: a camera square to the plate)".into()
                    }
                },
            )),
        }
        const SHOW: usize = 40;
        for fl in d.flagged.iter().take(SHOW) {
            flagged.push(kv(
                &format!("frame {} (t = {:.3} s)", fl.frame, fl.t_s),
                format!(
                    "{}: {}",
                    fl.status.as_str(),
                    fl.flag.map_or("-", |f| f.as_str())
                ),
            ));
        }
        flagged_more = d.flagged.len().saturating_sub(SHOW);
    }
    let mut fit = vec![
        kv("turning points", f.n_extremes.to_string()),
        kv(
            "equilibrium, envelope fit / Eq. 38-39",
            format!(
                "{:.4} deg / {:.4} deg",
                f.psi_eq_rad.to_degrees(),
                f.psi_eq_paper_rad.to_degrees()
            ),
        ),
        kv(
            "envelope slope a (measured)",
            format!("{:.4e} rad/s", f.a_rad_s),
        ),
        kv(
            "envelope slope of the fitted model",
            format!("{:.4e} rad/s", f.a_model_rad_s),
        ),
        s_r_expanded(r),
    ];
    fit.extend(air_rows(r));
    fit.extend([
        kv(
            "s_r, the angles' 95 % interval (geometry exact)",
            format!(
                "{:.4e} .. {:.4e} m (u = {:.4e} m, k = {:.2})",
                f.s_r_interval95_m[0], f.s_r_interval95_m[1], f.s_r_u_m, r.budget.angles.k
            ),
        ),
        kv(
            "s_r, least-squares 95 % CI (turning points independent)",
            format!("{:.4e} .. {:.4e} m", f.s_r_ci95_m[0], f.s_r_ci95_m[1]),
        ),
        kv("beta", figures::trim(f.beta)),
        kv("mu_r = s_r N_0^(beta-1) / r", format!("{:.4e}", f.mu_r)),
        kv(
            "residual RMS of the amplitudes",
            format!("{:.4} deg", f.residual_rms_rad.to_degrees()),
        ),
        kv("Gauss-Newton iterations", f.iterations.to_string()),
        kv(
            "period measured -> d (cross-check)",
            format!(
                "{:.4} s -> {:.4} m (geometry: {:.4} m, {:+.2} %)",
                f.period_s,
                f.d_from_period_m,
                g.d_m,
                100.0 * (f.d_from_period_m - g.d_m) / g.d_m
            ),
        ),
        kv(
            "normal force min / mean / max (Eq. 30)",
            format!(
                "{:.5} / {:.5} / {:.5} N ({:.4} %)",
                f.reactions.n_min_n,
                f.reactions.n_mean_n,
                f.reactions.n_max_n,
                f.reactions.n_variation_pct
            ),
        ),
        kv("max |T|/N (Eq. 31, 34)", format!("{:.3e}", f.max_t_over_n)),
    ]);
    if let Some(t) = r.truth_s_r_m {
        fit.push(kv(
            "synthetic truth s_r",
            format!("{t:.4e} m ({})", fmt_pct((f.s_r_m - t) / t)),
        ));
    }
    for c in &f.beta_comparison {
        fit.push(kv(
            &format!("beta = {}", figures::trim(c.beta)),
            format!(
                "s_r {:.4e}, RSS {:.3e} rad^2, AICc {:.2}",
                c.s_r, c.rss, c.aicc
            ),
        ));
    }
    let mut extremes: Vec<(f64, ExtremeView)> = m
        .extremes
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let view = ExtremeView {
                k: if e.release {
                    format!("{k} (release)")
                } else {
                    k.to_string()
                },
                t: format!("{:.3}", e.t),
                angle: format!("{:.4}", e.angle.to_degrees()),
                amplitude: format!("{:.4}", m.amplitudes[k].to_degrees()),
                residual: f
                    .residuals_rad
                    .get(k)
                    .map_or("-".into(), |v| format!("{:+.4}", v.to_degrees())),
            };
            (e.t, view)
        })
        .collect();
    for o in &f.outliers {
        if o.dropped {
            extremes.push((
                o.t_s,
                ExtremeView {
                    k: "dropped".into(),
                    t: format!("{:.3}", o.t_s),
                    angle: format!("{:.4}", o.angle_rad.to_degrees()),
                    amplitude: format!("{:.4}", o.amplitude_rad.to_degrees()),
                    residual: format!("{:+.4} (not fitted)", o.residual_rad.to_degrees()),
                },
            ));
        }
    }
    extremes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let extremes = extremes.into_iter().map(|(_, v)| v).collect();
    let fit_notes = fit_notes(f);
    let torsion = r
        .torsion
        .map(|c| {
            torsion_rows(&c, "the fit")
                .into_iter()
                .map(|(k, v)| kv(k, v))
                .collect()
        })
        .unwrap_or_default();
    let rolling = match (r.sliding_mu, r.pure_rolling) {
        (Some(mu), Some(true)) => format!(
            "Pure rolling holds: max |T|/N = {:.3e} < mu = {mu} (Eq. 34), {:.0} times smaller.",
            f.max_t_over_n,
            mu / f.max_t_over_n
        ),
        (Some(mu), _) => format!(
            "Pure rolling FAILS: max |T|/N = {:.3e} >= mu = {mu} (Eq. 34).",
            f.max_t_over_n
        ),
        _ => "No sliding coefficient given: Eq. 34 not checked.".into(),
    };
    ExperimentView {
        name: r.name.clone(),
        material: r.material.clone(),
        notes: r.notes.clone(),
        synthetic: r.synthetic,
        angles: r.angles.clone(),
        tool: crate::hash::TOOL,
        inputs: vec![
            kv("experiment file", r.inputs.experiment_file.clone()),
            kv("experiment SHA-256", r.inputs.experiment_sha256.clone()),
            kv("angles SHA-256", r.inputs.angles_sha256.clone()),
        ],
        geometry,
        has_detection: r.detection.is_some(),
        detection,
        flagged,
        flagged_more,
        has_fig11,
        has_review: false,
        fit,
        fit_notes,
        checks: r.checks.iter().map(check_view).collect(),
        extremes,
        torsion,
        rolling,
        pass: r.passed(),
        // A suspect verdict heads the page too: "within tolerances" above a suspect
        // banner would read as a pass.
        standing_class: if !r.compared() {
            "measured"
        } else if r.passed() && !r.verdict.blocks() {
            "pass"
        } else {
            "fail"
        },
        standing: match (r.standing(), r.verdict.blocks()) {
            ("within tolerances", true) => "within tolerances, but SUSPECT (see the verdict)",
            (s, _) => s,
        },
        measured: if r.compared() {
            Vec::new()
        } else {
            vec![
                s_r_expanded(r),
                kv("mu_r", format!("{:.4e}", f.mu_r)),
                kv("envelope slope a", format!("{:.4e} rad/s", f.a_rad_s)),
            ]
        },
        verdict: r.verdict.label(),
        suspect: !r.verdict.warnings.is_empty(),
        verdict_class: if r.verdict.warnings.is_empty() {
            "ok"
        } else if r.verdict.blocks() {
            "suspect"
        } else {
            "accepted"
        },
        warnings: r
            .verdict
            .warnings
            .iter()
            .map(|w| WarningView {
                check: w.check.clone(),
                value: fmt_sci(w.value, 3),
                limit: fmt_sci(w.limit, 3),
                reason: w.reason.clone(),
                accepted: w.accepted.clone().unwrap_or_default(),
            })
            .collect(),
        widened: r
            .tolerances
            .widened()
            .iter()
            .map(|(k, v, d)| format!("{k} {v} (default {d})"))
            .collect::<Vec<_>>()
            .join(", "),
        widened_reason: r.tolerances.reason.clone(),
        budget: budget_rows(&r.budget),
        budget_total: budget_total(&r.budget),
        has_monte_carlo: r.monte_carlo.is_some(),
        monte_carlo: r
            .monte_carlo
            .as_ref()
            .map(|mc| monte_carlo_rows(mc, &r.budget))
            .unwrap_or_default(),
    }
}
