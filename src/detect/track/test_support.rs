//! Trackers over regions drawn in memory, for the tests that step one through frames.

use super::*;

/// A tracker of a 320x240 region on a flat wall at 200 (the noise threshold 4 grey
/// levels everywhere), its wire dark and hung from (160, 20), seen from 30 to 190 px and
/// between `theta` rad: for tests that step it through frames drawn in memory.
pub(in crate::detect) fn test_tracker(theta: (f64, f64)) -> Tracker {
    let flat = Mat::new_rows_cols_with_default(240, 320, core::CV_8UC1, Scalar::all(200.0));
    test_tracker_over(flat.unwrap(), theta)
}

/// [`test_tracker`] with the first look's background `bg` (320x240).
pub(in crate::detect) fn test_tracker_over(bg: Mat, theta: (f64, f64)) -> Tracker {
    use opencv::core::CV_8UC1;
    let roi = Roi {
        x: 0,
        y: 0,
        w: 320,
        h: 240,
    };
    let geo = WireGeometry {
        pivot: Pt::new(160.0, 20.0),
        dark: true,
        r_lo: 30.0,
        r_hi: 190.0,
        theta_min: theta.0,
        theta_max: theta.1,
        roi,
        initial_angles: Vec::new(),
        lines_used: 20,
        jumps: 0,
        roughness: 0.0,
        stage: 0,
        second: None,
        rival: None,
    };
    let flat = |v: f64| Mat::new_rows_cols_with_default(240, 320, CV_8UC1, Scalar::all(v));
    Tracker::new(
        &geo,
        &DetectOptions::default(),
        bg,
        flat(4.0).unwrap(),
        flat(200.0).unwrap(),
        1.0,
        roi,
    )
    .unwrap()
}
