//! A frame shrunk by a whole factor `k` of 3 or more: each pixel the mean of a `k` x `k`
//! block, rounded as OpenCV's `INTER_AREA` rounds it at such a factor (the block's sum
//! times `1 / k^2` in single precision, to the nearest, ties to even). The streaming
//! pass shrinks every frame of its region so when the working scale is coarser than the
//! video's (a 1920x1080 video at the default side: 3 x 3 blocks); OpenCV's path for
//! these factors visits the block's pixels one by one through a table of offsets, and
//! took a third of a still 1920x1080 twin's streaming pass. Here the block's rows are
//! summed a whole row at a time (runs of bytes the compiler vectorises), then each
//! block's columns; the result is OpenCV's to the byte (test below). At 2 OpenCV has a
//! path of its own in vector registers, no slower than this one (paired on the 1280x720
//! bench twins), and it is used.

use anyhow::Result;
use opencv::core::{self, Mat, Scalar};
use opencv::imgproc;
use opencv::prelude::*;

/// Buffers kept from frame to frame.
#[derive(Default)]
pub(crate) struct Shrink {
    /// Per source column, the sum of the block's rows.
    rows: Vec<u16>,
    /// Per block's sum, its mean as OpenCV rounds it, for the factor `lut_k`.
    lut: Vec<u8>,
    lut_k: usize,
}

impl Shrink {
    /// `src` (`sw` x `sh` px, row-major) shrunk by block means into `small` (`w` x `h`
    /// px, 8-bit), as OpenCV's `INTER_AREA`: here by a whole factor of 3 or more, by
    /// OpenCV itself at 2 or at sizes that are not a whole number of blocks.
    pub(crate) fn area(
        &mut self,
        src: &[u8],
        (sw, sh): (usize, usize),
        small: &mut Mat,
        (w, h): (i32, i32),
    ) -> Result<()> {
        let (wu, hu) = (w.max(1) as usize, h.max(1) as usize);
        let k = sw / wu;
        if k >= 3 && (sw, sh) == (wu * k, hu * k) {
            if small.cols() != w || small.rows() != h || small.typ() != core::CV_8UC1 {
                *small = Mat::new_rows_cols_with_default(h, w, core::CV_8UC1, Scalar::all(0.0))?;
            }
            self.block_means(src, k, wu, hu, small.data_bytes_mut()?);
        } else {
            let full = Mat::new_rows_cols_with_data(sh as i32, sw as i32, src)?;
            imgproc::resize(
                &full,
                small,
                core::Size::new(w, h),
                0.0,
                0.0,
                imgproc::INTER_AREA,
            )?;
        }
        Ok(())
    }

    /// `src` (`w * k` x `h * k` px, row-major) shrunk `k` times into `out` (`w` x `h`
    /// px). `k` is at least 3 and at most 257 (a column's sum of `k` bytes fits 16
    /// bits).
    fn block_means(&mut self, src: &[u8], k: usize, w: usize, h: usize, out: &mut [u8]) {
        assert!(
            (2..=257).contains(&k),
            "a whole factor of 2 to 257, not {k}"
        );
        let sw = w * k;
        assert_eq!(src.len(), sw * h * k, "a {sw}x{} image", h * k);
        assert_eq!(out.len(), w * h, "a {w}x{h} image");
        if self.lut_k != k {
            let scale = 1.0f32 / (k * k) as f32;
            self.lut = (0..=255 * k * k)
                .map(|sum| (sum as f32 * scale).round_ties_even() as u8)
                .collect();
            self.lut_k = k;
        }
        self.rows.resize(sw, 0);
        if w == 0 {
            return;
        }
        for (y, out_row) in out.chunks_exact_mut(w).enumerate() {
            let block = &src[y * k * sw..(y + 1) * k * sw];
            let (first, rest) = block.split_at(sw);
            for (s, &v) in self.rows.iter_mut().zip(first) {
                *s = u16::from(v);
            }
            for row in rest.chunks_exact(sw) {
                for (s, &v) in self.rows.iter_mut().zip(row) {
                    *s += u16::from(v);
                }
            }
            match k {
                3 => columns::<3>(&self.rows, &self.lut, out_row),
                4 => columns::<4>(&self.rows, &self.lut, out_row),
                _ => {
                    for (o, cols) in out_row.iter_mut().zip(self.rows.chunks_exact(k)) {
                        let sum: u32 = cols.iter().map(|&c| u32::from(c)).sum();
                        *o = self.lut[sum as usize];
                    }
                }
            }
        }
    }
}

/// Each block of `K` columns of the rows' sums `rows`, its mean by `lut` into `out`.
fn columns<const K: usize>(rows: &[u16], lut: &[u8], out: &mut [u8]) {
    for (o, cols) in out.iter_mut().zip(rows.chunks_exact(K)) {
        let sum: u32 = cols.iter().map(|&c| u32::from(c)).sum();
        *o = lut[sum as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use opencv::core::Size;

    fn opencv_area(src: &[u8], k: usize, w: usize, h: usize) -> Vec<u8> {
        let m = Mat::new_rows_cols_with_data((h * k) as i32, (w * k) as i32, src).unwrap();
        let mut out = Mat::default();
        imgproc::resize(
            &m,
            &mut out,
            Size::new(w as i32, h as i32),
            0.0,
            0.0,
            imgproc::INTER_AREA,
        )
        .unwrap();
        out.data_bytes().unwrap().to_vec()
    }

    #[test]
    fn whole_factor_block_means_are_opencv_s_area_shrink_to_the_byte() {
        let mut rng = Rng::new(17);
        let mut shrink = Shrink::default();
        // Noise over the whole range; a dark plate with a thin bright line on a slope
        // and blocks whose sums fall on a half (ties) everywhere.
        for k in 3..=7 {
            for (w, h) in [(1, 1), (3, 2), (17, 5), (64, 33), (141, 139), (194, 180)] {
                for kind in 0..3 {
                    let (sw, sh) = (w * k, h * k);
                    let src: Vec<u8> = (0..sw * sh)
                        .map(|i| {
                            let (x, y) = ((i % sw) as f64, (i / sw) as f64);
                            let v = match kind {
                                0 => 255.0 * rng.uniform(),
                                1 => {
                                    20.0 + 6.0 * rng.uniform()
                                        + if (x - 0.7 * y).abs() < 1.0 {
                                            200.0
                                        } else {
                                            0.0
                                        }
                                }
                                _ => (((i % sw) + (i / sw)) % 2) as f64 * (1.0 + (x % 3.0)),
                            };
                            v.round().clamp(0.0, 255.0) as u8
                        })
                        .collect();
                    let mut out = vec![0u8; w * h];
                    shrink.block_means(&src, k, w, h, &mut out);
                    assert!(
                        out == opencv_area(&src, k, w, h),
                        "{sw}x{sh} shrunk {k} times, image of kind {kind}: the means differ"
                    );
                }
            }
        }
    }
}
