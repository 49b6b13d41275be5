//! The air's drag on the rolling ball: a sphere's drag force from its Reynolds number.
//!
//! The paper's equation of motion (Eq. 33) has no air. The ball's centre moves at
//! `v = L |psi'|` (pure rolling, Eq. 19), so a drag force `F_d(v)` on it, parallel to
//! the plate, adds a term to the tangential balance. With the ball's rotation
//! `J_z omega' = T r - M_r sgn(psi')` and its translation
//! `m L psi'' = -m g sin(alpha) sin(psi) - T - F_d sgn(psi')` (the signs of Eq. 31),
//! eliminating `T` gives
//!
//! `psi'' = -(m g r^2 sin(alpha) / (J_C L)) sin(psi) - (r M_r / (J_C L)) sgn(psi')
//!          - (r^2 F_d / (J_C L)) sgn(psi')`
//!
//! and the friction force of Eq. 31 becomes
//! `T = (J_z / J_C) (m g sin(alpha) sin(psi) + F_d sgn(psi')) - (m r / J_C) M_r sgn(psi')`.
//! The same follows from the energy: the drag's power `F_d v` is taken from
//! `1/2 J_C (L psi' / r)^2`.
//!
//! **The drag of a sphere** (diameter `D = 2 r`, `Re = rho v D / mu`) is that of
//! Schiller and Naumann (1933), `C_d = 24 / Re (1 + 0.15 Re^0.687)` for `Re <= 1000`,
//! and Newton's `C_d = 0.44` above (up to the drag crisis near `Re = 2e5`): the
//! standard correlation of the drag curve for a solid sphere, within about 5 % of the
//! measured curve over that range (Clift, Grace & Weber, *Bubbles, Drops, and
//! Particles*, 1978, table 5.2). The two meet at `Re = 1000` (0.438 and 0.44). The force
//! is written `F_d = 3 pi mu D v (1 + 0.15 Re^0.687)`, which stays finite as `v -> 0`
//! (Stokes' drag). A ball rolling on a plate is not a sphere in open air: the plate
//! adds drag (the wall factor, given or taken as 1 with its uncertainty).
//!
//! **Air**: density from the ideal gas law for dry air (`R = 287.05 J/(kg K)`) and
//! viscosity from Sutherland's law (`mu_0 = 1.716e-5 Pa s` at 273.15 K, `S = 110.4 K`),
//! 1.204 kg/m^3 and 1.813e-5 Pa s at 20 degC and 101.325 kPa.

/// Specific gas constant of dry air, J/(kg K).
pub const R_DRY_AIR: f64 = 287.05;
/// Sutherland's law for air: reference viscosity (Pa s) at `T_0` (K), and `S` (K).
const SUTHERLAND_MU0: f64 = 1.716e-5;
const SUTHERLAND_T0: f64 = 273.15;
const SUTHERLAND_S: f64 = 110.4;
/// Where Schiller and Naumann's correlation hands over to Newton's constant.
pub const RE_NEWTON: f64 = 1000.0;
/// Newton's drag coefficient of a sphere, `1e3 < Re < 2e5`.
pub const CD_NEWTON: f64 = 0.44;

/// Density of dry air at `temperature_c` (degC) and `pressure_pa`, kg/m^3 (ideal gas).
pub fn air_density(temperature_c: f64, pressure_pa: f64) -> f64 {
    pressure_pa / (R_DRY_AIR * (temperature_c + 273.15))
}

/// Dynamic viscosity of air at `temperature_c` (degC), Pa s (Sutherland's law).
pub fn air_viscosity(temperature_c: f64) -> f64 {
    let t = temperature_c + 273.15;
    SUTHERLAND_MU0 * (t / SUTHERLAND_T0).powf(1.5) * (SUTHERLAND_T0 + SUTHERLAND_S)
        / (t + SUTHERLAND_S)
}

/// The drag coefficient of a sphere at Reynolds number `re` (Schiller–Naumann below
/// [`RE_NEWTON`], Newton's constant above).
pub fn drag_coefficient(re: f64) -> f64 {
    if re <= RE_NEWTON {
        24.0 / re * (1.0 + 0.15 * re.powf(0.687))
    } else {
        CD_NEWTON
    }
}

/// How the drag coefficient is found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DragLaw {
    /// The standard drag curve of a sphere ([`drag_coefficient`]).
    Sphere,
    /// A constant drag coefficient (a twin with a known `C_d`).
    Constant(f64),
}

/// The air around the ball and the drag it exerts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Air {
    /// Density `rho`, kg/m^3.
    pub density: f64,
    /// Dynamic viscosity `mu`, Pa s.
    pub viscosity: f64,
    /// Drag of the ball on the plate against a free sphere's (>= 1 near a wall).
    pub wall_factor: f64,
    /// A scale on the whole drag (1 unless fitted or varied for the budget).
    pub scale: f64,
    pub law: DragLaw,
}

impl Air {
    /// Still dry air at `temperature_c` and `pressure_pa`, the standard drag curve, no
    /// wall.
    pub fn at(temperature_c: f64, pressure_pa: f64) -> Self {
        Self {
            density: air_density(temperature_c, pressure_pa),
            viscosity: air_viscosity(temperature_c),
            wall_factor: 1.0,
            scale: 1.0,
            law: DragLaw::Sphere,
        }
    }

    /// Drag force on a sphere of radius `r` (m) moving at speed `v` (m/s, >= 0), N.
    #[inline]
    pub fn force(&self, r: f64, v: f64) -> f64 {
        let v = v.abs();
        let k = self.wall_factor * self.scale;
        let dia = 2.0 * r;
        let re = self.density * v * dia / self.viscosity;
        let f = match self.law {
            DragLaw::Sphere if re <= RE_NEWTON => {
                3.0 * std::f64::consts::PI
                    * self.viscosity
                    * dia
                    * v
                    * (1.0 + 0.15 * re.powf(0.687))
            }
            DragLaw::Sphere => {
                0.5 * self.density * v * v * std::f64::consts::PI * r * r * CD_NEWTON
            }
            DragLaw::Constant(cd) => 0.5 * self.density * v * v * std::f64::consts::PI * r * r * cd,
        };
        k * f
    }

    /// Reynolds number of a sphere of radius `r` at speed `v`.
    pub fn reynolds(&self, r: f64, v: f64) -> f64 {
        self.density * v.abs() * 2.0 * r / self.viscosity
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_air_at_20_degrees() {
        // Handbook values at 20 degC and 1 atm: 1.204 kg/m^3 and 1.81e-5 Pa s.
        assert!((air_density(20.0, 101_325.0) - 1.2041).abs() < 1e-3);
        assert!((air_viscosity(20.0) - 1.8133e-5).abs() < 1e-8);
        // Sutherland's reference point.
        assert!((air_viscosity(0.0) - 1.716e-5).abs() < 1e-12);
    }

    #[test]
    fn drag_curve_meets_newton_and_stokes() {
        // The two branches meet at Re = 1000 within 0.5 %.
        let below = drag_coefficient(RE_NEWTON);
        assert!((below / CD_NEWTON - 1.0).abs() < 0.005, "{below}");
        // Stokes' law as Re -> 0: C_d Re -> 24.
        assert!((drag_coefficient(1e-6) * 1e-6 - 24.0).abs() < 1e-3);
        // The tabulated standard curve at Re = 100 is 1.09 (Clift et al.).
        assert!((drag_coefficient(100.0) - 1.09).abs() < 0.03);
    }

    #[test]
    fn force_is_the_drag_coefficient_times_dynamic_pressure() {
        let air = Air::at(20.0, 101_325.0);
        let (r, v) = (0.03175, 0.06);
        let re = air.reynolds(r, v);
        let want = 0.5 * air.density * v * v * std::f64::consts::PI * r * r * drag_coefficient(re);
        assert!((air.force(r, v) / want - 1.0).abs() < 1e-12);
        // Finite and linear in v as v -> 0 (Stokes: 6 pi mu r v).
        let slow = air.force(r, 1e-9) / 1e-9;
        assert!((slow / (6.0 * std::f64::consts::PI * air.viscosity * r) - 1.0).abs() < 1e-3);
        let c = Air {
            law: DragLaw::Constant(0.5),
            wall_factor: 1.2,
            ..air
        };
        let want = 1.2 * 0.5 * air.density * v * v * std::f64::consts::PI * r * r * 0.5;
        assert!((c.force(r, v) - want).abs() < 1e-18);
    }
}

#[cfg(test)]
mod motion_tests {
    use super::*;
    use crate::physics::ode::{integrate, OdeOptions};
    use crate::physics::{incline_from_h_l, FrictionLaw, Pendulum};

    /// Quadratic drag alone, `F = c v^2`, at a small amplitude `A`: over a half swing
    /// `v = L A w sin(w t)` loses `c (L A w)^3 (4/3) / w` of the energy
    /// `1/2 J_C (L A w / r)^2`, so the amplitude falls by `(4/3) c L A^2 r^2 / J_C`.
    #[test]
    fn quadratic_drag_loses_the_hand_computed_amplitude() {
        let air = Air {
            law: DragLaw::Constant(0.5),
            ..Air::at(20.0, 101_325.0)
        };
        let p = Pendulum::solid_ball(0.03175, 1.0458, 0.1774, incline_from_h_l(0.142, 1.5), 9.81)
            .unwrap()
            .with_air(Some(air));
        let c = 0.5 * air.density * std::f64::consts::PI * p.r * p.r * 0.5;
        let a = 3f64.to_radians();
        let opts = OdeOptions {
            max_turns: 1,
            ..OdeOptions::default()
        };
        let tr = integrate(&p, &FrictionLaw::new(0.0, 1.0), 0.0, [a, 0.0], &opts);
        let drop = a - tr.turns[0].psi.abs();
        let want = 4.0 / 3.0 * c * p.l * a * a * p.r * p.r / p.j_c;
        assert!((drop / want - 1.0).abs() < 0.01, "{drop:e} vs {want:e}");
        // Without air nothing is lost.
        let bare = integrate(
            &p.with_air(None),
            &FrictionLaw::new(0.0, 1.0),
            0.0,
            [a, 0.0],
            &opts,
        );
        assert!((a - bare.turns[0].psi.abs()).abs() < 1e-9);
    }
}
