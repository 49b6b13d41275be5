//! Lines in pixel coordinates and the orthogonal (total least-squares) fits of weighted
//! pixels, free or through the pivot, also from stored pixel moments.

use super::Pt;

/// An infinite line through `point` along the unit vector `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub point: Pt,
    pub dir: Pt,
}

impl Line {
    pub fn through(a: Pt, b: Pt) -> Self {
        Self {
            point: a,
            dir: (b - a).normalize(),
        }
    }

    pub fn normal(&self) -> Pt {
        Pt::new(-self.dir.y, self.dir.x)
    }

    pub fn distance(&self, p: Pt) -> f64 {
        (p - self.point).dot(&self.normal()).abs()
    }
}

/// The angle `a + 2 pi k` nearest to `reference`: the branch the detector reports in.
/// The wire's image angle is continuous over a video (a pendulum swings far less than
/// half a turn), so every angle is taken within half a turn of a reference on its
/// continuous branch (the prediction, or the rest direction of the first look),
/// whatever the camera's roll: a wire that hangs towards -x reads 180 +/- its swing,
/// never a jump from +180 to -180.
pub fn unwrap_near(a: f64, reference: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let d = a - reference;
    if d > PI || d <= -PI {
        a - TAU * ((d - PI) / TAU).ceil()
    } else {
        a
    }
}

/// Orthogonal (total) least-squares line through weighted points: the principal axis
/// of the weighted pixel cloud (ERRATA §6: unlike `y = A x + B`, exact for any slope).
pub fn fit_line_weighted(pts: &[(Pt, f64)]) -> Option<Line> {
    if pts.len() < 2 {
        return None;
    }
    moments(pts).free_line()
}

/// Orthogonal least-squares line constrained to pass through `pivot`: the principal
/// axis of the weighted second moments about the pivot (Eq. 35 done as ERRATA §6 asks,
/// with the wire's known fixed point).
pub fn fit_line_through(pivot: Pt, pts: &[(Pt, f64)]) -> Option<Line> {
    if pts.len() < 2 {
        return None;
    }
    line_through_moments(pivot, &moments(pts))
}

/// The line through `pivot` of pixels with moments `m` ([`fit_line_through`]).
pub fn line_through_moments(pivot: Pt, m: &[f64; 6]) -> Option<Line> {
    let (th, _) = m.line_about(pivot)?;
    Some(Line {
        point: pivot,
        dir: Pt::new(th.cos(), th.sin()),
    })
}

/// Weighted pixel moments `[sum w, sum w x, sum w y, sum w x^2, sum w x y, sum w y^2]`.
pub fn moments(pts: &[(Pt, f64)]) -> [f64; 6] {
    moments_of(pts.iter().copied())
}

/// [`moments`] of pixels given one by one (weights made as they are summed).
pub fn moments_of(pts: impl IntoIterator<Item = (Pt, f64)>) -> [f64; 6] {
    let mut m = [0.0f64; 6];
    for (q, w) in pts {
        m[0] += w;
        m[1] += w * q.x;
        m[2] += w * q.y;
        m[3] += w * q.x * q.x;
        m[4] += w * q.x * q.y;
        m[5] += w * q.y * q.y;
    }
    m
}

/// Line fits from stored pixel moments.
pub(super) trait Moments {
    /// The orthogonal fit constrained through `p`: angle (pointing away from `p`) and
    /// the pixels' centroid.
    fn line_about(&self, p: Pt) -> Option<(f64, Pt)>;
    /// The unconstrained orthogonal fit.
    fn free_line(&self) -> Option<Line>;
}

impl Moments for [f64; 6] {
    fn line_about(&self, p: Pt) -> Option<(f64, Pt)> {
        let [sw, sx, sy, sxx, sxy, syy] = *self;
        if sw <= 0.0 || !(sxx + syy).is_finite() {
            return None;
        }
        // Second moments about p.
        let mxx = sxx - 2.0 * p.x * sx + sw * p.x * p.x;
        let mxy = sxy - p.x * sy - p.y * sx + sw * p.x * p.y;
        let myy = syy - 2.0 * p.y * sy + sw * p.y * p.y;
        let th = 0.5 * (2.0 * mxy).atan2(mxx - myy);
        let d = Pt::new(th.cos(), th.sin());
        let c = Pt::new(sx / sw, sy / sw);
        let d = if (c - p).dot(&d) >= 0.0 { d } else { -d };
        Some((d.y.atan2(d.x), c))
    }

    fn free_line(&self) -> Option<Line> {
        let [sw, sx, sy, sxx, sxy, syy] = *self;
        if sw <= 0.0 {
            return None;
        }
        let c = Pt::new(sx / sw, sy / sw);
        let (cxx, cxy, cyy) = (
            sxx / sw - c.x * c.x,
            sxy / sw - c.x * c.y,
            syy / sw - c.y * c.y,
        );
        let th = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
        Some(Line {
            point: c,
            dir: Pt::new(th.cos(), th.sin()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_unwrap_to_the_branch_of_their_reference() {
        use std::f64::consts::PI;
        // A wire hanging towards -x: atan2 gives -179 deg for 181 deg.
        let a = unwrap_near((-179f64).to_radians(), PI);
        assert!((a.to_degrees() - 181.0).abs() < 1e-9, "{a}");
        assert!((unwrap_near(179f64.to_radians(), PI).to_degrees() - 179.0).abs() < 1e-9);
        // Within half a turn: unchanged (bit for bit).
        assert_eq!(unwrap_near(1.25, 0.5), 1.25);
        // Several turns away, either side.
        let b = unwrap_near(0.1 + 6.0 * PI, -0.2);
        assert!((b - 0.1).abs() < 1e-9, "{b}");
        let c = unwrap_near(0.1, 4.0 * PI + 3.0);
        assert!((c - (0.1 + 4.0 * PI)).abs() < 1e-9, "{c}");
        // Exactly half a turn away: the branch above (reference - pi, reference + pi].
        assert!((unwrap_near(-PI, 0.0) - PI).abs() < 1e-12);
    }

    #[test]
    fn orthogonal_fit_is_exact_for_a_vertical_line() {
        let pts: Vec<(Pt, f64)> = (0..50).map(|i| (Pt::new(10.0, i as f64), 1.0)).collect();
        let l = fit_line_weighted(&pts).unwrap();
        assert!(l.dir.x.abs() < 1e-12, "{l:?}");
        assert!((l.point.x - 10.0).abs() < 1e-12);
    }
}
