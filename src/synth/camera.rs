//! What the camera adds to the scene: a hand passing (a spoiler) and the sensor's
//! noise, drift and flicker.

use super::look::{pt, to_u8};
use super::plan::stream;
use crate::rng::Rng;
use anyhow::Result;
use opencv::core::{self, Mat, Point, Scalar, Size};
use opencv::imgproc;
use opencv::prelude::*;
use std::f64::consts::PI;

// ---------------------------------------------------------------------------------------
// Spoilers: a hand passing.

/// Masks reused between hand frames.
#[derive(Default)]
pub(super) struct HandPainter {
    mask: Mat,
    shadow: Mat,
    shade: Mat,
    tmp: Mat,
}

/// A hand seen from above, fingers along local -y, arm along local +y; `u` is about a
/// finger's width.
fn draw_hand(m: &mut Mat, c: [f64; 2], u: f64, tilt: f64) -> Result<()> {
    let (ca, sa) = (tilt.cos(), tilt.sin());
    let at = |x: f64, y: f64| {
        pt(
            c[0] + ca * x * u - sa * y * u,
            c[1] + sa * x * u + ca * y * u,
        )
    };
    let white = Scalar::all(255.0);
    let th = |k: f64| ((k * u).round() as i32).max(1);
    imgproc::ellipse(
        m,
        at(0.0, 0.0),
        Size::new((1.55 * u * 16.0) as i32, (1.8 * u * 16.0) as i32),
        tilt.to_degrees(),
        0.0,
        360.0,
        white,
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    for (bx, len, spread) in [
        (-1.0, 1.9, -0.3),
        (-0.34, 2.35, -0.1),
        (0.34, 2.25, 0.1),
        (1.0, 1.75, 0.3),
    ] {
        imgproc::line(
            m,
            at(bx, -1.2),
            at(bx + spread, -1.2 - len),
            white,
            th(0.64),
            imgproc::LINE_AA,
            4,
        )?;
    }
    imgproc::line(
        m,
        at(1.2, 0.4),
        at(2.5, -0.7),
        white,
        th(0.75),
        imgproc::LINE_AA,
        4,
    )?;
    imgproc::line(
        m,
        at(0.0, 1.2),
        at(0.4, 9.0),
        white,
        th(2.4),
        imgproc::LINE_AA,
        4,
    )?;
    Ok(())
}

impl HandPainter {
    /// Paint a hand centred at `c` over `frame`, blurred along x by `smear` px.
    pub(super) fn paint(
        &mut self,
        frame: &mut Mat,
        illum: &[f32],
        c: [f64; 2],
        u: f64,
        tilt: f64,
        smear: f64,
    ) -> Result<()> {
        let size = frame.size()?;
        let zero = || Mat::new_size_with_default(size, core::CV_8UC1, Scalar::all(0.0));
        let mut mask = zero()?;
        draw_hand(&mut mask, c, u, tilt)?;
        let mut shadow = zero()?;
        draw_hand(&mut shadow, [c[0] + 0.9 * u, c[1] + 1.3 * u], u, tilt)?;
        let k = ((smear.round() as i32) | 1).max(1);
        let line = Size::new(k, 1);
        let anchor = Point::new(-1, -1);
        // Shadow: soft, smeared.
        imgproc::gaussian_blur(
            &shadow,
            &mut self.tmp,
            Size::new(0, 0),
            0.8 * u,
            0.8 * u,
            core::BORDER_REFLECT,
        )?;
        imgproc::blur(
            &self.tmp,
            &mut self.shadow,
            line,
            anchor,
            core::BORDER_REFLECT,
        )?;
        // Shading: thick parts brighter than edges.
        imgproc::gaussian_blur(
            &mask,
            &mut self.tmp,
            Size::new(0, 0),
            0.6 * u,
            0.6 * u,
            core::BORDER_REFLECT,
        )?;
        imgproc::blur(
            &self.tmp,
            &mut self.shade,
            line,
            anchor,
            core::BORDER_REFLECT,
        )?;
        // Coverage: out of focus (nearer the camera) and smeared.
        let s = 0.06 * u + 1.0;
        imgproc::gaussian_blur(
            &mask,
            &mut self.tmp,
            Size::new(0, 0),
            s,
            s,
            core::BORDER_REFLECT,
        )?;
        imgproc::blur(
            &self.tmp,
            &mut self.mask,
            line,
            anchor,
            core::BORDER_REFLECT,
        )?;
        let skin = [112.0f32, 146.0, 198.0];
        let (a, sh, sd) = (
            self.mask.data_bytes()?,
            self.shadow.data_bytes()?,
            self.shade.data_bytes()?,
        );
        let buf = frame.data_bytes_mut()?;
        for i in 0..a.len() {
            if a[i] == 0 && sh[i] == 0 {
                continue;
            }
            let (al, s, t) = (
                a[i] as f32 / 255.0,
                sh[i] as f32 / 255.0,
                sd[i] as f32 / 255.0,
            );
            let il = illum[i].max(0.5) * 1.1;
            for ch in 0..3 {
                let base = buf[3 * i + ch] as f32 * (1.0 - 0.45 * s);
                let col = skin[ch] * (0.55 + 0.55 * t) * il;
                buf[3 * i + ch] = to_u8(base + (col - base) * al);
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------
// Sensor: noise, drift, flicker.

pub(super) struct Sensor {
    /// Gaussian noise, grey levels, one frame's worth plus `pad`, read at a random offset.
    pub(super) noise: Vec<i8>,
    pad: usize,
    /// Slow drift: (amplitude, period s, phase).
    drift: [(f64, f64, f64); 3],
    flicker_phase: f64,
    /// Flicker: frequency, Hz, and relative amplitude.
    flicker_hz: f64,
    flicker_depth: f64,
    seed: u64,
}

/// The lights: flicker frequency (Hz) and depth, and the slow drift's total relative
/// amplitude.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lights {
    pub(super) flicker_hz: f64,
    pub(super) flicker_depth: f64,
    pub(super) drift_depth: f64,
}

impl Sensor {
    pub(super) fn new(len: usize, sigma: f64, seed: u64, lights: Lights) -> Self {
        let mut rng = Rng::new(stream(seed, 3));
        let pad = 8192;
        let noise = (0..len + pad)
            .map(|_| (sigma * rng.normal()).round().clamp(-127.0, 127.0) as i8)
            .collect();
        let mut drift = [(0.0, 0.0, 0.0); 3];
        let mut total = 0.0;
        for d in &mut drift {
            *d = (
                0.5 + rng.uniform(),
                15.0 + 45.0 * rng.uniform(),
                2.0 * PI * rng.uniform(),
            );
            total += d.0;
        }
        for d in &mut drift {
            d.0 *= lights.drift_depth / total;
        }
        Self {
            noise,
            pad,
            drift,
            flicker_phase: 2.0 * PI * rng.uniform(),
            flicker_hz: lights.flicker_hz,
            flicker_depth: lights.flicker_depth,
            seed: stream(seed, 4),
        }
    }

    /// Gain at frame `i` (time `t`) and the frame's noise offset.
    pub(super) fn frame(&self, i: usize, t: f64) -> (f64, usize) {
        let mut rng = Rng::new(self.seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let drift: f64 = self
            .drift
            .iter()
            .map(|&(a, p, ph)| a * (2.0 * PI * t / p + ph).sin())
            .sum();
        // Mains flicker sampled at the frame rate (a beat), plus jitter.
        let flicker = self.flicker_depth
            * (2.0 * PI * self.flicker_hz * t + self.flicker_phase).sin()
            + 0.004 * rng.normal();
        let off = (rng.uniform() * self.pad as f64) as usize;
        ((1.0 + drift) * (1.0 + flicker), off.min(self.pad))
    }
}

/// `p <- p * gain + offset + noise`, saturating; gain below 4. In 16-bit lanes (units of
/// 1/64 grey level) so that it vectorises with plain SSE2.
pub(super) fn expose(buf: &mut [u8], noise: &[i8], gain: f64, offset: f64) {
    // gain * 64 = hi + lo / 256, so that both products fit 16 bits.
    let g = (gain.clamp(0.0, 3.99) * 16384.0).round() as u32;
    let (hi, lo) = ((g >> 8) as u16, (g & 255) as u16);
    let bias = ((offset * 64.0).round() + 32.0).clamp(0.0, 65535.0) as u16;
    for (p, &n) in buf.iter_mut().zip(noise) {
        let q = *p as u16;
        let v = (q * hi) + ((q * lo) >> 8);
        let v = v
            .saturating_add(bias)
            .saturating_add(((n as i16 + 128) as u16) << 6)
            .saturating_sub(128 << 6);
        *p = (v >> 6).min(255) as u8;
    }
}
