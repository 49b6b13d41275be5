//! Repeated frames found after the pass, from both sides.

use super::{AngleRow, Flag};

/// A repeated frame, found once every angle is known: the same picture measures the
/// same, so its angle equals the previous frame's (to the codec's loss) where its
/// neighbours on both sides say the wire moved on by several times the measurement
/// noise. (While streaming, only the previous frames predict, three times less
/// precisely; a repeat near a turning point, where the wire hardly moves, hides there.)
pub(super) fn flag_repeats(rows: &mut [AngleRow]) {
    // Frames the gate turned away count as neighbours: after a repeat has entered the
    // history, the prediction lags and the gate refuses the next few good frames.
    let good = |r: &AngleRow| {
        matches!(r.flag, None | Some(Flag::Gate))
            .then_some(r.angle_rad)
            .flatten()
    };
    // For frame i with good frames i-2..=i+2: the angle the neighbours predict (cubic
    // through i-2, i-1, i+1, i+2 in time) and the previous frame's.
    let mut cases: Vec<(usize, f64, f64)> = Vec::new();
    for i in 2..rows.len().saturating_sub(2) {
        let pts: Option<Vec<(f64, f64)>> = [i - 2, i - 1, i + 1, i + 2]
            .iter()
            .map(|&j| good(&rows[j]).map(|a| (rows[j].t_s, a)))
            .collect();
        let (Some(pts), Some(a)) = (pts, good(&rows[i])) else {
            continue;
        };
        let t = rows[i].t_s;
        let predicted: f64 = (0..4)
            .map(|k| {
                let l: f64 = (0..4)
                    .filter(|&m| m != k)
                    .map(|m| (t - pts[m].0) / (pts[k].0 - pts[m].0))
                    .product();
                l * pts[k].1
            })
            .sum();
        cases.push((i, a - predicted, predicted - pts[1].1));
    }
    if cases.len() < 20 {
        return;
    }
    // The measurement noise (robust: median absolute residual; never zero, or exact
    // data would make every step significant).
    let mut res: Vec<f64> = cases.iter().map(|c| c.1.abs()).collect();
    let sigma = (1.4826 * crate::numerics::upper_median(&mut res)).max(1e-7);
    // A wild frame (a glint taken for the wire) pulls the cubic of the frames beside
    // it: only the frame that disagrees most with its neighbours within two frames
    // may be a repeat.
    let mut misfit = vec![0.0f64; rows.len()];
    for &(i, resid, _) in &cases {
        misfit[i] = resid.abs();
    }
    for (i, resid, step) in cases {
        let worst_nearby = misfit[i - 2..=i + 2].iter().all(|&m| m <= resid.abs());
        // The frame disagrees with its neighbours and lies nearer the previous frame's
        // angle than theirs, where they expect a step from the previous frame well
        // above the noise.
        let moved = (resid + step).abs();
        if rows[i].flag.is_none()
            && worst_nearby
            && step.abs() > 4.0 * sigma
            && resid.abs() > 3.0 * sigma
            && moved < resid.abs()
        {
            rows[i].flag = Some(Flag::Duplicate);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::Status;

    /// 60 frames/s of a 1 s period swing of 0.2 rad, with 0.0002 rad of noise (a
    /// fixed pseudo-random sequence).
    fn swing_rows() -> Vec<AngleRow> {
        let noise = |i: usize| 2e-4 * (((i * 7919) % 101) as f64 / 50.0 - 1.0);
        let angle = |t: f64| 1.5 + 0.2 * (std::f64::consts::TAU * t).sin();
        (0..240)
            .map(|i| {
                let t = i as f64 / 60.0;
                AngleRow {
                    frame: i as u64,
                    t_s: t,
                    angle_rad: Some(angle(t) + noise(i)),
                    status: Status::Ok,
                    quality: 1.0,
                    flag: None,
                    moments: None,
                }
            })
            .collect()
    }

    fn flagged(rows: &[AngleRow]) -> Vec<(u64, Flag)> {
        rows.iter()
            .filter_map(|r| r.flag.map(|f| (r.frame, f)))
            .collect()
    }

    #[test]
    fn a_repeated_frame_is_flagged_and_a_turning_point_is_not() {
        // Frame 100 repeats frame 99's picture (and so its measurement, up to a little
        // codec noise). There the wire turns at 0.63 rad/s: frame 100 lags by 0.010
        // rad, 50 times the noise.
        let mut rows = swing_rows();
        rows[100].angle_rad = Some(rows[99].angle_rad.unwrap() + 5e-5);
        flag_repeats(&mut rows);
        assert_eq!(flagged(&rows), vec![(100, Flag::Duplicate)]);
        // A repeat at a turning point (t = 0.25 s, frame 15) moves nothing that the
        // noise does not: it is left alone, and so is every true turning point.
        let mut rows = swing_rows();
        rows[15].angle_rad = rows[14].angle_rad;
        flag_repeats(&mut rows);
        assert_eq!(flagged(&rows), vec![]);
    }

    #[test]
    fn a_wild_frame_does_not_make_its_neighbours_repeats() {
        // Frames the gate refused, 0.02 rad off, at a turning point and mid-swing:
        // they pull their neighbours' cubics, but stay what the gate called them.
        let mut rows = swing_rows();
        for i in [15, 45, 100] {
            rows[i].angle_rad = Some(rows[i].angle_rad.unwrap() + 0.02);
            rows[i].flag = Some(Flag::Gate);
        }
        flag_repeats(&mut rows);
        assert_eq!(
            flagged(&rows),
            vec![(15, Flag::Gate), (45, Flag::Gate), (100, Flag::Gate)]
        );
    }
}
