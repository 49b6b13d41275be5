//! The plate's plane as a camera sees it: plane-to-plane homographies, and the plate
//! calibration (`video.calibration`) that measures the wire's angle in the plate's own
//! plane rather than in the image.
//!
//! A camera tilted by `tau` from the plate's normal maps the plate onto the image by a
//! homography (a pinhole camera looking at a plane), which scales angles about a point
//! at the picture's centre by between `cos tau` and `1 / cos tau` depending on the
//! direction, and by more or less elsewhere (perspective). Four or
//! more image points with their plate coordinates (protractor marks, say) give that
//! homography back: the normalised direct linear transform (Hartley & Zisserman,
//! *Multiple View Geometry*, 2nd ed., Alg. 4.2). A straight line maps to a straight
//! line, so the wire's image direction at the pivot maps exactly to its plate
//! direction through the homography's derivative there.

use crate::rng::Rng;
use anyhow::{bail, ensure, Result};
use nalgebra::{DMatrix, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// A plane-to-plane projective map, `[x', y', w']^T = M [x, y, 1]^T`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Homography {
    pub m: Matrix3<f64>,
}

impl Homography {
    /// The identity map.
    pub fn identity() -> Self {
        Self {
            m: Matrix3::identity(),
        }
    }

    /// The image of point `p`.
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let v = self.m * Vector3::new(p[0], p[1], 1.0);
        [v[0] / v[2], v[1] / v[2]]
    }

    /// The inverse map (`None` when singular).
    pub fn inverse(&self) -> Option<Self> {
        self.m.try_inverse().map(|m| Self { m })
    }

    /// `self` after `first`: `p -> self(first(p))`.
    pub fn after(&self, first: &Self) -> Self {
        Self {
            m: self.m * first.m,
        }
    }

    /// The third homogeneous coordinate of `p`'s image: its sign tells the sides of the
    /// map's horizon apart.
    pub fn w(&self, p: [f64; 2]) -> f64 {
        self.m[(2, 0)] * p[0] + self.m[(2, 1)] * p[1] + self.m[(2, 2)]
    }

    /// The derivative of the map at `p` (2 x 2, row-major).
    pub fn jacobian(&self, p: [f64; 2]) -> [[f64; 2]; 2] {
        let m = &self.m;
        let w = self.w(p);
        let q = self.apply(p);
        let mut j = [[0.0; 2]; 2];
        for (r, row) in j.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = (m[(r, c)] - q[r] * m[(2, c)]) / w;
            }
        }
        j
    }

    /// The local area scale at `p`: `sqrt |det J|`.
    pub fn local_scale(&self, p: [f64; 2]) -> f64 {
        let j = self.jacobian(p);
        (j[0][0] * j[1][1] - j[0][1] * j[1][0]).abs().sqrt()
    }

    /// The direction (angle from the x axis, rad) into which the map takes the direction
    /// `theta` at point `p`: exact for a straight line through `p`.
    pub fn direction(&self, p: [f64; 2], theta: f64) -> f64 {
        let j = self.jacobian(p);
        let (c, s) = (theta.cos(), theta.sin());
        (j[1][0] * c + j[1][1] * s).atan2(j[0][0] * c + j[0][1] * s)
    }

    /// The homography taking each `from[i]` to `to[i]` (at least four pairs, no three of
    /// a minimal four on a line), least squares in the algebraic sense on normalised
    /// coordinates (the normalised DLT).
    pub fn fit(from: &[[f64; 2]], to: &[[f64; 2]]) -> Result<Self> {
        ensure!(
            from.len() == to.len(),
            "{} points against {}",
            from.len(),
            to.len()
        );
        let n = from.len();
        ensure!(n >= 4, "{n} points: a homography needs at least four");
        ensure!(
            from.iter()
                .chain(to)
                .all(|p| p[0].is_finite() && p[1].is_finite()),
            "a point is not finite"
        );
        let (ta, tb) = (normaliser(from)?, normaliser(to)?);
        // Two equations per pair; padded with zero rows to nine so that the SVD gives
        // all nine right singular vectors.
        let mut a = DMatrix::<f64>::zeros((2 * n).max(9), 9);
        for (i, (p, q)) in from.iter().zip(to).enumerate() {
            let [x, y] = ta.apply(*p);
            let [u, v] = tb.apply(*q);
            let r0 = [x, y, 1.0, 0.0, 0.0, 0.0, -u * x, -u * y, -u];
            let r1 = [0.0, 0.0, 0.0, x, y, 1.0, -v * x, -v * y, -v];
            for c in 0..9 {
                a[(2 * i, c)] = r0[c];
                a[(2 * i + 1, c)] = r1[c];
            }
        }
        let svd = a.svd(false, true);
        let vt = svd.v_t.expect("asked for V^T");
        let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
        order.sort_by(|&i, &j| svd.singular_values[i].total_cmp(&svd.singular_values[j]));
        let next = svd.singular_values[order[1]];
        let largest = svd.singular_values[order[order.len() - 1]];
        if next <= 1e-9 * largest {
            bail!(
                "the points do not fix a homography (three of them on a line, or points \
                 repeated)"
            );
        }
        if n == 4 {
            for pts in [from, to] {
                if let Some(t) = collinear_triple(pts) {
                    bail!(
                        "points {}, {} and {} of four lie on a line: add a point off that line \
                         (or a fifth point)",
                        t[0] + 1,
                        t[1] + 1,
                        t[2] + 1
                    );
                }
            }
        }
        let h = vt.row(order[0]);
        let hn = Matrix3::new(h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7], h[8]);
        let Some(tb_inv) = tb.inverse() else {
            bail!("the plate points are all at one place");
        };
        let mut m = tb_inv.m * hn * ta.m;
        let scale = m[(2, 2)];
        if scale.abs() > 1e-12 * m.norm() {
            m /= scale;
        } else {
            m /= m.norm();
        }
        let out = Self { m };
        let sv = hn.singular_values();
        let (lo, hi) = (sv.min(), sv.max());
        ensure!(
            lo > 1e-6 * hi && out.inverse().is_some(),
            "the points do not fix a homography (it is singular: three of them on a line?)"
        );
        // Every point on the same side of the map's horizon (no point behind the camera).
        let sides: Vec<f64> = from.iter().map(|p| out.w(*p)).collect();
        ensure!(
            sides.iter().all(|&w| w > 0.0) || sides.iter().all(|&w| w < 0.0),
            "the points do not fit one view of a plane (they lie on both sides of its horizon)"
        );
        Ok(out)
    }
}

/// Three of four points on a line (twice their triangle's area below 1 % of the square
/// of the set's largest distance): their indices.
fn collinear_triple(pts: &[[f64; 2]]) -> Option<[usize; 3]> {
    let mut span2 = 0.0f64;
    for a in pts {
        for b in pts {
            span2 = span2.max((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2));
        }
    }
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            for k in j + 1..pts.len() {
                let (a, b, c) = (pts[i], pts[j], pts[k]);
                let area2 = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
                if area2 < 0.01 * span2 {
                    return Some([i, j, k]);
                }
            }
        }
    }
    None
}

/// Hartley's normalisation of `pts`: their centroid to the origin, their mean distance
/// from it to `sqrt 2`.
fn normaliser(pts: &[[f64; 2]]) -> Result<Homography> {
    let n = pts.len() as f64;
    let cx = pts.iter().map(|p| p[0]).sum::<f64>() / n;
    let cy = pts.iter().map(|p| p[1]).sum::<f64>() / n;
    let mean = pts
        .iter()
        .map(|p| (p[0] - cx).hypot(p[1] - cy))
        .sum::<f64>()
        / n;
    ensure!(mean > 0.0, "the points are all at one place");
    let s = std::f64::consts::SQRT_2 / mean;
    Ok(Homography {
        m: Matrix3::new(s, 0.0, -s * cx, 0.0, s, -s * cy, 0.0, 0.0, 1.0),
    })
}

/// The uncertainty of an image coordinate of a calibration point when the points
/// cannot estimate it themselves (exactly four), px: a mark located to half a pixel,
/// as a standard uncertainty.
pub const DEFAULT_POINT_U_PX: f64 = 0.5;

/// The least uncertainty of an image coordinate estimated from a calibration's residual,
/// px: a mark is not located better than a tenth of a pixel, however well a few points
/// happen to agree (with 2 to 4 degrees of freedom the estimate alone is often far too
/// small).
pub const MIN_POINT_U_PX: f64 = 0.1;

/// Monte Carlo draws of the calibration's effect on the swing's scale.
const SCALE_DRAWS: usize = 400;

/// A plate calibration: the image-to-plate homography fitted to the points of
/// `video.calibration`, and how well it fits them.
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    /// Image (px) to plate (the points' own unit).
    pub to_plate: Homography,
    pub image: Vec<[f64; 2]>,
    pub plate: Vec<[f64; 2]>,
    /// RMS distance, px, between each image point and its plate point taken back into
    /// the image.
    pub residual_rms_px: f64,
    /// Degrees of freedom of that residual, `2 n - 8`.
    pub dof: usize,
    /// The standard uncertainty of each image coordinate, px: given, else the residual's
    /// own estimate `sqrt(sum r^2 / (2 n - 8))` (at least [`MIN_POINT_U_PX`]) when there
    /// are more than four points, else [`DEFAULT_POINT_U_PX`]. The plate coordinates are
    /// taken as exact.
    pub point_u_px: f64,
    /// Where `point_u_px` comes from.
    pub point_u_source: PointUSource,
}

/// Where a calibration's point uncertainty comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PointUSource {
    /// `video.calibration.u_px`.
    Given,
    /// The fit's residual (more than four points).
    Residual,
    /// [`DEFAULT_POINT_U_PX`] (four points leave no residual).
    Default,
}

impl PointUSource {
    /// In words, as the reports give it.
    pub fn describe(self) -> &'static str {
        match self {
            PointUSource::Given => "given",
            PointUSource::Residual => "the fit's residual",
            PointUSource::Default => "default: four points leave no residual",
        }
    }
}

impl Calibration {
    /// The calibration from image points and their plate coordinates, with the image
    /// points' standard uncertainty `u_px` when given.
    pub fn new(image: &[[f64; 2]], plate: &[[f64; 2]], u_px: Option<f64>) -> Result<Self> {
        let to_plate = Homography::fit(image, plate)?;
        let Some(back) = to_plate.inverse() else {
            bail!("the calibration's homography is singular");
        };
        let ss: f64 = image
            .iter()
            .zip(plate)
            .map(|(p, q)| {
                let r = back.apply(*q);
                (r[0] - p[0]).powi(2) + (r[1] - p[1]).powi(2)
            })
            .sum();
        let n = image.len();
        let dof = 2 * n - 8;
        let (point_u_px, point_u_source) = match u_px {
            Some(u) => (u, PointUSource::Given),
            None if dof > 0 => (
                (ss / dof as f64).sqrt().max(MIN_POINT_U_PX),
                PointUSource::Residual,
            ),
            None => (DEFAULT_POINT_U_PX, PointUSource::Default),
        };
        Ok(Self {
            to_plate,
            image: image.to_vec(),
            plate: plate.to_vec(),
            residual_rms_px: (ss / n as f64).sqrt(),
            dof,
            point_u_px,
            point_u_source,
        })
    }

    /// The plate angle of a wire seen at image angle `theta` through the image point
    /// `pivot`, rad (in (-pi, pi]): exact for a straight wire through the pivot on the
    /// calibration points' side of the horizon (see [`Calibration::new`]).
    pub fn plate_angle(&self, pivot: [f64; 2], theta: f64) -> f64 {
        self.to_plate.direction(pivot, theta)
    }

    /// Whether the image point `p` lies on the calibration points' side of the plate's
    /// horizon (where the homography describes the plate).
    pub fn sees(&self, p: [f64; 2]) -> bool {
        let (a, b) = (self.to_plate.w(p), self.to_plate.w(self.image[0]));
        a * b > 0.0
    }

    /// Image angles about `pivot` as plate angles, kept continuous: each is taken within
    /// half a turn of the one before it (missing ones stay missing), and the first
    /// within half a turn of the first image angle.
    pub fn plate_angles(&self, pivot: [f64; 2], image: &[Option<f64>]) -> Vec<Option<f64>> {
        let mut last = image.iter().flatten().next().copied();
        image
            .iter()
            .map(|a| {
                let a = (*a)?;
                let mut q = self.plate_angle(pivot, a);
                if let Some(l) = last {
                    q += std::f64::consts::TAU * ((l - q) / std::f64::consts::TAU).round();
                }
                last = Some(q);
                Some(q)
            })
            .collect()
    }

    /// The relative standard uncertainty that the calibration puts on the swing's
    /// scale: the plate angle between the wire at `rest - amp` and at `rest + amp`
    /// (plate angles, rad, about the image point `pivot`), re-measured through the
    /// homographies of [`SCALE_DRAWS`] draws of the image points (each coordinate
    /// normal with `point_u_px`). The scale of `s_r` follows the swing's (a swing
    /// measured 1 % large makes the amplitude fall 1 % faster).
    pub fn scale_u_rel(&self, pivot: [f64; 2], rest: f64, amp: f64) -> f64 {
        if self.point_u_px <= 0.0 || amp <= 0.0 {
            return 0.0;
        }
        let Some(back) = self.to_plate.inverse() else {
            return f64::NAN;
        };
        let at = self.to_plate.apply(pivot);
        // The two image directions of the wire at the swing's ends.
        let ends = [rest - amp, rest + amp].map(|a| back.direction(at, a));
        let mut rng = Rng::new(0xCA1B_0A7E);
        let mut scales = Vec::with_capacity(SCALE_DRAWS);
        for _ in 0..SCALE_DRAWS {
            let drawn: Vec<[f64; 2]> = self
                .image
                .iter()
                .map(|p| {
                    [
                        p[0] + self.point_u_px * rng.normal(),
                        p[1] + self.point_u_px * rng.normal(),
                    ]
                })
                .collect();
            let Ok(h) = Homography::fit(&drawn, &self.plate) else {
                continue;
            };
            let [lo, hi] = ends.map(|e| h.direction(pivot, e));
            let mut span = hi - lo;
            span -= std::f64::consts::TAU * (span / std::f64::consts::TAU).round();
            scales.push(span.abs() / (2.0 * amp));
        }
        if scales.len() < 2 {
            return f64::NAN;
        }
        let n = scales.len() as f64;
        let mean = scales.iter().sum::<f64>() / n;
        (scales.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    }
}

/// What a report says of a calibration.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CalibrationSummary {
    pub points: usize,
    pub residual_rms_px: f64,
    pub dof: usize,
    pub point_u_px: f64,
    pub point_u_source: PointUSource,
}

impl From<&Calibration> for CalibrationSummary {
    fn from(c: &Calibration) -> Self {
        Self {
            points: c.image.len(),
            residual_rms_px: c.residual_rms_px,
            dof: c.dof,
            point_u_px: c.point_u_px,
            point_u_source: c.point_u_source,
        }
    }
}

/// A pinhole camera of focal length `f` px looking at the plate, tilted by `tilt`
/// (rad) from the plate's normal about the plate axis at angle `axis` (rad, from the
/// x axis), its optical axis through the plate point `centre`, which it shows at
/// `image_centre`, at unit scale along the axis there (`cos(tilt)` across it): plate
/// (px of the untilted view) to image.
/// With `tilt` 0 it is a translation.
pub fn tilted_view(
    f: f64,
    tilt: f64,
    axis: f64,
    centre: [f64; 2],
    image_centre: [f64; 2],
) -> Homography {
    let (ux, uy) = (axis.cos(), axis.sin());
    // Rodrigues: rotation by `tilt` about (ux, uy, 0).
    let (c, s) = (tilt.cos(), tilt.sin());
    let k = Matrix3::new(0.0, 0.0, uy, 0.0, 0.0, -ux, -uy, ux, 0.0);
    let r = Matrix3::identity() * c
        + k * s
        + Vector3::new(ux, uy, 0.0) * Vector3::new(ux, uy, 0.0).transpose() * (1.0 - c);
    // Camera coordinates of plate point (X, Y, 0) relative to `centre`: R X + (0, 0, f);
    // projected: f x / z.
    let proj = Matrix3::new(
        f * r[(0, 0)],
        f * r[(0, 1)],
        0.0,
        f * r[(1, 0)],
        f * r[(1, 1)],
        0.0,
        r[(2, 0)],
        r[(2, 1)],
        f,
    );
    let shift = |x: f64, y: f64| Matrix3::new(1.0, 0.0, x, 0.0, 1.0, y, 0.0, 0.0, 1.0);
    Homography {
        m: shift(image_centre[0], image_centre[1]) * proj * shift(-centre[0], -centre[1]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn close(a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
        (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol
    }

    #[test]
    fn four_points_of_a_known_map_give_it_back() {
        let h = tilted_view(800.0, 0.35, 0.6, [300.0, 200.0], [320.0, 240.0]);
        let plate = [[0.0, 0.0], [400.0, 10.0], [380.0, 330.0], [20.0, 300.0]];
        let image: Vec<[f64; 2]> = plate.iter().map(|p| h.apply(*p)).collect();
        let back = Homography::fit(&image, &plate).unwrap();
        for p in [[123.0, 45.0], [-50.0, 500.0], [300.0, 200.0]] {
            assert!(close(back.apply(h.apply(p)), p, 1e-7), "{p:?}");
        }
    }

    #[test]
    fn an_untilted_view_is_a_translation_and_keeps_angles() {
        let h = tilted_view(900.0, 0.0, 1.0, [10.0, 20.0], [50.0, 60.0]);
        assert!(close(h.apply([10.0, 20.0]), [50.0, 60.0], 1e-12));
        assert!(close(h.apply([110.0, 20.0]), [150.0, 60.0], 1e-12));
        assert!((h.direction([3.0, 4.0], 1.2) - 1.2).abs() < 1e-12);
    }

    #[test]
    fn a_tilt_scales_angles_between_cos_and_its_inverse() {
        // Far from the camera's centre of view a tilt by tau about the x axis
        // foreshortens y by cos tau (at the centre, exactly): a wire at 45 degrees to
        // the axis is seen at atan(cos tau).
        let tau = 20f64.to_radians();
        let h = tilted_view(1e6, tau, 0.0, [0.0, 0.0], [0.0, 0.0]);
        let seen = h.direction([0.0, 0.0], PI / 4.0);
        assert!((seen - tau.cos().atan()).abs() < 1e-9, "{seen}");
        // A small swing about the axis's normal is stretched by 1 / cos tau, about the
        // axis itself shrunk by cos tau.
        let d = 1e-4;
        let about_normal = (h.direction([0.0, 0.0], PI / 2.0 + d)
            - h.direction([0.0, 0.0], PI / 2.0 - d))
            / (2.0 * d);
        let about_axis = (h.direction([0.0, 0.0], d) - h.direction([0.0, 0.0], -d)) / (2.0 * d);
        assert!(
            (about_normal - 1.0 / tau.cos()).abs() < 1e-6,
            "{about_normal}"
        );
        assert!((about_axis - tau.cos()).abs() < 1e-6, "{about_axis}");
    }

    #[test]
    fn calibrated_angles_are_the_plate_angles_and_continuous() {
        let h = tilted_view(700.0, 0.4, 2.0, [320.0, 100.0], [320.0, 240.0]);
        let plate = [
            [320.0, 100.0],
            [420.0, 100.0],
            [320.0, 200.0],
            [220.0, 100.0],
            [390.0, 170.0],
        ];
        let image: Vec<[f64; 2]> = plate.iter().map(|p| h.apply(*p)).collect();
        let cal = Calibration::new(&image, &plate, None).unwrap();
        assert!(cal.residual_rms_px < 1e-8);
        assert_eq!(cal.dof, 2);
        let pivot = h.apply([320.0, 100.0]);
        // A wire through the pivot at plate angles near pi (crossing +-pi).
        let truth: Vec<f64> = (0..50).map(|k| PI - 0.2 + 0.008 * k as f64).collect();
        let image_angles: Vec<Option<f64>> = truth
            .iter()
            .map(|&a| {
                let e = h.apply([320.0 + 100.0 * a.cos(), 100.0 + 100.0 * a.sin()]);
                Some((e[1] - pivot[1]).atan2(e[0] - pivot[0]))
            })
            .collect();
        let got = cal.plate_angles(pivot, &image_angles);
        for (g, t) in got.iter().zip(&truth) {
            let g = g.unwrap();
            assert!(
                (g - t).abs() < 1e-9 || (g - t - 2.0 * PI).abs() < 1e-9,
                "{g} {t}"
            );
        }
        for w in got.windows(2) {
            assert!((w[1].unwrap() - w[0].unwrap()).abs() < 0.01);
        }
    }

    #[test]
    fn collinear_points_are_refused() {
        let image = [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]];
        let plate = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]];
        assert!(Homography::fit(&image, &plate).is_err());
        // The natural four marks: the fulcrum, both ends of the base line (on one line
        // with it) and the 90 degree tick, picked with a little noise.
        let h = tilted_view(900.0, 0.35, 0.3, [320.0, 100.0], [320.0, 240.0]);
        let plate = [[0.0, 0.0], [60.0, 0.0], [-60.0, 0.0], [0.0, 58.5]];
        let image: Vec<[f64; 2]> = plate
            .iter()
            .zip([[0.1, -0.2], [-0.3, 0.1], [0.2, 0.2], [0.0, -0.1]])
            .map(|(p, e)| {
                let q = h.apply([320.0 + 2.0 * p[0], 100.0 + 2.0 * p[1]]);
                [q[0] + e[0], q[1] + e[1]]
            })
            .collect();
        let e = Homography::fit(&image, &plate).unwrap_err().to_string();
        assert!(e.contains("points 1, 2 and 3 of four lie on a line"), "{e}");
    }

    #[test]
    fn a_few_agreeing_points_do_not_claim_a_perfect_calibration() {
        let h = tilted_view(800.0, 0.3, 0.0, [0.0, 0.0], [320.0, 240.0]);
        let plate = [
            [0.0, 0.0],
            [100.0, 0.0],
            [0.0, 100.0],
            [100.0, 100.0],
            [50.0, 30.0],
        ];
        let image: Vec<[f64; 2]> = plate.iter().map(|p| h.apply(*p)).collect();
        let c = Calibration::new(&image, &plate, None).unwrap();
        assert_eq!(c.point_u_source, PointUSource::Residual);
        assert_eq!(c.point_u_px, MIN_POINT_U_PX);
        assert!(c.sees(h.apply([50.0, 50.0])));
    }

    #[test]
    fn the_scale_uncertainty_grows_with_the_points_uncertainty() {
        let h = tilted_view(900.0, 0.35, 0.3, [320.0, 100.0], [320.0, 240.0]);
        let plate: Vec<[f64; 2]> = (0..8)
            .map(|k| {
                let a = PI * k as f64 / 7.0;
                [320.0 + 150.0 * a.cos(), 100.0 + 150.0 * a.sin()]
            })
            .collect();
        let image: Vec<[f64; 2]> = plate.iter().map(|p| h.apply(*p)).collect();
        let pivot = h.apply([320.0, 100.0]);
        let u = |px: f64| {
            Calibration::new(&image, &plate, Some(px))
                .unwrap()
                .scale_u_rel(pivot, PI / 2.0, 0.17)
        };
        let (small, large) = (u(0.1), u(1.0));
        assert!(small > 0.0 && small < 0.01, "{small}");
        // Linear in the points' uncertainty, within the draws' scatter.
        assert!((large / small - 10.0).abs() < 1.5, "{small} {large}");
    }
}
