//! What the detector did on one video, as the build caches it and the reports show it.

use super::{Detection, Flag};
use crate::series::Status;
use serde::{Deserialize, Serialize};

/// One flagged frame of a detection.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FlaggedFrame {
    pub frame: u64,
    pub t_s: f64,
    pub status: Status,
    /// Why, when the gate or a check flagged it (`-` in the JSON otherwise).
    #[serde(with = "flag_or_dash")]
    pub flag: Option<Flag>,
}

/// A summary of a detection.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DetectionSummary {
    /// The video as the reports name it (relative to the manifest).
    pub video: String,
    /// SHA-256 of a lab video; the twin's render key for a synthetic one.
    pub video_id: String,
    pub synthetic: bool,
    pub decoder: String,
    pub frames: usize,
    pub ok: usize,
    pub corrected: usize,
    pub manual: usize,
    pub missing: usize,
    pub pivot_px: [f64; 2],
    pub roi: [u32; 4],
    pub dark_wire: bool,
    pub flagged: Vec<FlaggedFrame>,
    pub figure11_frame: u64,
    /// How much more the wire's own direction turns than its angle about the pivot
    /// (1 when the pivot lies on the wire's line): the `pivot` check's value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub swing_scale: Option<f64>,
    /// The plate calibration the angles were measured through, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<crate::plane::CalibrationSummary>,
    /// The camera's own motion, when it moved (each frame was steadied onto the first, or
    /// each from `from_s` on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<super::steady::CameraMotion>,
    /// A rolling shutter's readout, fitted to how the moving wire bows (each angle taken
    /// to its frame's time), when one stood clear of the bows' noise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shutter: Option<super::shutter::WireReadout>,
    /// The lens the angles were measured through (`video.lens`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lens: Option<crate::lens::SeenThrough>,
    /// Whether what was followed is a pendulum's wire, with what it saw.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verdict: Option<super::judge::DetectionVerdict>,
}

impl DetectionSummary {
    /// Summarise `d`, a detection of the video named `video` with content id `video_id`.
    pub fn of(
        d: &Detection,
        video: String,
        video_id: String,
        synthetic: bool,
        figure11_frame: u64,
    ) -> Self {
        let flagged = d
            .rows
            .iter()
            .filter(|r| r.flag.is_some() || r.status != Status::Ok)
            .map(|r| FlaggedFrame {
                frame: r.frame,
                t_s: r.t_s,
                status: r.status,
                flag: r.flag,
            })
            .collect();
        Self {
            video,
            video_id,
            synthetic,
            decoder: d.decoder.clone(),
            frames: d.rows.len(),
            ok: d.count(Status::Ok),
            corrected: d.count(Status::Corrected),
            manual: d.count(Status::Manual),
            missing: d.count(Status::Missing),
            pivot_px: d.pivot_px,
            roi: d.roi,
            dark_wire: d.dark_wire,
            flagged,
            figure11_frame,
            swing_scale: d.swing_scale,
            calibration: d.calibration.as_ref().map(Into::into),
            camera: d.camera,
            shutter: d.shutter,
            lens: d.lens.map(|lens| crate::lens::SeenThrough {
                lens,
                band_px: d.band_px,
            }),
            verdict: Some(d.verdict.clone()),
        }
    }
}

/// One picture of the review page as the build caches it (`review.json` beside the
/// PNG files): the frame, the picture's file name and size, and what the pass saw.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ReviewPicture {
    pub frame: u64,
    pub t_s: f64,
    /// The PNG's file name (`frame-000123.png`).
    pub file: String,
    /// The picture's size, px: the region of interest's, or shrunk from it.
    pub width: usize,
    pub height: usize,
    /// The angle the pass measured, before any correction, rad.
    pub detected_rad: Option<f64>,
    /// The angle predicted from the previous frames, rad.
    pub predicted_rad: Option<f64>,
    pub quality: f64,
    #[serde(with = "flag_or_dash")]
    pub flag: Option<Flag>,
}

impl ReviewPicture {
    /// The cached description of `f`.
    pub fn of(f: &super::ReviewFrame) -> Self {
        Self {
            frame: f.frame,
            t_s: f.t_s,
            file: format!("frame-{:06}.png", f.frame),
            width: f.width,
            height: f.height,
            detected_rad: f.detected_rad,
            predicted_rad: f.predicted_rad,
            quality: f.quality,
            flag: f.flag,
        }
    }
}

mod flag_or_dash {
    use super::Flag;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(f: &Option<Flag>, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(f.map_or("-", |f| f.as_str()))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Flag>, D::Error> {
        let s = String::deserialize(d)?;
        if s == "-" {
            return Ok(None);
        }
        Flag::parse(&s)
            .map(Some)
            .ok_or_else(|| serde::de::Error::custom(format!("unknown flag `{s}`")))
    }
}
