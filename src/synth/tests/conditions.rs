//! The twin's filming conditions: a faint wire, its shadow, flicker and drift, a held
//! ball, a fulcrum above the frame, a variable frame rate and a tilted camera.

use super::*;

/// Sum over the pixels within 6 px of the wire's middle half (a quarter to three
/// quarters of its length) of `bg - frame`, grey levels: the darkening the wire adds.
fn wire_darkening(frame: &Mat, bg: &Mat, pivot: [f64; 2], d_px: f64, theta: f64) -> f64 {
    let (f, b) = (frame.data_bytes().unwrap(), bg.data_bytes().unwrap());
    let w = frame.cols() as usize;
    let (ux, uy) = (theta.cos(), theta.sin());
    let mut sum = 0.0;
    for y in 0..frame.rows() as usize {
        for x in 0..w {
            let (dx, dy) = (x as f64 - pivot[0], y as f64 - pivot[1]);
            let along = dx * ux + dy * uy;
            let across = (dx * uy - dy * ux).abs();
            if across <= 6.0 && along > 0.25 * d_px && along < 0.75 * d_px {
                let j = 3 * (y * w + x);
                for c in 0..3 {
                    sum += (b[j + c] as f64 - f[j + c] as f64) / 3.0;
                }
            }
        }
    }
    sum
}

#[test]
fn a_faint_thin_wire_darkens_in_proportion_to_its_width_and_contrast() {
    // 640x480, clean: the darkening the wire adds is proportional to its width (the
    // line-spread profile integrates to the width) and to its contrast.
    let render = |extra: &str| {
        let e = exp(&format!(", width: 640, height: 480, clean: true{extra}"));
        let mut twin = Twin::new(Plan::new(&e, Some(1.0)).unwrap()).unwrap();
        twin.render_frame(10).unwrap();
        let g = twin.plan.geo.clone();
        let theta = twin.plan.truth[10].angle_rad;
        (twin.frame, g, theta)
    };
    let (bg, g, theta) = render(", wire_contrast: 0");
    let dark = |extra: &str| {
        let (f, g2, _) = render(extra);
        assert_eq!(g2.pivot, g.pivot);
        wire_darkening(&f, &bg, g.pivot, g.d_px, theta)
    };
    let default = render("").1;
    // 480 lines: 480 / 288 px, raised to 2 px.
    assert_eq!(default.wire_w, 2.0);
    let (w3, w1) = (dark(", wire_width_px: 3"), dark(", wire_width_px: 1"));
    let faint = dark(", wire_width_px: 1, wire_contrast: 0.3");
    // The plate is ~150 grey levels lighter than the wire: 3 px over ~180 px of length.
    assert!(w3 > 3.0 * 120.0 * 0.5 * g.d_px, "{w3}");
    assert!((w1 / w3 - 1.0 / 3.0).abs() < 0.03, "{w1} / {w3}");
    assert!((faint / w1 - 0.3).abs() < 0.03, "{faint} / {w1}");
    let (f, g1, _) = render(", wire_width_px: 1, wire_contrast: 0.3");
    assert_eq!(g1.wire_w, 1.0);
    let got = wire_found(&f, g.pivot, g.d_px, 0.2, theta, false);
    assert!((got - theta).abs() < 1.5 / (0.2 * g.d_px), "{got} {theta}");
}

#[test]
fn the_wire_casts_a_soft_shadow_at_its_angle_that_moves_with_it() {
    // Clean renders with and without the shadow differ only by it: along a circle
    // around the pivot, the darkening peaks at the wire's angle plus the shadow's,
    // takes `strength` of the plate there, and follows the wire from frame to frame.
    let base = exp(", clean: true, style: light-wire");
    let shaded = exp(
        ", clean: true, style: light-wire, shadow: { angle_deg: -6, blur_px: 1.5, strength: 0.5 }",
    );
    let (mut a, mut b) = (
        Twin::new(Plan::new(&base, Some(2.0)).unwrap()).unwrap(),
        Twin::new(Plan::new(&shaded, Some(2.0)).unwrap()).unwrap(),
    );
    let g = a.plan.geo.clone();
    let r = 0.5 * g.d_px;
    let mut peaks = Vec::new();
    for i in [5, 20] {
        a.render_frame(i).unwrap();
        b.render_frame(i).unwrap();
        let (fa, fb) = (a.frame.data_bytes().unwrap(), b.frame.data_bytes().unwrap());
        let grey = |f: &[u8], j: usize| f[j..j + 3].iter().map(|&v| v as f64).sum::<f64>() / 3.0;
        let theta = a.plan.truth[i].angle_rad;
        let mut best = (0.0, 0.0, 0.0);
        for k in -600..=600 {
            let ang = theta + (k as f64 / 600.0) * 0.3;
            let (x, y) = (g.pivot[0] + r * ang.cos(), g.pivot[1] + r * ang.sin());
            let j = 3 * ((y.round() as usize) * g.w + x.round() as usize);
            let (ga, gb) = (grey(fa, j), grey(fb, j));
            if ga - gb > best.0 {
                best = (ga - gb, ang, ga);
            }
        }
        let (dark, at, plate) = best;
        let want = theta - 6f64.to_radians();
        assert!(
            (at - want).abs() < 1.5 / r,
            "frame {i}: shadow at {at}, want {want}"
        );
        assert!(
            (dark / plate - 0.5).abs() < 0.1,
            "frame {i}: {dark} of {plate}"
        );
        peaks.push(at);
        // Nothing else changed: far from the wire, the frames are the same.
        let far = theta + 0.8;
        let (x, y) = (g.pivot[0] + r * far.cos(), g.pivot[1] + r * far.sin());
        let j = 3 * ((y.round() as usize) * g.w + x.round() as usize);
        assert_eq!(fa[j..j + 3], fb[j..j + 3]);
    }
    let moved = a.plan.truth[20].angle_rad - a.plan.truth[5].angle_rad;
    assert!(moved.abs() > 0.05, "{moved}");
    assert!((peaks[1] - peaks[0] - moved).abs() < 3.0 / r);
}

#[test]
fn a_lamps_share_bounds_the_shadow_to_the_light_the_wire_blocks() {
    // A 1 px wire's shadow blurred by 4 px. Across it, the darkening summed (px of the
    // plate's brightness) is the light the wire blocks: its width times the darkening
    // per unit of coverage. With `lamp_share: 1` that is at most the wire's 1 px, its
    // middle at most about a tenth of the plate; `strength: 0.5` alone asks the middle
    // for half the plate, which takes about five times the light a 1 px wire blocks.
    let across = |shadow: &str| {
        let base = exp(", clean: true, style: light-wire, wire_width_px: 1");
        let shaded = exp(&format!(
            ", clean: true, style: light-wire, wire_width_px: 1, shadow: {{ angle_deg: -6, \
             blur_px: 4, strength: 0.5{shadow} }}"
        ));
        let (mut a, mut b) = (
            Twin::new(Plan::new(&base, Some(2.0)).unwrap()).unwrap(),
            Twin::new(Plan::new(&shaded, Some(2.0)).unwrap()).unwrap(),
        );
        a.render_frame(5).unwrap();
        b.render_frame(5).unwrap();
        let g = a.plan.geo.clone();
        let r = 0.5 * g.d_px;
        let (fa, fb) = (a.frame.data_bytes().unwrap(), b.frame.data_bytes().unwrap());
        let grey = |f: &[u8], j: usize| f[j..j + 3].iter().map(|&v| v as f64).sum::<f64>() / 3.0;
        let mid = a.plan.truth[5].angle_rad - 6f64.to_radians();
        // Along the circle of radius `r` through the shadow, 0.05 px a step, 25 px
        // either side of its middle (beyond four blurs; the wire, near the window's
        // end, is drawn alike in both frames).
        let (step, n) = (0.05, 500);
        let (mut sum, mut peak) = (0.0, 0.0f64);
        for k in -n..=n {
            let ang = mid + k as f64 * step / r;
            let (x, y) = (g.pivot[0] + r * ang.cos(), g.pivot[1] + r * ang.sin());
            let j = 3 * ((y.round() as usize) * g.w + x.round() as usize);
            let (plate, dark) = (grey(fa, j), grey(fa, j) - grey(fb, j));
            sum += step * dark / plate;
            peak = peak.max(dark / plate);
        }
        (sum, peak)
    };
    let (bounded, bounded_peak) = across(", lamp_share: 1");
    let (asked, asked_peak) = across("");
    assert!(
        (bounded - 1.0).abs() < 0.1,
        "bounded: {bounded} px of the plate's light blocked"
    );
    assert!(bounded_peak < 0.12, "bounded: its middle {bounded_peak}");
    assert!(asked > 4.0 * bounded, "asked: {asked} px against {bounded}");
    assert!(
        (asked_peak - 0.5).abs() < 0.05,
        "asked: its middle {asked_peak}"
    );
    // A lamp giving half the light: half the darkening.
    let (half, _) = across(", lamp_share: 0.5");
    assert!(
        (half / bounded - 0.5).abs() < 0.05,
        "{half} against {bounded}"
    );
}

/// Least-squares amplitude `sqrt(a^2 + c^2)` of `y = b (1 + a sin(w t) + c cos(w t))`
/// over the samples, relative to the mean `b` (fitted as `y = p + q sin + r cos`).
fn relative_amplitude(t: &[f64], y: &[f64], w: f64) -> f64 {
    // Normal equations of a 3-parameter linear model, solved by Gauss-Jordan.
    let mut m = [[0.0f64; 4]; 3];
    for (&ti, &yi) in t.iter().zip(y) {
        let x = [1.0, (w * ti).sin(), (w * ti).cos()];
        for (row, &xr) in m.iter_mut().zip(&x) {
            for (v, &xc) in row.iter_mut().zip(&x) {
                *v += xr * xc;
            }
            row[3] += xr * yi;
        }
    }
    for k in 0..3 {
        let pivot = m[k];
        for (r, row) in m.iter_mut().enumerate() {
            if r != k {
                let f = row[k] / pivot[k];
                for (v, p) in row.iter_mut().zip(pivot) {
                    *v -= f * p;
                }
            }
        }
    }
    let p: Vec<f64> = (0..3).map(|k| m[k][3] / m[k][k]).collect();
    p[1].hypot(p[2]) / p[0]
}

#[test]
fn flicker_modulates_the_frames_at_its_frequency_and_depth() {
    // Strong flicker, no drift: the frames' mean brightness (over pixels far from
    // clipping) swings at the flicker's alias by the asked depth. 100 Hz at 30 frames/s
    // beats at 10 Hz, 120 Hz at 25 frames/s at 5 Hz; the default is a faint flicker
    // (seen on a light plate: on the dark one, 1.2 % is less than half a grey level).
    for (fps, hz, depth, extra) in [
        (30.0, 100.0, 0.15, "light-wire, flicker_depth: 0.15"),
        (
            25.0,
            120.0,
            0.15,
            "light-wire, flicker_hz: 120, flicker_depth: 0.15",
        ),
        (30.0, 100.0, 0.012, "dark-wire"),
    ] {
        let e = exp(&format!(
            ", fps: {fps}, spoiled_frames: 0, drift_depth: 0, style: {extra}"
        ));
        let mut twin = Twin::new(Plan::new(&e, Some(1.5)).unwrap()).unwrap();
        twin.render_frame(0).unwrap();
        // Pixels far from clipping, away from where the wire and the ball swing.
        let g = twin.plan.geo.clone();
        let mask: Vec<bool> = (twin.frame.data_bytes().unwrap().chunks(3).enumerate())
            .map(|(j, p)| {
                let (dx, dy) = ((j % g.w) as f64 - g.pivot[0], (j / g.w) as f64 - g.pivot[1]);
                let off = (dy.atan2(dx) - g.theta_rest).abs();
                let swept = dx.hypot(dy) < g.d_px + 2.5 * g.ball_r && off < 0.7;
                !swept && p.iter().all(|&v| (25..200).contains(&v))
            })
            .collect();
        let (mut t, mut y) = (Vec::new(), Vec::new());
        for i in 0..twin.plan.truth.len() {
            twin.render_frame(i).unwrap();
            let buf = twin.frame.data_bytes().unwrap();
            let (mut sum, mut n) = (0.0, 0.0);
            for (p, _) in buf.chunks(3).zip(&mask).filter(|(_, &m)| m) {
                sum += p.iter().map(|&v| v as f64).sum::<f64>();
                n += 3.0;
            }
            t.push(twin.plan.truth[i].t_s);
            y.push(sum / n);
        }
        let got = relative_amplitude(&t, &y, 2.0 * PI * hz);
        assert!(
            (got - depth).abs() < 0.1 * depth + 0.002,
            "{fps} fps, {hz} Hz: depth {got}, want {depth}"
        );
    }
}

#[test]
fn lighting_drift_follows_its_strength() {
    // No flicker: frames 3 s apart over 30 s stay within the per-frame jitter without
    // drift, and wander by several percent with a strong one.
    let spread = |drift: &str| {
        let e = exp(&format!(
            ", style: light-wire, spoiled_frames: 0, flicker_depth: 0, drift_depth: {drift}"
        ));
        let mut twin = Twin::new(Plan::new(&e, Some(30.0)).unwrap()).unwrap();
        let b: Vec<f64> = (0..=10)
            .map(|k| {
                twin.render_frame(90 * k).unwrap();
                brightness(&twin.frame)
            })
            .collect();
        let (lo, hi) = b
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        hi / lo - 1.0
    };
    let (none, strong) = (spread("0"), spread("0.3"));
    assert!(none < 0.02, "{none}");
    assert!(strong > 0.08, "{strong}");
}

#[test]
fn a_held_ball_stands_still_then_swings_as_released_at_the_hold() {
    // Held for 0.5 s: the truth is the release angle until then, and afterwards the
    // motion without a hold, shifted by 0.5 s; clean frames before the release are the
    // same pixels, and the wire has moved in the frames after it.
    let held = Plan::new(&exp(", clean: true, hold_s: 0.5"), Some(2.0)).unwrap();
    let free = Plan::new(&exp(", clean: true"), Some(2.0)).unwrap();
    let release = free.truth[0].angle_rad;
    assert!((release - (91.7f64 - 10.0).to_radians()).abs() < 1e-12);
    for row in &held.truth {
        if row.t_s <= 0.5 {
            assert_eq!(row.angle_rad, release, "{row:?}");
        } else {
            let want = free.theta(row.t_s - 0.5);
            assert!((row.angle_rad - want).abs() < 1e-9, "{row:?} {want}");
        }
    }
    let mut twin = Twin::new(held).unwrap();
    twin.render_frame(0).unwrap();
    let first = twin.frame.data_bytes().unwrap().to_vec();
    for i in [1, 7, 15] {
        twin.render_frame(i).unwrap();
        assert!(twin.frame.data_bytes().unwrap() == first, "frame {i}");
    }
    twin.render_frame(25).unwrap();
    let after = twin.frame.data_bytes().unwrap();
    let moved = after.iter().zip(&first).filter(|(a, b)| a != b).count();
    assert!(moved > 500, "{moved} pixels changed");
    // The camera's angle series (`rollfric simulate`) holds as well.
    let e = exp(", hold_s: 0.5, angle_noise_deg: 0");
    let rec = simulate::record(&e, &simulate::camera_of(&e).unwrap()).unwrap();
    assert_eq!(rec.trajectory.t0, 0.5);
    assert_eq!(rec.trajectory.state(0.25), [10f64.to_radians(), 0.0]);
}

#[test]
fn a_fulcrum_above_the_frame_still_shows_most_of_the_wire() {
    // The pivot 5 % of the height above the frame: the ball stays inside, and the
    // wire's pixels lie where the truth says, seen from the off-frame pivot.
    let plan = Plan::new(&exp(", clean: true, pivot_frac: [0.5, -0.05]"), Some(2.0)).unwrap();
    let g = plan.geo.clone();
    assert_eq!(g.pivot, [160.0, -12.0]);
    assert!(g.d_px > 0.5 * 240.0, "{}", g.d_px);
    for row in &plan.truth {
        let (x, y) = (
            g.pivot[0] + g.d_px * row.angle_rad.cos(),
            g.pivot[1] + g.d_px * row.angle_rad.sin(),
        );
        assert!(x - g.ball_r > 0.0 && x + g.ball_r < 320.0, "{row:?}");
        assert!(y - g.ball_r > 0.0 && y + g.ball_r < 240.0, "{row:?}");
    }
    let mut twin = Twin::new(plan).unwrap();
    for i in [0, 20] {
        twin.render_frame(i).unwrap();
        let want = twin.plan.truth[i].angle_rad;
        for frac in [0.3, 0.6] {
            let got = wire_found(&twin.frame, g.pivot, g.d_px, frac, want, false);
            assert!(
                (got - want).abs() < 1.5 / (frac * g.d_px),
                "frame {i} at {frac}: {got} vs {want}"
            );
        }
    }
    // Mirrored, the pivot is mirrored too.
    let m = Plan::new(&exp(", pivot_frac: [0.2, -0.05], mirror: true"), Some(1.0)).unwrap();
    assert_eq!(m.image_pivot(), [319.0 - 64.0, -12.0]);
    // Where no wire can be seen, the render is refused, naming the key.
    for bad in ["[0.5, 1.5]", "[0.5, 0.97]", "[-0.9, 0.5]"] {
        let e = exp(&format!(", pivot_frac: {bad}"));
        let err = format!("{:#}", Plan::new(&e, Some(1.0)).err().unwrap());
        assert!(err.contains("`synthetic.pivot_frac` = ["), "{bad}: {err}");
    }
}

#[test]
fn variable_frame_rate_videos_carry_each_frames_own_time() {
    if !crate::video::need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let e = exp(", vfr_jitter: 0.3, spoiled_frames: 0");
    let truth = truth(&e, Some(1.0)).unwrap();
    // Irregular, increasing, within 0.3 of a frame late, whole milliseconds.
    let gaps: Vec<f64> = truth.windows(2).map(|w| w[1].t_s - w[0].t_s).collect();
    assert!(gaps
        .iter()
        .all(|&g| g > 0.7 / 30.0 - 1e-3 && g < 1.3 / 30.0 + 1e-3));
    let (lo, hi) = gaps
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &g| (l.min(g), h.max(g)));
    assert!(hi - lo > 0.005, "gaps {lo}..{hi}");
    for (k, r) in truth.iter().enumerate() {
        assert!(r.t_s >= k as f64 / 30.0 - 5e-4 && r.t_s < (k as f64 + 0.3) / 30.0 + 5e-4);
        assert!((r.t_s * 1000.0 - (r.t_s * 1000.0).round()).abs() < 1e-9);
    }
    // Rendered at its own time: the truth's angle is the motion's at that time.
    let plan = Plan::new(&e, Some(1.0)).unwrap();
    for r in &plan.truth {
        assert_eq!(r.angle_rad, plan.theta(r.t_s));
    }
    for name in ["vfr.avi", "vfr.mp4", "vfr.mkv"] {
        let rep = render(&e, &dir.path().join(name), Some(1.0), &mut |_, _| {}).unwrap();
        assert!(
            rep.codec.ends_with("ffmpeg, variable frame rate)"),
            "{}",
            rep.codec
        );
        assert_eq!(rep.truth, truth);
        // ffprobe's times, and the detector's reader's (`-fps_mode passthrough`).
        let probed = ffprobe_times(&rep.path);
        let mut src = crate::video::FfmpegSource::open(&rep.path, None, 1).unwrap();
        let mut frame = crate::video::Frame::default();
        let mut decoded = Vec::new();
        while crate::video::FrameSource::next_frame(&mut src, &mut frame).unwrap() {
            decoded.push(frame.t_s);
        }
        for (what, times) in [("ffprobe", &probed), ("FfmpegSource", &decoded)] {
            assert_eq!(times.len(), truth.len(), "{name}: {what}");
            for (t, r) in times.iter().zip(&truth) {
                assert!((t - r.t_s).abs() < 1e-6, "{name}: {what} {t} vs {}", r.t_s);
            }
        }
    }
    // Every frame as rendered at its own time (up to the codec's loss).
    let frames = read_back(&dir.path().join("vfr.avi"), 320, 240);
    let mut twin = Twin::new(plan).unwrap();
    assert_eq!(frames.len(), twin.plan.truth.len());
    for (i, f) in frames.iter().enumerate() {
        twin.render_frame(i).unwrap();
        let d = diff(f, &twin.frame);
        assert!(d < 2.5, "frame {i}: {d}");
    }
    // An odd size (4:4:4 MJPG, converted by ffmpeg) keeps the variable rate too.
    let odd = exp(", vfr_jitter: 0.3, width: 322, height: 241, spoiled_frames: 0");
    let rep = render(&odd, &dir.path().join("odd.avi"), Some(1.0), &mut |_, _| {}).unwrap();
    assert_eq!(rep.codec, "MJPG 4:4:4 (avi, ffmpeg, variable frame rate)");
    let probed = ffprobe_times(&rep.path);
    assert_eq!(probed.len(), rep.truth.len());
    for (t, r) in probed.iter().zip(&rep.truth) {
        assert!((t - r.t_s).abs() < 1e-6, "odd: {t} vs {}", r.t_s);
    }
}

#[test]
fn a_tilted_camera_keeps_the_swing_in_the_frame_and_refuses_the_horizon() {
    // 20 degrees: the protractor's marks land where the view puts them, inside.
    let plan = Plan::new(
        &exp(", camera_tilt_deg: 20, tilt_axis_deg: 180, pivot_frac: [0.35, 0.2]"),
        Some(1.0),
    )
    .unwrap();
    let marks = plan.calibration_points();
    assert_eq!(marks.len(), 8, "{marks:?}");
    let (w, h) = (plan.geo.w as f64, plan.geo.h as f64);
    for (q, _) in &marks {
        assert!(q[0] > 0.0 && q[0] < w && q[1] > 0.0 && q[1] < h, "{q:?}");
    }
    // The fulcrum mark is the image pivot, to the 0.1 px the marks are rounded to.
    let p = plan.image_pivot();
    assert!((marks[0].0[0] - p[0]).abs() <= 0.05 && (marks[0].0[1] - p[1]).abs() <= 0.05);
    // 40 degrees through a wide lens puts the plate's horizon near the frame: refused.
    let wide = exp(", camera_tilt_deg: 40, tilt_axis_deg: 90, camera_focal_px: 100");
    let e = Plan::new(&wide, Some(1.0))
        .err()
        .expect("refused")
        .to_string();
    assert!(e.contains("horizon"), "{e}");
}
