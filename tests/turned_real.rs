//! The real clips (`../shared/fixtures/real/`), turned by 90, 180 and 270 degrees and
//! mirrored (ffmpeg `transpose`, `hflip`, `vflip`, made here at test time and never
//! kept), must measure like the clip as filmed: the same turning-point amplitudes
//! within 0.2 degrees, and at most 2 % of frames missing. A camera can be mounted at
//! any roll, so the wire's rest direction can point anywhere on the circle (a wire
//! hanging towards -x crosses atan2's +-180 seam).
//!
//! Every variant, the unturned one included, is cut and encoded the same way (H.264,
//! CRF 12), so that only the turn differs between them.
//!
//! A turning point next to frames the gate rejected (a hand passing over the wire) is
//! interpolated from the frames around them, and which frames are rejected depends on
//! the pixels the hand covers: those turning points are held to 0.6 degrees, and
//! counted.

mod common;

use common::{fixture, need_ffmpeg, rollfric_ok, root, turning_amplitudes};
use rollfric::series::AngleSeries;
use std::path::Path;
use std::process::Command;

/// The turns: a name and the ffmpeg filter that makes it.
const TURNS: [(&str, &str); 5] = [
    ("as filmed", "null"),
    ("90 deg", "transpose=clock"),
    ("180 deg", "hflip,vflip"),
    ("270 deg", "transpose=cclock"),
    ("mirrored", "hflip"),
];

/// Encode `src` through `prep` (a cut or a crop) and `turn` into `out`.
fn encode(src: &Path, prep: &str, turn: &str, frames: u32, out: &Path) {
    let status = Command::new("ffmpeg")
        .args(["-nostdin", "-v", "error", "-y", "-i"])
        .arg(src)
        .args(["-frames:v", &frames.to_string(), "-an", "-vf"])
        .arg(format!("{prep},{turn}"))
        .args([
            "-c:v", "libx264", "-preset", "veryfast", "-crf", "12", "-pix_fmt", "yuv420p",
        ])
        .arg(out)
        .status()
        .expect("ffmpeg runs");
    assert!(status.success(), "ffmpeg failed to make {}", out.display());
}

struct Measured {
    /// Turning points: time (s) and amplitude about the equilibrium (deg).
    amps: Vec<(f64, f64)>,
    frames: usize,
    missing: usize,
    /// Times of the frames that are not `ok`.
    flagged: Vec<f64>,
}

fn measure(video: &Path) -> Measured {
    let csv = video.with_extension("csv");
    rollfric_ok(
        &[
            "detect".as_ref(),
            video.as_os_str(),
            "-o".as_ref(),
            csv.as_os_str(),
        ],
        &root(),
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let series = AngleSeries::parse_csv(&text).unwrap();
    Measured {
        amps: turning_amplitudes(&series),
        frames: text.lines().count() - 1,
        missing: text.lines().filter(|l| l.contains(",missing,")).count(),
        flagged: text
            .lines()
            .skip(1)
            .filter(|l| !l.contains(",ok,"))
            .filter_map(|l| l.split(',').next()?.parse().ok())
            .collect(),
    }
}

/// The clip `name`, prepared by `prep` and cut to `frames`, in every turn: each turn's
/// turning points against the unturned one's.
fn turned_clip_measures_as_filmed(name: &str, prep: &str, frames: u32) {
    if !need_ffmpeg() {
        return;
    }
    let Some(src) = fixture(name) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let measured: Vec<(&str, Measured)> = TURNS
        .iter()
        .map(|(turn, filter)| {
            let out = dir.path().join(format!("{}.mp4", turn.replace(' ', "-")));
            encode(&src, prep, filter, frames, &out);
            (*turn, measure(&out))
        })
        .collect();
    let (_, base) = &measured[0];
    assert!(
        base.amps.len() >= 6,
        "{name}: only {} turning points as filmed",
        base.amps.len()
    );
    let mut failures = Vec::new();
    for (turn, m) in &measured {
        // Each turning point of the unturned clip, matched by time; near a rejected
        // frame (of either clip) or not.
        let near_flagged = |t: f64| {
            [&base.flagged, &m.flagged]
                .iter()
                .any(|f| f.iter().any(|u| (u - t).abs() <= 0.15))
        };
        let (mut worst, mut worst_near) = ((0.0f64, 0.0f64), (0.0f64, 0.0f64));
        let (mut unmatched, mut near) = (0, 0);
        for &(t, a) in &base.amps {
            let Some(&(_, b)) = m.amps.iter().find(|(u, _)| (u - t).abs() < 0.1) else {
                unmatched += 1;
                continue;
            };
            let w = if near_flagged(t) {
                near += 1;
                &mut worst_near
            } else {
                &mut worst
            };
            if (b - a).abs() > w.1.abs() {
                *w = (t, b - a);
            }
        }
        eprintln!(
            "{name} {turn}: {} turning points, worst amplitude difference {:+.3} deg at \
             {:.2} s ({:+.3} deg at {:.2} s among the {near} next to rejected frames), \
             {unmatched} unmatched, {} of {} frames missing",
            m.amps.len(),
            worst.1,
            worst.0,
            worst_near.1,
            worst_near.0,
            m.missing,
            m.frames
        );
        if worst.1.abs() > 0.2 || worst_near.1.abs() > 0.6 || unmatched > 0 {
            failures.push(format!(
                "{turn}: amplitudes differ by {:+.3} deg at {:.2} s ({:+.3} deg at {:.2} s \
                 next to rejected frames; {unmatched} turning points unmatched)",
                worst.1, worst.0, worst_near.1, worst_near.0
            ));
        }
        if m.missing as f64 > 0.02 * m.frames as f64 {
            failures.push(format!(
                "{turn}: {} of {} frames missing",
                m.missing, m.frames
            ));
        }
    }
    assert!(failures.is_empty(), "{name}: {}", failures.join("; "));
}

#[test]
fn greenscreen_clip_turned_and_mirrored() {
    // 301 frames at 25 fps: the clip's README range.
    turned_clip_measures_as_filmed("sborquez_video1_greenscreen.mp4", "null", 301);
}

#[test]
fn splitscreen_clip_turned_and_mirrored() {
    // The left panel, frames 0-366 (a splice follows).
    turned_clip_measures_as_filmed("sborquez_video2_splitscreen.mp4", "crop=240:360:0:0", 367);
}

#[test]
fn fhd_clip_turned_and_mirrored() {
    // The first 12 s, at half size (the detector looks at it shrunk in any case).
    turned_clip_measures_as_filmed("bartekpacia_film1_fhd.mp4", "scale=960:540", 720);
}
