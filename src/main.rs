//! `rollfric`: parse the command line, call the library, print the result or one line
//! of error and exit non-zero.

use clap::{Parser, Subcommand};
use rollfric::commands::{self, FitArgs, SimulateArgs};
use rollfric::config::locate;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "rollfric",
    version,
    about = "Rolling-friction coefficients from a conical pendulum"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Fit every experiment of the manifest and print Table 1 reproduced.
    Build {
        /// The manifest listing the experiments.
        #[arg(long, default_value = "experiments/manifest.yaml")]
        manifest: PathBuf,
        /// Print the results as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Write what a camera would record of an experiment's digital twin (t_s,angle_rad).
    Simulate {
        /// Experiment file, or its name in experiments/.
        experiment: String,
        /// Output CSV.
        #[arg(short, long)]
        output: PathBuf,
        /// Frame rate, frames/s (default: the experiment's).
        #[arg(long)]
        fps: Option<f64>,
        /// Per-frame angle noise, degrees (default: the experiment's `angle_noise_deg`).
        #[arg(long)]
        noise_deg: Option<f64>,
        /// Noise seed (default: the experiment's).
        #[arg(long)]
        seed: Option<u64>,
        /// Recording length, s (default: until the ball stops plus 2 s, at most 120 s).
        #[arg(long)]
        duration: Option<f64>,
    },
    /// Measure turning points and fit s_r for one experiment.
    Fit {
        /// Experiment file, or its name in experiments/.
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
    },
    /// The wire-torsion table of Appendix A for one experiment.
    Torsion {
        /// Experiment file, or its name in experiments/.
        experiment: String,
        /// Rolling-friction coefficient to compare with, m (default: the synthetic truth).
        #[arg(long)]
        s_r: Option<f64>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Versions and the video back-ends of the system OpenCV.
    Info,
}

fn run(cli: Cli) -> anyhow::Result<bool> {
    let out = match cli.cmd {
        Cmd::Build { manifest, json } => {
            let (text, ok) = commands::build_cmd(&manifest, json)?;
            print!("{text}");
            return Ok(ok);
        }
        Cmd::Simulate {
            experiment,
            output,
            fps,
            noise_deg,
            seed,
            duration,
        } => {
            let args = SimulateArgs {
                fps,
                noise_deg,
                seed,
                duration_s: duration,
            };
            let msg = commands::simulate(&locate(&experiment), &output, &args)?;
            eprint!("{msg}");
            String::new()
        }
        Cmd::Fit {
            experiment,
            angles,
            beta,
            compare_beta,
            json,
        } => {
            let args = FitArgs {
                angles,
                beta,
                compare_betas: compare_beta,
            };
            commands::fit_cmd(&locate(&experiment), &args, json)?
        }
        Cmd::Torsion {
            experiment,
            s_r,
            json,
        } => commands::torsion_cmd(&locate(&experiment), s_r, json)?,
        Cmd::Info => rollfric::video::info()?,
    };
    print!("{out}");
    Ok(true)
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
