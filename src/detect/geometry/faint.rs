//! The faint look: when no threshold keeps enough of the wire to make a line (a pixel
//! wide, a few grey levels dark, under flicker), each frame's line is found along whole
//! lines of the image (the standard Hough transform of the pixels a little over the
//! median), and kept where its pixels run without a gap.

use super::*;
use crate::detect::tuning::{
    FAINT_CANDIDATES, FAINT_GAP, FAINT_SIGMAS, FAINT_VOTES, LINE_APART_DEG, LINE_PIXELS_PX,
    THRESHOLD_MAX_LEVELS,
};

/// [`WireGeometry::stage`] of a wire found by the faint look.
pub const FAINT_STAGE: usize = 4;

/// The faint look's per-pixel threshold ([`FAINT_SIGMAS`]).
pub(super) fn faint_threshold_map(init: &InitFrames, noise: &[u8]) -> Result<Mat> {
    let t: Vec<u8> = noise
        .iter()
        .map(|&m| {
            (FAINT_SIGMAS * (m as f64 / 0.95).max(1.0)).clamp(1.0, THRESHOLD_MAX_LEVELS) as u8
        })
        .collect();
    Ok(Mat::new_rows_cols_with_data(init.h as i32, init.w as i32, &t)?.try_clone()?)
}

/// A faint wire's lines in one frame: the strongest lines of `bin` (its pixels over
/// the faint threshold) by the standard Hough transform, which counts every pixel along
/// a whole line of the image however broken; on each (up to three, in distinct
/// directions), the longest run of those pixels within 1.5 px of it with no gap over
/// [`FAINT_GAP`], kept when at least `min_len` long and fitted (orthogonal least
/// squares, weighted by the evidence `ev`) as [`frame_lines`] fits a segment; a run
/// along an edge of the frame (`edges`) is not one.
pub(super) fn faint_frame_lines(
    ev: &impl MatTraitConst,
    bin: &Mat,
    min_len: f64,
    edges: &FrameEdges,
) -> Result<Vec<FrameLine>> {
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
            .any(|d| d.dot(&dir).abs() >= LINE_APART_DEG.to_radians().cos())
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
            .filter(|q| line.distance(*q) <= LINE_PIXELS_PX)
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
        if b <= a
            || along[b - 1].0 - along[a].0 < min_len
            || edges.along(along[a].1, along[b - 1].1)
        {
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
