//! The `synthetic:` block of an experiment file: the digital twin's truth, its camera
//! and its room (serde structs with their units, defaults and docs).

use super::air::AirFile;
use super::file::{default_beta, BetaSpec};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The digital twin's parameters: the truth the pipeline must measure back.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Synthetic {
    /// True rolling-friction coefficient `s_r`, m·N^(1-beta).
    pub s_r_m: f64,
    /// True exponent. Default 1.
    #[serde(default = "default_beta")]
    pub beta: BetaSpec,
    /// The air the twin's ball moves through (its own `model`, temperature, pressure,
    /// wall factor, or a constant `drag_coefficient`). Default: the experiment's `air`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub air: Option<AirFile>,
    /// Release amplitude `psi_0`, degrees. Default 10.
    #[serde(default = "default_psi0")]
    pub psi0_deg: f64,
    /// Recording length, s. Default: until the ball stops plus 2 s, at most 120 s.
    pub duration_s: Option<f64>,
    /// Camera frame rate, frames/s. Default 60.
    #[serde(default = "default_fps")]
    pub fps: f64,
    /// Angle of the wire at rest, from the image x axis (y down), degrees: any angle,
    /// the camera's roll over the full circle (the plate, the protractor and the wire
    /// turn with it; the style's own turn is added). Taken into (-180, 180] for the
    /// truth, whose angles stay continuous around it (within `psi0_deg` of it, so they
    /// may pass 180). Default 91.7 (a camera turned 1.7 degrees).
    #[serde(default = "default_rest_angle")]
    pub rest_angle_deg: f64,
    /// Random seed for noise. Default 1.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Per-frame noise of the simulated angle series when the twin stands in for a
    /// detector, degrees. Default 0.05.
    #[serde(default = "default_angle_noise")]
    pub angle_noise_deg: f64,
    /// Rendered video width, px. Default 1280.
    #[serde(default = "default_width")]
    pub width: u32,
    /// Rendered video height, px. Default 720.
    #[serde(default = "default_height")]
    pub height: u32,
    /// Look of the rendered scene. Default `dark-wire`.
    #[serde(default)]
    pub style: Style,
    /// Number of spoiled frames (a hand passing, a flash, a duplicated frame, in turn).
    /// Default 3.
    #[serde(default = "default_spoiled")]
    pub spoiled_frames: u32,
    /// Render without camera defects (noise, blur, drift, flicker, spoiled frames): for
    /// debugging the detector. Default false.
    #[serde(default)]
    pub clean: bool,
    /// The image mirrored left-right, as a phone's front camera or a view in a mirror
    /// films it: the whole frame is flipped (the numerals read backwards, the light
    /// comes from the other side), so a wire at image angle `theta` is seen at
    /// `pi - theta`, and the truth (`rest_angle_rad`, every frame's angle, the pivot)
    /// is the mirrored one. Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub mirror: bool,
    /// Width of the wire as drawn at the output resolution, px, 1 to 32 (the pixels'
    /// own integration and, with camera defects, the defocus soften it further): 1 for
    /// a thin wire filmed from afar. Default `height / 288` kept within 2 to 3 px (2.5
    /// px at 720 lines, 2 px at 540 or fewer).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wire_width_px: Option<f64>,
    /// The wire's contrast against what lies behind it, as a fraction of the style's,
    /// 0 to 1: the wire's colour is mixed with the background's in this proportion
    /// (0.3 a faint wire, 0 none). Default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wire_contrast: Option<f64>,
    /// A soft shadow of the wire on the plate: a second, blurred line from the fulcrum,
    /// as long as the wire, at a small angle from it, moving with it, darker than the
    /// plate (whatever the wire's colour). Absent: no shadow (the default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shadow: Option<WireShadow>,
    /// Frequency of the lights' flicker, Hz, more than 0 and at most 10000 (100 on
    /// 50 Hz mains, 120 on 60 Hz). Each frame is lit as at its mid-exposure instant, so
    /// the flicker shows as its alias at the frame rate (a beat): none at all when the
    /// frame rate divides it (100 Hz at 25 or 50 frames/s). Camera defects only (not
    /// with `clean`). Default 100.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flicker_hz: Option<f64>,
    /// Depth of the flicker: the amplitude of the frame brightness's relative
    /// modulation, 0 to 0.5 (0.15 for strong flicker), plus a random 0.4 % per frame.
    /// Camera defects only. Default 0.012.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flicker_depth: Option<f64>,
    /// Strength of the slow lighting drift (three sines with periods of 15 to 60 s):
    /// the sum of their relative amplitudes, 0 to 0.5. Camera defects only. Default
    /// 0.08.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drift_depth: Option<f64>,
    /// The operator holds the ball at its release angle `psi0_deg` for this long from
    /// the start of the recording, s, then lets go: the wire stands still until
    /// `hold_s`, and the motion (the same as without a hold, `s_r_m` unchanged) starts
    /// from rest there. Zero or more, less than `duration_s`; a default duration (until
    /// the ball stops plus 2 s, at most 120 s) counts from the start, hold included.
    /// Also shifts the angle series `rollfric simulate` writes. Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hold_s: Option<f64>,
    /// The operator's hand holds the ball until `hold_s` and then draws back, out of the
    /// way in 0.4 s: a hand seen from above, its fingers on the ball from beyond it, its
    /// arm reaching away from the fulcrum (the wire stays in view; the frames are not
    /// spoiled). Needs `hold_s`. Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub release_hand: bool,
    /// Where the fulcrum is in the image, `[x, y]` as fractions of the width and the
    /// height from the top left corner, each -1 to 2: anywhere, also outside the frame
    /// (`[0.5, -0.05]`: just above it). The wire is then as long as keeps the ball's
    /// swing 3 % inside the frame's edges (at most 60 % of the height), and the render
    /// is refused when no wire of a tenth of the frame does, or when less than half of
    /// the wire would be in the frame. Default: the wire's swing, ball included,
    /// centred in the frame with the wire 60 % of the height or as long as fits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pivot_frac: Option<[f64; 2]>,
    /// Variable frame rate, as a phone records: frame `k` is at `(k + j u_k) / fps`, `j`
    /// this value (0 to 0.9 of a frame interval) and `u_k` in [0, 1) from the seed
    /// (`u_0 = 0`), rounded to the millisecond; each frame is rendered at its own time,
    /// the truth gives it, and the video carries it (a decoder that keeps timestamps,
    /// such as ffmpeg with `-fps_mode passthrough`, returns it). In `.avi` the stream
    /// counts milliseconds, with empty chunks between frames, as FFmpeg writes a variable rate there (so its
    /// header's frame count is the milliseconds'); `.mkv` and `.mp4` carry the times as
    /// such. At least 2 ms between frames: `(1 - j) / fps` >= 0.002 s. Default 0 (a
    /// constant rate, `k / fps`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vfr_jitter: Option<f64>,
    /// Frames the recorder drops, as a phone under load does: this share of the frames
    /// (0 to 0.2), drawn from the seed, is missing from the video, whose timestamps keep
    /// the gaps (the frames left keep their own times, as with `vfr_jitter`); the truth
    /// has no row for them. Never the first or last frame, a spoiled one, nor the frame
    /// before a duplicated one (the recorder repeats what it wrote). Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dropped_share: Option<f64>,
    /// A rolling shutter, as a phone's sensor reads its rows: the time from the first
    /// row to the last, as a fraction of the frame interval (0 to 1; a phone's is 0.5 to
    /// 0.9 at 30 frames/s). Row `y` of `h` is exposed at `t + (y / (h - 1) - 1/2)` of it
    /// times the interval, so the swinging wire bends and a moving camera's picture
    /// shears (in 16 bands of rows, each at its own time; the second pendulum, the hand
    /// and the walker are drawn at the frame's time). The truth stays the wire's angle
    /// at `t`, the middle row's time. Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_shutter: Option<f64>,
    /// The camera tilted from the plate's normal by this angle, degrees, 0 to 40: a
    /// pinhole camera (its focal length `camera_focal_px`) on the plate's normal through
    /// the frame's centre, turned about an axis in the plate (`tilt_axis_deg`), so that
    /// the plate is seen in perspective and angles about the fulcrum are scaled by
    /// between `cos` and `1 / cos` of the tilt at the frame's centre, by direction, and
    /// by more or less elsewhere. The scene is zoomed out
    /// to keep the ball's swing in the frame. The truth stays in plate angles (those of
    /// the untilted view); `rollfric synth --calibration` prints protractor marks'
    /// image points for `video.calibration`. Not with `mirror`. Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera_tilt_deg: Option<f64>,
    /// The axis of `camera_tilt_deg`, an image angle of the untilted view from the x
    /// axis (y down), degrees. Default 0 (the camera tips about the image's x axis).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt_axis_deg: Option<f64>,
    /// Focal length of the tilted camera, px, 0.3 to 10 times the frame's width (0.8:
    /// a phone's wide lens); the render is refused when the frame would reach too near
    /// the plate's horizon. Default 1.2 times the width.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera_focal_px: Option<f64>,
    /// The camera moves while it films: a phone held in the hand (`{px: 2, deg: 0.3, hz:
    /// 5}`), a tripod that sways slowly (`{px: 1, deg: 0.05, hz: 0.5}`), a slow drift
    /// (`{drift_px: 6}`). The whole picture is shifted and turned about its centre by a
    /// smooth random path from the seed, zero at the first frame (so the first frame is
    /// the plate's view and the truth is unchanged). Absent: a still camera.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shake: Option<Shake>,
    /// The encoder's quality: x264's constant rate factor, 0 to 51 (34 and up: the
    /// heavy compression of a phone's or a messenger's copy, blocks and smeared thin
    /// lines). In `.avi` (MJPG) it sets the quantiser `-q:v` to `3 + (crf - 18) / 2`,
    /// within 2 to 31. Default 18.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crf: Option<u32>,
    /// Radial lens distortion: a point at distance `r` from the frame's centre, in units
    /// of the frame's width (a lens of one width's focal length), is seen at `r (1 + k1
    /// r^2)` of the undistorted view, zoomed so that the frame's corners stay filled;
    /// -0.5 to 0.5 (negative: barrel, a phone's wide lens, to about -0.3; positive:
    /// pincushion). The truth stays the undistorted plate's. Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lens_k1: Option<f64>,
    /// What else the room puts in the picture: a ruled or gridded board behind the
    /// pendulum, straight static edges near the fulcrum, a second pendulum, a person
    /// walking through. Absent: an empty room.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub room: Option<Room>,
}

/// What else the room puts in the picture (`synthetic.room`), e.g. `{board: grid,
/// edges: 2, second_string: true, walker_s: 8}`.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Room {
    /// Lines printed on the plate behind the pendulum: `ruled` (parallel lines, about
    /// a twentieth of the wire apart, at a random angle), `grid` (two sets, square), or
    /// `none`. Default `none`.
    #[serde(default)]
    pub board: Board,
    /// Straight static edges drawn through or near the fulcrum, 0 to 6: a protractor's
    /// base line, a table's edge, a cable, each long, dark or light, at a random angle.
    /// Default 0.
    #[serde(default)]
    pub edges: u32,
    /// A second pendulum swinging elsewhere in the frame: its own fulcrum, wire and
    /// ball, a shorter wire, its own period and phase. Default false.
    #[serde(default)]
    pub second_string: bool,
    /// A person walks between the camera and the plate, starting at this time, s: a
    /// large dark shape crosses the whole frame in 4 s and covers the wire for about a second
    /// (the truth marks those frames `walker`). Absent: nobody.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub walker_s: Option<f64>,
}

/// Lines printed on the plate (`synthetic.room.board`).
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Board {
    /// A plain plate.
    #[default]
    None,
    /// Parallel lines.
    Ruled,
    /// A square grid.
    Grid,
}

/// The camera's motion (`synthetic.shake`).
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Shake {
    /// RMS of the picture's shift, px, 0 to 50. Default 0.
    #[serde(default)]
    pub px: f64,
    /// RMS of the picture's turn, degrees, 0 to 5. Default 0.
    #[serde(default)]
    pub deg: f64,
    /// The motion's typical frequency, Hz, 0.05 to 30 (its four sines per axis lie
    /// from 0.6 to 1.4 times it): 3 to 8 for a hand, below 1 for a swaying tripod.
    /// Default 5.
    #[serde(default = "default_shake_hz")]
    pub hz: f64,
    /// A slow drift on top: the picture moves this far in a straight line over the
    /// recording, px, 0 to 500. Default 0.
    #[serde(default)]
    pub drift_px: f64,
}

fn default_shake_hz() -> f64 {
    5.0
}

/// The wire's shadow (`synthetic.shadow`), e.g. `{angle_deg: 3, blur_px: 4, strength:
/// 0.5, lamp_share: 1}`.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WireShadow {
    /// The shadow's image angle minus the wire's, degrees, -45 to 45 (positive turns
    /// from the image x axis towards y, as the image angle does; before `mirror`).
    /// Default 3.
    #[serde(default = "default_shadow_angle")]
    pub angle_deg: f64,
    /// Blur of the shadow (the standard deviation of a Gaussian across it), px, 0 to
    /// 50, on top of the wire's own softness. Default 4.
    #[serde(default = "default_shadow_blur")]
    pub blur_px: f64,
    /// How much of the plate's brightness the shadow takes along its middle, 0 to 1.
    /// Default 0.5.
    #[serde(default = "default_shadow_strength")]
    pub strength: f64,
    /// The lamp's share of the plate's light, 0 to 1. Given, the shadow takes no more
    /// light than the wire blocks of the lamp's: at each point at most `lamp_share`
    /// times the wire's coverage there, blurred as the shadow is, so that a thin wire's
    /// shadow blurred wide is faint, as a real one is (a 1 px wire's shadow blurred by 4
    /// px takes at most a tenth of the light along its middle, whatever `strength`).
    /// Absent: `strength` alone, which can draw a shadow darker than any wire casts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lamp_share: Option<f64>,
}

/// `synthetic.flicker_hz` when not given.
pub const DEFAULT_FLICKER_HZ: f64 = 100.0;
/// `synthetic.flicker_depth` when not given.
pub const DEFAULT_FLICKER_DEPTH: f64 = 0.012;
/// `synthetic.drift_depth` when not given.
pub const DEFAULT_DRIFT_DEPTH: f64 = 0.08;

fn default_shadow_angle() -> f64 {
    3.0
}
fn default_shadow_blur() -> f64 {
    4.0
}
fn default_shadow_strength() -> f64 {
    0.5
}

/// Look of the digital twin's video.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Style {
    /// A dark wire over a light protractor on a light plate.
    #[default]
    DarkWire,
    /// A light wire over a dark plate.
    LightWire,
    /// A camera turned far from the plate's axes, dim and low in contrast.
    Oblique,
}

fn default_width() -> u32 {
    1280
}
fn default_height() -> u32 {
    720
}
fn default_spoiled() -> u32 {
    3
}

fn default_angle_noise() -> f64 {
    0.05
}

fn default_psi0() -> f64 {
    10.0
}
fn default_fps() -> f64 {
    60.0
}
fn default_rest_angle() -> f64 {
    91.7
}
fn default_seed() -> u64 {
    1
}
