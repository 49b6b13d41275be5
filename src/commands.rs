//! The command-line verbs, as library functions (so that tests call them directly and
//! `main.rs` only parses arguments). Each returns its text output.

use crate::config::{self, Experiment};
use crate::fit::{self, BetaChoice, FitOptions, FitResult};
use crate::fsutil;
use crate::physics::torsion::{torsion_check, TorsionCheck};
use crate::physics::FrictionLaw;
use crate::series::AngleSeries;
use crate::simulate;
use anyhow::{bail, Context, Result};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// Options of `rollfric simulate`.
#[derive(Clone, Debug, Default)]
pub struct SimulateArgs {
    pub fps: Option<f64>,
    pub noise_deg: Option<f64>,
    pub seed: Option<u64>,
    pub duration_s: Option<f64>,
}

/// `rollfric simulate`: write the camera's angle series of the experiment's twin.
pub fn simulate(exp_path: &Path, out: &Path, args: &SimulateArgs) -> Result<String> {
    let exp = Experiment::load(exp_path)?;
    let mut cam = simulate::camera_of(&exp)?;
    if let Some(f) = args.fps {
        if !(f.is_finite() && f > 0.0) {
            bail!("--fps {f}: expected a positive frame rate");
        }
        cam.fps = f;
    }
    if let Some(n) = args.noise_deg {
        if !(n.is_finite() && n >= 0.0) {
            bail!("--noise-deg {n}: expected zero or a positive angle");
        }
        cam.noise_rad = n.to_radians();
    }
    if let Some(d) = args.duration_s {
        if !(d.is_finite() && d > 0.0) {
            bail!("--duration {d}: expected a positive number of seconds");
        }
        cam.duration_s = Some(d);
    }
    cam.seed = args.seed.unwrap_or(cam.seed);
    let rec = simulate::record(&exp, &cam)?;
    fsutil::write_atomic(out, rec.series.to_csv().as_bytes())?;
    Ok(format!(
        "{}: {} frames at {} fps, {} turning points, {}; s_r = {:e} m, noise {:.3} deg -> {}\n",
        exp.name,
        rec.series.len(),
        cam.fps,
        rec.trajectory.turns.len(),
        match rec.trajectory.stopped_at {
            Some(t) => format!("ball stops at {t:.2} s"),
            None => "still moving at the end".into(),
        },
        rec.law.s_r,
        cam.noise_rad.to_degrees(),
        out.display()
    ))
}

/// Where the angles of a fit came from.
#[derive(Clone, Debug, Serialize)]
pub struct AnglesSource {
    /// `csv` or `synthetic`.
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
    #[serde(flatten)]
    pub fit: FitResult,
}

/// Options of `rollfric fit`.
#[derive(Clone, Debug, Default)]
pub struct FitArgs {
    pub angles: Option<std::path::PathBuf>,
    pub beta: Option<String>,
    pub compare_betas: bool,
}

/// Load the angles an experiment is fitted from: an explicit CSV, the file's `angles:`,
/// or else its video (`video.path`, or the digital twin's rendered video), detected now.
pub fn angles_for(
    exp: &Experiment,
    explicit: Option<&Path>,
) -> Result<(AngleSeries, AnglesSource)> {
    let csv = explicit
        .map(Path::to_path_buf)
        .or_else(|| exp.file.angles.as_deref().map(|a| exp.resolve(a)));
    if let Some(path) = csv {
        let s = AngleSeries::read_csv(&path)?;
        return Ok((
            s,
            AnglesSource {
                kind: "csv".into(),
                description: format!("measured angles from {}", path.display()),
            },
        ));
    }
    let video = video_for(exp)?;
    let opts = exp
        .file
        .video
        .as_ref()
        .map(crate::detect::DetectOptions::from_video)
        .unwrap_or_default();
    let d = crate::detect::detect(&video, &opts)?;
    let synthetic = exp.file.synthetic.is_some()
        && exp
            .file
            .video
            .as_ref()
            .and_then(|v| v.path.as_ref())
            .is_none();
    Ok((
        d.series(),
        AnglesSource {
            kind: if synthetic {
                "synthetic-video"
            } else {
                "video"
            }
            .into(),
            description: format!(
                "{}angles detected in {} ({} frames: {} corrected, {} missing)",
                if synthetic {
                    "SYNTHETIC: the digital twin's video; "
                } else {
                    ""
                },
                video.display(),
                d.rows.len(),
                d.count(crate::detect::Status::Corrected),
                d.count(crate::detect::Status::Missing)
            ),
        },
    ))
}

/// Fit one experiment.
pub fn fit_experiment(exp: &Experiment, args: &FitArgs) -> Result<FitReport> {
    let (series, source) = angles_for(exp, args.angles.as_deref())?;
    let beta = match &args.beta {
        Some(b) => config::parse_beta(&config::BetaSpec::Text(b.clone()), "--beta")?,
        None => exp.beta,
    };
    let opts = FitOptions {
        beta,
        compare_betas: args.compare_betas || exp.file.model.compare_betas,
        ..FitOptions::default()
    };
    let what = || match &args.angles {
        Some(p) => format!("{}", p.display()),
        None => format!("{}", exp.path.display()),
    };
    let m = fit::analyze(&exp.pendulum, &series, beta).with_context(what)?;
    let result = fit::fit(&exp.pendulum, &m, &opts)
        .with_context(|| format!("{}: fitting s_r", exp.path.display()))?;
    let mu = exp.file.sliding.as_ref().map(|s| s.mu);
    Ok(FitReport {
        experiment: exp.name.clone(),
        material: exp.material.clone(),
        truth_s_r_m: if source.kind.starts_with("synthetic") {
            exp.synthetic_law().map(|l| l.s_r)
        } else {
            None
        },
        pure_rolling: mu.map(|mu| result.max_t_over_n < mu),
        sliding_mu: mu,
        angles: source,
        fit: result,
    })
}

/// `rollfric fit`: human-readable or JSON.
pub fn fit_cmd(exp_path: &Path, args: &FitArgs, json: bool) -> Result<String> {
    let exp = Experiment::load(exp_path)?;
    let r = fit_experiment(&exp, args)?;
    if json {
        return Ok(serde_json::to_string_pretty(&r)? + "\n");
    }
    let f = &r.fit;
    let p = &exp.pendulum;
    let mut o = String::new();
    let _ = writeln!(o, "experiment       {} ({})", exp.name, exp.path.display());
    let _ = writeln!(o, "angles           {}", r.angles.description);
    let _ = writeln!(o, "turning points   {}", f.n_extremes);
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
    Ok(o)
}

/// `rollfric torsion`: the Appendix A table, with `s_r` from `--s-r`, else the synthetic
/// truth, else the reference value (said which).
pub fn torsion_cmd(exp_path: &Path, s_r: Option<f64>, json: bool) -> Result<String> {
    let exp = Experiment::load(exp_path)?;
    let t = exp
        .file
        .torsion
        .as_ref()
        .with_context(|| format!("{}: no `torsion:` block", exp.path.display()))?;
    let (s_r, from) = match (
        s_r,
        exp.synthetic_law(),
        exp.file.reference.as_ref().and_then(|r| r.s_r_m),
    ) {
        (Some(v), _, _) => (v, "--s-r"),
        (None, Some(l), _) => (l.s_r, "synthetic truth"),
        (None, None, Some(v)) => (v, "reference value"),
        _ => bail!("{}: no s_r to compare with: pass --s-r", exp.path.display()),
    };
    let beta = match exp.beta {
        BetaChoice::Fixed(b) => b,
        BetaChoice::Free => 1.0,
    };
    let c = torsion_check(
        &exp.pendulum,
        &FrictionLaw::new(s_r, beta),
        t.period_s,
        t.wire_length_m,
        t.psi0_max_deg.to_radians(),
    );
    if json {
        return Ok(serde_json::to_string_pretty(&c)? + "\n");
    }
    Ok(torsion_table(&exp.name, &c, from))
}

/// The Appendix A table's rows, label and formatted value (the text table and the
/// report pages both show these).
pub fn torsion_rows(c: &TorsionCheck, s_r_from: &str) -> Vec<(&'static str, String)> {
    vec![
        ("torsion period T", format!("{:.1} s", c.period_s)),
        ("wire length", format!("{:.3} m", c.wire_length_m)),
        (
            "k_t = 4 pi^2 J_z / T^2 (A5)",
            format!("{:.3e} N m/rad", c.k_t_n_m_per_rad),
        ),
        (
            "psi_0 -> phi_0 = psi_0 / sin(delta)",
            format!(
                "{:.1} deg -> {:.3} rad ({:.1} deg)",
                c.psi0_rad.to_degrees(),
                c.phi0_rad,
                c.phi0_rad.to_degrees()
            ),
        ),
        ("M_t,max = k_t phi_0", format!("{:.3e} N m", c.m_t_max_n_m)),
        (
            "M_r = s_r m g",
            format!("{:.3e} N m (s_r from {s_r_from})", c.m_r_n_m),
        ),
        (
            "M_r = s_r N_0^beta (model)",
            format!("{:.3e} N m", c.m_r_model_n_m),
        ),
        ("100 M_t,max / M_r", format!("{:.2} %", c.ratio_pct)),
    ]
}

/// The Appendix A table as text.
pub fn torsion_table(name: &str, c: &TorsionCheck, s_r_from: &str) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "wire torsion, {name} (Appendix A)");
    for (k, v) in torsion_rows(c, s_r_from) {
        let _ = writeln!(o, "  {k:<38} {v}");
    }
    o
}

/// Options of `rollfric detect`.
#[derive(Clone, Debug, Default)]
pub struct DetectArgs {
    pub experiment: Option<std::path::PathBuf>,
    /// Write diagnostic images of flagged frames next to the CSV.
    pub diagnostics: bool,
    /// Decode with OpenCV even when ffmpeg is installed.
    pub opencv: bool,
    /// Override the experiment's region of interest, frame range and pivot.
    pub roi: Option<[u32; 4]>,
    pub frames: Option<[u64; 2]>,
    pub pivot: Option<[f64; 2]>,
}

/// `rollfric detect`: per-frame wire angles of a video, written as CSV.
pub fn detect_cmd(video: &Path, out: &Path, args: &DetectArgs) -> Result<String> {
    use crate::detect::{self, DetectOptions, Status};
    let mut opts = match &args.experiment {
        Some(e) => {
            let exp = Experiment::load(e)?;
            exp.file
                .video
                .as_ref()
                .map(DetectOptions::from_video)
                .unwrap_or_default()
        }
        None => DetectOptions::default(),
    };
    opts.force_opencv = args.opencv;
    if let Some([x, y, w, h]) = args.roi {
        opts.roi = Some(crate::video::Roi { x, y, w, h });
    }
    opts.frames = args.frames.or(opts.frames);
    opts.pivot = args.pivot.or(opts.pivot);
    if args.diagnostics {
        opts.diag_dir = Some(out.with_extension("diag"));
    }
    let started = std::time::Instant::now();
    let d = detect::detect(video, &opts)?;
    let secs = started.elapsed().as_secs_f64();
    fsutil::write_atomic(out, d.to_csv().as_bytes())?;
    let n = d.rows.len();
    Ok(format!(
        "{}: {n} frames in {secs:.2} s ({:.0} frames/s, {}, peak memory {}): {} ok, {} corrected, \
         {} manual, {} missing; pivot ({:.1}, {:.1}) px, {} wire, ROI {:?} -> {}\n",
        video.display(),
        n as f64 / secs,
        d.decoder,
        peak_memory().map_or("?".to_string(), |m| format!("{m:.0} MiB")),
        d.count(Status::Ok),
        d.count(Status::Corrected),
        d.count(Status::Manual),
        d.count(Status::Missing),
        d.pivot_px[0],
        d.pivot_px[1],
        if d.dark_wire { "dark" } else { "light" },
        d.roi,
        out.display()
    ))
}

/// `rollfric synth`: render the experiment's digital-twin video (and its truth CSV).
pub fn synth_cmd(
    exp_path: &Path,
    out: &Path,
    truth: Option<&Path>,
    duration_s: Option<f64>,
) -> Result<String> {
    let exp = Experiment::load(exp_path)?;
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let started = std::time::Instant::now();
    let mut progress = |done: usize, total: usize| {
        if tty {
            eprint!("\rsynth: frame {done}/{total}");
        }
    };
    let r = crate::synth::render(&exp, out, duration_s, &mut progress)?;
    if tty {
        eprintln!();
    }
    if let Some(t) = truth {
        fsutil::write_atomic(t, crate::synth::truth_csv(&r.truth).as_bytes())?;
    }
    let spoiled = r.truth.iter().filter(|t| t.spoiled != "none").count();
    Ok(format!(
        "{}: SYNTHETIC {} frames {}x{} at {} fps, {} ({:?} style, {spoiled} spoiled frames, pivot ({:.1}, {:.1}) px) in {:.1} s -> {}\n",
        exp.name,
        r.frames,
        r.width,
        r.height,
        r.fps,
        r.codec,
        r.style,
        r.pivot_px[0],
        r.pivot_px[1],
        started.elapsed().as_secs_f64(),
        r.path.display()
    ))
}

/// The video of an experiment: its `video.path`, or for a digital twin the rendered
/// file under `build/<name>/` (rendered now when its render key is stale).
pub fn video_for(exp: &Experiment) -> Result<std::path::PathBuf> {
    if let Some(path) = crate::build::lab_video(exp)? {
        return Ok(path);
    }
    crate::build::no_video_unless_twin(exp)?;
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let started = std::time::Instant::now();
    let (video, _, rendered) =
        crate::build::twin(exp, Path::new("build"), &mut |_, done, total| {
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
    Ok(video)
}

/// This process's peak resident memory (Linux `VmHWM`), MiB.
pub fn peak_memory() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let kb: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))?
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    Some(kb / 1024.0)
}
