//! The lens's coefficient from the wire itself: a taut wire is straight on the plate,
//! and through a wide lens every stretch of it off the frame's centre is seen bowed.
//! Each frame's strip gives the middle's offset from the chord between its ends
//! ([`Bowed`]); the lens predicts that offset for the same chord (`k1` times
//! [`Lens::bow`]); the `k1` that best explains the frames' bows
//! is the lens the wire was filmed through, whether or not one was given with the
//! video. The wire sweeps across the picture as it swings, so its bow changes from
//! frame to frame as the lens's does: a bend of the wire's own, which turns with it,
//! or a shadow beside it bows every frame alike.

use super::Lens;

/// One frame's stretch of wire as seen (full-frame px).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bowed {
    /// The stretch's ends, along its fitted straight line.
    pub ends: [[f64; 2]; 2],
    /// How far its middle lies from the chord between its ends, px, positive to the
    /// left of the direction from the first end to the second (x right, y down: the
    /// side `(dy, -dx)` points to).
    pub mid_px: f64,
    /// The share of a true offset the measurement shows: a strip narrower than the
    /// wire's profile cuts its flanks, and its centroid follows a shift only partly.
    pub response: f64,
}

impl Bowed {
    /// Whether its offset, ends and response are finite, and the strip follows at least
    /// `min_response` of an offset: a bow a fit can use.
    pub fn usable(&self, min_response: f64) -> bool {
        self.mid_px.is_finite()
            && self.response >= min_response
            && self.ends.iter().flatten().all(|x| x.is_finite())
    }
}

/// The coefficient the wire's bows give, and its standard uncertainty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WireK1 {
    pub k1: f64,
    pub u_k1: f64,
    /// Frames it was fitted to.
    pub frames: usize,
}

/// Contiguous blocks the frames are cut into for the jackknife (a bow's noise follows
/// the swing: a rolling shutter bends a moving wire, a codec smears it).
const JACKKNIFE_BLOCKS: usize = 10;
/// Fewest frames to fit.
const MIN_FRAMES: usize = 100;

impl Lens {
    /// The offset of the middle of a line straight on the plate, seen through this lens
    /// from `ends` to `ends` (image px), from the chord between them (as
    /// [`Bowed::mid_px`]): the ends taken back through the lens, the plate's point
    /// half-way between them seen through it.
    pub fn bow(&self, ends: [[f64; 2]; 2]) -> f64 {
        let [p, q] = ends.map(|e| self.undistort(e));
        let m = self.distort([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
        mid_offset(ends[0], ends[1], m)
    }
}

/// How far `m` lies from the chord `a`-`b`, positive to its left ([`Bowed::mid_px`]).
pub fn mid_offset(a: [f64; 2], b: [f64; 2], m: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let n = dx.hypot(dy);
    ((m[0] - a[0]) * dy - (m[1] - a[1]) * dx) / n
}

/// Gauss-Newton steps of [`k1_from_bows`] (the bow grows faster than `k1` near the
/// frame's edge: a wire across the edge of a 1280x720 frame bent by -0.24 reads -0.277
/// to first order) ...
const STEPS: usize = 8;
/// ... the last of which moves `k1` by less than this (a fit that has not settled says
/// nothing) ...
const SETTLED: f64 = 1e-4;
/// ... to a coefficient within this of zero (the lens model's reach: a phone's wide
/// lens bends to about -0.3).
const K1_REACH: f64 = 0.6;
/// Frames whose strip follows less of a shift than this ([`Bowed::response`]: a wire
/// much wider than its strip) are left out.
const MIN_RESPONSE: f64 = 0.2;

/// The `k1` of a lens on a `w` x `h` frame that explains the bows `seen` (in the order
/// filmed), with an offset of the wire's own (a bend, a shadow's pull: the same in every
/// frame), by least squares: each frame's predicted offset is [`Lens::bow`] of its ends
/// times its response. Its uncertainty is the jackknife over [`JACKKNIFE_BLOCKS`] even
/// runs of frames (each run left out, one Gauss-Newton step from the fit). `None` with
/// fewer than [`MIN_FRAMES`] frames, none the lens would bow, or a fit that does not
/// settle.
pub fn k1_from_bows(seen: &[Bowed], w: u32, h: u32) -> Option<WireK1> {
    let seen: Vec<&Bowed> = seen.iter().filter(|b| b.usable(MIN_RESPONSE)).collect();
    let n = seen.len();
    if n < MIN_FRAMES {
        return None;
    }
    const DK: f64 = 1e-4;
    // Each frame's residual and its derivative in k1, at `k1` (a frame the lens cannot
    // take back, none).
    let at = |k1: f64| -> Vec<(f64, f64)> {
        let (l, h) = (Lens::new(k1, 0.0, w, h), Lens::new(k1 + DK, 0.0, w, h));
        seen.iter()
            .map(|b| {
                let (p, q) = (l.bow(b.ends), h.bow(b.ends));
                let r = (b.mid_px - b.response * p, b.response * (q - p) / DK);
                if r.0.is_finite() && r.1.is_finite() {
                    r
                } else {
                    (0.0, 0.0)
                }
            })
            .collect()
    };
    // The normal equations of the offset and the step in k1, the residuals taken less
    // the offset `a`.
    let sums = |p: &[(f64, f64)], a: f64| {
        p.iter().fold([0.0; 5], |s, (r, d)| {
            let r = r - a;
            [s[0] + 1.0, s[1] + d, s[2] + d * d, s[3] + r, s[4] + r * d]
        })
    };
    let step = |s: [f64; 5]| -> Option<(f64, f64)> {
        let det = s[0] * s[2] - s[1] * s[1];
        (det > 1e-12 * s[0] * s[2]).then(|| {
            (
                (s[2] * s[3] - s[1] * s[4]) / det,
                (s[0] * s[4] - s[1] * s[3]) / det,
            )
        })
    };
    let (mut a, mut k1) = (0.0, 0.0);
    let mut last = at(k1);
    let mut moved = f64::INFINITY;
    for _ in 0..STEPS {
        let (da, dk) = step(sums(&last, a))?;
        a += da;
        k1 += dk;
        moved = dk.abs();
        if !k1.is_finite() || k1.abs() >= K1_REACH {
            return None;
        }
        last = at(k1);
    }
    if moved > SETTLED {
        return None;
    }
    let all = sums(&last, a);
    let blocks = JACKKNIFE_BLOCKS;
    let leave_out: Vec<f64> = (0..blocks)
        .map(|i| {
            let s = sums(&last[i * n / blocks..(i + 1) * n / blocks], a);
            let rest: [f64; 5] = std::array::from_fn(|j| all[j] - s[j]);
            step(rest).map(|(_, dk)| k1 + dk)
        })
        .collect::<Option<_>>()?;
    Some(WireK1 {
        k1,
        u_k1: crate::numerics::jackknife_u(&leave_out),
        frames: n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wire from a pivot swinging across a frame seen through `lens`: each frame's
    /// stretch from `r0` to `r1` px, its middle's offset from its chord as seen.
    fn swinging(lens: &Lens, pivot: [f64; 2], rest: f64, r: [f64; 2], n: usize) -> Vec<Bowed> {
        (0..n)
            .map(|i| {
                let a = rest + 0.3 * (i as f64 * 0.1).sin();
                let at = |r: f64| lens.distort([pivot[0] + r * a.cos(), pivot[1] + r * a.sin()]);
                let (p, q, m) = (at(r[0]), at(r[1]), at(0.5 * (r[0] + r[1])));
                Bowed {
                    ends: [p, q],
                    mid_px: mid_offset(p, q, m),
                    response: 1.0,
                }
            })
            .collect()
    }

    #[test]
    fn a_chord_through_the_centre_does_not_bow_and_one_beside_it_does_by_hand() {
        let lens = Lens::new(1e-3, 0.0, 1280, 720);
        // Along the centre line: a straight line stays straight.
        assert!(lens.bow([[100.0, 359.5], [1100.0, 359.5]]).abs() < 1e-9);
        // A horizontal chord 300 px above the centre, from x 140 to 1140. By hand: a
        // lens of a small k1 moves a point at r (frame widths from the centre) by
        // k1 r^2 of its distance from the centre (the zoom scales every point alike,
        // which keeps a line straight). The ends, at r^2 = (500^2 + 300^2) / 1280^2 =
        // 0.2075, move up by 300 * 0.2075 k1, the middle, at (300 / 1280)^2 = 0.0549,
        // by 300 * 0.0549 k1: the middle lies 300 * (0.2075 - 0.0549) = 45.8 k1 px
        // below the chord, to its right going +x.
        let g = lens.bow([[140.0, 59.5], [1140.0, 59.5]]) / 1e-3;
        assert!((g + 45.8).abs() < 1.0, "{g}");
    }

    #[test]
    fn the_bows_of_a_swinging_wire_give_back_the_lens() {
        for (k1, pivot, rest) in [
            (-0.24, [1320.0, 300.0], std::f64::consts::PI),
            (-0.17, [270.0, -30.0], 1.6),
            (0.0, [640.0, 0.0], 1.2),
        ] {
            let lens = Lens::new(k1, 0.0, 1280, 720);
            let seen = swinging(&lens, pivot, rest, [80.0, 400.0], 400);
            let fit = k1_from_bows(&seen, 1280, 720).expect("a fit");
            assert!(
                (fit.k1 - k1).abs() < 0.01 * k1.abs() + 1e-4,
                "{k1}: {fit:?}"
            );
            assert_eq!(fit.frames, 400);
        }
    }

    #[test]
    fn a_bend_of_the_wire_s_own_is_not_a_lens_and_too_few_frames_give_none() {
        // No lens; every frame's strip bows 0.3 px to its left (a shadow's pull, which
        // turns with the wire): the offset takes it, and k1 is 0.
        let lens = Lens::new(0.0, 0.0, 640, 480);
        let mut seen = swinging(&lens, [320.0, 0.0], 1.57, [50.0, 400.0], 300);
        for b in &mut seen {
            b.mid_px += 0.3;
        }
        let fit = k1_from_bows(&seen, 640, 480).expect("a fit");
        assert!(fit.k1.abs() < 1e-6, "{fit:?}");
        assert!(k1_from_bows(&seen[..99], 640, 480).is_none());
        // A strip that follows too little of a shift says nothing.
        for b in &mut seen {
            b.response = 0.1;
        }
        assert!(k1_from_bows(&seen, 640, 480).is_none());
    }
}
