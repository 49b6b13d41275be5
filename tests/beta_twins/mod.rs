//! Randomised series of twins of one material pair at four normal forces (four steel
//! balls of one plate), with a known exponent `beta`: each run simulated as a camera
//! records it (no video), fitted alone with `beta = 1` as a build fits it, and the
//! series fitted for `beta` as the index fits it (`rollfric::fit::beta_series`). Shared
//! by `tests/beta_series.rs` and `examples/beta_series.rs`.

use anyhow::{Context, Result};
use rollfric::config::Experiment;
use rollfric::fit::{beta_series, BetaSeries, SeriesRun};
use rollfric::pipeline::{self, Angles, Overrides, Source};
use rollfric::rng::Rng;
use rollfric::series::AngleTable;
use rollfric::simulate;
use std::path::Path;

/// One randomised series: the truth drawn and the fitted series.
pub struct Outcome {
    pub s_r_true: f64,
    pub series: BetaSeries,
}

/// What changes the normal force from run to run.
#[derive(Clone, Copy, PartialEq)]
pub enum Lever {
    /// Four steel balls, radius `r0` (15 to 22 mm) times 1, 1.26, 1.59 and 2.
    Balls,
    /// One ball (the paper's) on four inclines: 3, 5.4, 8 and 12 deg.
    Inclines,
}

/// The series `seed` with the true exponent `beta`: a torque of 1e-5 to 2e-4 N m at
/// 10 N (log-uniform), a pendulum of 0.15 to 0.3 m, the runs of `lever`, per-frame
/// noise of 0.02 to 0.08 deg at 30 frames/s for 60 s, no air.
pub fn series(seed: u64, beta: f64, lever: Lever) -> Result<Outcome> {
    let mut rng = Rng::new(0xbe7a_0000 + seed);
    let m10 = (1e-5f64.ln() + rng.uniform() * (2e-4f64 / 1e-5).ln()).exp();
    let s_r = m10 / 10f64.powf(beta);
    let d = 0.15 + 0.15 * rng.uniform();
    let r0 = 0.015 + 0.007 * rng.uniform();
    let noise = 0.02 + 0.06 * rng.uniform();
    let mut runs = Vec::new();
    for k in 0..4 {
        let (r, incline) = match lever {
            Lever::Balls => (
                r0 * [1.0, 1.26, 1.59, 2.0][k],
                "h_m: 0.142, l_m: 1.5".to_string(),
            ),
            Lever::Inclines => (0.03175, format!("angle_deg: {}", [3.0, 5.4, 8.0, 12.0][k])),
        };
        let m = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * 7850.0;
        let text = format!(
            "name: run{k}\npair: p\nair: {{ model: none }}\ngeometry:\n  incline: {{ {incline} }}\n  \
             pendulum: {{ d_m: {d} }}\n  ball: {{ radius_m: {r}, mass_kg: {m}, material: steel }}\n\
             synthetic:\n  s_r_m: {s_r:e}\n  beta: {beta}\n  psi0_deg: 10\n  duration_s: 60\n  fps: 30\n  \
             angle_noise_deg: {noise}\n  seed: {}\n",
            seed * 10 + k as u64
        );
        let exp = Experiment::parse(Path::new("run.yaml"), &text)
            .with_context(|| format!("series {seed}, run {k}"))?;
        let rec = simulate::record(&exp, &simulate::camera_of(&exp)?)?;
        let angles = Angles {
            source: Source::Twin,
            table: AngleTable::parse_csv(&rec.series.to_csv())?,
            detection: None,
        };
        let a = pipeline::analyze(&exp, &angles, Overrides::default())
            .with_context(|| format!("series {seed}, run {k}: fitting"))?;
        runs.push(SeriesRun::of(
            &format!("run{k}"),
            a.fit.s_r_m,
            a.budget.u_c_m,
            a.fit.beta,
            a.fit.reactions.n_mean_n,
        ));
    }
    let series = beta_series("p", runs).context("a series of four runs")?;
    Ok(Outcome {
        s_r_true: s_r,
        series,
    })
}
