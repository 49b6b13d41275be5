//! Frames where something static in the swing's path pulls the wire's angle the same
//! way on every swing (`Flag::Pulled`).

use super::{swing_fits, unflagged};
use crate::detect::judge::SwingSpan;
use crate::detect::tuning::{
    FILL_REACH_S, PULL_BASE_DEG, PULL_BIN_DEG, PULL_JOIN_DEG, PULL_MARGIN_DEG, PULL_MAX_SHARE,
    PULL_MIN_BINS, PULL_MIN_DEG, PULL_MIN_FRAMES, PULL_MIN_PASSES, PULL_RING_FROM_DEG, PULL_SIGMAS,
};
use crate::detect::{AngleRow, Flag};
use std::collections::{BTreeMap, BTreeSet};

/// One direction of swing's frames in a bin of angle ([`flag_pulled`]): the sum of
/// their residuals from the swing's path, how many, and the half periods they fall in.
#[derive(Default)]
struct BinSide {
    sum: f64,
    n: usize,
    passes: BTreeSet<i64>,
}

/// Flag the found frames at the angles where something static in the swing's path
/// pulls the wire's measured angle the same way on every swing (`Flag::Pulled`). Each
/// found frame's residual from the swing's own path ([`flag_off_swing`]'s fits, the
/// frame's own step) is put in a bin of [`PULL_BIN_DEG`] by its angle and its
/// direction of swing. A bin is pulled when, in both directions, at least
/// [`PULL_MIN_FRAMES`] frames from [`PULL_MIN_PASSES`] half periods average a residual
/// the same way beyond [`PULL_MIN_DEG`] and [`PULL_SIGMAS`] standard errors (the fits'
/// median robust scatter over the square root of their number), each against the
/// median residual of the same direction's frames [`PULL_RING_FROM_DEG`] to
/// [`PULL_BASE_DEG`] away in angle: the path fitted over two periods misses a wide or
/// oblique swing's shape a little, at the same angle on every swing, but smoothly. At
/// least [`PULL_MIN_BINS`] pulled bins, each within [`PULL_JOIN_DEG`] of the next, make
/// a pull (a line pulls the wire towards it from either side), widened by
/// [`PULL_MARGIN_DEG`] each side, and its frames are flagged where the wire crosses it
/// within [`FILL_REACH_S`] (a dwell there, at a turning point, is left as found), none
/// when they are more than [`PULL_MAX_SHARE`] of the found frames: the fill then
/// bridges each crossing from the frames either side of it. Noise and a codec's errors do not keep their sign
/// from swing to swing; a lag (a rolling shutter, the exposure) turns its sign with the
/// direction of swing. A bright rod through the fulcrum of seed 1's sweep scene 57
/// (1280x720, a dark wire and its shadow 2.1 deg off) pulled the angle by 0.1 to 1.0
/// deg for four or five frames at each crossing, `ok`, twice a period.
pub(super) fn flag_pulled(rows: &mut [AngleRow], span: &SwingSpan) {
    let (at, t, a) = unflagged(rows);
    let mut res: Vec<Option<f64>> = vec![None; t.len()];
    let mut scatters = Vec::new();
    swing_fits(&t, &a, span, |step, window, r, scatter| {
        for (k, r) in window.zip(r) {
            if step.contains(&t[k]) {
                res[k] = Some(*r);
            }
        }
        scatters.push(scatter);
    });
    if scatters.is_empty() {
        return;
    }
    let scatter = crate::numerics::median(&mut scatters);
    // The frames judged: angle, residual, direction of swing (0 rising, 1 falling),
    // time; the direction from the found frames either side, when they lie within an
    // eighth of a period (not across a long loss, beyond a turning point).
    let judged: Vec<(f64, f64, usize, f64)> = (1..t.len().saturating_sub(1))
        .filter(|&k| t[k + 1] - t[k - 1] <= 0.125 * span.period_s)
        .filter_map(|k| {
            let turn = a[k + 1] - a[k - 1];
            (turn != 0.0).then_some((a[k], res[k]?, usize::from(turn < 0.0), t[k]))
        })
        .collect();
    // Each direction's residuals in the order of their angles, for the rings.
    let by_angle: [Vec<(f64, f64)>; 2] = std::array::from_fn(|dir| {
        let mut v: Vec<(f64, f64)> = judged
            .iter()
            .filter(|j| j.2 == dir)
            .map(|j| (j.0, j.1))
            .collect();
        v.sort_by(|x, y| x.0.total_cmp(&y.0));
        v
    });
    let bin = PULL_BIN_DEG.to_radians();
    let half = 0.5 * span.period_s;
    let mut bins: BTreeMap<i64, [BinSide; 2]> = BTreeMap::new();
    for &(ak, r, dir, tk) in &judged {
        let side = &mut bins.entry((ak / bin).floor() as i64).or_default()[dir];
        side.sum += r;
        side.n += 1;
        side.passes
            .insert(((tk - span.first_s) / half).floor() as i64);
    }
    let (ring_from, ring_to) = (PULL_RING_FROM_DEG.to_radians(), PULL_BASE_DEG.to_radians());
    let min = PULL_MIN_DEG.to_radians();
    let pulled: Vec<i64> = bins
        .iter()
        .filter(|(&b, sides)| {
            let centre = (b as f64 + 0.5) * bin;
            let off: Vec<f64> = (0..2)
                .filter_map(|dir| {
                    let s = &sides[dir];
                    if s.n < PULL_MIN_FRAMES || s.passes.len() < PULL_MIN_PASSES {
                        return None;
                    }
                    let v = &by_angle[dir];
                    let within = |lo: f64, hi: f64| {
                        v[v.partition_point(|q| q.0 < lo)..v.partition_point(|q| q.0 <= hi)]
                            .iter()
                            .map(|q| q.1)
                    };
                    let mut ring: Vec<f64> = within(centre - ring_to, centre - ring_from)
                        .chain(within(centre + ring_from, centre + ring_to))
                        .collect();
                    if ring.len() < PULL_MIN_FRAMES {
                        return None;
                    }
                    let off = s.sum / s.n as f64 - crate::numerics::median(&mut ring);
                    let limit = min.max(PULL_SIGMAS * scatter / (s.n as f64).sqrt());
                    (off.abs() > limit).then_some(off)
                })
                .collect();
            off.len() == 2 && off[0].signum() == off[1].signum()
        })
        .map(|(&b, _)| b)
        .collect();
    // The pulls: runs of pulled bins, each within the join of the next, of at least
    // `PULL_MIN_BINS`, widened.
    let join = (PULL_JOIN_DEG / PULL_BIN_DEG).round() as i64;
    let mut runs: Vec<(i64, i64, usize)> = Vec::new();
    for b in pulled {
        match runs.last_mut() {
            Some(last) if b - last.1 <= join => (last.1, last.2) = (b, last.2 + 1),
            _ => runs.push((b, b, 1)),
        }
    }
    let margin = PULL_MARGIN_DEG.to_radians();
    let ranges: Vec<(f64, f64)> = runs
        .into_iter()
        .filter(|r| r.2 >= PULL_MIN_BINS)
        .map(|(lo, hi, _)| (lo as f64 * bin - margin, (hi + 1) as f64 * bin + margin))
        .collect();
    let within = |k: usize| ranges.iter().any(|&(lo, hi)| a[k] >= lo && a[k] < hi);
    // The found frames in a pull, by runs one after another; a run longer than the fill
    // reaches is the wire dwelling at a turning point in the pull's range, not crossing
    // it, and is left as found.
    let mut inside: Vec<usize> = Vec::new();
    let mut k = 0;
    while k < a.len() {
        if !within(k) {
            k += 1;
            continue;
        }
        let start = k;
        while k < a.len() && within(k) {
            k += 1;
        }
        if t[k - 1] - t[start] <= FILL_REACH_S {
            inside.extend(start..k);
        }
    }
    // A pull is local: residuals that keep their sign over much of the swing are a path
    // the fit does not follow (a track on something else), for the other checks.
    if inside.len() as f64 > PULL_MAX_SHARE * a.len() as f64 {
        return;
    }
    for k in inside {
        rows[at[k]].flag = Some(Flag::Pulled);
    }
}
