//! The streaming pass: per frame, the evidence against a background that follows the
//! scene, the wire's angle in a wedge around the prediction, and the gate.

mod background;
mod beside;
mod contrast;
mod diag;
mod evidence;
mod measure;
mod pivot;
mod undecided;

use super::geometry::WireGeometry;
use super::light::Brightness;
use super::row::KeptMoments;
use super::shrink::Shrink;
use super::{full_to_shrunk, AngleRow, DetectOptions, Flag, Pt, Status};
use crate::detect::tuning::{
    BG_DECAY_FRAMES, DISTURBED_MIN_MAD, DISTURBED_TIMES, FLASH_MIN_LEVEL, FLASH_SHARE,
    LONG_FIT_FRAMES, LONG_FIT_S, PAIR_SEP_TOL, PREDICT_BEYOND_SWEEP_DEG, REANCHOR_AWAY_GATES,
    REANCHOR_STILL_DEG, REPEAT_MAD, REPEAT_SHARE, START_FRAMES, UNDECIDED_MAX_FRAMES,
};
use crate::video::{Frame, Roi};
use anyhow::{bail, Context, Result};
use opencv::core::{self, Mat, Scalar};
use opencv::imgproc;
use opencv::prelude::*;
use std::path::PathBuf;

/// A frame accepted while the side a wire lies on beside its shadow was not known, since
/// the first accepted on one ridge of a pair: the angle taken, and the other ridge's
/// angle, quality and moments (none in a frame that saw no pair).
struct Undecided {
    frame: u64,
    t_s: f64,
    taken: f64,
    other: Option<(f64, f64, KeptMoments)>,
}

/// A row the pass measured again on the other ridge of its pair (angle, quality,
/// moments), or refused (none: a frame between two so restated, which saw no pair).
pub(super) struct Restated {
    pub frame: u64,
    pub other: Option<(f64, f64, KeptMoments)>,
}

/// Per-frame state of the streaming pass.
pub(super) struct Tracker {
    geo: WireGeometry,
    /// Work at 1/scale of the full frame, in a region starting at `(roi_x, roi_y)`.
    scale: f64,
    roi_x: f64,
    roi_y: f64,
    /// The lens the video is measured through (`video.lens`), set by [`Self::through`].
    lens: Option<crate::lens::Lens>,
    /// Pivot and band in the scaled region's pixels.
    piv: Pt,
    r_lo: f64,
    r_hi: f64,
    small: Mat,
    /// The buffers of `small`'s shrinking (see [`Shrink`]).
    shrink: Shrink,
    bg: Mat,
    /// What the line fits divide each pixel's evidence by, and the static marks they
    /// leave out (from the first look's background).
    contrast: contrast::Contrast,
    /// Each frame's brightness against the first look's first frame.
    light: Brightness,
    tmp: Mat,
    /// The difference from the background around the wedge, its top-hat's buffers and
    /// the top-hat (`ev_outer`).
    diff: Vec<u8>,
    morph: super::morph::Morph,
    /// Per-pixel detection threshold (grey levels).
    tmap: Mat,
    /// The evidence, exact in `rect` (around the wedge `wedge` searched this frame)
    /// and zero elsewhere; `ev_outer` is the top-hat's working area around `rect`.
    ev: Mat,
    ev_outer: Vec<u8>,
    rect: core::Rect,
    wedge: (f64, f64),
    scratch: measure::Scratch,
    /// Which side of a wire-and-shadow pair the wire lies on, as learnt.
    ridges: measure::Ridges,
    /// This frame's measurement of the other ridge of a pair, taken while the side was
    /// not known; the accepted frames holding one, until it is; and the rows restated
    /// once it is, for the pass to take ([`Tracker::take_restated`]).
    pair_other: Option<(f64, f64, KeptMoments)>,
    undecided: Vec<Undecided>,
    restated: Vec<Restated>,
    /// The looks beside the followed line, for the `beside` check.
    beside: beside::Looks,
    prev: Vec<u8>,
    mean_level: Option<f64>,
    gate: f64,
    /// Recent accepted (t, angle) for the prediction.
    hist: Vec<(f64, f64)>,
    /// The last few raw measurements (accepted or not).
    raw: Vec<(f64, f64)>,
    /// Typical quality of accepted frames (a faint wire covers less of its band).
    q_ref: Option<f64>,
    /// Typical mean absolute change between consecutive frames.
    mad_ref: Option<f64>,
    /// Mean square innovation of accepted frames, and how many were seen.
    innov: Option<(f64, usize)>,
    since_good: usize,
    /// Repeated frames since the last accepted one: they widen neither the search nor
    /// the gate's base, but the prediction reaches that many frames further (the gate's
    /// allowance for the motion grows with it) and, with the refused frames, gives up
    /// after a long run.
    repeats_since_good: usize,
    decay_every: u64,
    /// The time and angle of the first accepted frame since the wire last moved or the
    /// track was lost (see [`Tracker::note_still`], [`Tracker::wire_at_rest`]).
    still: Option<(f64, f64)>,
    diag_dir: Option<PathBuf>,
    pub(super) diagnostics: Vec<PathBuf>,
    /// `detect --steps`: the frame to picture; its index, frame and background as the
    /// evidence saw them; the pictures drawn (file name, PNG).
    steps: Option<u64>,
    steps_seen: Option<(u64, Mat, Mat)>,
    pub(super) steps_drawn: Vec<(String, Vec<u8>)>,
    /// `ROLLFRIC_DEBUG=frames` or `=mad`: a line per frame on stderr (read once).
    debug: Option<String>,
    /// The last frame's predicted angle.
    last_pred: Option<f64>,
}

impl Tracker {
    /// Measured through `lens`: each strip's pixels are also kept in the undistorted
    /// view ([`KeptMoments::plate`](crate::detect::row::KeptMoments::plate)).
    pub(super) fn through(&mut self, lens: Option<crate::lens::Lens>) {
        self.lens = lens;
    }

    pub(super) fn new(
        geo: &WireGeometry,
        opts: &DetectOptions,
        init_bg: Mat,
        init_tmap: Mat,
        init_reference: Mat,
        shrink: f64,
        bound: Roi,
    ) -> Result<Self> {
        // The first seconds' background covers `bound` at the shrunk scale: map it onto
        // the region of interest at full scale.
        let roi = geo.roi;
        // The streaming pass works at the same scale as the first seconds: a faint wire
        // that the area average brings out there stays visible, and the angle does not
        // depend on scale. Map from the shrunk `bound` to the shrunk region.
        let m = Mat::from_slice_2d(&[
            [1.0, 0.0, (roi.x as f64 - bound.x as f64) / shrink],
            [0.0, 1.0, (roi.y as f64 - bound.y as f64) / shrink],
        ])?;
        let (sw, sh) = (
            (roi.w as f64 / shrink).floor() as i32,
            (roi.h as f64 / shrink).floor() as i32,
        );
        let to_roi = |src: &Mat| -> Result<Mat> {
            let mut out = Mat::default();
            imgproc::warp_affine(
                src,
                &mut out,
                &m,
                core::Size::new(sw, sh),
                imgproc::INTER_LINEAR | imgproc::WARP_INVERSE_MAP,
                core::BORDER_REPLICATE,
                Scalar::default(),
            )?;
            Ok(out)
        };
        let bg = to_roi(&init_bg)?;
        let contrast = contrast::Contrast::new(&bg, geo.dark)?;
        let debug = std::env::var("ROLLFRIC_DEBUG").ok();
        if debug.is_some() {
            eprintln!(
                "track: static marks cover {:.1} % of the region",
                100.0 * contrast.marked_share()
            );
        }
        let tmap = to_roi(&init_tmap)?;
        let reference = to_roi(&init_reference)?;
        if let Some(d) = &opts.diag_dir {
            std::fs::create_dir_all(d)
                .with_context(|| format!("{}: cannot create folder", d.display()))?;
        }
        Ok(Self {
            geo: geo.clone(),
            scale: shrink,
            roi_x: roi.x as f64,
            roi_y: roi.y as f64,
            lens: None,
            piv: full_to_shrunk(geo.pivot, Pt::new(roi.x as f64, roi.y as f64), shrink),
            r_lo: geo.r_lo / shrink,
            r_hi: geo.r_hi / shrink,
            small: Mat::default(),
            shrink: Shrink::default(),
            bg,
            contrast,
            light: Brightness::new(reference.data_bytes()?),
            tmp: Mat::default(),
            diff: Vec::new(),
            morph: super::morph::Morph::default(),
            tmap,
            ev: Mat::default(),
            ev_outer: Vec::new(),
            rect: core::Rect::default(),
            wedge: (0.0, 0.0),
            scratch: measure::Scratch::default(),
            ridges: measure::Ridges::default(),
            pair_other: None,
            undecided: Vec::new(),
            restated: Vec::new(),
            beside: beside::Looks::default(),
            prev: Vec::new(),
            mean_level: None,
            gate: opts.gate_deg.to_radians(),
            hist: Vec::new(),
            raw: Vec::new(),
            q_ref: None,
            mad_ref: None,
            innov: None,
            since_good: 0,
            repeats_since_good: 0,
            decay_every: BG_DECAY_FRAMES,
            still: None,
            diag_dir: opts.diag_dir.clone(),
            diagnostics: Vec::new(),
            steps: opts.steps,
            steps_seen: None,
            steps_drawn: Vec::new(),
            debug,
            last_pred: None,
        })
    }

    /// The angle predicted for the last frame [`Tracker::step`] measured, rad.
    pub(super) fn predicted(&self) -> Option<f64> {
        self.last_pred
    }

    fn predict(&self, t: f64) -> Option<f64> {
        let lo = self.geo.theta_min - PREDICT_BEYOND_SWEEP_DEG.to_radians();
        let hi = self.geo.theta_max + PREDICT_BEYOND_SWEEP_DEG.to_radians();
        self.predict_raw(t)
            .filter(|p| *p > lo - 0.2 && *p < hi + 0.2)
            .map(|p| p.clamp(lo, hi))
    }

    /// The track holds: at most four frames refused or repeated since the last accepted
    /// one (past that the prediction gives up).
    fn held(&self) -> bool {
        self.since_good + self.repeats_since_good <= 4
    }

    fn predict_raw(&self, t: f64) -> Option<f64> {
        let n = self.hist.len();
        if n == 0 || !self.held() {
            return None;
        }
        // Frames after a refused one are predicted further ahead, where three noisy
        // angles' curvature throws the quadratic off: the least-squares quadratic of
        // the accepted angles of the last [`LONG_FIT_S`] then.
        if self.since_good + self.repeats_since_good > 0 {
            let t_last = self.hist[n - 1].0;
            let from = self.hist.partition_point(|h| h.0 < t_last - LONG_FIT_S);
            if n - from >= LONG_FIT_FRAMES {
                if let Some(p) = crate::numerics::quadratic_at(self.hist[from..].iter().copied(), t)
                {
                    return Some(p);
                }
            }
        }
        let recent = &self.hist[n.saturating_sub(3)..];
        if recent.len() == 3 && recent[2].0 - recent[0].0 < 0.25 {
            // The quadratic through the last three accepted angles (Lagrange form).
            let [(t0, a0), (t1, a1), (t2, a2)] = [recent[0], recent[1], recent[2]];
            let l0 = (t - t1) * (t - t2) / ((t0 - t1) * (t0 - t2));
            let l1 = (t - t0) * (t - t2) / ((t1 - t0) * (t1 - t2));
            let l2 = (t - t0) * (t - t1) / ((t2 - t0) * (t2 - t1));
            return Some(a0 * l0 + a1 * l1 + a2 * l2);
        }
        if recent.len() >= 2 {
            let (t1, a1) = recent[recent.len() - 2];
            let (t2, a2) = recent[recent.len() - 1];
            return Some(a2 + (a2 - a1) / (t2 - t1) * (t - t2));
        }
        Some(recent[0].1)
    }

    /// Whether a run of refused frames re-anchors the track on the last three raw
    /// measurements: they agree with one another (a smooth motion), so the history, not
    /// the wire, was wrong. Not onto a line that stands still away from where the track
    /// last was: a wire that was moving does not stop dead elsewhere, but a fixed mark
    /// does not move (a twin's protractor numerals took the track that way at the
    /// release, and held it for 2.7 s while the wire swung 19 deg away). Nor onto a
    /// shadow: once the side the wire lies on beside its shadow is learnt, a line a
    /// like pair's separation from the prediction `pred` on the shadow's side (a shadow
    /// moves with its wire, as smoothly: a hand-held twin's wire, faint for three
    /// frames near its turning point, gave three on its shadow 3.8 deg off, and the
    /// track re-anchored there twice in 23 s, three frames `ok` on the shadow).
    fn reanchors(&self, pred: Option<f64>) -> bool {
        let r = &self.raw[self.raw.len() - 3..];
        let smooth = (r[2].1 - 2.0 * r[1].1 + r[0].1).abs() < self.gate && r[2].0 - r[0].0 < 0.2;
        let still_elsewhere = (r[2].1 - r[0].1).abs() < REANCHOR_STILL_DEG.to_radians()
            && self
                .hist
                .last()
                .is_some_and(|h| (r[2].1 - h.1).abs() > REANCHOR_AWAY_GATES * self.gate);
        let onto_shadow = pred
            .zip(self.ridges.side())
            .is_some_and(|(p, (side, sep))| {
                let off = r[2].1 - p;
                off * side < 0.0 && (off.abs() - sep).abs() <= PAIR_SEP_TOL * sep
            });
        smooth && !still_elsewhere && !onto_shadow
    }

    pub(super) fn step(&mut self, f: &Frame, hint: Option<f64>) -> Result<AngleRow> {
        let (w, h) = (self.bg.cols(), self.bg.rows());
        // Global brightness: a flash or a dropout is kept out of the background.
        let level = sampled_mean(&f.data, 7);
        let flash = self
            .mean_level
            .is_some_and(|m| (level - m).abs() > FLASH_SHARE * m.max(FLASH_MIN_LEVEL));
        // Flicker and slow lighting changes: the frame brought to the first look's
        // brightness before the background, the noise and the gate see it (at full
        // size, normalised as it is copied).
        let mut gain = 1.0;
        if self.scale > 1.0 {
            // The region is a whole number of blocks (see `geometry::search`).
            self.shrink
                .area(&f.data, (f.width, f.height), &mut self.small, (w, h))?;
            if !flash {
                gain = self.light.normalise(self.small.data_bytes_mut()?);
            }
        } else {
            if f.width as i32 != w || f.height as i32 != h || f.data.len() != f.width * f.height {
                bail!(
                    "frame {} is {}x{} px, expected {w}x{h}",
                    f.index,
                    f.width,
                    f.height
                );
            }
            if self.small.cols() != w || self.small.rows() != h {
                self.small =
                    Mat::new_rows_cols_with_default(h, w, core::CV_8UC1, Scalar::all(0.0))?;
            }
            let out = self.small.data_bytes_mut()?;
            if flash {
                out.copy_from_slice(&f.data);
            } else {
                gain = self.light.normalise_into(&f.data, out);
            }
        }
        // A repeated frame (the camera dropped one and the recorder repeated the last)
        // differs from its predecessor far less than the sensor noise makes any two
        // real frames differ.
        let mad = if self.prev.is_empty() {
            f64::NAN
        } else {
            mean_abs_diff_sampled(self.small.data_bytes()?, &self.prev, 5)
        };
        let duplicate = mad < REPEAT_MAD || self.mad_ref.is_some_and(|r| mad < REPEAT_SHARE * r);
        let foreign = if flash { 0.0 } else { self.light.foreign() };
        let covered = !flash && self.light.covered(gain);
        let disturbed = covered
            || self
                .mad_ref
                .is_some_and(|r| mad > DISTURBED_TIMES * r.max(DISTURBED_MIN_MAD));
        if self.debug.as_deref() == Some("mad") {
            eprintln!(
                "mad {} {mad:.3} ref {:?} foreign {foreign:.3} gain {gain:.3} covered {covered}",
                f.index, self.mad_ref
            );
        }
        // A flash (the frame left at its own brightness) is no measure of how real
        // frames differ, nor what the next frame is compared with: deep flicker read
        // as flashes had the typical change learnt from them, ten times a frame's, and
        // every frame after taken for a repeat.
        if mad.is_finite() && !duplicate && !flash {
            self.mad_ref = Some(match self.mad_ref {
                Some(r) => 0.95 * r + 0.05 * mad.min(3.0 * r),
                None => mad,
            });
        }
        if !flash || self.prev.is_empty() {
            self.prev.clear();
            self.prev.extend(self.small.data_bytes()?.iter().step_by(5));
        }
        if !flash {
            self.mean_level = Some(match self.mean_level {
                Some(m) => 0.9 * m + 0.1 * level,
                None => level,
            });
        }
        // During the first seconds the geometry pass's angle of this very frame is the
        // better guess until three frames have been accepted.
        let pred = if self.starting() {
            // A hint is the first look's line in this frame, and it may be the wire's
            // shadow in one frame and the wire in the next (their lines meet at the
            // pivot): once a frame is accepted, a hint that leaves the line it followed
            // gives way to the track's own prediction. Taken in turn, a shadow's frames
            // and the wire's sent the prediction 30 deg off.
            match (hint, self.predict(f.t_s)) {
                (Some(h), Some(p)) if (h - p).abs() > self.gate => Some(p),
                (h, p) => h.or(p),
            }
        } else {
            self.predict(f.t_s).or(hint)
        };
        self.last_pred = pred;
        // Evidence (thin structures only: a top-hat removes the bob and a hand's
        // palm) where the wire can be, then the background follows the scene. While the
        // track starts on a first-look hint, the wedge is the whole sweep (as without a
        // prediction): the hint may be the wire's shadow, and the sharpest-ridge rule
        // sees both.
        let wedge_about = pred.filter(|_| !(self.starting() && hint.is_some()));
        self.evidence(wedge_about)?;
        self.keep_step_inputs(f.index)?;
        // Nor a disturbed frame (a person passing, a hand): the background is the
        // scene's running extreme, which gives back a grey level every
        // `BG_DECAY_FRAMES`, and a bright shirt taken into a dark wire's held the
        // evidence beside the wire for half a minute (a sweep twin's wire at rest after
        // a walker: 0.2 deg off for 25 s).
        if !flash && !disturbed {
            self.follow_scene(f.index)?;
        }
        let mut row = AngleRow {
            frame: f.index,
            t_s: f.t_s,
            angle_rad: None,
            status: Status::Ok,
            quality: 0.0,
            flag: None,
            moments: None,
        };
        if flash {
            row.flag = Some(Flag::Flash);
            self.since_good += 1;
            self.save_diag(f.index, f64::NAN, pred)?;
            return Ok(row);
        }
        let gate = self.accept_gate();
        let full = (self.scale > 1.0).then_some(measure::Full {
            data: &f.data,
            w: f.width,
            h: f.height,
        });
        let (angle, quality, moments) = match self.measure(pred, gate, full)? {
            Some((a, q, m)) => (a, q, Some(m)),
            None => (f64::NAN, 0.0, None),
        };
        row.quality = quality;
        row.moments = moments;
        self.save_steps(f.index, angle, pred, gate)?;
        // A repeated frame that the codec did not keep identical is found after the
        // pass, from both sides (`flag_repeats`): the previous frames alone overshoot
        // at a turning point, where a wire that stops looks like a repeat.
        let flag = if duplicate {
            Some(Flag::Duplicate)
        } else if disturbed {
            Some(Flag::Disturbed)
        } else if !angle.is_finite() || quality < (0.5 * self.q_ref.unwrap_or(0.6)).max(0.1) {
            Some(Flag::Weak)
        } else if pred.is_some_and(|p| (angle - p).abs() > gate) {
            Some(Flag::Gate)
        } else {
            None
        };
        if angle.is_finite() {
            row.angle_rad = Some(angle);
        }
        if flag.is_none() && angle.is_finite() {
            self.look_beside(f, angle)?;
        }
        if self.debug.as_deref() == Some("frames") {
            eprintln!(
                "frame {} t {:.3} angle {:.2} pred {:?} q {:.2} flag {:?} side {:?} undecided {}",
                f.index,
                f.t_s,
                angle.to_degrees(),
                pred.map(|p| (p.to_degrees() * 100.0).round() / 100.0),
                quality,
                flag,
                self.ridges.side(),
                self.undecided.len()
            );
        }
        // A weak measurement (too little of the band covered) is no evidence of where
        // the wire went: the re-anchoring below does not count it.
        if angle.is_finite() && flag != Some(Flag::Weak) {
            self.raw.push((f.t_s, angle));
            if self.raw.len() > 8 {
                self.raw.remove(0);
            }
        }
        // Re-anchor after a run of rejections (see `Tracker::reanchors`).
        let flag = match flag {
            Some(Flag::Gate)
                if self.since_good >= 2 && self.raw.len() >= 3 && self.reanchors(pred) =>
            {
                let r = &self.raw[self.raw.len() - 3..];
                self.hist.clear();
                self.hist.extend_from_slice(&r[..2]);
                self.still = None;
                None
            }
            other => other,
        };
        match flag {
            None => {
                if let Some(p) = pred.filter(|_| !self.starting()) {
                    let e2 = (angle - p).powi(2);
                    self.innov = Some(match self.innov {
                        Some((ms, n)) => (0.97 * ms + 0.03 * e2.min(9.0 * ms.max(1e-12)), n + 1),
                        None => (e2, 1),
                    });
                }
                self.q_ref = Some(match self.q_ref {
                    Some(q) => 0.95 * q + 0.05 * quality,
                    None => quality,
                });
                self.hist.push((f.t_s, angle));
                self.note_still(f.t_s, angle);
                if self.hist.len() > 16 {
                    self.hist.drain(..8);
                }
                self.since_good = 0;
                self.repeats_since_good = 0;
                let other = self.pair_other.take();
                let held = !self.undecided.is_empty()
                    && self.undecided.len() < UNDECIDED_MAX_FRAMES
                    && self.ridges.side().is_none();
                if other.is_some() || held {
                    self.undecided.push(Undecided {
                        frame: f.index,
                        t_s: f.t_s,
                        taken: angle,
                        other,
                    });
                }
            }
            // A repeated frame says nothing new: it neither widens the search nor the
            // gate (widened, a wire at rest beside its own shadow was lost to the shadow
            // at the first repeat).
            Some(Flag::Duplicate) => {
                row.flag = Some(Flag::Duplicate);
                self.repeats_since_good += 1;
            }
            Some(fl) => {
                row.flag = Some(fl);
                self.since_good += 1;
                self.save_diag(f.index, angle, pred)?;
            }
        }
        self.restate_undecided();
        Ok(row)
    }

    /// The offsets of the sharper ridges beside the followed line, per look
    /// ([`beside::sharper_beside`]).
    pub(super) fn beside(&self) -> &[Vec<f64>] {
        self.beside.found()
    }

    /// The rows restated since the last call ([`Tracker::restate_undecided`]).
    pub(super) fn take_restated(&mut self) -> Vec<Restated> {
        std::mem::take(&mut self.restated)
    }

    /// Fewer than [`START_FRAMES`] frames accepted since the track began (or was
    /// re-anchored): the prediction is poor, and there is no track to keep yet.
    fn starting(&self) -> bool {
        self.hist.len() < START_FRAMES
    }

    /// How far this frame's angle may lie from its prediction to be accepted: the
    /// configured gate, tightened to the accepted frames' innovations, widened for fast
    /// motion, after refused or repeated frames, and while the history is short.
    fn accept_gate(&self) -> f64 {
        // Fewer than three accepted frames make a poor prediction: open the gate.
        let short = if self.starting() { 4.0 } else { 1.0 };
        // Fast motion at a low frame rate predicts less well: widen the gate by half the
        // last accepted step.
        let step = match self.hist.as_slice() {
            [.., (_, a), (_, b)] => (b - a).abs(),
            _ => 0.0,
        };
        // Once the innovations (measured minus predicted) of accepted frames are known,
        // the gate tightens to four times their RMS: a repeated frame that the codec did
        // not keep bit-identical still lags its prediction by a fraction of a degree.
        let base = match self.innov {
            Some((ms, n)) if n >= 30 => (4.0 * ms.sqrt()).clamp(0.05f64.to_radians(), self.gate),
            _ => self.gate,
        };
        let reach = 1.0 + self.repeats_since_good as f64;
        (base + 0.5 * step * reach) * (1.0 + self.since_good as f64) * short
    }
}

/// Mean of every `step`-th byte.
fn sampled_mean(d: &[u8], step: usize) -> f64 {
    let (mut s, mut n) = (0u64, 0u64);
    for v in d.iter().step_by(step) {
        s += *v as u64;
        n += 1;
    }
    s as f64 / n.max(1) as f64
}

/// Mean absolute difference between every `step`-th byte of `a` and the bytes of
/// `sampled` (which holds every `step`-th byte of the previous frame).
fn mean_abs_diff_sampled(a: &[u8], sampled: &[u8], step: usize) -> f64 {
    let (mut s, mut n) = (0u64, 0u64);
    for (x, y) in a.iter().step_by(step).zip(sampled) {
        s += x.abs_diff(*y) as u64;
        n += 1;
    }
    if n as usize != sampled.len() {
        return f64::INFINITY;
    }
    s as f64 / n.max(1) as f64
}

#[cfg(test)]
mod test_support;
#[cfg(test)]
pub(super) use test_support::{test_tracker, test_tracker_over};

#[cfg(test)]
mod tests;
