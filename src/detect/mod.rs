//! The wire detector (the paper's section 2.3.2, done right): per frame, the angle of
//! the wire from the image x axis (Eq. 35 via an orthogonal line fit, ERRATA §6).
//!
//! 1. [`geometry`] finds, from the first seconds of motion, the wire's polarity, its
//!    pivot, the band of radii where it is visible and a region of interest (or takes
//!    them from the experiment's `video:` block). Of a still start (the ball held
//!    before its release) the look keeps only its last frames: see `still`.
//! 2. Frames stream through once, cropped to the region: the moving-object evidence is
//!    the difference from a background that follows the scene (the running maximum for
//!    a dark wire, minimum for a light one, decaying slowly with the lighting; frames
//!    with a global flash are kept out of it). Pixels above a noise threshold that lie
//!    in a wedge around the angle predicted from the previous frames and in the band
//!    vote in a histogram of angles about the pivot, each angle's votes counted by the
//!    share of the band they reach; the sharpest peak is the wire (a hand or the bob
//!    is broad, the bob's rim short). The orthogonal line fit through the pivot of
//!    every evidence pixel in a ±2.5 px strip along it gives the angle: below the
//!    threshold too, since a threshold that differs from pixel to pixel cuts a blurred
//!    wire's flanks unevenly and tilts the fit; parts of the band whose pixels stray
//!    from the line (the bob's rim beside the wire) are dropped from it.
//! 3. The gate: a measured angle farther from the prediction than `gate_deg`, a
//!    frame with too little of the wire, a flash, or a frame identical to the previous
//!    one (a dropped frame the recorder repeated) is flagged. After the pass, a repeat
//!    that the codec did not keep identical is found from both sides (its angle stays
//!    at the previous frame's where the neighbours say the wire moved on). Flagged
//!    frames are filled from their good neighbours (status `corrected`), or left
//!    `missing` when there are none; operator marks replace the detection (`manual`).
//!    Each frame the gate flags while streaming, repeats aside, gets a diagnostic
//!    image with the detected and predicted lines (the paper's Figure 11).
//!
//! Memory is flat: one frame, the background and the evidence at a time, whatever the
//! video's length (the per-frame angles are a few bytes each), and a few frames'
//! regions for Figure 11 ([`figure11_png`]) and for the review page ([`Review`], at
//! most 80 pictures of at most 512 px a side), kept by the pass instead of decoding
//! again.
//!
//! The frames come from a [`VideoInput`], opened twice (the first look, shrunk for a
//! large frame, then the streaming pass, whose decoder starts while the geometry is
//! worked out): a [`VideoFile`] for [`detect`], or frames
//! made in memory ([`MemoryVideo`]) for tests that need no decoder.

mod figure11;
mod fill;
pub mod geometry;
mod input;
mod light;
mod line;
mod morph;
mod options;
mod repeats;
pub mod review;
mod row;
mod still;
pub mod summary;
mod track;

pub use figure11::{figure11_frame, figure11_png, Figure11};
pub use input::{MemoryVideo, VideoFile, VideoInput};
pub use line::{fit_line_through, fit_line_weighted, moments, unwrap_near, Line};
pub use options::{DetectOptions, FrameProgress};
pub use review::{Review, ReviewFrame};
pub use row::{AngleRow, Detection, Flag, Status};

use crate::video::{Frame, FrameSource, Roi};
use anyhow::{bail, ensure, Context, Result};
use fill::{apply_marks, fill_flagged};
use geometry::InitFrames;
use nalgebra::Vector2;
use repeats::flag_repeats;
use std::io::IsTerminal;
use std::path::Path;
use track::Tracker;

/// A point or vector in pixel coordinates (x right, y down).
pub type Pt = Vector2<f64>;

/// Full-frame coordinates of a point of a grid shrunk `s` times from the full frame's
/// pixels starting at `origin`: its pixel `i` averages full pixels `origin + s i` to
/// `origin + s i + s - 1`, so its centre lies at `origin + s i + (s - 1) / 2`.
fn shrunk_to_full(p: Pt, origin: Pt, s: f64) -> Pt {
    origin + p * s + Pt::repeat(0.5 * (s - 1.0))
}

/// The inverse of [`shrunk_to_full`].
fn full_to_shrunk(p: Pt, origin: Pt, s: f64) -> Pt {
    (p - origin - Pt::repeat(0.5 * (s - 1.0))) / s
}

/// Length of the first look at the video (geometry and background), s: more than half
/// a swing of any pendulum up to a 5 s period.
const INIT_SECONDS: f64 = 2.5;

/// The most frames a first look keeps (a high frame rate's [`INIT_SECONDS`]).
const LOOK_MAX_FRAMES: usize = 300;

/// The detector's peak memory at a working side, estimated before it starts, MiB: a
/// base of 40 MiB and 2.3 copies of the first look's frames at the scale the working
/// side gives (the look's frames, its background and the frames held for the streaming
/// pass), as measured at 1280 px on a 1280x720 video (184 MiB) and at 4096 px on a
/// 3840x2160 one (1.5 GiB). For `--work-side`: a larger side costs memory, and the
/// command says how much before it is spent.
pub fn peak_memory_estimate_mib(info: &crate::video::VideoInfo, work_side_px: f64) -> f64 {
    let side = f64::from(info.width.max(info.height));
    let shrink = (side / work_side_px.max(WORK_SIDE_PX)).ceil().max(1.0);
    let fps = match (info.frames_header, info.duration_s) {
        (Some(n), Some(d)) if d > 0.0 => n as f64 / d,
        _ => 30.0,
    };
    let frames = (INIT_SECONDS * fps).ceil().min(LOOK_MAX_FRAMES as f64);
    let frame =
        (f64::from(info.width) / shrink).floor() * (f64::from(info.height) / shrink).floor();
    40.0 + 2.3 * frames * frame / f64::from(1u32 << 20)
}

/// Of a still start (a held ball, see [`still`]), the first look keeps the last this
/// many frames and starts its clock at the first of them. A release from an extreme
/// without a hold moves the wire visibly within a few frames at any frame rate.
const STILL_KEEP: usize = 8;

/// A still start longer than this (s) is taken as the motion's start: the look does
/// not wait for ever on a wire it cannot see move.
const STILL_MAX_SECONDS: f64 = 10.0;

/// Detect the wire angle in every frame of a video file (decoded by `ffmpeg`).
pub fn detect(path: &Path, opts: &DetectOptions) -> Result<Detection> {
    detect_from(&VideoFile::open(path)?, opts)
}

/// Detect the wire angle in every frame of `input` (the input decides how it
/// decodes).
pub fn detect_from(input: &dyn VideoInput, opts: &DetectOptions) -> Result<Detection> {
    let started = std::time::Instant::now();
    let info = input.info();
    let name = input.name();
    let bound = opts.roi.unwrap_or(Roi {
        x: 0,
        y: 0,
        w: info.width,
        h: info.height,
    });
    if bound.x + bound.w > info.width || bound.y + bound.h > info.height {
        bail!(
            "{}: `video.roi` = [{}, {}, {}, {}] does not fit in the {}x{} frame",
            name,
            bound.x,
            bound.y,
            bound.w,
            bound.h,
            info.width,
            info.height
        );
    }
    let (first, last) = match opts.frames {
        Some([a, b]) => (a, b),
        None => (0, u64::MAX),
    };
    // 1. Geometry from the first seconds, at the working scale that sees the wire best.
    let looks = FirstLook {
        input,
        opts,
        bound,
        first,
        last,
        started,
    };
    let (look, other) = looks.at_best_scale()?;
    // 2. The streaming pass at that scale.
    let d = streaming_pass(looks, look)?;
    // 3. A pivot the pass's own lines do not bear out (a swing scale far from 1: the
    // wire's direction turns more or less than its angle about the pivot) is the look's
    // at a scale that saw something else as the wire (a 2 px wire and its blurred shadow
    // merged into one line by shrinking, with a pivot 5 px off): the other scale's look
    // is measured too, and the pass whose pivot its lines bear out better is kept.
    let off = |d: &Detection| d.swing_scale.map_or(0.0, |s| (s - 1.0).abs());
    let Some(other) = other.filter(|_| off(&d) > SWING_SCALE_RETRY) else {
        return Ok(d);
    };
    eprintln!(
        "{}: the wire's lines turn {:.3} times as much as its angle about the pivot the \
         first look found; measuring again from a look at the other working scale",
        input.name(),
        d.swing_scale.unwrap_or(f64::NAN)
    );
    let again = match other {
        Other::Looked(l) => Ok(*l),
        Other::Unlooked(k) => looks.at(k),
    }
    .and_then(|l| streaming_pass(looks, l));
    let kept = match again {
        Ok(a) if a.swing_scale.is_some() && off(&a) < off(&d) => Detection {
            decodings: a.decodings + d.decodings,
            ..a
        },
        Ok(a) => {
            eprintln!(
                "{}: at the other scale they turn {:.3} times as much: the first \
                 measurement is kept",
                input.name(),
                a.swing_scale.unwrap_or(f64::NAN)
            );
            Detection {
                decodings: d.decodings + a.decodings,
                ..d
            }
        }
        Err(e) => {
            eprintln!(
                "{}: the other scale measures nothing ({e:#}): the first measurement is \
                 kept",
                input.name()
            );
            d
        }
    };
    Ok(kept)
}

/// A swing scale ([`Tracker::swing_scale`]) further than this from 1 has the other
/// working scale's look measured too ([`detect_from`]). On the robustness sweep's twins
/// (both seeds, 126 measured) it lies within 0.002 of 1, and within 0.001 for 122 of
/// them; a 960x540 twin whose shrunk look took a wire and its shadow for one line gave
/// 1.09.
const SWING_SCALE_RETRY: f64 = 0.02;

/// The working scale [`FirstLook::at_best_scale`] did not keep: its look (when it found a
/// wire), or its shrink factor (not looked at).
enum Other<'a> {
    Looked(Box<Located<'a>>),
    Unlooked(u32),
}

/// The streaming pass over the region `look` found, and the detection it makes.
fn streaming_pass<'a>(looks: FirstLook<'a>, mut look: Located<'a>) -> Result<Detection> {
    let FirstLook {
        input,
        opts,
        first,
        last,
        started,
        ..
    } = looks;
    let info = input.info();
    let name = input.name();
    let stream = look.stream.take();
    let continued = stream.is_some();
    let geo = &look.geo;
    let mut frame = Frame::default();

    // The region of interest: the first look's decoder going on (its frames cut to the
    // region here), or a decoder cropping to it.
    let mut src: Box<dyn FrameSource + '_> = match stream {
        Some(from) => Box::new(CropSource::new(from, geo.roi)?),
        None => input.open(geo.roi, 1)?,
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
    // The header's count, within the frames asked for (the header may be wrong: the
    // last report below gives the frames actually measured).
    let total = info
        .frames_header
        .map(|n| n.min(last.saturating_add(1)).saturating_sub(first));
    let tty = std::io::stderr().is_terminal() && opts.progress.is_none();
    let mut rows = Vec::new();
    let mut keeper = figure11::Keeper::new(figure11::PER_SIDE);
    let mut review = review::Keeper::new();
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
        let hint = geo
            .initial_angles
            .get(k.saturating_sub(look.dropped))
            .copied()
            .flatten();

        let row = tracker.step(&frame, hint)?;
        keeper.offer(&row, &frame);
        review.offer(&row, &frame, tracker.predicted())?;
        rows.push(row);
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
    if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
        eprintln!(
            "timing: streaming pass done at {:.2} s ({waited:.2} s waiting for frames)",
            started.elapsed().as_secs_f64()
        );
    }
    drop(src);
    if rows.is_empty() {
        bail!("{}: no frame in the requested range", name);
    }
    if rows.iter().any(|r| !r.t_s.is_finite()) {
        bail!("{}: the decoder gave frames without timestamps", name);
    }
    flag_repeats(&mut rows);
    let pivot = tracker.refine_pivot(&mut rows);
    fill_flagged(&mut rows);
    apply_marks(
        &mut rows,
        &opts.marks,
        pivot,
        0.5 * (geo.theta_min + geo.theta_max),
    );
    let usable = rows.iter().filter(|r| r.status != Status::Missing).count();
    if usable < rows.len() / 2 {
        bail!(
            "{}: the wire was found in only {usable} of {} frames (last good frame {}); \
             check `video.roi`, `video.pivot` and `video.polarity`",
            name,
            rows.len(),
            rows.iter()
                .rev()
                .find(|r| r.status == Status::Ok)
                .map_or(0, |r| r.frame)
        );
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
    let swing_scale = tracker.swing_scale(&rows, pivot);
    let figure11 = keeper.take(&rows);
    Ok(Detection {
        rows,
        pivot_px: [pivot.x, pivot.y],
        roi: [geo.roi.x, geo.roi.y, geo.roi.w, geo.roi.h],
        dark_wire: geo.dark,
        band_px: [geo.r_lo, geo.r_hi],
        decoder: input.decoder(),
        decodings,
        diagnostics: tracker.diagnostics,
        figure11,
        review: review.take(),
        swing_scale,
        calibration: opts.calibration.clone(),
    })
}

/// The first look's frames as decoded and its decoder, going on into the streaming
/// pass (see [`decode_once`]).
struct Continued<'a> {
    /// The look's frames, as decoded (no brightness correction), from the first asked for.
    held: std::collections::VecDeque<Frame>,
    /// The rest of the stream (none when the frames asked for end within the look).
    rest: Option<Box<dyn FrameSource + 'a>>,
    /// The region the decoder crops (the look's), in which the streaming pass's lies.
    bound: Roi,
}

/// The frames of a [`Continued`] look, each cut to `roi` (which lies within the look's
/// region): the bytes a decoder cropping to `roi` gives.
struct CropSource<'a> {
    from: Continued<'a>,
    roi: Roi,
    /// The frame as decoded, at the look's region.
    full: Frame,
}

impl<'a> CropSource<'a> {
    /// The frames of `from` cut to `roi`, which must lie within the look's region.
    fn new(from: Continued<'a>, roi: Roi) -> Result<Self> {
        let bound = from.bound;
        ensure!(
            roi.x >= bound.x
                && roi.y >= bound.y
                && roi.x + roi.w <= bound.x + bound.w
                && roi.y + roi.h <= bound.y + bound.h,
            "the region {roi:?} does not lie within the first look's {bound:?}"
        );
        Ok(Self {
            from,
            roi,
            full: Frame::default(),
        })
    }
}

impl FrameSource for CropSource<'_> {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        match self.from.held.pop_front() {
            Some(f) => {
                let spent = std::mem::replace(&mut self.full, f);
                if let Some(rest) = &mut self.from.rest {
                    rest.recycle(spent.data);
                }
            }
            None => {
                let more = match &mut self.from.rest {
                    Some(rest) => rest.next_frame(&mut self.full)?,
                    None => false,
                };
                if !more {
                    return Ok(false);
                }
            }
        }
        let (bound, roi, full) = (self.from.bound, self.roi, &self.full);
        ensure!(
            full.width == bound.w as usize && full.height == bound.h as usize,
            "frame {}: decoded at {}x{} px, not at the first look's {}x{}",
            full.index,
            full.width,
            full.height,
            bound.w,
            bound.h
        );
        input::crop_rows(
            &full.data,
            full.width,
            ((roi.x - bound.x) as usize, (roi.y - bound.y) as usize),
            (roi.w as usize, roi.h as usize),
            &mut frame.data,
        );
        frame.width = roi.w as usize;
        frame.height = roi.h as usize;
        frame.index = full.index;
        frame.t_s = full.t_s;
        Ok(true)
    }
}

/// The first look's decoder goes on into the streaming pass when the look is at full
/// size and the frames asked for, at the look's region, amount to at most this many
/// bytes (so that no decoder starts again, and the look's frames are not decoded
/// twice); a longer video starts a decoder that crops to the region of interest, whose
/// fewer bytes through the pipe then outweigh a second decoder's start. Measured with
/// `make bench`: see the README's detector paragraph.
const DECODE_ONCE_MAX_BYTES: u64 = 256 << 20;

/// The first look's frames, as decoded, held for the streaming pass at most to this
/// many bytes: a look expected to need more (a high frame rate at a large region:
/// 960x540 at 60 frames/s) is not decoded once, and one that comes to need more (a long
/// still start) starts a decoder again for the streaming pass.
const HELD_MAX_BYTES: usize = 48 << 20;

/// What the first look's decoder may decode ahead of the look, bytes: the frames after
/// the look come while its geometry is worked out, so that the decoder does not wait on
/// the geometry. A 960x540 look's geometry takes 0.2-0.3 s, in which the decoder gives
/// about 150 frames of 0.5 MB; with 24 MiB it stopped after 48 of them, and the
/// streaming pass waited 0.2 s for frames. Bounded: a video decoded once is at most
/// [`DECODE_ONCE_MAX_BYTES`] in all, and its frames go as the streaming pass takes them.
const READ_AHEAD_BYTES: usize = 96 << 20;

/// Whether the first look at `shrink` over `bound` decodes once for the whole detection
/// ([`DECODE_ONCE_MAX_BYTES`]).
fn decode_once(
    info: &crate::video::VideoInfo,
    bound: Roi,
    shrink: u32,
    first: u64,
    last: u64,
) -> bool {
    let (Some(n), Some(d)) = (info.frames_header, info.duration_s) else {
        return false;
    };
    let frames = n.min(last.saturating_add(1)).saturating_sub(first);
    let bytes = u64::from(bound.w) * u64::from(bound.h);
    // The look's frames at the nominal rate (at most `LOOK_MAX_FRAMES`).
    let look = (INIT_SECONDS * n as f64 / d.max(1e-3))
        .ceil()
        .min(LOOK_MAX_FRAMES as f64) as u64;
    shrink == 1
        && frames.saturating_mul(bytes) <= DECODE_ONCE_MAX_BYTES
        && look.saturating_mul(bytes) <= HELD_MAX_BYTES as u64
}

/// The first look's findings at one working scale: the geometry, and what the
/// streaming pass starts from (the background, the threshold map, the reference frame,
/// all at that scale).
struct Located<'a> {
    /// The look's decoder, when it goes on into the streaming pass.
    stream: Option<Continued<'a>>,
    /// The first looks decoded (one per working scale looked at).
    looks: usize,
    geo: geometry::WireGeometry,
    init_bg: opencv::core::Mat,
    init_tmap: opencv::core::Mat,
    init_reference: opencv::core::Mat,
    /// The shrink factor of the look.
    shrink: u32,
    /// The look's region (cut to whole multiples of `shrink`).
    bound: Roi,
    /// Frames of a still start dropped from the front of the look.
    dropped: usize,
}

/// The working side, px, by default (`video.work_side_px` asks for a larger one): a
/// frame is shrunk by a whole factor towards this size for the first look, and the
/// streaming pass works at the look's scale. A 1280x720 video is so measured at half
/// size, its 2 px wire sampled as 1 px: at full size its angles err less, for about
/// twice the detector's own processor time (README, "Working scale").
const WORK_SIDE_PX: f64 = 640.0;

/// What every first look at one video shares: the input, the options, the region
/// asked for, the frames asked for and the detection's start (for the timing lines).
#[derive(Clone, Copy)]
struct FirstLook<'a> {
    input: &'a dyn VideoInput,
    opts: &'a DetectOptions,
    bound: Roi,
    first: u64,
    last: u64,
    started: std::time::Instant,
}

impl<'a> FirstLook<'a> {
    /// The first look at the working scale that sees the wire best. A frame is shrunk by
    /// whole factors only, so two scales bracket [`WORK_SIDE_PX`]: the coarser (larger side
    /// at most 640 px) and the finer (at least 640 px). With a larger working side asked
    /// for (`work_side_px`), the finer is the finest at most that wide instead (for 1280:
    /// 1280x720 at full size, 1920x1080 at half size). By default they coincide for 640,
    /// 1280 and 1920 px wide frames; for others (960x540, say) the coarser one may blur a
    /// 1 px wire into its own shadow while the finer one sees edges too sharply to settle
    /// on the wire. The finer scale is looked at first and kept when it found, at the strict
    /// threshold (against either background), a wire that never jumps; otherwise the
    /// coarser one is looked at too, and the scale whose wire needed fewer of the
    /// geometry's fallbacks (then fewer jumps) wins, the finer on a tie.
    ///
    /// On the sweep's 960x540 twins the finer scale is kept in 11 of 12 (one refuses
    /// there: a 2 px wire under a blurred shadow); on a real 1920x1080 clip scaled to
    /// 960x540 and turned by 180 or 270 degrees it needs the lower threshold or refuses,
    /// and the coarser scale (which measures the clip as filmed) is kept.
    ///
    /// With the look kept comes the other scale ([`Other`]), when there is one.
    fn at_best_scale(&self) -> Result<(Located<'a>, Option<Other<'a>>)> {
        let side = self.bound.w.max(self.bound.h) as f64;
        let coarse = (side / WORK_SIDE_PX).ceil().max(1.0) as u32;
        let fine = if self.opts.work_side_px > WORK_SIDE_PX {
            (side / self.opts.work_side_px).ceil().max(1.0) as u32
        } else {
            (side / WORK_SIDE_PX).floor().max(1.0) as u32
        };
        if fine == coarse {
            return Ok((self.at(coarse)?, None));
        }
        let mut at_fine = self.at(fine);
        let rank = |l: &Located| (l.geo.stage, l.geo.jumps);
        if let Ok(l) = &mut at_fine {
            if l.geo.stage <= 1 && l.geo.jumps == 0 {
                return Ok((at_fine?, Some(Other::Unlooked(coarse))));
            }
            // The other scale is looked at: this look's decoder stops (and its frames
            // go), and the streaming pass decodes anew whichever scale wins. The other
            // look's decoder starts now.
            if l.stream.take().is_some() {
                self.input.prepare();
            }
        }
        let at_coarse = self.at(coarse);
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            let say = |r: &Result<Located>| match r {
                Ok(l) => format!("stage {} jumps {}", l.geo.stage, l.geo.jumps),
                Err(e) => format!("{e:#}"),
            };
            eprintln!(
                "geometry: shrunk {fine}x: {}; shrunk {coarse}x: {}",
                say(&at_fine),
                say(&at_coarse)
            );
        }
        // The look not kept is kept aside, without its decoder (a look decoded once
        // would have it go on): its frames' decoding was counted with the kept one.
        let aside = |mut l: Located<'a>| {
            l.stream = None;
            Some(Other::Looked(Box::new(Located { looks: 0, ..l })))
        };
        let (best, other) = match (at_fine, at_coarse) {
            (Ok(f), Ok(c)) if rank(&c) < rank(&f) => (c, aside(f)),
            (Ok(f), Ok(c)) => (f, aside(c)),
            (Ok(f), Err(_)) => (f, None),
            (Err(_), c) => (c?, None),
        };
        Ok((Located { looks: 2, ..best }, other))
    }

    /// The first look (about [`INIT_SECONDS`] of motion) shrunk `use_shrink` times, and the
    /// geometry found in it.
    fn at(&self, use_shrink: u32) -> Result<Located<'a>> {
        let FirstLook {
            input,
            opts,
            bound,
            first,
            last,
            started,
        } = *self;
        let info = input.info();
        let name = input.name();
        // The first look's region, cut to whole multiples of the shrink factor: each of
        // its pixels averages exactly `use_shrink` x `use_shrink` full pixels.
        let bound = Roi {
            w: bound.w - bound.w % use_shrink,
            h: bound.h - bound.h % use_shrink,
            ..bound
        };
        // Decoded once (see `decode_once`): the look's frames are held as decoded for the
        // streaming pass, and the decoder reads ahead while the geometry is worked out.
        let once = opts.decode_once && decode_once(info, bound, use_shrink, first, last);
        let mut src = if once {
            input.open_ahead(bound, READ_AHEAD_BYTES)?
        } else {
            input.open(bound, use_shrink)?
        };
        let mut held = once.then(std::collections::VecDeque::new);
        let mut held_bytes = 0usize;
        let mut past_last = false;
        let mut init = InitFrames {
            w: 0,
            h: 0,
            shrink: use_shrink as f64,
            x0: bound.x as f64,
            y0: bound.y as f64,
            data: Vec::new(),
        };
        let mut frame = Frame::default();
        // Every frame at the first frame's brightness (flicker, drift): see `light`.
        // Both against the first frame, made when it arrives.
        let mut against_first: Option<(light::Brightness, still::Stillness)> = None;
        // The times of the kept frames, and how many frames of a still start were dropped
        // from the front.
        let mut times = std::collections::VecDeque::new();
        let mut dropped = 0usize;
        let mut t_first = None;
        let mut decoded = 0u64;
        while src
            .next_frame(&mut frame)
            .with_context(|| "finding the wire".to_string())?
        {
            decoded = frame.index + 1;
            if frame.index < first {
                continue;
            }
            if frame.index > last {
                // The frames asked for end within the look: the stream has nothing more
                // for the streaming pass (and the rest of the video is not read).
                past_last = true;
                break;
            }
            if let Some(h) = &mut held {
                held_bytes += frame.data.len();
                if held_bytes <= HELD_MAX_BYTES {
                    h.push_back(frame.clone());
                } else {
                    held = None;
                }
            }
            init.w = frame.width;
            init.h = frame.height;
            let t_first = *t_first.get_or_insert(frame.t_s);
            init.data.push(frame.data.clone());
            times.push_back(frame.t_s);
            let newest = init.data.last_mut().expect("just pushed");
            match &mut against_first {
                Some((l, s)) => {
                    l.normalise(newest);
                    let held = frame.t_s - t_first < STILL_MAX_SECONDS;
                    if held && !s.moved(newest) && init.data.len() > STILL_KEEP {
                        init.data.remove(0);
                        times.pop_front();
                        dropped += 1;
                    }
                }
                None => {
                    against_first = Some((
                        light::Brightness::new(newest),
                        still::Stillness::new(newest),
                    ))
                }
            }
            if frame.t_s - times[0] >= INIT_SECONDS || init.data.len() >= LOOK_MAX_FRAMES {
                break;
            }
        }
        let mut stream = match held {
            Some(held) => Some(Continued {
                held,
                rest: (!past_last).then_some(src),
                bound,
            }),
            None => {
                drop(src);
                // The streaming pass (or a look at another scale) follows: its decoder
                // starts while the geometry is worked out.
                input.prepare();
                None
            }
        };
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!(
                "timing: first look decoded at {:.2} s ({} frames, {dropped} of a still start dropped)",
                started.elapsed().as_secs_f64(),
                init.data.len()
            );
        }
        if init.data.is_empty() {
            if let (Some([a, b]), true) = (opts.frames, decoded > 0) {
                bail!(
                    "{name}: frames {a}..{b} asked for, but the video has only {decoded} (0..{})",
                    decoded - 1
                );
            }
            bail!("{}: no frame could be decoded", name);
        }
        let noise = geometry::noise_map(&init);
        let geo = geometry::find(
            &init,
            &noise,
            info.width,
            info.height,
            opts.polarity,
            opts.pivot.map(|[x, y]| Pt::new(x, y)),
            opts.roi,
        )
        .with_context(|| format!("{}: no wire found", name))?;
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!(
                "timing: geometry done at {:.2} s",
                started.elapsed().as_secs_f64()
            );
        }
        let init_bg = geometry::extreme_frame(&init, geo.dark)?;
        let init_tmap = geometry::threshold_map(&init, &noise, 0.5 * opts.threshold_sigma, 6.0)?;
        let init_reference = geometry::frame_mat(&init, 0)?;
        // The look's frames, done with, go to the decoder going on (see `recycle`).
        if let Some(rest) = stream.as_mut().and_then(|s| s.rest.as_mut()) {
            for buf in init.data {
                rest.recycle(buf);
            }
        }
        Ok(Located {
            stream,
            looks: 1,
            geo,
            init_bg,
            init_tmap,
            init_reference,
            shrink: use_shrink,
            bound,
            dropped,
        })
    }
}

#[cfg(test)]
mod tests;
