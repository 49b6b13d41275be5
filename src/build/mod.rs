//! `rollfric build`: the manifest's experiments through the pipeline's stages (twin ->
//! detect -> analysis and pages), each cached under a key hashed from its inputs and
//! the source of the code that produces it, experiments in parallel, one failure
//! stopping only its own experiment.
//!
//! Cache layout, under `--cache` (default `build/`), one folder per experiment:
//!
//! | stage    | outputs                                   | key covers |
//! |----------|-------------------------------------------|------------|
//! | synth    | `twin.avi`                                | geometry, model, `synthetic:`, the `synth` module's closure |
//! | detect   | `angles.csv`, `detect.json`, `fig11.png`, `review.json`, `review/` | the video's id, `video:` settings, the `detect` module's closure |
//! | analysis | `result.json` and the experiment's pages  | the YAML's bytes, the angles' id, the `pipeline` and `report` closures |
//!
//! A module's closure is its source with that of every module it names and the
//! templates it embeds, hashed by `build.rs` ([`crate::sources`]). Every file is written
//! to a temporary name and renamed; a stage's key is written last, so a build killed at
//! any moment leaves old or new files, never torn ones, and the next build reruns
//! exactly the stages whose keys are missing or stale.
//!
//! The same stages run one at a time from outside ([`stage`], `rollfric stage NAME
//! EXPERIMENT`: a workflow engine's jobs), each refusing when the one before it is not
//! current; [`report`] then assembles the index from the cached results. [`build`] is
//! those stages in its own worker pool: one code path (`stages::run_experiment` under a
//! `Runs` policy). Each stage's key file (`twin.key`, `detect.key`, `analysis.key`) is
//! also a workflow engine's output: a stage command touches it when the key is current,
//! and with `--record-failure` writes `failed` into it and the experiment's error into
//! `failed.txt`, which `report` shows; `report` writes `report.key` (the SHA-256 of the
//! summary) at the cache's top.

mod lock;
pub mod progress;
mod stages;
pub mod workflow;
mod writer;

pub use stages::{cached_angles, Stage};
pub(crate) use writer::pathdiff;
pub use writer::relative;

use crate::config::{Experiment, Manifest};
use crate::report::{self, Outcome};
use crate::{fsutil, hash};
use anyhow::{bail, Context, Result};
use progress::Progress;
use stages::{Ctx, Runs};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;
use writer::{remove_stale_temporaries, Writer};

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
    /// Refuse, instead of waiting, when another build holds the folders.
    pub no_wait: bool,
}

/// What a build did.
pub struct BuildOutcome {
    pub summary: report::Summary,
    /// Experiments that failed (they are in the summary with their error).
    pub failed: usize,
    /// Experiments whose values miss their tolerances.
    pub missed: usize,
    /// Experiments whose verdict is `suspect` with a warning nobody accepted.
    pub suspect: usize,
    pub seconds: f64,
    /// Report files rewritten (unchanged files are left alone).
    pub written: usize,
}

/// Run the build: every stage of every experiment, then the index.
pub fn build(opts: &BuildOptions) -> Result<BuildOutcome> {
    run(opts, Runs::All)
}

/// Assemble the reports' index, Table 1, Figure 19 and `summary.json` from the cached
/// results of every experiment (`rollfric report`): nothing is computed; an experiment
/// whose stages are not current fails, naming the stage command that makes it so.
pub fn report(opts: &BuildOptions) -> Result<BuildOutcome> {
    run(opts, Runs::Cached)
}

/// What `rollfric stage` does.
#[derive(Clone, Debug)]
pub struct StageOptions {
    pub manifest: PathBuf,
    /// The experiment: its name, or its file (one of the manifest's).
    pub experiment: String,
    pub stage: Stage,
    pub out: PathBuf,
    pub cache: PathBuf,
    pub quiet: bool,
    pub no_wait: bool,
    /// On the experiment's failure, record it for `report` (as the build would show it),
    /// mark the stage's key file failed (so the next run computes it again) and return
    /// normally: a workflow engine's job then succeeds and the report still assembles.
    pub record_failure: bool,
}

/// One cached stage of one experiment of the manifest, into the cache layout the build
/// uses (and, for `analyze`, its pages into the reports folder); a no-op when the
/// stage's key is current. The stages before it must be current. Stage commands of
/// different experiments may run at once (each holds the cache folder shared and its
/// experiment's folder exclusively); a build waits for them, and they for a build.
/// Returns what was done, one line.
pub fn stage(opts: &StageOptions) -> Result<String> {
    let started = Instant::now();
    let (_, files) = Manifest::load(&opts.manifest)?;
    let root = root_or_here(opts.manifest.parent().unwrap_or(Path::new("")));
    let loaded: Vec<Result<(Experiment, Vec<u8>)>> = files
        .iter()
        .map(|f| Experiment::load_with_bytes(f))
        .collect();
    let wanted = Path::new(&opts.experiment);
    let same_file = |f: &Path| matches!((std::fs::canonicalize(f), std::fs::canonicalize(wanted)), (Ok(a), Ok(b)) if a == b);
    // By name; by the file's stem when the file does not load (the name the build
    // gives it then); by file.
    let Some(i) = (0..files.len()).find(|&i| match &loaded[i] {
        Ok((e, _)) => e.name == opts.experiment || same_file(&files[i]),
        Err(_) => display_name(&files[i]) == opts.experiment || same_file(&files[i]),
    }) else {
        bail!(
            "{}: no experiment named or found at `{}` in the manifest",
            opts.manifest.display(),
            opts.experiment
        );
    };
    let name = loaded[i]
        .as_ref()
        .map_or_else(|_| display_name(&files[i]), |(e, _)| e.name.clone());
    let _cache_lock = lock::Lock::acquire_shared(&opts.cache, !opts.no_wait)?;
    let _exp_lock = lock::Lock::acquire(&opts.cache.join(&name), !opts.no_wait)?;
    let failure = stages::failure_file(&opts.cache, &name);
    let ran = (|| -> Result<String> {
        let folders = [(&opts.out, "reports"), (&opts.cache, "cache")];
        if let Some(why) = &name_collisions(&root, &files, &loaded, &folders)[i] {
            bail!("{why}");
        }
        let (exp, yaml) = match &loaded[i] {
            Ok(l) => l,
            Err(e) => bail!("{e:#}"),
        };
        run_stage(opts, &root, &files[i], exp, yaml)
    })();
    let key = stages::key_file(&opts.cache, &name, opts.stage);
    match ran {
        Ok(how) => {
            if failure.exists() {
                std::fs::remove_file(&failure)
                    .with_context(|| format!("{}: cannot remove", failure.display()))?;
            }
            // A workflow engine judges a job by its output's time: a stage that found
            // its key current says so by touching the key file (its content, what
            // rollfric reads, is unchanged).
            if key.exists() {
                hash::touch(&key)?;
            }
            Ok(format!(
                "{}: stage {}: {how} in {:.1} s\n",
                display_name(&files[i]),
                opts.stage.as_str(),
                started.elapsed().as_secs_f64()
            ))
        }
        Err(e) if opts.record_failure => {
            // A stage refused because an earlier one failed keeps that failure.
            let earlier = e.downcast_ref::<stages::NotCurrent>().is_some() && failure.exists();
            if !earlier {
                let msg = writer::unrooted(&root, &format!("{e:#}"));
                fsutil::write_atomic(&failure, msg.as_bytes())?;
            }
            // Not a key: the stage is stale for rollfric, done for the engine.
            fsutil::write_atomic(&key, b"failed\n")?;
            Ok(format!(
                "{}: stage {}: FAILED (recorded for the report): {e:#}\n",
                display_name(&files[i]),
                opts.stage.as_str()
            ))
        }
        Err(e) => Err(e),
    }
}

/// The stage of [`stage`] on a loaded experiment.
fn run_stage(
    opts: &StageOptions,
    root: &Path,
    file: &Path,
    exp: &Experiment,
    yaml: &[u8],
) -> Result<String> {
    let _out_lock = if opts.stage == Stage::Analyze && !same_folder(&opts.cache, &opts.out) {
        Some(lock::Lock::acquire_shared(&opts.out, !opts.no_wait)?)
    } else {
        None
    };
    let progress = Arc::new(Progress::new(1, opts.quiet));
    let writer = Writer::new(&opts.out);
    let ctx = Ctx {
        root,
        cache: &opts.cache,
        progress: &progress,
        label: display_name(file),
        writer: &writer,
        runs: Runs::Only(opts.stage),
    };
    let (_, how) = stages::run_experiment(file, exp, yaml, &ctx)?;
    progress.clear();
    Ok(how)
}

/// Every experiment through the stages `runs` allows, then the index.
fn run(opts: &BuildOptions, runs: Runs) -> Result<BuildOutcome> {
    let started = Instant::now();
    let (manifest, files) = Manifest::load(&opts.manifest)?;
    // The manifest's folder; `.` for a bare file name, so that paths in the reports are
    // relative to it however the manifest was spelled.
    let root = root_or_here(opts.manifest.parent().unwrap_or(Path::new("")));
    for (flag, dir) in [("--out", &opts.out), ("--cache", &opts.cache)] {
        if same_folder(&root, dir) {
            bail!(
                "{flag} {}: that is the manifest's own folder; the build would write among the experiments",
                dir.display()
            );
        }
    }
    // One build per folder at a time: held until this function returns. A report
    // computes nothing: it shares the cache with stage commands (and waits for a build).
    let _cache_lock = if runs == Runs::Cached {
        lock::Lock::acquire_shared(&opts.cache, !opts.no_wait)?
    } else {
        lock::Lock::acquire(&opts.cache, !opts.no_wait)?
    };
    let _out_lock = if same_folder(&opts.cache, &opts.out) {
        None
    } else {
        Some(lock::Lock::acquire(&opts.out, !opts.no_wait)?)
    };
    remove_stale_temporaries(&opts.out, 3);
    remove_stale_temporaries(&opts.cache, 3);
    // Each experiment file is read and validated once; a failure stays with its
    // experiment.
    let loaded: Vec<Result<(Experiment, Vec<u8>)>> = files
        .iter()
        .map(|f| Experiment::load_with_bytes(f))
        .collect();
    let collisions = name_collisions(
        &root,
        &files,
        &loaded,
        &[(&opts.out, "reports"), (&opts.cache, "cache")],
    );
    let progress = Arc::new(Progress::new(files.len(), opts.quiet));
    let jobs = opts
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()))
        .clamp(1, files.len().max(1));
    // Longest first, so that the slowest experiment does not start last.
    let mut order: Vec<usize> = (0..files.len()).collect();
    let cost: Vec<f64> = loaded
        .iter()
        .map(|l| l.as_ref().map_or(0.0, |(e, _)| estimated_cost(e)))
        .collect();
    order.sort_by(|&a, &b| cost[b].total_cmp(&cost[a]).then(a.cmp(&b)));
    let queue = Mutex::new(order.into_iter());
    let writer = Writer::new(&opts.out);
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
                    cache: &opts.cache,
                    progress: &progress,
                    label: label.clone(),
                    writer: &writer,
                    runs,
                };
                let r = match &collisions[i] {
                    Some(why) => Err(anyhow::anyhow!("{why}")),
                    None => {
                        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                            match &loaded[i] {
                                Ok((exp, yaml)) => stages::run_experiment(file, exp, yaml, &ctx),
                                Err(e) => Err(anyhow::anyhow!("{e:#}")),
                            }
                        }))
                        .unwrap_or_else(|_| Err(anyhow::anyhow!("internal error (panic)")))
                    }
                };
                let secs = t0.elapsed().as_secs_f64();
                let outcome = match r {
                    Ok((Some(res), how)) => {
                        progress.finish(&label, &format!("{how} in {secs:.1} s: {}", res.line()));
                        Outcome::Built(Box::new(res))
                    }
                    Ok((None, _)) => {
                        unreachable!("a build or report runs every experiment to its result")
                    }
                    Err(e) => {
                        // A report shows the failure a stage command recorded, as the
                        // build would have shown it.
                        let name = loaded[i]
                            .as_ref()
                            .map_or_else(|_| label.clone(), |(e, _)| e.name.clone());
                        let recorded = (runs == Runs::Cached)
                            .then(|| {
                                std::fs::read_to_string(stages::failure_file(&opts.cache, &name))
                                    .ok()
                            })
                            .flatten();
                        let error =
                            recorded.unwrap_or_else(|| writer::unrooted(&root, &format!("{e:#}")));
                        progress.finish(&label, &format!("FAILED: {error}"));
                        Outcome::Failed {
                            name: label.clone(),
                            file: relative(&root, file),
                            error,
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
    let (summary, index) = report::index_pages(&manifest, outcomes)?;
    writer.write(&index)?;
    let current: Vec<&str> = index
        .iter()
        .map(|f| f.path.as_str())
        .chain(
            summary
                .experiments
                .iter()
                .filter_map(|e| e.result.as_ref())
                .flat_map(|r| r.pages.iter().map(|p| p.path.as_str())),
        )
        .collect();
    writer.prune(&current)?;
    if runs == Runs::Cached {
        // For a workflow engine: the report's own key file, written on every report
        // (the index files keep their time when unchanged).
        let summary_file = index.iter().find(|f| f.path == "summary.json");
        let id = summary_file.map_or_else(String::new, |f| crate::hash::sha256(&f.bytes));
        crate::hash::record(&opts.cache.join(REPORT_KEY), &id)?;
    }
    let written = writer.written();
    let failed = summary.experiments.iter().filter(|e| e.failed()).count();
    let missed = summary
        .experiments
        .iter()
        .filter(|e| e.result.as_ref().is_some_and(|r| r.missed()))
        .count();
    let suspect = summary
        .experiments
        .iter()
        .filter(|e| e.result.as_ref().is_some_and(|r| r.verdict.blocks()))
        .count();
    Ok(BuildOutcome {
        summary,
        failed,
        missed,
        suspect,
        seconds: started.elapsed().as_secs_f64(),
        written,
    })
}

/// The file `rollfric report` writes in the cache after each report (the SHA-256 of the
/// summary it wrote): a workflow's final output.
pub const REPORT_KEY: &str = "report.key";

/// Names the reports folder uses for itself (its index, summary and the committed
/// README.md): no experiment may take them, in any case (a page `README.md` would
/// replace the README on a case-blind file system too).
const RESERVED_NAMES: [&str; 3] = ["index", "summary", "readme"];

/// For each experiment, why its name cannot be used: reserved, taken by another
/// experiment of the manifest (the same file listed twice included), or its folder in
/// one of `folders` (the reports, the cache) a symbolic link, through which the build
/// would write into a folder not its own. Every experiment of a colliding group fails,
/// naming the others, so none silently overwrites another's pages. A file that does
/// not load keeps its file name here and fails later with its own error.
fn name_collisions(
    root: &Path,
    files: &[PathBuf],
    loaded: &[Result<(Experiment, Vec<u8>)>],
    folders: &[(&PathBuf, &str)],
) -> Vec<Option<String>> {
    let names: Vec<String> = files
        .iter()
        .zip(loaded)
        .map(|(f, l)| {
            l.as_ref()
                .map_or_else(|_| display_name(f), |(e, _)| e.name.clone())
        })
        .collect();
    let mut by_name: std::collections::HashMap<&str, Vec<usize>> = Default::default();
    for (i, n) in names.iter().enumerate() {
        by_name.entry(n.as_str()).or_default().push(i);
    }
    names
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let me = relative(root, &files[i]);
            if RESERVED_NAMES.contains(&n.to_lowercase().as_str()) {
                return Some(format!(
                    "{me}: the experiment name `{n}` is the reports' own (index.html, index.md, summary.json, README.md); choose another `name:`"
                ));
            }
            for (dir, what) in folders {
                let own = dir.join(n);
                if std::fs::symlink_metadata(&own).is_ok_and(|m| m.file_type().is_symlink()) {
                    return Some(format!(
                        "{me}: {} is a symbolic link; the build writes the {what} of `{n}` \
                         only into a folder of its own: remove the link",
                        own.display()
                    ));
                }
            }
            let group = &by_name[n.as_str()];
            let others: Vec<String> = group
                .iter()
                .filter(|&&j| j != i)
                .take(SHOWN_OTHERS)
                .map(|&j| relative(root, &files[j]))
                .collect();
            let more = match group.len() - 1 {
                k if k > SHOWN_OTHERS => format!(" and {} more", k - SHOWN_OTHERS),
                _ => String::new(),
            };
            (!others.is_empty()).then(|| {
                format!(
                    "{me}: the experiment name `{n}` is also that of {}{more} in the manifest (each experiment needs its own name: its pages are <name>.html and <name>.md)",
                    others.join(", ")
                )
            })
        })
        .collect()
}

/// The most experiments of a colliding group one error names (a file listed 20 000
/// times gives 20 000 short errors, not 20 000 lists of every other entry).
const SHOWN_OTHERS: usize = 3;

/// The manifest's folder, `.` when it is the current one.
fn root_or_here(root: &Path) -> PathBuf {
    if root.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        root.to_path_buf()
    }
}

/// Whether two folders (both existing) are the same one.
fn same_folder(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

fn display_name(file: &Path) -> String {
    file.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| file.display().to_string())
}

/// Rough cost of an experiment (frames to render and detect), for ordering only.
fn estimated_cost(exp: &Experiment) -> f64 {
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
