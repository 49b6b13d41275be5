//! The conical pendulum of the paper: a ball of radius `r` tied by a wire to a
//! fulcrum `O` on a plate inclined at `alpha`, rolling without slipping.
//!
//! Notation and equations follow `paper.md` with the corrections of `ERRATA.md`:
//!
//! * `sin(delta) = r / d` (Fig. 8), `L = d cos(delta) = sqrt(d^2 - r^2)` (Eq. 37),
//!   `J_z = 2/5 m r^2` (Eq. 9) unless given, `J_C = J_z + m r^2` (ERRATA, identity).
//! * Normal force, Eq. 30 (with the gravity term the printed Eq. 29 lacks, ERRATA §1):
//!   `N = J_C psi'^2 / r + m g (cos(alpha) + sin(alpha) tan(delta) cos(psi))`.
//! * Friction force, Eq. 31 (with `sgn(psi')`, ERRATA §3):
//!   `T = (J_z / J_C) m g sin(alpha) sin(psi) - (m r / J_C) s_r N^beta sgn(psi')`.
//! * Equation of motion, Eq. 33 (missing from the text; ERRATA §2), from Eq. 29 and 32:
//!   `psi'' = -(m g r^2 sin(alpha) / (J_C L)) sin(psi) - (r s_r N^beta / (J_C L)) sgn(psi')`.
//! * Pure rolling holds while `|T| / N < mu` (Eq. 34).
//! * Beyond the paper, the air's drag on the ball adds `-(r^2 F_d / (J_C L)) sgn(psi')`
//!   to Eq. 33 and `(J_z / J_C) F_d sgn(psi')` to Eq. 31 ([`air`]), when the pendulum has
//!   air ([`Pendulum::with_air`]).
//!
//! The integrator lives in [`ode`]; the torsion appendix (A1–A5) in [`torsion`].
//! All quantities are SI: metres, kilograms, seconds, radians.

pub mod air;
pub mod ode;
pub mod torsion;

pub use air::Air;

use anyhow::{ensure, Result};
use serde::Serialize;

/// Which exponent `beta` of `M_r = s_r N^beta` (Eq. 28) to use.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum BetaChoice {
    Fixed(f64),
    /// Fit `beta` as well (by profiling it over `[0.5, 2.0]`).
    Free,
}

/// Rolling-resistance law `M_r = s_r N^beta` (Eq. 28).
///
/// `s_r` is in m·N^(1-beta): metres for the paper's `beta = 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionLaw {
    pub s_r: f64,
    pub beta: f64,
}

impl FrictionLaw {
    pub fn new(s_r: f64, beta: f64) -> Self {
        Self { s_r, beta }
    }

    /// Rolling-friction torque for a normal force `n` (N), in N·m (Eq. 28).
    #[inline]
    pub fn torque(&self, n: f64) -> f64 {
        if self.s_r == 0.0 {
            0.0
        } else if self.beta == 1.0 {
            self.s_r * n.max(0.0)
        } else {
            self.s_r * n.max(0.0).powf(self.beta)
        }
    }
}

/// Geometry and mass of one pendulum, with the derived quantities the equations use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pendulum {
    /// Ball radius `r`, m.
    pub r: f64,
    /// Ball mass `m`, kg.
    pub m: f64,
    /// Moment of inertia about a diameter `J_z`, kg·m^2 (Eq. 9 for a solid ball).
    pub j_z: f64,
    /// Fulcrum-to-centre distance `d`, m.
    pub d: f64,
    /// Plate inclination `alpha`, rad (Eq. 36).
    pub alpha: f64,
    /// Gravitational acceleration, m/s^2.
    pub g: f64,
    /// `delta = asin(r / d)`, rad (Fig. 8).
    pub delta: f64,
    /// Fulcrum-to-contact distance `L = sqrt(d^2 - r^2)`, m (Eq. 37).
    pub l: f64,
    /// Moment of inertia about the contact axis `J_C = J_z + m r^2`, kg·m^2.
    pub j_c: f64,
    /// The air the ball moves through (`None`: the paper's model, in a vacuum).
    pub air: Option<Air>,
    /// Constants of the hot path, computed once.
    c: Cached,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Cached {
    /// `m g r^2 sin(alpha) / (J_C L)` and `r / (J_C L)` of Eq. 33.
    k_grav: f64,
    k_fric: f64,
    /// `r^2 / (J_C L)`: the drag force's share of `psi''`.
    k_air: f64,
}

impl Pendulum {
    /// A solid ball (`J_z = 2/5 m r^2`, Eq. 9).
    pub fn solid_ball(r: f64, m: f64, d: f64, alpha: f64, g: f64) -> Result<Self> {
        Self::new(r, m, 0.4 * m * r * r, d, alpha, g)
    }

    pub fn new(r: f64, m: f64, j_z: f64, d: f64, alpha: f64, g: f64) -> Result<Self> {
        for (name, v) in [("r", r), ("m", m), ("J_z", j_z), ("d", d), ("g", g)] {
            ensure!(
                v.is_finite() && v > 0.0,
                "{name} = {v} must be a positive number"
            );
        }
        ensure!(
            d > r,
            "d = {d} m must exceed the ball radius r = {r} m (sin(delta) = r/d < 1, Fig. 8)"
        );
        ensure!(
            alpha.is_finite() && alpha > 0.0 && alpha < std::f64::consts::FRAC_PI_2,
            "plate inclination alpha = {alpha} rad must lie strictly between 0 and pi/2"
        );
        let delta = (r / d).asin();
        let l = (d * d - r * r).sqrt();
        let j_c = j_z + m * r * r;
        Ok(Self {
            r,
            m,
            j_z,
            d,
            alpha,
            g,
            delta,
            l,
            j_c,
            air: None,
            c: Cached {
                k_grav: m * g * r * r * alpha.sin() / (j_c * l),
                k_fric: r / (j_c * l),
                k_air: r * r / (j_c * l),
            },
        })
    }

    /// The same pendulum moving through `air` (`None`: in a vacuum, as the paper).
    pub fn with_air(self, air: Option<Air>) -> Self {
        Self { air, ..self }
    }

    /// The drag force on the ball at the rate `psi_dot`, N (0 without air).
    #[inline]
    pub fn drag_force(&self, psi_dot: f64) -> f64 {
        self.air
            .as_ref()
            .map_or(0.0, |a| a.force(self.r, self.l * psi_dot))
    }

    /// Small-angle angular frequency `omega_0 = sqrt(m g r^2 sin(alpha) / (J_C L))`, rad/s.
    /// For a solid ball this is `sqrt(5 g sin(alpha) / (7 L))` (ERRATA §2).
    pub fn omega0(&self) -> f64 {
        self.c.k_grav.sqrt()
    }

    /// Small-angle period `2 pi / omega_0`, s.
    pub fn small_angle_period(&self) -> f64 {
        std::f64::consts::TAU / self.omega0()
    }

    /// Normal force at rest at `psi = 0`: `N_0 = m g (cos(alpha) + sin(alpha) tan(delta))`.
    pub fn rest_normal_force(&self) -> f64 {
        self.normal_force(0.0, 0.0)
    }

    /// Normal force `N` (Eq. 30, ERRATA §1), N.
    pub fn normal_force(&self, psi: f64, psi_dot: f64) -> f64 {
        self.j_c * psi_dot * psi_dot / self.r
            + self.m * self.g * (self.alpha.cos() + self.alpha.sin() * self.delta.tan() * psi.cos())
    }

    /// In-plane friction force `T` (Eq. 31 with `sgn(psi')`, ERRATA §3; with the air's
    /// drag `F_d`, [`air`]), N.
    pub fn friction_force(&self, law: &FrictionLaw, psi: f64, psi_dot: f64) -> f64 {
        self.friction_force_towards(law, psi, psi_dot, sign(psi_dot))
    }

    /// [`Pendulum::friction_force`] of a ball moving in the direction `dir` (+1 or -1)
    /// at the rate `psi_dot`, which may be 0 (a turning point, where the rolling
    /// resistance still acts against the coming motion): the forces at `psi_dot`, their
    /// signs by `dir`.
    pub fn friction_force_towards(
        &self,
        law: &FrictionLaw,
        psi: f64,
        psi_dot: f64,
        dir: f64,
    ) -> f64 {
        let n = self.normal_force(psi, psi_dot);
        self.j_z / self.j_c
            * (self.m * self.g * self.alpha.sin() * psi.sin() + self.drag_force(psi_dot) * dir)
            - self.m * self.r / self.j_c * law.torque(n) * dir
    }

    /// Angular acceleration `psi''` (Eq. 33, ERRATA §2) while the wire moves in the
    /// direction `dir` (+1 or -1): `dir` stands for `sgn(psi')`, held fixed over a half
    /// swing so that the right-hand side stays smooth.
    #[inline]
    pub fn psi_ddot(&self, law: &FrictionLaw, psi: f64, psi_dot: f64, dir: f64) -> f64 {
        let mut friction = self.c.k_fric * law.torque(self.normal_force(psi, psi_dot));
        if self.air.is_some() {
            friction += self.c.k_air * self.drag_force(psi_dot);
        }
        -(self.c.k_grav * psi.sin() + friction * dir)
    }

    /// Whether gravity can start the ball from rest at `psi` against the rolling
    /// resistance: `m g r sin(alpha) |sin(psi)| > M_r(N(psi, 0))`.
    pub fn can_restart(&self, law: &FrictionLaw, psi: f64) -> bool {
        let drive = self.m * self.g * self.r * self.alpha.sin() * psi.sin().abs();
        drive > law.torque(self.normal_force(psi, 0.0))
    }

    /// Mechanical energy (ERRATA §2): `1/2 J_C (L psi'/r)^2 - m g L sin(alpha) cos(psi)`, J.
    pub fn energy(&self, psi: f64, psi_dot: f64) -> f64 {
        let w = self.l * psi_dot / self.r;
        0.5 * self.j_c * w * w - self.m * self.g * self.l * self.alpha.sin() * psi.cos()
    }

    /// Ball angular speed `|omega| = L |psi'| / r` (pure rolling, Eq. 19), rad/s.
    pub fn ball_spin(&self, psi_dot: f64) -> f64 {
        self.l * psi_dot.abs() / self.r
    }

    /// Closed-form small-angle amplitude drop per half swing, rad (ERRATA §2):
    /// `2 s_r N_0^beta / (m g r sin(alpha))`.
    pub fn drop_per_half_swing(&self, law: &FrictionLaw) -> f64 {
        2.0 * law.torque(self.rest_normal_force()) / (self.m * self.g * self.r * self.alpha.sin())
    }

    /// Closed-form small-angle envelope slope `a = drop * omega_0 / pi`, rad/s: the
    /// proportionality of the paper's Fig. 19, with its constant (ERRATA §2).
    pub fn envelope_slope(&self, law: &FrictionLaw) -> f64 {
        self.drop_per_half_swing(law) * self.omega0() / std::f64::consts::PI
    }

    /// Rotation of the ball about its own axis for a precession `psi` (pure rolling,
    /// Eq. 19): `phi = psi / sin(delta) = psi d / r` in magnitude, rad.
    pub fn spin_angle(&self, psi: f64) -> f64 {
        psi / self.delta.sin()
    }

    /// Pendulum length implied by a measured small-angle period, by inverting
    /// `T = 2 pi / omega_0` for `L` and then Eq. 37: `d = sqrt(L^2 + r^2)`, m.
    pub fn d_from_period(&self, period: f64) -> f64 {
        let w = std::f64::consts::TAU / period;
        let l = self.m * self.g * self.r * self.r * self.alpha.sin()
            / ((self.j_z + self.m * self.r * self.r) * w * w);
        (l * l + self.r * self.r).sqrt()
    }

    /// Pendulum length implied by a period measured at the swing amplitude `amp` (rad):
    /// the period brought to small swings by the circular pendulum's `1 + A^2 / 16`,
    /// then [`Self::d_from_period`], m.
    pub fn d_from_swing_period(&self, period: f64, amp: f64) -> f64 {
        self.d_from_period(period / (1.0 + amp * amp / 16.0))
    }
}

/// `sgn(x)` with `sgn(0) = 0`, as in Eq. 27, 29 and 31.
pub fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Plate inclination from the support geometry, `alpha = asin(h / l)` (Eq. 36), rad.
pub fn incline_from_h_l(h: f64, l: f64) -> f64 {
    (h / l).asin()
}

/// `d` from the measurable fulcrum-to-contact length, `d = sqrt(L^2 + r^2)` (Eq. 37), m.
pub fn d_from_contact_length(l: f64, r: f64) -> f64 {
    (l * l + r * r).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn paper_pendulum(d: f64) -> Pendulum {
        let alpha = incline_from_h_l(0.142, 1.5);
        Pendulum::solid_ball(0.03175, 1.0458, d, alpha, 9.81).unwrap()
    }

    #[test]
    fn eq36_gives_the_papers_angle() {
        let alpha = incline_from_h_l(0.142, 1.5);
        assert!((alpha.to_degrees() - 5.432).abs() < 5e-4);
    }

    #[test]
    fn contact_length_and_d_round_trip() {
        let p = paper_pendulum(0.195);
        assert!((d_from_contact_length(p.l, p.r) - 0.195).abs() < 1e-15);
        assert!((p.j_c - 1.4 * p.m * p.r * p.r).abs() < 1e-18);
        assert!((p.delta.sin() * p.d - p.r).abs() < 1e-15);
    }

    #[test]
    fn omega0_matches_solid_ball_form() {
        let p = paper_pendulum(0.2);
        let w = (5.0 * p.g * p.alpha.sin() / (7.0 * p.l)).sqrt();
        assert!((p.omega0() - w).abs() < 1e-14 * w);
        assert!((p.d_from_period(p.small_angle_period()) - p.d).abs() < 1e-12);
    }

    #[test]
    fn normal_force_at_rest_is_gravity_plus_wire_term() {
        let p = paper_pendulum(0.14);
        let n0 = p.m * p.g * (p.alpha.cos() + p.alpha.sin() * p.delta.tan());
        assert!((p.rest_normal_force() - n0).abs() < 1e-12);
        // N is close to m g: the paper's Appendix approximation.
        assert!((p.rest_normal_force() / (p.m * p.g) - 1.0).abs() < 0.02);
    }

    #[test]
    fn rejects_wire_shorter_than_radius() {
        let err = Pendulum::solid_ball(0.03175, 1.0, 0.02, 0.1, 9.81).unwrap_err();
        assert!(
            err.to_string().contains("must exceed the ball radius"),
            "{err}"
        );
    }

    #[test]
    fn friction_force_vanishes_at_rest_without_friction() {
        let p = paper_pendulum(0.2);
        let law = FrictionLaw::new(0.0, 1.0);
        assert_eq!(p.friction_force(&law, 0.0, 0.3), 0.0);
        // Eq. 31 with s_r = 0: T = (J_z / J_C) m g sin(alpha) sin(psi) = 2/7 ...
        let t = p.friction_force(&law, 0.1, 0.0);
        let want = 2.0 / 7.0 * p.m * p.g * p.alpha.sin() * 0.1f64.sin();
        assert!((t - want).abs() < 1e-12);
    }
}
