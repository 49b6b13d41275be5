//! The digital twin's video: what the paper's camera sees (a top view of the inclined
//! plate near the protractor), rendered frame by frame from the simulated motion, with
//! the camera's defects, plus the truth the detector must measure back.
//!
//! * Static scene, drawn once per video in the plate's own frame and then turned into
//!   the image: plate texture (smooth random shading plus fine grain, scratches, dust),
//!   a protractor centred at the pivot (a tick every degree, longer every 5 and 10,
//!   numerals), the block that holds it, and the fulcrum screw.
//! * Moving parts, per frame, only inside their bounding box: the wire (a thin line
//!   from the pivot at the image angle `theta(t) = rest - psi(t)`, x right and y down)
//!   and the ball at its end, with an exact line-spread profile (width, pixel
//!   integration, defocus) averaged over sub-times of the exposure (motion blur).
//! * Camera defects (none when `synthetic.clean`): defocus, motion blur, sensor noise
//!   (one precomputed noise field read at a random offset per frame), slow lighting
//!   drift and flicker, lossy compression (the codec), and spoiled frames.
//! * Other cameras' conditions, each off unless its `synthetic:` key is set: the camera
//!   rolled over the full circle (`rest_angle_deg`, taken into (-180, 180]), a mirrored
//!   image (`mirror`: the finished frame flipped left-right, the truth `pi - theta`), a
//!   thin faint wire (`wire_width_px`, `wire_contrast`), the wire's soft shadow on the
//!   plate (`shadow`), stronger or other mains flicker and drift (`flicker_hz`,
//!   `flicker_depth`, `drift_depth`), the ball held before its release (`hold_s`), a
//!   fulcrum anywhere, also outside the frame (`pivot_frac`), a variable frame rate
//!   (`vfr_jitter`: each frame rendered at its own time, which the file carries; see
//!   the `vfr` module), and frames the recorder drops (`dropped_share`: gaps in the
//!   file's times, and no truth row).
//! * The camera and the room (`shake`, `lens_k1`, `crf`, `room`; see the `shake` and
//!   `room` modules): a camera that moves (the whole picture shifted and turned, zero
//!   at the first frame), a wide lens's radial distortion, heavy compression, a ruled
//!   or gridded board and straight static edges on the plate, a second pendulum beside
//!   the first, and a person walking through (the frames where it covers the wire are
//!   tagged `walker` in the truth).
//! * Spoiled frames: `synthetic.spoiled_frames` counts spoiling *events*, in turn a
//!   hand passing (1 to 3 consecutive frames, each tagged `hand`), a flash (one frame,
//!   near white) and a duplicated frame (the recorder repeats the previous frame), one
//!   per equal slot of the video, at least 2 s (a fifth of a short video) from its ends.
//! * Writing: MJPG in `.avi`, or H.264 (x264, `veryfast`) for other extensions, by the
//!   `ffmpeg` program: each frame is converted here to planar Y'CbCr 4:2:0 (BT.601, full
//!   range for JPEG, limited for H.264) on a second thread while the next frame
//!   renders, and piped to ffmpeg, which encodes in its own process; an odd width or
//!   height is written as 4:4:4 MJPG, from BGR frames ffmpeg converts. The `ffmpeg`
//!   program is required (OpenCV's `videoio` is not linked).
//!
//! Every random choice comes from [`Rng`](crate::rng::Rng) streams derived from
//! `synthetic.seed`, and each frame's own randomness is seeded from its index, so a
//! frame renders the same whichever frames are rendered before it.

mod camera;
mod encode;
mod look;
mod mover;
mod plan;
mod room;
mod scene;
mod shake;
mod twin;
mod vfr;
mod yuv;

#[cfg(test)]
mod tests;

use crate::config::{Experiment, Style};
use anyhow::{bail, ensure, Context, Result};
use encode::open_writer;
use opencv::core::Mat;
use opencv::prelude::*;
use plan::{Plan, Spoil};
use std::io::Write;
use std::path::{Path, PathBuf};
use twin::Twin;

/// One frame's truth.
#[derive(Clone, Debug, PartialEq)]
pub struct TruthRow {
    /// Mid-exposure time of the frame, `i / fps` (with `vfr_jitter`, the frame's own
    /// time, whole milliseconds, as the video carries it), s.
    pub t_s: f64,
    /// True image angle of the wire at `t_s`, from the image x axis (y down), rad: the
    /// rest angle (in (-pi, pi]) minus the swing, continuous (not wrapped). For a
    /// duplicated frame this is still the true angle at `t_s`, not the repeated content.
    pub angle_rad: f64,
    /// `none`, `hand`, `flash` or `duplicate`.
    pub spoiled: &'static str,
}

/// What [`render`] wrote.
#[derive(Clone, Debug)]
pub struct SynthReport {
    /// The file actually written (`.avi` if H.264 was not available).
    pub path: PathBuf,
    /// The codec, the container (the file's extension) and the writer, as in
    /// `MJPG (avi, ffmpeg)`, `MJPG 4:4:4 (avi, ffmpeg)` (an odd size) or
    /// `H.264 (mp4, ffmpeg, variable frame rate)`.
    pub codec: String,
    /// Frames written (the dropped ones not counted).
    pub frames: usize,
    pub width: u32,
    pub height: u32,
    pub fps: f64,
    /// The wire's pivot in the image, px (pixel centres at integer coordinates).
    pub pivot_px: [f64; 2],
    /// Pivot to the end of the wire (the ball's centre), px (of the untilted view, with
    /// `camera_tilt_deg`).
    pub wire_length_px: f64,
    /// Drawn width of the wire, px.
    pub wire_width_px: f64,
    /// Radius of the ball drawn at the wire's end, px (of the untilted view, with
    /// `camera_tilt_deg`).
    pub ball_radius_px: f64,
    /// Image angle of the wire at rest (`rest_angle_deg` plus the style's turn, taken
    /// into (-pi, pi]; `pi` minus that when mirrored, likewise taken), rad; with
    /// `camera_tilt_deg`, the plate angle (the truth's).
    pub rest_angle_rad: f64,
    pub style: Style,
    /// Rendered without camera defects.
    pub clean: bool,
    /// One row per frame written (a dropped frame has none).
    pub truth: Vec<TruthRow>,
}

/// The containers a twin may be written in, by file extension.
pub const CONTAINERS: [&str; 5] = ["mp4", "mkv", "mov", "m4v", "avi"];

/// Render the experiment's `synthetic:` twin to `out`.
///
/// The extension decides the container: `.avi` is MJPG; anything else (`.mp4`) is
/// H.264, and if ffmpeg has no x264 or the size is odd the video goes to the same name
/// with `.avi` in MJPG instead (said on stderr; the returned path
/// is the file written). The same frames give the same bytes (for a given FFmpeg).
/// The file is written under a temporary name in the same folder and renamed when
/// complete. `duration_s` overrides the block's duration; `progress` is called with
/// `(frames_done, frames_total)` every 100 frames and at the end.
pub fn render(
    exp: &Experiment,
    out: &Path,
    duration_s: Option<f64>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<SynthReport> {
    if crate::fsutil::is_special(out) {
        bail!(
            "{}: not a regular file (a device or a FIFO); the video is written to a file \
             and renamed into place",
            out.display()
        );
    }
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    ensure!(
        ext.as_deref().is_some_and(|e| CONTAINERS.contains(&e)),
        "{}: expected a video file name ending in .{} (.avi is MJPG, the others H.264)",
        out.display(),
        CONTAINERS.join(", .")
    );
    ensure!(
        crate::video::have_ffmpeg(),
        "{}: rendering needs the ffmpeg program, which is not on PATH (Debian: apt-get install ffmpeg)",
        out.display()
    );
    render_inner(exp, out, duration_s, progress)
        .with_context(|| format!("{}: cannot render the synthetic video", out.display()))
}

/// Truth CSV text: header `t_s,angle_rad,spoiled`, one row per frame.
pub fn truth_csv(rows: &[TruthRow]) -> String {
    let mut s = String::with_capacity(32 * rows.len() + 24);
    s.push_str("t_s,angle_rad,spoiled\n");
    for r in rows {
        s.push_str(&format!("{:.6},{:.9},{}\n", r.t_s, r.angle_rad, r.spoiled));
    }
    s
}

/// The truth [`render`] would produce, without rendering.
pub fn truth(exp: &Experiment, duration_s: Option<f64>) -> Result<Vec<TruthRow>> {
    Ok(Plan::new(exp, duration_s)?.written_truth())
}

/// What the encoder thread is handed.
enum Job {
    /// A rendered frame (its buffer comes back for reuse once the next frame is in).
    Frame(Mat),
    /// Repeat the last frame: a duplicated frame.
    Repeat,
}

/// Render frames `first..` (frame 0 is already in `twin.frame`) and hand each to `write`
/// on a second thread, which runs behind the renderer and does the conversion and
/// encoding work. Rendered frames travel in a few recycled buffers swapped with
/// `twin.frame` (a render overwrites the whole frame), so no frame is copied; a
/// duplicated frame is written again from the encoder's last frame.
fn pump(
    twin: &mut Twin,
    first: usize,
    progress: &mut dyn FnMut(usize, usize),
    mut write: impl FnMut(&Mat) -> Result<()> + Send,
) -> Result<()> {
    let total = twin.plan.truth.len();
    let mut last = if first > 0 {
        Some(twin.frame.try_clone()?)
    } else {
        None
    };
    let (to_encoder, jobs) = std::sync::mpsc::sync_channel::<Job>(2);
    let (recycle, buffers) = std::sync::mpsc::channel::<Mat>();
    std::thread::scope(|scope| -> Result<()> {
        let encoder = scope.spawn(move || -> Result<()> {
            for job in jobs {
                if let Job::Frame(m) = job {
                    if let Some(old) = last.replace(m) {
                        let _ = recycle.send(old);
                    }
                }
                let m = last.as_ref().context("a repeated frame before any frame")?;
                write(m)?;
            }
            Ok(())
        });
        let rendered = (|| -> Result<()> {
            for i in first..total {
                // A dropped frame is piped as a repeat, which FFmpeg drops.
                let job =
                    if i > 0 && (twin.plan.spoils[i] == Spoil::Duplicate || twin.plan.dropped[i]) {
                        Job::Repeat
                    } else {
                        if i > 0 {
                            twin.render_frame(i)?;
                        }
                        let spare = match buffers.try_recv() {
                            Ok(m) => m,
                            Err(_) => twin.frame.try_clone()?,
                        };
                        Job::Frame(std::mem::replace(&mut twin.frame, spare))
                    };
                if to_encoder.send(job).is_err() {
                    break; // the encoder stopped: its error is reported below
                }
                if (i + 1) % 100 == 0 || i + 1 == total {
                    progress(i + 1, total);
                }
            }
            if first >= total {
                progress(total, total);
            }
            Ok(())
        })();
        drop(to_encoder);
        let encoded = encoder
            .join()
            .unwrap_or_else(|_| Err(anyhow::anyhow!("the video encoder panicked")));
        rendered.and(encoded)
    })
}

/// Protractor marks of the twin's picture with their plate coordinates, as
/// `video.calibration` takes them: `(image px, plate mm)` (see `camera_tilt_deg`).
pub fn calibration_points(exp: &Experiment) -> Result<Vec<([f64; 2], [f64; 2])>> {
    Ok(Plan::new(exp, Some(1.0))?.calibration_points())
}

fn render_inner(
    exp: &Experiment,
    out: &Path,
    duration_s: Option<f64>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<SynthReport> {
    let plan = Plan::new(exp, duration_s)?;
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create folder", dir.display()))?;
    }
    let mut twin = Twin::new(plan)?;
    let (w, h) = (twin.plan.geo.w, twin.plan.geo.h);
    twin.render_frame(0)?;
    let times = twin.plan.filters();
    let (mut pipe, mut tmp, path, codec) = open_writer(
        out,
        (w, h),
        twin.plan.fps,
        times.as_deref(),
        twin.plan.s.crf,
        &twin.frame,
    )?;
    let tmp_path = tmp.path();
    let raw = pipe.raw;
    let pumped = {
        let stdin = pipe.stdin.as_mut().expect("open until finished");
        let mut buf = Vec::new();
        pump(&mut twin, 1, progress, |m: &Mat| {
            Ok(stdin.write_all(raw.bytes(m.data_bytes()?, (w, h), &mut buf))?)
        })
    };
    if let Err(e) = pumped {
        let tail = pipe.abort();
        if tail.is_empty() {
            return Err(e);
        }
        return Err(e.context(format!("{}: ffmpeg stopped: {tail}", tmp_path.display())));
    }
    pipe.finish(&tmp_path)?;
    let len = std::fs::metadata(&tmp_path).map(|m| m.len()).unwrap_or(0);
    ensure!(
        len > 0,
        "{}: the video writer produced an empty file",
        tmp_path.display()
    );
    std::fs::rename(&tmp_path, &path).with_context(|| {
        format!(
            "{}: cannot rename to {}",
            tmp_path.display(),
            path.display()
        )
    })?;
    tmp.0 = None;
    let g = &twin.plan.geo;
    Ok(SynthReport {
        path,
        codec,
        frames: twin.plan.dropped.iter().filter(|&&d| !d).count(),
        width: g.w as u32,
        height: g.h as u32,
        fps: twin.plan.fps,
        pivot_px: twin.plan.image_pivot(),
        wire_length_px: g.d_px,
        wire_width_px: g.wire_w,
        ball_radius_px: g.ball_r,
        rest_angle_rad: twin.plan.image_rest,
        style: twin.plan.s.style,
        clean: twin.plan.s.clean,
        truth: twin.plan.written_truth(),
    })
}
