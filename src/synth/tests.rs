//! The unit tests of `synth`: the twin's plan, its rendering and its YUV conversion.

use super::plan::{Plan, Spoil};
use super::twin::Twin;
use super::yuv::{bgr_to_yuv420, YuvRange};
use super::*;
use crate::rng::Rng;
use crate::simulate;
use opencv::core;
use std::f64::consts::PI;
use std::process::Command;

/// A 320x240, 30 frames/s twin unless `extra` sets the size or the rate.
fn exp(extra: &str) -> Experiment {
    let size = if extra.contains("width") {
        ""
    } else {
        ", width: 320, height: 240"
    };
    let fps = if extra.contains(" fps:") {
        ""
    } else {
        "fps: 30, "
    };
    let text = format!(
        "
geometry:
  incline: {{ h_m: 0.142, l_m: 1.5 }}
  pendulum: {{ d_m: 0.187 }}
  ball: {{ radius_m: 0.03175, mass_kg: 1.0458 }}
synthetic: {{ s_r_m: 4.445e-6, {fps}seed: 3{size}{extra} }}
"
    );
    Experiment::parse(Path::new("t/twin.yaml"), &text).unwrap()
}

/// Every frame of a video as BGR (decoded by the `ffmpeg` program, every frame kept),
/// checking its size.
fn read_back(path: &Path, w: i32, h: i32) -> Vec<Mat> {
    let out = Command::new("ffmpeg")
        .args(["-nostdin", "-v", "error", "-i"])
        .arg(path)
        .args(["-map", "0:v", "-fps_mode", "passthrough"])
        .args(["-f", "rawvideo", "-pix_fmt", "bgr24", "-"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let size = (w * h * 3) as usize;
    assert_eq!(
        out.stdout.len() % size,
        0,
        "{}: not {w}x{h}",
        path.display()
    );
    out.stdout
        .chunks_exact(size)
        .map(|f| {
            Mat::new_rows_cols_with_data(h, w * 3, f)
                .unwrap()
                .reshape(3, h)
                .unwrap()
                .try_clone()
                .unwrap()
        })
        .collect()
}

fn count_frames(path: &Path) -> usize {
    read_back(path, 320, 240).len()
}

/// Mean absolute difference of two frames, grey levels.
fn diff(a: &Mat, b: &Mat) -> f64 {
    let mut d = Mat::default();
    core::absdiff(a, b, &mut d).unwrap();
    let m = core::mean(&d, &core::no_array()).unwrap();
    (m[0] + m[1] + m[2]) / 3.0
}

fn brightness(a: &Mat) -> f64 {
    let m = core::mean(a, &core::no_array()).unwrap();
    (m[0] + m[1] + m[2]) / 3.0
}

#[test]
fn odd_sizes_fall_back_to_mjpg_and_spoiled_frames_look_spoiled() {
    if !crate::video::need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let e = exp(", width: 322, height: 241");
    let rep = render(&e, &dir.path().join("odd.mp4"), Some(1.0), &mut |_, _| {}).unwrap();
    assert_eq!(rep.path, dir.path().join("odd.avi"));
    assert_eq!(rep.codec, "MJPG 4:4:4 (avi, ffmpeg)");
    // The whole picture, every row and column, in 4:4:4.
    let probed = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0", "-show_entries"])
        .args(["stream=codec_name,width,height,pix_fmt", "-of", "csv=p=0"])
        .arg(&rep.path)
        .output()
        .unwrap();
    assert_eq!(
        String::from_utf8_lossy(&probed.stdout).trim(),
        "mjpeg,322,241,yuvj444p"
    );
    let frames = read_back(&rep.path, 322, 241);
    assert_eq!(frames.len(), rep.truth.len());
    for (i, row) in rep.truth.iter().enumerate().skip(1) {
        let (d, b) = (diff(&frames[i], &frames[i - 1]), brightness(&frames[i]));
        match row.spoiled {
            "duplicate" => assert!(d < 0.3, "frame {i}: {d}"),
            "flash" => assert!(b > 225.0, "frame {i}: {b}"),
            "hand" => assert!(d > 8.0, "frame {i}: {d}"),
            _ => {
                assert!(b < 200.0, "frame {i}: {b}");
                if rep.truth[i - 1].spoiled == "none" {
                    assert!((1.0..8.0).contains(&d), "frame {i}: {d}");
                }
            }
        }
    }
    // No temporary file left behind, and no `.mp4`.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["odd.avi"]);
}

#[test]
fn one_second_render_has_every_frame_and_its_truth() {
    if !crate::video::need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let e = exp("");
    let mut calls = Vec::new();
    let rep = render(&e, &dir.path().join("twin.mp4"), Some(1.0), &mut |d, t| {
        calls.push((d, t))
    })
    .unwrap();
    // 1 s at 30 fps: frames 0..=30.
    assert_eq!(rep.frames, 31);
    assert_eq!(rep.truth.len(), 31);
    assert_eq!(calls.last(), Some(&(31, 31)));
    assert!(rep.path.exists(), "{}", rep.path.display());
    assert_eq!(count_frames(&rep.path), 31);
    // No temporary file left behind.
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(left.len(), 1);
    // The truth is rest - psi(t), psi from the simulation.
    let mut cam = simulate::camera_of(&e).unwrap();
    cam.duration_s = Some(1.0);
    let rec = simulate::record(&e, &cam).unwrap();
    let rest = 91.7f64.to_radians();
    for (row, &t) in rep.truth.iter().zip(&rec.series.t) {
        assert_eq!(row.t_s, t);
        let want = rest - rec.trajectory.state(t)[0];
        assert!(
            (row.angle_rad - want).abs() < 1e-12,
            "{} {}",
            row.angle_rad,
            want
        );
    }
    assert!((rep.truth[0].angle_rad - (91.7f64 - 10.0).to_radians()).abs() < 1e-9);
    // Three spoiling events, one of each kind, counted as runs of equal tags.
    let mut runs = Vec::new();
    for (i, r) in rep.truth.iter().enumerate() {
        if r.spoiled != "none" && (i == 0 || rep.truth[i - 1].spoiled != r.spoiled) {
            runs.push(r.spoiled);
        }
    }
    assert_eq!(runs, ["hand", "flash", "duplicate"]);
    let csv = truth_csv(&rep.truth);
    assert!(
        csv.starts_with("t_s,angle_rad,spoiled\n0.000000,1.42"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 32);
}

#[test]
fn spoiled_frames_are_spoiled_and_clean_renders_are_not() {
    let e = exp(", spoiled_frames: 6");
    let truth = truth(&e, Some(20.0)).unwrap();
    let tags = |kind: &str| truth.iter().filter(|r| r.spoiled == kind).count();
    assert_eq!(tags("flash"), 2);
    assert_eq!(tags("duplicate"), 2);
    assert!((2..=6).contains(&tags("hand")));
    // Away from the first and last 2 s.
    for (i, r) in truth.iter().enumerate() {
        if r.spoiled != "none" {
            assert!(i >= 60 && i + 60 < truth.len(), "frame {i}");
        }
    }
    let clean = self::truth(&exp(", clean: true, spoiled_frames: 6"), Some(20.0)).unwrap();
    assert!(clean.iter().all(|r| r.spoiled == "none"));
    // Same seed, same plan.
    assert_eq!(truth, self::truth(&e, Some(20.0)).unwrap());
}

/// Where the wire crosses a circle of radius `frac * d_px` around the pivot in the
/// rendered frame: the darkest (or, `light`, brightest) pixel within 0.5 rad of `want`,
/// as an image angle; `pivot` and the frame's size as the image has them.
fn wire_found(frame: &Mat, pivot: [f64; 2], d_px: f64, frac: f64, want: f64, light: bool) -> f64 {
    let buf = frame.data_bytes().unwrap();
    let w = frame.cols() as usize;
    let r = frac * d_px;
    let mut best = (f64::MIN, 0.0);
    for k in -400..=400 {
        let a = want + (k as f64 / 400.0) * 0.5;
        let (x, y) = (pivot[0] + r * a.cos(), pivot[1] + r * a.sin());
        let (x, y) = (x.round(), y.round());
        if x < 0.0 || y < 0.0 || x >= w as f64 || y >= frame.rows() as f64 {
            continue;
        }
        let j = 3 * ((y as usize) * w + x as usize);
        let v = buf[j] as f64 + buf[j + 1] as f64 + buf[j + 2] as f64;
        let score = if light { v } else { -v };
        if score > best.0 {
            best = (score, a);
        }
    }
    best.1
}

#[test]
fn pixels_show_the_wire_where_the_truth_says() {
    // Clean render: the darkest pixels along a circle around the pivot lie on the
    // truth's angle, for each style.
    for style in [
        "dark-wire",
        "light-wire",
        "oblique",
        "dark-wire, rest_angle_deg: 3",
    ] {
        let e = exp(&format!(", clean: true, style: {style}"));
        let plan = Plan::new(&e, Some(2.0)).unwrap();
        let g = plan.geo.clone();
        let mut twin = Twin::new(plan).unwrap();
        let i = 20;
        twin.render_frame(i).unwrap();
        let want = twin.plan.truth[i].angle_rad;
        let light = style == "light-wire";
        let got = wire_found(&twin.frame, g.pivot, g.d_px, 0.2, want, light);
        assert!(
            (got - want).abs() < 1.5 / (0.2 * g.d_px),
            "{style}: wire found at {got} rad, truth {want}"
        );
    }
}

#[test]
fn the_scene_turns_with_any_rest_angle() {
    // The camera rolled over the full circle: the rest angle is taken into (-180, 180],
    // the wire lies where the truth says, and the protractor (brighter than the plate)
    // lies on the wire's side of the pivot, the plate on the other.
    for (rest, want_deg) in [
        (180.0, 180.0),
        (270.0, -90.0),
        (-135.0, -135.0),
        (-180.0, 180.0),
        (451.7, 91.7),
    ] {
        let e = exp(&format!(", clean: true, rest_angle_deg: {rest}"));
        let plan = Plan::new(&e, Some(2.0)).unwrap();
        let g = plan.geo.clone();
        assert!(
            (g.theta_rest - f64::to_radians(want_deg)).abs() < 1e-12,
            "{rest}: rest {}",
            g.theta_rest
        );
        let mut twin = Twin::new(plan).unwrap();
        let i = 20;
        twin.render_frame(i).unwrap();
        let row = &twin.plan.truth[i];
        assert!(
            (row.angle_rad - g.theta_rest).abs() < 0.25,
            "{rest}: {row:?}"
        );
        let got = wire_found(&twin.frame, g.pivot, g.d_px, 0.2, row.angle_rad, false);
        assert!(
            (got - row.angle_rad).abs() < 1.5 / (0.2 * g.d_px),
            "{rest}: wire found at {got} rad, truth {}",
            row.angle_rad
        );
        let buf = twin.frame.data_bytes().unwrap();
        let mean_at = |dir: f64| {
            let mut sum = 0.0;
            // Away from the wire: 25 to 75 degrees either side of `dir`.
            for k in -20..=20 {
                let side = if k < 0 { -25.0 } else { 25.0 };
                let a = dir + (side + 2.5 * k as f64).to_radians();
                let r = 0.5 * g.rp;
                let (x, y) = (g.pivot[0] + r * a.cos(), g.pivot[1] + r * a.sin());
                let j = 3 * ((y.round() as usize) * g.w + x.round() as usize);
                sum += buf[j..j + 3].iter().map(|&v| v as f64).sum::<f64>() / 3.0;
            }
            sum / 41.0
        };
        let (front, back) = (mean_at(g.theta_rest), mean_at(g.theta_rest + PI));
        assert!(
            front > back + 15.0,
            "{rest}: protractor {front}, plate {back}"
        );
    }
}

/// BT.601 as floating point, chroma of the 2x2 block's mean colour.
fn yuv_reference(bgr: &[u8], w: usize, h: usize, range: YuvRange) -> Vec<f64> {
    let (ky, kc, y0) = match range {
        YuvRange::Full => (1.0, 1.0, 0.0),
        YuvRange::Limited => (219.0 / 255.0, 224.0 / 255.0, 16.0),
    };
    let luma = |p: [f64; 3]| 0.114 * p[0] + 0.587 * p[1] + 0.299 * p[2];
    let px = |x: usize, y: usize| {
        let j = 3 * (y * w + x);
        [bgr[j] as f64, bgr[j + 1] as f64, bgr[j + 2] as f64]
    };
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            out.push(y0 + ky * luma(px(x, y)));
        }
    }
    let mut cb = Vec::new();
    let mut cr = Vec::new();
    for y in (0..h).step_by(2) {
        for x in (0..w).step_by(2) {
            let mut m = [0.0; 3];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let p = px(x + dx, y + dy);
                (0..3).for_each(|c| m[c] += p[c] / 4.0);
            }
            let l = luma(m);
            cb.push(128.0 + kc * 0.5 / 0.886 * (m[0] - l));
            cr.push(128.0 + kc * 0.5 / 0.701 * (m[2] - l));
        }
    }
    out.extend(cb);
    out.extend(cr);
    out
}

#[test]
fn yuv_conversion_is_bt601_within_one_level() {
    let (w, h) = (38, 6);
    let mut rng = Rng::new(7);
    let mut bgr: Vec<u8> = (0..3 * w * h)
        .map(|_| (rng.uniform() * 256.0) as u8)
        .collect();
    // Extremes: black, white, pure B, G, R, as uniform 2x2 blocks in the top rows.
    for (k, c) in [
        [0, 0, 0],
        [255, 255, 255],
        [255, 0, 0],
        [0, 255, 0],
        [0, 0, 255],
    ]
    .iter()
    .enumerate()
    {
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let j = 3 * (dy * w + 2 * k + dx);
            bgr[j..j + 3].copy_from_slice(c);
        }
    }
    for range in [YuvRange::Full, YuvRange::Limited] {
        let mut got = vec![9; 3];
        bgr_to_yuv420(&bgr, w, h, range, &mut got);
        let want = yuv_reference(&bgr, w, h, range);
        assert_eq!(got.len(), want.len());
        for (i, (&g, &e)) in got.iter().zip(&want).enumerate() {
            assert!(
                (g as f64 - e).abs() <= 1.0,
                "{range:?} byte {i}: {g} vs {e:.2}"
            );
        }
        // White and black exactly, and grey without colour.
        let (y, c) = match range {
            YuvRange::Full => ([0, 255], 128),
            YuvRange::Limited => ([16, 235], 128),
        };
        assert_eq!([got[0], got[2]], y, "{range:?}");
        let (cb, cr) = (w * h, w * h + w * h / 4);
        assert_eq!([got[cb], got[cr], got[cb + 1], got[cr + 1]], [c; 4]);
    }
}

#[test]
fn ffmpeg_writes_every_frame_the_same_way_twice() {
    if !crate::video::need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let e = exp(", spoiled_frames: 3");
    let mut files = Vec::new();
    for k in 0..2 {
        let out = dir.path().join(format!("twin{k}.avi"));
        let rep = render(&e, &out, Some(1.0), &mut |_, _| {}).unwrap();
        assert_eq!(rep.codec, "MJPG (avi, ffmpeg)");
        assert_eq!(rep.path, out);
        files.push(std::fs::read(&out).unwrap());
    }
    assert!(files[0] == files[1], "two renders differ");
    // Every frame, as rendered (up to the codec's loss), duplicates included.
    let path = dir.path().join("twin0.avi");
    let frames = read_back(&path, 320, 240);
    let mut twin = Twin::new(Plan::new(&e, Some(1.0)).unwrap()).unwrap();
    assert_eq!(frames.len(), twin.plan.truth.len());
    for (i, f) in frames.iter().enumerate() {
        let src = match twin.plan.spoils[i] {
            Spoil::Duplicate => i - 1,
            _ => i,
        };
        twin.render_frame(src).unwrap();
        let d = diff(f, &twin.frame);
        assert!(d < 2.5, "frame {i}: {d}");
    }
    // Constant rate: ffprobe counts every frame at exactly 30 frames/s.
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=nb_read_frames,r_frame_rate,avg_frame_rate",
        ])
        .args(["-of", "csv=p=0"])
        .arg(&path)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.trim(), format!("30/1,30/1,{}", frames.len()));
}

#[test]
fn a_mirrored_twin_is_the_twin_flipped_with_its_truth() {
    // With and without camera defects: the mirrored frame is the plain one flipped
    // left-right, pixel for pixel, and the truth is mirrored (pi - theta). A camera
    // turned 30 degrees, so that the mirrored wire is far from the plain one.
    for extra in [", clean: true, rest_angle_deg: 60", ", rest_angle_deg: 60"] {
        let plain = Plan::new(&exp(extra), Some(2.0)).unwrap();
        let mirrored = Plan::new(&exp(&format!("{extra}, mirror: true")), Some(2.0)).unwrap();
        let g = plain.geo.clone();
        assert_eq!(plain.truth.len(), mirrored.truth.len());
        assert!((mirrored.image_rest - (PI - plain.image_rest)).abs() < 1e-12);
        for (a, b) in plain.truth.iter().zip(&mirrored.truth) {
            assert_eq!((a.t_s, a.spoiled), (b.t_s, b.spoiled));
            assert!(
                (b.angle_rad - (PI - a.angle_rad)).abs() < 1e-12,
                "{a:?} {b:?}"
            );
        }
        let pivot = mirrored.image_pivot();
        assert_eq!(pivot, [(g.w - 1) as f64 - g.pivot[0], g.pivot[1]]);
        let (mut a, mut b) = (Twin::new(plain).unwrap(), Twin::new(mirrored).unwrap());
        for i in [0, 20, 45] {
            a.render_frame(i).unwrap();
            b.render_frame(i).unwrap();
            let mut flipped = Mat::default();
            core::flip(&a.frame, &mut flipped, 1).unwrap();
            assert_eq!(
                b.frame.data_bytes().unwrap(),
                flipped.data_bytes().unwrap(),
                "frame {i}{extra}"
            );
            if extra.contains("clean") {
                let want = b.plan.truth[i].angle_rad;
                let got = wire_found(&b.frame, pivot, g.d_px, 0.2, want, false);
                assert!((got - want).abs() < 1.5 / (0.2 * g.d_px), "{got} {want}");
                // Not where the unmirrored truth would put it.
                assert!((got - a.plan.truth[i].angle_rad).abs() > 0.5, "{got}");
            }
        }
    }
}

mod conditions;
mod room;

/// Every frame's presentation time as ffprobe decodes it, s.
pub(super) fn ffprobe_times(path: &Path) -> Vec<f64> {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0"])
        .args(["-show_entries", "frame=pts_time", "-of", "csv=p=0"])
        .arg(path)
        .output()
        .unwrap();
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split(',').next()?.trim().parse().ok())
        .collect()
}

#[test]
fn dropped_frames_leave_gaps_in_the_times_and_the_truth() {
    if !crate::video::need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let full = render(
        &exp(""),
        &dir.path().join("full.avi"),
        Some(3.0),
        &mut |_, _| {},
    )
    .unwrap();
    // A long video dropping many frames: FFmpeg takes the whole list.
    let many = exp(", dropped_share: 0.2");
    let long = render(
        &many,
        &dir.path().join("many.avi"),
        Some(20.0),
        &mut |_, _| {},
    )
    .unwrap();
    assert!(601 - long.frames > 90, "{} frames written", long.frames);
    assert_eq!(ffprobe_times(&long.path).len(), long.frames);
    let dropping = exp(", dropped_share: 0.1");
    for ext in ["mp4", "avi"] {
        let rep = render(
            &dropping,
            &dir.path().join(format!("drop.{ext}")),
            Some(3.0),
            &mut |_, _| {},
        )
        .unwrap();
        // 3 s at 30 frames/s is 91 frames; about a tenth of them are gone.
        let gone = 91 - rep.frames;
        assert!((3..=20).contains(&gone), "{ext}: {gone} dropped");
        assert_eq!(rep.truth.len(), rep.frames);
        assert_eq!(rep.truth, truth(&dropping, Some(3.0)).unwrap());
        // The file carries the written frames' own times: gaps where frames are gone.
        let times = ffprobe_times(&rep.path);
        assert_eq!(times.len(), rep.frames, "{ext}");
        for (t, r) in times.iter().zip(&rep.truth) {
            assert!((t - r.t_s).abs() < 1e-6, "{ext}: {t} against {}", r.t_s);
        }
        let gaps = times
            .windows(2)
            .filter(|w| w[1] - w[0] > 1.5 / 30.0)
            .count();
        assert!(gaps >= 3, "{ext}: {gaps} gaps");
        // The truth of each written frame is the full twin's at its time (whole
        // milliseconds, against k / 30 s: the wire moves at most 0.01 deg in 0.5 ms).
        for r in &rep.truth {
            let k = (r.t_s * 30.0).round() as usize;
            assert!((full.truth[k].t_s - r.t_s).abs() < 5e-4, "{ext}: frame {k}");
            let off = (full.truth[k].angle_rad - r.angle_rad).abs();
            assert!(off < 3e-4, "{ext}: frame {k} {off} rad off");
        }
        // Each written frame is the full render's frame of its time: as near it as its
        // neighbours, or nearer (each frame has its own sensor noise; a duplicated one
        // repeats its predecessor).
        if ext == "avi" {
            let back = read_back(&rep.path, 320, 240);
            let whole = read_back(&full.path, 320, 240);
            for (m, r) in back.iter().zip(&rep.truth) {
                // A duplicated frame repeats its predecessor.
                if r.spoiled == "duplicate" {
                    continue;
                }
                let k = (r.t_s * 30.0).round() as usize;
                let d = diff(m, &whole[k]);
                for j in [k.saturating_sub(1), (k + 1).min(90)] {
                    if j != k {
                        let dj = diff(m, &whole[j]);
                        assert!(
                            d <= dj,
                            "the frame at {} s: {d} from frame {k}, {dj} from {j}",
                            r.t_s
                        );
                    }
                }
            }
        }
    }
}

/// A rolling shutter's band of rows is the still shutter's frame at that band's own time
/// (the wire and the camera's motion with it), and the bands' times differ.
#[test]
fn a_rolling_shutter_s_rows_are_each_seen_at_their_own_time() {
    let keys = ", clean: true, shake: {px: 3.0, deg: 0.4, hz: 6.0}";
    let rolling = exp(&format!("{keys}, rolling_shutter: 0.9"));
    let mut rs = Twin::new(Plan::new(&rolling, Some(1.0)).unwrap()).unwrap();
    let mut still = Twin::new(Plan::new(&exp(keys), Some(1.0)).unwrap()).unwrap();
    let i = 12;
    rs.render_frame(i).unwrap();
    let t = rs.plan.truth[i].t_s;
    let (h, step) = (240usize, 3 * 320usize);
    let rows =
        |m: &Mat, y0: usize, y1: usize| m.data_bytes().unwrap()[y0 * step..y1 * step].to_vec();
    let most = |a: &[u8], b: &[u8]| a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
    let mut apart = 0;
    for b in [0, 5, 15] {
        let (y0, y1) = (b * h / 16, (b + 1) * h / 16);
        let yc = 0.5 * (y0 + y1) as f64 - 0.5;
        still.plan.truth[i].t_s = t + (yc / (h - 1) as f64 - 0.5) * 0.9 / 30.0;
        still.render_frame(i).unwrap();
        // (The band's warp counts its rows from its own first: OpenCV's fixed-point
        // interpolation may round a pixel or two differently.)
        let (a, s) = (rows(&rs.frame, y0, y1), rows(&still.frame, y0, y1));
        let mean = a
            .iter()
            .zip(&s)
            .map(|(x, y)| f64::from(x.abs_diff(*y)))
            .sum::<f64>()
            / a.len() as f64;
        assert!(
            most(&a, &s) <= 3 && mean < 0.05,
            "band {b}: {} grey levels off its own time's frame at most, {mean} on average",
            most(&a, &s)
        );
        // At the frame's own time the camera stood elsewhere for the outer bands.
        still.plan.truth[i].t_s = t;
        still.render_frame(i).unwrap();
        if most(&rows(&rs.frame, y0, y1), &rows(&still.frame, y0, y1)) > 10 {
            apart += 1;
        }
    }
    assert!(
        apart >= 2,
        "{apart} of 3 bands differ from the frame's own time"
    );
}

/// The operator's hand is on the ball while it is held, draws back at the release, and is
/// gone 0.4 s later; nowhere near the fulcrum.
#[test]
fn the_releasing_hand_holds_the_ball_then_leaves_the_picture_as_it_was() {
    let keys = ", hold_s: 0.5, spoiled_frames: 0";
    let mut with =
        Twin::new(Plan::new(&exp(&format!("{keys}, release_hand: true")), Some(2.0)).unwrap())
            .unwrap();
    let mut without = Twin::new(Plan::new(&exp(keys), Some(2.0)).unwrap()).unwrap();
    let pivot = with.plan.image_pivot();
    let changed = |a: &Mat, b: &Mat| {
        let (a, b) = (a.data_bytes().unwrap(), b.data_bytes().unwrap());
        let mut n = 0;
        let mut near_pivot = 0;
        for (i, (x, y)) in a.chunks(3).zip(b.chunks(3)).enumerate() {
            if x.iter().zip(y).any(|(p, q)| p.abs_diff(*q) > 20) {
                n += 1;
                let (px, py) = ((i % 320) as f64, (i / 320) as f64);
                if (px - pivot[0]).hypot(py - pivot[1]) < 40.0 {
                    near_pivot += 1;
                }
            }
        }
        (n, near_pivot)
    };
    // Held (frame 6, 0.2 s), drawing back (frame 18, 0.6 s), gone (frame 30, 1 s).
    for (i, hand) in [(6, true), (18, true), (30, false)] {
        with.render_frame(i).unwrap();
        without.render_frame(i).unwrap();
        let (n, near) = changed(&with.frame, &without.frame);
        if hand {
            assert!(n > 300, "frame {i}: {n} pixels show the hand");
            assert_eq!(near, 0, "frame {i}: the hand reaches the fulcrum");
        } else {
            assert_eq!(n, 0, "frame {i}: {n} pixels still differ");
        }
    }
}
