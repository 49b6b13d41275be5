//! BGR to planar Y'CbCr 4:2:0 (BT.601), the raw frames piped to `ffmpeg`.

/// BT.601 Y'CbCr: full range (JPEG's, `yuvj420p`) or limited range (video's, `yuv420p`:
/// luma 16..235, chroma 16..240).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum YuvRange {
    Full,
    Limited,
}

/// Fixed-point weights of the BGR to Y'CbCr conversion.
#[derive(Clone, Debug)]
struct YuvWeights {
    /// Luma weights of B, G and R, units of 2^-15, times every byte value (a table
    /// lookup costs less than a multiplication here).
    y: [[u32; 256]; 3],
    /// The sum of the weights (2^15 for full range).
    sum: i64,
    /// Luma offset plus one half, units of 2^-15.
    y_bias: u32,
    /// `Cb = 128 + cb (B - Y)` and `Cr = 128 + cr (R - Y)` with `Y` the unscaled luma,
    /// turned into factors on a 2x2 block's sums `sum * (B1 + .. + B4) - (L1 + .. + L4)`
    /// (`L` the luma before the shift), units of 2^-32.
    cb: i64,
    cr: i64,
}

impl YuvWeights {
    fn new(range: YuvRange) -> Self {
        let (ky, kc, y0) = match range {
            YuvRange::Full => (1.0, 1.0, 0.0),
            YuvRange::Limited => (219.0 / 255.0, 224.0 / 255.0, 16.0),
        };
        let (wb, wr) = (0.114, 0.299);
        let k = [wb, 1.0 - wb - wr, wr].map(|w: f64| (w * ky * 32768.0).round() as u32);
        let sum = k.iter().map(|&k| k as i64).sum::<i64>();
        let chroma = |w: f64| (kc * 0.5 / (1.0 - w) / (4.0 * sum as f64) * 2f64.powi(32)).round();
        Self {
            y: k.map(|k| std::array::from_fn(|v| k * v as u32)),
            sum,
            y_bias: ((y0 + 0.5) * 32768.0) as u32,
            cb: chroma(wb) as i64,
            cr: chroma(wr) as i64,
        }
    }
}

/// Convert a BGR frame (`w` x `h`, both even) to planar Y'CbCr 4:2:0 in `out`: the luma
/// plane, then Cb, then Cr (`w h 3 / 2` bytes, the layout of FFmpeg's `yuv420p`).
/// BT.601 in integer fixed point (within one grey level of the exact conversion); the
/// chroma of each 2x2 block is that of its mean colour. One pass over 2x2 blocks, with
/// the luma sums reused for the chroma.
pub(super) fn bgr_to_yuv420(bgr: &[u8], w: usize, h: usize, range: YuvRange, out: &mut Vec<u8>) {
    debug_assert!(w.is_multiple_of(2) && h.is_multiple_of(2) && bgr.len() == 3 * w * h);
    out.resize(w * h * 3 / 2, 0);
    let k = YuvWeights::new(range);
    let (luma, chroma) = out.split_at_mut(w * h);
    let (cb_plane, cr_plane) = chroma.split_at_mut(w * h / 4);
    let [yb, yg, yr] = &k.y;
    let weigh = |p: &[u8]| yb[p[0] as usize] + yg[p[1] as usize] + yr[p[2] as usize];
    let bias = (128i64 << 32) + (1 << 31);
    let rows = bgr.chunks_exact(6 * w).zip(luma.chunks_exact_mut(2 * w));
    let planes = cb_plane
        .chunks_exact_mut(w / 2)
        .zip(cr_plane.chunks_exact_mut(w / 2));
    for ((two, lum), (cbs, crs)) in rows.zip(planes) {
        let (top, bottom) = two.split_at(3 * w);
        let (y_top, y_bottom) = lum.split_at_mut(w);
        let blocks = top.chunks_exact(6).zip(bottom.chunks_exact(6));
        let outs = y_top.chunks_exact_mut(2).zip(y_bottom.chunks_exact_mut(2));
        for (((a, b), (ya, yb)), (cb, cr)) in blocks.zip(outs).zip(cbs.iter_mut().zip(crs)) {
            let l = [
                weigh(&a[..3]),
                weigh(&a[3..]),
                weigh(&b[..3]),
                weigh(&b[3..]),
            ];
            ya[0] = ((l[0] + k.y_bias) >> 15) as u8;
            ya[1] = ((l[1] + k.y_bias) >> 15) as u8;
            yb[0] = ((l[2] + k.y_bias) >> 15) as u8;
            yb[1] = ((l[3] + k.y_bias) >> 15) as u8;
            let sl = (l[0] + l[1] + l[2] + l[3]) as i64;
            let sb = (a[0] as u32 + a[3] as u32 + b[0] as u32 + b[3] as u32) as i64;
            let sr = (a[2] as u32 + a[5] as u32 + b[2] as u32 + b[5] as u32) as i64;
            *cb = (((sb * k.sum - sl) * k.cb + bias) >> 32).clamp(0, 255) as u8;
            *cr = (((sr * k.sum - sl) * k.cr + bias) >> 32).clamp(0, 255) as u8;
        }
    }
}
