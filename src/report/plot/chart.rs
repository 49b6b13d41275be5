//! The chart as plain data: colours, series kinds, series and the chart itself.

use plotters::style::RGBColor;

use super::DEFAULT_SIZE;

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

    pub(super) fn color(self) -> RGBColor {
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
    pub(super) fn is_line(self) -> bool {
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

/// A drawing backend's error, in our words.
pub(super) fn draw_err<E: std::fmt::Display>(e: E) -> anyhow::Error {
    anyhow::anyhow!("drawing the chart failed: {e}")
}
