//! The unit tests of `fit/mod.rs`.

use super::*;
use crate::physics::incline_from_h_l;
use crate::series::AngleSeries;

fn pendulum(d: f64) -> Pendulum {
    Pendulum::solid_ball(0.03175, 1.0458, d, incline_from_h_l(0.142, 1.5), 9.81).unwrap()
}

fn sampled(p: &Pendulum, law: &FrictionLaw, fps: f64, dur: f64) -> AngleSeries {
    let opts = OdeOptions {
        t_end: dur,
        ..OdeOptions::default()
    };
    let tr = integrate(p, law, 0.0, [10f64.to_radians(), 0.0], &opts);
    let t: Vec<f64> = (0..(dur * fps) as usize).map(|i| i as f64 / fps).collect();
    let a = t.iter().map(|&x| 1.3 - tr.state(x)[0]).collect();
    AngleSeries::new(t, a)
}

#[test]
fn recovers_s_r_from_its_own_model() {
    let p = pendulum(0.1774);
    let law = FrictionLaw::new(3.714e-6, 1.0);
    let m = measure(&sampled(&p, &law, 60.0, 60.0)).unwrap();
    let r = fit(&p, &m, &FitOptions::default()).unwrap();
    assert!(
        ((r.s_r_m - law.s_r) / law.s_r).abs() < 1e-3,
        "{} vs {}",
        r.s_r_m,
        law.s_r
    );
    assert!(r.s_r_ci95_m[0] <= r.s_r_m && r.s_r_m <= r.s_r_ci95_m[1]);
    assert!(
        (r.d_from_period_m - p.d).abs() < 1e-3 * p.d,
        "{}",
        r.d_from_period_m
    );
    assert!((r.psi_eq_rad - 1.3).abs() < 1e-5);
    assert!(r.max_t_over_n > 0.0 && r.max_t_over_n < 0.01);
    assert!(r.reactions.n_variation_pct < 0.2);
}

#[test]
fn any_beta_recovers_its_own_s_r_and_compares_exponents() {
    let p = pendulum(0.195);
    // Same torque at rest as s_r = 5e-6 m with beta = 1.
    let n0 = p.rest_normal_force();
    let law = FrictionLaw::new(5e-6 / n0.sqrt(), 1.5);
    let series = sampled(&p, &law, 60.0, 60.0);
    let m = analyze(&p, &series, BetaChoice::Fixed(1.5)).unwrap();
    let opts = FitOptions {
        beta: BetaChoice::Fixed(1.5),
        compare_betas: true,
        ..FitOptions::default()
    };
    let r = fit(&p, &m, &opts).unwrap();
    assert!(
        ((r.s_r_m - law.s_r) / law.s_r).abs() < 1e-3,
        "{:e}",
        r.s_r_m
    );
    // N hardly varies, so every exponent fits with the same torque s_r N_0^beta:
    // the comparison reports them, and mu_r (the torque's lever arm) agrees.
    assert_eq!(r.beta_comparison.len(), 3);
    for c in &r.beta_comparison {
        let torque = c.s_r * n0.powf(c.beta);
        assert!((torque / (5e-6 * n0) - 1.0).abs() < 2e-3, "{c:?}");
    }
    assert!((r.mu_r - 5e-6 / p.r).abs() < 2e-3 * r.mu_r);
}

/// Released from rest at 10 deg at `t_rel` (held there before), sampled from 0.
fn held(p: &Pendulum, law: &FrictionLaw, fps: f64, dur: f64, t_rel: f64) -> AngleSeries {
    let opts = OdeOptions {
        t_end: dur,
        ..OdeOptions::default()
    };
    let tr = integrate(p, law, t_rel, [10f64.to_radians(), 0.0], &opts);
    let t: Vec<f64> = (0..(dur * fps) as usize).map(|i| i as f64 / fps).collect();
    let a = t.iter().map(|&x| 1.3 - tr.state(x)[0]).collect();
    AngleSeries::new(t, a)
}

/// Moves the samples within 0.15 s of the turning point nearest `near` outwards by
/// `deg` (a spoiled turning point); returns its time.
fn spoil(s: &mut AngleSeries, near: f64, deg: f64) -> f64 {
    let k = (0..s.len())
        .filter(|&i| (s.t[i] - near).abs() < 0.8)
        .max_by(|&i, &j| {
            (s.angle[i] - 1.3)
                .abs()
                .total_cmp(&(s.angle[j] - 1.3).abs())
        })
        .unwrap();
    let (tk, out) = (s.t[k], (s.angle[k] - 1.3).signum());
    for (t, a) in s.t.iter().zip(s.angle.iter_mut()) {
        if (t - tk).abs() <= 0.15 {
            *a += out * deg.to_radians();
        }
    }
    tk
}

#[test]
fn a_held_start_is_fitted_from_the_release() {
    let p = pendulum(0.1774);
    let law = FrictionLaw::new(3.714e-6, 1.0);
    let s = held(&p, &law, 60.0, 60.0, 1.0);
    let m = analyze(&p, &s, BetaChoice::Fixed(1.0)).unwrap();
    let r = m.release.expect("a held start");
    assert!((r.t_s - 1.0).abs() < 1e-3, "{r:?}");
    assert!(s.t[r.frame - 1] <= r.t_s && r.t_s < s.t[r.frame], "{r:?}");
    assert!(m.extremes[0].release && m.extremes.iter().skip(1).all(|e| !e.release));
    assert!((m.amplitudes[0] - 10f64.to_radians()).abs() < 1e-4);
    let f = fit(&p, &m, &FitOptions::default()).unwrap();
    assert!(
        ((f.s_r_m - law.s_r) / law.s_r).abs() < 1e-3,
        "{:e}",
        f.s_r_m
    );
    assert!((f.a_start_rad - 10f64.to_radians()).abs() < 1e-4);
    assert_eq!(f.release, m.release);
}

#[test]
fn one_bad_turning_point_is_dropped_and_named() {
    let p = pendulum(0.1774);
    let law = FrictionLaw::new(3.714e-6, 1.0);
    let mut s = sampled(&p, &law, 60.0, 60.0);
    let tk = spoil(&mut s, 50.0, 1.5);
    let m = analyze(&p, &s, BetaChoice::Fixed(1.0)).unwrap();
    let plain = fit(&p, &m, &FitOptions::default()).unwrap();
    let dev = |f: &FitResult| (f.s_r_m - law.s_r) / law.s_r;
    assert!(dev(&plain).abs() > 5e-3, "dragged: {:+.4}", dev(&plain));
    let (kept, f) = fit_robust(&p, &m, &FitOptions::default(), 0.0).unwrap();
    assert!(dev(&f).abs() < 1e-3, "{:+.5}", dev(&f));
    assert_eq!(f.outliers.len(), 1, "{:?}", f.outliers);
    let o = f.outliers[0];
    assert!(o.dropped && (o.t_s - tk).abs() < 0.05, "{o:?}");
    assert!(o.robust_z > OUTLIER_ROBUST_Z, "{o:?}");
    assert_eq!(kept.extremes.len(), m.extremes.len() - 1);
    assert_eq!(f.n_extremes, kept.extremes.len());
}

#[test]
fn a_clean_fit_drops_nothing_and_is_the_plain_fit() {
    let p = pendulum(0.1774);
    let law = FrictionLaw::new(3.714e-6, 1.0);
    let m = measure(&sampled(&p, &law, 60.0, 60.0)).unwrap();
    let f = fit(&p, &m, &FitOptions::default()).unwrap();
    let (kept, g) = fit_robust(&p, &m, &FitOptions::default(), 1e-3).unwrap();
    assert!(g.outliers.is_empty() && g.release.is_none());
    assert_eq!(kept.extremes, m.extremes);
    assert_eq!(g.s_r_m.to_bits(), f.s_r_m.to_bits());
    assert_eq!(g.residuals_rad, f.residuals_rad);
}

#[test]
fn more_outliers_than_the_cap_are_kept_and_named() {
    // About 18 turning points: one may be dropped.
    let p = pendulum(0.1774);
    let law = FrictionLaw::new(3.714e-6, 1.0);
    let mut s = sampled(&p, &law, 60.0, 30.0);
    for near in [8.0, 14.0, 20.0] {
        spoil(&mut s, near, 1.5);
    }
    let m = analyze(&p, &s, BetaChoice::Fixed(1.0)).unwrap();
    assert_eq!(outlier_cap(m.extremes.len()), 1, "{}", m.extremes.len());
    let (kept, f) = fit_robust(&p, &m, &FitOptions::default(), 0.0).unwrap();
    let dropped = f.outliers.iter().filter(|o| o.dropped).count();
    assert_eq!((dropped, f.outliers.len()), (1, 3), "{:?}", f.outliers);
    assert_eq!(kept.extremes.len(), m.extremes.len() - 1);
    assert!(f.outliers.windows(2).all(|w| w[0].t_s < w[1].t_s));
}

/// A ball that stops early under a camera that sways (seed 1's sweep scene 11: its
/// angles wander 0.45 deg either side at 0.58 Hz, the camera found moving only at 24 s
/// and steadied from then on, its angle then wandering by 0.05 deg and jumping 0.15 deg
/// aside in a frame of three, as a plain wall's misread motions make it; the ball at
/// rest from 23 s of 40): the ball at rest crosses the series' centre often and little,
/// and its many short lobes must not set the half swing the turning points are sought
/// with (they did: none was found, and the fit was refused).
#[test]
fn a_ball_at_rest_under_a_swaying_camera_leaves_the_half_swing_to_the_swing() {
    let p = pendulum(0.1831);
    let law = FrictionLaw::new(18.986e-6, 1.0);
    let still = sampled(&p, &law, 25.0, 40.0);
    let mut rng = crate::rng::Rng::new(11);
    let angle: Vec<f64> = still
        .t
        .iter()
        .zip(&still.angle)
        .map(|(&t, &a)| {
            let tau = std::f64::consts::TAU;
            let noise = 0.0165 * rng.normal();
            let (u, side) = (rng.uniform(), rng.uniform());
            let deg = if t < 24.0 {
                0.45 * (tau * 0.58 * t).sin() + noise
            } else {
                // Steadied: a slow wander, and a frame in three jumps 0.15 deg aside.
                let jump = if u < 0.3 {
                    0.15f64.copysign(side - 0.5)
                } else {
                    0.0
                };
                0.05 * (tau * 0.75 * t + 1.0).sin() + noise + jump
            };
            a + deg.to_radians()
        })
        .collect();
    let swaying = AngleSeries::new(still.t.clone(), angle);
    let truth = measure(&still).unwrap();
    let m = measure(&swaying).unwrap();
    // The ball stops about its last turning point (the still series': 22 s).
    let last = truth.extremes.last().unwrap().t;
    assert!((20.0..24.0).contains(&last), "{last}");
    let stop = m.stop.expect("the ball at rest is told");
    assert!(
        (last - 1.0..last + 2.0).contains(&stop.t_s),
        "{stop:?} after {last} s"
    );
    assert!(
        m.extremes.len() >= 10,
        "{} turning points",
        m.extremes.len()
    );
    assert!(
        (m.period_s - truth.period_s).abs() < 0.02 * truth.period_s,
        "{} s against {} s",
        m.period_s,
        truth.period_s
    );
}

/// The angles seed 1205's sweep scene 33 was measured at (`tests/fit_series/
/// handheld_rest.csv`: 1280x720 at 25 frames/s, hand-held 3.2 px and 0.48 deg at 3.8
/// Hz, steadied, 0.15 deg RMS off the truth; copper, the ball at rest from 22 s of
/// 40). The ball at rest wanders across the centre a few times a second, and its lobes
/// set the median gap of every lobe at 0.84 s, half the swing's 1.68, without leaving
/// the windows too short to hold a turning point's samples: 2 turning points were found
/// and the fit was refused. Those windows find too few, and the swing's own half swing
/// finds 12 ([`measure`]); with them the period is the twin's (3.377 s).
#[test]
fn a_hand_held_ball_at_rest_is_measured_over_the_swing_own_half_swing() {
    let text = include_str!("../../tests/fit_series/handheld_rest.csv");
    let series = AngleSeries::parse_csv(text).unwrap();
    assert_eq!(series.t.len(), 1001);
    let every = crate::signal::find_extremes(&series).unwrap();
    assert!(
        every.len() < MIN_EXTREMES,
        "{} found over every lobe's half swing",
        every.len()
    );
    let m = measure(&series).unwrap();
    assert!(
        m.extremes.len() >= 10,
        "{} turning points",
        m.extremes.len()
    );
    let stop = m.stop.expect("the ball at rest is told");
    assert!((21.0..25.0).contains(&stop.t_s), "{stop:?}");
    assert!((m.period_s - 3.377).abs() < 0.02, "{} s", m.period_s);
}

#[test]
fn rejects_too_few_turning_points() {
    let p = pendulum(0.1774);
    let law = FrictionLaw::new(60e-6, 1.0);
    let err = measure(&sampled(&p, &law, 30.0, 20.0)).unwrap_err();
    assert!(format!("{err:#}").contains("turning point"), "{err:#}");
}

/// A twin in air with a known, constant drag coefficient: the fit with the air
/// modelled recovers the truth; the paper's model (no air) reads the air's damping as
/// rolling friction, and `air` says by how much.
#[test]
fn air_with_a_known_drag_coefficient_is_taken_out_of_s_r() {
    use crate::physics::air::{Air, DragLaw};
    let air = Air {
        law: DragLaw::Constant(0.7),
        ..Air::at(20.0, 101_325.0)
    };
    let p = pendulum(0.1774).with_air(Some(air));
    let law = FrictionLaw::new(3.714e-6, 1.0);
    let m = measure(&sampled(&p, &law, 60.0, 60.0)).unwrap();
    let r = fit(&p, &m, &FitOptions::default()).unwrap();
    let rel = (r.s_r_m - law.s_r) / law.s_r;
    assert!(rel.abs() < 2e-4, "with the air: {rel:e}");
    let a = r.air.expect("the air's share");
    let bare = fit(&p.with_air(None), &m, &FitOptions::default()).unwrap();
    assert!((a.s_r_without_air_m / bare.s_r_m - 1.0).abs() < 1e-6);
    assert!(bare.air.is_none());
    // The paper's model reads the drag as friction: s_r too large by about the air's
    // share of the energy (0.1-0.3 % for glass at 10 degrees).
    let bias = (bare.s_r_m - law.s_r) / law.s_r;
    assert!(bias > 1e-3 && bias < 4e-3, "without the air: {bias:e}");
    assert!(
        (a.correction_pct / 100.0 + bias / (1.0 + bias)).abs() < 2e-4,
        "{} vs {bias}",
        a.correction_pct
    );
    assert!(a.energy_share_pct > 0.1 && a.energy_share_pct < 0.4);
    assert!(a.reynolds_max > 150.0 && a.reynolds_max < 350.0);
}

/// A drag five times the curve's, fitted as a scale besides `s_r` from a long run.
#[test]
fn a_drag_scale_is_fitted_when_asked() {
    use crate::physics::air::Air;
    let air = Air {
        scale: 5.0,
        ..Air::at(20.0, 101_325.0)
    };
    let p = pendulum(0.1774).with_air(Some(air));
    let law = FrictionLaw::new(1.0e-6, 1.0);
    let m = measure(&sampled(&p, &law, 60.0, 90.0)).unwrap();
    let start = p.with_air(Some(Air::at(20.0, 101_325.0)));
    let (k, se) = fit_drag_scale(&start, &m, 1.0, 1e-7).unwrap();
    assert!((k - 5.0).abs() < 0.05, "{k} +- {se}");
    assert!(se > 0.0 && se < 0.5, "{se}");
}

#[test]
fn a_release_followed_by_a_gap_keeps_its_amplitude() {
    // The ball let go at 1 s, then the wire seen for 0.35 s only (a hand in front, a
    // moving camera's steadying lost) until after the next turning point, at 2.7 s: the
    // release's window holds the hold and a short stretch of motion, whose curvature
    // alone cannot tell the amplitude from the local equilibrium. Over twelve draws of
    // a sweep twin's noise the refitted amplitude was up to 0.28 deg off (s_r 2.3 %).
    let p = pendulum(0.1774);
    let law = FrictionLaw::new(3.714e-6, 1.0);
    let clean = held(&p, &law, 60.0, 40.0, 1.0);
    for seed in 0..12 {
        let mut rng = crate::rng::Rng::new(seed);
        let (mut t, mut a) = (Vec::new(), Vec::new());
        for (&ti, &ai) in clean.t.iter().zip(&clean.angle) {
            if !(1.35..3.0).contains(&ti) {
                t.push(ti);
                a.push(ai + 0.017f64.to_radians() * rng.normal());
            }
        }
        let s = AngleSeries::new(t, a);
        let m = analyze(&p, &s, BetaChoice::Fixed(1.0)).unwrap();
        assert!(m.extremes[0].release);
        let off = (m.amplitudes[0] - 10f64.to_radians()).to_degrees();
        assert!(
            off.abs() < 0.02,
            "seed {seed}: release amplitude {off:.4} deg off"
        );
        let f = fit(&p, &m, &FitOptions::default()).unwrap();
        let err = f.s_r_m / law.s_r - 1.0;
        assert!(
            err.abs() < 0.003,
            "seed {seed}: s_r {:+.3} % off",
            err * 100.0
        );
    }
}
