//! The wire detector (the paper's section 2.3.2, done right): per frame, the angle of
//! the wire from the image x axis (Eq. 35 via an orthogonal line fit, ERRATA §6).
//!
//! 1. [`geometry`] finds, from the first seconds, the wire's polarity, its pivot, the
//!    band of radii where it is visible and a region of interest (or takes them from
//!    the experiment's `video:` block).
//! 2. Frames stream through once, cropped to the region: the moving-object evidence is
//!    the difference from a background that follows the scene (the running maximum for
//!    a dark wire, minimum for a light one, decaying slowly with the lighting; frames
//!    with a global flash are kept out of it). Pixels above a noise threshold that lie
//!    in a wedge around the angle predicted from the previous frames and in the band
//!    vote in a histogram of angles about the pivot; the sharpest peak is the wire
//!    (a hand or the bob is broad). The orthogonal line fit through the pivot of
//!    every evidence pixel in a ±2.5 px strip along it gives the angle: below the
//!    threshold too, since a threshold that differs from pixel to pixel cuts a blurred
//!    wire's flanks unevenly and tilts the fit.
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
//! video's length (the per-frame angles are a few bytes each).

mod figure11;
pub mod geometry;
pub mod summary;

pub use figure11::{figure11_frame, figure11_png};

use crate::config::{Polarity, Video};
use crate::series::AngleSeries;
use crate::video::{self, FfmpegSource, Frame, FrameSource, OpenCvSource, Roi, VideoInfo};
use anyhow::{bail, Context, Result};
use geometry::{InitFrames, WireGeometry};
use nalgebra::Vector2;
use opencv::core::{self, Mat, Point, Scalar, Vector};
use opencv::prelude::*;
use opencv::{imgcodecs, imgproc};
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

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

/// An infinite line through `point` along the unit vector `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub point: Pt,
    pub dir: Pt,
}

impl Line {
    pub fn through(a: Pt, b: Pt) -> Self {
        Self {
            point: a,
            dir: (b - a).normalize(),
        }
    }

    pub fn normal(&self) -> Pt {
        Pt::new(-self.dir.y, self.dir.x)
    }

    pub fn distance(&self, p: Pt) -> f64 {
        (p - self.point).dot(&self.normal()).abs()
    }
}

/// Orthogonal (total) least-squares line through weighted points: the principal axis
/// of the weighted pixel cloud (ERRATA §6: unlike `y = A x + B`, exact for any slope).
pub fn fit_line_weighted(pts: &[(Pt, f64)]) -> Option<Line> {
    if pts.len() < 2 {
        return None;
    }
    moments(pts).free_line()
}

/// Orthogonal least-squares line constrained to pass through `pivot`: the principal
/// axis of the weighted second moments about the pivot (Eq. 35 done as ERRATA §6 asks,
/// with the wire's known fixed point).
pub fn fit_line_through(pivot: Pt, pts: &[(Pt, f64)]) -> Option<Line> {
    if pts.len() < 2 {
        return None;
    }
    let (th, _) = moments(pts).line_about(pivot)?;
    Some(Line {
        point: pivot,
        dir: Pt::new(th.cos(), th.sin()),
    })
}

/// Weighted pixel moments `[sum w, sum w x, sum w y, sum w x^2, sum w x y, sum w y^2]`.
pub fn moments(pts: &[(Pt, f64)]) -> [f64; 6] {
    let mut m = [0.0f64; 6];
    for (q, w) in pts {
        m[0] += w;
        m[1] += w * q.x;
        m[2] += w * q.y;
        m[3] += w * q.x * q.x;
        m[4] += w * q.x * q.y;
        m[5] += w * q.y * q.y;
    }
    m
}

pub use crate::series::Status;

/// Why a frame was flagged.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Flag {
    /// The measured angle is too far from the prediction.
    Gate,
    /// Too little of the wire was seen.
    Weak,
    /// The whole frame's brightness jumped (a flash).
    Flash,
    /// The frame repeats the previous one (a dropped frame).
    Duplicate,
    /// Much of the region changed at once (a hand or a shadow passing).
    Disturbed,
}

impl Flag {
    /// The name the reports use (as serialised).
    pub fn as_str(&self) -> &'static str {
        match self {
            Flag::Gate => "gate",
            Flag::Weak => "weak",
            Flag::Flash => "flash",
            Flag::Duplicate => "duplicate",
            Flag::Disturbed => "disturbed",
        }
    }

    /// The flag named `s` (as [`Flag::as_str`] writes it).
    pub fn parse(s: &str) -> Option<Self> {
        [
            Flag::Gate,
            Flag::Weak,
            Flag::Flash,
            Flag::Duplicate,
            Flag::Disturbed,
        ]
        .into_iter()
        .find(|f| f.as_str() == s)
    }
}

/// One frame's result.
#[derive(Clone, Debug, Serialize)]
pub struct AngleRow {
    pub frame: u64,
    pub t_s: f64,
    /// Angle of the wire from the image x axis (y down), rad; `None` when missing.
    pub angle_rad: Option<f64>,
    pub status: Status,
    /// 0..1: the fraction of the wire's visible band covered by detected pixels.
    pub quality: f64,
    pub flag: Option<Flag>,
    /// Weighted moments of the wire pixels `[sum w, sum w x, sum w y, sum w x^2,
    /// sum w x y, sum w y^2]` (working-scale region pixels), so that the angle can be
    /// refitted about a refined pivot after the pass.
    #[serde(skip)]
    pub moments: Option<[f64; 6]>,
}

impl Moments for [f64; 6] {
    fn line_about(&self, p: Pt) -> Option<(f64, Pt)> {
        let [sw, sx, sy, sxx, sxy, syy] = *self;
        if sw <= 0.0 || !(sxx + syy).is_finite() {
            return None;
        }
        // Second moments about p.
        let mxx = sxx - 2.0 * p.x * sx + sw * p.x * p.x;
        let mxy = sxy - p.x * sy - p.y * sx + sw * p.x * p.y;
        let myy = syy - 2.0 * p.y * sy + sw * p.y * p.y;
        let th = 0.5 * (2.0 * mxy).atan2(mxx - myy);
        let d = Pt::new(th.cos(), th.sin());
        let c = Pt::new(sx / sw, sy / sw);
        let d = if (c - p).dot(&d) >= 0.0 { d } else { -d };
        Some((d.y.atan2(d.x), c))
    }

    fn free_line(&self) -> Option<Line> {
        let [sw, sx, sy, sxx, sxy, syy] = *self;
        if sw <= 0.0 {
            return None;
        }
        let c = Pt::new(sx / sw, sy / sw);
        let (cxx, cxy, cyy) = (
            sxx / sw - c.x * c.x,
            sxy / sw - c.x * c.y,
            syy / sw - c.y * c.y,
        );
        let th = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
        Some(Line {
            point: c,
            dir: Pt::new(th.cos(), th.sin()),
        })
    }
}

/// Line fits from stored pixel moments.
trait Moments {
    /// The orthogonal fit constrained through `p`: angle (pointing away from `p`) and
    /// the pixels' centroid.
    fn line_about(&self, p: Pt) -> Option<(f64, Pt)>;
    /// The unconstrained orthogonal fit.
    fn free_line(&self) -> Option<Line>;
}

/// Settings of one detection.
#[derive(Clone, Debug)]
pub struct DetectOptions {
    pub roi: Option<Roi>,
    pub pivot: Option<[f64; 2]>,
    pub frames: Option<[u64; 2]>,
    pub polarity: Polarity,
    pub threshold_sigma: f64,
    pub gate_deg: f64,
    pub marks: BTreeMap<u64, [[f64; 2]; 2]>,
    /// Folder for the diagnostic images of flagged frames (none if `None`).
    pub diag_dir: Option<PathBuf>,
    /// Use OpenCV's decoder even when `ffmpeg` is available.
    pub force_opencv: bool,
    /// Told the frames done (and the header's frame count) every 100 frames; when set,
    /// the detector prints no progress of its own.
    pub progress: Option<FrameProgress>,
}

/// A progress callback: `(frames done, frames expected)`.
#[derive(Clone)]
pub struct FrameProgress(pub std::sync::Arc<dyn Fn(u64, Option<u64>) + Send + Sync>);

impl std::fmt::Debug for FrameProgress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("FrameProgress")
    }
}

impl Default for DetectOptions {
    fn default() -> Self {
        Self {
            roi: None,
            pivot: None,
            frames: None,
            polarity: Polarity::Auto,
            threshold_sigma: 4.0,
            gate_deg: 1.5,
            marks: BTreeMap::new(),
            diag_dir: None,
            force_opencv: false,
            progress: None,
        }
    }
}

impl DetectOptions {
    /// Settings from an experiment's `video:` block.
    pub fn from_video(v: &Video) -> Self {
        Self {
            roi: v.roi.map(|[x, y, w, h]| Roi { x, y, w, h }),
            pivot: v.pivot,
            frames: v.frames,
            polarity: v.polarity,
            threshold_sigma: v.threshold_sigma.unwrap_or(4.0),
            gate_deg: v.gate_deg.unwrap_or(1.5),
            marks: v.marks.clone(),
            ..Self::default()
        }
    }
}

/// The result of a detection.
#[derive(Clone, Debug, Serialize)]
pub struct Detection {
    pub rows: Vec<AngleRow>,
    pub pivot_px: [f64; 2],
    pub roi: [u32; 4],
    pub dark_wire: bool,
    pub band_px: [f64; 2],
    pub decoder: String,
    pub diagnostics: Vec<PathBuf>,
}

impl Detection {
    /// The usable angles (every row but `missing`).
    pub fn series(&self) -> AngleSeries {
        let mut s = AngleSeries::default();
        for r in &self.rows {
            if let Some(a) = r.angle_rad {
                s.t.push(r.t_s);
                s.angle.push(a);
            }
        }
        s
    }

    /// Count of rows per status.
    pub fn count(&self, st: Status) -> usize {
        self.rows.iter().filter(|r| r.status == st).count()
    }

    /// CSV: `t_s,angle_rad,status,quality` (angle empty when missing).
    pub fn to_csv(&self) -> String {
        let mut out = String::with_capacity(40 * self.rows.len() + 32);
        out.push_str("t_s,angle_rad,status,quality\n");
        for r in &self.rows {
            let a = r.angle_rad.map(|a| format!("{a:.9}")).unwrap_or_default();
            out.push_str(&format!(
                "{:.6},{a},{},{:.3}\n",
                r.t_s,
                r.status.as_str(),
                r.quality
            ));
        }
        out
    }
}

fn open_source(
    path: &Path,
    info: &VideoInfo,
    roi: Option<Roi>,
    shrink: u32,
    opts: &DetectOptions,
) -> Result<(Box<dyn FrameSource>, &'static str)> {
    if !opts.force_opencv && video::have_ffmpeg() {
        Ok((
            Box::new(FfmpegSource::open(path, info, roi, shrink)?),
            "ffmpeg (luma plane, cropped)",
        ))
    } else {
        if shrink > 1 {
            bail!("shrunk decoding needs the ffmpeg program");
        }
        Ok((
            Box::new(OpenCvSource::open(path, roi)?),
            "OpenCV VideoCapture",
        ))
    }
}

/// Length of the first look at the video (geometry and background), s: more than half
/// a swing of any pendulum up to a 5 s period.
const INIT_SECONDS: f64 = 2.5;

/// Detect the wire angle in every frame of a video.
pub fn detect(path: &Path, opts: &DetectOptions) -> Result<Detection> {
    let started = std::time::Instant::now();
    let info = video::probe(path)?;
    let bound = opts.roi.unwrap_or(Roi {
        x: 0,
        y: 0,
        w: info.width,
        h: info.height,
    });
    if bound.x + bound.w > info.width || bound.y + bound.h > info.height {
        bail!(
            "{}: `video.roi` = [{}, {}, {}, {}] does not fit in the {}x{} frame",
            path.display(),
            bound.x,
            bound.y,
            bound.w,
            bound.h,
            info.width,
            info.height
        );
    }
    let (first, last) = match opts.frames {
        Some([a, b]) => (a, b),
        None => (0, u64::MAX),
    };
    // 1. Geometry from the first seconds (shrunk so the larger side is <= 640 px).
    let shrink = ((bound.w.max(bound.h) as f64) / 640.0).ceil().max(1.0) as u32;
    let use_shrink = if !opts.force_opencv && video::have_ffmpeg() {
        shrink
    } else {
        1
    };
    // The first look's region, cut to whole multiples of the shrink factor: each of
    // its pixels averages exactly `use_shrink` x `use_shrink` full pixels.
    let bound = Roi {
        w: bound.w - bound.w % use_shrink,
        h: bound.h - bound.h % use_shrink,
        ..bound
    };
    let (mut src, _) = open_source(path, &info, Some(bound), use_shrink, opts)?;
    let mut init = InitFrames {
        w: 0,
        h: 0,
        shrink: use_shrink as f64,
        x0: bound.x as f64,
        y0: bound.y as f64,
        data: Vec::new(),
    };
    let mut frame = Frame {
        index: 0,
        t_s: 0.0,
        width: 0,
        height: 0,
        data: Vec::new(),
    };
    let mut t_start = None;
    while src
        .next_frame(&mut frame)
        .with_context(|| "finding the wire".to_string())?
    {
        if frame.index < first {
            continue;
        }
        if frame.index > last {
            break;
        }
        let t0 = *t_start.get_or_insert(frame.t_s);
        init.w = frame.width;
        init.h = frame.height;
        init.data.push(frame.data.clone());
        if frame.t_s - t0 >= INIT_SECONDS || init.data.len() >= 300 {
            break;
        }
    }
    drop(src);
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "timing: first look decoded at {:.2} s ({} frames)",
            started.elapsed().as_secs_f64(),
            init.data.len()
        );
    }
    if init.data.is_empty() {
        bail!("{}: no frame could be decoded", path.display());
    }
    let noise = geometry::noise_map(&init);
    let geo = geometry::find(
        &init,
        &noise,
        info.width,
        info.height,
        opts.polarity,
        opts.pivot.map(|[x, y]| Pt::new(x, y)),
        opts.roi,
    )
    .with_context(|| format!("{}: no wire found", path.display()))?;
    let init_angles = geo.initial_angles.clone();
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "timing: geometry done at {:.2} s",
            started.elapsed().as_secs_f64()
        );
    }
    let init_bg = geometry::extreme_frame(&init, geo.dark)?;
    let init_tmap = geometry::threshold_map(&init, &noise, 0.5 * opts.threshold_sigma)?;
    drop(init);

    // 2. The streaming pass over the region of interest.
    let (mut src, decoder) = open_source(path, &info, Some(geo.roi), 1, opts)?;
    let mut tracker = Tracker::new(&geo, opts, init_bg, init_tmap, use_shrink as f64, bound)?;
    let total = info.frames_header;
    let tty = std::io::stderr().is_terminal() && opts.progress.is_none();
    let mut rows = Vec::new();
    let mut k = 0usize;
    let mut waited = 0.0f64;
    loop {
        let t_wait = std::time::Instant::now();
        let more = src.next_frame(&mut frame)?;
        waited += t_wait.elapsed().as_secs_f64();
        if !more {
            break;
        }
        if frame.index < first {
            continue;
        }
        if frame.index > last {
            break;
        }
        let hint = init_angles.get(k).copied().flatten();

        rows.push(tracker.step(&frame, hint)?);
        k += 1;
        if let Some(p) = opts.progress.as_ref().filter(|_| k.is_multiple_of(100)) {
            (p.0)(k as u64, total);
        }
        if tty && k.is_multiple_of(100) {
            match total {
                Some(n) => eprint!("\rdetect: frame {k}/{n}"),
                None => eprint!("\rdetect: frame {k}"),
            }
        }
    }
    if tty {
        eprintln!();
    }
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "timing: streaming pass done at {:.2} s ({waited:.2} s waiting for frames)",
            started.elapsed().as_secs_f64()
        );
    }
    drop(src);
    if rows.is_empty() {
        bail!("{}: no frame in the requested range", path.display());
    }
    if rows.iter().any(|r| !r.t_s.is_finite()) {
        bail!(
            "{}: the decoder gave frames without timestamps",
            path.display()
        );
    }
    flag_repeats(&mut rows);
    let pivot = tracker.refine_pivot(&mut rows);
    fill_flagged(&mut rows);
    apply_marks(&mut rows, &opts.marks, pivot);
    let usable = rows.iter().filter(|r| r.status != Status::Missing).count();
    if usable < rows.len() / 2 {
        bail!(
            "{}: the wire was found in only {usable} of {} frames (last good frame {}); \
             check `video.roi`, `video.pivot` and `video.polarity`",
            path.display(),
            rows.len(),
            rows.iter()
                .rev()
                .find(|r| r.status == Status::Ok)
                .map_or(0, |r| r.frame)
        );
    }
    Ok(Detection {
        rows,
        pivot_px: [pivot.x, pivot.y],
        roi: [geo.roi.x, geo.roi.y, geo.roi.w, geo.roi.h],
        dark_wire: geo.dark,
        band_px: [geo.r_lo, geo.r_hi],
        decoder: decoder.to_string(),
        diagnostics: tracker.diagnostics,
    })
}

/// Per-frame state of the streaming pass.
struct Tracker {
    geo: WireGeometry,
    /// Work at 1/scale of the full frame, in a region starting at `(roi_x, roi_y)`.
    scale: f64,
    roi_x: f64,
    roi_y: f64,
    /// Pivot and band in the scaled region's pixels.
    piv: Pt,
    r_lo: f64,
    r_hi: f64,
    small: Mat,
    bg: Mat,
    tmp: Mat,
    raw_ev: Mat,
    kernel: Mat,
    /// Per-pixel detection threshold (grey levels).
    tmap: Mat,
    ev: Mat,
    bin: Mat,
    prev: Vec<u8>,
    mean_level: Option<f64>,
    gate: f64,
    /// Recent accepted (t, angle) for the prediction.
    hist: Vec<(f64, f64)>,
    /// The last few raw measurements (accepted or not).
    raw: Vec<(f64, f64)>,
    /// Typical quality of accepted frames (a faint wire covers less of its band).
    q_ref: Option<f64>,
    /// Typical mean absolute change between consecutive frames.
    mad_ref: Option<f64>,
    /// Mean square innovation of accepted frames, and how many were seen.
    innov: Option<(f64, usize)>,
    since_good: usize,
    decay_every: u64,
    diag_dir: Option<PathBuf>,
    diagnostics: Vec<PathBuf>,
}

impl Tracker {
    fn new(
        geo: &WireGeometry,
        opts: &DetectOptions,
        init_bg: Mat,
        init_tmap: Mat,
        shrink: f64,
        bound: Roi,
    ) -> Result<Self> {
        // The first seconds' background covers `bound` at the shrunk scale: map it onto
        // the region of interest at full scale.
        let roi = geo.roi;
        // The streaming pass works at the same scale as the first seconds: a faint wire
        // that the area average brings out there stays visible, and the angle does not
        // depend on scale. Map from the shrunk `bound` to the shrunk region.
        let m = Mat::from_slice_2d(&[
            [1.0, 0.0, (roi.x as f64 - bound.x as f64) / shrink],
            [0.0, 1.0, (roi.y as f64 - bound.y as f64) / shrink],
        ])?;
        let (sw, sh) = (
            (roi.w as f64 / shrink).floor() as i32,
            (roi.h as f64 / shrink).floor() as i32,
        );
        let to_roi = |src: &Mat| -> Result<Mat> {
            let mut out = Mat::default();
            imgproc::warp_affine(
                src,
                &mut out,
                &m,
                core::Size::new(sw, sh),
                imgproc::INTER_LINEAR | imgproc::WARP_INVERSE_MAP,
                core::BORDER_REPLICATE,
                Scalar::default(),
            )?;
            Ok(out)
        };
        let bg = to_roi(&init_bg)?;
        let tmap = to_roi(&init_tmap)?;
        if let Some(d) = &opts.diag_dir {
            std::fs::create_dir_all(d)
                .with_context(|| format!("{}: cannot create folder", d.display()))?;
        }
        Ok(Self {
            geo: geo.clone(),
            scale: shrink,
            roi_x: roi.x as f64,
            roi_y: roi.y as f64,
            piv: full_to_shrunk(geo.pivot, Pt::new(roi.x as f64, roi.y as f64), shrink),
            r_lo: geo.r_lo / shrink,
            r_hi: geo.r_hi / shrink,
            small: Mat::default(),
            bg,
            raw_ev: Mat::default(),
            tmp: Mat::default(),
            kernel: imgproc::get_structuring_element_def(
                imgproc::MORPH_ELLIPSE,
                core::Size::new(7, 7),
            )?,
            tmap,
            ev: Mat::default(),
            bin: Mat::default(),
            prev: Vec::new(),
            mean_level: None,
            gate: opts.gate_deg.to_radians(),
            hist: Vec::new(),
            raw: Vec::new(),
            q_ref: None,
            mad_ref: None,
            innov: None,
            since_good: 0,
            decay_every: 120,
            diag_dir: opts.diag_dir.clone(),
            diagnostics: Vec::new(),
        })
    }

    fn predict(&self, t: f64) -> Option<f64> {
        let lo = self.geo.theta_min - 15f64.to_radians();
        let hi = self.geo.theta_max + 15f64.to_radians();
        self.predict_raw(t)
            .filter(|p| *p > lo - 0.2 && *p < hi + 0.2)
            .map(|p| p.clamp(lo, hi))
    }

    fn predict_raw(&self, t: f64) -> Option<f64> {
        let n = self.hist.len();
        if n == 0 || self.since_good > 4 {
            return None;
        }
        let recent = &self.hist[n.saturating_sub(3)..];
        if recent.len() == 3 && recent[2].0 - recent[0].0 < 0.25 {
            // The quadratic through the last three accepted angles (Lagrange form).
            let [(t0, a0), (t1, a1), (t2, a2)] = [recent[0], recent[1], recent[2]];
            let l0 = (t - t1) * (t - t2) / ((t0 - t1) * (t0 - t2));
            let l1 = (t - t0) * (t - t2) / ((t1 - t0) * (t1 - t2));
            let l2 = (t - t0) * (t - t1) / ((t2 - t0) * (t2 - t1));
            return Some(a0 * l0 + a1 * l1 + a2 * l2);
        }
        if recent.len() >= 2 {
            let (t1, a1) = recent[recent.len() - 2];
            let (t2, a2) = recent[recent.len() - 1];
            return Some(a2 + (a2 - a1) / (t2 - t1) * (t - t2));
        }
        Some(recent[0].1)
    }

    fn step(&mut self, f: &Frame, hint: Option<f64>) -> Result<AngleRow> {
        let full = Mat::new_rows_cols_with_data(f.height as i32, f.width as i32, &f.data)?;
        let (w, h) = (self.bg.cols(), self.bg.rows());
        if self.scale > 1.0 {
            imgproc::resize(
                &full,
                &mut self.small,
                core::Size::new(w, h),
                0.0,
                0.0,
                imgproc::INTER_AREA,
            )?;
        } else {
            if full.cols() != w || full.rows() != h {
                bail!(
                    "frame {} is {}x{} px, expected {w}x{h}",
                    f.index,
                    full.cols(),
                    full.rows()
                );
            }
            full.copy_to(&mut self.small)?;
        }
        // Global brightness: a flash or a dropout is kept out of the background.
        let level = sampled_mean(&f.data, 7);
        let flash = self
            .mean_level
            .is_some_and(|m| (level - m).abs() > 0.2 * m.max(20.0));
        // A repeated frame (the camera dropped one and the recorder repeated the last)
        // differs from its predecessor far less than the sensor noise makes any two
        // real frames differ.
        let mad = if self.prev.is_empty() {
            f64::NAN
        } else {
            mean_abs_diff_sampled(&f.data, &self.prev, 5)
        };
        let duplicate = mad < 0.02 || self.mad_ref.is_some_and(|r| mad < 0.15 * r);
        let disturbed = self.mad_ref.is_some_and(|r| mad > 4.0 * r.max(0.5));
        if std::env::var("ROLLFRIC_DEBUG").is_ok_and(|v| v == "mad") {
            eprintln!("mad {} {mad:.3} ref {:?}", f.index, self.mad_ref);
        }
        if mad.is_finite() && !duplicate {
            self.mad_ref = Some(match self.mad_ref {
                Some(r) => 0.95 * r + 0.05 * mad.min(3.0 * r),
                None => mad,
            });
        }

        self.prev.clear();
        self.prev.extend(f.data.iter().step_by(5));
        if !flash {
            self.mean_level = Some(match self.mean_level {
                Some(m) => 0.9 * m + 0.1 * level,
                None => level,
            });
        }
        // Evidence (thin structures only: a top-hat removes the bob and a hand's
        // palm), then the background follows the scene.
        if self.geo.dark {
            core::subtract_def(&self.bg, &self.small, &mut self.raw_ev)?;
        } else {
            core::subtract_def(&self.small, &self.bg, &mut self.raw_ev)?;
        }
        imgproc::morphology_ex_def(
            &self.raw_ev,
            &mut self.ev,
            imgproc::MORPH_TOPHAT,
            &self.kernel,
        )?;
        if !flash {
            if self.geo.dark {
                core::max(&self.bg, &self.small, &mut self.tmp)?;
            } else {
                core::min(&self.bg, &self.small, &mut self.tmp)?;
            }
            std::mem::swap(&mut self.bg, &mut self.tmp);
            if f.index.is_multiple_of(self.decay_every) {
                let one = Scalar::all(1.0);
                if self.geo.dark {
                    core::subtract_def(&self.bg, &one, &mut self.tmp)?;
                } else {
                    core::add_def(&self.bg, &one, &mut self.tmp)?;
                }
                std::mem::swap(&mut self.bg, &mut self.tmp);
            }
        }
        // During the first seconds the geometry pass's angle of this very frame is the
        // better guess until three frames have been accepted.
        let pred = if self.hist.len() < 3 {
            hint.or(self.predict(f.t_s))
        } else {
            self.predict(f.t_s).or(hint)
        };
        let mut row = AngleRow {
            frame: f.index,
            t_s: f.t_s,
            angle_rad: None,
            status: Status::Ok,
            quality: 0.0,
            flag: None,
            moments: None,
        };
        if flash {
            row.flag = Some(Flag::Flash);
            self.since_good += 1;
            self.save_diag(f.index, f64::NAN, pred)?;
            return Ok(row);
        }
        let (angle, quality, moments) = match self.measure(pred)? {
            Some((a, q, m)) => (a, q, Some(m)),
            None => (f64::NAN, 0.0, None),
        };
        row.quality = quality;
        row.moments = moments;
        // Fewer than three accepted frames make a poor prediction: open the gate.
        let short = if self.hist.len() < 3 { 4.0 } else { 1.0 };
        // Fast motion at a low frame rate predicts less well: widen the gate by half the
        // last accepted step.
        let step = match self.hist.as_slice() {
            [.., (_, a), (_, b)] => (b - a).abs(),
            _ => 0.0,
        };
        // Once the innovations (measured minus predicted) of accepted frames are known,
        // the gate tightens to four times their RMS: a repeated frame that the codec did
        // not keep bit-identical still lags its prediction by a fraction of a degree.
        let base = match self.innov {
            Some((ms, n)) if n >= 30 => (4.0 * ms.sqrt()).clamp(0.05f64.to_radians(), self.gate),
            _ => self.gate,
        };
        let gate = (base + 0.5 * step) * (1.0 + self.since_good as f64) * short;
        // A repeated frame that the codec did not keep identical is found after the
        // pass, from both sides (`flag_repeats`): the previous frames alone overshoot
        // at a turning point, where a wire that stops looks like a repeat.
        let flag = if duplicate {
            Some(Flag::Duplicate)
        } else if disturbed {
            Some(Flag::Disturbed)
        } else if !angle.is_finite() || quality < (0.5 * self.q_ref.unwrap_or(0.6)).max(0.1) {
            Some(Flag::Weak)
        } else if pred.is_some_and(|p| (angle - p).abs() > gate) {
            Some(Flag::Gate)
        } else {
            None
        };
        if angle.is_finite() {
            row.angle_rad = Some(angle);
        }
        if std::env::var("ROLLFRIC_DEBUG").is_ok_and(|v| v == "frames") {
            eprintln!(
                "frame {} t {:.3} angle {:.2} pred {:?} q {:.2} flag {:?}",
                f.index,
                f.t_s,
                angle.to_degrees(),
                pred.map(|p| (p.to_degrees() * 100.0).round() / 100.0),
                quality,
                flag
            );
        }
        if angle.is_finite() {
            self.raw.push((f.t_s, angle));
            if self.raw.len() > 8 {
                self.raw.remove(0);
            }
        }
        // Re-anchor after a run of rejections when the last three raw measurements agree
        // with one another (a smooth motion): the history, not the wire, was wrong.
        let flag = match flag {
            Some(Flag::Gate) if self.since_good >= 2 && self.raw.len() >= 3 => {
                let r = &self.raw[self.raw.len() - 3..];
                let smooth =
                    (r[2].1 - 2.0 * r[1].1 + r[0].1).abs() < self.gate && r[2].0 - r[0].0 < 0.2;
                if smooth {
                    self.hist.clear();
                    self.hist.extend_from_slice(&r[..2]);
                    None
                } else {
                    flag
                }
            }
            other => other,
        };
        match flag {
            None => {
                if let Some(p) = pred.filter(|_| self.hist.len() >= 3) {
                    let e2 = (angle - p).powi(2);
                    self.innov = Some(match self.innov {
                        Some((ms, n)) => (0.97 * ms + 0.03 * e2.min(9.0 * ms.max(1e-12)), n + 1),
                        None => (e2, 1),
                    });
                }
                self.q_ref = Some(match self.q_ref {
                    Some(q) => 0.95 * q + 0.05 * quality,
                    None => quality,
                });
                self.hist.push((f.t_s, angle));
                if self.hist.len() > 16 {
                    self.hist.drain(..8);
                }
                self.since_good = 0;
            }
            Some(fl) => {
                row.flag = Some(fl);
                self.since_good += 1;
                if fl != Flag::Duplicate {
                    self.save_diag(f.index, angle, pred)?;
                }
            }
        }
        Ok(row)
    }

    /// The wire's angle and coverage in the current evidence image, searching a wedge
    /// around `pred` (or every angle the wire was seen at, without a prediction).
    fn measure(&mut self, pred: Option<f64>) -> Result<Option<(f64, f64, [f64; 6])>> {
        core::compare(&self.ev, &self.tmap, &mut self.bin, core::CMP_GT)?;
        let mut nz = Vector::<Point>::new();
        core::find_non_zero(&self.bin, &mut nz)?;
        let g = &self.geo;
        let (lo, hi) = match pred {
            Some(p) => {
                let wdg = (3.0 * self.gate * (1.0 + self.since_good as f64)).max(2f64.to_radians());
                (p - wdg, p + wdg)
            }
            None => (g.theta_min - 0.35, g.theta_max + 0.35),
        };
        let piv = self.piv;
        let (r_lo, r_hi) = (self.r_lo, self.r_hi);
        let r_mid = 0.5 * (r_lo + r_hi);
        let bin_w = (0.75 / r_mid).max(1e-4);
        let nb = (((hi - lo) / bin_w).ceil() as usize).clamp(8, 20_000);
        let mut histo = vec![0.0f64; nb];
        let ev = self.ev.data_bytes()?;
        let stride = self.ev.cols() as usize;
        let mut cand: Vec<(Pt, f64, f64)> = Vec::new(); // (point, weight, angle)
        for p in nz.iter() {
            let q = Pt::new(p.x as f64, p.y as f64);
            let d = q - piv;
            let r = d.norm();
            if r < r_lo || r > r_hi {
                continue;
            }
            let th = d.y.atan2(d.x);
            if th < lo || th > hi {
                continue;
            }
            let wgt = ev[p.y as usize * stride + p.x as usize] as f64;
            let b = (((th - lo) / bin_w) as usize).min(nb - 1);
            histo[b] += wgt;
            cand.push((q, wgt, th));
            if cand.len() > 200_000 {
                break;
            }
        }
        if cand.len() < 5 {
            return Ok(None);
        }
        // Sharpest peak: a bin's mass against its neighbourhood (a broad blob scores low).
        let k = 4usize;
        let sm: Vec<f64> = (0..nb)
            .map(|i| histo[i.saturating_sub(1)..(i + 2).min(nb)].iter().sum())
            .collect();
        let mut best = (f64::MIN, 0usize);
        for i in 0..nb {
            let side = 0.5
                * (sm.get(i.wrapping_sub(3 * k)).copied().unwrap_or(0.0)
                    + sm.get(i + 3 * k).copied().unwrap_or(0.0));
            let score = sm[i] - side;
            if score > best.0 {
                best = (score, i);
            }
        }
        let th0 = lo + (best.1 as f64 + 0.5) * bin_w;
        let l0 = Line {
            point: piv,
            dir: Pt::new(th0.cos(), th0.sin()),
        };
        // Pixels along that line, then the orthogonal fit constrained to the pivot
        // (twice, tightening the strip).
        let mut line = l0;
        let mut sel: Vec<(Pt, f64)> = Vec::new();
        for strip in [4.0, 2.5] {
            sel = cand
                .iter()
                .filter(|(q, _, _)| line.distance(*q) <= strip)
                .map(|(q, w, _)| (*q, *w))
                .collect();
            match fit_line_through(piv, &sel) {
                Some(l) => line = l,
                None => return Ok(None),
            }
        }
        if sel.len() < 5 {
            return Ok(None);
        }
        // Coverage of the band by the selected pixels.
        let nbins = 24usize;
        let mut cov = vec![false; nbins];
        for (q, _) in &sel {
            let r = (q - piv).norm();
            let b = (((r - r_lo) / (r_hi - r_lo)) * nbins as f64) as usize;
            cov[b.min(nbins - 1)] = true;
        }
        let quality = cov.iter().filter(|c| **c).count() as f64 / nbins as f64;
        // The angle itself from every pixel of the strip, below the threshold too: the
        // threshold, which differs from pixel to pixel, would cut the blurred wire's
        // flanks unevenly and tilt the fit (by about 0.4 % of the swing on a light wire).
        for _ in 0..2 {
            let px = self.strip_pixels(&line, 2.5)?;
            match fit_line_through(piv, &px) {
                Some(l) => line = l,
                None => return Ok(None),
            }
            sel = px;
        }
        if sel.len() < 5 {
            return Ok(None);
        }
        // Point the direction away from the pivot, towards the pixels.
        let c = sel.iter().fold(Pt::zeros(), |a, (q, w)| a + (q - piv) * *w);
        let d = if c.dot(&line.dir) >= 0.0 {
            line.dir
        } else {
            -line.dir
        };
        Ok(Some((d.y.atan2(d.x), quality, moments(&sel))))
    }

    /// The evidence pixels within `half` px of `line` (a line through the pivot), in
    /// the band, with their weights. Walks the strip row by row (or column by column
    /// for a line closer to horizontal), so only the strip's own pixels are visited.
    fn strip_pixels(&self, line: &Line, half: f64) -> Result<Vec<(Pt, f64)>> {
        let (cols, rows) = (self.ev.cols() as usize, self.ev.rows() as usize);
        let ev = self.ev.data_bytes()?;
        let (piv, d) = (self.piv, line.dir);
        let (a, b) = (piv + d * self.r_lo, piv + d * self.r_hi);
        // Along the major axis `u` (y when the line is steep), the strip at `u` spans
        // `v` within `half / |d_u|` of the line.
        let steep = d.y.abs() >= d.x.abs();
        let (pu, pv, du, dv, nu, nv) = if steep {
            (piv.y, piv.x, d.y, d.x, rows, cols)
        } else {
            (piv.x, piv.y, d.x, d.y, cols, rows)
        };
        let (au, bu) = if steep { (a.y, b.y) } else { (a.x, b.x) };
        let span = half / du.abs();
        let u0 = (au.min(bu) - half).floor().max(0.0) as usize;
        let u1 = ((au.max(bu) + half).ceil().max(0.0) as usize).min(nu);
        let (r_lo2, r_hi2) = (self.r_lo * self.r_lo, self.r_hi * self.r_hi);
        let mut out = Vec::new();
        for u in u0..u1 {
            let vc = pv + (u as f64 - pu) * dv / du;
            let v0 = (vc - span).ceil().max(0.0) as usize;
            let v1 = ((vc + span).floor() + 1.0).clamp(0.0, nv as f64) as usize;
            for v in v0..v1 {
                let (x, y) = if steep { (v, u) } else { (u, v) };
                let w = ev[y * cols + x];
                if w == 0 {
                    continue;
                }
                let q = Pt::new(x as f64, y as f64);
                let r2 = (q - piv).norm_squared();
                if r2 >= r_lo2 && r2 <= r_hi2 {
                    out.push((q, w as f64));
                }
            }
        }
        Ok(out)
    }

    /// Refine the pivot from the whole pass: the robust intersection of every accepted
    /// frame's free line fit (hundreds of lines at different angles, against the few
    /// dozen of the first seconds), then refit every angle about it from the stored
    /// pixel moments. Returns the pivot in full-frame pixels.
    fn refine_pivot(&self, rows: &mut [AngleRow]) -> Pt {
        let to_full = |p: Pt| shrunk_to_full(p, Pt::new(self.roi_x, self.roi_y), self.scale);
        let lines: Vec<Line> = rows
            .iter()
            .filter(|r| r.flag.is_none())
            .filter_map(|r| r.moments.as_ref().and_then(|m| m.free_line()))
            .collect();
        let angles: Vec<f64> = lines
            .iter()
            .map(|l| l.dir.y.atan2(l.dir.x).rem_euclid(std::f64::consts::PI))
            .collect();
        let spread = angles.iter().fold(f64::MIN, |a, &b| a.max(b))
            - angles.iter().fold(f64::MAX, |a, &b| a.min(b));
        if lines.len() < 20 || spread < 2f64.to_radians() {
            return to_full(self.piv);
        }
        let Ok(p) = geometry::intersect(&lines) else {
            return to_full(self.piv);
        };
        // Accept a refinement, not a jump elsewhere.
        if (p - self.piv).norm() > 0.05 * (self.r_lo + self.r_hi) {
            return to_full(self.piv);
        }
        for r in rows.iter_mut() {
            if let Some((a, _)) = r.moments.as_ref().and_then(|m| m.line_about(p)) {
                if r.angle_rad.is_some() {
                    r.angle_rad = Some(a);
                }
            }
        }
        to_full(p)
    }

    /// The paper's Figure 11 for a flagged frame: detected line red, predicted green.
    fn save_diag(&mut self, index: u64, angle: f64, pred: Option<f64>) -> Result<()> {
        let Some(dir) = &self.diag_dir else {
            return Ok(());
        };
        if self.diagnostics.len() >= 40 {
            return Ok(());
        }
        let mut bgr = Mat::default();
        imgproc::cvt_color_def(&self.small, &mut bgr, imgproc::COLOR_GRAY2BGR)?;
        let (piv, r_lo, r_hi) = (self.piv, self.r_lo, self.r_hi);
        let mut draw = |th: f64, color: Scalar| -> Result<()> {
            let a = piv + Pt::new(th.cos(), th.sin()) * r_lo;
            let b = piv + Pt::new(th.cos(), th.sin()) * r_hi;
            imgproc::line(
                &mut bgr,
                Point::new(a.x as i32, a.y as i32),
                Point::new(b.x as i32, b.y as i32),
                color,
                1,
                imgproc::LINE_AA,
                0,
            )?;
            Ok(())
        };
        if let Some(p) = pred {
            draw(p, Scalar::new(0.0, 200.0, 0.0, 0.0))?;
        }
        if angle.is_finite() {
            draw(angle, Scalar::new(0.0, 0.0, 255.0, 0.0))?;
        }
        let path = dir.join(format!("frame-{index:06}.png"));
        imgcodecs::imwrite_def(path.to_string_lossy().into_owned(), &bgr)
            .with_context(|| format!("{}: cannot write", path.display()))?;
        self.diagnostics.push(path);
        Ok(())
    }
}

/// Mean of every `step`-th byte.
fn sampled_mean(d: &[u8], step: usize) -> f64 {
    let (mut s, mut n) = (0u64, 0u64);
    for v in d.iter().step_by(step) {
        s += *v as u64;
        n += 1;
    }
    s as f64 / n.max(1) as f64
}

/// Mean absolute difference between every `step`-th byte of `a` and the bytes of
/// `sampled` (which holds every `step`-th byte of the previous frame).
fn mean_abs_diff_sampled(a: &[u8], sampled: &[u8], step: usize) -> f64 {
    let (mut s, mut n) = (0u64, 0u64);
    for (x, y) in a.iter().step_by(step).zip(sampled) {
        s += x.abs_diff(*y) as u64;
        n += 1;
    }
    if n as usize != sampled.len() {
        return f64::INFINITY;
    }
    s as f64 / n.max(1) as f64
}

/// Operator marks replace the detection: the angle of the line through the two points,
/// pointing away from the pivot.
fn apply_marks(rows: &mut [AngleRow], marks: &BTreeMap<u64, [[f64; 2]; 2]>, pivot: Pt) {
    for r in rows.iter_mut() {
        if let Some([[x1, y1], [x2, y2]]) = marks.get(&r.frame) {
            let (a, b) = (Pt::new(*x1, *y1), Pt::new(*x2, *y2));
            let (near, far) = if (a - pivot).norm() <= (b - pivot).norm() {
                (a, b)
            } else {
                (b, a)
            };
            let d = far - near;
            r.angle_rad = Some(d.y.atan2(d.x));
            r.status = Status::Manual;
            r.flag = None;
            r.quality = 1.0;
        }
    }
}

/// A repeated frame, found once every angle is known: the same picture measures the
/// same, so its angle equals the previous frame's (to the codec's loss) where its
/// neighbours on both sides say the wire moved on by several times the measurement
/// noise. (While streaming, only the previous frames predict, three times less
/// precisely; a repeat near a turning point, where the wire hardly moves, hides there.)
fn flag_repeats(rows: &mut [AngleRow]) {
    // Frames the gate turned away count as neighbours: after a repeat has entered the
    // history, the prediction lags and the gate refuses the next few good frames.
    let good = |r: &AngleRow| {
        matches!(r.flag, None | Some(Flag::Gate))
            .then_some(r.angle_rad)
            .flatten()
    };
    // For frame i with good frames i-2..=i+2: the angle the neighbours predict (cubic
    // through i-2, i-1, i+1, i+2 in time) and the previous frame's.
    let mut cases: Vec<(usize, f64, f64)> = Vec::new();
    for i in 2..rows.len().saturating_sub(2) {
        let pts: Option<Vec<(f64, f64)>> = [i - 2, i - 1, i + 1, i + 2]
            .iter()
            .map(|&j| good(&rows[j]).map(|a| (rows[j].t_s, a)))
            .collect();
        let (Some(pts), Some(a)) = (pts, good(&rows[i])) else {
            continue;
        };
        let t = rows[i].t_s;
        let predicted: f64 = (0..4)
            .map(|k| {
                let l: f64 = (0..4)
                    .filter(|&m| m != k)
                    .map(|m| (t - pts[m].0) / (pts[k].0 - pts[m].0))
                    .product();
                l * pts[k].1
            })
            .sum();
        cases.push((i, a - predicted, predicted - pts[1].1));
    }
    if cases.len() < 20 {
        return;
    }
    // The measurement noise (robust: median absolute residual; never zero, or exact
    // data would make every step significant).
    let mut res: Vec<f64> = cases.iter().map(|c| c.1.abs()).collect();
    res.sort_by(f64::total_cmp);
    let sigma = (1.4826 * res[res.len() / 2]).max(1e-7);
    // A wild frame (a glint taken for the wire) pulls the cubic of the frames beside
    // it: only the frame that disagrees most with its neighbours within two frames
    // may be a repeat.
    let mut misfit = vec![0.0f64; rows.len()];
    for &(i, resid, _) in &cases {
        misfit[i] = resid.abs();
    }
    for (i, resid, step) in cases {
        let worst_nearby = misfit[i - 2..=i + 2].iter().all(|&m| m <= resid.abs());
        // The frame disagrees with its neighbours and lies nearer the previous frame's
        // angle than theirs, where they expect a step from the previous frame well
        // above the noise.
        let moved = (resid + step).abs();
        if rows[i].flag.is_none()
            && worst_nearby
            && step.abs() > 4.0 * sigma
            && resid.abs() > 3.0 * sigma
            && moved < resid.abs()
        {
            rows[i].flag = Some(Flag::Duplicate);
        }
    }
}

const FILL_REACH_S: f64 = 0.3;

/// Fill each flagged frame from its good neighbours (a local quadratic in time through
/// up to three good frames on each side, within 0.3 s); without good
/// neighbours on both sides it stays missing.
fn fill_flagged(rows: &mut [AngleRow]) {
    let good: Vec<usize> = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.flag.is_none() && r.angle_rad.is_some())
        .map(|(i, _)| i)
        .collect();
    let flagged: Vec<usize> = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.flag.is_some())
        .map(|(i, _)| i)
        .collect();
    for i in flagged {
        let t = rows[i].t_s;
        let k = good.partition_point(|&g| g < i);
        let before: Vec<usize> = good[k.saturating_sub(3)..k]
            .iter()
            .copied()
            .filter(|&g| t - rows[g].t_s <= FILL_REACH_S)
            .collect();
        let after: Vec<usize> = good[k..(k + 3).min(good.len())]
            .iter()
            .copied()
            .filter(|&g| rows[g].t_s - t <= FILL_REACH_S)
            .collect();
        if before.is_empty() || after.is_empty() {
            rows[i].angle_rad = None;
            rows[i].status = Status::Missing;
            continue;
        }
        if before.len() + after.len() == 2 {
            // Straight line between the two neighbours.
            let (a, b) = (&rows[before[0]], &rows[after[0]]);
            let (ya, yb) = (a.angle_rad.unwrap_or(0.0), b.angle_rad.unwrap_or(0.0));
            let v = ya + (yb - ya) * (t - a.t_s) / (b.t_s - a.t_s);
            rows[i].angle_rad = Some(v);
            rows[i].status = Status::Corrected;
            continue;
        }
        let mut ata = nalgebra::Matrix3::<f64>::zeros();
        let mut atb = nalgebra::Vector3::<f64>::zeros();
        for &g in before.iter().chain(&after) {
            let x = rows[g].t_s - t;
            let v = nalgebra::Vector3::new(1.0, x, x * x);
            ata += v * v.transpose();
            atb += v * rows[g].angle_rad.expect("good rows have angles");
        }
        match ata.cholesky() {
            Some(c) => {
                rows[i].angle_rad = Some(c.solve(&atb)[0]);
                rows[i].status = Status::Corrected;
            }
            None => {
                rows[i].angle_rad = None;
                rows[i].status = Status::Missing;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shrunk_pixel_centres_map_to_the_centres_of_the_pixels_they_average() {
        let origin = Pt::new(10.0, 3.0);
        // Shrunk 2x: pixel 0 averages full pixels 10 and 11 (centre 10.5).
        assert_eq!(
            shrunk_to_full(Pt::new(0.0, 0.0), origin, 2.0),
            Pt::new(10.5, 3.5)
        );
        // 3x: pixel 1 averages 13, 14 and 15.
        assert_eq!(
            shrunk_to_full(Pt::new(1.0, 1.0), origin, 3.0),
            Pt::new(14.0, 7.0)
        );
        assert_eq!(
            shrunk_to_full(Pt::new(4.0, 5.0), origin, 1.0),
            Pt::new(14.0, 8.0)
        );
        let p = Pt::new(123.25, -640.5);
        assert!((shrunk_to_full(full_to_shrunk(p, origin, 3.0), origin, 3.0) - p).norm() < 1e-12);
    }

    /// 60 frames/s of a 1 s period swing of 0.2 rad, with 0.0002 rad of noise (a
    /// fixed pseudo-random sequence).
    fn swing_rows() -> Vec<AngleRow> {
        let noise = |i: usize| 2e-4 * (((i * 7919) % 101) as f64 / 50.0 - 1.0);
        let angle = |t: f64| 1.5 + 0.2 * (std::f64::consts::TAU * t).sin();
        (0..240)
            .map(|i| {
                let t = i as f64 / 60.0;
                AngleRow {
                    frame: i as u64,
                    t_s: t,
                    angle_rad: Some(angle(t) + noise(i)),
                    status: Status::Ok,
                    quality: 1.0,
                    flag: None,
                    moments: None,
                }
            })
            .collect()
    }

    fn flagged(rows: &[AngleRow]) -> Vec<(u64, Flag)> {
        rows.iter()
            .filter_map(|r| r.flag.map(|f| (r.frame, f)))
            .collect()
    }

    #[test]
    fn a_repeated_frame_is_flagged_and_a_turning_point_is_not() {
        // Frame 100 repeats frame 99's picture (and so its measurement, up to a little
        // codec noise). There the wire turns at 0.63 rad/s: frame 100 lags by 0.010
        // rad, 50 times the noise.
        let mut rows = swing_rows();
        rows[100].angle_rad = Some(rows[99].angle_rad.unwrap() + 5e-5);
        flag_repeats(&mut rows);
        assert_eq!(flagged(&rows), vec![(100, Flag::Duplicate)]);
        // A repeat at a turning point (t = 0.25 s, frame 15) moves nothing that the
        // noise does not: it is left alone, and so is every true turning point.
        let mut rows = swing_rows();
        rows[15].angle_rad = rows[14].angle_rad;
        flag_repeats(&mut rows);
        assert_eq!(flagged(&rows), vec![]);
    }

    #[test]
    fn a_wild_frame_does_not_make_its_neighbours_repeats() {
        // Frames the gate refused, 0.02 rad off, at a turning point and mid-swing:
        // they pull their neighbours' cubics, but stay what the gate called them.
        let mut rows = swing_rows();
        for i in [15, 45, 100] {
            rows[i].angle_rad = Some(rows[i].angle_rad.unwrap() + 0.02);
            rows[i].flag = Some(Flag::Gate);
        }
        flag_repeats(&mut rows);
        assert_eq!(
            flagged(&rows),
            vec![(15, Flag::Gate), (45, Flag::Gate), (100, Flag::Gate)]
        );
    }

    #[test]
    fn orthogonal_fit_is_exact_for_a_vertical_line() {
        let pts: Vec<(Pt, f64)> = (0..50).map(|i| (Pt::new(10.0, i as f64), 1.0)).collect();
        let l = fit_line_weighted(&pts).unwrap();
        assert!(l.dir.x.abs() < 1e-12, "{l:?}");
        assert!((l.point.x - 10.0).abs() < 1e-12);
    }

    #[test]
    fn flagged_frames_are_filled_from_neighbours_or_left_missing() {
        let mut rows: Vec<AngleRow> = (0..20)
            .map(|i| {
                let t = i as f64 / 30.0;
                AngleRow {
                    frame: i,
                    t_s: t,
                    angle_rad: Some(1.0 + 0.5 * t * t),
                    status: Status::Ok,
                    quality: 1.0,
                    flag: None,
                    moments: None,
                }
            })
            .collect();
        rows[7].flag = Some(Flag::Gate);
        rows[7].angle_rad = Some(9.0);
        rows[0].flag = Some(Flag::Weak);
        fill_flagged(&mut rows);
        assert_eq!(rows[7].status, Status::Corrected);
        let t = rows[7].t_s;
        assert!((rows[7].angle_rad.unwrap() - (1.0 + 0.5 * t * t)).abs() < 1e-9);
        assert_eq!(rows[0].status, Status::Missing);
        assert_eq!(rows[0].angle_rad, None);
    }

    #[test]
    fn marks_give_the_angle_away_from_the_pivot() {
        let mut rows = vec![AngleRow {
            frame: 3,
            t_s: 0.1,
            angle_rad: None,
            status: Status::Missing,
            quality: 0.0,
            flag: Some(Flag::Weak),
            moments: None,
        }];
        let mut marks = BTreeMap::new();
        marks.insert(3, [[100.0, 300.0], [100.0, 100.0]]);
        apply_marks(&mut rows, &marks, Pt::new(100.0, 0.0));
        assert_eq!(rows[0].status, Status::Manual);
        assert!((rows[0].angle_rad.unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
