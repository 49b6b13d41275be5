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

use std::collections::HashSet;

use anyhow::{anyhow, bail, Result};
use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

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

/// A colour given by its red, green and blue parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    pub const BLUE: Rgb = Rgb(31, 119, 180);
    pub const RED: Rgb = Rgb(214, 39, 40);
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const GREEN: Rgb = Rgb(44, 160, 44);
    pub const ORANGE: Rgb = Rgb(255, 127, 14);
    pub const GREY: Rgb = Rgb(127, 127, 127);
    pub const PURPLE: Rgb = Rgb(148, 103, 189);

    fn color(self) -> RGBColor {
        RGBColor(self.0, self.1, self.2)
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// Solid line through the points in their order.
    Line,
    /// Dashed line through the points in their order.
    Dashed,
    /// Small filled dots.
    Dots,
    /// Hollow circles of radius 6 px, to ring points drawn by another series.
    Circles,
    /// Filled circles of radius 4 px.
    Markers,
    /// Diagonal crosses.
    Crosses,
}

impl Kind {
    fn is_line(self) -> bool {
        matches!(self, Kind::Line | Kind::Dashed)
    }
}

/// One set of points drawn in one way and one colour.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Name shown in the legend; an empty label keeps the series out of it.
    pub label: String,
    pub kind: Kind,
    pub color: Rgb,
    /// Points as (x, y) in data units; points that are not finite are skipped.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A series of the given kind.
    pub fn new(label: &str, kind: Kind, color: Rgb, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            kind,
            color,
            points,
        }
    }

    /// A solid line.
    pub fn line(label: &str, color: Rgb, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, Kind::Line, color, points)
    }

    /// A dashed line.
    pub fn dashed(label: &str, color: Rgb, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, Kind::Dashed, color, points)
    }

    /// Small filled dots.
    pub fn dots(label: &str, color: Rgb, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, Kind::Dots, color, points)
    }

    /// Hollow circles, to mark points of another series.
    pub fn circles(label: &str, color: Rgb, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, Kind::Circles, color, points)
    }

    /// Filled circle markers.
    pub fn markers(label: &str, color: Rgb, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, Kind::Markers, color, points)
    }

    /// Cross markers.
    pub fn crosses(label: &str, color: Rgb, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, Kind::Crosses, color, points)
    }
}

/// A two-dimensional chart with linear axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// Caption above the plot; empty for none.
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// Drawing size in pixels (width, height).
    pub size: (u32, u32),
    /// Fixed x range; `None` takes it from the data with a 3 % margin.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None` takes it from the data (within a fixed x range)
    /// with a 3 % margin.
    pub y_range: Option<(f64, f64)>,
    /// Series in drawing order: later series are drawn on top.
    pub series: Vec<Series>,
    /// Show a legend when any series has a label. It goes in the upper right
    /// corner unless another corner covers clearly fewer data.
    pub legend: bool,
}

impl Chart {
    /// An empty chart of the default size with a legend.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Chart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            size: DEFAULT_SIZE,
            x_range: None,
            y_range: None,
            series: Vec::new(),
            legend: true,
        }
    }

    /// The chart with one more series.
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }
}

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
    match layout.legend {
        Some((w, _)) => {
            // A legend that would hide data inside the plot goes to its right.
            if let Some(svg) = draw(chart, &layout, false)? {
                return Ok(svg);
            }
            let outside = Layout {
                margin_right: layout.margin_right.max(w as u32 + 2 * LEGEND_GAP),
                ..layout
            };
            draw(chart, &outside, true)?.ok_or_else(|| anyhow!("the chart legend found no place"))
        }
        None => draw(chart, &layout, false)?.ok_or_else(|| anyhow!("the chart was not drawn")),
    }
}

/// Gap between the plot and a legend placed to its right, in pixels.
const LEGEND_GAP: u32 = 10;

/// Sizes and formats fixed before drawing.
struct Layout {
    x_range: (f64, f64),
    y_range: (f64, f64),
    x_format: TickFormat,
    y_format: TickFormat,
    n_x: usize,
    n_y: usize,
    x_area: u32,
    y_area: u32,
    margin_right: u32,
    /// Estimated legend size in pixels, when there is a legend.
    legend: Option<(i32, i32)>,
}

impl Layout {
    fn new(chart: &Chart) -> Result<Self> {
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
            legend,
        })
    }
}

/// Draws the chart. With the legend inside the plot, gives `None` when every
/// corner would hide a fair share of the data and there is room for the
/// legend to the right of the plot.
fn draw(chart: &Chart, layout: &Layout, legend_outside: bool) -> Result<Option<String>> {
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
            .margin_bottom(6)
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
        let legend_at = match layout.legend {
            None => None,
            Some(_) if legend_outside => Some((plot.2 + LEGEND_GAP as i32, plot.1)),
            Some(size) => {
                let (corner, hidden, total) = legend_corner(&prepared, plot, size);
                let room = (size.0 as u32 + 2 * LEGEND_GAP) * 3 <= width;
                if room && hidden > 2 && hidden * 100 > total {
                    return Ok(None);
                }
                Some(corner)
            }
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

fn draw_err<E: std::fmt::Display>(e: E) -> anyhow::Error {
    anyhow!("drawing the chart failed: {e}")
}

/// The x and y ranges of the axes.
fn axis_ranges(chart: &Chart) -> Result<((f64, f64), (f64, f64))> {
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
fn widen((lo, hi): (f64, f64)) -> (f64, f64) {
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
struct TickFormat {
    /// Decimal exponent of the tick step.
    step_exp: i32,
    /// Scientific notation (`3.2e-6`) rather than plain decimals.
    scientific: bool,
    /// The labels of the ticks the mesh will draw.
    labels: Vec<String>,
}

impl TickFormat {
    fn for_range((lo, hi): (f64, f64), max_ticks: usize) -> Self {
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

    fn format(&self, v: f64) -> String {
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
fn text_width(font: u32, text: &str) -> u32 {
    let em = font as f64 / 1.24 / 1.24;
    (em * 0.7 * text.chars().count() as f64).round() as u32
}

/// A point in data units.
type Point = (f64, f64);
/// Maps a point to backend pixels.
type ToPixel<'a> = dyn Fn(&Point) -> (i32, i32) + 'a;

/// Axis ranges as a clipping box.
struct Bounds {
    x: (f64, f64),
    y: (f64, f64),
}

impl Bounds {
    fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.x.0 && x <= self.x.1 && y >= self.y.0 && y <= self.y.1
    }

    /// The part of the segment a-b inside the box (Liang-Barsky), with the
    /// parameters where it starts and ends.
    fn clip(&self, a: Point, b: Point) -> Option<(Point, Point, f64, f64)> {
        if self.contains(a) && self.contains(b) {
            return Some((a, b, 0.0, 1.0));
        }
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let mut t0 = 0.0_f64;
        let mut t1 = 1.0_f64;
        for (p, q) in [
            (-dx, a.0 - self.x.0),
            (dx, self.x.1 - a.0),
            (-dy, a.1 - self.y.0),
            (dy, self.y.1 - a.1),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
        if t0 > t1 {
            return None;
        }
        let at = |t: f64| {
            if t == 0.0 {
                a
            } else if t == 1.0 {
                b
            } else {
                (a.0 + t * dx, a.1 + t * dy)
            }
        };
        Some((at(t0), at(t1), t0, t1))
    }
}

/// What is drawn of one series.
enum Shape {
    /// Polylines in data units, already clipped and thinned.
    Pieces(Vec<Vec<(f64, f64)>>),
    /// Marker positions in data units, inside the axes, one per pixel.
    Points(Vec<(f64, f64)>),
}

/// A series ready to draw, with the pixel positions used to place the legend.
struct Prepared {
    shape: Shape,
    /// Backend pixel positions of the drawn points or polyline vertices.
    pixels: Vec<Vec<(i32, i32)>>,
}

impl Prepared {
    fn new(series: &Series, bounds: &Bounds, to_px: &ToPixel<'_>) -> Self {
        if series.kind.is_line() {
            let pieces: Vec<Vec<(f64, f64)>> =
                join_pieces(clip_line(&series.points, bounds), to_px)
                    .into_iter()
                    .map(|piece| thin_line(&piece, to_px))
                    .filter(|piece| piece.len() >= 2)
                    .collect();
            let pixels = pieces
                .iter()
                .map(|piece| piece.iter().map(to_px).collect())
                .collect();
            Prepared {
                shape: Shape::Pieces(pieces),
                pixels,
            }
        } else {
            let mut seen = HashSet::new();
            let mut points = Vec::new();
            let mut pixels = Vec::new();
            for &p in &series.points {
                if p.0.is_finite() && p.1.is_finite() && bounds.contains(p) {
                    let px = to_px(&p);
                    if seen.insert(px) {
                        points.push(p);
                        pixels.push(px);
                    }
                }
            }
            Prepared {
                shape: Shape::Points(points),
                pixels: vec![pixels],
            }
        }
    }
}

/// Splits a line into the pieces that lie inside the bounds, breaking it at
/// points that are not finite. A piece may be a single point.
fn clip_line(points: &[(f64, f64)], bounds: &Bounds) -> Vec<Vec<(f64, f64)>> {
    let mut pieces = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let mut flush = |current: &mut Vec<(f64, f64)>| {
        if !current.is_empty() {
            pieces.push(std::mem::take(current));
        }
    };
    let mut prev: Option<(f64, f64)> = None;
    for &p in points {
        if !(p.0.is_finite() && p.1.is_finite()) {
            flush(&mut current);
            prev = None;
            continue;
        }
        match prev {
            None => {
                if bounds.contains(p) {
                    current.push(p);
                }
            }
            Some(a) => match bounds.clip(a, p) {
                None => flush(&mut current),
                Some((start, end, t0, t1)) => {
                    if t0 > 0.0 || current.is_empty() {
                        flush(&mut current);
                        current.push(start);
                    }
                    current.push(end);
                    if t1 < 1.0 {
                        flush(&mut current);
                    }
                }
            },
        }
        prev = Some(p);
    }
    flush(&mut current);
    pieces
}

/// Joins consecutive pieces of a line whose break is at most one pixel
/// column wide, where a gap could not be seen anyway.
fn join_pieces(pieces: Vec<Vec<Point>>, to_px: &ToPixel<'_>) -> Vec<Vec<Point>> {
    let mut joined: Vec<Vec<Point>> = Vec::with_capacity(pieces.len());
    for piece in pieces {
        if let (Some(prev), Some(first)) = (joined.last_mut(), piece.first()) {
            if let Some(last) = prev.last() {
                if (to_px(last).0 - to_px(first).0).abs() <= 1 {
                    prev.extend(piece);
                    continue;
                }
            }
        }
        joined.push(piece);
    }
    joined
}

/// Thins a polyline for drawing: of each run of points in the same pixel
/// column it keeps the first, lowest, highest and last, in their order, and
/// then drops points that land on the same pixel as the one before.
fn thin_line(points: &[(f64, f64)], to_px: &ToPixel<'_>) -> Vec<(f64, f64)> {
    let px: Vec<(i32, i32)> = points.iter().map(to_px).collect();
    let mut keep: Vec<usize> = Vec::with_capacity(points.len().min(4096));
    let mut start = 0;
    while start < px.len() {
        let column = px[start].0;
        let mut end = start;
        let (mut lo, mut hi) = (start, start);
        while end + 1 < px.len() && px[end + 1].0 == column {
            end += 1;
            if px[end].1 < px[lo].1 {
                lo = end;
            }
            if px[end].1 > px[hi].1 {
                hi = end;
            }
        }
        let mut run = [start, lo, hi, end];
        run.sort_unstable();
        for i in run {
            if keep.last() != Some(&i) {
                keep.push(i);
            }
        }
        start = end + 1;
    }
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(keep.len());
    let mut last_px = None;
    for i in keep {
        if last_px != Some(px[i]) {
            out.push(points[i]);
            last_px = Some(px[i]);
        }
    }
    // Keep the true end so that a line ends where its data ends.
    if let (Some(&end), Some(&drawn)) = (points.last(), out.last()) {
        if end != drawn {
            out.push(end);
        }
    }
    out
}

/// Height of one legend row in pixels.
const LEGEND_ROW: i32 = 19;

/// Estimated legend box size in pixels. The text width gets 10 % extra, as
/// common sans-serif faces with wide digits run longer than the estimate.
fn legend_size(labels: &[&str]) -> (i32, i32) {
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
fn draw_legend<DB: DrawingBackend>(
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

/// Picks the legend corner inside the plot `(left, top, right, bottom)`:
/// upper right unless another corner hides less than half as much of the
/// drawn data. Gives the upper left point of the box, how much data it hides
/// and how much there is in all, counted as samples about every 3 pixels
/// along lines and 4 per marker.
fn legend_corner(
    prepared: &[Prepared],
    (left, top, right, bottom): (i32, i32, i32, i32),
    (w, h): (i32, i32),
) -> ((i32, i32), usize, usize) {
    let inset = 6;
    let corners = [
        (right - w - inset, top + inset),
        (left + inset, top + inset),
        (right - w - inset, bottom - h - inset),
        (left + inset, bottom - h - inset),
    ];
    let count = |inside: &dyn Fn((i32, i32)) -> bool| -> usize {
        let mut count = 0;
        for prep in prepared {
            match prep.shape {
                Shape::Points(_) => {
                    count += 4 * prep.pixels.iter().flatten().filter(|p| inside(**p)).count();
                }
                Shape::Pieces(_) => {
                    for piece in &prep.pixels {
                        for seg in piece.windows(2) {
                            count += covered_samples(seg[0], seg[1], inside);
                        }
                    }
                }
            }
        }
        count
    };
    let hidden: Vec<usize> = corners
        .iter()
        .map(|&(x0, y0)| count(&|(x, y)| x >= x0 && x <= x0 + w && y >= y0 && y <= y0 + h))
        .collect();
    let total = count(&|_| true);
    let mut best = 0;
    for i in 1..corners.len() {
        if hidden[i] < hidden[best] {
            best = i;
        }
    }
    if hidden[best] * 2 >= hidden[0] {
        best = 0;
    }
    (corners[best], hidden[best], total)
}

/// Number of samples, about every 3 pixels along the segment a-b, that fall
/// inside a box.
fn covered_samples(a: (i32, i32), b: (i32, i32), inside: &dyn Fn((i32, i32)) -> bool) -> usize {
    let (dx, dy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
    let n = ((dx.abs().max(dy.abs()) / 3.0).ceil() as usize).max(1);
    (0..n)
        .filter(|&i| {
            let t = i as f64 / n as f64;
            inside((a.0 + (t * dx).round() as i32, a.1 + (t * dy).round() as i32))
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic noise in [-1, 1).
    fn noise(i: usize) -> f64 {
        let mut x = (i as u64)
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        x ^= x >> 33;
        x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
        x ^= x >> 33;
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    fn sine(n: usize) -> Vec<(f64, f64)> {
        (0..n)
            .map(|i| {
                let t = i as f64 / 60.0;
                (t, (t * 2.0).sin())
            })
            .collect()
    }

    /// Values of one attribute over all elements of one tag.
    fn attr_values(svg: &str, tag: &str, attr: &str) -> Vec<String> {
        tagged_values(svg, tag, "", attr)
    }

    /// Values of one attribute over the elements of one tag whose line
    /// contains `filter`.
    fn tagged_values(svg: &str, tag: &str, filter: &str, attr: &str) -> Vec<String> {
        svg.lines()
            .filter(|l| l.starts_with(&format!("<{tag} ")) && l.contains(filter))
            .filter_map(|l| {
                let key = format!(" {attr}=\"");
                let start = l.find(&key)? + key.len();
                let end = start + l[start..].find('"')?;
                Some(l[start..end].to_string())
            })
            .collect()
    }

    /// All vertices of the polylines of one colour.
    fn polyline_points(svg: &str, color: &str) -> Vec<(i32, i32)> {
        tagged_values(svg, "polyline", &format!("stroke=\"{color}\""), "points")
            .iter()
            .flat_map(|pts| {
                pts.split_whitespace()
                    .map(|p| {
                        let (x, y) = p.split_once(',').unwrap();
                        (x.parse().unwrap(), y.parse().unwrap())
                    })
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    /// Text of all `<text>` elements.
    fn texts(svg: &str) -> Vec<String> {
        let mut out = Vec::new();
        let mut rest = svg;
        while let Some(i) = rest.find("<text ") {
            rest = &rest[i..];
            let open = rest.find('>').unwrap() + 1;
            let close = rest.find("</text>").unwrap();
            out.push(rest[open..close].trim().to_string());
            rest = &rest[close..];
        }
        out
    }

    fn all_kinds() -> Chart {
        let pts = |k: f64| (0..12).map(|i| (i as f64, k + (i as f64).sin())).collect();
        Chart::new("Kinds", "x", "y")
            .with(Series::line("line", Rgb::BLUE, pts(0.0)))
            .with(Series::dashed("dashed", Rgb::RED, pts(3.0)))
            .with(Series::dots("dots", Rgb::GREEN, pts(6.0)))
            .with(Series::circles("circles", Rgb::ORANGE, pts(9.0)))
            .with(Series::markers("markers", Rgb::PURPLE, pts(12.0)))
            .with(Series::crosses("crosses", Rgb::GREY, pts(15.0)))
    }

    #[test]
    fn output_is_deterministic() {
        let chart = all_kinds().with(Series::line("long", Rgb::BLACK, sine(5000)));
        let a = render_svg(&chart).unwrap();
        let b = render_svg(&chart).unwrap();
        assert_eq!(a, b);
        let c = render_svg(&chart.clone()).unwrap();
        assert_eq!(a, c);
    }

    #[test]
    fn document_is_standalone_svg_with_text() {
        let chart = Chart::new("Angle <run 1> & more", "t (s)", "θ (rad)").with(Series::line(
            "measured",
            Rgb::BLUE,
            sine(600),
        ));
        let svg = render_svg(&chart).unwrap();
        assert!(svg.starts_with("<svg "));
        assert!(svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains(r#"xmlns="http://www.w3.org/2000/svg""#));
        assert!(svg.contains(r#"width="760" height="420" viewBox="0 0 760 420""#));
        assert!(svg.contains(r#"font-family="sans-serif""#));
        assert!(!svg.contains("href"), "no external resources");
        let texts = texts(&svg);
        for expected in [
            "Angle &lt;run 1&gt; &amp; more",
            "t (s)",
            "θ (rad)",
            "measured",
        ] {
            assert!(
                texts.iter().any(|t| t == expected),
                "{expected} in {texts:?}"
            );
        }
    }

    #[test]
    fn size_is_honoured_and_checked() {
        let mut chart = Chart::new("t", "x", "y").with(Series::line("", Rgb::RED, sine(10)));
        chart.size = (400, 250);
        let svg = render_svg(&chart).unwrap();
        assert!(svg.contains(r#"viewBox="0 0 400 250""#));
        chart.size = (0, 250);
        assert!(render_svg(&chart).is_err());
        chart.size = (400, 250);
        chart.x_range = Some((0.0, f64::NAN));
        assert!(render_svg(&chart).is_err());
    }

    #[test]
    fn non_finite_points_are_skipped() {
        let mut points = sine(300);
        points[100].1 = f64::NAN;
        points[200].0 = f64::INFINITY;
        points.push((f64::NEG_INFINITY, 1e300));
        let chart = Chart::new("gaps", "x", "y")
            .with(Series::line("", Rgb::BLUE, points.clone()))
            .with(Series::markers("", Rgb::RED, points));
        let svg = render_svg(&chart).unwrap();
        assert!(!svg.to_lowercase().contains("nan"));
        assert!(!svg.contains("inf"));
        // The line breaks at each of the two bad points inside it.
        let blue = "stroke=\"#1F77B4\"";
        assert_eq!(tagged_values(&svg, "polyline", blue, "points").len(), 3);
        // The huge y of the bad last point does not stretch the axis.
        assert!(texts(&svg).iter().any(|t| t == "1.0"));
    }

    #[test]
    fn empty_charts_still_have_axes() {
        let bare = Chart::new("nothing", "x", "y");
        let with_empty = Chart::new("nothing", "x", "y")
            .with(Series::line("empty line", Rgb::BLUE, vec![]))
            .with(Series::dots("", Rgb::RED, vec![(f64::NAN, 1.0)]));
        for chart in [bare, with_empty] {
            let svg = render_svg(&chart).unwrap();
            let texts = texts(&svg);
            assert!(texts.iter().any(|t| t == "0"), "{texts:?}");
            assert!(texts.iter().any(|t| t == "1.0"), "{texts:?}");
            assert!(svg.contains("<line "), "mesh lines drawn");
        }
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        let flat: Vec<(f64, f64)> = (0..50).map(|i| (i as f64, 2.5)).collect();
        let one = vec![(3.0, -7.0)];
        let tiny = vec![(1e-9, 4.2e-6), (1e-9, 4.2e-6)];
        for points in [flat, one, tiny] {
            let chart = Chart::new("flat", "x", "y").with(Series::line("", Rgb::BLUE, points));
            let svg = render_svg(&chart).unwrap();
            assert!(texts(&svg).len() > 6, "ticks drawn");
        }
        assert_eq!(widen((2.5, 2.5)), (2.375, 2.625));
        assert_eq!(widen((0.0, 0.0)), (-1.0, 1.0));
        let (lo, hi) = widen((-f64::MAX, f64::MAX));
        assert!((hi - lo).is_finite());
    }

    #[test]
    fn each_kind_renders() {
        let svg = render_svg(&all_kinds()).unwrap();
        let circles = attr_values(&svg, "circle", "r");
        // 12 points and one legend sample each.
        for r in ["2", "6", "4"] {
            assert_eq!(circles.iter().filter(|v| *v == r).count(), 13, "r={r}");
        }
        let strokes = attr_values(&svg, "line", "stroke");
        assert_eq!(strokes.iter().filter(|s| *s == "#7F7F7F").count(), 26);
        let lines = attr_values(&svg, "polyline", "stroke");
        assert!(lines.iter().filter(|s| *s == "#1F77B4").count() >= 2);
        // Dashes are separate polylines.
        assert!(lines.iter().filter(|s| *s == "#D62728").count() > 10);
        let texts = texts(&svg);
        for label in ["line", "dashed", "dots", "circles", "markers", "crosses"] {
            assert!(texts.iter().any(|t| t == label), "{label}");
        }
    }

    #[test]
    fn legend_only_for_labelled_series() {
        let mut chart = Chart::new("t", "x", "y")
            .with(Series::line("shown", Rgb::BLUE, sine(100)))
            .with(Series::line("", Rgb::RED, sine(50)));
        let svg = render_svg(&chart).unwrap();
        assert!(texts(&svg).iter().any(|t| t == "shown"));
        assert_eq!(
            attr_values(&svg, "rect", "stroke").len(),
            3,
            "background, legend"
        );
        chart.legend = false;
        let svg = render_svg(&chart).unwrap();
        assert!(!texts(&svg).iter().any(|t| t == "shown"));
    }

    #[test]
    fn long_line_is_thinned_but_keeps_extremes() {
        let n = 100_000;
        let mut points: Vec<(f64, f64)> = (0..n).map(|i| (i as f64, noise(i))).collect();
        points[31_337].1 = 5.0;
        points[77_777].1 = -7.0;
        let range = (Some((-10_000.0, 110_000.0)), Some((-8.0, 6.0)));
        let mut line = Chart::new("noise", "i", "y").with(Series::line("", Rgb::BLUE, points));
        (line.x_range, line.y_range) = range;
        let svg = render_svg(&line).unwrap();
        assert!(svg.len() < 100_000, "{} bytes", svg.len());

        // The same axes with only the two extremes, drawn as markers.
        let extremes = vec![(31_337.0, 5.0), (77_777.0, -7.0)];
        let mut marks = Chart::new("noise", "i", "y").with(Series::markers("", Rgb::RED, extremes));
        (marks.x_range, marks.y_range) = range;
        let marks = render_svg(&marks).unwrap();
        let cy: Vec<i32> = attr_values(&marks, "circle", "cy")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        let ys: Vec<i32> = polyline_points(&svg, "#1F77B4")
            .iter()
            .map(|p| p.1)
            .collect();
        assert_eq!(ys.iter().min(), cy.iter().min());
        assert_eq!(ys.iter().max(), cy.iter().max());
    }

    #[test]
    fn frequent_gaps_and_clipping_stay_small() {
        let n = 50_000;
        let gappy: Vec<(f64, f64)> = (0..n)
            .map(|i| (i as f64, if i % 3 == 0 { f64::NAN } else { noise(i) }))
            .collect();
        let chart = Chart::new("gaps", "i", "y").with(Series::line("", Rgb::BLUE, gappy));
        let svg = render_svg(&chart).unwrap();
        assert!(svg.len() < 100_000, "{} bytes", svg.len());
        assert!(polyline_points(&svg, "#1F77B4").len() > 1000);

        let noisy: Vec<(f64, f64)> = (0..n).map(|i| (i as f64, noise(i))).collect();
        let mut chart = Chart::new("clipped", "i", "y").with(Series::line("", Rgb::BLUE, noisy));
        chart.y_range = Some((-0.5, 0.5));
        let svg = render_svg(&chart).unwrap();
        assert!(svg.len() < 100_000, "{} bytes", svg.len());
    }

    #[test]
    fn minute_at_sixty_fps_stays_small() {
        let points: Vec<(f64, f64)> = (0..3600)
            .map(|i| {
                (
                    i as f64 / 60.0,
                    1e-3 * (i as f64 / 9.0).sin() + 1e-4 * noise(i),
                )
            })
            .collect();
        let chart = Chart::new("x", "t (s)", "x (m)").with(Series::line("x", Rgb::BLUE, points));
        let svg = render_svg(&chart).unwrap();
        assert!(svg.len() < 60_000, "{} bytes", svg.len());
    }

    #[test]
    fn lines_are_clipped_to_fixed_ranges() {
        let bounds = Bounds {
            x: (0.0, 1.0),
            y: (0.0, 1.0),
        };
        let pieces = clip_line(&[(-1.0, 0.5), (2.0, 0.5), (0.5, 2.0), (0.5, 0.25)], &bounds);
        assert_eq!(
            pieces,
            vec![vec![(0.0, 0.5), (1.0, 0.5)], vec![(0.5, 1.0), (0.5, 0.25)]]
        );
        assert!(clip_line(&[(2.0, 2.0), (3.0, 3.0)], &bounds).is_empty());

        let mut chart = Chart::new("zoom", "t", "y")
            .with(Series::line("", Rgb::BLUE, sine(6000)))
            .with(Series::dots("", Rgb::RED, sine(6000)));
        chart.x_range = Some((20.0, 30.0));
        chart.y_range = Some((-0.5, 0.5));
        let svg = render_svg(&chart).unwrap();
        // All vertices lie within the axes, whose corners the tick lines mark.
        let xs: Vec<i32> = attr_values(&svg, "line", "x1")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        let (left, right) = (*xs.iter().min().unwrap(), *xs.iter().max().unwrap());
        let ys: Vec<i32> = attr_values(&svg, "line", "y2")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        let top = *ys.iter().min().unwrap();
        let line = polyline_points(&svg, "#1F77B4");
        for &(x, y) in &line {
            assert!(x >= left && x <= right, "{x} outside {left}..{right}");
            assert!(y >= top, "{y} above {top}");
        }
        // Clipped, not squashed onto the edge: only the crossings touch it.
        let on_top = line.iter().filter(|p| p.1 == top).count();
        assert!(on_top <= 14, "{on_top} vertices on the top edge");
        for cx in attr_values(&svg, "circle", "cx") {
            let cx: i32 = cx.parse().unwrap();
            assert!(cx >= left && cx <= right);
        }
    }

    #[test]
    fn thinning_keeps_first_extremes_and_last_per_column() {
        let points: Vec<(f64, f64)> = vec![
            (0.0, 0.0),
            (0.1, 5.0),
            (0.2, -3.0),
            (0.3, 1.0),
            (0.4, 2.0),
            (1.0, 0.0),
            (1.5, 9.0),
        ];
        let to_px = |p: &(f64, f64)| (p.0.floor() as i32, (p.1 * 10.0).round() as i32);
        let thin = thin_line(&points, &to_px);
        assert_eq!(
            thin,
            vec![
                (0.0, 0.0),
                (0.1, 5.0),
                (0.2, -3.0),
                (0.4, 2.0),
                (1.0, 0.0),
                (1.5, 9.0)
            ]
        );
    }

    #[test]
    fn tick_labels_are_compact() {
        let labels = |lo: f64, hi: f64, n: usize| TickFormat::for_range((lo, hi), n).labels;
        assert_eq!(
            labels(0.0, 1.0, 6),
            ["0", "0.2", "0.4", "0.6", "0.8", "1.0"]
        );
        assert_eq!(labels(0.0, 3.5e-6, 4), ["0", "1e-6", "2e-6", "3e-6"]);
        assert_eq!(
            labels(1.0e-6, 1.6e-6, 4),
            ["1.0e-6", "1.2e-6", "1.4e-6", "1.6e-6"]
        );
        assert_eq!(
            labels(-2.0e5, 2.0e5, 5),
            ["-2e5", "-1e5", "0", "1e5", "2e5"]
        );
        assert_eq!(labels(-1.0, 1.0, 5), ["-1.0", "-0.5", "0", "0.5", "1.0"]);
        assert_eq!(
            labels(0.0, 40_000.0, 5),
            ["0", "10000", "20000", "30000", "40000"]
        );
        assert_eq!(labels(1.0, 1.0005, 6)[1], "1.0001");
    }
}
