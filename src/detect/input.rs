//! Where the detector's frames come from: a [`VideoInput`] tells the video's size and
//! opens streams of grey frames cropped to a region (and shrunk by an integer factor).
//! [`VideoFile`] decodes a file (the `ffmpeg` program, a decoder started ahead of each
//! stream: see [`VideoInput::prepare`]); [`MemoryVideo`] holds frames
//! made in memory, so that the whole detector can be tested without a decoder or a
//! file.

use crate::detect::tuning::MAX_FRAME_PIXELS;
use crate::video::{Decoder, Frame, FrameSource, Roi, VideoInfo};
use anyhow::{bail, Result};
use std::path::{Path, PathBuf};

/// A video the detector can read, as often as it needs to.
pub trait VideoInput {
    /// The video's size and header facts.
    fn info(&self) -> &VideoInfo;
    /// What the messages call the video (its path).
    fn name(&self) -> String;
    /// What decodes the frames, as the detection reports it.
    fn decoder(&self) -> String;
    /// The frames from the first, cropped to `roi` and, when `shrink > 1`, shrunk by
    /// that factor (each pixel the mean of a `shrink` x `shrink` block of the crop;
    /// `roi.w / shrink` x `roi.h / shrink` pixels).
    fn open(&self, roi: Roi, shrink: u32) -> Result<Box<dyn FrameSource + '_>>;
    /// The frames from the first, cropped to `roi` at full size, with up to
    /// `ahead_bytes` of them decoded ahead of the reader (by default, [`VideoInput::open`]
    /// unshrunk: frames in memory are there already).
    fn open_ahead(&self, roi: Roi, _ahead_bytes: usize) -> Result<Box<dyn FrameSource + '_>> {
        self.open(roi, 1)
    }
    /// Another [`VideoInput::open`] will follow: its decoder may start now, so that its
    /// start-up overlaps the work in between (by default, nothing to do).
    fn prepare(&self) {}
}

/// A video file, decoded by the `ffmpeg` program (luma plane, cropped and shrunk by
/// ffmpeg). The decoder that described the video at [`VideoFile::open`] serves the first
/// stream; [`VideoInput::prepare`] starts the next one's ahead of it.
pub struct VideoFile {
    path: PathBuf,
    info: VideoInfo,
    /// A decoder started and waiting for its filters, for the next stream.
    ready: std::sync::Mutex<Option<Decoder>>,
}

impl std::fmt::Debug for VideoFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VideoFile")
            .field("path", &self.path)
            .field("info", &self.info)
            .finish_non_exhaustive()
    }
}

impl VideoFile {
    /// Start decoding `path` far enough to know the video (refused when the `ffmpeg`
    /// program is not installed).
    pub fn open(path: &Path) -> Result<Self> {
        let decoder = Decoder::start(path)?;
        let info = decoder.info().clone();
        let pixels = u64::from(info.width) * u64::from(info.height);
        if pixels > MAX_FRAME_PIXELS {
            anyhow::bail!(
                "{}: the frames are {} x {} px; the detector takes at most {MAX_FRAME_PIXELS} px a frame (8192 x 8192)",
                path.display(),
                info.width,
                info.height
            );
        }
        Ok(Self {
            path: path.to_path_buf(),
            info,
            ready: std::sync::Mutex::new(Some(decoder)),
        })
    }

    /// The waiting decoder, or a new one.
    fn take_decoder(&self) -> Result<Decoder> {
        let ready = self.ready.lock().ok().and_then(|mut r| r.take());
        match ready {
            Some(d) => Ok(d),
            None => Decoder::spawn(&self.path),
        }
    }
}

impl VideoInput for VideoFile {
    fn info(&self) -> &VideoInfo {
        &self.info
    }

    fn name(&self) -> String {
        self.path.display().to_string()
    }

    fn decoder(&self) -> String {
        "ffmpeg (luma plane, cropped)".to_string()
    }

    fn open(&self, roi: Roi, shrink: u32) -> Result<Box<dyn FrameSource + '_>> {
        Ok(Box::new(self.take_decoder()?.run(Some(roi), shrink)?))
    }

    fn open_ahead(&self, roi: Roi, ahead_bytes: usize) -> Result<Box<dyn FrameSource + '_>> {
        Ok(Box::new(self.take_decoder()?.run_ahead(
            Some(roi),
            1,
            ahead_bytes,
        )?))
    }

    fn prepare(&self) {
        if let Ok(mut ready) = self.ready.lock() {
            if ready.is_none() {
                // Started, not waited for: it loads and opens the video meanwhile. Best
                // effort: one that cannot start now is started (and its refusal
                // reported) by the `open` that needs it.
                *ready = Decoder::spawn(&self.path).ok();
            }
        }
    }
}

/// Grey frames held in memory (`width * height` bytes each, row-major), at a steady
/// frame rate: cropping and shrinking are done here, no decoder is involved.
#[derive(Clone, Debug)]
pub struct MemoryVideo {
    info: VideoInfo,
    fps: f64,
    frames: Vec<Vec<u8>>,
}

impl MemoryVideo {
    /// Frames of `width` x `height` grey pixels, frame `k` at `k / fps` s.
    pub fn new(width: u32, height: u32, fps: f64, frames: Vec<Vec<u8>>) -> Result<Self> {
        if width == 0 || height == 0 || !fps.is_finite() || fps <= 0.0 {
            bail!("in-memory video: {width}x{height} px at {fps} frames/s");
        }
        let len = width as usize * height as usize;
        if let Some(k) = frames.iter().position(|f| f.len() != len) {
            bail!(
                "in-memory video: frame {k} has {} bytes, expected {len} ({width}x{height})",
                frames[k].len()
            );
        }
        Ok(Self {
            info: VideoInfo {
                width,
                height,
                frames_header: Some(frames.len() as u64),
                duration_s: Some(frames.len() as f64 / fps),
                codec: "grey frames in memory".to_string(),
                luma_plane: true,
            },
            fps,
            frames,
        })
    }

    /// Frame `k`'s full grey picture.
    pub fn frame(&self, k: usize) -> Option<&[u8]> {
        self.frames.get(k).map(Vec::as_slice)
    }
}

impl VideoInput for MemoryVideo {
    fn info(&self) -> &VideoInfo {
        &self.info
    }

    fn name(&self) -> String {
        "in-memory video".to_string()
    }

    fn decoder(&self) -> String {
        "in memory (cropped)".to_string()
    }

    fn open(&self, roi: Roi, shrink: u32) -> Result<Box<dyn FrameSource + '_>> {
        let (w, h) = (self.info.width, self.info.height);
        if roi.w == 0 || roi.h == 0 || roi.x + roi.w > w || roi.y + roi.h > h {
            bail!("in-memory video: region {roi:?} does not fit in the {w}x{h} frame");
        }
        let shrink = shrink.max(1);
        if roi.w < shrink || roi.h < shrink {
            bail!("in-memory video: region {roi:?} is smaller than the shrink factor {shrink}");
        }
        Ok(Box::new(MemorySource {
            video: self,
            roi,
            shrink,
            next: 0,
        }))
    }
}

/// The `w` x `h` pixels from `(x, y)` of a grey picture `stride` pixels wide, row by row
/// into `out` (what a decoder's crop gives).
pub(super) fn crop_rows(
    src: &[u8],
    stride: usize,
    (x, y): (usize, usize),
    (w, h): (usize, usize),
    out: &mut Vec<u8>,
) {
    out.clear();
    out.reserve(w * h);
    for row in src.chunks_exact(stride).skip(y).take(h) {
        out.extend_from_slice(&row[x..x + w]);
    }
}

/// The frames of a [`MemoryVideo`], cropped and shrunk.
struct MemorySource<'a> {
    video: &'a MemoryVideo,
    roi: Roi,
    shrink: u32,
    next: usize,
}

impl FrameSource for MemorySource<'_> {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        let Some(full) = self.video.frames.get(self.next) else {
            return Ok(false);
        };
        let stride = self.video.info.width as usize;
        let s = self.shrink as usize;
        let (x0, y0) = (self.roi.x as usize, self.roi.y as usize);
        let (ow, oh) = (self.roi.w as usize / s, self.roi.h as usize / s);
        if s == 1 {
            crop_rows(full, stride, (x0, y0), (ow, oh), &mut frame.data);
        } else {
            frame.data.clear();
            frame.data.reserve(ow * oh);
            // Each pixel the rounded mean of its block.
            let n = (s * s) as u32;
            for oy in 0..oh {
                for ox in 0..ow {
                    let mut sum = 0u32;
                    for y in y0 + oy * s..y0 + (oy + 1) * s {
                        let row = &full[y * stride..];
                        sum += row[x0 + ox * s..x0 + (ox + 1) * s]
                            .iter()
                            .map(|&v| v as u32)
                            .sum::<u32>();
                    }
                    frame.data.push(((sum + n / 2) / n) as u8);
                }
            }
        }
        frame.width = ow;
        frame.height = oh;
        frame.index = self.next as u64;
        frame.t_s = self.next as f64 / self.video.fps;
        self.next += 1;
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_frames_are_cropped_and_shrunk_by_block_means() {
        // 6x4 pixels valued 10 x + y, two frames at 10 frames/s.
        let (w, h) = (6u32, 4u32);
        let f: Vec<u8> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (10 * x + y) as u8))
            .collect();
        let v = MemoryVideo::new(w, h, 10.0, vec![f.clone(), f]).unwrap();
        let mut src = v
            .open(
                Roi {
                    x: 1,
                    y: 1,
                    w: 4,
                    h: 3,
                },
                1,
            )
            .unwrap();
        let mut fr = Frame::default();
        assert!(src.next_frame(&mut fr).unwrap());
        assert_eq!((fr.width, fr.height), (4, 3));
        assert_eq!(&fr.data[..4], &[11, 21, 31, 41]);
        assert_eq!(&fr.data[8..], &[13, 23, 33, 43]);
        assert!(src.next_frame(&mut fr).unwrap());
        assert_eq!((fr.index, fr.t_s), (1, 0.1));
        assert!(!src.next_frame(&mut fr).unwrap());
        // Shrunk 2x from (1, 0): blocks {11, 21, 10, 20} -> 15.5 -> 16, then 36 (35.5).
        let mut src = v
            .open(
                Roi {
                    x: 1,
                    y: 0,
                    w: 5,
                    h: 4,
                },
                2,
            )
            .unwrap();
        assert!(src.next_frame(&mut fr).unwrap());
        assert_eq!((fr.width, fr.height), (2, 2));
        assert_eq!(fr.data, vec![16, 36, 18, 38]);
    }
}
