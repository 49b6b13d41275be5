//! Tests of the chart builder, on the SVG it writes.

use super::axes::{widen, TickFormat};
use super::lines::{clip_line, thin_line, Bounds};
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

/// A box in pixels: `(x, y, width, height)`.
type PxBox = (i32, i32, i32, i32);

/// The legend box of a chart and the centres of the markers drawn before it (the
/// data; the legend's own samples come after it).
fn legend_and_markers(svg: &str) -> Option<(PxBox, Vec<(i32, i32)>)> {
    let box_line = svg
        .lines()
        .position(|l| l.starts_with("<rect ") && l.contains("stroke=\"#AAAAAA\""))?;
    let lines: Vec<&str> = svg.lines().collect();
    let num = |l: &str, a: &str| -> i32 {
        tagged_values(l, l[1..].split(' ').next().unwrap(), "", a)[0]
            .parse()
            .unwrap()
    };
    let l = lines[box_line];
    let legend = (num(l, "x"), num(l, "y"), num(l, "width"), num(l, "height"));
    let markers = lines[..box_line]
        .iter()
        .filter(|l| l.starts_with("<circle "))
        .map(|l| (num(l, "cx"), num(l, "cy")))
        .collect();
    Some((legend, markers))
}

/// A cloud of markers filling the square `[x0, x0 + 1] x [y0, y0 + 1]`.
fn cloud(x0: f64, y0: f64, n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| (x0 + 0.5 + 0.5 * noise(i), y0 + 0.5 + 0.5 * noise(i + 7919)))
        .collect()
}

#[test]
fn the_legend_goes_to_an_empty_corner_inside_else_outside_the_plot() {
    let ranges = (Some((0.0, 4.0)), Some((0.0, 4.0)));
    let plot_right = |svg: &str| -> i32 {
        // The x axis line runs along the plot's bottom, from its left to its right.
        polyline_points(svg, "#5A5A5A")
            .iter()
            .map(|p| p.0)
            .max()
            .unwrap()
    };
    // Data in the upper right and the lower left: the legend takes the upper left.
    let mut two = Chart::new("t", "x", "y")
        .with(Series::circles(
            "upper right",
            Rgb::RED,
            cloud(3.0, 3.0, 200),
        ))
        .with(Series::circles(
            "lower left",
            Rgb::BLUE,
            cloud(0.0, 0.0, 200),
        ));
    (two.x_range, two.y_range) = ranges;
    let svg = render_svg(&two).unwrap();
    let ((x, y, w, h), markers) = legend_and_markers(&svg).unwrap();
    assert_eq!(markers.len(), 400);
    let right = plot_right(&svg);
    assert!(x + w < right, "legend inside the plot: {x} + {w} < {right}");
    let reach = CIRCLE_RADIUS as i32 + MARKER_STROKE as i32;
    let covered = |m: &(i32, i32)| {
        m.0 + reach >= x && m.0 - reach <= x + w && m.1 + reach >= y && m.1 - reach <= y + h
    };
    assert_eq!(markers.iter().filter(|m| covered(m)).count(), 0);
    assert!(x < right / 2, "upper left: x = {x}");

    // Data in every corner: no corner is free, the legend goes to the right of the plot.
    let mut four = two;
    four = four
        .with(Series::circles("", Rgb::GREEN, cloud(0.0, 3.0, 200)))
        .with(Series::circles("", Rgb::GREEN, cloud(3.0, 0.0, 200)));
    let svg = render_svg(&four).unwrap();
    let ((x, y, w, h), markers) = legend_and_markers(&svg).unwrap();
    assert_eq!(markers.len(), 800);
    assert!(x > plot_right(&svg), "legend outside the plot");
    assert_eq!(
        markers
            .iter()
            .filter(|m| m.0 + reach >= x
                && m.0 - reach <= x + w
                && m.1 + reach >= y
                && m.1 - reach <= y + h)
            .count(),
        0
    );
}

#[test]
fn one_marker_under_every_corner_sends_the_legend_out_even_beside_much_data() {
    // A dense line across the middle (thousands of samples) and one marker in each
    // corner: however small a share of the data that marker is, it is not hidden.
    let line: Vec<(f64, f64)> = (0..2000)
        .map(|i| (i as f64 / 500.0, 2.0 + 0.4 * noise(i)))
        .collect();
    let corners = vec![(0.05, 0.05), (3.95, 0.05), (0.05, 3.95), (3.95, 3.95)];
    let mut chart = Chart::new("t", "x", "y")
        .with(Series::line("a dense line", Rgb::BLUE, line))
        .with(Series::markers("corners", Rgb::RED, corners));
    (chart.x_range, chart.y_range) = (Some((0.0, 4.0)), Some((0.0, 4.0)));
    let svg = render_svg(&chart).unwrap();
    let ((x, _, _, _), markers) = legend_and_markers(&svg).unwrap();
    assert_eq!(markers.len(), 4);
    let right = markers.iter().map(|m| m.0).max().unwrap();
    assert!(
        x > right,
        "legend at x = {x}, inside the plot (markers up to {right})"
    );
}
