//! The wire's angle in one frame's evidence: the sharpest peak of a histogram of
//! angles about the pivot, then the orthogonal fit through the pivot of the strip
//! along it.

mod band;
mod ridge;
mod strip;

use super::Tracker;
use crate::detect::line::{
    fit_line_through, line_through_moments, moments, moments_of, unwrap_near, Line, Moments,
};
use crate::detect::row::KeptMoments;
use crate::detect::tuning::{
    BOW_MAD_FLOOR_PX, BOW_MIN_STEPS, BOW_OUTLIER_MADS, CELLS, FREE_STRIP_DRIFT, FREE_STRIP_FROM,
    FREE_STRIP_HALF, FREE_STRIP_PASSES, FULL_WIDTH_HALF_PX, FULL_WIDTH_OFF_PX, FULL_WIDTH_PROFILES,
    HIST_BIN_PX, HIST_MAX_BINS, HIST_MIN_BINS, MAX_CANDIDATES, MIN_LINE_PIXELS, PAIR_LEAD_SIGMAS,
    PAIR_MAX, PAIR_MIN_VOTES, PAIR_MOVE, PAIR_REACH_MARGIN_DEG, PAIR_SEP_TOL, PAIR_VOTE_RATIO,
    PEAK_STEP_BINS, RIVAL_COVER, RIVAL_REACH_BINS, RIVAL_SCORE, RIVAL_SHARPER, RIVAL_SHARPER_START,
    RIVAL_WIDER_GATED, SELECT_STRIP_NARROW, SELECT_STRIP_WIDE, STRIP_HALF, STRIP_REFITS,
    UNDECIDED_MAX_FRAMES, WIDTH_STRIP,
};
use crate::detect::{full_to_shrunk, shrunk_to_full, Pt};
use anyhow::Result;
use band::*;
use opencv::prelude::*;
pub(super) use ridge::{Full, Ridges};
use strip::*;

/// The per-frame buffers of [`Tracker::measure`], kept from frame to frame so that a
/// frame allocates nothing (a frame with rival peaks aside, see `sharpest_ridge`).
#[derive(Default)]
pub(super) struct Scratch {
    /// Evidence pixels above the threshold, in the wedge's rectangle (x, y).
    nz: Vec<(i32, i32)>,
    /// (point, weight, angle) of the evidence pixels in the wedge and the band.
    cand: Vec<(Pt, f64, f64)>,
    /// Evidence per angle bin, then smoothed over three bins, then scored.
    histo: Vec<f64>,
    /// Evidence per angle bin and part of the band ([`CELLS`] parts per bin).
    cells: Vec<f64>,
    sm: Vec<f64>,
    scores: Vec<f64>,
    /// The pixels the line is fitted to, and the strip being walked.
    sel: Vec<(Pt, f64)>,
    strip: Vec<(Pt, f64)>,
    /// The far strip's first pixels ([`Tracker::free_strip_moments`]).
    far: Vec<(Pt, f64)>,
    /// The band's part of each of the strip's pixels ([`drop_stray_parts`]).
    parts: Vec<u8>,
    /// The strip's steps along its line, and their deviations from its parabola
    /// ([`strip_parabola`]).
    bins: Vec<[f64; 3]>,
    devs: Vec<f64>,
}

impl Tracker {
    /// The wire's angle and coverage in the current evidence image, searching the
    /// wedge `evidence` prepared around `pred` (or every angle the wire was seen at,
    /// without a prediction). `gate` is how far from `pred` the angle will be accepted.
    /// `full` is the frame at the full scale when the pass works shrunk.
    pub(super) fn measure(
        &mut self,
        pred: Option<f64>,
        gate: f64,
        full: Option<Full>,
    ) -> Result<Option<(f64, f64, KeptMoments)>> {
        let mut b = std::mem::take(&mut self.scratch);
        let found = self.measure_with(&mut b, pred, gate, full);
        self.scratch = b;
        found
    }

    fn measure_with(
        &mut self,
        b: &mut Scratch,
        pred: Option<f64>,
        gate: f64,
        full: Option<Full>,
    ) -> Result<Option<(f64, f64, KeptMoments)>> {
        self.pair_other = None;
        // Only the wedge's rectangle holds evidence this frame (see `evidence`): its
        // pixels over their threshold, row by row.
        let rect = self.rect;
        b.nz.clear();
        if rect.width > 0 && rect.height > 0 {
            let (ev, tmap) = (self.ev.data_bytes()?, self.tmap.data_bytes()?);
            let stride = self.ev.cols() as usize;
            let (x0, w) = (rect.x as usize, rect.width as usize);
            for y in rect.y as usize..(rect.y + rect.height) as usize {
                let (e, t) = (&ev[y * stride + x0..][..w], &tmap[y * stride + x0..][..w]);
                over_threshold(e, t, |i| b.nz.push(((x0 + i) as i32, y as i32)));
            }
        }
        let (lo, hi) = self.wedge;
        // Angles on the wedge's own branch (the wire may hang across -x).
        let mid = 0.5 * (lo + hi);
        let piv = self.piv;
        let (r_lo, r_hi) = (self.r_lo, self.r_hi);
        let r_mid = 0.5 * (r_lo + r_hi);
        let bin_w = (HIST_BIN_PX / r_mid).max(1e-4);
        let nb = (((hi - lo) / bin_w).ceil() as usize).clamp(HIST_MIN_BINS, HIST_MAX_BINS);
        b.histo.clear();
        b.histo.resize(nb, 0.0);
        b.cells.clear();
        b.cells.resize(nb * CELLS, 0.0);
        b.cand.clear();
        let ev = self.ev.data_bytes()?;
        let stride = self.ev.cols() as usize;
        let outside = WedgeTest::new(lo, hi);
        for &(x, y) in &b.nz {
            let q = Pt::new(x as f64, y as f64);
            let d = q - piv;
            let r = d.norm();
            if r < r_lo || r > r_hi || outside.surely(d, r) {
                continue;
            }
            let th = unwrap_near(d.y.atan2(d.x), mid);
            if th < lo || th > hi {
                continue;
            }
            let wgt = ev[y as usize * stride + x as usize] as f64;
            let k = (((th - lo) / bin_w) as usize).min(nb - 1);
            b.cells[k * CELLS + band_part(r, (r_lo, r_hi))] += wgt;
            b.cand.push((q, wgt, th));
            if b.cand.len() > MAX_CANDIDATES {
                break;
            }
        }
        if b.cand.len() < MIN_LINE_PIXELS {
            return Ok(None);
        }
        covered_bins(&b.cells, &mut b.histo);
        // Sharpest peak: a bin's mass against its neighbourhood (a broad blob scores low).
        let k = PEAK_STEP_BINS;
        let histo = &b.histo;
        b.sm.clear();
        b.sm.extend(
            (0..nb).map(|i| -> f64 { histo[i.saturating_sub(1)..(i + 2).min(nb)].iter().sum() }),
        );
        let sm = &b.sm;
        let side = |i: usize| {
            (
                sm.get(i.wrapping_sub(3 * k)).copied().unwrap_or(0.0),
                sm.get(i + 3 * k).copied().unwrap_or(0.0),
            )
        };
        let mut best = (f64::MIN, 0usize);
        for (i, m) in sm.iter().enumerate() {
            let (a, c) = side(i);
            let score = m - 0.5 * (a + c);
            if score > best.0 {
                best = (score, i);
            }
        }
        // Rivals are scored against their lower side: a wire beside its own shadow keeps
        // its peak.
        b.scores.clear();
        b.scores.extend((0..nb).map(|i| {
            let (a, c) = side(i);
            sm[i] - a.min(c)
        }));
        let (best_i, other) =
            self.sharpest_ridge(&b.scores, best, &b.cand, (lo, bin_w), pred, gate, full)?;
        let at = |i: usize| lo + (i as f64 + 0.5) * bin_w;
        let found = self.refine(b, at(best_i), mid)?;
        // The pair's other ridge measured too while the side the wire lies on is not
        // known: the frame is restated once it is ([`Tracker::restate_undecided`]).
        self.pair_other = match other {
            Some(o) if found.is_some() => self.refine(b, at(o), mid)?,
            _ => None,
        };
        Ok(found)
    }

    /// The wire's angle, coverage and strip moments about the line through the pivot at
    /// `th0` (a histogram peak's angle), from the candidates `b.cand`; `mid` is the
    /// wedge's middle, the branch the angle is given on.
    fn refine(
        &self,
        b: &mut Scratch,
        th0: f64,
        mid: f64,
    ) -> Result<Option<(f64, f64, KeptMoments)>> {
        let piv = self.piv;
        let (r_lo, r_hi) = (self.r_lo, self.r_hi);
        let mut line = Line {
            point: piv,
            dir: Pt::new(th0.cos(), th0.sin()),
        };
        // Pixels along that line, then the orthogonal fit constrained to the pivot
        // (twice, tightening the strip).
        for strip in [SELECT_STRIP_WIDE, SELECT_STRIP_NARROW] {
            b.sel.clear();
            b.sel.extend(
                b.cand
                    .iter()
                    .filter(|(q, _, _)| line.distance(*q) <= strip)
                    .map(|(q, w, _)| (*q, *w)),
            );
            match fit_line_through(piv, &b.sel) {
                Some(l) => line = l,
                None => return Ok(None),
            }
        }
        if b.sel.len() < MIN_LINE_PIXELS {
            return Ok(None);
        }
        // Coverage of the band by the selected pixels.
        let mut cov = [false; CELLS];
        for (q, _) in &b.sel {
            cov[band_part((q - piv).norm(), (r_lo, r_hi))] = true;
        }
        let quality = cov.iter().filter(|c| **c).count() as f64 / CELLS as f64;
        // The angle itself from every pixel of the strip, below the threshold too: the
        // threshold, which differs from pixel to pixel, would cut the blurred wire's
        // flanks unevenly and tilt the fit (by about 0.4 % of the swing on a light wire).
        for _ in 0..STRIP_REFITS {
            self.strip_pixels(&line, STRIP_HALF, &mut b.strip)?;
            match fit_line_through(piv, &b.strip) {
                Some(l) => line = l,
                None => return Ok(None),
            }
            if drop_stray_parts(piv, (r_lo, r_hi), line, &mut b.strip, &mut b.parts) {
                match fit_line_through(piv, &b.strip) {
                    Some(l) => line = l,
                    None => return Ok(None),
                }
            }
            std::mem::swap(&mut b.sel, &mut b.strip);
        }
        let sel = &b.sel;
        if sel.len() < MIN_LINE_PIXELS {
            return Ok(None);
        }
        // Point the direction away from the pivot, towards the pixels.
        let c = sel.iter().fold(Pt::zeros(), |a, (q, w)| a + (q - piv) * *w);
        let d = if c.dot(&line.dir) >= 0.0 {
            line.dir
        } else {
            -line.dir
        };
        let angle = unwrap_near(d.y.atan2(d.x), mid);
        let m = self.free_strip_moments(&line, b)?;
        Ok(Some((angle, quality, m)))
    }

    /// The moments the pass keeps for the pivot's refinement and the angles' refit
    /// (`Tracker::refine_pivot`): those of the strip centred on the wire's own free
    /// line, not on the line through the current pivot. A strip about the line through
    /// a pivot that is off holds the wire off its centre towards the band's ends, and
    /// the noise and the part of the wire's flanks it keeps pull every free line
    /// towards the line through that pivot: the lines' intersection then corrects only
    /// part of the pivot's error (three quarters on a 960x540 twin with a camera's
    /// defects, leaving 0.8 px along the wire and its swing 0.46 % small). Re-centring
    /// the strip on the free line [`FREE_STRIP_PASSES`] times leaves that share of the
    /// pull to the power of the passes. A free line that leaves the pivot's line by
    /// more than [`FREE_STRIP_DRIFT`] px at either end of the band (a neighbouring
    /// ridge) keeps the strip about the pivot's line. The re-centred strip is narrower
    /// ([`FREE_STRIP_HALF`]) than the one the line is found in: it holds the wire's
    /// ridge and less of its flanks' neighbours (a shadow's edge, the noise). It
    /// is kept twice ([`KeptMoments`]): over the whole band, and without the wire nearest
    /// the pivot ([`FREE_STRIP_FROM`] of the band's outer radius), where a shadow or a
    /// static edge merges with it. `b.sel` holds the first strip on entry.
    fn free_strip_moments(&self, about: &Line, b: &mut Scratch) -> Result<KeptMoments> {
        let fallback = moments(&b.sel);
        let ends = [self.r_lo, self.r_hi].map(|r| about.point + about.dir * r);
        // A band that starts beyond the cut (a pivot beyond the frame's edge) keeps
        // the whole strip: the same moments, not measured twice.
        let from = FREE_STRIP_FROM * self.r_hi;
        let split = from > self.r_lo;
        // Both strips' first pass walks about the same free line (that of the first
        // strip's pixels): the far strip's pixels are the whole one's from `from` out,
        // taken from the one walk ([`Self::strip_beyond`]).
        let Some(free) = free_line_within(&fallback, &ends) else {
            let plate = self.plate_moments(&b.sel).map(|m| [m; 2]);
            return Ok(KeptMoments {
                moments: [fallback; 2],
                free: [false; 2],
                bow: None,
                plate,
            });
        };
        self.strip_pixels_from(&free, FREE_STRIP_HALF, self.r_lo, &mut b.strip)?;
        let far_first = if split {
            self.strip_beyond(&free, FREE_STRIP_HALF, from, &b.strip, &mut b.far);
            (b.far.len() >= MIN_LINE_PIXELS).then(|| moments(&b.far))
        } else {
            None
        };
        let whole_first = (b.strip.len() >= MIN_LINE_PIXELS).then(|| moments(&b.strip));
        // Each strip's moments, and the line its last pass walked about (none when it
        // was not re-centred: the fallback's).
        let recentre = |first: Option<[f64; 6]>,
                        from: f64,
                        b: &mut Scratch|
         -> Result<([f64; 6], Option<Line>)> {
            Ok(first
                .map(|m| self.recentred_moments(&ends, m, free, from, b))
                .transpose()?
                .flatten()
                .map_or((fallback, None), |(m, walked)| (m, Some(walked))))
        };
        let whole = recentre(whole_first, self.r_lo, b)?;
        // The whole strip's last pass: how it bows about the line it was walked about.
        let bow = whole
            .1
            .and_then(|walked| self.strip_bow(&walked, &b.strip, &mut b.bins, &mut b.devs));
        // Each strip's pixels behind its moments: its last walk's when re-centred
        // (`recentred_moments` walks at least once more), else the first strip's.
        let pixels = |walked: bool, b: &Scratch| -> Option<[f64; 6]> {
            self.plate_moments(if walked { &b.strip } else { &b.sel })
        };
        let whole_plate = pixels(whole.1.is_some(), b);
        let far = if split {
            recentre(far_first, from, b)?
        } else {
            whole
        };
        let far_plate = if split {
            pixels(far.1.is_some(), b)
        } else {
            whole_plate
        };
        Ok(KeptMoments {
            moments: [whole.0, far.0],
            free: [whole.1.is_some(), far.1.is_some()],
            bow,
            plate: whole_plate.zip(far_plate).map(|(w, f)| [w, f]),
        })
    }

    /// Through the pass's lens, the moments of the strip's pixels `pts` each taken
    /// into the undistorted view (its point at the working scale); `None` without a
    /// lens.
    fn plate_moments(&self, pts: &[(Pt, f64)]) -> Option<[f64; 6]> {
        let lens = self.lens.as_ref()?;
        let origin = Pt::new(self.roi_x, self.roi_y);
        // Each pixel's Newton steps start from the one before's (they lie along a line).
        let mut guess = None;
        Some(moments_of(pts.iter().map(|&(p, w)| {
            let f = shrunk_to_full(p, origin, self.scale);
            let (u, k) = lens.undistort_from([f.x, f.y], guess);
            guess = Some(k);
            (full_to_shrunk(Pt::new(u[0], u[1]), origin, self.scale), w)
        })))
    }

    /// The strip's moments from the radius `from` out, re-centred on the wire's free
    /// line from the moments `m` of its first pass for the remaining
    /// [`FREE_STRIP_PASSES`] ([`Self::free_strip_moments`]); `None` when a pass
    /// cannot go on (the free line leaves the pivot's line at `ends`, or too few
    /// pixels), which keeps the strip about the pivot's line.
    fn recentred_moments(
        &self,
        ends: &[Pt; 2],
        mut m: [f64; 6],
        mut walked: Line,
        from: f64,
        b: &mut Scratch,
    ) -> Result<Option<([f64; 6], Line)>> {
        for _ in 1..FREE_STRIP_PASSES {
            let Some(free) = free_line_within(&m, ends) else {
                return Ok(None);
            };
            self.strip_pixels_from(&free, FREE_STRIP_HALF, from, &mut b.strip)?;
            if b.strip.len() < MIN_LINE_PIXELS {
                return Ok(None);
            }
            m = moments(&b.strip);
            walked = free;
        }
        Ok(Some((m, walked)))
    }

    /// How the strip's pixels `strip`, walked about the line `walked`, bow: the
    /// [`crate::lens::bow::Bowed`] of the parabola across that line fitted to them, in
    /// full-frame px, the line pointing away from the pivot (a free line has no
    /// direction of its own: a hanging wire's would point down on one side of the
    /// vertical and up on the other, and a bend of the wire's own would flip its sign
    /// from one half swing to the next).
    fn strip_bow(
        &self,
        walked: &Line,
        strip: &[(Pt, f64)],
        bins: &mut Vec<[f64; 3]>,
        devs: &mut Vec<f64>,
    ) -> Option<crate::lens::bow::Bowed> {
        let outwards = if (walked.point - self.piv).dot(&walked.dir) >= 0.0 {
            *walked
        } else {
            Line {
                point: walked.point,
                dir: -walked.dir,
            }
        };
        let (mid, response, ends) = strip_parabola(&outwards, strip, FREE_STRIP_HALF, bins, devs)?;
        let origin = Pt::new(self.roi_x, self.roi_y);
        let full = |u: f64| {
            let q = shrunk_to_full(outwards.point + outwards.dir * u, origin, self.scale);
            [q.x, q.y]
        };
        Some(crate::lens::bow::Bowed {
            ends: ends.map(full),
            mid_px: mid * self.scale,
            response,
        })
    }

    /// Of the pixels `strip` that [`Self::strip_pixels_from`] found about `line`
    /// within `half` px from a radius under `from`, into `out`: those it finds from
    /// `from` out, in the same order with the same weights (its walk from `from`
    /// visits the same pixels of its rows, fewer rows, and keeps those with their
    /// squared radius from `from`'s, reckoned the same way).
    fn strip_beyond(
        &self,
        line: &Line,
        half: f64,
        from: f64,
        strip: &[(Pt, f64)],
        out: &mut Vec<(Pt, f64)>,
    ) {
        let rows = self.strip_rows(line, half, from);
        let (piv_u, piv_v) = rows.along(self.piv);
        let from2 = from * from;
        out.clear();
        out.extend(strip.iter().copied().filter(|(q, _)| {
            let (u, v) = rows.along(*q);
            let off_u = u - piv_u;
            let du2 = off_u * off_u;
            let off_v = v - piv_v;
            rows.u.contains(&(u as usize)) && off_v * off_v + du2 >= from2
        }));
    }

    /// The evidence pixels within `half` px of `line` (a line through the pivot, or
    /// one near it), in the band of radii about the pivot, with their weights: each
    /// pixel's evidence over the contrast behind it, static marks and their mirror
    /// images across the line left out ([`super::contrast`]). Walks the strip row by
    /// row (or column by column for a line closer to horizontal), so only the strip's
    /// own pixels are visited. A pixel on the strip's edge counts by the share of it
    /// inside ([`edge_share`]), so the strip holds the same area of evidence wherever
    /// the line falls between pixel centres.
    fn strip_pixels(&self, line: &Line, half: f64, out: &mut Vec<(Pt, f64)>) -> Result<()> {
        self.strip_pixels_from(line, half, self.r_lo, out)
    }

    /// [`Self::strip_pixels`] from the radius `r_lo` (px of the working scale) out.
    fn strip_pixels_from(
        &self,
        line: &Line,
        half: f64,
        r_lo: f64,
        out: &mut Vec<(Pt, f64)>,
    ) -> Result<()> {
        let (cols, rows) = (self.ev.cols() as usize, self.ev.rows() as usize);
        let ev = self.ev.data_bytes()?;
        let piv = self.piv;
        let rows_of = self.strip_rows(line, half, r_lo);
        let StripRows { d, foot, steep, .. } = rows_of;
        // Along the major axis `u` (y when the line is steep), the strip at `u` spans
        // `v` within `(half + STRIP_EDGE) / |d_u|` of the line: a step of `v` is `|d_u|`
        // px across it.
        // The line's foot, its direction and the pivot along `u` and `v`.
        let (pu, pv) = rows_of.along(foot);
        let (du, dv) = rows_of.along(d);
        let (piv_u, piv_v) = rows_of.along(piv);
        let nv = if steep { cols } else { rows };
        let across = du.abs();
        let span = (half + STRIP_EDGE) / across;
        let walk = StripWalk {
            ev,
            bg: self.bg.data_bytes()?,
            contrast: &self.contrast,
            cols,
            rows: rows_of.u.clone(),
            line: (pu, pv, dv, du),
            span,
            nv,
            piv: (piv_u, piv_v),
            band2: (r_lo * r_lo, self.r_hi * self.r_hi),
            half,
            across,
        };
        out.clear();
        if steep {
            walk.run::<true>(out);
        } else {
            walk.run::<false>(out);
        }
        Ok(())
    }

    /// The rows (columns for a line closer to horizontal) a strip about `line`
    /// within `half` px, from the radius `r_lo` out, walks.
    fn strip_rows(&self, line: &Line, half: f64, r_lo: f64) -> StripRows {
        let piv = self.piv;
        // The direction away from the pivot (a line through the pivot has it already),
        // and the line's point nearest the pivot (the pivot itself on such a line).
        let d = if (line.point - piv).dot(&line.dir) >= 0.0 {
            line.dir
        } else {
            -line.dir
        };
        let foot = line.point + d * (piv - line.point).dot(&d);
        let (a, b) = (foot + d * r_lo, foot + d * self.r_hi);
        let steep = d.y.abs() >= d.x.abs();
        let (au, bu, nu) = if steep {
            (a.y, b.y, self.ev.rows() as usize)
        } else {
            (a.x, b.x, self.ev.cols() as usize)
        };
        let u0 = (au.min(bu) - half).floor().max(0.0) as usize;
        let u1 = ((au.max(bu) + half).ceil().max(0.0) as usize).min(nu);
        StripRows {
            d,
            foot,
            steep,
            u: u0..u1,
        }
    }
}

/// The rows of a strip's walk ([`Tracker::strip_rows`]): the line's direction away
/// from the pivot, its point nearest the pivot, whether `u` runs along y, and the
/// range of `u` walked.
struct StripRows {
    d: Pt,
    foot: Pt,
    steep: bool,
    u: std::ops::Range<usize>,
}

impl StripRows {
    /// A point's coordinates along `u` and `v`.
    fn along(&self, p: Pt) -> (f64, f64) {
        if self.steep {
            (p.y, p.x)
        } else {
            (p.x, p.y)
        }
    }
}

/// The free line of the moments `m`, unless it leaves the pivot's line by more than
/// [`FREE_STRIP_DRIFT`] px at either of its band's `ends` (a neighbouring ridge).
fn free_line_within(m: &[f64; 6], ends: &[Pt; 2]) -> Option<Line> {
    let free = m.free_line()?;
    (!ends.iter().any(|e| free.distance(*e) > FREE_STRIP_DRIFT)).then_some(free)
}

#[cfg(test)]
mod tests;
