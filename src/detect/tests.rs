//! The unit tests of `detect/mod.rs`.

use super::*;

#[test]
fn a_larger_working_side_is_priced_before_it_is_spent() {
    let video = |width, height, fps: u64| crate::video::VideoInfo {
        width,
        height,
        frames_header: Some(60 * fps),
        duration_s: Some(60.0),
        codec: "h264".into(),
        luma_plane: true,
    };
    // 4K at 4096 px: full size, 75 frames of 8 294 400 px, thinned to every 3rd
    // (`first_look::look_stride`: 25 frames, one every tenth of a second), 2.3 copies,
    // 40 MiB.
    let uhd = peak_memory_estimate_mib(&video(3840, 2160, 30), 4096.0);
    assert!((uhd - (40.0 + 2.3 * 25.0 * 8_294_400.0 / 1_048_576.0)).abs() < 1e-9);
    assert!((450.0..550.0).contains(&uhd), "{uhd}");
    // The default side shrinks it three times: 640x360.
    let small = peak_memory_estimate_mib(&video(3840, 2160, 30), 640.0);
    assert!((small - (40.0 + 2.3 * 75.0 * 230_400.0 / 1_048_576.0)).abs() < 1e-9);
    // At most LOOK_MAX_FRAMES frames, however fast the video: 300 of 0.92 MB are over
    // the look's 160 MiB, which holds 181: every 2nd is kept.
    let fast = peak_memory_estimate_mib(&video(1280, 720, 1000), 1280.0);
    assert!((fast - (40.0 + 2.3 * 150.0 * 921_600.0 / 1_048_576.0)).abs() < 1e-9);
}

#[test]
fn a_larger_working_side_is_held_to_a_bounded_frame() {
    // 4K at 4096 px: full size, 8 294 400 px, at the bound: not held.
    assert_eq!(work_scale(3840, 2160, 4096.0), (1, false));
    // 8K at 8192: 33 Mpx at full size; half size is 4K.
    assert_eq!(work_scale(7680, 4320, 8192.0), (2, true));
    // 8192x8192 at 8192: 67 Mpx, 16.8 at half size, 7.5 at a third (2730x2730).
    assert_eq!(work_scale(8192, 8192, 8192.0), (3, true));
    // A region of it, 3000x2000, at full size.
    assert_eq!(work_scale(3000, 2000, 8192.0), (1, false));
    // The default side is never held.
    assert_eq!(work_scale(1920, 1080, 640.0), (3, false));
    assert_eq!(work_scale(8192, 8192, 640.0), (13, false));
    // Whatever the side and the frame (up to the largest a video may have) and the rate,
    // the estimated peak stays under 600 MiB.
    let video = |width, height, fps: u64| crate::video::VideoInfo {
        width,
        height,
        frames_header: Some(10 * fps),
        duration_s: Some(10.0),
        codec: "h264".into(),
        luma_plane: true,
    };
    for (w, h) in [
        (8192, 8192),
        (8192, 1080),
        (7680, 4320),
        (5000, 5000),
        (4097, 4097),
    ] {
        for side in [640.0, 1280.0, 2048.0, 4096.0, 8192.0] {
            for fps in [10, 30, 60, 240] {
                let mib = peak_memory_estimate_mib(&video(w, h, fps), side);
                assert!(
                    mib < 600.0,
                    "{w}x{h} at {side} px, {fps} frames/s: {mib} MiB"
                );
            }
        }
    }
}

#[test]
fn shrunk_pixel_centres_map_to_the_centres_of_the_pixels_they_average() {
    let origin = Pt::new(10.0, 3.0);
    // Shrunk 2x: pixel 0 averages full pixels 10 and 11 (centre 10.5).
    assert_eq!(
        shrunk_to_full(Pt::new(0.0, 0.0), origin, 2.0),
        Pt::new(10.5, 3.5)
    );
    // 3x: pixel 1 averages 13, 14 and 15.
    assert_eq!(
        shrunk_to_full(Pt::new(1.0, 1.0), origin, 3.0),
        Pt::new(14.0, 7.0)
    );
    assert_eq!(
        shrunk_to_full(Pt::new(4.0, 5.0), origin, 1.0),
        Pt::new(14.0, 8.0)
    );
    let p = Pt::new(123.25, -640.5);
    assert!((shrunk_to_full(full_to_shrunk(p, origin, 3.0), origin, 3.0) - p).norm() < 1e-12);
}

#[test]
fn the_other_scales_pass_replaces_the_first_by_its_look_then_by_its_lines_and_checks() {
    let pass = |off: f64, fails: usize, look_sweep_deg: f64, amplitude: f64| Pass {
        off: Some(off),
        fails,
        look_sweep_deg,
        amplitude_deg: Some(amplitude),
    };
    // Film 1's first 12 s moved by hand: the wire (its look 24.3 deg, its track 24.4,
    // five checks failed, lines turning 0.997 times) against the ball's beads (88 deg,
    // 7, four failed, 1.0017): nearer and failing fewer, the beads are not kept, their
    // look far from their swing; the other way round, the wire replaces the beads.
    let wire = pass(0.003, 5, 24.3, 12.2);
    let beads = pass(0.0017, 4, 88.4, 3.4);
    assert!(!wire.replaced_by(beads, false));
    assert!(beads.replaced_by(wire, false));
    // Two looks that agree with their swings (or two that do not): the nearer swing
    // scale that fails fewer checks, and only that.
    let near = pass(0.001, 2, 24.0, 12.0);
    let far = pass(0.004, 3, 25.0, 12.0);
    assert!(far.replaced_by(near, false));
    assert!(!near.replaced_by(far, false));
    assert!(!pass(0.004, 2, 25.0, 12.0).replaced_by(pass(0.001, 2, 24.0, 12.0), false));
    assert!(!beads.replaced_by(pass(0.001, 5, 60.0, 3.0), false));
    // Between the two limits (a look 1.7 times the swing): not decided by the look.
    assert!(!wire.replaced_by(pass(0.001, 6, 41.0, 12.0), false));
    // Measured again for a swing scale far from 1: the nearer is kept, whatever else.
    let off_scale = pass(0.05, 1, 24.0, 12.0);
    assert!(off_scale.replaced_by(pass(0.001, 4, 88.0, 3.0), true));
    assert!(!off_scale.replaced_by(pass(0.06, 0, 24.0, 12.0), true));
    // A pass whose swing scale was not measured replaces nothing.
    let unmeasured = Pass { off: None, ..near };
    assert!(!far.replaced_by(unmeasured, false));
    // Film 1 jittered by hand: the first pass followed a static line and never turned
    // (no amplitude; `turns` and `beside` failed), the look against the median found
    // the wire (its look 24.5 deg, its swing 24.4; `smooth` and `envelope` failed). The
    // swing is kept though it fails as many checks, and only when its look agrees.
    let still_line = Pass {
        amplitude_deg: None,
        ..pass(0.0006, 2, 24.7, 1.0)
    };
    assert!(still_line.replaced_by(pass(0.002, 2, 24.5, 12.2), false));
    assert!(!still_line.replaced_by(pass(0.002, 2, 41.0, 12.2), false));
    assert!(!pass(0.002, 2, 24.5, 12.2).replaced_by(still_line, false));
}
