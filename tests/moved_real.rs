//! Real clips (`../shared/fixtures/real/`) filmed as if by a hand-held phone: a moving
//! crop of +-3 px (4.3 and 5.7 Hz) and a turn of 0.3 deg at 5 Hz, made here by ffmpeg at
//! test time and never kept. Detected with no options, each must swing as the same clip
//! cropped still (encoded the same way): the same peak-to-peak angle over the first 4 s
//! within 0.2 deg, and the camera's motion reported. Unsteadied, the green-screen clip
//! lost its wire to a static edge after 4 s (56.16 deg against 58.00), and the split
//! screen's exposure drift led the alignment astray (the other panel taken).
//!
//! The off-screen pivot clip, shrunk to a phone's 960x540 export and moved too, is not
//! yet measured: whatever the detector makes of it must then not be called `ok`. Nor
//! must the red apple and film 1 moved, whose plain wall cannot steady them; and the
//! clips whose README asks for a refusal or a `suspect` keep that outcome moved.

mod common;

use common::{detect_json, fixture, need_ffmpeg, outcomes, rollfric_ok, root};
use std::path::Path;
use std::process::Command;

const STILL: &str = "crop=iw-8:ih-8:4:4";
const MOVED: &str = "rotate=0.3*PI/180*sin(2*PI*5*t):ow=iw:oh=ih:bilinear=1,\
                     crop=iw-8:ih-8:4+3*sin(2*PI*4.3*t):4+3*sin(2*PI*5.7*t+1)";

fn encode(src: &Path, filter: &str, out: &Path) {
    let status = Command::new("ffmpeg")
        .args(["-nostdin", "-v", "error", "-y", "-i"])
        .arg(src)
        .args(["-an", "-vf", filter])
        .args([
            "-c:v", "libx264", "-preset", "veryfast", "-crf", "18", "-pix_fmt", "yuv420p",
        ])
        .arg(out)
        .status()
        .expect("ffmpeg runs");
    assert!(status.success(), "ffmpeg failed to make {}", out.display());
}

/// The detector's summary and the peak-to-peak angle (deg) of the first 4 s.
fn swing(video: &Path, extra: &[&str]) -> (String, f64) {
    let csv = video.with_extension("csv");
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "detect".as_ref(),
        video.as_os_str(),
        "-o".as_ref(),
        csv.as_os_str(),
    ];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    let (_, said) = rollfric_ok(&args, &root());
    (said, peak_to_peak(&csv))
}

/// The peak-to-peak angle (deg) of the first 4 s of an angle CSV.
fn peak_to_peak(csv: &Path) -> f64 {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut t0 = None;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for l in text.lines().skip(1).filter(|l| !l.starts_with('#')) {
        let v: Vec<&str> = l.split(',').collect();
        let t: f64 = v[0].parse().unwrap();
        let t0 = *t0.get_or_insert(t);
        if t - t0 > 4.0 {
            break;
        }
        if let Ok(a) = v[1].parse::<f64>() {
            lo = lo.min(a.to_degrees());
            hi = hi.max(a.to_degrees());
        }
    }
    hi - lo
}

/// A faster hand: 0.4 deg at 7 Hz, +-4 px at 7.9 and 6.3 Hz.
const FASTER: &str = "rotate=0.4*PI/180*sin(2*PI*7*t):ow=iw:oh=ih:bilinear=1,\
                      crop=iw-8:ih-8:4+4*sin(2*PI*7.9*t):4+4*sin(2*PI*6.3*t+1)";

/// `extra`: the detector's flags for both, as a user gives them.
fn check(name: &str, extra: &[&str]) {
    check_moved(name, MOVED, extra);
}

/// [`check`] with the hand's motion `moved` (an ffmpeg filter).
fn check_moved(name: &str, moved_by: &str, extra: &[&str]) {
    if !need_ffmpeg() {
        return;
    }
    let Some(src) = fixture(name) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (still, moved) = (dir.path().join("still.mp4"), dir.path().join("moved.mp4"));
    encode(&src, STILL, &still);
    encode(&src, moved_by, &moved);
    let (said_still, a) = swing(&still, extra);
    let (said_moved, b) = swing(&moved, extra);
    assert!(
        !said_still.contains("the camera moved"),
        "{name}: a still camera taken as moving: {said_still}"
    );
    assert!(
        said_moved.contains("the camera moved"),
        "{name}: the camera's motion not seen: {said_moved}"
    );
    assert!(
        (a - b).abs() <= 0.2,
        "{name}: {b:.2} deg peak to peak moved, {a:.2} still"
    );
}

#[test]
fn a_hand_held_greenscreen_clip_swings_as_the_still_one() {
    check("sborquez_video1_greenscreen.mp4", &[]);
}

/// The still crop's pass started 3 px off the wire's pivot and, its wire blurred
/// mid-swing, held half its strips about that pivot's line: refined from all the lines,
/// its pivot stayed 1.8 px across the wire and its swing read 57.81 deg against 58.07
/// moved (called `ok`); refined from the slow frames' re-centred lines, 57.99 and 58.06.
#[test]
fn a_faster_hand_held_greenscreen_clip_swings_as_the_still_one() {
    check_moved("sborquez_video1_greenscreen.mp4", FASTER, &[]);
}

#[test]
fn a_hand_held_splitscreen_clip_swings_as_the_still_one() {
    // Two pendulums: the right panel's, by its region (the frames cropped by 4 px).
    check(
        "sborquez_video2_splitscreen.mp4",
        &["--roi", "236,0,236,352"],
    );
}

/// The off-screen pivot clip (`bartekpacia_film1_fhd.mp4`, README: period about 1.02 s,
/// about +-11.75 deg at the start, +-10.2 at 25 s) shrunk to 960x540 (its first 12 s):
/// its wire is a line 1 px wide, about 150 px of it visible above a ball 95 px across.
/// Still, the first look against the running extreme takes the ball's edges (a pivot
/// at (592, 168) px, 3.8 deg peak to peak over 4 s); the look against the median alone
/// finds the wire's pivot, (494, -315) px, but the track loses the wire in many frames
/// (24.46 deg peak to peak, `suspect (found, crossed, period)`). Hand-held too (24.89
/// deg against 24.34 with the pivot given). Both are `suspect`. A detection called `ok` must have
/// measured the wire: the README's period within 2 % and its amplitudes within 1.5 deg
/// (at the start; at 12 s, 11.0 deg by the README's linear decay); one not `ok` is
/// `suspect` with its angles written (exit 0), or refused (exit 1), as a CI job reads it.
#[test]
fn the_off_screen_pivot_clip_shrunk_is_never_called_ok_unless_measured() {
    if !need_ffmpeg() {
        return;
    }
    let Some(src) = fixture("bartekpacia_film1_fhd.mp4") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let first = "trim=end_frame=720,scale=960:540";
    for (name, filter) in [
        ("still", first.to_string()),
        ("hand-held", format!("{first},{MOVED}")),
    ] {
        let video = dir.path().join(format!("{name}.mp4"));
        encode(&src, &filter, &video);
        let (v, out, csv) = detect_json(&video, &[], dir.path());
        let verdict = v["verdict"].as_str().unwrap();
        let seen = |k: &str| v["seen"][k].as_f64().unwrap_or(f64::NAN);
        eprintln!(
            "{name}: {verdict}, period {:.3} s, amplitude {:.2} -> {:.2} deg",
            seen("period_s"),
            seen("amplitude_start_deg"),
            seen("amplitude_end_deg")
        );
        match verdict {
            "ok" => {
                assert!(
                    (seen("period_s") / 1.02 - 1.0).abs() < 0.02,
                    "{name}: `ok`, period {} s",
                    seen("period_s")
                );
                assert!(
                    (seen("amplitude_start_deg") - 11.75).abs() <= 1.5
                        && (seen("amplitude_end_deg") - 11.0).abs() <= 1.5,
                    "{name}: `ok`, amplitude {} -> {} deg",
                    seen("amplitude_start_deg"),
                    seen("amplitude_end_deg")
                );
            }
            "suspect" => assert!(out.status.success() && csv.exists(), "{name}: {out:?}"),
            _ => assert!(
                verdict == "refused" && !out.status.success(),
                "{name}: {verdict}, {}",
                out.status
            ),
        }
    }
}

/// Film 1 cropped by 8 px a side (1904x1064), the camera still: against the running
/// extreme, the first look took the bob's stripes for the wire (seven lines meeting
/// beside the bob at (1174, 328) px and sweeping 87 deg) and its pass swung 7 deg,
/// `suspect`; the look against the median alone, made when a pass does not swing as a
/// wire does, finds the off-screen pivot (about (990, -640) px by the README) and the
/// clip swings as it does cropped by 4 px a side, `ok`.
#[test]
fn the_off_screen_pivot_clip_cropped_wider_is_measured_about_its_pivot() {
    let Some((v, b, a)) = film1_about_its_pivot("crop=iw-16:ih-16:8:8") else {
        return;
    };
    assert_eq!(v["verdict"], "ok", "{}", v["reason"]);
    assert!(
        (a - b).abs() <= 0.2,
        "{b:.2} deg peak to peak, {a:.2} cropped by 4 px"
    );
}

/// Film 1 made by the ffmpeg filter `made` (within a crop of 8 px a side), detected
/// with no options: its detection (JSON), once its pivot is checked to lie about the
/// README's, and the peak-to-peak angle (deg) of its first 4 s and of the clip cropped
/// still by 4 px a side. `None` without ffmpeg or the clip.
fn film1_about_its_pivot(made: &str) -> Option<(serde_json::Value, f64, f64)> {
    if !need_ffmpeg() {
        return None;
    }
    let src = fixture("bartekpacia_film1_fhd.mp4")?;
    let dir = tempfile::tempdir().unwrap();
    let (video, still) = (dir.path().join("made.mp4"), dir.path().join("still.mp4"));
    encode(&src, made, &video);
    encode(&src, STILL, &still);
    let (v, out, csv) = detect_json(&video, &[], dir.path());
    assert!(out.status.success(), "{}", v["reason"]);
    let pivot = &v["seen"]["pivot_px"];
    let (x, y) = (pivot[0].as_f64().unwrap(), pivot[1].as_f64().unwrap());
    // The README's pivot, (990, -640) px give or take 10 and 30, 8 px up and left.
    assert!(
        (x - 982.0).abs() <= 15.0 && (y + 648.0).abs() <= 40.0,
        "pivot ({x:.1}, {y:.1}) px: {} {}",
        v["verdict"],
        v["reason"]
    );
    let (_, a) = swing(&still, &[]);
    Some((v, peak_to_peak(&csv), a))
}

/// A jittery hand: shifts of 0.8 to 1.5 px at 2.3 to 6.1 Hz each way and turns of 0.1
/// deg at 3.1 and 5.9 Hz, within a crop of 8 px a side.
const JITTERY: &str = "rotate=(0.12*sin(2*PI*3.1*t)+0.1*sin(2*PI*5.9*t+1))*PI/180:ow=iw:oh=ih:\
                       bilinear=1,crop=iw-16:ih-16:8+1.5*sin(2*PI*2.3*t)+1.2*sin(2*PI*4.7*t+2)\
                       +0.8*sin(2*PI*6.1*t):8+1.3*sin(2*PI*3.7*t+1)+1*sin(2*PI*5.3*t)";

/// Film 1 under a jittery hand: its look against the running extreme took the light
/// polarity, a static line (a dark stripe's edge) that the jitter made move, and its
/// track lay on that line for seconds at a time, turning back 0 times in 25.6 s (0.50
/// deg peak to peak over the first 4 s). A track that turns back too seldom over a long
/// video is measured again from a look against the median alone, which follows the
/// wire about the off-screen pivot and swings as the clip cropped still.
#[test]
fn the_off_screen_pivot_clip_under_a_jittery_hand_follows_its_wire() {
    let Some((v, b, a)) = film1_about_its_pivot(JITTERY) else {
        return;
    };
    assert!(
        (a - b).abs() <= 0.2,
        "{b:.2} deg peak to peak moved, {a:.2} still ({} {})",
        v["verdict"],
        v["reason"]
    );
}

/// The real clips whose README's correct outcome is a refusal or a `suspect`, moved by
/// the hand: they keep it. The invisible rope is not called good, the two rods are not
/// mixed, the rod knocked far is refused saying why.
#[test]
fn the_hard_real_clips_moved_keep_their_outcome() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    type Outcome = fn(&str, &serde_json::Value, bool);
    let clips: [(&str, Outcome); 3] = [
        ("bartekpacia_film2_vga.mp4", outcomes::invisible_rope),
        ("katiebutler_pendulum.mov", outcomes::two_rods),
        ("dfki_rvDIST35.mp4", outcomes::rod_knocked_far),
    ];
    for (name, outcome) in clips {
        let Some(src) = fixture(name) else {
            return;
        };
        let moved = dir.path().join(format!("{name}.moved.mp4"));
        encode(&src, MOVED, &moved);
        let (v, out, _) = detect_json(&moved, &[], dir.path());
        eprintln!("{name} moved: {} {}", v["verdict"], v["reason"]);
        outcome(&format!("{name} moved"), &v, out.status.success());
    }
}

/// Moved by the hand over a plain wall, which holds too little to measure the camera
/// by, the red apple and film 1 are not steadied, and their swings differ from the
/// still crops' (by 0.41 and 0.21 deg peak to peak over the first 4 s): such a
/// measurement is never called `ok`. The still crops are.
#[test]
fn a_moved_clip_that_swings_off_the_still_one_is_not_called_ok() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "christianausb_redapple_480p.mov",
        "bartekpacia_film1_fhd.mp4",
    ] {
        let Some(src) = fixture(name) else {
            return;
        };
        let mut seen = Vec::new();
        for (kind, filter) in [("still", STILL), ("moved", MOVED)] {
            let video = dir.path().join(format!("{name}.{kind}.mp4"));
            encode(&src, filter, &video);
            let (v, out, csv) = detect_json(&video, &[], dir.path());
            assert!(out.status.success(), "{name} {kind}: {}", v["reason"]);
            seen.push((
                v["verdict"].as_str().unwrap().to_string(),
                peak_to_peak(&csv),
            ));
        }
        let ((still, a), (moved, b)) = (&seen[0], &seen[1]);
        eprintln!("{name}: still {still} {a:.2} deg, moved {moved} {b:.2} deg");
        assert_eq!(still, "ok", "{name} still");
        assert!(
            (a - b).abs() <= 0.2 || moved != "ok",
            "{name}: moved {b:.2} deg against {a:.2} still, called ok"
        );
    }
}
