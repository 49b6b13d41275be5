//! A camera the look saw still, found moving (or not) later in the pass: `Late`'s
//! glances under noise, bumps, drifts and a camera known to move.

use super::*;

/// `f` with strong noise (a heavily compressed recording's): each pixel moved by up to
/// +-`amp` grey levels, differently in each frame.
fn noisy(mut f: Frame, amp: f64) -> Frame {
    let mut z = f.index.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    for v in &mut f.data {
        z ^= z << 13;
        z ^= z >> 7;
        z ^= z << 17;
        let u = (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        *v = (f64::from(*v) + 2.0 * amp * u).round().clamp(0.0, 255.0) as u8;
    }
    f
}

/// A camera the look saw still, offered 12 s of textured frames at 10 frames/s with
/// noise of +-`noise` grey levels, shifted along x by `dx(t)` px.
fn late_on(dx: impl Fn(f64) -> f64, noise: f64) -> Late {
    late_in(480.0, dx, noise)
}

/// As [`late_on`], the 480x320 frames a region of a video of largest side `side` px.
fn late_in(side: f64, dx: impl Fn(f64) -> f64, noise: f64) -> Late {
    let (w, h) = (480, 320);
    let sweep = Sweep::around((-500.0, -500.0), 10.0, (0.0, 0.1), (0.0, 0.0));
    let mut late = Late::new(sweep, side);
    for i in 0..120u64 {
        let t = i as f64 / 10.0;
        let m = Motion {
            dx: dx(t),
            ..Motion::default()
        };
        let mut f = noisy(textured(w, h, m, i), noise);
        f.t_s = t;
        late.offer(&mut f).unwrap();
    }
    late
}

/// Whether a camera the look saw still is found to move over 12 s of noisy frames at
/// 10 frames/s drifting `px_per_s` along x.
fn late_follows(px_per_s: f64) -> bool {
    late_on(|t| px_per_s * t, 150.0).camera().is_some()
}

/// At this noise the glances explain a drifting frame by less than `EXPLAINS` (without
/// `Late::drifts`, the drift is not followed and this fails).
#[test]
fn a_slow_drift_under_heavy_noise_is_followed_and_a_still_camera_is_not() {
    assert!(late_follows(0.8));
    assert!(!late_follows(0.0));
}

/// A camera the look saw still, over 12 s of frames at 10 frames/s with noise of
/// +-`noise` grey levels, bumped by `bump_px` along x at 7 s: whether it was followed,
/// and how far the static scene lay at the end's look ([`Late::unfollowed`]).
fn bumped(bump_px: f64, noise: f64) -> (bool, Option<f64>) {
    let late = late_on(|t| if t >= 7.0 { bump_px } else { 0.0 }, noise);
    (late.camera().is_some(), late.unfollowed().unwrap())
}

/// A bump late in a noisy recording is seen by the last two glances only: too few to
/// be followed as a drift, and the end's look at the static scene finds it (the
/// detection's `still` check); a still camera's static scene stays put; a bump the
/// glances follow leaves nothing to find.
#[test]
fn a_camera_bumped_late_and_not_followed_is_found_by_the_ends_look() {
    let (followed, at_end) = bumped(2.0, 150.0);
    assert!(!followed);
    let d = at_end.expect("the end's look measures the bump");
    assert!((d - 2.0).abs() < 0.4, "{d} px");
    let (followed, at_end) = bumped(0.0, 150.0);
    assert!(!followed);
    assert!(at_end.expect("measured") < 0.2, "{at_end:?}");
    let (followed, at_end) = bumped(2.0, 0.0);
    assert!(followed && at_end.is_none(), "{followed} {at_end:?}");
}

/// A camera bumped by 2 px at 1 s, before the first glance (2 s in), in a noisy
/// recording, is not hidden by the end's look measuring from the first glance: it is
/// followed (here as a drift, its glances agreeing with each other), or the end's look
/// finds it. (Were it neither, the first glance, displaced from the first frame as a
/// whole, would have the end's look judge from the first frame.)
#[test]
fn a_camera_bumped_before_the_first_glance_is_not_hidden() {
    let late = late_on(|t| if t >= 1.0 { 2.0 } else { 0.0 }, 150.0);
    let at_end = late.unfollowed().unwrap();
    assert!(
        late.camera().is_some() || at_end.is_some_and(|d| (d - 2.0).abs() < 0.4),
        "{:?} {at_end:?}",
        late.camera().is_some()
    );
}

/// A camera displaced by 2 px from 3 s to 7 s of a noisy recording and back (a tripod
/// knocked, swaying back): the glances at 4 s and 6 s see it, too few to be followed as
/// a drift, and the last two glances (8 s and 10 s) find the static scene where it was.
/// Two glances in a row found it off: the `still` check's figure is theirs.
#[test]
fn a_camera_displaced_for_a_while_is_found_by_two_glances_in_a_row() {
    let late = late_on(|t| if (3.0..7.0).contains(&t) { 2.0 } else { 0.0 }, 150.0);
    assert!(late.camera().is_none());
    let d = late.unfollowed().unwrap().expect("measured");
    assert!((d - 2.0).abs() < 0.4, "{d} px");
}

/// A camera found moving after the look is said to be steadied from the frame it was
/// found at, the frames before taken as still; one that moved from the start (no
/// glance found it still) is told apart (`detect` then measures it again).
#[test]
fn a_camera_found_moving_later_is_steadied_from_then_and_one_from_the_start_is_told() {
    let late = late_on(|t| if t >= 5.0 { 2.0 } else { 0.0 }, 0.0);
    let c = late.camera().expect("followed");
    let from = c.from_s.expect("found after the look");
    assert!((5.0..9.0).contains(&from), "{from}");
    assert!(!late.moved_from_start());
    assert!(
        c.steadied().contains(&format!("from {from:.1} s on")),
        "{}",
        c.steadied()
    );
    let late = late_on(|t| if t > 0.0 { 2.0 } else { 0.0 }, 0.0);
    assert!(late.camera().is_some() && late.moved_from_start());
    let still = late_on(|_| 0.0, 0.0);
    assert!(still.camera().is_none() && !still.moved_from_start());
}

/// A region's frames move with the whole picture: a drift to 18 px, past 2 % of the
/// 480 px region's side (`MAX_SHIFT`) but within 2 % of the 1920 px video's, is
/// followed to its end; judged against the region's side, the frames past 9.6 px went
/// unmeasured (held at the last measured).
#[test]
fn a_drift_is_followed_as_far_as_the_video_s_side_allows_not_the_region_s() {
    let drift = |t: f64| 1.5 * t;
    let c = late_in(1920.0, drift, 0.0).camera().expect("followed");
    assert_eq!(c.unmeasured, 0, "{c:?}");
    assert!(c.max_px > 16.0, "{c:?}");
    let c = late_in(480.0, drift, 0.0).camera().expect("followed");
    assert!(c.unmeasured > 20, "{c:?}");
}

/// A camera a pass found moving later is followed by the next pass from its first
/// frame: every frame is steadied, none taken as still.
#[test]
fn a_camera_known_to_move_is_followed_from_the_first_frame() {
    let (w, h) = (480, 320);
    let sweep = Sweep::around((-500.0, -500.0), 10.0, (0.0, 0.1), (0.0, 0.0));
    let mut late = Late::following(sweep, w as f64);
    for i in 0..60u64 {
        let t = i as f64 / 10.0;
        let m = Motion {
            dx: 0.3 * t,
            ..Motion::default()
        };
        let mut f = textured(w, h, m, i);
        f.t_s = t;
        late.offer(&mut f).unwrap();
    }
    let c = late.camera().expect("followed");
    assert_eq!(c.from_s, None, "{c:?}");
    assert!(!late.moved_from_start());
    assert_eq!(c.unmeasured, 0, "{c:?}");
    assert!((c.max_px - 0.3 * 5.9).abs() < 0.1, "{c:?}");
    assert_eq!(late.take_steadied().len(), 60);
    // Glanced at, the same frames are taken as still until two glances see the drift.
    let late = late_on(|t| 0.3 * t, 0.0);
    assert!(late
        .camera()
        .and_then(|c| c.from_s)
        .is_some_and(|t| t > 0.0));
}
