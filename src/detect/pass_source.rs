//! The streaming pass's frames: the first look's decoder going on, its frames cut to the
//! region of interest (and a moving camera's warped back), or a decoder cropping to it.

use super::{input, steady};
use crate::video::{Frame, FrameSource, Roi};
use anyhow::{ensure, Result};

/// The first look's frames as decoded and its decoder, going on into the streaming
/// pass (see [`decode_once`](super::first_look::decode_once)).
pub(super) struct Continued<'a> {
    /// The look's frames, as decoded (no brightness correction), from the first asked for.
    pub(super) held: std::collections::VecDeque<Frame>,
    /// The rest of the stream (none when the frames asked for end within the look).
    pub(super) rest: Option<Box<dyn FrameSource + 'a>>,
    /// The region the decoder crops (the look's), in which the streaming pass's lies.
    pub(super) bound: Roi,
}

/// The frames of a [`Continued`] look, each cut to `roi` (which lies within the look's
/// region): the bytes a decoder cropping to `roi` gives.
pub(super) struct CropSource<'a> {
    from: Continued<'a>,
    roi: Roi,
    /// The frame as decoded, at the look's region.
    full: Frame,
    /// A moving camera: the frames from this index on are warped back onto the first of
    /// them.
    pub(super) steady_from: Option<u64>,
    steady: Option<steady::Steady>,
    /// The pendulum's part of the look's region, which the steadying does not read.
    sweep: steady::Sweep,
    pub(super) followed: steady::Followed,
    warped: opencv::core::Mat,
}

impl<'a> CropSource<'a> {
    /// The frames of `from` cut to `roi`, which must lie within the look's region; with
    /// `steady_from`, each frame from that index on warped back onto the first of them.
    pub(super) fn new(
        from: Continued<'a>,
        roi: Roi,
        steady_from: Option<u64>,
        sweep: steady::Sweep,
    ) -> Result<Self> {
        let bound = from.bound;
        ensure!(
            roi.x >= bound.x
                && roi.y >= bound.y
                && roi.x + roi.w <= bound.x + bound.w
                && roi.y + roi.h <= bound.y + bound.h,
            "the region {roi:?} does not lie within the first look's {bound:?}"
        );
        Ok(Self {
            from,
            roi,
            full: Frame::default(),
            steady_from,
            steady: None,
            sweep,
            followed: steady::Followed::default(),
            warped: opencv::core::Mat::default(),
        })
    }
}

/// The streaming pass's frames: cut from the first look's (or a moving camera's), or
/// from a decoder cropping to the region of interest.
pub(super) enum PassSource<'a> {
    Crop(Box<CropSource<'a>>),
    Decoder(Box<dyn FrameSource + 'a>),
}

impl PassSource<'_> {
    pub(super) fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        match self {
            PassSource::Crop(c) => c.next_frame(frame),
            PassSource::Decoder(d) => d.next_frame(frame),
        }
    }

    /// The camera's motion the frames were warped back from, when it moved.
    pub(super) fn camera(&self) -> Option<steady::CameraMotion> {
        match self {
            PassSource::Crop(c) => c.steady_from.map(|_| c.followed.camera()),
            PassSource::Decoder(_) => None,
        }
    }
}

impl FrameSource for CropSource<'_> {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        match self.from.held.pop_front() {
            Some(f) => {
                let spent = std::mem::replace(&mut self.full, f);
                if let Some(rest) = &mut self.from.rest {
                    rest.recycle(spent.data);
                }
            }
            None => {
                let more = match &mut self.from.rest {
                    Some(rest) => rest.next_frame(&mut self.full)?,
                    None => false,
                };
                if !more {
                    return Ok(false);
                }
            }
        }
        let (bound, roi, full) = (self.from.bound, self.roi, &self.full);
        ensure!(
            full.width == bound.w as usize && full.height == bound.h as usize,
            "frame {}: decoded at {}x{} px, not at the first look's {}x{}",
            full.index,
            full.width,
            full.height,
            bound.w,
            bound.h
        );
        let origin = ((roi.x - bound.x) as usize, (roi.y - bound.y) as usize);
        let size = (roi.w as usize, roi.h as usize);
        match self.steady_from.filter(|&from| full.index >= from) {
            Some(_) => {
                let st = match &mut self.steady {
                    Some(st) => st,
                    None => self
                        .steady
                        .insert(steady::Steady::new(full, Some(&self.sweep))?),
                };
                let m = self.followed.next(st, full)?;
                steady::warp_into(full, m, origin, size, &mut self.warped)?;
                frame.data.clear();
                frame.data.extend_from_slice(steady::bytes(&self.warped)?);
            }
            None => input::crop_rows(&full.data, full.width, origin, size, &mut frame.data),
        }
        frame.width = roi.w as usize;
        frame.height = roi.h as usize;
        frame.index = full.index;
        frame.t_s = full.t_s;
        Ok(true)
    }
}
