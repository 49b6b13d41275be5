//! The frame's light against the first frame's, fitted for each alignment.

use super::align::{biweight, Reader};
use super::{Level, Motion};
use crate::detect::tuning::{EXPLAIN_PX, LIGHT_LEVELS, LIGHT_ROUNDS, MAX_GAIN};
use anyhow::Result;
use opencv::core::Mat;

/// The frame's greys against the first's: `first = gain * frame + offset` on the static
/// scene (the lights drift, a camera's exposure follows the scene). Fitted for each frame,
/// from the median difference, on the pixels that agree: a frame's own level and contrast
/// would move with a person walking through part of it, and leave every pixel of the
/// rest more than `TUKEY_LEVELS` off (the alignment then followed whatever still matched:
/// 40 px astray on a hand-held twin).
#[derive(Clone, Copy, Debug)]
pub(super) struct Light {
    pub(super) gain: f32,
    pub(super) offset: f32,
}

impl Light {
    /// The median difference of the first frame's greys from the frame's, read through
    /// motion `m`, as the offset (gain 1).
    pub(super) fn at(level: &Level, img: &Mat, m: Motion) -> Result<Self> {
        let at = Reader::new(level, img, m)?;
        // Each pixel read once: the frame's grey, the first frame's, and the tolerance of
        // their difference, where it shows.
        let n = level.points.len();
        let (mut g, mut r, mut tol) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for p in &level.points {
            if let Some(grey) = at.grey(p) {
                g.push(grey);
                r.push(p.grey);
                tol.push(LIGHT_LEVELS + EXPLAIN_PX * p.gradient);
            }
        }
        let mut d: Vec<f32> = g.iter().zip(&r).map(|(&g, &r)| r - g).collect();
        let offset = if d.is_empty() {
            0.0
        } else {
            let k = d.len() / 2;
            *d.select_nth_unstable_by(k, f32::total_cmp).1
        };
        let mut light = Self { gain: 1.0, offset };
        // Then the gain and offset refitted on the pixels within a wide tolerance (the
        // frame not yet aligned) of the line: each round's weights in one pass (the
        // division in lanes), then their sums in the pixels' order.
        let mut w = d;
        for _ in 0..LIGHT_ROUNDS {
            for (((w, &g), &r), &t) in w.iter_mut().zip(&g).zip(&r).zip(&tol) {
                let v = biweight(light.gain * g + light.offset - r, t);
                *w = v * v;
            }
            let mut sums = Sums::default();
            for ((&w, &g), &r) in w.iter().zip(&g).zip(&r) {
                sums.add(f64::from(w), f64::from(g), f64::from(r));
            }
            light.refit(&sums);
        }
        Ok(light)
    }

    /// Fitted anew from the weighted sums of the pixels read, when they fix a gain
    /// within [`1 / MAX_GAIN`, `MAX_GAIN`]: the ratio of the greys' spreads, not the
    /// regression's slope (with the frame not yet aligned, the greys agree less and the
    /// slope shrinks towards 0, and the alignment's steps with it: 0.25 and a tenth of a
    /// pixel a step, on a frame a person darkened two fifths of).
    pub(super) fn refit(&mut self, s: &Sums) {
        if s.w < 1.0 {
            return;
        }
        let (mg, mr) = (s.g / s.w, s.r / s.w);
        let var_g = s.gg / s.w - mg * mg;
        let var_r = s.rr / s.w - mr * mr;
        let cov = s.gr / s.w - mg * mr;
        if var_g <= 1e-6 || var_r <= 1e-6 || cov <= 0.0 {
            return;
        }
        let gain = (var_r / var_g).sqrt();
        if !(1.0 / MAX_GAIN..=MAX_GAIN).contains(&gain) {
            return;
        }
        self.gain = gain as f32;
        self.offset = (mr - gain * mg) as f32;
    }
}

/// Weighted sums of the frame's greys `g` and the first frame's `r` at the pixels read.
#[derive(Default)]
pub(super) struct Sums {
    w: f64,
    g: f64,
    gg: f64,
    r: f64,
    rr: f64,
    gr: f64,
}

impl Sums {
    pub(super) fn add(&mut self, w: f64, g: f64, r: f64) {
        self.w += w;
        self.g += w * g;
        self.gg += w * g * g;
        self.r += w * r;
        self.rr += w * r * r;
        self.gr += w * g * r;
    }
}
