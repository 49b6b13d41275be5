//! A lens's radial distortion (`video.lens`, and the twin's `synthetic.lens_k1`): the
//! one-coefficient model, angles about the pivot measured through it, and what its
//! coefficient's uncertainty puts on the swing's scale. Its coefficient is fitted from
//! a picture's straight lines ([`plumb`], `rollfric lens`) or read from the wire's own
//! bow ([`bow`], the detection's `bent` check).
//!
//! A point at distance `r` from the frame's centre in the undistorted view, in frame
//! widths (a lens of one width's focal length), is seen at `z r (1 + k1 r^2)`, where the
//! zoom `z = 1 / (1 + k1 r_c^2)` keeps the frame's corners (at `r_c`) where they are, as
//! a phone crops its wide lens's picture to fill the frame. `k1 < 0` is barrel
//! distortion (a phone's wide lens, to about -0.3), `k1 > 0` pincushion.

pub mod bow;
pub mod plumb;

use serde::{Deserialize, Serialize};

/// The radial distortion of a `w` x `h` px frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lens {
    pub k1: f64,
    /// Standard uncertainty of `k1`.
    pub u_k1: f64,
    zoom: f64,
    centre: [f64; 2],
    w: f64,
}

/// A detection's angles as measured through a lens: the lens and the radii of the
/// wire's visible band (px from the pivot), as the build caches them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeenThrough {
    pub lens: Lens,
    pub band_px: [f64; 2],
}

/// The standard uncertainty of `k1` for a wide lens that could not be calibrated
/// (`video.lens: {k1: 0, u_k1: 0.15}`): a phone's wide lens bends to about -0.3, two
/// such uncertainties. The angles are then taken as seen, and the `scale` checks say
/// whether the unknown distortion matters where the wire is.
pub const UNKNOWN_U_K1: f64 = 0.15;

/// Radii of a wire's visible band at which [`Lens::plate_angle`] reads the wire.
const BAND_STEPS: usize = 16;

impl Lens {
    pub fn new(k1: f64, u_k1: f64, w: u32, h: u32) -> Self {
        let (wf, hf) = (f64::from(w), f64::from(h));
        let centre = [(wf - 1.0) / 2.0, (hf - 1.0) / 2.0];
        let corner2 = (centre[0] * centre[0] + centre[1] * centre[1]) / (wf * wf);
        Self {
            k1,
            u_k1,
            zoom: 1.0 / (1.0 + k1 * corner2),
            centre,
            w: wf,
        }
    }

    /// The same lens with another coefficient.
    fn with_k1(&self, k1: f64) -> Self {
        let h = 2.0 * self.centre[1] + 1.0;
        Self::new(k1, self.u_k1, self.w as u32, h as u32)
    }

    /// Where the undistorted view's point `p` is seen, px.
    pub fn distort(&self, p: [f64; 2]) -> [f64; 2] {
        let (dx, dy) = (p[0] - self.centre[0], p[1] - self.centre[1]);
        let r2 = (dx * dx + dy * dy) / (self.w * self.w);
        let k = self.zoom * (1.0 + self.k1 * r2);
        [self.centre[0] + k * dx, self.centre[1] + k * dy]
    }

    /// The undistorted view's point seen at `p`, px (Newton's method on the radius).
    pub fn undistort(&self, p: [f64; 2]) -> [f64; 2] {
        let (dx, dy) = (p[0] - self.centre[0], p[1] - self.centre[1]);
        let rho = dx.hypot(dy) / self.w;
        if rho < 1e-12 {
            return p;
        }
        let target = rho / self.zoom;
        let r = self.radius(target, target, None);
        let k = r / rho;
        [self.centre[0] + k * dx, self.centre[1] + k * dy]
    }

    /// The undistorted radius (frame widths) seen at `target` / zoom: at most eight of
    /// Newton's steps from `r`, and fewer once a step moves it by less than `stop`.
    fn radius(&self, target: f64, mut r: f64, stop: Option<f64>) -> f64 {
        for _ in 0..8 {
            let f = r * (1.0 + self.k1 * r * r) - target;
            let df = 1.0 + 3.0 * self.k1 * r * r;
            if df.abs() < 1e-9 {
                break;
            }
            let step = f / df;
            r -= step;
            if stop.is_some_and(|s| step.abs() < s) {
                break;
            }
        }
        r
    }

    /// [`Self::undistort`] by Newton's method started from `guess`, the ratio of the
    /// undistorted radius to the seen one at a point near `p` (`None`: the seen radius
    /// itself, as `undistort` starts), and stopped once a step moves the radius by less
    /// than 1e-14 of a frame width: the undistorted point and its ratio, for the next.
    /// Along a strip of pixels each starts from its neighbour's, and two or three steps
    /// do what eight from the seen radius do.
    pub fn undistort_from(&self, p: [f64; 2], guess: Option<f64>) -> ([f64; 2], f64) {
        let (dx, dy) = (p[0] - self.centre[0], p[1] - self.centre[1]);
        let rho = dx.hypot(dy) / self.w;
        if rho < 1e-12 {
            return (p, 1.0);
        }
        let target = rho / self.zoom;
        let r = self.radius(target, guess.map_or(target, |k| k * rho), Some(1e-14));
        let k = r / rho;
        ([self.centre[0] + k * dx, self.centre[1] + k * dy], k)
    }

    /// The undistorted angle of a wire seen at image angle `theta` through the image
    /// point `pivot`, read over the radii `band` (px) where the detector saw it, rad:
    /// the points of the seen line at those radii, undistorted, and their directions
    /// from the undistorted pivot averaged with weights `r^2`, as a line fitted
    /// through the pivot weighs its pixels. A straight wire seen through the lens is
    /// a slight curve: the line the detector fits through the pivot follows its
    /// chords, and the error of taking it for straight is of the curve's order squared.
    pub fn plate_angle(&self, pivot: [f64; 2], theta: f64, band: [f64; 2]) -> f64 {
        let q = self.undistort(pivot);
        let (c, s) = (theta.cos(), theta.sin());
        let (mut sw, mut sa) = (0.0, 0.0);
        for k in 0..BAND_STEPS {
            let r = band[0] + (band[1] - band[0]) * (k as f64 + 0.5) / BAND_STEPS as f64;
            let p = self.undistort([pivot[0] + r * c, pivot[1] + r * s]);
            let a = (p[1] - q[1]).atan2(p[0] - q[0]);
            // Near theta: no branch cut inside the sum.
            let a = theta + (a - theta + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            let w = r * r;
            sw += w;
            sa += w * a;
        }
        sa / sw
    }

    /// Image angles about `pivot` as undistorted angles, each kept near its own image
    /// angle (missing ones stay missing).
    pub fn plate_angles(
        &self,
        pivot: [f64; 2],
        band: [f64; 2],
        image: &[Option<f64>],
    ) -> Vec<Option<f64>> {
        image
            .iter()
            .map(|a| a.map(|a| self.plate_angle(pivot, a, band)))
            .collect()
    }

    /// The relative standard uncertainty `u_k1` puts on the swing's scale: the
    /// undistorted swing between the image angles `rest - amp` and `rest + amp` about
    /// `pivot`, its derivative in `k1` (central differences) times `u_k1`, over the
    /// swing.
    pub fn scale_u_rel(&self, pivot: [f64; 2], rest: f64, amp: f64, band: [f64; 2]) -> f64 {
        if self.u_k1 <= 0.0 || amp <= 0.0 {
            return 0.0;
        }
        let swing = |l: &Lens| {
            l.plate_angle(pivot, rest + amp, band) - l.plate_angle(pivot, rest - amp, band)
        };
        let h = 1e-3;
        let (lo, hi) = (self.with_k1(self.k1 - h), self.with_k1(self.k1 + h));
        let d = (swing(&hi) - swing(&lo)) / (2.0 * h);
        (d * self.u_k1 / swing(self)).abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn the_lens_keeps_the_centre_and_corners_and_undoes_itself() {
        let lens = Lens::new(-0.3, 0.0, 960, 540);
        let c = [479.5, 269.5];
        assert_eq!(lens.distort(c), c);
        let corner = lens.distort([0.0, 0.0]);
        assert!(
            corner[0].abs() < 1e-9 && corner[1].abs() < 1e-9,
            "{corner:?}"
        );
        // Barrel: a point half-way out is pushed outwards (a magnified centre).
        let mid = lens.distort([c[0] + 200.0, c[1]]);
        assert!(mid[0] > c[0] + 200.0, "{mid:?}");
        for p in [[10.0, 20.0], [700.0, 400.0], [480.0, 100.0]] {
            let q = lens.undistort(lens.distort(p));
            assert!((q[0] - p[0]).abs() < 1e-6 && (q[1] - p[1]).abs() < 1e-6);
        }
    }

    #[test]
    fn undistorting_from_a_neighbours_ratio_gives_the_same_point() {
        // Along a strip of pixels near the frame's edge, each started from the one
        // before's ratio, or from nothing: the point `undistort` gives.
        let lens = Lens::new(-0.24, 0.0, 1280, 720);
        let mut guess = None;
        for i in 0..300 {
            let p = [1260.0 - i as f64, 300.0 + 0.1 * i as f64];
            let (q, k) = lens.undistort_from(p, guess);
            let want = lens.undistort(p);
            assert!(
                (q[0] - want[0]).abs() < 1e-9 && (q[1] - want[1]).abs() < 1e-9,
                "{p:?}: {q:?} against {want:?}"
            );
            guess = Some(k);
        }
        assert_eq!(lens.undistort_from([639.5, 359.5], None).0, [639.5, 359.5]);
    }

    #[test]
    fn a_wire_seen_through_the_lens_is_measured_at_its_own_angle() {
        // A straight wire from a pivot near the frame's left edge, seen through a
        // barrel lens: its image is a curve; the line through the pivot fitted to it
        // (here: the r^2-weighted mean direction of its points, as the detector's fit
        // weighs them), taken back through the lens, is the wire's own angle.
        let lens = Lens::new(-0.24, 0.02, 1280, 720);
        let pivot = [40.0, 300.0];
        let band = [60.0, 420.0];
        for true_deg in [-10.0f64, 0.0, 8.0, 25.0] {
            let t = true_deg.to_radians();
            let seen_pivot = lens.distort(pivot);
            // The wire's points as seen, and the line through the seen pivot the
            // detector would fit to them.
            let (mut sw, mut sa) = (0.0, 0.0);
            for k in 0..200 {
                let r = 20.0 + 480.0 * k as f64 / 199.0;
                let p = lens.distort([pivot[0] + r * t.cos(), pivot[1] + r * t.sin()]);
                let (dx, dy) = (p[0] - seen_pivot[0], p[1] - seen_pivot[1]);
                let rr = dx.hypot(dy);
                if rr < band[0] || rr > band[1] {
                    continue;
                }
                sw += rr * rr;
                sa += rr * rr * dy.atan2(dx);
            }
            let seen = sa / sw;
            let back = lens.plate_angle(seen_pivot, seen, band);
            // Uncorrected, the lens turns this wire by up to a degree or more.
            assert!(
                (back - t).abs() < 0.02_f64.to_radians(),
                "{true_deg}: {} vs {}",
                back.to_degrees(),
                seen.to_degrees()
            );
        }
        // Its coefficient's uncertainty puts a share on the swing's scale.
        let u = lens.scale_u_rel(lens.distort(pivot), 0.0, 0.17, band);
        assert!(u > 1e-4 && u < 0.05, "{u}");
        // On the frame's centre line through the centre, nothing turns.
        let centred = Lens::new(-0.3, 0.0, 960, 540);
        let a = centred.plate_angle([479.5, 100.0], FRAC_PI_2, [50.0, 300.0]);
        assert!((a - FRAC_PI_2).abs() < 1e-12);
    }
}
