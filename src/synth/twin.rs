//! The twin: everything prepared once, then frames on demand.

use super::camera::{expose, HandPainter, Lights, Sensor};
use super::mover::Mover;
use super::plan::{stream, Plan, Spoil, EXPOSURE, SUBSAMPLES};
use super::room::{LensWarp, SecondString};
use super::scene::build_background;
use super::shake::{self, ShakePath};
use crate::config::{DEFAULT_DRIFT_DEPTH, DEFAULT_FLICKER_DEPTH, DEFAULT_FLICKER_HZ};
use crate::rng::Rng;
use anyhow::Result;
use opencv::core::{self, Mat, Scalar};
use opencv::prelude::*;

/// A rolling shutter's bands of rows (`synthetic.rolling_shutter`), each drawn at its
/// own time.
const RS_BANDS: usize = 16;
/// The hand that releases the ball (`synthetic.release_hand`) is out of the way this long
/// after the release, s.
const RELEASE_S: f64 = 0.4;

pub(super) struct Twin {
    pub(super) plan: Plan,
    bg: Vec<u8>,
    illum: Vec<f32>,
    mover: Mover,
    sensor: Option<Sensor>,
    hand: HandPainter,
    /// The camera's own motion (`synthetic.shake`).
    shake: Option<ShakePath>,
    /// A second pendulum (`room.second_string`).
    second: Option<SecondString>,
    /// The lens's distortion (`lens_k1`).
    lens: Option<LensWarp>,
    pub(super) frame: Mat,
    /// Scratch for a mirrored frame.
    flipped: Mat,
}

impl Twin {
    pub(super) fn new(plan: Plan) -> Result<Self> {
        let defects = !plan.s.clean;
        let mut rng = Rng::new(stream(plan.s.seed, 5));
        let defocus = defects.then(|| 0.8 + 0.4 * rng.uniform());
        let (bg, illum) = build_background(&plan, defocus)?;
        // Pixel integration (~0.4 px) combined with the defocus.
        let sigma = (0.4f64.powi(2) + defocus.unwrap_or(0.0).powi(2)).sqrt();
        let contrast = plan.s.wire_contrast.unwrap_or(1.0);
        let mover = Mover::new(
            &plan.geo,
            plan.view,
            &plan.look,
            sigma,
            contrast,
            plan.s.shadow,
        );
        let s = &plan.s;
        let lights = Lights {
            flicker_hz: s.flicker_hz.unwrap_or(DEFAULT_FLICKER_HZ),
            flicker_depth: s.flicker_depth.unwrap_or(DEFAULT_FLICKER_DEPTH),
            drift_depth: s.drift_depth.unwrap_or(DEFAULT_DRIFT_DEPTH),
        };
        let sensor = defects.then(|| Sensor::new(bg.len(), plan.look.noise_sigma, s.seed, lights));
        let shake = plan.s.shake.as_ref().map(|k| {
            let duration = plan.truth.last().map_or(0.0, |r| r.t_s);
            ShakePath::new(k, plan.s.seed, duration)
        });
        let second = plan
            .s
            .room
            .filter(|r| r.second_string)
            .map(|_| SecondString::new(&plan, sigma, contrast));
        let lens = match &plan.lens {
            Some(l) => Some(LensWarp::new(l, plan.geo.w, plan.geo.h)?),
            None => None,
        };
        let frame = Mat::new_rows_cols_with_default(
            plan.geo.h as i32,
            plan.geo.w as i32,
            core::CV_8UC3,
            Scalar::all(0.0),
        )?;
        Ok(Self {
            plan,
            bg,
            illum,
            mover,
            sensor,
            hand: HandPainter::default(),
            shake,
            second,
            lens,
            frame,
            flipped: Mat::default(),
        })
    }

    /// Render frame `i` into `self.frame` (a duplicate is rendered as its own content
    /// would be: the caller repeats the previous frame instead).
    pub(super) fn render_frame(&mut self, i: usize) -> Result<()> {
        let plan = &self.plan;
        let t = plan.truth[i].t_s;
        let dt = 1.0 / plan.fps;
        let n_sub = if self.sensor.is_some() { SUBSAMPLES } else { 1 };
        // The exposure's sub-times about `tc`, and the wire's angle at each.
        let exposure = |tc: f64| {
            let (mut ts, mut thetas) = ([0.0; SUBSAMPLES], [0.0; SUBSAMPLES]);
            for k in 0..n_sub {
                let f = if n_sub == 1 {
                    0.0
                } else {
                    k as f64 / (n_sub - 1) as f64 - 0.5
                };
                ts[k] = tc + f * EXPOSURE * dt;
                thetas[k] = plan.theta(ts[k]);
            }
            (ts, thetas)
        };
        let (ts, _) = exposure(t);
        // A rolling shutter's bands of rows, each with its own time (the frame's time
        // at the middle row).
        let h = plan.geo.h;
        let bands: Vec<(usize, usize, f64)> = match plan.s.rolling_shutter.filter(|&r| r > 0.0) {
            Some(r) => (0..RS_BANDS)
                .map(|b| {
                    let (y0, y1) = (b * h / RS_BANDS, (b + 1) * h / RS_BANDS);
                    let yc = 0.5 * (y0 + y1) as f64 - 0.5;
                    (y0, y1, t + (yc / (h - 1) as f64 - 0.5) * r * dt)
                })
                .collect(),
            None => vec![(0, h, t)],
        };
        {
            let buf = self.frame.data_bytes_mut()?;
            buf.copy_from_slice(&self.bg);
            // The second pendulum first: the first is drawn over it.
            let under = match &mut self.second {
                Some(sec) => {
                    sec.draw(buf, &self.bg, &self.illum, &ts[..n_sub]);
                    &sec.under
                }
                None => &self.bg,
            };
            // Each band with the wire as its own time saw it (one band, the whole frame,
            // without a rolling shutter).
            for &(y0, y1, tb) in &bands {
                let (_, thetas) = exposure(tb);
                self.mover.draw(
                    buf,
                    under,
                    &self.illum,
                    &thetas[..n_sub],
                    plan.theta(tb),
                    Some((y0, y1)),
                );
            }
        }
        if let Spoil::Hand { k, n, event } = plan.spoils[i] {
            let g = &plan.geo;
            let mut rng = Rng::new(stream(plan.s.seed, 100 + event as u64));
            let dir = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
            let tilt = dir * (0.25 + 0.2 * rng.uniform());
            // Start of the event: the hand crosses the wire's middle.
            let th0 = plan.theta(plan.truth[i - k as usize].t_s);
            let mid = plan.to_image([
                g.pivot[0] + 0.55 * g.d_px * th0.cos(),
                g.pivot[1] + 0.55 * g.d_px * th0.sin(),
            ]);
            let u = 0.1 * g.h as f64;
            let step = 0.3 * g.w as f64;
            let off = k as f64 - (n as f64 - 1.0) / 2.0;
            let c = [
                mid[0] + dir * off * step + (rng.uniform() - 0.5) * u,
                mid[1] + 1.2 * u + (rng.uniform() - 0.5) * u,
            ];
            let smear = (0.04 * g.w as f64).max(3.0);
            self.hand
                .paint(&mut self.frame, &self.illum, c, u, tilt, smear)?;
        }
        // The operator's hand holds the ball until its release and draws back
        // (`release_hand`): its fingertips at the ball's centre, from beyond it.
        if let Some(hold) = plan.s.hold_s.filter(|&h| h > 0.0 && plan.s.release_hand) {
            let since = t - hold;
            if since < RELEASE_S {
                let g = &plan.geo;
                let th = plan.theta(0.0);
                let u = 0.55 * g.ball_r;
                let back = 3.0 + 8.0 * (since / RELEASE_S).max(0.0);
                let r = g.d_px + back * u;
                let p = [g.pivot[0] + r * th.cos(), g.pivot[1] + r * th.sin()];
                let c = plan.view.map_or(p, |v| v.apply(p));
                // Drawing back, it moves 8 u in `RELEASE_S`, blurred over the exposure.
                let smear = if since > 0.0 {
                    (8.0 * u / RELEASE_S * EXPOSURE * dt).max(1.0)
                } else {
                    1.0
                };
                self.hand.paint(
                    &mut self.frame,
                    &self.illum,
                    c,
                    u,
                    th - std::f64::consts::FRAC_PI_2,
                    smear,
                )?;
            }
        }
        if let Some(path) = &self.shake {
            if let [(_, _, tb)] = bands[..] {
                shake::apply(&mut self.frame, path.at(tb), &mut self.flipped)?;
            } else {
                // Each band of rows as the camera stood at its own time.
                self.flipped = self.frame.try_clone()?;
                let mut band = Mat::default();
                for &(y0, y1, tb) in &bands {
                    shake::warp_rows(&self.flipped, path.at(tb), y0 as i32, y1 as i32, &mut band)?;
                    let step = 3 * plan.geo.w;
                    self.frame.data_bytes_mut()?[y0 * step..y1 * step]
                        .copy_from_slice(band.data_bytes()?);
                }
            }
        }
        if let Some(walker) = &plan.walker {
            walker.paint(&mut self.frame, &self.illum, t)?;
        }
        if let Some(lens) = &mut self.lens {
            lens.apply(&mut self.frame)?;
        }
        if let Some(sensor) = &self.sensor {
            let (gain, off) = sensor.frame(i, t);
            let (gain, offset) = if plan.spoils[i] == Spoil::Flash {
                (3.5 * gain, 100.0)
            } else {
                (gain, 0.0)
            };
            let buf = self.frame.data_bytes_mut()?;
            let n = buf.len();
            expose(buf, &sensor.noise[off..off + n], gain, offset);
        }
        if plan.s.mirror {
            core::flip(&self.frame, &mut self.flipped, 1)?;
            std::mem::swap(&mut self.frame, &mut self.flipped);
        }
        Ok(())
    }
}
