//! How much of the wire a pixel's evidence shows. A thin wire that covers a share `k`
//! of a pixel changes it by `k` times the contrast between the wire and what lies
//! behind it: a dark wire darkens a pixel of the plate's level `b` by about `k b` (a
//! black wire, the light falling on both alike), and lightens it towards white by
//! `k (255 - b)` when the wire is light. The line fits weigh each pixel by its evidence
//! divided by that contrast ([`Contrast::weight`]), so that the wire's profile across
//! it keeps its shape where the background is darker on one side than on the other (a
//! tick of a protractor, a numeral, a shadow's edge), instead of leaning away from the
//! darker side.
//!
//! Where a static mark of the scene is nearly as dark as the wire itself (or as light,
//! for a light wire), no division brings the wire back: the pixel shows nothing of it.
//! Such marks ([`static_marks`]) are left out of the fits, and with each its mirror
//! image across the fitted line, so that the pixels kept lie evenly on both sides of
//! it. A 1280x720 twin's dark wire crossing a protractor's ticks (robustness seed 1,
//! scene 39) leaned towards its rest direction: swing 0.42 % small, angle RMS 0.028
//! deg; with both, 0.10 % and 0.007 deg.

use crate::detect::tuning::{
    CONTRAST_FLOOR, MARKS_MAX_SHARE, MARK_MIN_LEVELS, MARK_SHARE, MARK_SIZE, WEIGHT_SCALE,
};
use anyhow::Result;
use opencv::core::{self, Mat};
use opencv::imgproc;
use opencv::prelude::*;

/// The contrast behind each pixel for a dark or a light wire, and the static marks.
pub(super) struct Contrast {
    /// Per grey level of the background, the contrast the evidence is divided by.
    denominator: [f64; 256],
    /// 1 where a static mark hides the wire, row-major over the region.
    marks: Vec<u8>,
}

impl Contrast {
    /// For a dark (`dark`) or light wire, with the marks of the background `bg`.
    pub(super) fn new(bg: &Mat, dark: bool) -> Result<Self> {
        Ok(Self {
            denominator: std::array::from_fn(|b| {
                let b = b as f64;
                let c = if dark { b } else { 255.0 - b };
                c.max(CONTRAST_FLOOR)
            }),
            marks: static_marks(bg, dark)?,
        })
    }

    /// The weight of evidence `ev` at a pixel whose background is `bg`.
    #[inline]
    pub(super) fn weight(&self, ev: u8, bg: u8) -> f64 {
        ev as f64 * WEIGHT_SCALE / self.denominator[bg as usize]
    }

    /// Whether pixel `i` (row-major over the region) is a static mark.
    #[inline]
    pub(super) fn is_mark(&self, i: usize) -> bool {
        self.marks[i] != 0
    }

    /// The share of the region's pixels that are marks.
    pub(super) fn marked_share(&self) -> f64 {
        let n = self.marks.iter().filter(|&&m| m != 0).count();
        n as f64 / self.marks.len().max(1) as f64
    }
}

/// The static marks of a background (`CV_8UC1`): 1 where a closing (dark wire) or an
/// opening (light wire) by a [`MARK_SIZE`] ellipse moves the pixel by more than
/// [`MARK_MIN_LEVELS`] and [`MARK_SHARE`] of the surroundings' level; none when they
/// cover more than [`MARKS_MAX_SHARE`] of it.
pub(super) fn static_marks(bg: &Mat, dark: bool) -> Result<Vec<u8>> {
    let n = bg.rows().max(0) as usize * bg.cols().max(0) as usize;
    if n == 0 {
        return Ok(Vec::new());
    }
    let element = imgproc::get_structuring_element(
        imgproc::MORPH_ELLIPSE,
        core::Size::new(MARK_SIZE, MARK_SIZE),
        core::Point::new(-1, -1),
    )?;
    let mut around = Mat::default();
    imgproc::morphology_ex(
        bg,
        &mut around,
        if dark {
            imgproc::MORPH_CLOSE
        } else {
            imgproc::MORPH_OPEN
        },
        &element,
        core::Point::new(-1, -1),
        1,
        core::BORDER_REPLICATE,
        imgproc::morphology_default_border_value()?,
    )?;
    let marks: Vec<u8> = bg
        .data_bytes()?
        .iter()
        .zip(around.data_bytes()?)
        .map(|(&b, &a)| {
            let lift = if dark {
                a as f64 - b as f64
            } else {
                b as f64 - a as f64
            };
            u8::from(lift > MARK_MIN_LEVELS.max(MARK_SHARE * a as f64))
        })
        .collect();
    let marked = marks.iter().filter(|&&m| m != 0).count();
    if marked as f64 > MARKS_MAX_SHARE * n as f64 {
        return Ok(vec![0; n]);
    }
    Ok(marks)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mat(w: usize, h: usize, px: &[u8]) -> Mat {
        Mat::new_rows_cols_with_data(h as i32, w as i32, px)
            .unwrap()
            .try_clone()
            .unwrap()
    }

    #[test]
    fn a_dark_tick_on_a_plain_plate_is_a_mark_and_the_plate_is_not() {
        let (w, h) = (40, 30);
        let mut px = vec![180u8; w * h];
        // A tick 2 px wide, 60 levels darker; a gentle shading elsewhere.
        for y in 0..h {
            for x in 0..w {
                px[y * w + x] = (170 + x / 4) as u8;
            }
            px[y * w + 20] = 110;
            px[y * w + 21] = 110;
        }
        let marks = static_marks(&mat(w, h, &px), true).unwrap();
        for y in 0..h {
            for x in 0..w {
                let want = x == 20 || x == 21;
                assert_eq!(marks[y * w + x] != 0, want, "({x}, {y})");
            }
        }
        // For a light wire the same tick hides nothing (it is darker, not lighter).
        let light = static_marks(&mat(w, h, &px), false).unwrap();
        assert!(light.iter().all(|&m| m == 0));
    }

    #[test]
    fn a_faint_tick_is_not_a_mark() {
        // 6 grey levels under MARK_MIN_LEVELS, and 4 % of the level.
        let (w, h) = (30, 20);
        let mut px = vec![150u8; w * h];
        for y in 0..h {
            px[y * w + 15] = 144;
        }
        let marks = static_marks(&mat(w, h, &px), true).unwrap();
        assert!(marks.iter().all(|&m| m == 0));
    }

    #[test]
    fn a_textured_background_has_no_marks() {
        // Dark grain every third column: a third of the region would be marks.
        let (w, h) = (30, 20);
        let px: Vec<u8> = (0..w * h)
            .map(|i| if (i % w) % 3 == 0 { 60 } else { 200 })
            .collect();
        let marks = static_marks(&mat(w, h, &px), true).unwrap();
        assert!(marks.iter().all(|&m| m == 0));
    }

    #[test]
    fn the_weight_is_the_evidence_over_the_contrast_behind_it() {
        let bg = mat(4, 4, &[200u8; 16]);
        let dark = Contrast::new(&bg, true).unwrap();
        // 20 levels darker on a plate of 200 and 10 darker on a mark of 100: the same
        // coverage, the same weight.
        assert_eq!(dark.weight(20, 200), dark.weight(10, 100));
        assert_eq!(dark.weight(20, 200), 10.0);
        // Below the floor the contrast is taken as CONTRAST_FLOOR.
        assert_eq!(dark.weight(5, 3), 50.0);
        let light = Contrast::new(&bg, false).unwrap();
        // A light wire: the contrast is the way up to white.
        assert_eq!(light.weight(20, 155), 20.0);
        assert_eq!(light.weight(20, 255), 200.0);
    }
}
