//! The Monte Carlo check of an uncertainty budget (JCGM 101:2008 §8): every input
//! drawn from its distribution, `s_r` re-fitted for each draw, and the distribution's
//! standard deviation and 95 % interval set beside the budget's.

use super::*;

/// The Monte Carlo check of a budget (JCGM 101).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct MonteCarlo {
    pub draws: usize,
    pub seed: u64,
    pub mean_m: f64,
    /// The draws' standard deviation, m.
    pub u_m: f64,
    /// The 2.5 % and 97.5 % quantiles of the draws, m.
    pub interval95_m: [f64; 2],
    /// `u_m / u_c` of the budget.
    pub u_ratio: f64,
    /// The draws' histogram (for the figure): [`HISTOGRAM_BINS`] equal bins from the
    /// smallest draw to the largest.
    pub histogram: Histogram,
}

/// Bins of the Monte Carlo histogram.
pub const HISTOGRAM_BINS: usize = 40;

/// Counts of values in equal bins over `[lo, hi]`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Histogram {
    pub lo: f64,
    pub hi: f64,
    pub counts: Vec<usize>,
}

impl Histogram {
    /// `bins` equal bins over the range of the sorted `values`.
    pub fn of_sorted(values: &[f64], bins: usize) -> Self {
        let (lo, hi) = (values[0], values[values.len() - 1]);
        let mut counts = vec![0; bins];
        let w = (hi - lo) / bins as f64;
        for v in values {
            let i = if w > 0.0 {
                (((v - lo) / w) as usize).min(bins - 1)
            } else {
                0
            };
            counts[i] += 1;
        }
        Self { lo, hi, counts }
    }
}

/// A Student's t deviate with `nu` degrees of freedom.
fn student(rng: &mut Rng, nu: f64) -> f64 {
    let z = rng.normal();
    if !nu.is_finite() || nu > 1000.0 {
        return z;
    }
    let k = nu.round().max(1.0) as usize;
    let chi2: f64 = (0..k).map(|_| rng.normal().powi(2)).sum();
    z / (chi2 / k as f64).sqrt()
}

/// JCGM 101: `draws` draws of every input of `b` from its distribution, `s_r` re-fitted
/// for each draw of the geometry, the angles' parts added; `progress` is called with the
/// draws done.
pub fn monte_carlo(
    exp: &Experiment,
    m: &Measurement,
    f: &FitResult,
    b: &Budget,
    draws: usize,
    seed: u64,
    progress: &mut dyn FnMut(usize),
) -> Result<MonteCarlo> {
    let ins = inputs(exp, f);
    let base = Setting::of(exp, f);
    let start = [f.s_r_m, f.a_start_rad];
    let mut rng = Rng::new(seed);
    let mut values = Vec::with_capacity(draws);
    for done in 0..draws {
        let mut g = base.clone();
        for c in &b.components {
            let Some(i) = ins.iter().find(|i| i.key == c.key) else {
                continue;
            };
            let x = match c.distribution {
                Distribution::Rectangular => {
                    i.value + c.u * 3.0_f64.sqrt() * (2.0 * rng.uniform() - 1.0)
                }
                _ => i.value + c.u * rng.normal(),
            };
            (i.set)(&mut g, x);
        }
        let p = g.pendulum().context("a Monte Carlo draw of the geometry")?;
        let mut s =
            fit::refit(&p, m, f.beta, start, RTOL).context("re-fitting a Monte Carlo draw")?[0];
        // The angles' parts and the plate calibration add to s_r directly.
        for c in b.components.iter().filter(|c| c.adds_to_s_r()) {
            s += c.u
                * match c.distribution {
                    Distribution::Student => student(&mut rng, c.dof.unwrap_or(f64::INFINITY)),
                    _ => rng.normal(),
                };
        }
        values.push(s);
        progress(done + 1);
    }
    let mean = values.iter().sum::<f64>() / draws as f64;
    let u = sd(&values);
    values.sort_by(f64::total_cmp);
    let q = |p: f64| values[((draws as f64 * p).round() as usize).min(draws - 1)];
    Ok(MonteCarlo {
        draws,
        seed,
        mean_m: mean,
        u_m: u,
        interval95_m: [q(0.025), q(0.975)],
        u_ratio: u / b.u_c_m,
        histogram: Histogram::of_sorted(&values, HISTOGRAM_BINS),
    })
}
