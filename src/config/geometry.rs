//! The `geometry:` block as a pendulum: the incline (Eq. 36), the length (Eq. 37), the
//! ball's mass and its density's plausibility.

use super::values::{bounded, in_range};
use super::{quoted, shown, Ball, Geometry, BALL_DENSITIES};
use crate::physics::{self, Pendulum};
use anyhow::{bail, Result};

/// Geometry block -> pendulum parameters (Eq. 36, 37, 9).
/// The pendulum of a geometry's measured inputs (every value checked, errors name the
/// key).
pub fn pendulum_of(g: &Geometry) -> Result<Pendulum> {
    bounded("geometry.g_m_s2", g.g_m_s2, 100.0, "m/s^2")?;
    let alpha = match (&g.incline.h_m, &g.incline.l_m, &g.incline.angle_deg) {
        (Some(h), Some(l), None) => {
            bounded("geometry.incline.h_m", *h, 100.0, "m")?;
            bounded("geometry.incline.l_m", *l, 100.0, "m")?;
            if h >= l {
                bail!("`geometry.incline.h_m` = {h} m: expected less than `l_m` = {l} m (sin(alpha) = h/l, Eq. 36)");
            }
            physics::incline_from_h_l(*h, *l)
        }
        (None, None, Some(a)) => {
            in_range("geometry.incline.angle_deg", *a, 0.0, 90.0, "deg")?;
            a.to_radians()
        }
        _ => bail!("`geometry.incline`: expected either `h_m` and `l_m` (Eq. 36) or `angle_deg`, not both or neither"),
    };
    let r = g.ball.radius_m;
    bounded("geometry.ball.radius_m", r, 1.0, "m")?;
    let m = match (g.ball.mass_kg, g.ball.density_kg_m3) {
        (Some(m), None) => {
            bounded("geometry.ball.mass_kg", m, 1000.0, "kg")?;
            m
        }
        (None, Some(rho)) => {
            bounded("geometry.ball.density_kg_m3", rho, 1e5, "kg/m^3")?;
            4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * rho
        }
        _ => bail!(
            "`geometry.ball`: expected either `mass_kg` or `density_kg_m3`, not both or neither"
        ),
    };
    let d = match (g.pendulum.d_m, g.pendulum.contact_length_m) {
        (Some(d), None) => {
            bounded("geometry.pendulum.d_m", d, 100.0, "m")?;
            if d <= r {
                bail!("`geometry.pendulum.d_m` = {d} m must exceed the ball radius {r} m");
            }
            d
        }
        (None, Some(l)) => {
            bounded("geometry.pendulum.contact_length_m", l, 100.0, "m")?;
            physics::d_from_contact_length(l, r)
        }
        _ => bail!("`geometry.pendulum`: expected either `d_m` or `contact_length_m` (Eq. 37), not both or neither"),
    };
    Pendulum::solid_ball(r, m, d, alpha, g.g_m_s2)
}

/// How far a ball's density may stray outside its material's range: a mass and a
/// radius each measured to a percent move it by 3 %.
const DENSITY_SLACK: f64 = 0.05;

/// Refuse a ball whose mass and radius give a density its material cannot have: a
/// diameter entered as the radius gives an eighth of it, a mass in grams a thousand
/// times it. With no `geometry.ball.material` the density must be that of some ball
/// material (nylon's to tungsten carbide's), and the refusal says the material was not
/// given; `other` is not checked.
pub(super) fn ball_density(ball: &Ball, m: f64, r: f64) -> Result<()> {
    let rho = m / (4.0 / 3.0 * std::f64::consts::PI * r.powi(3));
    let given = ball.material.as_deref();
    let (what, lo, hi) = match given {
        Some("other") => return Ok(()),
        None => {
            let lo = BALL_DENSITIES
                .iter()
                .map(|b| b.1)
                .fold(f64::INFINITY, f64::min);
            let hi = BALL_DENSITIES.iter().map(|b| b.2).fold(0.0, f64::max);
            (
                "any ball material (`geometry.ball.material` not given)".to_string(),
                lo,
                hi,
            )
        }
        Some(n) => {
            let name = if n == "aluminum" { "aluminium" } else { n };
            let Some(&(_, lo, hi)) = BALL_DENSITIES.iter().find(|(b, _, _)| *b == name) else {
                bail!(
                    "`geometry.ball.material` = `{}`: expected one of {}, or `other`",
                    quoted(name, 40),
                    BALL_DENSITIES.map(|b| b.0).join(", ")
                );
            };
            (format!("a {name} ball"), lo, hi)
        }
    };
    let fits = |rho: f64| rho >= lo * (1.0 - DENSITY_SLACK) && rho <= hi * (1.0 + DENSITY_SLACK);
    if !fits(rho) {
        let hint = if fits(rho * 8.0) {
            ": is `radius_m` the diameter?"
        } else if fits(rho / 1000.0) {
            ": is `mass_kg` in grams?"
        } else if fits(rho * 1e9) {
            ": is `radius_m` in mm?"
        } else {
            ""
        };
        bail!(
            "`geometry.ball`: a mass of {} kg and a radius of {} m give a density of {} \
             kg/m^3; {what} has {lo:.0} to {hi:.0} kg/m^3{hint}",
            shown(m),
            shown(r),
            shown(rho.round())
        );
    }
    Ok(())
}
