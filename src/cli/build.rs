//! `rollfric build` and `rollfric check`.

use super::Done;
use crate::build::{self, BuildOptions, Stage, StageOptions};
use crate::report::{self, Summary};
use anyhow::Result;
use std::path::PathBuf;

/// The manifest and the two folders every verb over the manifest's experiments takes.
#[derive(clap::Args)]
pub(super) struct Folders {
    /// The manifest listing the experiments (report paths are relative to its folder).
    #[arg(long, default_value = "experiments/manifest.yaml")]
    pub manifest: PathBuf,
    /// Folder for the reports.
    #[arg(long, default_value = "reports")]
    pub out: PathBuf,
    /// Folder for the stages' cached outputs (rendered videos, angles, fits).
    #[arg(long, default_value = "build")]
    pub cache: PathBuf,
}

#[derive(clap::Args)]
pub struct BuildArgs {
    #[command(flatten)]
    folders: Folders,
    /// Experiments built at once (default: the number of cores).
    #[arg(long, short, value_parser = clap::value_parser!(u16).range(1..))]
    jobs: Option<u16>,
    /// No progress output.
    #[arg(long, short)]
    quiet: bool,
    /// Refuse instead of waiting when another build uses the same folders.
    #[arg(long)]
    no_wait: bool,
}

#[derive(clap::Args)]
pub struct CheckArgs {
    /// The build's summary.
    #[arg(long, default_value = "reports/summary.json")]
    summary: PathBuf,
}

/// The stage `rollfric stage` runs.
#[derive(Clone, Copy, clap::ValueEnum)]
enum StageName {
    /// Render the digital twin's video (nothing to do for a lab video or a CSV).
    Synth,
    /// Measure the wire angle in every frame (nothing to do for a CSV).
    Detect,
    /// Fit, check, draw and write the experiment's pages.
    Analyze,
}

#[derive(clap::Args)]
pub struct StageArgs {
    /// The stage.
    #[arg(value_enum)]
    stage: StageName,
    /// The experiment: its name or its file, one of the manifest's.
    experiment: String,
    #[command(flatten)]
    folders: Folders,
    /// No progress output.
    #[arg(long, short)]
    quiet: bool,
    /// Refuse instead of waiting when a build uses the same folders.
    #[arg(long)]
    no_wait: bool,
    /// When the experiment fails: record the failure for `rollfric report` (which then
    /// marks it FAILED as a build does), mark the stage's key file failed, and exit 0,
    /// so that a workflow engine goes on with the other experiments.
    #[arg(long)]
    record_failure: bool,
}

/// `rollfric stage`: one cached stage of one experiment.
pub fn stage(a: StageArgs) -> Result<Done> {
    let stage = match a.stage {
        StageName::Synth => Stage::Synth,
        StageName::Detect => Stage::Detect,
        StageName::Analyze => Stage::Analyze,
    };
    build::stage(&StageOptions {
        manifest: a.folders.manifest,
        experiment: a.experiment,
        stage,
        out: a.folders.out,
        cache: a.folders.cache,
        quiet: a.quiet,
        no_wait: a.no_wait,
        record_failure: a.record_failure,
    })
    .map(Done::ok)
}

/// `rollfric build`, or with `cached` `rollfric report` (every result from the cache).
pub fn build(a: BuildArgs, cached: bool) -> Result<Done> {
    let out = a.folders.out.clone();
    let opts = BuildOptions {
        manifest: a.folders.manifest,
        out: a.folders.out,
        cache: a.folders.cache,
        jobs: a.jobs.map(usize::from),
        quiet: a.quiet,
        no_wait: a.no_wait,
    };
    let o = if cached {
        build::report(&opts)?
    } else {
        build::build(&opts)?
    };
    let n = o.summary.experiments.len();
    // Why each experiment failed, also under -q (the log lines are the progress's).
    for e in o.summary.experiments.iter().filter(|e| e.failed()) {
        eprintln!(
            "FAILED {}: {}",
            e.name,
            e.error.as_deref().unwrap_or("no result")
        );
    }
    Ok(Done {
        out: format!(
            "{} experiments in {:.1} s: {} built, {} failed, {} missing a tolerance, {} suspect; {} report files rewritten -> {}\n",
            n,
            o.seconds,
            n - o.failed,
            o.failed,
            o.missed,
            o.suspect,
            o.written,
            out.join("index.html").display()
        ),
        // A build's exit status judges the results; a report's says only that the
        // reports were assembled (a workflow's job), `rollfric check` judges them.
        ok: cached || (o.failed == 0 && o.missed == 0),
    })
}

pub fn check(a: CheckArgs) -> Result<Done> {
    let (out, ok) = report::check(&Summary::read(&a.summary)?);
    Ok(Done { out, ok })
}
