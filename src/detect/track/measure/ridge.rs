//! Which ridge of the histogram is the wire: the strongest peak, unless a rival is
//! clearly sharper across or, while tracking, the one the gate admits; the side of a
//! wire's shadow learnt over the frames ([`Ridges`]); and, for the pass that works
//! shrunk, a ridge's width measured across it in the full-scale frame ([`full_width`]).

use super::*;
/// A frame at the full scale, for the pass that works shrunk: its grey levels, `w` x `h`.
#[derive(Clone, Copy)]
pub(in crate::detect::track) struct Full<'a> {
    pub data: &'a [u8],
    pub w: usize,
    pub h: usize,
}

impl Full<'_> {
    /// The grey level at `p` (px, pixel centres at whole numbers), bilinear; none
    /// outside the frame.
    fn at(&self, p: Pt) -> Option<f64> {
        let (x0, y0) = (p.x.floor(), p.y.floor());
        if x0 < 0.0 || y0 < 0.0 || x0 + 1.0 >= self.w as f64 || y0 + 1.0 >= self.h as f64 {
            return None;
        }
        let (fx, fy) = (p.x - x0, p.y - y0);
        let i = y0 as usize * self.w + x0 as usize;
        let g = |k: usize| self.data[k] as f64;
        let top = g(i) * (1.0 - fx) + g(i + 1) * fx;
        let bottom = g(i + self.w) * (1.0 - fx) + g(i + self.w + 1) * fx;
        Some(top * (1.0 - fy) + bottom * fy)
    }
}

/// The width, px at the full scale, of the line through `piv` at angle `th` (radians)
/// in `full`: the median, over [`FULL_WIDTH_PROFILES`] profiles across the line at radii
/// spread over `band` (px from `piv`), of each profile's RMS spread about its own middle
/// of its darkness (`dark`; else its brightness) against its ends, above a quarter of
/// its peak, where that middle lies within [`FULL_WIDTH_OFF_PX`] of the line. Only
/// radii where the nearest other line, `apart` radians away, lies beyond the profile by
/// [`FULL_WIDTH_HALF_PX`] count (a wire and its shadow meet at the pivot); none when
/// fewer than a third of the profiles can be measured.
pub(super) fn full_width(
    full: &Full,
    piv: Pt,
    th: f64,
    band: (f64, f64),
    apart: f64,
    dark: bool,
) -> Option<f64> {
    let half = FULL_WIDTH_HALF_PX;
    let n = FULL_WIDTH_PROFILES;
    let r_from = band.0.max(2.0 * half / apart.sin().max(1e-6));
    if r_from >= band.1 {
        return None;
    }
    let (dir, across) = (Pt::new(th.cos(), th.sin()), Pt::new(-th.sin(), th.cos()));
    let steps = 2 * half as usize + 1;
    let mut profile = vec![0.0; steps];
    let mut widths = Vec::with_capacity(n);
    for i in 0..n {
        let r = r_from + (band.1 - r_from) * (i as f64 + 0.5) / n as f64;
        let c = piv + dir * r;
        let mut whole = true;
        for (k, v) in profile.iter_mut().enumerate() {
            match full.at(c + across * (k as f64 - half)) {
                Some(g) => *v = g,
                None => whole = false,
            }
        }
        if !whole {
            continue;
        }
        let base = 0.25 * (profile[0] + profile[1] + profile[steps - 2] + profile[steps - 1]);
        let sign = if dark { -1.0 } else { 1.0 };
        let peak = profile
            .iter()
            .map(|v| sign * (v - base))
            .fold(f64::MIN, f64::max);
        if peak <= 0.0 {
            continue;
        }
        let (mut m0, mut m1, mut m2) = (0.0, 0.0, 0.0);
        for (k, v) in profile.iter().enumerate() {
            let u = (sign * (v - base) - 0.25 * peak).max(0.0);
            let x = k as f64 - half;
            m0 += u;
            m1 += u * x;
            m2 += u * x * x;
        }
        let mean = m1 / m0;
        if mean.abs() > FULL_WIDTH_OFF_PX {
            continue;
        }
        widths.push((m2 / m0 - mean * mean).max(0.0).sqrt());
    }
    if widths.len() * 3 < n {
        return None;
    }
    widths.sort_by(f64::total_cmp);
    Some(widths[widths.len() / 2])
}

/// Which side of a pair of ridges the wire lies on, as the frames showing both have told
/// it. A soft shadow beside a wire lies on the same side of it all along, a few degrees
/// off, and the wire is the sharper ridge, though in any one frame the two widths may
/// differ by a few percent only and either may be the stronger (a copper wire at
/// 960x540: the sharper in 158 of 194 frames, by a median 6 %). Taking the stronger ridge
/// in each frame then follows the wire and its shadow in turn; the side learnt over the
/// frames keeps the wire.
#[derive(Debug, Default)]
pub(in crate::detect::track) struct Ridges {
    /// The frames that voted.
    pub(super) votes: usize,
    /// The sum of the votes' sides (+1: the narrower ridge at the larger angle).
    side_sum: f64,
    /// The sum of the voting pairs' separations, rad.
    sep_sum: f64,
    /// The angle of the last vote's narrower ridge.
    last: Option<f64>,
}

impl Ridges {
    /// A frame's pair: each ridge's angle and width.
    pub(super) fn observe(&mut self, (a0, w0): (f64, f64), (a1, w1): (f64, f64)) {
        let ((an, wn), (aw, ww)) = if w1 < w0 {
            ((a1, w1), (a0, w0))
        } else {
            ((a0, w0), (a1, w1))
        };
        if wn > PAIR_VOTE_RATIO * ww || self.last.is_some_and(|l| (an - l).abs() < PAIR_MOVE) {
            return;
        }
        self.last = Some(an);
        self.votes += 1;
        self.side_sum += (an - aw).signum();
        self.sep_sum += (an - aw).abs();
    }

    /// Ridges whose side is learnt: the wire at the larger angle for `side` +1, the
    /// pairs `sep` rad apart (for the tests).
    #[cfg(test)]
    pub(in crate::detect::track) fn learnt(side: f64, sep: f64) -> Self {
        // All on one side: a lead of `votes`, past `PAIR_LEAD_SIGMAS * sqrt(votes)` from
        // `PAIR_LEAD_SIGMAS^2` votes on.
        let votes = PAIR_MIN_VOTES.max(PAIR_LEAD_SIGMAS.powi(2).ceil() as usize);
        Self {
            votes,
            side_sum: side.signum() * votes as f64,
            sep_sum: sep * votes as f64,
            last: None,
        }
    }

    /// The side the wire lies on (+1 at the larger angle) and the pairs' mean separation
    /// (rad), once known.
    pub(in crate::detect::track) fn side(&self) -> Option<(f64, f64)> {
        let n = self.votes as f64;
        (self.votes >= PAIR_MIN_VOTES && self.side_sum.abs() >= PAIR_LEAD_SIGMAS * n.sqrt())
            .then(|| (self.side_sum.signum(), self.sep_sum / n))
    }

    /// How far past the prediction the search reaches on the wire's side, rad: the
    /// farthest a pair like the learnt one (separation `sep`) lies, and the room the
    /// histogram's peak score needs beyond it.
    pub(in crate::detect::track) fn reach(sep: f64) -> f64 {
        (1.0 + PAIR_SEP_TOL) * sep + PAIR_REACH_MARGIN_DEG.to_radians()
    }
}

impl Tracker {
    /// The histogram bin of the wire: the strongest peak `best` (score, bin), unless a
    /// rival peak (a local maximum of `scores`, each bin's mass against its lower side)
    /// that runs the band is clearly sharper across, or, while tracking, lies within the
    /// gate of the prediction `pred` when the strongest does not and is no wider. A
    /// peak's width is the weighted RMS distance across its line of the evidence (below
    /// the threshold too) nearer to it than to any other peak's; working shrunk, its
    /// width across it in the full-scale frame `full` where that can be measured
    /// ([`full_width`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn sharpest_ridge(
        &mut self,
        scores: &[f64],
        best: (f64, usize),
        cand: &[(Pt, f64, f64)],
        (lo, bin_w): (f64, f64),
        pred: Option<f64>,
        gate: f64,
        full: Option<Full>,
    ) -> Result<(usize, Option<usize>)> {
        let reach = RIVAL_REACH_BINS;
        let own = scores[best.1];
        let is_rival = |i: usize| {
            let s = scores[i];
            i.abs_diff(best.1) > reach
                && s >= RIVAL_SCORE * own
                && scores[i.saturating_sub(reach)..(i + reach + 1).min(scores.len())]
                    .iter()
                    .all(|&o| o <= s)
        };
        // Most frames have no rival: decided without collecting anything.
        if best.0 <= 0.0 || !(0..scores.len()).any(is_rival) {
            return Ok((best.1, None));
        }
        // The strongest first (index 0), then its rivals.
        let peaks: Vec<usize> = std::iter::once(best.1)
            .chain((0..scores.len()).filter(|&i| is_rival(i)))
            .collect();
        let angle_of = |j: usize| lo + (peaks[j] as f64 + 0.5) * bin_w;
        let piv = self.piv;
        let (r_lo, r_hi) = (self.r_lo, self.r_hi);
        let lines: Vec<Line> = (0..peaks.len())
            .map(|j| {
                let th = angle_of(j);
                Line {
                    point: piv,
                    dir: Pt::new(th.cos(), th.sin()),
                }
            })
            .collect();
        let nearest = |q: Pt| -> (usize, f64) {
            lines
                .iter()
                .map(|l| l.distance(q))
                .enumerate()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("two peaks or more")
        };
        // The band's parts each peak's thresholded pixels reach.
        let mut seen = vec![[false; CELLS]; peaks.len()];
        for (q, _, _) in cand {
            let (j, dj) = nearest(*q);
            if dj <= WIDTH_STRIP {
                seen[j][band_part((*q - piv).norm(), (r_lo, r_hi))] = true;
            }
        }
        let cover = |j: usize| seen[j].iter().filter(|c| **c).count() as f64;
        let mut width = Vec::with_capacity(peaks.len());
        let mut px = Vec::new();
        for (j, l) in lines.iter().enumerate() {
            let (mut s2, mut sw) = (0.0, 0.0);
            self.strip_pixels(l, WIDTH_STRIP, &mut px)?;
            for &(q, w) in &px {
                let (k, d) = nearest(q);
                if k == j {
                    s2 += w * d * d;
                    sw += w;
                }
            }
            width.push(if sw > 0.0 {
                (s2 / sw).sqrt()
            } else {
                f64::INFINITY
            });
        }
        // Working shrunk, a sharp wire and its shadow blurred a few px are both about a
        // pixel wide (a 1920x1080 twin at a third of its scale: 1.07 to 1.11 px, either
        // the narrower): measured at the full scale, the wire is the narrower by far.
        if let Some(full) = full {
            let s = self.scale;
            let at_full = piv * s + Pt::repeat(0.5 * (s - 1.0));
            let band = (r_lo * s, r_hi * s);
            let at: Vec<f64> = (0..peaks.len()).map(angle_of).collect();
            let found: Vec<Option<f64>> = (0..peaks.len())
                .map(|j| {
                    let apart = at
                        .iter()
                        .enumerate()
                        .filter(|&(k, _)| k != j)
                        .map(|(_, a)| (a - at[j]).abs())
                        .fold(std::f64::consts::PI, f64::min);
                    full_width(&full, at_full, at[j], band, apart, self.geo.dark)
                })
                .collect();
            if found.iter().all(Option::is_some) {
                width = found.into_iter().flatten().collect();
            }
        }
        let rivals = || (1..peaks.len()).filter(|&j| cover(j) >= RIVAL_COVER * cover(0));
        let mut pick = 0;
        let sharper = if self.starting() || pred.is_none() {
            RIVAL_SHARPER_START
        } else {
            RIVAL_SHARPER
        };
        for j in rivals() {
            if width[j] < sharper * width[0] && width[j] < width[pick] {
                pick = j;
            }
        }
        // The rival nearest the strongest, when close enough to make a pair with it.
        let sep = |j: usize| angle_of(j) - angle_of(0);
        let pair = rivals()
            .filter(|&j| sep(j).abs() <= PAIR_MAX)
            .min_by(|&a, &b| sep(a).abs().total_cmp(&sep(b).abs()));
        let learnt = self.ridges.side();
        if let Some(j) = pair {
            if self.debug.as_deref() == Some("frames") {
                eprintln!(
                    "pair {:.2} w {:.3} / {:.2} w {:.3} cover {} {}",
                    angle_of(0).to_degrees(),
                    width[0],
                    angle_of(j).to_degrees(),
                    width[j],
                    cover(0),
                    cover(j)
                );
            }
            self.ridges
                .observe((angle_of(0), width[0]), (angle_of(j), width[j]));
        }
        // Neither clearly sharper: a pair like the ones seen is told by the side the wire
        // lies on ([`Ridges`]), unless the ridge on that side is clearly wider.
        let mut decided = pick != 0;
        if let (Some(j), Some((side, along))) = (pair, learnt) {
            let like_learnt = (sep(j).abs() - along).abs() <= PAIR_SEP_TOL * along;
            if like_learnt && !decided && !self.starting() {
                // The rival on the shadow's side: the strongest is the wire.
                if sep(j) * side < 0.0 {
                    decided = true;
                } else if width[j] <= RIVAL_WIDER_GATED * width[0] {
                    pick = j;
                    decided = true;
                }
            }
        }
        // Neither clearly sharper: while tracking, a rival within the gate of the
        // prediction is the wire when the strongest lies outside it (the strongest would
        // be refused, and a run of refusals would re-anchor the track on it). The gate
        // is the narrower of the one the frame is accepted by and the configured gate
        // widened by the refused frames. The latter alone let a wire's shadow, stronger
        // once a passing hand had made the wire's frames `disturbed`, win while the
        // acceptance refused it, until the refusals re-anchored the track on it; the
        // former alone, widened by a fast swing's last step, accepted a shadow 3.8 deg
        // from a faint wire. The rival may be a little wider than the strongest (a hand
        // passing over the wire blurred it 6 % wider than its shadow for a few frames),
        // not clearly wider.
        if let Some(p) = pred.filter(|_| !decided && !self.starting()) {
            let gate = gate.min(self.gate * (1.0 + self.since_good as f64));
            let off = |j: usize| (angle_of(j) - p).abs();
            if off(0) > gate {
                if let Some(j) = rivals()
                    .filter(|&j| off(j) <= gate && width[j] <= RIVAL_WIDER_GATED * width[0])
                    .min_by(|&a, &b| off(a).total_cmp(&off(b)))
                {
                    pick = j;
                }
            }
        }
        // The pair's other member, while the side is not known and the capacity for
        // frames awaiting it lasts.
        let other = pair
            .filter(|_| learnt.is_none() && self.undecided.len() < UNDECIDED_MAX_FRAMES)
            .and_then(|j| match pick {
                0 => Some(peaks[j]),
                p if p == j => Some(peaks[0]),
                _ => None,
            });
        Ok((peaks[pick], other))
    }
}
