//! Charts for reports, drawn as standalone SVG documents.
//!
//! A [`Chart`] is plain data: a title, axis labels, optional axis ranges and a
//! list of [`Series`]. [`render_svg`] turns it into a complete SVG document
//! that a browser shows through `<img src="...svg">`: it has no external
//! resources, its text is drawn as `<text>` elements in a generic
//! `sans-serif` family (no font file is read when building or rendering), and
//! the same chart always gives byte-identical output.
//!
//! Points that are not finite are left out; a line breaks where such a point
//! sits, unless the gap is too narrow to see (one pixel column or less).
//! Lines with many points are thinned before drawing: within each horizontal
//! pixel column only the first, lowest, highest and last point of a run are
//! kept, so a noisy series of a minute at 60 frames per second looks the same
//! as the full data but stays small. Repeated markers on the same pixel are
//! drawn once. Anything outside the axis ranges is clipped away.
//!
//! Dense marker series and long noisy dashed lines are not thinned further:
//! every visible marker and every dash is one SVG element, so tens of
//! thousands of scattered dots make a document of megabytes. Long measured
//! series are best drawn as lines.

mod axes;
mod chart;
mod layout;
mod legend;
mod lines;
mod render;
#[cfg(test)]
mod tests;

use anyhow::{anyhow, bail, Result};

pub use chart::{Chart, Kind, Rgb, Series};
use layout::Layout;
use render::{draw, LegendPlace};

/// Default drawing size in pixels (width, height).
pub const DEFAULT_SIZE: (u32, u32) = (760, 420);

/// Relative margin added on each side of a range taken from the data.
const DATA_MARGIN: f64 = 0.03;

/// Font family of all text; browsers pick their own sans-serif face.
const FONT: &str = "sans-serif";
/// Font sizes as plotters counts them: the SVG `font-size` is this / 1.24.
const TITLE_FONT: u32 = 20;
const DESC_FONT: u32 = 16;
const TICK_FONT: u32 = 14;
const LEGEND_FONT: u32 = 15;

/// Legend: width of the sample glyph area and inner margin, in pixels.
const LEGEND_GLYPH: u32 = 30;
const LEGEND_MARGIN: u32 = 8;

/// Marker sizes in pixels.
const DOT_RADIUS: u32 = 2;
const CIRCLE_RADIUS: u32 = 6;
const MARKER_RADIUS: u32 = 4;
const CROSS_HALF: u32 = 4;
const MARKER_STROKE: u32 = 2;
const LINE_WIDTH: u32 = 2;
/// Dash and gap length of dashed lines in pixels.
const DASH: i32 = 7;
const GAP: i32 = 5;

/// Gap between the plot and a legend placed to its right, in pixels.
const LEGEND_GAP: u32 = 10;

/// Draws the chart as a standalone SVG document.
///
/// Fails on a drawing size below 160 x 120 or above 20000 x 20000 pixels and
/// on a fixed range that is not finite.
pub fn render_svg(chart: &Chart) -> Result<String> {
    let (width, height) = chart.size;
    if !(160..=20_000).contains(&width) || !(120..=20_000).contains(&height) {
        bail!("chart size {width}x{height} is outside 160x120 .. 20000x20000 pixels");
    }
    let layout = Layout::new(chart)?;
    let Some((w, h)) = layout.legend else {
        return draw(chart, &layout, LegendPlace::Inside)?
            .ok_or_else(|| anyhow!("the chart was not drawn"));
    };
    // A legend that would hide data inside the plot goes to its right when that
    // leaves the plot two thirds of the width, else under the x axis's label.
    if let Some(svg) = draw(chart, &layout, LegendPlace::Inside)? {
        return Ok(svg);
    }
    let (outside, place) = if (w as u32 + 2 * LEGEND_GAP) * 3 <= width {
        let margin_right = layout.margin_right.max(w as u32 + 2 * LEGEND_GAP);
        (
            Layout {
                margin_right,
                ..layout
            },
            LegendPlace::Right,
        )
    } else {
        let margin_bottom = layout.margin_bottom + h as u32 + LEGEND_GAP;
        (
            Layout {
                margin_bottom,
                ..layout
            },
            LegendPlace::Below,
        )
    };
    draw(chart, &outside, place)?.ok_or_else(|| anyhow!("the chart legend found no place"))
}
