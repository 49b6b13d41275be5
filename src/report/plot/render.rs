//! Drawing one chart with plotters' SVG backend.

use anyhow::Result;
use plotters::prelude::*;

use super::chart::{draw_err, Chart, Kind};
use super::layout::Layout;
use super::legend::{draw_legend, legend_corner};
use super::lines::{Bounds, Prepared, Shape};
use super::{
    CIRCLE_RADIUS, CROSS_HALF, DASH, DESC_FONT, DOT_RADIUS, FONT, GAP, LEGEND_GAP, LINE_WIDTH,
    MARKER_RADIUS, MARKER_STROKE, TICK_FONT, TITLE_FONT,
};

/// Where the legend goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum LegendPlace {
    /// In the first corner of the plot that covers no data ([`legend_corner`]).
    Inside,
    /// To the right of the plot (the layout leaves room).
    Right,
    /// Under the x axis's label, from the plot's left edge (the layout leaves room).
    Below,
}

/// Draws the chart. With the legend [`LegendPlace::Inside`], gives `None` when every
/// corner would hide some data: the caller makes room outside the plot.
pub(super) fn draw(chart: &Chart, layout: &Layout, place: LegendPlace) -> Result<Option<String>> {
    let (width, height) = chart.size;
    let has_title = !chart.title.is_empty();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;

        let mut builder = ChartBuilder::on(&root);
        builder
            .margin_top(if has_title { 8 } else { 14 })
            .margin_left(8)
            .margin_bottom(layout.margin_bottom)
            .margin_right(layout.margin_right)
            .x_label_area_size(layout.x_area)
            .y_label_area_size(layout.y_area);
        if has_title {
            builder.caption(&chart.title, (FONT, TITLE_FONT));
        }
        let (xr, yr) = (layout.x_range, layout.y_range);
        let mut cc = builder
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(draw_err)?;

        let x_fmt = |v: &f64| layout.x_format.format(*v);
        let y_fmt = |v: &f64| layout.y_format.format(*v);
        let mut mesh = cc.configure_mesh();
        mesh.x_labels(layout.n_x)
            .y_labels(layout.n_y)
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .bold_line_style(RGBColor(222, 222, 222))
            .light_line_style(TRANSPARENT)
            .axis_style(RGBColor(90, 90, 90))
            .label_style((FONT, TICK_FONT).into_font().color(&RGBColor(40, 40, 40)))
            .axis_desc_style((FONT, DESC_FONT));
        if !chart.x_label.is_empty() {
            mesh.x_desc(chart.x_label.as_str());
        }
        if !chart.y_label.is_empty() {
            mesh.y_desc(chart.y_label.as_str());
        }
        mesh.draw().map_err(draw_err)?;

        let bounds = Bounds { x: xr, y: yr };
        let to_px = |p: &(f64, f64)| cc.backend_coord(p);
        let prepared: Vec<Prepared> = chart
            .series
            .iter()
            .map(|s| Prepared::new(s, &bounds, &to_px))
            .collect();

        // Decide on the legend place before drawing anything more.
        let (px, py) = cc.plotting_area().get_pixel_range();
        let plot = (px.start, py.start, px.end, py.end);
        let legend_at = match (layout.legend, place) {
            (None, _) => None,
            (Some(_), LegendPlace::Right) => Some((plot.2 + LEGEND_GAP as i32, plot.1)),
            (Some((_, h)), LegendPlace::Below) => Some((plot.0, height as i32 - 6 - h)),
            (Some(size), LegendPlace::Inside) => match legend_corner(&prepared, plot, size) {
                Some(corner) => Some(corner),
                None => return Ok(None),
            },
        };

        for (series, prep) in chart.series.iter().zip(&prepared) {
            let color = series.color.color();
            match &prep.shape {
                Shape::Pieces(pieces) => {
                    let style = color.stroke_width(LINE_WIDTH);
                    for piece in pieces {
                        let points = piece.iter().copied();
                        if series.kind == Kind::Dashed {
                            cc.draw_series(DashedLineSeries::new(points, DASH, GAP, style))
                        } else {
                            cc.draw_series(LineSeries::new(points, style))
                        }
                        .map_err(draw_err)?;
                    }
                }
                Shape::Points(points) => {
                    let pts = points.iter().copied();
                    let thin = color.stroke_width(MARKER_STROKE);
                    let fill = color.filled();
                    match series.kind {
                        Kind::Dots => cc.draw_series(pts.map(|p| Circle::new(p, DOT_RADIUS, fill))),
                        Kind::Circles => {
                            cc.draw_series(pts.map(|p| Circle::new(p, CIRCLE_RADIUS, thin)))
                        }
                        Kind::Crosses => {
                            cc.draw_series(pts.map(|p| Cross::new(p, CROSS_HALF, thin)))
                        }
                        Kind::Markers | Kind::Line | Kind::Dashed => {
                            cc.draw_series(pts.map(|p| Circle::new(p, MARKER_RADIUS, fill)))
                        }
                    }
                    .map_err(draw_err)?;
                }
            }
        }

        if let Some(corner) = legend_at {
            draw_legend(&root, chart, corner)?;
        }
        root.present().map_err(draw_err)?;
    }
    Ok(Some(svg))
}
