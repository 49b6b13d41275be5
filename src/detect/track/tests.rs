//! The unit tests of `detect/track.rs`.

use super::background::decay_where_seen;
use super::pivot::{angular_speeds, central_spread, refined_pivot, refinement_lines, FreeLine};
use super::*;
use crate::detect::line::Line;

/// A line through `p` at `deg` (from +x towards +y), moved `off` px across itself.
fn line(p: Pt, deg: f64, off: f64) -> Line {
    let dir = Pt::new(deg.to_radians().cos(), deg.to_radians().sin());
    Line {
        point: p + Pt::new(-dir.y, dir.x) * off,
        dir,
    }
}

/// Deterministic noise in [-1, 1), and another sequence unrelated to it.
fn noise(k: usize) -> f64 {
    ((k * 7919 + 13) % 1000) as f64 / 500.0 - 1.0
}
fn noise2(k: usize) -> f64 {
    ((k * 104_729 + 7) % 997) as f64 / 498.5 - 1.0
}

#[test]
fn nearly_parallel_lines_do_not_move_the_pivot_whatever_a_few_others_say() {
    let piv = Pt::new(100.0, 50.0);
    // A track on a fixed mark: 200 lines within 0.25 deg of 90 deg, through a point
    // 8.5 px from the pivot, each 0.3 px off at most; and 12 frames of the wire
    // through the pivot, 3 deg either side. Their robust intersection lies 9.9 px
    // from the pivot, within the bound, and anywhere along the mark's direction
    // that the lines' noise puts it.
    let mark = Pt::new(103.0, 58.0);
    let mut lines: Vec<Line> = (0..200)
        .map(|k| line(mark, 90.0 + 0.25 * noise(k), 0.3 * noise2(k)))
        .collect();
    lines.extend((0..12).map(|k| line(piv, if k % 2 == 0 { 87.0 } else { 93.0 }, 0.0)));
    let extremes = {
        let a: Vec<f64> = lines
            .iter()
            .map(|l| l.dir.y.atan2(l.dir.x).rem_euclid(std::f64::consts::PI))
            .collect();
        a.iter().fold(f64::MIN, |m, &b| m.max(b)) - a.iter().fold(f64::MAX, |m, &b| m.min(b))
    };
    assert!(extremes.to_degrees() > 5.9, "{}", extremes.to_degrees());
    let central = central_spread(&lines).to_degrees();
    assert!(central < 0.6, "central spread {central} deg");
    assert_eq!(refined_pivot(&lines, piv, 12.0), None);
}

#[test]
fn a_fan_of_lines_refines_the_pivot_and_a_far_one_is_refused() {
    let piv = Pt::new(100.0, 50.0);
    let truth = Pt::new(101.5, 47.0);
    // 200 lines from 80 to 100 deg, 0.2 px of noise across each.
    let fan = |at: Pt| -> Vec<Line> {
        (0..200)
            .map(|k| line(at, 80.0 + 0.1 * k as f64, 0.2 * noise(k)))
            .collect()
    };
    let p = refined_pivot(&fan(truth), piv, 12.0).expect("a refinement");
    assert!((p - truth).norm() < 0.1, "{p:?}");
    // The same fan 20 px away is a jump, not a refinement.
    assert_eq!(
        refined_pivot(&fan(piv + Pt::new(0.0, 20.0)), piv, 12.0),
        None
    );
    // Too few lines.
    assert_eq!(refined_pivot(&fan(truth)[..19], piv, 12.0), None);
}

/// A pendulum's frames about `truth` (90 +- 20 deg, period 1.33 s, 25 frames/s, 4 s):
/// each frame's free line passes `blur` px beside the pivot per unit of its speed's
/// share of the fastest, on the side it turns to; the frames turning one way faster
/// than half the fastest were held about the pass's pivot `held_at` (not re-centred),
/// when given.
fn blurred_swing(truth: Pt, blur: f64, held_at: Option<Pt>) -> Vec<FreeLine> {
    let w = std::f64::consts::TAU / 1.33;
    (0..100)
        .map(|k| {
            let t = k as f64 / 25.0;
            let deg = 90.0 + 20.0 * (w * t).sin();
            let speed = 20f64.to_radians() * w * (w * t).cos();
            let share = speed / (20f64.to_radians() * w);
            let held = held_at.filter(|_| share > 0.5);
            FreeLine {
                t_s: t,
                line: match held {
                    Some(p) => line(p, deg, 0.1 * noise(k)),
                    None => line(truth, deg, blur * share + 0.1 * noise(k)),
                },
                free: held.is_none(),
                speed: Some(speed.abs()),
            }
        })
        .collect()
}

#[test]
fn a_blurred_swing_refines_the_pivot_from_its_slow_free_lines() {
    let truth = Pt::new(100.0, 50.0);
    let pass_pivot = Pt::new(97.0, 48.0);
    let lines = |f: &[&FreeLine]| f.iter().map(|f| f.line).collect::<Vec<Line>>();
    // Every frame's line re-centred, the blur's offsets cancel between the two ways
    // of the swing: all of them refine the pivot as before.
    let even = blurred_swing(truth, 2.0, None);
    assert!(refinement_lines(&even).is_none());
    let all: Vec<&FreeLine> = even.iter().collect();
    let p = refined_pivot(&lines(&all), pass_pivot, 12.0).expect("a refinement");
    assert!((p - truth).norm() < 0.2, "{p:?}");
    // A third of the frames held about the pass's pivot, all from one way of the
    // swing: all the lines meet off the wire's pivot ...
    let held = blurred_swing(truth, 2.0, Some(pass_pivot));
    let n_held = held.iter().filter(|f| !f.free).count();
    assert!((30..=40).contains(&n_held), "{n_held} held");
    let all: Vec<&FreeLine> = held.iter().collect();
    let off = refined_pivot(&lines(&all), pass_pivot, 12.0).expect("a refinement");
    assert!((off - truth).norm() > 0.5, "{off:?}");
    // ... the slow free lines near it.
    let slow = refinement_lines(&held).expect("the slow free lines");
    assert!(slow.iter().all(|f| f.free && f.speed.unwrap() < 0.3 * 1.65));
    assert!(slow.len() >= 20, "{} slow lines", slow.len());
    let p = refined_pivot(&lines(&slow), pass_pivot, 12.0).expect("a refinement");
    assert!((p - truth).norm() < 0.2, "{p:?}");
}

#[test]
fn the_angular_speed_is_its_neighbours_difference() {
    let mut rows: Vec<AngleRow> = (0..5)
        .map(|k| AngleRow::found(k, k as f64 * 0.04, 1.0 + 0.02 * k as f64))
        .collect();
    rows[3].flag = Some(Flag::Gate);
    let w = angular_speeds(&rows);
    assert_eq!(w[0], None);
    assert!((w[1].unwrap() - 0.5).abs() < 1e-12, "{:?}", w[1]);
    // A flagged neighbour has no angle to take.
    assert_eq!(w[2], None);
    assert_eq!(w[4], None);
    assert!((w[3].unwrap() - 0.5).abs() < 1e-12);
}

#[test]
fn after_a_refused_frame_the_prediction_is_the_longer_fit_not_three_noisy_angles() {
    let mut t = test_tracker((1.3, 1.9));
    // A wire turning 1 deg a frame at 25 frames/s, slowing by 0.02 deg a frame each
    // frame, measured with 0.15 deg of noise, alternately either side.
    let truth = |k: f64| (80.0 + k - 0.01 * k * k).to_radians();
    for k in 0..8 {
        let e = if k % 2 == 0 { 0.15 } else { -0.15 };
        t.hist
            .push((k as f64 / 25.0, truth(k as f64) + f64::to_radians(e)));
    }
    // One frame refused; the next is two frames ahead of the last accepted.
    t.since_good = 1;
    let p = t.predict_raw(9.0 / 25.0).expect("a prediction");
    let err = (p - truth(9.0)).to_degrees();
    assert!(err.abs() < 0.3, "predicted {err:.2} deg off");
    // The three last angles alone put it off by 1.8 deg (their second difference
    // is 0.6 deg of noise against 0.02 of motion): the track's own.
    t.since_good = 0;
    let three = (t.predict_raw(9.0 / 25.0).unwrap() - truth(9.0)).to_degrees();
    assert!(three.abs() > 1.0, "three angles: {three:.2} deg off");
}

#[test]
fn the_spread_of_lines_either_side_of_horizontal_is_their_own() {
    // Directions from -5 to +5 deg: 175 to 185 deg as lines.
    let lines: Vec<Line> = (0..101)
        .map(|k| line(Pt::zeros(), 175.0 + 0.1 * k as f64, 0.0))
        .collect();
    let s = central_spread(&lines).to_degrees();
    assert!((s - 8.0).abs() < 0.05, "{s} deg");
}

#[test]
fn a_frame_beside_one_restated_on_its_shadow_s_ridge_is_refused_with_it() {
    // The wire lies 5.5 deg above its shadow (side +1). Frame 0 was taken on the shadow
    // and saw the pair; frame 1, on the shadow too, saw no pair; frame 2, on the wire,
    // saw none either.
    let (wire, shadow) = ((-56.6f64).to_radians(), (-62.1f64).to_radians());
    let mut tr = test_tracker((-1.2, -0.8));
    tr.ridges = measure::Ridges::learnt(1.0, wire - shadow);
    let held = [(0, shadow, Some(wire)), (1, shadow, None), (2, wire, None)];
    for (frame, taken, other) in held {
        let t_s = frame as f64 / 25.0;
        tr.hist.push((t_s, taken));
        tr.undecided.push(Undecided {
            frame,
            t_s,
            taken,
            other: other.map(|o| {
                let moments = crate::detect::row::KeptMoments {
                    moments: [[0.0; 6]; 2],
                    free: [true; 2],
                    bow: None,
                    plate: None,
                };
                (o, 1.0, moments)
            }),
        });
    }
    tr.restate_undecided();
    let restated: Vec<(u64, bool)> = tr
        .take_restated()
        .iter()
        .map(|r| (r.frame, r.other.is_some()))
        .collect();
    // Frame 0 restated onto the wire, frame 1 refused (nothing to restate it by), frame
    // 2 kept.
    assert_eq!(restated, vec![(0, true), (1, false)]);
    let hist: Vec<f64> = tr.hist.iter().map(|h| h.1).collect();
    assert_eq!(hist, vec![wire, wire]);
}

#[test]
fn a_run_of_refused_frames_on_the_learnt_shadow_s_side_does_not_re_anchor_the_track() {
    // A wire swinging 0.35 deg a frame, its shadow 3.8 deg below it (the wire on the
    // larger angle's side, +1, learnt). The track accepted the wire up to frame 9;
    // frames 10 to 12 measured the shadow, smoothly, and were refused (gate).
    let deg = |d: f64| d.to_radians();
    let wire = |k: f64| deg(-30.0 + 0.35 * k);
    let sep = deg(3.8);
    let t_of = |k: f64| k / 30.0;
    let runs = |side: f64, shift: f64| {
        let mut tr = test_tracker((deg(-45.0), deg(-15.0)));
        tr.gate = deg(1.0);
        tr.ridges = measure::Ridges::learnt(side, sep);
        tr.hist = (0..10).map(|k| (t_of(k as f64), wire(k as f64))).collect();
        tr.raw = (10..13)
            .map(|k| (t_of(k as f64), wire(k as f64) + shift))
            .collect();
        tr.since_good = 3;
        tr.reanchors(Some(wire(12.0)))
    };
    // Onto the shadow's side by the pair's separation: not re-anchored.
    assert!(!runs(1.0, -sep), "re-anchored onto the shadow");
    // The same run with the wire learnt on the other side (the run is then the wire's
    // side): re-anchored, as is a run on the wire's side (a track that was on the
    // shadow finds the wire again).
    assert!(runs(-1.0, -sep), "not re-anchored onto the wire's side");
    assert!(runs(1.0, sep), "not re-anchored back onto the wire");
    // Nothing learnt: re-anchored, as before.
    let mut tr = test_tracker((deg(-45.0), deg(-15.0)));
    tr.gate = deg(1.0);
    tr.hist = (0..10).map(|k| (t_of(k as f64), wire(k as f64))).collect();
    tr.raw = (10..13)
        .map(|k| (t_of(k as f64), wire(k as f64) - sep))
        .collect();
    tr.since_good = 3;
    assert!(tr.reanchors(Some(wire(12.0))));
}

/// A 320x240 wall at 200 with a dark wire from (160, 20) at `wire` rad, and a bright
/// block (a person's shirt) over `block` (x and y ranges), when given.
fn wall_wire(index: u64, wire: f64, block: Option<((usize, usize), (usize, usize))>) -> Frame {
    let (w, h) = (320usize, 240usize);
    let mut data = vec![200u8; w * h];
    for y in 0..h {
        for x in 0..w {
            let v = Pt::new(x as f64 - 160.0, y as f64 - 20.0);
            let along = v.x * wire.cos() + v.y * wire.sin();
            let across = v.x * wire.sin() - v.y * wire.cos();
            let mut g = 200.0;
            if (0.0..=200.0).contains(&along) {
                g -= 40.0 * (1.5 - across.abs()).clamp(0.0, 1.0);
            }
            if let Some(((x0, x1), (y0, y1))) = block {
                if (x0..x1).contains(&x) && (y0..y1).contains(&y) {
                    g = 250.0;
                }
            }
            data[y * w + x] = g.round() as u8;
        }
    }
    Frame {
        index,
        t_s: index as f64 / 25.0,
        width: w,
        height: h,
        data,
    }
}

#[test]
fn a_person_passing_is_not_taken_into_the_background() {
    let deg = |d: f64| d.to_radians();
    let mut t = test_tracker((deg(78.0), deg(102.0)));
    let wire = |k: u64| deg(85.0 + 0.5 * k as f64);
    for k in 0..20 {
        t.step(&wall_wire(k, wire(k), None), None).unwrap();
    }
    let before = t.bg.data_bytes().unwrap().to_vec();
    // A bright shirt across the middle of the region, in front of the wire.
    let row = t
        .step(&wall_wire(20, wire(20), Some(((60, 260), (60, 200)))), None)
        .unwrap();
    assert_eq!(row.flag, Some(Flag::Disturbed));
    // The background (a dark wire's: the brightest the scene was) did not take the
    // shirt: it would have held it for 120 frames a grey level, and the evidence
    // beside the wire with it (a sweep twin's wire at rest, after a walker, 0.2 deg off
    // for 25 s).
    let after = t.bg.data_bytes().unwrap();
    let raised = before.iter().zip(after).filter(|(b, a)| a > b).count();
    assert_eq!(
        raised, 0,
        "{raised} pixels of the background took the shirt"
    );
}

#[test]
fn the_background_decays_but_under_the_wire() {
    // A dark wire: the background is the running maximum and decays downwards. The
    // plate (100 under 100), a noisy plate (97: within its threshold of 4), the wire
    // (80: 20 below, over its threshold) and a saturated black pixel at 0, all on the
    // wire's strip.
    let mut bg = [100u8, 100, 100, 0];
    decay_where_seen(
        &mut bg,
        &[100, 97, 80, 0],
        &[4, 4, 4, 4],
        true,
        false,
        |_| true,
    );
    assert_eq!(bg, [99, 99, 100, 0]);
    // Off the wire's strip, whatever stands there decays.
    let mut bg = [100u8, 100];
    decay_where_seen(&mut bg, &[80, 80], &[4, 4], true, false, |i| i == 0);
    assert_eq!(bg, [100, 99]);
    // A light wire: the running minimum, decaying upwards; 255 stays 255.
    let mut bg = [100u8, 100, 100, 255];
    decay_where_seen(
        &mut bg,
        &[100, 104, 130, 255],
        &[4, 4, 4, 4],
        false,
        false,
        |_| true,
    );
    assert_eq!(bg, [101, 101, 100, 255]);
    // The threshold is the pixel's own: 5 levels is noise under 6, the wire under 4.
    let mut bg = [100u8, 100];
    decay_where_seen(&mut bg, &[95, 95], &[6, 4], true, false, |_| true);
    assert_eq!(bg, [99, 100]);
    // A wire at rest (`whole`): its strip keeps its level, noise and all; off it, decay.
    let mut bg = [100u8, 100, 100];
    decay_where_seen(&mut bg, &[100, 97, 97], &[4, 4, 4], true, true, |i| i < 2);
    assert_eq!(bg, [100, 100, 99]);
}

#[test]
fn a_wire_is_at_rest_after_a_second_within_half_its_strip() {
    // The test tracker's strip reaches 190 px: the band is half of 2.5 px seen from there.
    let mut tr = test_tracker((1.2, 1.9));
    let tol = 0.5 * crate::detect::tuning::STRIP_HALF / 190.0;
    let accept = |tr: &mut Tracker, t: f64, a: f64| {
        tr.hist.push((t, a));
        tr.note_still(t, a);
        tr.since_good = 0;
    };
    // 30 frames a second, scattered within the band: at rest once a second has passed.
    for k in 0..30 {
        accept(&mut tr, k as f64 / 30.0, 1.5 + 0.9 * tol * (k % 2) as f64);
    }
    assert!(!tr.wire_at_rest(), "0.97 s is not yet a second");
    accept(&mut tr, 1.0, 1.5);
    assert!(tr.wire_at_rest());
    // A line out of the band starts the second again from itself.
    accept(&mut tr, 1.1, 1.5 + 1.1 * tol);
    assert!(!tr.wire_at_rest());
    accept(&mut tr, 2.1, 1.5 + 1.1 * tol);
    assert!(tr.wire_at_rest());
    // The track lost (five frames refused): not at rest, and the next accepted frame
    // starts the second again, wherever it lies.
    tr.since_good = 5;
    assert!(!tr.wire_at_rest());
    tr.hist.push((2.5, 1.5 + 1.1 * tol));
    tr.note_still(2.5, 1.5 + 1.1 * tol);
    tr.since_good = 0;
    accept(&mut tr, 3.4, 1.5 + 1.1 * tol);
    assert!(!tr.wire_at_rest(), "0.9 s since the track came back");
    accept(&mut tr, 3.5, 1.5 + 1.1 * tol);
    assert!(tr.wire_at_rest());
}
