//! Choosing between measurements of one video made from different looks: the first
//! look's and the other working scale's ([`Pass`]), and a look against the median alone
//! where the first, against the running extreme, followed something that is not a wire
//! ([`against_median`]).

use super::first_look::FirstLook;
use super::stream::FoundTooFew;
use super::{measure, Detection};
use crate::detect::tuning::{LOOK_SWING_AGREE, LOOK_SWING_APART, TURNS_LONG_S};
use anyhow::Result;

/// How far a look's sweep lies from a track's swing (both deg), as the log of their
/// ratio, either way.
fn look_against_swing(sweep_deg: f64, swing_deg: f64) -> f64 {
    (sweep_deg / swing_deg).ln().abs()
}

/// A pass's swing, deg: twice its first amplitude, or, with too few turning points to
/// give one, the range of the angles it saw the wire at; `None` when that is nothing.
fn swing_deg(d: &Detection) -> Option<f64> {
    let seen = || {
        let (lo, hi) = d
            .rows
            .iter()
            .filter(|r| r.seen_on_wire())
            .filter_map(|r| r.angle_rad)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), a| {
                (lo.min(a), hi.max(a))
            });
        (hi - lo).to_degrees()
    };
    let swing = match d.verdict.seen.amplitude_start_deg {
        Some(a) => 2.0 * a,
        None => seen(),
    };
    (swing > 0.0).then_some(swing)
}

/// Whether `d`'s video is long enough ([`TURNS_LONG_S`], first row to last) that a wire
/// swinging in it turns back `TURNS_MIN` times or more.
fn long(d: &Detection) -> bool {
    match (d.rows.first(), d.rows.last()) {
        (Some(a), Some(b)) => b.t_s - a.t_s >= TURNS_LONG_S,
        _ => false,
    }
}

/// The end of step 3 of `detect_looked`: a look against the running extreme (the first
/// look's `stage` 0 or 2) keeps the trail of whatever passed, and a large bob's stripes
/// or rim, turning with it, can make the lines that meet in its pivot. When the pass
/// kept from it and the other working scale (`first`) does not swing as a wire does
/// (its period is not timed or varies from swing to swing: `period` failed; or its
/// track swung far more or less than its look swept, beyond [`LOOK_SWING_APART`] either
/// way; or it turned back too seldom for a wire in a video of [`TURNS_LONG_S`] or
/// more: `turns` failed there) or found the wire in too few frames ([`FoundTooFew`]),
/// the look is made again at
/// the first look's scale (`shrink`) against the median alone, which holds no trails,
/// and measured afresh (what the camera does judged anew, as for a finer scale's look).
/// It replaces `first` when [`Pass::replaced_by`] says so (its look agrees with its own
/// swing and the first's does not, or the first never swung; else a swing scale nearer
/// 1 and fewer failed checks), or when `first` measured nothing. An angle that only
/// jitters (`smooth`) is not enough: hand-held sweep twins whose steadying left it
/// noisy (seed 1206's scenes 14, 47 and 56) were measured again to no gain, one of
/// them (1920x1080, measured eight times over already) at 33 ms a frame. Nor are too
/// few turning points in a short video (an 8 s twin held for 1.5 s turns back three
/// times): film 1 under a jittery hand (shifts of 0.8 to 1.5 px at 2.3 to 6.1 Hz, turns
/// of 0.1 deg) took the light polarity, a static line the jitter made move, and its
/// track lay on it for seconds at a time and on the wire between, turning back 0 times
/// in 25.6 s; against the median it follows the wire.
///
/// Film 1 (the real off-screen pivot clip) cropped by 8 px a side: against the extreme
/// its look took the bob's stripes, seven lines meeting beside the bob at (1174, 328) px
/// and sweeping 87 deg, and its pass swung 7 deg, `suspect (found, decays, period,
/// smooth, still)`; against the median, seven lines through (981, -644) px sweeping
/// 24.3 deg, `ok`, its swing 24.4 deg as the clip cropped by 4 px (whose look against
/// the extreme saw only four lines meet, and went on to the median by itself). Moved by
/// a slow sway (1.5 px at 0.8 Hz, 0.1 deg), film 1 was refused (the wire found in 567
/// of 1535 frames, about a pivot at (763, 334) px); against the median it is `ok`.
pub(super) fn against_median(
    looks: &FirstLook,
    stage: usize,
    shrink: u32,
    first: Result<Detection>,
) -> Result<Detection> {
    let unlike = |d: &Detection| {
        d.verdict
            .failed()
            .any(|c| c.check == "period" || (c.check == "turns" && long(d)))
            || swing_deg(d)
                .is_some_and(|s| look_against_swing(d.look_sweep_deg, s) > LOOK_SWING_APART.ln())
    };
    let why = match &first {
        _ if !matches!(stage, 0 | 2) || looks.median_only => return first,
        Ok(d) if unlike(d) => format!("it is {}", d.verdict.label()),
        Err(e) if e.downcast_ref::<FoundTooFew>().is_some() => format!("{e:#}"),
        _ => return first,
    };
    let name = looks.input.name();
    eprintln!(
        "{name}: measured from a look against the running extreme, {why}: measuring again \
         from a look against the median alone"
    );
    let mut fresh = FirstLook {
        median_only: true,
        moving: false,
        follow_region: false,
        ..*looks
    };
    let again = fresh.at(shrink).and_then(|l| measure(&mut fresh, l));
    match (first, again) {
        (Ok(d), Ok(a)) if Pass::of(&d).replaced_by(Pass::of(&a), false) => Ok(Detection {
            decodings: a.decodings + d.decodings,
            ..a
        }),
        (Ok(d), Ok(a)) => {
            eprintln!(
                "{name}: against the median it is {} (measured first, {}): the first \
                 measurement is kept",
                a.verdict.label(),
                d.verdict.label()
            );
            Ok(Detection {
                decodings: a.decodings + d.decodings,
                ..d
            })
        }
        (Ok(d), Err(e)) => {
            eprintln!(
                "{name}: against the median it measures nothing ({e:#}): the first \
                 measurement is kept"
            );
            Ok(d)
        }
        (Err(_), Ok(a)) => Ok(a),
        (Err(e), Err(_)) => Err(e),
    }
}

/// What chooses between a pass and the other working scale's ([`detect_from`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Pass {
    /// How far its swing scale lies from 1 (`None`: not measured).
    pub(super) off: Option<f64>,
    /// The detection's checks it fails.
    pub(super) fails: usize,
    /// Its look's sweep and its track's first amplitude, deg.
    pub(super) look_sweep_deg: f64,
    pub(super) amplitude_deg: Option<f64>,
}

impl Pass {
    pub(super) fn of(d: &Detection) -> Self {
        Pass {
            off: d.swing_scale.map(|s| (s - 1.0).abs()),
            fails: d.verdict.failed().count(),
            look_sweep_deg: d.look_sweep_deg,
            amplitude_deg: d.verdict.seen.amplitude_start_deg,
        }
    }

    /// How far its look's sweep lies from its track's swing (twice its first amplitude),
    /// as the log of their ratio, either way.
    fn apart(self) -> Option<f64> {
        let a = self.amplitude_deg.filter(|a| *a > 0.0)?;
        Some(look_against_swing(self.look_sweep_deg, 2.0 * a))
    }

    /// Whether the other scale's pass `other` (or the look against the median alone's,
    /// [`against_median`]) replaces this one, measured again because its swing scale lay
    /// more than `SWING_SCALE_RETRY` from 1 (`by_scale`: the nearer is kept), or because
    /// its motion is not a pendulum's. Then `other` is kept when its
    /// look agrees with its own swing and this one's does not: a sweep within
    /// `LOOK_SWING_AGREE` of twice the first amplitude, against one beyond
    /// `LOOK_SWING_APART` (a look whose lines swept far more or less than its track swings
    /// saw something else than the pass followed), or when its look agrees and this one
    /// never swung (too few turning points for an amplitude). Else when its swing scale
    /// is nearer 1 and it fails fewer of the detection's checks. Film 1 (the real
    /// off-screen pivot clip) moved by hand was measured first on its wire, its look
    /// sweeping 24.3 deg and its track 24.4, its lines turning 0.998 times as much; at the
    /// other scale on the ball's beads, their look 88 deg and their track 7, their lines
    /// 1.002 times, failing four checks to the wire's five in its first 12 s.
    pub(super) fn replaced_by(self, other: Pass, by_scale: bool) -> bool {
        let Some(off) = other.off else {
            return false;
        };
        let nearer = off < self.off.unwrap_or(0.0);
        if by_scale {
            return nearer;
        }
        let agrees = |x: f64| x <= LOOK_SWING_AGREE.ln();
        let apart = |x: f64| x > LOOK_SWING_APART.ln();
        match (other.apart(), self.apart()) {
            (Some(x), Some(y)) if agrees(x) && apart(y) => true,
            (Some(x), Some(y)) if agrees(y) && apart(x) => false,
            // This pass never swung (too few turning points to give an amplitude), and
            // the other's look agrees with its own swing: the other followed a pendulum.
            (Some(x), None) if agrees(x) => true,
            _ => nearer && other.fails < self.fails,
        }
    }
}
