//! What else the room puts in the picture (`synthetic.room`, `synthetic.lens_k1`): a
//! ruled or gridded board and straight static edges on the plate, a second pendulum, a
//! person walking through, and the lens's radial distortion (the model is
//! [`crate::lens`]'s).

use super::look::{bgr, mix, pt, scale, Look};
use super::mover::Mover;
use super::plan::{stream, Geometry, Plan, SUBSAMPLES};
use crate::config::{Board, Room};
use crate::lens::Lens;
use crate::rng::Rng;
use anyhow::Result;
use opencv::core::{self, Mat, Scalar};
use opencv::imgproc;
use opencv::prelude::*;
use std::f64::consts::PI;

/// The board's lines and the static edges, drawn on the plate's canvas (the plate's
/// own frame: the pivot at `c`, the wire at rest along +y) over the plate's texture and
/// under the instruments (`edges` over them: a cable lies on the protractor).
pub(super) fn draw_board(
    canvas: &mut Mat,
    c: [f64; 2],
    g: &Geometry,
    look: &Look,
    room: &Room,
    seed: u64,
) -> Result<()> {
    let mut rng = Rng::new(stream(seed, 20));
    let ink = bgr(mix(look.plate, look.marks, 0.35));
    let spacing = (g.d_px / 20.0).max(6.0);
    let sets: &[f64] = match room.board {
        Board::None => &[],
        Board::Ruled => &[0.0],
        Board::Grid => &[0.0, PI / 2.0],
    };
    let base = rng.uniform() * PI;
    for &turn in sets {
        let a = base + turn;
        let (u, n) = ([a.cos(), a.sin()], [-a.sin(), a.cos()]);
        let lines = (diag(canvas)? / spacing).ceil() as i32;
        let phase = rng.uniform() * spacing;
        for k in -lines..=lines {
            let o = phase + f64::from(k) * spacing;
            let m = [c[0] + o * n[0], c[1] + o * n[1]];
            across(canvas, m, u, ink, 1)?;
        }
    }
    Ok(())
}

/// The canvas's diagonal, px: a line that long through any point of it crosses it.
fn diag(canvas: &Mat) -> Result<f64> {
    let size = canvas.size()?;
    Ok(f64::from(size.width).hypot(f64::from(size.height)))
}

/// A line across the whole canvas through `m` along the unit direction `u`.
fn across(canvas: &mut Mat, m: [f64; 2], u: [f64; 2], colour: Scalar, width: i32) -> Result<()> {
    let d = diag(canvas)?;
    imgproc::line(
        canvas,
        pt(m[0] - d * u[0], m[1] - d * u[1]),
        pt(m[0] + d * u[0], m[1] + d * u[1]),
        colour,
        width,
        imgproc::LINE_AA,
        4,
    )?;
    Ok(())
}

/// Straight static edges through or near the fulcrum (`room.edges`), on the canvas
/// after the instruments: each as long as the canvas, at a random angle, 2 to 6 px
/// wide, dark or light.
pub(super) fn draw_edges(
    canvas: &mut Mat,
    c: [f64; 2],
    g: &Geometry,
    look: &Look,
    room: &Room,
    seed: u64,
) -> Result<()> {
    let mut rng = Rng::new(stream(seed, 21));
    for _ in 0..room.edges {
        let a = rng.uniform() * PI;
        let off = 0.15 * g.d_px * (2.0 * rng.uniform() - 1.0);
        let m = [c[0] - off * a.sin(), c[1] + off * a.cos()];
        let colour = if rng.uniform() < 0.5 {
            scale(look.plate, 0.4)
        } else {
            mix(look.plate, [240.0; 3], 0.7)
        };
        let width = 2 + (rng.uniform() * 5.0) as i32;
        across(canvas, m, [a.cos(), a.sin()], bgr(colour), width)?;
    }
    Ok(())
}

/// A second pendulum (`room.second_string`): beside the first across its rest
/// direction, a shorter wire, its own period, amplitude and phase, lightly damped.
pub(super) struct SecondString {
    mover: Mover,
    rest: f64,
    amp: f64,
    period_s: f64,
    phase: f64,
    tau_s: f64,
    /// The frame with the second pendulum drawn: the first one's background.
    pub(super) under: Vec<u8>,
}

impl SecondString {
    pub(super) fn new(plan: &Plan, sigma: f64, contrast: f64) -> Self {
        let g = &plan.geo;
        let mut rng = Rng::new(stream(plan.s.seed, 22));
        let side = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        let across = [-g.theta_rest.sin(), g.theta_rest.cos()];
        let off = side * (0.5 + 0.2 * rng.uniform()) * g.d_px;
        let d_px = (0.45 + 0.3 * rng.uniform()) * g.d_px;
        let geo = Geometry {
            pivot: [g.pivot[0] + off * across[0], g.pivot[1] + off * across[1]],
            d_px,
            ball_r: g.ball_r * d_px / g.d_px,
            screw_r: g.screw_r * 0.8,
            ..g.clone()
        };
        Self {
            mover: Mover::new(&geo, plan.view, &plan.look, sigma, contrast, None),
            rest: g.theta_rest,
            amp: (5.0 + 10.0 * rng.uniform()).to_radians(),
            period_s: 0.8 + 1.2 * rng.uniform(),
            phase: 2.0 * PI * rng.uniform(),
            tau_s: 30.0 + 60.0 * rng.uniform(),
            under: Vec::new(),
        }
    }

    fn theta(&self, t: f64) -> f64 {
        self.rest
            + self.amp * (-t / self.tau_s).exp() * (2.0 * PI * t / self.period_s + self.phase).sin()
    }

    /// Draw it into `frame`, which holds `bg`, at the exposure's times `ts`; keep the
    /// result in `under`.
    pub(super) fn draw(&mut self, frame: &mut [u8], bg: &[u8], illum: &[f32], ts: &[f64]) {
        let mut thetas = [0.0; SUBSAMPLES];
        for (th, &t) in thetas.iter_mut().zip(ts) {
            *th = self.theta(t);
        }
        let mid = self.theta(ts[ts.len() / 2]);
        self.mover
            .draw(frame, bg, illum, &thetas[..ts.len()], mid, None);
        self.under.clear();
        self.under.extend_from_slice(frame);
    }
}

/// How long the walker takes to cross the frame, s.
pub const WALKER_S: f64 = 4.0;

/// A person walking between the camera and the plate (`room.walker_s`): a large dark,
/// soft-edged band, a third of the frame wide, crossing it from one side to the other.
#[derive(Clone, Debug)]
pub(super) struct Walker {
    t0: f64,
    w: f64,
    h: f64,
    /// +1 left to right, -1 right to left.
    dir: f64,
    colour: [f32; 3],
    wobble: f64,
}

impl Walker {
    pub(super) fn new(t0: f64, w: usize, h: usize, seed: u64) -> Self {
        let mut rng = Rng::new(stream(seed, 23));
        let dark = 35.0 + 40.0 * rng.uniform() as f32;
        Self {
            t0,
            w: w as f64,
            h: h as f64,
            dir: if rng.uniform() < 0.5 { -1.0 } else { 1.0 },
            colour: [dark * 0.9, dark, dark * 1.2],
            wobble: 2.0 * PI * rng.uniform(),
        }
    }

    /// The band's centre column and half-width at row `y` at time `t`, px, when it is
    /// in the frame.
    fn band(&self, y: f64, t: f64) -> Option<(f64, f64)> {
        let f = (t - self.t0) / WALKER_S;
        if !(0.0..=1.0).contains(&f) {
            return None;
        }
        let x = -0.3 * self.w + 1.6 * self.w * f;
        let x = if self.dir > 0.0 { x } else { self.w - x };
        let half = 0.16 * self.w * (1.0 + 0.15 * (2.0 * PI * y / self.h + self.wobble).sin());
        Some((x, half))
    }

    /// Edge softness (defocus and motion), px.
    fn soft(&self) -> f64 {
        0.02 * self.w
    }

    /// How much of the pixel `(x, y)` the walker covers at time `t`, 0 to 1.
    pub(super) fn alpha(&self, x: f64, y: f64, t: f64) -> f64 {
        self.band(y, t)
            .map_or(0.0, |(cx, half)| self.cover(x, cx, half))
    }

    /// How much of column `x` a band at `cx` of half-width `half` covers, 0 to 1.
    fn cover(&self, x: f64, cx: f64, half: f64) -> f64 {
        let z = (half - (x - cx).abs()) / self.soft();
        0.97 / (1.0 + (-1.7 * z).exp())
    }

    /// Paint the walker over `frame` (BGR) at time `t`, lit by `illum`.
    pub(super) fn paint(&self, frame: &mut Mat, illum: &[f32], t: f64) -> Result<()> {
        let (w, h) = (self.w as usize, self.h as usize);
        let buf = frame.data_bytes_mut()?;
        for y in 0..h {
            let Some((cx, half)) = self.band(y as f64, t) else {
                return Ok(());
            };
            let reach = half + 6.0 * self.soft();
            let x0 = (cx - reach).floor().max(0.0) as usize;
            let x1 = ((cx + reach).ceil().max(0.0) as usize).min(w);
            for x in x0..x1 {
                let a = self.cover(x as f64, cx, half) as f32;
                if a < 1e-3 {
                    continue;
                }
                let j = y * w + x;
                let k = 3 * j;
                let p = [buf[k] as f32, buf[k + 1] as f32, buf[k + 2] as f32];
                let q = mix(p, scale(self.colour, illum[j]), a);
                for (c, v) in q.into_iter().enumerate() {
                    buf[k + c] = (v + 0.5) as u8;
                }
            }
        }
        Ok(())
    }
}

/// The maps `remap` takes for `lens`: for each image pixel, its source in the
/// undistorted view.
fn lens_maps(lens: &Lens, w: usize, h: usize) -> Result<(Mat, Mat)> {
    let mut mx =
        Mat::new_rows_cols_with_default(h as i32, w as i32, core::CV_32FC1, Scalar::all(0.0))?;
    let mut my = mx.clone();
    {
        let xs = mx.data_typed_mut::<f32>()?;
        let ys = my.data_typed_mut::<f32>()?;
        for y in 0..h {
            for x in 0..w {
                let s = lens.undistort([x as f64, y as f64]);
                xs[y * w + x] = s[0] as f32;
                ys[y * w + x] = s[1] as f32;
            }
        }
    }
    Ok((mx, my))
}

/// The lens applied to a frame: its maps and a scratch frame.
pub(super) struct LensWarp {
    mx: Mat,
    my: Mat,
    out: Mat,
}

impl LensWarp {
    pub(super) fn new(lens: &Lens, w: usize, h: usize) -> Result<Self> {
        let (mx, my) = lens_maps(lens, w, h)?;
        Ok(Self {
            mx,
            my,
            out: Mat::default(),
        })
    }

    pub(super) fn apply(&mut self, frame: &mut Mat) -> Result<()> {
        imgproc::remap(
            frame,
            &mut self.out,
            &self.mx,
            &self.my,
            imgproc::INTER_LINEAR,
            core::BORDER_REFLECT_101,
            Scalar::all(0.0),
        )?;
        std::mem::swap(frame, &mut self.out);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_walker_crosses_the_frame_in_its_time() {
        let w = Walker::new(2.0, 640, 480, 1);
        assert_eq!(w.alpha(320.0, 240.0, 1.9), 0.0);
        assert_eq!(w.alpha(320.0, 240.0, 2.0 + WALKER_S + 0.1), 0.0);
        // Half-way, the band covers the middle of the frame.
        assert!(w.alpha(320.0, 240.0, 2.0 + WALKER_S / 2.0) > 0.9);
    }
}
