//! What a detection gives: each frame's row (angle, status, flag) and the whole
//! detection, with its CSV.

use super::{Figure11, Review};
use serde::Serialize;
use std::path::PathBuf;

pub use crate::series::Status;

/// Why a frame was flagged.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Flag {
    /// The measured angle is too far from the prediction.
    Gate,
    /// Too little of the wire was seen.
    Weak,
    /// The whole frame's brightness jumped (a flash).
    Flash,
    /// The frame repeats the previous one (a dropped frame).
    Duplicate,
    /// Much of the region changed at once (a hand or a shadow passing).
    Disturbed,
    /// A few frames found between two losses of the wire (a person passing in front of
    /// it): not trusted on their own.
    Isolated,
    /// The angle leaves the smooth path of the found frames about it, as a wire cannot
    /// (a shadow or an edge taken for one frame).
    Jump,
    /// The camera moves, and this frame's motion could not be measured (a person hid
    /// the static scene): the angle, steadied by the last motion measured, is a guess.
    Unsteadied,
    /// Near a loss of the wire, the angle leaves the swing's path through the found
    /// frames about it (the track took up something else: a person's edge).
    OffSwing,
    /// The frame's run of found frames leaps from or to a longer run by more than a
    /// swing can turn (the track sat on something else for a while).
    Leapt,
    /// A few frames found beyond every angle the longer runs reached: a swing never
    /// grows (the track took up a person's edge as they passed).
    Beyond,
    /// The track stands still beyond the swing before it, where a wire does not come to
    /// rest (after a loss of the wire it took a static line).
    StillBeyond,
    /// The angle lies where something static in the swing's path (a rod or an edge
    /// through the pivot) pulls the angles of every swing the same way.
    Pulled,
}

impl Flag {
    /// The name the reports use (as serialised).
    pub fn as_str(&self) -> &'static str {
        match self {
            Flag::Gate => "gate",
            Flag::Weak => "weak",
            Flag::Flash => "flash",
            Flag::Duplicate => "duplicate",
            Flag::Disturbed => "disturbed",
            Flag::Isolated => "isolated",
            Flag::Jump => "jump",
            Flag::Unsteadied => "unsteadied",
            Flag::OffSwing => "off-swing",
            Flag::Leapt => "leapt",
            Flag::Beyond => "beyond-swing",
            Flag::StillBeyond => "still-beyond",
            Flag::Pulled => "pulled",
        }
    }

    /// The flag named `s` (as [`Flag::as_str`] writes it).
    pub fn parse(s: &str) -> Option<Self> {
        [
            Flag::Gate,
            Flag::Weak,
            Flag::Flash,
            Flag::Duplicate,
            Flag::Disturbed,
            Flag::Isolated,
            Flag::Jump,
            Flag::Unsteadied,
            Flag::OffSwing,
            Flag::Leapt,
            Flag::Beyond,
            Flag::StillBeyond,
            Flag::Pulled,
        ]
        .into_iter()
        .find(|f| f.as_str() == s)
    }
}

/// The moments a found frame keeps of its wire's strip, re-centred on its own free
/// line: `[whole, far]` (indexed 0 and 1), the whole band's strip (the swing scale's
/// check) and the strip beyond [`crate::detect::tuning::FREE_STRIP_FROM`] of the band's
/// outer radius (the pivot's refinement and the angles' refit), where no shadow or
/// static edge merges with the wire near the pivot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeptMoments {
    pub moments: [[f64; 6]; 2],
    /// Whether each strip was re-centred on the wire's free line. One that was not
    /// (its free line left the pivot's line, or too few pixels) keeps the strip about
    /// the line through the current pivot: its free line leans towards that pivot and
    /// says little about where the wire's lines meet (see `Tracker::refine_pivot`).
    pub free: [bool; 2],
    /// How the whole strip, re-centred, bows (the `bent` check's evidence); `None`
    /// when it was not re-centred.
    pub bow: Option<crate::lens::bow::Bowed>,
    /// Through a lens (`video.lens`), the same two strips' moments with each pixel
    /// taken into the undistorted view (the working scale's pixels of it): the wire's
    /// free lines there, whatever the weights along it (`Tracker::refine_pivot`).
    pub plate: Option<[[f64; 6]; 2]>,
}

impl std::ops::Index<usize> for KeptMoments {
    type Output = [f64; 6];

    fn index(&self, i: usize) -> &[f64; 6] {
        &self.moments[i]
    }
}

/// One frame's result.
#[derive(Clone, Debug, Serialize)]
pub struct AngleRow {
    pub frame: u64,
    pub t_s: f64,
    /// Angle of the wire from the image x axis (y down), rad; `None` when missing.
    pub angle_rad: Option<f64>,
    pub status: Status,
    /// 0..1: the fraction of the wire's visible band covered by detected pixels.
    pub quality: f64,
    pub flag: Option<Flag>,
    /// Weighted moments of the wire pixels `[sum w, sum w x, sum w y, sum w x^2,
    /// sum w x y, sum w y^2]` (working-scale region pixels), so that the angle can be
    /// refitted about a refined pivot after the pass ([`KeptMoments`]).
    #[serde(skip)]
    pub moments: Option<KeptMoments>,
}

impl AngleRow {
    /// The angle of a frame found and not flagged (none otherwise): what the checks
    /// after the pass judge and the fill fills from.
    pub(crate) fn unflagged_angle(&self) -> Option<f64> {
        self.angle_rad.filter(|_| self.flag.is_none())
    }

    /// Whether the wire was seen in the frame: `ok`, or seen where something static
    /// pulled its angle (`Flag::Pulled`) and filled from the frames either side. What
    /// the detection's verdict judges the swing by.
    pub(crate) fn seen_on_wire(&self) -> bool {
        self.status == Status::Ok || (self.flag == Some(Flag::Pulled) && self.angle_rad.is_some())
    }
}

#[cfg(test)]
impl AngleRow {
    /// A frame found (`ok`, full quality, unflagged) at `t_s` with `angle_rad`: the
    /// unit tests' hand-made series.
    pub(crate) fn found(frame: u64, t_s: f64, angle_rad: f64) -> Self {
        AngleRow {
            frame,
            t_s,
            angle_rad: Some(angle_rad),
            status: Status::Ok,
            quality: 1.0,
            flag: None,
            moments: None,
        }
    }
}

/// A detection's processor time, s, before its first streaming pass and from then on
/// ([`Detection::cpu_s`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CpuSplit {
    pub before_pass: f64,
    pub pass: f64,
}

/// The result of a detection.
#[derive(Clone, Debug, Serialize)]
pub struct Detection {
    pub rows: Vec<AngleRow>,
    /// Whether what was followed is a pendulum's wire, and what it saw.
    pub verdict: super::judge::DetectionVerdict,
    pub pivot_px: [f64; 2],
    pub roi: [u32; 4],
    pub dark_wire: bool,
    pub band_px: [f64; 2],
    pub decoder: String,
    /// How many times the video was decoded from its start: 1 when the first look's
    /// decoder went on into the streaming pass (a short video), one more for each
    /// first look otherwise.
    #[serde(skip)]
    pub decodings: usize,
    /// The detector's processor time (this process's; the decoder is another), s: from
    /// the detection's start to its first streaming pass (the first look, its geometry,
    /// and any look made again before it: a cost fixed per video; with the frames a
    /// reader thread copies ahead meanwhile), and from then to the detection's end (the
    /// pass, and any pass made again with the look made again for it, and the later
    /// looks and the measurement again of a failed `length` check: on a still camera
    /// measured once, the cost per frame). None where the clock cannot be read, or
    /// before the detection ends. Not in the JSON: it differs from run to run.
    #[serde(skip)]
    pub cpu_s: Option<CpuSplit>,
    pub diagnostics: Vec<PathBuf>,
    /// `detect --steps`: the pictures of the frame's steps (file name, PNG bytes), of
    /// the pass that was kept; empty when the frame was not measured.
    #[serde(skip)]
    pub steps: Vec<(String, Vec<u8>)>,
    /// The frame shown as Figure 11 ([`super::figure11_frame`]), kept by the pass.
    #[serde(skip)]
    pub figure11: Option<Figure11>,
    /// The pictures kept for the review page.
    #[serde(skip)]
    pub review: Review,
    /// How much more the wire's own direction turns than its angle about the pivot
    /// (1 when the pivot lies on the wire's line; see the `pivot` check).
    pub swing_scale: Option<f64>,
    /// The range of directions the first look's lines took, deg (`geometry::sweep_deg`):
    /// about the swing's own peak to peak when the look saw what the pass followed.
    #[serde(skip)]
    pub look_sweep_deg: f64,
    /// The plate calibration the angles CSV is measured through (the rows keep image
    /// angles).
    #[serde(skip)]
    pub calibration: Option<crate::plane::Calibration>,
    /// The lens the angles CSV is measured through (`video.lens`; the rows keep image
    /// angles).
    #[serde(skip)]
    pub lens: Option<crate::lens::Lens>,
    /// The camera's own motion, when it moved (each frame was warped back onto the
    /// first: see `steady`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<super::steady::CameraMotion>,
    /// A rolling shutter's readout, fitted to how the moving wire bows, with each angle
    /// taken to its frame's time (see `shutter::wire`). Absent: none stood clear of the
    /// bows' noise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shutter: Option<super::shutter::WireReadout>,
    /// The camera, taken as still by the first look, was found moving from the pass's
    /// start: its first frames were not steadied (`detect` measures it again).
    #[serde(skip)]
    pub moved_from_start: bool,
    /// The camera was found moving by a later glance, from this time, s, after glances
    /// that found it still: the frames before were not steadied (`detect` measures it
    /// again, every frame steadied).
    #[serde(skip)]
    pub moved_later_s: Option<f64>,
}

impl Detection {
    /// Count of rows per status.
    pub fn count(&self, st: Status) -> usize {
        self.rows.iter().filter(|r| r.status == st).count()
    }

    /// Each row's angle as the CSV gives it: the image angle, or with a plate
    /// calibration the plate angle of the wire through the pivot (kept continuous), or
    /// through a lens (`video.lens`) the undistorted wire's.
    pub fn angles(&self) -> Vec<Option<f64>> {
        let image: Vec<Option<f64>> = self.rows.iter().map(|r| r.angle_rad).collect();
        match (&self.calibration, &self.lens) {
            (Some(c), _) => c.plate_angles(self.pivot_px, &image),
            (None, Some(l)) => l.plate_angles(self.pivot_px, self.band_px, &image),
            (None, None) => image,
        }
    }

    /// CSV: `t_s,angle_rad,status,quality` (angle empty when missing); with a plate
    /// calibration, `angle_rad` is the plate angle ([`Detection::angles`]).
    pub fn to_csv(&self) -> String {
        let mut out = String::with_capacity(40 * self.rows.len() + 32);
        out.push_str("t_s,angle_rad,status,quality\n");
        for (r, a) in self.rows.iter().zip(self.angles()) {
            let a = a.map(|a| format!("{a:.9}")).unwrap_or_default();
            out.push_str(&format!(
                "{:.6},{a},{},{:.3}\n",
                r.t_s,
                r.status.as_str(),
                r.quality
            ));
        }
        out
    }
}
