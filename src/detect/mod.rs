//! The wire detector (the paper's section 2.3.2, done right): per frame, the angle of
//! the wire from the image x axis (Eq. 35 via an orthogonal line fit, ERRATA §6).
//!
//! 1. [`geometry`] finds, from the first seconds of motion, the wire's polarity, its
//!    pivot, the band of radii where it is visible and a region of interest (or takes
//!    them from the experiment's `video:` block). Of a still start (the ball held
//!    before its release) the look keeps only its last frames: see `still`.
//! 2. Frames stream through once, cropped to the region: the moving-object evidence is
//!    the difference from a background that follows the scene (the running maximum for
//!    a dark wire, minimum for a light one, decaying slowly with the lighting; frames
//!    with a global flash are kept out of it). Pixels above a noise threshold that lie
//!    in a wedge around the angle predicted from the previous frames and in the band
//!    vote in a histogram of angles about the pivot, each angle's votes counted by the
//!    share of the band they reach; the sharpest peak is the wire (a hand or the bob
//!    is broad, the bob's rim short). The orthogonal line fit through the pivot of
//!    every evidence pixel in a ±2.5 px strip along it gives the angle: below the
//!    threshold too, since a threshold that differs from pixel to pixel cuts a blurred
//!    wire's flanks unevenly and tilts the fit; parts of the band whose pixels stray
//!    from the line (the bob's rim beside the wire) are dropped from it.
//! 3. The gate: a measured angle farther from the prediction than `gate_deg`, a
//!    frame with too little of the wire, a flash, or a frame identical to the previous
//!    one (a dropped frame the recorder repeated) is flagged. After the pass, a repeat
//!    that the codec did not keep identical is found from both sides (its angle stays
//!    at the previous frame's where the neighbours say the wire moved on). Flagged
//!    frames are filled from their good neighbours (status `corrected`), or left
//!    `missing` when there are none; operator marks replace the detection (`manual`).
//!    Each frame the gate flags while streaming, repeats aside, gets a diagnostic
//!    image with the detected and predicted lines (the paper's Figure 11).
//!
//! Memory is flat: one frame, the background and the evidence at a time, whatever the
//! video's length (the per-frame angles are a few bytes each), and a few frames'
//! regions for Figure 11 ([`figure11_png`]) and for the review page ([`Review`], at
//! most 80 pictures of at most 512 px a side), kept by the pass instead of decoding
//! again.
//!
//! The frames come from a [`VideoInput`], opened twice (the first look, shrunk for a
//! large frame, then the streaming pass, whose decoder starts while the geometry is
//! worked out): a [`VideoFile`] for [`detect`], or frames
//! made in memory ([`MemoryVideo`]) for tests that need no decoder.

mod figure11;
mod fill;
mod first_look;
pub mod geometry;
mod input;
pub mod judge;
mod light;
mod line;
mod morph;
mod options;
mod repeats;
pub mod review;
mod row;
mod shrink;
pub mod shutter;
pub mod steady;
mod still;
pub mod summary;
mod track;
pub mod tuning;

use crate::detect::tuning::{
    INIT_SECONDS, LENGTH_LOOKS, LOOK_MAX_FRAMES, PER_SIDE, SECOND_APART, STILL_AGAIN_NOISE_MAX_DEG,
    SWING_SCALE_RETRY, WORK_MAX_PIXELS, WORK_SIDE_PX,
};
pub use figure11::{figure11_frame, figure11_png, Figure11};
pub use input::{MemoryVideo, VideoFile, VideoInput};
pub use line::{fit_line_through, fit_line_weighted, moments, unwrap_near, Line};
pub use options::{DetectOptions, FrameProgress, PendulumGiven};
pub use review::{Review, ReviewFrame};
pub use row::{AngleRow, CpuSplit, Detection, Flag, Status};

use crate::video::{Frame, Roi};
use anyhow::{bail, ensure, Context, Result};
use fill::{
    apply_marks, fill_flagged, flag_against_swing, flag_beyond_swing, flag_isolated, flag_jumps,
    flag_still_beyond, flag_unsteadied,
};
use first_look::*;
use geometry::InitFrames;
use nalgebra::Vector2;
use repeats::flag_repeats;
use std::io::IsTerminal;
use std::path::Path;
use track::Tracker;

/// A point or vector in pixel coordinates (x right, y down).
pub type Pt = Vector2<f64>;

/// Full-frame coordinates of a point of a grid shrunk `s` times from the full frame's
/// pixels starting at `origin`: its pixel `i` averages full pixels `origin + s i` to
/// `origin + s i + s - 1`, so its centre lies at `origin + s i + (s - 1) / 2`.
fn shrunk_to_full(p: Pt, origin: Pt, s: f64) -> Pt {
    origin + p * s + Pt::repeat(0.5 * (s - 1.0))
}

/// The inverse of [`shrunk_to_full`].
fn full_to_shrunk(p: Pt, origin: Pt, s: f64) -> Pt {
    (p - origin - Pt::repeat(0.5 * (s - 1.0))) / s
}

/// The working scale a working side gives a region of `w` x `h` px: the whole factor
/// it is shrunk by, and whether [`WORK_MAX_PIXELS`] held it coarser than the side asked.
pub fn work_scale(w: u32, h: u32, work_side_px: f64) -> (u32, bool) {
    let k = first_look::work_shrink(w, h, work_side_px);
    (k, k > first_look::side_shrink(w, h, work_side_px))
}

/// The most pixels a frame holds at the working scale ([`WORK_MAX_PIXELS`]).
pub fn work_max_pixels() -> u64 {
    WORK_MAX_PIXELS
}

/// The detector's peak memory at a working side, estimated before it starts, MiB: a
/// base of 40 MiB and 2.3 copies of the first look's frames at the scale the working
/// side gives (the look's frames, its background and the frames held for the streaming
/// pass), as measured at 1280 px on a 1280x720 video (184 MiB), with the look thinned to
/// its byte budget at a large side (`first_look::look_stride`: 471 MiB measured at 4096
/// px on a 3840x2160 video at 60 frames/s, 517 estimated). For `--work-side`: a larger
/// side costs memory, and the command says how much before it is spent.
pub fn peak_memory_estimate_mib(info: &crate::video::VideoInfo, work_side_px: f64) -> f64 {
    let shrink = f64::from(first_look::work_shrink(
        info.width,
        info.height,
        work_side_px.max(WORK_SIDE_PX),
    ));
    let fps = match (info.frames_header, info.duration_s) {
        (Some(n), Some(d)) if d > 0.0 => n as f64 / d,
        _ => 30.0,
    };
    let frames = (INIT_SECONDS * fps).ceil().min(LOOK_MAX_FRAMES as f64);
    let frame =
        (f64::from(info.width) / shrink).floor() * (f64::from(info.height) / shrink).floor();
    let stride = first_look::look_stride(info, frame as usize) as f64;
    let kept = (frames / stride).ceil();
    40.0 + 2.3 * kept * frame / f64::from(1u32 << 20)
}

/// Under `ROLLFRIC_DEBUG`, a timing line: `what` happened this long after `started`, with
/// the process's processor time so far, then `more`.
fn debug_timing(what: &str, started: std::time::Instant, more: &str) {
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "timing: {what} at {:.2} s, CPU {:.2} s{more}",
            started.elapsed().as_secs_f64(),
            crate::usage::own_cpu_seconds().unwrap_or(f64::NAN)
        );
    }
}

/// Detect the wire angle in every frame of a video file (decoded by `ffmpeg`).
pub fn detect(path: &Path, opts: &DetectOptions) -> Result<Detection> {
    detect_from(&VideoFile::open(path)?, opts)
}

/// The pivots a refusal of two pendulums names (`... about pivots (x1, y1) px and (x2,
/// y2) px ...`, as [`streaming_pass`] words it), px; none for another message.
pub fn pivots_named(message: &str) -> Vec<[f64; 2]> {
    if !message.contains(TWO_PENDULUMS) {
        return Vec::new();
    }
    message
        .split(" px")
        .filter_map(|p| {
            let (x, y) = p
                .rsplit_once('(')?
                .1
                .trim_end_matches(')')
                .split_once(", ")?;
            Some([x.parse().ok()?, y.parse().ok()?])
        })
        .collect()
}

/// How a refusal of two pendulums begins (after the video's name).
const TWO_PENDULUMS: &str = "two pendulums swing in the frame";

/// Detect the wire angle in every frame of `input` (the input decides how it
/// decodes).
pub fn detect_from(input: &dyn VideoInput, opts: &DetectOptions) -> Result<Detection> {
    let cpu_from = crate::usage::own_cpu_seconds();
    let pass_from = std::cell::OnceCell::new();
    let mut d = detect_looked(input, opts, &pass_from)?;
    d.cpu_s = match (
        cpu_from,
        pass_from.get().copied().flatten(),
        crate::usage::own_cpu_seconds(),
    ) {
        (Some(a), Some(b), Some(c)) => Some(CpuSplit {
            before_pass: b - a,
            pass: c - b,
        }),
        _ => None,
    };
    Ok(d)
}

/// [`detect_from`], the processor time when the first streaming pass starts kept in
/// `pass_from` (by that pass).
fn detect_looked(
    input: &dyn VideoInput,
    opts: &DetectOptions,
    pass_from: &std::cell::OnceCell<Option<f64>>,
) -> Result<Detection> {
    let started = std::time::Instant::now();
    let looks = FirstLook::new(input, opts, started, pass_from)?;
    let d = detect_scaled(looks)?;
    another_pendulum(looks, d)
}

/// Step 4 of [`detect_looked`]: a period that is not the experiment's pendulum's (the
/// `length` check failed, a pendulum given and neither a pivot nor a region) may be
/// another pendulum's, one that swung through the first look while the ball was held
/// still. Seed 1205's sweep scene 31 (1280x720, the ball held for 1.96 s of the look's
/// 2.5, a second string swinging below the fulcrum) followed the string, 1.37 s against
/// the pendulum's 3.32, `suspect (length)`; a look from 2.5 s on finds the pendulum's
/// pivot. Looked again at most [`LENGTH_LOOKS`] times, each [`INIT_SECONDS`] after the
/// one before: the first look that finds a pivot (its own or a second pendulum's) more
/// than [`SECOND_APART`] of the frame's larger side from the one followed has the video
/// measured again with that pivot given (and the look's region and polarity, for its
/// own pendulum), and that measurement is kept when its period is seen and is the
/// pendulum's, whatever its other checks say (they are its own verdict: the first
/// measurement followed something else).
fn another_pendulum(looks: FirstLook, d: Detection) -> Result<Detection> {
    let FirstLook { input, opts, .. } = looks;
    let length = |d: &Detection| {
        d.verdict
            .checks
            .iter()
            .find(|c| c.check == "length")
            .cloned()
    };
    let length_failed = length(&d).is_some_and(|c| !c.passed);
    if !length_failed || opts.pivot.is_some() || opts.roi.is_some() {
        return Ok(d);
    }
    let name = input.name();
    let info = input.info();
    let side = f64::from(info.width.max(info.height));
    let followed = Vector2::new(d.pivot_px[0], d.pivot_px[1]);
    let Some(t0) = d.rows.first().map(|r| r.t_s) else {
        return Ok(d);
    };
    let mut decodings = 0;
    for j in 1..=LENGTH_LOOKS {
        let t = t0 + j as f64 * INIT_SECONDS;
        let Some(row) = d.rows.iter().find(|r| r.t_s >= t) else {
            break;
        };
        let later = FirstLook {
            first: row.frame,
            ..looks
        };
        let Ok((look, _)) = later.at_best_scale() else {
            continue;
        };
        decodings += look.looks;
        let geo = &look.geo;
        let far = |p: &Pt| (Vector2::new(p.x, p.y) - followed).norm() > SECOND_APART * side;
        // The look's own pendulum with its region and polarity (given only the pivot,
        // the look from the start, the ball held, took a hand's light edges through it
        // for the wire: seed 1205's scene 54); a second pendulum's pivot alone. The
        // look's region holds the angles it saw and 10 deg more (`ROI_MARGIN_DEG`),
        // which holds what the swing lost since the start: the fastest decay of the
        // paper's rows (glass fiber fabric, 10 deg to rest in 13 s) loses 5.8 deg by
        // the last look, at 7.5 s. A region widened further held scene 54's second
        // string, which kept the look from the start from dropping the held ball's
        // frames: its angles were 0.023 deg RMS off, not 0.002.
        let polarity = match geo.dark {
            true => crate::config::Polarity::Dark,
            false => crate::config::Polarity::Light,
        };
        let (p, roi, polarity) = match (far(&geo.pivot), geo.second.filter(far)) {
            (true, _) => (geo.pivot, Some(geo.roi), polarity),
            (false, Some(q)) => (q, None, opts.polarity),
            (false, None) => continue,
        };
        drop(look);
        eprintln!(
            "{name}: the period seen is not the pendulum's ({}); a look from {:.1} s finds \
             another pivot, ({:.1}, {:.1}) px: measuring again about it",
            d.verdict.label(),
            row.t_s,
            p.x,
            p.y
        );
        let about = DetectOptions {
            pivot: Some([p.x, p.y]),
            roi,
            polarity,
            ..opts.clone()
        };
        let again =
            FirstLook::new(input, &about, looks.started, looks.pass_from).and_then(detect_scaled);
        return Ok(match again {
            Ok(a) if length(&a).is_some_and(|c| c.passed) => Detection {
                decodings: d.decodings + decodings + a.decodings,
                ..a
            },
            Ok(a) => {
                let why = match length(&a) {
                    Some(c) => format!("its period is not the pendulum's either ({})", c.reason),
                    None => format!("no period is seen ({})", a.verdict.label()),
                };
                eprintln!(
                    "{name}: about ({:.1}, {:.1}) px {why}: the first measurement is kept",
                    p.x, p.y
                );
                Detection {
                    decodings: d.decodings + decodings + a.decodings,
                    ..d
                }
            }
            Err(e) => {
                eprintln!(
                    "{name}: about ({:.1}, {:.1}) px it measures nothing ({e:#}): the first \
                     measurement is kept",
                    p.x, p.y
                );
                Detection {
                    decodings: d.decodings + decodings,
                    ..d
                }
            }
        });
    }
    Ok(Detection {
        decodings: d.decodings + decodings,
        ..d
    })
}

/// Steps 1 to 3 of [`detect_looked`] from `looks`.
fn detect_scaled(mut looks: FirstLook) -> Result<Detection> {
    // 1. Geometry from the first seconds, at the working scale that sees the wire best.
    let (look, other) = looks.at_best_scale()?;
    // 2. The streaming pass at that scale (measured again steadied when the camera was
    // found moving).
    let (stage, shrink) = (look.geo.stage, look.shrink);
    let kept = measure(&mut looks, look).map(|d| other_scale(looks, d, other));
    // 3, last: what is kept still does not swing as a wire does, or found it in too few
    // frames, from a look against the running extreme: measured again from a look
    // against the median alone.
    choose::against_median(&looks, stage, shrink, kept)
}

/// Step 3 of [`detect_looked`], but its end: the pass `d` at the first look's scale, or
/// the other scale's (`other`), as [`Pass::replaced_by`] chooses.
fn other_scale(looks: FirstLook, d: Detection, other: Option<Other>) -> Detection {
    let FirstLook { input, .. } = looks;
    // 3. A pivot the pass's own lines do not bear out (a swing scale far from 1: the
    // wire's direction turns more or less than its angle about the pivot) is the look's
    // at a scale that saw something else as the wire (a 2 px wire and its blurred shadow
    // merged into one line by shrinking, with a pivot 5 px off): the other scale's look
    // is measured too, and the pass whose pivot its lines bear out better is kept. So is
    // a pass whose motion is not a pendulum's (its period varies from swing to swing, or
    // its angle jitters): its look too may have taken something else for the wire (a
    // real clip turned upside down, its wire's shadow beside it, at a pivot 480 px
    // off, its lines turning 0.989 times as much).
    let off = |d: &Detection| d.swing_scale.map_or(0.0, |s| (s - 1.0).abs());
    let unlike = |d: &Detection| {
        d.verdict
            .failed()
            .any(|c| c.check == "period" || c.check == "smooth")
    };
    let Some(other) = other.filter(|_| off(&d) > SWING_SCALE_RETRY || unlike(&d)) else {
        return d;
    };
    let by_scale = off(&d) > SWING_SCALE_RETRY;
    let scale = match other {
        Other::Finer(_) => "a finer working scale",
        _ => "the other working scale",
    };
    if by_scale {
        eprintln!(
            "{}: the wire's lines turn {:.3} times as much as its angle about the pivot the \
             first look found; measuring again from a look at {scale}",
            input.name(),
            d.swing_scale.unwrap_or(f64::NAN)
        );
    } else {
        eprintln!(
            "{}: what was followed does not swing as a wire does ({}); measuring again from \
             a look at {scale}",
            input.name(),
            d.verdict.label()
        );
    }
    // A look made before the camera was found moving from the start is made again,
    // steadied. A finer scale's look is made afresh: what the camera does was judged
    // about the region of the look that followed something else (the motion a swinging
    // ball gives the static scene about its rim).
    let again = match other {
        Other::Looked(l) if !looks.moving => streaming_pass(looks, *l),
        Other::Looked(l) => looks.at(l.shrink).and_then(|l| streaming_pass(looks, l)),
        Other::Unlooked(k) => looks.at(k).and_then(|l| streaming_pass(looks, l)),
        Other::Finer(k) => {
            let mut fresh = FirstLook {
                moving: false,
                follow_region: false,
                ..looks
            };
            fresh.at(k).and_then(|l| measure(&mut fresh, l))
        }
    };
    // See `Pass::replaced_by`.
    let better = |a: &Detection| Pass::of(&d).replaced_by(Pass::of(a), by_scale);
    let kept = match again {
        Ok(a) if better(&a) => Detection {
            decodings: a.decodings + d.decodings,
            ..a
        },
        Ok(a) => {
            let turn = a.swing_scale.unwrap_or(f64::NAN);
            let why = match (by_scale, a.swing_scale) {
                (false, Some(_)) => format!(
                    "it is {}, its lines turning {turn:.3} times as much (measured first, {})",
                    a.verdict.label(),
                    d.verdict.label()
                ),
                _ => format!("they turn {turn:.3} times as much"),
            };
            eprintln!(
                "{}: at the other scale {why}: the first measurement is kept",
                input.name()
            );
            Detection {
                decodings: d.decodings + a.decodings,
                ..d
            }
        }
        Err(e) => {
            eprintln!(
                "{}: the other scale measures nothing ({e:#}): the first measurement is \
                 kept",
                input.name()
            );
            d
        }
    };
    kept
}

/// The streaming pass from `look`, measured again with every frame steadied when the pass
/// found the camera moving (or its static scene off) where the look took it for still,
/// and once more from a look steadied throughout when what is kept from a look that took
/// it for still is in doubt ([`looked_again_steadied`]); `looks` learns what the camera
/// does.
fn measure(looks: &mut FirstLook, look: Located) -> Result<Detection> {
    let name = looks.input.name();
    let (shrink, look_steadied) = (look.shrink, look.moving);
    let mut d = streaming_pass(*looks, look)?;
    // A camera the first look took for still that the pass found moving from its start
    // (no glance found it still): the frames before it was found were measured where
    // they lie, so every frame is measured again steadied, from a look steadied too.
    // One found moving later (a drift, or a sway that grew, until two glances in a row
    // saw it; the look saw it still): every frame of the region is measured again
    // steadied onto the first, as the frames after it was found were. A drift's first
    // seconds carry its early part (8.6 px over 40 s, found at 8 s: those frames erred
    // up to 0.37 deg). One never confirmed, whose static scene two glances in a row find
    // off (the `still` check failed: a sway whose period is about twice the glances' 2 s,
    // each glance seeing it at the opposite phase, so that no two in a row agree; or one
    // whose motion explains too little of a plain or compressed frame), is measured
    // again the same way.
    let from_start = d.moved_from_start;
    let unconfirmed =
        !from_start && d.moved_later_s.is_none() && d.verdict.failed().any(|c| c.check == "still");
    let again = if from_start {
        looks.moving = true;
        Some("the camera moved from the start, which the first look took for still".to_string())
    } else if let Some(t) = d.moved_later_s {
        looks.follow_region = true;
        Some(format!(
            "the camera was found moving at {t:.1} s, and the frames before were taken as \
             still"
        ))
    } else if unconfirmed {
        looks.follow_region = true;
        Some(
            "the static scene lies off at two glances in a row, though no two glances in a \
             row found the camera moving"
                .to_string(),
        )
    } else {
        None
    };
    // The noise from frame to frame the steadying added, deg (in quadrature): on a scene
    // that fixes the motion poorly (a plain wall), misread motions jitter every frame.
    let added_noise = |a: &Detection| {
        let n = |d: &Detection| d.verdict.seen.noise_deg.unwrap_or(0.0);
        (n(a).powi(2) - n(&d).powi(2)).max(0.0).sqrt()
    };
    // Measured again about the look's region (found moving late, or its scene off).
    let about_region = again.is_some() && !from_start;
    if let Some(why) = again {
        eprintln!(
            "{name}: {why} (measured so, {}): measuring again with every frame steadied",
            d.verdict.label()
        );
        match looks.at(shrink).and_then(|l| streaming_pass(*looks, l)) {
            // Found later, by glances that found it still before: the second measurement
            // is kept when its detection is `ok`, or when it fails only some of the
            // checks the first failed and no other, its `turn` aside where the first,
            // never steadied, showed the motion in its angles
            // (`DetectionVerdict::steadied_fails_a_part_of`).
            // A drift of 11 px found at 8 s (seed 7's scene 18): measured first, the
            // track lay 4 deg off from 4 to 16 s, `suspect (rhythm, stalls, pivot)`, and
            // the fit refused it; steadied, 0.11 deg off, `suspect (pivot)`. Else the
            // first stands, with its own verdict (a still clip turned upside down, its
            // pivot placed 300 px below the frame, was found moving at 8 s; steadied
            // throughout, its angles lost every turning point).
            Ok(a) => {
                // Never confirmed, it is kept only when steadying added no more than
                // `STILL_AGAIN_NOISE_MAX_DEG` of noise: plain 320x240 walls whose glances
                // misread 1.2 to 2.8 px of motion gained 0.04 to 0.11 deg, three swaying
                // sweep twins 0.005 to 0.007. Unless the first measurement's angles
                // themselves show the motion's harm (a check besides `still` failed; the
                // second must then fail only a part of its checks, below): a drift of 11 px at 640x480 (seed
                // 43's scene 0) turned the wire's direction 2.8 % less than its angle
                // about the pivot (`pivot`) and scattered the swings (`envelope`), 0.89
                // deg RMS off; steadied, it gained 0.016 deg of noise and lay 0.024 deg
                // off.
                let by_noise = unconfirmed && d.verdict.failed().all(|c| c.check == "still");
                let refused = if by_noise && added_noise(&a) > STILL_AGAIN_NOISE_MAX_DEG {
                    Some(format!(
                        "its angle's noise from frame to frame grows by {:.4} deg (at most \
                         {STILL_AGAIN_NOISE_MAX_DEG} deg): the motions were misread, and the \
                         first measurement is kept",
                        added_noise(&a)
                    ))
                } else if !from_start
                    && a.verdict.failed().next().is_some()
                    && !a.verdict.steadied_fails_a_part_of(&d.verdict)
                {
                    Some(format!(
                        "it is {} (measured first, {}): the first measurement is kept",
                        a.verdict.label(),
                        d.verdict.label()
                    ))
                } else {
                    None
                };
                match refused {
                    Some(why) => {
                        eprintln!("{name}: steadied from the start {why}");
                        d.decodings += a.decodings;
                        // A look at the other scale (below) is measured as the first was.
                        looks.follow_region = false;
                    }
                    None => {
                        d = Detection {
                            decodings: a.decodings + d.decodings,
                            ..a
                        }
                    }
                }
            }
            Err(e) => {
                eprintln!(
                    "{name}: steadied from the start it measures nothing ({e:#}): the first \
                     measurement is kept"
                );
                looks.follow_region = false;
            }
        }
    }
    if !look_steadied && !looks.moving {
        d = looked_again_steadied(looks, shrink, about_region, d);
    }
    Ok(d)
}

/// A measurement from a look that took the camera for still (then found moving by the
/// pass, or its static scene off, and measured again about the look's region:
/// `about_region`; or never found moving): when what is kept still jitters (`smooth`),
/// or, measured about the region, bears out no pivot (`pivot`), the look's geometry, or
/// its judgement that the camera stood still, is in doubt, and the video is measured
/// once more from a look steadied throughout. A still camera's pivot that the lines do
/// not bear out is left to the other working scale ([`detect_scaled`]: a light 1 px
/// wire whose dark shadow the shrunk look took, steadied, read 0.03 px of motion and
/// was kept for failing fewer checks, the finer look never made). That
/// measurement is kept when it is `ok`, or fails a part of the checks `d` failed and no
/// other (see [`judge::DetectionVerdict::fails_a_part_of`]).
///
/// A hand-held camera shaking at 7.5 Hz (1.84 px and 0.18 deg, 640x480, a plain room;
/// seed 2's sweep scene 54) is seen at a random phase at each of the glances, 2 s apart,
/// that judge whether it moved: as 40 s of AVI, its static scene was found off and it was
/// measured about the look's region, the look (made on frames taken as still) having
/// placed the pivot 23 px down the wire in a region of 130x148 px: `suspect (smooth,
/// turn, pivot)`, 0.24 deg RMS off the truth, `s_r` 16 % off; as 20 s of H.264, never
/// found moving: `suspect (smooth)`, 0.35 deg RMS off. From a look steadied throughout,
/// both are `ok`, 0.018 and 0.028 deg RMS off. Measured so whatever they were, 7 of 28
/// sweep scenes found moving late came nearer the truth and 7 went further (one, 3.5 %
/// off, called `ok`): none of those 7 failed `smooth` or `pivot`.
fn looked_again_steadied(
    looks: &mut FirstLook,
    shrink: u32,
    about_region: bool,
    mut d: Detection,
) -> Detection {
    let name = looks.input.name();
    let in_doubt =
        |c: &judge::DetectionCheck| c.check == "smooth" || (about_region && c.check == "pivot");
    if !d.verdict.failed().any(in_doubt) {
        return d;
    }
    eprintln!(
        "{name}: measured from a look that took the camera for still it is {}: measuring \
         again from a look steadied throughout",
        d.verdict.label()
    );
    let (moving, follow_region) = (looks.moving, looks.follow_region);
    looks.moving = true;
    looks.follow_region = false;
    let why = match looks.at(shrink).and_then(|l| streaming_pass(*looks, l)) {
        Ok(a) if a.verdict.failed().next().is_none() || a.verdict.fails_a_part_of(&d.verdict) => {
            return Detection {
                decodings: a.decodings + d.decodings,
                ..a
            };
        }
        Ok(a) => {
            d.decodings += a.decodings;
            format!("it is {}", a.verdict.label())
        }
        Err(e) => format!("it measures nothing ({e:#})"),
    };
    eprintln!("{name}: from a look steadied throughout {why}: the measurement before is kept");
    (looks.moving, looks.follow_region) = (moving, follow_region);
    d
}

/// The working scale [`FirstLook::at_best_scale`] did not keep: its look (when it found a
/// wire), or its shrink factor (not looked at).
enum Other<'a> {
    Looked(Box<Located<'a>>),
    Unlooked(u32),
    /// Where one scale is the working side's (a side that 640 divides: 1280, 1920, 3840
    /// px), a finer one, looked at and measured afresh (see [`FirstLook::at_best_scale`]).
    Finer(u32),
}

mod choose;
mod pass_source;
mod stream;
#[cfg(test)]
mod tests;

use choose::Pass;
use pass_source::{Continued, CropSource, PassSource};
use stream::streaming_pass;
