//! The digital twin end to end: rendered videos of every style (noise, blur, lighting
//! drift and flicker, compression, spoiled frames) measured back by the detector, and
//! the rolling-friction coefficient of every experiment measured back from its video.

mod common;

use common::{need_ffmpeg, numbers_after, pivot_in, rollfric_ok, root, scatter_deg};
use std::path::Path;

struct Row {
    angle: Option<f64>,
    tag: String,
}

fn read(path: &Path, col: &str) -> Vec<Row> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let ia = head.iter().position(|h| *h == "angle_rad").unwrap();
    let it = head.iter().position(|h| *h == col).unwrap();
    lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            Row {
                angle: v[ia].parse().ok(),
                tag: v[it].to_string(),
            }
        })
        .collect()
}

#[test]
fn every_style_is_measured_within_a_twentieth_of_a_degree() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let glass = std::fs::read_to_string(root().join("experiments/glass.yaml")).unwrap();
    // Two recordings of each style. The second seeds put a repeated frame near a
    // turning point, where the wire moves 0.07-0.13 deg per frame: a gate that
    // predicts from the previous frames only cannot tell it from a wire slowing down.
    for (style, seed) in [
        ("dark-wire", 20),
        ("light-wire", 21),
        ("oblique", 22),
        ("dark-wire", 33),
        ("light-wire", 31),
        ("oblique", 31),
    ] {
        // 60 frames/s for 12 s, whatever the experiment's own camera.
        let text: String = glass
            .lines()
            .filter(|l| !l.trim_start().starts_with("duration_s:"))
            .map(|l| {
                if l.trim_start().starts_with("fps:") {
                    "  fps: 60\n  duration_s: 12\n".to_string()
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        assert!(text.contains("  fps: 60\n"), "glass.yaml has no `fps:`");
        let text = text
            .replace("style: dark-wire", &format!("style: {style}"))
            .replace("  seed: 3\n", &format!("  seed: {seed}\n"));
        let style = format!("{style} (seed {seed})");
        let name = style.replace([' ', '(', ')'], "");
        let exp = d.join(format!("{name}.yaml"));
        std::fs::write(&exp, text).unwrap();
        let (video, truth, angles) = (
            d.join(format!("{name}.mp4")),
            d.join(format!("{name}-truth.csv")),
            d.join(format!("{name}-angles.csv")),
        );
        let s = |p: &Path| p.to_str().unwrap().to_string();
        let (_, rendered) = rollfric_ok(
            &["synth", &s(&exp), "-o", &s(&video), "--truth", &s(&truth)],
            d,
        );
        // H.264 when ffmpeg has x264, MJPG otherwise.
        let video = if video.exists() {
            video
        } else {
            video.with_extension("avi")
        };
        let (_, detected) = rollfric_ok(&["detect", &s(&video), "-o", &s(&angles)], d);
        // The pivot found in the shrunk frames, mapped back to the full frame, is the
        // rendered one (pixel centres at integers in both).
        let (want, got) = (pivot_in(&rendered), pivot_in(&detected));
        assert!(
            (got.0 - want.0).abs() <= 0.3 && (got.1 - want.1).abs() <= 0.3,
            "{style}: pivot {got:?} px, rendered at {want:?}"
        );
        let t = read(&truth, "spoiled");
        let a = read(&angles, "status");
        assert_eq!(t.len(), a.len(), "{style}: one row per frame");
        let mut spoiled = 0;
        let mut diffs = Vec::new();
        for (tr, de) in t.iter().zip(&a) {
            if tr.tag != "none" {
                spoiled += 1;
                // Flagged, or untouched by the spoiling (a hand still outside the
                // region of interest leaves the wire's angle as it was).
                let err = de.angle.map(|a| (a - tr.angle.unwrap()).abs().to_degrees());
                assert!(
                    de.tag != "ok" || err.is_some_and(|e| e < 0.05),
                    "{style}: a `{}` frame passed as ok with error {err:?} deg",
                    tr.tag
                );
            }
            if let Some(x) = de.angle {
                diffs.push(x - tr.angle.unwrap());
            }
        }
        assert!(spoiled >= 3, "{style}: {spoiled} spoiled frames");
        let missing = a.iter().filter(|r| r.tag == "missing").count();
        assert!(missing * 100 <= a.len(), "{style}: {missing} missing");
        let rms = scatter_deg(&diffs);
        assert!(rms <= 0.05, "{style}: angle RMS {rms:.4} deg");
    }
}

#[test]
fn every_experiment_measures_back_its_s_r_from_video() {
    if !need_ffmpeg() {
        return;
    }
    // Every experiment of the manifest. Renders (or reuses) the twins under build/, as
    // `make reports` does.
    let (_, files) =
        rollfric::config::Manifest::load(&root().join("experiments/manifest.yaml")).unwrap();
    for file in files {
        let exp = file.display().to_string();
        let (out, _) = rollfric_ok(&["fit", &exp, "--json"], &root());
        let j: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert!(
            j["angles"]["kind"]
                .as_str()
                .unwrap()
                .starts_with("synthetic-video"),
            "{exp}: {}",
            j["angles"]
        );
        let truth = j["truth_s_r_m"].as_f64().unwrap();
        let got = j["s_r_m"].as_f64().unwrap();
        let dev = (got - truth) / truth;
        assert!(
            dev.abs() < 0.01,
            "{exp}: s_r from video {got:e} vs truth {truth:e} ({:+.2} %)",
            100.0 * dev
        );
    }
}

/// The paper's operator holds the ball at its release angle for a second or two before
/// letting go. A first look spent on the held ball sees too little of the swing: this
/// twin (a faint 1 px light wire, 640x480 at 30 frames/s, held for 2 s) was refused
/// with "the moving lines turn irregularly". The look keeps a few frames of the still
/// start and spans the motion after it; every frame, held or swinging, is measured
/// (angle RMS 0.028 deg).
#[test]
fn a_ball_held_for_two_seconds_is_measured_in_every_frame() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "glass",
        "  s_r_m: 3.714e-6\n  psi0_deg: 10\n  width: 640\n  height: 480\n  \
         fps: 30\n  style: light-wire\n  seed: 1042\n  rest_angle_deg: -95.6\n  \
         wire_width_px: 1\n  wire_contrast: 0.45\n  hold_s: 2\n  duration_s: 10\n",
    );
    std::fs::write(d.join("held.yaml"), text).unwrap();
    rollfric_ok(
        &[
            "synth",
            "held.yaml",
            "-o",
            "held.mp4",
            "--truth",
            "truth.csv",
        ],
        d,
    );
    let video = if d.join("held.mp4").exists() {
        "held.mp4"
    } else {
        "held.avi"
    };
    rollfric_ok(&["detect", video, "-o", "angles.csv"], d);
    // Four of the frames are spoiled on purpose (a hand, a flash): filled, not lost.
    let diffs = ok_errors_against_truth(d);
    let rms = scatter_deg(&diffs);
    // As every style's bar: 10 s leave the pivot a few hundredths of a degree of
    // amplitude scale (40 s of the same scene: 0.010 deg).
    assert!(rms <= 0.05, "angle RMS {rms:.4} deg");
}

/// A wire a pixel wide and a few grey levels dark (0.40 of the full contrast), under
/// 100 Hz flicker at 25 frames/s: no threshold keeps enough of it in any frame to make a
/// segment, and the detector refused ("no moving wire found in the first 64 frames
/// (lines seen in 0 of them)"; the robustness sweep's scene 49, seed 1). The faint look
/// finds each frame's line along whole lines of the image; the pivot comes out where
/// the twin put it and every frame is measured.
#[test]
fn a_faint_one_pixel_wire_under_flicker_is_found_and_followed() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "steel",
        "  s_r_m: 4.508e-6\n  psi0_deg: 10\n  width: 640\n  height: 480\n  \
         fps: 25\n  style: oblique\n  seed: 1049\n  rest_angle_deg: -155.3\n  \
         wire_width_px: 1\n  wire_contrast: 0.40\n  flicker_hz: 100\n  flicker_depth: 0.103\n  \
         duration_s: 12\n",
    );
    std::fs::write(d.join("faint.yaml"), text).unwrap();
    let (_, rendered) = rollfric_ok(
        &[
            "synth",
            "faint.yaml",
            "-o",
            "faint.avi",
            "--truth",
            "truth.csv",
        ],
        d,
    );
    let (_, detected) = rollfric_ok(&["detect", "faint.avi", "-o", "angles.csv"], d);
    let (want, got) = (pivot_in(&rendered), pivot_in(&detected));
    assert!(
        (got.0 - want.0).abs() <= 0.5 && (got.1 - want.1).abs() <= 0.5,
        "pivot detected at {got:?} px, rendered at {want:?}"
    );
    let rms = scatter_deg(&ok_errors_against_truth(d));
    assert!(rms <= 0.05, "angle RMS {rms:.4} deg");
}

/// The experiment `experiments/NAME.yaml` with its `synthetic:` block replaced by
/// `block` (the block's lines, indented).
fn with_synthetic(name: &str, block: &str) -> String {
    let text = std::fs::read_to_string(root().join(format!("experiments/{name}.yaml"))).unwrap();
    let head = &text[..text
        .find("\nsynthetic:")
        .unwrap_or_else(|| panic!("{name}.yaml has `synthetic:`"))];
    format!("{head}\nsynthetic:\n{block}")
}

/// A sweep twin in `d`: experiment `name`'s `synthetic:` block replaced by `block`,
/// rendered as `twin.<ext>` with its truth, and detected with what a user gave
/// (`given`, one `video:` key, its lens or its pivot): the truth's rows, the angles'
/// rows and what `detect` said.
fn detect_twin(
    d: &Path,
    name: &str,
    block: &str,
    ext: &str,
    given: &str,
) -> (Vec<Row>, Vec<Row>, String) {
    let video = format!("twin.{ext}");
    let text = with_synthetic(name, block).replace(
        "\nsynthetic:",
        &format!("\nvideo:\n  path: {video}\n  {given}\nsynthetic:"),
    );
    std::fs::write(d.join("twin.yaml"), text).unwrap();
    rollfric_ok(
        &["synth", "twin.yaml", "-o", &video, "--truth", "truth.csv"],
        d,
    );
    let (_, said) = rollfric_ok(
        &[
            "detect",
            "--experiment",
            "twin.yaml",
            &video,
            "-o",
            "angles.csv",
        ],
        d,
    );
    (
        read(&d.join("truth.csv"), "spoiled"),
        read(&d.join("angles.csv"), "status"),
        said,
    )
}

/// The detected angle minus the true one (rad) of every `ok` frame of `angles` from
/// frame `from` on, against `truth`.
fn ok_errors(truth: &[Row], angles: &[Row], from: usize) -> Vec<f64> {
    truth[from..]
        .iter()
        .zip(&angles[from..])
        .filter(|(_, de)| de.tag == "ok")
        .map(|(tr, de)| de.angle.unwrap() - tr.angle.unwrap())
        .collect()
}

/// The detected angle minus the true one of every `ok` frame of `d/angles.csv`
/// against `d/truth.csv` (rad), after checking one row per frame, no frame missing
/// and at least 95 % of them `ok`.
fn ok_errors_against_truth(d: &Path) -> Vec<f64> {
    let t = read(&d.join("truth.csv"), "spoiled");
    let a = read(&d.join("angles.csv"), "status");
    assert_eq!(t.len(), a.len(), "one row per frame");
    let diffs = ok_errors(&t, &a, 0);
    assert!(
        a.iter().all(|r| r.tag != "missing") && diffs.len() * 100 >= a.len() * 95,
        "{} of {} frames ok",
        diffs.len(),
        a.len()
    );
    diffs
}

/// The swing's scale: the angles of `d/angles.csv` (its `ok` frames) regressed on the
/// true ones of `truth`.
fn swing_scale_against(truth: &[Row], d: &Path) -> f64 {
    let a = read(&d.join("angles.csv"), "status");
    let (x, y): (Vec<f64>, Vec<f64>) = truth
        .iter()
        .zip(&a)
        .filter(|(_, de)| de.tag == "ok")
        .map(|(tr, de)| (tr.angle.unwrap(), de.angle.unwrap()))
        .unzip();
    rollfric::numerics::linear_fit(&x, &y).slope
}

/// A pivot off by a few pixels is refined onto the wire, not part of the way. Each
/// frame's free line was fitted to the strip about the line through the pivot given,
/// whose noise and cut flanks pulled it towards that pivot: a pivot 3.4 px off along
/// the wire of the aluminum twin (960x540, a camera's defects) was refined to 0.8 px
/// off, and every swing measured 0.46 % small (s_r -0.54 %). The strip the pivot's
/// refinement reads is now centred on each frame's free line.
#[test]
fn a_pivot_given_a_few_pixels_off_is_refined_onto_the_wire() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = std::fs::read_to_string(root().join("experiments/aluminum.yaml"))
        .unwrap()
        .replace("  duration_s: 80 ", "  duration_s: 24 ");
    assert!(text.contains("duration_s: 24"), "aluminum.yaml's duration");
    std::fs::write(d.join("al.yaml"), text).unwrap();
    let (_, rendered) = rollfric_ok(
        &["synth", "al.yaml", "-o", "al.avi", "--truth", "truth.csv"],
        d,
    );
    let want = pivot_in(&rendered);
    let truth = read(&d.join("truth.csv"), "spoiled");
    // The wire hangs along +y: 4 px up is along it, 3 px left across it.
    for (what, off) in [("along", (0.0, -4.0)), ("across", (-3.0, 0.0))] {
        let given = format!("{:.1},{:.1}", want.0 + off.0, want.1 + off.1);
        let (_, detected) = rollfric_ok(
            &["detect", "al.avi", "--pivot", &given, "-o", "angles.csv"],
            d,
        );
        let got = pivot_in(&detected);
        // Both printed to 0.1 px: 0.25 px holds a refinement within 0.15 px of the truth.
        assert!(
            (got.0 - want.0).abs() <= 0.25 && (got.1 - want.1).abs() <= 0.25,
            "{what}: given {given}, refined to {got:?} px, rendered at {want:?}"
        );
        let slope = swing_scale_against(&truth, d);
        // Within the detector's stated scale uncertainty (the budget's Type B part).
        assert!(
            (slope - 1.0).abs() <= rollfric::uncertainty::DETECTOR_SCALE_REL,
            "{what}: the swing measured {:+.3} % of its size",
            100.0 * (slope - 1.0)
        );
    }
}

#[test]
fn a_wire_at_rest_is_not_swapped_for_its_shadow_at_a_repeated_frame() {
    if !need_ffmpeg() {
        return;
    }
    // A randomised sweep's twin (seed 2, scene 57): 1920x1080, looked at shrunk three
    // times, where the wire's soft shadow 5.8 degrees away is about as sharp as the
    // wire and darker. The ball rests from about 25 s; at 31.9 s the recorder repeats a
    // frame. A repeat once widened the search, which took in the shadow and kept it for
    // the last 8 s (2.3 deg RMS, every frame `ok`).
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("pc.yaml"),
        "name: pc
geometry:
  incline: { h_m: 0.142, l_m: 1.500 }
  pendulum: { d_m: 0.1831 }
  ball: { radius_m: 0.03175, mass_kg: 1.0458 }
synthetic:
  s_r_m: 18.986e-6
  psi0_deg: 10
  width: 1920
  height: 1080
  fps: 30
  style: oblique
  seed: 2057
  rest_angle_deg: 137.1
  mirror: true
  wire_width_px: 2
  wire_contrast: 0.98
  shadow: {angle_deg: -5.8, blur_px: 3.2, strength: 0.30}
  flicker_hz: 100
  flicker_depth: 0.125
  hold_s: 1.08
  duration_s: 40
",
    )
    .unwrap();
    rollfric_ok(
        &["synth", "pc.yaml", "-o", "pc.mp4", "--truth", "truth.csv"],
        d,
    );
    rollfric_ok(&["detect", "pc.mp4", "-o", "angles.csv"], d);
    let truth = read(&d.join("truth.csv"), "spoiled");
    // The repeat this is about: a frame the recorder repeated while the ball rests.
    assert!(
        truth[930..1000].iter().any(|r| r.tag == "duplicate"),
        "the twin repeats a frame between frames 930 and 1000"
    );
    let a = read(&d.join("angles.csv"), "status");
    let mut off: Vec<(usize, f64)> = truth
        .iter()
        .zip(&a)
        .enumerate()
        .filter(|(_, (_, de))| de.tag == "ok")
        .map(|(k, (tr, de))| (k, (de.angle.unwrap() - tr.angle.unwrap()).to_degrees()))
        .collect();
    assert!(off.len() > 1100, "{} frames ok", off.len());
    let mut sorted: Vec<f64> = off.iter().map(|o| o.1).collect();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    off.sort_by(|x, y| (x.1 - median).abs().total_cmp(&(y.1 - median).abs()));
    let (k, worst) = off[off.len() - 1];
    assert!(
        (worst - median).abs() < 0.1,
        "ok frame {k} is {:.3} deg off the others",
        worst - median
    );
}

#[test]
fn a_wire_at_rest_for_seventeen_seconds_is_followed_to_the_end() {
    if !need_ffmpeg() {
        return;
    }
    // A randomised sweep's twin (seed 53, scene 55): 1280x720 at 60 fps through a wide
    // lens (given), a 1 px wire whose soft shadow lies 2.4 deg away, the ball at rest
    // from about 23 s. The background once decayed under the resting wire too, one
    // grey level every 120 frames: the wire faded into it, and the track lost it (every
    // frame missing from 36 s). The first pass, about the shrunk look's pivot, ends on
    // the shadow, its lines turning 1.066 times as much as its angle: a pass that fails
    // the `pivot` check (over 0.75 % off) is measured again from the other scale's look.
    let dir = tempfile::tempdir().unwrap();
    let (truth, a, said) = detect_twin(
        dir.path(),
        "polycarbonate",
        "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 1280\n  height: 720\n  fps: 60\n  \
         style: oblique\n  seed: 53055\n  rest_angle_deg: -12.2\n  mirror: true\n  \
         wire_width_px: 1\n  wire_contrast: 0.78\n  \
         shadow: {angle_deg: -2.4, blur_px: 2.1, strength: 0.49, lamp_share: 1}\n  \
         pivot_frac: [-0.0140, 0.4992]\n  lens_k1: -0.153\n  room: {board: ruled}\n  \
         rolling_shutter: 0.54\n  duration_s: 40\n",
        "avi",
        "lens: { k1: -0.153, u_k1: 0.0003 }",
    );
    assert!(
        said.contains("measuring again from a look at a finer working scale"),
        "the first pass, about the shrunk look's pivot, is measured again: {said}"
    );
    // The last 8 s, at rest: every frame found, on the wire.
    let last: Vec<f64> = ok_errors(&truth, &a, 1920)
        .into_iter()
        .map(f64::to_degrees)
        .collect();
    assert!(
        last.len() >= 470,
        "{} of the last 481 frames ok: {said}",
        last.len()
    );
    let worst = last.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    assert!(worst < 0.1, "a frame at rest {worst:.3} deg off: {said}");
}

#[test]
fn a_faint_wire_at_rest_keeps_its_whole_strip() {
    if !need_ffmpeg() {
        return;
    }
    // A randomised sweep's twin (seed 97, scene 59): 960x540 at 30 fps, a 1 px wire
    // shrunk 1.5 times, 100 Hz flicker, a wide lens (given) and a rolling shutter; the
    // ball at rest from about 25 s. When only the strip's pixels over their threshold
    // kept their level at the background's lowering, the faint wire's others faded into
    // it, and its angle at rest scattered by 0.07 deg (0.03 while it swung): the
    // detection was `suspect (smooth)` and the fit refused its spurious turning points.
    let dir = tempfile::tempdir().unwrap();
    let (truth, a, said) = detect_twin(
        dir.path(),
        "copper",
        "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  fps: 30\n  \
         style: oblique\n  seed: 97059\n  rest_angle_deg: -100.8\n  wire_width_px: 1\n  \
         wire_contrast: 0.82\n  flicker_hz: 100\n  flicker_depth: 0.125\n  \
         lens_k1: -0.112\n  rolling_shutter: 0.74\n  duration_s: 40\n",
        "mp4",
        "lens: { k1: -0.112, u_k1: 0.0005 }",
    );
    assert!(said.contains("detection ok"), "{said}");
    // From 26 s, at rest: the error's scatter about its mean.
    let rest = ok_errors(&truth, &a, 780);
    assert!(
        rest.len() >= 400,
        "{} of 421 frames at rest ok: {said}",
        rest.len()
    );
    let sd = scatter_deg(&rest);
    assert!(
        sd < 0.045,
        "at rest the angle scatters by {sd:.4} deg: {said}"
    );
}

#[test]
fn a_camera_found_moving_late_leaves_a_second_pendulum_out_within_a_second() {
    if !need_ffmpeg() {
        return;
    }
    // A randomised sweep's twin (seed 1, scene 0): 640x480 at 30 fps, a drift of 6.7 px
    // over 40 s, a second pendulum swinging above the first, a walker from 11.7 s; given
    // the pivot, as a user would after the refusal naming both. The camera is found
    // moving at 10.1 s, and each frame from then on is steadied. Counted over the first
    // 100 measured frames before it was left out, the second pendulum pulled the
    // steadying 12.4 px and 2 deg off from 11.1 s, and the angles, corrected by it, 5.5
    // deg: 40 frames `ok` more than 0.5 deg off. Left out after 30 frames, the motion is
    // read at most 6.7 px, and no `ok` frame lies 0.5 deg off (asked here: under 8.5 px,
    // and none 1 deg off).
    let dir = tempfile::tempdir().unwrap();
    let (truth, a, said) = detect_twin(
        dir.path(),
        "glass-fiber-fabric",
        "  s_r_m: 53.023e-6\n  psi0_deg: 15\n  width: 640\n  height: 480\n  fps: 30\n  \
         style: oblique\n  seed: 1000\n  rest_angle_deg: 159.3\n  \
         shadow: {angle_deg: -5.2, blur_px: 2.0, strength: 0.56, lamp_share: 1}\n  \
         flicker_hz: 120\n  flicker_depth: 0.073\n  hold_s: 0.71\n  \
         shake: {drift_px: 6.7}\n  vfr_jitter: 0.16\n  \
         room: {second_string: true, walker_s: 11.7}\n  release_hand: true\n  \
         duration_s: 40\n",
        "avi",
        "pivot: [483.2, 321.5]",
    );
    let camera = said
        .split("the camera moved (")
        .nth(1)
        .and_then(|s| s.split(')').next())
        .unwrap_or_else(|| panic!("no camera motion said: {said}"));
    let most_px: f64 = numbers_after(camera, "at most ", ' ')[0];
    assert!(
        most_px < 8.5,
        "the camera read as far as {most_px} px (6.7 drawn): {said}"
    );
    let errors = ok_errors(&truth, &a, 0);
    assert!(errors.len() >= 1100, "{} frames ok: {said}", errors.len());
    let worst = errors
        .iter()
        .fold(0.0f64, |m, e| m.max(e.abs()))
        .to_degrees();
    assert!(worst < 1.0, "an ok frame {worst:.2} deg off: {said}");
}

/// A short video is decoded once: the first look's decoder goes on into the streaming
/// pass (the look's frames held as decoded, the rest read ahead during the geometry,
/// each cut to the region of interest by the detector). On a 960x540 twin held at its
/// release for 1.5 s under flicker (the look drops the still frames but the pass
/// measures them), the CSV is the one a second decoder cropped by ffmpeg gives, byte
/// for byte.
#[test]
fn a_short_video_decoded_once_gives_the_angles_of_two_decodings() {
    if !need_ffmpeg() {
        return;
    }
    use rollfric::detect::{detect, DetectOptions};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "glass",
        "  s_r_m: 4.0e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  fps: 25\n  \
         style: dark-wire\n  seed: 7\n  hold_s: 1.5\n  flicker_hz: 100\n  \
         flicker_depth: 0.08\n  duration_s: 8\n",
    );
    std::fs::write(d.join("held.yaml"), text).unwrap();
    rollfric_ok(&["synth", "held.yaml", "-o", "held.avi"], d);
    let video = d.join("held.avi");
    let once = detect(&video, &DetectOptions::default()).unwrap();
    let twice = detect(
        &video,
        &DetectOptions {
            decode_once: false,
            ..DetectOptions::default()
        },
    )
    .unwrap();
    assert_eq!((once.decodings, twice.decodings), (1, 2));
    assert_eq!(once.rows.len(), 201, "a row per frame (0 to 8 s)");
    assert!(once.to_csv() == twice.to_csv(), "the CSVs differ");
    assert_eq!(
        (once.pivot_px, once.roi),
        (twice.pivot_px, twice.roi),
        "pivot and region"
    );
    // And the command line says how often it decoded.
    let (_, said) = rollfric_ok(&["detect", "held.avi", "-o", "angles.csv"], d);
    assert!(said.contains("decoded once"), "{said}");
    // The processor time is split where the streaming pass starts (the first look and
    // its geometry before, a cost fixed per video), and the command line gives the part
    // before it within the whole.
    let cpu = once.cpu_s.expect("the processor time is read from /proc");
    assert!(cpu.before_pass >= 0.0 && cpu.pass >= 0.0, "{cpu:?}");
    let figure = |from: &str, to: &str, last: bool| -> f64 {
        let part = said.split(from).nth(1 - usize::from(last)).unwrap_or("");
        let part = if last {
            part.rsplit(", ").next()
        } else {
            part.split(to).next()
        };
        part.and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no figure in: {said}"))
    };
    let total = figure("CPU besides the decoder ", " s, ", false);
    let before = figure(" s of it before the pass", "", true);
    assert!((0.0..=total).contains(&before), "{said}");
}

/// A look shrunk to half size can take a wire and its blurred shadow for one line: a
/// 960x540 twin (sweep seed 2 scene 16: a 2 px wire, its shadow 3.2 deg away, the
/// fulcrum 16 px left of the frame) was looked at shrunk twice, where the merged line
/// met 5 px from the pivot, and the pass at that scale followed the shadow as often as
/// the wire (2.1 deg RMS, its lines turning 1.058 times as much as its angles). The
/// pass's own swing scale says so, and the look at full size is then measured too.
#[test]
fn a_look_that_merged_the_wire_with_its_shadow_is_measured_again_at_the_other_scale() {
    if !need_ffmpeg() {
        return;
    }
    use rollfric::detect::{detect, DetectOptions};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "copper",
        "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  fps: 50\n  \
         style: oblique\n  seed: 2016\n  rest_angle_deg: -0.0\n  \
         shadow: {angle_deg: -3.2, blur_px: 3.0, strength: 0.32}\n  \
         pivot_frac: [-0.0168, 0.5873]\n  duration_s: 12\n",
    );
    std::fs::write(d.join("cu.yaml"), text).unwrap();
    rollfric_ok(
        &["synth", "cu.yaml", "-o", "cu.avi", "--truth", "truth.csv"],
        d,
    );
    let det = detect(&d.join("cu.avi"), &DetectOptions::default()).unwrap();
    std::fs::write(d.join("angles.csv"), det.to_csv()).unwrap();
    let s = det.swing_scale.unwrap();
    assert!((s - 1.0).abs() < 0.005, "swing scale {s}");
    assert!(
        det.decodings >= 3,
        "measured again: {} decodings",
        det.decodings
    );
    let rms = scatter_deg(&ok_errors_against_truth(d));
    assert!(rms < 0.03, "angle RMS {rms:.4} deg");
}

/// A phone held in the hand (a shift of 2.5 px RMS and a turn of 0.3 deg RMS about 5
/// Hz): the detector measures the camera's motion against the first frame and steadies
/// every frame, so the angles are the plate's. Unsteadied, the turn alone is 0.3 deg of
/// error, and the pivot moving with the picture more (0.26 deg RMS when the turn was not
/// measured); steadied, 0.082 deg.
#[test]
fn a_hand_held_twin_is_steadied_onto_its_first_frame() {
    let Some((detected, rms)) = moving_twin(
        "steel",
        "  s_r_m: 4.508e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  \
         fps: 25\n  style: dark-wire\n  seed: 2\n  duration_s: 20\n  \
         shake: {px: 2.5, deg: 0.3, hz: 5}\n",
    ) else {
        return;
    };
    assert!(
        detected.contains("the camera moved (RMS"),
        "no camera motion reported: {detected}"
    );
    assert!(rms <= 0.12, "angle RMS {rms:.4} deg");
}

/// A tripod swaying slowly in a plain room (seed 8897's sweep scene 55, cut to 12 s:
/// 960x540 at 60 fps, an oblique view, 1.6 px and 0.06 deg at 0.7 Hz): the plain plate
/// fixes each frame's motion only to a few hundredths of a pixel, and the frames warped
/// back by it carried that noise into the angles (0.0302 deg RMS against the truth). The
/// motions' frame-to-frame departures explain it, and it is taken out (0.0212).
#[test]
fn the_steadying_s_own_noise_is_taken_out_of_the_angles() {
    let Some((detected, rms, json)) = twin_summary(
        "glass",
        "  s_r_m: 3.714e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  fps: 60\n  \
         style: oblique\n  seed: 8897055\n  rest_angle_deg: -177.1\n  flicker_hz: 100\n  \
         flicker_depth: 0.088\n  shake: {px: 1.58, deg: 0.059, hz: 0.69}\n  duration_s: 12\n",
    ) else {
        return;
    };
    assert!(
        detected.contains("frame-to-frame noise taken out of the angles"),
        "{detected}"
    );
    assert!(rms <= 0.024, "angle RMS {rms:.4} deg: {detected}");
    let taken = json["camera"]["jitter_deg"].as_f64().expect("jitter_deg");
    assert!(taken > 0.01 && taken < 0.04, "{taken} deg taken out");
}

/// Experiment `name` with the twin `synthetic` (the lines of its `synthetic:` block),
/// rendered and detected in a folder of its own (see [`twin_detected`]): what `detect`
/// said, and the RMS of its `ok` angles' errors against the truth about their mean, deg.
/// None without ffmpeg.
fn moving_twin(name: &str, synthetic: &str) -> Option<(String, f64)> {
    twin_summary(name, synthetic).map(|(detected, rms, _)| (detected, rms))
}

/// [`moving_twin`], and the summary `detect --json` wrote.
fn twin_summary(name: &str, synthetic: &str) -> Option<(String, f64, serde_json::Value)> {
    if !need_ffmpeg() {
        return None;
    }
    let dir = tempfile::tempdir().unwrap();
    let detected = twin_detected(dir.path(), &with_synthetic(name, synthetic));
    let rms = scatter_deg(&ok_errors_against_truth(dir.path()));
    let json = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    Some((detected, rms, serde_json::from_str(&json).unwrap()))
}

/// `text`, an experiment with a twin, written to `d/twin.yaml` and rendered there to
/// `video` (its truth `truth.csv`).
fn twin_rendered(d: &Path, text: &str, video: &str) {
    std::fs::write(d.join("twin.yaml"), text).unwrap();
    rollfric_ok(
        &["synth", "twin.yaml", "-o", video, "--truth", "truth.csv"],
        d,
    );
}

/// `text`, an experiment with a twin, rendered in `d` (`twin.mp4`, its truth
/// `truth.csv`) and detected (`angles.csv`, its summary `summary.json`): what `detect`
/// said.
fn twin_detected(d: &Path, text: &str) -> String {
    twin_rendered(d, text, "twin.mp4");
    rollfric_ok(
        &[
            "detect",
            "twin.mp4",
            "-o",
            "angles.csv",
            "--json",
            "summary.json",
        ],
        d,
    )
    .1
}

/// A hand-held camera the first look takes for still: at 2560x1440 the look works shrunk
/// four times, where the glances' motions (a few tenths of a degree) explain too few of
/// the pixels to count. The pass's later glances find it moving from the start, and the
/// video is measured again with every frame steadied: before, the first 3.5 s were
/// measured where they lay and called `ok` (0.16 deg RMS against the truth, 0.008 now).
#[test]
fn a_camera_moving_from_the_start_that_the_look_took_for_still_is_measured_steadied() {
    let Some((detected, rms)) = moving_twin(
        "glass",
        "  s_r_m: 3.714e-6\n  psi0_deg: 10\n  width: 2560\n  height: 1440\n  \
         fps: 25\n  style: dark-wire\n  seed: 3\n  duration_s: 6\n  \
         shake: {px: 2, deg: 0.3, hz: 5}\n",
    ) else {
        return;
    };
    assert!(
        detected.contains("the camera moved from the start, which the first look took for still"),
        "{detected}"
    );
    assert!(detected.contains("the camera moved (RMS"), "{detected}");
    assert!(rms <= 0.03, "angle RMS {rms:.4} deg");
}

/// A hand-held camera shaking at 7.5 Hz over a plain room (seed 2's sweep, scene 54, cut
/// to 20 s: 640x480, 1.84 px and 0.18 deg): each of the glances that judge whether the
/// camera moved, 2 s apart, sees it at a random phase, and none found it moving. Taken
/// for still throughout, its angles carried the shake, 0.35 deg RMS off the truth,
/// `suspect (smooth)`. What jitters from a look that took the camera for still is
/// measured again from a look steadied throughout, and kept when that is `ok`.
#[test]
fn a_shake_no_glance_caught_is_measured_again_from_a_steadied_look() {
    let Some((detected, rms)) = moving_twin(
        "copper",
        "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 640\n  height: 480\n  \
         fps: 30\n  style: oblique\n  seed: 2054\n  rest_angle_deg: 82.8\n  \
         wire_width_px: 2\n  wire_contrast: 0.50\n  \
         shake: {px: 1.84, deg: 0.180, hz: 7.5}\n  duration_s: 20\n",
    ) else {
        return;
    };
    assert!(
        detected.contains("measuring again from a look steadied throughout"),
        "{detected}"
    );
    assert!(detected.contains("the camera moved (RMS"), "{detected}");
    assert!(detected.contains("detection ok"), "{detected}");
    assert!(rms <= 0.04, "angle RMS {rms:.4} deg");
}

/// A hand-held camera over a plain plate (faint shading, a protractor at the frame's
/// edge, the pivot just beyond it): the measuring scale of the alignment fixes the
/// camera's turn poorly, the coarser scale well. The turn was held at none in most
/// frames, and each angle carried the turn's error (0.09 deg RMS over these 10 s,
/// `suspect (turn)`; seed 4's sweep, scene 16); the turn the coarser scale measured is
/// now kept, and the angles follow the truth.
#[test]
fn a_hand_held_camera_whose_turn_only_the_coarser_scale_fixes_is_steadied() {
    let Some((detected, rms)) = moving_twin(
        "carbon-fiber",
        "  s_r_m: 5.81e-6\n  psi0_deg: 10\n  width: 1280\n  height: 720\n  \
         fps: 25\n  style: oblique\n  seed: 4016\n  rest_angle_deg: -3.9\n  \
         mirror: true\n  wire_width_px: 2\n  wire_contrast: 1.00\n  \
         pivot_frac: [-0.0310, 0.4717]\n  shake: {px: 3.48, deg: 0.462, hz: 4.8}\n  \
         vfr_jitter: 0.35\n  duration_s: 10\n",
    ) else {
        return;
    };
    assert!(detected.contains("the camera moved (RMS"), "{detected}");
    assert!(detected.contains("detection ok"), "{detected}");
    assert!(rms <= 0.03, "angle RMS {rms:.4} deg");
}

/// Seed 2's sweep, scene 49, cut to 16 s: a ball held 1.97 s under a camera swaying
/// 1.1 px (960x540, a ruled board).
const SCENE_49: &str = "  s_r_m: 5.81e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  \
                        fps: 30\n  style: dark-wire\n  seed: 2049\n  rest_angle_deg: 96.8\n  \
                        mirror: true\n  wire_width_px: 1\n  wire_contrast: 0.63\n  \
                        hold_s: 1.97\n  shake: {px: 1.11, deg: 0.057, hz: 0.27}\n  \
                        vfr_jitter: 0.20\n  room: {board: ruled}\n  duration_s: 16\n";

/// A ball held for 2 s under a slowly swaying camera (seed 2's sweep, scene 49: 960x540,
/// a ruled board, 1.1 px of sway): every edge moved, so no frame of the still start was
/// dropped, and the look, spent on the held wire, took the protractor's base line
/// through the pivot (steadied a little off) for the moving lines: refused, "the moving
/// lines jump back and forth across 180 deg". Looked at again with the still start
/// judged under the camera's motion, the wire is found and followed.
#[test]
fn a_ball_held_under_a_moving_camera_is_not_the_look_s_whole_view() {
    let Some((detected, rms)) = moving_twin("carbon-fiber", SCENE_49) else {
        return;
    };
    assert!(detected.contains("the camera moved (RMS"), "{detected}");
    assert!(rms <= 0.04, "angle RMS {rms:.4} deg");
}

/// The same held ball let go by the operator's hand (seed 2's sweep, scene 49 as it is
/// now drawn): the hand drawing back moved the scene and the look found a wire, but one
/// that swept 3 deg (the held wire and the swing's first moments), whose lines put the
/// pivot 37 px down the wire: the angles swung 24 % too far, 1.3 deg RMS against the
/// truth over 40 s, called `ok`. The look is taken again with the still start judged
/// under the camera's motion, and sees the wire sweep 20 deg about its pivot.
#[test]
fn a_hand_releasing_a_held_ball_under_a_swaying_camera_does_not_leave_the_look_a_sliver() {
    let Some((detected, rms)) =
        moving_twin("carbon-fiber", &format!("{SCENE_49}  release_hand: true\n"))
    else {
        return;
    };
    assert!(detected.contains("the camera moved (RMS"), "{detected}");
    assert!(detected.contains("(swing scale 1.00"), "{detected}");
    assert!(rms <= 0.04, "angle RMS {rms:.4} deg");
}

/// A phone in the hand whose rolling shutter reads its rows out over 0.8 of the frame's
/// interval (640x480 at 30 fps, 2.5 px and 0.3 deg at 5 Hz): each frame steadied by one
/// shift and turn, the wire still leaned by the camera's motion over its rows (0.134 deg
/// RMS against the truth, `suspect (turn)`). The readout is fitted to the angles and the
/// lean taken out; the same twin with a global shutter is left as it is.
#[test]
fn a_rolling_shutter_s_lean_under_a_hand_held_camera_is_taken_out() {
    let keys = "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 640\n  height: 480\n  \
                fps: 30\n  style: dark-wire\n  seed: 5\n  duration_s: 12\n  \
                shake: {px: 2.5, deg: 0.3, hz: 5}\n";
    let Some((detected, rms)) = moving_twin("copper", &format!("{keys}  rolling_shutter: 0.8\n"))
    else {
        return;
    };
    assert!(
        detected.contains("a rolling shutter read out over"),
        "{detected}"
    );
    assert!(rms <= 0.06, "angle RMS {rms:.4} deg");
    let (global, rms) = moving_twin("copper", keys).expect("ffmpeg is there");
    assert!(!global.contains("rolling shutter"), "{global}");
    assert!(rms <= 0.02, "angle RMS {rms:.4} deg");
}

/// A still camera whose rows are read out over 0.9 of a 30 fps frame's interval (960x540,
/// the pivot just above the frame, so the wire lies in the picture's upper half): each
/// row sees the wire at its own time, and the angle, fitted to the wire's rows, is that
/// of about 3 ms before the frame's time (its middle row's), 0.040 deg RMS against the
/// truth. The readout is fitted to how the moving wire bows (30.2 ms of the 30.0) and
/// each angle taken to the frame's time (0.0075 deg RMS); the same twin with a global
/// shutter says nothing of a shutter.
#[test]
fn a_rolling_shutter_s_lag_on_the_moving_wire_is_fitted_from_its_bow_and_taken_out() {
    let keys = "  s_r_m: 4.445e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  \
                fps: 30\n  style: dark-wire\n  seed: 7\n  pivot_frac: [0.5, -0.04]\n  \
                duration_s: 12\n";
    let Some((detected, rms, json)) =
        twin_summary("aluminum", &format!("{keys}  rolling_shutter: 0.9\n"))
    else {
        return;
    };
    let said = "a rolling shutter: its rows read out over ";
    let ms: f64 = detected
        .split(said)
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no readout said: {detected}"));
    assert!((ms - 30.0).abs() < 1.5, "readout {ms} ms: {detected}");
    assert!(rms <= 0.015, "angle RMS {rms:.4} deg: {detected}");
    // `detect --json` carries it, as said.
    let shutter = &json["shutter"];
    assert!(
        (shutter["rows_ms"].as_f64().unwrap() - ms).abs() < 0.051,
        "{shutter} against {ms} ms said"
    );
    assert!(shutter["u_rows_ms"].as_f64().unwrap() > 0.0, "{shutter}");
    assert!(shutter["max_lag_ms"].as_f64().unwrap() > 0.0, "{shutter}");
    let (global, rms, json) = twin_summary("aluminum", keys).expect("ffmpeg is there");
    assert!(!global.contains("rolling shutter"), "{global}");
    assert!(rms <= 0.015, "angle RMS {rms:.4} deg");
    assert!(json.get("shutter").is_none(), "{json}");
}

/// A camera swaying 1.2 px beside a second pendulum (seed 2's sweep, scene 32, cut to
/// 12 s: 640x480, two balls among the strongest gradients): one glance of the look in
/// 12 explained its frame, the camera was taken for still, and its static edges were
/// the moving lines: refused, "the moving lines turn irregularly". The look that finds
/// no wire is steadied and searched again: the wire is followed, on the camera's
/// motion, and the detection says when it doubts.
#[test]
fn a_look_refused_as_it_lies_is_steadied_when_a_glance_found_the_camera_moved() {
    let Some((detected, rms)) = moving_twin(
        "aluminum",
        "  s_r_m: 4.445e-6\n  psi0_deg: 10\n  width: 640\n  height: 480\n  fps: 30\n  \
         style: oblique\n  seed: 2032\n  rest_angle_deg: 37.4\n  wire_width_px: 2\n  \
         wire_contrast: 0.89\n  flicker_hz: 120\n  flicker_depth: 0.035\n  \
         shake: {px: 1.23, deg: 0.041, hz: 0.59}\n  lens_k1: -0.174\n  \
         room: {second_string: true}\n  duration_s: 12\n",
    ) else {
        return;
    };
    assert!(detected.contains("the camera moved (RMS"), "{detected}");
    // On the wire (measured: 0.10 deg, the lens left uncorrected), and `ok` only if
    // within the sweep's 0.05 deg.
    assert!(rms <= 0.2, "angle RMS {rms:.4} deg");
    assert!(
        rms <= 0.05 || !detected.contains("detection ok"),
        "{detected}"
    );
}

/// A slow drift (2.6 px over 12 s, 640x480) the first look takes for still: the pass's
/// glances find it moving at 8 s, the frames before measured where they lay (0.16 deg
/// RMS against the truth, `suspect (rest)`). The video is measured again, every frame
/// of the region steadied onto the first.
#[test]
fn a_drift_found_late_is_measured_again_with_every_frame_steadied() {
    let Some((detected, rms)) = moving_twin(
        "glass",
        "  s_r_m: 3.714e-6\n  psi0_deg: 10\n  width: 640\n  height: 480\n  fps: 50\n  \
         style: oblique\n  seed: 4057\n  rest_angle_deg: -95.4\n  mirror: true\n  \
         flicker_hz: 120\n  flicker_depth: 0.039\n  shake: {drift_px: 2.6}\n  \
         room: {edges: 1}\n  duration_s: 12\n",
    ) else {
        return;
    };
    assert!(
        detected.contains("the camera was found moving at")
            && detected.contains("measuring again with every frame steadied"),
        "{detected}"
    );
    assert!(
        detected.contains("each frame was steadied onto the first"),
        "{detected}"
    );
    assert!(rms <= 0.03, "angle RMS {rms:.4} deg");
}

/// A tripod swaying 1.07 px and 0.05 deg every 4 s (1280x720): the pass's glances, 2 s
/// apart, each see it at the opposite phase and never two in a row agree, so the camera
/// is taken for still, and two glances in a row find the static scene off (before: 0.15 deg
/// RMS against the truth, `suspect (still)`). The video is measured again, every frame
/// of the region steadied onto the first, and that measurement is `ok`.
#[test]
fn a_sway_the_glances_never_confirmed_is_measured_again_with_every_frame_steadied() {
    let Some((detected, rms)) = moving_twin(
        "glass-fiber-fabric",
        "  s_r_m: 53.023e-6\n  psi0_deg: 15\n  width: 1280\n  height: 720\n  fps: 60\n  \
         style: oblique\n  seed: 4004\n  rest_angle_deg: -47.7\n  \
         shake: {px: 1.07, deg: 0.051, hz: 0.25}\n  room: {board: ruled}\n  \
         duration_s: 12\n",
    ) else {
        return;
    };
    assert!(
        detected.contains("the static scene lies off at two glances in a row")
            && detected.contains("measuring again with every frame steadied"),
        "{detected}"
    );
    assert!(detected.contains("detection ok"), "{detected}");
    assert!(rms <= 0.03, "angle RMS {rms:.4} deg");
}

/// The detected angle minus the true one, deg, of every `ok` frame of `d/csv` whose
/// truth is unspoiled, and the number of frames.
fn ok_errors_deg(d: &Path, csv: &str) -> (Vec<f64>, usize) {
    let t = read(&d.join("truth.csv"), "spoiled");
    let a = read(&d.join(csv), "status");
    let e = t
        .iter()
        .zip(&a)
        .filter(|(tr, de)| de.tag == "ok" && tr.tag == "none")
        .filter_map(|(tr, de)| Some((de.angle? - tr.angle?).to_degrees()))
        .collect();
    (e, a.len())
}

/// A slow drift of 11 px over 20 s at 640x480 (MJPG, a wide lens, a hand's release;
/// seed 43's scene 0 of the robustness sweep, shortened): no two glances in a row find
/// the camera moving, the last ones find the static scene off, and the first
/// measurement's own angles show the harm besides (`pivot`, `envelope`: 0.82 deg RMS
/// against the truth). Steadied, the angle's noise grows by 0.019 deg, more than a
/// measurement whose only failure is `still` may gain: the second measurement is kept
/// all the same, since the first's angles failed on their own.
#[test]
fn a_drift_that_spoiled_the_angles_is_measured_steadied_though_steadying_adds_noise() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "polycarbonate",
        "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 640\n  height: 480\n  fps: 50\n  \
         style: oblique\n  seed: 43000\n  rest_angle_deg: 107.6\n  mirror: true\n  \
         shadow: {angle_deg: -5.0, blur_px: 2.7, strength: 0.38}\n  hold_s: 0.89\n  \
         shake: {drift_px: 11.1}\n  vfr_jitter: 0.20\n  lens_k1: -0.134\n  \
         room: {edges: 1}\n  rolling_shutter: 0.70\n  release_hand: true\n  \
         duration_s: 20\n",
    );
    twin_rendered(d, &text, "twin.avi");
    let (_, detected) = rollfric_ok(&["detect", "twin.avi", "-o", "angles.csv"], d);
    assert!(
        detected.contains("measuring again with every frame steadied")
            && !detected.contains("the first measurement is kept"),
        "{detected}"
    );
    assert!(detected.contains("detection ok"), "{detected}");
    let rms = scatter_deg(&ok_errors_against_truth(d));
    assert!(rms <= 0.05, "angle RMS {rms:.4} deg");
}

/// A still camera (960x540, 25 fps, CRF 34, a light wire) whose first frame holds the
/// hand that lets the ball go, and a person walking in front of the wire at 10.4 s
/// (seed 1205's sweep, scene 36). Its last two glances find the static scene 0.65 px
/// off the first frame's, but 0.38 px off the first glance's, 2 s in, itself 0.27 px
/// off the first frame: the hand lay in the first frame, and the camera is taken as
/// still. (Measured again steadied onto the
/// first frame, the still camera was read turning by up to 0.16 deg for seconds, and by
/// 3 deg as the person passed: 0.082 deg RMS off the truth, three frames beside the
/// person `ok` 0.5 to 0.8 deg off.) The frame before the person hid the wire, seen on
/// half of it 0.9 deg off, is not `ok`: beside a loss of the wire, a frame 0.3 deg off
/// the swing's path is flagged.
#[test]
fn a_hand_in_the_first_frame_is_no_drift_and_a_walker_hides_no_ok_frame() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "aluminum",
        "  s_r_m: 4.445e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  fps: 25\n  \
         style: light-wire\n  seed: 1205036\n  rest_angle_deg: -66.6\n  flicker_hz: 100\n  \
         flicker_depth: 0.144\n  hold_s: 1.15\n  crf: 34\n  room: {walker_s: 8.9}\n  \
         dropped_share: 0.025\n  release_hand: true\n  duration_s: 40\n",
    );
    twin_rendered(d, &text, "twin.mp4");
    let (_, detected) = rollfric_ok(
        &[
            "detect",
            "twin.mp4",
            "-o",
            "angles.csv",
            "--json",
            "summary.json",
        ],
        d,
    );
    assert!(
        !detected.contains("measuring again") && detected.contains("detection ok"),
        "{detected}"
    );
    // The `still` check's figure is the first glance's reading (0.38 px; from the
    // first frame, 0.65).
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("summary.json")).unwrap()).unwrap();
    let still = summary["checks"]
        .as_array()
        .expect("checks")
        .iter()
        .find(|c| c["check"] == "still")
        .cloned()
        .expect("a `still` check");
    let px = still["value"].as_f64().unwrap();
    assert!(px > 0.2 && px < 0.5, "{still}");
    let (e, _) = ok_errors_deg(d, "angles.csv");
    let rms = (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
    assert!(rms <= 0.04, "angle RMS {rms:.4} deg");
    let t = read(&d.join("truth.csv"), "spoiled");
    let a = read(&d.join("angles.csv"), "status");
    let hidden_off: Vec<f64> = t
        .iter()
        .zip(&a)
        .filter(|(tr, de)| tr.tag == "walker" && de.tag == "ok")
        .filter_map(|(tr, de)| Some((de.angle? - tr.angle?).to_degrees()))
        .filter(|e| e.abs() > 0.5)
        .collect();
    assert!(hidden_off.is_empty(), "walker frames ok: {hidden_off:?}");
}

/// The mean of the detected angle minus the true one over the frames of `csv` (in
/// `d`, against `d/truth.csv`) both give, deg.
fn mean_error_deg(d: &Path, csv: &str) -> f64 {
    let (e, frames) = ok_errors_deg(d, csv);
    assert!(e.len() * 10 >= frames * 8, "{} of {frames} frames", e.len());
    e.iter().sum::<f64>() / e.len() as f64
}

/// A light wire 1 px wide, faint, and its dark shadow 4.8 deg off it (the light from
/// one side): the first look sees both swing about the pivot, in 27 and 26 directions,
/// and took the shadow (the angles 4.8 deg off, 0.11 deg RMS about that, called `ok`:
/// seed 4's sweep, scene 40). It cannot tell which is the wire, so it says so:
/// `suspect (polarity)`, naming `video.polarity`, which measures the wire. The shadow
/// does not pass through the pivot along its own line: its swing scale reads 1.0078,
/// which the `pivot` check calls off, and the other scale's look is measured, which
/// takes the wire.
#[test]
fn a_light_wire_and_its_dark_shadow_alike_are_said_and_polarity_picks_the_wire() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "aluminum",
        "  s_r_m: 4.445e-6\n  psi0_deg: 10\n  width: 1920\n  height: 1080\n  \
         fps: 50\n  style: light-wire\n  seed: 4040\n  rest_angle_deg: 88.4\n  \
         mirror: true\n  wire_width_px: 1\n  wire_contrast: 0.52\n  \
         shadow: {angle_deg: -4.8, blur_px: 2.0, strength: 0.48}\n  duration_s: 10\n",
    );
    // The shrunk look takes the dark shadow, whose pass turns 1.008 times as much as
    // its angle: measured again from the finer look, the light wire is kept (nearer 1),
    // and the shadow beside it said (it was followed, 4.7 deg off, while a swing scale
    // within 2 % of 1 was not measured again).
    let said = twin_detected(d, &text);
    assert!(
        said.contains("measuring again from a look at a finer working scale"),
        "{said}"
    );
    assert!(said.contains("detection suspect (polarity"), "{said}");
    assert!(said.contains("`video.polarity: dark`"), "{said}");
    let off = mean_error_deg(d, "angles.csv");
    assert!(off.abs() < 0.05, "mean error {off:.3} deg");
    // Told the wire's polarity, the detector measures the wire, and no rival is said.
    let told = text.replace("\nsynthetic:", "\nvideo:\n  polarity: light\nsynthetic:");
    std::fs::write(d.join("told.yaml"), told).unwrap();
    let said = rollfric_ok(
        &[
            "detect",
            "twin.mp4",
            "-o",
            "told.csv",
            "--experiment",
            "told.yaml",
        ],
        d,
    )
    .1;
    assert!(
        said.contains("light wire") && !said.contains("polarity:"),
        "{said}"
    );
    let off = mean_error_deg(d, "told.csv");
    assert!(off.abs() < 0.05, "mean error {off:.3} deg");
}

/// Seed 31's sweep scene 1, cut to 12 s: the ball is held still for 1.5 s while a
/// second string swings beside it, so the first look (2.5 s) sees only the string
/// move, takes its pivot, and the pass follows it smoothly to the end, every check on
/// the angles passing (`ok` before the `length` check, 5.9 deg RMS off the pendulum
/// over 40 s). Given the experiment, the detection judges the period it saw against
/// the geometry's: 1.612 s implies d = 0.054 m, not 0.183 m (`suspect (length)`). It
/// then looks again from 2.5 s, where the pendulum swings, finds its pivot, measures
/// the video again about it, and keeps that measurement, whose period is the
/// pendulum's. (Rendered without its heavy compression, `crf: 34`, the look sees both
/// swing and the video is refused as two pendulums.)
#[test]
fn a_second_pendulum_followed_in_place_of_the_first_is_left_for_the_first() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "polycarbonate",
        "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 640\n  height: 480\n  \
         fps: 30\n  style: light-wire\n  seed: 31001\n  rest_angle_deg: 157.8\n  \
         hold_s: 1.50\n  crf: 34\n  room: {edges: 3, second_string: true}\n  \
         rolling_shutter: 0.67\n  dropped_share: 0.011\n  release_hand: true\n  \
         duration_s: 12\n",
    );
    twin_rendered(d, &text, "twin.avi");
    let said = rollfric_ok(
        &[
            "detect",
            "twin.avi",
            "-o",
            "angles.csv",
            "--experiment",
            "twin.yaml",
            "--json",
            "summary.json",
        ],
        d,
    )
    .1;
    assert!(
        said.contains("the period seen is not the pendulum's (suspect (length))")
            && said.contains("a look from 2.5 s finds another pivot")
            && !said.contains("px it is ")
            && !said.contains("px it measures nothing"),
        "{said}"
    );
    assert!(said.contains("detection ok"), "{said}");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("summary.json")).unwrap()).unwrap();
    let checks = summary["checks"].as_array().expect("checks");
    let length = checks
        .iter()
        .find(|c| c["check"] == "length")
        .expect("a `length` check");
    assert_eq!(length["passed"], true, "{length}");
    let (e, _) = ok_errors_deg(d, "angles.csv");
    let rms = (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
    assert!(rms < 0.05, "angle RMS {rms:.4} deg");
}

/// A room that is not empty: a gridded board behind the pendulum, two static edges near
/// the fulcrum, a second pendulum swinging beside the first, and a person walking
/// through who covers the wire for about a second. The two pendulums are told apart
/// (refused, naming both, until a pivot says which). The track stays on the wire: the
/// frames the walker covers are `missing` or `corrected`, never `ok` on something else,
/// and the other frames are measured as in an empty room (0.0073 deg; 0.0056 empty).
#[test]
fn a_twin_in_a_busy_room_is_measured_and_its_occluded_frames_are_not_ok() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "steel",
        "  s_r_m: 4.508e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  \
         fps: 25\n  style: dark-wire\n  seed: 2\n  duration_s: 20\n  \
         room: {board: grid, edges: 2, second_string: true, walker_s: 6}\n",
    );
    std::fs::write(d.join("room.yaml"), text).unwrap();
    rollfric_ok(
        &[
            "synth",
            "room.yaml",
            "-o",
            "room.mp4",
            "--truth",
            "truth.csv",
        ],
        d,
    );
    // Two pendulums: refused, naming both pivots, until a pivot says which; the first
    // pendulum's hangs in the frame's middle column (480 px), the second's beside it.
    let out = common::rollfric(&["detect", "room.mp4", "-o", "angles.csv"], d);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("two pendulums"),
        "{err}"
    );
    let pivots = rollfric::detect::pivots_named(&err);
    assert_eq!(pivots.len(), 2, "{err}");
    let first = pivots
        .iter()
        .min_by(|a, b| (a[0] - 480.0).abs().total_cmp(&(b[0] - 480.0).abs()))
        .unwrap();
    assert!((first[0] - 480.0).abs() < 20.0, "{err}");
    let pivot = format!("{},{}", first[0], first[1]);
    rollfric_ok(
        &["detect", "room.mp4", "-o", "angles.csv", "--pivot", &pivot],
        d,
    );
    let t = read(&d.join("truth.csv"), "spoiled");
    let a = read(&d.join("angles.csv"), "status");
    assert_eq!(t.len(), a.len(), "one row per frame");
    let walked = t.iter().filter(|r| r.tag == "walker").count();
    assert!(walked >= 10, "the walker covers {walked} frames");
    let mut clear = Vec::new();
    let mut clear_frames = 0;
    for (tr, de) in t.iter().zip(&a) {
        let err = de.angle.map(|x| x - tr.angle.unwrap());
        match tr.tag.as_str() {
            "walker" if de.tag == "ok" => {
                let e = err.unwrap().abs().to_degrees();
                assert!(e <= 0.5, "a covered frame called ok {e:.2} deg off");
            }
            "none" => {
                clear_frames += 1;
                if de.tag == "ok" {
                    clear.push(err.unwrap());
                }
            }
            _ => {}
        }
    }
    assert!(
        clear.len() * 100 >= clear_frames * 95,
        "{} of {clear_frames} clear frames ok",
        clear.len()
    );
    let rms = scatter_deg(&clear);
    assert!(rms <= 0.02, "angle RMS {rms:.4} deg");
}

/// Through a wide lens (barrel, k1 = -0.24, given), a fulcrum 4 % beyond the frame's
/// side is refined onto the wire's lines. Each frame's wire is a slight curve in the
/// image; its free line, a chord of it taken into the undistorted view by two of its
/// points, lay up to 0.17 px off the undistorted wire, more at the swing's ends, and
/// the lines (seen over 20 deg) met 0.8 px short along the wire: the swing 0.38 % wide
/// on this twin drawn clean (seed 1's sweep scene 21, 0.55 % with its camera's defects,
/// `ok`). Each strip's pixels are now taken into the undistorted view one by one.
#[test]
fn a_pivot_beyond_the_edge_of_a_wide_lens_is_refined_onto_the_wire() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let synthetic = "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 1280\n  height: 720\n  \
         fps: 30\n  style: light-wire\n  seed: 1021\n  clean: true\n  rest_angle_deg: 3.2\n  \
         mirror: true\n  wire_width_px: 1\n  wire_contrast: 0.73\n  \
         pivot_frac: [-0.0350, 0.4155]\n  lens_k1: -0.240\n  duration_s: 20\n";
    let text = with_synthetic("copper", synthetic).replace(
        "\nsynthetic:",
        "\nvideo:\n  lens: {k1: -0.24, u_k1: 0.0002}\nsynthetic:",
    );
    std::fs::write(d.join("lens.yaml"), text).unwrap();
    let (_, rendered) = rollfric_ok(
        &[
            "synth",
            "lens.yaml",
            "-o",
            "lens.avi",
            "--truth",
            "truth.csv",
        ],
        d,
    );
    let (_, detected) = rollfric_ok(
        &[
            "detect",
            "--experiment",
            "lens.yaml",
            "lens.avi",
            "-o",
            "angles.csv",
        ],
        d,
    );
    let (want, got) = (pivot_in(&rendered), pivot_in(&detected));
    assert!(
        (got.0 - want.0).abs() <= 0.25 && (got.1 - want.1).abs() <= 0.25,
        "refined to {got:?} px, rendered at {want:?}"
    );
    let slope = swing_scale_against(&read(&d.join("truth.csv"), "spoiled"), d);
    assert!(
        (slope - 1.0).abs() <= rollfric::uncertainty::DETECTOR_SCALE_REL,
        "the swing measured {:+.3} % of its size",
        100.0 * (slope - 1.0)
    );
}

/// A wide lens (barrel, k1 = -0.24) and a fulcrum just off the frame's left edge, where
/// the distortion is strongest: measured as the image shows it, the swing is off by
/// several percent (0.60 deg angle RMS); with `video.lens` giving the coefficient, each
/// angle and the pivot are measured in the undistorted view (0.029 deg). The
/// coefficient `rollfric lens` fits from a gridded sheet filmed through the same lens
/// (a second of the same camera's twin with a grid over its plate) is the lens's, and
/// undoes it as well. Measured with none, the wire's own bow says a lens bent it
/// (`bent`), and how much.
#[test]
fn a_wide_lens_is_undone_when_its_coefficient_is_given_or_fitted_from_a_sheet() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let synthetic = "  s_r_m: 4.508e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  \
         fps: 25\n  style: dark-wire\n  seed: 2\n  duration_s: 20\n  \
         pivot_frac: [-0.035, 0.4155]\n  rest_angle_deg: 3.2\n  lens_k1: -0.24\n";
    std::fs::write(d.join("lens.yaml"), with_synthetic("steel", synthetic)).unwrap();
    std::fs::write(
        d.join("known.yaml"),
        format!(
            "{}video:\n  lens: {{k1: -0.24, u_k1: 0.01}}\n",
            with_synthetic("steel", synthetic)
        ),
    )
    .unwrap();
    rollfric_ok(
        &[
            "synth",
            "lens.yaml",
            "-o",
            "lens.mp4",
            "--truth",
            "truth.csv",
        ],
        d,
    );
    // The angles' scatter from the truth, detected with the experiment's `video:` block
    // (its lens) or with none.
    let scatter_with = |experiment: Option<&str>| {
        let mut args = vec!["detect", "lens.mp4", "-o", "angles.csv"];
        args.extend(
            experiment
                .map(|e| ["--experiment", e])
                .into_iter()
                .flatten(),
        );
        let (_, said) = rollfric_ok(&args, d);
        (scatter_deg(&ok_errors_against_truth(d)), said)
    };
    let (seen, said) = scatter_with(None);
    assert!(seen > 0.3, "the lens uncorrected: {seen:.4} deg");
    // The wire's own bow says so, and gives the lens.
    assert!(said.contains("detection suspect (bent)"), "{said}");
    let k1: f64 = common::numbers_after(&said, "the wire's bow gives `lens: {k1: ", ',')[0];
    assert!((k1 + 0.24).abs() < 0.05, "{k1}: {said}");
    let (undone, said) = scatter_with(Some("known.yaml"));
    assert!(undone < 0.05, "the lens undone: {undone:.4} deg");
    assert!(
        !said.contains("(bent") && !said.contains(", bent"),
        "{said}"
    );
    // The plain scene shows no straight line: `rollfric lens` refuses it and says how
    // to declare the lens unknown; so declared, the result says that its scale is not
    // known well enough, with the figure (the swing near the frame's edge).
    let out = common::rollfric(&["lens", "lens.mp4"], d);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && said.contains("`lens: {k1: 0, u_k1: 0.15}`"),
        "{said}"
    );
    std::fs::write(
        d.join("unknown.yaml"),
        format!(
            "{}video:\n  path: lens.mp4\n  lens: {{k1: 0, u_k1: 0.15}}\n",
            with_synthetic("steel", synthetic)
        ),
    )
    .unwrap();
    let (text, _) = rollfric_ok(&["fit", "unknown.yaml", "--cache", "cache"], d);
    assert!(
        text.contains("suspect (") && text.contains("scale: the swing's scale through the lens"),
        "{text}"
    );

    // The sheet: the same camera and lens, a grid over the plate, one second.
    assert!(synthetic.contains("duration_s: 20"));
    let sheet = synthetic.replace("duration_s: 20", "duration_s: 1") + "  room: {board: grid}\n";
    std::fs::write(d.join("sheet.yaml"), with_synthetic("steel", &sheet)).unwrap();
    rollfric_ok(&["synth", "sheet.yaml", "-o", "sheet.mp4"], d);
    let (out, _) = rollfric_ok(&["lens", "sheet.mp4", "--json"], d);
    let fit: serde_json::Value = serde_json::from_str(&out).unwrap();
    let (k1, u) = (fit["k1"].as_f64().unwrap(), fit["u_k1"].as_f64().unwrap());
    assert!((k1 + 0.24).abs() < 0.01, "fitted k1 {k1} +- {u}");
    // 26 frames, every 10th fitted: frames 0, 10 and 20.
    let frames: Vec<u64> = fit["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f[0].as_u64().unwrap())
        .collect();
    assert_eq!(frames, [0, 10, 20]);
    assert!(
        u > 0.0 && u < 0.01 && (k1 + 0.24).abs() < 3.0 * u + 0.002,
        "{k1} +- {u}"
    );
    std::fs::write(
        d.join("fitted.yaml"),
        format!(
            "{}video:\n  lens: {{k1: {k1}, u_k1: {u}}}\n",
            with_synthetic("steel", synthetic)
        ),
    )
    .unwrap();
    let (fitted, _) = scatter_with(Some("fitted.yaml"));
    assert!(fitted < 0.05, "the lens fitted and undone: {fitted:.4} deg");
    // Its text says what to write into the experiment file.
    let (text, _) = rollfric_ok(&["lens", "sheet.mp4"], d);
    assert!(text.contains("lens: {k1: -0.2"), "{text}");
}

/// `detect --steps N` pictures frame N's steps: four pictures of one size, the evidence
/// over its threshold (red) in the third and the measured line (red) in the fourth, and
/// a frame that is not measured is said to be so.
#[test]
fn detect_steps_pictures_one_frame() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = common::short_glass_twin("steps", "3.714e-6", "")
        .replace("duration_s: 20", "duration_s: 4");
    assert!(text.contains("duration_s: 4"), "the twin's duration");
    std::fs::write(d.join("g.yaml"), text).unwrap();
    rollfric_ok(&["synth", "g.yaml", "-o", "g.mp4"], d);
    let (_, said) = rollfric_ok(&["detect", "g.mp4", "-o", "a.csv", "--steps", "60"], d);
    assert!(said.contains("the steps of frame 60: 4 pictures"), "{said}");
    let names = ["1-geometry", "2-background", "3-evidence", "4-angle"];
    let pictures: Vec<_> = names
        .iter()
        .map(|n| {
            let p = d.join(format!("a.steps/frame-000060-{n}.png"));
            let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            rollfric::picture::decode(&bytes).unwrap()
        })
        .collect();
    assert!(pictures
        .iter()
        .all(|p| (p.width, p.height) == (pictures[0].width, pictures[0].height)));
    // Pure red (BGR 40, 40, 255 or the line's 0, 0, 255) below the caption band.
    let red = |p: &rollfric::picture::Decoded| {
        p.pixels
            .chunks_exact(3)
            .skip(20 * p.width)
            .filter(|c| c[2] > 200 && c[0] < 60 && c[1] < 60)
            .count()
    };
    let height = pictures[0].height;
    assert!(red(&pictures[2]) > height, "the evidence over threshold");
    assert!(red(&pictures[3]) > height / 2, "the measured line");
    assert_eq!(red(&pictures[1]), 0, "the background has no red");

    let (_, said) = rollfric_ok(&["detect", "g.mp4", "-o", "b.csv", "--steps", "100000"], d);
    assert!(
        said.contains("--steps 100000: no pictures: that frame was not measured"),
        "{said}"
    );
    assert!(!d.join("b.steps/frame-100000-4-angle.png").exists());
}

/// Flicker of 120 Hz at 50 frames/s, 0.148 deep (the robustness sweep's scene 17,
/// seed 8897, without its drift and second string): two frames in five stray from the
/// running brightness enough to be taken for flashes, left at their own brightness. The
/// typical change from frame to frame was learnt from them too, ten times a real
/// frame's, and every frame after was then taken for a repeat: "the wire was found in
/// only 6 of 601 frames (... flagged: duplicate 581, ...)". A flash no longer teaches
/// the repeat test, nor is the next frame compared with it: every frame is measured.
#[test]
fn deep_flicker_read_as_flashes_leaves_no_frame_taken_for_a_repeat() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = with_synthetic(
        "copper",
        "  s_r_m: 18.986e-6\n  psi0_deg: 10\n  width: 960\n  height: 540\n  \
         fps: 50\n  style: oblique\n  seed: 8897017\n  rest_angle_deg: 5.2\n  mirror: true\n  \
         wire_width_px: 2\n  wire_contrast: 0.48\n  flicker_hz: 120\n  flicker_depth: 0.148\n  \
         hold_s: 0.94\n  duration_s: 12\n",
    );
    twin_rendered(d, &text, "flicker.avi");
    let (_, detected) = rollfric_ok(&["detect", "flicker.avi", "-o", "angles.csv"], d);
    let angles = read(&d.join("angles.csv"), "status");
    let ok = angles.iter().filter(|r| r.tag == "ok").count();
    assert!(
        ok * 10 >= angles.len() * 9,
        "{ok} of {} ok: {detected}",
        angles.len()
    );
    let rms = scatter_deg(&ok_errors_against_truth(d));
    assert!(rms <= 0.05, "angle RMS {rms:.4} deg");
}
