//! The digital twin's verbs (`simulate`, `synth`) and the torsion table (`torsion`).

use crate::clobber;
use crate::config::{locate, Experiment};
use crate::fsutil;
use crate::physics::torsion::torsion_check;
use crate::physics::{BetaChoice, FrictionLaw};
use crate::simulate;
use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Experiment file, or its name: NAME.yaml here, then in experiments/.
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
    /// Replace an existing output that is not an angle CSV.
    #[arg(long)]
    force: bool,
}

/// `rollfric simulate`: write the camera's angle series of the experiment's twin.
pub fn simulate(a: SimulateArgs) -> Result<String> {
    let path = locate(&a.experiment);
    clobber::check(
        &[clobber::Output {
            flag: "-o",
            path: &a.output,
            kind: clobber::Kind::Angles,
        }],
        &[("the experiment file", &path)],
        a.force,
    )?;
    let exp = Experiment::load(&path)?;
    let mut cam = simulate::camera_of(&exp)?;
    if let Some(f) = a.fps {
        if !(f.is_finite() && f > 0.0) {
            bail!("--fps {f}: expected a positive frame rate");
        }
        cam.fps = f;
    }
    if let Some(n) = a.noise_deg {
        crate::config::noise_deg("--noise-deg", n)?;
        cam.noise_rad = n.to_radians();
    }
    if let Some(d) = a.duration {
        if !(d.is_finite() && d > 0.0) {
            bail!("--duration {d}: expected a positive number of seconds");
        }
        cam.duration_s = Some(d);
    }
    crate::config::frame_budget(("--fps", cam.fps), ("--duration", cam.duration_s))?;
    cam.seed = a.seed.unwrap_or(cam.seed);
    let rec = simulate::record(&exp, &cam)?;
    fsutil::write_atomic(&a.output, rec.series.to_csv().as_bytes())?;
    eprintln!(
        "{}: {} frames at {} fps, {} turning points, {}; s_r = {:e} m, noise {:.3} deg -> {}",
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
        a.output.display()
    );
    Ok(String::new())
}

#[derive(clap::Args)]
pub struct SynthArgs {
    /// Experiment file, or its name: NAME.yaml here, then in experiments/.
    experiment: String,
    /// Output video.
    #[arg(short, long, required_unless_present = "calibration")]
    output: Option<PathBuf>,
    /// Also write the true angle of every frame (t_s,angle_rad,spoiled).
    #[arg(long)]
    truth: Option<PathBuf>,
    /// Recording length, s (default: the experiment's).
    #[arg(long)]
    duration: Option<f64>,
    /// Print, instead of rendering, a `video.calibration` block of protractor marks as
    /// the twin's camera sees them (image px) with their plate coordinates (mm from
    /// the fulcrum, the untilted view's axes): for a twin filmed at a tilt.
    #[arg(long, conflicts_with_all = ["output", "truth", "duration"])]
    calibration: bool,
    /// Replace existing outputs that are not a twin's video or truth CSV.
    #[arg(long)]
    force: bool,
}

/// The `video.calibration` block of the twin's protractor marks.
fn calibration_block(exp: &Experiment) -> Result<String> {
    if exp.file.synthetic.as_ref().is_some_and(|s| s.mirror) {
        bail!(
            "{}: `synthetic.mirror`: the protractor marks are printed for an unmirrored twin only",
            exp.path.display()
        );
    }
    let pts = crate::synth::calibration_points(exp)?;
    if pts.len() < 4 {
        bail!(
            "{}: only {} protractor mark(s) in the frame; a calibration needs four",
            exp.path.display(),
            pts.len()
        );
    }
    let mut out = String::from("  calibration:\n    points:\n");
    for (i, p) in pts {
        out.push_str(&format!(
            "      - {{image: [{:.1}, {:.1}], plate: [{:.2}, {:.2}]}}\n",
            i[0], i[1], p[0], p[1]
        ));
    }
    Ok(out)
}

/// `rollfric synth`: render the experiment's digital-twin video (and its truth CSV).
pub fn synth(a: SynthArgs) -> Result<String> {
    let path = locate(&a.experiment);
    let exp = Experiment::load(&path)?;
    let Some(output) = a.output.filter(|_| !a.calibration) else {
        return calibration_block(&exp);
    };
    let mut outputs = vec![clobber::Output {
        flag: "-o",
        path: &output,
        kind: clobber::Kind::Twin,
    }];
    if let Some(t) = &a.truth {
        outputs.push(clobber::Output {
            flag: "--truth",
            path: t,
            kind: clobber::Kind::Truth,
        });
    }
    clobber::check(&outputs, &[("the experiment file", &path)], a.force)?;
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let started = std::time::Instant::now();
    let mut progress = |done: usize, total: usize| {
        if tty {
            eprint!("\rsynth: frame {done}/{total}");
        }
    };
    if let (Some(s), Some(_)) = (&exp.file.synthetic, a.duration) {
        crate::config::frame_budget(("synthetic.fps", s.fps), ("--duration", a.duration))?;
    }
    let r = crate::synth::render(&exp, &output, a.duration, &mut progress)?;
    if tty {
        eprintln!();
    }
    if let Some(t) = &a.truth {
        fsutil::write_atomic(t, crate::synth::truth_csv(&r.truth).as_bytes())?;
    }
    let spoiled = r.truth.iter().filter(|t| t.spoiled != "none").count();
    eprintln!(
        "{}: SYNTHETIC {} frames {}x{} at {} fps, {} ({:?} style, {spoiled} spoiled frames, pivot ({:.1}, {:.1}) px) in {:.1} s -> {}",
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
    );
    Ok(String::new())
}

#[derive(clap::Args)]
pub struct TorsionArgs {
    /// Experiment file, or its name: NAME.yaml here, then in experiments/.
    experiment: String,
    /// Rolling-friction coefficient to compare with, m (default: the synthetic truth).
    #[arg(long)]
    s_r: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// `rollfric torsion`: the Appendix A table, with `s_r` from `--s-r`, else the synthetic
/// truth, else the reference value (said which).
pub fn torsion(a: TorsionArgs) -> Result<String> {
    let exp = Experiment::load(&locate(&a.experiment))?;
    let t = exp
        .file
        .torsion
        .as_ref()
        .with_context(|| format!("{}: no `torsion:` block", exp.path.display()))?;
    let (s_r, from) = match (
        a.s_r,
        exp.synthetic_law(),
        exp.file.reference.as_ref().and_then(|r| r.s_r_m),
    ) {
        (Some(v), _, _) => (v, "--s-r"),
        (None, Some(l), _) => (l.s_r, "synthetic truth"),
        (None, None, Some(v)) => (v, "reference value"),
        _ => bail!("{}: no s_r to compare with: pass --s-r", exp.path.display()),
    };
    if a.s_r.is_some() {
        crate::config::s_r("--s-r", s_r)?;
    }
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
    if a.json {
        return Ok(serde_json::to_string_pretty(&c)? + "\n");
    }
    let mut o = String::new();
    let _ = writeln!(o, "wire torsion, {} (Appendix A)", exp.name);
    for (k, v) in crate::report::torsion_rows(&c, from) {
        let _ = writeln!(o, "  {k:<38} {v}");
    }
    Ok(o)
}
