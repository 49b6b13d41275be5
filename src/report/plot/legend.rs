//! The legend: its size, its corner and its drawing.

use anyhow::Result;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axes::text_width;
use super::chart::{draw_err, Chart, Kind, Series};
use super::lines::{Prepared, Shape};
use super::{
    CIRCLE_RADIUS, CROSS_HALF, DASH, DOT_RADIUS, FONT, GAP, LEGEND_FONT, LEGEND_GLYPH,
    LEGEND_MARGIN, LINE_WIDTH, MARKER_RADIUS, MARKER_STROKE,
};

/// Height of one legend row in pixels.
const LEGEND_ROW: i32 = 19;

/// Estimated legend box size in pixels. The text width gets 10 % extra, as
/// common sans-serif faces with wide digits run longer than the estimate.
pub(super) fn legend_size(labels: &[&str]) -> (i32, i32) {
    let text = labels
        .iter()
        .map(|s| text_width(LEGEND_FONT, s))
        .max()
        .unwrap_or(0) as i32
        * 11
        / 10;
    let m = LEGEND_MARGIN as i32;
    (
        m + LEGEND_GLYPH as i32 + text + m,
        2 * m + LEGEND_ROW * labels.len() as i32,
    )
}

/// Draws the legend box with its upper left corner at `(x0, y0)`.
pub(super) fn draw_legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart,
    (x0, y0): (i32, i32),
) -> Result<()> {
    let entries: Vec<&Series> = chart
        .series
        .iter()
        .filter(|s| !s.label.is_empty())
        .collect();
    let labels: Vec<&str> = entries.iter().map(|s| s.label.as_str()).collect();
    let (w, h) = legend_size(&labels);
    let corners = [(x0, y0), (x0 + w, y0 + h)];
    root.draw(&Rectangle::new(corners, WHITE.mix(0.88).filled()))
        .map_err(draw_err)?;
    root.draw(&Rectangle::new(corners, RGBColor(170, 170, 170)))
        .map_err(draw_err)?;
    let font = (FONT, LEGEND_FONT)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let m = LEGEND_MARGIN as i32;
    for (i, series) in entries.iter().enumerate() {
        let y = y0 + m + LEGEND_ROW * i as i32 + LEGEND_ROW / 2;
        let x = x0 + m;
        let text_x = x + LEGEND_GLYPH as i32;
        root.draw(&Text::new(series.label.as_str(), (text_x, y), font.clone()))
            .map_err(draw_err)?;
        let color = series.color.color();
        let line = color.stroke_width(LINE_WIDTH);
        let thin = color.stroke_width(MARKER_STROKE);
        let fill = color.filled();
        let centre = (x + 11, y);
        match series.kind {
            Kind::Line => root.draw(&PathElement::new(vec![(x, y), (x + 22, y)], line)),
            Kind::Dashed => root.draw(&DashedPathElement::new(
                vec![(x, y), (x + 2 * DASH + GAP, y)],
                DASH,
                GAP,
                line,
            )),
            Kind::Dots => root.draw(&Circle::new(centre, DOT_RADIUS, fill)),
            Kind::Circles => root.draw(&Circle::new(centre, CIRCLE_RADIUS, thin)),
            Kind::Markers => root.draw(&Circle::new(centre, MARKER_RADIUS, fill)),
            Kind::Crosses => root.draw(&Cross::new(centre, CROSS_HALF, thin)),
        }
        .map_err(draw_err)?;
    }
    Ok(())
}

/// How far around the legend box a plotted point still counts as under it, px: the
/// largest marker's radius and its stroke, so that no marker is half covered.
const LEGEND_CLEARANCE: i32 = (CIRCLE_RADIUS + MARKER_STROKE) as i32;

/// The legend's corner inside the plot `(left, top, right, bottom)`: the upper left
/// point of the box in the first of upper right, upper left, lower right and lower left
/// whose box (widened by [`LEGEND_CLEARANCE`]) covers no drawn data (markers, and lines
/// sampled about every 3 pixels); `None` when every corner covers some.
pub(super) fn legend_corner(
    prepared: &[Prepared],
    (left, top, right, bottom): (i32, i32, i32, i32),
    (w, h): (i32, i32),
) -> Option<(i32, i32)> {
    let inset = 6;
    let corners = [
        (right - w - inset, top + inset),
        (left + inset, top + inset),
        (right - w - inset, bottom - h - inset),
        (left + inset, bottom - h - inset),
    ];
    let covers = |inside: &dyn Fn((i32, i32)) -> bool| -> bool {
        prepared.iter().any(|prep| match prep.shape {
            Shape::Points(_) => prep.pixels.iter().flatten().any(|p| inside(*p)),
            Shape::Pieces(_) => prep.pixels.iter().any(|piece| {
                piece
                    .windows(2)
                    .any(|seg| segment_covered(seg[0], seg[1], inside))
            }),
        })
    };
    let c = LEGEND_CLEARANCE;
    corners.into_iter().find(|&(x0, y0)| {
        !covers(&|(x, y)| x >= x0 - c && x <= x0 + w + c && y >= y0 - c && y <= y0 + h + c)
    })
}

/// Whether a sample of the segment a-b, about every 3 pixels, falls inside a box.
fn segment_covered(a: (i32, i32), b: (i32, i32), inside: &dyn Fn((i32, i32)) -> bool) -> bool {
    let (dx, dy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
    let n = ((dx.abs().max(dy.abs()) / 3.0).ceil() as usize).max(1);
    (0..n).any(|i| {
        let t = i as f64 / n as f64;
        inside((a.0 + (t * dx).round() as i32, a.1 + (t * dy).round() as i32))
    })
}
