//! The reactions along the fitted motion: the normal force (Eq. 30, Fig. 17) and the
//! friction force over it (Eq. 31, 34, Fig. 18).

use crate::physics::ode::Trajectory;
use serde::Serialize;

/// The reactions along the fitted motion (Eq. 30, 31, 34).
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize, PartialEq)]
pub struct Reactions {
    pub n_min_n: f64,
    pub n_max_n: f64,
    pub n_mean_n: f64,
    /// `100 (N_max - N_min) / N_mean`, %.
    pub n_variation_pct: f64,
    /// Largest `|T| / N` (must stay below the sliding coefficient, Eq. 34).
    pub max_t_over_n: f64,
}

/// `N(t)` and `|T|/N` sampled densely along a trajectory between `t0` and `t1`.
pub fn reactions(tr: &Trajectory, t0: f64, t1: f64) -> Reactions {
    let p = &tr.pendulum;
    let samples = 4000;
    let (mut lo, mut hi, mut sum, mut ratio) = (f64::INFINITY, 0.0f64, 0.0, 0.0f64);
    for i in 0..=samples {
        let t = t0 + (t1 - t0) * i as f64 / samples as f64;
        let [psi, w] = tr.state(t);
        let n = p.normal_force(psi, w);
        let dir = if w == 0.0 {
            tr.direction(t)
        } else {
            crate::physics::sign(w)
        };
        let tf = p.friction_force_towards(&tr.law, psi, w, dir);
        lo = lo.min(n);
        hi = hi.max(n);
        sum += n;
        ratio = ratio.max(tf.abs() / n);
    }
    let mean = sum / (samples + 1) as f64;
    Reactions {
        n_min_n: lo,
        n_max_n: hi,
        n_mean_n: mean,
        n_variation_pct: 100.0 * (hi - lo) / mean,
        max_t_over_n: ratio,
    }
}
