//! The white top-hat by OpenCV's 7 x 7 elliptic structuring element, on grey bytes, as
//! the first look needs it for each frame it searches for lines and the streaming
//! pass for every frame's wedge: the image less its opening (the
//! erosion, then the dilation). OpenCV's general morphology visits the element's 33
//! pixels for every pixel and builds a filter engine per call; here the element is
//! the union of three rectangles (1 x 7, 5 x 5 and 7 x 3: the rows of
//! `getStructuringElement(MORPH_ELLIPSE, 7x7)` are 1, 5, 7, 7, 7, 5 and 1 pixels
//! wide), so each extreme is the extreme of three separable rectangle passes. Each
//! pass shifts the whole image against itself (by pixels along the rows, by whole
//! rows down the columns): long runs of bytes the compiler vectorises. The rows are
//! padded on either side with the extreme's neutral byte (255 for the erosion, 0 for
//! the dilation), so that no shift along a row reaches the next row's pixels and
//! pixels beyond the image are left out of every extreme, as OpenCV's default border
//! for morphology does; the result is OpenCV's to the byte (test below).

/// Buffers of one image's top-hat, kept from frame to frame.
#[derive(Default)]
pub(crate) struct Morph {
    a: Vec<u8>,
    b: Vec<u8>,
    padded: Vec<u8>,
    eroded: Vec<u8>,
    opened: Vec<u8>,
}

/// Padding on either side of a row: the rectangles' widest half width.
const PAD: usize = 3;

impl Morph {
    /// The top-hat of the `w` x `h` image `src` (row-major) into `out` (resized).
    pub(crate) fn tophat(&mut self, src: &[u8], w: usize, h: usize, out: &mut Vec<u8>) {
        assert_eq!(src.len(), w * h, "a {w}x{h} image");
        let Self {
            a,
            b,
            padded,
            eroded,
            opened,
        } = self;
        let wp = w + 2 * PAD;
        padded.clear();
        for row in src.chunks_exact(w.max(1)).take(h) {
            padded.extend_from_slice(&[u8::MAX; PAD]);
            padded.extend_from_slice(row);
            padded.extend_from_slice(&[u8::MAX; PAD]);
        }
        extreme::<Min>(padded, wp, eroded, a, b);
        // The dilation's neutral byte in the padding.
        for row in eroded.chunks_exact_mut(wp) {
            row[..PAD].fill(0);
            row[PAD + w..].fill(0);
        }
        extreme::<Max>(eroded, wp, opened, a, b);
        out.clear();
        for (row, o) in src.chunks_exact(w.max(1)).zip(opened.chunks_exact(wp)) {
            out.extend(row.iter().zip(&o[PAD..]).map(|(s, o)| s.saturating_sub(*o)));
        }
    }
}

/// The erosion (`F` = [`Min`]) or dilation ([`Max`]) by the element of the padded image
/// `src` (rows `wp` bytes long), into `out` (`a` and `b` are scratch): exact on the
/// image's own pixels. A window of radius `k + 1` is the extreme of two of radius `k`
/// one step apart, so the columns' extremes within 1, 2 and 3 rows follow one from
/// another (and so do the rows' within 1, 2 and 3 pixels): the rectangles 1 x 7, 5 x 5
/// and 7 x 3 are then the extremes within 3 rows, within 2 pixels of those within 2
/// rows, and within 3 pixels of those within 1 row.
fn extreme<F: Extreme>(src: &[u8], wp: usize, out: &mut Vec<u8>, a: &mut Vec<u8>, b: &mut Vec<u8>) {
    // a = within 1 row; out = within 3 rows (1 x 7).
    step::<F>(src, wp, a);
    step::<F>(a, wp, b);
    step::<F>(b, wp, out);
    // Within 2 rows and 2 pixels (5 x 5), into out.
    let mut c = std::mem::take(b);
    step::<F>(&c, 1, b);
    step::<F>(b, 1, &mut c);
    combine::<F>(out, &c);
    // Within 1 row and 3 pixels (7 x 3), into out.
    step::<F>(a, 1, b);
    step::<F>(b, 1, &mut c);
    step::<F>(&c, 1, b);
    combine::<F>(out, b);
    *b = c;
}

/// `out` = the extreme of each element of `src` and its neighbours `by` elements before
/// and after it (`by` = 1 along a padded row; a row's length down a column), each
/// within `src`.
fn step<F: Extreme>(src: &[u8], by: usize, out: &mut Vec<u8>) {
    let n = src.len();
    out.clear();
    if n < 2 * by {
        // Too short for an element with neighbours on both sides.
        out.extend_from_slice(src);
        if by < n {
            combine::<F>(&mut out[..n - by], &src[by..]);
            combine::<F>(&mut out[by..], &src[..n - by]);
        }
        return;
    }
    // One pass, written once: the first `by` elements have no neighbour before them,
    // the last `by` none after, the rest both.
    out.reserve(n);
    out.extend(
        src[..by]
            .iter()
            .zip(&src[by..2 * by])
            .map(|(a, b)| F::of(*a, *b)),
    );
    out.extend(
        src[..n - 2 * by]
            .iter()
            .zip(&src[by..n - by])
            .zip(&src[2 * by..])
            .map(|((a, b), c)| F::of(F::of(*a, *b), *c)),
    );
    out.extend(
        src[n - 2 * by..n - by]
            .iter()
            .zip(&src[n - by..])
            .map(|(a, b)| F::of(*a, *b)),
    );
}

/// The minimum or the maximum of two bytes (a type, so that each pass is compiled for
/// its own and vectorised).
trait Extreme {
    fn of(a: u8, b: u8) -> u8;
}
struct Min;
struct Max;
impl Extreme for Min {
    #[inline(always)]
    fn of(a: u8, b: u8) -> u8 {
        a.min(b)
    }
}
impl Extreme for Max {
    #[inline(always)]
    fn of(a: u8, b: u8) -> u8 {
        a.max(b)
    }
}

/// `a` becomes the pixelwise extreme of `a` and `b`.
#[inline(always)]
fn combine<F: Extreme>(a: &mut [u8], b: &[u8]) {
    for (x, y) in a.iter_mut().zip(b) {
        *x = F::of(*x, *y);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The element's rectangles, as [`extreme`] makes them: (half width, half
    /// height).
    const RECTS: [(usize, usize); 3] = [(0, 3), (2, 2), (3, 1)];
    use opencv::core::{self, Mat, Size};
    use opencv::imgproc;
    use opencv::prelude::*;

    fn opencv_tophat(src: &[u8], w: usize, h: usize) -> Vec<u8> {
        let m = Mat::new_rows_cols_with_data(h as i32, w as i32, src)
            .unwrap()
            .try_clone()
            .unwrap();
        let kernel =
            imgproc::get_structuring_element_def(imgproc::MORPH_ELLIPSE, Size::new(7, 7)).unwrap();
        let mut out = Mat::default();
        imgproc::morphology_ex_def(&m, &mut out, imgproc::MORPH_TOPHAT, &kernel).unwrap();
        assert_eq!(out.typ(), core::CV_8UC1);
        out.data_bytes().unwrap().to_vec()
    }

    #[test]
    fn the_element_is_opencv_s_seven_pixel_ellipse() {
        let kernel =
            imgproc::get_structuring_element_def(imgproc::MORPH_ELLIPSE, Size::new(7, 7)).unwrap();
        for y in 0..7usize {
            for x in 0..7usize {
                let (dx, dy) = (x.abs_diff(3), y.abs_diff(3));
                let ours = RECTS.iter().any(|&(rx, ry)| dx <= rx && dy <= ry);
                let theirs = *kernel.at_2d::<u8>(y as i32, x as i32).unwrap() != 0;
                assert_eq!(ours, theirs, "element pixel ({x}, {y})");
            }
        }
    }

    #[test]
    fn the_top_hat_is_opencv_s_to_the_byte() {
        let mut rng = Rng::new(11);
        let mut morph = Morph::default();
        let mut out = Vec::new();
        // Sizes narrower and shorter than the element too; noise, and thin lines on a
        // slope (what the evidence holds).
        for (w, h) in [(1, 1), (3, 2), (6, 7), (7, 6), (13, 9), (40, 31), (97, 64)] {
            for kind in 0..3 {
                let src: Vec<u8> = (0..w * h)
                    .map(|i| {
                        let (x, y) = ((i % w) as f64, (i / w) as f64);
                        let v = match kind {
                            0 => 255.0 * rng.uniform(),
                            1 => {
                                8.0 * rng.uniform()
                                    + if (x - 0.4 * y).abs() < 1.0 { 90.0 } else { 0.0 }
                            }
                            _ => {
                                30.0 + 0.5 * x
                                    + 3.0 * rng.normal()
                                    + if (y - 0.3 * x - 2.0).abs() < 1.5 {
                                        60.0
                                    } else {
                                        0.0
                                    }
                            }
                        };
                        v.round().clamp(0.0, 255.0) as u8
                    })
                    .collect();
                morph.tophat(&src, w, h, &mut out);
                assert!(
                    out == opencv_tophat(&src, w, h),
                    "{w}x{h} image of kind {kind}: the top-hats differ"
                );
            }
        }
    }
}
