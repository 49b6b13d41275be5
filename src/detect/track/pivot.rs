//! The pivot the streaming pass's own lines meet in: its refinement, its uncertainty
//! and how far the lines stray from it over time.

use crate::detect::geometry;
use crate::detect::line::Line;
use crate::detect::{unwrap_near, Pt};

/// The pivot the pass's lines meet in ([`Tracker::refine_pivot`]).
pub(in crate::detect) struct RefinedPivot {
    /// Full-frame px.
    pub pivot: Pt,
    /// Its standard uncertainty, px ([`pivot_uncertainty`]).
    pub u_px: Option<f64>,
    /// How far the wire's lines stray from it for a while ([`pivot_drift`]), deg.
    pub drift_deg: Option<f64>,
}

/// How far the wire's free lines pass from the pivot `p` for a while, as an angle seen
/// from the band's middle radius `r` (px, the lines' scale): the largest median signed
/// distance over [`DRIFT_WINDOW_S`] windows, at `r`, deg. A camera that moved and was
/// not followed moves the wire's lines off the pivot it found; the lines of a still
/// camera pass through it all along (on either side of it by their noise).
pub(super) fn pivot_drift(timed: &[(f64, Line)], p: Pt, r: f64) -> Option<f64> {
    let (t0, t1) = (timed.first()?.0, timed.last()?.0);
    let windows = ((t1 - t0) / DRIFT_WINDOW_S).floor() as usize;
    if windows < 2 || r <= 0.0 {
        return None;
    }
    // Signed: the side of the wire (pointing away from the pivot) the pivot lies on.
    let signed = |l: &Line| {
        let out = if (l.point - p).dot(&l.dir) >= 0.0 {
            l.dir
        } else {
            -l.dir
        };
        (p - l.point).dot(&Pt::new(-out.y, out.x))
    };
    let mut worst = 0.0f64;
    for k in 0..windows {
        let (a, b) = (
            t0 + k as f64 * DRIFT_WINDOW_S,
            t0 + (k + 1) as f64 * DRIFT_WINDOW_S,
        );
        let mut d: Vec<f64> = timed
            .iter()
            .filter(|(t, _)| *t >= a && *t < b)
            .map(|(_, l)| signed(l))
            .collect();
        if d.len() < 10 {
            continue;
        }
        d.sort_by(f64::total_cmp);
        worst = worst.max(d[d.len() / 2].abs());
    }
    Some((worst / r).atan().to_degrees())
}

/// The windows [`pivot_drift`] takes the median of, s.
const DRIFT_WINDOW_S: f64 = 2.0;

/// The standard uncertainty of `p`, the least-squares intersection of `lines`, px (the
/// radius along its worst direction): the lines' scatter about it (those within three
/// times the median distance: the robust fit's own), through the normal equations,
/// sigma^2 (sum n n^T)^-1, whose largest eigenvalue is taken.
pub(super) fn pivot_uncertainty(lines: &[Line], p: Pt) -> Option<f64> {
    let mut d: Vec<f64> = lines.iter().map(|l| l.distance(p)).collect();
    d.sort_by(f64::total_cmp);
    let cut = 3.0 * d.get(d.len() / 2)?.max(1e-6);
    let (mut a11, mut a12, mut a22, mut ss, mut k) = (0.0, 0.0, 0.0, 0.0, 0usize);
    for l in lines.iter().filter(|l| l.distance(p) <= cut) {
        let n = Pt::new(-l.dir.y, l.dir.x);
        a11 += n.x * n.x;
        a12 += n.x * n.y;
        a22 += n.y * n.y;
        ss += l.distance(p).powi(2);
        k += 1;
    }
    if k < 3 {
        return None;
    }
    let sigma2 = ss / (k - 2) as f64;
    // The smallest eigenvalue of [[a11, a12], [a12, a22]] is the largest of its inverse.
    let (tr, det) = (a11 + a22, a11 * a22 - a12 * a12);
    let lmin = 0.5 * tr - (0.25 * tr * tr - det).max(0.0).sqrt();
    (lmin > 0.0).then(|| (sigma2 / lmin).sqrt())
}

/// The robust intersection of the pass's free `lines` when it refines `piv`: at least
/// [`REFINE_LINES`] lines, the central [`REFINE_CENTRAL`] of their directions spread
/// over [`REFINE_SPREAD_DEG`] or more, and the intersection within `bound` px of `piv`
/// (a refinement, not a jump elsewhere). Nearly parallel lines locate nothing along
/// their direction, and a few lines at other angles do not change that: the spread is
/// that of the central share, not the extremes'. Judged by its extremes, a pass that
/// sat on a protractor's numerals (lines within 0.5 deg of one another) with a few
/// frames on the wire 3 deg away moved a 1280x720 twin's pivot 12 px along the wire.
pub(super) fn refined_pivot(lines: &[Line], piv: Pt, bound: f64) -> Option<Pt> {
    if lines.len() < REFINE_LINES || central_spread(lines) < REFINE_SPREAD_DEG.to_radians() {
        return None;
    }
    let p = geometry::intersect(lines).ok()?;
    ((p - piv).norm() <= bound).then_some(p)
}

/// How far the central [`REFINE_CENTRAL`] of the lines' directions spread (rad): each
/// direction (a line has no sense) measured from their mean, the mean of the doubled
/// angles halved, so that lines either side of horizontal are near one another.
pub(super) fn central_spread(lines: &[Line]) -> f64 {
    let doubled = |l: &Line| 2.0 * l.dir.y.atan2(l.dir.x);
    let (s, c) = lines.iter().fold((0.0, 0.0), |(s, c), l| {
        (s + doubled(l).sin(), c + doubled(l).cos())
    });
    let mean = 0.5 * f64::atan2(s, c);
    let mut off: Vec<f64> = lines
        .iter()
        .map(|l| 0.5 * unwrap_near(doubled(l), 2.0 * mean) - mean)
        .collect();
    if off.is_empty() {
        return 0.0;
    }
    off.sort_by(f64::total_cmp);
    let tail = (0.5 * (1.0 - REFINE_CENTRAL) * (off.len() - 1) as f64).round() as usize;
    off[off.len() - 1 - tail] - off[tail]
}

/// Fewest free lines, and the share of them whose directions must spread over
/// [`REFINE_SPREAD_DEG`], for [`refined_pivot`].
const REFINE_LINES: usize = 20;
const REFINE_CENTRAL: f64 = 0.8;
const REFINE_SPREAD_DEG: f64 = 2.0;
