//! The unit tests of `detect/fill.rs`: flagging and filling on hand-made rows.

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

/// Beside a loss of the wire (a person covering it), a frame 0.6 deg off the swing is
/// flagged, on either side of the loss and up to `LOSS_EDGE_S` from it; as far off
/// but further from the loss, or 0.2 deg off beside it, a frame is kept.
#[test]
fn frames_partly_hidden_beside_a_loss_are_flagged_nearer_the_swing() {
    let mut rows = swinging(660, 1.5);
    for r in &mut rows[300..310] {
        r.flag = Some(Flag::Weak);
    }
    // At 30 frames/s, five frames (0.17 s) before the loss's first frame (300) and
    // after its last (309) lie within the edge's reach (0.2 s); seven (0.23 s), beyond.
    let edge = (LOSS_EDGE_S * 30.0).round() as usize;
    let (before, after) = (300 - (edge - 1), 309 + (edge - 1));
    for (k, deg) in [
        (299, 0.6),
        (before, -0.6),
        (after, 0.6),
        (298, 0.2),
        (311, -0.2),
        (before - 2, 0.6),
        (after + 2, -0.6),
        (450, -0.6),
    ] {
        *rows[k].angle_rad.as_mut().unwrap() += f64::to_radians(deg);
    }
    assert_eq!(off_swing(&mut rows), vec![before, 299, after]);
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

/// A swing (40 deg held 1.5 s, then 10 deg about 30 deg, period 2 s) lost for a second
/// at 10 s, after which the track stands on a line at 55 deg, still, to the end (15 deg
/// beyond the swing's 40 deg release, 5.6 beyond the 8 s before it widened by half its
/// range): that stretch is flagged. The held start (a still wire with no swing before it), and a
/// ball that comes to rest within its swing, are not.
#[test]
fn a_track_standing_still_beyond_the_swing_before_it_is_flagged() {
    let beyond = |rows: &[AngleRow]| -> Vec<usize> {
        (0..rows.len())
            .filter(|&i| rows[i].flag == Some(Flag::StillBeyond))
            .collect()
    };
    let mut rows = swinging(600, 1.5);
    for r in &mut rows[300..330] {
        r.angle_rad = None;
        r.status = Status::Missing;
    }
    for (k, r) in rows[330..].iter_mut().enumerate() {
        r.angle_rad = Some((55.0 + 0.1 * (k % 3) as f64).to_radians());
    }
    let stand = rows.clone();
    flag_still_beyond(&mut rows);
    assert_eq!(beyond(&rows), (330..600).collect::<Vec<_>>());
    // A frame 1.3 deg off early in the stand (0.33 s into it) breaks it: the piece
    // before it, too short to judge, and the frame itself are flagged with the rest.
    let mut rows = stand.clone();
    *rows[340].angle_rad.as_mut().unwrap() += 1.3f64.to_radians();
    flag_still_beyond(&mut rows);
    assert_eq!(beyond(&rows), (330..600).collect::<Vec<_>>());
    // Held for 3 s (no swing before it), and at rest within the swing (30.5 deg, its
    // last turning points 21 to 39 deg): kept.
    let mut rows = swinging(600, 3.0);
    for r in &mut rows[330..] {
        r.angle_rad = Some(30.5f64.to_radians());
    }
    flag_still_beyond(&mut rows);
    assert!(beyond(&rows).is_empty(), "{:?}", beyond(&rows));
}

/// A swing of period 2 s about 30 deg, 10 deg decaying by 0.1 deg a second, at 30
/// frames/s for 40 s, with 0.02 deg of noise, each frame's angle moved by
/// `spoil(true angle, angular speed)` (deg, deg/s); and the true angles, deg.
fn spoilt_swing(spoil: impl Fn(f64, f64) -> f64) -> (Vec<AngleRow>, Vec<f64>) {
    let pi = std::f64::consts::PI;
    (0..1200u64)
        .map(|i| {
            let t = i as f64 / 30.0;
            let noise = 0.02 * ((i * 7919 % 101) as f64 / 50.0 - 1.0);
            let amp = 10.0 - 0.1 * t;
            let truth = 30.0 + amp * (pi * t).cos();
            let speed = -0.1 * (pi * t).cos() - amp * pi * (pi * t).sin();
            let deg = truth + spoil(truth, speed) + noise;
            (AngleRow::found(i, t, deg.to_radians()), truth)
        })
        .unzip()
}

fn pulled(rows: &[AngleRow]) -> Vec<usize> {
    (0..rows.len())
        .filter(|&i| rows[i].flag == Some(Flag::Pulled))
        .collect()
}

/// A static line at 33 deg, inside the swing, pulls the wire's measured angle towards
/// it by 0.4 of the distance within 1 deg of it (up to 0.4 deg), at every crossing:
/// those frames are flagged and filled from the frames either side, and no frame more
/// than 2 deg from the line is flagged. Without the pull, with an offset at the line
/// whose sign turns with the direction of swing (a lag's), or with a fourth harmonic
/// the swing's path does not hold, nothing is flagged.
#[test]
fn frames_a_static_line_pulls_on_every_swing_are_flagged_and_filled() {
    let line = 33.0;
    let pull = |deg: f64, _: f64| {
        let d = deg - line;
        if d.abs() < 1.0 {
            -0.4 * d
        } else {
            0.0
        }
    };
    let (mut rows, truth) = spoilt_swing(pull);
    let off = |rows: &[AngleRow]| {
        rows.iter()
            .zip(&truth)
            .filter_map(|(r, t)| Some((r.angle_rad?.to_degrees() - t).abs()))
            .fold(0.0, f64::max)
    };
    assert!(off(&rows) > 0.35, "{}", off(&rows));
    flag_against_swing(&mut rows);
    let flagged = pulled(&rows);
    assert!(flagged.len() > 50, "{} flagged", flagged.len());
    for &i in &flagged {
        assert!(
            (truth[i] - line).abs() < 2.0,
            "frame {i} at {:.2} deg",
            truth[i]
        );
    }
    for (i, t) in truth.iter().enumerate() {
        let moved = pull(*t, 0.0).abs();
        assert!(
            moved < 0.1 || rows[i].flag.is_some(),
            "frame {i} at {t:.2} deg, moved {moved:.2} deg, not flagged"
        );
    }
    fill_flagged(&mut rows);
    assert!(off(&rows) < 0.06, "{}", off(&rows));
    // Nothing to flag.
    let (mut rows, _) = spoilt_swing(|_, _| 0.0);
    flag_against_swing(&mut rows);
    assert_eq!(pulled(&rows), Vec::<usize>::new());
    // An offset at the line that turns with the direction of swing (a lag's, a
    // rolling shutter's).
    let (mut rows, _) = spoilt_swing(|deg, speed| {
        if (deg - line).abs() < 1.0 {
            0.3 * speed.signum()
        } else {
            0.0
        }
    });
    flag_against_swing(&mut rows);
    assert_eq!(pulled(&rows), Vec::<usize>::new());
    // A swing the path's harmonics do not hold (a fourth of 0.3 deg), smooth in angle.
    let (mut rows, _) = spoilt_swing(|deg, _| 0.3 * (4.0 * ((deg - 30.0) / 10.0).acos()).cos());
    flag_against_swing(&mut rows);
    assert_eq!(pulled(&rows), Vec::<usize>::new());
}
