//! Series prepared for drawing: clipped to the axes, lines broken at points
//! that are not finite and thinned, repeated markers dropped.

use std::collections::HashSet;

use super::chart::Series;

/// A point in data units.
type Point = (f64, f64);
/// Maps a point to backend pixels.
type ToPixel<'a> = dyn Fn(&Point) -> (i32, i32) + 'a;

/// Axis ranges as a clipping box.
pub(super) struct Bounds {
    pub(super) x: (f64, f64),
    pub(super) y: (f64, f64),
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
pub(super) enum Shape {
    /// Polylines in data units, already clipped and thinned.
    Pieces(Vec<Vec<(f64, f64)>>),
    /// Marker positions in data units, inside the axes, one per pixel.
    Points(Vec<(f64, f64)>),
}

/// A series ready to draw, with the pixel positions used to place the legend.
pub(super) struct Prepared {
    pub(super) shape: Shape,
    /// Backend pixel positions of the drawn points or polyline vertices.
    pub(super) pixels: Vec<Vec<(i32, i32)>>,
}

impl Prepared {
    pub(super) fn new(series: &Series, bounds: &Bounds, to_px: &ToPixel<'_>) -> Self {
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
pub(super) fn clip_line(points: &[(f64, f64)], bounds: &Bounds) -> Vec<Vec<(f64, f64)>> {
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
pub(super) fn thin_line(points: &[(f64, f64)], to_px: &ToPixel<'_>) -> Vec<(f64, f64)> {
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
