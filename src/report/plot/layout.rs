//! Sizes and tick formats fixed before drawing.

use anyhow::Result;

use super::axes::{axis_ranges, text_width, TickFormat};
use super::chart::Chart;
use super::legend::legend_size;
use super::TICK_FONT;

/// Sizes and formats fixed before drawing.
pub(super) struct Layout {
    pub(super) x_range: (f64, f64),
    pub(super) y_range: (f64, f64),
    pub(super) x_format: TickFormat,
    pub(super) y_format: TickFormat,
    pub(super) n_x: usize,
    pub(super) n_y: usize,
    pub(super) x_area: u32,
    pub(super) y_area: u32,
    pub(super) margin_right: u32,
    pub(super) margin_bottom: u32,
    /// Estimated legend size in pixels, when there is a legend.
    pub(super) legend: Option<(i32, i32)>,
}

impl Layout {
    pub(super) fn new(chart: &Chart) -> Result<Self> {
        let (width, height) = chart.size;
        let (x_range, y_range) = axis_ranges(chart)?;
        // Tick positions are computed here the same way the mesh computes
        // them, so that the labels share one number format and the label
        // area fits the widest label.
        let top = if chart.title.is_empty() { 14 } else { 38 };
        let x_area: u32 = if chart.x_label.is_empty() { 28 } else { 48 };
        let est_plot_h = height.saturating_sub(top + x_area + 10);
        let n_y = (est_plot_h / 40).clamp(2, 10) as usize;
        let y_format = TickFormat::for_range(y_range, n_y);
        let widest = |f: &TickFormat| {
            f.labels
                .iter()
                .map(|s| text_width(TICK_FONT, s))
                .max()
                .unwrap_or(0)
        };
        let y_area = widest(&y_format) + 16 + if chart.y_label.is_empty() { 0 } else { 24 };
        let est_plot_w = width.saturating_sub(y_area + 30);
        let n_x = (est_plot_w / 85).clamp(2, 10) as usize;
        let x_format = TickFormat::for_range(x_range, n_x);
        // Room for half of the last x tick label, which is centred on the
        // right end of the axis.
        let last_x = x_format.labels.last().map(|s| text_width(TICK_FONT, s));
        let margin_right = 22.max(last_x.unwrap_or(0) / 2 + 6);
        let labels: Vec<&str> = chart
            .series
            .iter()
            .filter(|s| !s.label.is_empty())
            .map(|s| s.label.as_str())
            .collect();
        let legend = if chart.legend && !labels.is_empty() {
            Some(legend_size(&labels))
        } else {
            None
        };
        Ok(Layout {
            x_range,
            y_range,
            x_format,
            y_format,
            n_x,
            n_y,
            x_area,
            y_area,
            margin_right,
            margin_bottom: 6,
            legend,
        })
    }
}
