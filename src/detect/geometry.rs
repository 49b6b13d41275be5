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

mod faint;
mod pivot;
mod search;

use crate::detect::tuning::{
    EDGE_MARGIN_SHARE, EDGE_MIN_PX, FAINT_MIN_DIRECTIONS, HOUGH_MAX_GAP_PX, HOUGH_MIN_VOTES,
    HOUGH_VOTE_SHARE, LINE_APART_DEG, LINE_PIXELS_PX, LOOK_DIRECTIONS, LOOK_FLOOR, LOOK_SIGMAS,
    LOW_DIRECTIONS, LOW_FLOOR, LOW_SIGMAS, MAX_JUMPS, MAX_ROUGHNESS, MAX_SWEEP_DEG,
    THRESHOLD_MAX_LEVELS,
};
use faint::faint_threshold_map;
pub use faint::FAINT_STAGE;
pub use pivot::intersect;
use pivot::{ransac_pivot, through_tol, Seen};
use search::find_against;

use super::{fit_line_weighted, full_to_shrunk, shrunk_to_full, unwrap_near, Line, Pt};
use crate::config::Polarity;
use crate::video::Roi;
use anyhow::{bail, Result};
use opencv::core::{self, Mat, Point, Vector};
use opencv::imgproc;
use opencv::prelude::*;

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
    /// A second pendulum's pivot, when another line swings through a pivot of its own
    /// (looked for only when neither `video.pivot` nor `video.roi` is given).
    pub second: Option<Pt>,
    /// Lines of the other polarity that swing about the same pivot as widely, off the
    /// wire's (looked for only when `video.polarity` is `auto`).
    pub rival: Option<RivalPolarity>,
}

/// Lines of the polarity the first look did not take that swing about the same pivot
/// in nearly as many directions (see `RIVAL_POLARITY_SHARE`), off the lines taken: a
/// light wire and its dark shadow, or the reverse. Which one is the wire the look
/// cannot tell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RivalPolarity {
    /// The rival lines are darker than the background.
    pub dark: bool,
    /// The directions their lines took, and the taken polarity's.
    pub directions: usize,
    pub of: usize,
    /// How far they lie from the lines taken, the median over the frames both see, and
    /// the spread between its quartiles, deg.
    pub offset_deg: f64,
    pub spread_deg: f64,
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

/// The edges of the video's frame that a look's frame shares, and how near one a line's
/// two ends must lie to run along it ([`EDGE_MARGIN_SHARE`]): an empty border that a
/// stabilised or software-turned picture shows moves with the picture, and its edge is
/// a moving line of the frame's own direction (the real off-screen pivot clip, turned
/// and shifted by ffmpeg: the look's pivot on the frame's corner, its lines at 0 and 90
/// deg).
#[derive(Clone, Copy, Debug)]
struct FrameEdges {
    /// The look frame's size, px.
    w: f64,
    h: f64,
    /// Left, top, right, bottom: whether the look frame's edge is the video's.
    shared: [bool; 4],
    margin: f64,
}

impl FrameEdges {
    fn of(init: &InitFrames, full_w: u32, full_h: u32) -> Self {
        let (w, h, s) = (init.w as f64, init.h as f64, init.shrink);
        let (fw, fh) = (f64::from(full_w), f64::from(full_h));
        FrameEdges {
            w,
            h,
            shared: [
                init.x0 < s,
                init.y0 < s,
                init.x0 + w * s > fw - 2.0 * s,
                init.y0 + h * s > fh - 2.0 * s,
            ],
            margin: (EDGE_MARGIN_SHARE * fw.min(fh) / s).max(EDGE_MIN_PX),
        }
    }

    /// Whether the segment from `a` to `b` (look px) runs along a shared edge.
    fn along(&self, a: Pt, b: Pt) -> bool {
        let m = self.margin;
        let near = [
            a.x.max(b.x) <= m,
            a.y.max(b.y) <= m,
            a.x.min(b.x) >= self.w - 1.0 - m,
            a.y.min(b.y) >= self.h - 1.0 - m,
        ];
        self.shared.iter().zip(near).any(|(s, n)| *s && n)
    }
}

/// The longest straight segments of the pixels `bin` keeps (non-zero) of one evidence
/// image (up to three, in different directions), each refined by an orthogonal fit of
/// the kept pixels along it, weighted by their evidence. A segment along an edge of the
/// frame (`edges`) is not one.
fn frame_lines(
    evidence: &impl MatTraitConst,
    bin: &Mat,
    min_len: f64,
    edges: &FrameEdges,
) -> Result<Vec<FrameLine>> {
    let mut segs = Vector::<core::Vec4i>::new();
    imgproc::hough_lines_p(
        bin,
        &mut segs,
        1.0,
        std::f64::consts::PI / 360.0,
        (min_len * HOUGH_VOTE_SHARE).max(HOUGH_MIN_VOTES) as i32,
        min_len,
        HOUGH_MAX_GAP_PX,
    )?;
    let mut segs: Vec<(Pt, Pt)> = segs
        .iter()
        .map(|v| {
            (
                Pt::new(v[0] as f64, v[1] as f64),
                Pt::new(v[2] as f64, v[3] as f64),
            )
        })
        .filter(|(a, b)| !edges.along(*a, *b))
        .collect();
    segs.sort_by(|a, b| (b.1 - b.0).norm().total_cmp(&(a.1 - a.0).norm()));
    let mut chosen: Vec<(Pt, Pt)> = Vec::new();
    for sg in segs {
        let d = (sg.1 - sg.0).normalize();
        if chosen
            .iter()
            .all(|c| (c.1 - c.0).normalize().dot(&d).abs() < LINE_APART_DEG.to_radians().cos())
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
            if seg.distance(q) <= LINE_PIXELS_PX && along >= -0.1 * len && along <= 1.1 * len {
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
            ((sigmas + 2.0) * sigma).clamp(floor, THRESHOLD_MAX_LEVELS) as u8
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

/// Each pixel's median over the frames (the upper median for an even count): the
/// `k`-th smallest of its `n` values, `k = n / 2`, found a bit at a time from the
/// highest, for a run of pixels at once. A value `v` is at most the median exactly when
/// at most `k` of the pixel's values lie below it, so the median is the largest `v` with
/// that count, and each bit of it is set when the count below the median's higher bits
/// with that bit set stays within `k`. Each of the eight bits reads every frame's run
/// once, comparing and counting whole runs of bytes (which the compiler does many at a
/// time), where selecting the median pixel by pixel sorted each pixel's own values: the
/// same bytes (test in `geometry/tests.rs`) in a sixth of the instructions (seed 1
/// scene 27 of the sweep: 544 to 97 M).
pub fn median_frame(init: &InitFrames) -> Vec<u8> {
    let k = init.data.len() / 2;
    // The counts need only tell whether they pass `k`: bytes that stop at 255 do,
    // twice as many at a time as 16-bit counts, for a look of up to 509 frames.
    match u8::try_from(k) {
        Ok(k) if k < u8::MAX => median_by_bits::<u8>(init, k.into()),
        _ => median_by_bits::<u16>(init, k as u32),
    }
}

/// How many of a pixel's values lie below a trial value, counted in `u8` or `u16`
/// (stopping at its largest value, which lies above the count looked for).
trait Count: Copy + Default {
    fn add(self, below: bool) -> Self;
    fn within(self, k: u32) -> bool;
}
macro_rules! count_in {
    ($($t:ty),*) => {$(
        impl Count for $t {
            #[inline(always)]
            fn add(self, below: bool) -> Self {
                self.saturating_add(<$t>::from(below))
            }
            #[inline(always)]
            fn within(self, k: u32) -> bool {
                u32::from(self) <= k
            }
        }
    )*};
}
count_in!(u8, u16);

/// [`median_frame`] with counts of type `C`, the median the `k`-th smallest value.
fn median_by_bits<C: Count>(init: &InitFrames, k: u32) -> Vec<u8> {
    let n = init.w * init.h;
    let mut out = vec![0u8; n];
    const RUN: usize = 1024;
    let (mut below, mut trial) = ([C::default(); RUN], [0u8; RUN]);
    for start in (0..n).step_by(RUN) {
        let len = RUN.min(n - start);
        let found = &mut out[start..start + len];
        for bit in (0..8).rev() {
            for (t, f) in trial.iter_mut().zip(found.iter()) {
                *t = *f | (1 << bit);
            }
            let (below, trial) = (&mut below[..len], &trial[..len]);
            below.fill(C::default());
            for d in &init.data {
                for ((c, &v), &t) in below.iter_mut().zip(&d[start..start + len]).zip(trial) {
                    *c = c.add(v < t);
                }
            }
            for ((f, &c), &t) in found.iter_mut().zip(below.iter()).zip(trial) {
                if c.within(k) {
                    *f = t;
                }
            }
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

/// What the first look is given ([`find`]): the experiment's polarity, pivot and
/// region, and whether it looks against the median alone.
#[derive(Clone, Copy, Debug)]
pub struct Asked {
    pub polarity: Polarity,
    pub pivot: Option<Pt>,
    pub roi: Option<Roi>,
    /// Against the median only, never the running extreme: a detection from a look
    /// against the extreme followed something that does not swing as a wire does (a
    /// large bob's stripes, whose trail the extreme keeps; see `detect_scaled`).
    pub median_only: bool,
}

/// Find polarity, pivot, band and ROI from the first seconds' frames: against the
/// running extreme first, which sees the most of the wire; when that finds no wire, or
/// lines no pendulum makes (a sweep wider than [`MAX_SWEEP_DEG`]), against the median
/// (against the median alone when [`Asked::median_only`]).
pub fn find(
    init: &InitFrames,
    noise: &[u8],
    full_w: u32,
    full_h: u32,
    asked: Asked,
) -> Result<WireGeometry> {
    let Asked {
        polarity,
        pivot: pivot_given,
        roi: roi_given,
        median_only,
    } = asked;
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
        match look_both(&look, &plausible, median_only) {
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

/// The first look's thresholds, in turn: noise sigmas above each pixel's noise, a
/// floor in grey levels, and the directions the lines must take (a low threshold
/// lets the noise make lines too: those do not turn with a pendulum).
const LOOK_THRESHOLDS: [(f64, f64, usize); 2] = [
    (LOOK_SIGMAS, LOOK_FLOOR, LOOK_DIRECTIONS),
    (LOW_SIGMAS, LOW_FLOOR, LOW_DIRECTIONS),
];

/// How the reason for a look that found no line at all begins.
const NO_WIRE: &str = "no moving wire found";

/// One threshold's look against the extreme, then (no wire, or an implausible one)
/// against the median; against the median alone when `median_only`.
fn look_both(
    look: &Look,
    plausible: &dyn Fn(&WireGeometry) -> bool,
    median_only: bool,
) -> Result<WireGeometry> {
    let first = match median_only {
        true => Err(anyhow::anyhow!(
            "{NO_WIRE}: not looked at against the extreme"
        )),
        false => find_against(look, Background::Extreme),
    };
    let first = match first {
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
        // Neither look found a wire: the first one's reason (the median's when it
        // was the only one).
        (Err(m), Err(_)) if median_only => Err(m),
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
pub fn sweep_deg(g: &WireGeometry) -> f64 {
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

#[cfg(test)]
mod tests;
