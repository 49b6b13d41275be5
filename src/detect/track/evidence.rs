//! Where the wire can be: each frame's evidence is computed only in the rectangle
//! around the wedge the search will look at (the band of radii, the angles within the
//! gate of the prediction), not over the whole region of interest. The background
//! still follows every pixel of the region (`Tracker::step`): a pixel may enter the
//! wedge on any later frame.
//!
//! The wire's angle is the same as with the evidence of the whole region: the search
//! keeps only pixels in the wedge, the top-hat of a pixel depends on the pixels within
//! [`TOPHAT_REACH`] of it, and the strips the line fit walks stay within
//! [`EVIDENCE_MARGIN`] of the wedge.

use super::Tracker;
use crate::detect::tuning::EVIDENCE_MARGIN;
use crate::detect::Pt;
use anyhow::Result;
use opencv::core::{self, Mat, Rect, Scalar};
use opencv::prelude::*;
use std::f64::consts::{FRAC_PI_2, TAU};

/// How far the top-hat of a pixel reaches, px: the erosion and then the dilation of the
/// 7 x 7 structuring element, 3 px each ([`super::morph`]).
const TOPHAT_REACH: i32 = 6;

impl Tracker {
    /// The angle range searched: within three gates of the prediction (wider after
    /// refused frames), or every angle the wire was seen at without a prediction. Once
    /// the side of a wire-and-shadow pair the wire lies on is known, the range reaches
    /// past the pair's separation on that side: a track on the shadow then sees the
    /// wire beside it, and goes back to it.
    pub(super) fn search_wedge(&self, pred: Option<f64>) -> (f64, f64) {
        match pred {
            Some(p) => {
                let wdg = (3.0 * self.gate * (1.0 + self.since_good as f64)).max(2f64.to_radians());
                let (mut lo, mut hi) = (p - wdg, p + wdg);
                if let Some((side, sep)) = self.ridges.side() {
                    let reach = super::measure::Ridges::reach(sep);
                    if side > 0.0 {
                        hi = hi.max(p + reach);
                    } else {
                        lo = lo.min(p - reach);
                    }
                }
                (lo, hi)
            }
            None => (self.geo.theta_min - 0.35, self.geo.theta_max + 0.35),
        }
    }

    /// This frame's evidence (the top-hat of the difference from the background) in
    /// the rectangle of the wedge around `pred`; zero elsewhere.
    pub(super) fn evidence(&mut self, pred: Option<f64>) -> Result<()> {
        let (w, h) = (self.small.cols(), self.small.rows());
        self.wedge = self.search_wedge(pred);
        let radii = (self.r_lo, self.r_hi);
        let r = sector_rect(self.piv, radii, self.wedge, EVIDENCE_MARGIN, w, h);
        if self.ev.cols() != w || self.ev.rows() != h {
            self.ev = Mat::new_rows_cols_with_default(h, w, core::CV_8UC1, Scalar::all(0.0))?;
        } else {
            // The last frame's rectangle back to zero where this frame's does not
            // overwrite it.
            clear_outside(self.ev.data_bytes_mut()?, w as usize, self.rect, r);
        }
        self.rect = r;
        if r.width == 0 || r.height == 0 {
            return Ok(());
        }
        // The difference where the top-hat of `r` reads it, the top-hat there, and its
        // exact part (`r`) into the evidence image.
        let outer = grow(r, TOPHAT_REACH, w, h);
        let (cols, x0, x1) = (
            w as usize,
            outer.x as usize,
            (outer.x + outer.width) as usize,
        );
        {
            let (bg, frame) = (self.bg.data_bytes()?, self.small.data_bytes()?);
            self.diff.clear();
            for y in outer.y as usize..(outer.y + outer.height) as usize {
                let (b, f) = (
                    &bg[y * cols + x0..y * cols + x1],
                    &frame[y * cols + x0..y * cols + x1],
                );
                if self.geo.dark {
                    self.diff
                        .extend(b.iter().zip(f).map(|(b, f)| b.saturating_sub(*f)));
                } else {
                    self.diff
                        .extend(f.iter().zip(b).map(|(f, b)| f.saturating_sub(*b)));
                }
            }
        }
        let ow = outer.width as usize;
        self.morph
            .tophat(&self.diff, ow, outer.height as usize, &mut self.ev_outer);
        let ev = self.ev.data_bytes_mut()?;
        let (dx, dy) = ((r.x - outer.x) as usize, (r.y - outer.y) as usize);
        let rw = r.width as usize;
        for k in 0..r.height as usize {
            let from = (dy + k) * ow + dx;
            let to = (r.y as usize + k) * cols + r.x as usize;
            ev[to..to + rw].copy_from_slice(&self.ev_outer[from..from + rw]);
        }
        Ok(())
    }
}

/// The pixels of a `cols` x `rows` image within `margin` px of the annular sector
/// about `piv` between radii `r_lo` and `r_hi` and angles `lo` to `hi` (rad, from +x
/// towards +y): its bounding box, grown by `margin` and cut to the image (empty when
/// the sector lies outside).
pub(super) fn sector_rect(
    piv: Pt,
    (r_lo, r_hi): (f64, f64),
    (lo, hi): (f64, f64),
    margin: f64,
    cols: i32,
    rows: i32,
) -> Rect {
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    let mut add = |th: f64, r: f64| {
        let p = piv + Pt::new(th.cos(), th.sin()) * r;
        x0 = x0.min(p.x);
        y0 = y0.min(p.y);
        x1 = x1.max(p.x);
        y1 = y1.max(p.y);
    };
    if hi - lo >= TAU {
        for k in 0..4 {
            add(k as f64 * FRAC_PI_2, r_hi);
        }
    } else {
        // The corners, and where the outer arc crosses an axis (its extremes in x, y).
        for th in [lo, hi] {
            add(th, r_lo);
            add(th, r_hi);
        }
        let (k0, k1) = (
            (lo / FRAC_PI_2).ceil() as i64,
            (hi / FRAC_PI_2).floor() as i64,
        );
        for k in k0..=k1 {
            add(k as f64 * FRAC_PI_2, r_hi);
        }
    }
    let left = ((x0 - margin).floor().max(0.0) as i32).min(cols);
    let top = ((y0 - margin).floor().max(0.0) as i32).min(rows);
    let right = (((x1 + margin).ceil() + 1.0).max(0.0) as i32).min(cols);
    let bottom = (((y1 + margin).ceil() + 1.0).max(0.0) as i32).min(rows);
    Rect::new(left, top, (right - left).max(0), (bottom - top).max(0))
}

/// Zero the pixels of rectangle `old` that lie outside rectangle `new` in an image of
/// `cols` bytes a row (both rectangles within it): the rows of `old` above and below
/// `new`, and on the rows they share, the parts left and right of it.
fn clear_outside(img: &mut [u8], cols: usize, old: Rect, new: Rect) {
    if old.width <= 0 || old.height <= 0 {
        return;
    }
    let (ox0, ox1) = (old.x as usize, (old.x + old.width) as usize);
    let (nx0, nx1) = (new.x as usize, (new.x + new.width) as usize);
    let shared = |y: i32| new.width > 0 && (new.y..new.y + new.height).contains(&y);
    for y in old.y..old.y + old.height {
        let row = &mut img[y as usize * cols..][..cols];
        if shared(y) {
            row[ox0..nx0.clamp(ox0, ox1)].fill(0);
            row[nx1.clamp(ox0, ox1)..ox1].fill(0);
        } else {
            row[ox0..ox1].fill(0);
        }
    }
}

/// `r` grown by `by` px on every side, cut to a `cols` x `rows` image.
fn grow(r: Rect, by: i32, cols: i32, rows: i32) -> Rect {
    let (left, top) = ((r.x - by).max(0), (r.y - by).max(0));
    let right = (r.x + r.width + by).min(cols);
    let bottom = (r.y + r.height + by).min(rows);
    Rect::new(left, top, right - left, bottom - top)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inside(r: Rect, x: i32, y: i32) -> bool {
        x >= r.x && x < r.x + r.width && y >= r.y && y < r.y + r.height
    }

    #[test]
    fn every_pixel_of_the_sector_lies_in_its_rectangle_and_the_rectangle_is_tight() {
        let piv = Pt::new(200.3, 140.7);
        let (cols, rows) = (400, 300);
        // Wedges hanging down, across -x (the angles unwrapped past pi), and a full turn.
        for (lo, hi) in [(1.4, 1.7), (2.9, 3.5), (-0.2, 0.3), (0.0, 7.0)] {
            let r = sector_rect(piv, (30.0, 120.0), (lo, hi), 0.0, cols, rows);
            let (mut x0, mut x1) = (i32::MAX, i32::MIN);
            for y in 0..rows {
                for x in 0..cols {
                    let d = Pt::new(x as f64, y as f64) - piv;
                    let th = crate::detect::unwrap_near(d.y.atan2(d.x), 0.5 * (lo + hi));
                    let full = hi - lo >= TAU;
                    if d.norm() >= 30.0 && d.norm() <= 120.0 && (full || (th >= lo && th <= hi)) {
                        assert!(
                            inside(r, x, y),
                            "({x}, {y}) of wedge {lo}..{hi} outside {r:?}"
                        );
                        x0 = x0.min(x);
                        x1 = x1.max(x);
                    }
                }
            }
            // Tight to within two pixels on either side (the sector's corners fall between
            // pixels).
            if x1 >= x0 {
                assert!(
                    x0 - r.x <= 2 && r.x + r.width - 1 - x1 <= 2,
                    "{lo}..{hi}: {r:?} vs {x0}..{x1}"
                );
            }
        }
        // A wedge that points off the image has an empty rectangle.
        let r = sector_rect(
            Pt::new(10.0, 10.0),
            (20.0, 50.0),
            (-1.7, -1.4),
            0.0,
            cols,
            rows,
        );
        assert_eq!(r.height, 0, "{r:?}");
    }

    #[test]
    fn clearing_outside_leaves_zero_where_only_the_old_rectangle_was() {
        let (cols, rows) = (30, 20);
        let cases = [
            (Rect::new(5, 4, 10, 8), Rect::new(8, 2, 6, 14)),
            (Rect::new(5, 4, 10, 8), Rect::new(0, 6, 30, 2)),
            (Rect::new(5, 4, 10, 8), Rect::new(20, 0, 5, 5)),
            (Rect::new(5, 4, 10, 8), Rect::new(0, 0, 0, 0)),
            (Rect::new(0, 0, 30, 20), Rect::new(3, 3, 4, 4)),
            (Rect::new(0, 0, 0, 0), Rect::new(3, 3, 4, 4)),
        ];
        for (old, new) in cases {
            let mut img = vec![9u8; cols * rows];
            clear_outside(&mut img, cols, old, new);
            for y in 0..rows as i32 {
                for x in 0..cols as i32 {
                    let want = if inside(old, x, y) && !inside(new, x, y) {
                        0
                    } else {
                        9
                    };
                    assert_eq!(
                        img[y as usize * cols + x as usize],
                        want,
                        "({x}, {y}) for {old:?} then {new:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn growing_stays_in_the_image() {
        let r = grow(Rect::new(2, 5, 10, 10), 6, 15, 100);
        assert_eq!(r, Rect::new(0, 0, 15, 21));
    }
}
