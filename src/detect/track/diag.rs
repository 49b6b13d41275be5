//! Diagnostic images: the frames the gate flags, and the steps of one frame (`--steps`).

use super::Tracker;
use crate::detect::Pt;
use anyhow::{Context, Result};
use opencv::core::{Mat, Point, Scalar};
use opencv::imgproc;
use opencv::prelude::*;

impl Tracker {
    /// The paper's Figure 11 for a flagged frame: detected line red, predicted green.
    pub(super) fn save_diag(&mut self, index: u64, angle: f64, pred: Option<f64>) -> Result<()> {
        let Some(dir) = &self.diag_dir else {
            return Ok(());
        };
        if self.diagnostics.len() >= 40 {
            return Ok(());
        }
        let mut bgr = Mat::default();
        imgproc::cvt_color_def(&self.small, &mut bgr, imgproc::COLOR_GRAY2BGR)?;
        let (piv, r_lo, r_hi) = (self.piv, self.r_lo, self.r_hi);
        let mut draw = |th: f64, color: Scalar| -> Result<()> {
            let a = piv + Pt::new(th.cos(), th.sin()) * r_lo;
            let b = piv + Pt::new(th.cos(), th.sin()) * r_hi;
            imgproc::line(
                &mut bgr,
                Point::new(a.x as i32, a.y as i32),
                Point::new(b.x as i32, b.y as i32),
                color,
                1,
                imgproc::LINE_AA,
                0,
            )?;
            Ok(())
        };
        if let Some(p) = pred {
            draw(p, Scalar::new(0.0, 200.0, 0.0, 0.0))?;
        }
        if angle.is_finite() {
            draw(angle, Scalar::new(0.0, 0.0, 255.0, 0.0))?;
        }
        let path = dir.join(format!("frame-{index:06}.png"));
        let png = crate::picture::encode_bgr_mat(&bgr)
            .with_context(|| format!("{}: cannot encode", path.display()))?;
        std::fs::write(&path, png).with_context(|| format!("{}: cannot write", path.display()))?;
        self.diagnostics.push(path);
        Ok(())
    }
}

/// Step pictures narrower than this (px) are drawn two to four times larger.
const STEPS_MIN_WIDTH: f64 = 420.0;
/// Colours of the step pictures (BGR).
const PIVOT: (f64, f64, f64) = (0.0, 220.0, 255.0);
const BAND: (f64, f64, f64) = (255.0, 160.0, 0.0);
const WEDGE: (f64, f64, f64) = (255.0, 255.0, 0.0);
const PREDICTED: (f64, f64, f64) = (0.0, 200.0, 0.0);
const MEASURED: (f64, f64, f64) = (0.0, 0.0, 255.0);

fn colour(c: (f64, f64, f64)) -> Scalar {
    Scalar::new(c.0, c.1, c.2, 0.0)
}

impl Tracker {
    /// `detect --steps`: the frame and the background as the evidence of frame `index`
    /// saw them (before the background takes the frame in).
    pub(super) fn keep_step_inputs(&mut self, index: u64) -> Result<()> {
        if self.steps == Some(index) {
            self.steps_seen = Some((index, self.small.try_clone()?, self.bg.try_clone()?));
        }
        Ok(())
    }

    /// `detect --steps`: four pictures of frame `index` at the working scale, in the
    /// order the pass works: the first look's pivot, band and sweep on the frame; the
    /// background; the evidence in the wedge (red where over its threshold); the
    /// measured angle (red) against the prediction and its gate (green).
    pub(super) fn save_steps(
        &mut self,
        index: u64,
        angle: f64,
        pred: Option<f64>,
        gate: f64,
    ) -> Result<()> {
        // Kept for this very frame (a flash frame is not measured: its inputs are
        // dropped here, at the next frame).
        let Some((frame, bg)) = self
            .steps_seen
            .take()
            .filter(|s| s.0 == index)
            .map(|s| (s.1, s.2))
        else {
            return Ok(());
        };
        // A small region drawn larger (whole pixels, nearest), so that the lines and
        // the captions can be read.
        let k = (STEPS_MIN_WIDTH / frame.cols().max(1) as f64)
            .ceil()
            .clamp(1.0, 4.0);
        let bgr = |grey: &Mat| -> Result<Mat> {
            let mut big = Mat::default();
            imgproc::resize(
                grey,
                &mut big,
                opencv::core::Size::default(),
                k,
                k,
                imgproc::INTER_NEAREST,
            )?;
            let mut out = Mat::default();
            imgproc::cvt_color_def(&big, &mut out, imgproc::COLOR_GRAY2BGR)?;
            Ok(out)
        };
        // Pixel centres: pixel `i` covers `[i k, (i + 1) k)` when drawn larger.
        let point = |p: Pt| {
            Point::new(
                ((p.x + 0.5) * k - 0.5).round() as i32,
                ((p.y + 0.5) * k - 0.5).round() as i32,
            )
        };
        let (piv, r_lo, r_hi) = (self.piv, self.r_lo, self.r_hi);
        let ray = |m: &mut Mat, th: f64, c: Scalar, from: f64, to: f64| -> Result<()> {
            let (u, v) = (th.cos(), th.sin());
            imgproc::line(
                m,
                point(piv + Pt::new(u, v) * from),
                point(piv + Pt::new(u, v) * to),
                c,
                1,
                imgproc::LINE_AA,
                0,
            )?;
            Ok(())
        };

        // 1: the first look's geometry on the frame.
        let mut one = bgr(&frame)?;
        let (a0, a1) = (
            self.geo.theta_min.to_degrees(),
            self.geo.theta_max.to_degrees(),
        );
        for r in [r_lo, r_hi] {
            let rr = (r * k).round() as i32;
            imgproc::ellipse(
                &mut one,
                point(piv),
                opencv::core::Size::new(rr, rr),
                0.0,
                a0,
                a1,
                colour(BAND),
                1,
                imgproc::LINE_AA,
                0,
            )?;
        }
        for th in [self.geo.theta_min, self.geo.theta_max] {
            ray(&mut one, th, colour(BAND), 0.0, r_hi)?;
        }
        imgproc::circle(
            &mut one,
            point(piv),
            4,
            colour(PIVOT),
            -1,
            imgproc::LINE_AA,
            0,
        )?;
        caption(&mut one, "1 first look: pivot, band, sweep")?;

        // 2: the background.
        let mut two = bgr(&bg)?;
        caption(&mut two, "2 background (running extreme)")?;

        // 3: the evidence, stretched to white at its largest, red over its threshold.
        let ev = self.ev.data_bytes()?;
        let tmap = self.tmap.data_bytes()?;
        let top = ev.iter().copied().max().unwrap_or(0).max(1) as f64;
        let mut grey = Mat::default();
        self.ev
            .convert_to(&mut grey, opencv::core::CV_8UC1, 255.0 / top, 0.0)?;
        let mut three = bgr(&grey)?;
        {
            let (w, kk) = (self.ev.cols() as usize, k as usize);
            let big_w = three.cols() as usize;
            let px = three.data_bytes_mut()?;
            for (i, (e, t)) in ev.iter().zip(tmap).enumerate() {
                if e > t {
                    let (x, y) = (i % w, i / w);
                    for yy in y * kk..(y + 1) * kk {
                        let at = 3 * (yy * big_w + x * kk);
                        for q in px[at..at + 3 * kk].chunks_exact_mut(3) {
                            q.copy_from_slice(&[40, 40, 255]);
                        }
                    }
                }
            }
        }
        for th in [self.wedge.0, self.wedge.1] {
            ray(&mut three, th, colour(WEDGE), r_lo, r_hi)?;
        }
        caption(&mut three, "3 evidence in the wedge (red: over threshold)")?;

        // 4: the angle against the prediction and its gate.
        let mut four = bgr(&frame)?;
        if let Some(p) = pred {
            ray(&mut four, p, colour(PREDICTED), r_lo, r_hi)?;
            for g in [p - gate, p + gate] {
                ray(
                    &mut four,
                    g,
                    colour(PREDICTED),
                    r_lo,
                    r_lo + 0.3 * (r_hi - r_lo),
                )?;
            }
        }
        if angle.is_finite() {
            ray(&mut four, angle, colour(MEASURED), 0.0, r_hi)?;
        }
        caption(&mut four, "4 measured (red), predicted and gate (green)")?;

        for (name, m) in [
            ("1-geometry", one),
            ("2-background", two),
            ("3-evidence", three),
            ("4-angle", four),
        ] {
            let file = format!("frame-{index:06}-{name}.png");
            let png = crate::picture::encode_bgr_mat(&m)
                .with_context(|| format!("{file}: cannot encode"))?;
            self.steps_drawn.push((file, png));
        }
        Ok(())
    }
}

/// A line of text on a dark band along the picture's top.
fn caption(m: &mut Mat, text: &str) -> Result<()> {
    let w = m.cols();
    imgproc::rectangle(
        m,
        opencv::core::Rect::new(0, 0, w, 18),
        Scalar::all(0.0),
        -1,
        imgproc::LINE_8,
        0,
    )?;
    imgproc::put_text(
        m,
        text,
        Point::new(4, 13),
        imgproc::FONT_HERSHEY_SIMPLEX,
        0.4,
        Scalar::all(255.0),
        1,
        imgproc::LINE_AA,
        false,
    )?;
    Ok(())
}
