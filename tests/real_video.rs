//! The detector on real camera footage (`../shared/fixtures/real/`, read in place: the
//! clips carry no licence to redistribute). Expected values are the fixtures README's
//! hand estimates (about ±1–2°); the detector must agree within 1.5° with at most 2 %
//! of frames missing, without being captured by the clips' distractors.

mod common;

use common::{fixture, rollfric_ok, root, turning_amplitudes};
use rollfric::series::AngleSeries;
use std::ffi::OsStr;
use std::path::Path;

struct Detected {
    series: AngleSeries,
    frames: usize,
    missing: usize,
    pivot: (f64, f64),
    /// The region of interest `[x, y, w, h]` the summary reports.
    roi: Vec<u32>,
}

fn detect(video: &Path, extra: &[&str]) -> Detected {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("angles.csv");
    let mut args = vec![
        OsStr::new("detect"),
        video.as_os_str(),
        OsStr::new("-o"),
        csv.as_os_str(),
    ];
    args.extend(extra.iter().map(OsStr::new));
    let (_, msg) = rollfric_ok(&args, &root());
    let text = std::fs::read_to_string(&csv).unwrap();
    let frames = text.lines().count() - 1;
    let missing = text.lines().filter(|l| l.contains(",missing,")).count();
    let piv = common::pivot_in(&msg);
    let roi = common::numbers_after(&msg, "ROI [", ']');
    Detected {
        roi,
        series: AngleSeries::parse_csv(&text).unwrap(),
        frames,
        missing,
        pivot: piv,
    }
}

/// Mean amplitude of the first and of the last `k` turning points before `t_end`.
fn start_end(amps: &[(f64, f64)], k: usize, t_end: f64) -> (f64, f64) {
    let upto: Vec<f64> = amps.iter().filter(|a| a.0 <= t_end).map(|a| a.1).collect();
    let first = upto[..k].iter().sum::<f64>() / k as f64;
    let last = upto[upto.len() - k..].iter().sum::<f64>() / k as f64;
    (first, last)
}

fn check(name: &str, d: &Detected, (start, end): (f64, f64), want: (f64, f64)) {
    eprintln!(
        "{name}: pivot ({:.1}, {:.1}) px, amplitude {start:.2} -> {end:.2} deg \
         (README {:.2} -> {:.2}), {} of {} frames missing",
        d.pivot.0, d.pivot.1, want.0, want.1, d.missing, d.frames
    );
    assert!(
        (d.missing as f64) <= 0.02 * d.frames as f64,
        "{name}: {} of {} frames missing",
        d.missing,
        d.frames
    );
    assert!(
        (start - want.0).abs() <= 1.5 && (end - want.1).abs() <= 1.5,
        "{name}: amplitude {start:.2} -> {end:.2} deg, expected {:.2} -> {:.2}",
        want.0,
        want.1
    );
}

#[test]
fn greenscreen_clip_ignores_the_hand_and_stopwatch() {
    let Some(v) = fixture("sborquez_video1_greenscreen.mp4") else {
        return;
    };
    let d = detect(&v, &[]);
    // README: pivot about (571, 105); 301 frames at 25 fps (not the header's 31.47).
    assert!(
        (d.pivot.0 - 571.0).abs() < 8.0 && (d.pivot.1 - 105.0).abs() < 8.0,
        "{:?}",
        d.pivot
    );
    assert_eq!(d.frames, 301);
    let dt = d.series.t[1] - d.series.t[0];
    assert!(
        (dt - 0.04).abs() < 1e-6,
        "frame times from timestamps: {dt}"
    );
    let amps = turning_amplitudes(&d.series);
    // README: about ±29 deg at the start, ±25 deg at 11.6 s.
    check("greenscreen", &d, start_end(&amps, 2, 11.7), (29.0, 25.0));
}

#[test]
fn splitscreen_clip_one_panel_at_a_time_ignores_the_fan_lines() {
    let Some(v) = fixture("sborquez_video2_splitscreen.mp4") else {
        return;
    };
    // README: use frames 0-366 (a splice follows); one ROI per panel.
    for (name, roi, pivot, want) in [
        ("left", "0,0,240,360", (128.0, 48.0), (25.0, 23.0)),
        ("right", "240,0,240,360", (370.0, 48.0), (11.5, 10.75)),
    ] {
        let d = detect(&v, &["--roi", roi, "--frames", "0,366"]);
        assert_eq!(d.frames, 367);
        assert!(
            (d.pivot.0 - pivot.0).abs() < 6.0 && (d.pivot.1 - pivot.1).abs() < 6.0,
            "{name}: {:?}",
            d.pivot
        );
        let amps = turning_amplitudes(&d.series);
        check(name, &d, start_end(&amps, 2, 11.6), want);
    }
}

#[test]
fn off_screen_pivot_clip_ignores_the_dark_stripe() {
    let Some(v) = fixture("bartekpacia_film1_fhd.mp4") else {
        return;
    };
    let d = detect(&v, &[]);
    // README: pivot about (990, -640) (±10 px in x, ±30 px in y), off the frame.
    assert!(
        (d.pivot.0 - 990.0).abs() < 15.0 && (d.pivot.1 + 640.0).abs() < 40.0,
        "{:?}",
        d.pivot
    );
    // 1920 px wide: the detector works on frames shrunk 3 times, so its region's sizes
    // are multiples of 3 (and of 2, for the decoder's crop).
    assert!(
        d.roi[2].is_multiple_of(6) && d.roi[3].is_multiple_of(6),
        "ROI {:?} not in whole 3x3 blocks",
        d.roi
    );
    let amps = turning_amplitudes(&d.series);
    // README: about ±12 deg at the start (+10.7/-12.8), ±10 deg at 25 s (+9.3/-11.1).
    check("fhd", &d, start_end(&amps, 2, 25.6), (11.75, 10.2));
}

/// `rollfric init` on each real clip writes an experiment file that refuses until its
/// geometry is filled in; filled in (with a length near what the clip's period implies)
/// and listed in a manifest by `init --manifest`, `rollfric build` builds it unchanged.
#[test]
fn init_writes_a_file_that_builds_once_filled_in() {
    let clips = [
        "sborquez_video1_greenscreen.mp4",
        "sborquez_video2_splitscreen.mp4",
        "bartekpacia_film1_fhd.mp4",
    ];
    let dir = tempfile::tempdir().unwrap();
    let manifest = dir.path().join("manifest.yaml");
    std::fs::write(&manifest, "title: init\nexperiments:\n").unwrap();
    for (k, clip) in clips.iter().enumerate() {
        let Some(v) = fixture(clip) else { return };
        let yaml = dir.path().join(format!("clip{k}.yaml"));
        let mut args = vec![
            OsStr::new("init"),
            v.as_os_str(),
            OsStr::new("-o"),
            yaml.as_os_str(),
        ];
        // The first adds to an empty list, which is not a block list yet: by hand.
        if k > 0 {
            args.extend([OsStr::new("--manifest"), manifest.as_os_str()]);
        }
        // Two pendulums swing in the split-screen clip: the right panel's, by its region
        // (and the file keeps it, so that the build measures the same one).
        if clip.contains("splitscreen") {
            args.extend([OsStr::new("--roi"), OsStr::new("240,0,240,360")]);
        }
        let (out, _) = rollfric_ok(&args, &root());
        assert!(out.contains("FILL IN"), "{out}");
        if k == 0 {
            std::fs::write(&manifest, "title: init\nexperiments:\n  - clip0.yaml\n").unwrap();
        }
        let text = std::fs::read_to_string(&yaml).unwrap();
        // Refused until filled in, naming the file.
        let fit = common::rollfric(&[OsStr::new("fit"), yaml.as_os_str()], &root());
        let err = String::from_utf8_lossy(&fit.stderr);
        assert!(
            !fit.status.success() && err.contains(&format!("clip{k}.yaml")),
            "{err}"
        );
        let filled = common::fill_init_geometry(&text);
        std::fs::write(&yaml, filled).unwrap();
    }
    let listed = std::fs::read_to_string(&manifest).unwrap();
    assert!(
        listed.contains("clip1.yaml") && listed.contains("clip2.yaml"),
        "{listed}"
    );
    let (out, err) = rollfric_ok(
        &[
            OsStr::new("build"),
            OsStr::new("--manifest"),
            manifest.as_os_str(),
            OsStr::new("--out"),
            dir.path().join("reports").as_os_str(),
            OsStr::new("--cache"),
            dir.path().join("build").as_os_str(),
            OsStr::new("-q"),
        ],
        &root(),
    );
    for k in 0..3 {
        assert!(
            dir.path().join(format!("reports/clip{k}.html")).exists(),
            "{out}{err}"
        );
    }
    // The FHD clip's hundreds of flagged frames: the review page lists every one, with
    // pictures of at most 48, spread over the video, each at most 512 px a side.
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("build/clip2/detect.json")).unwrap())
            .unwrap();
    let flagged = summary["flagged"].as_array().unwrap().len();
    let frames = summary["frames"].as_u64().unwrap();
    let pictures: Vec<serde_json::Value> =
        serde_json::from_slice(&std::fs::read(dir.path().join("build/clip2/review.json")).unwrap())
            .unwrap();
    assert!(flagged > 100, "the FHD clip flags {flagged} frames");
    assert!(
        (24..=48).contains(&pictures.len()),
        "{} pictures of {flagged} flagged frames",
        pictures.len()
    );
    let last = pictures.last().unwrap()["frame"].as_u64().unwrap();
    assert!(
        last * 10 > frames * 8,
        "the last picture is of frame {last} of {frames}"
    );
    for p in &pictures {
        let (w, h) = (p["width"].as_u64().unwrap(), p["height"].as_u64().unwrap());
        assert!(w.max(h) <= 512, "{p}");
        let png = dir
            .path()
            .join("reports/clip2/review")
            .join(p["file"].as_str().unwrap());
        assert!(png.is_file(), "{} is missing", png.display());
    }
    let page = std::fs::read_to_string(dir.path().join("reports/clip2/review.html")).unwrap();
    assert_eq!(
        page.matches("\"status\":").count(),
        flagged,
        "the review page lists every flagged frame"
    );

    // The FHD clip's Figure 12 carries hundreds of flag circles: no legend over any.
    let covered = common::legends_over_data(&dir.path().join("reports"));
    assert!(
        covered.is_empty(),
        "legends over data:\n{}",
        covered.join("\n")
    );

    // `fit` reads the angles the build measured while the video and its `video:` block
    // are unchanged: the same result as measuring again (`--fresh`), saying where the
    // angles came from; a changed `video:` setting is measured again.
    let yaml = dir.path().join("clip0.yaml");
    let cache = dir.path().join("build");
    let fit = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec![
            OsStr::new("fit"),
            yaml.as_os_str(),
            OsStr::new("--json"),
            OsStr::new("--cache"),
            cache.as_os_str(),
        ];
        args.extend(extra.iter().map(OsStr::new));
        serde_json::from_str(&rollfric_ok(&args, &root()).0).unwrap()
    };
    let said = |v: &serde_json::Value| v["angles"]["description"].as_str().unwrap().to_string();
    let (cached, fresh) = (fit(&[]), fit(&["--fresh"]));
    assert!(
        said(&cached).contains("measured by a build"),
        "{}",
        said(&cached)
    );
    assert!(
        !said(&fresh).contains("measured by a build"),
        "{}",
        said(&fresh)
    );
    assert_eq!(cached["s_r_m"], fresh["s_r_m"]);
    assert!(
        cached["s_r_m"].as_f64().is_some_and(|v| v > 0.0),
        "{cached}"
    );
    let text = std::fs::read_to_string(&yaml).unwrap();
    let polarity = if text.contains("polarity: dark") {
        "dark"
    } else {
        "light"
    };
    std::fs::write(
        &yaml,
        text.replace(&format!("polarity: {polarity}"), "polarity: auto"),
    )
    .unwrap();
    let changed = fit(&[]);
    assert!(
        !said(&changed).contains("measured by a build"),
        "{}",
        said(&changed)
    );
}
