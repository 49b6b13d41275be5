//! The air's share of the damping: `s_r` with and without the air's drag in the
//! equation of motion ([`crate::physics::air`]), the share of the energy the air takes,
//! and (when asked) a scale on the drag fitted besides `s_r`.

use super::{fit_core_from, Measurement};
use crate::numerics::golden_section_min;
use crate::physics::ode::Trajectory;
use crate::physics::{Air, Pendulum};
use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

/// The air's share of a fit.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct AirShare {
    /// `s_r` fitted to the same turning points with the air left out (the paper's
    /// model), m.
    pub s_r_without_air_m: f64,
    /// `100 (s_r - s_r_without_air) / s_r_without_air`: what modelling the air changes,
    /// %.
    pub correction_pct: f64,
    /// The air's share of the energy the fitted motion loses, %.
    pub energy_share_pct: f64,
    /// The largest Reynolds number of the ball along the fitted motion.
    pub reynolds_max: f64,
    /// Air density and viscosity, kg/m^3 and Pa s.
    pub density_kg_m3: f64,
    pub viscosity_pa_s: f64,
    /// The ball's drag against a free sphere's.
    pub wall_factor: f64,
    /// The scale on the drag: 1, or fitted (`air.fit_scale`) with its standard error.
    pub drag_scale: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag_scale_se: Option<f64>,
}

/// Widest drag scale the fit of the scale searches, from 0 (no air).
pub const MAX_DRAG_SCALE: f64 = 20.0;

/// The air's share of a fit of `s_r` (with starting amplitude `a0`) on the pendulum `p`
/// to `m`, along the fitted motion `model` (`None` when `p` has no air).
pub fn air_share(
    p: &Pendulum,
    m: &Measurement,
    beta: f64,
    rtol: f64,
    [s_r, a0]: [f64; 2],
    model: &Trajectory,
    drag_scale_se: Option<f64>,
) -> Result<Option<AirShare>> {
    let Some(air) = p.air else {
        return Ok(None);
    };
    let bare = p.with_air(None);
    let without = fit_core_from(&bare, m, beta, rtol, Some([s_r, a0]))
        .context("fitting s_r without the air")?
        .s_r;
    let (t0, t1) = (model.t0, model.t_last);
    let samples = 4000;
    let (mut drag, mut rolling, mut v_max) = (0.0, 0.0, 0.0f64);
    for i in 0..=samples {
        let t = t0 + (t1 - t0) * i as f64 / samples as f64;
        let [psi, w] = model.state(t);
        let v = p.l * w.abs();
        v_max = v_max.max(v);
        drag += p.drag_force(w) * v;
        rolling += model.law.torque(p.normal_force(psi, w)) / p.r * v;
    }
    Ok(Some(AirShare {
        s_r_without_air_m: without,
        correction_pct: 100.0 * (s_r - without) / without,
        energy_share_pct: 100.0 * drag / (drag + rolling).max(f64::MIN_POSITIVE),
        reynolds_max: air.reynolds(p.r, v_max),
        density_kg_m3: air.density,
        viscosity_pa_s: air.viscosity,
        wall_factor: air.wall_factor,
        drag_scale: air.scale,
        drag_scale_se,
    }))
}

/// The drag scale that fits `m` best with `s_r` (profiled out), in
/// `[0, MAX_DRAG_SCALE]`, and its standard error from the profile's curvature:
/// `se^2 = 2 sigma^2 / RSS''` with `sigma^2 = RSS / (n - 3)`.
pub fn fit_drag_scale(p: &Pendulum, m: &Measurement, beta: f64, rtol: f64) -> Result<(f64, f64)> {
    let air = p
        .air
        .context("fitting the drag's scale needs air (`air.model: sphere`)")?;
    let rss = |k: f64| {
        let pk = p.with_air(Some(Air { scale: k, ..air }));
        fit_core_from(&pk, m, beta, rtol, None).map(|c| c.rss)
    };
    let k = golden_section_min(rss, (0.0, MAX_DRAG_SCALE), 1e-3)?;
    let n = m.amplitudes.len();
    let h = 0.05f64.max(0.05 * k);
    let lo = (k - h).max(0.0);
    let (r_lo, r_mid, r_hi) = (rss(lo)?, rss(lo + h)?, rss(lo + 2.0 * h)?);
    let curv = (r_hi - 2.0 * r_mid + r_lo) / (h * h);
    let sigma2 = r_mid / (n.saturating_sub(3).max(1)) as f64;
    let se = if curv > 0.0 {
        (2.0 * sigma2 / curv).sqrt()
    } else {
        f64::INFINITY
    };
    Ok((k, se))
}
