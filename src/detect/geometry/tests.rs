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
