//! The paper's figures, recomputed from each experiment's data (SVG via [`super::plot`]).
//! Angles are drawn in degrees; every curve comes from the measurement or from
//! integrating the fitted model, never from published numbers.

use super::plot::{render_svg, Chart, Rgb, Series};
use crate::fit::Measurement;
use crate::numerics::slope_through_origin;
use crate::physics::ode::{integrate, OdeOptions, Trajectory};
use crate::physics::{FrictionLaw, Pendulum};
use crate::series::{AngleRow, Status};
use crate::uncertainty::{Budget, MonteCarlo};
use anyhow::Result;

/// A named figure, ready to write.
pub struct Figure {
    pub file: String,
    pub svg: String,
}

fn fig(file: &str, chart: &Chart) -> Result<Figure> {
    Ok(Figure {
        file: file.to_string(),
        svg: render_svg(chart)?,
    })
}

/// The fitted model's motion over the measured span: from the first turning point, with
/// the fitted start amplitude, `s_r` and `beta`.
pub fn model_motion(p: &Pendulum, law: &FrictionLaw, t0: f64, a0: f64, t1: f64) -> Trajectory {
    integrate(
        p,
        law,
        t0,
        [a0, 0.0],
        &OdeOptions {
            t_end: t1,
            rtol: 1e-9,
            atol: 1e-10,
            ..OdeOptions::default()
        },
    )
}

/// `psi(t)` of a trajectory in the camera's frame, degrees: `psi_eq + side0 * psi`.
fn signal(
    tr: &Trajectory,
    t0: f64,
    t1: f64,
    psi_eq: f64,
    side0: f64,
    per_s: f64,
) -> Vec<(f64, f64)> {
    let n = (((t1 - t0) * per_s).ceil() as usize).clamp(2, 200_000);
    (0..=n)
        .map(|i| {
            let t = t0 + (t1 - t0) * i as f64 / n as f64;
            (t, (psi_eq + side0 * tr.state(t)[0]).to_degrees())
        })
        .collect()
}

/// Envelope lines `psi_eq +/- (A0 - a t)` over `[t0, t1]`, degrees.
fn envelope_lines(psi_eq: f64, a0: f64, a: f64, t0: f64, t1: f64) -> [Vec<(f64, f64)>; 2] {
    let at = |t: f64, s: f64| (t, (psi_eq + s * (a0 - a * t)).to_degrees());
    [
        vec![at(t0, 1.0), at(t1, 1.0)],
        vec![at(t0, -1.0), at(t1, -1.0)],
    ]
}

/// Inputs of an experiment's figures.
pub struct Inputs<'a> {
    pub name: &'a str,
    pub rows: &'a [AngleRow],
    pub m: &'a Measurement,
    pub p: &'a Pendulum,
    pub law: FrictionLaw,
    /// Fitted amplitude at the first turning point, rad.
    pub a_start: f64,
    /// Relative change of `s_r` shown in Figure 16.
    pub delta_rel: f64,
    pub mu: Option<f64>,
    /// The release from rest after a held start, `(t, angle)` (s, rad): marked in
    /// Figure 12.
    pub release: Option<(f64, f64)>,
    /// Turning points dropped from the fit as outliers, `(t, angle)` (s, rad): marked in
    /// Figures 14a, 15 and 16.
    pub dropped: &'a [(f64, f64)],
}

/// Figures 12, 14a, 14b, 15, 16a, 16b, 17 and 18 of one experiment.
pub fn experiment_figures(x: &Inputs) -> Result<Vec<Figure>> {
    let m = x.m;
    let ex = &m.extremes;
    let (t0, t1) = (ex[0].t, ex[ex.len() - 1].t);
    let eq = m.equilibrium.envelope;
    let side0 = ex[0].side;
    let deg = f64::to_degrees;
    let mut out = Vec::new();

    // Figure 12: the raw angle per frame, flagged frames circled.
    let ok: Vec<(f64, f64)> = x
        .rows
        .iter()
        .filter_map(|r| r.angle_rad.map(|a| (r.t_s, deg(a))))
        .collect();
    let flagged: Vec<(f64, f64)> = x
        .rows
        .iter()
        .filter(|r| !matches!(r.status, Status::Ok | Status::Manual))
        .filter_map(|r| r.angle_rad.map(|a| (r.t_s, deg(a))))
        .collect();
    let manual: Vec<(f64, f64)> = x
        .rows
        .iter()
        .filter(|r| r.status == Status::Manual)
        .filter_map(|r| r.angle_rad.map(|a| (r.t_s, deg(a))))
        .collect();
    let mut c = Chart::new(
        &format!("Fig. 12 - {}: wire angle per frame", x.name),
        "t (s)",
        "angle from image x axis (deg)",
    )
    .with(Series::line("detected angle", Rgb::BLUE, ok))
    .with(Series::circles(
        "flagged (corrected or missing)",
        Rgb::RED,
        flagged,
    ));
    if !manual.is_empty() {
        c = c.with(Series::crosses("operator mark", Rgb::GREEN, manual));
    }
    if let Some((t, a)) = x.release {
        c = c.with(Series::markers(
            "release from rest (the fit starts here)",
            Rgb::PURPLE,
            vec![(t, deg(a))],
        ));
    }
    out.push(fig("fig12.svg", &c)?);
    let dropped: Vec<(f64, f64)> = x.dropped.iter().map(|&(t, a)| (t, deg(a))).collect();
    let with_dropped = |c: Chart| {
        if dropped.is_empty() {
            c
        } else {
            c.with(Series::crosses(
                "dropped as outlier (not fitted)",
                Rgb::PURPLE,
                dropped.clone(),
            ))
        }
    };

    // Figure 14a: turning points as measured, with both equilibrium estimates.
    let maxima: Vec<(f64, f64)> = ex
        .iter()
        .filter(|e| e.side > 0.0)
        .map(|e| (e.t, deg(e.angle)))
        .collect();
    let minima: Vec<(f64, f64)> = ex
        .iter()
        .filter(|e| e.side < 0.0)
        .map(|e| (e.t, deg(e.angle)))
        .collect();
    let h = |v: f64| vec![(t0, deg(v)), (t1, deg(v))];
    out.push(fig(
        "fig14a.svg",
        &with_dropped(
            Chart::new(
                &format!("Fig. 14a - {}: extreme elongations as measured", x.name),
                "t (s)",
                "angle (deg)",
            )
            .with(Series::markers("maxima", Rgb::BLUE, maxima))
            .with(Series::markers("minima", Rgb::ORANGE, minima))
            .with(Series::dashed(
                "equilibrium, Eq. 38-39 (mean of extremes)",
                Rgb::GREY,
                h(m.equilibrium.paper),
            ))
            .with(Series::line(
                "equilibrium, envelope fit",
                Rgb::BLACK,
                h(m.equilibrium.envelope),
            )),
        ),
    )?);

    // Figure 14b: amplitudes about the equilibrium, both estimators, with the regression.
    let about = |q: f64| -> Vec<(f64, f64)> {
        ex.iter().map(|e| (e.t, deg((e.angle - q).abs()))).collect()
    };
    let fit_line = vec![
        (t0, deg(m.envelope.intercept + m.envelope.slope * t0)),
        (t1, deg(m.envelope.intercept + m.envelope.slope * t1)),
    ];
    out.push(fig(
        "fig14b.svg",
        &Chart::new(
            &format!("Fig. 14b - {}: amplitude about the equilibrium", x.name),
            "t (s)",
            "|psi_k - psi_eq| (deg)",
        )
        .with(Series::markers(
            "about the envelope-fit equilibrium",
            Rgb::BLUE,
            about(m.equilibrium.envelope),
        ))
        .with(Series::crosses(
            "about the Eq. 38-39 equilibrium",
            Rgb::ORANGE,
            about(m.equilibrium.paper),
        ))
        .with(Series::dashed(
            "regression line (slope -a)",
            Rgb::BLACK,
            fit_line,
        )),
    )?);

    // Figure 15: the fitted model's signal over the measured turning points.
    let model = model_motion(x.p, &x.law, t0, x.a_start, t1);
    let [up, down] = envelope_lines(eq, m.equilibrium.a0, m.equilibrium.a, t0, t1);
    let points: Vec<(f64, f64)> = ex.iter().map(|e| (e.t, deg(e.angle))).collect();
    out.push(fig(
        "fig15.svg",
        &with_dropped(
            Chart::new(
                &format!(
                    "Fig. 15 - {}: model signal, s_r = {:.3e} {}, beta = {}",
                    x.name,
                    x.law.s_r,
                    s_r_unit(x.law.beta),
                    trim(x.law.beta)
                ),
                "t (s)",
                "angle (deg)",
            )
            .with(Series::line(
                "model (Eq. 33, fitted)",
                Rgb::BLUE,
                signal(&model, t0, t1, eq, side0, 40.0 / m.period_s.max(0.1)),
            ))
            .with(Series::markers("measured extremes", Rgb::RED, points))
            .with(Series::dashed("envelope fit", Rgb::BLACK, up))
            .with(Series::dashed("", Rgb::BLACK, down)),
        ),
    )?);
    // Figures 16a/b: at page size a change of s_r by delta is invisible in the signal,
    // so they show what it does to the fit: each measured amplitude (extreme about the
    // equilibrium, on its own side) minus the model's there, for the fitted s_r (about
    // zero) and for s_r changed by +delta (a) or -delta (b), whose residuals drift off
    // as the model's amplitude falls too fast or too slowly.
    let residuals = |tr: &Trajectory| -> Vec<(f64, f64)> {
        ex.iter()
            .map(|e| {
                (
                    e.t,
                    deg(e.side * (e.angle - (eq + side0 * tr.state(e.t)[0]))),
                )
            })
            .collect()
    };
    let best = residuals(&model);
    // The turning points dropped as outliers, against the fitted model, on their side of
    // the equilibrium.
    let dropped_residuals: Vec<(f64, f64)> = x
        .dropped
        .iter()
        .map(|&(t, a)| {
            let side = (a - eq).signum();
            (t, deg(side * (a - (eq + side0 * model.state(t)[0]))))
        })
        .collect();
    let unit = s_r_unit(x.law.beta);
    for (file, sign, tag) in [("fig16a.svg", 1.0, "a"), ("fig16b.svg", -1.0, "b")] {
        let law = FrictionLaw::new(x.law.s_r * (1.0 + sign * x.delta_rel), x.law.beta);
        let tr = model_motion(x.p, &law, t0, x.a_start, t1);
        let chart = Chart::new(
            &format!(
                "Fig. 16{tag} - {}: amplitude minus model, s_r {:+.0} % = {:.3e} {unit}",
                x.name,
                100.0 * sign * x.delta_rel,
                law.s_r,
            ),
            "t (s)",
            "measured - model amplitude (deg)",
        )
        .with(Series::dashed("", Rgb::BLACK, vec![(t0, 0.0), (t1, 0.0)]))
        .with(Series::markers(
            &format!("fitted s_r = {:.3e} {unit}", x.law.s_r),
            Rgb::BLUE,
            best.clone(),
        ))
        .with(Series::crosses(
            &format!("s_r {:+.0} %", 100.0 * sign * x.delta_rel),
            Rgb::RED,
            residuals(&tr),
        ));
        let chart = if dropped_residuals.is_empty() {
            chart
        } else {
            chart.with(Series::crosses(
                "dropped as outlier (not fitted), against the fitted s_r",
                Rgb::PURPLE,
                dropped_residuals.clone(),
            ))
        };
        out.push(fig(file, &chart)?);
    }

    // Figure 17: the normal force along the fitted motion; Figure 18: |T|/N.
    let n = 4000;
    let mut nf = Vec::with_capacity(n + 1);
    let mut tn = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let t = t0 + (t1 - t0) * i as f64 / n as f64;
        let [psi, w] = model.state(t);
        let nn = x.p.normal_force(psi, w);
        let tf = x.p.friction_force_towards(
            &x.law,
            psi,
            w,
            if w == 0.0 {
                model.direction(t)
            } else {
                crate::physics::sign(w)
            },
        );
        nf.push((t, nn));
        tn.push((t, (tf / nn).abs()));
    }
    let (lo, hi) = nf.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &(_, v)| {
        (l.min(v), h.max(v))
    });
    let mean = nf.iter().map(|p| p.1).sum::<f64>() / nf.len() as f64;
    let hl = |v: f64| vec![(t0, v), (t1, v)];
    out.push(fig(
        "fig17.svg",
        &Chart::new(
            &format!(
                "Fig. 17 - {}: normal force, varies {:.4} % of its mean",
                x.name,
                100.0 * (hi - lo) / mean
            ),
            "t (s)",
            "N (newton)",
        )
        .with(Series::line("N(t) (Eq. 30)", Rgb::BLUE, nf))
        .with(Series::dashed(&format!("max {hi:.5} N"), Rgb::RED, hl(hi)))
        .with(Series::dashed(
            &format!("mean {mean:.5} N"),
            Rgb::BLACK,
            hl(mean),
        ))
        .with(Series::dashed(
            &format!("min {lo:.5} N"),
            Rgb::GREEN,
            hl(lo),
        )),
    )?);
    let tmax = tn.iter().map(|p| p.1).fold(0.0f64, f64::max);
    let mut c = Chart::new(
        &format!(
            "Fig. 18 - {}: |T|/N along the motion (max {tmax:.2e})",
            x.name
        ),
        "t (s)",
        "|T| / N (dimensionless)",
    )
    .with(Series::line("|T|/N (Eq. 31 over Eq. 30)", Rgb::BLUE, tn));
    if let Some(mu) = x.mu {
        c = c.with(Series::dashed(
            &format!("sliding friction mu = {mu} (Eq. 34)"),
            Rgb::RED,
            hl(mu),
        ));
        c.y_range = Some((0.0, 1.1 * mu.max(tmax)));
    }
    out.push(fig("fig18.svg", &c)?);
    Ok(out)
}

/// The unit of `s_r` in `M_r = s_r N^beta` (M_r in N m): `m` for beta = 1, else
/// `N^(1 - beta) m` (`N^-0.5 m` for beta = 3/2).
pub fn s_r_unit(beta: f64) -> String {
    if beta == 1.0 {
        "m".to_string()
    } else {
        format!("N^{} m", trim(1.0 - beta))
    }
}

/// A number without trailing zeros (`1`, `1.5`, `1.3333`).
/// Degrees of freedom as a reader takes them: `∞` for infinitely many, and for so many
/// that Student's k is the normal one to three figures (more than 1000).
pub fn dof(nu: Option<f64>) -> String {
    match nu {
        Some(v) if v.is_finite() && v <= 1000.0 => format!("{v:.0}"),
        Some(_) => "> 1000".to_string(),
        None => "∞".to_string(),
    }
}

pub fn trim(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

/// One point of Figure 19.
pub struct Fig19Point {
    pub label: String,
    pub a_rad_s: f64,
    pub mu_r: f64,
    /// The expanded uncertainty of `mu_r` (95 %, from the budget of `s_r`).
    pub mu_r_expanded: f64,
    /// The model's analytic ratio `mu_r / a` for this experiment's geometry.
    pub model_ratio: f64,
    pub d_m: f64,
}

/// Figure 19: `mu_r` against `a`, the fitted proportionality line through the origin and
/// the model's analytic lines (ERRATA §2) for the shortest and longest pendulum.
pub fn figure19(points: &[Fig19Point]) -> Result<Figure> {
    let xs: Vec<(f64, f64)> = points
        .iter()
        .map(|p| (p.a_rad_s * 1e3, p.mu_r * 1e3))
        .collect();
    let amax = points.iter().map(|p| p.a_rad_s).fold(0.0f64, f64::max) * 1.1;
    let (a, mu): (Vec<f64>, Vec<f64>) = points.iter().map(|p| (p.a_rad_s, p.mu_r)).unzip();
    let k = slope_through_origin(&a, &mu);
    let mut c = Chart::new(
        "Fig. 19 - coefficient of rolling friction against envelope slope",
        "a (1e-3 rad/s)",
        "mu_r (1e-3, dimensionless)",
    )
    .with(Series::markers("reproduced experiments", Rgb::RED, xs))
    .with(Series::line(
        "mu_r ± U (95 %, the uncertainty budget)",
        Rgb::RED,
        points
            .iter()
            .flat_map(|p| {
                let x = p.a_rad_s * 1e3;
                [
                    (x, (p.mu_r - p.mu_r_expanded) * 1e3),
                    (x, (p.mu_r + p.mu_r_expanded) * 1e3),
                    (f64::NAN, f64::NAN),
                ]
            })
            .collect(),
    ))
    .with(Series::line(
        &format!("fitted proportionality mu_r = {k:.4} s x a"),
        Rgb::BLUE,
        vec![(0.0, 0.0), (amax * 1e3, k * amax * 1e3)],
    ));
    let mut by_d: Vec<&Fig19Point> = points.iter().collect();
    by_d.sort_by(|a, b| a.d_m.total_cmp(&b.d_m));
    let ends: Vec<&Fig19Point> = match (by_d.first(), by_d.last()) {
        (Some(a), Some(b)) if (a.d_m - b.d_m).abs() > 1e-9 => vec![*a, *b],
        (Some(a), _) => vec![*a],
        _ => vec![],
    };
    for (p, color) in ends.iter().zip([Rgb::GREY, Rgb::PURPLE]) {
        c = c.with(Series::dashed(
            &format!(
                "model, d = {:.4} m (mu_r = pi tan(alpha) a / 2 omega_0)",
                p.d_m
            ),
            color,
            vec![(0.0, 0.0), (amax * 1e3, p.model_ratio * amax * 1e3)],
        ));
    }
    c.x_range = Some((0.0, amax * 1e3));
    fig("fig19.svg", &c)
}

/// Figure 2: the model's signals for beta = 1 and beta = 3/2 with the same torque at rest.
pub fn figure2(p: &Pendulum, s_r: f64, psi0: f64) -> Result<Vec<Figure>> {
    let n0 = p.rest_normal_force();
    let period = std::f64::consts::TAU / p.omega0();
    let mut out = Vec::new();
    for (file, beta, tag) in [("fig2a.svg", 1.0, "a"), ("fig2b.svg", 1.5, "b")] {
        // Same rolling torque at rest: s_r' N0^beta = s_r N0.
        let law = FrictionLaw::new(s_r * n0.powf(1.0 - beta), beta);
        let t1 = 40.0 * period;
        let tr = model_motion(p, &law, 0.0, psi0, t1);
        let end = tr.stopped_at.unwrap_or(t1).min(t1);
        out.push(fig(
            file,
            &Chart::new(
                &format!(
                    "Fig. 2{tag} - model signal, M_r = s_r N^beta, beta = {}, s_r = {:.3e} {}",
                    trim(beta),
                    law.s_r,
                    s_r_unit(beta)
                ),
                "t (s)",
                "psi (deg)",
            )
            .with(Series::line(
                "psi(t), Eq. 33",
                Rgb::BLUE,
                signal(&tr, 0.0, end, 0.0, 1.0, 40.0 / period),
            )),
        )?);
    }
    Ok(out)
}

/// The Monte Carlo check of the uncertainty budget (JCGM 101): the draws' histogram,
/// the budget's distribution of `s_r` (Student's t with its effective degrees of
/// freedom, scaled by `u_c`, or normal) in the same counts per bin, and both 95 %
/// intervals. `s_r` in units of the budget's value (`s_r / s_r_fit - 1`, %).
pub fn monte_carlo_figure(name: &str, mc: &MonteCarlo, b: &Budget) -> Result<Figure> {
    let s0 = b.s_r_m;
    let pct = |v: f64| 100.0 * (v / s0 - 1.0);
    let h = &mc.histogram;
    let bins = h.counts.len();
    let w = (h.hi - h.lo) / bins as f64;
    let mut steps = Vec::with_capacity(2 * bins + 2);
    for (i, &c) in h.counts.iter().enumerate() {
        let (x0, x1) = (h.lo + i as f64 * w, h.lo + (i + 1) as f64 * w);
        steps.push((pct(x0), c as f64));
        steps.push((pct(x1), c as f64));
    }
    let top = h.counts.iter().copied().max().unwrap_or(0) as f64;
    let density = |x: f64| {
        let z = (x - s0) / b.u_c_m;
        let pdf = match b.nu_eff {
            Some(nu) if nu.is_finite() && nu < 1e6 => crate::stats::student_t_pdf(z, nu),
            _ => (-0.5 * z * z).exp() / (std::f64::consts::TAU).sqrt(),
        };
        mc.draws as f64 * w * pdf / b.u_c_m
    };
    let n = 200;
    let (lo, hi) = (
        h.lo.min(b.interval95_m[0] - b.u_c_m),
        h.hi.max(b.interval95_m[1] + b.u_c_m),
    );
    let curve: Vec<(f64, f64)> = (0..=n)
        .map(|i| {
            let x = lo + (hi - lo) * i as f64 / n as f64;
            (pct(x), density(x))
        })
        .collect();
    let ymax = top.max(curve.iter().map(|p| p.1).fold(0.0, f64::max)) * 1.15;
    let bars = |iv: [f64; 2]| {
        vec![
            (pct(iv[0]), 0.0),
            (pct(iv[0]), ymax),
            (f64::NAN, f64::NAN),
            (pct(iv[1]), 0.0),
            (pct(iv[1]), ymax),
        ]
    };
    let c = Chart::new(
        &format!("Monte Carlo check of the uncertainty budget - {name}"),
        &format!("s_r / {s0:.4e} m - 1 (%)"),
        &format!("draws per bin ({} in all)", mc.draws),
    )
    .with(Series::line(
        &format!("Monte Carlo draws (u = {:.3e} m)", mc.u_m),
        Rgb::BLUE,
        steps,
    ))
    .with(Series::line(
        &format!("the budget's distribution (u_c = {:.3e} m)", b.u_c_m),
        Rgb::RED,
        curve,
    ))
    .with(Series::dashed(
        "95 %: Monte Carlo quantiles",
        Rgb::BLUE,
        bars(mc.interval95_m),
    ))
    .with(Series::dashed(
        "95 %: s_r ± U",
        Rgb::RED,
        bars(b.interval95_m),
    ));
    fig("mc.svg", &c)
}

#[cfg(test)]
mod tests {
    #[test]
    fn degrees_of_freedom_read_as_a_reader_takes_them() {
        assert_eq!(super::dof(None), "∞");
        assert_eq!(super::dof(Some(16.4)), "16");
        assert_eq!(super::dof(Some(1000.0)), "1000");
        assert_eq!(super::dof(Some(152_064_263.0)), "> 1000");
        assert_eq!(super::dof(Some(f64::INFINITY)), "> 1000");
    }
}
