//! Step 1 of the plumb-line fit: the picture's edge points. Its gradient and noise are
//! worked out once ([`Gradients::of`]); the points over each threshold the fit tries
//! are picked from them ([`Gradients::edgels`]).

use super::{Grey, EDGE_MIN, EDGE_QUANTILE};

/// An edge point: where it is (px) and the unit normal of its edge.
#[derive(Clone, Copy, Debug)]
pub(super) struct Edgel {
    pub(super) p: [f64; 2],
    pub(super) n: [f64; 2],
}

/// A picture's grey gradient (smoothed by a 3x3 binomial, central differences) and its
/// noise: the fifth-quantile gradient size, on every second pixel of every second row.
pub(super) struct Gradients {
    w: usize,
    h: usize,
    gx: Vec<f32>,
    gy: Vec<f32>,
    mag: Vec<f32>,
    low: f64,
}

impl Gradients {
    /// The gradients of `pic`; none for a picture under 8 px a side.
    pub(super) fn of(pic: Grey) -> Option<Self> {
        let (w, h) = (pic.w, pic.h);
        if w < 8 || h < 8 {
            return None;
        }
        // 3x3 binomial smoothing, separable.
        let mut tmp = vec![0f32; w * h];
        for y in 0..h {
            let row = &pic.data[y * w..(y + 1) * w];
            for x in 1..w - 1 {
                tmp[y * w + x] =
                    (f32::from(row[x - 1]) + 2.0 * f32::from(row[x]) + f32::from(row[x + 1])) / 4.0;
            }
        }
        let mut s = vec![0f32; w * h];
        for y in 1..h - 1 {
            for x in 1..w - 1 {
                let i = y * w + x;
                s[i] = (tmp[i - w] + 2.0 * tmp[i] + tmp[i + w]) / 4.0;
            }
        }
        // Gradients by central differences, away from the smoothing's border.
        let mut gx = vec![0f32; w * h];
        let mut gy = vec![0f32; w * h];
        let mut mag = vec![0f32; w * h];
        for y in 2..h - 2 {
            for x in 2..w - 2 {
                let i = y * w + x;
                gx[i] = (s[i + 1] - s[i - 1]) / 2.0;
                gy[i] = (s[i + w] - s[i - w]) / 2.0;
                mag[i] = gx[i].hypot(gy[i]);
            }
        }
        let mut inner: Vec<f32> = Vec::with_capacity((w / 2) * (h / 2));
        for y in (2..h - 2).step_by(2) {
            for x in (2..w - 2).step_by(2) {
                inner.push(mag[y * w + x]);
            }
        }
        let at_q = (inner.len() as f64 * EDGE_QUANTILE) as usize;
        let low = f64::from(*inner.select_nth_unstable_by(at_q, f32::total_cmp).1);
        Some(Self {
            w,
            h,
            gx,
            gy,
            mag,
            low,
        })
    }

    /// The edge points whose gradient is over `times` the picture's noise (and at
    /// least [`EDGE_MIN`]) and a local maximum across the edge, each placed to a
    /// fraction of a pixel by a parabola through the gradient's size across it.
    pub(super) fn edgels(&self, times: f64) -> Vec<Edgel> {
        let (w, h, mag) = (self.w, self.h, &self.mag);
        let threshold = (times * self.low).max(EDGE_MIN) as f32;
        let at = |x: f64, y: f64| -> f64 {
            // Bilinear, inside [2, w-3] x [2, h-3].
            let (x0, y0) = (x.floor() as usize, y.floor() as usize);
            let (fx, fy) = (x - x0 as f64, y - y0 as f64);
            let i = y0 * w + x0;
            let m = |k: usize| f64::from(mag[k]);
            (1.0 - fy) * ((1.0 - fx) * m(i) + fx * m(i + 1))
                + fy * ((1.0 - fx) * m(i + w) + fx * m(i + w + 1))
        };
        let mut out = Vec::new();
        for y in 3..h - 3 {
            for x in 3..w - 3 {
                let i = y * w + x;
                let m0 = mag[i];
                if m0 < threshold {
                    continue;
                }
                let (nx, ny) = (f64::from(self.gx[i] / m0), f64::from(self.gy[i] / m0));
                let (xf, yf) = (x as f64, y as f64);
                let (mm, mp) = (at(xf - nx, yf - ny), at(xf + nx, yf + ny));
                let m0 = f64::from(m0);
                if !(m0 >= mm && m0 > mp) {
                    continue;
                }
                let den = mm - 2.0 * m0 + mp;
                let off = if den < 0.0 {
                    (0.5 * (mm - mp) / den).clamp(-0.5, 0.5)
                } else {
                    0.0
                };
                out.push(Edgel {
                    p: [xf + off * nx, yf + off * ny],
                    n: [nx, ny],
                });
            }
        }
        out
    }
}
