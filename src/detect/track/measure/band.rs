//! The band's parts by distance from the pivot: how many of them a histogram bin's
//! evidence reaches, and the parts whose pixels stray from the fitted line.

use super::*;
use crate::detect::tuning::{
    CELLS, COVERED_FULL, HEAVY_COUNTS, HEAVY_TIMES, STRAY_MAX_SHARE, STRAY_MIN_PX, STRAY_TIMES,
};

/// The part of the band `r_lo..r_hi` (0 to [`CELLS`] - 1) a pixel `r` px from the pivot
/// lies in.
pub(super) fn band_part(r: f64, (r_lo, r_hi): (f64, f64)) -> usize {
    (((r - r_lo) / (r_hi - r_lo)) * CELLS as f64).clamp(0.0, (CELLS - 1) as f64) as usize
}

/// Each angle bin's evidence (`cells`, [`CELLS`] parts of the band per bin) times the
/// share of [`COVERED_FULL`] parts it reaches, at most 1. A wire runs the band; the rim
/// of the bob at the band's end (the wire's line runs on over the bob) is a crescent
/// that holds as much evidence in its three or four parts as a faint wire in all of
/// them. On a 1280x720
/// oblique twin with a 1 px wire, the bob come to a turning point beside its wire took
/// the histogram's peak, 1.4 deg off, for up to ten frames at each turning point on
/// that side (angle RMS 0.10 deg, s_r -2.4 %).
pub(super) fn covered_bins(cells: &[f64], histo: &mut [f64]) {
    for (h, bin) in histo.iter_mut().zip(cells.chunks_exact(CELLS)) {
        let (mut sum, mut seen) = (0.0, 0usize);
        for &c in bin {
            sum += c;
            seen += usize::from(c > 0.0);
        }
        *h = sum * (seen as f64 / COVERED_FULL as f64).min(1.0);
    }
}

/// Drops from a strip (`pts`, about `piv` in the band `r_lo..r_hi`, fitted by `fitted`)
/// the pixels of the band's parts ([`CELLS`]) whose weighted mean distance across the
/// line strays from the other parts' ([`STRAY_MIN_PX`], [`STRAY_TIMES`]); true when
/// any went. They are judged against `fitted`, or, where parts are heavy
/// ([`HEAVY_TIMES`]), against the line fitted with those made lighter: the rim of a bob
/// beside its wire at a turning point (the twin above) held seven times the evidence of
/// the wire's parts in the last two parts, 1 px to one side, and turned the fitted line
/// half way towards it, so that judged against that line no part strayed. With the
/// histogram's peak on the wire and the rim's parts dropped, that twin's angle RMS went
/// from 0.10 to 0.037 deg. A strip with no stray part is left as it was.
pub(super) fn drop_stray_parts(
    piv: Pt,
    band: (f64, f64),
    fitted: Line,
    pts: &mut Vec<(Pt, f64)>,
    parts: &mut Vec<u8>,
) -> bool {
    // Each pixel's part, found once.
    parts.clear();
    parts.extend(
        pts.iter()
            .map(|(q, _)| band_part((q - piv).norm(), band) as u8),
    );
    let mut sums = [0.0f64; CELLS];
    for (&(_, w), &c) in pts.iter().zip(parts.iter()) {
        sums[c as usize] += w;
    }
    let Some(median) = median_of_positive(&sums) else {
        return false;
    };
    let line = if sums.iter().any(|&s| s > HEAVY_TIMES * median) {
        // The fit through the pivot of the pixels so weighed (no copy of the strip).
        let cap = HEAVY_COUNTS * median;
        let m = moments_of(pts.iter().zip(parts.iter()).map(|(&(q, w), &c)| {
            let s = sums[c as usize];
            (q, if s > cap { w * cap / s } else { w })
        }));
        match line_through_moments(piv, &m).filter(|_| pts.len() >= 2) {
            Some(l) => l,
            None => return false,
        }
    } else {
        fitted
    };
    // Each part's weighted mean signed distance across the line, then its size.
    let normal = line.normal();
    let mut offs = [0.0f64; CELLS];
    for (&(q, w), &c) in pts.iter().zip(parts.iter()) {
        offs[c as usize] += w * (q - line.point).dot(&normal);
    }
    let mut mean = [0.0f64; CELLS];
    for c in 0..CELLS {
        if sums[c] > 0.0 {
            mean[c] = (offs[c] / sums[c]).abs();
        }
    }
    let Some(typical) = median_of_positive(&mean) else {
        return false;
    };
    let limit = STRAY_MIN_PX.max(STRAY_TIMES * typical);
    let stray: [bool; CELLS] = std::array::from_fn(|c| sums[c] > 0.0 && mean[c] > limit);
    let count = stray.iter().filter(|s| **s).count();
    let seen = sums.iter().filter(|s| **s > 0.0).count();
    if count == 0 || count as f64 > STRAY_MAX_SHARE * seen as f64 {
        return false;
    }
    let mut kept = 0;
    for i in 0..pts.len() {
        if !stray[parts[i] as usize] {
            pts[kept] = pts[i];
            kept += 1;
        }
    }
    pts.truncate(kept);
    true
}

/// The median of the positive values of `v` (four or more of them), else `None`.
pub(super) fn median_of_positive(v: &[f64; CELLS]) -> Option<f64> {
    let mut seen = [0.0f64; CELLS];
    let mut n = 0;
    for &x in v {
        if x > 0.0 {
            seen[n] = x;
            n += 1;
        }
    }
    (n >= 4).then(|| {
        let seen = &mut seen[..n];
        seen.sort_unstable_by(f64::total_cmp);
        seen[n / 2]
    })
}
