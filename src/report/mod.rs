//! The reports: per-experiment pages, the index with Table 1 reproduced, `summary.json`,
//! and `rollfric check`.
//!
//! Pages are rendered by tera from the templates in `templates/` (compiled into the
//! binary, so a report never depends on where the tool runs from) in HTML and
//! Markdown. Every number on them is computed here from the inputs; published values
//! appear only in the `reference` columns. Nothing machine-specific is written: paths
//! are relative to the manifest and there are no dates, so the same inputs give the same
//! bytes.

pub mod figures;
pub mod plot;

use crate::build::cache;
use crate::config::{Experiment, Manifest, Reference, Tolerances};
use crate::detect::Detection;
use crate::fit::{self, FitOptions};
use crate::fsutil;
use crate::physics::torsion::{torsion_check, TorsionCheck};
use crate::physics::FrictionLaw;
use crate::series::AngleSeries;
use anyhow::{bail, Context, Result};
use figures::Row;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

/// The templates, compiled in.
const TEMPLATES: &[(&str, &str)] = &[
    ("style.css", include_str!("../../templates/style.css")),
    (
        "index.html",
        include_str!("../../templates/index.html.tera"),
    ),
    ("index.md", include_str!("../../templates/index.md.tera")),
    (
        "experiment.html",
        include_str!("../../templates/experiment.html.tera"),
    ),
    (
        "experiment.md",
        include_str!("../../templates/experiment.md.tera"),
    ),
];

/// Hashes of the inputs, for provenance.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Inputs {
    pub experiment_file: String,
    pub experiment_sha256: String,
    pub angles_sha256: String,
}

/// One flagged frame of a detection.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FlaggedFrame {
    pub frame: u64,
    pub t_s: f64,
    pub status: String,
    pub flag: String,
}

/// What the detector did on one video.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DetectionSummary {
    pub video: String,
    /// SHA-256 of a lab video; the twin's render key for a synthetic one.
    pub video_id: String,
    pub synthetic: bool,
    pub decoder: String,
    pub frames: usize,
    pub ok: usize,
    pub corrected: usize,
    pub manual: usize,
    pub missing: usize,
    pub pivot_px: [f64; 2],
    pub roi: [u32; 4],
    pub dark_wire: bool,
    pub flagged: Vec<FlaggedFrame>,
    pub figure11_frame: u64,
}

/// Derived geometry (Eq. 36, 37 and the model's constants).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GeometryView {
    pub alpha_deg: f64,
    pub h_m: Option<f64>,
    pub l_m: Option<f64>,
    pub d_m: f64,
    pub contact_length_m: f64,
    pub delta_deg: f64,
    pub r_m: f64,
    pub m_kg: f64,
    pub j_z_kg_m2: f64,
    pub n0_n: f64,
    pub g_m_s2: f64,
    pub period_small_angle_s: f64,
}

/// One comparison of a reproduced value with an expected one.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Check {
    /// `s_r`, `mu_r` or `a`.
    pub quantity: String,
    /// `Table 1` (the reference) or `synthetic truth`.
    pub against: String,
    pub value: f64,
    pub expected: f64,
    pub tolerance_rel: f64,
    pub deviation_rel: f64,
    pub pass: bool,
}

impl Check {
    fn new(quantity: &str, against: &str, value: f64, expected: f64, tol: f64) -> Self {
        let dev = (value - expected) / expected;
        Self {
            quantity: quantity.into(),
            against: against.into(),
            value,
            expected,
            tolerance_rel: tol,
            deviation_rel: dev,
            pass: dev.abs() <= tol,
        }
    }

    /// Recompute the verdict from the numbers (a summary's `pass` is not trusted).
    pub fn verdict(&self) -> bool {
        let dev = (self.value - self.expected) / self.expected;
        dev.is_finite() && dev.abs() <= self.tolerance_rel
    }
}

/// A page file the build wrote, with its hash (to know the pages are intact).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PageFile {
    pub path: String,
    pub sha256: String,
}

/// Everything one experiment produced.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ExperimentResult {
    pub name: String,
    pub material: String,
    pub notes: String,
    pub inputs: Inputs,
    /// Whether the angles come from the digital twin (synthetic, not a lab recording).
    pub synthetic: bool,
    pub angles: String,
    pub geometry: GeometryView,
    pub results: fit::FitResult,
    /// The model's `mu_r / a` for this geometry (Fig. 19's analytic line), s.
    pub model_mu_r_per_a_s: f64,
    pub truth_s_r_m: Option<f64>,
    pub reference: Option<Reference>,
    pub tolerances: Tolerances,
    pub checks: Vec<Check>,
    pub sliding_mu: Option<f64>,
    pub pure_rolling: Option<bool>,
    pub torsion: Option<TorsionCheck>,
    pub detection: Option<DetectionSummary>,
    pub pages: Vec<PageFile>,
}

impl ExperimentResult {
    /// One line for the build's log.
    pub fn line(&self) -> String {
        let truth = self
            .truth_s_r_m
            .map(|t| {
                format!(
                    " ({:+.2} % vs synthetic truth)",
                    100.0 * (self.results.s_r_m - t) / t
                )
            })
            .unwrap_or_default();
        format!(
            "s_r = {:.4e} m{truth}, {}",
            self.results.s_r_m,
            if self.checks.iter().all(Check::verdict) {
                "within tolerances"
            } else {
                "MISSES a tolerance"
            }
        )
    }
}

/// An experiment's outcome in a build.
#[derive(Clone, Debug)]
pub enum Outcome {
    Built(Box<ExperimentResult>),
    Failed {
        name: String,
        file: String,
        error: String,
    },
}

/// One experiment in `summary.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Entry {
    pub name: String,
    pub file: String,
    /// `ok` or `failed`.
    pub status: String,
    pub error: Option<String>,
    pub result: Option<ExperimentResult>,
}

impl Entry {
    pub fn failed(&self) -> bool {
        self.result.is_none()
    }

    /// Built and every check within tolerance.
    pub fn passed(&self) -> bool {
        self.result
            .as_ref()
            .is_some_and(|r| r.checks.iter().all(Check::verdict))
    }
}

/// `reports/summary.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    pub title: String,
    pub tool: String,
    pub manifest_sha256: String,
    pub experiments: Vec<Entry>,
}

/// Read an angle CSV with `t_s`, `angle_rad` and optionally `status` (the detector's
/// output, or a measured series).
pub fn read_rows(path: &Path) -> Result<Vec<Row>> {
    let mut rd =
        csv::Reader::from_path(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let h = rd.headers()?.clone();
    let col = |n: &str| h.iter().position(|c| c.trim() == n);
    let (Some(ti), Some(ai)) = (col("t_s"), col("angle_rad")) else {
        bail!("{}: expected columns `t_s` and `angle_rad`", path.display());
    };
    let si = col("status");
    let mut rows = Vec::new();
    for (i, rec) in rd.records().enumerate() {
        let rec = rec.with_context(|| format!("{}: line {}", path.display(), i + 2))?;
        let t_s: f64 = rec.get(ti).unwrap_or("").trim().parse().with_context(|| {
            format!("{}: line {}: `t_s` is not a number", path.display(), i + 2)
        })?;
        let a = rec.get(ai).unwrap_or("").trim();
        let status = si
            .and_then(|s| rec.get(s))
            .unwrap_or("ok")
            .trim()
            .to_string();
        let angle_rad = if a.is_empty() || status == "missing" {
            None
        } else {
            Some(a.parse().with_context(|| {
                format!(
                    "{}: line {}: `angle_rad` is not a number",
                    path.display(),
                    i + 2
                )
            })?)
        };
        rows.push(Row {
            t_s,
            angle_rad,
            status,
        });
    }
    Ok(rows)
}

/// The frame shown as Figure 11 (the detector's choice, kept by its pass).
pub use crate::detect::figure11_frame;

/// Figure 11: the region of interest of frame `frame`, as the detector kept it, with
/// the detected wire line (red), the pivot (cyan) and the region's outline (yellow); PNG.
pub fn figure11(video: &Path, d: &Detection, frame: u64, out: &Path) -> Result<()> {
    let what = || format!("{}: Figure 11 (frame {frame})", video.display());
    if d.figure11.as_ref().map(|f| f.frame) != Some(frame) {
        bail!("{}: the detection did not keep that frame", what());
    }
    let png = crate::detect::figure11_png(d).with_context(what)?;
    fsutil::write_atomic(out, &png)
}

fn fmt_sci(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return "-".into();
    }
    format!("{v:.digits$e}")
}

fn fmt_pct(v: f64) -> String {
    if !v.is_finite() {
        return "-".into();
    }
    format!("{:+.2} %", 100.0 * v)
}

/// Fit, check, draw and write one experiment's pages. `cache_dir` holds the detection's
/// Figure 11; `out` is the reports folder. Returns the result and how many files were
/// rewritten (unchanged ones are left alone).
pub fn analyze_and_write(
    exp: &Experiment,
    angles_csv: &Path,
    detection: Option<DetectionSummary>,
    inputs: Inputs,
    cache_dir: &Path,
    out: &Path,
) -> Result<(ExperimentResult, usize)> {
    let rows = read_rows(angles_csv)?;
    let (t, a): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter_map(|r| r.angle_rad.map(|a| (r.t_s, a)))
        .unzip();
    let series = AngleSeries::new(t, a);
    let p = &exp.pendulum;
    let what = || format!("{}: fitting", exp.path.display());
    let m = fit::analyze(p, &series, exp.beta).with_context(what)?;
    let opts = FitOptions {
        beta: exp.beta,
        compare_betas: exp.file.model.compare_betas,
        ..FitOptions::default()
    };
    let f = fit::fit(p, &m, &opts).with_context(what)?;
    let law = FrictionLaw::new(f.s_r_m, f.beta);
    let synthetic = detection.as_ref().is_some_and(|d| d.synthetic);
    let truth = synthetic
        .then(|| exp.synthetic_law().map(|l| l.s_r))
        .flatten();
    let tol = exp.file.tolerances.clone();
    let mut checks = Vec::new();
    if let Some(r) = &exp.file.reference {
        let src = if r.source.is_empty() {
            "reference"
        } else {
            &r.source
        };
        if let Some(v) = r.s_r_m {
            checks.push(Check::new("s_r", src, f.s_r_m, v, tol.reference_rel));
        }
        if let Some(v) = r.mu_r {
            checks.push(Check::new("mu_r", src, f.mu_r, v, tol.reference_rel));
        }
        if let Some(v) = r.a_rad_s {
            checks.push(Check::new("a", src, f.a_rad_s, v, tol.reference_rel));
        }
    }
    if let Some(v) = truth {
        checks.push(Check::new(
            "s_r",
            "synthetic truth",
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
    let inc = &exp.file.geometry.incline;
    let geometry = GeometryView {
        alpha_deg: p.alpha.to_degrees(),
        h_m: inc.h_m,
        l_m: inc.l_m,
        d_m: p.d,
        contact_length_m: p.l,
        delta_deg: p.delta.to_degrees(),
        r_m: p.r,
        m_kg: p.m,
        j_z_kg_m2: p.j_z,
        n0_n: p.rest_normal_force(),
        g_m_s2: p.g,
        period_small_angle_s: p.small_angle_period(),
    };
    // Figure 16 shows s_r changed by the larger of 15 % and three times the CI.
    let ci_rel = (f.s_r_ci95_m[1] - f.s_r_m) / f.s_r_m;
    let figs = figures::experiment_figures(&figures::Inputs {
        name: &exp.name,
        rows: &rows,
        m: &m,
        p,
        law,
        a_start: f.a_start_rad,
        delta_rel: (3.0 * ci_rel).max(0.15),
        mu,
    })?;
    let mut result = ExperimentResult {
        name: exp.name.clone(),
        material: exp.material.clone(),
        notes: exp.file.notes.clone(),
        inputs,
        synthetic,
        angles: match &detection {
            Some(d) if d.synthetic => format!(
                "SYNTHETIC: detected in the digital twin's rendered video {}",
                d.video
            ),
            Some(d) => format!("detected in the video {}", d.video),
            None => format!(
                "measured angle CSV {}",
                exp.file.angles.clone().unwrap_or_default()
            ),
        },
        geometry,
        // mu_r = s_r / r with s_r = r: the analytic a of mu_r = 1.
        model_mu_r_per_a_s: 1.0 / p.envelope_slope(&FrictionLaw::new(p.r, 1.0)),
        results: f.clone(),
        truth_s_r_m: truth,
        reference: exp.file.reference.clone(),
        tolerances: tol,
        checks,
        sliding_mu: mu,
        pure_rolling: mu.map(|mu| f.max_t_over_n < mu),
        torsion,
        detection,
        pages: Vec::new(),
    };
    // Files: figures under <name>/, then the two pages.
    let mut files: Vec<(String, Vec<u8>)> = figs
        .into_iter()
        .map(|fg| (format!("{}/{}", exp.name, fg.file), fg.svg.into_bytes()))
        .collect();
    let fig11 = cache_dir.join("fig11.png");
    let has_fig11 = result.detection.is_some() && fig11.exists();
    if has_fig11 {
        files.push((format!("{}/fig11.png", exp.name), std::fs::read(&fig11)?));
    }
    let view = experiment_view(&result, &m, has_fig11);
    let tera = templates()?;
    let ctx = tera::Context::from_serialize(&view)?;
    files.push((
        format!("{}.html", exp.name),
        tera.render("experiment.html", &ctx)?.into_bytes(),
    ));
    files.push((
        format!("{}.md", exp.name),
        tera.render("experiment.md", &ctx)?.into_bytes(),
    ));
    let mut written = 0;
    for (rel, bytes) in &files {
        written += usize::from(fsutil::write_if_changed(&out.join(rel), bytes)?);
        result.pages.push(PageFile {
            path: rel.clone(),
            sha256: cache::sha256(bytes),
        });
    }
    Ok((result, written))
}

/// Whether every page file of a cached result is in `out` with its recorded bytes.
pub fn pages_intact(out: &Path, r: &ExperimentResult) -> bool {
    !r.pages.is_empty()
        && r.pages
            .iter()
            .all(|f| std::fs::read(out.join(&f.path)).is_ok_and(|b| cache::sha256(&b) == f.sha256))
}

fn templates() -> Result<tera::Tera> {
    let mut t = tera::Tera::default();
    t.add_raw_templates(TEMPLATES.iter().copied())
        .context("templates")?;
    t.autoescape_on(vec![".html"]);
    Ok(t)
}

/// Key-value rows of a page's tables (already formatted).
#[derive(Serialize)]
struct Kv {
    k: String,
    v: String,
}

fn kv(k: &str, v: String) -> Kv {
    Kv { k: k.into(), v }
}

#[derive(Serialize)]
struct ExperimentView {
    name: String,
    material: String,
    notes: String,
    synthetic: bool,
    angles: String,
    tool: &'static str,
    inputs: Vec<Kv>,
    geometry: Vec<Kv>,
    detection: Vec<Kv>,
    flagged: Vec<Kv>,
    flagged_more: usize,
    has_detection: bool,
    has_fig11: bool,
    fit: Vec<Kv>,
    checks: Vec<CheckView>,
    extremes: Vec<ExtremeView>,
    torsion: Vec<Kv>,
    rolling: String,
    pass: bool,
}

#[derive(Serialize)]
struct CheckView {
    quantity: String,
    against: String,
    value: String,
    expected: String,
    deviation: String,
    tolerance: String,
    pass: bool,
}

#[derive(Serialize)]
struct ExtremeView {
    k: usize,
    t: String,
    angle: String,
    amplitude: String,
    residual: String,
}

fn check_view(c: &Check) -> CheckView {
    CheckView {
        quantity: c.quantity.clone(),
        against: c.against.clone(),
        value: fmt_sci(c.value, 4),
        expected: fmt_sci(c.expected, 4),
        deviation: fmt_pct(c.deviation_rel),
        tolerance: format!("{:.1} %", 100.0 * c.tolerance_rel),
        pass: c.verdict(),
    }
}

fn experiment_view(r: &ExperimentResult, m: &fit::Measurement, has_fig11: bool) -> ExperimentView {
    let g = &r.geometry;
    let f = &r.results;
    let mut geometry = Vec::new();
    if let (Some(h), Some(l)) = (g.h_m, g.l_m) {
        geometry.push(kv(
            "inclination alpha = asin(h / l) (Eq. 36)",
            format!("asin({h} / {l}) = {:.4} deg", g.alpha_deg),
        ));
    } else {
        geometry.push(kv("inclination alpha", format!("{:.4} deg", g.alpha_deg)));
    }
    geometry.extend([
        kv(
            "pendulum length d (fulcrum to ball centre)",
            format!("{:.4} m", g.d_m),
        ),
        kv(
            "L = sqrt(d^2 - r^2), fulcrum to contact (Eq. 37)",
            format!("{:.4} m", g.contact_length_m),
        ),
        kv("delta = asin(r / d)", format!("{:.3} deg", g.delta_deg)),
        kv("ball radius r", format!("{:.5} m", g.r_m)),
        kv("ball mass m", format!("{:.4} kg", g.m_kg)),
        kv("J_z = 2/5 m r^2", format!("{:.4e} kg m^2", g.j_z_kg_m2)),
        kv(
            "normal force at rest N_0 = m g cos(alpha)",
            format!("{:.4} N", g.n0_n),
        ),
        kv(
            "small-angle period (model)",
            format!("{:.4} s", g.period_small_angle_s),
        ),
    ]);
    let mut detection = Vec::new();
    let mut flagged = Vec::new();
    let mut flagged_more = 0;
    if let Some(d) = &r.detection {
        detection.extend([
            kv("video", d.video.clone()),
            kv("decoder", d.decoder.clone()),
            kv("frames", d.frames.to_string()),
            kv(
                "ok / corrected / manual / missing",
                format!("{} / {} / {} / {}", d.ok, d.corrected, d.manual, d.missing),
            ),
            kv(
                "pivot",
                format!("({:.1}, {:.1}) px", d.pivot_px[0], d.pivot_px[1]),
            ),
            kv("region of interest [x, y, w, h]", format!("{:?} px", d.roi)),
            kv(
                "wire",
                if d.dark_wire {
                    "darker than the background"
                } else {
                    "lighter than the background"
                }
                .into(),
            ),
            kv("Figure 11 frame", d.figure11_frame.to_string()),
        ]);
        const SHOW: usize = 40;
        for fl in d.flagged.iter().take(SHOW) {
            flagged.push(kv(
                &format!("frame {} (t = {:.3} s)", fl.frame, fl.t_s),
                format!("{}: {}", fl.status, fl.flag),
            ));
        }
        flagged_more = d.flagged.len().saturating_sub(SHOW);
    }
    let mut fit = vec![
        kv("turning points", f.n_extremes.to_string()),
        kv(
            "equilibrium, envelope fit / Eq. 38-39",
            format!(
                "{:.4} deg / {:.4} deg",
                f.psi_eq_rad.to_degrees(),
                f.psi_eq_paper_rad.to_degrees()
            ),
        ),
        kv(
            "envelope slope a (measured)",
            format!("{:.4e} rad/s", f.a_rad_s),
        ),
        kv(
            "envelope slope of the fitted model",
            format!("{:.4e} rad/s", f.a_model_rad_s),
        ),
        kv(
            "s_r (95 % CI)",
            format!(
                "{:.4e} m ({:.4e} .. {:.4e})",
                f.s_r_m, f.s_r_ci95_m[0], f.s_r_ci95_m[1]
            ),
        ),
        kv("beta", figures::trim(f.beta)),
        kv("mu_r = s_r N_0^(beta-1) / r", format!("{:.4e}", f.mu_r)),
        kv(
            "residual RMS of the amplitudes",
            format!("{:.4} deg", f.residual_rms_rad.to_degrees()),
        ),
        kv("Gauss-Newton iterations", f.iterations.to_string()),
        kv(
            "period measured -> d (cross-check)",
            format!(
                "{:.4} s -> {:.4} m (geometry: {:.4} m, {:+.2} %)",
                f.period_s,
                f.d_from_period_m,
                g.d_m,
                100.0 * (f.d_from_period_m - g.d_m) / g.d_m
            ),
        ),
        kv(
            "normal force min / mean / max (Eq. 30)",
            format!(
                "{:.5} / {:.5} / {:.5} N ({:.4} %)",
                f.reactions.n_min_n,
                f.reactions.n_mean_n,
                f.reactions.n_max_n,
                f.reactions.n_variation_pct
            ),
        ),
        kv("max |T|/N (Eq. 31, 34)", format!("{:.3e}", f.max_t_over_n)),
    ];
    if let Some(t) = r.truth_s_r_m {
        fit.push(kv(
            "synthetic truth s_r",
            format!("{t:.4e} m ({})", fmt_pct((f.s_r_m - t) / t)),
        ));
    }
    for c in &f.beta_comparison {
        fit.push(kv(
            &format!("beta = {}", figures::trim(c.beta)),
            format!(
                "s_r {:.4e}, RSS {:.3e} rad^2, AICc {:.2}",
                c.s_r, c.rss, c.aicc
            ),
        ));
    }
    let extremes = m
        .extremes
        .iter()
        .enumerate()
        .map(|(k, e)| ExtremeView {
            k,
            t: format!("{:.3}", e.t),
            angle: format!("{:.4}", e.angle.to_degrees()),
            amplitude: format!("{:.4}", m.amplitudes[k].to_degrees()),
            residual: f
                .residuals_rad
                .get(k)
                .map_or("-".into(), |v| format!("{:+.4}", v.to_degrees())),
        })
        .collect();
    let torsion = r.torsion.map(torsion_rows).unwrap_or_default();
    let rolling = match (r.sliding_mu, r.pure_rolling) {
        (Some(mu), Some(true)) => format!(
            "Pure rolling holds: max |T|/N = {:.3e} < mu = {mu} (Eq. 34), {:.0} times smaller.",
            f.max_t_over_n,
            mu / f.max_t_over_n
        ),
        (Some(mu), _) => format!(
            "Pure rolling FAILS: max |T|/N = {:.3e} >= mu = {mu} (Eq. 34).",
            f.max_t_over_n
        ),
        _ => "No sliding coefficient given: Eq. 34 not checked.".into(),
    };
    ExperimentView {
        name: r.name.clone(),
        material: r.material.clone(),
        notes: r.notes.clone(),
        synthetic: r.synthetic,
        angles: r.angles.clone(),
        tool: cache::TOOL,
        inputs: vec![
            kv("experiment file", r.inputs.experiment_file.clone()),
            kv("experiment SHA-256", r.inputs.experiment_sha256.clone()),
            kv("angles SHA-256", r.inputs.angles_sha256.clone()),
        ],
        geometry,
        has_detection: r.detection.is_some(),
        detection,
        flagged,
        flagged_more,
        has_fig11,
        fit,
        checks: r.checks.iter().map(check_view).collect(),
        extremes,
        torsion,
        rolling,
        pass: r.checks.iter().all(Check::verdict),
    }
}

fn torsion_rows(c: TorsionCheck) -> Vec<Kv> {
    crate::commands::torsion_rows(&c, "the fit")
        .into_iter()
        .map(|(k, v)| kv(k, v))
        .collect()
}

#[derive(Serialize)]
struct IndexView {
    title: String,
    tool: &'static str,
    manifest_sha256: String,
    rows: Vec<TableRow>,
    failures: Vec<Kv>,
    torsion: Vec<TorsionRow>,
    provenance: Vec<Kv>,
    synthetic: Vec<String>,
    measured: Vec<String>,
    fig19: bool,
    fig2: bool,
    fig2_note: String,
    passed: usize,
    total: usize,
}

#[derive(Serialize)]
struct TableRow {
    name: String,
    material: String,
    synthetic: bool,
    s_r: String,
    s_r_paper: String,
    s_r_dev: String,
    mu_r: String,
    mu_r_paper: String,
    mu_r_dev: String,
    a: String,
    a_paper: String,
    a_dev: String,
    truth_dev: String,
    pass: bool,
}

#[derive(Serialize)]
struct TorsionRow {
    material: String,
    k_t: String,
    m_t: String,
    m_r: String,
    ratio: String,
}

/// Write the index pages, its figures and `summary.json` from the experiments'
/// outcomes. Returns the summary and how many files were rewritten.
pub fn write_index(
    out: &Path,
    manifest: &Manifest,
    outcomes: Vec<Outcome>,
) -> Result<(Summary, usize)> {
    let manifest_sha256 = cache::sha256(
        serde_json::to_string(manifest)
            .unwrap_or_default()
            .as_bytes(),
    );
    let entries: Vec<Entry> = outcomes
        .into_iter()
        .map(|o| match o {
            Outcome::Built(r) => Entry {
                name: r.name.clone(),
                file: r.inputs.experiment_file.clone(),
                status: "ok".into(),
                error: None,
                result: Some(*r),
            },
            Outcome::Failed { name, file, error } => Entry {
                name,
                file,
                status: "failed".into(),
                error: Some(error),
                result: None,
            },
        })
        .collect();
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let mut torsion = Vec::new();
    let mut provenance = Vec::new();
    let (mut synthetic, mut measured) = (Vec::new(), Vec::new());
    let mut f19 = Vec::new();
    for e in &entries {
        let Some(r) = &e.result else {
            failures.push(kv(&e.name, e.error.clone().unwrap_or_default()));
            provenance.push(kv(&e.file, "failed: no output".into()));
            continue;
        };
        let find = |q: &str| {
            r.checks
                .iter()
                .find(|c| c.quantity == q && c.against != "synthetic truth")
        };
        let paper = |q: &str| find(q).map_or("-".into(), |c| fmt_sci(c.expected, 3));
        let dev = |q: &str| find(q).map_or("-".into(), |c| fmt_pct(c.deviation_rel));
        let truth = r
            .checks
            .iter()
            .find(|c| c.against == "synthetic truth")
            .map_or("-".into(), |c| fmt_pct(c.deviation_rel));
        let f = &r.results;
        rows.push(TableRow {
            name: r.name.clone(),
            material: r.material.clone(),
            synthetic: r.synthetic,
            s_r: fmt_sci(f.s_r_m, 3),
            s_r_paper: paper("s_r"),
            s_r_dev: dev("s_r"),
            mu_r: fmt_sci(f.mu_r, 3),
            mu_r_paper: paper("mu_r"),
            mu_r_dev: dev("mu_r"),
            a: fmt_sci(f.a_rad_s, 3),
            a_paper: paper("a"),
            a_dev: dev("a"),
            truth_dev: truth,
            pass: r.checks.iter().all(Check::verdict),
        });
        if let Some(c) = r.torsion {
            torsion.push(TorsionRow {
                material: r.material.clone(),
                k_t: fmt_sci(c.k_t_n_m_per_rad, 3),
                m_t: fmt_sci(c.m_t_max_n_m, 3),
                m_r: fmt_sci(c.m_r_model_n_m, 3),
                ratio: format!("{:.2} %", c.ratio_pct),
            });
        }
        let mut p = format!("experiment {}", r.inputs.experiment_sha256);
        let _ = write!(p, "; angles {}", r.inputs.angles_sha256);
        if let Some(d) = &r.detection {
            let _ = write!(
                p,
                "; video {} {}",
                if d.synthetic { "render key" } else { "SHA-256" },
                d.video_id
            );
        }
        provenance.push(kv(&r.inputs.experiment_file, p));
        if r.synthetic {
            synthetic.push(r.material.clone());
        } else {
            measured.push(r.material.clone());
        }
        f19.push(figures::Fig19Point {
            label: r.material.clone(),
            a_rad_s: f.a_rad_s,
            mu_r: f.mu_r,
            model_ratio: r.model_mu_r_per_a_s,
            d_m: r.geometry.d_m,
        });
    }
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    if !f19.is_empty() {
        files.push((
            "fig19.svg".into(),
            figures::figure19(&f19)?.svg.into_bytes(),
        ));
    }
    // Figure 2 on the first built experiment's pendulum and fitted s_r.
    let mut fig2_note = String::new();
    if let Some(r) = entries.iter().find_map(|e| e.result.as_ref()) {
        let g = &r.geometry;
        let p = crate::physics::Pendulum::new(
            g.r_m,
            g.m_kg,
            g.j_z_kg_m2,
            g.d_m,
            g.alpha_deg.to_radians(),
            g.g_m_s2,
        )?;
        for fg in figures::figure2(&p, r.results.s_r_m, 10f64.to_radians())? {
            files.push((fg.file, fg.svg.into_bytes()));
        }
        fig2_note = format!(
            "{} pendulum (d = {:.4} m), released at 10 deg; s_r = {:.3e} m for beta = 1, and the s_r giving the same torque at rest for beta = 3/2.",
            r.material, g.d_m, r.results.s_r_m
        );
    }
    let summary = Summary {
        title: manifest.title.clone(),
        tool: cache::TOOL.into(),
        manifest_sha256: manifest_sha256.clone(),
        experiments: entries,
    };
    let view = IndexView {
        title: manifest.title.clone(),
        tool: cache::TOOL,
        manifest_sha256,
        passed: summary.experiments.iter().filter(|e| e.passed()).count(),
        total: summary.experiments.len(),
        rows,
        failures,
        torsion,
        provenance,
        synthetic,
        measured,
        fig19: !f19.is_empty(),
        fig2: !fig2_note.is_empty(),
        fig2_note,
    };
    let tera = templates()?;
    let ctx = tera::Context::from_serialize(&view)?;
    files.push((
        "index.html".into(),
        tera.render("index.html", &ctx)?.into_bytes(),
    ));
    files.push((
        "index.md".into(),
        tera.render("index.md", &ctx)?.into_bytes(),
    ));
    files.push((
        "summary.json".into(),
        (serde_json::to_string_pretty(&summary)? + "\n").into_bytes(),
    ));
    let mut written = 0;
    for (rel, bytes) in &files {
        written += usize::from(fsutil::write_if_changed(&out.join(rel), bytes)?);
    }
    Ok((summary, written))
}

/// `rollfric check`: the reproduced values of a summary against their expected values
/// and tolerances (recomputed from the numbers). Returns the table and whether all pass.
pub fn check(summary_path: &Path) -> Result<(String, bool)> {
    let text = fsutil::read_to_string(summary_path)?;
    let s: Summary = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a rollfric summary", summary_path.display()))?;
    if s.experiments.is_empty() {
        bail!(
            "{}: the summary lists no experiment",
            summary_path.display()
        );
    }
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{:<22} {:<6} {:<16} {:>11} {:>11} {:>9} {:>7}  verdict",
        "experiment", "value", "against", "reproduced", "expected", "dev", "tol"
    );
    let mut ok = true;
    for e in &s.experiments {
        let Some(r) = &e.result else {
            ok = false;
            let _ = writeln!(
                o,
                "{:<22} FAILED: {}",
                e.name,
                e.error.as_deref().unwrap_or("no result")
            );
            continue;
        };
        if r.checks.is_empty() {
            let _ = writeln!(o, "{:<22} (no expected values)", e.name);
        }
        for c in &r.checks {
            let pass = c.verdict();
            ok &= pass;
            let _ = writeln!(
                o,
                "{:<22} {:<6} {:<16} {:>11} {:>11} {:>9} {:>6.1}%  {}",
                e.name,
                c.quantity,
                c.against,
                fmt_sci(c.value, 4),
                fmt_sci(c.expected, 4),
                fmt_pct((c.value - c.expected) / c.expected),
                100.0 * c.tolerance_rel,
                if pass { "pass" } else { "MISS" }
            );
        }
    }
    let n = s.experiments.len();
    let good = s.experiments.iter().filter(|e| e.passed()).count();
    let _ = writeln!(o, "{good}/{n} experiments within their tolerances");
    Ok((o, ok))
}
