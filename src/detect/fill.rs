//! After the pass: flagged frames filled from their good neighbours, and operator
//! marks.

use super::judge::SwingSpan;
use super::steady::Steadied;
use super::{unwrap_near, AngleRow, Flag, Pt, Status};
use crate::detect::tuning::{
    BEYOND_SWING_SHARE, FILL_REACH_S, ISOLATED_RUN, JUMP_MIN_DEG, JUMP_STEPS, LEAP_RUN_PERIODS,
    LEAP_SPEED_TIMES, LOSS_EDGE_MIN_DEG, LOSS_EDGE_S, LOSS_FRAMES, OFF_SWING_KEEP_SIGMAS,
    OFF_SWING_MIN_DEG, OFF_SWING_MIN_FIT, OFF_SWING_ROUNDS, OFF_SWING_SIGMAS,
    STILL_BEYOND_BAND_DEG, STILL_BEYOND_PRIOR_S, STILL_BEYOND_QUANTILE, STILL_BEYOND_S,
    STILL_BEYOND_SHARE,
};
use std::collections::BTreeMap;

/// Operator marks replace the detection: the angle of the line through the two points,
/// pointing away from the pivot, on the branch within half a turn of `reference` (the
/// wire's direction in the first look), as the detected angles are.
pub(super) fn apply_marks(
    rows: &mut [AngleRow],
    marks: &BTreeMap<u64, [[f64; 2]; 2]>,
    pivot: Pt,
    reference: f64,
) {
    for r in rows.iter_mut() {
        if let Some([[x1, y1], [x2, y2]]) = marks.get(&r.frame) {
            let (a, b) = (Pt::new(*x1, *y1), Pt::new(*x2, *y2));
            let (near, far) = if (a - pivot).norm() <= (b - pivot).norm() {
                (a, b)
            } else {
                (b, a)
            };
            let d = far - near;
            r.angle_rad = Some(unwrap_near(d.y.atan2(d.x), reference));
            r.status = Status::Manual;
            r.flag = None;
            r.quality = 1.0;
        }
    }
}

/// Flag the found frames of a moving camera whose motion could not be measured
/// (`Flag::Unsteadied`; `steadied` in frame order): steadied by the last motion
/// measured, their angles carry whatever the camera did since. A person hiding the
/// static scene for a second hides part of the wire too.
pub(super) fn flag_unsteadied(rows: &mut [AngleRow], steadied: &[Steadied]) {
    debug_assert!(steadied.windows(2).all(|w| w[0].index < w[1].index));
    for r in rows.iter_mut().filter(|r| r.flag.is_none()) {
        let at = steadied.binary_search_by_key(&r.frame, |s| s.index).ok();
        if at.is_some_and(|i| !steadied[i].measured) {
            r.flag = Some(Flag::Unsteadied);
        }
    }
}

/// Flag the good frames of a short run between two losses of the wire: a track that
/// finds something for a frame or two while a person walks in front of the wire (the
/// gate wide open after the loss) is as likely on the person's edge as on the wire.
/// On a twin with a walker (1920x1080, copper), two such frames were 7.5 deg off and
/// called `ok`, and the frames filled from them up to 6 deg off.
pub(super) fn flag_isolated(rows: &mut [AngleRow]) {
    let bad = |r: &AngleRow| r.flag.is_some() || r.angle_rad.is_none();
    for (start, end) in good_runs(rows) {
        let lost_before = start >= LOSS_FRAMES && rows[start - LOSS_FRAMES..start].iter().all(bad);
        let lost_after =
            end + LOSS_FRAMES <= rows.len() && rows[end..end + LOSS_FRAMES].iter().all(bad);
        if end - start < ISOLATED_RUN && lost_before && lost_after {
            for r in &mut rows[start..end] {
                r.flag = Some(Flag::Isolated);
            }
        }
    }
}

/// The runs of good frames (an angle, no flag), each as `start..end` row indices.
fn good_runs(rows: &[AngleRow]) -> Vec<(usize, usize)> {
    runs_where(rows, true)
}

/// The longest runs of rows with an unflagged angle (`good`) or without one (`!good`),
/// each as `start..end` row indices.
fn runs_where(rows: &[AngleRow], good: bool) -> Vec<(usize, usize)> {
    let mut runs = Vec::new();
    let mut i = 0;
    while i < rows.len() {
        if rows[i].unflagged_angle().is_some() != good {
            i += 1;
            continue;
        }
        let start = i;
        while i < rows.len() && rows[i].unflagged_angle().is_some() == good {
            i += 1;
        }
        runs.push((start, i));
    }
    runs
}

/// Flag the good frames of a short run (under [`ISOLATED_RUN`] frames) whose angle lies
/// beyond the range of the angles of the longer runs by more than
/// [`BEYOND_SWING_SHARE`] of that range (`Flag::Beyond`): a swing never grows, so such
/// a frame is not on the wire. Judged after [`flag_jumps`], which breaks up the runs a
/// track on something else makes by leaving its path. A person walking past at a
/// turning point hid the wire for
/// 0.7 s, and the track, its gate wide open, took their edge in two frames 42 and 23
/// deg off, each between short losses (no loss of three frames on both sides, so not
/// `isolated`) and `ok`; the frames filled from them were up to 48 deg off, and the fit
/// refused the series (seed 7's sweep scene 15).
pub(super) fn flag_beyond_swing(rows: &mut [AngleRow]) {
    let runs = good_runs(rows);
    let long = runs
        .iter()
        .filter(|(s, e)| e - s >= ISOLATED_RUN)
        .flat_map(|&(s, e)| rows[s..e].iter().filter_map(AngleRow::unflagged_angle));
    let (lo, hi) = long.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), a| {
        (lo.min(a), hi.max(a))
    });
    if lo > hi {
        return;
    }
    let margin = BEYOND_SWING_SHARE * (hi - lo);
    for &(s, e) in runs.iter().filter(|(s, e)| e - s < ISOLATED_RUN) {
        for r in &mut rows[s..e] {
            if r.angle_rad
                .is_some_and(|a| a < lo - margin || a > hi + margin)
            {
                r.flag = Some(Flag::Beyond);
            }
        }
    }
}

/// Flag the found frames of a track that stands still beyond the swing before it
/// (`Flag::StillBeyond`): a stretch of [`STILL_BEYOND_S`] or longer whose found angles
/// lie within [`STILL_BEYOND_BAND_DEG`] of one another, whose median lies beyond the
/// swing of the [`STILL_BEYOND_PRIOR_S`] before it by more than [`STILL_BEYOND_SHARE`]
/// of that swing's range. The swing is the found angles there but those within the band
/// of the stretch's median (its own earlier pieces, broken off by a frame or a creep),
/// from their [`STILL_BEYOND_QUANTILE`] to their `1 - STILL_BEYOND_QUANTILE` quantile (a
/// stray frame does not widen it), and must span twice the band at least. The
/// stretches that follow a flagged one, or lead up to it, and lie beyond the same bounds
/// are flagged too, however short: the stand goes on past a break. A wire comes to rest
/// inside its last swing (its equilibrium, or its last turning point); a
/// track that lost the wire (a person walking past) and took a static line stands where
/// no swing reached. Seed 1's sweep scene 32 (640x480, hand-held, steadied, a static
/// edge in the room) took the edge as the walker left the wire, 14 deg beyond the
/// swing's extreme, and stood on it, `ok`, for the last 27 s of 40. A held start is
/// judged only where a swing of twice the band was found in the seconds before it.
pub(super) fn flag_still_beyond(rows: &mut [AngleRow]) {
    let band = STILL_BEYOND_BAND_DEG.to_radians();
    let good: Vec<(usize, f64, f64)> = rows
        .iter()
        .enumerate()
        .filter_map(|(i, r)| Some((i, r.t_s, r.unflagged_angle()?)))
        .collect();
    // The longest stretches within the band, one after another: `start..end` in `good`
    // and their median angle.
    let mut stretches: Vec<(usize, usize, f64)> = Vec::new();
    let mut j = 0;
    while j < good.len() {
        let (mut lo, mut hi, mut end) = (good[j].2, good[j].2, j + 1);
        while end < good.len() && hi.max(good[end].2) - lo.min(good[end].2) <= band {
            (lo, hi) = (lo.min(good[end].2), hi.max(good[end].2));
            end += 1;
        }
        let mut still: Vec<f64> = good[j..end].iter().map(|g| g.2).collect();
        stretches.push((j, end, crate::numerics::median(&mut still)));
        j = end;
    }
    // The swing about the stretch at `at` from `j`, as the bounds it must lie beyond.
    let bounds = |j: usize, at: f64| {
        let t0 = good[j].1;
        let from = good[..j].partition_point(|g| g.1 < t0 - STILL_BEYOND_PRIOR_S);
        let mut swing: Vec<f64> = good[from..j]
            .iter()
            .map(|g| g.2)
            .filter(|a| (a - at).abs() > band)
            .collect();
        swing.sort_by(f64::total_cmp);
        let last = swing.len().saturating_sub(1) as f64;
        let at_share = |q: f64| swing.get((q * last).round() as usize).copied();
        match (
            at_share(STILL_BEYOND_QUANTILE),
            at_share(1.0 - STILL_BEYOND_QUANTILE),
        ) {
            (Some(lo), Some(hi)) if hi - lo >= 2.0 * band => {
                let margin = STILL_BEYOND_SHARE * (hi - lo);
                Some((lo - margin, hi + margin))
            }
            _ => None,
        }
    };
    let outside = |at: f64, (lo, hi): (f64, f64)| at < lo || at > hi;
    let mut flagged = vec![false; stretches.len()];
    // The bounds the stand last flagged was judged beyond.
    let mut beyond: Option<(f64, f64)> = None;
    for (k, &(j, end, at)) in stretches.iter().enumerate() {
        let long = good[end - 1].1 - good[j].1 >= STILL_BEYOND_S;
        let judged = match beyond.filter(|&b| outside(at, b)) {
            Some(b) => Some(b),
            None if long => bounds(j, at).filter(|&b| outside(at, b)),
            None => None,
        };
        if let Some(b) = judged {
            flagged[k] = true;
            // The stand's first pieces, broken off before it was long enough to judge.
            for back in (0..k).rev() {
                if flagged[back] || !outside(stretches[back].2, b) {
                    break;
                }
                flagged[back] = true;
            }
        }
        beyond = judged;
    }
    for (&(j, end, _), _) in stretches.iter().zip(&flagged).filter(|(_, &f)| f) {
        for &(i, _, _) in &good[j..end] {
            rows[i].flag = Some(Flag::StillBeyond);
        }
    }
}

/// Flag the found frames whose angle leaves the smooth path of the found frames about
/// them (`Flag::Jump`): a quadratic in time through up to three good frames on each side
/// within [`FILL_REACH_S`], the frame itself left out; a frame is flagged when it lies
/// more than [`JUMP_MIN_DEG`] and more than [`JUMP_STEPS`] frames' motion (the
/// quadratic's slope over the median frame interval) off it, and lies further off than
/// any good frame within three on either side (the others are judged again without it,
/// a jump pulling its neighbours' paths). A wire cannot leave its path for a frame and
/// come back: a track starting beside a wire's shadow took the shadow for one frame,
/// 5.3 deg off, between frames on the wire, and called it `ok` (seed 2's sweep scene 8).
pub(super) fn flag_jumps(rows: &mut [AngleRow]) {
    let dt = {
        let mut d: Vec<f64> = rows.windows(2).map(|w| w[1].t_s - w[0].t_s).collect();
        if d.is_empty() {
            return;
        }
        crate::numerics::median(&mut d)
    };
    let min = JUMP_MIN_DEG.to_radians();
    loop {
        let good: Vec<usize> = rows
            .iter()
            .enumerate()
            .filter(|(_, r)| r.flag.is_none() && r.status == Status::Ok && r.angle_rad.is_some())
            .map(|(i, _)| i)
            .collect();
        let angle = |i: usize| rows[i].angle_rad.unwrap_or(0.0);
        let off: Vec<f64> = (0..good.len())
            .map(|j| {
                let (i, t) = (good[j], rows[good[j]].t_s);
                let near = |g: &usize| (rows[*g].t_s - t).abs() <= FILL_REACH_S;
                let before = good[j.saturating_sub(3)..j].iter().filter(|g| near(g));
                let after = good[j + 1..(j + 4).min(good.len())]
                    .iter()
                    .filter(|g| near(g));
                if before.clone().count() == 0 || after.clone().count() == 0 {
                    return 0.0;
                }
                let pts = before.chain(after).map(|&g| {
                    let x = rows[g].t_s - t;
                    ([1.0, x, x * x], angle(g))
                });
                match crate::numerics::least_squares3(pts) {
                    Some([at, slope, _]) => {
                        let off = (angle(i) - at).abs();
                        if off > min && off > JUMP_STEPS * slope.abs() * dt {
                            off
                        } else {
                            0.0
                        }
                    }
                    None => 0.0,
                }
            })
            .collect();
        let mut flagged = false;
        for j in 0..good.len() {
            let around = j.saturating_sub(3)..(j + 4).min(good.len());
            if off[j] > 0.0 && around.clone().all(|k| off[k] <= off[j]) {
                rows[good[j]].flag = Some(Flag::Jump);
                flagged = true;
            }
        }
        if !flagged {
            return;
        }
    }
}

/// Flag the found frames the swing their unflagged neighbours make (see
/// [`SwingSpan`]) shows not to be the wire's: a short run a leap parts from it
/// ([`flag_leapt`]), then a frame off its path ([`flag_off_swing`]), then the frames
/// where something static pulls every swing's angle ([`flag_pulled`]). Without two
/// whole swings, nothing is judged.
pub(super) fn flag_against_swing(rows: &mut [AngleRow]) {
    let (t, a): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter_map(|r| Some((r.t_s, r.unflagged_angle()?)))
        .unzip();
    if let Some(span) = super::judge::swing_span(&t, &a) {
        flag_leapt(rows, &span);
        flag_off_swing(rows, &span);
        flag_pulled(rows, &span);
    }
}

/// Flag the found frames that leave the swing's path (`Flag::OffSwing`). Over the
/// swing (`span`: from a quarter period before its first crossing of the rest angle to
/// a quarter period after its last; a ball held before its release, or come to rest,
/// is not judged), in steps of half a period, the path is fitted by least squares to
/// the found frames of the swing from a period before the step to a period after it: a
/// sinusoid of the swing's period whose amplitude and rest angle each change linearly
/// in time, with its second and third harmonics (an oblique view and a wide swing bend
/// the image angle's path). The fit is made [`OFF_SWING_ROUNDS`] times, each on the
/// frames the one before left within [`OFF_SWING_KEEP_SIGMAS`] times its robust
/// scatter (and half of [`OFF_SWING_MIN_DEG`]); a frame of the step more than
/// [`OFF_SWING_MIN_DEG`] and [`OFF_SWING_SIGMAS`] times the last fit's scatter off it is
/// flagged. A step with fewer than [`OFF_SWING_MIN_FIT`] found frames about it is not
/// judged. A wire cannot leave its swing: after a person crossing a swaying 640x480
/// twin hid the wire for a second, the track, its prediction lapsed, followed the
/// person's edge for seven frames, up to 16 deg off, `ok`; on a 1920x1080 twin under
/// CRF 39 the track lost the wire at the swing's fastest and took what lay in its gate
/// for a few frames at a time, 23 frames `ok` 1 to 7.6 deg off.
///
/// Within [`LOSS_EDGE_S`] of a loss of the wire ([`LOSS_FRAMES`] frames in a row
/// without an unflagged angle), [`LOSS_EDGE_MIN_DEG`] stands in for [`OFF_SWING_MIN_DEG`]:
/// whatever hid the wire for the loss hid part of it in the frames just before and
/// after, and the line through what was left leans towards the hider's edge. A
/// person walking in front of a still 960x540 twin's wire (seed 1205's sweep, scene
/// 36) covered it over four frames, the last of them measured on half its cells 0.91
/// deg off and `ok`.
fn flag_off_swing(rows: &mut [AngleRow], span: &SwingSpan) {
    let (at, t, a) = unflagged(rows);
    let near = near_loss(rows);
    let (min, edge) = (
        OFF_SWING_MIN_DEG.to_radians(),
        LOSS_EDGE_MIN_DEG.to_radians(),
    );
    let mut off = Vec::new();
    swing_fits(&t, &a, span, |step, window, res, scatter| {
        off.extend(window.zip(res).filter_map(|(k, r)| {
            let floor = if near[at[k]] { edge } else { min };
            let limit = (OFF_SWING_SIGMAS * scatter).max(floor);
            (step.contains(&t[k]) && r.abs() > limit).then_some(at[k])
        }));
    });
    for k in off {
        rows[k].flag = Some(Flag::OffSwing);
    }
}

/// The found frames not flagged: their rows' indices, times and angles.
fn unflagged(rows: &[AngleRow]) -> (Vec<usize>, Vec<f64>, Vec<f64>) {
    let (at, (t, a)): (Vec<usize>, (Vec<f64>, Vec<f64>)) = rows
        .iter()
        .enumerate()
        .filter_map(|(k, r)| Some((k, (r.t_s, r.unflagged_angle()?))))
        .unzip();
    (at, t, a)
}

/// Whether each row lies within [`LOSS_EDGE_S`] of a loss of the wire: a row of a run
/// of at least [`LOSS_FRAMES`] rows in a row without an unflagged angle (`rows` in
/// time order).
fn near_loss(rows: &[AngleRow]) -> Vec<bool> {
    let mut near = vec![false; rows.len()];
    for (start, end) in runs_where(rows, false) {
        if end - start >= LOSS_FRAMES {
            let (a, b) = (
                rows[start].t_s - LOSS_EDGE_S,
                rows[end - 1].t_s + LOSS_EDGE_S,
            );
            let from = rows.partition_point(|r| r.t_s < a);
            let to = rows.partition_point(|r| r.t_s <= b);
            near[from..to].fill(true);
        }
    }
    near
}

/// The swing's own path fitted about each step of half a period (see
/// [`flag_off_swing`]), over the angles `a` at times `t` (in time order): for each step
/// whose fit holds, `f(step, window, residuals, scatter)` with the step's times, the
/// indices into `t` of the frames fitted, their residuals and the fit's robust scatter.
fn swing_fits(
    t: &[f64],
    a: &[f64],
    span: &SwingSpan,
    mut f: impl FnMut(std::ops::Range<f64>, std::ops::Range<usize>, &[f64], f64),
) {
    let p = span.period_s;
    let omega = std::f64::consts::TAU / p;
    let min = OFF_SWING_MIN_DEG.to_radians();
    let (from, to) = (span.first_s - 0.25 * p, span.last_s + 0.25 * p);
    let mut s = from;
    while s < to {
        let e = (s + 0.5 * p).min(to);
        let mid = 0.5 * (s + e);
        let terms = |t: f64| {
            let x = t - mid;
            let (s1, c1) = (omega * x).sin_cos();
            let (s2, c2) = (2.0 * omega * x).sin_cos();
            let (s3, c3) = (3.0 * omega * x).sin_cos();
            [1.0, x, c1, s1, x * c1, x * s1, c2, s2, c3, s3]
        };
        let (lo, hi) = ((s - p).max(from), (e + p).min(to));
        let window = t.partition_point(|&v| v < lo)..t.partition_point(|&v| v <= hi);
        let fitted: Vec<(usize, [f64; 10], f64)> =
            window.clone().map(|k| (k, terms(t[k]), a[k])).collect();
        if let Some((res, scatter)) = robust_fit(&fitted, min) {
            f(s..e, window, &res, scatter);
        }
        s = e;
    }
}

/// How far the found angles `a` (at times `t`, in time order) stray from the swing's own
/// path: the median, over the steps of half a period, of the robust scatter about it
/// (see [`flag_off_swing`]), rad. `None` without two whole swings or a step fitted. A
/// wire followed well strays by its noise from frame to frame; a track that the
/// steadying of a moving camera or a codec moves slowly strays more (see
/// `judge::judge`'s `wander`).
pub(super) fn swing_scatter(t: &[f64], a: &[f64]) -> Option<f64> {
    let span = super::judge::swing_span(t, a)?;
    let mut scatters = Vec::new();
    swing_fits(t, a, &span, |_, _, _, scatter| scatters.push(scatter));
    (!scatters.is_empty()).then(|| crate::numerics::median(&mut scatters))
}

/// Flag the found frames of a run that a leap no swing makes parts from a longer run
/// beside it (`Flag::Leapt`). Between two found frames `dt` s apart, a wire swinging
/// at the swing's period and amplitude scale (`span`) turns at most `omega A dt`;
/// a change of more than [`LEAP_SPEED_TIMES`] that and [`JUMP_MIN_DEG`] is a leap. The
/// found frames are cut into runs at each leap, and a run shorter than the longer of
/// the runs it leaps from or to, and lasting less than [`LEAP_RUN_PERIODS`] of the
/// period, is flagged: one of the two sides is not the wire, and the shorter is the
/// likelier. On a hand-held 640x480 twin (seed 1's sweep, scene 32)
/// the track sat on a static edge for its first 16 found frames, 24 to 32 deg off and
/// `ok`, and leapt 19 deg onto the wire; the swing had not begun to cross its rest
/// angle, where `flag_off_swing` does not judge.
fn flag_leapt(rows: &mut [AngleRow], span: &SwingSpan) {
    let found: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].unflagged_angle().is_some())
        .collect();
    let speed = std::f64::consts::TAU / span.period_s * span.scale;
    let angle = |i: usize| rows[i].angle_rad.unwrap_or(0.0);
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut start = 0;
    for k in 1..=found.len() {
        let leap = k == found.len() || {
            let (a, b) = (found[k - 1], found[k]);
            let dt = rows[b].t_s - rows[a].t_s;
            let limit = LEAP_SPEED_TIMES * speed * dt + JUMP_MIN_DEG.to_radians();
            (angle(b) - angle(a)).abs() > limit
        };
        if leap {
            runs.push((start, k));
            start = k;
        }
    }
    let len = |r: &(usize, usize)| r.1 - r.0;
    let lasts = |r: &(usize, usize)| rows[found[r.1 - 1]].t_s - rows[found[r.0]].t_s;
    let mut leapt = Vec::new();
    for (j, run) in runs.iter().enumerate() {
        let before = j.checked_sub(1).map_or(0, |i| len(&runs[i]));
        let after = runs.get(j + 1).map_or(0, len);
        if len(run) < before.max(after) && lasts(run) < LEAP_RUN_PERIODS * span.period_s {
            leapt.extend(found[run.0..run.1].iter().copied());
        }
    }
    for i in leapt {
        rows[i].flag = Some(Flag::Leapt);
    }
}

/// The residuals of `window`'s angles (row, regressors, angle) from their least-squares
/// fit, and the fit's robust scatter (1.4826 times the median absolute residual of the
/// frames it was fitted to), after [`OFF_SWING_ROUNDS`] fits (see [`flag_off_swing`]).
/// `None` with fewer than [`OFF_SWING_MIN_FIT`] frames, or frames that do not fix the
/// fit.
fn robust_fit(window: &[(usize, [f64; 10], f64)], min: f64) -> Option<(Vec<f64>, f64)> {
    if window.len() < OFF_SWING_MIN_FIT {
        return None;
    }
    let mut kept = vec![true; window.len()];
    let mut fitted = None;
    for _ in 0..OFF_SWING_ROUNDS {
        let rows = window.iter().zip(&kept).filter(|(_, k)| **k);
        let c = crate::numerics::least_squares(rows.map(|((_, x, y), _)| (*x, *y)))?;
        let res: Vec<f64> = window
            .iter()
            .map(|(_, x, y)| y - x.iter().zip(&c).map(|(a, b)| a * b).sum::<f64>())
            .collect();
        let mut dev: Vec<f64> = res
            .iter()
            .zip(&kept)
            .filter(|(_, k)| **k)
            .map(|(r, _)| r.abs())
            .collect();
        if dev.len() < OFF_SWING_MIN_FIT {
            return None;
        }
        let scatter = 1.4826 * crate::numerics::median(&mut dev);
        let within = (OFF_SWING_KEEP_SIGMAS * scatter).max(0.5 * min);
        for (k, r) in kept.iter_mut().zip(&res) {
            *k = r.abs() < within;
        }
        fitted = Some((res, scatter));
    }
    fitted
}

/// Fill each flagged frame from its good neighbours (a local quadratic in time through
/// up to three good frames on each side, within 0.3 s); without good
/// neighbours on both sides it stays missing.
pub(super) fn fill_flagged(rows: &mut [AngleRow]) {
    let good: Vec<usize> = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.unflagged_angle().is_some())
        .map(|(i, _)| i)
        .collect();
    let flagged: Vec<usize> = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.flag.is_some())
        .map(|(i, _)| i)
        .collect();
    for i in flagged {
        let t = rows[i].t_s;
        let k = good.partition_point(|&g| g < i);
        let before: Vec<usize> = good[k.saturating_sub(3)..k]
            .iter()
            .copied()
            .filter(|&g| t - rows[g].t_s <= FILL_REACH_S)
            .collect();
        let after: Vec<usize> = good[k..(k + 3).min(good.len())]
            .iter()
            .copied()
            .filter(|&g| rows[g].t_s - t <= FILL_REACH_S)
            .collect();
        if before.is_empty() || after.is_empty() {
            rows[i].angle_rad = None;
            rows[i].status = Status::Missing;
            continue;
        }
        if before.len() + after.len() == 2 {
            // Straight line between the two neighbours.
            let (a, b) = (&rows[before[0]], &rows[after[0]]);
            let (ya, yb) = (a.angle_rad.unwrap_or(0.0), b.angle_rad.unwrap_or(0.0));
            let v = ya + (yb - ya) * (t - a.t_s) / (b.t_s - a.t_s);
            rows[i].angle_rad = Some(v);
            rows[i].status = Status::Corrected;
            continue;
        }
        let near = before.iter().chain(&after).map(|&g| {
            let r = &rows[g];
            (r.t_s, r.angle_rad.expect("good rows have angles"))
        });
        match crate::numerics::quadratic_at(near, t) {
            Some(v) => {
                rows[i].angle_rad = Some(v);
                rows[i].status = Status::Corrected;
            }
            None => {
                rows[i].angle_rad = None;
                rows[i].status = Status::Missing;
            }
        }
    }
}

mod pull;
use pull::flag_pulled;

#[cfg(test)]
mod tests;
