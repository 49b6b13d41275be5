//! The `air:` block (the air the ball moves through) and its `synthetic.air` twin.

use super::values::{in_range, non_negative, positive, within};
use crate::physics::air::{Air, DragLaw};
use anyhow::{bail, Result};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The air around the ball: its drag joins the equation of motion (a sphere's drag
/// curve, Schiller–Naumann; docs/air.md). Every key has a default: still dry air at 20
/// degC and 101.325 kPa, no wall factor. `model: none` leaves the air out, as the paper
/// does.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AirFile {
    /// `sphere` (the drag of a sphere, the default) or `none` (no air, as the paper).
    #[serde(default)]
    pub model: AirModel,
    /// Air temperature, degC, -30 to 60. Default 20.
    #[serde(default = "default_temperature")]
    pub temperature_c: f64,
    /// Air pressure, kPa, 50 to 110 (about 90 at 1000 m above the sea). Default
    /// 101.325.
    #[serde(default = "default_pressure")]
    pub pressure_kpa: f64,
    /// The ball's drag on the plate against a free sphere's, 0.5 to 5 (more than 1 near
    /// a wall). Default 1.
    #[serde(default = "default_wall_factor")]
    pub wall_factor: f64,
    /// A constant drag coefficient instead of the sphere's drag curve (a twin with a
    /// known `C_d`), 0.01 to 10. Default: the drag curve.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag_coefficient: Option<f64>,
    /// Fit a scale on the whole drag besides `s_r` (the air's share then comes from
    /// the recording, not from the drag curve): only for long runs whose envelope
    /// bends measurably. Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub fit_scale: bool,
    /// Standard uncertainties for the uncertainty budget. Defaults in each key.
    #[serde(default)]
    pub uncertainty: AirUncertainty,
}

impl Default for AirFile {
    fn default() -> Self {
        Self {
            model: AirModel::default(),
            temperature_c: default_temperature(),
            pressure_kpa: default_pressure(),
            wall_factor: default_wall_factor(),
            drag_coefficient: None,
            fit_scale: false,
            uncertainty: AirUncertainty::default(),
        }
    }
}

/// Whether the air is modelled.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, JsonSchema, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum AirModel {
    /// The drag of a sphere.
    #[default]
    Sphere,
    /// No air (the paper's model).
    None,
}

/// Standard uncertainties of the air's inputs (GUM Type B). A value given is read as
/// the standard deviation of a normal distribution; a default as a rectangular one.
#[derive(Debug, Clone, Default, Deserialize, Serialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AirUncertainty {
    /// `u(T)`, degC. Default 1.7 (a room within +-3 degC of the value).
    pub temperature_c: Option<f64>,
    /// `u(p)`, kPa. Default 2.9 (+-5 kPa: the weather, and a lab up to 400 m above the
    /// sea at the default).
    pub pressure_kpa: Option<f64>,
    /// `u(wall factor)`. Default 0.14 (+-0.25: the plate's share of the drag of a ball
    /// rolling on it is not well known at these Reynolds numbers).
    pub wall_factor: Option<f64>,
    /// The drag curve's relative standard uncertainty. Default 0.029 (+-5 %: the
    /// correlation against the measured curve of a sphere).
    pub drag_rel: Option<f64>,
}

/// Default standard uncertainties (rectangular half-widths over `sqrt 3`).
pub const AIR_DEFAULT_U_T: f64 = 3.0 / 1.732_050_807_568_877_2;
pub const AIR_DEFAULT_U_P_KPA: f64 = 5.0 / 1.732_050_807_568_877_2;
pub const AIR_DEFAULT_U_WALL: f64 = 0.25 / 1.732_050_807_568_877_2;
pub const AIR_DEFAULT_U_DRAG_REL: f64 = 0.05 / 1.732_050_807_568_877_2;

fn default_temperature() -> f64 {
    20.0
}

fn default_pressure() -> f64 {
    101.325
}

fn default_wall_factor() -> f64 {
    1.0
}

impl AirFile {
    /// No air: `model: none`.
    pub fn none() -> Self {
        Self {
            model: AirModel::None,
            ..Self::default()
        }
    }

    /// Check every value, naming its key under `at` (`air` or `synthetic.air`).
    pub fn check(&self, at: &str) -> Result<()> {
        in_range(
            &format!("{at}.temperature_c"),
            self.temperature_c,
            -30.0,
            60.0,
            "degC",
        )?;
        in_range(
            &format!("{at}.pressure_kpa"),
            self.pressure_kpa,
            50.0,
            110.0,
            "kPa",
        )?;
        within(&format!("{at}.wall_factor"), self.wall_factor, 0.5, 5.0, "")?;
        if let Some(cd) = self.drag_coefficient {
            within(&format!("{at}.drag_coefficient"), cd, 0.01, 10.0, "")?;
        }
        let u = &self.uncertainty;
        for (k, v) in [
            ("temperature_c", u.temperature_c),
            ("pressure_kpa", u.pressure_kpa),
            ("wall_factor", u.wall_factor),
            ("drag_rel", u.drag_rel),
        ] {
            if let Some(v) = v {
                non_negative(&format!("{at}.uncertainty.{k}"), v, "")?;
            }
        }
        if let Some(v) = u.drag_rel {
            if v >= 1.0 {
                bail!(
                    "`{at}.uncertainty.drag_rel` = {v}: expected a fraction below 1 (0.03 for 3 %)"
                );
            }
        }
        if self.model == AirModel::None && self.fit_scale {
            bail!("`{at}.fit_scale`: there is no air to scale with `model: none`");
        }
        positive(&format!("{at}.pressure_kpa"), self.pressure_kpa, "kPa")
    }

    /// The physics' air (`None` for `model: none`), the drag scaled by `scale`.
    pub fn air(&self) -> Option<Air> {
        (self.model == AirModel::Sphere).then(|| Air {
            wall_factor: self.wall_factor,
            law: self
                .drag_coefficient
                .map_or(DragLaw::Sphere, DragLaw::Constant),
            ..Air::at(self.temperature_c, 1e3 * self.pressure_kpa)
        })
    }
}
