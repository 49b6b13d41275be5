//! The experiment file's keys: serde structs with their units, defaults and docs. Unknown
//! keys are errors; [`super::Experiment::parse`] validates the values.

use super::air::AirFile;
use super::synthetic::Synthetic;
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
    /// One material pair measured at several normal forces (other balls, other
    /// inclines): the experiments of a manifest that name the same `pair` are fitted
    /// together for `beta` and `s_r` on the index (docs/beta.md), and are not pooled
    /// as repeat runs of their material. Optional.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pair: Option<String>,
    /// Free text shown on the report (where the numbers came from, caveats).
    #[serde(default)]
    pub notes: String,
    /// The rig as measured: the plate's incline, the pendulum's length, the ball.
    pub geometry: Geometry,
    /// The rolling-resistance law to fit. Default: `beta` 1.
    #[serde(default)]
    pub model: Model,
    /// The air the ball moves through, whose drag joins the equation of motion.
    /// Default: still air at 20 degC and 101.325 kPa; `{ model: none }` leaves it out.
    #[serde(default, skip_serializing_if = "is_default_air")]
    pub air: AirFile,
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

fn is_default_air(a: &AirFile) -> bool {
    *a == AirFile::default()
}

/// The consistency checks' names, as `accept[].check` names them.
pub const CHECKS: [&str; 9] = [
    "period",
    "residual",
    "envelope",
    "halves",
    "interval",
    "outliers",
    "pivot",
    "scale",
    "detection",
];

/// One accepted consistency warning.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Accept {
    /// The check's name: `period`, `residual`, `envelope`, `halves`, `interval`,
    /// `outliers`, `pivot`, `scale` or `detection`.
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

pub(super) fn default_beta() -> BetaSpec {
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
    /// The detection's `length` check judges the period it saw by the same limit.
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
    /// `scale` check (angles measured through a lens or a plate calibration): largest
    /// relative standard uncertainty the swing's scale puts on `s_r` (the lens's `u_k1`,
    /// the calibration points' scatter). Default 0.005: beyond it, the scale alone
    /// spreads the 95 % interval over 1 % either side, and a lens fitted from too few
    /// lines (the twins' sweep: `u_k1` 0.06, `s_r` 1.4 % off) is said, not trusted.
    #[serde(default = "default_scale_rel")]
    pub scale_rel: f64,
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
            ("scale_rel", self.scale_rel, d.scale_rel),
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
            scale_rel: default_scale_rel(),
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
fn default_scale_rel() -> f64 {
    0.005
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
    /// and a 1920x1080 one at half size (docs/detector.md, "Working scale"). A frame at
    /// the working scale holds at most 3840 x 2160 px, whatever the side: a larger one
    /// is shrunk further (an 8192x8192 video at 8192 is measured at 2730x2730), so that
    /// the detector's memory stays under 600 MB.
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
