//! Figure 11: a frame of the video with the detected wire, the pivot and the region.

use super::{Detection, Status};
use anyhow::{bail, Context, Result};
use std::path::Path;

/// The frame shown as Figure 11: the first frame near a turning point in the first
/// seconds (the wire well away from rest), detected `ok`.
pub fn figure11_frame(d: &Detection) -> u64 {
    let ok: Vec<_> = d
        .rows
        .iter()
        .filter(|r| r.status == Status::Ok && r.angle_rad.is_some())
        .collect();
    if ok.is_empty() {
        return d.rows.first().map_or(0, |r| r.frame);
    }
    let t0 = ok[0].t_s;
    let early: Vec<_> = ok.iter().filter(|r| r.t_s - t0 <= 4.0).collect();
    let mut angles: Vec<f64> = early.iter().filter_map(|r| r.angle_rad).collect();
    let median = crate::numerics::upper_median(&mut angles);
    early
        .iter()
        .max_by(|a, b| {
            let da = (a.angle_rad.unwrap_or(median) - median).abs();
            let db = (b.angle_rad.unwrap_or(median) - median).abs();
            da.total_cmp(&db).then(b.frame.cmp(&a.frame))
        })
        .map_or(0, |r| r.frame)
}

/// Figure 11: frame `frame` of the video with the detected wire line (red), the pivot
/// (cyan) and the region of interest (yellow), cropped around the region, as PNG bytes.
pub fn figure11_png(video: &Path, d: &Detection, frame: u64) -> Result<Vec<u8>> {
    use opencv::{core, core::Mat, imgcodecs, imgproc, prelude::*, videoio};
    let what = || format!("{}: Figure 11 (frame {frame})", video.display());
    let mut cap = videoio::VideoCapture::from_file(video, videoio::CAP_ANY).with_context(what)?;
    if !cap.is_opened().with_context(what)? {
        bail!("{}: cannot open", what());
    }
    let mut img = Mat::default();
    // Read up to the frame (sequential reading is exact for every container).
    for _ in 0..=frame {
        if !cap.read(&mut img).with_context(what)? {
            bail!("{}: the video ended first", what());
        }
    }
    let row = d.rows.iter().find(|r| r.frame == frame);
    let [px, py] = d.pivot_px;
    let [rx, ry, rw, rh] = d.roi.map(|v| v as i32);
    let reach = ((rx as f64 - px).abs().max((rx + rw) as f64 - px).powi(2)
        + (ry as f64 - py).abs().max((ry + rh) as f64 - py).powi(2))
    .sqrt();
    let pt = |x: f64, y: f64| core::Point::new(x.round() as i32, y.round() as i32);
    imgproc::rectangle(
        &mut img,
        core::Rect::new(rx, ry, rw, rh),
        core::Scalar::new(0.0, 220.0, 255.0, 0.0),
        1,
        imgproc::LINE_AA,
        0,
    )?;
    if let Some(a) = row.and_then(|r| r.angle_rad) {
        imgproc::line(
            &mut img,
            pt(px, py),
            pt(px + reach * a.cos(), py + reach * a.sin()),
            core::Scalar::new(0.0, 0.0, 255.0, 0.0),
            1,
            imgproc::LINE_AA,
            0,
        )?;
    }
    imgproc::circle(
        &mut img,
        pt(px, py),
        4,
        core::Scalar::new(255.0, 255.0, 0.0, 0.0),
        2,
        imgproc::LINE_AA,
        0,
    )?;
    // Crop: the region and the pivot with a margin, inside the frame.
    let (w, h) = (img.cols(), img.rows());
    let m = (rw.max(rh) / 6).max(8);
    let x0 = (rx.min(px as i32) - m).clamp(0, w - 1);
    let y0 = (ry.min(py as i32) - m).clamp(0, h - 1);
    let x1 = ((rx + rw).max(px as i32) + m).clamp(x0 + 1, w);
    let y1 = ((ry + rh).max(py as i32) + m).clamp(y0 + 1, h);
    let crop = Mat::roi(&img, core::Rect::new(x0, y0, x1 - x0, y1 - y0))?.try_clone()?;
    let mut buf = core::Vector::<u8>::new();
    imgcodecs::imencode(".png", &crop, &mut buf, &core::Vector::new()).with_context(what)?;
    Ok(buf.as_slice().to_vec())
}
