//! Finding the wire's geometry in a plain video: which polarity it has, where its pivot
//! is, the band of distances from the pivot where it is visible, and a region of
//! interest, from the first seconds of the recording.
//!
//! Over those frames (shrunk so the larger side is at most 640 px) the per-pixel maximum
//! and minimum are the background for a dark and for a light wire: the wire moves on,
//! so each pixel sees the background at some point. In each frame, the evidence of a
//! thin moving structure is `max - I` (dark) or `I - min` (light) after a morphological
//! top-hat, which removes anything wider than a few pixels (the bob, a hand). The
//! longest straight segment of each frame (probabilistic Hough, then an orthogonal
//! least-squares fit, ERRATA §6) is the wire. All those lines pass through the pivot:
//! it is their robust least-squares intersection, which may lie outside the frame.
//!
//! The extremes also keep the trail of everything that passed: a bob's bright rim or
//! glints leave long arcs whose edges make straight lines of their own, and when those
//! outnumber a faint wire the lines meet in a point that no pendulum swings about (their
//! directions fan out over more than [`MAX_SWEEP_DEG`]). The look is then repeated
//! against each pixel's median, which forgets whatever passes briefly.

mod pivot;

pub use pivot::intersect;
use pivot::{ransac_pivot, through_tol, Seen};

use super::{fit_line_weighted, full_to_shrunk, shrunk_to_full, unwrap_near, Line, Pt};
use crate::config::Polarity;
use crate::video::Roi;
use anyhow::{bail, Result};
use opencv::core::{self, Mat, Point, Vector};
use opencv::imgproc;
use opencv::prelude::*;

/// At most this many threads look for the first look's lines (one per processor).
const GEOMETRY_THREADS: usize = 4;

/// The geometry found (or given), in full-frame pixel coordinates.
#[derive(Clone, Debug)]
pub struct WireGeometry {
    pub pivot: Pt,
    pub dark: bool,
    /// Distances from the pivot where the wire is visible, px.
    pub r_lo: f64,
    pub r_hi: f64,
    /// Angles (image, from the x axis) the wire was seen at during the first seconds.
    pub theta_min: f64,
    pub theta_max: f64,
    pub roi: Roi,
    /// Per initial frame: the wire's angle, if a line was found.
    pub initial_angles: Vec<Option<f64>>,
    /// Lines used for the pivot.
    pub lines_used: usize,
    /// Jumps of more than half the sweep between frames looked at one after the other
    /// ([`jumps`]).
    pub jumps: usize,
    /// How irregularly the wire's angle turns from frame to frame ([`roughness`]).
    pub roughness: f64,
    /// Which of the first look's tries found it ([`find`]): 0 at the first threshold
    /// against the running extreme, 1 against the median, 2 and 3 the same at the
    /// lower threshold, [`FAINT_STAGE`] the faint look. An earlier try needed less
    /// leniency to see a wire.
    pub stage: usize,
}

/// Frames of the first seconds, shrunk: `data[k]` is `w * h` grey bytes.
pub struct InitFrames {
    pub w: usize,
    pub h: usize,
    /// Shrink factor from the source crop to these frames.
    pub shrink: f64,
    /// Offset of the crop in the full frame.
    pub x0: f64,
    pub y0: f64,
    pub data: Vec<Vec<u8>>,
}

fn mat_of(w: usize, h: usize, data: &[u8]) -> Result<Mat> {
    let m = Mat::new_rows_cols_with_data(h as i32, w as i32, data)?;
    Ok(m.try_clone()?)
}

struct FrameLine {
    line: Line,
    /// Inlier pixels (shrunk coordinates) with weights.
    pts: Vec<(Pt, f64)>,
}

/// The longest straight segments of the pixels `bin` keeps (non-zero) of one evidence
/// image (up to three, in different directions), each refined by an orthogonal fit of
/// the kept pixels along it, weighted by their evidence.
fn frame_lines(evidence: &impl MatTraitConst, bin: &Mat, min_len: f64) -> Result<Vec<FrameLine>> {
    let mut segs = Vector::<core::Vec4i>::new();
    imgproc::hough_lines_p(
        bin,
        &mut segs,
        1.0,
        std::f64::consts::PI / 360.0,
        (min_len * 0.5).max(10.0) as i32,
        min_len,
        4.0,
    )?;
    let mut segs: Vec<(Pt, Pt)> = segs
        .iter()
        .map(|v| {
            (
                Pt::new(v[0] as f64, v[1] as f64),
                Pt::new(v[2] as f64, v[3] as f64),
            )
        })
        .collect();
    segs.sort_by(|a, b| (b.1 - b.0).norm().total_cmp(&(a.1 - a.0).norm()));
    let mut chosen: Vec<(Pt, Pt)> = Vec::new();
    for sg in segs {
        let d = (sg.1 - sg.0).normalize();
        if chosen
            .iter()
            .all(|c| (c.1 - c.0).normalize().dot(&d).abs() < 8f64.to_radians().cos())
        {
            chosen.push(sg);
            if chosen.len() == 3 {
                break;
            }
        }
    }
    if chosen.is_empty() {
        return Ok(Vec::new());
    }
    let mut nz = Vector::<Point>::new();
    core::find_non_zero(bin, &mut nz)?;
    let mut out = Vec::new();
    for (p0, p1) in chosen {
        let seg = Line::through(p0, p1);
        let len = (p1 - p0).norm();
        // The thresholded pixels within 1.5 px of the segment's line, over its extent.
        let mut pts = Vec::new();
        for p in nz.iter() {
            let q = Pt::new(p.x as f64, p.y as f64);
            let along = (q - p0).dot(&seg.dir);
            if seg.distance(q) <= 1.5 && along >= -0.1 * len && along <= 1.1 * len {
                let w = *evidence.at_2d::<u8>(p.y, p.x)? as f64;
                pts.push((q, w));
            }
        }
        if let Some(line) = fit_line_weighted(&pts) {
            out.push(FrameLine { line, pts });
        }
    }
    Ok(out)
}

/// Each pixel's noise in the first seconds: the median of its frame-to-frame changes
/// (a passing wire is rare at any one pixel, so it does not move the median), found by
/// the streaming ±1 median. Flickering edges and compression noise come out higher
/// than a flat wall.
pub fn noise_map(init: &InitFrames) -> Vec<u8> {
    let mut med = vec![0u8; init.w * init.h];
    // A running median: one grey level towards each new value (branch-free, so that
    // it vectorises).
    for pair in init.data.windows(2) {
        for ((m, a), b) in med.iter_mut().zip(&pair[0]).zip(&pair[1]) {
            let d = a.abs_diff(*b);
            *m = *m + u8::from(d > *m) - u8::from(d < *m);
        }
    }
    med
}

/// Per-pixel detection threshold, `sigmas` above each pixel's noise ([`noise_map`]),
/// at least `floor` grey levels.
pub fn threshold_map(init: &InitFrames, noise: &[u8], sigmas: f64, floor: f64) -> Result<Mat> {
    // median |I_t - I_t-1| = 0.95 sigma for Gaussian noise; the running-extreme
    // background adds about two sigma of its own.
    let t: Vec<u8> = noise
        .iter()
        .map(|&m| {
            let sigma = (m as f64 / 0.95).max(1.0);
            ((sigmas + 2.0) * sigma).clamp(floor, 250.0) as u8
        })
        .collect();
    Ok(Mat::new_rows_cols_with_data(init.h as i32, init.w as i32, &t)?.try_clone()?)
}

/// Frame `k` of the first look as an image.
pub fn frame_mat(init: &InitFrames, k: usize) -> Result<Mat> {
    mat_of(init.w, init.h, &init.data[k])
}

/// Each pixel's maximum (`dark`) or minimum over the frames: the background of a dark
/// or light wire, as the streaming pass starts it.
pub fn extreme_frame(init: &InitFrames, dark: bool) -> Result<Mat> {
    let mut out = init.data[0].clone();
    for d in &init.data[1..] {
        for (o, &v) in out.iter_mut().zip(d) {
            *o = if dark { (*o).max(v) } else { (*o).min(v) };
        }
    }
    mat_of(init.w, init.h, &out)
}

/// Each pixel's median over the frames (the upper median for an even count).
pub fn median_frame(init: &InitFrames) -> Vec<u8> {
    let n = init.w * init.h;
    let k = init.data.len() / 2;
    let mut out = vec![0u8; n];
    // Work in runs of pixels so that each frame's bytes are read in order.
    const RUN: usize = 256;
    let mut col = vec![0u8; RUN * init.data.len()];
    for start in (0..n).step_by(RUN) {
        let len = RUN.min(n - start);
        for (f, d) in init.data.iter().enumerate() {
            for (i, &v) in d[start..start + len].iter().enumerate() {
                col[i * init.data.len() + f] = v;
            }
        }
        for (i, o) in out[start..start + len].iter_mut().enumerate() {
            let c = &mut col[i * init.data.len()..(i + 1) * init.data.len()];
            *o = *c.select_nth_unstable(k).1;
        }
    }
    out
}

/// What the first look compares each frame with.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Background {
    /// Each pixel's maximum (dark wire) or minimum over the look, as the streaming pass
    /// does: the wire stands out wherever it passes, over the bob too.
    Extreme,
    /// Each pixel's median: the trail of everything bright or dark that passed (a
    /// bob's rim, its glints) is gone, at the price of the wire where the bob dwells.
    Median,
}

/// Widest sweep of a pendulum's wire seen in the first look: lines that fan out over
/// more than this are an outline (a bob's trail), not a wire.
const MAX_SWEEP_DEG: f64 = 120.0;

/// Find polarity, pivot, band and ROI from the first seconds' frames: against the
/// running extreme first, which sees the most of the wire; when that finds no wire, or
/// lines no pendulum makes (a sweep wider than [`MAX_SWEEP_DEG`]), against the median.
pub fn find(
    init: &InitFrames,
    noise: &[u8],
    full_w: u32,
    full_h: u32,
    polarity: Polarity,
    pivot_given: Option<Pt>,
    roi_given: Option<Roi>,
) -> Result<WireGeometry> {
    if init.data.len() < 5 {
        bail!("too few frames ({}) to find the wire", init.data.len());
    }
    let plausible = |g: &WireGeometry| {
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!(
                "geometry: sweep {:.1} deg, {} jumps, roughness {:.3}",
                sweep_deg(g),
                g.jumps,
                g.roughness
            );
        }
        pivot_given.is_some()
            || (sweep_deg(g) <= MAX_SWEEP_DEG
                && g.jumps <= MAX_JUMPS
                && g.roughness <= MAX_ROUGHNESS)
    };
    // A faint wire (a pixel wide, a few grey levels darker than the plate) leaves too
    // few pixels above the first threshold to make a line, and a wire seen in a few
    // frames only is outvoted by stray edges: when neither background finds a wire a
    // pendulum could be, the look is repeated with a lower threshold.
    let mut first_reason = None;
    // Whether every look's reason was "no moving wire found": lines in too few frames,
    // too few directions or too few meeting in one point (not lines that make something
    // else: no common pivot, a sweep, jumps or turns no pendulum makes). Of a look
    // against both backgrounds, the reason against the extreme is the one judged.
    let mut saw_little = true;
    for (t, (sigmas, floor, min_directions)) in LOOK_THRESHOLDS.into_iter().enumerate() {
        let look = Look {
            init,
            tmap: threshold_map(init, noise, sigmas, floor)?,
            min_directions,
            faint: false,
            full_w,
            full_h,
            polarity,
            pivot_given,
            roi_given,
        };
        match look_both(&look, &plausible) {
            Ok(g) => {
                return Ok(WireGeometry {
                    stage: 2 * t + g.stage,
                    ..g
                })
            }
            Err(e) => {
                if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                    eprintln!("geometry: {e:#}; now with a lower threshold");
                }
                saw_little &= format!("{e:#}").starts_with(NO_WIRE);
                first_reason.get_or_insert(e);
            }
        }
    }
    // A wire so faint that no threshold keeps enough of it to make a segment (a pixel
    // wide, a few grey levels, under flicker) still darkens a whole line of pixels a
    // little: the last look finds each frame's lines along whole lines of the image,
    // against the median (which holds no trails at so low a threshold). Only when the
    // looks saw too little (`saw_little`): lines that make something other than a wire
    // are a scene the faint look would not read better.
    if !saw_little {
        return Err(first_reason.expect("one threshold tried"));
    }
    let look = Look {
        init,
        tmap: faint_threshold_map(init, noise)?,
        min_directions: FAINT_MIN_DIRECTIONS,
        faint: true,
        full_w,
        full_h,
        polarity,
        pivot_given,
        roi_given,
    };
    match find_against(&look, Background::Median) {
        Ok(g) if plausible(&g) => Ok(WireGeometry {
            stage: FAINT_STAGE,
            ..g
        }),
        other => {
            if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                match other {
                    Ok(g) => eprintln!(
                        "geometry: the faint look's lines sweep {:.0} deg, {} jumps",
                        sweep_deg(&g),
                        g.jumps
                    ),
                    Err(e) => eprintln!("geometry: the faint look: {e:#}"),
                }
            }
            Err(first_reason.expect("one threshold tried"))
        }
    }
}

/// [`WireGeometry::stage`] of a wire found by the faint look.
pub const FAINT_STAGE: usize = 4;

/// The faint look's threshold: this many noise sigmas above the median (no allowance
/// for the running extreme's own offset), at least one grey level.
const FAINT_SIGMAS: f64 = 1.5;

/// Directions the faint look's lines must take (its threshold lets the noise through).
const FAINT_MIN_DIRECTIONS: usize = 8;

/// A faint line's votes, as a share of the shortest wire: its pixels over the faint
/// threshold along it.
const FAINT_VOTES: f64 = 0.5;

/// The strongest lines of a frame the faint look weighs, and the widest gap (px) along
/// one between pixels over its threshold that still joins them into one wire: the
/// noise that passes the faint threshold (a few pixels in a hundred) leaves wider gaps.
const FAINT_CANDIDATES: usize = 12;
const FAINT_GAP: f64 = 3.0;

/// The faint look's per-pixel threshold ([`FAINT_SIGMAS`]).
fn faint_threshold_map(init: &InitFrames, noise: &[u8]) -> Result<Mat> {
    let t: Vec<u8> = noise
        .iter()
        .map(|&m| (FAINT_SIGMAS * (m as f64 / 0.95).max(1.0)).clamp(1.0, 250.0) as u8)
        .collect();
    Ok(Mat::new_rows_cols_with_data(init.h as i32, init.w as i32, &t)?.try_clone()?)
}

/// A faint wire's lines in one frame: the strongest lines of `bin` (its pixels over
/// the faint threshold) by the standard Hough transform, which counts every pixel along
/// a whole line of the image however broken; on each (up to three, in distinct
/// directions), the longest run of those pixels within 1.5 px of it with no gap over
/// [`FAINT_GAP`], kept when at least `min_len` long and fitted (orthogonal least
/// squares, weighted by the evidence `ev`) as [`frame_lines`] fits a segment.
fn faint_frame_lines(ev: &impl MatTraitConst, bin: &Mat, min_len: f64) -> Result<Vec<FrameLine>> {
    let mut found = Vector::<core::Vec2f>::new();
    imgproc::hough_lines_def(
        bin,
        &mut found,
        1.0,
        std::f64::consts::PI / 360.0,
        (FAINT_VOTES * min_len).max(10.0) as i32,
    )?;
    if found.is_empty() {
        return Ok(Vec::new());
    }
    let mut nz = Vector::<Point>::new();
    core::find_non_zero(bin, &mut nz)?;
    let mut dirs: Vec<Pt> = Vec::new();
    let mut out = Vec::new();
    // Strongest first (the transform sorts its lines by their votes).
    for v in found.iter().take(FAINT_CANDIDATES) {
        let (rho, th) = (v[0] as f64, v[1] as f64);
        let normal = Pt::new(th.cos(), th.sin());
        let dir = Pt::new(-th.sin(), th.cos());
        if dirs
            .iter()
            .any(|d| d.dot(&dir).abs() >= 8f64.to_radians().cos())
        {
            continue;
        }
        let line = Line {
            point: normal * rho,
            dir,
        };
        let mut along: Vec<(f64, Pt)> = nz
            .iter()
            .map(|p| Pt::new(p.x as f64, p.y as f64))
            .filter(|q| line.distance(*q) <= 1.5)
            .map(|q| ((q - line.point).dot(&dir), q))
            .collect();
        along.sort_by(|a, b| a.0.total_cmp(&b.0));
        // The longest run with no gap over FAINT_GAP: [from, to).
        let (mut best, mut from) = ((0usize, 0usize), 0usize);
        for to in 1..=along.len() {
            if to == along.len() || along[to].0 - along[to - 1].0 > FAINT_GAP {
                let len = |(a, b): (usize, usize)| {
                    if b > a {
                        along[b - 1].0 - along[a].0
                    } else {
                        -1.0
                    }
                };
                if len((from, to)) > len(best) {
                    best = (from, to);
                }
                from = to;
            }
        }
        let (a, b) = best;
        if b <= a || along[b - 1].0 - along[a].0 < min_len {
            continue;
        }
        dirs.push(dir);
        let mut pts = Vec::with_capacity(b - a);
        for (_, q) in &along[a..b] {
            let w = *ev.at_2d::<u8>(q.y as i32, q.x as i32)? as f64;
            pts.push((*q, w));
        }
        if let Some(fit) = fit_line_weighted(&pts) {
            out.push(FrameLine { line: fit, pts });
        }
        if out.len() == 3 {
            break;
        }
    }
    Ok(out)
}

/// The first look's thresholds, in turn: noise sigmas above each pixel's noise, a
/// floor in grey levels, and the directions the lines must take (a low threshold
/// lets the noise make lines too: those do not turn with a pendulum).
const LOOK_THRESHOLDS: [(f64, f64, usize); 2] = [(4.0, 6.0, 0), (2.0, 4.0, 8)];

/// How the reason for a look that found no line at all begins.
const NO_WIRE: &str = "no moving wire found";

/// One threshold's look against the extreme, then (no wire, or an implausible one)
/// against the median.
fn look_both(look: &Look, plausible: &dyn Fn(&WireGeometry) -> bool) -> Result<WireGeometry> {
    let first = match find_against(look, Background::Extreme) {
        Ok(g) if plausible(&g) => return Ok(WireGeometry { stage: 0, ..g }),
        first => first,
    };
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        match &first {
            Ok(g) => eprintln!(
                "geometry: sweep {:.0} deg against the extreme; now against the median",
                sweep_deg(g)
            ),
            Err(e) => eprintln!("geometry: {e:#}; now against the median"),
        }
    }
    match (find_against(look, Background::Median), first) {
        (Ok(g), _) if plausible(&g) => Ok(WireGeometry { stage: 1, ..g }),
        // Neither look found a wire: the first one's reason.
        (Err(_), Err(e)) => Err(e),
        (Ok(g), _) | (Err(_), Ok(g)) if g.jumps > MAX_JUMPS => bail!(
            "the moving lines jump back and forth across {:.0} deg between frames ({} times), \
             unlike a pendulum's wire; give `video.pivot`",
            sweep_deg(&g),
            g.jumps
        ),
        (Ok(g), _) | (Err(_), Ok(g)) if g.roughness > MAX_ROUGHNESS => bail!(
            "the moving lines turn irregularly from frame to frame (roughness {:.2}, a \
             swinging wire's is under {MAX_ROUGHNESS}); give `video.pivot`",
            g.roughness
        ),
        (Ok(g), _) | (Err(_), Ok(g)) => bail!(
            "the moving lines sweep {:.0} deg, more than a pendulum's wire; give `video.pivot`",
            sweep_deg(&g)
        ),
    }
}

/// Lines through one pivot that make a wire (with `video.pivot` given, three do).
const MIN_WIRE_LINES: usize = 6;

/// Jumps a first look may show and still be a pendulum's wire ([`jumps`]).
const MAX_JUMPS: usize = 1;

/// How often the wire's angle jumps by more than half of `sweep` between two frames
/// looked at one after the other (`stride` frames apart). A wire does not: moving half
/// its sweep within one look's step (at most a tenth of a second) takes a pendulum of
/// a period under 0.7 s. Lines that alternate between two structures (the wire and a
/// static edge, or two edges of a stripe) do, as soon as both are seen; a wire seen
/// only near its turning points (blurred in mid swing) leaves frames without a line
/// between the two, and no jump.
fn jumps(angles: &[Option<f64>], stride: usize, sweep: f64) -> usize {
    seen_in_steps(angles, stride)
        .windows(2)
        .filter(|p| p[1].0 - p[0].0 == 1.0 && (p[1].1 - p[0].1).abs() > 0.5 * sweep)
        .count()
}

/// The frames that gave a line, as (time in look steps of `stride` frames, angle).
fn seen_in_steps(angles: &[Option<f64>], stride: usize) -> Vec<(f64, f64)> {
    angles
        .iter()
        .enumerate()
        .filter_map(|(k, a)| a.map(|a| (k as f64 / stride as f64, a)))
        .collect()
}

/// The roughness a first look may show and still be a pendulum's wire ([`roughness`]).
const MAX_ROUGHNESS: f64 = 0.35;

/// How irregularly the angle turns: the RMS second divided difference of the angles
/// of three lines seen one after the other (at most four looks apart; in units of the
/// look's step, `stride` frames), against the range of the middle 80 % of all the
/// angles (one stray line does not widen it). A swinging wire turns smoothly: its
/// second derivative is at most `omega^2` times its amplitude, so per look step
/// (under a tenth of a second) under 0.2 of its range for any period over 1 s; lines
/// that jitter about one direction (edges of a test pattern, a static stripe) score
/// near 0.5 and more. `0` when fewer than five triples were seen (nothing to judge).
fn roughness(angles: &[Option<f64>], stride: usize) -> f64 {
    let seen = seen_in_steps(angles, stride);
    let d2: Vec<f64> = seen
        .windows(3)
        .filter(|w| w[2].0 - w[0].0 <= 4.0)
        .map(|w| {
            let (h1, h2) = (w[1].0 - w[0].0, w[2].0 - w[1].0);
            let dd = 2.0 * ((w[2].1 - w[1].1) / h2 - (w[1].1 - w[0].1) / h1) / (h1 + h2);
            dd * dd
        })
        .collect();
    if d2.len() < 5 {
        return 0.0;
    }
    let mut sorted: Vec<f64> = seen.iter().map(|s| s.1).collect();
    sorted.sort_by(f64::total_cmp);
    let q = |p: f64| sorted[((sorted.len() - 1) as f64 * p).round() as usize];
    let range = (q(0.9) - q(0.1)).max(1e-9);
    (d2.iter().sum::<f64>() / d2.len() as f64).sqrt() / range
}

/// The range of directions the first look's wire lines cover, deg, on the branch
/// about their circular mean: a bob's outline fans out over most of the circle.
fn sweep_deg(g: &WireGeometry) -> f64 {
    (g.theta_max - g.theta_min).to_degrees()
}

/// The half-degree bin of a line's direction (modulo half a turn), as the first look
/// counts the directions its lines take.
fn direction_bin(l: &FrameLine) -> i64 {
    (l.line
        .dir
        .y
        .atan2(l.line.dir.x)
        .rem_euclid(std::f64::consts::PI)
        .to_degrees()
        * 2.0) as i64
}

/// The second polarity's look against the first's directions (`beat`): it is given up
/// as soon as the directions seen so far, one more for each frame still to look at,
/// cannot reach `beat` (a frame adds at most one direction, its longest line's), since
/// it could then not win (the score is directions first). A frame it no longer looks
/// at cannot fail it either: an error OpenCV would have raised there goes unsaid, as
/// the polarity's result would have gone unused. Without `beat` (the first polarity)
/// it is never given up. Shared by the look's threads.
struct Race {
    beat: Option<usize>,
    /// Frames the look searches for lines (every `stride`-th).
    to_look_at: usize,
    /// The directions seen so far and the frames looked at.
    seen: std::sync::Mutex<(std::collections::BTreeSet<i64>, usize)>,
    lost: std::sync::atomic::AtomicBool,
}

impl Race {
    fn new(beat: Option<usize>, to_look_at: usize) -> Self {
        Self {
            beat,
            to_look_at,
            seen: Default::default(),
            lost: Default::default(),
        }
    }

    /// A frame looked at, with its longest line if any.
    fn looked(&self, longest: Option<&FrameLine>) {
        let Some(beat) = self.beat else {
            return;
        };
        let mut seen = self.seen.lock().expect("no thread panics holding it");
        if let Some(l) = longest {
            seen.0.insert(direction_bin(l));
        }
        seen.1 += 1;
        if seen.0.len() + (self.to_look_at - seen.1) < beat {
            self.lost.store(true, std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// Whether the look is given up.
    fn lost(&self) -> bool {
        self.lost.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// One first look's inputs, tried against either background.
struct Look<'a> {
    init: &'a InitFrames,
    /// Per-pixel detection threshold.
    tmap: Mat,
    /// Directions (half-degree bins) the lines must take to be a moving wire.
    min_directions: usize,
    /// Each frame's lines found along whole lines of the image ([`faint_frame_lines`]),
    /// not as segments of pixels over the threshold ([`frame_lines`]).
    faint: bool,
    full_w: u32,
    full_h: u32,
    polarity: Polarity,
    pivot_given: Option<Pt>,
    roi_given: Option<Roi>,
}

/// One geometry thread's buffers for a frame's lines ([`find_against`]), kept from frame
/// to frame: an image the size of the look allocated afresh for every frame costs its
/// pages' faults each time.
#[derive(Default)]
struct Scratch {
    ev: Mat,
    morph: super::morph::Morph,
    top: Vec<u8>,
    keep: Mat,
}

/// One first look against `kind` of background.
fn find_against(look: &Look, kind: Background) -> Result<WireGeometry> {
    let Look {
        init,
        ref tmap,
        min_directions,
        faint,
        full_w,
        full_h,
        polarity,
        pivot_given,
        roi_given,
    } = *look;
    let (w, h) = (init.w, init.h);
    let median = match kind {
        Background::Median => Some(mat_of(w, h, &median_frame(init))?),
        Background::Extreme => None,
    };
    // The wire is long; the bob's edges and a hand's fingers are short.
    let min_len = 0.2 * (w.min(h) as f64);
    let candidates: Vec<bool> = match polarity {
        Polarity::Dark => vec![true],
        Polarity::Light => vec![false],
        Polarity::Auto => vec![true, false],
    };
    // Per frame (every `stride`-th, at most about 60 looked at closely), the longest
    // straight thin structures darker (`dark`) or brighter than `bg`.
    let stride = init.data.len().div_ceil(60).max(1);
    let frame_lines_against =
        |bg: &Mat, dark: bool, k: usize, sc: &mut Scratch| -> Result<Vec<FrameLine>> {
            if !k.is_multiple_of(stride) {
                return Ok(Vec::new());
            }
            let f = Mat::new_rows_cols_with_data(h as i32, w as i32, &init.data[k])?;
            if dark {
                core::subtract_def(bg, &f, &mut sc.ev)?;
            } else {
                core::subtract_def(&f, bg, &mut sc.ev)?;
            }
            sc.morph.tophat(sc.ev.data_bytes()?, w, h, &mut sc.top);
            let th = Mat::new_rows_cols_with_data(h as i32, w as i32, &sc.top)?;
            // Keep what exceeds each pixel's own noise threshold (at least one grey level).
            core::compare(&th, tmap, &mut sc.keep, core::CMP_GT)?;
            if faint {
                faint_frame_lines(&th, &sc.keep, min_len)
            } else {
                frame_lines(&th, &sc.keep, min_len)
            }
        };
    // The frames' lines, each frame alone: shared among up to [`GEOMETRY_THREADS`]
    // processors (the look's geometry is most of the detector's fixed cost on a short
    // video), in the frames' order; `None` when `race` gave the polarity up.
    let looked_at = (0..init.data.len())
        .filter(|k| k.is_multiple_of(stride))
        .count();
    let lines_against =
        |bg: &Mat, dark: bool, race: &Race| -> Result<Option<Vec<Vec<FrameLine>>>> {
            let n = init.data.len();
            let workers = std::thread::available_parallelism()
                .map_or(1, |p| p.get())
                .clamp(1, GEOMETRY_THREADS);
            let per = n.div_ceil(workers).max(1);
            let parts: Vec<Result<Vec<Vec<FrameLine>>>> = std::thread::scope(|s| {
                let handles: Vec<_> = (0..n)
                    .step_by(per)
                    .map(|from| {
                        let work = &frame_lines_against;
                        s.spawn(move || {
                            let mut scratch = Scratch::default();
                            (from..(from + per).min(n))
                                .take_while(|_| !race.lost())
                                .map(|k| {
                                    let lines = work(bg, dark, k, &mut scratch)?;
                                    if k.is_multiple_of(stride) {
                                        race.looked(lines.first());
                                    }
                                    Ok(lines)
                                })
                                .collect::<Result<Vec<_>>>()
                        })
                    })
                    .collect();
                handles
                    .into_iter()
                    .map(|h| h.join().expect("a geometry thread panicked"))
                    .collect()
            });
            let mut lines = Vec::with_capacity(n);
            for part in parts {
                lines.extend(part?);
            }
            Ok((!race.lost()).then_some(lines))
        };
    let mut best: Option<(bool, f64, Vec<Vec<FrameLine>>)> = None;
    for &dark in &candidates {
        let race = Race::new(best.as_ref().map(|b| (b.1 / 1e9) as usize), looked_at);
        let lines = match &median {
            Some(m) => lines_against(m, dark, &race)?,
            None => lines_against(&extreme_frame(init, dark)?, dark, &race)?,
        };
        let Some(lines) = lines else {
            if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                eprintln!(
                    "geometry: dark={dark} cannot take {} directions; not looked at further",
                    race.beat.unwrap_or(0)
                );
            }
            continue;
        };
        // The wire moves: its lines take many directions. A ghost (the background's
        // memory of something of the other polarity lingering at a turning point) keeps
        // one. Score = directions seen (half-degree bins), then the evidence's weight
        // (far under 1e9: a frame's longest line holds a few thousand pixels of at most
        // 255, and a look has at most about 60 frames).
        let mut bins = std::collections::BTreeSet::new();
        let mut weight = 0.0;
        for l in lines.iter().filter_map(|v| v.first()) {
            bins.insert(direction_bin(l));
            weight += l.pts.iter().map(|p| p.1).sum::<f64>();
        }
        let total = bins.len() as f64 * 1e9 + weight;
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!(
                "geometry: dark={dark} lines={} directions={} weight={weight:.0}",
                lines.iter().filter(|v| !v.is_empty()).count(),
                bins.len()
            );
        }
        if best.as_ref().is_none_or(|b| total > b.1) {
            best = Some((dark, total, lines));
        }
    }
    let (dark, total, lines) = best.expect("one polarity tried");
    let directions = (total / 1e9) as usize;
    if directions < min_directions {
        bail!(
            "{NO_WIRE} in the first {} frames (the lines take only {directions} directions)",
            init.data.len()
        );
    }
    let found: Vec<Seen> = lines.iter().flatten().map(Seen::of).collect();
    let with_lines = lines.iter().filter(|v| !v.is_empty()).count();
    if with_lines < 3 {
        bail!(
            "{NO_WIRE} in the first {} frames (lines seen in {with_lines} of them)",
            init.data.len()
        );
    }
    let origin = Pt::new(init.x0, init.y0);
    let to_full = |p: Pt| shrunk_to_full(p, origin, init.shrink);
    // Pivot: the robust intersection of the lines (shrunk coordinates).
    let center = Pt::new(w as f64 / 2.0, h as f64 / 2.0);
    let base_tol = 2.0f64.max(0.005 * (w.max(h) as f64));
    let pivot_s = match pivot_given {
        Some(p) => full_to_shrunk(p, origin, init.shrink),
        None => match ransac_pivot(&found, center, base_tol) {
            Some(p) => p,
            None => bail!("the moving lines do not meet in a pivot; give `video.pivot`"),
        },
    };
    // Per frame, the line through the pivot (if any).
    let tol = 2.0 * through_tol(pivot_s, center, base_tol);
    let per_frame: Vec<Option<&FrameLine>> = lines
        .iter()
        .map(|v| {
            v.iter()
                .filter(|f| Seen::of(f).points_at(pivot_s, tol))
                .min_by(|a, b| {
                    a.line
                        .distance(pivot_s)
                        .total_cmp(&b.line.distance(pivot_s))
                })
        })
        .collect();
    let good: Vec<&FrameLine> = per_frame.iter().flatten().copied().collect();
    if good.len() < 3 {
        match pivot_given {
            Some(p) => bail!(
                "no moving line passes through the given pivot ({:.1}, {:.1}) px ({} frames \
                 with lines); check `video.pivot` (or --pivot): the point the wire turns about, \
                 in the video's full-size pixels",
                p.x,
                p.y,
                with_lines
            ),
            None => {
                bail!("the moving lines do not share a pivot; give `video.pivot` (and `video.roi`)")
            }
        }
    }
    // Too few lines to tell a swinging wire from a few stray edges that happen to meet.
    if good.len() < MIN_WIRE_LINES && pivot_given.is_none() {
        bail!(
            "{NO_WIRE} in the first {} frames (only {} lines meet in a pivot)",
            init.data.len(),
            good.len()
        );
    }
    let mut radii: Vec<f64> = good
        .iter()
        .flat_map(|f| f.pts.iter().map(|(q, _)| (*q - pivot_s).norm()))
        .collect();
    radii.sort_by(f64::total_cmp);
    let pct = |p: f64| radii[((radii.len() - 1) as f64 * p) as usize];
    let (r_lo, r_hi) = (pct(0.08) * 0.97, pct(0.98) * 1.02);
    let angle_of = |f: &FrameLine| {
        let c = f.line.point - pivot_s;
        let d = if c.dot(&f.line.dir) >= 0.0 {
            f.line.dir
        } else {
            -f.line.dir
        };
        d.y.atan2(d.x)
    };
    // The rest direction: the circular mean of the wire's directions. Every angle is
    // taken on its branch (within half a turn of it), so a wire that hangs towards -x
    // (a camera at any roll) sweeps a few degrees about 180, not 359 across +-180.
    let (sin, cos) = good.iter().fold((0.0, 0.0), |(s, c), f| {
        let a = angle_of(f);
        (s + a.sin(), c + a.cos())
    });
    let rest = sin.atan2(cos);
    let initial_angles: Vec<Option<f64>> = per_frame
        .iter()
        .map(|l| l.map(|f| unwrap_near(angle_of(f), rest)))
        .collect();
    let mut thetas: Vec<f64> = good
        .iter()
        .map(|f| unwrap_near(angle_of(f), rest))
        .collect();
    thetas.sort_by(f64::total_cmp);
    let (theta_min, theta_max) = (thetas[0], thetas[thetas.len() - 1]);
    if theta_max - theta_min < 1f64.to_radians() && pivot_given.is_none() {
        bail!(
            "the wire moved by only {:.2} deg in the first frames: too little to locate its pivot; give `video.pivot`",
            (theta_max - theta_min).to_degrees()
        );
    }
    // ROI: the sector the wire can sweep (its angles so far plus a margin), in the band.
    let pivot = to_full(pivot_s);
    let (r_lo_f, r_hi_f) = (r_lo * init.shrink, r_hi * init.shrink);
    let margin = 10f64.to_radians();
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for i in 0..=40 {
        let th = theta_min - margin + (theta_max - theta_min + 2.0 * margin) * i as f64 / 40.0;
        for r in [r_lo_f, r_hi_f] {
            let p = pivot + Pt::new(th.cos(), th.sin()) * r;
            x0 = x0.min(p.x);
            y0 = y0.min(p.y);
            x1 = x1.max(p.x);
            y1 = y1.max(p.y);
        }
    }
    let pad = 8.0;
    let bound = roi_given.unwrap_or(Roi {
        x: 0,
        y: 0,
        w: full_w,
        h: full_h,
    });
    let cx0 = (x0 - pad).floor().max(bound.x as f64) as u32;
    let cy0 = (y0 - pad).floor().max(bound.y as f64) as u32;
    let cx1 = ((x1 + pad).ceil() as u32).min(bound.x + bound.w);
    let cy1 = ((y1 + pad).ceil() as u32).min(bound.y + bound.h);
    if cx1 <= cx0 + 8 || cy1 <= cy0 + 8 {
        bail!("the wire's region lies outside the frame");
    }
    // Sizes that are multiples of 2 (every decoder crops those exactly) and of the
    // shrink factor (so that the streaming pass's grid is exactly `shrink` times
    // coarser along both axes, as its coordinate mapping assumes).
    let s = init.shrink as u32;
    let m = if s.is_multiple_of(2) { s } else { 2 * s };
    let size = |lo: u32, hi: u32, limit: u32| {
        let n = (hi - lo) / m * m;
        if n > 0 {
            n
        } else if lo + m <= limit {
            m
        } else {
            0
        }
    };
    let roi = Roi {
        x: cx0,
        y: cy0,
        w: size(cx0, cx1, bound.x + bound.w),
        h: size(cy0, cy1, bound.y + bound.h),
    };
    if roi.w == 0 || roi.h == 0 {
        bail!("the wire's region is too small at the frame's edge");
    }
    if std::env::var("ROLLFRIC_DEBUG").is_ok_and(|v| v == "angles") {
        for (k, a) in initial_angles.iter().enumerate() {
            if let Some(a) = a {
                eprintln!("look {k} {:.2}", a.to_degrees());
            }
        }
    }
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "geometry: pivot {pivot:?} band {r_lo_f:.1}..{r_hi_f:.1} theta {:.1}..{:.1} deg roi {roi:?} good lines {}",
            theta_min.to_degrees(),
            theta_max.to_degrees(),
            good.len()
        );
    }
    Ok(WireGeometry {
        pivot,
        dark,
        r_lo: r_lo_f,
        r_hi: r_hi_f,
        theta_min,
        theta_max,
        roi,
        jumps: jumps(&initial_angles, stride, theta_max - theta_min),
        roughness: roughness(&initial_angles, stride),
        initial_angles,
        lines_used: good.len(),
        stage: 0,
    })
}

#[cfg(test)]
mod tests;
