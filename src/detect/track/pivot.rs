//! The pivot the streaming pass's own lines meet in: its refinement, its uncertainty
//! and how far the lines stray from it over time; the swing scale that checks it.

use super::Tracker;
use crate::detect::geometry;
use crate::detect::line::{Line, Moments};
use crate::detect::tuning::{
    DRIFT_WINDOW_S, REFINE_CENTRAL, REFINE_HELD_SHARE, REFINE_LINES, REFINE_SLOW_SHARE,
    REFINE_SPREAD_DEG, SWING_SCALE_FRAMES, SWING_SCALE_SPREAD_DEG,
};
use crate::detect::{full_to_shrunk, shrunk_to_full, unwrap_near, AngleRow, Pt, Status};
use crate::lens::Lens;

/// The pivot the pass's lines meet in ([`Tracker::refine_pivot`]).
pub(in crate::detect) struct RefinedPivot {
    /// Full-frame px.
    pub pivot: Pt,
    /// Its standard uncertainty, px ([`pivot_uncertainty`]).
    pub u_px: Option<f64>,
    /// How far the wire's lines stray from it for a while ([`pivot_drift`]), deg.
    pub drift_deg: Option<f64>,
}

impl Tracker {
    /// How much more the wire's own direction turns than its angle about `pivot`
    /// (full-frame px): the slope of each accepted frame's free line fit (its direction
    /// alone, whatever the pivot) against its angle through the pivot, by least squares
    /// over the pass. 1 when the pivot is on the wire's line; a pivot off along the wire
    /// by `delta` at a mean radius `R` gives about `(R + delta) / R`, and scales the
    /// angles' swing, and `s_r` with it, by the inverse. The free fits' noise is in the
    /// regressand, so it does not bias the slope. Frames whose whole strip was not
    /// re-centred ([`KeptMoments::free`]) are left out: their free lines lean towards
    /// the line through the pass's pivot, and pull the slope towards 1 there and away
    /// from it elsewhere. `None` with fewer than
    /// [`SWING_SCALE_FRAMES`] accepted frames or a swing under
    /// [`SWING_SCALE_SPREAD_DEG`].
    ///
    /// Through a lens, both are the undistorted view's: the free line fitted to the
    /// strip's pixels each taken into it (`pixels`: `lens` is the pass's own), else the
    /// image's free line taken into it by two of its points; the angle about the pivot
    /// by [`Lens::plate_angle`].
    ///
    /// [`KeptMoments::free`]: crate::detect::row::KeptMoments::free
    pub(in crate::detect) fn swing_scale(
        &self,
        rows: &[AngleRow],
        pivot: Pt,
        lens: Option<&Lens>,
        pixels: bool,
    ) -> Option<f64> {
        let origin = Pt::new(self.roi_x, self.roi_y);
        let p = full_to_shrunk(pivot, origin, self.scale);
        let to_full = |q: Pt| shrunk_to_full(q, origin, self.scale);
        let band = [self.r_lo * self.scale, self.r_hi * self.scale];
        let half = 0.25 * (self.r_hi - self.r_lo);
        let pairs: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.flag.is_none() && r.status == Status::Ok)
            .filter_map(|r| {
                // A strip not re-centred leans towards the pass's own pivot's line.
                let kept = r.moments.as_ref().filter(|m| m.free[0])?;
                let m = &kept[0];
                let (about, _) = m.line_about(p)?;
                let free = m.free_line()?;
                let (about, free) = match lens {
                    Some(l) if pixels => (
                        l.plate_angle([pivot.x, pivot.y], about, band),
                        kept.plate?[0].free_line()?,
                    ),
                    Some(l) => {
                        let ends = [free.point - free.dir * half, free.point + free.dir * half]
                            .map(|q| {
                                let f = to_full(q);
                                let u = l.undistort([f.x, f.y]);
                                Pt::new(u[0], u[1])
                            });
                        (
                            l.plate_angle([pivot.x, pivot.y], about, band),
                            Line::through(ends[0], ends[1]),
                        )
                    }
                    None => (about, free),
                };
                // The free line has no direction: the branch nearest the angle about
                // the pivot.
                let f = unwrap_near(free.dir.y.atan2(free.dir.x), about);
                let f = if (f - about).abs() > std::f64::consts::FRAC_PI_2 {
                    unwrap_near(f + std::f64::consts::PI, about)
                } else {
                    f
                };
                Some((about, f))
            })
            .collect();
        if pairs.len() < SWING_SCALE_FRAMES {
            return None;
        }
        let n = pairs.len() as f64;
        let mx = pairs.iter().map(|q| q.0).sum::<f64>() / n;
        let my = pairs.iter().map(|q| q.1).sum::<f64>() / n;
        let sxx: f64 = pairs.iter().map(|q| (q.0 - mx).powi(2)).sum();
        let sxy: f64 = pairs.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
        let (lo, hi) = pairs.iter().fold((f64::MAX, f64::MIN), |(lo, hi), q| {
            (lo.min(q.0), hi.max(q.0))
        });
        if hi - lo < SWING_SCALE_SPREAD_DEG.to_radians() || sxx <= 0.0 {
            return None;
        }
        Some(sxy / sxx)
    }

    /// Refine the pivot from the whole pass: the robust intersection of every accepted
    /// frame's free line fit (hundreds of lines at different angles, against the few
    /// dozen of the first seconds), then refit every angle about it from the stored
    /// pixel moments. Returns the pivot in full-frame pixels.
    ///
    /// Through a lens (`video.lens`), the wire's image is a slight curve and its free
    /// lines, chords of it, meet off the pivot: the lines are fitted in the undistorted
    /// view, they are intersected there, and the pivot is taken back into the image.
    /// With `pixels` (`lens` is the pass's own), each is fitted to its strip's pixels
    /// taken each into that view ([`KeptMoments::plate`]); else each image line is
    /// taken into it by two of its points, half the visible band apart. Through the
    /// points, seed 1's sweep scene 21 (a lens of k1 -0.24, its pivot 4 % beyond the
    /// frame's side; drawn clean, no camera defects) had its pivot refined 0.6 px short
    /// along the wire and its swing 0.38 % wide: each image line lay up to 0.17 px off
    /// the chord of the wire's drawn curve, growing with the angle, and the lines,
    /// seen over 20 deg, meet that far off. Through the pixels, the lines pass within
    /// 0.04 px of the true pivot at every angle.
    ///
    /// [`KeptMoments::plate`]: crate::detect::row::KeptMoments::plate
    pub(in crate::detect) fn refine_pivot(
        &self,
        rows: &mut [AngleRow],
        lens: Option<&Lens>,
        pixels: bool,
    ) -> RefinedPivot {
        let origin = Pt::new(self.roi_x, self.roi_y);
        let to_full = |p: Pt| shrunk_to_full(p, origin, self.scale);
        let undistort = |l: &Lens, p: Pt| {
            let f = to_full(p);
            let u = l.undistort([f.x, f.y]);
            full_to_shrunk(Pt::new(u[0], u[1]), origin, self.scale)
        };
        let half = 0.25 * (self.r_hi - self.r_lo);
        let speeds = angular_speeds(rows);
        let found: Vec<FreeLine> = rows
            .iter()
            .zip(speeds)
            .filter(|(r, _)| r.flag.is_none())
            .filter_map(|(r, speed)| {
                let m = r.moments.as_ref()?;
                let ln = m[1].free_line()?;
                let line = match lens {
                    Some(_) if pixels => m.plate?[1].free_line()?,
                    Some(l) => Line::through(
                        undistort(l, ln.point - ln.dir * half),
                        undistort(l, ln.point + ln.dir * half),
                    ),
                    None => ln,
                };
                Some(FreeLine {
                    t_s: r.t_s,
                    line,
                    free: m.free[1],
                    speed,
                })
            })
            .collect();
        let start = lens.map_or(self.piv, |l| undistort(l, self.piv));
        let bound = 0.05 * (self.r_lo + self.r_hi);
        // The slow frames' free lines when many were held (and they locate the pivot),
        // else all of them.
        let refined = refinement_lines(&found)
            .into_iter()
            .chain(std::iter::once(found.iter().collect()))
            .find_map(|set: Vec<&FreeLine>| {
                let lines: Vec<Line> = set.iter().map(|f| f.line).collect();
                let p = refined_pivot(&lines, start, bound)?;
                Some((lines, p))
            });
        let Some((lines, p)) = refined else {
            return RefinedPivot {
                pivot: to_full(self.piv),
                u_px: None,
                drift_deg: None,
            };
        };
        // The drift is the camera's: judged on every frame's line.
        let timed: Vec<(f64, Line)> = found.iter().map(|f| (f.t_s, f.line)).collect();
        let u = pivot_uncertainty(&lines, p).map(|u| u * self.scale);
        let drift_deg = pivot_drift(&timed, p, 0.5 * (self.r_lo + self.r_hi));
        let p = match lens {
            Some(l) => {
                let f = to_full(p);
                let d = l.distort([f.x, f.y]);
                full_to_shrunk(Pt::new(d[0], d[1]), origin, self.scale)
            }
            None => p,
        };
        for r in rows.iter_mut() {
            if let Some((a, _)) = r.moments.as_ref().and_then(|m| m[1].line_about(p)) {
                if let Some(old) = r.angle_rad {
                    r.angle_rad = Some(unwrap_near(a, old));
                }
            }
        }
        RefinedPivot {
            pivot: to_full(p),
            u_px: u,
            drift_deg,
        }
    }
}

/// A frame's free line for the pivot's refinement ([`Tracker::refine_pivot`]).
pub(super) struct FreeLine {
    pub(super) t_s: f64,
    /// The free line of its far strip (undistorted through a lens).
    pub(super) line: Line,
    /// Whether that strip was re-centred on it ([`KeptMoments::free`]).
    ///
    /// [`KeptMoments::free`]: crate::detect::row::KeptMoments::free
    pub(super) free: bool,
    /// The wire's angular speed there, rad/s ([`angular_speeds`]).
    pub(super) speed: Option<f64>,
}

/// Each row's angular speed, rad/s: the central difference of its neighbours' angles
/// (found and not flagged), `None` where either is missing.
pub(super) fn angular_speeds(rows: &[AngleRow]) -> Vec<Option<f64>> {
    (0..rows.len())
        .map(|i| {
            let (a, b) = (rows.get(i.checked_sub(1)?)?, rows.get(i + 1)?);
            let (aa, ab) = (a.unflagged_angle()?, b.unflagged_angle()?);
            let dt = b.t_s - a.t_s;
            (dt > 0.0).then(|| (unwrap_near(ab, aa) - aa).abs() / dt)
        })
        .collect()
}

/// The lines to refine the pivot from before all of `found`: when more than
/// [`REFINE_HELD_SHARE`] of them were not re-centred (their strips held about the
/// current pivot's line, towards which they lean), the re-centred lines of the frames
/// turning slower than [`REFINE_SLOW_SHARE`] of the fast speed (the 95th percentile of
/// theirs); none otherwise. A wire blurred by its speed (a real clip at 25 fps) loses
/// its free line mid-swing in one direction of swing more than the other, and the
/// fast frames' lines pass beside the pivot on the side the wire moves to: the rest of
/// the lines then meet near the pivot they started from, not the wire's.
pub(super) fn refinement_lines(found: &[FreeLine]) -> Option<Vec<&FreeLine>> {
    let held = found.iter().filter(|f| !f.free).count();
    if (held as f64) <= REFINE_HELD_SHARE * found.len() as f64 {
        return None;
    }
    let mut speeds: Vec<f64> = found
        .iter()
        .filter(|f| f.free)
        .filter_map(|f| f.speed)
        .collect();
    if speeds.is_empty() {
        return None;
    }
    speeds.sort_by(f64::total_cmp);
    let fast = speeds[(0.95 * (speeds.len() - 1) as f64).round() as usize];
    Some(
        found
            .iter()
            .filter(|f| f.free && f.speed.is_some_and(|w| w < REFINE_SLOW_SHARE * fast))
            .collect(),
    )
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
