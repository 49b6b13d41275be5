//! Diagnostic images of the frames the gate flags.

use super::Tracker;
use crate::detect::Pt;
use anyhow::{Context, Result};
use opencv::core::{Mat, Point, Scalar};
use opencv::imgproc;

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
