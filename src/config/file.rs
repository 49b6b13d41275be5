//! The experiment file's keys: serde structs with their units, defaults and docs. Unknown
//! keys are errors; [`super::Experiment::parse`] validates the values.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// One experiment: a material pair on one pendulum.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExperimentFile {
    /// Short identifier used for output names. Default: the file name without `.yaml`.
    pub name: Option<String>,
    /// Plate material, as the report's tables name it. Default: the name.
    pub material: Option<String>,
    /// Free text shown on the report (where the numbers came from, caveats).
    #[serde(default)]
    pub notes: String,
    /// The rig as measured: the plate's incline, the pendulum's length, the ball.
    pub geometry: Geometry,
    /// The rolling-resistance law to fit. Default: `beta` 1.
    #[serde(default)]
    pub model: Model,
    /// Wire-torsion test (Appendix A). Optional.
    pub torsion: Option<Torsion>,
    /// Sliding friction between ball and plate, for the pure-rolling check (Eq. 34).
    pub sliding: Option<Sliding>,
    /// The paper's published values: used only as a reference to compare against.
    pub reference: Option<Reference>,
    /// How close results must come, and the consistency checks' limits. Every key has
    /// a default.
    #[serde(default)]
    pub tolerances: Tolerances,
    /// The digital twin: what to simulate when the experiment has no lab recording.
    pub synthetic: Option<Synthetic>,
    /// A measured angle CSV (`t_s,angle_rad`), relative to this file. Optional.
    pub angles: Option<String>,
    /// The video and the detector's settings. Optional.
    pub video: Option<Video>,
    /// Draws of the Monte Carlo check of the uncertainty budget (JCGM 101) on the
    /// experiment's page (its figure and comparison). Default: none (the check costs
    /// about one fit per draw).
    pub monte_carlo_draws: Option<usize>,
    /// Consistency warnings accepted, each with a written reason (the result stays
    /// `suspect`, and its page says the warning was accepted and why).
    #[serde(default)]
    pub accept: Vec<Accept>,
}

/// The consistency checks' names, as `accept[].check` names them.
pub const CHECKS: [&str; 8] = [
    "period",
    "residual",
    "envelope",
    "halves",
    "interval",
    "outliers",
    "pivot",
    "detection",
];

/// One accepted consistency warning.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Accept {
    /// The check's name: `period`, `residual`, `envelope`, `halves`, `interval`,
    /// `outliers`, `pivot` or `detection`.
    pub check: String,
    /// Why the warning does not invalidate the result.
    pub reason: String,
}

/// The rig's measured geometry.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// The plate's inclination: `h_m` and `l_m`, or `angle_deg`.
    pub incline: Incline,
    /// The pendulum's length: `d_m` or `contact_length_m`.
    pub pendulum: PendulumLength,
    /// The ball's radius and mass (or density).
    pub ball: Ball,
    /// Local gravitational acceleration, m/s^2. Default 9.81.
    #[serde(default = "default_g")]
    pub g_m_s2: f64,
    /// Standard uncertainties of these inputs, for the uncertainty budget (GUM). Every
    /// key has a default from the resolution of the instrument that usually measures it.
    #[serde(default)]
    pub uncertainty: InputUncertainty,
}

/// Standard uncertainties `u` of the geometry's inputs, in the inputs' own units (GUM
/// Type B). A value given here is read as the standard deviation of a normal
/// distribution. A key left out takes its default: half a division of the usual
/// instrument, read as a rectangular distribution (`u = division / (2 sqrt 3)`).
#[derive(Debug, Clone, Default, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InputUncertainty {
    /// `u(h)`, m. Default 2.9e-4 (a rule with 1 mm divisions).
    pub h_m: Option<f64>,
    /// `u(l)`, m. Default 2.9e-4 (a rule with 1 mm divisions).
    pub l_m: Option<f64>,
    /// `u(alpha)`, degrees. Default 0.029 (an inclinometer reading to 0.1 deg).
    pub angle_deg: Option<f64>,
    /// `u(d)`, m. Default 2.9e-4 (a rule with 1 mm divisions).
    pub d_m: Option<f64>,
    /// `u(L)`, m. Default 2.9e-4 (a rule with 1 mm divisions).
    pub contact_length_m: Option<f64>,
    /// `u(r)`, m. Default 5.8e-6 (a caliper reading to 0.02 mm).
    pub radius_m: Option<f64>,
    /// `u(m)`, kg. Default 2.9e-5 (a balance reading to 0.1 g).
    pub mass_kg: Option<f64>,
    /// `u(rho)`, kg/m^3. Default 0.58 % of the value (a handbook density, +-1 %).
    pub density_kg_m3: Option<f64>,
    /// `u(g)`, m/s^2. Default 0.017 (9.81 stands for 9.78..9.84 over the Earth).
    pub g_m_s2: Option<f64>,
}

fn default_g() -> f64 {
    9.81
}

/// Plate inclination: either the support geometry (Eq. 36) or the angle itself.
#[derive(Debug, Clone, Default, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Incline {
    /// Height difference between the plate's ends `h`, m (Eq. 36, with `l_m`).
    pub h_m: Option<f64>,
    /// Length of the supporting plate `l`, m (Eq. 36, with `h_m`).
    pub l_m: Option<f64>,
    /// Inclination `alpha`, degrees (instead of `h_m` and `l_m`).
    pub angle_deg: Option<f64>,
}

/// Pendulum length: either `d` or the measurable fulcrum-to-contact length `L` (Eq. 37).
#[derive(Debug, Clone, Default, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PendulumLength {
    /// Fulcrum-to-ball-centre distance `d`, m.
    pub d_m: Option<f64>,
    /// Fulcrum-to-contact-point distance `L`, m; `d = sqrt(L^2 + r^2)` (Eq. 37).
    pub contact_length_m: Option<f64>,
}

/// The ball: radius and mass (or density); solid, so `J_z = 2/5 m r^2` (Eq. 9).
#[derive(Debug, Clone, Default, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Ball {
    /// Radius `r`, m.
    pub radius_m: f64,
    /// Mass `m`, kg (or give `density_kg_m3`).
    pub mass_kg: Option<f64>,
    /// Density, kg/m^3: `m = 4/3 pi r^3 rho` (instead of `mass_kg`).
    pub density_kg_m3: Option<f64>,
    /// What the ball is made of, for a check of the density its mass and radius give (a
    /// diameter entered as the radius gives an eighth of it): `steel`,
    /// `stainless-steel`, `glass`, `aluminium`, `brass`, `tungsten-carbide`,
    /// `silicon-nitride`, `zirconia`, `alumina`, `pom`, `nylon`, `ptfe`, or `other`
    /// (not checked). When it is not given, the density must be that of one of them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

/// The densities of ball materials, kg/m^3 (handbook ranges of the grades balls are made
/// of), for `geometry.ball.material`.
pub const BALL_DENSITIES: [(&str, f64, f64); 12] = [
    ("steel", 7750.0, 7900.0),
    ("stainless-steel", 7700.0, 8000.0),
    ("glass", 2400.0, 2800.0),
    ("aluminium", 2640.0, 2850.0),
    ("brass", 8400.0, 8750.0),
    ("tungsten-carbide", 14500.0, 15700.0),
    ("silicon-nitride", 3150.0, 3300.0),
    ("zirconia", 5700.0, 6100.0),
    ("alumina", 3600.0, 3990.0),
    ("pom", 1390.0, 1430.0),
    ("nylon", 1120.0, 1160.0),
    ("ptfe", 2100.0, 2250.0),
];

/// The rolling-resistance law `M_r = s_r N^beta` (Eq. 28).
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Exponent `beta`: a number (`1`, `1.3333`, `1.5`, ...), a fraction as text
    /// (`"4/3"`, `"3/2"`), or `free` to fit it. Default 1 (the paper's choice).
    #[serde(default = "default_beta")]
    pub beta: BetaSpec,
    /// Also fit beta = 1, 4/3 and 3/2 and report their figures of merit. Default false.
    #[serde(default)]
    pub compare_betas: bool,
}

impl Default for Model {
    fn default() -> Self {
        Self {
            beta: default_beta(),
            compare_betas: false,
        }
    }
}

fn default_beta() -> BetaSpec {
    BetaSpec::Number(1.0)
}

/// `beta` as written in YAML.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(untagged)]
pub enum BetaSpec {
    /// The exponent itself.
    Number(f64),
    /// A fraction (`"4/3"`) or `free`.
    Text(String),
}

/// Appendix A's torsion test.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Torsion {
    /// Torsion-pendulum period `T`, s (A4).
    pub period_s: f64,
    /// Length of the wire in the torsion test, m.
    pub wire_length_m: f64,
    /// Largest precession amplitude of the conical pendulum `psi_0`, degrees.
    pub psi0_max_deg: f64,
}

/// Sliding friction for the pure-rolling condition `|T|/N < mu` (Eq. 34).
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Sliding {
    /// Coefficient of sliding friction `mu` between ball and plate (dimensionless).
    pub mu: f64,
}

/// Published values, for comparison only (never used as inputs to a computation).
#[derive(Debug, Clone, Default, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Reference {
    /// Where the values come from, e.g. "Table 1".
    #[serde(default)]
    pub source: String,
    /// `s_r`, m.
    pub s_r_m: Option<f64>,
    /// `mu_r = s_r / r` (dimensionless).
    pub mu_r: Option<f64>,
    /// Envelope slope `a`, rad/s.
    pub a_rad_s: Option<f64>,
}

/// How close reproduced values must come (relative deviations), and the limits of the
/// consistency checks that make a result `suspect`.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Tolerances {
    /// Against `reference` values. Default 0.02.
    #[serde(default = "default_ref_tol")]
    pub reference_rel: f64,
    /// Against the synthetic truth `s_r`. Default 0.01.
    #[serde(default = "default_truth_tol")]
    pub truth_rel: f64,
    /// `period` check: largest relative difference between the pendulum length the
    /// measured period implies (small-angle period, ERRATA §2) and the geometry's `d`.
    /// Default 0.10 (a length measured to a centimetre on a 0.2 m pendulum is 5 %).
    #[serde(default = "default_period_rel")]
    pub period_rel: f64,
    /// `residual` check: largest ratio of the fit's amplitude residual RMS to the
    /// scatter the series' own per-frame noise explains (`sigma / sqrt(frames per
    /// turning point)`). Default 10 (the twins sit at 1-4; a bad turning point at
    /// hundreds).
    #[serde(default = "default_residual_factor")]
    pub residual_factor: f64,
    /// `envelope` check: largest AICc advantage of an exponential (viscous) amplitude
    /// envelope over the linear one of rolling friction. Default 10 ("clearly
    /// preferred").
    #[serde(default = "default_envelope_aicc")]
    pub envelope_aicc: f64,
    /// `halves` check: largest relative difference between the `s_r` of the earlier and
    /// of the later half of the turning points, each fitted alone (not judged with fewer
    /// than six turning points). Default 0.02 (the
    /// randomised twins sit within 1.1 %; a twin whose detector followed the wire's
    /// shadow in a tilted view, s_r 7 % off, at 3.4 %).
    #[serde(default = "default_halves_rel")]
    pub halves_rel: f64,
    /// `interval` check: largest relative half-width of the 95 % interval on `s_r` (which
    /// must also exclude zero). Default 0.25.
    #[serde(default = "default_interval_rel")]
    pub interval_rel: f64,
    /// `outliers` check: how many turning points the fit may drop as outliers without a
    /// warning. Default 0 (any dropped turning point is said); more than a tenth of them
    /// always warns, whatever this says. Written out only when set.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub outliers: usize,
    /// `pivot` check (a video's angles only): largest relative difference between the
    /// swing of the wire's own direction (each frame's free line fit) and the swing of
    /// its angle about the pivot. A pivot off along the wire scales the measured swing,
    /// and s_r, by about as much. Default 0.02 (the twins and the real clips sit within
    /// 0.01).
    #[serde(default = "default_pivot_rel")]
    pub pivot_rel: f64,
    /// Why a tolerance is wider than its default: required when one is (a wider
    /// tolerance lets a result through that the default would stop, so it is said, on
    /// the page and in the summary, as an accepted warning is). Written out only when
    /// set.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub reason: String,
}

impl Tolerances {
    /// The tolerances wider than their defaults: `(key, value, default)`.
    pub fn widened(&self) -> Vec<(&'static str, f64, f64)> {
        let d = Self::default();
        [
            ("reference_rel", self.reference_rel, d.reference_rel),
            ("truth_rel", self.truth_rel, d.truth_rel),
            ("period_rel", self.period_rel, d.period_rel),
            ("residual_factor", self.residual_factor, d.residual_factor),
            ("envelope_aicc", self.envelope_aicc, d.envelope_aicc),
            ("halves_rel", self.halves_rel, d.halves_rel),
            ("interval_rel", self.interval_rel, d.interval_rel),
            ("outliers", self.outliers as f64, d.outliers as f64),
            ("pivot_rel", self.pivot_rel, d.pivot_rel),
        ]
        .into_iter()
        .filter(|(_, v, d)| v > d)
        .collect()
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            reference_rel: default_ref_tol(),
            truth_rel: default_truth_tol(),
            period_rel: default_period_rel(),
            residual_factor: default_residual_factor(),
            envelope_aicc: default_envelope_aicc(),
            halves_rel: default_halves_rel(),
            interval_rel: default_interval_rel(),
            outliers: 0,
            pivot_rel: default_pivot_rel(),
            reason: String::new(),
        }
    }
}

fn default_period_rel() -> f64 {
    0.10
}
fn default_residual_factor() -> f64 {
    10.0
}
fn default_envelope_aicc() -> f64 {
    10.0
}
fn default_halves_rel() -> f64 {
    0.02
}
fn default_interval_rel() -> f64 {
    0.25
}

fn default_pivot_rel() -> f64 {
    0.02
}

fn default_ref_tol() -> f64 {
    0.02
}
fn default_truth_tol() -> f64 {
    0.01
}

/// The digital twin's parameters: the truth the pipeline must measure back.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Synthetic {
    /// True rolling-friction coefficient `s_r`, m·N^(1-beta).
    pub s_r_m: f64,
    /// True exponent. Default 1.
    #[serde(default = "default_beta")]
    pub beta: BetaSpec,
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
/// 0.5}`.
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

/// Wire polarity for the detector.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Polarity {
    /// Decide from the video.
    #[default]
    Auto,
    /// The wire is darker than what is behind it.
    Dark,
    /// The wire is lighter than what is behind it.
    Light,
}

/// Where the video is and how to read it. Every key is optional: with none, the
/// detector finds the moving wire, its pivot and a region of interest by itself.
#[derive(Debug, Clone, Default, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Video {
    /// The recording, relative to this file. Default for a synthetic experiment: the
    /// rendered twin under `build/<name>/`.
    pub path: Option<String>,
    /// Region of interest `[x, y, width, height]`, px.
    pub roi: Option<[u32; 4]>,
    /// Pivot of the wire `[x, y]`, px (may lie outside the frame).
    pub pivot: Option<[f64; 2]>,
    /// Frames to use, `[first, last]` (0-based, inclusive).
    pub frames: Option<[u64; 2]>,
    /// Wire polarity: `auto`, `dark` or `light`. Default `auto`.
    #[serde(default)]
    pub polarity: Polarity,
    /// Detection threshold, in units of the image noise. Default 4.
    pub threshold_sigma: Option<f64>,
    /// Gate: a measured angle farther than this from the value predicted from the
    /// previous frames is flagged, degrees. Default 1.5.
    pub gate_deg: Option<f64>,
    /// Operator marks: frame number -> two points `[[x1, y1], [x2, y2]]` on the wire,
    /// px. They replace the detection for that frame (status `manual`).
    #[serde(default)]
    pub marks: std::collections::BTreeMap<u64, [[f64; 2]; 2]>,
    /// Plate calibration for a camera not square to the plate: at least four image
    /// points with their plate coordinates (protractor marks, say). Every angle is then
    /// measured in the plate's plane, through the homography the points fix, and the
    /// angles CSV holds plate angles (from the plate's x axis towards its y axis). The
    /// calibration's own uncertainty enters the budget of `s_r`. Absent: angles are the
    /// image's (a camera square to the plate).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<PlateCalibration>,
    /// The lens's radial distortion, e.g. `{k1: -0.2, u_k1: 0.02}` for a phone's wide
    /// lens: a point at distance `r` from the frame's centre, in frame widths, is seen
    /// at `z r (1 + k1 r^2)` (`z` keeps the frame's corners in place; the twin's
    /// `synthetic.lens_k1` renders the same model). Every angle is then measured as the
    /// undistorted wire's, and `u_k1` enters the budget of `s_r`. Not with
    /// `calibration` (whose points would have to be undistorted first). Absent: an
    /// undistorted view.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lens: Option<LensSpec>,
    /// The largest side, px, the detector works at: a frame (or its region of interest)
    /// is shrunk by a whole factor to at most this before the wire is measured (and to
    /// the default's scale when the finer one's look is in doubt). Default 640, at
    /// least 640. A larger one measures high-resolution footage more finely, for more of
    /// the detector's time and memory: 1280 measures a 1280x720 video at its full size
    /// and a 1920x1080 one at half size (docs/detector.md, "Working scale").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub work_side_px: Option<u32>,
}

/// `video.lens`: the one-coefficient radial distortion and its uncertainty.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LensSpec {
    /// The coefficient, -0.5 to 0.5 (negative: barrel).
    pub k1: f64,
    /// Its standard uncertainty, 0 to 0.5. Default 0.
    #[serde(default)]
    pub u_k1: f64,
}

/// `video.calibration`, e.g. `{points: [{image: [412.5, 96.0], plate: [0, 0]}, ...]}`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlateCalibration {
    /// Four or more points, no three of four on a line.
    pub points: Vec<CalibrationPoint>,
    /// Standard uncertainty of each image coordinate, px. Default: estimated from the
    /// fit's residual with more than four points (`2 n - 8` degrees of freedom), 0.5
    /// px with exactly four.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_px: Option<f64>,
}

/// One point of `video.calibration.points`.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CalibrationPoint {
    /// Where the point is in the image, `[x, y]`, px (x right, y down, pixel centres at
    /// whole numbers).
    pub image: [f64; 2],
    /// Where it is on the plate, `[x, y]`, in any one unit of length (mm, say), axes of
    /// your choosing: plate angles are measured from this x axis towards this y axis.
    pub plate: [f64; 2],
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
