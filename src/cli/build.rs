//! `rollfric build` and `rollfric check`.

use super::Done;
use crate::build::{self, BuildOptions};
use crate::report::{self, Summary};
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct BuildArgs {
    /// The manifest listing the experiments.
    #[arg(long, default_value = "experiments/manifest.yaml")]
    manifest: PathBuf,
    /// Folder for the reports.
    #[arg(long, default_value = "reports")]
    out: PathBuf,
    /// Folder for the stages' cached outputs (rendered videos, angles, fits).
    #[arg(long, default_value = "build")]
    cache: PathBuf,
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

pub fn build(a: BuildArgs) -> Result<Done> {
    let o = build::build(&BuildOptions {
        manifest: a.manifest,
        out: a.out.clone(),
        cache: a.cache,
        jobs: a.jobs.map(usize::from),
        quiet: a.quiet,
        no_wait: a.no_wait,
    })?;
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
            a.out.join("index.html").display()
        ),
        ok: o.failed == 0 && o.missed == 0,
    })
}

pub fn check(a: CheckArgs) -> Result<Done> {
    let (out, ok) = report::check(&Summary::read(&a.summary)?);
    Ok(Done { out, ok })
}
