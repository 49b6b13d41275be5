//! The record of one experiment that the reports show and `summary.json` keeps.

use super::{Analysis, Angles, Source};
use crate::config::{Experiment, Reference, Tolerances};
use crate::detect::summary::DetectionSummary;
use crate::fit::FitResult;
use crate::physics::torsion::TorsionCheck;
use crate::physics::FrictionLaw;
use crate::uncertainty::{Budget, MonteCarlo};
use crate::verdict::{Check, Verdict};
use serde::{Deserialize, Serialize};

/// Hashes of the inputs, for provenance.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Inputs {
    pub experiment_file: String,
    pub experiment_sha256: String,
    pub angles_sha256: String,
}

/// Derived geometry (Eq. 36, 37 and the model's constants).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GeometryView {
    pub alpha_deg: f64,
    pub h_m: Option<f64>,
    pub l_m: Option<f64>,
    pub d_m: f64,
    pub contact_length_m: f64,
    pub delta_deg: f64,
    pub r_m: f64,
    pub m_kg: f64,
    pub j_z_kg_m2: f64,
    /// The normal force at rest, `m g (cos(alpha) + sin(alpha) tan(delta))`, N.
    pub n0_n: f64,
    pub g_m_s2: f64,
    pub period_small_angle_s: f64,
}

/// A report file the build wrote, with its hash (to know the pages are intact).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PageFile {
    pub path: String,
    pub sha256: String,
}

/// Everything one experiment produced.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ExperimentResult {
    pub name: String,
    pub material: String,
    /// The material pair of a series at several normal forces (`pair`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pair: Option<String>,
    pub notes: String,
    pub inputs: Inputs,
    /// Whether the angles come from the digital twin (synthetic, not a lab recording).
    pub synthetic: bool,
    pub angles: String,
    pub geometry: GeometryView,
    pub results: FitResult,
    /// The model's `mu_r / a` for this geometry (Fig. 19's analytic line), s.
    pub model_mu_r_per_a_s: f64,
    pub truth_s_r_m: Option<f64>,
    pub reference: Option<Reference>,
    pub tolerances: Tolerances,
    pub checks: Vec<Check>,
    /// `ok`, or `suspect` with its warnings (`"verdict"`, `"warnings"`).
    #[serde(flatten, default)]
    pub verdict: Verdict,
    pub sliding_mu: Option<f64>,
    pub pure_rolling: Option<bool>,
    pub torsion: Option<TorsionCheck>,
    pub detection: Option<DetectionSummary>,
    /// The uncertainty budget of `s_r` (GUM), and its Monte Carlo check when asked for.
    pub budget: Budget,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<MonteCarlo>,
    /// The report files written for it (filled in by the writer).
    pub pages: Vec<PageFile>,
}

impl ExperimentResult {
    /// The record of `exp`'s analysis `a` of `angles`.
    pub fn new(exp: &Experiment, angles: &Angles, a: &Analysis, inputs: Inputs) -> Self {
        let p = &exp.pendulum;
        let inc = &exp.file.geometry.incline;
        let detection = angles.detection.clone();
        Self {
            name: exp.name.clone(),
            material: exp.material.clone(),
            pair: exp.file.pair.clone(),
            notes: exp.file.notes.clone(),
            inputs,
            synthetic: angles.source.is_synthetic(),
            angles: match (&detection, &angles.source) {
                (Some(d), Source::Twin) => format!(
                    "SYNTHETIC: detected in the digital twin's rendered video {}",
                    d.video
                ),
                (Some(d), _) => format!("detected in the video {}", d.video),
                (None, _) => format!(
                    "measured angle CSV {}",
                    exp.file.angles.clone().unwrap_or_default()
                ),
            },
            geometry: GeometryView {
                alpha_deg: p.alpha.to_degrees(),
                h_m: inc.h_m,
                l_m: inc.l_m,
                d_m: p.d,
                contact_length_m: p.l,
                delta_deg: p.delta.to_degrees(),
                r_m: p.r,
                m_kg: p.m,
                j_z_kg_m2: p.j_z,
                n0_n: p.rest_normal_force(),
                g_m_s2: p.g,
                period_small_angle_s: p.small_angle_period(),
            },
            // mu_r = s_r / r with s_r = r: the analytic a of mu_r = 1.
            model_mu_r_per_a_s: 1.0 / p.envelope_slope(&FrictionLaw::new(p.r, 1.0)),
            results: a.fit.clone(),
            truth_s_r_m: a.truth_s_r_m,
            reference: exp.file.reference.clone(),
            tolerances: exp.file.tolerances.clone(),
            checks: a.checks.clone(),
            verdict: a.verdict.clone(),
            sliding_mu: a.sliding_mu,
            pure_rolling: a.pure_rolling,
            torsion: a.torsion,
            detection,
            budget: a.budget.clone(),
            monte_carlo: a.monte_carlo.clone(),
            pages: Vec::new(),
        }
    }

    /// Compared with an expected value (a reference or the synthetic truth): without
    /// one, a result is only measured, never "within tolerances".
    pub fn compared(&self) -> bool {
        !self.checks.is_empty()
    }

    /// Compared, and every check within its tolerance (recomputed from the numbers).
    pub fn passed(&self) -> bool {
        self.compared() && self.checks.iter().all(Check::verdict)
    }

    /// A check outside its tolerance.
    pub fn missed(&self) -> bool {
        !self.checks.iter().all(Check::verdict)
    }

    /// How the result stands against its expected values: `within tolerances`,
    /// `MISSES a tolerance` or `measured` (nothing to compare with).
    pub fn standing(&self) -> &'static str {
        if !self.compared() {
            "measured (nothing to compare with)"
        } else if self.passed() {
            "within tolerances"
        } else {
            "MISSES a tolerance"
        }
    }

    /// One line for the build's log.
    pub fn line(&self) -> String {
        let truth = self
            .truth_s_r_m
            .map(|t| {
                format!(
                    " ({:+.2} % vs synthetic truth)",
                    100.0 * (self.results.s_r_m - t) / t
                )
            })
            .unwrap_or_default();
        format!(
            "s_r = {:.4e} m{truth}, {}, verdict {}",
            self.results.s_r_m,
            self.standing(),
            self.verdict.label()
        )
    }
}
