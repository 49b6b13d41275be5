//! What a camera would record of the model: the wire angle per frame, measured from the
//! image x axis with the camera's constant offset (as the paper's detector writes it,
//! section 2.3.2), plus optional Gaussian measurement noise.

use crate::config::Experiment;
use crate::physics::ode::{integrate, OdeOptions, Trajectory};
use crate::physics::FrictionLaw;
use crate::rng::Rng;
use crate::series::AngleSeries;
use anyhow::{Context, Result};

/// Longest default recording, s.
pub const MAX_DEFAULT_DURATION_S: f64 = crate::config::DEFAULT_MAX_DURATION_S;

/// Camera settings for one simulated recording.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub fps: f64,
    /// Recording length, s; `None` = until the ball stops plus 2 s (at most 120 s).
    pub duration_s: Option<f64>,
    /// Standard deviation of the per-frame angle noise, rad.
    pub noise_rad: f64,
    pub seed: u64,
    /// Image angle of the wire at rest, rad.
    pub rest_angle_rad: f64,
    /// The ball is held at its release angle until this time, s (`synthetic.hold_s`).
    pub hold_s: f64,
}

/// The true motion and the camera's angle series of a synthetic experiment.
pub struct Recording {
    pub law: FrictionLaw,
    pub trajectory: Trajectory,
    pub series: AngleSeries,
}

/// The camera settings an experiment's `synthetic:` block asks for.
pub fn camera_of(exp: &Experiment) -> Result<Camera> {
    let s =
        exp.file.synthetic.as_ref().with_context(|| {
            format!("{}: no `synthetic:` block to simulate", exp.path.display())
        })?;
    Ok(Camera {
        fps: s.fps,
        duration_s: s.duration_s,
        noise_rad: s.angle_noise_deg.to_radians(),
        seed: s.seed,
        rest_angle_rad: s.rest_angle_deg.to_radians(),
        hold_s: s.hold_s.unwrap_or(0.0),
    })
}

/// Simulate the experiment's synthetic truth as the camera records it.
///
/// The ball is released from rest at `psi_0` at `t = hold_s` (0 unless the operator
/// holds it first: until then it stays at `psi_0`). The image angle is
/// `rest_angle - psi` (the image y axis points down, so the image's sense of rotation is
/// the opposite of the plate's).
pub fn record(exp: &Experiment, cam: &Camera) -> Result<Recording> {
    let s =
        exp.file.synthetic.as_ref().with_context(|| {
            format!("{}: no `synthetic:` block to simulate", exp.path.display())
        })?;
    let law = exp
        .synthetic_law()
        .with_context(|| format!("{}: `synthetic.beta` must be a number", exp.path.display()))?;
    let psi0 = s.psi0_deg.to_radians();
    let p = &exp.twin_pendulum();
    let full = OdeOptions {
        t_end: cam.duration_s.unwrap_or(MAX_DEFAULT_DURATION_S),
        ..OdeOptions::default()
    };
    let trajectory = integrate(p, &law, cam.hold_s, [psi0, 0.0], &full);
    let duration = cam.duration_s.unwrap_or_else(|| {
        trajectory.stopped_at.map_or(MAX_DEFAULT_DURATION_S, |t| {
            (t + 2.0).min(MAX_DEFAULT_DURATION_S)
        })
    });
    let frames = (duration * cam.fps).floor() as usize + 1;
    let mut rng = Rng::new(cam.seed);
    let mut series = AngleSeries::default();
    series.t.reserve(frames);
    series.angle.reserve(frames);
    for i in 0..frames {
        let t = i as f64 / cam.fps;
        let noise = if cam.noise_rad > 0.0 {
            cam.noise_rad * rng.normal()
        } else {
            0.0
        };
        series.t.push(t);
        series
            .angle
            .push(cam.rest_angle_rad - trajectory.state(t)[0] + noise);
    }
    Ok(Recording {
        law,
        trajectory,
        series,
    })
}
