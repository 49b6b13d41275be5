//! Whether a detection saw a pendulum's wire: what it saw, in numbers (the period, the
//! amplitude at the start and at the end, the pivot with its uncertainty, the share of
//! frames found), and named checks on it, each with its figure and its limit. A failed
//! check makes the detection `suspect`; the fit's verdict takes it over.

mod swing;

use super::{AngleRow, Status};
use crate::detect::tuning::{
    CROSSED_MIN, ENVELOPE_MAX_DEG, ENVELOPE_NOISE_FACTOR, ENVELOPE_SHARE, FOUND_MIN, HYSTERESIS,
    LENS_SCALE_MAX, NOISE_SHARE_MAX, PERIOD_SPREAD_MAX, PIVOT_SCALE_MAX, REST_NOISE_FACTOR,
    REST_WANDER_MAX_DEG, RHYTHM_MAX, RIVAL_POLARITY_SHARE, STALL_RANGE, STALL_SHARE_MAX,
    STALL_WINDOW, STILL_MAX_PX, TURNS_MIN, TURN_FOLLOW_MAX_DEG, TURN_FOLLOW_SIGNIFICANCE,
    WANDER_MIN_DEG, WANDER_NOISE_FACTOR,
};
use crate::verdict::Status as Verdict;
use serde::{Deserialize, Serialize};
use swing::*;
pub(in crate::detect) use swing::{paired_fourth_differences, slope_through_origin};

/// What the detector saw, without any geometry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Seen {
    /// The median period of the swing (between crossings of the rest angle in the same
    /// sense), s; `None` with fewer than two whole swings.
    pub period_s: Option<f64>,
    /// Whole swings seen.
    pub swings: usize,
    /// The swing's amplitude about the rest angle, deg: the mean of the first two and of
    /// the last two turning points.
    pub amplitude_start_deg: Option<f64>,
    pub amplitude_end_deg: Option<f64>,
    /// The rest angle (from the image's x axis), deg.
    pub rest_deg: Option<f64>,
    /// The pivot, px, and the radius of its standard uncertainty, px (from the scatter
    /// of the wire's lines about it).
    pub pivot_px: [f64; 2],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pivot_u_px: Option<f64>,
    /// How far the wire's lines pass the pivot over a couple of seconds at most, as an
    /// angle seen from the middle of the wire's visible band, deg (a camera that moved
    /// unfollowed makes it large; real strings, which bow, give up to 0.3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pivot_drift_deg: Option<f64>,
    /// The share of frames the wire was found in (`ok`).
    pub ok_share: f64,
    /// The angle's noise from frame to frame, deg (the fourth differences of runs of
    /// five found frames, a robust RMS); `None` with fewer than twenty such runs.
    pub noise_deg: Option<f64>,
}

/// One check of a detection.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DetectionCheck {
    /// `found`, `turns`, `crossed`, `period`, `rhythm`, `smooth`, `wander`, `stalls`,
    /// `rest`, `envelope`, `still`, `turn`, `polarity`, `lens` or `pivot`.
    pub check: String,
    pub value: f64,
    pub limit: f64,
    pub passed: bool,
    /// One line: what was measured against what.
    pub reason: String,
}

/// A detection's verdict: `suspect` when a check failed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DetectionVerdict {
    pub verdict: Verdict,
    pub checks: Vec<DetectionCheck>,
    pub seen: Seen,
}

impl DetectionVerdict {
    /// The failed checks.
    pub fn failed(&self) -> impl Iterator<Item = &DetectionCheck> {
        self.checks.iter().filter(|c| !c.passed)
    }

    /// `ok` or `suspect (period, smooth)`.
    pub fn label(&self) -> String {
        let names: Vec<&str> = self.failed().map(|c| c.check.as_str()).collect();
        if names.is_empty() {
            "ok".into()
        } else {
            format!("suspect ({})", names.join(", "))
        }
    }
}

impl DetectionVerdict {
    /// The verdict with `c` among its checks (`suspect` when it failed).
    pub fn with(mut self, c: DetectionCheck) -> Self {
        if !c.passed {
            self.verdict = Verdict::Suspect;
        }
        self.checks.push(c);
        self
    }
}

/// `still`: a camera taken as still throughout, whose static scene (the pendulum's
/// sweep left out) is found displaced by more than [`STILL_MAX_PX`] (`reach_px`, at the
/// region's farthest corner) between the first frame and two glances in a row, moved
/// unfollowed: every angle carries the pivot's displacement (a tenth of a degree for
/// every 0.4 px at 230 px from the pivot).
pub fn still_check(reach_px: f64) -> DetectionCheck {
    check(
        "still",
        reach_px,
        STILL_MAX_PX,
        reach_px <= STILL_MAX_PX,
        format!(
            "the camera was taken as still, and the static scene lies {reach_px:.2} px from \
             where the first frame has it at two glances in a row (at most {STILL_MAX_PX} px)"
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
        .filter(|r| r.status == Status::Ok)
        .filter_map(|r| r.angle_rad.map(|a| (r.t_s, a)))
        .unzip();
    let scatter = super::fill::swing_scatter(&t, &a)?.to_degrees();
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
/// `None` without a steadied frame, or with fewer than twenty runs and no frame held.
pub fn turn_check(
    rows: &[AngleRow],
    turns: &[crate::detect::steady::Turn],
) -> Option<DetectionCheck> {
    debug_assert!(
        turns.windows(2).all(|w| w[0].0 < w[1].0),
        "the turns in frame order"
    );
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

impl Seen {
    /// One line: `period 1.333 s (8 swings), amplitude 29.00 -> 25.27 deg, pivot (570.0,
    /// 105.0) px +- 0.2, 100 % of frames ok, noise 0.0489 deg`.
    pub fn describe(&self) -> String {
        format!(
            "period {}, amplitude {} -> {} deg, pivot ({:.1}, {:.1}) px{}, {:.0} % of frames \
             ok, noise {} deg",
            self.period_s
                .map_or("-".into(), |p| format!("{p:.3} s ({} swings)", self.swings)),
            self.amplitude_start_deg
                .map_or("-".into(), |a| format!("{a:.2}")),
            self.amplitude_end_deg
                .map_or("-".into(), |a| format!("{a:.2}")),
            self.pivot_px[0],
            self.pivot_px[1],
            self.pivot_u_px
                .map_or(String::new(), |u| format!(" +- {u:.2}")),
            100.0 * self.ok_share,
            self.noise_deg.map_or("-".into(), |n| format!("{n:.4}"))
        )
    }
}

/// A check: `measured` says what was measured against what; `meaning`, what a failure
/// means, is added to it when the check failed.
fn check(
    name: &str,
    value: f64,
    limit: f64,
    passed: bool,
    measured: String,
    meaning: &str,
) -> DetectionCheck {
    DetectionCheck {
        check: name.into(),
        value,
        limit,
        passed,
        reason: if passed {
            measured
        } else {
            format!("{measured}: {meaning}")
        },
    }
}

/// What the rows saw, and the checks on it. `pivot_u_px` is the pivot's uncertainty,
/// `pivot_drift_deg` how far the wire's lines stray from it for a while, if known.
/// The swing of the angles `a` at times `t` about their rest angle (the median midpoint
/// of successive turning points, found about the middle of the central 90 % of the
/// angles): the rest angle, the amplitude's scale (half that range) and the swing.
fn swing_about_rest(t: &[f64], a: &[f64]) -> (f64, f64, Swing) {
    let mut sorted = a.to_vec();
    sorted.sort_by(f64::total_cmp);
    let pct = |p: f64| sorted[((sorted.len() - 1) as f64 * p).round() as usize];
    let (rest0, scale) = if sorted.is_empty() {
        (f64::NAN, f64::NAN)
    } else {
        (0.5 * (pct(0.05) + pct(0.95)), 0.5 * (pct(0.95) - pct(0.05)))
    };
    let first = swing(t, a, rest0, HYSTERESIS * scale);
    let rest = if first.turns.len() >= 2 {
        median(
            first
                .turns
                .windows(2)
                .map(|w| 0.5 * (w[0].1 + w[1].1))
                .collect(),
        )
    } else {
        rest0
    };
    (rest, scale, swing(t, a, rest, HYSTERESIS * scale))
}

/// A swing's median period, s (`None` with fewer than two whole swings), and its whole
/// swings.
fn period_of(sw: &Swing) -> (Option<f64>, usize) {
    let p = periods(sw);
    let swings = sw.up.len().min(sw.down.len()).saturating_sub(1);
    ((swings >= 2 && !p.is_empty()).then(|| median(p)), swings)
}

/// Where the angles swing: the median period (as [`Seen::period_s`]), the first and
/// last crossings of the rest angle, s, and the amplitude's scale (half the range of
/// the central 90 % of the angles), rad.
pub(super) struct SwingSpan {
    pub period_s: f64,
    pub first_s: f64,
    pub last_s: f64,
    pub scale: f64,
}

/// The swing of the angles `a` at times `t` (none with fewer than two whole swings).
pub(super) fn swing_span(t: &[f64], a: &[f64]) -> Option<SwingSpan> {
    let (_, scale, sw) = swing_about_rest(t, a);
    let crossings = || sw.up.iter().chain(&sw.down).map(|c| c.0);
    Some(SwingSpan {
        period_s: period_of(&sw).0?,
        first_s: crossings().fold(f64::INFINITY, f64::min),
        last_s: crossings().fold(f64::NEG_INFINITY, f64::max),
        scale,
    })
}

pub fn judge(
    rows: &[AngleRow],
    pivot_px: [f64; 2],
    pivot_u_px: Option<f64>,
    pivot_drift_deg: Option<f64>,
) -> DetectionVerdict {
    let n = rows.len().max(1);
    let ok_share = rows.iter().filter(|r| r.status == Status::Ok).count() as f64 / n as f64;
    // The found frames' angles (the filled ones are the detector's guesses).
    let (t, a): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter(|r| r.status == Status::Ok)
        .filter_map(|r| r.angle_rad.map(|a| (r.t_s, a)))
        .unzip();
    let (rest, scale, sw) = swing_about_rest(&t, &a);
    let p = periods(&sw);
    let (period, swings) = period_of(&sw);
    let amp = |turns: &[(f64, f64)]| {
        (turns.len() == 2).then(|| {
            turns
                .iter()
                .map(|e| (e.1 - rest).abs())
                .sum::<f64>()
                .to_degrees()
                / 2.0
        })
    };
    let k = sw.turns.len();
    let (amp_start, amp_end) = if k >= 4 {
        (amp(&sw.turns[..2]), amp(&sw.turns[k - 2..]))
    } else {
        (None, None)
    };
    // The noise, from runs of five found frames (at least twenty of them).
    let d4 = fourth_differences(rows);
    let noise = (d4.len() >= 20).then(|| noise_of(d4.iter().map(|d| d.1)));
    let noise0 = noise.unwrap_or(0.0);
    let seen = Seen {
        period_s: period,
        swings,
        amplitude_start_deg: amp_start,
        amplitude_end_deg: amp_end,
        rest_deg: rest.is_finite().then(|| rest.to_degrees()),
        pivot_px,
        pivot_u_px,
        pivot_drift_deg,
        ok_share,
        noise_deg: noise.map(f64::to_degrees),
    };
    // found: judged up to the swing's end when the pendulum came to rest before the
    // video's (its wire at rest fades into the still scene, and is not looked for).
    let end = period.and_then(|p| swing_end(&t, &a, rest, scale, p));
    let (found_share, until) = match end {
        Some(end) => {
            let (judged, ok) = rows
                .iter()
                .filter(|r| r.t_s <= end)
                .fold((0usize, 0usize), |(n, ok), r| {
                    (n + 1, ok + usize::from(r.status == Status::Ok))
                });
            (
                ok as f64 / judged.max(1) as f64,
                format!(
                    " up to {end:.1} s, a period after the swing died out ({:.0} % of all)",
                    100.0 * ok_share
                ),
            )
        }
        None => (ok_share, String::new()),
    };
    let mut checks = vec![check(
        "found",
        found_share,
        FOUND_MIN,
        found_share >= FOUND_MIN,
        format!(
            "the wire was found in {:.0} % of the frames{until} (at least {:.0} % expected)",
            100.0 * found_share,
            100.0 * FOUND_MIN
        ),
        "no wire seen in many frames: the detector lost it, or followed something it often \
         lost (a frame off the path of those about it is not found)",
    )];
    // turns: a wire swinging turns back at every half swing. With fewer turning points
    // than the fit needs, the checks on the motion (period, rest, envelope) have nothing
    // to judge, and a track that followed something else, far from the wire, would pass
    // them all (a hand-held 640x480 sweep twin: 11.7 deg RMS off, no turning point,
    // called `ok`).
    let turns = sw.turns.len();
    checks.push(check(
        "turns",
        turns as f64,
        TURNS_MIN as f64,
        turns >= TURNS_MIN,
        format!(
            "the angle turned back {turns} times (a swinging wire's, in a video the fit can \
             use, at least {TURNS_MIN} times)"
        ),
        "what was followed does not swing: not the wire, or a wire at rest",
    ));
    // crossed: a wire swinging is seen where it moves fastest, crossing its rest angle.
    // A track that loses it there at every half swing (and picks up something else
    // beside it: a shadow) has no crossing timed, and no period to judge (a sweep twin
    // on its shadow at one side of each swing, 2.2 deg RMS, was called `ok` so).
    if sw.sides >= TURNS_MIN {
        let timed = (sw.up.len() + sw.down.len()) as f64 / sw.sides as f64;
        checks.push(check(
            "crossed",
            timed,
            CROSSED_MIN,
            timed >= CROSSED_MIN,
            format!(
                "{:.0} % of the swing's {} crossings of its rest angle were seen (at least \
                 {:.0} %)",
                100.0 * timed,
                sw.sides,
                100.0 * CROSSED_MIN
            ),
            "the track loses the wire where it moves fastest, and may take up something \
             beside it",
        ));
    }
    // period: a pendulum's period holds from swing to swing (judged on four periods or
    // more).
    if let Some(m) = period.filter(|_| p.len() >= 4) {
        let spread = 1.4826 * median(p.iter().map(|x| (x - m).abs()).collect()) / m;
        checks.push(check(
            "period",
            spread,
            PERIOD_SPREAD_MAX,
            spread <= PERIOD_SPREAD_MAX,
            format!(
                "the period is {m:.3} s and varies by {:.1} % from swing to swing (a \
                 pendulum's holds within {:.0} %)",
                100.0 * spread,
                100.0 * PERIOD_SPREAD_MAX
            ),
            "what was followed does not swing as a wire does (no wire seen: a ball's edge, a \
             shadow?)",
        ));
    }
    // rhythm: a pendulum turns back once every half period, so its turning points come
    // at the pace its crossings of the rest angle give. A track that jumps between things
    // (a static edge, the wire now and then) can cross its "rest" in quick flicks and
    // turn back seldom: seed 4's sweep scene 48 crossed every 0.27 s and turned back
    // every 0.91 s, 6.1 deg RMS off, and every other check passed.
    if let Some(m) = period.filter(|_| turns >= TURNS_MIN) {
        let (first, last) = (sw.turns[0].0, sw.turns[turns - 1].0);
        let half = (last - first) / (turns - 1) as f64;
        let ratio = half / (0.5 * m);
        checks.push(check(
            "rhythm",
            ratio,
            RHYTHM_MAX,
            (1.0 / RHYTHM_MAX..=RHYTHM_MAX).contains(&ratio),
            format!(
                "the angle turned back every {half:.3} s, {ratio:.2} times the half period \
                 its crossings give ({:.3} s; a pendulum's agree within a factor {:.2})",
                0.5 * m,
                RHYTHM_MAX
            ),
            "what was followed does not swing as a wire does (it jumps between things)",
        ));
    }
    // smooth: the frame-to-frame noise is small against the swing.
    if let Some(noise) = noise {
        let share = noise / scale;
        let share = if share.is_finite() {
            share
        } else {
            f64::INFINITY
        };
        checks.push(check(
            "smooth",
            share,
            NOISE_SHARE_MAX,
            share <= NOISE_SHARE_MAX,
            format!(
                "the angle's noise from frame to frame is {:.4} deg, {:.2} % of the swing's \
                 {:.2} deg (a wire's is under {:.2} %)",
                noise.to_degrees(),
                100.0 * share,
                scale.to_degrees(),
                100.0 * NOISE_SHARE_MAX
            ),
            "what was followed jitters, as a faint or broken line does",
        ));
    }
    // stalls: a wire swinging through holds still only at its turning points, and
    // there for a moment; an angle that holds over a tenth of a period between the
    // first and the last frame of the swing (away from a held start and a stop at the
    // end) is the track resting on something static.
    let per_frame = median(t.windows(2).map(|w| w[1] - w[0]).collect());
    let h = HYSTERESIS * scale;
    let swinging = |x: &&f64| (*x - rest).abs() > h;
    let span = (
        a.iter()
            .position(|x| swinging(&x))
            .map_or(f64::INFINITY, |i| t[i]),
        a.iter()
            .rposition(|x| swinging(&x))
            .map_or(f64::NEG_INFINITY, |i| t[i]),
    );
    let window = ((STALL_WINDOW * period.unwrap_or(1.0) / per_frame).round() as usize).max(3);
    let stall_share = if a.len() > window {
        stalled_frames(&t, &a, window, rest, span) as f64 / n as f64
    } else {
        0.0
    };
    checks.push(check(
        "stalls",
        stall_share,
        STALL_SHARE_MAX,
        stall_share <= STALL_SHARE_MAX,
        format!(
            "the angle holds still (within {:.0} % of the swing's amplitude over {window} \
             frames) in {:.1} % of the frames while it swings (at most {:.0} %)",
            100.0 * STALL_RANGE,
            100.0 * stall_share,
            100.0 * STALL_SHARE_MAX
        ),
        "the track rests on something static for a while",
    ));
    // rest: the rest angle, from each three successive turning points (where rolling
    // friction's linear decay cancels), holds, or drifts slowly and evenly (a swing
    // measured a little asymmetrically, whose asymmetry shrinks with it: real footage
    // drifts by up to 0.04 deg/s); a camera that turns, or a pivot that moves, makes it
    // wander about its trend. The limit grows with what the angle noise alone gives.
    let half = ((0.05 * period.unwrap_or(1.0) / per_frame).round() as usize).max(2);
    let rests = rest_from_turns(&t, &a, &sw.turns, half);
    if rests.len() >= 4 {
        let wander = detrended_rms(&rests).to_degrees();
        let limit = REST_WANDER_MAX_DEG
            .max(REST_NOISE_FACTOR * noise0.to_degrees() * 0.92 / ((2 * half + 1) as f64).sqrt());
        checks.push(check(
            "rest",
            wander,
            limit,
            wander <= limit,
            format!(
                "the rest angle, from each three successive turning points, wanders about its \
                 trend by {wander:.3} deg RMS (at most {limit:.3} deg at this noise)"
            ),
            "the camera turned or the pivot moved, and the detector did not follow",
        ));
    }
    // envelope: the swing from turning point to turning point shrinks smoothly (a
    // parabola in time holds any rolling-friction law and the air); a track that
    // leaves the wire for a while, or a camera that sways unfollowed, scatters it.
    let sp = spans(&t, &a, &sw.turns, half);
    if sp.len() >= 6 {
        let scatter = quadratic_rms(&sp).to_degrees();
        let mean_span = sp.iter().map(|p| p.1).sum::<f64>() / sp.len() as f64;
        let limit = ENVELOPE_MAX_DEG
            .max(ENVELOPE_SHARE * mean_span.to_degrees())
            .max(
                ENVELOPE_NOISE_FACTOR * noise0.to_degrees() * 1.5 * 2f64.sqrt()
                    / ((2 * half + 1) as f64).sqrt(),
            );
        checks.push(check(
            "envelope",
            scatter,
            limit,
            scatter <= limit,
            format!(
                "the swings from turning point to turning point scatter about a smooth decay \
                 by {scatter:.3} deg RMS (at most {limit:.3} deg at this noise and swing)"
            ),
            "for a while the track left the wire, or the camera swayed unfollowed",
        ));
    }
    let verdict = if checks.iter().all(|c| c.passed) {
        Verdict::Ok
    } else {
        Verdict::Suspect
    };
    DetectionVerdict {
        verdict,
        checks,
        seen,
    }
}

#[cfg(test)]
mod tests;
