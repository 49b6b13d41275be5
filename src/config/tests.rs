//! The experiment file's and the manifest's validation, case by case.

use super::*;

const GOOD: &str = "
geometry:
  incline: { h_m: 0.142, l_m: 1.5 }
  pendulum: { d_m: 0.14 }
  ball: { radius_m: 0.03175, mass_kg: 1.0458 }
synthetic: { s_r_m: 3.2e-6 }
";

#[test]
fn a_name_is_a_file_here_first_then_one_in_experiments() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("experiments")).unwrap();
    std::fs::write(d.join("experiments/green.yaml"), "").unwrap();
    assert_eq!(locate_in(d, "green"), d.join("experiments/green.yaml"));
    std::fs::write(d.join("green.yaml"), "").unwrap();
    assert_eq!(locate_in(d, "green"), d.join("green.yaml"));
    // A path is taken as given, found or not.
    assert_eq!(locate_in(d, "lab/blue.yaml"), d.join("lab/blue.yaml"));
    assert_eq!(locate_in(d, "red"), d.join("experiments/red.yaml"));
}

fn err(text: &str) -> String {
    format!(
        "{:#}",
        Experiment::parse(Path::new("x/glass.yaml"), text).unwrap_err()
    )
}

#[test]
fn parses_a_minimal_experiment_with_defaults() {
    let e = Experiment::parse(Path::new("x/glass.yaml"), GOOD).unwrap();
    assert_eq!(e.name, "glass");
    assert!((e.pendulum.alpha.to_degrees() - 5.432).abs() < 1e-3);
    assert_eq!(e.beta, BetaChoice::Fixed(1.0));
    let s = e.file.synthetic.as_ref().unwrap();
    assert_eq!((s.fps, s.psi0_deg, s.seed), (60.0, 10.0, 1));
    assert_eq!(e.file.geometry.g_m_s2, 9.81);
}

#[test]
fn contact_length_and_density_are_alternatives() {
    let text = GOOD
        .replace("d_m: 0.14", "contact_length_m: 0.13632")
        .replace("mass_kg: 1.0458", "density_kg_m3: 7800");
    let e = Experiment::parse(Path::new("g.yaml"), &text).unwrap();
    assert!((e.pendulum.d - 0.14).abs() < 1e-4);
    assert!((e.pendulum.m - 1.0458).abs() < 0.01);
}

#[test]
fn the_working_side_is_read_and_one_out_of_range_is_refused_by_its_key() {
    let with = |side: &str| format!("{GOOD}video:\n  work_side_px: {side}\n");
    let e = Experiment::parse(Path::new("g.yaml"), &with("1280")).unwrap();
    assert_eq!(e.file.video.as_ref().unwrap().work_side_px, Some(1280));
    let e = Experiment::parse(Path::new("g.yaml"), GOOD).unwrap();
    assert!(e.file.video.is_none());
    for bad in ["320", "9000"] {
        let e = err(&with(bad));
        assert!(
            e.contains(&format!("`video.work_side_px` = {bad} px"))
                && e.contains("640 (the default) to 8192"),
            "{e}"
        );
    }
}

#[test]
fn a_plate_calibration_needs_four_points_that_fix_a_homography() {
    let with = |pts: &str| format!("{GOOD}video:\n  calibration:\n    points: [{pts}]\n");
    let p = |i: [f64; 2], q: [f64; 2]| {
        format!(
            "{{image: [{}, {}], plate: [{}, {}]}}",
            i[0], i[1], q[0], q[1]
        )
    };
    let square = [
        p([100.0, 100.0], [0.0, 0.0]),
        p([300.0, 110.0], [60.0, 0.0]),
        p([290.0, 300.0], [60.0, 60.0]),
        p([110.0, 290.0], [0.0, 60.0]),
    ];
    let e = Experiment::parse(Path::new("g.yaml"), &with(&square.join(", "))).unwrap();
    let c = e.calibration.unwrap();
    assert_eq!((c.image.len(), c.dof), (4, 0));
    let e = err(&with(&square[..3].join(", ")));
    assert!(
        e.contains("`video.calibration.points`: 3 point(s)") && e.contains("four"),
        "{e}"
    );
    let line = [
        p([0.0, 0.0], [0.0, 0.0]),
        p([10.0, 10.0], [1.0, 0.0]),
        p([20.0, 20.0], [2.0, 0.0]),
        p([30.0, 30.0], [3.0, 0.0]),
    ];
    let e = err(&with(&line.join(", ")));
    assert!(
        e.contains("`video.calibration.points`") && e.contains("on a line"),
        "{e}"
    );
    let e = err(&format!("{}    u_px: -1\n", with(&square.join(", "))));
    assert!(e.contains("video.calibration.u_px"), "{e}");
}

#[test]
fn a_tilted_twin_is_not_mirrored() {
    let e = err(&GOOD.replace(
        "synthetic: { s_r_m: 3.2e-6 }",
        "synthetic: { s_r_m: 3.2e-6, camera_tilt_deg: 20, mirror: true }",
    ));
    assert!(
        e.contains("`synthetic.camera_tilt_deg` = 20 with `synthetic.mirror`"),
        "{e}"
    );
    let e = err(&GOOD.replace(
        "synthetic: { s_r_m: 3.2e-6 }",
        "synthetic: { s_r_m: 3.2e-6, camera_tilt_deg: 50 }",
    ));
    assert!(e.contains("synthetic.camera_tilt_deg"), "{e}");
}

#[test]
fn unknown_key_is_named() {
    let e = err(&GOOD.replace("d_m: 0.14", "d_m: 0.14, dd: 1"));
    assert!(
        e.contains("unknown field `dd`, expected one of d_m, contact_length_m"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
}

#[test]
fn a_wider_tolerance_needs_a_reason_and_text_is_bounded() {
    let wide = format!("{GOOD}tolerances: {{ period_rel: 100, halves_rel: 100 }}\n");
    let e = err(&wide);
    assert!(
        e.contains("`tolerances.period_rel` = 100: wider than its default 0.1"),
        "{e}"
    );
    let given = wide.replace("100 }", "100, reason: \"d measured by eye\" }");
    let exp = Experiment::parse(Path::new("x.yaml"), &given).unwrap();
    let keys: Vec<&str> = exp.file.tolerances.widened().iter().map(|w| w.0).collect();
    assert_eq!(keys, ["period_rel", "halves_rel"]);
    // Narrower than the defaults needs no reason.
    let narrow = format!("{GOOD}tolerances: {{ period_rel: 0.05 }}\n");
    assert!(Experiment::parse(Path::new("x.yaml"), &narrow).is_ok());
    let huge = format!("{GOOD}material: \"{}\"\n", "x".repeat(10_000));
    let e = err(&huge);
    assert!(
        e.contains("`material`") && e.contains("10000 characters"),
        "{e}"
    );
    assert!(e.len() < 200, "{e}");
}

#[test]
fn a_file_of_another_kind_is_not_quoted() {
    let e = err("root:x:0:0:root:/root:/bin/bash\nsecret: 1\n");
    assert!(
        e.contains("not an experiment file") && !e.contains("root"),
        "{e}"
    );
}

#[test]
fn bad_values_name_key_value_and_expectation() {
    let e = err(&GOOD.replace("d_m: 0.14", "d_m: 0.02"));
    assert!(
        e.contains("`geometry.pendulum.d_m` = 0.02 m must exceed the ball radius 0.03175 m"),
        "{e}"
    );
    let e = err(&GOOD.replace("mass_kg: 1.0458", "mass_kg: -1"));
    assert!(
        e.contains("`geometry.ball.mass_kg` = -1 kg: expected a positive number"),
        "{e}"
    );
    let e = err(&GOOD.replace("radius_m: 0.03175", "radius_m: 0"));
    assert!(e.contains("`geometry.ball.radius_m` = 0"), "{e}");
    let e = err(&GOOD.replace("d_m: 0.14", "d_m: 1e300"));
    assert!(
        e.contains("`geometry.pendulum.d_m` = 1e300 m: expected at most 100 m"),
        "{e}"
    );
    let e = err(&GOOD.replace("mass_kg: 1.0458", "mass_kg: 1e9"));
    assert!(e.contains("`geometry.ball.mass_kg`"), "{e}");
    let e = err(&format!("{GOOD}accept: [{{check: periodd, reason: x}}]\n"));
    assert!(e.contains("`accept[0].check` = `periodd`"), "{e}");
    let e = err(&format!(
        "{GOOD}accept: [{{check: period, reason: \"\"}}]\n"
    ));
    assert!(e.contains("needs a written reason"), "{e}");
    let e = err(&GOOD.replace("{ h_m: 0.142, l_m: 1.5 }", "{ h_m: 0.142, angle_deg: 5 }"));
    assert!(e.contains("`geometry.incline`"), "{e}");
    let e = err(&format!("{GOOD}model: {{ beta: fast }}\n"));
    assert!(e.contains("`model.beta` = `fast`"), "{e}");
}

/// `GOOD` with `extra` keys in its `synthetic:` block.
fn synthetic_with(extra: &str) -> String {
    GOOD.replace(
        "synthetic: { s_r_m: 3.2e-6 }",
        &format!("synthetic: {{ s_r_m: 3.2e-6, {extra} }}"),
    )
}

#[test]
fn other_cameras_conditions_are_checked_naming_the_key() {
    let text = synthetic_with(
        "mirror: true, wire_width_px: 1, wire_contrast: 0.25, shadow: { blur_px: 2 }",
    );
    let e = Experiment::parse(Path::new("x/glass.yaml"), &text).unwrap();
    let s = e.file.synthetic.unwrap();
    assert!(s.mirror);
    assert_eq!((s.wire_width_px, s.wire_contrast), (Some(1.0), Some(0.25)));
    let sh = s.shadow.unwrap();
    assert_eq!((sh.angle_deg, sh.blur_px, sh.strength), (3.0, 2.0, 0.5));
    assert_eq!(sh.lamp_share, None);
    for (extra, want) in [
            (
                "wire_width_px: 0.5",
                "`synthetic.wire_width_px` = 0.5 px: expected a value from 1 to 32 px",
            ),
            (
                "wire_contrast: 1.5",
                "`synthetic.wire_contrast` = 1.5 : expected a value from 0 to 1",
            ),
            ("wire_contrast: .nan", "`synthetic.wire_contrast` = NaN"),
            (
                "shadow: { angle_deg: 60 }",
                "`synthetic.shadow.angle_deg` = 60 deg: expected a value from -45 to 45 deg",
            ),
            (
                "shadow: { blur_px: -1 }",
                "`synthetic.shadow.blur_px` = -1 px",
            ),
            (
                "shadow: { strength: 2 }",
                "`synthetic.shadow.strength` = 2 :",
            ),
            (
                "shadow: { lamp_share: 1.2 }",
                "`synthetic.shadow.lamp_share` = 1.2 :",
            ),
            ("shadow: { streng: 2 }", "unknown field `streng`"),
            (
                "flicker_hz: 0",
                "`synthetic.flicker_hz` = 0 Hz: expected a positive number",
            ),
            ("flicker_hz: 2e4", "`synthetic.flicker_hz` = 20000 Hz"),
            (
                "flicker_depth: 0.6",
                "`synthetic.flicker_depth` = 0.6 : expected a value from 0 to 0.5",
            ),
            ("drift_depth: -0.1", "`synthetic.drift_depth` = -0.1"),
            (
                "pivot_frac: [0.5, 3]",
                "`synthetic.pivot_frac[1]` = 3 : expected a value from -1 to 2",
            ),
            ("pivot_frac: [0.5]", "pivot_frac"),
            (
                "vfr_jitter: 1",
                "`synthetic.vfr_jitter` = 1 : expected a value from 0 to 0.9",
            ),
            (
                "dropped_share: 0.3",
                "`synthetic.dropped_share` = 0.3 : expected a value from 0 to 0.2",
            ),
            (
                "rolling_shutter: 1.5",
                "`synthetic.rolling_shutter` = 1.5 : expected a value from 0 to 1",
            ),
            (
                "release_hand: true",
                "`synthetic.release_hand` without `synthetic.hold_s`",
            ),
            (
                "vfr_jitter: 0.9, fps: 60",
                "`synthetic.vfr_jitter` = 0.9 at `synthetic.fps` = 60: frames would come less than 2 ms apart",
            ),
            (
                "hold_s: -1",
                "`synthetic.hold_s` = -1 s: expected zero or a positive number",
            ),
            (
                "hold_s: 5, duration_s: 5",
                "`synthetic.hold_s` = 5 s: expected less than the recording's 5 s",
            ),
        ] {
            let e = err(&synthetic_with(extra));
            assert!(e.contains(want), "{extra}: {e}");
        }
}

#[test]
fn unset_camera_conditions_leave_the_render_key_as_it_was() {
    // The twin's render key hashes the `synthetic:` block as JSON: keys left out
    // must not appear in it, so that adding keys does not change old blocks' JSON.
    let e = Experiment::parse(Path::new("x/glass.yaml"), GOOD).unwrap();
    let json = serde_json::to_string(e.file.synthetic.as_ref().unwrap()).unwrap();
    assert_eq!(
        json,
        r#"{"s_r_m":3.2e-6,"beta":1.0,"psi0_deg":10.0,"duration_s":null,"fps":60.0,"rest_angle_deg":91.7,"seed":1,"angle_noise_deg":0.05,"width":1280,"height":720,"style":"dark-wire","spoiled_frames":3,"clean":false}"#
    );
}

#[test]
fn beta_accepts_numbers_fractions_and_free() {
    let b = |s: &str| parse_beta(&BetaSpec::Text(s.into()), "b").unwrap();
    assert_eq!(b("4/3"), BetaChoice::Fixed(4.0 / 3.0));
    assert_eq!(b("1.5"), BetaChoice::Fixed(1.5));
    assert_eq!(b("free"), BetaChoice::Free);
    assert!(parse_beta(&BetaSpec::Number(-1.0), "b").is_err());
}
