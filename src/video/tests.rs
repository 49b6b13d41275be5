//! The unit tests of `video.rs`.

use super::*;
use opencv::prelude::MatTraitConstManual;

/// Every frame of the video at `path`, decoded cropped to `roi` and shrunk `shrink`
/// times.
fn frames_of(path: &Path, roi: Roi, shrink: u32) -> Vec<Frame> {
    let mut src = FfmpegSource::open(path, Some(roi), shrink).unwrap();
    let mut out = Vec::new();
    let mut f = Frame::default();
    while src.next_frame(&mut f).unwrap() {
        out.push(f.clone());
    }
    out
}

/// Five frames of ffmpeg's `testsrc2` at `size` (`WxH`), encoded with `codec` (its
/// flags) to `path`.
fn test_clip(path: &Path, size: &str, codec: &[&str]) {
    clip_at(path, size, (10, 0.5), codec);
}

/// A test pattern of `rate` frames/s for `duration` s.
fn clip_at(path: &Path, size: &str, (rate, duration): (u32, f64), codec: &[&str]) {
    let st = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-f", "lavfi", "-i"])
        .arg(format!(
            "testsrc2=size={size}:rate={rate}:duration={duration}"
        ))
        .args(codec)
        .arg(path)
        .status()
        .unwrap();
    assert!(st.success(), "{}", path.display());
}

#[test]
fn every_frame_of_a_long_or_fast_video_keeps_its_own_time() {
    if !crate::require::require("ffmpeg", crate::require::MAKE_DEPS, have_ffmpeg()) {
        return;
    }
    // 240 frames/s for 9 s: frame 2084 on is past 500 000 / fps, where the raw
    // output's frames once fell on one tick of the muxer's time base, were dropped
    // by it, and the video was refused as damaged after the last frame. Both
    // containers, each with its own time base (1/15360 in MP4, 1/240 in AVI).
    let dir = tempfile::tempdir().unwrap();
    for (name, codec) in [
        ("fast.mp4", &["-c:v", "libx264", "-preset", "ultrafast"][..]),
        ("fast.avi", &["-c:v", "mjpeg"][..]),
    ] {
        let path = dir.path().join(name);
        clip_at(&path, "32x24", (240, 9.0), codec);
        let mut src = FfmpegSource::open(&path, None, 1).unwrap();
        let mut frame = Frame::default();
        let mut n = 0u64;
        while src.next_frame(&mut frame).unwrap() {
            assert_eq!(frame.index, n);
            let want = n as f64 / 240.0;
            assert!(
                (frame.t_s - want).abs() < 1e-9,
                "{name} frame {n}: {} s",
                frame.t_s
            );
            n += 1;
        }
        assert_eq!(n, 2160, "{name}");
    }
}

#[test]
fn a_ten_bit_video_comes_as_one_byte_a_pixel_and_does_not_hang() {
    if !crate::require::require("ffmpeg", crate::require::MAKE_DEPS, have_ffmpeg()) {
        return;
    }
    // The same scene stored losslessly at 8 and at 10 bits a sample.
    let dir = tempfile::tempdir().unwrap();
    let clip = |name: &str, pix_fmt: &str| {
        let path = dir.path().join(name);
        test_clip(&path, "320x240", &["-c:v", "ffv1", "-pix_fmt", pix_fmt]);
        path
    };
    let eight = clip("8.mkv", "yuv420p");
    let ten = clip("10.mkv", "yuv420p10le");
    let roi = Roi {
        x: 0,
        y: 0,
        w: 320,
        h: 240,
    };
    for shrink in [1u32, 2] {
        // Two bytes a pixel once read as two frames a frame, then waited forever for
        // a time the decoder never sent: decoded on a thread, with a deadline.
        let (tx, rx) = mpsc::channel();
        let path = ten.clone();
        std::thread::spawn(move || {
            let _ = tx.send(frames_of(&path, roi, shrink));
        });
        let deep = rx
            .recv_timeout(std::time::Duration::from_secs(60))
            .expect("decoding a 10-bit video hung");
        let plain = frames_of(&eight, roi, shrink);
        assert_eq!(deep.len(), 5, "shrunk {shrink}x");
        assert_eq!(deep.len(), plain.len(), "shrunk {shrink}x");
        for (d, p) in deep.iter().zip(&plain) {
            assert_eq!((d.width, d.height), (p.width, p.height));
            assert_eq!(d.data.len(), d.width * d.height);
            let worst = d
                .data
                .iter()
                .zip(&p.data)
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap();
            assert!(
                worst <= 1,
                "shrunk {shrink}x, frame {}: {worst} levels apart",
                d.index
            );
        }
    }
}

#[test]
fn a_shrunk_look_sees_the_luma_as_stored_averaged_in_blocks() {
    if !crate::require::require("ffmpeg", crate::require::MAKE_DEPS, have_ffmpeg()) {
        return;
    }
    // Limited-range (TV) luma, as H.264 stores it, and full-range (PC) luma, as MJPG
    // does: both must come shrunk as the means of the stored bytes.
    let dir = tempfile::tempdir().unwrap();
    for (name, codec) in [
        ("tv.mp4", ["-c:v", "libx264", "-pix_fmt", "yuv420p"]),
        ("pc.avi", ["-c:v", "mjpeg", "-pix_fmt", "yuvj420p"]),
    ] {
        let path = dir.path().join(name);
        test_clip(&path, "400x240", &codec);
        // A region at odd offsets, a whole number of blocks wide and high.
        let roi = Roi {
            x: 7,
            y: 5,
            w: 384,
            h: 216,
        };
        let full = frames_of(&path, roi, 1);
        assert_eq!(full.len(), 5, "{name}");
        for shrink in [2u32, 3] {
            let small = frames_of(&path, roi, shrink);
            assert_eq!(small.len(), full.len(), "{name}");
            let (w, h) = (384 / shrink as usize, 216 / shrink as usize);
            let n = shrink * shrink;
            for (f, s) in full.iter().zip(&small) {
                assert_eq!((s.width, s.height), (w, h), "{name}");
                // The rounded mean of each block of the stored luma, by hand.
                let mean: Vec<u8> = (0..w * h)
                    .map(|i| {
                        let (bx, by) = (i % w * shrink as usize, i / w * shrink as usize);
                        let sum: u32 = (0..shrink as usize)
                            .flat_map(|dy| (0..shrink as usize).map(move |dx| (dx, dy)))
                            .map(|(dx, dy)| f.data[(by + dy) * f.width + bx + dx] as u32)
                            .sum();
                        ((sum + n / 2) / n) as u8
                    })
                    .collect();
                let worst = mean
                    .iter()
                    .zip(&s.data)
                    .map(|(a, b)| a.abs_diff(*b))
                    .max()
                    .unwrap();
                let bias = mean
                    .iter()
                    .zip(&s.data)
                    .map(|(a, b)| *b as f64 - *a as f64)
                    .sum::<f64>()
                    / mean.len() as f64;
                // Exactly at 2x; at 3x the scaler's fixed point rounds a block now and
                // then the other way. A stretched range is 9 levels brighter at the
                // mean and up to 20 apart.
                assert!(
                    worst <= 1 && bias.abs() < 0.01,
                    "{name}, shrunk {shrink}x, frame {}: {worst} levels apart at worst, \
                         {bias:.3} on average",
                    s.index
                );
                // The same as the streaming pass's own shrink (OpenCV's area average).
                let m = opencv::core::Mat::new_rows_cols_with_data(
                    f.height as i32,
                    f.width as i32,
                    &f.data,
                )
                .unwrap();
                let mut r = opencv::core::Mat::default();
                opencv::imgproc::resize(
                    &m,
                    &mut r,
                    opencv::core::Size::new(w as i32, h as i32),
                    0.0,
                    0.0,
                    opencv::imgproc::INTER_AREA,
                )
                .unwrap();
                assert_eq!(r.data_bytes().unwrap(), &mean[..], "{name}, {shrink}x");
            }
        }
    }
}

#[test]
fn a_video_stream_is_known_by_its_description() {
    let h264 = "[info]   Stream #0:0[0x1](und): Video: h264 (High) (avc1 / 0x31637661), \
                    yuv420p(tv, bt709, progressive), 640x480 [SAR 1:1 DAR 4:3], 1010 kb/s, \
                    30 fps, 30 tbr, 15360 tbn (default)";
    let v = parse_video_stream(h264, Some(80.0)).unwrap();
    assert_eq!((v.width, v.height, v.codec.as_str()), (640, 480, "h264"));
    assert_eq!((v.frames_header, v.duration_s), (Some(2400), Some(80.0)));
    let mjpeg = "[info]   Stream #0:1: Video: mjpeg (Baseline) (MJPG / 0x47504A4D), \
                     yuvj420p(pc, bt470bg/unknown/unknown), 960x540, 5432 kb/s, 29.97 fps, \
                     29.97 tbr, 29.97 tbn";
    let v = parse_video_stream(mjpeg, Some(12.04)).unwrap();
    assert_eq!((v.width, v.height, v.codec.as_str()), (960, 540, "mjpeg"));
    assert_eq!(v.frames_header, Some(361));
    // No size, or no duration: nothing to go on, or no count.
    assert!(parse_video_stream("[info] Stream #0:0: Video: h264, yuv420p", None).is_none());
    let v = parse_video_stream("Stream #0:0: Video: rawvideo, gray, 2x3, 1k fps", None);
    assert_eq!(
        v.map(|v| (v.width, v.height, v.frames_header)),
        Some((2, 3, None))
    );
    assert_eq!(parse_clock("01:02:03.50"), Some(3723.5));
    assert_eq!(parse_clock("N/A"), None);
}

#[test]
fn complaints_are_told_by_their_level_not_their_words() {
    assert!(decoder_complaint(
        "[h264 @ 0x55] [error] Invalid NAL unit size (1210 > 415)."
    ));
    assert!(decoder_complaint(
        "[error] cut.mp4: Invalid data found when processing input"
    ));
    assert!(!decoder_complaint(
        "[info] Input #0, mov,mp4,m4a,3gp,3g2,mj2, from 'mirror_error_invalid_truncated.mp4':"
    ));
    assert!(!decoder_complaint("[warning] deprecated pixel format used"));
}

#[test]
fn the_muxers_complaints_are_not_the_videos() {
    let muxer = "[rawvideo @ 0x561e4064d5c0] [error] Application provided invalid, non \
                     monotonically increasing dts to muxer in stream 0: 1 >= 1";
    assert!(decoder_complaint(muxer) && own_side(muxer));
    assert!(own_side(
        "[Parsed_crop_0 @ 0x55] [error] Invalid too big or non positive size"
    ));
    assert!(!own_side(
        "[h264 @ 0x55] [error] Invalid NAL unit size (1210 > 415)."
    ));
    assert!(!own_side(
        "[error] cut.mp4: Invalid data found when processing input"
    ));
}
