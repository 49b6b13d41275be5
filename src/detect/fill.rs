//! After the pass: flagged frames filled from their good neighbours, and operator
//! marks.

use super::judge::SwingSpan;
use super::steady::Steadied;
use super::{unwrap_near, AngleRow, Flag, Pt, Status};
use crate::detect::tuning::{
    BEYOND_SWING_SHARE, FILL_REACH_S, ISOLATED_RUN, JUMP_MIN_DEG, JUMP_STEPS, LEAP_RUN_PERIODS,
    LEAP_SPEED_TIMES, LOSS_FRAMES, OFF_SWING_KEEP_SIGMAS, OFF_SWING_MIN_DEG, OFF_SWING_MIN_FIT,
    OFF_SWING_ROUNDS, OFF_SWING_SIGMAS,
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
    let mut i = 0;
    while i < rows.len() {
        if bad(&rows[i]) {
            i += 1;
            continue;
        }
        let start = i;
        while i < rows.len() && !bad(&rows[i]) {
            i += 1;
        }
        let lost_before = start >= LOSS_FRAMES && rows[start - LOSS_FRAMES..start].iter().all(bad);
        let lost_after = i + LOSS_FRAMES <= rows.len() && rows[i..i + LOSS_FRAMES].iter().all(bad);
        if i - start < ISOLATED_RUN && lost_before && lost_after {
            for r in &mut rows[start..i] {
                r.flag = Some(Flag::Isolated);
            }
        }
    }
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
    let good = |r: &AngleRow| r.unflagged_angle().is_some();
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut i = 0;
    while i < rows.len() {
        if !good(&rows[i]) {
            i += 1;
            continue;
        }
        let start = i;
        while i < rows.len() && good(&rows[i]) {
            i += 1;
        }
        runs.push((start, i));
    }
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
/// ([`flag_leapt`]), then a frame off its path ([`flag_off_swing`]). Without two whole
/// swings, nothing is judged.
pub(super) fn flag_against_swing(rows: &mut [AngleRow]) {
    let (t, a): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter_map(|r| Some((r.t_s, r.unflagged_angle()?)))
        .unzip();
    if let Some(span) = super::judge::swing_span(&t, &a) {
        flag_leapt(rows, &span);
        flag_off_swing(rows, &span);
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
fn flag_off_swing(rows: &mut [AngleRow], span: &SwingSpan) {
    let p = span.period_s;
    let omega = std::f64::consts::TAU / p;
    let min = OFF_SWING_MIN_DEG.to_radians();
    let (from, to) = (span.first_s - 0.25 * p, span.last_s + 0.25 * p);
    let mut off = Vec::new();
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
        let first = rows.partition_point(|r| r.t_s < lo);
        let window: Vec<(usize, [f64; 10], f64)> = rows[first..]
            .iter()
            .enumerate()
            .take_while(|(_, r)| r.t_s <= hi)
            .filter_map(|(k, r)| Some((first + k, terms(r.t_s), r.unflagged_angle()?)))
            .collect();
        if let Some((res, scatter)) = robust_fit(&window, min) {
            let limit = (OFF_SWING_SIGMAS * scatter).max(min);
            off.extend(window.iter().zip(&res).filter_map(|((k, _, _), r)| {
                let t = rows[*k].t_s;
                (t >= s && t < e && r.abs() > limit).then_some(*k)
            }));
        }
        s = e;
    }
    for k in off {
        rows[k].flag = Some(Flag::OffSwing);
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flagged_frames_are_filled_from_neighbours_or_left_missing() {
        let mut rows: Vec<AngleRow> = (0..20)
            .map(|i| {
                let t = i as f64 / 30.0;
                AngleRow {
                    frame: i,
                    t_s: t,
                    angle_rad: Some(1.0 + 0.5 * t * t),
                    status: Status::Ok,
                    quality: 1.0,
                    flag: None,
                    moments: None,
                }
            })
            .collect();
        rows[7].flag = Some(Flag::Gate);
        rows[7].angle_rad = Some(9.0);
        rows[0].flag = Some(Flag::Weak);
        fill_flagged(&mut rows);
        assert_eq!(rows[7].status, Status::Corrected);
        let t = rows[7].t_s;
        assert!((rows[7].angle_rad.unwrap() - (1.0 + 0.5 * t * t)).abs() < 1e-9);
        assert_eq!(rows[0].status, Status::Missing);
        assert_eq!(rows[0].angle_rad, None);
    }

    #[test]
    fn a_short_run_beyond_the_swing_is_not_trusted() {
        // A swing of +-10 deg (0.175 rad about 1) in long runs; frames 10 and 13 found
        // alone, between losses of two frames, at 0.4 and 0.05 rad below the swing's
        // least angle (20 % of its range is 0.07 rad).
        let row = |i: u64| {
            let t = i as f64 / 30.0;
            AngleRow {
                frame: i,
                t_s: t,
                angle_rad: Some(1.0 + 0.175 * (std::f64::consts::TAU * t / 1.5).cos()),
                status: Status::Ok,
                quality: 1.0,
                flag: None,
                moments: None,
            }
        };
        let mut rows: Vec<AngleRow> = (0..90).map(row).collect();
        for i in [8, 9, 11, 12, 14, 15] {
            rows[i].angle_rad = None;
            rows[i].status = Status::Missing;
        }
        let least = rows
            .iter()
            .filter_map(|r| r.angle_rad)
            .fold(f64::INFINITY, f64::min);
        rows[10].angle_rad = Some(least - 0.4);
        rows[13].angle_rad = Some(least - 0.05);
        flag_beyond_swing(&mut rows);
        let flagged: Vec<u64> = rows
            .iter()
            .filter(|r| r.flag.is_some())
            .map(|r| r.frame)
            .collect();
        assert_eq!(flagged, [10]);
        assert_eq!(rows[10].flag, Some(Flag::Beyond));
        // The same frame in a long run is a reference, not judged.
        let mut rows: Vec<AngleRow> = (0..90).map(row).collect();
        rows[10].angle_rad = Some(least - 0.4);
        flag_beyond_swing(&mut rows);
        assert!(rows.iter().all(|r| r.flag.is_none()));
    }

    #[test]
    fn a_short_run_between_two_losses_is_not_trusted() {
        let row = |i: u64, found: bool| AngleRow {
            frame: i,
            t_s: i as f64 / 30.0,
            angle_rad: found.then_some(1.0),
            status: if found { Status::Ok } else { Status::Missing },
            quality: 1.0,
            flag: (!found).then_some(Flag::Weak),
            moments: None,
        };
        // Lost 10-14, found 15-16, lost 17-19, found again from 20.
        let found = |i: u64| !(10..=14).contains(&i) && !(17..=19).contains(&i);
        let mut rows: Vec<AngleRow> = (0..40).map(|i| row(i, found(i))).collect();
        flag_isolated(&mut rows);
        let isolated: Vec<u64> = rows
            .iter()
            .filter(|r| r.flag == Some(Flag::Isolated))
            .map(|r| r.frame)
            .collect();
        assert_eq!(isolated, [15, 16]);
        // A loss of two frames on one side is not a loss: the run is kept.
        let found = |i: u64| !(10..=14).contains(&i) && !(17..=18).contains(&i);
        let mut rows: Vec<AngleRow> = (0..40).map(|i| row(i, found(i))).collect();
        flag_isolated(&mut rows);
        assert!(rows.iter().all(|r| r.flag != Some(Flag::Isolated)));
    }

    #[test]
    fn marks_give_the_angle_away_from_the_pivot() {
        let mut rows = vec![AngleRow {
            frame: 3,
            t_s: 0.1,
            angle_rad: None,
            status: Status::Missing,
            quality: 0.0,
            flag: Some(Flag::Weak),
            moments: None,
        }];
        let mut marks = BTreeMap::new();
        marks.insert(3, [[100.0, 300.0], [100.0, 100.0]]);
        apply_marks(&mut rows, &marks, Pt::new(100.0, 0.0), 1.5);
        assert_eq!(rows[0].status, Status::Manual);
        assert!((rows[0].angle_rad.unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    /// A swing of `amp_deg` with period `period_s` at 25 frames/s for 4 s, about 90 deg.
    fn swing(amp_deg: f64, period_s: f64) -> Vec<AngleRow> {
        (0..100)
            .map(|i| {
                let t = i as f64 / 25.0;
                let a = 90.0 + amp_deg * (std::f64::consts::TAU * t / period_s).cos();
                AngleRow::found(i, t, a.to_radians())
            })
            .collect()
    }

    fn jumps(rows: &mut [AngleRow]) -> Vec<u64> {
        flag_jumps(rows);
        rows.iter()
            .filter(|r| r.flag == Some(Flag::Jump))
            .map(|r| r.frame)
            .collect()
    }

    #[test]
    fn a_frame_off_its_neighbours_path_is_a_jump_and_is_filled() {
        // A smooth swing has none.
        assert!(jumps(&mut swing(10.0, 2.0)).is_empty());
        // One frame on a shadow 5 deg off (seed 2's sweep scene 8: 5.3 deg).
        let mut rows = swing(10.0, 2.0);
        let true_30 = rows[30].angle_rad;
        rows[30].angle_rad = rows[30].angle_rad.map(|a| a - 5f64.to_radians());
        assert_eq!(jumps(&mut rows), [30]);
        fill_flagged(&mut rows);
        assert_eq!(rows[30].status, Status::Corrected);
        let e = (rows[30].angle_rad.unwrap() - true_30.unwrap()).to_degrees();
        assert!(e.abs() < 0.05, "filled {e} deg off");
        // Two in a row: the worse first, then the other without it.
        let mut rows = swing(10.0, 2.0);
        rows[30].angle_rad = rows[30].angle_rad.map(|a| a - 5f64.to_radians());
        rows[31].angle_rad = rows[31].angle_rad.map(|a| a - 4f64.to_radians());
        assert_eq!(jumps(&mut rows), [30, 31]);
    }

    #[test]
    fn a_frame_off_by_less_than_its_own_motion_is_no_jump() {
        // 30 deg in 1.3 s at 25 frames/s: at the crossing (t = 0.325 s, frame 8) the wire
        // moves 5.8 deg a frame, and a frame 1.5 deg off its path (a quarter of a frame's
        // time) is no jump; at the turning point (frame 16, t = 0.65 s) it is.
        let mut rows = swing(30.0, 1.3);
        rows[8].angle_rad = rows[8].angle_rad.map(|a| a + 1.5f64.to_radians());
        assert!(jumps(&mut rows).is_empty());
        let mut rows = swing(30.0, 1.3);
        rows[16].angle_rad = rows[16].angle_rad.map(|a| a + 1.5f64.to_radians());
        assert_eq!(jumps(&mut rows), [16]);
        // Under a degree is not judged.
        let mut rows = swing(30.0, 1.3);
        rows[16].angle_rad = rows[16].angle_rad.map(|a| a + 0.9f64.to_radians());
        assert!(jumps(&mut rows).is_empty());
    }

    /// A ball held at 40 deg for `hold` s, then let go: a swing of period 2 s about 30
    /// deg, 10 deg decaying by 0.1 deg a second, at 30 frames/s with 0.02 deg of noise
    /// (a fixed pseudo-random sequence).
    fn swinging(n: u64, hold: f64) -> Vec<AngleRow> {
        (0..n)
            .map(|i| {
                let t = i as f64 / 30.0;
                let noise = 0.02 * ((i * 7919 % 101) as f64 / 50.0 - 1.0);
                let x = (t - hold).max(0.0);
                let deg = 30.0 + (10.0 - 0.1 * x) * (std::f64::consts::PI * x).cos() + noise;
                AngleRow {
                    frame: i,
                    t_s: t,
                    angle_rad: Some(deg.to_radians()),
                    status: Status::Ok,
                    quality: 1.0,
                    flag: None,
                    moments: None,
                }
            })
            .collect()
    }

    /// The swing of `rows`' found frames, and the frames `flag_off_swing` flags in it.
    fn off_swing(rows: &mut [AngleRow]) -> Vec<usize> {
        let (t, a): (Vec<f64>, Vec<f64>) = rows
            .iter()
            .filter_map(|r| Some((r.t_s, r.unflagged_angle()?)))
            .unzip();
        if let Some(span) = crate::detect::judge::swing_span(&t, &a) {
            assert!((span.period_s - 2.0).abs() < 0.01, "{}", span.period_s);
            flag_off_swing(rows, &span);
        }
        (0..rows.len())
            .filter(|&i| rows[i].flag == Some(Flag::OffSwing))
            .collect()
    }

    /// After a loss of ten frames, the track follows something else for six frames
    /// (from 1.5 deg off to 9 deg off), and one frame far from the loss is 1.5 deg off:
    /// those are flagged off the swing, and no other frame: not a frame 0.5 deg off,
    /// nor the ball held for 1.5 s before its release.
    #[test]
    fn frames_off_the_swing_are_flagged() {
        let mut rows = swinging(660, 1.5);
        for r in &mut rows[300..310] {
            r.flag = Some(Flag::Weak);
        }
        for (k, r) in rows[310..316].iter_mut().enumerate() {
            *r.angle_rad.as_mut().unwrap() += (1.5 + 1.5 * k as f64).to_radians();
        }
        *rows[320].angle_rad.as_mut().unwrap() += 0.5f64.to_radians();
        *rows[150].angle_rad.as_mut().unwrap() -= 1.5f64.to_radians();
        let mut want: Vec<usize> = (310..316).collect();
        want.insert(0, 150);
        assert_eq!(off_swing(&mut rows), want);
        // Fewer than two whole swings: not judged.
        let mut rows = swinging(120, 0.0);
        *rows[60].angle_rad.as_mut().unwrap() += 5f64.to_radians();
        assert!(off_swing(&mut rows).is_empty());
    }

    /// A track that sits on a static line 30 deg off for its first 16 found frames, then
    /// leaps onto the wire: those 16 are flagged, and no frame of the swing. A run as
    /// short but lasting more than half a period (frames far apart) is kept.
    #[test]
    fn a_short_run_a_leap_parts_from_the_swing_is_flagged() {
        let span = SwingSpan {
            period_s: 2.0,
            first_s: 1.0,
            last_s: 19.0,
            scale: 10f64.to_radians(),
        };
        let mut rows = swinging(600, 0.0);
        for r in &mut rows[2..18] {
            r.angle_rad = Some(0.0);
        }
        flag_leapt(&mut rows, &span);
        let leapt: Vec<usize> = (0..rows.len())
            .filter(|&i| rows[i].flag == Some(Flag::Leapt))
            .collect();
        // The first two frames, on the wire, are a run shorter than the static line's
        // and leap to it: they go too.
        assert_eq!(leapt, (0..18).collect::<Vec<_>>());
        // Two frames on the line 1.2 s apart (the others between not found).
        let mut rows = swinging(600, 0.0);
        for r in &mut rows[2..40] {
            r.angle_rad = Some(0.0);
        }
        for r in &mut rows[3..39] {
            r.flag = Some(Flag::Weak);
        }
        flag_leapt(&mut rows, &span);
        assert!(rows.iter().all(|r| r.flag != Some(Flag::Leapt)));
    }

    /// The found frames whose camera motion was held, not measured, are flagged.
    #[test]
    fn frames_whose_motion_was_not_measured_are_flagged() {
        let mut rows = swinging(10, 0.0);
        rows[4].flag = Some(Flag::Weak);
        let steadied: Vec<Steadied> = (2..10)
            .map(|i| Steadied {
                index: i,
                t_s: i as f64 / 30.0,
                motion: crate::detect::steady::Motion::default(),
                turn_held: false,
                measured: !(4..7).contains(&i),
            })
            .collect();
        flag_unsteadied(&mut rows, &steadied);
        let flags: Vec<Option<Flag>> = rows.iter().map(|r| r.flag).collect();
        let (w, u) = (Some(Flag::Weak), Some(Flag::Unsteadied));
        assert_eq!(flags, [None, None, None, None, w, u, u, None, None, None]);
    }
}
