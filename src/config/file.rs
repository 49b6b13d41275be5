//! The experiment file's keys: serde structs with their units, defaults and docs. Unknown
//! keys are errors; [`super::Experiment::parse`] validates the values.

use serde::{Deserialize, Serialize};

/// One experiment: a material pair on one pendulum.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentFile {
    /// Short identifier used for output names. Default: the file name without `.yaml`.
    pub name: Option<String>,
    /// Plate material, as the report's tables name it. Default: the name.
    pub material: Option<String>,
    /// Free text shown on the report (where the numbers came from, caveats).
    #[serde(default)]
    pub notes: String,
    pub geometry: Geometry,
    #[serde(default)]
    pub model: Model,
    /// Wire-torsion test (Appendix A). Optional.
    pub torsion: Option<Torsion>,
    /// Sliding friction between ball and plate, for the pure-rolling check (Eq. 34).
    pub sliding: Option<Sliding>,
    /// The paper's published values: used only as a reference to compare against.
    pub reference: Option<Reference>,
    #[serde(default)]
    pub tolerances: Tolerances,
    /// The digital twin: what to simulate when the experiment has no lab recording.
    pub synthetic: Option<Synthetic>,
    /// A measured angle CSV (`t_s,angle_rad`), relative to this file. Optional.
    pub angles: Option<String>,
    /// The video and the detector's settings. Optional.
    pub video: Option<Video>,
    /// Consistency warnings accepted, each with a written reason (the result stays
    /// `suspect`, and its page says the warning was accepted and why).
    #[serde(default)]
    pub accept: Vec<Accept>,
}

/// The consistency checks' names, as `accept[].check` names them.
pub const CHECKS: [&str; 5] = ["period", "residual", "envelope", "interval", "outliers"];

/// One accepted consistency warning.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Accept {
    /// The check's name: `period`, `residual`, `envelope`, `interval` or `outliers`.
    pub check: String,
    /// Why the warning does not invalidate the result.
    pub reason: String,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    pub incline: Incline,
    pub pendulum: PendulumLength,
    pub ball: Ball,
    /// Local gravitational acceleration, m/s^2. Default 9.81.
    #[serde(default = "default_g")]
    pub g_m_s2: f64,
}

fn default_g() -> f64 {
    9.81
}

/// Plate inclination: either the support geometry (Eq. 36) or the angle itself.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
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
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PendulumLength {
    /// Fulcrum-to-ball-centre distance `d`, m.
    pub d_m: Option<f64>,
    /// Fulcrum-to-contact-point distance `L`, m; `d = sqrt(L^2 + r^2)` (Eq. 37).
    pub contact_length_m: Option<f64>,
}

/// The ball: radius and mass (or density); solid, so `J_z = 2/5 m r^2` (Eq. 9).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Ball {
    /// Radius `r`, m.
    pub radius_m: f64,
    /// Mass `m`, kg (or give `density_kg_m3`).
    pub mass_kg: Option<f64>,
    /// Density, kg/m^3: `m = 4/3 pi r^3 rho` (instead of `mass_kg`).
    pub density_kg_m3: Option<f64>,
}

/// The rolling-resistance law `M_r = s_r N^beta` (Eq. 28).
#[derive(Debug, Clone, Deserialize, Serialize)]
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
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum BetaSpec {
    Number(f64),
    Text(String),
}

/// Appendix A's torsion test.
#[derive(Debug, Clone, Deserialize, Serialize)]
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
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Sliding {
    /// Coefficient of sliding friction `mu` between ball and plate (dimensionless).
    pub mu: f64,
}

/// Published values, for comparison only (never used as inputs to a computation).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
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
#[derive(Debug, Clone, Deserialize, Serialize)]
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
    /// `interval` check: largest relative half-width of the 95 % interval on `s_r` (which
    /// must also exclude zero). Default 0.25.
    #[serde(default = "default_interval_rel")]
    pub interval_rel: f64,
    /// `outliers` check: how many turning points the fit may drop as outliers without a
    /// warning. Default 0 (any dropped turning point is said); more than a tenth of them
    /// always warns, whatever this says. Written out only when set.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub outliers: usize,
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
            interval_rel: default_interval_rel(),
            outliers: 0,
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
fn default_interval_rel() -> f64 {
    0.25
}

fn default_ref_tol() -> f64 {
    0.02
}
fn default_truth_tol() -> f64 {
    0.01
}

/// The digital twin's parameters: the truth the pipeline must measure back.
#[derive(Debug, Clone, Deserialize, Serialize)]
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
    /// Angle of the wire at rest, from the image x axis, degrees. Default 91.7
    /// (a camera turned 1.7 degrees).
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
}

/// Look of the digital twin's video.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq)]
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
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq)]
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
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
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
