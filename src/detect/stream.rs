//! The streaming pass (step 2 of [`super`]): every frame of the region the first look
//! found, measured, gated and judged, into the detection.

use super::*;

/// The streaming pass over the region `look` found, and the detection it makes.
pub(super) fn streaming_pass<'a>(looks: FirstLook<'a>, mut look: Located<'a>) -> Result<Detection> {
    let FirstLook {
        input,
        opts,
        first,
        last,
        started,
        follow_region,
        pass_from,
        ..
    } = looks;
    pass_from.get_or_init(crate::usage::own_cpu_seconds);
    let info = input.info();
    let name = input.name();
    let stream = look.stream.take();
    let continued = stream.is_some();
    let geo = &look.geo;
    if let Some(q) = geo.second {
        bail!(
            "{name}: {TWO_PENDULUMS}, about pivots ({:.0}, {:.0}) px and ({:.0}, {:.0}) px: \
             give `video.pivot` (--pivot) or `video.roi` (--roi) to say which one to measure",
            geo.pivot.x,
            geo.pivot.y,
            q.x,
            q.y
        );
    }
    let mut frame = Frame::default();

    // The region of interest: the first look's decoder going on (its frames cut to the
    // region here), or a decoder cropping to it.
    // A moving camera's frames (see `steady`) are decoded at the look's region, each
    // warped back onto the first frame and cut to the region of interest.
    let steady = look.moving.then_some(first);
    let sweep = |origin: Roi| {
        steady::Sweep::around(
            (geo.pivot.x, geo.pivot.y),
            geo.r_hi,
            (geo.theta_min, geo.theta_max),
            (f64::from(origin.x), f64::from(origin.y)),
        )
    };
    let in_look = sweep(look.bound);
    let mut src = match (stream, steady) {
        (Some(from), _) => {
            PassSource::Crop(Box::new(CropSource::new(from, geo.roi, steady, in_look)?))
        }
        (None, Some(_)) => {
            let from = Continued {
                held: Default::default(),
                rest: Some(input.open(look.bound, 1)?),
                bound: look.bound,
            };
            PassSource::Crop(Box::new(CropSource::new(from, geo.roi, steady, in_look)?))
        }
        (None, None) => PassSource::Decoder(input.open(geo.roi, 1)?),
    };
    let decodings = look.looks + usize::from(!continued);
    let mut tracker = Tracker::new(
        geo,
        opts,
        look.init_bg,
        look.init_tmap,
        look.init_reference,
        look.shrink as f64,
        look.bound,
    )?;
    let lens = opts.lens.map(|l| {
        let info = input.info();
        crate::lens::Lens::new(l.k1, l.u_k1, info.width, info.height)
    });
    tracker.through(lens);
    // The header's count, within the frames asked for (the header may be wrong: the
    // last report below gives the frames actually measured).
    let total = info
        .frames_header
        .map(|n| n.min(last.saturating_add(1)).saturating_sub(first));
    let tty = std::io::stderr().is_terminal() && opts.progress.is_none();
    let mut rows = Vec::new();
    let mut keeper = figure11::Keeper::new(PER_SIDE);
    let mut review = review::Keeper::new();
    // A camera the first look saw still may start to move later (a slow drift, a bump):
    // glanced at now and then on the region's own frames, and steadied from then on.
    let side = f64::from(info.width.max(info.height));
    let mut late = (!look.moving).then(|| match follow_region {
        true => steady::Late::following(sweep(geo.roi), side),
        false => steady::Late::new(sweep(geo.roi), side),
    });
    let mut k = 0usize;
    let mut waited = 0.0f64;
    loop {
        let t_wait = std::time::Instant::now();
        let more = src.next_frame(&mut frame)?;
        waited += t_wait.elapsed().as_secs_f64();
        if !more {
            break;
        }
        if frame.index < first {
            continue;
        }
        if frame.index > last {
            break;
        }
        // The frames of a still start the look dropped held the wire where its first
        // kept frame has it.
        // A thinned look (`first_look::look_stride`) has the angle of one frame in
        // `stride`.
        let j = k.saturating_sub(look.dropped * look.stride);
        let hint = if j.is_multiple_of(look.stride) {
            geo.initial_angles.get(j / look.stride).copied().flatten()
        } else {
            None
        };

        if let Some(late) = &mut late {
            late.offer(&mut frame)?;
        }
        let row = tracker.step(&frame, hint)?;
        keeper.offer(&row, &frame);
        review.offer(&row, &frame, tracker.predicted())?;
        rows.push(row);
        for r in tracker.take_restated() {
            let Ok(i) = rows.binary_search_by_key(&r.frame, |row| row.frame) else {
                continue;
            };
            let row = &mut rows[i];
            match r.other {
                Some((angle, quality, moments)) => {
                    keeper.restate(r.frame, Some(angle));
                    row.angle_rad = Some(angle);
                    row.quality = quality;
                    row.moments = Some(moments);
                }
                None => {
                    keeper.restate(r.frame, None);
                    row.flag = Some(Flag::Gate);
                }
            }
        }
        k += 1;
        if let Some(p) = opts.progress.as_ref().filter(|_| k.is_multiple_of(100)) {
            (p.0)(k as u64, total);
        }
        if tty && k.is_multiple_of(100) {
            match total {
                Some(n) => eprint!("\rdetect: frame {k}/{n}"),
                None => eprint!("\rdetect: frame {k}"),
            }
        }
    }
    if let Some(p) = &opts.progress {
        (p.0)(k as u64, Some(k as u64));
    }
    if tty {
        eprintln!("\rdetect: frame {k}/{k}");
    }
    debug_timing(
        "streaming pass done",
        started,
        &format!(" ({waited:.2} s waiting for frames)"),
    );
    let unfollowed = match &late {
        Some(l) => l.unfollowed()?,
        None => None,
    };
    // Believed when the look's own glances hinted it (see `LOOK_HINT_EXPLAINS`).
    let moved_from_start = look.hinted && late.as_ref().is_some_and(|l| l.moved_from_start());
    let camera = src.camera().or(late.as_ref().and_then(|l| l.camera()));
    let moved_later_s = late
        .as_ref()
        .filter(|l| !l.moved_from_start())
        .and_then(|l| l.camera())
        .and_then(|c| c.from_s);
    // Each steadied frame (none for a still camera).
    let steadied = match (&mut src, &mut late) {
        (PassSource::Crop(c), _) if c.steady_from.is_some() => c.followed.take_steadied(),
        (_, Some(l)) => l.take_steadied(),
        _ => Vec::new(),
    };
    let turns: Vec<steady::Turn> = steadied.iter().map(steady::Steadied::turn).collect();
    drop(late);
    drop(src);
    if rows.is_empty() {
        bail!("{}: no frame in the requested range", name);
    }
    if rows.iter().any(|r| !r.t_s.is_finite()) {
        bail!("{}: the decoder gave frames without timestamps", name);
    }
    flag_repeats(&mut rows);
    flag_unsteadied(&mut rows, &steadied);
    let refined = tracker.refine_pivot(&mut rows, lens.as_ref(), true);
    let pivot = refined.pivot;
    // A rolling shutter's lean under the camera's motion, taken out of the angles.
    let readout = shutter::take_out(&mut rows, &steadied, f64::from(info.height));
    // The steadying's own frame-to-frame noise, taken out of the angles.
    let jitter = steady::jitter::take_out(&mut rows, &steadied);
    let camera = camera.map(|c| steady::CameraMotion {
        readout_ms: readout.map(|s| 1e3 * s),
        jitter_deg: jitter.map(|j| j.rms_deg),
        ..c
    });
    flag_isolated(&mut rows);
    flag_jumps(&mut rows);
    flag_beyond_swing(&mut rows);
    flag_still_beyond(&mut rows);
    flag_against_swing(&mut rows);
    fill_flagged(&mut rows);
    // A rolling shutter's lag on the wire's own motion, taken out of the angles (the
    // flags judged the angles as measured; the filled ones are taken back too).
    let interval = frame_interval(&rows);
    let wire_readout = shutter::take_out_wire_lag(
        &mut rows,
        pivot,
        [f64::from(info.width), f64::from(info.height)],
        interval,
    );
    apply_marks(
        &mut rows,
        &opts.marks,
        pivot,
        0.5 * (geo.theta_min + geo.theta_max),
    );
    let usable = rows.iter().filter(|r| r.status != Status::Missing).count();
    if usable < rows.len() / 2 {
        // What the frames left out were flagged for, most first: a track that stood on
        // something else is told from a wire not seen.
        let mut counts = std::collections::BTreeMap::<&str, usize>::new();
        for r in rows.iter().filter(|r| r.status == Status::Missing) {
            if let Some(f) = r.flag {
                *counts.entry(f.as_str()).or_default() += 1;
            }
        }
        let mut flags: Vec<(&str, usize)> = counts.into_iter().collect();
        flags.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        let why = match flags.is_empty() {
            true => String::new(),
            false => format!(
                "; of the frames left out, flagged: {}",
                flags
                    .iter()
                    .map(|(n, k)| format!("{n} {k}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        return Err(FoundTooFew(format!(
            "{}: the wire was found in only {usable} of {} frames (last good frame {}{why}); \
             check `video.roi`, `video.pivot` and `video.polarity`, or measure the frames \
             where it was found (`video.frames`)",
            name,
            rows.len(),
            rows.iter()
                .rev()
                .find(|r| r.status == Status::Ok)
                .map_or(0, |r| r.frame)
        ))
        .into());
    }
    if let Some(c) = &opts.calibration {
        ensure!(
            c.sees([pivot.x, pivot.y]),
            "{}: the pivot ({:.1}, {:.1}) px lies beyond the plate's horizon as \
             `video.calibration` fixes it: check the calibration's points",
            name,
            pivot.x,
            pivot.y
        );
    }
    let swing_scale = tracker.swing_scale(&rows, pivot, lens.as_ref(), true);
    let figure11 = keeper.take(&rows);
    let mut verdict = judge::judge(&rows, [pivot.x, pivot.y], refined.u_px, refined.drift_deg);
    // The checks beyond the angles', in this order. `wander` is judged on steadied
    // detections only (see `judge::wander_check`).
    let band = [geo.r_lo, geo.r_hi];
    let seen = &verdict.seen;
    let checks = [
        unfollowed.map(judge::still_check),
        judge::turn_check(&rows, &turns),
        (!turns.is_empty())
            .then(|| judge::wander_check(&rows, seen.noise_deg))
            .flatten(),
        geo.rival.as_ref().map(judge::polarity_check),
        judge::pivot_check(swing_scale),
        judge::beside_check(tracker.beside()),
        lens.as_ref()
            .and_then(|l| judge::lens_check(l, [pivot.x, pivot.y], band, seen)),
        judge::bent_check(&rows, lens.as_ref(), [info.width, info.height], |wire| {
            through_lens_wide(&tracker, &rows, lens.as_ref(), band, wire)
        }),
        opts.pendulum
            .as_ref()
            .and_then(|p| judge::length_check(seen, p)),
    ];
    for c in checks.into_iter().flatten() {
        verdict = verdict.with(c);
    }
    Ok(Detection {
        verdict,
        rows,
        pivot_px: [pivot.x, pivot.y],
        roi: [geo.roi.x, geo.roi.y, geo.roi.w, geo.roi.h],
        dark_wire: geo.dark,
        band_px: band,
        decoder: input.decoder(),
        decodings,
        cpu_s: None,
        diagnostics: tracker.diagnostics,
        steps: tracker.steps_drawn,
        figure11,
        review: review.take(),
        swing_scale,
        look_sweep_deg: geometry::sweep_deg(geo),
        calibration: opts.calibration.clone(),
        lens,
        camera,
        shutter: wire_readout,
        moved_from_start,
        moved_later_s,
    })
}

/// How much wider the swing of `rows` measured through `given` (or as seen) is than
/// the detector would measure it through the lens `wire` (the `bent` check): the pivot
/// refined through each from the same rows (those `ok` and unflagged now), each frame's
/// angle refitted about it and taken back through its lens, and the slope of the one's
/// angles on the other's, less one. `None` without two angles apart.
fn through_lens_wide(
    tracker: &Tracker,
    rows: &[AngleRow],
    given: Option<&crate::lens::Lens>,
    band: [f64; 2],
    wire: &crate::lens::Lens,
) -> Option<f64> {
    let measured = |lens: Option<&crate::lens::Lens>| -> Vec<Option<f64>> {
        let mut again = rows.to_vec();
        let p = tracker.refine_pivot(&mut again, lens, false).pivot;
        let found: Vec<Option<f64>> = again
            .iter()
            .map(|r| r.unflagged_angle().filter(|_| r.status == Status::Ok))
            .collect();
        match lens {
            Some(l) => l.plate_angles([p.x, p.y], band, &found),
            None => found,
        }
    };
    let (now, through) = (measured(given), measured(Some(wire)));
    let (x, y): (Vec<f64>, Vec<f64>) = through
        .iter()
        .zip(&now)
        .filter_map(|(x, y)| Some(((*x)?, (*y)?)))
        .unzip();
    let apart = x.iter().any(|v| *v != x[0]);
    apart.then(|| crate::numerics::linear_fit(&x, &y).slope - 1.0)
}

/// The frames' interval, s: the median of the steps between consecutive rows' times
/// (0 with fewer than two rows).
fn frame_interval(rows: &[AngleRow]) -> f64 {
    let mut steps: Vec<f64> = rows
        .windows(2)
        .map(|w| w[1].t_s - w[0].t_s)
        .filter(|d| *d > 0.0)
        .collect();
    if steps.is_empty() {
        return 0.0;
    }
    crate::numerics::median(&mut steps)
}

/// A pass's refusal for finding the wire in too few frames (its message says how many
/// and why the others were left out): the look may have taken something else for the
/// wire (see `choose::against_median`).
#[derive(Debug)]
pub(super) struct FoundTooFew(String);

impl std::fmt::Display for FoundTooFew {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for FoundTooFew {}
