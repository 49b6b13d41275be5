//! The unit tests of `verdict.rs`.

use super::*;

const LIM: Limits = Limits {
    period_rel: 0.1,
    residual_factor: 5.0,
    envelope_aicc: 10.0,
    halves_rel: 0.02,
    interval_rel: 0.25,
    outliers: 0,
    pivot_rel: 0.02,
    scale_rel: 0.005,
};

fn evidence<'a>(t: &'a [f64], amps: &'a [f64], samples: &'a [usize]) -> Evidence<'a> {
    Evidence {
        d_m: 0.2,
        d_from_period_m: 0.201,
        frame_noise_rad: 1e-3,
        samples,
        t,
        amplitudes: amps,
        residual_rms_rad: 5e-5,
        s_r: 4e-6,
        s_r_ci95: [3.9e-6, 4.1e-6],
        s_r_halves: Some([4.01e-6, 3.99e-6]),
        outliers_dropped: &[],
        outliers_kept: &[],
        outlier_cap: 4,
        swing_scale: Some(1.004),
        scale_u_rel: Some(0.001),
    }
}

#[test]
fn a_consistent_linear_decay_is_ok() {
    let t: Vec<f64> = (0..40).map(|k| 0.7 * k as f64).collect();
    let a: Vec<f64> = t
        .iter()
        .enumerate()
        .map(|(k, x)| 0.17 - 3e-3 * x + 1e-5 * if k % 2 == 0 { 1.0 } else { -1.0 })
        .collect();
    let s = vec![60; 40];
    let v = assess(&evidence(&t, &a, &s), &LIM);
    assert_eq!(v, Verdict::default(), "{v:?}");
    assert_eq!(v.label(), "ok");
}

#[test]
fn each_disagreement_is_named() {
    let t: Vec<f64> = (0..40).map(|k| 0.7 * k as f64).collect();
    let a: Vec<f64> = t.iter().map(|x| 0.17 * (-x / 8.0f64).exp()).collect();
    let s = vec![60; 40];
    let mut e = evidence(&t, &a, &s);
    e.d_from_period_m = 0.03;
    e.residual_rms_rad = 1e-2;
    e.s_r_ci95 = [-1e-6, 9e-6];
    e.swing_scale = Some(1.05);
    e.s_r_halves = Some([4.1e-6, 3.9e-6]);
    e.scale_u_rel = Some(0.024);
    let mut v = assess(&e, &LIM);
    let names: Vec<&str> = v.warnings.iter().map(|w| w.check.as_str()).collect();
    assert_eq!(
        names,
        ["period", "residual", "envelope", "halves", "interval", "pivot", "scale"]
    );
    for w in &v.warnings {
        assert!(!w.reason.contains("  "), "{}: {}", w.check, w.reason);
    }
    // 0.2e-6 apart on an s_r of 4e-6: 5 %.
    let h = &v.warnings[3];
    assert!((h.value - 0.05).abs() < 1e-12 && h.limit == 0.02, "{h:?}");
    assert!(h.reason.contains("5.0 % apart"), "{}", h.reason);
    assert_eq!(v.verdict, Status::Suspect);
    assert!(v.blocks());
    v.accept([("period", "the length was not measured")]);
    assert!(v.blocks());
    assert!(v.label().contains("accepted: period"), "{}", v.label());
    e.s_r_ci95 = [1e-6, 7e-6];
    let w = &assess(&e, &LIM).warnings[4];
    assert!((w.value - 0.75).abs() < 1e-12, "{w:?}");
}

/// Forty turning points 0.7 s apart decaying linearly from 0.17 rad, and the samples
/// behind each.
fn linear_decay() -> (Vec<f64>, Vec<f64>, Vec<usize>) {
    let t: Vec<f64> = (0..40).map(|k| 0.7 * k as f64).collect();
    let a: Vec<f64> = t.iter().map(|x| 0.17 - 3e-3 * x).collect();
    (t, a, vec![60; 40])
}

#[test]
fn a_pivot_off_along_the_wire_is_named_either_way() {
    let (t, a, s) = linear_decay();
    let mut e = evidence(&t, &a, &s);
    for (scale, word) in [(0.97, "less"), (1.03, "more")] {
        e.swing_scale = Some(scale);
        let v = assess(&e, &LIM);
        assert_eq!(v.warnings.len(), 1, "{v:?}");
        let w = &v.warnings[0];
        assert_eq!(w.check, "pivot");
        assert!((w.value - 0.03).abs() < 1e-12 && w.limit == 0.02, "{w:?}");
        assert!(w.reason.contains(&format!("3.0 % {word}")), "{}", w.reason);
    }
    // Within the limit, or not measured (an angle CSV): nothing to say.
    for scale in [Some(1.019), Some(0.981), None] {
        e.swing_scale = scale;
        assert!(assess(&e, &LIM).warnings.is_empty(), "{scale:?}");
    }
}

/// A lens fitted from too few lines (the sweep's `u_k1` 0.06 on a `k1` of -0.13: 2.4 %
/// on the swing's scale) is named; a well-fitted one, or angles measured with no lens
/// or calibration, say nothing.
#[test]
fn a_loosely_known_scale_is_named() {
    let (t, a, s) = linear_decay();
    let mut e = evidence(&t, &a, &s);
    e.scale_u_rel = Some(0.024);
    let v = assess(&e, &LIM);
    assert_eq!(v.warnings.len(), 1, "{v:?}");
    let w = &v.warnings[0];
    assert_eq!(
        (w.check.as_str(), w.value, w.limit),
        ("scale", 0.024, 0.005)
    );
    assert!(w.reason.contains("+/- 2.40 % only"), "{}", w.reason);
    assert_eq!(v.verdict, Status::Suspect);
    for u in [Some(0.005), Some(0.0), None] {
        e.scale_u_rel = u;
        assert!(assess(&e, &LIM).warnings.is_empty(), "{u:?}");
    }
}

#[test]
fn the_exponential_fit_finds_its_rate() {
    let t: Vec<f64> = (0..30).map(|k| 0.5 * k as f64).collect();
    let a: Vec<f64> = t.iter().map(|x| 0.2 * (-x / 5.0f64).exp()).collect();
    let (rss, k) = exponential_rss(&t, &a);
    assert!(rss < 1e-16 && (k - 0.2).abs() < 1e-6, "{rss} {k}");
    assert!(linear_rss(&t, &a) > 1e-4);
}

#[test]
fn degrees_are_suspected() {
    let rad: Vec<f64> = (0..100).map(|i| 1.6 + 0.17 * (i as f64).sin()).collect();
    assert_eq!(degrees_suspected(&rad, 1.6), None);
    let deg: Vec<f64> = rad.iter().map(|v| v.to_degrees()).collect();
    assert!(degrees_suspected(&deg, 91.7)
        .unwrap()
        .contains("are these degrees?"));
    let small: Vec<f64> = (0..100).map(|i| 91.7 + 1.0 * (i as f64).sin()).collect();
    assert!(degrees_suspected(&small, 91.7).is_some());
}

#[test]
fn the_verdict_comes_from_the_numbers() {
    let mut c = Check::new(Quantity::SR, Against::SyntheticTruth, 1.01, 1.0, 0.02);
    assert!(c.pass && c.verdict());
    c.value = 1.05;
    assert!(c.pass && !c.verdict(), "a stale pass flag is not trusted");
    let nan = Check::new(Quantity::A, Against::SyntheticTruth, f64::NAN, 1.0, 0.02);
    assert!(!nan.verdict());
}

#[test]
fn serialises_as_the_plain_names() {
    let c = Check::new(
        Quantity::MuR,
        Against::Reference("Table 1".into()),
        1.0,
        1.0,
        0.1,
    );
    let j = serde_json::to_string(&c).unwrap();
    assert!(
        j.starts_with(r#"{"quantity":"mu_r","against":"Table 1","#),
        "{j}"
    );
    let back: Check = serde_json::from_str(&j).unwrap();
    assert_eq!(back.against, Against::Reference("Table 1".into()));
    let t: Against = serde_json::from_str(r#""synthetic truth""#).unwrap();
    assert_eq!(t, Against::SyntheticTruth);
}
