//! `rollfric build`: the manifest's experiments through synth -> detect -> fit ->
//! torsion -> figures -> pages, each stage cached under a key hashed from its inputs,
//! experiments in parallel, one failure stopping only its own experiment.
//!
//! Cache layout, under `--cache` (default `build/`), one folder per experiment:
//!
//! | stage    | outputs                                   | key covers |
//! |----------|-------------------------------------------|------------|
//! | synth    | `twin.avi`                                | geometry, model, `synthetic:`, renderer source |
//! | detect   | `angles.csv`, `detect.json`, `fig11.png`  | the video's id, `video:` settings, detector source |
//! | analysis | `result.json` and the experiment's pages  | the YAML's bytes, the angles' bytes, detection summary, analysis and report source |
//!
//! Every file is written to a temporary name and renamed; a stage's key is written
//! last, so a build killed at any moment leaves old or new files, never torn ones, and
//! the next build reruns exactly the stages whose keys are missing or stale.

pub mod cache;
pub mod progress;

use crate::config::{Experiment, Manifest};
use crate::detect::{self, DetectOptions, FrameProgress};
use crate::fsutil;
use crate::report::{self, DetectionSummary, ExperimentResult, FlaggedFrame, Outcome};
use anyhow::{bail, Context, Result};
use cache::Key;
use progress::Progress;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Options of `rollfric build`.
#[derive(Clone, Debug)]
pub struct BuildOptions {
    pub manifest: PathBuf,
    /// Where the reports go.
    pub out: PathBuf,
    /// Where the stages' cached outputs go.
    pub cache: PathBuf,
    /// Experiments built at once (default: the number of cores).
    pub jobs: Option<usize>,
    /// No progress output.
    pub quiet: bool,
}

/// What a build did.
pub struct BuildOutcome {
    pub summary: report::Summary,
    /// Experiments that failed (they are in the summary with their error).
    pub failed: usize,
    /// Experiments whose values miss their tolerances.
    pub missed: usize,
    pub seconds: f64,
    /// Report files rewritten (unchanged files are left alone).
    pub written: usize,
}

/// Source of each stage, part of its key: a change to the code that produces an output
/// invalidates that output (the version alone would not, between releases).
const SYNTH_SOURCE: &[&str] = &[include_str!("../synth.rs")];
const DETECT_SOURCE: &[&str] = &[
    include_str!("../detect/mod.rs"),
    include_str!("../detect/geometry.rs"),
    include_str!("../detect/geometry/pivot.rs"),
    include_str!("../detect/figure11.rs"),
    include_str!("../detect/fill.rs"),
    include_str!("../detect/input.rs"),
    include_str!("../detect/line.rs"),
    include_str!("../detect/options.rs"),
    include_str!("../detect/repeats.rs"),
    include_str!("../detect/row.rs"),
    include_str!("../detect/track.rs"),
    include_str!("../detect/track/diag.rs"),
    include_str!("../detect/track/measure.rs"),
    include_str!("../video.rs"),
];
const ANALYSIS_SOURCE: &[&str] = &[
    include_str!("../fit.rs"),
    include_str!("../signal.rs"),
    include_str!("../physics/mod.rs"),
    include_str!("../physics/ode.rs"),
    include_str!("../physics/torsion.rs"),
    include_str!("../config.rs"),
    include_str!("../series.rs"),
    include_str!("../report/mod.rs"),
    include_str!("../report/figures.rs"),
    include_str!("../report/plot.rs"),
    include_str!("../../templates/experiment.html.tera"),
    include_str!("../../templates/experiment.md.tera"),
    include_str!("../../templates/style.css"),
];

fn with_source(mut k: Key, src: &[&str]) -> Key {
    for s in src {
        k = k.part("source", s.as_bytes());
    }
    k
}

/// Run the build.
pub fn build(opts: &BuildOptions) -> Result<BuildOutcome> {
    let started = Instant::now();
    let (manifest, files) = Manifest::load(&opts.manifest)?;
    let root = opts
        .manifest
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    remove_stale_temporaries(&opts.out, 2);
    remove_stale_temporaries(&opts.cache, 2);
    let progress = Arc::new(Progress::new(files.len(), opts.quiet));
    let jobs = opts
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()))
        .clamp(1, files.len().max(1));
    // Longest first, so that the slowest experiment does not start last.
    let mut order: Vec<usize> = (0..files.len()).collect();
    let cost: Vec<f64> = files.iter().map(|f| estimated_cost(f)).collect();
    order.sort_by(|&a, &b| cost[b].total_cmp(&cost[a]).then(a.cmp(&b)));
    let queue = Mutex::new(order.into_iter());
    let written = std::sync::atomic::AtomicUsize::new(0);
    let outcomes: Mutex<Vec<Option<Outcome>>> = Mutex::new(vec![None; files.len()]);
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| loop {
                let next = queue.lock().unwrap_or_else(|e| e.into_inner()).next();
                let Some(i) = next else { break };
                let file = &files[i];
                let label = display_name(file);
                let t0 = Instant::now();
                let ctx = Ctx {
                    root: &root,
                    out: &opts.out,
                    cache: &opts.cache,
                    progress: &progress,
                    label: label.clone(),
                    written: &written,
                };
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run_experiment(file, &ctx)
                }))
                .unwrap_or_else(|_| Err(anyhow::anyhow!("internal error (panic)")));
                let secs = t0.elapsed().as_secs_f64();
                let outcome = match r {
                    Ok((res, how)) => {
                        progress.finish(&label, &format!("{how} in {secs:.1} s: {}", res.line()));
                        Outcome::Built(Box::new(res))
                    }
                    Err(e) => {
                        let msg = format!("{e:#}");
                        progress.finish(&label, &format!("FAILED: {msg}"));
                        Outcome::Failed {
                            name: label.clone(),
                            file: relative(&root, file),
                            error: msg,
                        }
                    }
                };
                outcomes.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(outcome);
            });
        }
    });
    progress.clear();
    let outcomes: Vec<Outcome> = outcomes
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .map(|o| o.expect("every experiment ran"))
        .collect();
    let (summary, index_written) = report::write_index(&opts.out, &manifest, outcomes)?;
    let written = written.into_inner() + index_written;
    let failed = summary.experiments.iter().filter(|e| e.failed()).count();
    let missed = summary
        .experiments
        .iter()
        .filter(|e| !e.failed() && !e.passed())
        .count();
    Ok(BuildOutcome {
        summary,
        failed,
        missed,
        seconds: started.elapsed().as_secs_f64(),
        written,
    })
}

/// Remove the temporary files a killed build left (`.<name>.tmp<pid>[.<ext>]`, as
/// [`fsutil::write_atomic`] and the renderer name them), `depth` folders deep.
fn remove_stale_temporaries(dir: &Path, depth: usize) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if p.is_dir() {
            if depth > 1 {
                remove_stale_temporaries(&p, depth - 1);
            }
        } else if name.starts_with('.') && name.contains(".tmp") {
            let _ = std::fs::remove_file(&p);
        }
    }
}

/// What every stage of one experiment needs.
struct Ctx<'a> {
    root: &'a Path,
    out: &'a Path,
    cache: &'a Path,
    progress: &'a Arc<Progress>,
    label: String,
    /// Report files rewritten so far.
    written: &'a std::sync::atomic::AtomicUsize,
}

fn display_name(file: &Path) -> String {
    file.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| file.display().to_string())
}

/// A path as the reports show it: relative to the manifest's folder when inside it,
/// else its file name (no absolute paths in the reports).
pub fn relative(root: &Path, p: &Path) -> String {
    let abs = |q: &Path| std::fs::canonicalize(q).unwrap_or_else(|_| q.to_path_buf());
    let (r, a) = (abs(root), abs(p));
    match a.strip_prefix(&r) {
        Ok(rel) => rel.display().to_string(),
        Err(_) => pathdiff(&r, &a).unwrap_or_else(|| {
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        }),
    }
}

/// `a` relative to `base` with `..` steps, when they share a first component.
fn pathdiff(base: &Path, a: &Path) -> Option<String> {
    let b: Vec<_> = base.components().collect();
    let t: Vec<_> = a.components().collect();
    let common = b.iter().zip(&t).take_while(|(x, y)| x == y).count();
    if common <= 1 {
        return None;
    }
    let mut s: Vec<String> = vec!["..".into(); b.len() - common];
    s.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    Some(s.join("/"))
}

/// Rough cost of an experiment (frames to render and detect), for ordering only.
fn estimated_cost(file: &Path) -> f64 {
    let Ok(exp) = Experiment::load(file) else {
        return 0.0;
    };
    match &exp.file.synthetic {
        Some(s) => {
            // Until the ball stops: the release amplitude over the closed-form
            // envelope slope (ERRATA §2).
            let secs = s.duration_s.unwrap_or_else(|| {
                let a = exp
                    .synthetic_law()
                    .map_or(0.0, |l| exp.pendulum.envelope_slope(&l));
                if a > 0.0 {
                    (s.psi0_deg.to_radians() / a).min(120.0)
                } else {
                    120.0
                }
            });
            secs * s.fps * s.width as f64 * s.height as f64
        }
        None => 1e12,
    }
}

/// One experiment through every stage. Returns its result and how it was obtained.
fn run_experiment(file: &Path, ctx: &Ctx) -> Result<(ExperimentResult, String)> {
    let yaml = std::fs::read(file).with_context(|| format!("{}: cannot read", file.display()))?;
    let exp = Experiment::parse(file, &String::from_utf8_lossy(&yaml))
        .with_context(|| file.display().to_string())?;
    let dir = ctx.cache.join(&exp.name);
    let mut ran = Vec::new();

    // Angles: a measured CSV, or a video (the lab's, or the twin rendered here).
    let (angles_csv, angles_id, detection) = if let Some(a) = &exp.file.angles {
        let p = exp.resolve(a);
        let id = cache::sha256_file(&p)
            .with_context(|| format!("{}: `angles` = {a}", exp.path.display()))?;
        (p, id, None)
    } else {
        let (video, video_id, synthetic) = video_stage(&exp, ctx, &mut ran)?;
        let (csv, det, key) =
            detect_stage(&exp, &dir, &video, &video_id, synthetic, ctx, &mut ran)?;
        (csv, key, Some(det))
    };

    // Analysis and pages.
    let key = with_source(Key::new("analysis"), ANALYSIS_SOURCE)
        .part("yaml", &yaml)
        .part("angles", angles_id.as_bytes())
        .hex();
    let result_file = dir.join("result.json");
    let key_file = dir.join("analysis.key");
    if cache::fresh(&key_file, &key, &[&result_file]) {
        let cached: Option<ExperimentResult> = std::fs::read(&result_file)
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok());
        if let Some(r) = cached.filter(|r| report::pages_intact(ctx.out, r)) {
            let how = if ran.is_empty() {
                "cached".to_string()
            } else {
                format!("{} ran", ran.join(", "))
            };
            return Ok((r, how));
        }
    }
    ctx.progress
        .stage(&ctx.label, "analysis", "fit, torsion, figures, pages");
    let inputs = report::Inputs {
        experiment_file: relative(ctx.root, file),
        experiment_sha256: cache::sha256(&yaml),
        angles_sha256: cache::sha256_file(&angles_csv)?,
    };
    let (result, written) =
        report::analyze_and_write(&exp, &angles_csv, detection, inputs, &dir, ctx.out)?;
    ctx.written
        .fetch_add(written, std::sync::atomic::Ordering::Relaxed);
    fsutil::write_atomic(&result_file, &serde_json::to_vec_pretty(&result)?)?;
    cache::record(&key_file, &key)?;
    ran.push("analysis");
    Ok((result, format!("{} ran", ran.join(", "))))
}

/// The video to detect: `video.path`, or the twin (rendered when stale). Returns the
/// path, an id of its content for the detect key, and whether it is synthetic.
fn video_stage(
    exp: &Experiment,
    ctx: &Ctx,
    ran: &mut Vec<&'static str>,
) -> Result<(PathBuf, String, bool)> {
    if let Some(path) = lab_video(exp)? {
        ctx.progress.stage(&ctx.label, "video", "hashing");
        let id = cache::sha256_file(&path)?;
        return Ok((path, id, false));
    }
    no_video_unless_twin(exp)?;
    let label = ctx.label.clone();
    let progress = ctx.progress.clone();
    let (video, key, rendered) = twin(exp, ctx.cache, &mut |stage, done, total| {
        if done == 0 {
            progress.stage(&label, stage, "rendering the digital twin's video");
        }
        progress.frames(&label, done, Some(total));
    })?;
    if rendered {
        ran.push("synth");
    }
    Ok((video, key, true))
}

/// The experiment's recording (`video.path`), if it names one; an error when the file
/// is not there.
pub fn lab_video(exp: &Experiment) -> Result<Option<PathBuf>> {
    let Some(p) = exp.file.video.as_ref().and_then(|v| v.path.as_deref()) else {
        return Ok(None);
    };
    let path = exp.resolve(p);
    if !path.is_file() {
        bail!(
            "{}: `video.path` = {p}: the video does not exist ({})",
            exp.path.display(),
            path.display()
        );
    }
    Ok(Some(path))
}

/// Without a recording, an experiment needs a `synthetic:` block to have a video.
pub fn no_video_unless_twin(exp: &Experiment) -> Result<()> {
    if exp.file.synthetic.is_none() {
        bail!(
            "{}: no video: set `video.path`, or `angles:` for a measured angle CSV",
            exp.path.display()
        );
    }
    Ok(())
}

/// The digital twin's video of `exp` under `cache/<name>/twin.avi`, rendered when its
/// key is stale. Returns the path, the render key and whether it was rendered now.
/// `progress` hears `(stage, frames done, frames)`, first with 0 done.
pub fn twin(
    exp: &Experiment,
    cache: &Path,
    progress: &mut dyn FnMut(&str, u64, u64),
) -> Result<(PathBuf, String, bool)> {
    let Some(syn) = &exp.file.synthetic else {
        bail!("{}: no `synthetic:` block", exp.path.display());
    };
    let key = with_source(Key::new("synth"), SYNTH_SOURCE)
        .json("geometry", &exp.file.geometry)
        .json("model", &exp.file.model)
        .json("synthetic", syn)
        .hex();
    let dir = cache.join(&exp.name);
    let video = dir.join("twin.avi");
    let key_file = dir.join("twin.key");
    if cache::fresh(&key_file, &key, &[&video]) {
        return Ok((video, key, false));
    }
    progress("synth", 0, 0);
    let mut cb = |done: usize, total: usize| progress("synth", done as u64, total as u64);
    crate::synth::render(exp, &video, None, &mut cb)
        .with_context(|| format!("{}: rendering the twin", exp.path.display()))?;
    cache::record(&key_file, &key)?;
    Ok((video, key, true))
}

/// Detect the angles of `video` (cached). Returns the CSV and the detection summary.
fn detect_stage(
    exp: &Experiment,
    dir: &Path,
    video: &Path,
    video_id: &str,
    synthetic: bool,
    ctx: &Ctx,
    ran: &mut Vec<&'static str>,
) -> Result<(PathBuf, DetectionSummary, String)> {
    let settings = exp.file.video.clone().map(|mut v| {
        v.path = None;
        v
    });
    let key = with_source(Key::new("detect"), DETECT_SOURCE)
        .part("video", video_id.as_bytes())
        .json("settings", &settings)
        .hex();
    let csv = dir.join("angles.csv");
    let summary_file = dir.join("detect.json");
    let fig11 = dir.join("fig11.png");
    let key_file = dir.join("detect.key");
    if cache::fresh(&key_file, &key, &[&csv, &summary_file, &fig11]) {
        if let Some(s) = std::fs::read(&summary_file)
            .ok()
            .and_then(|b| serde_json::from_slice::<DetectionSummary>(&b).ok())
        {
            return Ok((csv, s, key));
        }
    }
    ctx.progress.stage(
        &ctx.label,
        "detect",
        "measuring the wire angle in every frame",
    );
    let mut opts = settings
        .as_ref()
        .map(DetectOptions::from_video)
        .unwrap_or_default();
    let (label, progress) = (ctx.label.clone(), ctx.progress.clone());
    opts.progress = Some(FrameProgress(Arc::new(move |d, t| {
        progress.frames(&label, d, t)
    })));
    let d = detect::detect(video, &opts)?;
    let rel_video = if synthetic {
        format!("{}/twin.avi (rendered by the build)", exp.name)
    } else {
        relative(ctx.root, video)
    };
    let flagged: Vec<FlaggedFrame> = d
        .rows
        .iter()
        .filter(|r| r.flag.is_some() || r.status != detect::Status::Ok)
        .map(|r| FlaggedFrame {
            frame: r.frame,
            t_s: r.t_s,
            status: r.status.as_str().to_string(),
            flag: r.flag.map_or("-", |f| f.as_str()).to_string(),
        })
        .collect();
    let fig_frame = report::figure11_frame(&d);
    report::figure11(video, &d, fig_frame, &fig11)?;
    let summary = DetectionSummary {
        video: rel_video,
        video_id: video_id.to_string(),
        synthetic,
        decoder: d.decoder.clone(),
        frames: d.rows.len(),
        ok: d.count(detect::Status::Ok),
        corrected: d.count(detect::Status::Corrected),
        manual: d.count(detect::Status::Manual),
        missing: d.count(detect::Status::Missing),
        pivot_px: d.pivot_px,
        roi: d.roi,
        dark_wire: d.dark_wire,
        flagged,
        figure11_frame: fig_frame,
    };
    fsutil::write_atomic(&csv, d.to_csv().as_bytes())?;
    fsutil::write_atomic(&summary_file, &serde_json::to_vec_pretty(&summary)?)?;
    cache::record(&key_file, &key)?;
    ran.push("detect");
    Ok((csv, summary, key))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_paths_are_relative_to_the_manifest() {
        let d = tempfile::tempdir().unwrap();
        let root = d.path().join("experiments");
        std::fs::create_dir_all(root.join("videos")).unwrap();
        std::fs::write(root.join("videos/a.mp4"), b"x").unwrap();
        assert_eq!(relative(&root, &root.join("videos/a.mp4")), "videos/a.mp4");
        std::fs::create_dir_all(d.path().join("other")).unwrap();
        std::fs::write(d.path().join("other/b.mp4"), b"x").unwrap();
        assert_eq!(
            relative(&root, &d.path().join("other/b.mp4")),
            "../other/b.mp4"
        );
    }
}
