//! The pivot: where the first look's lines meet (RANSAC over pairs of lines, scored
//! by the directions that point at a candidate), and the robust least-squares
//! intersection of lines.

use super::FrameLine;
use crate::detect::tuning::RANSAC_TRIES;
use crate::detect::{Line, Pt};
use anyhow::{bail, Result};

/// Distance within which a line counts as passing through a pivot at `p`: a few
/// pixels, growing with the distance from the frame's centre `c` (angles err too).
pub(super) fn through_tol(p: Pt, c: Pt, base: f64) -> f64 {
    base + 0.01 * (p - c).norm()
}

/// A frame's line with the extent of its pixels along it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Seen {
    line: Line,
    lo: f64,
    hi: f64,
}

impl Seen {
    pub(super) fn of(f: &FrameLine) -> Self {
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for (q, _) in &f.pts {
            let s = (q - f.line.point).dot(&f.line.dir);
            lo = lo.min(s);
            hi = hi.max(s);
        }
        Self {
            line: f.line,
            lo,
            hi,
        }
    }

    /// Whether the line passes within `tol` of `p` with `p` near or beyond one of its
    /// pixels' ends, not in their middle (a wire does not run past its own pivot).
    pub(super) fn points_at(&self, p: Pt, tol: f64) -> bool {
        let s = (p - self.line.point).dot(&self.line.dir);
        let margin = 0.1 * (self.hi - self.lo);
        self.line.distance(p) <= tol && (s < self.lo + margin || s > self.hi - margin)
    }
}

/// The pivot by RANSAC over pairs of lines, scored by how many different directions
/// (half-degree bins) point at it: the swinging wire's lines fan out from the pivot,
/// while the edges of a moving bob or hand are many but nearly parallel. Then least
/// squares on the lines that point at it.
pub(super) fn ransac_pivot(lines: &[Seen], center: Pt, base_tol: f64) -> Option<Pt> {
    ransac(lines, center, base_tol).map(|(_, p)| p)
}

/// [`ransac_pivot`], with the pivot's score: how many directions point at it.
fn ransac(lines: &[Seen], center: Pt, base_tol: f64) -> Option<(usize, Pt)> {
    let mut rng = crate::rng::Rng::new(0x5eed);
    let n = lines.len();
    if n < 2 {
        return None;
    }
    let dir_bin = |l: &Line| {
        (l.dir
            .y
            .atan2(l.dir.x)
            .rem_euclid(std::f64::consts::PI)
            .to_degrees()
            * 2.0) as i64
    };
    let score = |p: Pt| -> usize {
        let tol = through_tol(p, center, base_tol);
        let bins: std::collections::BTreeSet<i64> = lines
            .iter()
            .filter(|l| l.points_at(p, tol))
            .map(|l| dir_bin(&l.line))
            .collect();
        bins.len()
    };
    let mut best: Option<(usize, Pt)> = None;
    for _ in 0..RANSAC_TRIES {
        let i = (rng.uniform() * n as f64) as usize % n;
        let j = (rng.uniform() * n as f64) as usize % n;
        let (li, lj) = (lines[i].line, lines[j].line);
        if li.dir.dot(&lj.dir).abs() > 1f64.to_radians().cos() {
            continue;
        }
        let Ok(p) = intersect(&[li, lj]) else {
            continue;
        };
        if (p - center).norm() > 20.0 * center.norm() {
            continue;
        }
        let sc = score(p);
        if best.is_none_or(|b| sc > b.0) {
            best = Some((sc, p));
        }
    }
    let (sc, p) = best?;
    if sc < 3 {
        return None;
    }
    let tol = through_tol(p, center, base_tol);
    let inl: Vec<Line> = lines
        .iter()
        .filter(|l| l.points_at(p, tol))
        .map(|l| l.line)
        .collect();
    intersect(&inl).ok().map(|q| (sc, q))
}

/// A second pendulum: the pivot the lines that do not point at `first` meet in, with
/// how many directions point at it, and how many point at `first`.
pub(super) fn second_pivot(
    lines: &[Seen],
    first: Pt,
    center: Pt,
    base_tol: f64,
) -> Option<(Pt, usize, usize)> {
    let tol = 2.0 * through_tol(first, center, base_tol);
    let (at, rest): (Vec<Seen>, Vec<Seen>) = lines.iter().partition(|l| l.points_at(first, tol));
    let dir_bins = |ls: &[Seen]| {
        ls.iter()
            .map(|l| {
                (l.line
                    .dir
                    .y
                    .atan2(l.line.dir.x)
                    .rem_euclid(std::f64::consts::PI)
                    .to_degrees()
                    * 2.0) as i64
            })
            .collect::<std::collections::BTreeSet<_>>()
            .len()
    };
    let (sc, p) = ransac(&rest, center, base_tol)?;
    Some((p, sc, dir_bins(&at)))
}

/// Robust least-squares intersection of lines (Tukey-weighted, iterated).
pub fn intersect(lines: &[Line]) -> Result<Pt> {
    let solve = |wts: &[f64]| -> Option<Pt> {
        let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (l, &w) in lines.iter().zip(wts) {
            let n = l.normal();
            let c = n.dot(&l.point);
            a11 += w * n.x * n.x;
            a12 += w * n.x * n.y;
            a22 += w * n.y * n.y;
            b1 += w * n.x * c;
            b2 += w * n.y * c;
        }
        let det = a11 * a22 - a12 * a12;
        // Nearly parallel lines: no intersection to speak of.
        if det.abs() < 1e-6 * (a11 + a22).powi(2) {
            return None;
        }
        Some(Pt::new(
            (a22 * b1 - a12 * b2) / det,
            (a11 * b2 - a12 * b1) / det,
        ))
    };
    let mut w = vec![1.0; lines.len()];
    let Some(mut p) = solve(&w) else {
        bail!("the wire's lines are all parallel: cannot locate the pivot; give `video.pivot`");
    };
    for _ in 0..20 {
        let mut d: Vec<f64> = lines.iter().map(|l| l.distance(p)).collect();
        let mut s = d.clone();
        let c = (4.685 * 1.4826 * crate::numerics::upper_median(&mut s)).max(1.0);
        for (wi, di) in w.iter_mut().zip(d.iter_mut()) {
            let u = *di / c;
            *wi = if u < 1.0 { (1.0 - u * u).powi(2) } else { 0.0 };
        }
        match solve(&w) {
            Some(q) if (q - p).norm() < 1e-3 => {
                p = q;
                break;
            }
            Some(q) => p = q,
            None => break,
        }
    }
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intersects_lines_through_an_offscreen_pivot_despite_outliers() {
        let pivot = Pt::new(300.0, -600.0);
        let mut lines: Vec<Line> = (0..30)
            .map(|i| {
                let th = (80.0 + i as f64).to_radians();
                let d = Pt::new(th.cos(), th.sin());
                Line::through(pivot + d * 700.0, pivot + d * 900.0)
            })
            .collect();
        lines.push(Line::through(Pt::new(0.0, 0.0), Pt::new(100.0, 5.0)));
        lines.push(Line::through(Pt::new(50.0, 300.0), Pt::new(60.0, 0.0)));
        let p = intersect(&lines).unwrap();
        assert!((p - pivot).norm() < 0.5, "{p:?}");
    }
}
