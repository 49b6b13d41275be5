//! The camera's motion measured on textured frames moved by hand-set motions.

use super::*;

/// A textured frame (a smooth random pattern) seen under motion `m`.
fn textured(w: usize, h: usize, m: Motion, index: u64) -> Frame {
    // Value noise: random levels on a 6 px lattice, bilinearly joined, plus a few
    // sharp lines (a scene's edges).
    let lattice = |i: i64, j: i64| {
        let mut z = (i.wrapping_mul(73_856_093) ^ j.wrapping_mul(19_349_663)) as u64;
        z = z.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        ((z >> 40) % 200) as f64
    };
    let f = |x: f64, y: f64| {
        let (u, v) = (x / 6.0, y / 6.0);
        let (i, j) = (u.floor(), v.floor());
        let (a, b) = (u - i, v - j);
        let (i, j) = (i as i64, j as i64);
        let n = lattice(i, j) * (1.0 - a) * (1.0 - b)
            + lattice(i + 1, j) * a * (1.0 - b)
            + lattice(i, j + 1) * (1.0 - a) * b
            + lattice(i + 1, j + 1) * a * b;
        (28.0 + n).clamp(0.0, 255.0) as u8
    };
    // Pixel q of this frame shows the first frame's p with q = c + R (p - c) + t.
    let (c, s) = (m.rot_rad.cos(), m.rot_rad.sin());
    let (cx, cy) = (0.5 * (w as f64 - 1.0), 0.5 * (h as f64 - 1.0));
    let mut data = vec![0u8; w * h];
    for y in 0..h {
        for x in 0..w {
            let (qx, qy) = (x as f64 - cx - m.dx, y as f64 - cy - m.dy);
            let px = c * qx + s * qy + cx;
            let py = -s * qx + c * qy + cy;
            data[y * w + x] = f(px, py);
        }
    }
    Frame {
        index,
        t_s: index as f64 / 30.0,
        width: w,
        height: h,
        data,
    }
}

#[test]
fn a_shift_and_a_turn_are_measured_and_undone() {
    let (w, h) = (640, 360);
    let first = textured(w, h, Motion::default(), 0);
    let mut s = Steady::new(&first).unwrap();
    let still = s.measure(&first).unwrap().unwrap();
    assert!(still.reach(w as f64, h as f64) < 0.02, "{still:?}");
    let m = Motion {
        dx: 2.6,
        dy: -1.3,
        rot_rad: 0.4f64.to_radians(),
    };
    let mut moved = textured(w, h, m, 1);
    let got = s.measure(&moved).unwrap().unwrap();
    assert!((got.dx - m.dx).abs() < 0.08, "{got:?}");
    assert!((got.dy - m.dy).abs() < 0.08, "{got:?}");
    assert!(
        (got.rot_rad - m.rot_rad).abs() < 0.02f64.to_radians(),
        "{got:?}"
    );
    s.undo(&mut moved, got).unwrap();
    // Back onto the first frame, away from the borders the warp had to invent.
    let mut err = 0.0;
    let mut n = 0.0;
    for y in 40..h - 40 {
        for x in 40..w - 40 {
            err += (f64::from(moved.data[y * w + x]) - f64::from(first.data[y * w + x])).abs();
            n += 1.0;
        }
    }
    assert!(err / n < 2.0, "mean difference {}", err / n);
}

#[test]
fn a_plain_frame_has_no_motion_to_measure() {
    let f = Frame {
        index: 0,
        t_s: 0.0,
        width: 320,
        height: 240,
        data: vec![120; 320 * 240],
    };
    let mut s = Steady::new(&f).unwrap();
    assert_eq!(s.measure(&f).unwrap(), None);
}
