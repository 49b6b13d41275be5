//! The unit tests of `detect/geometry.rs`.

use super::*;

#[test]
fn median_background_ignores_what_passes_briefly() {
    // 5 frames of 300 pixels (more than one run of 256): a wall at 100 + x % 7,
    // crossed at each pixel once by something dark and once by something bright.
    let (w, h, n) = (30usize, 10usize, 5usize);
    let data: Vec<Vec<u8>> = (0..n)
        .map(|f| {
            (0..w * h)
                .map(|i| match (i + f) % n {
                    0 => 10,
                    1 => 250,
                    _ => 100 + (i % 7) as u8,
                })
                .collect()
        })
        .collect();
    let init = InitFrames {
        w,
        h,
        shrink: 1.0,
        x0: 0.0,
        y0: 0.0,
        data,
    };
    let m = median_frame(&init);
    assert!(m.iter().enumerate().all(|(i, &v)| v == 100 + (i % 7) as u8));
}

#[test]
fn the_median_is_each_pixel_s_middle_value_to_the_byte() {
    // Every count of frames from 1 to 9 and a look's largest (300), odd and even, on
    // runs of pixels longer and shorter than the median's own (1024): noise over the
    // whole byte range with its ends, and a few grey levels repeated many times.
    let mut rng = crate::rng::Rng::new(5);
    for (n, pixels) in [
        (1, 7),
        (2, 1500),
        (3, 1024),
        (4, 1025),
        (5, 3000),
        (6, 9),
        (7, 2100),
        (8, 300),
        (9, 2049),
        (300, 1030),
    ] {
        for kind in 0..2 {
            let data: Vec<Vec<u8>> = (0..n)
                .map(|_| {
                    (0..pixels)
                        .map(|_| match kind {
                            0 => [0, 255, (256.0 * rng.uniform()) as u8]
                                [(3.0 * rng.uniform()) as usize % 3],
                            _ => 100 + (4.0 * rng.uniform()) as u8,
                        })
                        .collect()
                })
                .collect();
            let expected: Vec<u8> = (0..pixels)
                .map(|i| {
                    let mut v: Vec<u8> = data.iter().map(|d| d[i]).collect();
                    v.sort_unstable();
                    v[n / 2]
                })
                .collect();
            let init = InitFrames {
                w: pixels,
                h: 1,
                shrink: 1.0,
                x0: 0.0,
                y0: 0.0,
                data,
            };
            assert!(
                median_frame(&init) == expected,
                "{n} frames of {pixels} px, kind {kind}"
            );
        }
    }
}

/// A look frame of `w` x `h` px shrunk `s` times from the crop at (`x0`, `y0`).
fn look_frame(w: usize, h: usize, s: f64, x0: f64, y0: f64) -> InitFrames {
    InitFrames {
        w,
        h,
        shrink: s,
        x0,
        y0,
        data: Vec::new(),
    }
}

#[test]
fn a_line_along_the_frames_edge_is_told_from_one_that_crosses_it() {
    // A 1920x1080 video seen whole at a third: the margin is 1 % of 1080 px, 3.6 px of
    // the look's 640x360.
    let e = FrameEdges::of(&look_frame(640, 360, 3.0, 0.0, 0.0), 1920, 1080);
    assert!((e.margin - 3.6).abs() < 1e-9);
    let p = Pt::new;
    // Along the top, the left, the right and the bottom edge.
    assert!(e.along(p(0.0, 1.0), p(600.0, 3.5)));
    assert!(e.along(p(2.0, 10.0), p(0.5, 300.0)));
    assert!(e.along(p(636.0, 10.0), p(639.0, 300.0)));
    assert!(e.along(p(10.0, 358.0), p(500.0, 356.0)));
    // A wire that crosses the top edge, one end 4 px in, and a line 5 px below it.
    assert!(!e.along(p(300.0, 0.0), p(320.0, 200.0)));
    assert!(!e.along(p(0.0, 1.0), p(600.0, 4.0)));
    assert!(!e.along(p(0.0, 5.0), p(600.0, 5.0)));
    // A region cut from the frame's middle shares no edge; one at its top-left corner
    // the top and the left (a small video: the least margin, 2 px).
    let mid = FrameEdges::of(&look_frame(200, 100, 1.0, 300.0, 200.0), 1920, 1080);
    assert!(!mid.along(p(0.0, 1.0), p(199.0, 1.0)));
    let corner = FrameEdges::of(&look_frame(100, 100, 1.0, 0.0, 0.0), 160, 120);
    assert_eq!(corner.shared, [true, true, false, false]);
    assert_eq!(corner.margin, EDGE_MIN_PX);
    assert!(corner.along(p(0.0, 1.9), p(99.0, 0.0)));
    assert!(!corner.along(p(0.0, 98.0), p(99.0, 99.0)));
}

#[test]
fn a_frames_lines_leave_out_one_along_its_edge() {
    // The look's evidence of one frame: an empty border moving along the top edge (a
    // row 1 px in, the longest line) and a wire crossing the frame from the top.
    let (w, h) = (200usize, 120usize);
    let mut img = vec![0u8; w * h];
    for x in 0..w {
        img[w + x] = 200;
    }
    for y in 0..100 {
        img[y * w + 60 + y / 10] = 200;
    }
    let ev = Mat::new_rows_cols_with_data(h as i32, w as i32, &img)
        .unwrap()
        .try_clone()
        .unwrap();
    let all_edges = FrameEdges::of(&look_frame(w, h, 1.0, 0.0, 0.0), 200, 120);
    let no_edges = FrameEdges::of(&look_frame(w, h, 1.0, 50.0, 50.0), 400, 300);
    let slope = |l: &FrameLine| (l.line.dir.y / l.line.dir.x).abs();
    // Seen as a region inside a larger frame, the row is a line (the longest, first);
    // at the frame's edge, only the wire is.
    let inside = frame_lines(&ev, &ev, 24.0, &no_edges).unwrap();
    assert!(
        inside.len() == 2 && slope(&inside[0]) < 0.01,
        "{}",
        inside.len()
    );
    let at_edge = frame_lines(&ev, &ev, 24.0, &all_edges).unwrap();
    assert_eq!(at_edge.len(), 1);
    assert!(slope(&at_edge[0]) > 5.0);
}
