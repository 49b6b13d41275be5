//! `rollfric fit`: one experiment through the pipeline, as text or JSON.

use crate::build;
use crate::config::{self, locate, Experiment};
use crate::detect::DetectOptions;
use crate::fit::FitResult;
use crate::hash;
use crate::pipeline::{self, Angles, Overrides, Source};
use crate::uncertainty::{Budget, MonteCarlo};
use crate::verdict::Verdict;
use anyhow::Result;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct FitArgs {
    /// Experiment file, or its name: NAME.yaml here, then in experiments/.
    experiment: String,
    /// Angle CSV with `t_s` and `angle_rad` columns (default: the experiment's).
    #[arg(long)]
    angles: Option<PathBuf>,
    /// Exponent of M_r = s_r N^beta: a number, 4/3, 3/2 or `free`.
    #[arg(long)]
    beta: Option<String>,
    /// Also fit beta = 1, 4/3, 3/2 and print their figures of merit.
    #[arg(long)]
    compare_beta: bool,
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
    /// The build's cache: a video's angles measured there by `rollfric build` are
    /// reused while the video and the `video:` settings are unchanged.
    #[arg(long, default_value = "build")]
    cache: PathBuf,
    /// Measure the video again even when the cache holds its angles.
    #[arg(long)]
    fresh: bool,
}

/// Where the angles of a fit came from.
#[derive(Clone, Debug, Serialize)]
pub struct AnglesSource {
    /// `csv`, `video` or `synthetic-video`.
    pub kind: String,
    pub description: String,
}

/// Everything `rollfric fit --json` prints.
#[derive(Clone, Debug, Serialize)]
pub struct FitReport {
    pub experiment: String,
    pub material: String,
    pub angles: AnglesSource,
    /// The synthetic truth, when the angles are the twin's.
    pub truth_s_r_m: Option<f64>,
    /// Sliding coefficient of Eq. 34 and whether pure rolling held.
    pub sliding_mu: Option<f64>,
    pub pure_rolling: Option<bool>,
    /// `ok`, or `suspect` with its warnings (`"verdict"`, `"warnings"`).
    #[serde(flatten)]
    pub verdict: Verdict,
    #[serde(flatten)]
    pub fit: FitResult,
    /// The uncertainty budget (GUM), and its Monte Carlo check when asked for.
    pub budget: Budget,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<MonteCarlo>,
}

/// The experiment's angles: a CSV, or its video (the lab's, or the twin's rendered
/// under `cache/<name>/`): the angles a build measured in it when they are current
/// (unless `fresh`), else detected now.
fn angles(
    exp: &Experiment,
    source: Source,
    cache: &Path,
    fresh: bool,
) -> Result<(Angles, AnglesSource)> {
    let (video, id) = match &source {
        Source::Csv(path) => {
            let a = Angles::from_csv(path)?;
            let description = format!("measured angles from {}", path.display());
            return Ok((
                a,
                AnglesSource {
                    kind: "csv".into(),
                    description,
                },
            ));
        }
        Source::LabVideo(path) => (path.clone(), None),
        Source::Twin => {
            let (video, key) = twin_video(exp, cache)?;
            (video, Some(key))
        }
    };
    let cached = if fresh {
        None
    } else {
        let id = match id {
            Some(key) => key,
            None => hash::sha256_file(&video)?,
        };
        build::cached_angles(exp, source.clone(), &id, cache)
    };
    let from_cache = cached.is_some();
    let a = match cached {
        Some(a) => a,
        None => {
            let opts: DetectOptions = pipeline::detect_options(exp);
            let label = video.display().to_string();
            pipeline::detect(&video, &opts, label, String::new(), source.clone())?.0
        }
    };
    let d = a.detection.as_ref().expect("a detection");
    let synthetic = source.is_synthetic();
    let description = format!(
        "{}angles detected in {} ({} frames: {} corrected, {} missing){}",
        if synthetic {
            "SYNTHETIC: the digital twin's video; "
        } else {
            ""
        },
        video.display(),
        d.frames,
        d.corrected,
        d.missing,
        if from_cache {
            format!(
                "; measured by a build, read from {} (--fresh measures again)",
                cache.join(&exp.name).display()
            )
        } else {
            String::new()
        }
    );
    let kind = if synthetic {
        "synthetic-video"
    } else {
        "video"
    };
    Ok((
        a,
        AnglesSource {
            kind: kind.into(),
            description,
        },
    ))
}

/// The twin's video under `cache/<name>/`, rendered now when its key is stale; and its
/// render key.
fn twin_video(exp: &Experiment, cache: &Path) -> Result<(PathBuf, String)> {
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let started = std::time::Instant::now();
    let (video, key, rendered) = pipeline::twin(exp, cache, &mut |done, total| {
        if tty && total > 0 {
            eprint!("\rsynth: frame {done}/{total}");
        }
    })?;
    if rendered {
        if tty {
            eprintln!();
        }
        eprintln!(
            "{}: rendered the digital twin's video in {:.1} s -> {}",
            exp.name,
            started.elapsed().as_secs_f64(),
            video.display()
        );
    }
    Ok((video, key))
}

/// Fit one experiment through the pipeline.
pub fn fit_report(exp: &Experiment, a: &FitArgs) -> Result<FitReport> {
    let source = Source::of(exp, a.angles.as_deref())?;
    let (angles, described) = angles(exp, source, &a.cache, a.fresh)?;
    let beta = match &a.beta {
        Some(b) => Some(config::parse_beta(
            &config::BetaSpec::Text(b.clone()),
            "--beta",
        )?),
        None => None,
    };
    let r = pipeline::analyze(
        exp,
        &angles,
        Overrides {
            beta,
            compare_betas: a.compare_beta,
        },
    )?;
    Ok(FitReport {
        experiment: exp.name.clone(),
        material: exp.material.clone(),
        truth_s_r_m: r.truth_s_r_m,
        pure_rolling: r.pure_rolling,
        sliding_mu: r.sliding_mu,
        angles: described,
        verdict: r.verdict,
        fit: r.fit,
        budget: r.budget,
        monte_carlo: r.monte_carlo,
    })
}

/// `rollfric fit`: human-readable or JSON.
pub fn fit(a: FitArgs) -> Result<String> {
    let exp = Experiment::load(&locate(&a.experiment))?;
    let r = fit_report(&exp, &a)?;
    if a.json {
        return Ok(serde_json::to_string_pretty(&r)? + "\n");
    }
    Ok(text(&exp, &r))
}

fn text(exp: &Experiment, r: &FitReport) -> String {
    let f = &r.fit;
    let p = &exp.pendulum;
    let mut o = String::new();
    let _ = writeln!(o, "experiment       {} ({})", exp.name, exp.path.display());
    let _ = writeln!(o, "angles           {}", r.angles.description);
    let _ = writeln!(o, "turning points   {}", f.n_extremes);
    if let Some(r) = &f.release {
        let _ = writeln!(
            o,
            "release          t = {:.3} s, from rest at {:.4} deg: the {} frames before it \
             (held {:.2} s) are not fitted",
            r.t_s,
            r.angle_rad.to_degrees(),
            r.frame,
            r.held_s
        );
    }
    if let Some(s) = &f.stop {
        let _ = writeln!(
            o,
            "stop             t = {:.3} s, where the turning points' envelope reaches zero: \
             the {} extreme(s) after it (the ball at rest) are not fitted",
            s.t_s, s.dropped
        );
    }
    for x in &f.outliers {
        let _ = writeln!(
            o,
            "outlier          t = {:.3} s, residual {:+.4} deg ({:.0} robust SD): {}",
            x.t_s,
            x.residual_rad.to_degrees(),
            x.robust_z,
            if x.dropped {
                "dropped, not fitted"
            } else {
                "kept (beyond the cap)"
            }
        );
    }
    let _ = writeln!(
        o,
        "equilibrium      {:.4} deg (envelope fit); {:.4} deg (Eq. 38-39, mean of extremes)",
        f.psi_eq_rad.to_degrees(),
        f.psi_eq_paper_rad.to_degrees()
    );
    let _ = writeln!(o, "envelope slope a {:.4e} rad/s", f.a_rad_s);
    let _ = writeln!(
        o,
        "s_r              {:.4e} m  (95 % CI {:.4e} .. {:.4e}; beta = {:.4})",
        f.s_r_m, f.s_r_ci95_m[0], f.s_r_ci95_m[1], f.beta
    );
    let _ = writeln!(
        o,
        "  the angles     {:.4e} .. {:.4e} m (95 %: statistics, drift, detector scale; u = {:.3e} m)",
        f.s_r_interval95_m[0], f.s_r_interval95_m[1], f.s_r_u_m
    );
    let _ = writeln!(
        o,
        "  the budget     s_r ± U = {} (geometry's inputs added)",
        crate::report::fmt_expanded(&r.budget)
    );
    if let Some(mc) = &r.monte_carlo {
        let _ = writeln!(
            o,
            "  Monte Carlo    {} draws: u = {:.3e} m ({:.3} of u_c), 95 % {:.4e} .. {:.4e} m",
            mc.draws, mc.u_m, mc.u_ratio, mc.interval95_m[0], mc.interval95_m[1]
        );
    }
    match &f.air {
        Some(a) => {
            let scale = a.drag_scale_se.map_or(String::new(), |se| {
                format!("; drag scale {:.3} +- {:.3}", a.drag_scale, se)
            });
            let _ = writeln!(
                o,
                "  without air    {:.4e} m (the air modelled changes s_r by {:+.3} %; it takes {:.3} % of the energy, Re up to {:.0}{scale})",
                a.s_r_without_air_m, a.correction_pct, a.energy_share_pct, a.reynolds_max
            );
        }
        None => {
            let _ = writeln!(o, "  the air        not modelled (`air.model: none`)");
        }
    }
    if let Some(t) = r.truth_s_r_m {
        let _ = writeln!(
            o,
            "synthetic truth  {:.4e} m  ({:+.3} %)",
            t,
            100.0 * (f.s_r_m - t) / t
        );
    }
    let _ = writeln!(o, "mu_r             {:.4e}", f.mu_r);
    let _ = writeln!(
        o,
        "period           {:.4} s -> d = {:.4} m (geometry says {:.4} m)",
        f.period_s, f.d_from_period_m, p.d
    );
    let _ = writeln!(
        o,
        "normal force     {:.4} N mean, varies {:.4} %",
        f.reactions.n_mean_n, f.reactions.n_variation_pct
    );
    let _ = write!(o, "max |T|/N        {:.3e}", f.max_t_over_n);
    match (r.sliding_mu, r.pure_rolling) {
        (Some(mu), Some(ok)) => {
            let _ = writeln!(
                o,
                "  (mu = {mu}: pure rolling {})",
                if ok { "holds" } else { "FAILS" }
            );
        }
        _ => {
            let _ = writeln!(o, "  (no `sliding.mu` given for Eq. 34)");
        }
    }
    let _ = writeln!(
        o,
        "fit              {} iterations, residual RMS {:.3e} deg",
        f.iterations,
        f.residual_rms_rad.to_degrees()
    );
    for c in &f.beta_comparison {
        let _ = writeln!(
            o,
            "  beta {:.4}: s_r {:.4e}, RSS {:.3e} rad^2, AICc {:.2}",
            c.beta, c.s_r, c.rss, c.aicc
        );
    }
    let aicc = f.beta_comparison.iter().map(|c| c.aicc);
    let spread = aicc.clone().fold(f64::MIN, f64::max) - aicc.fold(f64::MAX, f64::min);
    if !f.beta_comparison.is_empty() && spread < 2.0 {
        let _ = writeln!(
            o,
            "  the exponents fit equally well (AICc within {spread:.2}): N varies only {:.3} %, \
             so this recording cannot determine beta; s_r N_0^beta is what it measures",
            f.reactions.n_variation_pct
        );
    }
    let _ = writeln!(o, "verdict          {}", r.verdict.label());
    for w in &r.verdict.warnings {
        let _ = writeln!(
            o,
            "  {}{}: {}",
            w.check,
            if w.accepted.is_some() {
                " (accepted)"
            } else {
                ""
            },
            w.reason
        );
        if let Some(why) = &w.accepted {
            let _ = writeln!(o, "    accepted because: {why}");
        }
    }
    o
}
