//! A swing's features from its angles: the crossings of the rest angle and the
//! turning points between them, the periods, the noise, the stalls, the rest angle from
//! turning points and the spans between them.

use crate::detect::tuning::{
    AT_REST_MIN, DYING_SHARE_MAX, EVEN_TIMES, MAX_GAP_S, STALL_RANGE, STOP_SHARE,
};
use crate::detect::{AngleRow, Status};

/// The swing's crossings of `rest` and its turning points.
pub(super) struct Swing {
    /// Times of upward and of downward crossings, s, and the run of found frames (no
    /// gap of more than [`MAX_GAP_S`]) each lies in.
    pub up: Vec<(f64, usize)>,
    pub down: Vec<(f64, usize)>,
    /// The turning points between crossings: (time, angle).
    pub turns: Vec<(f64, f64)>,
    /// How many times the angle went from one side of `rest` to the other (beyond the
    /// hysteresis), timed or not.
    pub sides: usize,
}

/// Crossings of `rest` with hysteresis `h` (the angle must go beyond `rest +- h` to count
/// as on that side), each timed where the angle crosses `rest` (interpolated between the
/// frames about its last crossing), and the extremes between them.
pub(super) fn swing(t: &[f64], a: &[f64], rest: f64, h: f64) -> Swing {
    let mut s = Swing {
        up: Vec::new(),
        down: Vec::new(),
        turns: Vec::new(),
        sides: 0,
    };
    let mut side = 0i8;
    let mut last_cross: Option<f64> = None;
    let mut ext: Option<(f64, f64)> = None;
    let mut whole = false;
    let step = median(t.windows(2).map(|w| w[1] - w[0]).collect());
    let mut run = 0usize;
    for i in 0..a.len() {
        // A gap: no crossing is timed across it, and none after pairs with one before.
        let gap = i > 0 && t[i] - t[i - 1] > (1.5 * step).max(MAX_GAP_S);
        if gap {
            run += 1;
            last_cross = None;
        }
        if i > 0 && (a[i - 1] - rest) * (a[i] - rest) <= 0.0 && a[i] != a[i - 1] && !gap {
            let f = (rest - a[i - 1]) / (a[i] - a[i - 1]);
            last_cross = Some(t[i - 1] + f * (t[i] - t[i - 1]));
        }
        let now = if a[i] > rest + h {
            1
        } else if a[i] < rest - h {
            -1
        } else {
            0
        };
        if now != 0 && now != side {
            if side != 0 {
                s.sides += 1;
                if let Some(tc) = last_cross {
                    if now > 0 { &mut s.up } else { &mut s.down }.push((tc, run));
                }
                // The first side's extreme may be where the video starts, not a turn.
                if let Some(e) = ext.take().filter(|_| whole) {
                    s.turns.push(e);
                }
                whole = true;
            }
            side = now;
            ext = None;
        }
        if side != 0 {
            let beyond = ext.is_none_or(|(_, v)| (a[i] - v) * side as f64 > 0.0);
            if beyond {
                ext = Some((t[i], a[i]));
            }
        }
    }
    s
}

/// When a swing seen to die out is over, s: a `period` after the last found angle off
/// `rest` by more than [`STOP_SHARE`] of `scale`, when at least [`AT_REST_MIN`] found
/// angles follow it (all at rest, then) and the found angles of the period before it
/// lie within [`DYING_SHARE_MAX`] of `scale` of rest: the swing was seen to shrink to
/// nothing, not lost halfway. `None` for a swing that lasts to the end, or was lost.
/// A wire at rest fades into the still scene: its frames after the swing say nothing
/// of how well the swing was followed.
pub(super) fn swing_end(t: &[f64], a: &[f64], rest: f64, scale: f64, period: f64) -> Option<f64> {
    if !(scale > 0.0 && period > 0.0) {
        return None;
    }
    let off = |x: f64| (x - rest).abs() / scale;
    let last = a.iter().rposition(|&x| off(x) > STOP_SHARE)?;
    if a.len() - 1 - last < AT_REST_MIN {
        return None;
    }
    let end = t[last];
    let dying = t
        .iter()
        .zip(a)
        .filter(|(&ti, _)| ti > end - period && ti <= end)
        .all(|(_, &x)| off(x) <= DYING_SHARE_MAX);
    dying.then_some(end + period)
}

/// The median of `v` (NaN when empty).
pub(super) fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    crate::numerics::median(&mut v)
}

/// The periods between successive crossings in the same sense, in one run of found
/// frames (a person passing in front of the wire hides crossings).
pub(super) fn periods(s: &Swing) -> Vec<f64> {
    let diffs = |v: &[(f64, usize)]| {
        v.windows(2)
            .filter(|w| w[0].1 == w[1].1)
            .map(|w| w[1].0 - w[0].0)
            .collect::<Vec<_>>()
    };
    let mut p = diffs(&s.up);
    p.extend(diffs(&s.down));
    p
}

/// Fourth differences of the angles over runs of five consecutive found frames, and the
/// index of each run's middle frame. Each is taken at the frames' own times
/// ([`fourth_difference_weights`]): a phone's variable frame rate, or a dropped frame,
/// does not read as noise.
pub(super) fn fourth_differences(rows: &[AngleRow]) -> Vec<(usize, f64)> {
    weighted_fourth_differences(rows)
        .map(|(mid, _, d)| (mid, d))
        .collect()
}

/// [`fourth_differences`] with the weights each was taken with.
fn weighted_fourth_differences(
    rows: &[AngleRow],
) -> impl Iterator<Item = (usize, [f64; 5], f64)> + '_ {
    rows.windows(5).enumerate().filter_map(|(i, w)| {
        let ok = w
            .iter()
            .all(|r| r.status == Status::Ok && r.angle_rad.is_some())
            && w.windows(2).all(|p| p[1].frame == p[0].frame + 1);
        ok.then(|| {
            let c = fourth_difference_weights(w);
            let d = w
                .iter()
                .zip(c)
                .map(|(r, c)| c * r.angle_rad.unwrap_or(0.0))
                .sum();
            (i + 2, c, d)
        })
    })
}

/// The fourth differences of a quantity `x` known by row (none where it is not) paired
/// with the angles' over the same runs of five found frames (see
/// [`fourth_differences`]): `(x's, the angles')`, for a regression of the angles' noise
/// on it.
pub(in crate::detect) fn paired_fourth_differences(
    rows: &[AngleRow],
    x: &[Option<f64>],
) -> Vec<(f64, f64)> {
    weighted_fourth_differences(rows)
        .filter_map(|(mid, c, da)| {
            let v: Option<Vec<f64>> = x[mid - 2..=mid + 2].iter().copied().collect();
            v.map(|v| (v.iter().zip(c).map(|(v, c)| c * v).sum(), da))
        })
        .collect()
}

/// The weights of a fourth difference over five frames: `(1, -4, 6, -4, 1)` where their
/// intervals are even (each within [`EVEN_TIMES`] of their mean), else the fourth
/// divided difference's at the frames' times, `1 / prod_(j != i) (t_i - t_j)`, which is
/// zero on any cubic, scaled to the same signs and sum of squares (70), so that one
/// frame's noise reads the same either way (over [`D4_GAIN`]). On even times the two are
/// the same weights.
pub(super) fn fourth_difference_weights(w: &[AngleRow]) -> [f64; 5] {
    const EVEN: [f64; 5] = [1.0, -4.0, 6.0, -4.0, 1.0];
    let t: [f64; 5] = std::array::from_fn(|k| w[k].t_s);
    let mean = (t[4] - t[0]) / 4.0;
    let even = mean > 0.0
        && t.windows(2)
            .all(|p| ((p[1] - p[0]) / mean - 1.0).abs() <= EVEN_TIMES);
    if even {
        return EVEN;
    }
    let mut c = [0.0; 5];
    for (i, ci) in c.iter_mut().enumerate() {
        let prod: f64 = (0..5).filter(|&j| j != i).map(|j| t[i] - t[j]).product();
        *ci = 1.0 / prod;
    }
    let norm = c.iter().map(|c| c * c).sum::<f64>().sqrt();
    if !norm.is_finite() || norm == 0.0 {
        // Two frames at one time: no difference can be taken at their times.
        return EVEN;
    }
    c.map(|c| c * D4_GAIN / norm)
}

/// The least-squares slope through the origin of `(x, y)` pairs, and the slope over its
/// standard error; `None` when the `x` are all 0.
pub(in crate::detect) fn slope_through_origin(pairs: &[(f64, f64)]) -> Option<(f64, f64)> {
    let sxx: f64 = pairs.iter().map(|p| p.0 * p.0).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = pairs.iter().map(|p| p.0 * p.1).sum();
    let b = sxy / sxx;
    let s2 = pairs.iter().map(|p| (p.1 - b * p.0).powi(2)).sum::<f64>() / (pairs.len() - 1) as f64;
    Some((b, b / (s2 / sxx).sqrt().max(f64::MIN_POSITIVE)))
}

/// The noise of a series from its fourth differences `d4`: their robust standard
/// deviation (1.4826 times the median absolute value) over [`D4_GAIN`].
pub(super) fn noise_of(d4: impl Iterator<Item = f64>) -> f64 {
    1.4826 * median(d4.map(f64::abs).collect()) / D4_GAIN
}

/// Frames within `span` (times, s) that lie in a run of `window` frames whose angles
/// stay within [`STALL_RANGE`] of the local amplitude about `rest` (the largest swing
/// within five windows either side: about half a period), in the middle half of the
/// swing, where a pendulum moves fastest. Not at its turning points: there rolling
/// friction holds a ball whose swing nears the friction's dead band for a while (the
/// restoring force barely beats the friction once the ball has turned).
pub(super) fn stalled_frames(
    t: &[f64],
    a: &[f64],
    window: usize,
    rest: f64,
    span: (f64, f64),
) -> usize {
    let mut stalled = vec![false; a.len()];
    let reach = 5 * window;
    for (i, w) in a.windows(window).enumerate() {
        if t[i] < span.0 || t[i + window - 1] > span.1 {
            continue;
        }
        let (lo, hi) = w
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            });
        let around = &a[i.saturating_sub(reach)..(i + window + reach).min(a.len())];
        let amplitude = around.iter().fold(0.0f64, |m, &x| m.max((x - rest).abs()));
        let mid = 0.5 * (lo + hi);
        if hi - lo < STALL_RANGE * amplitude && (mid - rest).abs() < 0.5 * amplitude {
            stalled[i..i + window].iter_mut().for_each(|s| *s = true);
        }
    }
    stalled.iter().filter(|&&s| s).count()
}

/// The RMS of `(time, value)` pairs about their least-squares parabola.
pub(super) fn quadratic_rms(v: &[(f64, f64)]) -> f64 {
    let mid = v.iter().map(|p| p.0).sum::<f64>() / v.len() as f64;
    let rows = v.iter().map(|p| {
        let x = p.0 - mid;
        ([1.0, x, x * x], p.1)
    });
    let Some(c) = crate::numerics::least_squares3(rows) else {
        return 0.0;
    };
    let ss: f64 = v
        .iter()
        .map(|p| {
            let x = p.0 - mid;
            (p.1 - c[0] - c[1] * x - c[2] * x * x).powi(2)
        })
        .sum();
    (ss / (v.len() as f64 - 3.0).max(1.0)).sqrt()
}

/// The RMS of `(time, value)` pairs about their least-squares line.
pub(super) fn detrended_rms(v: &[(f64, f64)]) -> f64 {
    let n = v.len() as f64;
    let (mt, my) = v
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + p.1 / n));
    let (sty, stt) = v.iter().fold((0.0, 0.0), |(a, b), p| {
        (a + (p.0 - mt) * (p.1 - my), b + (p.0 - mt).powi(2))
    });
    let slope = if stt > 0.0 { sty / stt } else { 0.0 };
    let ss: f64 = v
        .iter()
        .map(|p| (p.1 - my - slope * (p.0 - mt)).powi(2))
        .sum();
    (ss / (n - 2.0).max(1.0)).sqrt()
}

/// Each turning point refined by a parabola through the angles within `half` frames
/// of it, and (at the middle one's time) the rest angle of each three successive ones, half a
/// swing apart: `(x0 + 2 x1 + x2) / 4`, exact for a linearly decaying swing.
pub(super) fn rest_from_turns(
    t: &[f64],
    a: &[f64],
    turns: &[(f64, f64)],
    half: usize,
) -> Vec<(f64, f64)> {
    let refined = refined_turns(t, a, turns, half);
    // Three turning points one half swing apart each (none lost in between).
    let half_swing = median(turns.windows(2).map(|w| w[1].0 - w[0].0).collect());
    let apart = |a: (f64, f64), b: (f64, f64)| ((b.0 - a.0) / half_swing - 1.0).abs() < 0.3;
    refined
        .windows(3)
        .filter_map(|w| {
            let (x0, x1, x2) = (w[0]?, w[1]?, w[2]?);
            (apart(x0, x1) && apart(x1, x2)).then_some((x1.0, 0.25 * (x0.1 + 2.0 * x1.1 + x2.1)))
        })
        .collect()
}

/// The swing from each refined turning point to the next, half a swing apart: (the
/// time between them, the angle between them).
pub(super) fn spans(t: &[f64], a: &[f64], turns: &[(f64, f64)], half: usize) -> Vec<(f64, f64)> {
    let refined = refined_turns(t, a, turns, half);
    let half_swing = median(turns.windows(2).map(|w| w[1].0 - w[0].0).collect());
    refined
        .windows(2)
        .filter_map(|w| {
            let (x0, x1) = (w[0]?, w[1]?);
            (((x1.0 - x0.0) / half_swing - 1.0).abs() < 0.3)
                .then(|| (0.5 * (x0.0 + x1.0), (x1.1 - x0.1).abs()))
        })
        .collect()
}

/// Each turning point refined by a parabola through the found angles within `half`
/// frames of it: (time, angle), `None` where frames are missing about it.
pub(super) fn refined_turns(
    t: &[f64],
    a: &[f64],
    turns: &[(f64, f64)],
    half: usize,
) -> Vec<Option<(f64, f64)>> {
    turns
        .iter()
        .map(|&(tt, _)| {
            let i = t.iter().position(|&x| x == tt)?;
            let (lo, hi) = (i.checked_sub(half)?, i + half);
            // Found frames only, one after the other (none filled in between).
            let step = t.get(lo + 1)? - t[lo];
            if hi >= a.len() || t[hi] - t[lo] > 2.0 * half as f64 * step * 1.5 {
                return None;
            }
            let rows = (lo..=hi).map(|j| {
                let x = t[j] - tt;
                ([1.0, x, x * x], a[j])
            });
            let c = crate::numerics::least_squares3(rows)?;
            (c[2] != 0.0).then(|| (tt, c[0] - c[1] * c[1] / (4.0 * c[2])))
        })
        .collect()
}

/// A fourth difference's standard deviation over that of one frame's noise: sqrt(70).
pub(super) const D4_GAIN: f64 = 8.366_600_265_340_756;
