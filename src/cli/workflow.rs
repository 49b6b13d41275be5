//! `rollfric workflow snakemake`.

use crate::build::workflow::{self, LOCAL_PROFILE, SLURM_PROFILE, SNAKEFILE_MARK};
use crate::fsutil;
use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, clap::ValueEnum)]
enum Engine {
    /// A Snakefile (Snakemake 8), with profiles for this machine and for Slurm.
    Snakemake,
}

#[derive(clap::Args)]
pub struct WorkflowArgs {
    /// The workflow engine.
    #[arg(value_enum)]
    engine: Engine,
    /// The Snakefile to write (profiles/ goes beside it). A file not written by this
    /// command is not replaced.
    #[arg(short, long, default_value = "Snakefile")]
    output: PathBuf,
    /// The manifest and the folders, as the jobs will see them.
    #[command(flatten)]
    folders: super::build::Folders,
}

pub fn workflow(a: WorkflowArgs) -> Result<String> {
    let Engine::Snakemake = a.engine;
    let f = &a.folders;
    let text = workflow::snakefile(&f.manifest, &f.cache, &f.out)?;
    if let Ok(old) = std::fs::read_to_string(&a.output) {
        if !old.starts_with(SNAKEFILE_MARK) {
            bail!(
                "{}: exists and was not written by `rollfric workflow snakemake`; not replaced \
                 (move it away, or give -o)",
                a.output.display()
            );
        }
    } else if a.output.exists() {
        bail!(
            "{}: exists and cannot be read; not replaced",
            a.output.display()
        );
    }
    fsutil::write_atomic(&a.output, text.as_bytes())?;
    let mut said = format!(
        "{}: Snakefile for {}\n",
        a.output.display(),
        f.manifest.display()
    );
    let dir = a.output.parent().unwrap_or(Path::new(""));
    for (name, body) in [("local", LOCAL_PROFILE), ("slurm", SLURM_PROFILE)] {
        let p = dir.join("profiles").join(name).join("config.yaml");
        if p.exists() {
            let _ = writeln!(said, "{}: kept (already there)", p.display());
            continue;
        }
        std::fs::create_dir_all(p.parent().expect("a folder"))
            .with_context(|| format!("{}: cannot create folder", p.display()))?;
        fsutil::write_atomic(&p, body.as_bytes())?;
        let _ = writeln!(said, "{}: {name} profile", p.display());
    }
    said.push_str(
        "run: snakemake --cores 2   (or --profile profiles/local, --profile profiles/slurm)\n",
    );
    Ok(said)
}
