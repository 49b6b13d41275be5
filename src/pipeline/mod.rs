//! One experiment through the stages: acquire its angles (a measured CSV, a lab video or
//! the digital twin's video) -> release and extremes -> equilibrium -> fit (outlying
//! turning points dropped) -> checks -> torsion.
//!
//! Every function here returns typed values and writes no report file; `rollfric fit`,
//! `rollfric build` and the tests all go through them, so they cannot disagree. The
//! build wraps each stage in its cache; the twin's video is the one file written here
//! (under the cache folder, keyed like every cached stage).

mod result;

pub use result::{ExperimentResult, GeometryView, Inputs, PageFile};

use crate::config::Experiment;
use crate::detect::{self, summary::DetectionSummary, DetectOptions, Detection};
use crate::fit::{self, FitOptions, FitResult, Measurement};
use crate::hash::{self, Key};
use crate::physics::torsion::{torsion_check, TorsionCheck};
use crate::physics::{BetaChoice, FrictionLaw};
use crate::series::AngleTable;
use crate::uncertainty::{self, Budget, MonteCarlo};
use crate::verdict::{self, Against, Check, Evidence, Limits, Quantity, Verdict};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// Where an experiment's angles come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A measured angle CSV (`angles:` in the experiment, or given on the command line).
    Csv(PathBuf),
    /// The lab's recording (`video.path`).
    LabVideo(PathBuf),
    /// The digital twin's video, rendered from the `synthetic:` block.
    Twin,
}

impl Source {
    /// The experiment's source: `explicit` (a CSV given on the command line), else its
    /// `angles:`, else its `video.path` (which must exist), else its twin.
    pub fn of(exp: &Experiment, explicit: Option<&Path>) -> Result<Self> {
        if let Some(p) = explicit {
            return Ok(Source::Csv(p.to_path_buf()));
        }
        if let Some(a) = &exp.file.angles {
            let path = exp.resolve(a);
            crate::fsutil::regular_file(&path)
                .with_context(|| format!("{}: `angles` = {a}", exp.path.display()))?;
            return Ok(Source::Csv(path));
        }
        if let Some(p) = exp.file.video.as_ref().and_then(|v| v.path.as_deref()) {
            let path = exp.resolve(p);
            crate::fsutil::regular_file(&path)
                .with_context(|| format!("{}: `video.path` = {p}", exp.path.display()))?;
            return Ok(Source::LabVideo(path));
        }
        if exp.file.synthetic.is_none() {
            bail!(
                "{}: no video: set `video.path`, or `angles:` for a measured angle CSV",
                exp.path.display()
            );
        }
        Ok(Source::Twin)
    }

    /// Whether the angles are synthetic: only then is a result measured against the
    /// twin's `s_r` (the one rule for "synthetic truth").
    pub fn is_synthetic(&self) -> bool {
        matches!(self, Source::Twin)
    }
}

/// An experiment's angles and where they came from.
#[derive(Clone, Debug)]
pub struct Angles {
    pub source: Source,
    /// Every row, missing frames included.
    pub table: AngleTable,
    /// What the detector did, for angles measured in a video.
    pub detection: Option<DetectionSummary>,
}

impl Angles {
    /// Read a measured angle CSV.
    pub fn from_csv(path: &Path) -> Result<Self> {
        Ok(Self {
            source: Source::Csv(path.to_path_buf()),
            table: AngleTable::read_csv(path)?,
            detection: None,
        })
    }
}

/// The digital twin's video of `exp` under `cache/<name>/twin.avi`, rendered when its
/// key is stale. Returns the path, the render key and whether it was rendered now.
/// `progress` hears `(frames done, frames)`, first with `(0, 0)`.
pub fn twin(
    exp: &Experiment,
    cache: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<(PathBuf, String, bool)> {
    let (video, key, key_file) = twin_files(exp, cache)?;
    if hash::fresh(&key_file, &key, &[&video]) {
        return Ok((video, key, false));
    }
    progress(0, 0);
    let mut cb = |done: usize, total: usize| progress(done as u64, total as u64);
    crate::synth::render(exp, &video, None, &mut cb)
        .with_context(|| format!("{}: rendering the twin", exp.path.display()))?;
    hash::record(&key_file, &key)?;
    Ok((video, key, true))
}

/// The twin's video and render key when the cache holds it rendered under the current
/// key; `None` when it must be rendered (see [`twin`]).
pub fn twin_cached(exp: &Experiment, cache: &Path) -> Result<Option<(PathBuf, String)>> {
    let (video, key, key_file) = twin_files(exp, cache)?;
    Ok(hash::fresh(&key_file, &key, &[&video]).then_some((video, key)))
}

/// The file under `cache/<name>/` holding the twin's render key.
pub const TWIN_KEY: &str = "twin.key";

/// The twin's video, its render key and the key's file under `cache/<name>/`.
fn twin_files(exp: &Experiment, cache: &Path) -> Result<(PathBuf, String, PathBuf)> {
    let Some(syn) = &exp.file.synthetic else {
        bail!("{}: no `synthetic:` block", exp.path.display());
    };
    let key = Key::new("synth")
        .part("source", crate::sources::hash("synth").as_bytes())
        .json("geometry", &exp.file.geometry)
        .json("model", &exp.file.model)
        .json("synthetic", syn)
        .hex();
    let dir = cache.join(&exp.name);
    Ok((dir.join("twin.avi"), key, dir.join(TWIN_KEY)))
}

/// The detector's settings for `exp` (its `video:` block and plate calibration;
/// defaults without them), with its pendulum for the `length` check.
pub fn detect_options(exp: &Experiment) -> DetectOptions {
    DetectOptions {
        calibration: exp.calibration.clone(),
        pendulum: Some(crate::detect::PendulumGiven {
            pendulum: exp.pendulum,
            d_rel: exp.file.tolerances.period_rel,
        }),
        ..exp
            .file
            .video
            .as_ref()
            .map(DetectOptions::from_video)
            .unwrap_or_default()
    }
}

/// The part of `exp`'s `video:` block that changes a detection (everything but the
/// path, which the video's content id stands for).
pub fn detect_settings(exp: &Experiment) -> Option<crate::config::Video> {
    exp.file.video.clone().map(|mut v| {
        v.path = None;
        v
    })
}

/// Measure the angles of `video` and summarise the detection. `label` is how the
/// reports name the video, `video_id` its content id.
pub fn detect(
    video: &Path,
    opts: &DetectOptions,
    label: String,
    video_id: String,
    source: Source,
) -> Result<(Angles, Detection)> {
    let d = detect::detect(video, opts)?;
    let fig = detect::figure11_frame(&d);
    let summary = DetectionSummary::of(&d, label, video_id, source.is_synthetic(), fig);
    let table = AngleTable::parse_csv(&d.to_csv())
        .with_context(|| format!("{}: the detector's angles", video.display()))?;
    Ok((
        Angles {
            source,
            table,
            detection: Some(summary),
        },
        d,
    ))
}

/// Overrides of the experiment's model choices (from the command line).
#[derive(Clone, Copy, Debug, Default)]
pub struct Overrides {
    pub beta: Option<BetaChoice>,
    pub compare_betas: bool,
}

/// Everything the analysis of one experiment's angles produced.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The turning points that were fitted (without any dropped as outliers; see
    /// `fit.outliers`).
    pub measurement: Measurement,
    pub fit: FitResult,
    /// The fitted friction law.
    pub law: FrictionLaw,
    /// The twin's `s_r`, when the angles are synthetic.
    pub truth_s_r_m: Option<f64>,
    pub checks: Vec<Check>,
    pub torsion: Option<TorsionCheck>,
    /// The sliding coefficient of Eq. 34, and whether pure rolling held.
    pub sliding_mu: Option<f64>,
    pub pure_rolling: Option<bool>,
    /// Whether the data agree with the physics of the fit (`ok` or `suspect`).
    pub verdict: Verdict,
    /// The uncertainty budget of `s_r` (GUM): the angles' share and the geometry's.
    pub budget: Budget,
    /// Its Monte Carlo check (JCGM 101), when the experiment asks for one.
    pub monte_carlo: Option<MonteCarlo>,
}

impl Analysis {
    /// Every check within its tolerance.
    pub fn passed(&self) -> bool {
        self.checks.iter().all(Check::verdict)
    }
}

/// Extremes, equilibrium, fit, checks and torsion of an experiment's angles.
pub fn analyze(exp: &Experiment, angles: &Angles, o: Overrides) -> Result<Analysis> {
    let series = angles.table.series().from_clock_start();
    let p = &exp.pendulum;
    let beta = o.beta.unwrap_or(exp.beta);
    let what = || match &angles.source {
        Source::Csv(csv) => format!(
            "{}: fitting the angles of {}",
            exp.path.display(),
            csv.display()
        ),
        _ => format!("{}: fitting", exp.path.display()),
    };
    if series.is_empty() {
        return Err(anyhow::anyhow!("no angles to fit (every row is missing)")).with_context(what);
    }
    let center = crate::numerics::median(&mut series.angle.clone());
    if let Some(why) = verdict::degrees_suspected(&series.angle, center) {
        return Err(anyhow::anyhow!(why)).with_context(what);
    }
    let m = fit::analyze(p, &series, beta).with_context(what)?;
    let mut opts = FitOptions {
        beta,
        compare_betas: o.compare_betas || exp.file.model.compare_betas,
        ..FitOptions::default()
    };
    // `air.fit_scale`: the drag's scale from the turning points, into the pendulum.
    let scaled;
    let p = match p.air {
        Some(air) if exp.file.air.fit_scale => {
            let fixed = match beta {
                fit::BetaChoice::Fixed(b) => b,
                fit::BetaChoice::Free => 1.0,
            };
            let (k, se) = fit::fit_drag_scale(p, &m, fixed, opts.rtol)
                .context("fitting the drag's scale (`air.fit_scale`)")
                .with_context(what)?;
            if !se.is_finite() {
                return Err(anyhow::anyhow!(
                    "`air.fit_scale`: this run cannot tell the drag's scale (the fit's \
                     residual does not change with it); leave `fit_scale` out to take the \
                     drag curve"
                ))
                .with_context(what);
            }
            opts.drag_scale_se = Some(se);
            scaled = p.with_air(Some(crate::physics::Air { scale: k, ..air }));
            &scaled
        }
        _ => p,
    };
    // The turning points that were fitted (outliers dropped) and the fit.
    let frame_noise_rad = crate::signal::noise_sigma(&series.angle);
    let (m, mut f) = fit::fit_robust(p, &m, &opts, frame_noise_rad).with_context(what)?;
    if let Some(r) = f.release.as_mut() {
        // Frames of the recording (missing ones included) before the release.
        r.frame = angles.table.rows.partition_point(|row| row.t_s <= r.t_s);
    }
    let swing_scale = angles.detection.as_ref().and_then(|d| d.swing_scale);
    let angle_u = uncertainty::angle_uncertainty(p, &m, &f, swing_scale);
    f.s_r_u_m = angle_u.u_m;
    f.s_r_interval95_m = angle_u.interval95_m;
    for (key, v) in [
        ("s_r", f.s_r_m),
        ("its standard error", f.s_r_se_m),
        ("the 95 % interval's lower end", f.s_r_ci95_m[0]),
        ("the 95 % interval's upper end", f.s_r_ci95_m[1]),
        ("its uncertainty", f.s_r_u_m),
        ("mu_r", f.mu_r),
        ("the envelope slope a", f.a_rad_s),
        ("the length implied by the period", f.d_from_period_m),
    ] {
        if !v.is_finite() {
            return Err(anyhow::anyhow!(
                "the fit gave {key} = {v}: not a measurement (check the geometry's values and the angles' units)"
            ))
            .with_context(what);
        }
    }
    let law = FrictionLaw::new(f.s_r_m, f.beta);
    // The twin's s_r in the fitted law: when the twin's exponent differs (a run of a
    // series at several normal forces, fitted with beta = 1), the s_r that gives the
    // twin's torque at the run's mean normal force.
    let truth = angles
        .source
        .is_synthetic()
        .then(|| {
            exp.synthetic_law()
                .map(|l| l.s_r * f.reactions.n_mean_n.powf(l.beta - f.beta))
        })
        .flatten();
    let tol = &exp.file.tolerances;
    let ts: Vec<f64> = m.extremes.iter().map(|e| e.t).collect();
    let samples: Vec<usize> = m.extremes.iter().map(|e| e.samples).collect();
    let (outliers_dropped, outliers_kept): (Vec<f64>, Vec<f64>) = {
        let times = |dropped: bool| {
            f.outliers
                .iter()
                .filter(|o| o.dropped == dropped)
                .map(|o| o.t_s)
                .collect()
        };
        (times(true), times(false))
    };
    // A plate calibration's share: the angles were measured through it.
    let plane = match (
        angles
            .detection
            .as_ref()
            .filter(|d| d.calibration.is_some()),
        &exp.calibration,
    ) {
        (Some(d), Some(c)) => {
            let amp = m.amplitudes.iter().copied().fold(0.0, f64::max);
            Some(uncertainty::PlaneScale::of(
                c,
                d.pivot_px,
                m.equilibrium.envelope,
                amp,
            ))
        }
        _ => None,
    };
    // A lens's share: the angles were measured through it. Its swing is the image's
    // (the rest angle taken back through the lens is near enough for a share).
    let lens = angles.detection.as_ref().and_then(|d| {
        let l = d.lens.as_ref()?;
        let amp = m.amplitudes.iter().copied().fold(0.0, f64::max);
        Some(uncertainty::LensScale::of(
            &l.lens,
            d.pivot_px,
            l.band_px,
            m.equilibrium.envelope,
            amp,
        ))
    });
    // The swing's scale's share of s_r's uncertainty, for the `scale` check.
    let scale_u_rel = (plane.is_some() || lens.is_some()).then(|| {
        plane
            .as_ref()
            .map_or(0.0, |p| p.u_rel)
            .hypot(lens.as_ref().map_or(0.0, |l| l.u_rel))
    });
    let mut verdict = verdict::assess(
        &Evidence {
            d_m: p.d,
            d_from_period_m: f.d_from_period_m,
            frame_noise_rad,
            samples: &samples,
            t: &ts,
            amplitudes: &m.amplitudes,
            residual_rms_rad: f.residual_rms_rad,
            s_r: f.s_r_m,
            s_r_ci95: f.s_r_ci95_m,
            s_r_halves: angle_u.halves_m,
            outliers_dropped: &outliers_dropped,
            outliers_kept: &outliers_kept,
            outlier_cap: fit::outlier_cap(m.amplitudes.len() + outliers_dropped.len()),
            swing_scale,
            scale_u_rel,
        },
        &Limits {
            period_rel: tol.period_rel,
            residual_factor: tol.residual_factor,
            envelope_aicc: tol.envelope_aicc,
            halves_rel: tol.halves_rel,
            interval_rel: tol.interval_rel,
            outliers: tol.outliers,
            pivot_rel: tol.pivot_rel,
            scale_rel: tol.scale_rel,
        },
    );
    // A suspect detection makes a suspect result: what was measured may not be the wire.
    if let Some(dv) = angles
        .detection
        .as_ref()
        .and_then(|d| d.verdict.as_ref())
        .filter(|v| v.verdict == verdict::Status::Suspect)
    {
        let failed: Vec<String> = dv
            .failed()
            .map(|c| format!("{}: {}", c.check, c.reason))
            .collect();
        verdict.warnings.push(verdict::Warning {
            check: "detection".into(),
            value: failed.len() as f64,
            limit: 0.0,
            reason: format!("the detection is suspect ({})", failed.join("; ")),
            accepted: None,
        });
        verdict.verdict = verdict::Status::Suspect;
    }
    verdict.accept(
        exp.file
            .accept
            .iter()
            .map(|a| (a.check.as_str(), a.reason.as_str())),
    );
    let mut checks = Vec::new();
    if let Some(r) = &exp.file.reference {
        let src = if r.source.is_empty() {
            "reference"
        } else {
            &r.source
        };
        let against = || Against::Reference(src.to_string());
        for (q, value, expected) in [
            (Quantity::SR, f.s_r_m, r.s_r_m),
            (Quantity::MuR, f.mu_r, r.mu_r),
            (Quantity::A, f.a_rad_s, r.a_rad_s),
        ] {
            if let Some(v) = expected {
                checks.push(Check::new(q, against(), value, v, tol.reference_rel));
            }
        }
    }
    if let Some(v) = truth {
        checks.push(Check::new(
            Quantity::SR,
            Against::SyntheticTruth,
            f.s_r_m,
            v,
            tol.truth_rel,
        ));
    }
    let torsion = exp.file.torsion.as_ref().map(|t| {
        torsion_check(
            p,
            &law,
            t.period_s,
            t.wire_length_m,
            t.psi0_max_deg.to_radians(),
        )
    });
    let mu = exp.file.sliding.as_ref().map(|s| s.mu);
    let budget = uncertainty::budget(exp, &m, &f, angle_u, plane.as_ref(), lens.as_ref())
        .context("the uncertainty budget")
        .with_context(what)?;
    let monte_carlo = match exp.file.monte_carlo_draws {
        Some(draws) => Some(
            uncertainty::monte_carlo(exp, &m, &f, &budget, draws, 1, &mut |_| {})
                .context("the uncertainty budget's Monte Carlo check")
                .with_context(what)?,
        ),
        None => None,
    };
    Ok(Analysis {
        budget,
        monte_carlo,
        pure_rolling: mu.map(|mu| f.max_t_over_n < mu),
        sliding_mu: mu,
        measurement: m,
        fit: f,
        law,
        truth_s_r_m: truth,
        checks,
        torsion,
        verdict,
    })
}
