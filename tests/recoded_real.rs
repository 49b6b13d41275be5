//! The off-screen pivot clip (`bartekpacia_film1_fhd.mp4`) as a user's tools copy it,
//! made here by ffmpeg at test time and never kept: its first 10 s re-encoded by x264's
//! fastest preset (its faint string smeared into the wall's texture), and scaled up to a
//! phone's 3840x2160. Detected with no options, each is measured about the wire's pivot
//! (the original's: (989.3, -630.0) px, twice that at 4K), not about the ball's rim.
//!
//! At the default working scale both took the rim (a pivot at (1179, 326) px, its lines
//! turning 1.92 times as much; at 4K (2310, 662), `suspect (decays, smooth, still)`);
//! looked at and measured at a finer scale too, the wire is found.

mod common;

use common::{detect_json, fixture, need_ffmpeg};
use std::path::Path;
use std::process::Command;

/// The first 10 s of `src` through the filter `vf`, encoded by x264 with `preset`.
fn encode(src: &Path, vf: &str, preset: &str, out: &Path) {
    let status = Command::new("ffmpeg")
        .args(["-nostdin", "-v", "error", "-y", "-i"])
        .arg(src)
        .args(["-an", "-t", "10", "-vf", vf])
        .args(["-c:v", "libx264", "-preset", preset, "-crf", "18"])
        .args(["-pix_fmt", "yuv420p"])
        .arg(out)
        .status()
        .expect("ffmpeg runs");
    assert!(status.success(), "ffmpeg failed to make {}", out.display());
}

/// The copy's verdict and pivot (px, in its own frame's pixels).
fn measured(vf: &str, preset: &str) -> Option<(String, [f64; 2])> {
    if !need_ffmpeg() {
        return None;
    }
    let src = fixture("bartekpacia_film1_fhd.mp4")?;
    let dir = tempfile::tempdir().unwrap();
    let video = dir.path().join("copy.mp4");
    encode(&src, vf, preset, &video);
    let (v, out, _) = detect_json(&video, &[], dir.path());
    assert!(out.status.success(), "{out:?}");
    let p = &v["seen"]["pivot_px"];
    let pivot = [0, 1].map(|i| p[i].as_f64().unwrap_or(f64::NAN));
    let verdict = v["verdict"].as_str().unwrap().to_string();
    eprintln!("{vf} {preset}: {verdict}, pivot {pivot:?}");
    Some((verdict, pivot))
}

fn near(p: [f64; 2], q: [f64; 2], px: f64) -> bool {
    (p[0] - q[0]).hypot(p[1] - q[1]) <= px
}

#[test]
fn an_ultrafast_copy_of_the_off_screen_pivot_clip_is_measured_about_the_wire() {
    let Some((verdict, pivot)) = measured("null", "ultrafast") else {
        return;
    };
    // Its string smeared, the wire's frame-to-frame noise lies at a wire's limit: the
    // verdict may be `suspect (smooth)`, but about the wire's pivot.
    assert!(
        near(pivot, [989.3, -630.0], 6.0),
        "{verdict}: pivot {pivot:?}, the wire's is (989.3, -630.0)"
    );
}

#[test]
fn a_4k_copy_of_the_off_screen_pivot_clip_is_measured_about_the_wire_and_ok() {
    let Some((verdict, pivot)) = measured("scale=3840:2160", "veryfast") else {
        return;
    };
    assert!(
        verdict == "ok" && near(pivot, [1978.6, -1260.0], 12.0),
        "{verdict}: pivot {pivot:?}, the wire's is (1978.6, -1260.0)"
    );
}
