//! One first look against one kind of background: each frame's lines, the polarity
//! whose lines take the most directions (the two raced on the look's threads), the
//! pivot they meet in, and the band and region of the wire.

use super::faint::faint_frame_lines;
use super::pivot::second_pivot;
use super::*;
use crate::detect::tuning::{
    BAND_INNER_PCT, BAND_INNER_SLACK, BAND_OUTER_PCT, BAND_OUTER_SLACK, BASE_TOL_PX,
    BASE_TOL_SHARE, GEOMETRY_THREADS, LOOK_CLOSE_FRAMES, MAX_JUMPS, MAX_ROUGHNESS, MIN_LEN_SHARE,
    MIN_WIRE_LINES, RIVAL_OFFSET_MIN_DEG, RIVAL_OFFSET_STEADY, RIVAL_POLARITY_SHARE,
    ROI_MARGIN_DEG, ROI_PAD_PX, SECOND_APART, SECOND_MIN_DIRECTIONS, STATIC_EDGE_DEG,
    STATIC_EDGE_SIDE_SHARE, STATIC_LINE_DEG, STATIC_LINE_SHARE,
};

/// The second polarity's look against a share of the first's directions (`beat`, see
/// `RIVAL_POLARITY_SHARE`): it is given up as soon as the directions seen so far, one
/// more for each frame still to look at, cannot reach `beat` (a frame adds at most one
/// direction, its longest line's), since it could then neither win (the score is
/// directions first) nor rival the winner. A frame it no longer looks at cannot fail
/// it either: an error OpenCV would have raised there goes unsaid, as the polarity's
/// result would have gone unused. Without `beat` (the first polarity) it is never
/// given up. Shared by the look's threads.
struct Race {
    beat: Option<usize>,
    /// Frames the look searches for lines (every `stride`-th).
    to_look_at: usize,
    /// The directions seen so far and the frames looked at.
    seen: std::sync::Mutex<(std::collections::BTreeSet<i64>, usize)>,
    lost: std::sync::atomic::AtomicBool,
}

impl Race {
    fn new(beat: Option<usize>, to_look_at: usize) -> Self {
        Self {
            beat,
            to_look_at,
            seen: Default::default(),
            lost: Default::default(),
        }
    }

    /// A frame looked at, with its longest line if any.
    fn looked(&self, longest: Option<&FrameLine>) {
        let Some(beat) = self.beat else {
            return;
        };
        let mut seen = self.seen.lock().expect("no thread panics holding it");
        if let Some(l) = longest {
            seen.0.insert(direction_bin(l));
        }
        seen.1 += 1;
        if seen.0.len() + (self.to_look_at - seen.1) < beat {
            self.lost.store(true, std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// Whether the look is given up.
    fn lost(&self) -> bool {
        self.lost.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// Per frame of `lines`, its line passing within `tol` of `q`, if any: the nearest,
/// unless it lies where lines through `q` lie in [`STATIC_LINE_SHARE`] of the frames
/// or more (within [`STATIC_LINE_DEG`]) and another line passes that does not: a
/// static edge through the pivot (a protractor's ruler) that a camera's sway the
/// glances did not see leaves in the evidence stays put, while the wire turns. Lines
/// of one direction (within [`STATIC_EDGE_DEG`]) seen on both sides of `q` (each side
/// in [`STATIC_EDGE_SIDE_SHARE`] of them or more, and twice) are never taken, however
/// seldom and even alone in a frame: a wire ends at its pivot, an edge runs through it.
fn lines_through(lines: &[Vec<FrameLine>], q: Pt, tol: f64) -> Vec<Option<&FrameLine>> {
    let through: Vec<Vec<&FrameLine>> = lines
        .iter()
        .map(|v| v.iter().filter(|f| Seen::of(f).points_at(q, tol)).collect())
        .collect();
    fn nearest<'a: 'b, 'b>(
        c: impl Iterator<Item = &'b &'a FrameLine>,
        q: Pt,
    ) -> Option<&'a FrameLine> {
        c.min_by(|a, b| a.line.distance(q).total_cmp(&b.line.distance(q)))
            .copied()
    }
    // A line's direction, as a line (modulo half a turn), rad.
    let direction = |f: &FrameLine| f.line.dir.y.atan2(f.line.dir.x);
    let apart = |a: f64, b: f64| {
        let d = (a - b).rem_euclid(std::f64::consts::PI);
        d.min(std::f64::consts::PI - d)
    };
    let seen_in = through.iter().filter(|c| !c.is_empty()).count() as f64;
    let fixed = |f: &FrameLine| {
        let a = direction(f);
        let recurs = through
            .iter()
            .filter(|c| {
                c.iter()
                    .any(|g| apart(direction(g), a) <= STATIC_LINE_DEG.to_radians())
            })
            .count();
        recurs as f64 >= STATIC_LINE_SHARE * seen_in
    };
    // Each line through `q`, once: its direction, and whether its pixels (their
    // weighted centre, the fitted line's point) lie along that direction from `q`.
    let sides: Vec<(f64, bool)> = through
        .iter()
        .flatten()
        .map(|f| {
            let d = direction(f);
            (d, (f.line.point - q).dot(&Pt::new(d.cos(), d.sin())) > 0.0)
        })
        .collect();
    // An edge running through `q`, not a wire ending there: lines of its direction on
    // both sides of `q`.
    let edge = |f: &FrameLine| {
        let a = direction(f);
        let (mut one, mut other) = (0usize, 0usize);
        for &(d, along) in &sides {
            if apart(d, a) <= STATIC_EDGE_DEG.to_radians() {
                // Directions are lines' (modulo half a turn): the side along `a`'s sense.
                if along == ((d - a).cos() >= 0.0) {
                    one += 1;
                } else {
                    other += 1;
                }
            }
        }
        one.min(other) >= 2
            && one.min(other) as f64 >= STATIC_EDGE_SIDE_SHARE * (one + other) as f64
    };
    through
        .iter()
        .map(|c| {
            let c: Vec<&FrameLine> = c.iter().copied().filter(|f| !edge(f)).collect();
            let n = nearest(c.iter(), q)?;
            if c.len() < 2 || !fixed(n) {
                return Some(n);
            }
            nearest(c.iter().filter(|f| !fixed(f)), q).or(Some(n))
        })
        .collect()
}

/// One first look against `kind` of background.
pub(super) fn find_against(look: &Look, kind: Background) -> Result<WireGeometry> {
    let Look {
        init,
        ref tmap,
        min_directions,
        faint,
        full_w,
        full_h,
        polarity,
        pivot_given,
        roi_given,
    } = *look;
    let (w, h) = (init.w, init.h);
    let median = match kind {
        Background::Median => Some(mat_of(w, h, &median_frame(init))?),
        Background::Extreme => None,
    };
    // The wire is long; the bob's edges and a hand's fingers are short.
    let min_len = MIN_LEN_SHARE * (w.min(h) as f64);
    let edges = FrameEdges::of(init, full_w, full_h);
    let candidates: Vec<bool> = match polarity {
        Polarity::Dark => vec![true],
        Polarity::Light => vec![false],
        Polarity::Auto => vec![true, false],
    };
    // Per frame (every `stride`-th, at most about 60 looked at closely), the longest
    // straight thin structures darker (`dark`) or brighter than `bg`.
    let stride = init.data.len().div_ceil(LOOK_CLOSE_FRAMES).max(1);
    let frame_lines_against =
        |bg: &Mat, dark: bool, k: usize, sc: &mut Scratch| -> Result<Vec<FrameLine>> {
            if !k.is_multiple_of(stride) {
                return Ok(Vec::new());
            }
            let f = Mat::new_rows_cols_with_data(h as i32, w as i32, &init.data[k])?;
            if dark {
                core::subtract_def(bg, &f, &mut sc.ev)?;
            } else {
                core::subtract_def(&f, bg, &mut sc.ev)?;
            }
            sc.morph.tophat(sc.ev.data_bytes()?, w, h, &mut sc.top);
            let th = Mat::new_rows_cols_with_data(h as i32, w as i32, &sc.top)?;
            // Keep what exceeds each pixel's own noise threshold (at least one grey level).
            core::compare(&th, tmap, &mut sc.keep, core::CMP_GT)?;
            if faint {
                faint_frame_lines(&th, &sc.keep, min_len, &edges)
            } else {
                frame_lines(&th, &sc.keep, min_len, &edges)
            }
        };
    // The frames' lines, each frame alone: shared among up to [`GEOMETRY_THREADS`]
    // processors (the look's geometry is most of the detector's fixed cost on a short
    // video), in the frames' order; `None` when `race` gave the polarity up.
    let looked_at = (0..init.data.len())
        .filter(|k| k.is_multiple_of(stride))
        .count();
    let lines_against =
        |bg: &Mat, dark: bool, race: &Race| -> Result<Option<Vec<Vec<FrameLine>>>> {
            let n = init.data.len();
            let workers = std::thread::available_parallelism()
                .map_or(1, |p| p.get())
                .clamp(1, GEOMETRY_THREADS);
            let per = n.div_ceil(workers).max(1);
            let parts: Vec<Result<Vec<Vec<FrameLine>>>> = std::thread::scope(|s| {
                let handles: Vec<_> = (0..n)
                    .step_by(per)
                    .map(|from| {
                        let work = &frame_lines_against;
                        s.spawn(move || {
                            let mut scratch = Scratch::default();
                            (from..(from + per).min(n))
                                .take_while(|_| !race.lost())
                                .map(|k| {
                                    let lines = work(bg, dark, k, &mut scratch)?;
                                    if k.is_multiple_of(stride) {
                                        race.looked(lines.first());
                                    }
                                    Ok(lines)
                                })
                                .collect::<Result<Vec<_>>>()
                        })
                    })
                    .collect();
                handles
                    .into_iter()
                    .map(|h| h.join().expect("a geometry thread panicked"))
                    .collect()
            });
            let mut lines = Vec::with_capacity(n);
            for part in parts {
                lines.extend(part?);
            }
            Ok((!race.lost()).then_some(lines))
        };
    let mut best: Option<(bool, f64, Vec<Vec<FrameLine>>)> = None;
    // The other polarity, when it was looked at to its end (see `RIVAL_POLARITY_SHARE`).
    let mut runner_up: Option<(bool, f64, Vec<Vec<FrameLine>>)> = None;
    for &dark in &candidates {
        let beat = best
            .as_ref()
            .map(|b| (RIVAL_POLARITY_SHARE * (b.1 / 1e9).floor()).ceil() as usize);
        let race = Race::new(beat, looked_at);
        let looked = match &median {
            Some(m) => lines_against(m, dark, &race),
            None => extreme_frame(init, dark).and_then(|e| lines_against(&e, dark, &race)),
        };
        // The second polarity's look failing (read further now, to tell a rival) leaves
        // the first's standing, as when it was given up before failing.
        let lines = match looked {
            Ok(l) => l,
            Err(e) if best.is_some() => {
                if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                    eprintln!("geometry: dark={dark} failed, the other taken: {e:#}");
                }
                None
            }
            Err(e) => return Err(e),
        };
        let Some(lines) = lines else {
            if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                eprintln!(
                    "geometry: dark={dark} cannot take {} directions; not looked at further",
                    race.beat.unwrap_or(0)
                );
            }
            continue;
        };
        // The wire moves: its lines take many directions. A ghost (the background's
        // memory of something of the other polarity lingering at a turning point) keeps
        // one. Score = directions seen (half-degree bins), then the evidence's weight
        // (far under 1e9: a frame's longest line holds a few thousand pixels of at most
        // 255, and a look has at most about 60 frames).
        let mut bins = std::collections::BTreeSet::new();
        let mut weight = 0.0;
        for l in lines.iter().filter_map(|v| v.first()) {
            bins.insert(direction_bin(l));
            weight += l.pts.iter().map(|p| p.1).sum::<f64>();
        }
        let total = bins.len() as f64 * 1e9 + weight;
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!(
                "geometry: dark={dark} lines={} directions={} weight={weight:.0}",
                lines.iter().filter(|v| !v.is_empty()).count(),
                bins.len()
            );
        }
        if best.as_ref().is_none_or(|b| total > b.1) {
            runner_up = best.replace((dark, total, lines));
        } else {
            runner_up = Some((dark, total, lines));
        }
    }
    let (dark, total, lines) = best.expect("one polarity tried");
    let directions = (total / 1e9) as usize;
    if directions < min_directions {
        bail!(
            "{NO_WIRE} in the first {} frames (the lines take only {directions} directions)",
            init.data.len()
        );
    }
    let found: Vec<Seen> = lines.iter().flatten().map(Seen::of).collect();
    let with_lines = lines.iter().filter(|v| !v.is_empty()).count();
    if with_lines < 3 {
        bail!(
            "{NO_WIRE} in the first {} frames (lines seen in {with_lines} of them)",
            init.data.len()
        );
    }
    let origin = Pt::new(init.x0, init.y0);
    let to_full = |p: Pt| shrunk_to_full(p, origin, init.shrink);
    // Pivot: the robust intersection of the lines (shrunk coordinates).
    let center = Pt::new(w as f64 / 2.0, h as f64 / 2.0);
    let base_tol = BASE_TOL_PX.max(BASE_TOL_SHARE * (w.max(h) as f64));
    let pivot_s = match pivot_given {
        Some(p) => full_to_shrunk(p, origin, init.shrink),
        None => match ransac_pivot(&found, center, base_tol) {
            Some(p) => p,
            None => bail!("the moving lines do not meet in a pivot; give `video.pivot`"),
        },
    };
    // Per frame, the line through the pivot (if any).
    let tol_at = |q: Pt| 2.0 * through_tol(q, center, base_tol);
    let through = |q: Pt| lines_through(&lines, q, tol_at(q));
    let per_frame = through(pivot_s);
    let good: Vec<&FrameLine> = per_frame.iter().flatten().copied().collect();
    if good.len() < 3 {
        match pivot_given {
            Some(p) => bail!(
                "no moving line passes through the given pivot ({:.1}, {:.1}) px ({} frames \
                 with lines); check `video.pivot` (or --pivot): the point the wire turns about, \
                 in the video's full-size pixels",
                p.x,
                p.y,
                with_lines
            ),
            None => {
                bail!("the moving lines do not share a pivot; give `video.pivot` (and `video.roi`)")
            }
        }
    }
    // Too few lines to tell a swinging wire from a few stray edges that happen to meet.
    if good.len() < MIN_WIRE_LINES && pivot_given.is_none() {
        bail!(
            "{NO_WIRE} in the first {} frames (only {} lines meet in a pivot)",
            init.data.len(),
            good.len()
        );
    }
    let mut radii: Vec<f64> = good
        .iter()
        .flat_map(|f| f.pts.iter().map(|(q, _)| (*q - pivot_s).norm()))
        .collect();
    radii.sort_by(f64::total_cmp);
    let pct = |p: f64| radii[((radii.len() - 1) as f64 * p) as usize];
    let (r_lo, r_hi) = (
        pct(BAND_INNER_PCT) * BAND_INNER_SLACK,
        pct(BAND_OUTER_PCT) * BAND_OUTER_SLACK,
    );
    let angle_about = |f: &FrameLine, pivot_s: Pt| {
        let c = f.line.point - pivot_s;
        let d = if c.dot(&f.line.dir) >= 0.0 {
            f.line.dir
        } else {
            -f.line.dir
        };
        d.y.atan2(d.x)
    };
    let angle_of = |f: &FrameLine| angle_about(f, pivot_s);
    // The rest direction: the circular mean of the wire's directions. Every angle is
    // taken on its branch (within half a turn of it), so a wire that hangs towards -x
    // (a camera at any roll) sweeps a few degrees about 180, not 359 across +-180.
    let (sin, cos) = good.iter().fold((0.0, 0.0), |(s, c), f| {
        let a = angle_of(f);
        (s + a.sin(), c + a.cos())
    });
    let rest = sin.atan2(cos);
    let initial_angles: Vec<Option<f64>> = per_frame
        .iter()
        .map(|l| l.map(|f| unwrap_near(angle_of(f), rest)))
        .collect();
    let mut thetas: Vec<f64> = good
        .iter()
        .map(|f| unwrap_near(angle_of(f), rest))
        .collect();
    thetas.sort_by(f64::total_cmp);
    let (theta_min, theta_max) = (thetas[0], thetas[thetas.len() - 1]);
    if theta_max - theta_min < 1f64.to_radians() && pivot_given.is_none() {
        bail!(
            "the wire moved by only {:.2} deg in the first frames: too little to locate its pivot; give `video.pivot`",
            (theta_max - theta_min).to_degrees()
        );
    }
    // ROI: the sector the wire can sweep (its angles so far plus a margin), in the band.
    let pivot = to_full(pivot_s);
    let (r_lo_f, r_hi_f) = (r_lo * init.shrink, r_hi * init.shrink);
    let margin = ROI_MARGIN_DEG.to_radians();
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for i in 0..=40 {
        let th = theta_min - margin + (theta_max - theta_min + 2.0 * margin) * i as f64 / 40.0;
        for r in [r_lo_f, r_hi_f] {
            let p = pivot + Pt::new(th.cos(), th.sin()) * r;
            x0 = x0.min(p.x);
            y0 = y0.min(p.y);
            x1 = x1.max(p.x);
            y1 = y1.max(p.y);
        }
    }
    let pad = ROI_PAD_PX;
    let bound = roi_given.unwrap_or(Roi {
        x: 0,
        y: 0,
        w: full_w,
        h: full_h,
    });
    let cx0 = (x0 - pad).floor().max(bound.x as f64) as u32;
    let cy0 = (y0 - pad).floor().max(bound.y as f64) as u32;
    let cx1 = ((x1 + pad).ceil() as u32).min(bound.x + bound.w);
    let cy1 = ((y1 + pad).ceil() as u32).min(bound.y + bound.h);
    if cx1 <= cx0 + 8 || cy1 <= cy0 + 8 {
        bail!("the wire's region lies outside the frame");
    }
    // Sizes that are multiples of 2 (every decoder crops those exactly) and of the
    // shrink factor (so that the streaming pass's grid is exactly `shrink` times
    // coarser along both axes, as its coordinate mapping assumes).
    let s = init.shrink as u32;
    let m = if s.is_multiple_of(2) { s } else { 2 * s };
    let size = |lo: u32, hi: u32, limit: u32| {
        let n = (hi - lo) / m * m;
        if n > 0 {
            n
        } else if lo + m <= limit {
            m
        } else {
            0
        }
    };
    let roi = Roi {
        x: cx0,
        y: cy0,
        w: size(cx0, cx1, bound.x + bound.w),
        h: size(cy0, cy1, bound.y + bound.h),
    };
    if roi.w == 0 || roi.h == 0 {
        bail!("the wire's region is too small at the frame's edge");
    }
    if std::env::var("ROLLFRIC_DEBUG").is_ok_and(|v| v == "angles") {
        for (k, a) in initial_angles.iter().enumerate() {
            if let Some(a) = a {
                eprintln!("look {k} {:.2}", a.to_degrees());
            }
        }
    }
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "geometry: pivot {pivot:?} band {r_lo_f:.1}..{r_hi_f:.1} theta {:.1}..{:.1} deg roi {roi:?} good lines {}",
            theta_min.to_degrees(),
            theta_max.to_degrees(),
            good.len()
        );
    }
    // A second pendulum: the lines that do not point at the pivot meet in another one,
    // in as many directions as half the wire's at least, and swing as a wire does
    // there (smoothly, without jumps). Only looked for when neither a pivot nor a
    // region says which pendulum is measured.
    let second = (pivot_given.is_none() && roi_given.is_none())
        .then(|| second_pivot(&found, pivot_s, center, base_tol))
        .flatten()
        .filter(|&(q, sc, first)| {
            let far = (q - pivot_s).norm() >= SECOND_APART * (w.max(h) as f64);
            if !far || sc < SECOND_MIN_DIRECTIONS || 2 * sc < first {
                return false;
            }
            let per = through(q);
            let n = per.iter().flatten().count();
            let angles: Vec<Option<f64>> =
                per.iter().map(|l| l.map(|f| angle_about(f, q))).collect();
            let (sin, cos) = angles
                .iter()
                .flatten()
                .fold((0.0, 0.0), |(s, c), a| (s + a.sin(), c + a.cos()));
            let mean = sin.atan2(cos);
            let angles: Vec<Option<f64>> = angles
                .iter()
                .map(|a| a.map(|a| unwrap_near(a, mean)))
                .collect();
            let (lo, hi) = angles
                .iter()
                .flatten()
                .fold((f64::MAX, f64::MIN), |(lo, hi), &a| (lo.min(a), hi.max(a)));
            let ok = n >= MIN_WIRE_LINES
                && hi - lo >= 1f64.to_radians()
                && jumps(&angles, stride, hi - lo) <= MAX_JUMPS
                && roughness(&angles, stride) <= MAX_ROUGHNESS;
            if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                eprintln!(
                    "geometry: a second pivot ({:.1}, {:.1}) px, {sc} directions (the first \
                     {first}), {n} lines, sweep {:.1} deg, jumps {}, roughness {:.2}: {}",
                    to_full(q).x,
                    to_full(q).y,
                    (hi - lo).to_degrees(),
                    jumps(&angles, stride, hi - lo),
                    roughness(&angles, stride),
                    if ok {
                        "a second pendulum"
                    } else {
                        "not a pendulum"
                    }
                );
            }
            ok
        })
        .map(|(q, _, _)| to_full(q));
    // A rival polarity: the other polarity's lines swing about the same pivot in nearly
    // as many directions, off the wire's by the same angle in the frames both see (a
    // wire and its shadow, one light and one dark, look alike to the look; a ghost of
    // the other polarity, the background's memory of the wire, or the scene's own lines
    // lie off it by angles that vary as it swings).
    let rival = runner_up.and_then(|(r_dark, r_total, r_lines)| {
        let r_directions = (r_total / 1e9) as usize;
        let r_per = lines_through(&r_lines, pivot_s, tol_at(pivot_s));
        // Signed: a shadow lies on one side of its wire.
        let mut off: Vec<f64> = per_frame
            .iter()
            .zip(&r_per)
            .filter_map(|(a, b)| {
                let d = angle_of(b.as_ref()?) - angle_of(a.as_ref()?);
                Some(
                    ((d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                        - std::f64::consts::PI)
                        .to_degrees(),
                )
            })
            .collect();
        let both = off.len();
        off.sort_by(f64::total_cmp);
        let at = |p: f64| off.get((both as f64 * p) as usize).copied().unwrap_or(0.0);
        let (offset_deg, spread_deg) = (at(0.5).abs(), at(0.75) - at(0.25));
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!(
                "geometry: the other polarity (dark={r_dark}) {r_directions} directions of \
                 {directions}, {both} frames with lines through the pivot in both, \
                 {offset_deg:.2} deg apart (median; quartiles {:.2} {:.2})",
                at(0.25),
                at(0.75)
            );
        }
        (r_directions as f64 >= RIVAL_POLARITY_SHARE * directions as f64
            && both >= MIN_WIRE_LINES
            && offset_deg >= RIVAL_OFFSET_MIN_DEG
            && spread_deg <= RIVAL_OFFSET_STEADY * offset_deg)
            .then_some(RivalPolarity {
                dark: r_dark,
                directions: r_directions,
                of: directions,
                offset_deg,
                spread_deg,
            })
    });
    Ok(WireGeometry {
        second,
        rival,
        pivot,
        dark,
        r_lo: r_lo_f,
        r_hi: r_hi_f,
        theta_min,
        theta_max,
        roi,
        jumps: jumps(&initial_angles, stride, theta_max - theta_min),
        roughness: roughness(&initial_angles, stride),
        initial_angles,
        lines_used: good.len(),
        stage: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line from `q` outward at `deg` (image angle), seen from `r0` to `r1` px, passing
    /// `off` px beside `q`.
    fn ray(q: Pt, deg: f64, r0: f64, r1: f64, off: f64) -> FrameLine {
        let d = Pt::new(deg.to_radians().cos(), deg.to_radians().sin());
        let n = Pt::new(-d.y, d.x) * off;
        let (a, b) = (q + n + d * r0, q + n + d * r1);
        FrameLine {
            line: Line::through(a, b),
            pts: vec![(a, 1.0), (b, 1.0)],
        }
    }

    #[test]
    fn a_static_edge_through_the_pivot_is_passed_over_for_the_wire_beside_it() {
        let q = Pt::new(300.0, 100.0);
        let wire = |k: usize| 90.0 + 10.0 * (k as f64 * 0.5).sin();
        // The ruler's edge, nearer the pivot than the wire, in 3 frames of 5.
        let frames = || -> Vec<Vec<FrameLine>> {
            (0..40)
                .map(|k| {
                    let mut v = vec![ray(q, wire(k), 50.0, 300.0, 0.8)];
                    if k % 5 < 3 {
                        v.push(ray(q, -108.0 + 0.1 * (k % 3) as f64, 20.0, 200.0, 0.0));
                    }
                    v
                })
                .collect()
        };
        let lines = frames();
        let taken = lines_through(&lines, q, 3.0);
        for (k, f) in taken.iter().enumerate() {
            let d = f.expect("a line through the pivot").line.dir;
            let deg = d.y.atan2(d.x).to_degrees().rem_euclid(180.0);
            assert!((deg - wire(k)).abs() < 0.5, "frame {k}: {deg} deg");
        }
        // Alone in a frame, the edge is still that frame's line; without a wire beside it
        // in any frame (a wire at rest and its shadow, both still), the nearest is taken.
        let mut alone = frames();
        alone[0].remove(0);
        assert!(lines_through(&alone, q, 3.0)[0].is_some());
        let at_rest: Vec<Vec<FrameLine>> = (0..40)
            .map(|_| {
                vec![
                    ray(q, 90.0, 50.0, 300.0, 0.8),
                    ray(q, 93.0, 50.0, 300.0, 0.2),
                ]
            })
            .collect();
        for f in lines_through(&at_rest, q, 3.0) {
            let d = f.expect("a line").line.dir;
            assert!((d.y.atan2(d.x).to_degrees().rem_euclid(180.0) - 93.0).abs() < 1e-6);
        }
    }

    /// The ruler's edge through the pivot, read now on one side of it and now on the
    /// other (its direction 1.5 deg apart from frame to frame under a sway), in a fifth
    /// of the frames and alone in them: never taken. A wire held still, alone in every
    /// frame, is on one side only: taken.
    #[test]
    fn an_edge_through_the_pivot_is_never_taken_but_a_held_wire_is() {
        let q = Pt::new(300.0, 100.0);
        let wire = |k: usize| 90.0 + 10.0 * (k as f64 * 0.5).sin();
        let lines: Vec<Vec<FrameLine>> = (0..40)
            .map(|k| {
                if k % 5 == 0 {
                    let deg = 30.0 + 1.5 * (k % 2) as f64 + if k % 10 == 0 { 180.0 } else { 0.0 };
                    vec![ray(q, deg, 20.0, 200.0, 0.0)]
                } else {
                    vec![ray(q, wire(k), 50.0, 300.0, 0.8)]
                }
            })
            .collect();
        for (k, f) in lines_through(&lines, q, 3.0).iter().enumerate() {
            assert_eq!(f.is_some(), k % 5 != 0, "frame {k}");
        }
        let held: Vec<Vec<FrameLine>> = (0..40)
            .map(|k| vec![ray(q, 90.0 + 1.5 * (k % 2) as f64, 50.0, 300.0, 0.8)])
            .collect();
        assert!(lines_through(&held, q, 3.0).iter().all(Option::is_some));
    }
}
