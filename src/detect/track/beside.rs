//! What runs beside the line followed: a frame accepted every [`BESIDE_EVERY_S`],
//! the profile across the line of how sharply each direction through the pivot stands
//! out of its neighbours, for the `beside` check ([`crate::detect::judge::beside_check`]).
//!
//! A wire's soft shadow can hold more evidence than a faint wire a few degrees from it,
//! and where the two are too close for the histogram of angles to show two peaks (the
//! wire on the shadow's flank), the track takes the shadow for the whole clip, and no
//! check on the angles sees it: the shadow swings as the wire does. Across the line, the
//! wire is the sharp ridge: the darkness at a point against its neighbours 1 px either
//! side holds most of the darkness against its neighbours 3.5 px either side, where a
//! blurred shadow's holds little of it.

use super::Tracker;
use crate::detect::tuning::{
    BESIDE_EVERY_S, BESIDE_MIN_APART_PX, BESIDE_MIN_SHARE, BESIDE_RADIAL_STEP_PX, BESIDE_REACH_DEG,
    BESIDE_SHARPER, BESIDE_SHARP_MIN, BESIDE_STEP_PX,
};
use crate::detect::Pt;
use crate::video::Frame;
use anyhow::Result;
use opencv::prelude::*;

/// The pass's looks beside the followed line: per look, the offsets (rad) of the
/// sharper ridges found there ([`sharper_beside`]), and when the next look is due.
#[derive(Debug)]
pub(super) struct Looks {
    found: Vec<Vec<f64>>,
    next_s: f64,
}

impl Default for Looks {
    fn default() -> Self {
        Self {
            found: Vec::new(),
            next_s: f64::NEG_INFINITY,
        }
    }
}

impl Looks {
    /// Whether a frame accepted at `t_s` is looked at: the first [`BESIDE_EVERY_S`]
    /// after the last look.
    pub(super) fn due(&self, t_s: f64) -> bool {
        t_s >= self.next_s
    }

    /// A look at `t_s` that `found` those offsets.
    pub(super) fn push(&mut self, t_s: f64, found: Vec<f64>) {
        self.next_s = t_s + BESIDE_EVERY_S;
        self.found.push(found);
    }

    /// Every look's offsets, in order.
    pub(super) fn found(&self) -> &[Vec<f64>] {
        &self.found
    }
}

/// A frame as a look reads it: its grey levels and the background's at the working
/// scale (`w` x `h`), the wire's polarity, the pivot and the band of radii (px).
pub(super) struct View<'a> {
    pub frame: &'a [u8],
    pub bg: &'a [u8],
    pub w: usize,
    pub h: usize,
    pub dark: bool,
    pub piv: Pt,
    pub band: (f64, f64),
}

/// Sums along one direction through the pivot, over the band of radii, of a point's
/// darkness (brightness for a light wire) against the background, less the mean of its
/// neighbours' 1, 2 and 3.5 px either side across the direction.
#[derive(Clone, Copy, Default)]
struct Across {
    at1: f64,
    at2: f64,
    at3: f64,
}

impl Tracker {
    /// A look beside the line accepted at `angle` in frame `f`, when one is due
    /// (`ROLLFRIC_DEBUG=beside` prints its offsets).
    pub(super) fn look_beside(&mut self, f: &Frame, angle: f64) -> Result<()> {
        if !self.beside.due(f.t_s) {
            return Ok(());
        }
        let found = sharper_beside(&self.view()?, angle);
        if self.debug.as_deref() == Some("beside") {
            eprintln!(
                "beside {} at {:.2} deg: {:?}",
                f.index,
                angle.to_degrees(),
                found.iter().map(|o| o.to_degrees()).collect::<Vec<_>>()
            );
        }
        self.beside.push(f.t_s, found);
        Ok(())
    }

    /// This frame as a look reads it.
    pub(super) fn view(&self) -> Result<View<'_>> {
        Ok(View {
            frame: self.small.data_bytes()?,
            bg: self.bg.data_bytes()?,
            w: self.small.cols() as usize,
            h: self.small.rows() as usize,
            dark: self.geo.dark,
            piv: self.piv,
            band: (self.r_lo, self.r_hi),
        })
    }
}

/// The directions near the line followed at `angle` (rad, within [`BESIDE_REACH_DEG`]
/// of it, at least [`BESIDE_MIN_APART_PX`] from it at the band's middle) where a ridge
/// sharper across than the followed one runs in `v`: a local maximum of the 2 px
/// contrast holding at least [`BESIDE_MIN_SHARE`] of the followed line's, whose 1 px
/// contrast is at least [`BESIDE_SHARPER`] times as large a share of its 3.5 px
/// contrast as the followed line's (and at least [`BESIDE_SHARP_MIN`]). Their offsets
/// from `angle`, rad; none when the followed line stands out of nothing.
pub(super) fn sharper_beside(v: &View, angle: f64) -> Vec<f64> {
    let (w, h, fr, bg) = (v.w, v.h, v.frame, v.bg);
    let (piv, (r_lo, r_hi)) = (v.piv, v.band);
    let r_mid = 0.5 * (r_lo + r_hi);
    let step = BESIDE_STEP_PX / r_mid;
    let n = (BESIDE_REACH_DEG.to_radians() / step).round() as i64;
    let reach = n as f64 * step;
    // The darkness against the background over the rectangle the looks sample
    // (the sector's corners and its arc's extremes, and the 3.5 px across).
    let (mut x_lo, mut y_lo, mut x_hi, mut y_hi) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for k in 0..=16 {
        let th = angle - reach + 2.0 * reach * k as f64 / 16.0;
        for r in [r_lo, r_hi] {
            let q = piv + Pt::new(th.cos(), th.sin()) * r;
            (x_lo, y_lo) = (x_lo.min(q.x), y_lo.min(q.y));
            (x_hi, y_hi) = (x_hi.max(q.x), y_hi.max(q.y));
        }
    }
    let clip = |x: f64, hi: usize| x.clamp(0.0, hi as f64) as usize;
    let (x0, y0) = (clip(x_lo - 5.0, w), clip(y_lo - 5.0, h));
    let (x1, y1) = (clip(x_hi + 6.0, w), clip(y_hi + 6.0, h));
    if x1 < x0 + 2 || y1 < y0 + 2 {
        return Vec::new();
    }
    let rw = x1 - x0;
    let mut dark = Vec::with_capacity(rw * (y1 - y0));
    for y in y0..y1 {
        let (b, f) = (&bg[y * w + x0..y * w + x1], &fr[y * w + x0..y * w + x1]);
        dark.extend(b.iter().zip(f).map(|(&b, &f)| {
            let d = f32::from(b) - f32::from(f);
            if v.dark {
                d
            } else {
                -d
            }
        }));
    }
    let (fw, fh) = ((rw - 1) as f64, (y1 - y0 - 1) as f64);
    let origin = Pt::new(x0 as f64, y0 as f64);
    let at = |p: Pt| -> f64 {
        let (xf, yf) = (p.x.floor(), p.y.floor());
        let (fx, fy) = ((p.x - xf) as f32, (p.y - yf) as f32);
        let i = yf as usize * rw + xf as usize;
        let (top, bottom) = (&dark[i..i + 2], &dark[i + rw..i + rw + 2]);
        f64::from(
            (top[0] * (1.0 - fx) + top[1] * fx) * (1.0 - fy)
                + (bottom[0] * (1.0 - fx) + bottom[1] * fx) * fy,
        )
    };
    let inside = |p: Pt| p.x >= 0.0 && p.y >= 0.0 && p.x < fw && p.y < fh;
    // Each direction's sums: the 2 px contrast alone (`full` false), or all three.
    let sums = |k: i64, full: bool| -> Across {
        let th = angle + k as f64 * step;
        let (dir, across) = (Pt::new(th.cos(), th.sin()), Pt::new(-th.sin(), th.cos()));
        let mut sum = Across::default();
        let mut r = r_lo;
        while r <= r_hi {
            let c = piv + dir * r - origin;
            r += BESIDE_RADIAL_STEP_PX;
            // The samples lie between the two 3.5 px out.
            if !inside(c + across * 3.5) || !inside(c - across * 3.5) {
                continue;
            }
            let side = |d: f64| 0.5 * (at(c + across * d) + at(c - across * d));
            let m = at(c);
            sum.at2 += m - side(2.0);
            if full {
                sum.at1 += m - side(1.0);
                sum.at3 += m - side(3.5);
            }
        }
        sum
    };
    let at2: Vec<f64> = (-n..=n).map(|k| sums(k, false).at2).collect();
    let own = sums(0, true);
    if own.at2 <= 0.0 || own.at3 <= 0.0 {
        return Vec::new();
    }
    let sharp = |a: &Across| a.at1 / a.at3;
    let least = (BESIDE_SHARPER * sharp(&own)).max(BESIDE_SHARP_MIN);
    let apart = BESIDE_MIN_APART_PX / r_mid;
    // The 2 px contrast's peaks far enough off and strong enough, then how sharp.
    (1..at2.len() - 1)
        .filter(|&i| {
            let off = (i as i64 - n) as f64 * step;
            at2[i] >= at2[i - 1]
                && at2[i] > at2[i + 1]
                && off.abs() >= apart
                && at2[i] >= BESIDE_MIN_SHARE * own.at2
        })
        .filter(|&i| {
            let p = sums(i as i64 - n, true);
            p.at3 > 0.0 && sharp(&p) >= least
        })
        .map(|i| (i as i64 - n) as f64 * step)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::judge::beside_check;
    use crate::detect::track::test_support::test_tracker;
    use opencv::core::{self, Mat, Scalar};

    /// A dark line: its angle, depth and profile across it.
    type DarkLine<'a> = (f64, f64, &'a dyn Fn(f64) -> f64);

    /// A 320x240 frame on the test tracker's wall (200), with dark lines from its pivot
    /// (160, 20): each at an angle (rad), with a depth (grey levels) and a profile across
    /// it (grey levels' share of the depth at a distance, px).
    fn frame(lines: &[DarkLine]) -> Mat {
        let (w, h) = (320usize, 240usize);
        let piv = Pt::new(160.0, 20.0);
        let mut m =
            Mat::new_rows_cols_with_default(h as i32, w as i32, core::CV_8UC1, Scalar::all(0.0))
                .unwrap();
        let data = m.data_bytes_mut().unwrap();
        for y in 0..h {
            for x in 0..w {
                let d = Pt::new(x as f64, y as f64) - piv;
                let mut g = 200.0;
                for (th, depth, across) in lines {
                    if d.x * th.cos() + d.y * th.sin() > 0.0 {
                        g -= depth * across((d.x * th.sin() - d.y * th.cos()).abs());
                    }
                }
                data[y * w + x] = g.round().clamp(0.0, 255.0) as u8;
            }
        }
        m
    }

    fn gauss(sigma: f64) -> impl Fn(f64) -> f64 {
        move |d: f64| (-0.5 * (d / sigma).powi(2)).exp()
    }

    #[test]
    fn a_faint_sharp_wire_is_found_beside_its_followed_shadow_and_not_the_other_way() {
        // A faint wire (sigma 0.6 px, 50 levels) at 95 deg and its soft shadow (sigma
        // 2.5 px, 60 levels) 2.5 deg from it: at the band's middle (110 px) 4.8 px apart.
        let (wire, shadow) = (95f64.to_radians(), 97.5f64.to_radians());
        let mut tr = test_tracker((80f64.to_radians(), 110f64.to_radians()));
        let (sharp, soft) = (gauss(0.6), gauss(2.5));
        tr.small = frame(&[(wire, 50.0, &sharp), (shadow, 60.0, &soft)]);
        let on_shadow = sharper_beside(&tr.view().unwrap(), shadow);
        assert!(
            on_shadow
                .iter()
                .any(|o| (o - (wire - shadow)).abs() < 0.3f64.to_radians()),
            "followed on the shadow, the wire beside it not found: {on_shadow:?}"
        );
        let on_wire = sharper_beside(&tr.view().unwrap(), wire);
        assert!(
            on_wire
                .iter()
                .all(|o| (o - (shadow - wire)).abs() > 1f64.to_radians()),
            "followed on the wire, its shadow found sharper: {on_wire:?}"
        );
        // Twelve looks on the shadow fail the check; twelve on the wire pass it (or
        // find nothing to judge).
        let looks = |a: f64, tr: &Tracker| vec![sharper_beside(&tr.view().unwrap(), a); 12];
        let c = beside_check(&looks(shadow, &tr)).expect("judged");
        assert!(!c.passed && c.value == 1.0, "{c:?}");
        assert!(beside_check(&looks(wire, &tr)).is_none_or(|c| c.passed));
    }

    #[test]
    fn sharp_lines_either_side_of_the_followed_one_are_not_one_line_beside_it() {
        // A wide line (sigma 3 px) followed, and a sharp one 3 deg either side of it, as
        // a rod's two edges would stand either side of its middle: each is found, and
        // the check leaves them be.
        let mid = 95f64.to_radians();
        let mut tr = test_tracker((80f64.to_radians(), 110f64.to_radians()));
        let (wide, sharp) = (gauss(3.0), gauss(0.6));
        let off = 3f64.to_radians();
        tr.small = frame(&[
            (mid, 80.0, &wide),
            (mid - off, 50.0, &sharp),
            (mid + off, 50.0, &sharp),
        ]);
        let found = sharper_beside(&tr.view().unwrap(), mid);
        for o in [-off, off] {
            assert!(
                found.iter().any(|x| (x - o).abs() < 0.3f64.to_radians()),
                "{found:?}"
            );
        }
        let looks = vec![found; 12];
        assert!(beside_check(&looks).is_none_or(|c| c.passed), "{looks:?}");
        // One edge alone is a line beside it.
        let one: Vec<Vec<f64>> = looks
            .iter()
            .map(|l| l.iter().copied().filter(|x| *x > 0.0).collect())
            .collect();
        assert!(!beside_check(&one).expect("judged").passed);
    }

    #[test]
    fn offsets_scattered_by_noise_or_too_few_looks_pass() {
        let deg = |d: f64| d.to_radians();
        // One look in three finds the same line: a third, passed.
        let mut looks: Vec<Vec<f64>> = (0..30)
            .map(|k| if k % 3 == 0 { vec![deg(2.0)] } else { vec![] })
            .collect();
        let c = beside_check(&looks).expect("judged");
        assert!(c.passed && (c.value - 1.0 / 3.0).abs() < 1e-12, "{c:?}");
        // Every look finds something, each somewhere else: passed.
        looks = (0..30).map(|k| vec![deg(-9.0 + 0.6 * k as f64)]).collect();
        assert!(beside_check(&looks).expect("judged").passed);
        // Nine looks, all finding it: too few to judge.
        assert!(beside_check(&vec![vec![deg(2.0)]; 9]).is_none());
        // Twenty looks, 11 on one side within 0.5 deg: failed, at 55 %.
        looks = (0..20)
            .map(|k| {
                if k < 11 {
                    vec![deg(2.0 + 0.04 * k as f64)]
                } else {
                    vec![]
                }
            })
            .collect();
        let c = beside_check(&looks).expect("judged");
        assert!(!c.passed && (c.value - 0.55).abs() < 1e-12, "{c:?}");
    }
}
