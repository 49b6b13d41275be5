//! The camera's own motion (a phone in the hand, a swaying tripod, a slow drift): each
//! frame's shift and turn against the first frame, measured on the static scene, and
//! the frame warped back onto the first, so that the plate, its static lines and the
//! pivot stay put and the wire's angle is the plate's.
//!
//! The measurement is a least-squares image alignment (Lucas and Kanade's, for a shift
//! and a small turn) of the frame, shrunk and smoothed, onto the first: every pixel with
//! a gradient speaks, so a plain wall's faint shading counts too, and the pixels that
//! differ much more than noise does (the wire, the ball, a hand) weigh nothing (Tukey's
//! biweight), and a direction of motion the scene does not fix (a plain wall, one
//! straight edge along itself) is not corrected on a guess.
//! It starts from the previous frame's motion, first on a frame shrunk twice
//! more, then on the measuring scale.

use crate::detect::tuning::{
    EST_SIDE, EXPLAINS, MAX_COARSE_POINTS, MAX_POINTS, MAX_RESIDUAL, MAX_SHIFT, MAX_TURN_DEG,
    MAX_WIDEN, MEASURE_PX, MIN_GRADIENT, NOISE_FRAMES, NOISE_SHARE, PRUNE_MIN_FRAMES,
    PRUNE_MIN_KEPT, RESTART, TUKEY_LEVELS,
};
use crate::video::Frame;
use align::{align_step, iterate, noise_share, prepare, Hold, Reader, Scratch, Step, Tukey};
use anyhow::Result;
use light::Light;
use opencv::core::Mat;
use opencv::prelude::*;
use std::cell::Cell;
use std::collections::VecDeque;

/// A frame's displacement against the first frame: a point `p` of the first frame is
/// seen at `c + R(rot) (p - c) + t` in this one (`c` the frame's centre), frame px.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    pub dx: f64,
    pub dy: f64,
    pub rot_rad: f64,
}

impl Motion {
    /// The largest displacement of a corner of a `w` x `h` frame, px.
    pub fn reach(&self, w: f64, h: f64) -> f64 {
        let r = 0.5 * w.hypot(h);
        self.dx.hypot(self.dy) + self.rot_rad.abs() * r
    }
}

/// One scale of the first frame: its pixels that hold information (a gradient), each
/// with its place, its grey and the motion's three derivatives there (shift x, shift y,
/// turn about the centre).
struct Level {
    w: i32,
    h: i32,
    /// Frame px per px of this scale.
    shrink: f64,
    points: Vec<Point>,
    /// How many of the scale's strongest pixels each point read stands for (every k-th
    /// kept: k), so that the information the scene holds is reckoned as from them all.
    each: f64,
}

/// A pixel of a [`Level`].
struct Point {
    x: f32,
    y: f32,
    grey: f32,
    jac: [f32; 3],
    /// The gradient's length, grey levels per px.
    gradient: f32,
}

impl Level {
    /// The scale `img` (`shrink` frame px per px), outside `sweep`, read at its strongest
    /// [`MAX_POINTS`] gradients, of which every k-th is kept when more than `most`.
    fn new(img: &Mat, shrink: f64, sweep: Option<&Sweep>, most: usize) -> Result<Self> {
        let (w, h) = (img.cols(), img.rows());
        let r = img.data_typed::<f32>()?;
        let (cx, cy) = (0.5 * (w as f32 - 1.0), 0.5 * (h as f32 - 1.0));
        let (wu, hu) = (w as usize, h as usize);
        let mut points = Vec::new();
        for y in 1..hu.saturating_sub(1) {
            for x in 1..wu.saturating_sub(1) {
                let i = y * wu + x;
                let gx = 0.5 * (r[i + 1] - r[i - 1]);
                let gy = 0.5 * (r[i + wu] - r[i - wu]);
                if gx * gx + gy * gy < MIN_GRADIENT * MIN_GRADIENT {
                    continue;
                }
                // A pixel's centre, in frame px.
                let at = |v: usize| (v as f64 + 0.5) * shrink - 0.5;
                if sweep.is_some_and(|s| s.holds(at(x), at(y))) {
                    continue;
                }
                let (px, py) = (x as f32 - cx, y as f32 - cy);
                points.push(Point {
                    x: x as f32,
                    y: y as f32,
                    grey: r[i],
                    jac: [gx, gy, -gx * py + gy * px],
                    gradient: (gx * gx + gy * gy).sqrt(),
                });
            }
        }
        // The strongest gradients, when there are many, in the frame's order, row by
        // row: read so, the frame's pixels come from memory in the order they lie, not
        // at random.
        strongest(&mut points, MAX_POINTS);
        // Fewer, as spread as these.
        let each = points.len().div_ceil(most).max(1);
        if each > 1 {
            points = points.into_iter().step_by(each).collect();
        }
        Ok(Self {
            w,
            h,
            shrink,
            points,
            each: each as f64,
        })
    }
}

/// The `n` points of the strongest gradients among `points` (made row by row), kept
/// in their order. Where the `n`-th strongest is stronger than the next, they are
/// those at least as strong, picked by their strength alone and filtered in order;
/// where the two are as strong (a tie that a selection decides its own way), they are
/// picked as before: selected by strength whole, then sorted back into the frame's
/// order. The same points either way (test in `steady/tests.rs`); selecting the
/// strengths alone (4 bytes, not a point's 28) and sorting nothing took a third of
/// the instructions of the first frame's scales.
fn strongest(points: &mut Vec<Point>, n: usize) {
    if points.len() <= n {
        return;
    }
    if n == 0 {
        points.clear();
        return;
    }
    let g2 = |p: &Point| p.jac[0] * p.jac[0] + p.jac[1] * p.jac[1];
    let mut strength: Vec<f32> = points.iter().map(g2).collect();
    let (stronger, &mut cut, weaker) =
        strength.select_nth_unstable_by(n - 1, |a, b| b.total_cmp(a));
    debug_assert_eq!(stronger.len(), n - 1);
    let next = weaker.iter().copied().max_by(f32::total_cmp);
    if next.is_some_and(|v| v.total_cmp(&cut).is_lt()) {
        points.retain(|p| g2(p).total_cmp(&cut).is_ge());
    } else {
        points.select_nth_unstable_by(n, |a, b| g2(b).total_cmp(&g2(a)));
        points.truncate(n);
        points.sort_unstable_by(|a, b| (a.y, a.x).partial_cmp(&(b.y, b.x)).expect("finite"));
    }
}

/// The first frame's scales and the scratch the measurement reuses.
pub(super) struct Steady {
    size: (usize, usize),
    /// The side, px, a plausible shift is a share of (see [`MAX_SHIFT`]): the frame's,
    /// or the whole video's when the frames are a region of it.
    side: f64,
    /// Frame px per px of the measuring scale.
    shrink: f64,
    levels: [Level; 2],
    /// The first frame's level and contrast (see [`prepare`]).
    norm: Option<(f64, f64)>,
    small: Mat,
    smooth: Mat,
    coarse: Mat,
    warped: Mat,
    /// The last measured motion, where the next frame's measurement starts.
    recent: Motion,
    /// Whether the pendulum's sweep is left out of the pixels read (see
    /// [`Steady::align_from`]).
    swept: bool,
    /// Tukey's loss of the last measured frame, aligned.
    loss: f64,
    /// Per level, per point: in how many of the frames tallied it differed from the
    /// first frame once aligned (see [`Steady::tally`]).
    off: [Vec<u32>; 2],
    tallied: u32,
    /// The same count over the frames of a run hidden from the steadying (see
    /// [`Steady::tally_change`]).
    changed: [Vec<u32>; 2],
    changed_of: u32,
    /// Whether a turn the scene fixes poorly is held at none (see [`Steady::steadying`]).
    hold_turn: bool,
    /// The last steadied frames' median differences from the first, aligned, as a share
    /// of Tukey's scale (see [`NOISE_SHARE`]), and the widening of that scale their
    /// lower quartile asks for.
    noise: VecDeque<f32>,
    widen: f32,
    /// Room for a frame's shares, then for the last frames' (see [`Steady::hear_noise`]).
    shares: Vec<f32>,
    /// Whether the turn of the frame last measured was so held.
    turn_held: bool,
    /// The losses of the frame last measured (see [`Steady::losses`]), once reckoned: a
    /// glance asks for them twice (whether the motion explains the frame, then whether
    /// it does as a drift's).
    losses: Option<(f64, f64)>,
    /// The pixels an alignment's step read (see [`Scratch`]).
    scratch: Cell<Scratch>,
}

impl Steady {
    /// The first frame as the reference; later frames are measured against it, on the
    /// static scene outside `sweep` when it is given.
    pub(super) fn new(first: &Frame, sweep: Option<&Sweep>) -> Result<Self> {
        let (w, h) = (first.width, first.height);
        let shrink = (w.max(h) as f64 / EST_SIDE).max(1.0);
        let mut small = Mat::default();
        let mut smooth = Mat::default();
        let mut coarse = Mat::default();
        let mut norm = None;
        prepare(
            first,
            shrink,
            &mut norm,
            &mut small,
            &mut smooth,
            &mut coarse,
        )?;
        let levels = [
            Level::new(&coarse, 2.0 * shrink, sweep, MAX_COARSE_POINTS)?,
            Level::new(&smooth, shrink, sweep, MAX_POINTS)?,
        ];
        Ok(Self {
            size: (w, h),
            side: w.max(h) as f64,
            shrink,
            levels,
            norm,
            small,
            smooth,
            coarse,
            warped: Mat::default(),
            recent: Motion::default(),
            swept: sweep.is_some(),
            loss: f64::INFINITY,
            off: Default::default(),
            tallied: 0,
            changed: Default::default(),
            changed_of: 0,
            hold_turn: false,
            noise: VecDeque::new(),
            widen: 1.0,
            shares: Vec::new(),
            turn_held: false,
            losses: None,
            scratch: Cell::default(),
        })
    }

    /// Shifts judged as a share of `side` px (a video's whole side, when the frames
    /// measured are a region of it: a camera moves its whole picture, and 2 % of a
    /// small region's side held a drift of 8.6 px in a 228x256 region at 5.1 px, 808
    /// frames of 2001 not measured).
    pub(super) fn within(mut self, side: f64) -> Self {
        self.side = self.side.max(side);
        self
    }

    /// From here on the frames measured are to be steadied (warped back by their
    /// motion), not glanced at: where the scene fixes the shift but not the turn, the
    /// turn is held at none and the shift fitted with it held (see [`align_step`]).
    /// Taking the direction the scene does not fix back to no motion, as a glance does,
    /// takes part of the shift with it into a turn, as that direction mixes the two when
    /// the texture lies to one side: on a plain plate with a protractor to one side, a
    /// camera's shift of 2.6 px alone read as 0.09 deg of turn and 0.45 px less shift,
    /// and the angles erred 0.069 deg RMS (0.050 held). A glance keeps it: whether the
    /// camera moved is judged on the motion that explains the frame best, a turn the
    /// scene fixes poorly included (held, a hand-held twin turning 0.46 deg was taken
    /// for still).
    pub(super) fn steadying(&mut self) {
        self.hold_turn = true;
    }

    /// Whether the turn of the frame last measured was held at none, the scene fixing
    /// its shift but not its turn (see [`Steady::steadying`]).
    pub(super) fn turn_held(&self) -> bool {
        self.turn_held
    }

    /// The motion of `f` against the first frame, or none when the frame cannot be
    /// aligned onto it (a plain wall has nothing to align; a frame that differs
    /// throughout, a flash or a cut, is not the same scene).
    pub(super) fn measure(&mut self, f: &Frame) -> Result<Option<Motion>> {
        self.losses = None;
        if (f.width, f.height) != self.size {
            return Ok(None);
        }
        prepare(
            f,
            self.shrink,
            &mut self.norm,
            &mut self.small,
            &mut self.smooth,
            &mut self.coarse,
        )?;
        // From the previous frame's motion; when that leaves more pixels off than the
        // previous frame's did (by `RESTART`), from none too, and the one that leaves
        // fewer off is kept: an alignment that went astray (pulled along by the ball
        // over a few frames) is not followed on from frame to frame.
        let (mut m, mut residual, mut loss, mut held, mut light) = self.align_from(self.recent)?;
        if self.recent != Motion::default() && (loss.is_nan() || loss > RESTART * self.loss) {
            let (m0, r0, l0, h0, light0) = self.align_from(Motion::default())?;
            if l0 < loss {
                (m, residual, loss, held, light) = (m0, r0, l0, h0, light0);
            }
        }
        self.turn_held = held;
        let Some(m) = m else {
            return Ok(None);
        };
        if !self.plausible(m, residual) {
            return Ok(None);
        }
        if self.hold_turn {
            self.hear_noise(m, light)?;
        }
        self.recent = m;
        self.loss = loss;
        Ok(Some(m))
    }

    /// The alignment of the prepared frame from motion `start`: the motion (none when
    /// the scene cannot fix it), the weighted RMS difference, Tukey's loss, whether its
    /// last step held the turn at none (see [`Steady::steadying`]), and the light
    /// fitted. Where the pendulum's sweep is left out, a turn the coarser scale fixed is
    /// kept as it is on the measuring scale when that does not fix it, not taken back to
    /// none: the coarser scale's pixels hold more of the turn (a hand-held twin turning 0.46 deg
    /// had its turn fixed on the coarser scale in each frame and held at none on the
    /// measuring scale in four of five, its angles off by 0.106 deg RMS; kept, 0.017).
    /// The first look's alignment, the pendulum not yet left out, holds it at none (kept,
    /// a static edge of a hand-held twin read as a moving line: no wire found).
    fn align_from(&mut self, start: Motion) -> Result<(Option<Motion>, f64, f64, bool, Light)> {
        let mut light = Light::at(&self.levels[0], &self.coarse, start)?;
        let hold = if self.hold_turn {
            Hold::WhereUnfixed
        } else {
            Hold::No
        };
        let coarse = self.at_level(0, start, hold, &mut light)?;
        let Some(m) = coarse.motion else {
            return Ok((None, coarse.residual, coarse.loss, coarse.held, light));
        };
        // The turn held as it is counts as measured: the coarser scale fixed it.
        let hold = if self.hold_turn && self.swept && coarse.turn_fixed {
            Hold::AsIs
        } else {
            hold
        };
        let fine = self.at_level(1, m, hold, &mut light)?;
        let at_none = fine.held && !hold.as_is();
        Ok((fine.motion, fine.residual, fine.loss, at_none, light))
    }

    /// Takes in the noise of a steadied frame aligned at motion `m` (and `light`): the
    /// frames after it are aligned at Tukey's scale widened for the noise so far (see
    /// [`NOISE_SHARE`]).
    fn hear_noise(&mut self, m: Motion, light: Light) -> Result<()> {
        let u = noise_share(&self.levels[1], &self.smooth, m, light, &mut self.shares)?;
        if self.noise.len() == NOISE_FRAMES {
            self.noise.pop_front();
        }
        self.noise.push_back(u);
        let recent = &mut self.shares;
        recent.clear();
        recent.extend(self.noise.iter().copied());
        let k = recent.len() / 4;
        let n = *recent.select_nth_unstable_by(k, f32::total_cmp).1;
        self.widen = (n / NOISE_SHARE).clamp(1.0, MAX_WIDEN);
        Ok(())
    }

    /// The alignment at level `k` from motion `start`: the motion reached, and what its
    /// last step found of the scene. A step that held the turn holds it at the later
    /// steps too (see [`Hold::Kept`]).
    fn at_level(&self, k: usize, start: Motion, hold: Hold, light: &mut Light) -> Result<Step> {
        let img = if k == 0 { &self.coarse } else { &self.smooth };
        let mut scratch = self.scratch.take();
        let step = iterate(
            &self.levels[k],
            img,
            start,
            hold,
            light,
            self.widen,
            &mut scratch,
        );
        self.scratch.set(scratch);
        step
    }

    /// Counts, for the frame last measured, the first frame's pixels it does not show
    /// alike once aligned: what moves in the scene (the pendulum, a person walking by)
    /// differs in most frames, the static scene in few.
    pub(super) fn tally(&mut self) -> Result<()> {
        let mut off = std::mem::take(&mut self.off);
        self.count_off(&mut off)?;
        self.off = off;
        self.tallied += 1;
        Ok(())
    }

    /// Adds 1 to `off`'s count of each point of the first frame the frame last measured
    /// does not show alike once aligned (at its own motion).
    fn count_off(&self, off: &mut [Vec<u32>; 2]) -> Result<()> {
        for (k, level) in self.levels.iter().enumerate() {
            let img = if k == 0 { &self.coarse } else { &self.smooth };
            let light = Light::at(level, img, self.recent)?;
            let at = Reader::new(level, img, self.recent)?;
            let off = &mut off[k];
            off.resize(level.points.len(), 0);
            for (p, n) in level.points.iter().zip(off.iter_mut()) {
                let differs = at.grey(p).is_none_or(|g| {
                    let e = light.gain * g + light.offset - p.grey;
                    e.abs() >= TUKEY_LEVELS + MEASURE_PX * p.gradient
                });
                *n += u32::from(differs);
            }
        }
        Ok(())
    }

    /// Counts, for a frame of a run hidden from the steadying (before it is taken
    /// back), the first frame's pixels it does not show alike: the count starts afresh
    /// with each run (`first`).
    pub(super) fn tally_change(&mut self, first: bool) -> Result<()> {
        if first {
            self.changed = Default::default();
            self.changed_of = 0;
        }
        let mut changed = std::mem::take(&mut self.changed);
        self.count_off(&mut changed)?;
        self.changed = changed;
        self.changed_of += 1;
        Ok(())
    }

    /// Drops the first frame's pixels that differed in more than `share` of a hidden
    /// run's frames (see [`Steady::tally_change`]): what the first frame showed and the
    /// scene no longer does (a hand that held the ball and left). Where fewer than
    /// [`PRUNE_MIN_KEPT`] percent would be kept, a level is left whole; whether any
    /// level lost a pixel.
    pub(super) fn prune_change(&mut self, share: f64) -> bool {
        if self.changed_of < PRUNE_MIN_FRAMES {
            return false;
        }
        let most = share * f64::from(self.changed_of);
        let mut pruned = false;
        for ((level, changed), off) in self
            .levels
            .iter_mut()
            .zip(&self.changed)
            .zip(self.off.iter_mut())
        {
            if changed.len() != level.points.len() {
                continue;
            }
            let keep: Vec<bool> = changed.iter().map(|&n| f64::from(n) <= most).collect();
            let kept = keep.iter().filter(|&&k| k).count();
            if kept == level.points.len() || kept < PRUNE_MIN_KEPT * level.points.len() / 100 {
                continue;
            }
            // The first frames' own count (`tally`) keeps to the points kept.
            if off.len() == keep.len() {
                retain_by(off, &keep);
            }
            retain_by(&mut level.points, &keep);
            pruned = true;
        }
        self.changed = Default::default();
        self.changed_of = 0;
        pruned
    }

    /// Drops the first frame's pixels that differed in more than `share` of the frames
    /// tallied (the pendulum's, or another thing that moved), when enough were tallied
    /// and the static scene keeps enough; then later frames are measured from no motion.
    pub(super) fn prune(&mut self, share: f64) {
        if self.drop_tallied(share) {
            self.forget();
        }
    }

    /// [`Steady::prune`] while frames go on one after another (the streaming pass): the
    /// next frame is measured on from the last frame's motion, not from none (a drift
    /// of 7 px by the first drop left the frame after it unmeasured from none); its loss
    /// is not compared with the last, of more pixels.
    pub(super) fn prune_going_on(&mut self, share: f64) {
        if self.drop_tallied(share) {
            self.losses = None;
            self.loss = f64::INFINITY;
        }
    }

    /// The drop of [`Steady::prune`], the count starting again; whether enough frames
    /// were tallied for it.
    fn drop_tallied(&mut self, share: f64) -> bool {
        if self.tallied < PRUNE_MIN_FRAMES {
            return false;
        }
        let most = share * f64::from(self.tallied);
        for (level, off) in self.levels.iter_mut().zip(&self.off) {
            let keep: Vec<bool> = off.iter().map(|&n| f64::from(n) <= most).collect();
            if keep.iter().filter(|&&k| k).count() < PRUNE_MIN_KEPT * level.points.len() / 100 {
                continue;
            }
            retain_by(&mut level.points, &keep);
        }
        self.off = Default::default();
        self.tallied = 0;
        true
    }

    /// Tukey's loss of the frame last measured, aligned (a share of its pixels).
    pub(super) fn loss(&self) -> f64 {
        self.loss
    }

    /// The frame last measured is not taken: the next is measured from `m` (whose frame
    /// was left off by `loss`), as though it had been the last.
    pub(super) fn back_to(&mut self, m: Motion, loss: f64) {
        self.losses = None;
        self.recent = m;
        self.loss = loss;
    }

    /// Later frames are measured from no motion, as the first frame's neighbours.
    pub(super) fn forget(&mut self) {
        self.losses = None;
        self.recent = Motion::default();
        self.loss = f64::INFINITY;
    }

    /// Whether the motion last measured explains the frame better than none: the pixels
    /// that differ from the first frame (Tukey's loss) fewer by [`EXPLAINS`]. A motion
    /// that does not is the moving wire's or the ball's pull on a plain scene, not the
    /// camera's.
    pub(super) fn explains(&mut self) -> Result<bool> {
        self.explains_by(EXPLAINS)
    }

    /// Whether the motion last measured leaves fewer pixels off than none, by `share`.
    pub(super) fn explains_by(&mut self, share: f64) -> Result<bool> {
        let (moved, still) = self.losses()?;
        Ok(moved < share * still)
    }

    /// The frame's pixels off (Tukey's loss) at the motion last measured and at none.
    pub(super) fn left_off(&mut self) -> Result<(f64, f64)> {
        self.losses()
    }

    /// The loss of the frame last measured at its motion and at none.
    fn losses(&mut self) -> Result<(f64, f64)> {
        if let Some(l) = self.losses {
            return Ok(l);
        }
        let (level, img) = (&self.levels[1], &self.smooth);
        let scratch = self.scratch.get_mut();
        let mut loss = |m: Motion| -> Result<f64> {
            let mut light = Light::at(level, img, m)?;
            Ok(align_step(
                level,
                img,
                m,
                Tukey::explaining(),
                &mut light,
                Hold::No,
                scratch,
            )?
            .loss)
        };
        let (moved, still) = (loss(self.recent)?, loss(Motion::default())?);
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!(
                "steady: {:?}: the frame's loss {moved:.3} aligned, {still:.3} not ({:.2})",
                self.recent,
                moved / still
            );
        }
        self.losses = Some((moved, still));
        Ok((moved, still))
    }

    /// The motion of `f` measured from no motion (for frames far apart, as the first
    /// look's glances are: the previous one's motion is no guide).
    pub(super) fn glance(&mut self, f: &Frame) -> Result<Option<Motion>> {
        self.forget();
        self.measure(f)
    }

    /// Whether a measured motion can be the camera's (see [`MAX_SHIFT`]) and aligns the
    /// frame well enough ([`MAX_RESIDUAL`]).
    fn plausible(&self, m: Motion, residual: f64) -> bool {
        let side = self.side;
        residual <= MAX_RESIDUAL
            && m.dx.is_finite()
            && m.dy.is_finite()
            && m.rot_rad.is_finite()
            && m.dx.hypot(m.dy) <= MAX_SHIFT * side
            && m.rot_rad.abs() <= MAX_TURN_DEG.to_radians()
    }

    /// `f` warped back onto the first frame by `m` (in place).
    pub(super) fn undo(&mut self, f: &mut Frame, m: Motion) -> Result<()> {
        warp_into(f, m, (0, 0), (f.width, f.height), &mut self.warped)?;
        f.data.copy_from_slice(self.warped.data_bytes()?);
        Ok(())
    }
}

/// Keeps the items of `v` whose `keep` is true (one flag per item).
fn retain_by<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut i = 0;
    v.retain(|_| {
        i += 1;
        keep[i - 1]
    });
}

mod align;
mod follow;
pub(super) mod jitter;
mod light;
mod sweep;
#[cfg(test)]
mod tests;
mod warp;

pub use follow::{CameraMotion, Steadied, Turn};
pub(super) use follow::{Followed, Late};
pub(in crate::detect) use sweep::Sweep;
pub(super) use warp::{bytes, warp_into};
