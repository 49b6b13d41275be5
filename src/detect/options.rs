//! The settings of one detection.

use crate::config::{Polarity, Video};
use crate::detect::tuning::WORK_SIDE_PX;
use crate::video::Roi;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Settings of one detection.
#[derive(Clone, Debug)]
pub struct DetectOptions {
    pub roi: Option<Roi>,
    pub pivot: Option<[f64; 2]>,
    pub frames: Option<[u64; 2]>,
    pub polarity: Polarity,
    pub threshold_sigma: f64,
    pub gate_deg: f64,
    pub marks: BTreeMap<u64, [[f64; 2]; 2]>,
    /// The plate calibration (`video.calibration`): the angles CSV then holds plate
    /// angles ([`super::Detection::to_csv`]); the detection itself works in the image.
    pub calibration: Option<crate::plane::Calibration>,
    /// The lens's radial distortion (`video.lens`): the angles CSV then holds the
    /// undistorted wire's angles; the detection itself works in the image.
    pub lens: Option<crate::config::LensSpec>,
    /// Folder for the diagnostic images of flagged frames (none if `None`).
    pub diag_dir: Option<PathBuf>,
    /// Pictures of each step of the streaming pass on this frame (`detect --steps`),
    /// kept in [`super::Detection::steps`].
    pub steps: Option<u64>,
    /// Told the frames done (and the header's frame count) every 100 frames; when set,
    /// the detector prints no progress of its own.
    pub progress: Option<FrameProgress>,
    /// Whether the first look's decoder may go on into the streaming pass (a short
    /// video at the look's full size: see `detect::decode_once`); `false` always
    /// decodes the streaming pass anew, cropped to the region of interest. Both give
    /// the same angles, byte for byte; the one decoder is faster on a short video.
    pub decode_once: bool,
    /// The side, px, a frame is shrunk towards by a whole factor before the wire is
    /// measured (`video.work_side_px`; see `FirstLook::at_best_scale`).
    pub work_side_px: f64,
    /// The experiment's pendulum, for the `length` check: the length the period seen
    /// implies against the geometry's `d` ([`crate::pipeline::detect_options`]; `None`,
    /// as for a bare video, leaves it unjudged).
    pub pendulum: Option<PendulumGiven>,
}

/// The pendulum an experiment's geometry describes, and how far (relative, on `d`) the
/// length its period implies may stray from it (`tolerances.period_rel`, as the fit's
/// `period` check).
#[derive(Clone, Copy, Debug)]
pub struct PendulumGiven {
    pub pendulum: crate::physics::Pendulum,
    pub d_rel: f64,
}

/// A progress callback: `(frames done, frames expected)`.
#[derive(Clone)]
pub struct FrameProgress(pub std::sync::Arc<dyn Fn(u64, Option<u64>) + Send + Sync>);

impl std::fmt::Debug for FrameProgress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("FrameProgress")
    }
}

impl Default for DetectOptions {
    fn default() -> Self {
        Self {
            roi: None,
            pivot: None,
            frames: None,
            polarity: Polarity::Auto,
            threshold_sigma: 4.0,
            gate_deg: 1.5,
            marks: BTreeMap::new(),
            calibration: None,
            lens: None,
            diag_dir: None,
            steps: None,
            progress: None,
            decode_once: true,
            work_side_px: WORK_SIDE_PX,
            pendulum: None,
        }
    }
}

impl DetectOptions {
    /// Settings from an experiment's `video:` block (but its plate calibration, which
    /// the experiment fits once: [`crate::pipeline::detect_options`]).
    pub fn from_video(v: &Video) -> Self {
        Self {
            roi: v.roi.map(|[x, y, w, h]| Roi { x, y, w, h }),
            pivot: v.pivot,
            frames: v.frames,
            polarity: v.polarity,
            threshold_sigma: v.threshold_sigma.unwrap_or(4.0),
            gate_deg: v.gate_deg.unwrap_or(1.5),
            marks: v.marks.clone(),
            lens: v.lens,
            work_side_px: v.work_side_px.map_or(WORK_SIDE_PX, f64::from),
            ..Self::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_working_side_comes_from_the_video_block_or_is_the_default() {
        let v: Video = serde_saphyr::from_str("work_side_px: 1280\n").unwrap();
        assert_eq!(DetectOptions::from_video(&v).work_side_px, 1280.0);
        let v: Video = serde_saphyr::from_str("polarity: dark\n").unwrap();
        assert_eq!(DetectOptions::from_video(&v).work_side_px, 640.0);
        assert_eq!(DetectOptions::default().work_side_px, 640.0);
    }
}
