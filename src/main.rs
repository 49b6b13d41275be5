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
    /// Build every experiment of the manifest (synth, detect, fit, torsion, figures,
    /// pages; cached stages are skipped) and write the reports.
    Build {
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
        #[arg(long, short)]
        jobs: Option<usize>,
        /// No progress output.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Compare the reproduced values of a build's summary with their expected values and
    /// tolerances; exit 1 on a miss.
    Check {
        /// The build's summary.
        #[arg(long, default_value = "reports/summary.json")]
        summary: PathBuf,
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
    /// Render the digital twin's video of an experiment (H.264 .mp4, or MJPG .avi).
    Synth {
        /// Experiment file, or its name in experiments/.
        experiment: String,
        /// Output video.
        #[arg(short, long)]
        output: PathBuf,
        /// Also write the true angle of every frame (t_s,angle_rad,spoiled).
        #[arg(long)]
        truth: Option<PathBuf>,
        /// Recording length, s (default: the experiment's).
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
    /// Measure the wire angle in every frame of a video (CSV: t_s,angle_rad,status,quality).
    Detect {
        /// The video file.
        video: PathBuf,
        /// Output CSV.
        #[arg(short, long)]
        output: PathBuf,
        /// Experiment whose `video:` block narrows the search (ROI, pivot, frames, marks).
        #[arg(long)]
        experiment: Option<String>,
        /// Write an image of each flagged frame (detected line red, predicted green).
        #[arg(long)]
        diagnostics: bool,
        /// Decode with OpenCV even when the ffmpeg program is installed.
        #[arg(long)]
        opencv: bool,
        /// Region of interest `x,y,width,height` (px).
        #[arg(long, value_delimiter = ',')]
        roi: Option<Vec<u32>>,
        /// Frames to use, `first,last` (0-based, inclusive).
        #[arg(long, value_delimiter = ',')]
        frames: Option<Vec<u64>>,
        /// Pivot `x,y` (px; may lie outside the frame).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        pivot: Option<Vec<f64>>,
    },
    /// Versions and the video back-ends of the system OpenCV.
    Info,
}

fn run(cli: Cli) -> anyhow::Result<bool> {
    let out = match cli.cmd {
        Cmd::Build {
            manifest,
            out,
            cache,
            jobs,
            quiet,
        } => {
            let o = rollfric::build::build(&rollfric::build::BuildOptions {
                manifest,
                out: out.clone(),
                cache,
                jobs,
                quiet,
            })?;
            let n = o.summary.experiments.len();
            println!(
                "{} experiments in {:.1} s: {} built, {} failed, {} missing a tolerance; {} report files rewritten -> {}",
                n,
                o.seconds,
                n - o.failed,
                o.failed,
                o.missed,
                o.written,
                out.join("index.html").display()
            );
            return Ok(o.failed == 0 && o.missed == 0);
        }
        Cmd::Check { summary } => {
            let (text, ok) = rollfric::report::check(&summary)?;
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
        Cmd::Synth {
            experiment,
            output,
            truth,
            duration,
        } => {
            let msg =
                commands::synth_cmd(&locate(&experiment), &output, truth.as_deref(), duration)?;
            eprint!("{msg}");
            String::new()
        }
        Cmd::Detect {
            video,
            output,
            experiment,
            diagnostics,
            opencv,
            roi,
            frames,
            pivot,
        } => {
            let want = |name: &str, got: usize, n: usize| {
                if got != n {
                    anyhow::bail!("--{name}: expected {n} comma-separated numbers, got {got}");
                }
                Ok(())
            };
            if let Some(v) = &roi {
                want("roi", v.len(), 4)?;
            }
            if let Some(v) = &frames {
                want("frames", v.len(), 2)?;
            }
            if let Some(v) = &pivot {
                want("pivot", v.len(), 2)?;
            }
            let args = commands::DetectArgs {
                experiment: experiment.map(|e| locate(&e)),
                diagnostics,
                opencv,
                roi: roi.map(|v| [v[0], v[1], v[2], v[3]]),
                frames: frames.map(|v| [v[0], v[1]]),
                pivot: pivot.map(|v| [v[0], v[1]]),
            };
            let msg = commands::detect_cmd(&video, &output, &args)?;
            eprint!("{msg}");
            String::new()
        }
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
