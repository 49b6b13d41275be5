//! The unit tests of `uncertainty.rs`.

use super::*;
use crate::fit::{analyze, fit, FitOptions};
use crate::physics::ode::{integrate, OdeOptions};
use crate::physics::{BetaChoice, FrictionLaw};
use crate::series::AngleSeries;

const GLASS: &str = "geometry:\n  incline: { h_m: 0.142, l_m: 1.500 }\n  pendulum: { d_m: 0.1774 }\n  ball: { radius_m: 0.03175, mass_kg: 1.0458 }\n";

fn experiment(extra: &str) -> Experiment {
    Experiment::parse(
        std::path::Path::new("glass.yaml"),
        &format!("{GLASS}{extra}"),
    )
    .unwrap()
}

/// The model's angles at 25 frames/s for 60 s, with Gaussian noise `noise_rad`
/// (seeded), measured and fitted.
fn fitted(exp: &Experiment, noise_rad: f64) -> (Measurement, FitResult) {
    let p = &exp.pendulum;
    let law = FrictionLaw::new(3.714e-6, 1.0);
    let tr = integrate(
        p,
        &law,
        0.0,
        [10f64.to_radians(), 0.0],
        &OdeOptions {
            t_end: 60.0,
            ..OdeOptions::default()
        },
    );
    let mut rng = Rng::new(7);
    let t: Vec<f64> = (0..1500).map(|i| i as f64 / 25.0).collect();
    let a = t
        .iter()
        .map(|&x| 1.3 - tr.state(x)[0] + noise_rad * rng.normal())
        .collect();
    let m = analyze(p, &AngleSeries::new(t, a), BetaChoice::Fixed(1.0)).unwrap();
    let f = fit(p, &m, &FitOptions::default()).unwrap();
    (m, f)
}

/// The fit and budget of the model's noiseless angles.
fn noiseless_budget(exp: &Experiment) -> (FitResult, Budget) {
    let (m, f) = fitted(exp, 0.0);
    let a = angle_uncertainty(&exp.pendulum, &m, &f, None);
    let b = budget(exp, &m, &f, a, None, None).unwrap();
    (f, b)
}

/// The sensitivity coefficient of the budget's quantity `q`.
fn sensitivity(b: &Budget, q: &str) -> f64 {
    b.components
        .iter()
        .find(|c| c.quantity == q)
        .unwrap()
        .sensitivity
}

#[test]
fn welch_satterthwaite_by_hand() {
    // u_c = sqrt(2), one part with 4 dof: nu = 4 / (1/4) = 16 (JCGM 100 G.4.1).
    let nu = welch_satterthwaite(2f64.sqrt(), &[(1.0, Some(4.0)), (1.0, None)]).unwrap();
    assert!((nu - 16.0).abs() < 1e-12, "{nu}");
    assert_eq!(welch_satterthwaite(1.0, &[(1.0, None)]), None);
    assert!((coverage_factor(None) - 1.96).abs() < 1e-3);
    assert!((coverage_factor(Some(16.0)) - 2.120).abs() < 1e-3);
}

#[test]
fn sensitivities_agree_with_the_small_angle_relation() {
    // For beta = 1 the drop per half swing is 2 s_r N_0 / (m g r sin(alpha))
    // (ERRATA §2) with N_0 = m g (cos(alpha) + sin(alpha) tan(delta)): for fixed
    // amplitudes s_r does not depend on m or g, and
    // d ln s_r / d alpha = cot(alpha) + (sin(alpha) - cos(alpha) tan(delta)) / (cos(alpha) + sin(alpha) tan(delta)).
    let exp = experiment("");
    let (f, b) = noiseless_budget(&exp);
    let c = |q: &str| sensitivity(&b, q);
    let s = f.s_r_m;
    // In air a heavier ball loses less to the drag: `s_r = D - k F_d / m` for a
    // measured decrement `D`, so `(m / s_r) ds_r/dm` is the air's correction.
    let correction = f.air.expect("in air").correction_pct / 100.0;
    let got_m = c("m") * 1.0458 / s;
    assert!(
        (got_m + correction).abs() < 0.3 * correction.abs(),
        "m: {got_m} against the air's {correction}"
    );
    // The paper's model, in a vacuum: s_r does not depend on m or g.
    let exp = experiment("air: { model: none }\n");
    let (f, b) = noiseless_budget(&exp);
    assert!(f.air.is_none());
    assert!(b.components.iter().all(|c| !c.key.starts_with("air.")));
    let c = |q: &str| sensitivity(&b, q);
    let s = f.s_r_m;
    assert!((c("m") * 1.0458 / s).abs() < 1e-4, "m: {}", c("m"));
    assert!((c("g") * 9.81 / s).abs() < 1e-4, "g: {}", c("g"));
    let p = &exp.pendulum;
    let (sa, ca, td) = (p.alpha.sin(), p.alpha.cos(), p.delta.tan());
    let dln_dalpha = ca / sa + (sa - ca * td) / (ca + sa * td);
    // alpha = asin(h / l): d alpha / d h = 1 / (l cos(alpha)).
    let expected = dln_dalpha / (1.5 * ca);
    let got = c("h") / s;
    assert!(
        (got / expected - 1.0).abs() < 0.02,
        "d ln s_r / d h: {got} vs {expected}"
    );
    // The budget: defaults, every part counted once, U = k u_c.
    assert_eq!(b.components.len(), 6 + 3);
    let sum: f64 = b.components.iter().map(|c| c.contribution_m.powi(2)).sum();
    assert!((sum.sqrt() - b.u_c_m).abs() < 1e-15);
    assert!((b.expanded_m - b.k * b.u_c_m).abs() < 1e-18);
    let h = b.components.iter().find(|c| c.quantity == "h").unwrap();
    assert_eq!(h.distribution, Distribution::Rectangular);
    assert!((h.u - 1e-3 / (2.0 * 3f64.sqrt())).abs() < 1e-12);
}

#[test]
fn a_given_uncertainty_replaces_the_default() {
    let exp = experiment("  uncertainty: { d_m: 0.002, g_m_s2: 0 }\n");
    let (m, f) = fitted(&exp, 0.0);
    let a = angle_uncertainty(&exp.pendulum, &m, &f, None);
    let b = budget(&exp, &m, &f, a.clone(), None, None).unwrap();
    let d = b.components.iter().find(|c| c.quantity == "d").unwrap();
    assert_eq!((d.u, d.distribution), (0.002, Distribution::Normal));
    let g = b.components.iter().find(|c| c.quantity == "g").unwrap();
    assert_eq!(g.contribution_m, 0.0);
}

#[test]
fn a_lens_adds_its_share_of_the_swing_scale() {
    let exp = experiment("");
    let (m, f) = fitted(&exp, 0.0);
    let a = angle_uncertainty(&exp.pendulum, &m, &f, None);
    let plain = budget(&exp, &m, &f, a.clone(), None, None).unwrap();
    let lens = LensScale {
        u_rel: 0.004,
        k1: -0.2,
        u_k1: 0.01,
    };
    let b = budget(&exp, &m, &f, a, None, Some(&lens)).unwrap();
    let c = b.components.iter().find(|c| c.key == "video.lens").unwrap();
    assert!((c.contribution_m - 0.004 * f.s_r_m.abs()).abs() < 1e-18);
    assert!(c.adds_to_s_r());
    // In quadrature with the rest.
    let expect = (plain.u_c_m.powi(2) + c.contribution_m.powi(2)).sqrt();
    assert!((b.u_c_m - expect).abs() < 1e-15 * expect);
}

#[test]
fn the_angles_share_holds_the_detector_scale_and_grows_with_noise() {
    let exp = experiment("");
    let p = &exp.pendulum;
    let (m, f) = fitted(&exp, 0.0);
    let quiet = angle_uncertainty(p, &m, &f, None);
    // Noise-free angles: the scale alone.
    assert!((quiet.u_scale_m / f.s_r_m - DETECTOR_SCALE_REL).abs() < 1e-12);
    assert!(quiet.u_m >= quiet.u_scale_m);
    let [lo, hi] = quiet.interval95_m;
    assert!((hi - lo) / 2.0 - quiet.k * quiet.u_m < 1e-18);
    // A swing scale 1 % off widens it.
    let off = angle_uncertainty(p, &m, &f, Some(1.01));
    assert!(off.scale_rel > 0.005, "{}", off.scale_rel);
    // Noisy angles: the statistics grow, and the block bootstrap is at least the
    // least-squares standard error.
    let (m2, f2) = fitted(&exp, 0.2f64.to_radians());
    let noisy = angle_uncertainty(p, &m2, &f2, None);
    assert!(noisy.u_stat_m >= f2.s_r_se_m);
    assert!(
        noisy.u_stat_m > 10.0 * quiet.u_stat_m,
        "{noisy:?} {quiet:?}"
    );
    assert_eq!(noisy.dof_stat, (m2.amplitudes.len() - 2) as f64);
}

#[test]
fn the_monte_carlo_check_agrees_with_the_budget() {
    let exp = experiment("");
    let (m, f) = fitted(&exp, 0.05f64.to_radians());
    let a = angle_uncertainty(&exp.pendulum, &m, &f, None);
    let b = budget(&exp, &m, &f, a.clone(), None, None).unwrap();
    let mut calls = 0;
    let mc = monte_carlo(&exp, &m, &f, &b, 1000, 1, &mut |_| calls += 1).unwrap();
    assert_eq!(calls, 1000);
    assert!((mc.u_ratio - 1.0).abs() < 0.1, "{}", mc.u_ratio);
    assert!((mc.mean_m / f.s_r_m - 1.0).abs() < 0.2 * b.u_c_m / f.s_r_m);
    assert!(mc.interval95_m[0] < f.s_r_m && f.s_r_m < mc.interval95_m[1]);
    assert_eq!(mc.histogram.counts.iter().sum::<usize>(), 1000);
    // The same seed, the same draws.
    let again = monte_carlo(&exp, &m, &f, &b, 1000, 1, &mut |_| {}).unwrap();
    assert_eq!(mc, again);
}

#[test]
fn a_group_by_hand() {
    let run = |s: f64| Run {
        name: format!("r{s}"),
        d_m: 0.2,
        s_r_m: s,
        u_angles_m: 1.0,
        u_c_m: 5f64.sqrt(),
    };
    let g = group("x", vec![run(1.0), run(2.0), run(3.0)]);
    assert_eq!(g.mean_m, 2.0);
    assert!((g.sd_m - 1.0).abs() < 1e-12);
    assert!((g.u_mean_m - 1.0 / 3f64.sqrt()).abs() < 1e-12);
    // u_c^2 - u_angles^2 = 4 for every run.
    assert!((g.u_geometry_m - 2.0).abs() < 1e-12);
    assert!((g.chi2 - 2.0).abs() < 1e-12 && (g.birge_ratio - 1.0).abs() < 1e-12);
    assert!(g.consistent);
    // Runs 10 of their uncertainties apart are not.
    let g = group("x", vec![run(0.0), run(10.0), run(20.0)]);
    assert!(g.birge_ratio > 9.0 && !g.consistent);
}
