//! Pictures for the review page (`reports/<name>/review.html`), kept during the
//! detector's own pass: the region of interest of the frames the gate flags, and of the
//! frames around a release from rest, so that a person can see each doubtful frame and
//! click the wire (`video.marks`) without the video being decoded again.
//!
//! Bounded whatever the video's length:
//! - at most [`MAX_FLAGGED`] flagged frames: when more are flagged, every other one is
//!   let go and only every second, fourth, ... flagged frame is kept from then on, so
//!   the pictures spread over the whole video instead of crowding its start;
//! - at most [`HOLD_FRAMES`] frames of the start: while the wire stays within
//!   [`HOLD_DEG`] of its first accepted angle (a ball held before its release, or the
//!   first frames at a turning point) the latest are kept, up to and including the
//!   frame that leaves; the release frame, found after the pass, is among them unless
//!   the hold's last [`HOLD_FRAMES`] frames were still within that band;
//! - each picture at most [`MAX_SIDE`] px on its longer side (a larger region is
//!   shrunk, area-averaged; the page maps clicks back to full-frame pixels).
//!
//! At the largest, `(MAX_FLAGGED + HOLD_FRAMES) * MAX_SIDE^2` bytes: 20 MiB.

use super::{AngleRow, Flag};
use crate::detect::tuning::{HOLD_DEG, HOLD_FRAMES, MAX_FLAGGED, MAX_SIDE};
use crate::video::Frame;
use anyhow::{Context, Result};
use opencv::core::{self, Mat};
use opencv::imgproc;
use opencv::prelude::*;
use std::collections::VecDeque;

/// One kept frame: its region of interest, grey (shrunk to at most [`MAX_SIDE`]), and
/// what the streaming pass saw in it.
#[derive(Clone)]
pub struct ReviewFrame {
    pub frame: u64,
    pub t_s: f64,
    /// Picture size, px (the region's, or shrunk from it).
    pub width: usize,
    pub height: usize,
    pub grey: Vec<u8>,
    /// The angle the pass measured (before any correction), rad.
    pub detected_rad: Option<f64>,
    /// The angle predicted from the previous frames, rad.
    pub predicted_rad: Option<f64>,
    pub quality: f64,
    pub flag: Option<Flag>,
    /// Position among the flagged frames (0, 1, ...), for the thinning.
    ordinal: u64,
}

impl std::fmt::Debug for ReviewFrame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ReviewFrame")
            .field("frame", &self.frame)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("flag", &self.flag)
            .finish_non_exhaustive()
    }
}

impl ReviewFrame {
    /// `f` as kept, its pixels written into `grey` (a buffer given back for reuse) with
    /// `scratch` for the shrinking.
    fn of(
        row: &AngleRow,
        f: &Frame,
        pred: Option<f64>,
        ordinal: u64,
        mut grey: Vec<u8>,
        scratch: &mut Mat,
    ) -> Result<Self> {
        let (width, height) = shrink(f, &mut grey, scratch)?;
        Ok(Self {
            frame: f.index,
            t_s: f.t_s,
            width,
            height,
            grey,
            detected_rad: row.angle_rad,
            predicted_rad: pred,
            quality: row.quality,
            flag: row.flag,
            ordinal,
        })
    }

    /// The picture as a grey PNG.
    pub fn png(&self) -> Result<Vec<u8>> {
        crate::picture::encode(
            self.width,
            self.height,
            crate::picture::Layout::Grey,
            &self.grey,
        )
        .with_context(|| format!("review picture of frame {}", self.frame))
    }
}

/// The frame's region, shrunk (area average, through `scratch`) so that its longer side
/// is at most [`MAX_SIDE`], into `grey`; returns its size.
fn shrink(f: &Frame, grey: &mut Vec<u8>, scratch: &mut Mat) -> Result<(usize, usize)> {
    grey.clear();
    let side = f.width.max(f.height);
    if side <= MAX_SIDE {
        grey.extend_from_slice(&f.data);
        return Ok((f.width, f.height));
    }
    let s = MAX_SIDE as f64 / side as f64;
    let (w, h) = (
        ((f.width as f64 * s).round() as usize).max(1),
        ((f.height as f64 * s).round() as usize).max(1),
    );
    let src = Mat::new_rows_cols_with_data(f.height as i32, f.width as i32, &f.data)?;
    imgproc::resize(
        &src,
        scratch,
        core::Size::new(w as i32, h as i32),
        0.0,
        0.0,
        imgproc::INTER_AREA,
    )?;
    grey.extend_from_slice(scratch.data_bytes()?);
    Ok((w, h))
}

/// What the pass kept for the review page.
#[derive(Clone, Debug, Default)]
pub struct Review {
    /// Flagged frames, in frame order.
    pub flagged: Vec<ReviewFrame>,
    /// The start's last frames within [`HOLD_DEG`] of the first angle, and the first
    /// beyond it.
    pub hold: Vec<ReviewFrame>,
}

impl Review {
    /// The pictures the review page shows: every kept flagged frame, and the frame at
    /// `release_t_s` (the first frame after a release from rest) when it was kept and
    /// is not flagged. In frame order.
    pub fn pictures(&self, release_t_s: Option<f64>) -> Vec<&ReviewFrame> {
        let mut out: Vec<&ReviewFrame> = self.flagged.iter().collect();
        if let Some(t) = release_t_s {
            let release = self.hold.iter().find(|f| f.t_s > t);
            // Only the frame right after the release: the first kept frame after it
            // must not be a later one (a hold longer than the kept frames).
            let first_after = self.hold.first().is_some_and(|f| f.t_s <= t);
            if let Some(r) = release.filter(|_| first_after) {
                if !out.iter().any(|f| f.frame == r.frame) {
                    out.push(r);
                }
            }
        }
        out.sort_by_key(|f| f.frame);
        out
    }
}

/// Keeps the review pictures during the streaming pass (see the module documentation).
pub(super) struct Keeper {
    review: Review,
    /// Flagged frames seen so far, and the current thinning stride.
    seen: u64,
    stride: u64,
    hold: VecDeque<ReviewFrame>,
    first_angle: Option<f64>,
    holding: bool,
    /// The shrinking's output, reused from frame to frame.
    scratch: Mat,
}

impl Keeper {
    pub(super) fn new() -> Self {
        Self {
            review: Review::default(),
            seen: 0,
            stride: 1,
            hold: VecDeque::new(),
            first_angle: None,
            holding: true,
            scratch: Mat::default(),
        }
    }

    /// Consider `frame`, whose streaming result is `row` and prediction `pred`.
    pub(super) fn offer(&mut self, row: &AngleRow, frame: &Frame, pred: Option<f64>) -> Result<()> {
        if row.flag.is_some() {
            let ordinal = self.seen;
            self.seen += 1;
            if ordinal.is_multiple_of(self.stride) {
                let flagged = &mut self.review.flagged;
                flagged.push(ReviewFrame::of(
                    row,
                    frame,
                    pred,
                    ordinal,
                    Vec::new(),
                    &mut self.scratch,
                )?);
                if flagged.len() > MAX_FLAGGED {
                    self.stride *= 2;
                    let stride = self.stride;
                    flagged.retain(|f| f.ordinal.is_multiple_of(stride));
                }
            }
        }
        if self.holding {
            if let (None, Some(a)) = (row.flag, row.angle_rad) {
                let first = *self.first_angle.get_or_insert(a);
                self.holding = (a - first).abs() <= HOLD_DEG.to_radians();
            }
            // A full ring gives its oldest frame's buffer to the newest: no allocation
            // per frame however long the hold.
            let buffer = if self.hold.len() >= HOLD_FRAMES {
                self.hold.pop_front().map(|f| f.grey).unwrap_or_default()
            } else {
                Vec::new()
            };
            let kept = ReviewFrame::of(row, frame, pred, 0, buffer, &mut self.scratch)?;
            self.hold.push_back(kept);
        }
        Ok(())
    }

    pub(super) fn take(self) -> Review {
        Review {
            hold: self.hold.into(),
            ..self.review
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::Status;

    fn row(k: u64, angle: f64, flag: Option<Flag>) -> AngleRow {
        AngleRow {
            frame: k,
            t_s: k as f64 / 25.0,
            angle_rad: Some(angle),
            status: Status::Ok,
            quality: 0.8,
            flag,
            moments: None,
        }
    }

    fn frame(k: u64, w: usize, h: usize) -> Frame {
        Frame {
            index: k,
            t_s: k as f64 / 25.0,
            width: w,
            height: h,
            data: vec![(k % 251) as u8; w * h],
        }
    }

    #[test]
    fn flagged_frames_are_bounded_and_spread_over_the_video() {
        let mut keeper = Keeper::new();
        // Every 3rd of 3000 frames flagged: 1000 flagged frames.
        for k in 0..3000u64 {
            let flag = k.is_multiple_of(3).then_some(Flag::Gate);
            keeper
                .offer(
                    &row(k, 1.0 + 0.3 * (k as f64 * 0.2).sin(), flag),
                    &frame(k, 8, 6),
                    Some(1.0),
                )
                .unwrap();
            assert!(keeper.review.flagged.len() <= MAX_FLAGGED);
        }
        let r = keeper.take();
        let frames: Vec<u64> = r.flagged.iter().map(|f| f.frame).collect();
        assert!(frames.len() >= MAX_FLAGGED / 2, "{frames:?}");
        assert!(frames.windows(2).all(|w| w[0] < w[1]));
        // From the start to the last tenth of the video, evenly.
        assert_eq!(frames[0], 0);
        assert!(*frames.last().unwrap() > 2700, "{frames:?}");
        let gaps: Vec<u64> = frames.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().all(|&g| g == gaps[0]), "{gaps:?}");
        // Each picture is the frame's own.
        assert!(r.flagged.iter().all(|f| f.grey[0] == (f.frame % 251) as u8));
    }

    #[test]
    fn a_large_region_is_shrunk_to_the_limit() {
        let mut keeper = Keeper::new();
        keeper
            .offer(&row(0, 1.0, Some(Flag::Weak)), &frame(0, 1200, 300), None)
            .unwrap();
        let f = &keeper.take().flagged[0];
        assert_eq!(
            (f.width, f.height, f.grey.len()),
            (MAX_SIDE, 128, MAX_SIDE * 128)
        );
        assert_eq!(f.detected_rad, Some(1.0));
        let png = f.png().unwrap();
        let m = crate::picture::decode(&png).unwrap();
        assert_eq!((m.width, m.height), (MAX_SIDE, 128));
        assert_eq!(m.layout, crate::picture::Layout::Grey);
    }

    #[test]
    fn the_release_frame_is_kept_from_a_held_start() {
        // Held at 1.2 rad for 100 frames, then let go: the angle leaves as 1 - cos.
        let angle = |k: u64| {
            if k < 100 {
                1.2
            } else {
                let t = (k - 100) as f64 / 25.0;
                1.2 - 0.2 * (1.0 - (3.0 * t).cos())
            }
        };
        let mut keeper = Keeper::new();
        for k in 0..300u64 {
            keeper
                .offer(&row(k, angle(k), None), &frame(k, 4, 4), None)
                .unwrap();
        }
        let r = keeper.take();
        assert!(r.hold.len() <= HOLD_FRAMES);
        // The release between frames 99 and 100: frame 100 is the first after it.
        let release_t = 99.5 / 25.0;
        let shown: Vec<u64> = r
            .pictures(Some(release_t))
            .iter()
            .map(|f| f.frame)
            .collect();
        assert_eq!(shown, vec![100]);
        assert!(r.pictures(None).is_empty());
        // A release long before the kept frames (a hold longer than they cover): the
        // kept frame after it is not the release frame, and none is shown.
        assert!(r.pictures(Some(10.0 / 25.0)).is_empty());
    }
}
