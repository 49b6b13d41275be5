//! Whether a detection saw a pendulum's wire: what it saw, in numbers (the period, the
//! amplitude at the start and at the end, the pivot with its uncertainty, the share of
//! frames found), and named checks on it, each with its figure and its limit. A failed
//! check makes the detection `suspect`; the fit's verdict takes it over.

mod added;
mod swing;

use super::{AngleRow, Status};
use crate::detect::tuning::{
    BENT_MIN_U, BENT_REL_U, BENT_SIGMAS, BESIDE_MAX_SHARE, BESIDE_MIN_SAMPLES, BESIDE_TOL_DEG,
    CROSSED_MIN, ENVELOPE_MAX_DEG, ENVELOPE_NOISE_FACTOR, ENVELOPE_SHARE, FOUND_MIN, GROWTH_MAX,
    HYSTERESIS, LENS_SCALE_MAX, NOISE_SHARE_MAX, PERIODS_MIN, PERIOD_SPREAD_MAX, PIVOT_SCALE_MAX,
    REST_NOISE_FACTOR, REST_WANDER_MAX_DEG, RHYTHM_MAX, RIVAL_POLARITY_SHARE, STALL_RANGE,
    STALL_SHARE_MAX, STALL_WINDOW, STILL_MAX_PX, TURNS_MIN, TURN_FOLLOW_MAX_DEG,
    TURN_FOLLOW_SIGNIFICANCE, UNTIMED_TURNS_MIN, WANDER_MIN_DEG, WANDER_NOISE_FACTOR,
};
use crate::verdict::Status as Verdict;
pub use added::*;
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
    /// `rest`, `envelope`, `decays`, `still`, `turn`, `polarity`, `lens`, `bent`, `pivot`
    /// or `length`.
    pub check: String,
    /// The measured figure; infinite where it has no finite size (a noise of zero, a
    /// swing of none). JSON has no infinity: such a figure is written as `null` and
    /// read back as infinite, so that a detection's summary reads back whole.
    #[serde(deserialize_with = "null_is_infinite")]
    pub value: f64,
    pub limit: f64,
    pub passed: bool,
    /// One line: what was measured against what.
    pub reason: String,
}

/// A check's figure as JSON holds it: a number, or `null` for the infinite figure
/// `serde_json` writes so (see [`DetectionCheck::value`]).
fn null_is_infinite<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
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

    /// Whether this verdict fails fewer checks than `other`, and none that `other`
    /// passed: a second measurement that fixed some of the first's failures and broke
    /// nothing the first got right.
    pub fn fails_a_part_of(&self, other: &DetectionVerdict) -> bool {
        self.part_of(other, |_| false)
    }

    /// Whether this verdict's failures, those `aside` left out, are fewer than
    /// `other`'s and each among them.
    fn part_of(&self, other: &DetectionVerdict, aside: impl Fn(&DetectionCheck) -> bool) -> bool {
        let theirs: Vec<&str> = other.failed().map(|c| c.check.as_str()).collect();
        let mine = || self.failed().filter(|c| !aside(c));
        mine().count() < theirs.len() && mine().all(|c| theirs.contains(&c.check.as_str()))
    }

    /// Whether this verdict, of a measurement steadied throughout, fails a part of
    /// `first`'s, of the measurement that took the camera for still at first (see
    /// [`Self::fails_a_part_of`]), its `turn` aside when `first` was never judged by
    /// `turn` (no frame of it was steadied) and failed a check besides `still`. `turn`
    /// judges a steadied measurement: the error that misread turns add to its angles. A
    /// first measurement that took the camera for still throughout was never judged by
    /// it: it carried the camera's motion whole, and its own angles showed it. Seed 53's
    /// sweep scene 13 (a tripod swaying 1.1 px and 0.08 deg at 0.6 Hz, the fulcrum left
    /// of a 1280x720 frame): measured first, `suspect (rest, envelope, still)`, 0.205 deg
    /// RMS off the truth; steadied, `suspect (turn)`, 0.0138 deg of its 0.0154 deg noise
    /// moving with the turn, and 0.018 deg RMS off. A first measurement steadied from the
    /// moment the camera was found moving has its own `turn`, passed or failed, and is
    /// compared as [`Self::fails_a_part_of`] compares.
    pub fn steadied_fails_a_part_of(&self, first: &DetectionVerdict) -> bool {
        let harmed = first.failed().any(|c| c.check != "still")
            && first.checks.iter().all(|c| c.check != "turn");
        self.part_of(first, |c| harmed && c.check == "turn")
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
    // The found frames' angles (the filled ones are the detector's guesses), and those
    // seen on the wire where something static pulled it, filled from the frames either
    // side ([`AngleRow::seen_on_wire`]): a rod through the fulcrum near the rest angle
    // would otherwise take the swing's crossings, and a share of the frames found,
    // with it.
    let seen_share = rows.iter().filter(|r| r.seen_on_wire()).count() as f64 / n as f64;
    let (t, a): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter(|r| r.seen_on_wire())
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
                    (n + 1, ok + usize::from(r.seen_on_wire()))
                });
            (
                ok as f64 / judged.max(1) as f64,
                format!(
                    " up to {end:.1} s, a period after the swing died out ({:.0} % of all)",
                    100.0 * seen_share
                ),
            )
        }
        None => (seen_share, String::new()),
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
    // decays: friction and the air only take amplitude from a pendulum left to itself, so
    // its last turning points lie no farther from rest than its first. A track that ends on
    // something else can swing wider: seed 31's sweep scene 8 (a shadow 4.5 deg off, the
    // wire found only in pieces, no period to judge) grew from 8.25 to 10.83 deg, 0.77 deg
    // RMS off, and every other check passed.
    if let (Some(a0), Some(a1)) = (amp_start, amp_end) {
        let growth = a1 / a0 - 1.0;
        checks.push(check(
            "decays",
            growth,
            GROWTH_MAX,
            growth <= GROWTH_MAX,
            format!(
                "the swing went from {a0:.2} to {a1:.2} deg ({:+.1} %; a pendulum left to itself \
                 loses amplitude: at most {:+.0} %)",
                100.0 * growth,
                100.0 * GROWTH_MAX
            ),
            "the track ended on something other than the wire it began on, or the swing was \
             driven",
        ));
    }
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
    if let Some(m) = period.filter(|_| p.len() >= PERIODS_MIN) {
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
    } else if turns >= UNTIMED_TURNS_MIN {
        // Untimed: a swing long enough to time its period many times, whose crossings of
        // the rest angle each lie in a run of found frames of their own (the track lost
        // what it followed for 0.2 s or more once a swing or more), has no period to
        // judge, nor a rhythm: seed 53's sweep scene 48 (a faint wire beside its shadow
        // 5.5 deg off, a drift, a walker), lost in every swing, was called `ok` so, 0.65
        // deg RMS off, its crossings seen at 45 % (downwards 8 of 11, upwards 2).
        checks.push(check(
            "period",
            p.len() as f64,
            PERIODS_MIN as f64,
            false,
            format!(
                "the angle turned back {turns} times, but its period was timed {} times from \
                 a crossing of its rest angle to the next within a run of found frames, in \
                 {swings} whole swings (at least {PERIODS_MIN}, in 2): the track was lost in \
                 every swing",
                p.len()
            ),
            "what was followed is lost once a swing or more: the wire only part of the time \
             (a shadow, a ball's edge)?",
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
