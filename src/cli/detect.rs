//! `rollfric detect`: per-frame wire angles of a video, written as CSV.

use crate::clobber;
use crate::config::{locate, Experiment};
use crate::detect::{self, DetectOptions, Status};
use crate::fsutil;
use crate::pipeline;
use crate::usage::{own_cpu_seconds, peak_memory};
use crate::video::Roi;
use anyhow::{bail, Context, Result};
use std::path::PathBuf;

/// The flags of `rollfric detect` (defined here only).
#[derive(clap::Args)]
pub struct DetectArgs {
    /// The video file.
    video: PathBuf,
    /// Output CSV.
    #[arg(short, long)]
    output: PathBuf,
    /// Experiment whose `video:` block narrows the search (ROI, pivot, frames, marks).
    #[arg(long)]
    experiment: Option<String>,
    /// Write an image of each flagged frame (detected line red, predicted green).
    #[arg(long)]
    diagnostics: bool,
    /// Write pictures of each step of the measurement of one frame (0-based) into
    /// `<output>.steps/`: the first look's pivot, band and sweep, the background, the
    /// evidence in the searched wedge, the measured angle against the prediction.
    #[arg(long, value_name = "FRAME")]
    steps: Option<u64>,
    /// Region of interest `x,y,width,height` (px).
    #[arg(long, value_delimiter = ',')]
    roi: Option<Vec<u32>>,
    /// Frames to use, `first,last` (0-based, inclusive).
    #[arg(long, value_delimiter = ',')]
    frames: Option<Vec<u64>>,
    /// Pivot `x,y` (px; may lie outside the frame).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pivot: Option<Vec<f64>>,
    /// The largest side (px) the detector works at: frames are shrunk by a whole factor
    /// to at most this (default 640, or the experiment's `video.work_side_px`); 1280
    /// measures 1280x720 footage at full size, more finely and more slowly. A frame at
    /// the working scale holds at most 3840x2160 px: a larger one is shrunk further.
    #[arg(long, value_name = "PX")]
    work_side: Option<u32>,
    /// Also write the detection's summary as JSON: its verdict (`ok`, `suspect` or
    /// `refused`, with the reason), each check with its figure and limit, what it saw
    /// (period, amplitudes, pivot), the frames' counts, the camera's motion when it
    /// moved. Written on a refusal too.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Replace an existing output that is not an angle CSV.
    #[arg(long)]
    force: bool,
}

/// `detect --json`'s summary.
#[derive(serde::Serialize)]
struct JsonSummary<'a> {
    /// Always `rollfric detect` (first, so that an older summary is known by it).
    kind: &'static str,
    video: String,
    /// `ok`, `suspect` or `refused`.
    verdict: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    reason: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    frames: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    counts: Option<Counts>,
    #[serde(skip_serializing_if = "Option::is_none")]
    roi: Option<[u32; 4]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    dark_wire: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    swing_scale: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    seen: Option<&'a detect::judge::Seen>,
    /// How the camera moved, when it did (each frame steadied).
    #[serde(skip_serializing_if = "Option::is_none")]
    camera: Option<&'a detect::steady::CameraMotion>,
    /// A rolling shutter's readout, fitted to how the moving wire bows, when one was
    /// found (each angle taken to its frame's time).
    #[serde(skip_serializing_if = "Option::is_none")]
    shutter: Option<&'a detect::shutter::WireReadout>,
    checks: &'a [detect::judge::DetectionCheck],
}

#[derive(serde::Serialize)]
struct Counts {
    ok: usize,
    corrected: usize,
    manual: usize,
    missing: usize,
}

/// The JSON text of `d`'s summary, or of a refusal (`d` an error).
fn json_summary(video: &std::path::Path, d: &Result<detect::Detection>) -> Result<String> {
    let s = match d {
        Ok(d) => JsonSummary {
            kind: "rollfric detect",
            video: video.display().to_string(),
            verdict: d.verdict.verdict.as_str(),
            reason: None,
            frames: Some(d.rows.len()),
            counts: Some(Counts {
                ok: d.count(Status::Ok),
                corrected: d.count(Status::Corrected),
                manual: d.count(Status::Manual),
                missing: d.count(Status::Missing),
            }),
            roi: Some(d.roi),
            dark_wire: Some(d.dark_wire),
            swing_scale: d.swing_scale,
            seen: Some(&d.verdict.seen),
            camera: d.camera.as_ref(),
            shutter: d.shutter.as_ref(),
            checks: &d.verdict.checks,
        },
        Err(e) => JsonSummary {
            kind: "rollfric detect",
            video: video.display().to_string(),
            verdict: "refused",
            reason: Some(format!("{e:#}")),
            frames: None,
            counts: None,
            roi: None,
            dark_wire: None,
            swing_scale: None,
            seen: None,
            camera: None,
            shutter: None,
            checks: &[],
        },
    };
    Ok(serde_json::to_string_pretty(&s)? + "\n")
}

/// Exactly `N` comma-separated numbers for `--name`.
fn exactly<T: Copy, const N: usize>(name: &str, v: Option<Vec<T>>) -> Result<Option<[T; N]>> {
    let Some(v) = v else { return Ok(None) };
    match <[T; N]>::try_from(v.as_slice()) {
        Ok(a) => Ok(Some(a)),
        Err(_) => bail!(
            "--{name}: expected {N} comma-separated numbers, got {}",
            v.len()
        ),
    }
}

/// The detector's options: the experiment's `video:` block, then the flags over it.
fn options(a: &DetectArgs) -> Result<DetectOptions> {
    let roi = exactly::<u32, 4>("roi", a.roi.clone())?;
    let frames = exactly::<u64, 2>("frames", a.frames.clone())?;
    let pivot = exactly::<f64, 2>("pivot", a.pivot.clone())?;
    let mut opts = match &a.experiment {
        Some(e) => pipeline::detect_options(&Experiment::load(&locate(e))?),
        None => DetectOptions::default(),
    };
    if let Some([x, y, w, h]) = roi {
        if w == 0 || h == 0 {
            bail!("--roi {x},{y},{w},{h}: the width and height must be at least 1 px");
        }
        opts.roi = Some(Roi { x, y, w, h });
    }
    if let Some([px, py]) = pivot {
        if !(px.is_finite() && py.is_finite()) {
            bail!("--pivot {px},{py}: expected two finite numbers (px)");
        }
    }
    if let Some([first, last]) = frames {
        if first > last {
            bail!("--frames {first},{last}: the first frame comes after the last");
        }
    }
    if let Some(side) = a.work_side {
        crate::config::work_side("--work-side", side)?;
        opts.work_side_px = f64::from(side);
    }
    opts.frames = frames.or(opts.frames);
    opts.pivot = pivot.or(opts.pivot);
    if a.diagnostics {
        opts.diag_dir = Some(a.output.with_extension("diag"));
    }
    opts.steps = a.steps;
    Ok(opts)
}

pub fn detect(a: DetectArgs) -> Result<String> {
    let experiment = a.experiment.as_deref().map(locate);
    let mut inputs = vec![("the video", a.video.as_path())];
    if let Some(e) = &experiment {
        inputs.push(("the experiment file", e.as_path()));
    }
    let mut outputs = vec![clobber::Output {
        flag: "-o",
        path: &a.output,
        kind: clobber::Kind::Angles,
    }];
    if let Some(j) = &a.json {
        outputs.push(clobber::Output {
            flag: "--json",
            path: j,
            kind: clobber::Kind::DetectJson,
        });
    }
    clobber::check(&outputs, &inputs, a.force)?;
    let opts = options(&a)?;
    if opts.work_side_px > 640.0 {
        // A larger working side costs memory: a frame is held to a bounded size, and a
        // side held smaller is said before the work starts.
        let mut dec = crate::video::Decoder::spawn(&a.video)?;
        let info = dec.describe()?;
        let (w, h) = opts.roi.map_or((info.width, info.height), |r| (r.w, r.h));
        let (k, held) = detect::work_scale(w, h, opts.work_side_px);
        if held {
            eprintln!(
                "{}: working side {} px: the finer working scale shrinks the {w}x{h} px \
                 {} {k} times ({}x{} px), as a frame at the working scale holds at most \
                 {:.1} Mpx (memory at the peak about {:.0} MiB)",
                a.video.display(),
                opts.work_side_px,
                if opts.roi.is_some() {
                    "region"
                } else {
                    "frame"
                },
                w / k,
                h / k,
                detect::work_max_pixels() as f64 / 1e6,
                detect::peak_memory_estimate_mib(
                    &crate::video::VideoInfo {
                        width: w,
                        height: h,
                        ..info.clone()
                    },
                    opts.work_side_px
                ),
            );
        }
    }
    let started = std::time::Instant::now();
    let d = detect::detect(&a.video, &opts);
    if let Some(j) = &a.json {
        fsutil::write_atomic(j, json_summary(&a.video, &d)?.as_bytes())?;
    }
    let d = d?;
    let secs = started.elapsed().as_secs_f64();
    fsutil::write_atomic(&a.output, d.to_csv().as_bytes())?;
    let n = d.rows.len();
    eprintln!(
        "{}: {n} frames in {secs:.2} s ({:.0} frames/s, {}, decoded {}, peak memory {}, CPU \
         besides the decoder {}): {} ok, {} corrected, {} manual, {} missing; pivot ({:.1}, \
         {:.1}) px (swing scale {}), {} wire, ROI {:?}{}{} -> {}; {}",
        a.video.display(),
        n as f64 / secs,
        d.decoder,
        match d.decodings {
            1 => "once".to_string(),
            k => format!("{k} times"),
        },
        peak_memory().map_or("?".to_string(), |m| format!("{m:.0} MiB")),
        own_cpu_seconds().map_or("?".to_string(), |c| match d.cpu_s {
            Some(split) => format!("{c:.2} s, {:.2} s of it before the pass", split.before_pass),
            None => format!("{c:.2} s"),
        }),
        d.count(Status::Ok),
        d.count(Status::Corrected),
        d.count(Status::Manual),
        d.count(Status::Missing),
        d.pivot_px[0],
        d.pivot_px[1],
        d.swing_scale.map_or("-".to_string(), |s| format!("{s:.4}")),
        if d.dark_wire { "dark" } else { "light" },
        d.roi,
        d.camera.map_or(String::new(), |c| format!(
            "; the camera moved ({}): {}",
            c.describe(),
            c.steadied()
        )),
        d.shutter.map_or(String::new(), |s| format!(
            "; a rolling shutter: {}",
            s.describe()
        )),
        a.output.display(),
        describe_verdict(&d.verdict)
    );
    if let Some(frame) = a.steps {
        let dir = a.output.with_extension("steps");
        if d.steps.is_empty() {
            eprintln!(
                "{}: --steps {frame}: no pictures: that frame was not measured (a flash, or \
                 outside the frames measured, {} to {})",
                a.video.display(),
                d.rows.first().map_or(0, |r| r.frame),
                d.rows.last().map_or(0, |r| r.frame)
            );
        } else {
            std::fs::create_dir_all(&dir)
                .with_context(|| format!("{}: cannot create folder", dir.display()))?;
            for (file, png) in &d.steps {
                fsutil::write_atomic(&dir.join(file), png)?;
            }
            eprintln!(
                "{}: the steps of frame {frame}: {} pictures in {}",
                a.video.display(),
                d.steps.len(),
                dir.display()
            );
        }
    }
    Ok(String::new())
}

/// The detection's verdict and what it saw, for the summary's line, with each failed
/// check's reason.
fn describe_verdict(v: &detect::judge::DetectionVerdict) -> String {
    let mut out = format!("detection {}: {}", v.label(), v.seen.describe());
    for c in v.failed() {
        out.push_str(&format!("; {}: {}", c.check, c.reason));
    }
    out
}
