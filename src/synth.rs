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
//! * Spoiled frames: `synthetic.spoiled_frames` counts spoiling *events*, in turn a
//!   hand passing (1 to 3 consecutive frames, each tagged `hand`), a flash (one frame,
//!   near white) and a duplicated frame (the recorder repeats the previous frame), one
//!   per equal slot of the video, at least 2 s (a fifth of a short video) from its ends.
//! * Writing: MJPG in `.avi`, or H.264 (x264, `veryfast`) for other extensions, by the
//!   `ffmpeg` program: each frame is converted here to planar Y'CbCr 4:2:0 (BT.601, full
//!   range for JPEG, limited for H.264) on a second thread while the next frame
//!   renders, and piped to ffmpeg, which encodes in its own process. OpenCV's
//!   `VideoWriter` is the fallback (no ffmpeg, or an odd width or height).
//!
//! Every random choice comes from [`Rng`] streams derived from `synthetic.seed`, and
//! each frame's own randomness is seeded from its index, so a frame renders the same
//! whichever frames are rendered before it.

use crate::config::{Experiment, Style, Synthetic};
use crate::rng::Rng;
use crate::simulate;
use anyhow::{bail, ensure, Context, Result};
use opencv::core::{self, Mat, Point, Rect, Scalar, Size};
use opencv::prelude::*;
use opencv::{imgcodecs, imgproc, videoio};
use std::f64::consts::{FRAC_PI_2, PI};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

/// One frame's truth.
#[derive(Clone, Debug, PartialEq)]
pub struct TruthRow {
    /// Mid-exposure time of the frame, `i / fps`, s.
    pub t_s: f64,
    /// True image angle of the wire at `t_s`, from the image x axis (y down), rad. For a
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
    /// `MJPG (avi, ffmpeg)` or `H.264 (mp4, OpenCV)`.
    pub codec: String,
    pub frames: usize,
    pub width: u32,
    pub height: u32,
    pub fps: f64,
    /// The wire's pivot in the image, px (pixel centres at integer coordinates).
    pub pivot_px: [f64; 2],
    /// Pivot to the end of the wire (the ball's centre), px.
    pub wire_length_px: f64,
    /// Drawn width of the wire, px.
    pub wire_width_px: f64,
    /// Radius of the ball drawn at the wire's end, px.
    pub ball_radius_px: f64,
    /// Image angle of the wire at rest (`rest_angle_deg` plus the style's turn), rad.
    pub rest_angle_rad: f64,
    pub style: Style,
    /// Rendered without camera defects.
    pub clean: bool,
    /// One row per frame.
    pub truth: Vec<TruthRow>,
}

/// Render the experiment's `synthetic:` twin to `out`.
///
/// The extension decides the container: `.avi` is MJPG; anything else (`.mp4`) is
/// H.264, and if neither ffmpeg (with x264) nor this OpenCV can write H.264 the video
/// goes to the same name with `.avi` in MJPG instead (said on stderr; the returned path
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
    Ok(Plan::new(exp, duration_s)?.truth)
}

/// Render single frames (0-based indices) to PNG files `<name>_<style>_<frame>.png` in
/// `dir`, exactly as they appear in the video before compression. Returns the paths.
pub fn stills(
    exp: &Experiment,
    duration_s: Option<f64>,
    frames: &[usize],
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let plan = Plan::new(exp, duration_s)?;
    let mut twin = Twin::new(plan)?;
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create folder", dir.display()))?;
    let mut paths = Vec::new();
    for &i in frames {
        ensure!(
            i < twin.plan.truth.len(),
            "frame {i}: the video has {} frames",
            twin.plan.truth.len()
        );
        let src = match twin.plan.spoils[i] {
            Spoil::Duplicate => i - 1,
            _ => i,
        };
        twin.render_frame(src)?;
        let path = dir.join(format!(
            "{}_{}_{i:05}.png",
            exp.name,
            style_name(twin.plan.s.style)
        ));
        let ok = imgcodecs::imwrite(&path, &twin.frame, &core::Vector::new())
            .with_context(|| format!("{}: cannot write", path.display()))?;
        ensure!(ok, "{}: cannot write", path.display());
        paths.push(path);
    }
    Ok(paths)
}

// ---------------------------------------------------------------------------------------
// Plan: the motion, the geometry and the spoiled frames (no pixels).

/// Sub-times of the exposure averaged for motion blur.
const SUBSAMPLES: usize = 7;
/// Exposure as a fraction of the frame interval.
const EXPOSURE: f64 = 0.5;
/// Kept clear of spoiled frames at each end of the video, s.
const SPOIL_MARGIN_S: f64 = 2.0;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Spoil {
    None,
    /// Frame `k` of `n` of a hand passing.
    Hand {
        k: u8,
        n: u8,
        event: u16,
    },
    Flash,
    Duplicate,
}

impl Spoil {
    fn tag(self) -> &'static str {
        match self {
            Spoil::None => "none",
            Spoil::Hand { .. } => "hand",
            Spoil::Flash => "flash",
            Spoil::Duplicate => "duplicate",
        }
    }
}

fn style_name(s: Style) -> &'static str {
    match s {
        Style::DarkWire => "dark-wire",
        Style::LightWire => "light-wire",
        Style::Oblique => "oblique",
    }
}

/// Independent, decorrelated seeds for the render's random streams.
fn stream(seed: u64, k: u64) -> u64 {
    Rng::new(seed ^ k.wrapping_mul(0xD1B5_4A32_D192_ED03)).next_u64()
}

struct Plan {
    s: Synthetic,
    look: Look,
    geo: Geometry,
    fps: f64,
    trajectory: crate::physics::ode::Trajectory,
    truth: Vec<TruthRow>,
    spoils: Vec<Spoil>,
}

impl Plan {
    fn new(exp: &Experiment, duration_s: Option<f64>) -> Result<Self> {
        let s =
            exp.file.synthetic.clone().with_context(|| {
                format!("{}: no `synthetic:` block to render", exp.path.display())
            })?;
        if let Some(d) = duration_s {
            ensure!(
                d.is_finite() && d > 0.0,
                "duration {d} s: expected a positive number"
            );
        }
        let mut cam = simulate::camera_of(exp)?;
        cam.duration_s = duration_s.or(cam.duration_s);
        cam.noise_rad = 0.0;
        let rec = simulate::record(exp, &cam)?;
        let look = Look::of(s.style);
        let theta_rest = (s.rest_angle_deg + look.turn_deg).to_radians();
        let geo = Geometry::new(
            s.width as usize,
            s.height as usize,
            theta_rest,
            s.psi0_deg.to_radians(),
            exp.pendulum.r / exp.pendulum.d,
        );
        let n = rec.series.t.len();
        let spoils = if s.clean {
            vec![Spoil::None; n]
        } else {
            plan_spoils(
                s.spoiled_frames as usize,
                n,
                s.fps,
                &mut Rng::new(stream(s.seed, 2)),
            )
        };
        let truth = rec
            .series
            .t
            .iter()
            .zip(&spoils)
            .map(|(&t, sp)| TruthRow {
                t_s: t,
                angle_rad: theta_rest - rec.trajectory.state(t)[0],
                spoiled: sp.tag(),
            })
            .collect();
        Ok(Self {
            fps: s.fps,
            s,
            look,
            geo,
            trajectory: rec.trajectory,
            truth,
            spoils,
        })
    }

    /// Image angle of the wire at time `t`.
    fn theta(&self, t: f64) -> f64 {
        self.geo.theta_rest - self.trajectory.state(t)[0]
    }
}

/// `n` spoiling events (hand, flash, duplicate, in turn) at pseudo-random frames, one
/// per equal slot of the video between margins of 2 s (less for short videos), away
/// from the slot's edges so that events stay apart. A hand covers 1 to 3 frames.
fn plan_spoils(n: usize, frames: usize, fps: f64, rng: &mut Rng) -> Vec<Spoil> {
    let mut out = vec![Spoil::None; frames];
    if n == 0 {
        return out;
    }
    let margin = ((SPOIL_MARGIN_S * fps).round() as usize)
        .min(frames / 5)
        .max(1);
    let usable = frames.saturating_sub(2 * margin);
    let fit = n.min(usable / 5);
    if fit < n {
        eprintln!("synth: only {fit} of {n} spoiling events fit in a video of {frames} frames");
    }
    if fit == 0 {
        return out;
    }
    let slot = usable as f64 / fit as f64;
    for (k, kind) in (0..fit).map(|k| (k, k % 3)) {
        let len = if kind == 0 {
            1 + (rng.uniform() * 3.0) as usize
        } else {
            1
        };
        let lo = margin as f64 + (k as f64 + 0.25) * slot;
        let hi = margin as f64 + (k as f64 + 0.75) * slot - len as f64;
        let start = (lo + rng.uniform() * (hi - lo).max(0.0)).round() as usize;
        for j in 0..len {
            out[start + j] = match kind {
                0 => Spoil::Hand {
                    k: j as u8,
                    n: len as u8,
                    event: k as u16,
                },
                1 => Spoil::Flash,
                _ => Spoil::Duplicate,
            };
        }
    }
    out
}

/// Where things are in the image, px.
#[derive(Clone, Debug)]
struct Geometry {
    w: usize,
    h: usize,
    pivot: [f64; 2],
    /// Pivot to the wire's end (the ball's centre).
    d_px: f64,
    ball_r: f64,
    /// Protractor radius.
    rp: f64,
    screw_r: f64,
    wire_w: f64,
    theta_rest: f64,
}

impl Geometry {
    /// Wire length 60 % of the frame height when the swing (plus 3 degrees) with the
    /// ball fits, shorter otherwise; the swing's bounding box is centred in the frame.
    fn new(w: usize, h: usize, theta_rest: f64, psi0: f64, ball_ratio: f64) -> Self {
        let amp = psi0 + 3f64.to_radians();
        let reach = ball_ratio * 1.3;
        let (mut x0, mut x1, mut y0, mut y1) = (-0.1f64, 0.1f64, -0.1f64, 0.1f64);
        for j in 0..=64 {
            let th = theta_rest - amp + 2.0 * amp * j as f64 / 64.0;
            let (cx, cy) = (th.cos(), th.sin());
            x0 = x0.min(cx - reach);
            x1 = x1.max(cx + reach);
            y0 = y0.min(cy - reach);
            y1 = y1.max(cy + reach);
        }
        let (wf, hf) = (w as f64, h as f64);
        let d_px = (0.6 * hf)
            .min(0.94 * wf / (x1 - x0))
            .min(0.94 * hf / (y1 - y0));
        let pivot = [
            wf / 2.0 - d_px * (x0 + x1) / 2.0,
            hf / 2.0 - d_px * (y0 + y1) / 2.0,
        ];
        Self {
            w,
            h,
            pivot,
            d_px,
            ball_r: ball_ratio * d_px,
            rp: 0.45 * d_px,
            screw_r: (0.028 * d_px).max(2.5),
            wire_w: (hf / 288.0).clamp(2.0, 3.0),
            theta_rest,
        }
    }
}

// ---------------------------------------------------------------------------------------
// Looks.

/// Colours are BGR, 0..255, before illumination.
#[derive(Clone, Debug)]
struct Look {
    plate: [f32; 3],
    /// Relative amplitude of the plate's smooth shading.
    shading: f32,
    /// Fine grain, grey levels.
    grain: f32,
    brushed: bool,
    body: [f32; 3],
    body_alpha: f64,
    marks: [f32; 3],
    block: [f32; 3],
    screw: [f32; 3],
    wire: [f32; 3],
    ball: [f32; 3],
    /// Illumination: level, gradient across x and y, vignetting.
    light: [f32; 4],
    /// The whole scene is turned by this much in the image, degrees.
    turn_deg: f64,
    noise_sigma: f64,
}

impl Look {
    fn of(style: Style) -> Self {
        match style {
            Style::DarkWire => Self {
                plate: [186.0, 190.0, 194.0],
                shading: 0.06,
                grain: 5.0,
                brushed: true,
                body: [236.0, 238.0, 236.0],
                body_alpha: 0.7,
                marks: [28.0, 28.0, 30.0],
                block: [92.0, 128.0, 160.0],
                screw: [55.0, 56.0, 60.0],
                wire: [34.0, 34.0, 38.0],
                ball: [150.0, 152.0, 156.0],
                light: [1.0, 0.07, 0.05, 0.14],
                turn_deg: 0.0,
                noise_sigma: 2.5,
            },
            Style::LightWire => Self {
                plate: [40.0, 37.0, 35.0],
                shading: 0.12,
                grain: 4.0,
                brushed: false,
                body: [70.0, 70.0, 68.0],
                body_alpha: 0.35,
                marks: [222.0, 224.0, 220.0],
                block: [72.0, 74.0, 78.0],
                screw: [165.0, 166.0, 170.0],
                wire: [228.0, 230.0, 232.0],
                ball: [175.0, 176.0, 180.0],
                light: [1.0, -0.06, 0.06, 0.2],
                turn_deg: 0.0,
                noise_sigma: 3.0,
            },
            Style::Oblique => Self {
                plate: [92.0, 102.0, 106.0],
                shading: 0.1,
                grain: 3.0,
                brushed: false,
                body: [132.0, 136.0, 138.0],
                body_alpha: 0.5,
                marks: [68.0, 70.0, 74.0],
                block: [78.0, 90.0, 100.0],
                screw: [45.0, 46.0, 50.0],
                wire: [50.0, 50.0, 54.0],
                ball: [120.0, 122.0, 126.0],
                light: [0.85, 0.5, 0.3, 0.3],
                turn_deg: 38.0,
                noise_sigma: 3.5,
            },
        }
    }
}

/// Illumination factor at pixel `(x, y)`.
fn illumination(light: [f32; 4], x: f32, y: f32, w: f32, h: f32) -> f32 {
    let (u, v) = (x / w - 0.5, y / h - 0.5);
    let r2 = (u * u + v * v) * 2.0;
    light[0] * (1.0 + light[1] * u + light[2] * v) * (1.0 - light[3] * r2)
}

// ---------------------------------------------------------------------------------------
// Static background.

fn pt(x: f64, y: f64) -> Point {
    // 4 fractional bits (drawing calls use shift = 4).
    Point::new((x * 16.0).round() as i32, (y * 16.0).round() as i32)
}

fn bgr(c: [f32; 3]) -> Scalar {
    Scalar::new(c[0] as f64, c[1] as f64, c[2] as f64, 0.0)
}

fn scale(c: [f32; 3], k: f32) -> [f32; 3] {
    [c[0] * k, c[1] * k, c[2] * k]
}

/// Round to the nearest grey level, saturating (`as` saturates; no `roundf` call).
#[inline]
fn to_u8(v: f32) -> u8 {
    (v + 0.5) as u8
}

fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}

/// Smooth random field with about `cells` features across the larger side, ~N(0, 1).
fn smooth_field(w: i32, h: i32, cells: i32, rng: &mut Rng) -> Result<Vec<f32>> {
    let (gw, gh) = if w >= h {
        (cells + 3, (cells * h / w).max(1) + 3)
    } else {
        ((cells * w / h).max(1) + 3, cells + 3)
    };
    let mut small = Mat::new_rows_cols_with_default(gh, gw, core::CV_32FC1, Scalar::all(0.0))?;
    for v in small.data_typed_mut::<f32>()? {
        *v = rng.normal() as f32;
    }
    let mut big = Mat::default();
    imgproc::resize(
        &small,
        &mut big,
        Size::new(w, h),
        0.0,
        0.0,
        imgproc::INTER_CUBIC,
    )?;
    Ok(big.data_typed::<f32>()?.to_vec())
}

/// The plate, seen from above: smooth shading, grain (brushed or not), scratches, dust.
fn plate_texture(w: i32, h: i32, look: &Look, rng: &mut Rng) -> Result<Mat> {
    let lf1 = smooth_field(w, h, 4, rng)?;
    let lf2 = smooth_field(w, h, 14, rng)?;
    let n = (w * h) as usize;
    let mut grain = Mat::new_rows_cols_with_default(h, w, core::CV_32FC1, Scalar::all(0.0))?;
    for g in grain.data_typed_mut::<f32>()? {
        *g = (rng.uniform() + rng.uniform() - 1.0) as f32 * 1.7;
    }
    if look.brushed {
        let mut b = Mat::default();
        imgproc::blur(
            &grain,
            &mut b,
            Size::new(25, 1),
            Point::new(-1, -1),
            core::BORDER_REFLECT,
        )?;
        let mut g2 = Mat::default();
        b.convert_to(&mut g2, core::CV_32F, 5.0 * 0.75, 0.0)?;
        // keep some isotropic grain too
        for (a, b) in g2
            .data_typed_mut::<f32>()?
            .iter_mut()
            .zip(grain.data_typed::<f32>()?)
        {
            *a += 0.35 * b;
        }
        grain = g2;
    }
    let grain = grain.data_typed::<f32>()?;
    let mut img = Mat::new_rows_cols_with_default(h, w, core::CV_8UC3, Scalar::all(0.0))?;
    {
        let buf = img.data_bytes_mut()?;
        for i in 0..n {
            let shade = 1.0 + look.shading * (lf1[i] + 0.4 * lf2[i]);
            let g = look.grain * grain[i];
            for c in 0..3 {
                buf[3 * i + c] = to_u8(look.plate[c] * shade + g);
            }
        }
    }
    // Faint scratches and dust: static, so a detector of the moving wire ignores them.
    let diag = ((w * w + h * h) as f64).sqrt();
    for _ in 0..14 {
        let (x, y) = (rng.uniform() * w as f64, rng.uniform() * h as f64);
        let a = rng.uniform() * PI;
        let l = diag * (0.01 + 0.04 * rng.uniform());
        let k = if rng.uniform() < 0.5 { 0.93 } else { 1.06 };
        let c = scale(look.plate, k);
        imgproc::line(
            &mut img,
            pt(x, y),
            pt(x + l * a.cos(), y + l * a.sin()),
            bgr(c),
            1,
            imgproc::LINE_AA,
            4,
        )?;
    }
    for _ in 0..40 {
        let (x, y) = (rng.uniform() * w as f64, rng.uniform() * h as f64);
        let r = 0.6 + 1.4 * rng.uniform();
        let k = if rng.uniform() < 0.7 { 0.8 } else { 1.15 };
        imgproc::circle(
            &mut img,
            pt(x, y),
            (r * 16.0) as i32,
            bgr(scale(look.plate, k)),
            -1,
            imgproc::LINE_AA,
            4,
        )?;
    }
    Ok(img)
}

/// Protractor, its block and the fulcrum screw, on the plate canvas. The canvas is the
/// plate's frame: the wire at rest points along +y from the pivot `c`.
fn draw_instruments(canvas: &mut Mat, c: [f64; 2], g: &Geometry, look: &Look) -> Result<()> {
    let rp = g.rp;
    let (cx, cy) = (c[0], c[1]);
    let size = canvas.size()?;
    let block = |dx: f64, dy: f64| {
        Rect::new(
            (cx - 1.08 * rp + dx).round() as i32,
            (cy - 0.34 * rp + dy).round() as i32,
            (2.16 * rp).round() as i32,
            (0.30 * rp).round() as i32,
        )
    };
    // Soft shadows of the block and of the protractor's edge (light from the upper left).
    let mut shadow = Mat::new_size_with_default(size, core::CV_8UC1, Scalar::all(0.0))?;
    imgproc::rectangle(
        &mut shadow,
        block(0.03 * rp, 0.045 * rp),
        Scalar::all(255.0),
        -1,
        imgproc::LINE_8,
        0,
    )?;
    let (ox, oy) = (0.012 * rp, 0.018 * rp);
    imgproc::ellipse(
        &mut shadow,
        pt(cx + ox, cy + oy),
        Size::new((rp * 16.0) as i32, (rp * 16.0) as i32),
        0.0,
        0.0,
        180.0,
        Scalar::all(150.0),
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    let mut soft = Mat::default();
    let sig = (0.03 * rp).max(1.0);
    imgproc::gaussian_blur(
        &shadow,
        &mut soft,
        Size::new(0, 0),
        sig,
        sig,
        core::BORDER_REFLECT,
    )?;
    {
        let m = soft.data_bytes()?.to_vec();
        let buf = canvas.data_bytes_mut()?;
        for (i, &s) in m.iter().enumerate() {
            if s > 0 {
                let k = 1.0 - 0.4 * s as f32 / 255.0;
                for ch in 0..3 {
                    buf[3 * i + ch] = (buf[3 * i + ch] as f32 * k) as u8;
                }
            }
        }
    }
    // Protractor body: translucent plastic, a half disc plus the strip above its base.
    let mut over = canvas.clone();
    let axes = Size::new((rp * 16.0) as i32, (rp * 16.0) as i32);
    imgproc::ellipse(
        &mut over,
        pt(cx, cy),
        axes,
        0.0,
        0.0,
        180.0,
        bgr(look.body),
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    imgproc::rectangle(
        &mut over,
        Rect::new(
            (cx - rp).round() as i32,
            (cy - 0.07 * rp).round() as i32,
            (2.0 * rp).round() as i32,
            (0.07 * rp).round() as i32 + 1,
        ),
        bgr(look.body),
        -1,
        imgproc::LINE_AA,
        0,
    )?;
    let mut blended = Mat::default();
    core::add_weighted(
        &*canvas,
        1.0 - look.body_alpha,
        &over,
        look.body_alpha,
        0.0,
        &mut blended,
        -1,
    )?;
    *canvas = blended;
    let marks = bgr(look.marks);
    let rim = bgr(mix(look.body, look.marks, 0.5));
    imgproc::ellipse(
        canvas,
        pt(cx, cy),
        axes,
        0.0,
        0.0,
        180.0,
        rim,
        1,
        imgproc::LINE_AA,
        4,
    )?;
    // Base line and the centre mark.
    imgproc::line(
        canvas,
        pt(cx - rp, cy),
        pt(cx + rp, cy),
        marks,
        1,
        imgproc::LINE_AA,
        4,
    )?;
    let r0 = rp * 0.975;
    for k in 0..=180 {
        let a = (k as f64).to_radians();
        let len = rp
            * if k % 10 == 0 {
                0.12
            } else if k % 5 == 0 {
                0.08
            } else {
                0.045
            };
        let (u, v) = (a.cos(), a.sin());
        imgproc::line(
            canvas,
            pt(cx + r0 * u, cy + r0 * v),
            pt(cx + (r0 - len) * u, cy + (r0 - len) * v),
            marks,
            1,
            imgproc::LINE_AA,
            4,
        )?;
    }
    // Inner scale's ticks and arc.
    let ri = rp * 0.74;
    imgproc::ellipse(
        canvas,
        pt(cx, cy),
        Size::new((ri * 16.0) as i32, (ri * 16.0) as i32),
        0.0,
        0.0,
        180.0,
        marks,
        1,
        imgproc::LINE_AA,
        4,
    )?;
    // Numerals, outer scale 0..180 and inner scale 180..0, every 10 degrees.
    let font = imgproc::FONT_HERSHEY_SIMPLEX;
    let mut base = 0;
    let unit = imgproc::get_text_size("0", font, 1.0, 1, &mut base)?.height as f64;
    for (radius, height, inner) in [(rp * 0.80, 0.05 * rp, false), (rp * 0.66, 0.038 * rp, true)] {
        let fs = height / unit;
        let th = if fs > 0.9 { 2 } else { 1 };
        for k in (0..=180).step_by(10) {
            let label = if inner { 180 - k } else { k }.to_string();
            let sz = imgproc::get_text_size(&label, font, fs, th, &mut base)?;
            let a = (k as f64).to_radians();
            let (x, y) = (cx + radius * a.cos(), cy + radius * a.sin());
            imgproc::put_text(
                canvas,
                &label,
                Point::new(
                    (x - sz.width as f64 / 2.0).round() as i32,
                    (y + sz.height as f64 / 2.0).round() as i32,
                ),
                font,
                fs,
                marks,
                th,
                imgproc::LINE_AA,
                false,
            )?;
        }
    }
    // The block, with lit and shaded edges and two screws.
    let b = block(0.0, 0.0);
    imgproc::rectangle(canvas, b, bgr(look.block), -1, imgproc::LINE_8, 0)?;
    let e = ((0.015 * rp).round() as i32).max(1);
    let hi = bgr(scale(look.block, 1.3));
    let lo = bgr(scale(look.block, 0.6));
    let (x0, y0, x1, y1) = (b.x, b.y, b.x + b.width - 1, b.y + b.height - 1);
    imgproc::rectangle(
        canvas,
        Rect::new(x0, y0, b.width, e),
        hi,
        -1,
        imgproc::LINE_8,
        0,
    )?;
    imgproc::rectangle(
        canvas,
        Rect::new(x0, y0, e, b.height),
        hi,
        -1,
        imgproc::LINE_8,
        0,
    )?;
    imgproc::rectangle(
        canvas,
        Rect::new(x0, y1 - e + 1, b.width, e),
        lo,
        -1,
        imgproc::LINE_8,
        0,
    )?;
    imgproc::rectangle(
        canvas,
        Rect::new(x1 - e + 1, y0, e, b.height),
        lo,
        -1,
        imgproc::LINE_8,
        0,
    )?;
    for sx in [-0.85, 0.85] {
        screw(canvas, cx + sx * rp, cy - 0.19 * rp, 0.04 * rp, look.screw)?;
    }
    // The fulcrum.
    screw(canvas, cx, cy, g.screw_r, look.screw)?;
    Ok(())
}

/// A screw head: a disc with a lit rim and a slot.
fn screw(canvas: &mut Mat, x: f64, y: f64, r: f64, col: [f32; 3]) -> Result<()> {
    let rr = |r: f64| (r * 16.0).round() as i32;
    imgproc::circle(canvas, pt(x, y), rr(r), bgr(col), -1, imgproc::LINE_AA, 4)?;
    imgproc::circle(
        canvas,
        pt(x - 0.15 * r, y - 0.15 * r),
        rr(0.6 * r),
        bgr(scale(col, 1.5)),
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    imgproc::circle(
        canvas,
        pt(x, y),
        rr(0.55 * r),
        bgr(scale(col, 1.2)),
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    let t = ((0.2 * r).round() as i32).max(1);
    imgproc::line(
        canvas,
        pt(x - 0.5 * r, y + 0.25 * r),
        pt(x + 0.5 * r, y - 0.25 * r),
        bgr(scale(col, 0.5)),
        t,
        imgproc::LINE_AA,
        4,
    )?;
    Ok(())
}

/// The static scene as the camera sees it: BGR bytes (lit, defocused) and the
/// illumination factor of every pixel.
fn build_background(plan: &Plan, defocus: Option<f64>) -> Result<(Vec<u8>, Vec<f32>)> {
    let g = &plan.geo;
    let look = &plan.look;
    let mut rng = Rng::new(stream(plan.s.seed, 1));
    let (w, h) = (g.w as i32, g.h as i32);
    let rot = g.theta_rest - FRAC_PI_2;
    let (c, s) = (rot.cos(), rot.sin());
    // The frame's corners in the plate's frame (pivot at the origin).
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for (x, y) in [
        (0.0, 0.0),
        (w as f64, 0.0),
        (0.0, h as f64),
        (w as f64, h as f64),
    ] {
        let (dx, dy) = (x - g.pivot[0], y - g.pivot[1]);
        let (u, v) = (c * dx + s * dy, -s * dx + c * dy);
        lo = [lo[0].min(u), lo[1].min(v)];
        hi = [hi[0].max(u), hi[1].max(v)];
    }
    let cw = (hi[0] - lo[0]).ceil() as i32 + 8;
    let ch = (hi[1] - lo[1]).ceil() as i32 + 8;
    let cp = [-lo[0] + 4.0, -lo[1] + 4.0];
    let mut canvas = plate_texture(cw, ch, look, &mut rng)?;
    draw_instruments(&mut canvas, cp, g, look)?;
    let m = Mat::from_slice_2d(&[
        [c, -s, g.pivot[0] - (c * cp[0] - s * cp[1])],
        [s, c, g.pivot[1] - (s * cp[0] + c * cp[1])],
    ])?;
    let mut img = Mat::default();
    imgproc::warp_affine(
        &canvas,
        &mut img,
        &m,
        Size::new(w, h),
        imgproc::INTER_LINEAR,
        core::BORDER_REFLECT,
        Scalar::all(0.0),
    )?;
    let (wf, hf) = (w as f32, h as f32);
    let mut illum = Vec::with_capacity(g.w * g.h);
    for y in 0..g.h {
        for x in 0..g.w {
            illum.push(illumination(look.light, x as f32, y as f32, wf, hf));
        }
    }
    {
        let buf = img.data_bytes_mut()?;
        for (px, &k) in buf.chunks_exact_mut(3).zip(&illum) {
            for v in px {
                *v = to_u8(*v as f32 * k);
            }
        }
    }
    if let Some(sig) = defocus {
        let mut b = Mat::default();
        imgproc::gaussian_blur(
            &img,
            &mut b,
            Size::new(0, 0),
            sig,
            sig,
            core::BORDER_REFLECT,
        )?;
        img = b;
    }
    Ok((img.data_bytes()?.to_vec(), illum))
}

// ---------------------------------------------------------------------------------------
// Moving parts.

/// `erf` (Abramowitz & Stegun 7.1.26, |error| < 1.5e-7).
fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let y = 1.0
        - t * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))))
            * (-x * x).exp();
    y.copysign(x)
}

/// A function tabulated on `[lo, lo + (n-1)/inv]`, clamped at both ends.
struct Table {
    lo: f32,
    inv: f32,
    v: Vec<f32>,
}

impl Table {
    fn new(lo: f64, hi: f64, steps_per_unit: f64, f: impl Fn(f64) -> f64) -> Self {
        let n = ((hi - lo) * steps_per_unit).ceil() as usize + 2;
        Self {
            lo: lo as f32,
            inv: steps_per_unit as f32,
            v: (0..n)
                .map(|i| f(lo + i as f64 / steps_per_unit) as f32)
                .collect(),
        }
    }

    #[inline]
    fn at(&self, x: f32) -> f32 {
        let i = ((x - self.lo) * self.inv).max(0.0) as usize;
        self.v[i.min(self.v.len() - 1)]
    }
}

/// The ball's shadow on the plate, in units of the ball's radius: centre offset x and y,
/// radius, softness, depth.
const SHADOW: [f32; 5] = [0.08, 0.12, 1.0, 0.12, 0.38];

/// Cells per side of the ball's shading table.
const BALL_TAB: usize = 160;

/// A steel ball seen from above: darker towards the rim, a sharp highlight and a broad
/// sheen towards the light (upper left).
fn ball_table(base: [f32; 3]) -> Vec<[f32; 3]> {
    let mut t = Vec::with_capacity(BALL_TAB * BALL_TAB);
    for iy in 0..BALL_TAB {
        for ix in 0..BALL_TAB {
            let q = |i: usize| (i as f64 + 0.5) / (BALL_TAB / 2) as f64 - 1.0;
            let (qx, qy) = (q(ix), q(iy));
            let z = (1.0 - qx * qx - qy * qy).max(0.0).sqrt();
            let tone = 0.32 + 0.68 * z;
            let h2 = (qx + 0.32).powi(2) + (qy + 0.38).powi(2);
            let spec = 230.0 * (-h2 * 28.0).exp() + 40.0 * (-h2 * 3.0).exp();
            t.push(base.map(|c| (c as f64 * tone + spec) as f32));
        }
    }
    t
}

/// Draws the wire and the ball into a frame that holds the background.
struct Mover {
    w: usize,
    h: usize,
    pivot: [f64; 2],
    d_px: f64,
    ball_r: f64,
    screw_r: f64,
    wire: [f32; 3],
    /// The ball's shaded colour on a `BALL_TAB` square grid over `[-1, 1]^2` (units of
    /// its radius), before illumination.
    ball_tab: Vec<[f32; 3]>,
    /// Wire coverage against distance from its axis, px.
    profile: Table,
    /// Distance beyond which the wire covers nothing, px.
    reach: f64,
    /// Standard normal CDF on [-5, 5].
    cdf: Table,
    /// Edge blur of the ball, px.
    sigma: f64,
    acc: Vec<f32>,
}

impl Mover {
    fn new(g: &Geometry, look: &Look, sigma: f64) -> Self {
        let hw = g.wire_w / 2.0;
        let s2 = sigma * std::f64::consts::SQRT_2;
        let reach = hw + 4.0 * sigma + 0.5;
        Self {
            w: g.w,
            h: g.h,
            pivot: g.pivot,
            d_px: g.d_px,
            ball_r: g.ball_r,
            screw_r: g.screw_r,
            wire: look.wire,
            ball_tab: ball_table(look.ball),
            profile: Table::new(0.0, reach, 64.0, |d| {
                0.5 * (erf((hw - d) / s2) + erf((hw + d) / s2))
            }),
            reach,
            cdf: Table::new(-5.0, 5.0, 64.0, |z| {
                0.5 * (1.0 + erf(z / std::f64::consts::SQRT_2))
            }),
            sigma,
            acc: Vec::new(),
        }
    }

    /// Composite the ball (at `theta_mid`) and the wire (averaged over `thetas`) over the
    /// background already in `frame`, lit by `illum`.
    fn draw(&mut self, frame: &mut [u8], bg: &[u8], illum: &[f32], thetas: &[f64], theta_mid: f64) {
        let [px, py] = self.pivot;
        let end = |th: f64| [px + self.d_px * th.cos(), py + self.d_px * th.sin()];
        let c = end(theta_mid);
        let r = self.ball_r;
        let ball_reach = 1.6 * r + 4.0 * self.sigma + 2.0;
        let (mut x0, mut x1) = (c[0] - ball_reach, c[0] + ball_reach);
        let (mut y0, mut y1) = (c[1] - ball_reach, c[1] + ball_reach);
        for &th in thetas {
            let e = end(th);
            x0 = x0.min(px.min(e[0]) - self.reach);
            x1 = x1.max(px.max(e[0]) + self.reach);
            y0 = y0.min(py.min(e[1]) - self.reach);
            y1 = y1.max(py.max(e[1]) + self.reach);
        }
        let clip = |v: f64, n: usize| (v.max(0.0) as usize).min(n);
        let (rx0, rx1) = (clip(x0.floor(), self.w), clip(x1.ceil() + 1.0, self.w));
        let (ry0, ry1) = (clip(y0.floor(), self.h), clip(y1.ceil() + 1.0, self.h));
        if rx0 >= rx1 || ry0 >= ry1 {
            return;
        }
        let rw = rx1 - rx0;
        let n = rw * (ry1 - ry0);
        if self.acc.len() < n {
            self.acc.resize(n, 0.0);
        }
        let acc = &mut self.acc[..n];
        acc.fill(0.0);
        let weight = 1.0 / thetas.len() as f32;
        for &th in thetas {
            let e = end(th);
            raster_segment(
                acc,
                [rx0, rx1, ry0, ry1],
                self.pivot,
                e,
                self.reach,
                &self.profile,
                weight,
            );
        }
        // The ball and its shadow (light from the upper left of the image), in units of
        // the ball's radius around its centre.
        let bx = [(c[0] - ball_reach) as f32, (c[0] + ball_reach) as f32];
        let by = [(c[1] - ball_reach) as f32, (c[1] + ball_reach) as f32];
        let inv_r = 1.0 / r as f32;
        let edge = 4.0 * self.sigma as f32 * inv_r;
        let (in2, out2) = ((1.0 - edge).max(0.0).powi(2), (1.0 + edge).powi(2));
        let k_edge = r as f32 / (self.sigma as f32).max(0.3);
        let s_out2 = (SHADOW[2] + 3.5 * SHADOW[3]).powi(2);
        let screw2 = (self.screw_r as f32 + 0.5).powi(2);
        let (cx, cy) = (c[0] as f32, c[1] as f32);
        let (pxf, pyf) = (px as f32, py as f32);
        let cell =
            |q: f32| (((q + 1.0) * (BALL_TAB / 2) as f32).max(0.0) as usize).min(BALL_TAB - 1);
        for y in ry0..ry1 {
            let yf = y as f32;
            let row = &acc[(y - ry0) * rw..(y - ry0 + 1) * rw];
            let ball_row = yf >= by[0] && yf <= by[1];
            let qy = (yf - cy) * inv_r;
            for (x, &cov) in (rx0..rx1).zip(row) {
                let xf = x as f32;
                let (mut cb, mut shadow, mut qx) = (0.0f32, 0.0f32, 0.0f32);
                if ball_row && xf >= bx[0] && xf <= bx[1] {
                    qx = (xf - cx) * inv_r;
                    let rho2 = qx * qx + qy * qy;
                    cb = if rho2 <= in2 {
                        1.0
                    } else if rho2 >= out2 {
                        0.0
                    } else {
                        self.cdf.at((1.0 - rho2.sqrt()) * k_edge)
                    };
                    if cb < 0.999 {
                        let (sx, sy) = (qx - SHADOW[0], qy - SHADOW[1]);
                        let s2 = sx * sx + sy * sy;
                        if s2 < s_out2 {
                            shadow = self.cdf.at((SHADOW[2] - s2.sqrt()) / SHADOW[3]);
                        }
                    }
                }
                if cov <= 1e-4 && cb <= 1e-4 && shadow <= 1e-4 {
                    continue;
                }
                let j = y * self.w + x;
                let il = illum[j];
                let k = 3 * j;
                let mut p = [bg[k] as f32, bg[k + 1] as f32, bg[k + 2] as f32];
                if shadow > 1e-4 {
                    p = scale(p, 1.0 - SHADOW[4] * shadow);
                }
                if cb > 1e-4 {
                    let col = self.ball_tab[cell(qy) * BALL_TAB + cell(qx)];
                    p = mix(p, scale(col, il), cb);
                }
                if cov > 1e-4 {
                    let (dx, dy) = (xf - pxf, yf - pyf);
                    let d2 = dx * dx + dy * dy;
                    let under_screw = if d2 >= screw2 {
                        1.0
                    } else {
                        (d2.sqrt() - self.screw_r as f32 + 0.5).clamp(0.0, 1.0)
                    };
                    p = mix(p, scale(self.wire, il), cov.min(1.0) * under_screw);
                }
                frame[k] = to_u8(p[0]);
                frame[k + 1] = to_u8(p[1]);
                frame[k + 2] = to_u8(p[2]);
            }
        }
    }
}

/// Add `weight * profile(distance to the segment a-b)` to `acc`, which covers
/// `[x0, x1) x [y0, y1)` of the image; only pixels within `reach` of the segment.
fn raster_segment(
    acc: &mut [f32],
    [x0, x1, y0, y1]: [usize; 4],
    a: [f64; 2],
    b: [f64; 2],
    reach: f64,
    profile: &Table,
    weight: f32,
) {
    let (vx, vy) = (b[0] - a[0], b[1] - a[1]);
    let len = (vx * vx + vy * vy).sqrt().max(1e-9);
    let (ux, uy) = (vx / len, vy / len);
    let rw = x1 - x0;
    let ya = (a[1].min(b[1]) - reach).floor().max(y0 as f64) as usize;
    let yb = ((a[1].max(b[1]) + reach).ceil() as usize + 1).min(y1);
    let (sx0, sx1) = (a[0].min(b[0]) - reach, a[0].max(b[0]) + reach);
    let steep = uy.abs() > 0.2;
    let reach2 = (reach * reach) as f32;
    let (ax, ay, ux32, uy32, len32) = (a[0] as f32, a[1] as f32, ux as f32, uy as f32, len as f32);
    for y in ya..yb {
        let yf = y as f64;
        let (mut xa, mut xb) = (sx0, sx1);
        if steep {
            let xc = a[0] + (yf - a[1]) * ux / uy;
            let half = reach / uy.abs() + 1.0;
            xa = xa.max(xc - half);
            xb = xb.min(xc + half);
        }
        let xa = (xa.floor().max(x0 as f64)) as usize;
        let xb = ((xb.ceil() + 1.0).max(0.0) as usize).min(x1);
        let row = &mut acc[(y - y0) * rw..(y - y0 + 1) * rw];
        let dy = y as f32 - ay;
        for x in xa..xb {
            let dx = x as f32 - ax;
            let t = (dx * ux32 + dy * uy32).clamp(0.0, len32);
            let (ex, ey) = (dx - t * ux32, dy - t * uy32);
            let d2 = ex * ex + ey * ey;
            if d2 < reach2 {
                row[x - x0] += weight * profile.at(d2.sqrt());
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Spoilers: a hand passing.

/// Masks reused between hand frames.
#[derive(Default)]
struct HandPainter {
    mask: Mat,
    shadow: Mat,
    shade: Mat,
    tmp: Mat,
}

/// A hand seen from above, fingers along local -y, arm along local +y; `u` is about a
/// finger's width.
fn draw_hand(m: &mut Mat, c: [f64; 2], u: f64, tilt: f64) -> Result<()> {
    let (ca, sa) = (tilt.cos(), tilt.sin());
    let at = |x: f64, y: f64| {
        pt(
            c[0] + ca * x * u - sa * y * u,
            c[1] + sa * x * u + ca * y * u,
        )
    };
    let white = Scalar::all(255.0);
    let th = |k: f64| ((k * u).round() as i32).max(1);
    imgproc::ellipse(
        m,
        at(0.0, 0.0),
        Size::new((1.55 * u * 16.0) as i32, (1.8 * u * 16.0) as i32),
        tilt.to_degrees(),
        0.0,
        360.0,
        white,
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    for (bx, len, spread) in [
        (-1.0, 1.9, -0.3),
        (-0.34, 2.35, -0.1),
        (0.34, 2.25, 0.1),
        (1.0, 1.75, 0.3),
    ] {
        imgproc::line(
            m,
            at(bx, -1.2),
            at(bx + spread, -1.2 - len),
            white,
            th(0.64),
            imgproc::LINE_AA,
            4,
        )?;
    }
    imgproc::line(
        m,
        at(1.2, 0.4),
        at(2.5, -0.7),
        white,
        th(0.75),
        imgproc::LINE_AA,
        4,
    )?;
    imgproc::line(
        m,
        at(0.0, 1.2),
        at(0.4, 9.0),
        white,
        th(2.4),
        imgproc::LINE_AA,
        4,
    )?;
    Ok(())
}

impl HandPainter {
    /// Paint a hand centred at `c` over `frame`, blurred along x by `smear` px.
    fn paint(
        &mut self,
        frame: &mut Mat,
        illum: &[f32],
        c: [f64; 2],
        u: f64,
        tilt: f64,
        smear: f64,
    ) -> Result<()> {
        let size = frame.size()?;
        let zero = || Mat::new_size_with_default(size, core::CV_8UC1, Scalar::all(0.0));
        let mut mask = zero()?;
        draw_hand(&mut mask, c, u, tilt)?;
        let mut shadow = zero()?;
        draw_hand(&mut shadow, [c[0] + 0.9 * u, c[1] + 1.3 * u], u, tilt)?;
        let k = ((smear.round() as i32) | 1).max(1);
        let line = Size::new(k, 1);
        let anchor = Point::new(-1, -1);
        // Shadow: soft, smeared.
        imgproc::gaussian_blur(
            &shadow,
            &mut self.tmp,
            Size::new(0, 0),
            0.8 * u,
            0.8 * u,
            core::BORDER_REFLECT,
        )?;
        imgproc::blur(
            &self.tmp,
            &mut self.shadow,
            line,
            anchor,
            core::BORDER_REFLECT,
        )?;
        // Shading: thick parts brighter than edges.
        imgproc::gaussian_blur(
            &mask,
            &mut self.tmp,
            Size::new(0, 0),
            0.6 * u,
            0.6 * u,
            core::BORDER_REFLECT,
        )?;
        imgproc::blur(
            &self.tmp,
            &mut self.shade,
            line,
            anchor,
            core::BORDER_REFLECT,
        )?;
        // Coverage: out of focus (nearer the camera) and smeared.
        let s = 0.06 * u + 1.0;
        imgproc::gaussian_blur(
            &mask,
            &mut self.tmp,
            Size::new(0, 0),
            s,
            s,
            core::BORDER_REFLECT,
        )?;
        imgproc::blur(
            &self.tmp,
            &mut self.mask,
            line,
            anchor,
            core::BORDER_REFLECT,
        )?;
        let skin = [112.0f32, 146.0, 198.0];
        let (a, sh, sd) = (
            self.mask.data_bytes()?,
            self.shadow.data_bytes()?,
            self.shade.data_bytes()?,
        );
        let buf = frame.data_bytes_mut()?;
        for i in 0..a.len() {
            if a[i] == 0 && sh[i] == 0 {
                continue;
            }
            let (al, s, t) = (
                a[i] as f32 / 255.0,
                sh[i] as f32 / 255.0,
                sd[i] as f32 / 255.0,
            );
            let il = illum[i].max(0.5) * 1.1;
            for ch in 0..3 {
                let base = buf[3 * i + ch] as f32 * (1.0 - 0.45 * s);
                let col = skin[ch] * (0.55 + 0.55 * t) * il;
                buf[3 * i + ch] = to_u8(base + (col - base) * al);
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------
// Sensor: noise, drift, flicker.

struct Sensor {
    /// Gaussian noise, grey levels, one frame's worth plus `pad`, read at a random offset.
    noise: Vec<i8>,
    pad: usize,
    /// Slow drift: (amplitude, period s, phase).
    drift: [(f64, f64, f64); 3],
    flicker_phase: f64,
    seed: u64,
}

impl Sensor {
    fn new(len: usize, sigma: f64, seed: u64) -> Self {
        let mut rng = Rng::new(stream(seed, 3));
        let pad = 8192;
        let noise = (0..len + pad)
            .map(|_| (sigma * rng.normal()).round().clamp(-127.0, 127.0) as i8)
            .collect();
        let mut drift = [(0.0, 0.0, 0.0); 3];
        let mut total = 0.0;
        for d in &mut drift {
            *d = (
                0.5 + rng.uniform(),
                15.0 + 45.0 * rng.uniform(),
                2.0 * PI * rng.uniform(),
            );
            total += d.0;
        }
        for d in &mut drift {
            d.0 *= 0.08 / total;
        }
        Self {
            noise,
            pad,
            drift,
            flicker_phase: 2.0 * PI * rng.uniform(),
            seed: stream(seed, 4),
        }
    }

    /// Gain at frame `i` (time `t`) and the frame's noise offset.
    fn frame(&self, i: usize, t: f64) -> (f64, usize) {
        let mut rng = Rng::new(self.seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let drift: f64 = self
            .drift
            .iter()
            .map(|&(a, p, ph)| a * (2.0 * PI * t / p + ph).sin())
            .sum();
        // 100 Hz mains flicker sampled at the frame rate (a beat), plus jitter.
        let flicker =
            0.012 * (2.0 * PI * 100.0 * t + self.flicker_phase).sin() + 0.004 * rng.normal();
        let off = (rng.uniform() * self.pad as f64) as usize;
        ((1.0 + drift) * (1.0 + flicker), off.min(self.pad))
    }
}

/// `p <- p * gain + offset + noise`, saturating; gain below 4. In 16-bit lanes (units of
/// 1/64 grey level) so that it vectorises with plain SSE2.
fn expose(buf: &mut [u8], noise: &[i8], gain: f64, offset: f64) {
    // gain * 64 = hi + lo / 256, so that both products fit 16 bits.
    let g = (gain.clamp(0.0, 3.99) * 16384.0).round() as u32;
    let (hi, lo) = ((g >> 8) as u16, (g & 255) as u16);
    let bias = ((offset * 64.0).round() + 32.0).clamp(0.0, 65535.0) as u16;
    for (p, &n) in buf.iter_mut().zip(noise) {
        let q = *p as u16;
        let v = (q * hi) + ((q * lo) >> 8);
        let v = v
            .saturating_add(bias)
            .saturating_add(((n as i16 + 128) as u16) << 6)
            .saturating_sub(128 << 6);
        *p = (v >> 6).min(255) as u8;
    }
}

// ---------------------------------------------------------------------------------------
// The twin: everything prepared once, then frames on demand.

struct Twin {
    plan: Plan,
    bg: Vec<u8>,
    illum: Vec<f32>,
    mover: Mover,
    sensor: Option<Sensor>,
    hand: HandPainter,
    frame: Mat,
}

impl Twin {
    fn new(plan: Plan) -> Result<Self> {
        let defects = !plan.s.clean;
        let mut rng = Rng::new(stream(plan.s.seed, 5));
        let defocus = defects.then(|| 0.8 + 0.4 * rng.uniform());
        let (bg, illum) = build_background(&plan, defocus)?;
        // Pixel integration (~0.4 px) combined with the defocus.
        let sigma = (0.4f64.powi(2) + defocus.unwrap_or(0.0).powi(2)).sqrt();
        let mover = Mover::new(&plan.geo, &plan.look, sigma);
        let sensor = defects.then(|| Sensor::new(bg.len(), plan.look.noise_sigma, plan.s.seed));
        let frame = Mat::new_rows_cols_with_default(
            plan.geo.h as i32,
            plan.geo.w as i32,
            core::CV_8UC3,
            Scalar::all(0.0),
        )?;
        Ok(Self {
            plan,
            bg,
            illum,
            mover,
            sensor,
            hand: HandPainter::default(),
            frame,
        })
    }

    /// Render frame `i` into `self.frame` (a duplicate is rendered as its own content
    /// would be: the caller repeats the previous frame instead).
    fn render_frame(&mut self, i: usize) -> Result<()> {
        let plan = &self.plan;
        let t = plan.truth[i].t_s;
        let dt = 1.0 / plan.fps;
        let mut thetas = [0.0; SUBSAMPLES];
        let n_sub = if self.sensor.is_some() { SUBSAMPLES } else { 1 };
        for (k, th) in thetas[..n_sub].iter_mut().enumerate() {
            let f = if n_sub == 1 {
                0.0
            } else {
                k as f64 / (n_sub - 1) as f64 - 0.5
            };
            *th = plan.theta(t + f * EXPOSURE * dt);
        }
        let theta_mid = plan.truth[i].angle_rad;
        {
            let buf = self.frame.data_bytes_mut()?;
            buf.copy_from_slice(&self.bg);
            self.mover
                .draw(buf, &self.bg, &self.illum, &thetas[..n_sub], theta_mid);
        }
        if let Spoil::Hand { k, n, event } = plan.spoils[i] {
            let g = &plan.geo;
            let mut rng = Rng::new(stream(plan.s.seed, 100 + event as u64));
            let dir = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
            let tilt = dir * (0.25 + 0.2 * rng.uniform());
            // Start of the event: the hand crosses the wire's middle.
            let th0 = plan.truth[i - k as usize].angle_rad;
            let mid = [
                g.pivot[0] + 0.55 * g.d_px * th0.cos(),
                g.pivot[1] + 0.55 * g.d_px * th0.sin(),
            ];
            let u = 0.1 * g.h as f64;
            let step = 0.3 * g.w as f64;
            let off = k as f64 - (n as f64 - 1.0) / 2.0;
            let c = [
                mid[0] + dir * off * step + (rng.uniform() - 0.5) * u,
                mid[1] + 1.2 * u + (rng.uniform() - 0.5) * u,
            ];
            let smear = (0.04 * g.w as f64).max(3.0);
            self.hand
                .paint(&mut self.frame, &self.illum, c, u, tilt, smear)?;
        }
        if let Some(sensor) = &self.sensor {
            let (gain, off) = sensor.frame(i, t);
            let (gain, offset) = if plan.spoils[i] == Spoil::Flash {
                (3.5 * gain, 100.0)
            } else {
                (gain, 0.0)
            };
            let buf = self.frame.data_bytes_mut()?;
            let n = buf.len();
            expose(buf, &sensor.noise[off..off + n], gain, offset);
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------
// Writing.

/// Removes the temporary file unless the render completed.
struct TempFile(Option<PathBuf>);

impl TempFile {
    fn path(&self) -> PathBuf {
        self.0.clone().unwrap_or_default()
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if let Some(p) = self.0.take() {
            let _ = std::fs::remove_file(p);
        }
    }
}

fn temp_name(path: &Path) -> PathBuf {
    let dir = path.parent().unwrap_or(Path::new(""));
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    let ext = path.extension().unwrap_or_default().to_string_lossy();
    dir.join(format!(".{stem}.tmp{}.{ext}", std::process::id()))
}

/// BT.601 Y'CbCr: full range (JPEG's, `yuvj420p`) or limited range (video's, `yuv420p`:
/// luma 16..235, chroma 16..240).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum YuvRange {
    Full,
    Limited,
}

/// Fixed-point weights of the BGR to Y'CbCr conversion.
#[derive(Clone, Debug)]
struct YuvWeights {
    /// Luma weights of B, G and R, units of 2^-15, times every byte value (a table
    /// lookup costs less than a multiplication here).
    y: [[u32; 256]; 3],
    /// The sum of the weights (2^15 for full range).
    sum: i64,
    /// Luma offset plus one half, units of 2^-15.
    y_bias: u32,
    /// `Cb = 128 + cb (B - Y)` and `Cr = 128 + cr (R - Y)` with `Y` the unscaled luma,
    /// turned into factors on a 2x2 block's sums `sum * (B1 + .. + B4) - (L1 + .. + L4)`
    /// (`L` the luma before the shift), units of 2^-32.
    cb: i64,
    cr: i64,
}

impl YuvWeights {
    fn new(range: YuvRange) -> Self {
        let (ky, kc, y0) = match range {
            YuvRange::Full => (1.0, 1.0, 0.0),
            YuvRange::Limited => (219.0 / 255.0, 224.0 / 255.0, 16.0),
        };
        let (wb, wr) = (0.114, 0.299);
        let k = [wb, 1.0 - wb - wr, wr].map(|w: f64| (w * ky * 32768.0).round() as u32);
        let sum = k.iter().map(|&k| k as i64).sum::<i64>();
        let chroma = |w: f64| (kc * 0.5 / (1.0 - w) / (4.0 * sum as f64) * 2f64.powi(32)).round();
        Self {
            y: k.map(|k| std::array::from_fn(|v| k * v as u32)),
            sum,
            y_bias: ((y0 + 0.5) * 32768.0) as u32,
            cb: chroma(wb) as i64,
            cr: chroma(wr) as i64,
        }
    }
}

/// Convert a BGR frame (`w` x `h`, both even) to planar Y'CbCr 4:2:0 in `out`: the luma
/// plane, then Cb, then Cr (`w h 3 / 2` bytes, the layout of FFmpeg's `yuv420p`).
/// BT.601 in integer fixed point (within one grey level of the exact conversion); the
/// chroma of each 2x2 block is that of its mean colour. One pass over 2x2 blocks, with
/// the luma sums reused for the chroma.
fn bgr_to_yuv420(bgr: &[u8], w: usize, h: usize, range: YuvRange, out: &mut Vec<u8>) {
    debug_assert!(w.is_multiple_of(2) && h.is_multiple_of(2) && bgr.len() == 3 * w * h);
    out.resize(w * h * 3 / 2, 0);
    let k = YuvWeights::new(range);
    let (luma, chroma) = out.split_at_mut(w * h);
    let (cb_plane, cr_plane) = chroma.split_at_mut(w * h / 4);
    let [yb, yg, yr] = &k.y;
    let weigh = |p: &[u8]| yb[p[0] as usize] + yg[p[1] as usize] + yr[p[2] as usize];
    let bias = (128i64 << 32) + (1 << 31);
    let rows = bgr.chunks_exact(6 * w).zip(luma.chunks_exact_mut(2 * w));
    let planes = cb_plane
        .chunks_exact_mut(w / 2)
        .zip(cr_plane.chunks_exact_mut(w / 2));
    for ((two, lum), (cbs, crs)) in rows.zip(planes) {
        let (top, bottom) = two.split_at(3 * w);
        let (y_top, y_bottom) = lum.split_at_mut(w);
        let blocks = top.chunks_exact(6).zip(bottom.chunks_exact(6));
        let outs = y_top.chunks_exact_mut(2).zip(y_bottom.chunks_exact_mut(2));
        for (((a, b), (ya, yb)), (cb, cr)) in blocks.zip(outs).zip(cbs.iter_mut().zip(crs)) {
            let l = [
                weigh(&a[..3]),
                weigh(&a[3..]),
                weigh(&b[..3]),
                weigh(&b[3..]),
            ];
            ya[0] = ((l[0] + k.y_bias) >> 15) as u8;
            ya[1] = ((l[1] + k.y_bias) >> 15) as u8;
            yb[0] = ((l[2] + k.y_bias) >> 15) as u8;
            yb[1] = ((l[3] + k.y_bias) >> 15) as u8;
            let sl = (l[0] + l[1] + l[2] + l[3]) as i64;
            let sb = (a[0] as u32 + a[3] as u32 + b[0] as u32 + b[3] as u32) as i64;
            let sr = (a[2] as u32 + a[5] as u32 + b[2] as u32 + b[5] as u32) as i64;
            *cb = (((sb * k.sum - sl) * k.cb + bias) >> 32).clamp(0, 255) as u8;
            *cr = (((sr * k.sum - sl) * k.cr + bias) >> 32).clamp(0, 255) as u8;
        }
    }
}

/// Whether the `ffmpeg` program has the encoder `name` (asked once per process).
fn ffmpeg_has_encoder(name: &str) -> bool {
    static LIST: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    let list = LIST.get_or_init(|| {
        Command::new("ffmpeg")
            .args(["-hide_banner", "-nostdin", "-encoders"])
            .stdin(Stdio::null())
            .stderr(Stdio::null())
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
            .unwrap_or_default()
    });
    list.lines()
        .any(|l| l.split_whitespace().nth(1) == Some(name))
}

/// `fps` as FFmpeg reads a frame rate: an integer when it is one, else the decimal.
fn rate_arg(fps: f64) -> String {
    if fps.fract() == 0.0 {
        format!("{}", fps as u64)
    } else {
        format!("{fps}")
    }
}

/// The codecs the `ffmpeg` program writes here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FfmpegCodec {
    /// MJPEG at `-q:v 3` (about the quality of OpenCV's MJPG; lossy like a camera's),
    /// with the standard Huffman tables (optimal ones cost the encoder a quarter more
    /// time for files a sixth smaller), on one thread (frame threads cost it a third
    /// more time, and the renderer keeps the other core busy), in `.avi`.
    Mjpeg,
    /// H.264 by x264 (`veryfast`, CRF 18) in the container of the file's extension.
    H264,
}

impl FfmpegCodec {
    fn range(self) -> YuvRange {
        match self {
            FfmpegCodec::Mjpeg => YuvRange::Full,
            FfmpegCodec::H264 => YuvRange::Limited,
        }
    }
}

/// Frames piped to the `ffmpeg` program as raw planar Y'CbCr 4:2:0, one after another at
/// a constant rate (every frame kept: `-fps_mode passthrough`). The output carries no
/// version strings or metadata (`bitexact`), and x264 runs a fixed number of threads,
/// so that the same frames give the same bytes on any machine with the same FFmpeg.
struct FfmpegPipe {
    child: Child,
    stdin: Option<ChildStdin>,
    /// The last lines ffmpeg wrote to stderr, gathered by a thread.
    stderr: Option<std::thread::JoinHandle<Vec<String>>>,
    range: YuvRange,
}

impl FfmpegPipe {
    /// Start ffmpeg writing `path` and hand it the first frame. `Ok(None)` when ffmpeg
    /// cannot be started or exits before taking that frame (said on stderr): the caller
    /// writes with OpenCV instead.
    fn start(
        path: &Path,
        codec: FfmpegCodec,
        (w, h): (usize, usize),
        fps: f64,
        first: &Mat,
    ) -> Result<Option<Self>> {
        let range = codec.range();
        let mut cmd = Command::new("ffmpeg");
        cmd.args(["-nostdin", "-hide_banner", "-loglevel", "error"])
            .args(["-f", "rawvideo", "-pix_fmt"])
            .arg(match range {
                YuvRange::Full => "yuvj420p",
                YuvRange::Limited => "yuv420p",
            })
            .args(["-s", &format!("{w}x{h}"), "-r", &rate_arg(fps), "-i", "-"])
            .args(["-map", "0:v", "-an", "-fps_mode", "passthrough"]);
        match codec {
            FfmpegCodec::Mjpeg => cmd
                .args(["-c:v", "mjpeg", "-q:v", "3", "-huffman", "default"])
                .args(["-threads", "1", "-f", "avi"]),
            FfmpegCodec::H264 => cmd
                .args(["-c:v", "libx264", "-preset", "veryfast", "-crf", "18"])
                .args(["-pix_fmt", "yuv420p", "-threads", "4"])
                .args(["-color_range", "tv", "-colorspace", "smpte170m"]),
        };
        cmd.args(["-fflags", "+bitexact", "-flags:v", "+bitexact"])
            .args(["-map_metadata", "-1", "-y"])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        let mut child = match cmd.spawn() {
            Ok(c) => c,
            Err(e) => {
                eprintln!(
                    "{}: cannot start ffmpeg ({e}); writing with OpenCV instead",
                    path.display()
                );
                return Ok(None);
            }
        };
        let stdin = child.stdin.take();
        let err = child.stderr.take().expect("piped");
        let stderr = std::thread::spawn(move || {
            let mut tail = std::collections::VecDeque::new();
            for line in BufReader::new(err).lines() {
                let Ok(line) = line else { break };
                if tail.len() == 8 {
                    tail.pop_front();
                }
                tail.push_back(line);
            }
            tail.into()
        });
        let mut pipe = Self {
            child,
            stdin,
            stderr: Some(stderr),
            range,
        };
        let mut yuv = Vec::new();
        bgr_to_yuv420(first.data_bytes()?, w, h, range, &mut yuv);
        if let Err(e) = pipe.write(&yuv) {
            let why = pipe.abort();
            eprintln!(
                "{}: ffmpeg did not take the first frame ({}); writing with OpenCV instead",
                path.display(),
                if why.is_empty() { e.to_string() } else { why }
            );
            return Ok(None);
        }
        Ok(Some(pipe))
    }

    fn write(&mut self, yuv: &[u8]) -> std::io::Result<()> {
        match &mut self.stdin {
            Some(s) => s.write_all(yuv),
            None => Err(std::io::ErrorKind::BrokenPipe.into()),
        }
    }

    /// ffmpeg's last words on stderr, one line.
    fn stderr_tail(&mut self) -> String {
        self.stderr
            .take()
            .and_then(|t| t.join().ok())
            .unwrap_or_default()
            .join(" | ")
    }

    /// Stop ffmpeg (the file is incomplete) and return its last words.
    fn abort(&mut self) -> String {
        self.stdin = None;
        let _ = self.child.kill();
        let _ = self.child.wait();
        self.stderr_tail()
    }

    /// Close the pipe and wait for ffmpeg to finish the file.
    fn finish(&mut self, path: &Path) -> Result<()> {
        self.stdin = None;
        let status = self
            .child
            .wait()
            .with_context(|| format!("{}: waiting for ffmpeg", path.display()))?;
        let tail = self.stderr_tail();
        ensure!(
            status.success(),
            "{}: ffmpeg failed ({status}): {}",
            path.display(),
            if tail.is_empty() { "no message" } else { &tail }
        );
        Ok(())
    }
}

impl Drop for FfmpegPipe {
    fn drop(&mut self) {
        if self.stdin.is_some() {
            self.abort();
        }
    }
}

/// Where the frames go.
enum Sink {
    /// The `ffmpeg` program, which already has frame 0.
    Ffmpeg(FfmpegPipe),
    OpenCv(videoio::VideoWriter),
}

/// Try to open a writer with one back-end and codec.
fn try_writer(
    path: &Path,
    api: i32,
    cc: [char; 4],
    fps: f64,
    size: Size,
) -> Result<Option<videoio::VideoWriter>> {
    let fourcc = videoio::VideoWriter::fourcc(cc[0], cc[1], cc[2], cc[3])?;
    match videoio::VideoWriter::new_with_backend(path, api, fourcc, fps, size, true) {
        Ok(wr) if wr.is_opened()? => Ok(Some(wr)),
        _ => {
            let _ = std::fs::remove_file(path);
            Ok(None)
        }
    }
}

/// Start the `ffmpeg` program writing `codec` into a temporary name for `fin`, if it is
/// installed (with x264 for H.264; its MJPEG encoder is always built in) and the size is
/// even (4:2:0).
fn try_ffmpeg(
    fin: &Path,
    codec: FfmpegCodec,
    (w, h): (usize, usize),
    fps: f64,
    first: &Mat,
) -> Result<Option<(Sink, TempFile)>> {
    let usable = crate::video::have_ffmpeg()
        && (codec == FfmpegCodec::Mjpeg || ffmpeg_has_encoder("libx264"));
    if w % 2 == 1 || h % 2 == 1 || !usable {
        return Ok(None);
    }
    let tmp = TempFile(Some(temp_name(fin)));
    Ok(FfmpegPipe::start(&tmp.path(), codec, (w, h), fps, first)?.map(|p| (Sink::Ffmpeg(p), tmp)))
}

/// Open a writer and give it the rendered frame 0 when it is the `ffmpeg` program.
/// Unless `out` ends in `.avi`: H.264 into `out`, by ffmpeg's x264, else by OpenCV's
/// FFmpeg back-end (fourcc `avc1`, else `H264`). Otherwise, or failing that: MJPG into
/// `out` with `.avi`, by ffmpeg, else by OpenCV (FFmpeg's encoder, else OpenCV's own at
/// quality 75; for odd sizes OpenCV's own first). ffmpeg is not used for odd sizes
/// (4:2:0). Returns the writer, the temporary and final paths and the codec's name
/// with the container and who wrote it.
///
/// OpenCV 4.6 leaves x264 at its default preset (`medium`, the slowest part of a
/// render: its `OPENCV_FFMPEG_WRITER_OPTIONS` do not reach the encoder in this
/// version), and converts BGR to Y'CbCr without a fast path: hence ffmpeg first, fed
/// frames converted here. OpenCV's MJPG is preferred from FFmpeg because OpenCV 4.6's
/// own MJPEG encoder writes an invalid DC coefficient in bright frames at some sizes (a
/// uniform frame brighter than 200 at 640x360: FFmpeg then reports `error dc` when
/// reading it).
fn open_writer(
    out: &Path,
    (w, h): (usize, usize),
    fps: f64,
    first: &Mat,
) -> Result<(Sink, TempFile, PathBuf, String)> {
    let size = Size::new(w as i32, h as i32);
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if ext != "avi" {
        let why = if w % 2 == 1 || h % 2 == 1 {
            "H.264 needs an even width and height"
        } else {
            if let Some((sink, tmp)) = try_ffmpeg(out, FfmpegCodec::H264, (w, h), fps, first)? {
                return Ok((
                    sink,
                    tmp,
                    out.to_path_buf(),
                    format!("H.264 ({ext}, ffmpeg)"),
                ));
            }
            for cc in [['a', 'v', 'c', '1'], ['H', '2', '6', '4']] {
                let tmp = TempFile(Some(temp_name(out)));
                let path = tmp.path();
                if let Some(wr) = try_writer(&path, videoio::CAP_FFMPEG, cc, fps, size)? {
                    let codec = format!("H.264 ({ext}, OpenCV)");
                    return Ok((Sink::OpenCv(wr), tmp, out.to_path_buf(), codec));
                }
            }
            "neither ffmpeg nor this OpenCV can write H.264"
        };
        eprintln!(
            "{}: {why}; writing MJPG to {} instead",
            out.display(),
            out.with_extension("avi").display()
        );
    }
    let fin = out.with_extension("avi");
    if let Some((sink, tmp)) = try_ffmpeg(&fin, FfmpegCodec::Mjpeg, (w, h), fps, first)? {
        return Ok((sink, tmp, fin, "MJPG (avi, ffmpeg)".into()));
    }
    // FFmpeg's MJPG (4:2:0) drops the last row or column of an odd size.
    let apis = if w % 2 == 1 || h % 2 == 1 {
        [videoio::CAP_OPENCV_MJPEG, videoio::CAP_FFMPEG]
    } else {
        [videoio::CAP_FFMPEG, videoio::CAP_OPENCV_MJPEG]
    };
    for api in apis {
        let tmp = TempFile(Some(temp_name(&fin)));
        let path = tmp.path();
        if let Some(mut wr) = try_writer(&path, api, ['M', 'J', 'P', 'G'], fps, size)? {
            // Honoured by OpenCV's own encoder only (FFmpeg's keeps its default).
            let _ = wr.set(videoio::VIDEOWRITER_PROP_QUALITY, 75.0);
            return Ok((Sink::OpenCv(wr), tmp, fin, "MJPG (avi, OpenCV)".into()));
        }
    }
    bail!("neither ffmpeg nor OpenCV can write H.264 or MJPG")
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
                let job = if i > 0 && twin.plan.spoils[i] == Spoil::Duplicate {
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
    let (sink, mut tmp, path, codec) = open_writer(out, (w, h), twin.plan.fps, &twin.frame)?;
    let tmp_path = tmp.path();
    match sink {
        Sink::Ffmpeg(mut pipe) => {
            let range = pipe.range;
            let pumped = {
                let stdin = pipe.stdin.as_mut().expect("open until finished");
                let mut yuv = Vec::new();
                pump(&mut twin, 1, progress, |m: &Mat| {
                    bgr_to_yuv420(m.data_bytes()?, w, h, range, &mut yuv);
                    Ok(stdin.write_all(&yuv)?)
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
        }
        Sink::OpenCv(mut writer) => {
            pump(&mut twin, 0, progress, |m: &Mat| Ok(writer.write(m)?))?;
            writer.release()?;
        }
    }
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
        frames: twin.plan.truth.len(),
        width: g.w as u32,
        height: g.h as u32,
        fps: twin.plan.fps,
        pivot_px: g.pivot,
        wire_length_px: g.d_px,
        wire_width_px: g.wire_w,
        ball_radius_px: g.ball_r,
        rest_angle_rad: g.theta_rest,
        style: twin.plan.s.style,
        clean: twin.plan.s.clean,
        truth: std::mem::take(&mut twin.plan.truth),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 320x240, 30 frames/s twin unless `extra` sets the size.
    fn exp(extra: &str) -> Experiment {
        let size = if extra.contains("width") {
            ""
        } else {
            ", width: 320, height: 240"
        };
        let text = format!(
            "
geometry:
  incline: {{ h_m: 0.142, l_m: 1.5 }}
  pendulum: {{ d_m: 0.187 }}
  ball: {{ radius_m: 0.03175, mass_kg: 1.0458 }}
synthetic: {{ s_r_m: 4.445e-6, fps: 30, seed: 3{size}{extra} }}
"
        );
        Experiment::parse(Path::new("t/twin.yaml"), &text).unwrap()
    }

    /// Every frame of a video, checking its size.
    fn read_back(path: &Path, w: i32, h: i32) -> Vec<Mat> {
        let mut cap = videoio::VideoCapture::from_file(path, videoio::CAP_ANY).unwrap();
        assert!(cap.is_opened().unwrap(), "{}", path.display());
        let mut frames = Vec::new();
        let mut m = Mat::default();
        while cap.read(&mut m).unwrap() && !m.empty() {
            assert_eq!((m.cols(), m.rows()), (w, h));
            frames.push(m.clone());
        }
        frames
    }

    fn count_frames(path: &Path) -> usize {
        read_back(path, 320, 240).len()
    }

    /// Mean absolute difference of two frames, grey levels.
    fn diff(a: &Mat, b: &Mat) -> f64 {
        let mut d = Mat::default();
        core::absdiff(a, b, &mut d).unwrap();
        let m = core::mean(&d, &core::no_array()).unwrap();
        (m[0] + m[1] + m[2]) / 3.0
    }

    fn brightness(a: &Mat) -> f64 {
        let m = core::mean(a, &core::no_array()).unwrap();
        (m[0] + m[1] + m[2]) / 3.0
    }

    #[test]
    fn odd_sizes_fall_back_to_mjpg_and_spoiled_frames_look_spoiled() {
        let dir = tempfile::tempdir().unwrap();
        let e = exp(", width: 322, height: 241");
        let rep = render(&e, &dir.path().join("odd.mp4"), Some(1.0), &mut |_, _| {}).unwrap();
        assert_eq!(rep.path, dir.path().join("odd.avi"));
        assert_eq!(rep.codec, "MJPG (avi, OpenCV)");
        let frames = read_back(&rep.path, 322, 241);
        assert_eq!(frames.len(), rep.truth.len());
        for (i, row) in rep.truth.iter().enumerate().skip(1) {
            let (d, b) = (diff(&frames[i], &frames[i - 1]), brightness(&frames[i]));
            match row.spoiled {
                "duplicate" => assert!(d < 0.3, "frame {i}: {d}"),
                "flash" => assert!(b > 225.0, "frame {i}: {b}"),
                "hand" => assert!(d > 8.0, "frame {i}: {d}"),
                _ => {
                    assert!(b < 200.0, "frame {i}: {b}");
                    if rep.truth[i - 1].spoiled == "none" {
                        assert!((1.0..8.0).contains(&d), "frame {i}: {d}");
                    }
                }
            }
        }
        // No temporary file left behind, and no `.mp4`.
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["odd.avi"]);
    }

    #[test]
    fn one_second_render_has_every_frame_and_its_truth() {
        let dir = tempfile::tempdir().unwrap();
        let e = exp("");
        let mut calls = Vec::new();
        let rep = render(&e, &dir.path().join("twin.mp4"), Some(1.0), &mut |d, t| {
            calls.push((d, t))
        })
        .unwrap();
        // 1 s at 30 fps: frames 0..=30.
        assert_eq!(rep.frames, 31);
        assert_eq!(rep.truth.len(), 31);
        assert_eq!(calls.last(), Some(&(31, 31)));
        assert!(rep.path.exists(), "{}", rep.path.display());
        assert_eq!(count_frames(&rep.path), 31);
        // No temporary file left behind.
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(left.len(), 1);
        // The truth is rest - psi(t), psi from the simulation.
        let mut cam = simulate::camera_of(&e).unwrap();
        cam.duration_s = Some(1.0);
        let rec = simulate::record(&e, &cam).unwrap();
        let rest = 91.7f64.to_radians();
        for (row, &t) in rep.truth.iter().zip(&rec.series.t) {
            assert_eq!(row.t_s, t);
            let want = rest - rec.trajectory.state(t)[0];
            assert!(
                (row.angle_rad - want).abs() < 1e-12,
                "{} {}",
                row.angle_rad,
                want
            );
        }
        assert!((rep.truth[0].angle_rad - (91.7f64 - 10.0).to_radians()).abs() < 1e-9);
        // Three spoiling events, one of each kind, counted as runs of equal tags.
        let mut runs = Vec::new();
        for (i, r) in rep.truth.iter().enumerate() {
            if r.spoiled != "none" && (i == 0 || rep.truth[i - 1].spoiled != r.spoiled) {
                runs.push(r.spoiled);
            }
        }
        assert_eq!(runs, ["hand", "flash", "duplicate"]);
        let csv = truth_csv(&rep.truth);
        assert!(
            csv.starts_with("t_s,angle_rad,spoiled\n0.000000,1.42"),
            "{csv}"
        );
        assert_eq!(csv.lines().count(), 32);
    }

    #[test]
    fn spoiled_frames_are_spoiled_and_clean_renders_are_not() {
        let e = exp(", spoiled_frames: 6");
        let truth = truth(&e, Some(20.0)).unwrap();
        let tags = |kind: &str| truth.iter().filter(|r| r.spoiled == kind).count();
        assert_eq!(tags("flash"), 2);
        assert_eq!(tags("duplicate"), 2);
        assert!((2..=6).contains(&tags("hand")));
        // Away from the first and last 2 s.
        for (i, r) in truth.iter().enumerate() {
            if r.spoiled != "none" {
                assert!(i >= 60 && i + 60 < truth.len(), "frame {i}");
            }
        }
        let clean = self::truth(&exp(", clean: true, spoiled_frames: 6"), Some(20.0)).unwrap();
        assert!(clean.iter().all(|r| r.spoiled == "none"));
        // Same seed, same plan.
        assert_eq!(truth, self::truth(&e, Some(20.0)).unwrap());
    }

    #[test]
    fn pixels_show_the_wire_where_the_truth_says() {
        // Clean render: the darkest pixels along a circle around the pivot lie on the
        // truth's angle, for each style.
        for style in [
            "dark-wire",
            "light-wire",
            "oblique",
            "dark-wire, rest_angle_deg: 3",
        ] {
            let e = exp(&format!(", clean: true, style: {style}"));
            let plan = Plan::new(&e, Some(2.0)).unwrap();
            let g = plan.geo.clone();
            let mut twin = Twin::new(plan).unwrap();
            let i = 20;
            twin.render_frame(i).unwrap();
            let want = twin.plan.truth[i].angle_rad;
            let buf = twin.frame.data_bytes().unwrap();
            let light = style == "light-wire";
            let r = 0.2 * g.d_px;
            let mut best = (f64::MIN, 0.0);
            for k in -400..=400 {
                let a = want + (k as f64 / 400.0) * 0.5;
                let (x, y) = (g.pivot[0] + r * a.cos(), g.pivot[1] + r * a.sin());
                let j = 3 * ((y.round() as usize) * g.w + x.round() as usize);
                let v = buf[j] as f64 + buf[j + 1] as f64 + buf[j + 2] as f64;
                let score = if light { v } else { -v };
                if score > best.0 {
                    best = (score, a);
                }
            }
            assert!(
                (best.1 - want).abs() < 1.5 / r,
                "{style}: wire found at {} rad, truth {want}",
                best.1
            );
        }
    }

    /// BT.601 as floating point, chroma of the 2x2 block's mean colour.
    fn yuv_reference(bgr: &[u8], w: usize, h: usize, range: YuvRange) -> Vec<f64> {
        let (ky, kc, y0) = match range {
            YuvRange::Full => (1.0, 1.0, 0.0),
            YuvRange::Limited => (219.0 / 255.0, 224.0 / 255.0, 16.0),
        };
        let luma = |p: [f64; 3]| 0.114 * p[0] + 0.587 * p[1] + 0.299 * p[2];
        let px = |x: usize, y: usize| {
            let j = 3 * (y * w + x);
            [bgr[j] as f64, bgr[j + 1] as f64, bgr[j + 2] as f64]
        };
        let mut out = Vec::new();
        for y in 0..h {
            for x in 0..w {
                out.push(y0 + ky * luma(px(x, y)));
            }
        }
        let mut cb = Vec::new();
        let mut cr = Vec::new();
        for y in (0..h).step_by(2) {
            for x in (0..w).step_by(2) {
                let mut m = [0.0; 3];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let p = px(x + dx, y + dy);
                    (0..3).for_each(|c| m[c] += p[c] / 4.0);
                }
                let l = luma(m);
                cb.push(128.0 + kc * 0.5 / 0.886 * (m[0] - l));
                cr.push(128.0 + kc * 0.5 / 0.701 * (m[2] - l));
            }
        }
        out.extend(cb);
        out.extend(cr);
        out
    }

    #[test]
    fn yuv_conversion_is_bt601_within_one_level() {
        let (w, h) = (38, 6);
        let mut rng = Rng::new(7);
        let mut bgr: Vec<u8> = (0..3 * w * h)
            .map(|_| (rng.uniform() * 256.0) as u8)
            .collect();
        // Extremes: black, white, pure B, G, R, as uniform 2x2 blocks in the top rows.
        for (k, c) in [
            [0, 0, 0],
            [255, 255, 255],
            [255, 0, 0],
            [0, 255, 0],
            [0, 0, 255],
        ]
        .iter()
        .enumerate()
        {
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let j = 3 * (dy * w + 2 * k + dx);
                bgr[j..j + 3].copy_from_slice(c);
            }
        }
        for range in [YuvRange::Full, YuvRange::Limited] {
            let mut got = vec![9; 3];
            bgr_to_yuv420(&bgr, w, h, range, &mut got);
            let want = yuv_reference(&bgr, w, h, range);
            assert_eq!(got.len(), want.len());
            for (i, (&g, &e)) in got.iter().zip(&want).enumerate() {
                assert!(
                    (g as f64 - e).abs() <= 1.0,
                    "{range:?} byte {i}: {g} vs {e:.2}"
                );
            }
            // White and black exactly, and grey without colour.
            let (y, c) = match range {
                YuvRange::Full => ([0, 255], 128),
                YuvRange::Limited => ([16, 235], 128),
            };
            assert_eq!([got[0], got[2]], y, "{range:?}");
            let (cb, cr) = (w * h, w * h + w * h / 4);
            assert_eq!([got[cb], got[cr], got[cb + 1], got[cr + 1]], [c; 4]);
        }
    }

    #[test]
    fn ffmpeg_writes_every_frame_the_same_way_twice() {
        if !crate::require::require(
            "ffmpeg",
            crate::require::MAKE_DEPS,
            crate::video::have_ffmpeg(),
        ) {
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let e = exp(", spoiled_frames: 3");
        let mut files = Vec::new();
        for k in 0..2 {
            let out = dir.path().join(format!("twin{k}.avi"));
            let rep = render(&e, &out, Some(1.0), &mut |_, _| {}).unwrap();
            assert_eq!(rep.codec, "MJPG (avi, ffmpeg)");
            assert_eq!(rep.path, out);
            files.push(std::fs::read(&out).unwrap());
        }
        assert!(files[0] == files[1], "two renders differ");
        // Every frame, as rendered (up to the codec's loss), duplicates included.
        let path = dir.path().join("twin0.avi");
        let frames = read_back(&path, 320, 240);
        let mut twin = Twin::new(Plan::new(&e, Some(1.0)).unwrap()).unwrap();
        assert_eq!(frames.len(), twin.plan.truth.len());
        for (i, f) in frames.iter().enumerate() {
            let src = match twin.plan.spoils[i] {
                Spoil::Duplicate => i - 1,
                _ => i,
            };
            twin.render_frame(src).unwrap();
            let d = diff(f, &twin.frame);
            assert!(d < 2.5, "frame {i}: {d}");
        }
        // Constant rate: ffprobe counts every frame at exactly 30 frames/s.
        let out = Command::new("ffprobe")
            .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
            .args([
                "-show_entries",
                "stream=nb_read_frames,r_frame_rate,avg_frame_rate",
            ])
            .args(["-of", "csv=p=0"])
            .arg(&path)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(text.trim(), format!("30/1,30/1,{}", frames.len()));
    }
}
