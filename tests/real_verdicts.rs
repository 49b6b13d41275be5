//! The detection's verdict on the seven real clips of `../shared/fixtures/real/`, with
//! no options, against the outcome their README states: measured (`ok`, within the
//! stated period and amplitude), or `suspect` / refused with the stated reason. Read
//! through `detect --json`, as a CI job would.

mod common;

use common::{fixture, outcomes};

/// `detect VIDEO --json` of a real fixture with `extra` flags: the summary's JSON, and
/// whether the command succeeded.
fn detect_json(video: &str, extra: &[&str]) -> Option<(serde_json::Value, bool)> {
    let v = fixture(video)?;
    let dir = tempfile::tempdir().unwrap();
    let (value, out, _) = common::detect_json(&v, extra, dir.path());
    assert_eq!(value["kind"], "rollfric detect");
    Some((value, out.status.success()))
}

fn num(v: &serde_json::Value, path: &[&str]) -> f64 {
    let mut x = v;
    for p in path {
        x = &x[*p];
    }
    x.as_f64().unwrap_or_else(|| panic!("{path:?} in {v}"))
}

/// A measured clip: `ok`, its period and its amplitude at the start and at the end
/// within the README's figures (period within 2 %, amplitudes within 1.5 deg).
fn measured(video: &str, extra: &[&str], period: f64, start: f64, end: f64) {
    let Some((v, ok)) = detect_json(video, extra) else {
        return;
    };
    assert!(ok, "{video}: refused: {}", v["reason"]);
    assert_eq!(v["verdict"], "ok", "{video}: {}", v["checks"]);
    let (p, a0, a1) = (
        num(&v, &["seen", "period_s"]),
        num(&v, &["seen", "amplitude_start_deg"]),
        num(&v, &["seen", "amplitude_end_deg"]),
    );
    eprintln!("{video}: period {p:.3} s, amplitude {a0:.2} -> {a1:.2} deg");
    assert!((p / period - 1.0).abs() < 0.02, "{video}: period {p}");
    assert!(
        (a0 - start).abs() <= 1.5 && (a1 - end).abs() <= 1.5,
        "{video}: amplitude {a0:.2} -> {a1:.2} deg, README {start} -> {end}"
    );
}

#[test]
fn greenscreen_is_measured() {
    // README: period about 1.33 s; about ±29 deg at the start, ±25 at 11.6 s.
    measured("sborquez_video1_greenscreen.mp4", &[], 1.33, 29.0, 25.0);
}

#[test]
fn off_screen_pivot_clip_is_measured() {
    // README: period about 1.02 s; ±12 (+10.7/-12.8) at the start, ±10 (+9.3/-11.1) at
    // 25 s.
    measured("bartekpacia_film1_fhd.mp4", &[], 1.02, 11.75, 10.2);
}

#[test]
fn red_apple_is_measured() {
    // README: period 2.07-2.09 s; ±25 deg at the start, ±18-21 after 20 s.
    measured("christianausb_redapple_480p.mov", &[], 2.08, 25.0, 21.0);
}

#[test]
fn split_screen_is_refused_without_a_panel_and_measured_with_one() {
    let Some((v, ok)) = detect_json("sborquez_video2_splitscreen.mp4", &[]) else {
        return;
    };
    // Two pendulums, neither chosen: refused, naming both pivots (README: about (128,
    // 48) and (370, 48)).
    assert!(!ok);
    assert_eq!(v["verdict"], "refused");
    let reason = v["reason"].as_str().unwrap();
    assert!(reason.contains("two pendulums"), "{reason}");
    for p in ["(128, 48)", "(370, 48)"] {
        assert!(reason.contains(p), "{p} not in: {reason}");
    }
    // A region says which: the right panel, measured (frames before the splice; period
    // about 1.6 s, ±11.5 -> ±10.2-11.3 deg).
    measured(
        "sborquez_video2_splitscreen.mp4",
        &["--roi", "240,0,240,360", "--frames", "0,366"],
        1.58,
        11.5,
        10.75,
    );
}

#[test]
fn invisible_rope_is_not_called_good() {
    if let Some((v, ok)) = detect_json("bartekpacia_film2_vga.mp4", &[]) {
        outcomes::invisible_rope("film 2", &v, ok);
    }
}

#[test]
fn two_rods_are_never_a_silent_mixture() {
    if let Some((v, ok)) = detect_json("katiebutler_pendulum.mov", &[]) {
        outcomes::two_rods("two rods", &v, ok);
    }
}

#[test]
fn a_rod_knocked_far_and_held_is_refused_with_a_reason() {
    if let Some((v, ok)) = detect_json("dfki_rvDIST35.mp4", &[]) {
        outcomes::rod_knocked_far("rod knocked far", &v, ok);
    }
}
