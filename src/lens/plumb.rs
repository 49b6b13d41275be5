//! The lens's coefficient from straight lines in the picture (`rollfric lens`): the
//! plumb-line method. Lines that are straight on the plate (a ruled or gridded sheet, a
//! table's edge, a protractor's base line, the wire itself) bend in the picture of a
//! wide lens; the coefficient `k1` of [`Lens`] is the one that straightens them.
//!
//! 1. **Edge points**: the picture smoothed (a 3x3 binomial), its grey gradient by
//!    central differences; points whose gradient is a local maximum across the edge and
//!    above a threshold, placed to a fraction of a pixel by a parabola through the
//!    gradient's size across the edge. Each keeps the edge's normal.
//! 2. **The coarse coefficient**: for each `k1` of a grid (steps of 0.05), every point
//!    and its normal are taken through the lens back to the plate, and the long straight
//!    lines found among them (step 3, within 1.5 px): the `k1` through which most points
//!    lie on such lines is the coarse one.
//! 3. **The lines**: seeded from the fullest bins of a vote (each point votes for the
//!    line through it: its normal's direction to a degree, its distance from the corner
//!    to 2 px), each line's points within 1.5 px (then 1 px) and a few degrees of the
//!    line fitted to them, grown twice; a line must be long (a fifth of the picture's
//!    shorter side) and hold enough points, densely along it ([`MIN_DENSITY`]: points in
//!    line by chance along a band of a compressed picture's noise are no line). The two
//!    edges of one drawn stroke are two such lines (their normals face apart) and count
//!    as one **stroke**; arcs and edges that are not straight on the plate fit badly and
//!    are dropped.
//! 4. **The fine coefficient**: the sum over the lines of the squared distances of their
//!    points from their own best line (each line refitted at each `k1`, total least
//!    squares), minimised by parabolas through three `k1`; lines found again and `k1`
//!    refined three times in all. Its uncertainty is the jackknife over the strokes
//!    (each left out once), so that a line that is not straight on the plate, or too
//!    few lines, shows as a wide uncertainty.

use super::Lens;
use crate::video::{FfmpegSource, Frame, FrameSource};
use anyhow::{bail, Result};
use edges::{Edgel, Gradients};
use std::path::Path;

/// The grid of the coarse search: `k1` from `-K1_MAX` to `K1_MAX` in `K1_STEP`.
const K1_MAX: f64 = 0.5;
const K1_STEP: f64 = 0.05;
/// Gradient threshold: this many times the picture's fifth-quantile gradient (its noise
/// and texture: a dense grid's own edges hold most of a picture's gradients above the
/// median), and at least `EDGE_MIN` grey levels per pixel. The first of
/// `EDGE_TIMES_QUANTILE` keeps the sharp edges only; where they hold too few straight
/// lines, the picture is looked at again under the next. A faint, soft grid (grey lines
/// 10 px apart, a little out of focus: a sweep twin's sheet at 640x480) has its edges
/// under six times the noise: one straight line was found at 6, eight at 4 (`k1` -0.078
/// fitted as -0.0785 +- 0.0035 over five frames).
const EDGE_QUANTILE: f64 = 0.2;
pub const EDGE_TIMES_QUANTILE: [f64; 3] = [6.0, 4.0, 3.0];
const EDGE_MIN: f64 = 3.0;
/// The coarse vote's bins: 1 deg of the normal's direction, 2 px of distance.
const VOTE_DEG: f64 = 1.0;
const VOTE_PX: f64 = 2.0;
/// A line's points lie within this of it (px) and turn by at most `GROW_DEG` from it.
const GROW_PX: [f64; 3] = [1.5, 1.0, 1.0];
const GROW_DEG: f64 = 6.0;
/// A line spans at least this share of the picture's shorter side ...
const MIN_EXTENT: f64 = 0.2;
/// ... and holds at least this many points ...
const MIN_POINTS: usize = 30;
/// ... and at least this many per px of its length: a ruled line is an edge along its
/// whole length, an edge point at most of its pixels (a twin's sheet at CRF 18: half of
/// its lines 0.56 or more, the least 0.26), where points scattered along a band and in
/// line by chance (a compressed picture's noise, its blocks' edges) are not (the same
/// sheet at CRF 39: a median of 0.05). Under heavy compression such bands outnumber
/// the grid's lines, and the coefficient that straightened them was any: that
/// 1920x1080 sheet, seen through `k1` -0.140, was fitted +0.32 +- 0.28 at CRF 39 (its
/// frames +0.50, 0.00, +0.46); a 640x480 MJPG sheet through -0.170 under the sweep's
/// CRF 34, -0.094 +- 0.128. Now -0.120 +- 0.024 and -0.186 +- 0.033. A quarter (0.25)
/// took too many of a compressed grid's own lines: a 640x480 sheet under CRF 34, fitted
/// +0.171 +- 0.061 before (`k1` +0.138) and +0.140 +- 0.003 now, was refused.
const MIN_DENSITY: f64 = 0.15;
/// At most this many lines (the fullest votes first).
const MAX_LINES: usize = 200;
/// A line whose points scatter about it by more than this many times the lines' median
/// scatter is not straight on the plate (an arc, a bent cable) and is dropped.
const DROP_TIMES_MEDIAN: f64 = 3.0;
/// Fewer strokes than this cannot say which way the picture bends.
const MIN_LINES: usize = 3;
/// The two edges of one stroke: parallel within this (deg) and this far apart at most
/// (px).
const STROKE_DEG: f64 = 3.0;
const STROKE_PX: f64 = 6.0;
/// A coefficient worth giving: at least this many times its uncertainty ...
const GIVE_TIMES_U: f64 = 3.0;
/// ... and at least this large (a phone's main lens: under 0.02).
const GIVE_MIN_K1: f64 = 0.03;

/// Whether a fitted coefficient is a lens to give (`video.lens`): clearly not zero, and
/// large enough to scale a swing near the frame's edge by a few tenths of a percent.
pub fn worth_giving(k1: f64, u_k1: f64) -> bool {
    k1.abs() >= GIVE_TIMES_U * u_k1 && k1.abs() >= GIVE_MIN_K1
}
/// Points taken at most (evenly spread) for the coarse search.
const COARSE_POINTS: usize = 40_000;

/// A grey picture, row-major, `w` bytes a row.
#[derive(Clone, Copy)]
pub struct Grey<'a> {
    pub data: &'a [u8],
    pub w: usize,
    pub h: usize,
}

/// The fitted coefficient and what it rests on.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Plumb {
    pub k1: f64,
    /// Standard uncertainty of `k1` (the jackknife over the lines).
    pub u_k1: f64,
    /// The straight lines used (strokes: a drawn line's two edges count once), and
    /// their edge points.
    pub lines: usize,
    pub points: usize,
    /// The points' scatter about their straightened lines, px (RMS).
    pub rms_px: f64,
    /// The coarse search's coefficient, and the scatter the same lines have through an
    /// undistorted view (`k1 = 0`), px (RMS): how much the lines bend.
    pub coarse_k1: f64,
    pub rms_straight_px: f64,
    /// The edges' threshold the lines were found at, times the picture's noise (the
    /// first of [`EDGE_TIMES_QUANTILE`] that held enough straight lines).
    pub edge_times: f64,
}

impl Plumb {
    /// Its lines were found only among faint edges (under the first threshold).
    pub fn faint(&self) -> bool {
        self.edge_times < EDGE_TIMES_QUANTILE[0]
    }
}

/// A video's frames fitted each on its own ([`fit_video`]).
#[derive(Debug, Clone, serde::Serialize)]
pub struct VideoFit {
    pub width: usize,
    pub height: usize,
    /// The frames' mean coefficient, and its standard uncertainty: the larger of the
    /// median of the frames' uncertainties and the frames' spread (the frames of one camera share a
    /// lens: their spread is what one frame's fit varies by, not an error of their mean
    /// that averaging would shrink).
    pub k1: f64,
    pub u_k1: f64,
    /// Each fitted frame: its index and its fit.
    pub frames: Vec<(u64, Plumb)>,
    /// The frames that could not be fitted, each with the reason.
    pub refused: Vec<String>,
}

/// The lens of the video (or still picture) at `path`: `frames` frames, every
/// `every`th from the first, each fitted on its own; refused when none can be.
pub fn fit_video(path: &Path, frames: usize, every: usize) -> Result<VideoFit> {
    if frames == 0 || every == 0 {
        bail!("frames to fit and their spacing: expected 1 or more");
    }
    let mut src = FfmpegSource::open(path, None, 1)?;
    let mut frame = Frame::default();
    let mut fits: Vec<(u64, Plumb)> = Vec::new();
    let mut refused = Vec::new();
    let (mut width, mut height) = (0, 0);
    while fits.len() + refused.len() < frames && src.next_frame(&mut frame)? {
        if frame.index % every as u64 != 0 {
            continue;
        }
        (width, height) = (frame.width, frame.height);
        let pic = Grey {
            data: &frame.data,
            w: width,
            h: height,
        };
        match fit(pic) {
            Ok(p) => fits.push((frame.index, p)),
            Err(e) => refused.push(format!("frame {}: {e}", frame.index)),
        }
    }
    let shown = path.display();
    if fits.is_empty() {
        match refused.first() {
            Some(r) => bail!("{shown}: the lens cannot be fitted: {r}"),
            None => bail!("{shown}: no frame decoded"),
        }
    }
    let n = fits.len() as f64;
    let k1 = fits.iter().map(|(_, p)| p.k1).sum::<f64>() / n;
    let spread = if fits.len() > 1 {
        (fits.iter().map(|(_, p)| (p.k1 - k1).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    let mut u: Vec<f64> = fits.iter().map(|(_, p)| p.u_k1).collect();
    Ok(VideoFit {
        width,
        height,
        k1,
        u_k1: crate::numerics::upper_median(&mut u).max(spread),
        frames: fits,
        refused,
    })
}

/// The coefficient that straightens the lines of `pic`: from its sharpest edges, or
/// where they hold too few straight lines, from fainter ones ([`EDGE_TIMES_QUANTILE`]);
/// refused as the faintest were.
pub fn fit(pic: Grey) -> Result<Plumb> {
    // The gradients once; the edge points at each threshold.
    let gradients = Gradients::of(pic);
    let mut refused = None;
    for times in EDGE_TIMES_QUANTILE {
        let edgels = gradients
            .as_ref()
            .map_or_else(Vec::new, |g| g.edgels(times));
        match fit_edges(pic, &edgels, times) {
            Ok(p) => return Ok(p),
            Err(e) => refused = Some(e),
        }
    }
    Err(refused.expect("a threshold was tried"))
}

/// The coefficient that straightens the lines of the edge points `edgels` of `pic`
/// (found over `times` the picture's noise).
fn fit_edges(pic: Grey, edgels: &[Edgel], times: f64) -> Result<Plumb> {
    let shorter = pic.w.min(pic.h) as f64;
    let lens_of = |k1: f64| Lens::new(k1, 0.0, pic.w as u32, pic.h as u32);
    if edgels.len() < MIN_POINTS * MIN_LINES {
        bail!(
            "too few edges in the picture to fit the lens ({} edge points): film a ruled or \
             gridded sheet that fills the frame",
            edgels.len()
        );
    }
    // The coefficients whose lens does not fold the frame over (its radius grows all the
    // way to the corners: `1 + 3 k1 r^2 > 0`; a portrait frame's corners lie farther out
    // in frame widths).
    let corner2 = 0.25 * (1.0 + (pic.h as f64 / pic.w as f64).powi(2));
    let k1_range = (-K1_MAX.min(0.9 / (3.0 * corner2)), K1_MAX);
    let coarse = coarse_k1(edgels, &lens_of, shorter * MIN_EXTENT, k1_range);
    // Three rounds: the lines found at the coefficient so far (at the coarse one within
    // 1.5 px, then within 1 px), and the coefficient refined on them.
    let mut k1 = coarse;
    let mut lines = Vec::new();
    let mut groups = Vec::new();
    for grow in GROW_PX {
        lines = find_lines(edgels, &lens_of(k1), grow, shorter * MIN_EXTENT, 1);
        drop_bent(edgels, &lens_of, k1, &mut lines);
        groups = strokes(edgels, &lines, &lens_of(k1));
        let n = groups.iter().max().map_or(0, |g| g + 1);
        if n < MIN_LINES {
            bail!(
                "too few straight lines in the picture to fit the lens ({n} found, {MIN_LINES} \
                 needed, each a fifth of the frame long): film a ruled or gridded sheet that \
                 fills the frame"
            );
        }
        k1 = refine(edgels, &lines, &lens_of, k1, k1_range);
    }
    let u_k1 = jackknife(edgels, &lines, &groups, &lens_of, k1, k1_range);
    let points: usize = lines.iter().map(Vec::len).sum();
    let rms = |k: f64| {
        let lens = lens_of(k);
        let ss: f64 = lines.iter().map(|l| line_ss(edgels, l, &lens)).sum();
        (ss / points as f64).sqrt()
    };
    Ok(Plumb {
        k1,
        u_k1,
        lines: groups.iter().max().map_or(0, |g| g + 1),
        points,
        rms_px: rms(k1),
        coarse_k1: coarse,
        rms_straight_px: rms(0.0),
        edge_times: times,
    })
}

/// The point seen at `p` through `lens`, in the undistorted view scaled back by the
/// lens's zoom, px: the picture's own scale at its centre (unscaled, a stronger barrel,
/// zoomed further in, would seem to straighten lines by shrinking them).
fn straight(lens: &Lens, p: [f64; 2]) -> [f64; 2] {
    let q = lens.undistort(p);
    [
        lens.centre[0] + lens.zoom * (q[0] - lens.centre[0]),
        lens.centre[1] + lens.zoom * (q[1] - lens.centre[1]),
    ]
}

/// A point and its normal taken back to the plate: the point, the normal, the normal's
/// direction (rad, 0 to 2 pi) and the line's signed distance from the origin.
fn straighten(lens: &Lens, e: &Edgel) -> ([f64; 2], [f64; 2], f64, f64) {
    let q = straight(lens, e.p);
    let t = [-e.n[1], e.n[0]];
    let q2 = straight(lens, [e.p[0] + t[0], e.p[1] + t[1]]);
    let (dx, dy) = (q2[0] - q[0], q2[1] - q[1]);
    let len = dx.hypot(dy).max(1e-12);
    let n = [dy / len, -dx / len];
    let phi = n[1].atan2(n[0]).rem_euclid(std::f64::consts::TAU);
    (q, n, phi, n[0] * q[0] + n[1] * q[1])
}

/// The coarse coefficient (step 2): the grid's `k1` through which most edge points lie
/// on long straight lines. (The votes' own concentration is no guide: a dense grid's
/// lines, bent the wrong way, cross each other's bins.)
fn coarse_k1(
    edgels: &[Edgel],
    lens_of: &dyn Fn(f64) -> Lens,
    min_extent: f64,
    range: (f64, f64),
) -> f64 {
    let stride = edgels.len().div_ceil(COARSE_POINTS);
    let some: Vec<Edgel> = edgels.iter().step_by(stride).copied().collect();
    let steps = (K1_MAX / K1_STEP).round() as i32;
    let mut best: (usize, f64) = (0, 0.0);
    for k in -steps..=steps {
        let k1 = f64::from(k) * K1_STEP;
        if k1 < range.0 || k1 > range.1 {
            continue;
        }
        let on_lines: usize = find_lines(&some, &lens_of(k1), GROW_PX[0], min_extent, stride)
            .iter()
            .map(Vec::len)
            .sum();
        // Ties to the smaller bend.
        if on_lines > best.0 || (on_lines == best.0 && k1.abs() < best.1.abs()) {
            best = (on_lines, k1);
        }
    }
    best.1
}

/// The straight lines through the lens `lens` (step 3): each the indices of its points.
/// `thinned` points are taken for one (the coarse search's), so a line needs that many
/// fewer.
fn find_lines(
    edgels: &[Edgel],
    lens: &Lens,
    grow: f64,
    min_extent: f64,
    thinned: usize,
) -> Vec<Vec<usize>> {
    let min_points = (MIN_POINTS / thinned).max(MIN_POINTS / 3);
    let seen: Vec<_> = edgels.iter().map(|e| straighten(lens, e)).collect();
    // Votes at a coarse scale, to seed lines from the fullest first.
    let mut by_bin: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
    for (i, &(_, _, phi, rho)) in seen.iter().enumerate() {
        let key = (
            (phi.to_degrees() / VOTE_DEG) as i64,
            (rho / VOTE_PX).floor() as i64,
        );
        by_bin.entry(key).or_default().push(i);
    }
    let mut seeds: Vec<((i64, i64), usize)> = by_bin.iter().map(|(k, v)| (*k, v.len())).collect();
    seeds.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let mut taken = vec![false; edgels.len()];
    let mut lines = Vec::new();
    let cos_grow = GROW_DEG.to_radians().cos();
    let wrap = 360 / VOTE_DEG as i64;
    for (key, count) in seeds {
        if count < min_points / 3 || lines.len() >= MAX_LINES {
            break;
        }
        let mut members: Vec<usize> = Vec::new();
        for da in -1..=1 {
            for dr in -1..=1 {
                let k = ((key.0 + da).rem_euclid(wrap), key.1 + dr);
                if let Some(v) = by_bin.get(&k) {
                    members.extend(v.iter().copied().filter(|&i| !taken[i]));
                }
            }
        }
        if members.len() < min_points / 3 {
            continue;
        }
        // Grown twice: every free point near the line fitted to the members, turned
        // like it.
        for _ in 0..2 {
            let Some((c, n)) = tls(members.iter().map(|&i| seen[i].0)) else {
                break;
            };
            let mean_n = members.iter().fold([0.0, 0.0], |a, &i| {
                [a[0] + seen[i].1[0], a[1] + seen[i].1[1]]
            });
            let sign = if mean_n[0] * n[0] + mean_n[1] * n[1] < 0.0 {
                -1.0
            } else {
                1.0
            };
            let n = [sign * n[0], sign * n[1]];
            members = (0..edgels.len())
                .filter(|&i| {
                    let (q, m, _, _) = seen[i];
                    !taken[i]
                        && ((q[0] - c[0]) * n[0] + (q[1] - c[1]) * n[1]).abs() <= grow
                        && m[0] * n[0] + m[1] * n[1] >= cos_grow
                })
                .collect();
        }
        if members.len() < min_points {
            continue;
        }
        let Some((c, n)) = tls(members.iter().map(|&i| seen[i].0)) else {
            continue;
        };
        let along = |i: usize| {
            let q = seen[i].0;
            (q[0] - c[0]) * -n[1] + (q[1] - c[1]) * n[0]
        };
        let (lo, hi) = members
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &i| {
                (lo.min(along(i)), hi.max(along(i)))
            });
        if hi - lo < min_extent || ((members.len() * thinned) as f64) < MIN_DENSITY * (hi - lo) {
            continue;
        }
        for &i in &members {
            taken[i] = true;
        }
        lines.push(members);
    }
    lines
}

/// The total-least-squares line through points.
struct BestLine {
    /// The points' centroid, px.
    c: [f64; 2],
    /// The line's unit normal.
    n: [f64; 2],
    /// The sum of the points' squared distances from the line (the smaller eigenvalue
    /// of their scatter), px^2.
    ss: f64,
}

/// The points' centroid and unit normal of their best line.
fn tls(points: impl Iterator<Item = [f64; 2]>) -> Option<([f64; 2], [f64; 2])> {
    best_line(points).map(|l| (l.c, l.n))
}

/// The points' best line (`None` for fewer than two points). Sums taken about the first
/// point, which keeps them small.
fn best_line(mut points: impl Iterator<Item = [f64; 2]>) -> Option<BestLine> {
    let o = points.next()?;
    let (mut n, mut sx, mut sy, mut xx, mut xy, mut yy) = (1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for p in points {
        let (dx, dy) = (p[0] - o[0], p[1] - o[1]);
        n += 1.0;
        sx += dx;
        sy += dy;
        xx += dx * dx;
        xy += dx * dy;
        yy += dy * dy;
    }
    if n < 2.0 {
        return None;
    }
    let (mx, my) = (sx / n, sy / n);
    let (xx, xy, yy) = (xx - n * mx * mx, xy - n * mx * my, yy - n * my * my);
    let tr = xx + yy;
    let det = xx * yy - xy * xy;
    let small = (tr / 2.0 - ((tr / 2.0).powi(2) - det).max(0.0).sqrt()).max(0.0);
    let v = if xy.abs() > 1e-12 {
        [xy, small - xx]
    } else if xx <= yy {
        [1.0, 0.0]
    } else {
        [0.0, 1.0]
    };
    let len = v[0].hypot(v[1]);
    Some(BestLine {
        c: [o[0] + mx, o[1] + my],
        n: [v[0] / len, v[1] / len],
        ss: small,
    })
}

/// A line's sum of squared distances from its own best line, through `lens`.
fn line_ss(edgels: &[Edgel], line: &[usize], lens: &Lens) -> f64 {
    best_line(line.iter().map(|&i| straight(lens, edgels[i].p)))
        .map(|l| l.ss)
        .unwrap_or(0.0)
}

/// Lines that are not straight on the plate, dropped (their scatter at `k1` is many
/// times the median line's).
fn drop_bent(
    edgels: &[Edgel],
    lens_of: &dyn Fn(f64) -> Lens,
    k1: f64,
    lines: &mut Vec<Vec<usize>>,
) {
    let lens = lens_of(k1);
    let rms: Vec<f64> = lines
        .iter()
        .map(|l| (line_ss(edgels, l, &lens) / l.len() as f64).sqrt())
        .collect();
    if rms.is_empty() {
        return;
    }
    let limit = DROP_TIMES_MEDIAN * crate::numerics::upper_median(&mut rms.clone());
    let mut k = 0;
    lines.retain(|_| {
        k += 1;
        rms[k - 1] <= limit
    });
}

/// The step in `k1` of the parabolas through `k1 - REFINE_H, k1, k1 + REFINE_H`.
const REFINE_H: f64 = 0.002;
/// The largest step of one parabola.
const MAX_STEP: f64 = 0.05;

/// Each line's sum of squared distances at `k1 - REFINE_H`, `k1` and `k1 + REFINE_H`.
fn line_parabolas(
    edgels: &[Edgel],
    lines: &[Vec<usize>],
    lens_of: &dyn Fn(f64) -> Lens,
    k1: f64,
) -> Vec<[f64; 3]> {
    let lenses = [-REFINE_H, 0.0, REFINE_H].map(|d| lens_of(k1 + d));
    lines
        .iter()
        .map(|l| lenses.map(|lens| line_ss(edgels, l, &lens)))
        .collect()
}

/// The step to the vertex of the parabola through the sums `s` (at most 0.05; downhill
/// if it is not a valley).
fn vertex_step(s: [f64; 3]) -> f64 {
    let [a, b, c] = s;
    let curv = a - 2.0 * b + c;
    if curv > 0.0 {
        (0.5 * REFINE_H * (a - c) / curv).clamp(-MAX_STEP, MAX_STEP)
    } else if a < c {
        -MAX_STEP
    } else {
        MAX_STEP
    }
}

/// The three sums added up.
fn sum3<'a>(sums: impl Iterator<Item = &'a [f64; 3]>) -> [f64; 3] {
    sums.fold([0.0; 3], |t, s| [t[0] + s[0], t[1] + s[1], t[2] + s[2]])
}

/// The coefficient that makes the lines straightest (step 4), from `k1`: parabolas
/// through three `k1` until the step is small, within `range`.
fn refine(
    edgels: &[Edgel],
    lines: &[Vec<usize>],
    lens_of: &dyn Fn(f64) -> Lens,
    mut k1: f64,
    range: (f64, f64),
) -> f64 {
    for _ in 0..10 {
        let sums = sum3(line_parabolas(edgels, lines, lens_of, k1).iter());
        let step = vertex_step(sums);
        k1 = (k1 + step).clamp(range.0, range.1);
        if step.abs() < 1e-5 {
            break;
        }
    }
    k1
}

/// The jackknife's standard uncertainty of `k1` over the strokes (`group` of each
/// line): each stroke left out once, the parabola of the others' sums at the fitted
/// `k1` giving its coefficient.
fn jackknife(
    edgels: &[Edgel],
    lines: &[Vec<usize>],
    group: &[usize],
    lens_of: &dyn Fn(f64) -> Lens,
    k1: f64,
    range: (f64, f64),
) -> f64 {
    let each = line_parabolas(edgels, lines, lens_of, k1);
    let total = sum3(each.iter());
    let n_groups = group.iter().max().map_or(0, |g| g + 1);
    let left_out: Vec<f64> = (0..n_groups)
        .map(|g| {
            let out = sum3(
                each.iter()
                    .zip(group)
                    .filter(|(_, &h)| h == g)
                    .map(|(s, _)| s),
            );
            let rest = [total[0] - out[0], total[1] - out[1], total[2] - out[2]];
            (k1 + vertex_step(rest)).clamp(range.0, range.1)
        })
        .collect();
    let n = left_out.len() as f64;
    let mean = left_out.iter().sum::<f64>() / n;
    ((n - 1.0) / n * left_out.iter().map(|k| (k - mean).powi(2)).sum::<f64>()).sqrt()
}

/// Each line's stroke (0, 1, ...): lines parallel within [`STROKE_DEG`] and within
/// [`STROKE_PX`] of each other, through `lens`, are the edges of one drawn line.
fn strokes(edgels: &[Edgel], lines: &[Vec<usize>], lens: &Lens) -> Vec<usize> {
    let fitted: Vec<Option<([f64; 2], [f64; 2])>> = lines
        .iter()
        .map(|l| tls(l.iter().map(|&i| straight(lens, edgels[i].p))))
        .collect();
    let cos_max = STROKE_DEG.to_radians().cos();
    let mut group: Vec<usize> = (0..lines.len()).collect();
    let root = |g: &Vec<usize>, mut i: usize| {
        while g[i] != i {
            i = g[i];
        }
        i
    };
    for a in 0..lines.len() {
        for b in a + 1..lines.len() {
            let (Some((ca, na)), Some((cb, nb))) = (fitted[a], fitted[b]) else {
                continue;
            };
            let parallel = (na[0] * nb[0] + na[1] * nb[1]).abs() >= cos_max;
            let apart = ((cb[0] - ca[0]) * na[0] + (cb[1] - ca[1]) * na[1]).abs();
            if parallel && apart <= STROKE_PX {
                let (ra, rb) = (root(&group, a), root(&group, b));
                group[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // Numbered 0, 1, ... in the order of their first line.
    let mut number = vec![usize::MAX; lines.len()];
    let mut next = 0;
    (0..lines.len())
        .map(|i| {
            let r = root(&group, i);
            if number[r] == usize::MAX {
                number[r] = next;
                next += 1;
            }
            number[r]
        })
        .collect()
}

mod edges;
#[cfg(test)]
pub(crate) mod tests;
