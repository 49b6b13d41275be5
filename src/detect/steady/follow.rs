//! Following the camera through a pass: a camera found moving later ([`Late`]), and
//! the frames' motions summed for the detection's record ([`CameraMotion`]).

use super::{Motion, Steady, Sweep};
use crate::detect::tuning::{
    HIDDEN_FOLLOW, HIDDEN_MIN_LOSS, HIDDEN_TIMES, LATE_AGREE, LATE_DRIFT_GLANCES, LATE_EVERY_S,
    LATE_EXPLAINS, LATE_GLANCES, MOVING_PX, PASS_FIRST_PRUNE_FRAMES, PASS_PRUNE_FRAMES,
    PRUNE_SHARE, SCENE_CHANGE_S, SCENE_CHANGE_SHARE, STILL_MAX_PX,
};
use crate::video::Frame;
use anyhow::Result;

/// A camera the first look saw still, glanced at every [`LATE_EVERY_S`] on the streaming
/// pass's own frames (the region of interest): once [`LATE_GLANCES`] glances in a row
/// find it moved (as the first look judges, [`MOVING_PX`] and `EXPLAINS`, or as one of
/// a drift, [`Late::drifts`]: its first glance does not count, so a drift takes three
/// glances in a row), every
/// frame from there on is measured and warped back onto the pass's first frame, within
/// the region, on the static scene (the pendulum's sweep left out), once that shows the
/// motion too. The glances read the whole region: with the sweep left out, the few
/// pixels a small region keeps let a wire the first look placed wrong turn a still
/// camera's glances after it.
pub(in crate::detect) struct Late {
    /// The pendulum's part of the region (see [`Sweep`]).
    sweep: Sweep,
    /// The video's largest side, px (the region's frames move with the whole picture).
    side: f64,
    /// The pass's first frame, kept until the camera is found to move.
    first: Option<Frame>,
    steady: Option<Steady>,
    next_t: f64,
    on: bool,
    /// Glances in a row that found the camera moved.
    glances: usize,
    /// The motions, measured afresh, of the glances in a row that found the camera
    /// moved by the weaker test and each near the one before (see [`Late::drifts`]).
    drift: Vec<Motion>,
    /// The last two glanced frames while the camera was taken as still (see
    /// [`Late::unfollowed`]) ...
    glanced: [Option<Frame>; 2],
    /// ... and the first.
    first_glanced: Option<Frame>,
    /// A glance found the camera still (see [`Late::moved_from_start`]).
    still_seen: bool,
    /// The static scene of the pass's first frame (the pendulum's sweep left out), that
    /// a glance found moved is measured on (see [`Late::unfollowed`]).
    on_scene: Option<Steady>,
    /// The last glance's displacement on the static scene, px at the region's farthest
    /// corner (none when it was not measured there) ...
    last_reach: Option<f64>,
    /// ... and the largest so far of the smaller of two glances' in a row.
    pair_reach: Option<f64>,
    /// The time of the frame the camera was found moving at.
    on_at: Option<f64>,
    followed: Followed,
}

impl Late {
    /// A camera to glance at, on frames (a region of a video of largest side `side`
    /// px) the pendulum sweeps `sweep` of.
    pub(in crate::detect) fn new(sweep: Sweep, side: f64) -> Self {
        Self {
            sweep,
            side,
            first: None,
            steady: None,
            next_t: 0.0,
            on: false,
            glances: 0,
            drift: Vec::new(),
            glanced: [None, None],
            first_glanced: None,
            still_seen: false,
            on_scene: None,
            last_reach: None,
            pair_reach: None,
            on_at: None,
            followed: Followed::default(),
        }
    }

    /// A camera known to move after the look (a pass found it): every frame of the
    /// region is measured and warped back onto the pass's first, on the static scene
    /// (`sweep` left out), from the first on.
    pub(in crate::detect) fn following(sweep: Sweep, side: f64) -> Self {
        Self {
            on: true,
            // The pass before found it still at first (not moved from the start).
            still_seen: true,
            ..Self::new(sweep, side)
        }
    }

    /// The pass's next frame, warped back when the camera has moved.
    pub(in crate::detect) fn offer(&mut self, f: &mut Frame) -> Result<()> {
        if self.on && self.steady.is_none() {
            self.steady = Some(Steady::new(f, Some(&self.sweep))?.within(self.side));
        }
        let Some(st) = &mut self.steady else {
            self.next_t = f.t_s + LATE_EVERY_S;
            self.steady = Some(Steady::new(f, None)?);
            self.first = Some(f.clone());
            return Ok(());
        };
        if !self.on {
            if f.t_s < self.next_t {
                return Ok(());
            }
            self.next_t = f.t_s + LATE_EVERY_S;
            // Kept for the end's look at the static scene (the older's buffer reused).
            if self.first_glanced.is_none() {
                self.first_glanced = Some(f.clone());
            }
            self.glanced.swap(0, 1);
            match &mut self.glanced[1] {
                Some(g) => g.clone_from(f),
                slot => *slot = Some(f.clone()),
            }
            let (w, h) = (f.width as f64, f.height as f64);
            let moved_px = st.measure(f)?.is_some_and(|m| m.reach(w, h) > MOVING_PX);
            // A glance that found the frame moved is measured on the static scene too (a
            // still camera's, which the pendulum does not pull, costs nothing more), and
            // counts when that motion explains the frame by `LATE_EXPLAINS`: a small
            // region that the swinging ball fills (124x82 px, a real clip, still) reads
            // 1.9 px there, at 0.98 to 1.03 of the loss unaligned; a tripod's sway over
            // a scene (0.46 Hz, 1280x720) 0.9 to 2.0 px at 0.48 to 0.72.
            let reach = if moved_px {
                let first = self.first.as_ref().expect("kept until the camera moves");
                let on_scene = match &mut self.on_scene {
                    Some(o) => o,
                    slot => slot.insert(Steady::new(first, Some(&self.sweep))?),
                };
                match on_scene.glance(f)? {
                    Some(m) if on_scene.explains_by(LATE_EXPLAINS)? => Some(m.reach(w, h)),
                    _ => None,
                }
            } else {
                None
            };
            if let (Some(a), Some(b)) = (self.last_reach, reach) {
                let pair = a.min(b);
                self.pair_reach = Some(self.pair_reach.map_or(pair, |p| p.max(pair)));
            }
            self.last_reach = reach;
            let moved = if moved_px {
                st.explains()? || Self::drifts(&mut self.drift, st, f)?
            } else {
                self.drift.clear();
                false
            };
            // Two glances in a row: a region that two rods or a shadow fill pulls one
            // glance of a still camera along now and then, not two running.
            self.glances = if moved { self.glances + 1 } else { 0 };
            self.still_seen |= !moved;
            if self.glances < LATE_GLANCES {
                return Ok(());
            }
            // The static scene (the pendulum's sweep left out) must show the motion too:
            // a still camera's glances that a wire or its shadow pulled along do not.
            let first = self.first.as_ref().expect("kept until the camera moves");
            let mut on_scene = Steady::new(first, Some(&self.sweep))?;
            if !on_scene
                .glance(f)?
                .is_some_and(|m| m.reach(w, h) > MOVING_PX)
            {
                self.glances = 0;
                self.drift.clear();
                self.still_seen = true;
                return Ok(());
            }
            // Followed from here on, its shift judged against the video's side (see
            // `Steady::within`); the glances, this one too, against the region's: a
            // small region's glances at a still camera are pulled further (a still
            // 960x540 clip turned upside down was found moving at 2 % of the video's).
            *st = on_scene.within(self.side);
            self.first = None;
            self.first_glanced = None;
            self.glanced = [None, None];
            self.on = true;
            self.on_at = Some(f.t_s);
        }
        let m = self.followed.next(st, f)?;
        st.undo(f, m)
    }

    /// Whether the glance at `f`, measured moved but not explaining the frame by
    /// `EXPLAINS`, is one of a drift: it explains it by [`LATE_EXPLAINS`], and measured
    /// afresh (from no motion) the frame is displaced near where the glance before was
    /// ([`LATE_AGREE`]), [`LATE_DRIFT_GLANCES`] times in a row. Heavy compression leaves
    /// most pixels off aligned or not (a drift of 11 px under CRF 35 explained a tenth
    /// of them, and went unfollowed: s_r 3 % off); a wire pulling the alignment does not
    /// displace the frame alike from glance to glance.
    fn drifts(drift: &mut Vec<Motion>, st: &mut Steady, f: &Frame) -> Result<bool> {
        let (w, h) = (f.width as f64, f.height as f64);
        let afresh = if st.explains_by(LATE_EXPLAINS)? {
            st.glance(f)?.filter(|m| m.reach(w, h) > MOVING_PX)
        } else {
            None
        };
        let Some(m) = afresh else {
            drift.clear();
            return Ok(false);
        };
        let near = |p: &Motion| {
            let d = Motion {
                dx: m.dx - p.dx,
                dy: m.dy - p.dy,
                rot_rad: m.rot_rad - p.rot_rad,
            };
            d.reach(w, h) < LATE_AGREE * m.reach(w, h).max(p.reach(w, h))
        };
        if !drift.last().is_none_or(near) {
            drift.clear();
        }
        drift.push(m);
        Ok(drift.len() >= LATE_DRIFT_GLANCES)
    }

    /// How far the static scene (the pendulum's sweep left out) moved from the pass's
    /// first frame at two glances in a row, when the camera was taken as still
    /// throughout, px at the farthest corner of the region: the smaller of the two (a
    /// person passing, or a shadow, displaces one glance, not a drift two in a row), at
    /// the last two glances, or at any two in a row that found the frame moved when
    /// those lie further (a tripod swaying every 2.2 s, each glance 2 s after the last,
    /// whose last two glances met it near its middle: 0.35 px at the last two, 1.37 px
    /// at the farthest two in a row; its angles 0.097 deg RMS off). Unless the first
    /// glance ([`LATE_EVERY_S`] in) lies displaced from the first frame by more than
    /// [`STILL_MAX_PX`], a motion that explains it ([`LATE_EXPLAINS`]: a camera bumped
    /// before the first glance, judged from the first frame), the last two are measured
    /// from the first glance too, the farther of them, and the nearer of the two
    /// readings is taken: a scene that has not moved since the first
    /// glance has not drifted, and what differs in the first frame lay in it (the hand
    /// that let the ball go: a still 960x540 twin under CRF 34 read 0.65 px off the first
    /// frame at its last two glances, 0.38 off the first glance; measured again steadied
    /// onto that first frame, its angles lay 0.082 deg RMS off the truth against 0.024;
    /// its first glance lay 0.27 px off the first frame). `None` when the camera was
    /// followed, or with fewer than two glances, or when no two glances in a row can be
    /// measured.
    pub(in crate::detect) fn unfollowed(&self) -> Result<Option<f64>> {
        let (Some(first), [Some(a), Some(b)]) = (&self.first, &self.glanced) else {
            return Ok(None);
        };
        if self.on {
            return Ok(None);
        }
        // The displacement of the last two glances from `on_scene`'s frame, the smaller
        // (`nearer`) or the larger.
        let off = |on_scene: &mut Steady, nearer: bool| -> Result<Option<f64>> {
            let mut reach: Option<f64> = None;
            for g in [a, b] {
                let Some(m) = on_scene.glance(g)? else {
                    return Ok(None);
                };
                let r = m.reach(g.width as f64, g.height as f64);
                reach = Some(reach.map_or(r, |p| if nearer { p.min(r) } else { p.max(r) }));
            }
            Ok(reach)
        };
        let mut on_scene = Steady::new(first, Some(&self.sweep))?;
        let mut reach = off(&mut on_scene, true)?;
        let earlier = self.first_glanced.as_ref().filter(|g| g.t_s < a.t_s);
        if let (Some(r), Some(g)) = (reach, earlier) {
            let moved = on_scene
                .glance(g)?
                .map(|m| m.reach(g.width as f64, g.height as f64));
            let shifted = match moved {
                Some(px) => px > STILL_MAX_PX && on_scene.explains_by(LATE_EXPLAINS)?,
                None => false,
            };
            let since = if shifted {
                None
            } else {
                off(&mut Steady::new(g, Some(&self.sweep))?, false)?
            };
            if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                eprintln!(
                    "steady: the last two glances {r:.3} px off the first frame, {since:?} \
                     off the first glance, which lies {moved:?} px off the first frame \
                     (bumped: {shifted})"
                );
            }
            if let Some(since) = since {
                reach = Some(r.min(since));
            }
        }
        Ok(reach.into_iter().chain(self.pair_reach).reduce(f64::max))
    }

    /// Whether the camera was found moving by glances none before which found it still:
    /// it moved from the pass's start, and the frames before it was found were measured
    /// where they lie (a camera the first look took for still: a 2560x1440 hand-held
    /// twin, shrunk 4 times, whose glances' motions explained too few of its pixels).
    pub(in crate::detect) fn moved_from_start(&self) -> bool {
        self.on && !self.still_seen
    }

    /// Each frame steadied (taken out).
    pub(in crate::detect) fn take_steadied(&mut self) -> Vec<Steadied> {
        self.followed.take_steadied()
    }

    /// The camera's motion, when it was found to move.
    pub(in crate::detect) fn camera(&self) -> Option<CameraMotion> {
        self.on.then(|| CameraMotion {
            from_s: self.on_at,
            ..self.followed.camera()
        })
    }
}

/// The camera's motion over a detection: how far the frames were moved back.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CameraMotion {
    /// RMS of the frames' shift, px (frame px at full size).
    pub rms_px: f64,
    /// RMS of the frames' turn, degrees.
    pub rms_deg: f64,
    /// The largest shift of a frame, px.
    pub max_px: f64,
    /// Frames whose motion could not be measured (held at the last measured).
    pub unmeasured: usize,
    /// A camera found moving after the first look: the time of the first frame steadied,
    /// s (the frames before were taken as still). Absent: every frame was steadied.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from_s: Option<f64>,
    /// A rolling shutter's readout, first row to last, ms, fitted to the angles and taken
    /// out of them (see `shutter`). Absent: none stood clear of the angles' noise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub readout_ms: Option<f64>,
    /// The steadying's own noise taken out of the angles (see `steady::jitter`): the RMS
    /// of what was taken, deg. Absent: none stood clear of chance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub jitter_deg: Option<f64>,
}

impl CameraMotion {
    /// Which frames were steadied, as the reports give it: "each frame was steadied onto
    /// the first", or "each frame from 12.3 s on was steadied onto the first (the frames
    /// before were taken as still)".
    pub fn steadied(&self) -> String {
        match self.from_s {
            Some(t) => format!(
                "each frame from {t:.1} s on was steadied onto the first (the frames before \
                 were taken as still)"
            ),
            None => "each frame was steadied onto the first".into(),
        }
    }

    /// In words, as the reports give it: "RMS 1.20 px and 0.150 deg, at most 3.1 px"
    /// (and the frames not measurable, if any, a rolling shutter's readout taken out,
    /// and the steadying's noise taken out).
    pub fn describe(&self) -> String {
        format!(
            "RMS {:.2} px and {:.3} deg, at most {:.1} px{}{}{}",
            self.rms_px,
            self.rms_deg,
            self.max_px,
            if self.unmeasured > 0 {
                format!(", {} frames not measurable", self.unmeasured)
            } else {
                String::new()
            },
            match self.readout_ms {
                Some(ms) => format!(
                    "; a rolling shutter read out over {ms:.1} ms, its lean taken out of the \
                     angles"
                ),
                None => String::new(),
            },
            match self.jitter_deg {
                Some(deg) => format!(
                    "; the measurement's frame-to-frame noise taken out of the angles \
                     ({deg:.4} deg RMS)"
                ),
                None => String::new(),
            }
        )
    }
}

/// Frames followed one after another: each one's motion measured, or held at the last
/// measured when it cannot be, and summed for [`CameraMotion`].
#[derive(Default)]
pub(in crate::detect) struct Followed {
    last: Motion,
    n: usize,
    sum_shift2: f64,
    sum_rot2: f64,
    max_px: f64,
    unmeasured: usize,
    /// The last measured frame's loss (see `Steady::loss`).
    last_loss: f64,
    /// A steadied frame's typical loss, and how many frames it was taken from (see
    /// [`Followed::hidden`]).
    typical_loss: f64,
    typical_of: usize,
    /// When the run of hidden frames now going on began, s (see [`Followed::hidden`]).
    hidden_from: Option<f64>,
    /// Each frame followed.
    steadied: Vec<Steadied>,
}

/// A frame steadied: its index and time, s, the motion it was warped back by, whether
/// the scene fixed its shift but not its turn, which was then held at none (see
/// `Steady::steadying`), and whether its motion was measured at all (not: held at the
/// last measured).
#[derive(Clone, Copy, Debug)]
pub struct Steadied {
    pub index: u64,
    pub t_s: f64,
    pub motion: Motion,
    pub turn_held: bool,
    pub measured: bool,
}

#[cfg(test)]
impl Steadied {
    /// Frame `index` at `t_s` steadied by a measured `motion`, its turn fixed: the unit
    /// tests' hand-made steadying.
    pub(crate) fn measured(index: u64, t_s: f64, motion: Motion) -> Self {
        Self {
            index,
            t_s,
            motion,
            turn_held: false,
            measured: true,
        }
    }
}

impl Steadied {
    /// The frame's index and the turn it was steadied by (see [`Turn`]).
    pub fn turn(&self) -> Turn {
        (self.index, (!self.turn_held).then_some(self.motion.rot_rad))
    }
}

/// A steadied frame's index and the turn it was steadied by, radians: `None` where the
/// scene fixed its shift but not its turn, which was then held at none (see
/// `Steady::steadying`): the frame's own turn is not known.
pub type Turn = (u64, Option<f64>);

impl Followed {
    /// The motion of `f`, the next frame, against `st`'s first.
    pub(in crate::detect) fn next(&mut self, st: &mut Steady, f: &Frame) -> Result<Motion> {
        st.steadying();
        let mut held = false;
        let measured = match st.measure(f)? {
            Some(m) if !self.hidden(st, f.t_s)? => Some(m),
            _ => None,
        };
        let m = match measured {
            Some(m) => {
                held = st.turn_held();
                // Over the first frames, what moves in the static scene is counted, then
                // left out, twice (see `PASS_FIRST_PRUNE_FRAMES`, `PASS_PRUNE_FRAMES`).
                let counted = self.n - self.unmeasured + 1;
                if counted <= PASS_PRUNE_FRAMES {
                    st.tally()?;
                    if counted == PASS_FIRST_PRUNE_FRAMES || counted == PASS_PRUNE_FRAMES {
                        st.prune_going_on(PRUNE_SHARE);
                    }
                }
                m
            }
            None => {
                self.unmeasured += 1;
                self.last
            }
        };
        self.last = m;
        self.steadied.push(Steadied {
            index: f.index,
            t_s: f.t_s,
            motion: m,
            turn_held: held,
            measured: measured.is_some(),
        });
        let d = m.dx.hypot(m.dy);
        self.n += 1;
        self.sum_shift2 += d * d;
        self.sum_rot2 += m.rot_rad * m.rot_rad;
        self.max_px = self.max_px.max(d);
        Ok(m)
    }

    /// Whether the frame `st` measured last had its static scene hidden (a person in
    /// front of the camera): aligned, its pixels are off more than [`HIDDEN_TIMES`] the
    /// typical steadied frame's and more than [`HIDDEN_MIN_LOSS`]. Its motion is then
    /// not taken, and the next frame is measured from the last taken. A walker crossing
    /// a 640x480 swaying twin left 0.87 of the pixels off (0.13 typical) and dragged the
    /// alignment after it, 8 px and 3 deg from the camera's 0.65 px and 0.06 deg: the
    /// wire's angles, corrected by that motion, were 3 deg off, 33 frames `ok`.
    ///
    /// A scene that stays hidden is one that changed: what the first frame showed is
    /// gone (the hand that held the ball at the start and left). Over a run of hidden
    /// frames (`t_s` the frame's time, s), the first frame's pixels each frame does not
    /// show alike are counted; once the run lasts [`SCENE_CHANGE_S`], those off in
    /// more than [`SCENE_CHANGE_SHARE`] of its frames are dropped from the static
    /// scene, and the frames after are measured on what is left. A person passing hides
    /// each pixel for less (the twin's walker, a third of the frame wide, crosses it in
    /// 4 s: under a second a pixel). Kept whole, a hand-held twin whose releasing hand
    /// was in its first frame had every frame after the release hidden (its pixels off
    /// 0.35, 0.03 before): the wire found in 32 frames of 1201, refused.
    fn hidden(&mut self, st: &mut Steady, t_s: f64) -> Result<bool> {
        let loss = st.loss();
        let hidden =
            self.typical_of > 0 && loss > (HIDDEN_TIMES * self.typical_loss).max(HIDDEN_MIN_LOSS);
        if hidden {
            let first = self.hidden_from.is_none();
            let since = *self.hidden_from.get_or_insert(t_s);
            st.tally_change(first)?;
            if t_s - since >= SCENE_CHANGE_S && st.prune_change(SCENE_CHANGE_SHARE) {
                self.hidden_from = None;
            }
            st.back_to(self.last, self.last_loss);
        } else {
            self.hidden_from = None;
            self.typical_of += 1;
            let k = (1.0 / self.typical_of as f64).max(HIDDEN_FOLLOW);
            self.typical_loss += k * (loss - self.typical_loss);
            self.last_loss = loss;
        }
        Ok(hidden)
    }

    /// Each frame followed so far (taken out).
    pub(in crate::detect) fn take_steadied(&mut self) -> Vec<Steadied> {
        std::mem::take(&mut self.steadied)
    }

    /// What the frames followed so far add up to.
    pub(in crate::detect) fn camera(&self) -> CameraMotion {
        let n = self.n.max(1) as f64;
        CameraMotion {
            rms_px: (self.sum_shift2 / n).sqrt(),
            rms_deg: (self.sum_rot2 / n).sqrt().to_degrees(),
            max_px: self.max_px,
            unmeasured: self.unmeasured,
            from_s: None,
            readout_ms: None,
            jitter_deg: None,
        }
    }
}
