//! The paper's Figure 11, kept during the detector's own pass: the region of interest
//! of one frame with the detected line, the pivot and the region's outline.
//!
//! The frame shown is the `ok` frame of the first seconds whose angle lies farthest
//! from their median ([`figure11_frame`]): a turning point, the wire well away from
//! rest. That frame is one of the highest or lowest angles of those seconds, so the
//! streaming pass keeps the grey region of a few of each ([`Keeper`]; a frame the
//! checks after the pass demote leaves the others) and the choice is made once every
//! status is known. No second decoding of the video.

use super::{AngleRow, Detection, Status};
use crate::detect::tuning::EARLY_S;
use crate::video::Frame;
use anyhow::{bail, Context, Result};
use opencv::core::{self, Mat, Point, Rect, Scalar};
use opencv::imgproc;

/// One frame's region of interest, grey, as the streaming pass decoded it (row-major,
/// `width` bytes per row; the region `Detection::roi` of the full frame).
#[derive(Clone)]
pub struct Figure11 {
    pub frame: u64,
    pub width: usize,
    pub height: usize,
    pub grey: Vec<u8>,
}

impl std::fmt::Debug for Figure11 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Figure11")
            .field("frame", &self.frame)
            .field("width", &self.width)
            .field("height", &self.height)
            .finish_non_exhaustive()
    }
}

impl Figure11 {
    fn of(f: &Frame) -> Self {
        Self {
            frame: f.index,
            width: f.width,
            height: f.height,
            grey: f.data.clone(),
        }
    }
}

/// The candidates for Figure 11 during the streaming pass: the first frame (shown
/// when no frame is `ok`) and, among the frames the gate accepts in the first
/// [`EARLY_S`] seconds, those with the `per_side` highest and lowest angles. At most
/// `2 per_side + 1` frames are held, whatever the video's length.
pub(super) struct Keeper {
    per_side: usize,
    t0: Option<f64>,
    first: Option<Figure11>,
    /// `(angle, frame)` of the highest and of the lowest angles so far.
    high: Vec<(f64, u64)>,
    low: Vec<(f64, u64)>,
    held: Vec<Figure11>,
}

impl Keeper {
    pub(super) fn new(per_side: usize) -> Self {
        Self {
            per_side: per_side.max(1),
            t0: None,
            first: None,
            high: Vec::new(),
            low: Vec::new(),
            held: Vec::new(),
        }
    }

    /// Consider `frame`, whose streaming result is `row`.
    pub(super) fn offer(&mut self, row: &AngleRow, frame: &Frame) {
        if self.first.is_none() {
            self.first = Some(Figure11::of(frame));
        }
        let (None, Some(a)) = (row.flag, row.angle_rad) else {
            return;
        };
        let t0 = *self.t0.get_or_insert(row.t_s);
        if row.t_s - t0 > EARLY_S {
            return;
        }
        let k = self.per_side;
        let enter = |side: &mut Vec<(f64, u64)>, better: fn(f64, f64) -> bool| -> bool {
            if side.len() < k {
                side.push((a, row.frame));
                return true;
            }
            // The side's worst member, replaced if `a` beats it.
            let (w, _) = side
                .iter()
                .enumerate()
                .fold((0, side[0].0), |(wi, wa), (i, &(x, _))| {
                    if better(wa, x) {
                        (i, x)
                    } else {
                        (wi, wa)
                    }
                });
            if better(a, side[w].0) {
                side[w] = (a, row.frame);
                true
            } else {
                false
            }
        };
        let high = enter(&mut self.high, |a, b| a > b);
        let low = enter(&mut self.low, |a, b| a < b);
        if !(high || low) {
            return;
        }
        let (hi, lo) = (&self.high, &self.low);
        self.held
            .retain(|f| hi.iter().chain(lo).any(|&(_, i)| i == f.frame));
        self.held.push(Figure11::of(frame));
    }

    /// The angle of `frame` measured again, or the frame refused
    /// (`Tracker::take_restated`).
    pub(super) fn restate(&mut self, frame: u64, angle: Option<f64>) {
        match angle {
            Some(a) => {
                for e in self.high.iter_mut().chain(&mut self.low) {
                    if e.1 == frame {
                        e.0 = a;
                    }
                }
            }
            None => {
                self.high.retain(|e| e.1 != frame);
                self.low.retain(|e| e.1 != frame);
            }
        }
    }

    /// Figure 11 once every row's status is final: the frame [`figure11_frame`]'s rule
    /// picks, or, should it not be held (the first `ok` frames of the pass demoted),
    /// the held frame that rule ranks first.
    pub(super) fn take(self, rows: &[AngleRow]) -> Option<Figure11> {
        let Self {
            first, mut held, ..
        } = self;
        held.extend(first);
        let frame = pick(rows, |_| true)
            .filter(|&f| held.iter().any(|h| h.frame == f))
            .or_else(|| pick(rows, |f| held.iter().any(|h| h.frame == f)))?;
        held.into_iter().find(|h| h.frame == frame)
    }
}

/// The frame shown as Figure 11: the `ok` frame of the first seconds (within 4 s of
/// the first `ok` frame) whose angle lies farthest from their median
/// (a turning point, the wire well away from rest); the first frame when none is
/// `ok`. The frame of `d.figure11` when the detection kept one.
pub fn figure11_frame(d: &Detection) -> u64 {
    match &d.figure11 {
        Some(f) => f.frame,
        None => pick(&d.rows, |_| true).unwrap_or(0),
    }
}

/// [`figure11_frame`]'s rule among the frames `held` allows (`None` if it allows none).
fn pick(rows: &[AngleRow], held: impl Fn(u64) -> bool) -> Option<u64> {
    let ok: Vec<_> = rows
        .iter()
        .filter(|r| r.status == Status::Ok && r.angle_rad.is_some())
        .collect();
    if ok.is_empty() {
        return rows.first().map(|r| r.frame).filter(|&f| held(f));
    }
    let t0 = ok[0].t_s;
    let early: Vec<_> = ok.iter().filter(|r| r.t_s - t0 <= EARLY_S).collect();
    let mut angles: Vec<f64> = early.iter().filter_map(|r| r.angle_rad).collect();
    let median = crate::numerics::upper_median(&mut angles);
    early
        .iter()
        .filter(|r| held(r.frame))
        .max_by(|a, b| {
            let da = (a.angle_rad.unwrap_or(median) - median).abs();
            let db = (b.angle_rad.unwrap_or(median) - median).abs();
            da.total_cmp(&db).then(b.frame.cmp(&a.frame))
        })
        .map(|r| r.frame)
}

/// Figure 11 as PNG: the kept frame's region of interest (grey, in a dark margin of a
/// sixth of its larger side) with the region's outline (yellow), the detected wire line
/// from the pivot (red) and the pivot (cyan, where it falls inside the picture).
pub fn figure11_png(d: &Detection) -> Result<Vec<u8>> {
    let Some(f) = &d.figure11 else {
        bail!("Figure 11: the detection kept no frame");
    };
    let what = || format!("Figure 11 (frame {})", f.frame);
    let [rx, ry, rw, rh] = d.roi.map(|v| v as i32);
    if f.width != rw as usize || f.height != rh as usize || f.grey.len() != f.width * f.height {
        bail!(
            "{}: the kept frame is {}x{} px ({} bytes), the region {rw}x{rh}",
            what(),
            f.width,
            f.height,
            f.grey.len()
        );
    }
    let grey = Mat::new_rows_cols_with_data(rh, rw, &f.grey).with_context(what)?;
    let m = (rw.max(rh) / 6).max(8);
    let mut img =
        Mat::new_rows_cols_with_default(rh + 2 * m, rw + 2 * m, core::CV_8UC3, Scalar::all(40.0))?;
    {
        let mut inner = Mat::roi_mut(&mut img, Rect::new(m, m, rw, rh))?;
        imgproc::cvt_color_def(&grey, &mut inner, imgproc::COLOR_GRAY2BGR).with_context(what)?;
    }
    // Full-frame pixel (x, y) lies at (x - rx + m, y - ry + m) in the picture.
    let [px, py] = d.pivot_px;
    let (ox, oy) = ((rx - m) as f64, (ry - m) as f64);
    let pt = |x: f64, y: f64| Point::new((x - ox).round() as i32, (y - oy).round() as i32);
    let reach = ((rx as f64 - px).abs().max((rx + rw) as f64 - px).powi(2)
        + (ry as f64 - py).abs().max((ry + rh) as f64 - py).powi(2))
    .sqrt();
    // The outline just outside the region's pixels.
    imgproc::rectangle(
        &mut img,
        Rect::new(m - 1, m - 1, rw + 2, rh + 2),
        Scalar::new(0.0, 220.0, 255.0, 0.0),
        1,
        imgproc::LINE_AA,
        0,
    )?;
    let row = d.rows.iter().find(|r| r.frame == f.frame);
    if let Some(a) = row.and_then(|r| r.angle_rad) {
        imgproc::line(
            &mut img,
            pt(px, py),
            pt(px + reach * a.cos(), py + reach * a.sin()),
            Scalar::new(0.0, 0.0, 255.0, 0.0),
            1,
            imgproc::LINE_AA,
            0,
        )?;
    }
    imgproc::circle(
        &mut img,
        pt(px, py),
        4,
        Scalar::new(255.0, 255.0, 0.0, 0.0),
        2,
        imgproc::LINE_AA,
        0,
    )?;
    crate::picture::encode_bgr_mat(&img).with_context(what)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::tuning::PER_SIDE;
    use crate::detect::Flag;

    /// 25 frames/s of a 2 s period swing about 1.5 rad, 8 s; frame `k`'s picture is
    /// one byte, `k`.
    fn swing() -> (Vec<AngleRow>, Vec<Frame>) {
        (0..200u64)
            .map(|k| {
                let t = k as f64 / 25.0;
                let row = AngleRow {
                    frame: k,
                    t_s: t,
                    angle_rad: Some(
                        1.5 + 0.3 * (std::f64::consts::PI * t).cos() * (-0.1 * t).exp(),
                    ),
                    status: Status::Ok,
                    quality: 1.0,
                    flag: None,
                    moments: None,
                };
                let frame = Frame {
                    index: k,
                    t_s: t,
                    width: 1,
                    height: 1,
                    data: vec![k as u8],
                };
                (row, frame)
            })
            .unzip()
    }

    fn detection(rows: Vec<AngleRow>, figure11: Option<Figure11>) -> Detection {
        Detection {
            verdict: crate::detect::judge::judge(&rows, [50.0, -10.0], None, None),
            rows,
            pivot_px: [50.0, -10.0],
            roi: [10, 20, 60, 40],
            dark_wire: true,
            band_px: [10.0, 80.0],
            decoder: "test".into(),
            decodings: 1,
            shutter: None,
            cpu_s: None,
            diagnostics: Vec::new(),
            steps: Vec::new(),
            figure11,
            review: Default::default(),
            swing_scale: None,
            look_sweep_deg: 0.0,
            calibration: None,
            lens: None,
            camera: None,
            moved_from_start: false,
            moved_later_s: None,
        }
    }

    #[test]
    fn the_kept_frame_is_the_rules_choice_even_after_a_demotion() {
        let (mut rows, frames) = swing();
        let mut keeper = Keeper::new(PER_SIDE);
        for (r, f) in rows.iter().zip(&frames) {
            keeper.offer(r, f);
            assert!(keeper.held.len() <= 2 * PER_SIDE);
        }
        // Frame 0 (t = 0, the largest angle) is the rule's choice; after the pass it
        // turns out a repeat and is filled: the rule then picks another, also held.
        let plain = detection(rows.clone(), None);
        assert_eq!(figure11_frame(&plain), 0);
        rows[0].flag = Some(Flag::Duplicate);
        rows[0].status = Status::Corrected;
        let want = figure11_frame(&detection(rows.clone(), None));
        assert_ne!(want, 0);
        let kept = keeper.take(&rows).expect("a frame kept");
        assert_eq!((kept.frame, kept.grey.clone()), (want, vec![want as u8]));
        assert_eq!(figure11_frame(&detection(rows, Some(kept))), want);
    }

    #[test]
    fn without_an_ok_frame_the_first_frame_is_kept() {
        let (mut rows, frames) = swing();
        let mut keeper = Keeper::new(PER_SIDE);
        for (r, f) in rows.iter_mut().zip(&frames) {
            r.flag = Some(Flag::Weak);
            keeper.offer(r, f);
            r.status = Status::Missing;
        }
        assert!(keeper.held.is_empty());
        assert_eq!(keeper.take(&rows).map(|f| f.frame), Some(0));
    }

    #[test]
    fn the_png_shows_the_region_with_the_line_and_pivot() {
        let (rows, _) = swing();
        let grey = vec![200u8; 60 * 40];
        let fig = Figure11 {
            frame: 0,
            width: 60,
            height: 40,
            grey,
        };
        let d = detection(rows, Some(fig));
        let png = figure11_png(&d).unwrap();
        let img = crate::picture::decode(&png).unwrap();
        // The region (60x40) in a margin of 10 px.
        assert_eq!((img.width, img.height), (80, 60));
        let at = |y: usize, x: usize| {
            let i = 3 * (y * img.width + x);
            [img.pixels[i], img.pixels[i + 1], img.pixels[i + 2]]
        };
        // The wire at 1.5 + 0.3 rad from the pivot (50, -10): red where it crosses the
        // region's middle row (y = 40), in the picture at (x - 0, y - 10).
        let a = d.rows[0].angle_rad.unwrap();
        let x = 50.0 + (40.0 + 10.0) / a.tan();
        let px = at(30, x.round() as usize);
        assert!(px[2] > 200 && px[1] < 150, "{px:?} at x {x:.1}");
        // Grey elsewhere in the region, the margin dark.
        assert_eq!(at(45, 20), [200, 200, 200]);
        assert_eq!(at(2, 2), [40, 40, 40]);
    }
}
