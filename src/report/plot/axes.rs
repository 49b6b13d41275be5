//! Axis ranges and tick labels.

use anyhow::{bail, Result};
use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;

use super::chart::Chart;
use super::DATA_MARGIN;

/// The x and y ranges of the axes.
pub(super) fn axis_ranges(chart: &Chart) -> Result<((f64, f64), (f64, f64))> {
    let fixed = |r: Option<(f64, f64)>, name: &str| -> Result<Option<(f64, f64)>> {
        match r {
            None => Ok(None),
            Some((a, b)) if a.is_finite() && b.is_finite() => Ok(Some((a.min(b), a.max(b)))),
            Some((a, b)) => bail!("{name} range ({a}, {b}) is not finite"),
        }
    };
    let fx = fixed(chart.x_range, "x")?;
    let fy = fixed(chart.y_range, "y")?;
    let within = |v: f64, r: Option<(f64, f64)>| r.is_none_or(|(lo, hi)| v >= lo && v <= hi);
    let finite = || {
        chart
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|(x, y)| x.is_finite() && y.is_finite())
    };
    let x = match fx {
        Some(r) => r,
        None => data_range(finite().filter(|p| within(p.1, fy)).map(|p| p.0)),
    };
    let y = match fy {
        Some(r) => r,
        None => data_range(finite().filter(|p| within(p.0, fx)).map(|p| p.1)),
    };
    Ok((widen(x), widen(y)))
}

/// Range of the values with the data margin, or (0, 1) without values.
fn data_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if lo > hi {
        return (0.0, 1.0);
    }
    let pad = (hi - lo) * DATA_MARGIN;
    (lo - pad, hi + pad)
}

/// Widens a range too narrow to carry ticks, and keeps its span finite.
pub(super) fn widen((lo, hi): (f64, f64)) -> (f64, f64) {
    let (lo, hi) = (lo.max(-f64::MAX / 4.0), hi.min(f64::MAX / 4.0));
    let span = hi - lo;
    let scale = lo.abs().max(hi.abs());
    if span > scale * 1e-9 && span > 1e-200 {
        return (lo, hi);
    }
    let mid = lo / 2.0 + hi / 2.0;
    let half = if mid.abs() < 1e-200 {
        1.0
    } else {
        mid.abs() * 0.05
    };
    (mid - half, mid + half)
}

/// Number format shared by all tick labels of one axis.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct TickFormat {
    /// Decimal exponent of the tick step.
    step_exp: i32,
    /// Scientific notation (`3.2e-6`) rather than plain decimals.
    scientific: bool,
    /// The labels of the ticks the mesh will draw.
    pub(super) labels: Vec<String>,
}

impl TickFormat {
    pub(super) fn for_range((lo, hi): (f64, f64), max_ticks: usize) -> Self {
        let ticks = RangedCoordf64::from(lo..hi).key_points(max_ticks);
        let step = ticks
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .filter(|d| *d > 0.0)
            .fold(f64::INFINITY, f64::min);
        let step = if step.is_finite() { step } else { hi - lo };
        let step_exp = exponent(step);
        let max_abs = ticks.iter().fold(0.0_f64, |m, t| m.max(t.abs()));
        let scientific = max_abs > 0.0 && {
            let e = exponent(max_abs);
            !(-3..5).contains(&e)
        };
        let mut format = TickFormat {
            step_exp,
            scientific,
            labels: Vec::new(),
        };
        format.labels = ticks.iter().map(|&t| format.format(t)).collect();
        format
    }

    pub(super) fn format(&self, v: f64) -> String {
        let tiny = 10f64.powi(self.step_exp) * 1e-6;
        if v.abs() < tiny {
            return "0".to_string();
        }
        if self.scientific {
            let decimals = (exponent(v.abs()) - self.step_exp).clamp(0, 12) as usize;
            format!("{v:.decimals$e}")
        } else {
            let decimals = (-self.step_exp).clamp(0, 15) as usize;
            format!("{v:.decimals$}")
        }
    }
}

/// Decimal exponent of a positive number, robust to rounding just below a
/// power of ten.
fn exponent(v: f64) -> i32 {
    (v.log10() + 1e-9).floor() as i32
}

/// Estimated width in pixels of a text, as plotters estimates it without
/// font files.
pub(super) fn text_width(font: u32, text: &str) -> u32 {
    let em = font as f64 / 1.24 / 1.24;
    (em * 0.7 * text.chars().count() as f64).round() as u32
}
