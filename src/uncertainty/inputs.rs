//! The budget's inputs: each measured quantity of the geometry and of the air, its value,
//! its given or default standard uncertainty, and how to set it in a copy of the
//! experiment's inputs to re-fit (`super::budget`, `super::monte_carlo`).

use crate::config::{pendulum_of, Experiment};
use crate::fit::FitResult;
use crate::physics::Pendulum;
use anyhow::Result;

/// A geometry input: its symbol, key, value, unit, given or default `u`, and how to set
/// it in a copy of the geometry.
pub(super) struct Input {
    pub(super) quantity: &'static str,
    pub(super) key: &'static str,
    pub(super) value: f64,
    pub(super) unit: &'static str,
    pub(super) given: Option<f64>,
    pub(super) default_u: f64,
    pub(super) default_why: &'static str,
    /// The value is on a ratio scale, so that a standard uncertainty as large as it is
    /// a unit's mistake (not so a temperature in degC, or a fitted scale that the run
    /// could barely tell from zero).
    pub(super) ratio: bool,
    pub(super) set: fn(&mut Setting, f64),
}

/// What the budget's inputs set: the geometry, the air, and a factor on the drag.
#[derive(Clone)]
pub(super) struct Setting {
    geometry: crate::config::Geometry,
    air: crate::config::AirFile,
    /// The drag's scale (1, or the fitted one), and a factor on it (the drag curve's
    /// uncertainty).
    drag_scale: f64,
    drag_factor: f64,
}

impl Setting {
    pub(super) fn of(exp: &Experiment, f: &FitResult) -> Self {
        Self {
            geometry: exp.file.geometry.clone(),
            air: exp.file.air.clone(),
            drag_scale: f.air.map_or(1.0, |a| a.drag_scale),
            drag_factor: 1.0,
        }
    }

    /// The pendulum these inputs make.
    pub(super) fn pendulum(&self) -> Result<Pendulum> {
        let air = self.air.air().map(|a| crate::physics::Air {
            // A budget step or a draw of a fitted scale may pass zero: no air then, not
            // an air that drives the swing.
            scale: (self.drag_scale * self.drag_factor).max(0.0),
            ..a
        });
        Ok(pendulum_of(&self.geometry)?.with_air(air))
    }
}

/// Half a division of `division`, as a rectangular standard uncertainty.
fn resolution(division: f64) -> f64 {
    division / (2.0 * 3.0_f64.sqrt())
}

pub(super) fn inputs(exp: &Experiment, f: &FitResult) -> Vec<Input> {
    let g = &exp.file.geometry;
    let u = &g.uncertainty;
    // A length read off a rule with 1 mm divisions.
    let ruled = |quantity, key, value, given, set| Input {
        quantity,
        key,
        value,
        unit: "m",
        given,
        default_u: resolution(1e-3),
        default_why: "a rule with 1 mm divisions",
        ratio: true,
        set,
    };
    let mut v = Vec::new();
    if let (Some(h), Some(l)) = (g.incline.h_m, g.incline.l_m) {
        v.push(ruled("h", "geometry.incline.h_m", h, u.h_m, |g, x| {
            g.geometry.incline.h_m = Some(x)
        }));
        v.push(ruled("l", "geometry.incline.l_m", l, u.l_m, |g, x| {
            g.geometry.incline.l_m = Some(x)
        }));
    }
    if let Some(a) = g.incline.angle_deg {
        v.push(Input {
            quantity: "alpha",
            key: "geometry.incline.angle_deg",
            value: a,
            unit: "deg",
            given: u.angle_deg,
            default_u: resolution(0.1),
            default_why: "an inclinometer reading to 0.1 deg",
            ratio: true,
            set: |s, x| s.geometry.incline.angle_deg = Some(x),
        });
    }
    if let Some(d) = g.pendulum.d_m {
        v.push(ruled("d", "geometry.pendulum.d_m", d, u.d_m, |g, x| {
            g.geometry.pendulum.d_m = Some(x)
        }));
    }
    if let Some(l) = g.pendulum.contact_length_m {
        v.push(ruled(
            "L",
            "geometry.pendulum.contact_length_m",
            l,
            u.contact_length_m,
            |s, x| s.geometry.pendulum.contact_length_m = Some(x),
        ));
    }
    v.push(Input {
        quantity: "r",
        key: "geometry.ball.radius_m",
        value: g.ball.radius_m,
        unit: "m",
        given: u.radius_m,
        default_u: resolution(0.02e-3),
        default_why: "a caliper reading to 0.02 mm",
        ratio: true,
        set: |s, x| s.geometry.ball.radius_m = x,
    });
    if let Some(m) = g.ball.mass_kg {
        v.push(Input {
            quantity: "m",
            key: "geometry.ball.mass_kg",
            value: m,
            unit: "kg",
            given: u.mass_kg,
            default_u: resolution(0.1e-3),
            default_why: "a balance reading to 0.1 g",
            ratio: true,
            set: |s, x| s.geometry.ball.mass_kg = Some(x),
        });
    }
    if let Some(rho) = g.ball.density_kg_m3 {
        v.push(Input {
            quantity: "rho",
            key: "geometry.ball.density_kg_m3",
            value: rho,
            unit: "kg/m^3",
            given: u.density_kg_m3,
            default_u: 0.01 * rho / 3.0_f64.sqrt(),
            default_why: "a handbook density, +-1 %",
            ratio: true,
            set: |s, x| s.geometry.ball.density_kg_m3 = Some(x),
        });
    }
    v.push(Input {
        quantity: "g",
        key: "geometry.g_m_s2",
        value: g.g_m_s2,
        unit: "m/s^2",
        given: u.g_m_s2,
        default_u: 0.03 / 3.0_f64.sqrt(),
        default_why: "9.81 stands for 9.78..9.84 over the Earth",
        ratio: true,
        set: |s, x| s.geometry.g_m_s2 = x,
    });
    v.extend(air_inputs(exp, f));
    v
}

/// The air's inputs: temperature, pressure, and the drag's wall factor and curve (or,
/// with `air.fit_scale`, the fitted scale alone).
fn air_inputs(exp: &Experiment, f: &FitResult) -> Vec<Input> {
    let a = &exp.file.air;
    let Some(share) = f.air.filter(|_| a.air().is_some()) else {
        return Vec::new();
    };
    if a.fit_scale {
        // The recording fixes the drag itself (the scale times the air's density or
        // viscosity): the scale's standard error holds the air's doubt, and varying T
        // and p at a fixed scale would count it twice.
        return vec![Input {
            quantity: "drag scale (fitted)",
            key: "air.fit_scale",
            value: share.drag_scale,
            unit: "",
            given: share.drag_scale_se,
            default_u: 0.0,
            default_why: "",
            ratio: false,
            set: |s, x| s.drag_scale = x,
        }];
    }
    let u = &a.uncertainty;
    let mut v = vec![
        Input {
            quantity: "T (air)",
            key: "air.temperature_c",
            value: a.temperature_c,
            unit: "degC",
            given: u.temperature_c,
            default_u: crate::config::AIR_DEFAULT_U_T,
            default_why: "a room within +-3 degC",
            ratio: false,
            set: |s, x| s.air.temperature_c = x,
        },
        Input {
            quantity: "p (air)",
            key: "air.pressure_kpa",
            value: a.pressure_kpa,
            unit: "kPa",
            given: u.pressure_kpa,
            default_u: crate::config::AIR_DEFAULT_U_P_KPA,
            default_why: "+-5 kPa: weather and altitude",
            ratio: true,
            set: |s, x| s.air.pressure_kpa = x,
        },
    ];
    v.push(Input {
        quantity: "wall factor (air)",
        key: "air.wall_factor",
        value: a.wall_factor,
        unit: "",
        given: u.wall_factor,
        default_u: crate::config::AIR_DEFAULT_U_WALL,
        default_why: "the plate's share of the drag, +-0.25",
        ratio: true,
        set: |s, x| s.air.wall_factor = x,
    });
    v.push(Input {
        quantity: "drag curve (air)",
        key: "air.uncertainty.drag_rel",
        value: 1.0,
        unit: "",
        given: u.drag_rel,
        default_u: crate::config::AIR_DEFAULT_U_DRAG_REL,
        default_why: "the drag correlation, +-5 %",
        ratio: true,
        set: |s, x| s.drag_factor = x,
    });
    v
}

/// The pendulum with input `i` set to `x`, a step of `u` from its value: an error
/// quotes the value given and the step, not the stepped value alone.
pub(super) fn pendulum_with(base: &Setting, i: &Input, x: f64, u: f64) -> Result<Pendulum> {
    let mut s = base.clone();
    (i.set)(&mut s, x);
    s.pendulum().map_err(|e| {
        anyhow::anyhow!(
            "`{}` = {} {unit}: a step of its standard uncertainty ({:.3e} {unit}) leaves the \
             geometry a pendulum can have ({e:#}); check the value and its uncertainty",
            i.key,
            crate::config::shown(i.value),
            u,
            unit = i.unit
        )
    })
}
