//! Integration of the equation of motion (Eq. 33, ERRATA §2) half swing by half swing.
//!
//! `sgn(psi')` makes the right-hand side discontinuous at every turning point, so the
//! trajectory is integrated as a chain of smooth half swings with the direction held
//! fixed. Each half swing uses the adaptive Dormand–Prince 5(4) pair with its
//! fourth-order dense output (Hairer, Nørsett & Wanner, *Solving ODEs I*, II.5–6). The
//! turning point (`psi' = 0`) is located on the dense output by bisection, then the step
//! is retaken exactly to it, so the restart begins from a fifth-order accurate state. At
//! each turning point the ball restarts only if gravity can overcome the rolling
//! resistance at rest ([`Pendulum::can_restart`]); otherwise it stays there for good.

use super::{sign, FrictionLaw, Pendulum};
use crate::numerics::bisect;

/// Tolerances and limits of one integration.
#[derive(Clone, Copy, Debug)]
pub struct OdeOptions {
    /// Relative tolerance on `(psi, psi')` per step.
    pub rtol: f64,
    /// Absolute tolerance per step (rad and rad/s).
    pub atol: f64,
    /// Stop after this time, s.
    pub t_end: f64,
    /// Stop after this many turning points (the start, if at rest, not counted).
    pub max_turns: usize,
}

impl Default for OdeOptions {
    fn default() -> Self {
        Self {
            rtol: 1e-10,
            atol: 1e-13,
            t_end: 600.0,
            max_turns: usize::MAX,
        }
    }
}

/// A point where `psi' = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurningPoint {
    pub t: f64,
    pub psi: f64,
}

/// One accepted step with its dense-output coefficients.
#[derive(Clone, Debug)]
struct Step {
    t0: f64,
    h: f64,
    /// `rcont[0..5]` for each of the two state components.
    rc: [[f64; 2]; 5],
}

impl Step {
    fn eval(&self, t: f64) -> [f64; 2] {
        let th = ((t - self.t0) / self.h).clamp(0.0, 1.0);
        let th1 = 1.0 - th;
        let mut y = [0.0; 2];
        for (i, yi) in y.iter_mut().enumerate() {
            let r = |k: usize| self.rc[k][i];
            *yi = r(0) + th * (r(1) + th1 * (r(2) + th * (r(3) + th1 * r(4))));
        }
        y
    }
}

/// The integrated motion: dense output over every half swing, and its turning points.
#[derive(Clone, Debug)]
pub struct Trajectory {
    pub pendulum: Pendulum,
    pub law: FrictionLaw,
    /// Start time and state.
    pub t0: f64,
    pub y0: [f64; 2],
    /// Turning points after the start, in time order.
    pub turns: Vec<TurningPoint>,
    /// Time from which the ball stays at rest, if it stopped within the span.
    pub stopped_at: Option<f64>,
    /// Last time covered by the dense output (or by rest, if stopped).
    pub t_last: f64,
    steps: Vec<Step>,
    /// Direction of motion over each step (`sgn(psi')`), for derived quantities.
    dirs: Vec<f64>,
}

impl Trajectory {
    /// State `(psi, psi')` at time `t`, clamped to the integrated span; at rest after a stop.
    pub fn state(&self, t: f64) -> [f64; 2] {
        if t <= self.t0 || self.steps.is_empty() {
            return self.y0;
        }
        let i = self.steps.partition_point(|s| s.t0 <= t).saturating_sub(1);
        let s = &self.steps[i];
        if t >= s.t0 + s.h {
            let mut y = s.eval(s.t0 + s.h);
            if self.stopped_at.is_some_and(|ts| t >= ts) {
                y[1] = 0.0;
            }
            return y;
        }
        s.eval(t)
    }

    /// Direction of motion `sgn(psi')` at time `t` (0 at rest).
    pub fn direction(&self, t: f64) -> f64 {
        if self.steps.is_empty() || t < self.t0 || self.stopped_at.is_some_and(|ts| t >= ts) {
            return 0.0;
        }
        let i = self.steps.partition_point(|s| s.t0 <= t).saturating_sub(1);
        if t > self.steps[i].t0 + self.steps[i].h {
            return 0.0;
        }
        self.dirs[i]
    }

    /// Step boundaries (for quadrature that must not straddle a turning point).
    pub fn step_bounds(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.steps.iter().map(|s| (s.t0, s.t0 + s.h))
    }
}

// Dormand–Prince 5(4) tableau (the system is autonomous, so the nodes c_i are unused).
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// Fifth-order minus fourth-order weights (the error estimate).
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// Dense-output weights of the fourth-order continuous extension.
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

struct Rhs<'a> {
    p: &'a Pendulum,
    law: &'a FrictionLaw,
    dir: f64,
}

impl Rhs<'_> {
    fn f(&self, y: [f64; 2]) -> [f64; 2] {
        [y[1], self.p.psi_ddot(self.law, y[0], y[1], self.dir)]
    }

    /// One Dormand–Prince step of size `h` from `y` with `k1 = f(y)`.
    /// Returns the new state, the stage derivatives and the scaled error norm.
    fn step(&self, y: [f64; 2], k1: [f64; 2], h: f64, o: &OdeOptions) -> StepOut {
        let mut k = [[0.0; 2]; 7];
        k[0] = k1;
        for s in 1..7 {
            let mut ys = y;
            for (j, kj) in k.iter().enumerate().take(s) {
                let a = A[s][j];
                if a != 0.0 {
                    ys[0] += h * a * kj[0];
                    ys[1] += h * a * kj[1];
                }
            }
            k[s] = self.f(ys);
            if s == 6 {
                // FSAL: stage 7 is evaluated at the new state.
                let mut err = 0.0f64;
                for i in 0..2 {
                    let e: f64 = (0..7).map(|j| E[j] * k[j][i]).sum::<f64>() * h;
                    let sc = o.atol + o.rtol * y[i].abs().max(ys[i].abs());
                    err = err.max((e / sc).abs());
                }
                return StepOut { y1: ys, k, err };
            }
        }
        unreachable!()
    }
}

struct StepOut {
    y1: [f64; 2],
    k: [[f64; 2]; 7],
    err: f64,
}

fn dense(y0: [f64; 2], o: &StepOut, h: f64) -> [[f64; 2]; 5] {
    let mut rc = [[0.0; 2]; 5];
    for i in 0..2 {
        let dy = o.y1[i] - y0[i];
        let bspl = h * o.k[0][i] - dy;
        rc[0][i] = y0[i];
        rc[1][i] = dy;
        rc[2][i] = bspl;
        rc[3][i] = dy - h * o.k[6][i] - bspl;
        rc[4][i] = h * (0..7).map(|j| D[j] * o.k[j][i]).sum::<f64>();
    }
    rc
}

/// Integrate the motion from `(psi0, psi_dot0)` at `t0`.
///
/// The first half swing's direction is `sgn(psi_dot0)`, or towards `psi = 0` when
/// starting from rest (if the ball can start at all).
pub fn integrate(
    p: &Pendulum,
    law: &FrictionLaw,
    t0: f64,
    y0: [f64; 2],
    opts: &OdeOptions,
) -> Trajectory {
    let mut tr = Trajectory {
        pendulum: *p,
        law: *law,
        t0,
        y0,
        turns: Vec::new(),
        stopped_at: None,
        t_last: t0,
        steps: Vec::new(),
        dirs: Vec::new(),
    };
    let period = p.small_angle_period();
    let h_max = period / 32.0;
    let mut t = t0;
    let mut y = y0;
    let mut dir = sign(y[1]);
    if dir == 0.0 {
        if !p.can_restart(law, y[0]) {
            tr.stopped_at = Some(t0);
            tr.t_last = opts.t_end.max(t0);
            return tr;
        }
        dir = -sign(y[0]);
    }
    let mut h = h_max / 8.0;
    'half_swings: while t < opts.t_end && tr.turns.len() < opts.max_turns {
        let rhs = Rhs { p, law, dir };
        let mut k1 = rhs.f(y);
        loop {
            let h_try = h.min(opts.t_end - t).min(h_max);
            if h_try <= 1e-12 * period {
                break 'half_swings;
            }
            let out = rhs.step(y, k1, h_try, opts);
            if out.err > 1.0 {
                h = h_try * (0.9 * out.err.powf(-0.2)).max(0.2);
                continue;
            }
            let crossed = out.y1[1] * dir <= 0.0;
            if !crossed {
                let rc = dense(y, &out, h_try);
                tr.steps.push(Step {
                    t0: t,
                    h: h_try,
                    rc,
                });
                tr.dirs.push(dir);
                t += h_try;
                y = out.y1;
                k1 = out.k[6];
                h = h_try * (0.9 * out.err.max(1e-10).powf(-0.2)).min(5.0);
                continue;
            }
            // The turning point lies in this step: find theta with psi'(theta) = 0 on the
            // dense output, then retake the step exactly to it.
            let step = Step {
                t0: t,
                h: h_try,
                rc: dense(y, &out, h_try),
            };
            let theta = bisect(
                |s| step.eval(t + s * h_try)[1] * dir > 0.0,
                (0.0, 1.0),
                200,
                1e-15,
            );
            let h_turn = theta * h_try;
            if h_turn > 0.0 {
                let out2 = rhs.step(y, k1, h_turn, opts);
                let rc = dense(y, &out2, h_turn);
                tr.steps.push(Step {
                    t0: t,
                    h: h_turn,
                    rc,
                });
                tr.dirs.push(dir);
                y = out2.y1;
                // One Newton correction of the event time with psi'' at the end.
                let acc = out2.k[6][1];
                let dt = if acc != 0.0 { -y[1] / acc } else { 0.0 };
                y[0] += 0.5 * y[1] * dt;
                t += h_turn + dt;
            }
            y[1] = 0.0;
            tr.turns.push(TurningPoint { t, psi: y[0] });
            tr.t_last = t;
            if !p.can_restart(law, y[0]) {
                tr.stopped_at = Some(t);
                tr.t_last = opts.t_end.max(t);
                return tr;
            }
            dir = -dir;
            h = h_try.max(h_max / 64.0);
            continue 'half_swings;
        }
    }
    tr.t_last = t;
    tr
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::incline_from_h_l;

    fn pendulum(d: f64) -> Pendulum {
        Pendulum::solid_ball(0.03175, 1.0458, d, incline_from_h_l(0.142, 1.5), 9.81).unwrap()
    }

    fn tight() -> OdeOptions {
        OdeOptions {
            rtol: 1e-13,
            atol: 1e-16,
            ..OdeOptions::default()
        }
    }

    #[test]
    fn energy_is_conserved_without_friction_over_50_periods() {
        let p = pendulum(0.195);
        let law = FrictionLaw::new(0.0, 1.0);
        let psi0 = 10f64.to_radians();
        let opts = OdeOptions {
            t_end: 50.0 * p.small_angle_period() * 1.01,
            ..tight()
        };
        let tr = integrate(&p, &law, 0.0, [psi0, 0.0], &opts);
        assert!(tr.turns.len() >= 100, "{} turns", tr.turns.len());
        let e0 = p.energy(psi0, 0.0);
        // Scale: the swing energy above the bottom of the well.
        let swing = e0 - p.energy(0.0, 0.0);
        let mut worst = 0.0f64;
        let n = 20_000;
        for i in 0..=n {
            let t = opts.t_end * i as f64 / n as f64;
            let [psi, w] = tr.state(t);
            worst = worst.max(((p.energy(psi, w) - e0) / swing).abs());
        }
        assert!(worst < 1e-9, "relative energy error {worst:e}");
        // The amplitude does not decay either.
        let last = tr.turns.last().unwrap().psi.abs();
        assert!((last - psi0).abs() < 1e-9 * psi0);
    }

    #[test]
    fn small_angle_period_matches_closed_form() {
        let p = pendulum(0.14);
        let law = FrictionLaw::new(0.0, 1.0);
        let psi0 = 1e-3;
        let opts = OdeOptions {
            max_turns: 20,
            ..tight()
        };
        let tr = integrate(&p, &law, 0.0, [psi0, 0.0], &opts);
        let period = tr.turns[19].t / 10.0;
        let want = std::f64::consts::TAU * (7.0 * p.l / (5.0 * p.g * p.alpha.sin())).sqrt();
        assert!(
            ((period - want) / want).abs() < 1e-6,
            "period {period} vs {want}"
        );
    }

    #[test]
    fn dissipated_energy_equals_work_of_rolling_torque() {
        let p = pendulum(0.1774);
        let law = FrictionLaw::new(20e-6, 1.0);
        let tr = integrate(&p, &law, 0.0, [0.15, 0.0], &tight());
        assert!(tr.stopped_at.is_some());
        let t_end = tr.t_last.min(tr.turns.last().unwrap().t);
        // Composite Simpson of M_r |omega| over each step (no step straddles a turn).
        let mut work = 0.0;
        for (a, b) in tr.step_bounds() {
            let f = |t: f64| {
                let [psi, w] = tr.state(t);
                law.torque(p.normal_force(psi, w)) * p.ball_spin(w)
            };
            let m = 8;
            let hh = (b - a) / m as f64;
            let mut s = f(a) + f(b);
            for i in 1..m {
                s += f(a + i as f64 * hh) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            work += s * hh / 3.0;
        }
        let [psi_e, w_e] = tr.state(t_end);
        let lost = p.energy(0.15, 0.0) - p.energy(psi_e, w_e);
        assert!(
            ((lost - work) / lost).abs() < 1e-8,
            "lost {lost:e} J vs work {work:e} J"
        );
    }

    #[test]
    fn envelope_slope_matches_closed_form_at_five_degrees() {
        for (d, beta) in [(0.14, 1.0), (0.195, 1.0), (0.24, 1.0), (0.195, 1.5)] {
            let p = pendulum(d);
            let law = FrictionLaw::new(5e-6, beta);
            let tr = integrate(&p, &law, 0.0, [5f64.to_radians(), 0.0], &tight());
            let n = tr.turns.len().min(12);
            assert!(n >= 6);
            let (ts, amps): (Vec<f64>, Vec<f64>) =
                tr.turns[..n].iter().map(|tp| (tp.t, tp.psi.abs())).unzip();
            let slope = -crate::numerics::linear_fit(&ts, &amps).slope;
            let want = p.envelope_slope(&law);
            assert!(
                ((slope - want) / want).abs() < 0.02,
                "d {d} beta {beta}: ODE {slope:e} vs closed form {want:e}"
            );
        }
    }

    #[test]
    fn stops_when_gravity_cannot_beat_resistance() {
        let p = pendulum(0.2);
        let law = FrictionLaw::new(50e-6, 1.0);
        let tr = integrate(&p, &law, 0.0, [0.1, 0.0], &OdeOptions::default());
        let ts = tr.stopped_at.expect("must stop");
        let last = tr.turns.last().unwrap();
        assert_eq!(ts, last.t);
        assert!(!p.can_restart(&law, last.psi));
        // Every earlier turn could restart, and the state stays put afterwards.
        assert!(tr.turns[..tr.turns.len() - 1]
            .iter()
            .all(|tp| p.can_restart(&law, tp.psi)));
        assert_eq!(tr.state(ts + 100.0), [last.psi, 0.0]);
        // Released inside the dead band, it never moves.
        let tiny = integrate(&p, &law, 0.0, [1e-4, 0.0], &OdeOptions::default());
        assert_eq!(tiny.stopped_at, Some(0.0));
        assert!(tiny.turns.is_empty());
    }

    #[test]
    fn turning_points_have_zero_velocity_and_alternate() {
        let p = pendulum(0.2);
        let law = FrictionLaw::new(5e-6, 1.0);
        let opts = OdeOptions {
            max_turns: 10,
            ..OdeOptions::default()
        };
        let tr = integrate(&p, &law, 0.0, [0.2, 0.0], &opts);
        assert_eq!(tr.turns.len(), 10);
        for w in tr.turns.windows(2) {
            assert!(w[0].psi * w[1].psi < 0.0);
            assert!(w[1].psi.abs() < w[0].psi.abs());
            let [_, v] = tr.state(w[1].t);
            assert!(v.abs() < 1e-8, "psi' at turn {v}");
        }
    }
}
