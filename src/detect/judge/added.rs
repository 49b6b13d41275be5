//! The detection's checks that weigh more than the angles: what the pass knew of the
//! camera (`still`, `turn`, `wander`), of the first look's other polarity
//! (`polarity`), of the pivot (`pivot`) and of the lens (`lens`). Each is added to the
//! verdict [`super::judge`] gives on the angles alone.

use super::*;

/// `still`: a camera taken as still throughout, whose static scene (the pendulum's
/// sweep left out) is found displaced by more than [`STILL_MAX_PX`] (`reach_px`, at the
/// region's farthest corner) between the first frame (or the first glance, where what
/// differs in the first frame is no bump: see `Late::unfollowed`) and two glances in
/// a row, moved unfollowed: every angle carries the pivot's displacement (a tenth of a
/// degree for every 0.4 px at 230 px from the pivot).
pub fn still_check(reach_px: f64) -> DetectionCheck {
    check(
        "still",
        reach_px,
        STILL_MAX_PX,
        reach_px <= STILL_MAX_PX,
        format!(
            "the camera was taken as still, and the static scene lies {reach_px:.2} px from \
             where the first frame (or the first glance) has it at two glances in a row (at \
             most {STILL_MAX_PX} px)"
        ),
        "the camera drifted and the detector did not follow it",
    )
}

/// `wander`: a moving camera's frames, each steadied, hold angles that stray from the
/// swing's own path (fitted half a period at a time over two and a half periods, see
/// `fill::swing_scatter`) by about their noise from frame to frame (`noise_deg`, the
/// judge's). A steadying that reads the camera's motion short or late under a codec
/// moves the angles slowly, over tenths of a second, and their fourth differences do
/// not show it: seed 7's sweep scene 2 (640x480 under CRF 34, a tripod sway of 0.89 px
/// at 0.76 Hz) strayed 0.061 deg, 3.85 times its noise, its angles 0.093 deg RMS off
/// and called `ok`. Judged on steadied detections only: a real pendulum filmed still
/// strays from this path by more than its noise too (the real clips measured `ok`: 1.8
/// to 4.3 times; the split-screen clip, measured about its pivot, 0.060 deg and 6.0
/// times); moved by ffmpeg and steadied, their noise grows, and they read 1.2 (green
/// screen) and 2.94 (split screen).
/// `None` without the noise or two whole swings.
pub fn wander_check(rows: &[AngleRow], noise_deg: Option<f64>) -> Option<DetectionCheck> {
    let (t, a): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter(|r| r.seen_on_wire())
        .filter_map(|r| r.angle_rad.map(|a| (r.t_s, a)))
        .unzip();
    let scatter = crate::detect::fill::swing_scatter(&t, &a)?.to_degrees();
    let times = scatter / noise_deg?;
    let times = if times.is_finite() {
        times
    } else {
        f64::INFINITY
    };
    Some(check(
        "wander",
        times,
        WANDER_NOISE_FACTOR,
        times <= WANDER_NOISE_FACTOR || scatter <= WANDER_MIN_DEG,
        format!(
            "the steadied angles stray from the swing's own path by {scatter:.4} deg, \
             {times:.2} times their noise from frame to frame (at most \
             {WANDER_NOISE_FACTOR} times, or {WANDER_MIN_DEG} deg)"
        ),
        "something moves the angles slowly that is not the swing: the camera's motion \
         read short or late (a codec's lag)",
    ))
}

/// `beside`: of the pass's looks across the followed line (`looks`, each the offsets,
/// rad, of the ridges sharper across than the followed line found beside it, see
/// `track::beside::sharper_beside`), the share that find one at about the same offset (within
/// [`BESIDE_TOL_DEG`], and none at about its mirror image: a wide rod's two edges lie
/// either side of it). A share over [`BESIDE_MAX_SHARE`] says the track follows a wide
/// line beside a sharp one that turns with it: a wire's shadow beside the wire. Seed 53's
/// sweep scenes 31, 55 and 62 (faint wires 1 px wide beside their soft shadows) followed
/// the shadow for the whole clip, 2.2 to 3.7 deg off the wire, and were called `ok`: the
/// twin's shadow turns with its wire at a fixed angle, so the swing was right, but a
/// lamp's shadow does not. `None` with fewer than [`BESIDE_MIN_SAMPLES`] looks, or none
/// that found a sharper ridge.
pub fn beside_check(looks: &[Vec<f64>]) -> Option<DetectionCheck> {
    if looks.len() < BESIDE_MIN_SAMPLES || looks.iter().all(Vec::is_empty) {
        return None;
    }
    let tol = BESIDE_TOL_DEG.to_radians();
    let near = |l: &[f64], o: f64| l.iter().any(|x| (x - o).abs() <= tol);
    // Offsets lie on each pass's grid of directions and repeat from look to look: each
    // is counted once (at its last place, so that ties fall as they would), which keeps
    // the work proportional to the looks, not their square, on a long recording.
    let mut offsets: Vec<f64> = Vec::new();
    for &o in looks.iter().flatten().rev() {
        if !offsets.contains(&o) {
            offsets.push(o);
        }
    }
    offsets.reverse();
    let (count, offset) = offsets
        .iter()
        .map(|&o| {
            let c = looks.iter().filter(|l| near(l, o) && !near(l, -o)).count();
            (c, o)
        })
        .max_by(|a, b| a.0.cmp(&b.0).then(b.1.abs().total_cmp(&a.1.abs())))?;
    let share = count as f64 / looks.len() as f64;
    Some(check(
        "beside",
        share,
        BESIDE_MAX_SHARE,
        share <= BESIDE_MAX_SHARE,
        format!(
            "{count} of {} looks across the followed line find a line sharper across it \
             {:+.2} deg beside it (at most {:.0} %)",
            looks.len(),
            offset.to_degrees(),
            100.0 * BESIDE_MAX_SHARE
        ),
        "the track follows a wide line beside a sharp one that turns with it, as a wire's \
         soft shadow lies beside a faint wire: the angles may be the shadow's",
    ))
}

/// `pivot`: the wire's own direction (each frame's free line fit, whatever the pivot)
/// swings `swing_scale` times its angle about the pivot (the detection's
/// swing scale). A pivot off along the wire by `delta` at a mean radius `R` makes it
/// about `R / (R + delta)`, and scales the measured swing, and `s_r`, by about as much;
/// on the wire it is 1 to within the free lines' noise. Seed 7's sweep scene 18 (a
/// steadied drift of 11.2 px through a lens, 1920x1080 oblique) read 0.9892: its swing
/// 0.82 % wide, 0.115 deg RMS off, and every other check passed. The fit's `pivot`
/// check judges the same figure against the experiment's `pivot_rel` (2 % unless set).
/// `None` without a swing scale.
pub fn pivot_check(swing_scale: Option<f64>) -> Option<DetectionCheck> {
    let off = swing_scale? - 1.0;
    Some(check(
        "pivot",
        off.abs(),
        PIVOT_SCALE_MAX,
        off.abs() <= PIVOT_SCALE_MAX,
        format!(
            "the wire's own direction swings {:.2} % {} than its angle about the pivot (at \
             most {:.2} % either way)",
            100.0 * off.abs(),
            if off > 0.0 { "more" } else { "less" },
            100.0 * PIVOT_SCALE_MAX
        ),
        "the pivot is off along the wire, which scales the measured swing, and s_r, by about \
         as much: give `video.pivot`",
    ))
}

/// `lens`: angles measured through a lens given with the video (`video.lens`) are the
/// plate's only as well as the lens is known. Its uncertainty `u_k1` puts a relative
/// uncertainty on the swing's scale ([`crate::lens::Lens::scale_u_rel`], for the swing
/// `seen`, through `pivot` over the wire's visible `band`, px): over
/// [`LENS_SCALE_MAX`], the angles may be that much too wide or too narrow, and nothing in
/// them shows it (a scale error keeps the swing's own path, its period and its decay).
/// A lens declared unknown (`{k1: 0, u_k1: 0.15}`, when no sheet could be fitted) or
/// fitted from too few lines leaves a swing a few percent uncertain: seed 2's sweep
/// scene 40 (declared unknown) read 3.2 % and was 2.07 % wide, seed 7's scene 60 (the
/// sheet's -0.131 +- 0.062 for -0.164) 3.0 % and 1.41 % wide, 0.066 and 0.076 deg RMS
/// off and called `ok` before. The fit's `scale` check judges `s_r` by the same limit.
/// `None` without a lens's uncertainty or a seen swing.
pub fn lens_check(
    lens: &crate::lens::Lens,
    pivot: [f64; 2],
    band: [f64; 2],
    seen: &Seen,
) -> Option<DetectionCheck> {
    if lens.u_k1 <= 0.0 {
        return None;
    }
    let rest = seen.rest_deg?.to_radians();
    let amp_deg = seen
        .amplitude_start_deg?
        .max(seen.amplitude_end_deg.unwrap_or(0.0));
    let u = lens.scale_u_rel(pivot, rest, amp_deg.to_radians(), band);
    Some(check(
        "lens",
        u,
        LENS_SCALE_MAX,
        u <= LENS_SCALE_MAX,
        format!(
            "the lens (k1 {:.3} +- {:.3}) leaves the swing's scale known to +- {:.2} % \
             ({:.3} deg at its {amp_deg:.2} deg amplitude; at most {:.2} %)",
            lens.k1,
            lens.u_k1,
            100.0 * u,
            u * amp_deg,
            100.0 * LENS_SCALE_MAX
        ),
        "the angles are the plate's only as well as the lens is known: fit it from a sheet \
         with more, sharper lines (`rollfric lens`), or film through a lens that does not \
         bend",
    ))
}

/// `bent`: the wire is straight on the plate, and seen through a wide lens every
/// stretch of it off the frame's centre bows. The found frames' bows (each strip's
/// parabola, [`crate::detect::row::KeptMoments::bow`]) give the lens's coefficient
/// ([`crate::lens::bow::k1_from_bows`]) on a frame of `frame` px. When it differs from
/// the lens given with the video (`given`; none: 0) by more than [`BENT_SIGMAS`] times
/// its uncertainty (the wire's jackknife, the lens given's, [`BENT_REL_U`] of the
/// wire's coefficient and [`BENT_MIN_U`], added in quadrature: the measurement's own
/// bias), `wide` says how much wider the swing measured is than the detector would
/// measure it through the wire's lens (a share), and the check fails over
/// [`LENS_SCALE_MAX`]. With no lens given the gate passes a wire's `k1` under about
/// 0.15 whatever its effect (`BENT_MIN_U` and `BENT_REL_U` alone make 3.5 uncertainties
/// of it). The wire's own bend takes part of the measured bows: a constant one (a
/// shadow's pull) is fitted as an offset, but a string that bends as it swings (the real
/// clips' light bobs) bends with the swing's distance from rest, as a lens does about
/// the frame's centre, and reads as a lens (to +0.16). Seed 1's sweep scenes 10
/// (640x480, k1 -0.17) and 21 (1280x720, k1 -0.24, the pivot at the frame's edge) were
/// filmed through a lens none was given for: their swings 1.3 and 10.0 % wide, `s_r` as
/// much, and called `ok`; the `pivot` check cannot see it (the wire's lines and its
/// angle bend alike). `None` with too few found frames (see `k1_from_bows`), or when
/// `wide` cannot say.
pub fn bent_check(
    rows: &[AngleRow],
    given: Option<&crate::lens::Lens>,
    frame: [u32; 2],
    wide: impl FnOnce(&crate::lens::Lens) -> Option<f64>,
) -> Option<DetectionCheck> {
    use crate::lens::{bow, Lens};
    let bows: Vec<bow::Bowed> = rows
        .iter()
        .filter(|r| r.status == Status::Ok && r.flag.is_none())
        .filter_map(|r| r.moments.as_ref()?.bow)
        .collect();
    let wire = bow::k1_from_bows(&bows, frame[0], frame[1])?;
    let (k_given, u_given) = given.map_or((0.0, 0.0), |l| (l.k1, l.u_k1));
    let u = wire
        .u_k1
        .hypot(u_given)
        .hypot(BENT_REL_U * wire.k1.abs())
        .hypot(BENT_MIN_U);
    let sigmas = (wire.k1 - k_given).abs() / u;
    let through = match given {
        Some(l) => format!("the lens given, {:+.3}", l.k1),
        None => "no lens given, 0".to_string(),
    };
    let bows = format!(
        "the wire bows as a straight line does through a lens of k1 {:+.3} +- {:.3} ({} \
         frames), {sigmas:.1} uncertainties from the angles' ({through})",
        wire.k1, u, wire.frames,
    );
    if sigmas <= BENT_SIGMAS {
        return Some(check(
            "bent",
            sigmas,
            BENT_SIGMAS,
            true,
            format!("{bows} (at most {BENT_SIGMAS})"),
            "",
        ));
    }
    let share = wide(&Lens::new(wire.k1, u, frame[0], frame[1]))?;
    Some(check(
        "bent",
        share.abs(),
        LENS_SCALE_MAX,
        share.abs() <= LENS_SCALE_MAX,
        format!(
            "{bows}: the swing measured is {:.2} % {} than through it (at most {:.2} %)",
            100.0 * share.abs(),
            if share > 0.0 { "wider" } else { "narrower" },
            100.0 * LENS_SCALE_MAX,
        ),
        &format!(
            "the video was filmed through a lens that bends the picture {}: give \
             `video.lens` (`rollfric lens` fits it from a picture of straight lines; the \
             wire's bow gives `lens: {{k1: {:.3}, u_k1: {:.3}}}`)",
            if given.is_some() {
                "otherwise than the lens given"
            } else {
                "and none was given"
            },
            wire.k1,
            u
        ),
    ))
}

/// `turn`: a moving camera's frames, each steadied by the turn measured for it, hold
/// angles whose noise from frame to frame does not move with that turn. Where the
/// static scene fixes the turn poorly (a plain plate's faint shading), the measured turn
/// errs, and each angle with it: the fourth differences of the angles, regressed on
/// those of the turns over the same runs of five found frames, then explain a share
/// `R^2` of them. The figure is the part of the angle's noise (reckoned as
/// [`Seen::noise_deg`] is, over the runs whose frames were all steadied) that moves
/// with the turn, `noise * sqrt(R^2)`, deg; judged when the regression's slope stands
/// [`TURN_FOLLOW_SIGNIFICANCE`] standard errors from 0 (reckoned as though the runs were
/// independent: neighbouring runs share frames, so the true standard error is about
/// 1.6 times larger for white noise, and the 4 of the limit about 2.5).
/// A frame whose turn the scene did not fix at all had it held at none (`None` in
/// `turns`; see `Steady::steadying`): its angle carries the camera's whole turn. Those
/// frames' share of the steadied ones, times the RMS of the turns measured on the
/// others, is the figure then, when it is the larger: the RMS the unmeasured turns add
/// to the angles (a hand-held twin turning 0.46 deg had half its frames held, and was
/// called `ok` 0.09 deg RMS off).
/// Where no steadied frame's turn was measured at all (none but exactly none: the first
/// frame's, steadied onto itself, and those of frames that could not be measured, held
/// at the last), there is nothing to reckon the held turns by: the angles carry the
/// camera's whole turn, of a size not known, and the check fails, its figure 1 (every
/// turn unknown; at most none).
/// A 1280x720 sweep twin on a tripod swaying 1.1 px and 0.05 deg at 0.27 Hz over a
/// plain plate had every turn held: its angles 0.038 deg RMS off the truth, called `ok`.
/// `None` without a steadied frame, or with fewer than twenty runs and no frame held.
pub fn turn_check(
    rows: &[AngleRow],
    turns: &[crate::detect::steady::Turn],
) -> Option<DetectionCheck> {
    debug_assert!(
        turns.windows(2).all(|w| w[0].0 < w[1].0),
        "the turns in frame order"
    );
    if !turns.is_empty() && turns.iter().all(|t| t.1.is_none_or(|r| r == 0.0)) {
        return Some(check(
            "turn",
            1.0,
            0.0,
            false,
            format!(
                "the turn of every steadied frame ({}) could not be measured and was held at \
                 none: their angles carry the camera's whole turn, of a size not known",
                turns.len()
            ),
            "the static scene fixes the camera's shift but not its turn, and each angle \
             carries the turn",
        ));
    }
    let held = turns_held(turns);
    let turn_at = |frame: u64| {
        turns
            .binary_search_by_key(&frame, |t| t.0)
            .ok()
            .map(|i| turns[i].1.unwrap_or(0.0))
    };
    let turn: Vec<Option<f64>> = rows.iter().map(|row| turn_at(row.frame)).collect();
    let pairs = paired_fourth_differences(rows, &turn);
    let (sxx, syy) = (
        pairs.iter().map(|p| p.0 * p.0).sum::<f64>(),
        pairs.iter().map(|p| p.1 * p.1).sum::<f64>(),
    );
    let judged = pairs.len() >= 20 && sxx > 0.0 && syy > 0.0;
    if let Some((deg, share, rms)) = held.filter(|h| !judged || h.0 > TURN_FOLLOW_MAX_DEG) {
        return Some(check(
            "turn",
            deg,
            TURN_FOLLOW_MAX_DEG,
            deg <= TURN_FOLLOW_MAX_DEG,
            format!(
                "the turn of {:.0} % of the steadied frames could not be measured and was \
                 held at none, while the others turned {rms:.3} deg RMS: their angles carry \
                 about {deg:.4} deg RMS of turn (at most {TURN_FOLLOW_MAX_DEG} deg)",
                100.0 * share
            ),
            "the static scene fixes the camera's turn poorly, and each angle carries the \
             turn's error",
        ));
    }
    if !judged {
        return None;
    }
    let sxy: f64 = pairs.iter().map(|p| p.0 * p.1).sum();
    let (_, z) = slope_through_origin(&pairs)?;
    let z = z.abs();
    let r2 = (sxy * sxy / (sxx * syy)).min(1.0);
    let noise = noise_of(pairs.iter().map(|p| p.1)).to_degrees();
    let moves = noise * r2.sqrt();
    let significant = z >= TURN_FOLLOW_SIGNIFICANCE;
    Some(check(
        "turn",
        moves,
        TURN_FOLLOW_MAX_DEG,
        moves <= TURN_FOLLOW_MAX_DEG || !significant,
        format!(
            "{moves:.4} deg of the angle's {noise:.4} deg noise from frame to frame moves \
             with the turn each frame was steadied by ({:.0} % of the variance of its \
             fourth differences, {z:.1} standard errors{}; at most {TURN_FOLLOW_MAX_DEG} deg)",
            100.0 * r2,
            if significant { "" } else { ", not significant" }
        ),
        "the static scene fixes the camera's turn poorly, and each angle carries the \
         turn's error",
    ))
}

/// Of steadied frames' `turns`, those held at none (see [`turn_check`]): the RMS they
/// add to the angles, deg (their share's square root times the RMS of the turns
/// measured on the others), their share, and that RMS, deg. `None` when none was held
/// or none measured.
fn turns_held(turns: &[crate::detect::steady::Turn]) -> Option<(f64, f64, f64)> {
    let measured: Vec<f64> = turns.iter().filter_map(|t| t.1).collect();
    let held = turns.len() - measured.len();
    if held == 0 || measured.is_empty() {
        return None;
    }
    let rms = (measured.iter().map(|r| r * r).sum::<f64>() / measured.len() as f64)
        .sqrt()
        .to_degrees();
    let share = held as f64 / turns.len() as f64;
    Some((share.sqrt() * rms, share, rms))
}

/// `polarity`: lines of the polarity the first look did not take swing about the same
/// pivot in nearly as many directions, a steady angle off the lines taken (`r`): a wire
/// and its shadow, one light and one dark, and which one was followed the look cannot
/// tell (a light 1 px wire's dark shadow, drawn 4.8 deg off and seen 4.7 deg off, was
/// taken for it).
/// Always failed: made only when there is such a rival.
pub fn polarity_check(r: &crate::detect::geometry::RivalPolarity) -> DetectionCheck {
    let (taken, other) = if r.dark {
        ("light", "dark")
    } else {
        ("dark", "light")
    };
    let share = r.directions as f64 / r.of.max(1) as f64;
    check(
        "polarity",
        share,
        RIVAL_POLARITY_SHARE,
        false,
        format!(
            "{other} lines swing about the same pivot in {} directions against the {taken} \
             lines' {} that were followed, {:.1} deg from them and steadily so (its quartiles \
             {:.2} deg apart) in the frames both show",
            r.directions, r.of, r.offset_deg, r.spread_deg
        ),
        &format!(
            "a wire and its shadow look alike here; `video.polarity: {other}` measures the \
             other line, `{taken}` keeps this one"
        ),
    )
}

/// `length`: the period seen is the experiment's pendulum's. The period (corrected to
/// small swings by `1 + A^2 / 16` at the mean amplitude `A` seen, as the fit's) implies
/// a length `d` (ERRATA §2's small-angle period inverted,
/// [`crate::physics::Pendulum::d_from_swing_period`]),
/// which must lie within the experiment's `tolerances.period_rel` of the geometry's, as
/// the fit's `period` check judges its own period. A track that follows another
/// pendulum swinging in the room fails it, whatever its other checks say: seed 31's
/// sweep scene 1 (a ball held still for the first look's 1.5 s while a second string
/// swung beside it) followed the second string, 1.612 s against the pendulum's 3.2 s,
/// 5.9 deg RMS off and called `ok`. `None` without a period seen or a pendulum given.
pub fn length_check(seen: &Seen, given: &crate::detect::PendulumGiven) -> Option<DetectionCheck> {
    let period = seen.period_s?;
    let amp = match (seen.amplitude_start_deg, seen.amplitude_end_deg) {
        (Some(a), Some(b)) => 0.5 * (a + b),
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => 0.0,
    }
    .to_radians();
    let p = &given.pendulum;
    let d = p.d_from_swing_period(period, amp);
    let dev = d / p.d - 1.0;
    Some(check(
        "length",
        dev.abs(),
        given.d_rel,
        dev.abs() <= given.d_rel,
        format!(
            "the period seen, {period:.3} s, implies d = {d:.4} m; the geometry says {:.4} m \
             ({:+.1} %, at most {:.0} % either way)",
            p.d,
            100.0 * dev,
            100.0 * given.d_rel
        ),
        "the track may follow something other than this pendulum's wire (a second pendulum, \
         a line in the room), or the geometry's `d` is wrong: give `video.pivot` or \
         `video.roi`, or check `geometry.pendulum.d_m`",
    ))
}
