//! After the pass: flagged frames filled from their good neighbours, and operator
//! marks.

use super::{unwrap_near, AngleRow, Flag, Pt, Status};
use crate::detect::tuning::{FILL_REACH_S, ISOLATED_RUN, LOSS_FRAMES};
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

/// Fill each flagged frame from its good neighbours (a local quadratic in time through
/// up to three good frames on each side, within 0.3 s); without good
/// neighbours on both sides it stays missing.
pub(super) fn fill_flagged(rows: &mut [AngleRow]) {
    let good: Vec<usize> = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.flag.is_none() && r.angle_rad.is_some())
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
}
