//! The strip about a line: its pixels, walked once per major axis with each edge pixel
//! counted by its share inside, the wedge test that passes over pixels surely outside
//! the search, and the scan for the pixels over their threshold.

use super::*;

/// A strip's walk ([`Tracker::strip_pixels`]), compiled once for each major axis: `u`
/// runs along the strip (y when `STEEP`, else x), `v` across it.
pub(super) struct StripWalk<'a> {
    pub(super) ev: &'a [u8],
    /// The background behind the evidence, and what a pixel of it weighs
    /// ([`super::contrast`]).
    pub(super) bg: &'a [u8],
    pub(super) contrast: &'a crate::detect::track::contrast::Contrast,
    pub(super) cols: usize,
    pub(super) rows: std::ops::Range<usize>,
    /// The line's point along `u` and `v`, and its direction's `v` and `u`.
    pub(super) line: (f64, f64, f64, f64),
    /// How far across (in `v`) a row reaches either side of the line, and its end.
    pub(super) span: f64,
    pub(super) nv: usize,
    /// The pivot along `u` and `v`, and the band's squared radii.
    pub(super) piv: (f64, f64),
    pub(super) band2: (f64, f64),
    pub(super) half: f64,
    pub(super) across: f64,
}

impl StripWalk<'_> {
    pub(super) fn run<const STEEP: bool>(&self, out: &mut Vec<(Pt, f64)>) {
        let (pu, pv, dv, du) = self.line;
        let (piv_u, piv_v) = self.piv;
        let (r_lo2, r_hi2) = self.band2;
        for u in self.rows.clone() {
            let vc = pv + (u as f64 - pu) * dv / du;
            let v0 = (vc - self.span).ceil().max(0.0) as usize;
            let v1 = ((vc + self.span).floor() + 1.0).clamp(0.0, self.nv as f64) as usize;
            // The same squared distance as `(q - piv).norm_squared()`, its `u` term
            // found once per row (a sum of two terms does not depend on their order).
            let off_u = u as f64 - piv_u;
            let du2 = off_u * off_u;
            // A pixel's mirror image across the line, on the same row: `twice - v`, the
            // rounding of `2 vc - v` found once a row (the same wherever it is >= 0).
            let twice = (2.0 * vc).round() as isize;
            for v in v0..v1 {
                let (x, y) = if STEEP { (v, u) } else { (u, v) };
                let i = y * self.cols + x;
                let w = self.ev[i];
                if w == 0 || self.contrast.is_mark(i) {
                    continue;
                }
                // A mark's mirror image across the line goes with it (the same row's
                // pixel as far on the other side), so that the strip's pixels lie
                // evenly about the line.
                let mirror = twice - v as isize;
                if mirror >= 0 && (mirror as usize) < self.nv {
                    let m = mirror as usize;
                    let j = if STEEP {
                        u * self.cols + m
                    } else {
                        m * self.cols + u
                    };
                    if self.contrast.is_mark(j) {
                        continue;
                    }
                }
                let off_v = v as f64 - piv_v;
                let r2 = off_v * off_v + du2;
                if r2 >= r_lo2 && r2 <= r_hi2 {
                    let share = edge_share(self.half, (v as f64 - vc).abs() * self.across);
                    if share > 0.0 {
                        let w = self.contrast.weight(w, self.bg[i]);
                        out.push((Pt::new(x as f64, y as f64), w * share));
                    }
                }
            }
        }
    }
}

/// A test that passes over, without trigonometry, the pixels that lie surely outside a
/// wedge of angles `lo..hi` about the pivot: those whose direction is further from the
/// wedge's middle than its half width and [`WEDGE_TEST_SLACK`]. The pixels it lets by
/// are tested by their angle as before, so the pixels kept are the same; the slack,
/// far above the rounding of a dot product, leaves a pixel on the wedge's edge to that
/// test.
pub(super) struct WedgeTest {
    /// The middle's direction and the cosine of the half width with its slack; `None`
    /// when the wedge is too wide (half width and slack past a right angle) to be
    /// tested so.
    pub(super) mid: Option<(Pt, f64)>,
}

impl WedgeTest {
    pub(super) fn new(lo: f64, hi: f64) -> Self {
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo) + WEDGE_TEST_SLACK);
        Self {
            mid: (half < std::f64::consts::FRAC_PI_2)
                .then(|| (Pt::new(mid.cos(), mid.sin()), half.cos())),
        }
    }

    /// True when `d` (from the pivot, of length `r`) is surely outside the wedge.
    #[inline]
    pub(super) fn surely(&self, d: Pt, r: f64) -> bool {
        self.mid.is_some_and(|(m, cos)| d.dot(&m) < r * cos)
    }
}

/// The slack of [`WedgeTest`], rad.
pub(super) const WEDGE_TEST_SLACK: f64 = 1e-6;

/// The share of a pixel whose centre lies `dist` px from a strip's line that counts in
/// a strip `half` px either side of it: all of it within `half - STRIP_EDGE`, none
/// beyond `half + STRIP_EDGE`, and in between a linear ramp (the share of a pixel-wide
/// box that lies inside). Counted whole or not at all, the pixels at the edge made the
/// strip a few tenths of a pixel wider on one side than the other, depending on where
/// the line fell between pixel centres: the noise's evidence on the wider side pulled
/// the line, differently in every frame. With the ramp, the angle noise (the error's
/// RMS after the swing scale) of 20 sweep twins fell in 17 and rose in one, by 4 % at
/// the median (a 1 px faint wire under flicker: 0.0229 to 0.0220 deg; a 640x480
/// shadowed dark wire: 0.0034 to 0.0023); of 32 others, drawn apart, it fell in 26 and
/// rose in one.
pub(super) fn edge_share(half: f64, dist: f64) -> f64 {
    ((half + STRIP_EDGE - dist) / (2.0 * STRIP_EDGE)).clamp(0.0, 1.0)
}

/// Half the width of the ramp at a strip's edge ([`edge_share`]), px.
pub(super) const STRIP_EDGE: f64 = 0.5;

/// Calls `found` with the index of every byte of `e` over the same one of `t`, in order.
/// The block [`over_threshold`] passes over at once, bytes.
const SCAN_BLOCK: usize = 32;

/// Most of the wedge lies under its threshold: blocks of [`SCAN_BLOCK`] bytes with none
/// over it are passed over by one comparison of the whole block (vectorised).
pub(super) fn over_threshold(e: &[u8], t: &[u8], mut found: impl FnMut(usize)) {
    let n = e.len().min(t.len());
    let (e, t) = (&e[..n], &t[..n]);
    let mut each = |from: usize, eb: &[u8], tb: &[u8]| {
        for (i, (a, b)) in eb.iter().zip(tb).enumerate() {
            if a > b {
                found(from + i);
            }
        }
    };
    // Whole blocks, each tested at once; then the row's last bytes one by one.
    let (e_blocks, t_blocks) = (e.chunks_exact(SCAN_BLOCK), t.chunks_exact(SCAN_BLOCK));
    let (e_rest, t_rest) = (e_blocks.remainder(), t_blocks.remainder());
    for (k, (eb, tb)) in e_blocks.zip(t_blocks).enumerate() {
        let (eb, tb): (&[u8; SCAN_BLOCK], &[u8; SCAN_BLOCK]) = (
            eb.try_into().expect("a block"),
            tb.try_into().expect("a block"),
        );
        let any = eb.iter().zip(tb).fold(0u8, |m, (a, b)| m | u8::from(a > b));
        if any != 0 {
            each(k * SCAN_BLOCK, eb, tb);
        }
    }
    each(n - e_rest.len(), e_rest, t_rest);
}

/// The parabola across `line` fitted to a strip's pixels `strip` (weighted, within
/// `half` px of it, [`edge_share`]'s ramp at the edges): how far its middle lies from
/// the chord between its ends (px, positive to the left of `line`'s direction: the
/// side `(dir.y, -dir.x)` points to), the share of a shift across the line the strip's
/// centroid follows, and the ends' places along the line (from `line.point`).
///
/// `strip` is walked about `line` (the shares of its edges' pixels are `line`'s). The
/// parabola is fitted to the strip's centroid across the line at each pixel's step
/// along it (`bins` and `devs`, reused from frame to frame), twice more without the
/// steps over [`BOW_OUTLIER_MADS`] robust deviations from it: where a static line crosses
/// the wire (a protractor's ticks, a cable) or the ball's rim meets it, the centroid
/// leaps for a few steps, and a whole-strip fit would bow with it. A strip of width
/// `2 half` holds the wire's profile `p` and cuts its flanks: its centroid follows a
/// shift by `1 - sum over the ramp of |v| p(v) / (2 STRIP_EDGE)` over the strip's
/// weight (the derivative of the windowed centroid): 0.67 for a wire whose profile is
/// a Gaussian of 1 px, 0.89 of 0.7 px, in a 1.75 px half strip. `None` with fewer than
/// [`BOW_MIN_STEPS`] steps.
pub(super) fn strip_parabola(
    line: &Line,
    strip: &[(Pt, f64)],
    half: f64,
    bins: &mut Vec<[f64; 3]>,
    devs: &mut Vec<f64>,
) -> Option<(f64, f64, [f64; 2])> {
    // A pixel's place along the line and across it (to its left).
    let place = |q: &Pt| {
        let d = q - line.point;
        (d.dot(&line.dir), d.x * line.dir.y - d.y * line.dir.x)
    };
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    let (mut total, mut ramp) = (0.0, 0.0);
    for (q, w) in strip {
        let (u, v) = place(q);
        lo = lo.min(u);
        hi = hi.max(u);
        total += w;
        let share = edge_share(half, v.abs());
        if share > 0.0 && share < 1.0 {
            ramp += v.abs() * (w / share) / (2.0 * STRIP_EDGE);
        }
    }
    if hi - lo < 2.0 || total <= 0.0 {
        return None;
    }
    // Each step's weight, weighted offset and place along the line.
    let steps = (hi - lo).round() as usize + 1;
    bins.clear();
    bins.resize(steps, [0.0; 3]);
    for (q, w) in strip {
        let (u, v) = place(q);
        let b = &mut bins[((u - lo).round() as usize).min(steps - 1)];
        b[0] += w;
        b[1] += w * v;
        b[2] += w * u;
    }
    bins.retain(|b| b[0] > 0.0);
    for b in bins.iter_mut() {
        b[1] /= b[0];
        b[2] /= b[0];
    }
    let fit = |bins: &[[f64; 3]], keep: &dyn Fn(&[f64; 3]) -> bool| {
        let (mut a, mut r) = ([[0.0f64; 3]; 3], [0.0f64; 3]);
        let mut n = 0;
        for b in bins.iter().filter(|b| keep(b)) {
            let f = [1.0, b[2], b[2] * b[2]];
            for i in 0..3 {
                r[i] += b[0] * f[i] * b[1];
                for j in 0..3 {
                    a[i][j] += b[0] * f[i] * f[j];
                }
            }
            n += 1;
        }
        (n >= BOW_MIN_STEPS)
            .then(|| {
                nalgebra::Matrix3::from_fn(|i, j| a[i][j])
                    .try_inverse()
                    .map(|m| m * nalgebra::Vector3::from(r))
            })
            .flatten()
    };
    let off =
        |x: &nalgebra::Vector3<f64>, b: &[f64; 3]| b[1] - (x[0] + x[1] * b[2] + x[2] * b[2] * b[2]);
    let mut x = fit(bins, &|_| true)?;
    for _ in 0..2 {
        devs.clear();
        devs.extend(bins.iter().map(|b| off(&x, b).abs()));
        let mid = devs.len() / 2;
        let mad = devs
            .select_nth_unstable_by(mid, f64::total_cmp)
            .1
            .max(BOW_MAD_FLOOR_PX);
        let cut = BOW_OUTLIER_MADS * mad;
        let prev = x;
        x = fit(bins, &|b| off(&prev, b).abs() <= cut)?;
    }
    let h = 0.5 * (hi - lo);
    Some((-x[2] * h * h, 1.0 - ramp / total, [lo, hi]))
}
