//! The command line: each verb's arguments and text output, over the library. `main.rs`
//! only calls [`main`]; every verb parses its flags here (once) and prints what the
//! library returns.

mod build;
mod detect;
mod fit;
mod init;
mod lens;
mod model;
mod workflow;

/// This process's processor time and peak memory, as `detect` reports them.
pub use crate::usage::{own_cpu_seconds, peak_memory};

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "rollfric",
    version,
    about = "Rolling-friction coefficients from a conical pendulum",
    after_help = "Every key of an experiment file and of the manifest: `rollfric schema` \
                  (also docs/experiment.md)."
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Build every experiment of the manifest (synth, detect, fit, torsion, figures,
    /// pages; cached stages are skipped) and write the reports.
    Build(build::BuildArgs),
    /// One cached stage of one experiment (synth, detect or analyze), into the cache
    /// layout `build` uses; nothing to do when its key is current. For a workflow
    /// engine: `build` is these stages in its own worker pool.
    Stage(build::StageArgs),
    /// Assemble the index, Table 1, Figure 19 and summary.json from the cached results
    /// of every experiment (after `stage analyze` of each); computes nothing. Exits 0
    /// once the reports are written: `check` judges them.
    Report(build::BuildArgs),
    /// Write a workflow engine's file for the manifest: `workflow snakemake` writes a
    /// Snakefile (one rule per stage) and profiles/ (local, Slurm) beside it.
    Workflow(workflow::WorkflowArgs),
    /// Compare the reproduced values of a build's summary with their expected values and
    /// tolerances; exit 1 on a miss.
    Check(build::CheckArgs),
    /// Write what a camera would record of an experiment's digital twin (t_s,angle_rad).
    Simulate(model::SimulateArgs),
    /// Render the digital twin's video of an experiment (H.264 .mp4, or MJPG .avi).
    Synth(model::SynthArgs),
    /// Measure turning points and fit s_r for one experiment.
    Fit(fit::FitArgs),
    /// The wire-torsion table of Appendix A for one experiment.
    Torsion(model::TorsionArgs),
    /// Measure the wire angle in every frame of a video (CSV: t_s,angle_rad,status,quality).
    Detect(detect::DetectArgs),
    /// Write a commented experiment file for a video (what the detector finds in it, and
    /// every geometry key to fill in), optionally listed in a manifest.
    Init(init::InitArgs),
    /// Fit the lens's radial distortion from the straight lines a video shows (a ruled or
    /// gridded sheet filmed with the experiment's camera), for `video.lens`.
    Lens(lens::LensArgs),
    /// Versions: rollfric, the system OpenCV, the ffmpeg program (or its absence).
    Info,
    /// Every key of an experiment file and of the manifest, with its type, default and
    /// meaning (Markdown, as docs/experiment.md).
    Schema(SchemaArgs),
    /// Every knob of the detector (threshold, limit, window, count): its value, unit,
    /// stage and the figure that chose it (Markdown with --markdown, as docs/tuning.md).
    Tuning(TuningArgs),
}

#[derive(clap::Args)]
struct SchemaArgs {
    /// Print the experiment file's JSON Schema instead (for editors that check YAML).
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
struct TuningArgs {
    /// Print the table as Markdown, one table per stage (docs/tuning.md).
    #[arg(long)]
    markdown: bool,
}

/// A verb's result: its text for standard output, and whether it succeeded (a build or
/// check that misses a tolerance prints its output and exits 1).
struct Done {
    out: String,
    ok: bool,
}

impl Done {
    fn ok(out: String) -> Self {
        Self { out, ok: true }
    }
}

fn run(cli: Cli) -> anyhow::Result<Done> {
    match cli.cmd {
        Cmd::Build(a) => build::build(a, false),
        Cmd::Stage(a) => build::stage(a),
        Cmd::Report(a) => build::build(a, true),
        Cmd::Workflow(a) => workflow::workflow(a).map(Done::ok),
        Cmd::Check(a) => build::check(a),
        Cmd::Simulate(a) => model::simulate(a).map(Done::ok),
        Cmd::Synth(a) => model::synth(a).map(Done::ok),
        Cmd::Fit(a) => fit::fit(a).map(Done::ok),
        Cmd::Torsion(a) => model::torsion(a).map(Done::ok),
        Cmd::Detect(a) => detect::detect(a).map(Done::ok),
        Cmd::Init(a) => init::init(a).map(Done::ok),
        Cmd::Lens(a) => lens::lens(a).map(Done::ok),
        Cmd::Info => crate::video::info().map(Done::ok),
        Cmd::Schema(a) => Ok(Done::ok(if a.json {
            crate::config::schema::experiment_json()
        } else {
            crate::config::schema::reference()
        })),
        Cmd::Tuning(a) => Ok(Done::ok(if a.markdown {
            crate::detect::tuning::markdown()
        } else {
            crate::detect::tuning::text()
        })),
    }
}

/// Parse the command line, run the verb, print its output or one line of error.
pub fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(d) => {
            print!("{}", d.out);
            if d.ok {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(1)
            }
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
