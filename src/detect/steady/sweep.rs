//! The part of the frame the pendulum sweeps, which the camera's alignment leaves out.

use crate::detect::tuning::{SWEEP_MARGIN_DEG, SWEEP_REACH};

/// The part of the frame the pendulum sweeps (its wire, ball and their shadows), which
/// the measurement does not read: it is not the static scene. Without it, a visible ball
/// near where the first frame has it pulls the alignment round the pivot after it (on a
/// hand-held twin, 2.4 deg within half a second). Frame px of the frame measured.
#[derive(Clone, Copy, Debug)]
pub(in crate::detect) struct Sweep {
    /// The pivot.
    centre: (f64, f64),
    /// The farthest reach from the pivot, px.
    reach: f64,
    /// The angles (image, from the x axis) swept, radians, `lo < hi`.
    lo: f64,
    hi: f64,
    /// The tests that pass over the distance and the angle where they are sure (see
    /// [`Sweep::holds`]).
    sure: Sure,
}

/// What [`Sweep::holds`] decides without a square root's rounding or an arc tangent:
/// the reach squared, with a relative slack of [`SURE_SLACK`] either way, and the
/// direction of the sweep's middle with the cosines of its half width widened and
/// narrowed by as much (radians; `None` where that passes a half turn or zero).
#[derive(Clone, Copy, Debug)]
struct Sure {
    beyond2: f64,
    within2: f64,
    mid: (f64, f64),
    outside_cos: Option<f64>,
    inside_cos: Option<f64>,
}

/// The slack of [`Sure`]: relative on the squared reach, radians on the angles; far
/// above the rounding of a sum of two squares, a product or an arc tangent.
const SURE_SLACK: f64 = 1e-6;

impl Sweep {
    /// The sweep of a wire seen out to `r_hi` px from `pivot` at angles `theta` (the
    /// least and the most, radians), widened for the ball at its end and the shadows
    /// beside it ([`SWEEP_REACH`], [`SWEEP_MARGIN_DEG`]); `origin` is the measured
    /// frame's corner in the same coordinates.
    pub(in crate::detect) fn around(
        pivot: (f64, f64),
        r_hi: f64,
        theta: (f64, f64),
        origin: (f64, f64),
    ) -> Self {
        let m = SWEEP_MARGIN_DEG.to_radians();
        let (reach, lo, hi) = (
            SWEEP_REACH * r_hi,
            theta.0.min(theta.1) - m,
            theta.0.max(theta.1) + m,
        );
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        let within_half_turn = |a: f64| (0.0..std::f64::consts::PI).contains(&a);
        Self {
            centre: (pivot.0 - origin.0, pivot.1 - origin.1),
            reach,
            lo,
            hi,
            sure: Sure {
                beyond2: reach * reach * (1.0 + SURE_SLACK),
                within2: reach * reach * (1.0 - SURE_SLACK),
                mid: (mid.cos(), mid.sin()),
                outside_cos: Some(half + SURE_SLACK)
                    .filter(|&a| within_half_turn(a))
                    .map(f64::cos),
                inside_cos: Some(half - SURE_SLACK)
                    .filter(|&a| within_half_turn(a))
                    .map(f64::cos),
            },
        }
    }

    /// Whether frame px `(x, y)` lies within: no further than the reach from the pivot,
    /// at an angle within the sweep. Where the squared distance, or the direction's
    /// cosine with the sweep's middle, lies beyond the slack of [`Sure`] either way,
    /// that decides; only a pixel near the edge is measured by its distance and angle
    /// themselves (the same answer; the first frame's scales of seed 1 scene 44, 194 to
    /// 108 M instructions).
    pub(super) fn holds(&self, x: f64, y: f64) -> bool {
        let (dx, dy) = (x - self.centre.0, y - self.centre.1);
        let d2 = dx * dx + dy * dy;
        let sure = &self.sure;
        if d2 > sure.beyond2 || (d2 >= sure.within2 && dx.hypot(dy) > self.reach) {
            return false;
        }
        let along = dx * sure.mid.0 + dy * sure.mid.1;
        let r = d2.sqrt();
        if sure.outside_cos.is_some_and(|c| along < r * c) {
            return false;
        }
        if sure.inside_cos.is_some_and(|c| along > r * c) {
            return true;
        }
        let mid = 0.5 * (self.lo + self.hi);
        let a = crate::detect::unwrap_near(dy.atan2(dx), mid);
        a >= self.lo && a <= self.hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sweep_holds_the_wedge_from_the_pivot_out_to_its_reach() {
        // Seen from 10 to 100 px at 80 to 100 deg, from a corner at (5, 5).
        let s = Sweep::around(
            (50.0, 20.0),
            100.0,
            (80f64.to_radians(), 100f64.to_radians()),
            (5.0, 5.0),
        );
        // The pivot at (45, 15) in the frame: straight down from it is within.
        assert!(s.holds(45.0, 15.0 + 120.0));
        // Beyond the reach (1.4 x 100 px).
        assert!(!s.holds(45.0, 15.0 + 150.0));
        // 110 deg is within the margin of 15 deg; 120 deg is not.
        let at = |deg: f64| {
            let a = deg.to_radians();
            (45.0 + 80.0 * a.cos(), 15.0 + 80.0 * a.sin())
        };
        assert!(s.holds(at(110.0).0, at(110.0).1));
        assert!(!s.holds(at(120.0).0, at(120.0).1));
        assert!(!s.holds(at(60.0).0, at(60.0).1));
    }

    #[test]
    fn a_sweep_holds_the_pixels_its_distance_and_angle_say() {
        // The sweep's own test against its distance and angle measured for every pixel:
        // sweeps hanging down, across -x (angles past pi), narrow and past a half turn,
        // and pixels on a grid through their edges, at the pivot and on its far side.
        let mut rng = crate::rng::Rng::new(23);
        for (lo, hi) in [
            (1.2, 1.9),
            (2.8, 3.6),
            (-0.3, 0.1),
            (0.5, 3.9),
            (-1.0, 5.0),
            (1.0, 1.0),
        ] {
            let s = Sweep::around((50.3, 40.7), 60.0, (lo, hi), (0.0, 0.0));
            let measured = |x: f64, y: f64| {
                let (dx, dy) = (x - s.centre.0, y - s.centre.1);
                if dx.hypot(dy) > s.reach {
                    return false;
                }
                let mid = 0.5 * (s.lo + s.hi);
                let a = crate::detect::unwrap_near(dy.atan2(dx), mid);
                a >= s.lo && a <= s.hi
            };
            let mut points: Vec<(f64, f64)> = (0..240)
                .flat_map(|y| (0..220).map(move |x| (x as f64 * 0.5 - 10.0, y as f64 * 0.5 - 10.0)))
                .collect();
            // Right on the edges: the reach's circle and the sweep's two sides.
            for _ in 0..5000 {
                let t = 2.0 * std::f64::consts::PI * rng.uniform();
                let r = s.reach * (1.0 + 1e-9 * (rng.uniform() - 0.5));
                points.push((s.centre.0 + r * t.cos(), s.centre.1 + r * t.sin()));
                let side =
                    if rng.uniform() < 0.5 { s.lo } else { s.hi } + 1e-9 * (rng.uniform() - 0.5);
                let r = s.reach * rng.uniform();
                points.push((s.centre.0 + r * side.cos(), s.centre.1 + r * side.sin()));
            }
            points.push(s.centre);
            let (mut inside, mut outside) = (0, 0);
            for (x, y) in points {
                let want = measured(x, y);
                assert_eq!(s.holds(x, y), want, "({x}, {y}) in the sweep {lo}..{hi}");
                if want {
                    inside += 1;
                } else {
                    outside += 1;
                }
            }
            assert!(
                inside > 100 && outside > 100,
                "{lo}..{hi}: {inside} in, {outside} out"
            );
        }
    }
}
