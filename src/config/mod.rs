//! Experiment files and the manifest that lists them.
//!
//! YAML is read with `serde-saphyr`: maintained (`serde_yaml` is archived upstream), pure
//! Rust with no `unsafe`-heavy C binding, and it reports the line and column of a bad
//! value. Every struct rejects unknown keys, so a typo is an error that names the key
//! and lists the valid ones instead of a silently ignored field.
//!
//! Units are in the key names (`_m`, `_kg`, `_deg`, `_s`); inside the program
//! everything is SI with angles in radians.

use crate::fsutil;
use crate::physics::{BetaChoice, FrictionLaw, Pendulum};
use anyhow::{bail, ensure, Context, Result};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

mod air;
mod file;
mod geometry;
pub mod schema;
mod synthetic;
mod values;
mod yaml;

pub use air::*;
pub use file::*;
use geometry::ball_density;
pub use geometry::pendulum_of;
pub use synthetic::*;
use values::{bounded, in_range, non_negative, positive, within};
pub use values::{noise_deg, s_r, shown, work_side, MAX_NOISE_DEG, MAX_S_R_M};
pub(crate) use yaml::quoted;
use yaml::{yaml_error, EXPERIMENT_KEYS, MANIFEST_KEYS};

/// `experiments/manifest.yaml`: which experiments make up the reports.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Title of the report set. Default: "Rolling friction".
    #[serde(default = "default_title")]
    pub title: String,
    /// Experiment files, relative to the manifest's folder, in report order.
    pub experiments: Vec<String>,
}

fn default_title() -> String {
    "Rolling friction".into()
}

impl Manifest {
    /// Load a manifest and check that each listed file exists.
    pub fn load(path: &Path) -> Result<(Self, Vec<PathBuf>)> {
        let text = fsutil::read_text_limited(path, fsutil::MAX_YAML_BYTES)?;
        Self::load_text(path, &text)
    }

    /// [`Manifest::load`] of `text`, the content of (or for) the file `path`.
    pub fn load_text(path: &Path, text: &str) -> Result<(Self, Vec<PathBuf>)> {
        let text = text.to_string();
        let m: Manifest = serde_saphyr::from_str(&text).map_err(|e| {
            yaml_error(&e, &text, MANIFEST_KEYS, "a manifest").context(path.display().to_string())
        })?;
        if m.experiments.is_empty() {
            bail!("{}: `experiments` lists no experiment", path.display());
        }
        text_limit("title", &m.title, MAX_TITLE_CHARS).context(path.display().to_string())?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let files = m.experiments.iter().map(|e| dir.join(e)).collect();
        Ok((m, files))
    }
}

/// A loaded, validated experiment with its derived quantities.
#[derive(Debug, Clone)]
pub struct Experiment {
    pub path: PathBuf,
    pub name: String,
    pub material: String,
    pub file: ExperimentFile,
    pub pendulum: Pendulum,
    pub beta: BetaChoice,
    /// The plate calibration `video.calibration` fixes (fitted when the file is read).
    pub calibration: Option<crate::plane::Calibration>,
}

/// The longest experiment name, characters (it names files and folders).
pub const MAX_NAME_CHARS: usize = 64;
/// The longest one-line text shown on pages (`material`, the manifest's `title`,
/// `reference.source`), characters.
pub const MAX_TITLE_CHARS: usize = 120;
/// The longest paragraph shown on pages (`notes`, an accepted warning's reason).
pub const MAX_NOTES_CHARS: usize = 4000;

/// Refuse a text key longer than `max` characters: every value echoed into a page, the
/// summary or an error is bounded.
fn text_limit(key: &str, value: &str, max: usize) -> Result<()> {
    let n = value.chars().count();
    if n > max {
        bail!(
            "`{key}` = `{}`: {n} characters; at most {max} (it is shown on the pages)",
            quoted(value, 40)
        );
    }
    Ok(())
}

/// Fewest and most draws of the budget's Monte Carlo check (`monte_carlo_draws`).
pub const MIN_MONTE_CARLO_DRAWS: usize = 100;
pub const MAX_MONTE_CARLO_DRAWS: usize = 100_000;

/// The highest frame rate a digital twin may be asked for, frames/s.
pub const MAX_FPS: f64 = 1000.0;
/// The longest recording a digital twin may be asked for, s.
pub const MAX_DURATION_S: f64 = 3600.0;
/// The most frames (frame rate x duration) a twin may be asked to simulate or render:
/// every per-frame vector is sized from this before anything is allocated.
pub const MAX_FRAMES: f64 = 200_000.0;
/// The recording length used when none is given (until the ball stops, at most this), s.
pub const DEFAULT_MAX_DURATION_S: f64 = 120.0;

/// Check a twin's frame rate and duration against the budgets above, before anything
/// is allocated; errors name the key (or flag) and the limit.
pub fn frame_budget(fps: (&str, f64), duration: (&str, Option<f64>)) -> Result<()> {
    let (fk, f) = fps;
    if !(f.is_finite() && f > 0.0 && f <= MAX_FPS) {
        bail!("`{fk}` = {f} frames/s: expected more than 0 and at most {MAX_FPS}");
    }
    let (dk, d) = duration;
    if let Some(d) = d {
        if !(d.is_finite() && d > 0.0 && d <= MAX_DURATION_S) {
            bail!("`{dk}` = {d} s: expected more than 0 and at most {MAX_DURATION_S}");
        }
    }
    let frames = f * d.unwrap_or(DEFAULT_MAX_DURATION_S);
    if frames > MAX_FRAMES {
        bail!(
            "`{fk}` x `{dk}` = {frames:.0} frames: at most {MAX_FRAMES:.0} frames may be simulated or rendered"
        );
    }
    Ok(())
}

/// Parse a `beta` value; `key` names it in errors.
pub fn parse_beta(b: &BetaSpec, key: &str) -> Result<BetaChoice> {
    let v = match b {
        BetaSpec::Number(v) => *v,
        BetaSpec::Text(t) if t.trim() == "free" => return Ok(BetaChoice::Free),
        BetaSpec::Text(t) => {
            let parsed = match t.split_once('/') {
                Some((a, b)) => a
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .zip(b.trim().parse::<f64>().ok())
                    .map(|(a, b)| a / b),
                None => t.trim().parse::<f64>().ok(),
            };
            parsed.with_context(|| {
                format!(
                    "`{key}` = `{}`: expected a number, a fraction such as 4/3, or `free`",
                    quoted(t, 60)
                )
            })?
        }
    };
    if !(v.is_finite() && v > 0.0 && v <= 3.0) {
        bail!(
            "`{key}` = {}: expected an exponent greater than 0 and at most 3",
            shown(v)
        );
    }
    Ok(BetaChoice::Fixed(v))
}

impl Experiment {
    /// Read, parse and validate an experiment file. Every error names the file.
    pub fn load(path: &Path) -> Result<Self> {
        Ok(Self::load_with_bytes(path)?.0)
    }

    /// [`Experiment::load`], also returning the file's bytes (for cache keys and
    /// provenance). A file that is not UTF-8 text is refused, naming the byte.
    pub fn load_with_bytes(path: &Path) -> Result<(Self, Vec<u8>)> {
        let bytes = fsutil::read_limited(path, fsutil::MAX_YAML_BYTES)?;
        let text = std::str::from_utf8(&bytes).map_err(|e| {
            anyhow::anyhow!(
                "{}: not UTF-8 text (invalid byte at offset {})",
                path.display(),
                e.valid_up_to()
            )
        })?;
        let exp = Self::parse(path, text).with_context(|| format!("{}", path.display()))?;
        Ok((exp, bytes))
    }

    /// Parse and validate experiment YAML; errors name the key, its value and what was
    /// expected (the caller adds the file name).
    pub fn parse(path: &Path, text: &str) -> Result<Self> {
        let file: ExperimentFile = serde_saphyr::from_str(text)
            .map_err(|e| yaml_error(&e, text, EXPERIMENT_KEYS, "an experiment file"))?;
        let name = file.name.clone().unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "experiment".into())
        });
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            bail!(
                "`name` = `{}`: expected letters, digits, `-` or `_` only (it names output files)",
                quoted(&name, 60)
            );
        }
        text_limit("name", &name, MAX_NAME_CHARS)?;
        let material = file.material.clone().unwrap_or_else(|| name.clone());
        text_limit("material", &material, MAX_TITLE_CHARS)?;
        text_limit("notes", &file.notes, MAX_NOTES_CHARS)?;
        if let Some(p) = &file.pair {
            text_limit("pair", p, MAX_TITLE_CHARS)?;
            if p.trim().is_empty() {
                bail!(
                    "`pair` is empty: name the material pair (`glass-steel`), or leave the key out"
                );
            }
        }
        if let Some(r) = &file.reference {
            text_limit("reference.source", &r.source, MAX_TITLE_CHARS)?;
        }
        for (i, a) in file.accept.iter().enumerate() {
            text_limit(&format!("accept[{i}].reason"), &a.reason, MAX_NOTES_CHARS)?;
        }
        let tol = &file.tolerances;
        text_limit("tolerances.reason", &tol.reason, MAX_NOTES_CHARS)?;
        if let Some((key, v, d)) = tol.widened().first() {
            if tol.reason.trim().is_empty() {
                bail!(
                    "`tolerances.{key}` = {}: wider than its default {}; a wider tolerance \
                     needs a written reason (`tolerances.reason`), shown with the result",
                    shown(*v),
                    shown(*d)
                );
            }
        }
        file.air.check("air")?;
        if let Some(a) = file.synthetic.as_ref().and_then(|s| s.air.as_ref()) {
            a.check("synthetic.air")?;
        }
        let pendulum = pendulum_of(&file.geometry)?.with_air(file.air.air());
        ball_density(&file.geometry.ball, pendulum.m, pendulum.r)?;
        let beta = parse_beta(&file.model.beta, "model.beta")?;
        let u = &file.geometry.uncertainty;
        for (k, v) in [
            ("geometry.uncertainty.h_m", u.h_m),
            ("geometry.uncertainty.l_m", u.l_m),
            ("geometry.uncertainty.angle_deg", u.angle_deg),
            ("geometry.uncertainty.d_m", u.d_m),
            ("geometry.uncertainty.contact_length_m", u.contact_length_m),
            ("geometry.uncertainty.radius_m", u.radius_m),
            ("geometry.uncertainty.mass_kg", u.mass_kg),
            ("geometry.uncertainty.density_kg_m3", u.density_kg_m3),
            ("geometry.uncertainty.g_m_s2", u.g_m_s2),
        ] {
            if let Some(v) = v {
                non_negative(k, v, "")?;
            }
        }
        if let Some(n) = file.monte_carlo_draws {
            if !(MIN_MONTE_CARLO_DRAWS..=MAX_MONTE_CARLO_DRAWS).contains(&n) {
                bail!("`monte_carlo_draws` = {n}: expected {MIN_MONTE_CARLO_DRAWS}..{MAX_MONTE_CARLO_DRAWS} (each draw is a fit)");
            }
        }
        if let Some(t) = &file.torsion {
            positive("torsion.period_s", t.period_s, "s")?;
            positive("torsion.wire_length_m", t.wire_length_m, "m")?;
            in_range("torsion.psi0_max_deg", t.psi0_max_deg, 0.0, 90.0, "deg")?;
        }
        if let Some(s) = &file.sliding {
            positive("sliding.mu", s.mu, "")?;
        }
        if let Some(r) = &file.reference {
            for (k, v) in [
                ("reference.s_r_m", r.s_r_m),
                ("reference.mu_r", r.mu_r),
                ("reference.a_rad_s", r.a_rad_s),
            ] {
                if let Some(v) = v {
                    positive(k, v, "")?;
                }
            }
        }
        positive(
            "tolerances.reference_rel",
            file.tolerances.reference_rel,
            "",
        )?;
        positive("tolerances.truth_rel", file.tolerances.truth_rel, "")?;
        let t = &file.tolerances;
        positive("tolerances.period_rel", t.period_rel, "")?;
        positive("tolerances.residual_factor", t.residual_factor, "")?;
        positive("tolerances.envelope_aicc", t.envelope_aicc, "")?;
        positive("tolerances.halves_rel", t.halves_rel, "")?;
        positive("tolerances.interval_rel", t.interval_rel, "")?;
        for (i, a) in file.accept.iter().enumerate() {
            if !CHECKS.contains(&a.check.as_str()) {
                bail!(
                    "`accept[{i}].check` = `{}`: expected one of {}",
                    quoted(&a.check, 60),
                    CHECKS.join(", ")
                );
            }
            if a.reason.trim().is_empty() {
                bail!(
                    "`accept[{i}].reason`: accepting the `{}` warning needs a written reason",
                    quoted(&a.check, 60)
                );
            }
        }
        if let Some(side) = file.video.as_ref().and_then(|v| v.work_side_px) {
            work_side("video.work_side_px", side)?;
        }
        let calibration = file
            .video
            .as_ref()
            .and_then(|v| v.calibration.as_ref())
            .map(plate_calibration)
            .transpose()?;
        if let Some(l) = file.video.as_ref().and_then(|v| v.lens) {
            within("video.lens.k1", l.k1, -0.5, 0.5, "")?;
            within("video.lens.u_k1", l.u_k1, 0.0, 0.5, "")?;
            ensure!(
                calibration.is_none(),
                "`video.lens` with `video.calibration`: not supported (the calibration's \
                 image points would have to be undistorted first); give one of them"
            );
        }
        if let Some(s) = &file.synthetic {
            self::s_r("synthetic.s_r_m", s.s_r_m)?;
            if parse_beta(&s.beta, "synthetic.beta")? == BetaChoice::Free {
                bail!("`synthetic.beta` = free: the simulated truth needs a number");
            }
            in_range("synthetic.psi0_deg", s.psi0_deg, 0.0, 60.0, "deg")?;
            noise_deg("synthetic.angle_noise_deg", s.angle_noise_deg)?;
            frame_budget(
                ("synthetic.fps", s.fps),
                ("synthetic.duration_s", s.duration_s),
            )?;
            if s.width < 64 || s.height < 64 || s.width > 7680 || s.height > 4320 {
                bail!(
                    "`synthetic.width` x `synthetic.height` = {} x {} px: expected 64..7680 x 64..4320",
                    s.width,
                    s.height
                );
            }
            if !s.rest_angle_deg.is_finite() {
                bail!(
                    "`synthetic.rest_angle_deg` = {}: expected a finite angle",
                    s.rest_angle_deg
                );
            }
            if let Some(w) = s.wire_width_px {
                within("synthetic.wire_width_px", w, 1.0, 32.0, "px")?;
            }
            if let Some(c) = s.wire_contrast {
                within("synthetic.wire_contrast", c, 0.0, 1.0, "")?;
            }
            if let Some(sh) = &s.shadow {
                within(
                    "synthetic.shadow.angle_deg",
                    sh.angle_deg,
                    -45.0,
                    45.0,
                    "deg",
                )?;
                within("synthetic.shadow.blur_px", sh.blur_px, 0.0, 50.0, "px")?;
                within("synthetic.shadow.strength", sh.strength, 0.0, 1.0, "")?;
                if let Some(l) = sh.lamp_share {
                    within("synthetic.shadow.lamp_share", l, 0.0, 1.0, "")?;
                }
            }
            if let Some(f) = s.flicker_hz {
                positive("synthetic.flicker_hz", f, "Hz")?;
                within("synthetic.flicker_hz", f, 0.0, 10_000.0, "Hz")?;
            }
            if let Some(d) = s.flicker_depth {
                within("synthetic.flicker_depth", d, 0.0, 0.5, "")?;
            }
            if let Some(d) = s.drift_depth {
                within("synthetic.drift_depth", d, 0.0, 0.5, "")?;
            }
            if let Some(k) = &s.shake {
                within("synthetic.shake.px", k.px, 0.0, 50.0, "px")?;
                within("synthetic.shake.deg", k.deg, 0.0, 5.0, "deg")?;
                within("synthetic.shake.hz", k.hz, 0.05, 30.0, "Hz")?;
                within("synthetic.shake.drift_px", k.drift_px, 0.0, 500.0, "px")?;
            }
            if let Some(q) = s.crf {
                ensure!(
                    q <= 51,
                    "`synthetic.crf` = {q}: expected 0 to 51 (x264's constant rate factor)"
                );
            }
            if let Some(k) = s.lens_k1 {
                within("synthetic.lens_k1", k, -0.5, 0.5, "")?;
            }
            if let Some(r) = &s.room {
                ensure!(
                    r.edges <= 6,
                    "`synthetic.room.edges` = {}: expected 0 to 6",
                    r.edges
                );
                if let Some(t) = r.walker_s {
                    within("synthetic.room.walker_s", t, 0.0, 3600.0, "s")?;
                }
            }
            if let Some(p) = s.pivot_frac {
                for (k, v) in ["synthetic.pivot_frac[0]", "synthetic.pivot_frac[1]"]
                    .into_iter()
                    .zip(p)
                {
                    within(k, v, -1.0, 2.0, "")?;
                }
            }
            if let Some(j) = s.vfr_jitter {
                within("synthetic.vfr_jitter", j, 0.0, 0.9, "")?;
                if j > 0.0 && (1.0 - j) / s.fps < 0.002 {
                    bail!("`synthetic.vfr_jitter` = {j} at `synthetic.fps` = {}: frames would come less than 2 ms apart (the times are whole milliseconds)", s.fps);
                }
            }
            if let Some(p) = s.dropped_share {
                within("synthetic.dropped_share", p, 0.0, 0.2, "")?;
            }
            if let Some(r) = s.rolling_shutter {
                within("synthetic.rolling_shutter", r, 0.0, 1.0, "")?;
            }
            if let Some(t) = s.camera_tilt_deg {
                within("synthetic.camera_tilt_deg", t, 0.0, 40.0, "deg")?;
                if t > 0.0 && s.mirror {
                    bail!("`synthetic.camera_tilt_deg` = {t} with `synthetic.mirror`: a tilted camera's twin is not mirrored (its truth is in plate angles)");
                }
            }
            if let Some(a) = s.tilt_axis_deg {
                within("synthetic.tilt_axis_deg", a, -360.0, 360.0, "deg")?;
            }
            if let Some(f) = s.camera_focal_px {
                let w = s.width as f64;
                within("synthetic.camera_focal_px", f, 0.3 * w, 10.0 * w, "px")?;
            }
            if s.release_hand && !s.hold_s.is_some_and(|h| h > 0.0) {
                bail!("`synthetic.release_hand` without `synthetic.hold_s`: the hand releases a ball held for a while (set `hold_s`)");
            }
            if let Some(h) = s.hold_s {
                non_negative("synthetic.hold_s", h, "s")?;
                let most = s.duration_s.unwrap_or(DEFAULT_MAX_DURATION_S);
                if h >= most {
                    bail!("`synthetic.hold_s` = {h} s: expected less than the recording's {most} s (`synthetic.duration_s`)");
                }
            }
        }
        Ok(Self {
            path: path.to_path_buf(),
            name,
            material,
            file,
            pendulum,
            beta,
            calibration,
        })
    }

    /// The synthetic truth's friction law, if the experiment has one.
    pub fn synthetic_law(&self) -> Option<FrictionLaw> {
        let s = self.file.synthetic.as_ref()?;
        match parse_beta(&s.beta, "synthetic.beta") {
            Ok(BetaChoice::Fixed(b)) => Some(FrictionLaw::new(s.s_r_m, b)),
            _ => None,
        }
    }

    /// The twin's pendulum: the experiment's, in the air `synthetic.air` names (the
    /// experiment's own `air` when it names none).
    pub fn twin_pendulum(&self) -> Pendulum {
        let air = self
            .file
            .synthetic
            .as_ref()
            .and_then(|s| s.air.as_ref())
            .unwrap_or(&self.file.air);
        self.pendulum.with_air(air.air())
    }

    /// A path given in the file, resolved against the file's folder.
    pub fn resolve(&self, rel: &str) -> PathBuf {
        self.path.parent().unwrap_or(Path::new(".")).join(rel)
    }
}

/// `video.calibration`: four or more finite points that fix a homography.
fn plate_calibration(c: &PlateCalibration) -> Result<crate::plane::Calibration> {
    let key = "video.calibration.points";
    if c.points.len() < 4 {
        bail!(
            "`{key}`: {} point(s); a plate calibration needs at least four",
            c.points.len()
        );
    }
    for (i, p) in c.points.iter().enumerate() {
        if !p.image.iter().chain(&p.plate).all(|v| v.is_finite()) {
            bail!(
                "`{key}[{i}]` = image {:?}, plate {:?}: expected finite numbers",
                p.image,
                p.plate
            );
        }
    }
    if let Some(u) = c.u_px {
        positive("video.calibration.u_px", u, "px")?;
        bounded("video.calibration.u_px", u, 100.0, "px")?;
    }
    let image: Vec<[f64; 2]> = c.points.iter().map(|p| p.image).collect();
    let plate: Vec<[f64; 2]> = c.points.iter().map(|p| p.plate).collect();
    crate::plane::Calibration::new(&image, &plate, c.u_px).with_context(|| format!("`{key}`"))
}

/// Find an experiment by path, or by name: `NAME.yaml` in the working folder first,
/// then in `experiments/`.
pub fn locate(arg: &str) -> PathBuf {
    locate_in(Path::new(""), arg)
}

/// [`locate`] from the folder `base` (the paths returned are `base` joined).
fn locate_in(base: &Path, arg: &str) -> PathBuf {
    let p = base.join(arg);
    if p.exists() || arg.ends_with(".yaml") || arg.ends_with(".yml") || arg.contains('/') {
        return p;
    }
    let here = base.join(format!("{arg}.yaml"));
    if here.exists() {
        return here;
    }
    base.join("experiments").join(format!("{arg}.yaml"))
}

#[cfg(test)]
mod tests;
