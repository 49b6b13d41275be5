//! The unit tests of `detect/judge.rs`: each check of the detection's verdict on hand-made angle series.

use super::*;
use crate::rng::Rng;

mod again;

const FPS: f64 = 50.0;
const PERIOD: f64 = 2.0;

/// A pendulum's angle under rolling friction (Eq. 33: the amplitude falls linearly),
/// about a rest of 90 deg from the x axis: 10 deg at first, 0.2 deg less each half
/// swing, 20 s at 50 frames/s, with 0.005 deg of noise.
fn swinging() -> Vec<AngleRow> {
    let mut rng = Rng::new(7);
    (0..(20.0 * FPS) as usize)
        .map(|k| {
            let t = k as f64 / FPS;
            let amp = 10.0 - 0.2 * (2.0 * t / PERIOD);
            let a = 90.0 + amp * (std::f64::consts::TAU * t / PERIOD).cos() + 0.005 * rng.normal();
            AngleRow::found(k as u64, t, a.to_radians())
        })
        .collect()
}

fn failed(v: &DetectionVerdict) -> Vec<&str> {
    v.failed().map(|c| c.check.as_str()).collect()
}

#[test]
fn a_pendulum_swinging_is_ok_and_its_period_and_amplitudes_are_seen() {
    let v = judge(&swinging(), [100.0, 20.0], Some(0.3), None);
    assert_eq!(v.verdict, Verdict::Ok, "{:?}", v.checks);
    let s = &v.seen;
    let p = s.period_s.unwrap();
    assert!((p - PERIOD).abs() < 0.002, "period {p}");
    // Ten whole swings in 20 s, of which nine lie between crossings in the same sense.
    assert_eq!(s.swings, 9);
    // The first turning points: 10 at t = 0 is no turn (no crossing before it); the
    // first two are the half swings at t = 1 and 2 s: 9.8 and 9.6 deg, mean 9.7.
    let (a0, a1) = (s.amplitude_start_deg.unwrap(), s.amplitude_end_deg.unwrap());
    assert!((a0 - 9.7).abs() < 0.02, "start {a0}");
    // The last two before 20 s (t = 18, 19 s): 6.4 and 6.2, mean 6.3.
    assert!((a1 - 6.3).abs() < 0.02, "end {a1}");
    assert!((s.rest_deg.unwrap() - 90.0).abs() < 0.01);
    let noise = s.noise_deg.unwrap();
    assert!((noise - 0.005).abs() < 0.001, "noise {noise}");
    assert_eq!(s.ok_share, 1.0);
    for c in [
        "found", "turns", "decays", "crossed", "period", "rhythm", "smooth", "stalls", "rest",
        "envelope",
    ] {
        assert!(v.checks.iter().any(|x| x.check == c), "no `{c}` check");
    }
}

#[test]
fn an_angle_whose_noise_is_a_large_share_of_its_swing_is_suspect() {
    // The swing's scale (half the range of its central 90 %) is about 7.5 deg: 0.02 deg
    // of noise is under 0.3 % of it, 0.05 deg over 0.6 %.
    let noisy = |sigma: f64| {
        let mut rng = Rng::new(11);
        let rows: Vec<AngleRow> = swinging()
            .into_iter()
            .map(|r| {
                let a = r.angle_rad.unwrap() + (sigma * rng.normal()).to_radians();
                AngleRow::found(r.frame, r.t_s, a)
            })
            .collect();
        judge(&rows, [100.0, 20.0], Some(0.3), None)
    };
    let calm = noisy(0.02);
    let share = calm.checks.iter().find(|c| c.check == "smooth").unwrap();
    assert!(share.passed, "{share:?}");
    assert!(share.value < 0.0035, "{share:?}");
    let rough = noisy(0.05);
    let share = rough.checks.iter().find(|c| c.check == "smooth").unwrap();
    assert!(!share.passed && share.value > 0.006, "{share:?}");
    assert_ne!(rough.verdict, Verdict::Ok);
}

/// A phone's variable frame rate: the same swing filmed at uneven times (each frame up
/// to 0.4 of an interval early or late), and with every seventh frame dropped. The
/// angle's noise is the one frame's noise either way: the swing's motion between
/// unevenly timed frames is not read as noise (at even weights it reads over 0.05 deg).
#[test]
fn uneven_frame_times_do_not_read_as_noise() {
    let even = judge(&swinging(), [100.0, 20.0], Some(0.3), None);
    let even_noise = even.seen.noise_deg.unwrap();
    assert!((0.003..0.008).contains(&even_noise), "{even_noise}");
    let mut rng = Rng::new(5);
    let mut noise = Rng::new(7);
    let shifted = |k: usize, rng: &mut Rng| (k as f64 + 0.8 * (rng.uniform() - 0.5)) / FPS;
    let jittered: Vec<AngleRow> = (0..(20.0 * FPS) as usize)
        .filter(|k| k % 7 != 3)
        .enumerate()
        .map(|(i, k)| {
            let t = shifted(k, &mut rng);
            let amp = 10.0 - 0.2 * (2.0 * t / PERIOD);
            let a =
                90.0 + amp * (std::f64::consts::TAU * t / PERIOD).cos() + 0.005 * noise.normal();
            AngleRow::found(i as u64, t, a.to_radians())
        })
        .collect();
    let v = judge(&jittered, [100.0, 20.0], Some(0.3), None);
    let n = v.seen.noise_deg.unwrap();
    assert!(
        n < 1.5 * even_noise,
        "noise {n} deg at uneven times, {even_noise} at even"
    );
    assert_eq!(v.verdict, Verdict::Ok, "{:?}", failed(&v));
}

/// On evenly timed frames the weights are the plain fourth difference's; on uneven
/// ones they vanish on a cubic and keep the plain weights' sum of squares.
#[test]
fn fourth_difference_weights_are_plain_on_even_times_and_exact_on_a_cubic() {
    let rows = |t: [f64; 5]| -> Vec<AngleRow> {
        t.iter()
            .enumerate()
            .map(|(i, &t)| AngleRow::found(i as u64, t, 0.0))
            .collect()
    };
    let even = swing::fourth_difference_weights(&rows([0.0, 0.02, 0.04, 0.06, 0.08]));
    assert_eq!(even, [1.0, -4.0, 6.0, -4.0, 1.0]);
    let t = [0.0, 0.013, 0.04, 0.071, 0.08];
    let c = swing::fourth_difference_weights(&rows(t));
    let sq: f64 = c.iter().map(|c| c * c).sum();
    assert!((sq - 70.0).abs() < 1e-9, "{sq}");
    let cubic: f64 = c
        .iter()
        .zip(t)
        .map(|(c, t)| c * (2.0 - 3.0 * t + 40.0 * t * t - 500.0 * t * t * t))
        .sum();
    assert!(cubic.abs() < 1e-9, "{cubic}");
    // Signs alternate, as the plain weights'.
    assert!(
        c[0] > 0.0 && c[1] < 0.0 && c[2] > 0.0 && c[3] < 0.0 && c[4] > 0.0,
        "{c:?}"
    );
}

/// A swing that dies out at 10 s (10 deg falling linearly to nothing, Eq. 33), then
/// 15 s at rest, 50 frames/s: found in every frame up to `lost_s`, then only in every
/// tenth frame within 0.5 deg of rest (a wire at rest fading into the still scene, or
/// a track that finds the wire only as it crosses).
fn swung_out(lost_s: f64) -> Vec<AngleRow> {
    (0..(25.0 * FPS) as usize)
        .map(|k| {
            let t = k as f64 / FPS;
            let amp = (10.0 * (1.0 - t / 10.0)).max(0.0);
            let dev = amp * (std::f64::consts::TAU * t / PERIOD).cos();
            let seen = t < lost_s || (k % 10 == 0 && dev.abs() < 0.5);
            let mut r = AngleRow::found(k as u64, t, (90.0 + dev).to_radians());
            if !seen {
                r.status = Status::Missing;
                r.angle_rad = None;
            }
            r
        })
        .collect()
}

#[test]
fn a_wire_at_rest_after_its_swing_is_not_looked_for() {
    // Found in 500 + 75 of 1250 frames (46 %), and in every frame of the swing: the
    // share up to a period after the swing's end (12 s) is 510 of 600.
    let v = judge(&swung_out(10.0), [100.0, 20.0], Some(0.3), None);
    let found = v.checks.iter().find(|c| c.check == "found").unwrap();
    assert!(found.passed && found.value > 0.8, "{found:?}");
    assert!(v.seen.ok_share < 0.5, "{}", v.seen.ok_share);
    // Lost at 4 s, swinging 6 deg, and found after only where the wire crosses its rest:
    // the share is the whole video's.
    let v = judge(&swung_out(4.0), [100.0, 20.0], Some(0.3), None);
    let found = v.checks.iter().find(|c| c.check == "found").unwrap();
    assert!(!found.passed && found.value < 0.25, "{found:?}");
    assert_ne!(v.verdict, Verdict::Ok);
}

#[test]
fn a_track_that_never_turns_back_is_suspect() {
    // Found in every frame, smooth, and drifting slowly over 3 deg: no turning point
    // (a track on something static, steadied by a camera's misread motion). No check on
    // the motion has anything to judge, and `ok` would have said the wire was seen.
    let mut rows = swinging();
    for r in rows.iter_mut() {
        r.angle_rad = Some((70.0 + 3.0 * r.t_s / 20.0).to_radians());
    }
    let v = judge(&rows, [0.0, 0.0], None, None);
    assert_eq!(failed(&v), ["turns"], "{:?}", v.checks);
    // Five and a half half swings (turning points at 1 to 5 s; 0 s has no crossing
    // before it) are enough.
    let rows: Vec<AngleRow> = swinging().into_iter().filter(|r| r.t_s <= 5.5).collect();
    let v = judge(&rows, [0.0, 0.0], None, None);
    assert!(!failed(&v).contains(&"turns"), "{:?}", v.checks);
}

#[test]
fn a_track_resting_on_a_static_line_stalls() {
    // From 5 s on, for 0.3 s of each swing the angle holds at 91 deg (an edge near the
    // rest the track falls onto), as the two-rod clip's did.
    let mut rows = swinging();
    for r in rows.iter_mut().filter(|r| r.t_s > 5.0) {
        let phase = (r.t_s / PERIOD).fract();
        if (0.2..0.35).contains(&phase) {
            r.angle_rad = Some(91f64.to_radians());
        }
    }
    let v = judge(&rows, [0.0, 0.0], None, None);
    assert!(failed(&v).contains(&"stalls"), "{:?}", v.checks);
}

#[test]
fn a_camera_that_turned_unfollowed_moves_the_rest() {
    // For 6 s in the middle, every angle is 0.3 deg off: the rest steps there and back.
    let mut rows = swinging();
    for r in rows.iter_mut().filter(|r| (7.0..13.0).contains(&r.t_s)) {
        r.angle_rad = r.angle_rad.map(|a| a + 0.3f64.to_radians());
    }
    let v = judge(&rows, [0.0, 0.0], None, None);
    assert!(failed(&v).contains(&"rest"), "{:?}", v.checks);
    // A slow, even drift of the same size is not a step: a swing measured a little
    // asymmetrically drifts so.
    let mut rows = swinging();
    for r in rows.iter_mut() {
        r.angle_rad = r.angle_rad.map(|a| a + (0.3 * r.t_s / 20.0).to_radians());
    }
    let v = judge(&rows, [0.0, 0.0], None, None);
    assert_eq!(v.verdict, Verdict::Ok, "{:?}", v.checks);
}

#[test]
fn a_motion_that_is_not_a_pendulums_fails_the_period() {
    // The track alternates between two things every 1.7 s: one swings with a period of
    // 2 s, the other of 0.7 s (a ball's edge seen now and then).
    let mut rows = swinging();
    for r in rows.iter_mut() {
        if (r.t_s / 1.7) as usize % 2 == 1 {
            let a = 90.0 + 6.0 * (std::f64::consts::TAU * r.t_s / 0.7).sin();
            r.angle_rad = Some(a.to_radians());
        }
    }
    let v = judge(&rows, [0.0, 0.0], None, None);
    assert!(failed(&v).contains(&"period"), "{:?}", v.checks);
}

#[test]
fn a_wire_found_in_few_frames_is_suspect() {
    let mut rows = swinging();
    for r in rows.iter_mut().step_by(2) {
        r.status = Status::Corrected;
    }
    let v = judge(&rows, [0.0, 0.0], None, None);
    assert_eq!(failed(&v), ["found"], "{:?}", v.checks);
    assert_eq!(v.seen.ok_share, 0.5);
    // No five found frames in a row: the noise cannot be told, and is not judged.
    assert_eq!(v.seen.noise_deg, None);
    assert!(!v.checks.iter().any(|c| c.check == "smooth"));
    assert_eq!(v.label(), "suspect (found)");
}

#[test]
fn a_person_passing_in_front_of_the_wire_hides_crossings_but_not_the_period() {
    // 1.5 s of frames missing, then 0.1 s: no period is timed across the first gap, the
    // second is bridged.
    let mut rows = swinging();
    for r in rows
        .iter_mut()
        .filter(|r| (6.3..7.8).contains(&r.t_s) || (12.0..12.1).contains(&r.t_s))
    {
        r.status = Status::Missing;
        r.angle_rad = None;
    }
    let v = judge(&rows, [0.0, 0.0], None, None);
    assert_eq!(v.verdict, Verdict::Ok, "{:?}", v.checks);
    let p = v.seen.period_s.unwrap();
    assert!((p - PERIOD).abs() < 0.002, "period {p}");
}

#[test]
fn a_still_camera_whose_static_scene_moved_makes_the_detection_suspect() {
    let v = judge(&swinging(), [50.0, -10.0], None, None);
    assert_eq!(v.verdict, Verdict::Ok);
    let kept = v.clone().with(still_check(0.1));
    assert_eq!(kept.verdict, Verdict::Ok);
    assert!(failed(&kept).is_empty());
    let moved = v.with(still_check(1.5));
    assert_eq!(moved.verdict, Verdict::Suspect);
    assert_eq!(failed(&moved), ["still"]);
    let c = moved.checks.last().unwrap();
    assert!(
        c.reason.contains("1.50 px") && c.reason.contains("did not follow"),
        "{}",
        c.reason
    );
}

/// A hand-held camera's turn at each frame (0.3 deg RMS, sines near 5 Hz), radians.
fn hand_turns(n: usize) -> Vec<(u64, Option<f64>)> {
    (0..n)
        .map(|k| {
            let t = k as f64 / FPS;
            let w = std::f64::consts::TAU;
            let deg = 0.3 * ((w * 4.3 * t).sin() + (w * 5.7 * t + 1.0).sin());
            (k as u64, Some(deg.to_radians()))
        })
        .collect()
}

#[test]
fn angles_that_follow_the_camera_s_turn_are_suspect_and_the_share_is_found() {
    let turns = hand_turns(swinging().len());
    // Steadied exactly: the angles are the pendulum's, whatever the camera's turn.
    let c = turn_check(&swinging(), &turns).expect("judged");
    assert!(c.passed, "{}", c.reason);
    assert!(c.value < 0.002, "{}", c.reason);
    // Each frame's turn measured with an error of 0.05 deg RMS, which the angle
    // carries: its noise is then nearly all the turn's error, and moves with the turn
    // measured.
    let mut rng = Rng::new(11);
    let mut rows = swinging();
    let mut measured = turns.clone();
    for (r, t) in rows.iter_mut().zip(measured.iter_mut()) {
        let e = 0.05f64.to_radians() * rng.normal();
        t.1 = t.1.map(|v| v + e);
        r.angle_rad = r.angle_rad.map(|a| a - e);
    }
    let c = turn_check(&rows, &measured).expect("judged");
    assert!(!c.passed, "{}", c.reason);
    // The angle's noise is 0.05 (the turn's error) and 0.005 (the rest) deg; the
    // turn's error is a small part of the measured turn's fourth differences (the
    // hand's own turn is most of them), so the share explained is below 1.
    assert!(c.value > 0.02 && c.value < 0.055, "{}", c.reason);
    // A still camera (no steadied frame) is not judged.
    assert!(turn_check(&rows, &[]).is_none());
}

/// Frames whose turn the scene could not fix were steadied with none: their angles carry
/// the camera's turn, which the turns measured on the other frames show.
#[test]
fn frames_whose_turn_was_held_are_suspect_when_the_others_turn() {
    let rows = swinging();
    let mut turns = hand_turns(rows.len());
    let rms = (turns.iter().map(|t| t.1.unwrap().powi(2)).sum::<f64>() / turns.len() as f64)
        .sqrt()
        .to_degrees();
    for t in turns.iter_mut().step_by(4) {
        t.1 = None;
    }
    let c = turn_check(&rows, &turns).expect("judged");
    assert!(!c.passed, "{}", c.reason);
    // A quarter held: half the turn's RMS.
    assert!(
        (c.value - 0.5 * rms).abs() < 0.1 * rms,
        "{} against {rms}",
        c.reason
    );
    assert!(
        c.reason.contains("25 % of the steadied frames"),
        "{}",
        c.reason
    );
    // A camera that turns little (0.003 deg RMS measured) adds little where it was held.
    let small: Vec<_> = turns
        .iter()
        .map(|&(k, t)| (k, t.map(|r| r / 100.0)))
        .collect();
    assert!(turn_check(&rows, &small).expect("judged").passed);
    // Every turn held: nothing measured to reckon the held ones by, nor to regress on;
    // the angles carry a turn of a size not known.
    let none: Vec<_> = turns.iter().map(|&(k, _)| (k, None)).collect();
    let c = turn_check(&rows, &none).expect("judged");
    assert!(!c.passed && c.value == 1.0, "{}", c.reason);
    assert!(
        c.reason
            .contains(&format!("every steadied frame ({})", rows.len())),
        "{}",
        c.reason
    );
    // The first frame, steadied onto itself, measured at exactly none: still unknown.
    let mut first = none.clone();
    first[0].1 = Some(0.0);
    assert!(!turn_check(&rows, &first).expect("judged").passed);
    // One frame's turn measured, and small: the held ones are reckoned by it.
    let mut one = none.clone();
    one[0].1 = Some(1e-7);
    assert!(turn_check(&rows, &one).expect("judged").passed);
}

#[test]
fn a_track_that_loses_the_wire_at_every_crossing_is_suspect() {
    // The frames within 4 deg of the rest angle not found (0.26 to 0.41 s of each half
    // swing, where the wire moves fastest): no crossing is timed, and no period measured
    // in its 19 turning points (`period`, untimed).
    let mut rows = swinging();
    for r in &mut rows {
        if (r.angle_rad.unwrap().to_degrees() - 90.0).abs() < 4.0 {
            r.status = Status::Missing;
            r.angle_rad = None;
        }
    }
    let v = judge(&rows, [100.0, 20.0], Some(0.3), None);
    assert_eq!(failed(&v), ["crossed", "period"], "{:?}", v.checks);
    assert_eq!(v.seen.period_s, None);
    let c = v.checks.iter().find(|c| c.check == "crossed").unwrap();
    assert_eq!(c.value, 0.0);
    // A person passing: the crossings of two seconds hidden, the rest seen.
    let mut rows = swinging();
    for r in &mut rows[(8.0 * FPS) as usize..(10.0 * FPS) as usize] {
        r.status = Status::Missing;
        r.angle_rad = None;
    }
    let v = judge(&rows, [100.0, 20.0], Some(0.3), None);
    let c = v.checks.iter().find(|c| c.check == "crossed").unwrap();
    assert!(c.passed && c.value > 0.7, "{:?}", c);
}

#[test]
fn a_track_lost_in_every_swing_has_no_period_and_is_suspect() {
    // The track lost about every other turning point (where the angle is largest, 90 +
    // 10 deg at t = 0, 2, 4 ... s), for `lost` s, over the first `swings` periods: past
    // 0.2 s, each crossing of the rest angle lies in a run of found frames of its own,
    // and no period is timed.
    let lost_at_every_swing = |lost: f64, swings: f64| {
        let mut rows = swinging();
        rows.truncate((swings * PERIOD * FPS) as usize);
        for r in &mut rows {
            let u = (r.t_s + 0.5 * lost) % PERIOD;
            if u < lost {
                r.status = Status::Missing;
                r.angle_rad = None;
            }
        }
        judge(&rows, [100.0, 20.0], Some(0.3), None)
    };
    let v = lost_at_every_swing(0.3, 10.0);
    assert_eq!(failed(&v), ["period"], "{:?}", v.checks);
    assert_eq!(v.verdict, Verdict::Suspect);
    assert_eq!(v.seen.period_s, None);
    let c = v.checks.iter().find(|c| c.check == "period").unwrap();
    assert_eq!(c.value, 0.0);
    assert!(c.reason.contains("turned back 19 times"), "{}", c.reason);
    // Lost for 0.1 s, the runs hold on across the gaps: the period is timed and judged.
    let v = lost_at_every_swing(0.1, 10.0);
    assert_eq!(v.verdict, Verdict::Ok, "{:?}", v.checks);
    let c = v.checks.iter().find(|c| c.check == "period").unwrap();
    assert!(c.passed && c.value < 0.01, "{:?}", c);
    // A short swing (fewer than `UNTIMED_TURNS_MIN` turning points) lost so is not
    // judged on its period: too few swings to time one.
    let v = lost_at_every_swing(0.3, 4.2);
    assert!(
        v.checks.iter().all(|c| c.check != "period"),
        "{:?}",
        v.checks
    );
}

#[test]
fn a_track_that_flicks_and_rests_between_has_no_pendulum_s_rhythm() {
    // Every 2.5 s the track flicks twice about 90 deg (a period of 0.3 s) and is lost for
    // 0.9 s: its crossings give a half period of 0.15 s, its turning points come every
    // half second or so (seed 4's sweep scene 48: 0.13 s against 0.91).
    let mut rows = swinging();
    for r in &mut rows {
        let u = r.t_s % 2.5;
        if u < 0.6 {
            let a = 90.0 + 5.0 * (std::f64::consts::TAU * u / 0.3).sin();
            r.angle_rad = Some(a.to_radians());
        } else if u < 1.5 {
            r.status = Status::Missing;
            r.angle_rad = None;
        } else {
            r.angle_rad = Some(90f64.to_radians());
        }
    }
    let v = judge(&rows, [0.0, 0.0], None, None);
    let c = v.checks.iter().find(|c| c.check == "rhythm").unwrap();
    assert!(!c.passed && c.value > 2.0, "{:?}", v.checks);
    // A pendulum's turning points come every half period its crossings give.
    let v = judge(&swinging(), [0.0, 0.0], None, None);
    let c = v.checks.iter().find(|c| c.check == "rhythm").unwrap();
    assert!(c.passed && (c.value - 1.0).abs() < 0.01, "{:?}", c);
}

#[test]
fn steadied_angles_that_stray_slowly_from_the_swing_are_suspect() {
    // Fitted half a period at a time, the swing's own path holds `swinging()` (its
    // amplitude falls linearly): the angles stray from it by their noise, 0.005 deg.
    let rows = swinging();
    let noise = |rows: &[AngleRow]| judge(rows, [100.0, 20.0], None, None).seen.noise_deg;
    let c = wander_check(&rows, noise(&rows)).expect("judged");
    assert!(c.passed && (0.7..1.3).contains(&c.value), "{c:?}");
    // A slow error at 0.77 Hz (no harmonic of the 0.5 Hz swing), as a steadying read
    // late gives: its fourth differences over 50 frames/s are 1/300 of it, so the
    // noise hardly grows, but the angles stray from the path by most of the error's
    // amplitude (0.069 deg of 0.08; the fit's linear terms take a little).
    let wander = |rows: &[AngleRow], amp_deg: f64| -> Vec<AngleRow> {
        rows.iter()
            .map(|r| {
                let e = amp_deg.to_radians() * (std::f64::consts::TAU * 0.77 * r.t_s).sin();
                AngleRow::found(r.frame, r.t_s, r.angle_rad.unwrap() + e)
            })
            .collect()
    };
    let strays = wander(&rows, 0.08);
    let c = wander_check(&strays, noise(&strays)).expect("judged");
    assert!(!c.passed && c.value > 10.0, "{c:?}");
    // Under `WANDER_MIN_DEG` it passes, however many times the noise (a quieter
    // swing, 0.002 deg of noise: 0.015 deg strays about 6 times that).
    let quiet: Vec<AngleRow> = rows
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let t = r.t_s;
            let amp = 10.0 - 0.2 * (2.0 * t / PERIOD);
            let clean = 90.0 + amp * (std::f64::consts::TAU * t / PERIOD).cos();
            let a = clean + 0.4 * (r.angle_rad.unwrap().to_degrees() - clean);
            AngleRow::found(k as u64, t, a.to_radians())
        })
        .collect();
    let slight = wander(&quiet, 0.015);
    let c = wander_check(&slight, noise(&slight)).expect("judged");
    assert!(c.passed && c.value > WANDER_NOISE_FACTOR, "{c:?}");
    // Without a noise (too few runs of found frames), nothing is judged.
    assert!(wander_check(&rows, None).is_none());
}

#[test]
fn a_lens_known_loosely_makes_the_swing_s_scale_and_the_detection_suspect() {
    // A swing of about 10 deg down from a pivot near the left edge of a 960x540 frame,
    // seen over 100 to 400 px: through a lens declared unknown (`k1` 0 +- 0.15), its
    // scale is a few percent uncertain; through one fitted to +- 0.002, a few
    // hundredths of a percent.
    let (pivot, band) = ([60.0, 60.0], [100.0, 400.0]);
    let v = judge(&swinging(), pivot, Some(0.3), None);
    let unknown = crate::lens::Lens::new(0.0, 0.15, 960, 540);
    let c = lens_check(&unknown, pivot, band, &v.seen).expect("judged");
    let u = unknown.scale_u_rel(pivot, 90f64.to_radians(), 9.7f64.to_radians(), band);
    assert!((c.value - u).abs() < 1e-3 * u, "{} vs {u}", c.value);
    assert!(c.value > 0.01 && !c.passed, "{c:?}");
    assert!(c.reason.contains("k1 0.000 +- 0.150"), "{}", c.reason);
    assert_eq!(failed(&v.clone().with(c)), ["lens"]);
    let fitted = crate::lens::Lens::new(-0.2, 0.002, 960, 540);
    let c = lens_check(&fitted, pivot, band, &v.seen).expect("judged");
    assert!(c.passed && c.value < 0.001, "{c:?}");
    // A lens given exactly (no uncertainty) is not judged.
    let exact = crate::lens::Lens::new(-0.2, 0.0, 960, 540);
    assert!(lens_check(&exact, pivot, band, &v.seen).is_none());
}

#[test]
fn a_pivot_off_along_the_wire_makes_the_detection_suspect() {
    // On the wire the wire's own direction swings as its angle about the pivot.
    let on = pivot_check(Some(0.9996)).expect("judged");
    assert!(on.passed, "{on:?}");
    // 40 px off along a wire seen at a mean radius of 300 px: R / (R + delta) = 0.882.
    let off = pivot_check(Some(300.0 / 340.0)).expect("judged");
    assert!(
        !off.passed && (off.value - 40.0 / 340.0).abs() < 1e-12,
        "{off:?}"
    );
    assert!(off.reason.contains("11.76 % less"), "{}", off.reason);
    // Seed 7's scene 18: 0.9892, its swing 0.82 % wide.
    assert!(!pivot_check(Some(0.9892)).unwrap().passed);
    assert!(!pivot_check(Some(1.0108)).unwrap().passed);
    assert!(pivot_check(None).is_none());
}

#[test]
fn a_period_that_is_not_the_pendulum_s_makes_the_detection_suspect() {
    // The swing's period is 2 s at a mean amplitude of 8 deg (9.7 -> 6.3): the pendulum
    // whose small-swing period is 2 s / (1 + A^2 / 16) is the one seen.
    let v = judge(&swinging(), [100.0, 20.0], Some(0.3), None);
    let alpha = (0.142f64 / 1.5).asin();
    let ball = |d: f64| crate::physics::Pendulum::solid_ball(0.03175, 1.0458, d, alpha, 9.81);
    let a = 8f64.to_radians();
    let d = ball(0.2).unwrap().d_from_swing_period(PERIOD, a);
    let given = |d_m: f64| crate::detect::PendulumGiven {
        pendulum: ball(d_m).unwrap(),
        d_rel: 0.10,
    };
    let c = length_check(&v.seen, &given(d)).expect("judged");
    assert!(c.passed && c.value < 0.005, "{c:?}");
    // 8 % longer: within the 10 %; 12 % longer or shorter, not.
    assert!(length_check(&v.seen, &given(1.08 * d)).unwrap().passed);
    assert!(!length_check(&v.seen, &given(1.12 * d)).unwrap().passed);
    assert!(!length_check(&v.seen, &given(d / 1.12)).unwrap().passed);
    // A second pendulum twice as fast as the experiment's (seed 31's scene 1): the
    // period implies about a quarter of the length.
    let c = length_check(&v.seen, &given(4.0 * d)).unwrap();
    assert!(!c.passed && (c.value - 0.75).abs() < 0.02, "{c:?}");
    assert!(c.reason.contains("the period seen, "), "{}", c.reason);
    assert_eq!(failed(&v.clone().with(c)), ["length"]);
    // Without a period seen, nothing is judged.
    let mut none = v.seen.clone();
    none.period_s = None;
    assert!(length_check(&none, &given(d)).is_none());
}

#[test]
fn a_swing_that_grows_is_suspect() {
    // `swinging` with its amplitude growing by `g` deg each half swing from 10 deg: the
    // first two turning points (t = 1, 2 s) lie 10 + g and 10 + 2 g off rest, the last
    // two (t = 18, 19 s) 10 + 18 g and 10 + 19 g.
    let driven = |g: f64| -> Vec<AngleRow> {
        swinging()
            .into_iter()
            .map(|r| {
                let t = r.t_s;
                let now = 10.0 - 0.2 * (2.0 * t / PERIOD);
                let grown = 10.0 + g * (2.0 * t / PERIOD);
                let a = 90.0 + (r.angle_rad.unwrap().to_degrees() - 90.0) * grown / now;
                AngleRow::found(r.frame, t, a.to_radians())
            })
            .collect()
    };
    let growth = |v: &DetectionVerdict| {
        let c = v
            .checks
            .iter()
            .find(|c| c.check == "decays")
            .expect("judged");
        (c.value, c.passed)
    };
    // The plain decay: 9.7 -> 6.3 deg, -35.1 %.
    let (g, passed) = growth(&judge(&swinging(), [100.0, 20.0], Some(0.3), None));
    assert!((g + 0.351).abs() < 0.003 && passed, "{g}");
    // 0.02 deg more each half swing: 10.03 -> 10.37 deg, +3.4 %, within 5 %.
    let (g, passed) = growth(&judge(&driven(0.02), [100.0, 20.0], Some(0.3), None));
    assert!((g - 0.0339).abs() < 0.003 && passed, "{g}");
    // 0.04 deg more: 10.06 -> 10.74 deg, +6.8 %: suspect, and for that check alone.
    let v = judge(&driven(0.04), [100.0, 20.0], Some(0.3), None);
    let (g, passed) = growth(&v);
    assert!((g - 0.0676).abs() < 0.003 && !passed, "{g}");
    assert_eq!(failed(&v), ["decays"], "{:?}", v.checks);
    assert_eq!(v.verdict, Verdict::Suspect);
}

#[test]
fn a_verdict_with_an_infinite_figure_reads_back_from_its_json() {
    // A noise of zero makes the wander figure infinite; `serde_json` writes it as
    // `null`, and a cached summary holding it must read back (else it is detected
    // again on every build, and `rollfric check` cannot read the reports' summary).
    let c = wander_check(&swinging(), Some(0.0)).expect("judged");
    assert_eq!(c.value, f64::INFINITY, "{c:?}");
    let mut v = judge(&swinging(), [100.0, 20.0], None, None);
    v.checks.push(c);
    let json = serde_json::to_string(&v).unwrap();
    assert!(json.contains("\"value\":null"), "{json}");
    let back: DetectionVerdict = serde_json::from_str(&json).expect("reads back");
    assert_eq!(back, v);
}
