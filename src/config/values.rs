//! Checks of single values, each naming its key (or flag), the value as given and the
//! range it must lie in.

use anyhow::{bail, Result};

/// The side the detector works at (`video.work_side_px`, `detect --work-side`): from
/// the default 640 px to the largest frame's side.
pub fn work_side(key: &str, side: u32) -> Result<()> {
    if !(640..=8192).contains(&side) {
        bail!(
            "`{key}` = {side} px: expected 640 (the default) to 8192 px, the largest side \
             the detector may work at"
        );
    }
    Ok(())
}

/// A number as a message quotes it: `1e300` as written, not as 301 digits.
pub fn shown(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e6).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// The largest rolling-friction coefficient taken, m (`synthetic.s_r_m`, `--s-r`): a
/// lever arm of a centimetre is far beyond any rolling contact.
pub const MAX_S_R_M: f64 = 0.01;
/// The largest angle noise a twin may be given, deg.
pub const MAX_NOISE_DEG: f64 = 10.0;

/// A rolling-friction coefficient `s_r` given by `key`: zero to [`MAX_S_R_M`].
pub fn s_r(key: &str, v: f64) -> Result<()> {
    within(key, v, 0.0, MAX_S_R_M, "m")
}

/// A twin's per-frame angle noise given by `key`: zero to [`MAX_NOISE_DEG`].
pub fn noise_deg(key: &str, v: f64) -> Result<()> {
    within(key, v, 0.0, MAX_NOISE_DEG, "deg")
}

pub(super) fn positive(key: &str, v: f64, unit: &str) -> Result<()> {
    if !(v.is_finite() && v > 0.0) {
        bail!("`{key}` = {} {unit}: expected a positive number", shown(v));
    }
    Ok(())
}

pub(super) fn non_negative(key: &str, v: f64, unit: &str) -> Result<()> {
    if !(v.is_finite() && v >= 0.0) {
        bail!(
            "`{key}` = {} {unit}: expected zero or a positive number",
            shown(v)
        );
    }
    Ok(())
}

/// A positive value no larger than `hi` (a physical bound: a typo such as `1e300` is
/// refused, naming the key, instead of reaching the fit).
pub(super) fn bounded(key: &str, v: f64, hi: f64, unit: &str) -> Result<()> {
    positive(key, v, unit)?;
    if v > hi {
        bail!("`{key}` = {v:e} {unit}: expected at most {hi} {unit} (a table-top pendulum)");
    }
    Ok(())
}

pub(super) fn in_range(key: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<()> {
    if !(v.is_finite() && v > lo && v < hi) {
        bail!(
            "`{key}` = {} {unit}: expected a value between {lo} and {hi} {unit}",
            shown(v)
        );
    }
    Ok(())
}

/// A value from `lo` to `hi`, both included.
pub(super) fn within(key: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<()> {
    if !(v.is_finite() && v >= lo && v <= hi) {
        bail!(
            "`{key}` = {} {unit}: expected a value from {lo} to {hi} {unit}",
            shown(v)
        );
    }
    Ok(())
}
