//! Small numerical tools shared by the analysis: medians, least-squares lines and
//! one-dimensional searches.
//!
//! * [`median`] averages the two middle values of an even count; [`upper_median`] takes
//!   the upper of them (`v[n / 2]` after sorting). Both sort their argument in place by
//!   [`f64::total_cmp`].
//! * [`linear_fit`] is the ordinary least-squares line `y = intercept + slope x` with the
//!   standard error of its slope; [`slope_through_origin`] is the least-squares line
//!   `y = k x`; [`quadratic_at`] is the least-squares quadratic's value at a point;
//!   [`least_squares3`] is the least-squares fit of `y` on three regressors, [`least_squares`]
//!   on any number.
//! * [`golden_section_min`] narrows a bracket around the minimum of a unimodal function;
//!   [`bisect`] narrows a bracket around the point where a condition stops holding.
//!
//! The arithmetic of each is fixed (the order of the sums and of the updates), so that a
//! result does not change by a bit from one caller or release to the next.

use serde::Serialize;

/// The least-squares quadratic through the points `(x, y)`, evaluated at `at`: the
/// points are taken about `at` (`x - at`, in their order) and the normal equations
/// solved by Cholesky. `None` with fewer than three points, or points that do not fix a
/// quadratic.
pub fn quadratic_at(pts: impl IntoIterator<Item = (f64, f64)>, at: f64) -> Option<f64> {
    let (chol, atb, n) = normal_equations(pts.into_iter().map(|(x, y)| {
        let x = x - at;
        ([1.0, x, x * x], y)
    }))?;
    if n < 3 {
        return None;
    }
    let p = chol.solve(&atb)[0];
    p.is_finite().then_some(p)
}

/// The normal equations of `y` on `N` regressors over the rows, summed in their order:
/// the Cholesky factor of `sum x x^T`, `sum x y` and the count of rows (`None` when the
/// factor does not exist).
fn normal_equations<const N: usize>(
    rows: impl IntoIterator<Item = ([f64; N], f64)>,
) -> Option<(
    nalgebra::Cholesky<f64, nalgebra::Const<N>>,
    nalgebra::SVector<f64, N>,
    usize,
)> {
    let mut ata = nalgebra::SMatrix::<f64, N, N>::zeros();
    let mut atb = nalgebra::SVector::<f64, N>::zeros();
    let mut n = 0;
    for (x, y) in rows {
        let v = nalgebra::SVector::<f64, N>::from(x);
        ata += v * v.transpose();
        atb += v * y;
        n += 1;
    }
    Some((ata.cholesky()?, atb, n))
}

/// The least-squares coefficients `c` of `y = c[0] x[0] + c[1] x[1] + c[2] x[2]` over the
/// rows `(x, y)`, by the normal equations solved by Cholesky (sums in the rows' order).
/// `None` when the rows do not fix the three coefficients (fewer than three, or
/// regressors that are not independent: a pivot of the Cholesky factor under 1e-6 of
/// the largest).
pub fn least_squares3(rows: impl IntoIterator<Item = ([f64; 3], f64)>) -> Option<[f64; 3]> {
    least_squares(rows)
}

/// [`least_squares3`] on `N` regressors.
pub fn least_squares<const N: usize>(
    rows: impl IntoIterator<Item = ([f64; N], f64)>,
) -> Option<[f64; N]> {
    let (chol, atb, _) = normal_equations(rows)?;
    // Dependent regressors leave a pivot of the factor at rounding level, not zero.
    let d = chol.l_dirty().diagonal();
    if d.min() <= 1e-6 * d.max() {
        return None;
    }
    let c = chol.solve(&atb);
    c.iter().all(|v| v.is_finite()).then(|| c.into())
}

/// The jackknife's standard uncertainty from the estimates `leave_out` made with each
/// of its blocks left out in turn: `sqrt((m - 1) / m * sum (x - mean)^2)` over the `m`
/// estimates.
pub fn jackknife_u(leave_out: &[f64]) -> f64 {
    let m = leave_out.len() as f64;
    let mean = leave_out.iter().sum::<f64>() / m;
    ((m - 1.0) / m * leave_out.iter().map(|x| (x - mean).powi(2)).sum::<f64>()).sqrt()
}

/// Median of `v`: the middle value of an odd count, the mean of the two middle values of
/// an even count. Sorts `v`; `v` must not be empty.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Upper median of `v`: `v[n / 2]` once sorted, the middle value of an odd count and the
/// upper of the two middle values of an even count (always one of the values). Sorts
/// `v`; `v` must not be empty.
pub fn upper_median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Straight line `y = intercept + slope x` by least squares, with standard errors.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct LineFit {
    pub slope: f64,
    pub intercept: f64,
    pub slope_se: f64,
    pub rms: f64,
}

/// Least-squares line through `(x, y)`; `x` must have at least two distinct values.
pub fn linear_fit(x: &[f64], y: &[f64]) -> LineFit {
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let rss: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - intercept - slope * a).powi(2))
        .sum();
    let dof = (x.len() as f64 - 2.0).max(1.0);
    LineFit {
        slope,
        intercept,
        slope_se: (rss / dof / sxx).sqrt(),
        rms: (rss / n).sqrt(),
    }
}

/// Least-squares slope `k` of the line `y = k x` through the origin: `sum(x y) / sum(x^2)`,
/// or NaN when every `x` is zero (or there are none).
pub fn slope_through_origin(x: &[f64], y: &[f64]) -> f64 {
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| a * b).sum();
    let sxx: f64 = x.iter().map(|a| a * a).sum();
    if sxx > 0.0 {
        sxy / sxx
    } else {
        f64::NAN
    }
}

/// The most steps of [`golden_section_min`].
const GOLDEN_MAX_STEPS: usize = 200;

/// Golden-section search for the minimum of `f` on `[lo, hi]`: narrows the bracket until
/// it is no wider than `tol` and gives its midpoint. `f` is evaluated at two inner points
/// first, then once per step; the first error of `f` ends the search. It stops after
/// `GOLDEN_MAX_STEPS` steps, when `tol` is finer than floats can resolve there.
pub fn golden_section_min<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    (lo, hi): (f64, f64),
    tol: f64,
) -> Result<f64, E> {
    let gr = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (lo, hi);
    let mut x1 = b - gr * (b - a);
    let mut x2 = a + gr * (b - a);
    let mut f1 = f(x1)?;
    let mut f2 = f(x2)?;
    // The bracket shrinks by 0.618 a step: 200 steps reach any tolerance a float can
    // hold; past that (a tolerance below the spacing of floats near the minimum, e.g.
    // times of 1e4 s with a 1e-15 s tolerance) the loop would never end.
    for _ in 0..GOLDEN_MAX_STEPS {
        if b - a <= tol {
            break;
        }
        if f1 < f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - gr * (b - a);
            f1 = f(x1)?;
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + gr * (b - a);
            f2 = f(x2)?;
        }
    }
    Ok(0.5 * (a + b))
}

/// Bisection on `[lo, hi]` for the point where `below` stops holding (`below(lo)` is
/// taken to hold and `below(hi)` not): halves the bracket at most `max_iter` times,
/// stopping early once it is narrower than `tol`, and gives its midpoint.
pub fn bisect(
    mut below: impl FnMut(f64) -> bool,
    (lo, hi): (f64, f64),
    max_iter: usize,
    tol: f64,
) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    for _ in 0..max_iter {
        let mid = 0.5 * (lo + hi);
        if below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < tol {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_least_squares_quadratic_is_exact_on_a_parabola() {
        let f = |t: f64| 1.0 - 2.0 * t + 3.0 * t * t;
        let pts: Vec<(f64, f64)> = (0..6)
            .map(|k| (0.1 * k as f64, f(0.1 * k as f64)))
            .collect();
        let p = quadratic_at(pts.iter().copied(), 0.8).unwrap();
        assert!((p - f(0.8)).abs() < 1e-9, "{p}");
        // Two points do not fix a quadratic.
        assert_eq!(quadratic_at(pts[..2].iter().copied(), 0.8), None);
    }

    #[test]
    fn three_regressors_are_recovered_exactly_and_dependent_ones_refused() {
        // y = 2 - 0.5 a + 4 b over a grid: the fit returns the three coefficients.
        let rows: Vec<([f64; 3], f64)> = (0..4)
            .flat_map(|i| (0..3).map(move |j| (i as f64, j as f64)))
            .map(|(a, b)| ([1.0, a, b], 2.0 - 0.5 * a + 4.0 * b))
            .collect();
        let c = least_squares3(rows.iter().copied()).unwrap();
        for (got, want) in c.iter().zip([2.0, -0.5, 4.0]) {
            assert!((got - want).abs() < 1e-9, "{c:?}");
        }
        // A regressor that is twice another fixes nothing.
        let dependent = rows.iter().map(|(x, y)| ([1.0, x[1], 2.0 * x[1]], *y));
        assert_eq!(least_squares3(dependent), None);
        assert_eq!(least_squares3(rows[..2].iter().copied()), None);
    }

    #[test]
    fn golden_section_ends_when_the_tolerance_is_below_float_spacing() {
        // Near 1e4 floats are 1.8e-12 apart: a 1e-15 bracket cannot be reached.
        let x = golden_section_min(
            |x| Ok::<_, ()>((x - 1e4).powi(2)),
            (1e4 - 1e-6, 1e4 + 1e-6),
            1e-15,
        )
        .unwrap();
        assert!((x - 1e4).abs() < 1e-9, "{x}");
    }

    #[test]
    fn medians_of_odd_and_even_counts() {
        let mut odd = [5.0, 1.0, 3.0];
        assert_eq!(median(&mut odd), 3.0);
        assert_eq!(odd, [1.0, 3.0, 5.0], "sorted in place");
        assert_eq!(upper_median(&mut [5.0, 1.0, 3.0]), 3.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(upper_median(&mut [4.0, 1.0, 3.0, 2.0]), 3.0);
        assert_eq!(median(&mut [7.0]), 7.0);
        assert_eq!(upper_median(&mut [7.0]), 7.0);
        assert_eq!(median(&mut [-1.0, -0.0, 0.0, 2.0]), 0.0);
    }

    #[test]
    fn line_through_exact_points() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let y: Vec<f64> = x.iter().map(|v| 1.0 + 2.0 * v).collect();
        let l = linear_fit(&x, &y);
        assert_eq!((l.slope, l.intercept), (2.0, 1.0));
        assert_eq!((l.slope_se, l.rms), (0.0, 0.0));
    }

    #[test]
    fn line_through_scattered_points() {
        // x = 0, 1, 2; y = 0, 2, 1: mean (1, 1), sxx = 2, sxy = 1, slope 1/2,
        // intercept 1/2, residuals -1/2, 1, -1/2 (rss 3/2), dof 1.
        let l = linear_fit(&[0.0, 1.0, 2.0], &[0.0, 2.0, 1.0]);
        assert_eq!((l.slope, l.intercept), (0.5, 0.5));
        assert!((l.slope_se - 0.75f64.sqrt()).abs() < 1e-15);
        assert!((l.rms - 0.5f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn slope_through_the_origin() {
        // sum(x y) = 1 + 4 + 6 = 11, sum(x^2) = 1 + 4 + 9 = 14.
        assert_eq!(
            slope_through_origin(&[1.0, 2.0, 3.0], &[1.0, 2.0, 2.0]),
            11.0 / 14.0
        );
        assert_eq!(slope_through_origin(&[2.0, 4.0], &[3.0, 6.0]), 1.5);
        assert!(slope_through_origin(&[0.0, 0.0], &[1.0, 2.0]).is_nan());
        assert!(slope_through_origin(&[], &[]).is_nan());
    }

    #[test]
    fn golden_section_finds_a_parabola_vertex() {
        let mut calls = 0;
        let x = golden_section_min(
            |x| {
                calls += 1;
                Ok::<f64, ()>((x - 0.3).powi(2))
            },
            (-1.0, 2.0),
            1e-9,
        )
        .unwrap();
        assert!((x - 0.3).abs() < 1e-9, "{x}");
        // Each step shrinks the bracket by 0.618: 3 * 0.618^k <= 1e-9 from k = 46,
        // plus the two first evaluations.
        assert_eq!(calls, 48);
        // An error of the function ends the search.
        let err = golden_section_min(|x| if x < 0.5 { Ok(x) } else { Err(x) }, (0.0, 1.0), 1e-6);
        assert!(err.is_err());
    }

    #[test]
    fn bisection_finds_a_threshold() {
        let x = bisect(|x| x * x < 2.0, (0.0, 2.0), 200, 0.0);
        assert!((x - 2f64.sqrt()).abs() < 1e-15, "{x}");
        // Without a tolerance, every halving is taken.
        let mut n = 0;
        bisect(
            |_| {
                n += 1;
                true
            },
            (0.0, 1.0),
            30,
            0.0,
        );
        assert_eq!(n, 30);
        // With one, the search stops once the bracket is narrower: 1 / 2^k < 1e-3 at k = 10.
        let mut n = 0;
        let x = bisect(
            |x| {
                n += 1;
                x < 0.25
            },
            (0.0, 1.0),
            200,
            1e-3,
        );
        assert_eq!(n, 10);
        assert!((x - 0.25).abs() < 1e-3);
    }
}
