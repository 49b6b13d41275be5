//! The first look at a video: its first seconds decoded (once, when short enough to go
//! on into the streaming pass), at the working scale that sees the wire best, and the
//! wire's geometry found in them.

use super::*;
use crate::detect::tuning::{
    DECODE_ONCE_MAX_BYTES, EXPLAINS, HELD_MAX_BYTES, HELD_SWEEP_DEG, INIT_SECONDS, LOOK_EVERY,
    LOOK_EVERY_S, LOOK_HINT_EXPLAINS, LOOK_MAX_BYTES, LOOK_MAX_FRAMES, LOOK_MIN_FRAMES, MOVING_PX,
    MOVING_SHARE, PASS_FLOOR, PRUNE_SHARE, READ_AHEAD_BYTES, STILL_KEEP, STILL_MAX_SECONDS,
    WORK_MAX_PIXELS, WORK_SIDE_PX,
};

/// The whole factor a region of `w` x `h` px is shrunk by at a working side of
/// `work_side_px`: the finest that brings its larger side to at most that side and its
/// pixels to at most [`WORK_MAX_PIXELS`] (the bound on a look's memory).
pub(crate) fn work_shrink(w: u32, h: u32, work_side_px: f64) -> u32 {
    let mut k = side_shrink(w, h, work_side_px);
    while u64::from(w / k) * u64::from(h / k) > WORK_MAX_PIXELS {
        k += 1;
    }
    k
}

/// The least whole factor that brings the larger side of a `w` x `h` px region to at
/// most `side` px.
pub(crate) fn side_shrink(w: u32, h: u32, side: f64) -> u32 {
    (f64::from(w.max(h)) / side).ceil().max(1.0) as u32
}

/// Every how many frames the look keeps one, for frames of `bytes` each and a video of
/// `info`'s rate: 1 unless its [`INIT_SECONDS`] would hold more than [`LOOK_MAX_BYTES`].
pub(super) fn look_stride(info: &crate::video::VideoInfo, bytes: usize) -> u64 {
    let look = match (info.frames_header, info.duration_s) {
        (Some(n), Some(d)) if n > 0 && d > 0.0 => (INIT_SECONDS * n as f64 / d)
            .ceil()
            .min(LOOK_MAX_FRAMES as f64) as usize,
        _ => LOOK_MAX_FRAMES,
    };
    if look.saturating_mul(bytes) <= LOOK_MAX_BYTES {
        return 1;
    }
    let keep = (LOOK_MAX_BYTES / bytes.max(1)).max(LOOK_MIN_FRAMES);
    look.div_ceil(keep).max(1) as u64
}

/// Whether the first look at `shrink` over `bound` decodes once for the whole detection
/// ([`DECODE_ONCE_MAX_BYTES`]).
pub(super) fn decode_once(
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
pub(super) struct Located<'a> {
    /// The look's decoder, when it goes on into the streaming pass.
    pub(super) stream: Option<Continued<'a>>,
    /// The first looks decoded (one per working scale looked at).
    pub(super) looks: usize,
    pub(super) geo: geometry::WireGeometry,
    pub(super) init_bg: opencv::core::Mat,
    pub(super) init_tmap: opencv::core::Mat,
    pub(super) init_reference: opencv::core::Mat,
    /// The shrink factor of the look.
    pub(super) shrink: u32,
    /// The look's region (cut to whole multiples of `shrink`).
    pub(super) bound: Roi,
    /// Frames of a still start dropped from the front of the look (of those it kept).
    pub(super) dropped: usize,
    /// The look kept one frame in this many ([`look_stride`]).
    pub(super) stride: usize,
    /// The camera moved in the look (a frame displaced by more than
    /// [`MOVING_PX`]): its frames were warped back onto its first, and the
    /// streaming pass's are too.
    pub(super) moving: bool,
    /// Enough of the look's glances found the camera moved by the weaker test of
    /// [`LOOK_HINT_EXPLAINS`]: a pass that finds it moving from the start is believed.
    pub(super) hinted: bool,
}

/// What every first look at one video shares: the input, the options, the region
/// asked for, the frames asked for and the detection's start (for the timing lines).
#[derive(Clone, Copy)]
pub(super) struct FirstLook<'a> {
    pub(super) input: &'a dyn VideoInput,
    pub(super) opts: &'a DetectOptions,
    pub(super) bound: Roi,
    pub(super) first: u64,
    pub(super) last: u64,
    pub(super) started: std::time::Instant,
    /// The process's processor time when the first streaming pass started, s (see
    /// [`Detection::cpu_s`]); set by that pass, none when the clock could not be read.
    pub(super) pass_from: &'a std::cell::OnceCell<Option<f64>>,
    /// The camera is known to move (a pass found it moving from the start): the look's
    /// frames are steadied whatever its own glances find.
    pub(super) moving: bool,
    /// A camera the pass found moving after glances found it still: the region's frames
    /// are steadied from the pass's first (see `steady::Late::following`).
    pub(super) follow_region: bool,
    /// A still start is judged under the camera's motion (see `still.rs`): the look as
    /// it lies found the camera moving and no wire, or a wire that swept little.
    pub(super) held_under_motion: bool,
    /// A wire that swept little in the look, as it lies, is kept as found: the look with
    /// the still start judged under the camera's motion dropped none of it or did not
    /// see it sweep more.
    pub(super) little_sweep_kept: bool,
    /// The look is made against the median alone ([`geometry::Asked::median_only`]).
    pub(super) median_only: bool,
}

impl<'a> FirstLook<'a> {
    /// The first looks of a detection with `opts` (its region and frames), none made yet.
    pub(super) fn new(
        input: &'a dyn VideoInput,
        opts: &'a DetectOptions,
        started: std::time::Instant,
        pass_from: &'a std::cell::OnceCell<Option<f64>>,
    ) -> Result<Self> {
        let info = input.info();
        let bound = opts.roi.unwrap_or(Roi {
            x: 0,
            y: 0,
            w: info.width,
            h: info.height,
        });
        if bound.x + bound.w > info.width || bound.y + bound.h > info.height {
            bail!(
                "{}: `video.roi` = [{}, {}, {}, {}] does not fit in the {}x{} frame",
                input.name(),
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
        Ok(FirstLook {
            input,
            opts,
            bound,
            first,
            last,
            started,
            pass_from,
            moving: false,
            follow_region: false,
            held_under_motion: false,
            little_sweep_kept: false,
            median_only: false,
        })
    }

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
    /// Where the two coincide (640 divides the larger side: 1280, 1920, 3840 px), the
    /// other scale is a finer one, half as coarse ([`Other::Finer`]): it is looked at when
    /// the detection at the working scale fails, or when its look finds no wire. A faint
    /// string smeared by a fast encoder, or a phone's 4K frame shrunk six times, loses the
    /// wire to the ball's rim at the working scale and keeps it at the finer one.
    ///
    /// With the look kept comes the other scale ([`Other`]), when there is one.
    pub(super) fn at_best_scale(&self) -> Result<(Located<'a>, Option<Other<'a>>)> {
        let side = self.bound.w.max(self.bound.h) as f64;
        let coarse = side_shrink(self.bound.w, self.bound.h, WORK_SIDE_PX);
        let fine = if self.opts.work_side_px > WORK_SIDE_PX {
            work_shrink(self.bound.w, self.bound.h, self.opts.work_side_px)
        } else {
            (side / WORK_SIDE_PX).floor().max(1.0) as u32
        };
        if fine == coarse {
            // The finer scale: half as coarse, as the frame's pixels allow.
            let finer =
                coarse
                    .div_ceil(2)
                    .max(work_shrink(self.bound.w, self.bound.h, f64::INFINITY));
            if finer == coarse {
                return Ok((self.at(coarse)?, None));
            }
            // A look that finds no wire at the working scale is made at the finer one.
            return match self.at(coarse) {
                Ok(l) => Ok((l, Some(Other::Finer(finer)))),
                Err(e) => match self.at(finer) {
                    Ok(l) => Ok((
                        Located {
                            looks: l.looks + 1,
                            ..l
                        },
                        None,
                    )),
                    Err(_) => Err(e),
                },
            };
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
    pub(super) fn at(&self, use_shrink: u32) -> Result<Located<'a>> {
        let FirstLook {
            input,
            opts,
            bound,
            first,
            last,
            started,
            moving: known_moving,
            held_under_motion,
            little_sweep_kept,
            median_only,
            ..
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
        // The camera's motion against the first frame: glanced at every
        // `LOOK_EVERY`th frame, `LOOK_EVERY_S` apart at least; when
        // enough of them moved, measured on all,
        // and the look's frames are warped back.
        let mut steady: Option<steady::Steady> = None;
        let (mut measured, mut moved, mut hinted) = (0usize, 0usize, 0usize);
        let mut last_glance: Option<(u64, f64)> = None;
        // Every how many frames the look keeps one (`look_stride`), from the first.
        let mut stride: Option<u64> = None;
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
            let st = match &mut steady {
                Some(st) => st,
                None => steady.insert(steady::Steady::new(&frame, None)?),
            };
            let glance = last_glance
                .is_none_or(|(k, t)| decoded - k >= LOOK_EVERY && frame.t_s - t >= LOOK_EVERY_S);
            if glance {
                last_glance = Some((decoded, frame.t_s));
                measured += 1;
                let m = st.glance(&frame)?;
                if m.is_some_and(|m| m.reach(init.w as f64, init.h as f64) > MOVING_PX) {
                    let (aligned, not) = st.left_off()?;
                    moved += usize::from(aligned < EXPLAINS * not);
                    hinted += usize::from(aligned < LOOK_HINT_EXPLAINS * not);
                }
            }
            let t_first = *t_first.get_or_insert(frame.t_s);
            let stride = *stride.get_or_insert_with(|| look_stride(info, frame.data.len()));
            if (frame.index - first) % stride != 0 {
                continue;
            }
            // Taken, not copied: the next frame comes in a buffer of its own.
            init.data.push(std::mem::take(&mut frame.data));
            times.push_back(frame.t_s);
            let newest = init.data.last_mut().expect("just pushed");
            match &mut against_first {
                Some((l, s)) => {
                    l.normalise(newest);
                    let held = frame.t_s - t_first < STILL_MAX_SECONDS;
                    // A frame that differs is measured against the first, for a camera
                    // that moves while the ball is held: by a motion a glance would count
                    // as moved (its reach and what it explains). Only when asked (see
                    // `still.rs`).
                    let camera = || {
                        if !held_under_motion {
                            return Ok(None);
                        }
                        let f = Frame {
                            data: newest.clone(),
                            width: init.w,
                            height: init.h,
                            ..Frame::default()
                        };
                        let reach = |m: &steady::Motion| m.reach(init.w as f64, init.h as f64);
                        Ok(match st.measure(&f)? {
                            Some(m) if reach(&m) > MOVING_PX && st.explains()? => Some(m),
                            _ => None,
                        })
                    };
                    if held && !s.moved(newest, camera)? && init.data.len() > STILL_KEEP {
                        init.data.remove(0);
                        times.pop_front();
                        dropped += 1;
                    }
                }
                None => {
                    against_first = Some((
                        light::Brightness::new(newest),
                        still::Stillness::new(newest, init.w),
                    ))
                }
            }
            if frame.t_s - times[0] >= INIT_SECONDS || init.data.len() >= LOOK_MAX_FRAMES {
                break;
            }
        }
        // The camera moved when enough frames did (a still camera's single frames may
        // measure a little off on a plain wall): every frame's motion is measured (the
        // frames in between too) and the look's frames are warped back.
        let moving =
            (known_moving && steady.is_some()) || moved as f64 > MOVING_SHARE * measured as f64;
        let hinted = hinted as f64 > MOVING_SHARE * measured as f64;
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!("steady: the look glanced at {measured} frames, {moved} moved");
        }
        if moving {
            steady_frames(steady.as_mut().expect("a frame was measured"), &mut init)?;
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
        super::debug_timing(
            "first look decoded",
            started,
            &format!(
                " ({} frames, {dropped} of a still start dropped)",
                init.data.len()
            ),
        );
        if init.data.is_empty() {
            if let (Some([a, b]), true) = (opts.frames, decoded > 0) {
                bail!(
                    "{name}: frames {a}..{b} asked for, but the video has only {decoded} (0..{})",
                    decoded - 1
                );
            }
            bail!("{}: no frame could be decoded", name);
        }
        let find = |init: &InitFrames| {
            let noise = geometry::noise_map(init);
            geometry::find(
                init,
                &noise,
                info.width,
                info.height,
                geometry::Asked {
                    polarity: opts.polarity,
                    pivot: opts.pivot.map(|[x, y]| Pt::new(x, y)),
                    roi: opts.roi,
                    median_only,
                },
            )
            .map(|geo| (geo, noise))
        };
        // A camera the glances hinted moved but did not find moving (under heavy
        // compression most pixels differ aligned or not) is steadied when the frames as
        // they lie show no wire: their static edges may be the moving lines.
        let (geo, noise, moving) = match find(&init) {
            Err(e) if !moving && (hinted || moved > 0) => {
                if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                    eprintln!("steady: no wire in the look as it lies ({e:#}); steadied");
                }
                steady_frames(steady.as_mut().expect("a frame was measured"), &mut init)?;
                match find(&init) {
                    Ok((geo, noise)) => (geo, noise, true),
                    Err(_) => return Err(e).with_context(|| format!("{}: no wire found", name)),
                }
            }
            // A camera found moving from a held ball's first frames on moves every edge,
            // and the still start is not dropped: the look spent on the held wire may show
            // its steadied static edges as the moving lines. Looked at again with the
            // still start judged under the camera's motion.
            Err(e) if moving && dropped == 0 && !held_under_motion => {
                if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                    eprintln!(
                        "still: no wire found ({e:#}); a still start under the camera's motion?"
                    );
                }
                drop(stream);
                input.prepare();
                let again = FirstLook {
                    held_under_motion: true,
                    ..*self
                };
                return match again.at(use_shrink) {
                    Ok(l) if l.dropped > 0 => Ok(Located {
                        looks: l.looks + 1,
                        ..l
                    }),
                    _ => Err(e).with_context(|| format!("{}: no wire found", name)),
                };
            }
            // A moving camera's look that found a wire sweeping little (under
            // `HELD_SWEEP_DEG`): a held ball whose wire the look spent its frames on, the
            // swing's first moments at its end (the camera's motion moved the scene from
            // the first frames, and the still start was not judged under it). Such a
            // sweep fixes the pivot poorly along the wire: a 3 deg sweep put it 37 px down
            // a swaying twin's wire (the hand that released the ball drawing back), and
            // the angles swung 24 % too far. Looked at again with the still start judged
            // under the camera's motion; kept when that drops more of a still start and
            // sees the wire sweep more.
            Ok((geo, _))
                if moving
                    && !held_under_motion
                    && !little_sweep_kept
                    && geometry::sweep_deg(&geo) < HELD_SWEEP_DEG =>
            {
                let swept = geometry::sweep_deg(&geo);
                if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
                    eprintln!(
                        "still: the wire swept {swept:.1} deg; a still start under the camera's \
                         motion?"
                    );
                }
                drop(stream);
                input.prepare();
                let again = FirstLook {
                    held_under_motion: true,
                    ..*self
                };
                if let Ok(l) = again.at(use_shrink) {
                    if l.dropped > dropped && geometry::sweep_deg(&l.geo) > swept {
                        return Ok(Located {
                            looks: l.looks + 1,
                            ..l
                        });
                    }
                }
                input.prepare();
                let kept = FirstLook {
                    little_sweep_kept: true,
                    ..*self
                };
                return kept.at(use_shrink).map(|l| Located {
                    looks: l.looks + 2,
                    ..l
                });
            }
            found => {
                let (geo, noise) = found.with_context(|| format!("{}: no wire found", name))?;
                (geo, noise, moving)
            }
        };
        super::debug_timing("geometry done", started, "");
        let init_bg = geometry::extreme_frame(&init, geo.dark)?;
        let init_tmap =
            geometry::threshold_map(&init, &noise, 0.5 * opts.threshold_sigma, PASS_FLOOR)?;
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
            stride: stride.unwrap_or(1) as usize,
            moving,
            hinted,
        })
    }
}

/// The look's frames measured against the first and warped back onto it: twice, first
/// to tell the static scene from what moves in it (see `Steady::tally`), then on the
/// static scene alone.
fn steady_frames(st: &mut steady::Steady, init: &mut InitFrames) -> Result<()> {
    st.steadying();
    st.forget();
    for data in &init.data {
        let f = Frame {
            data: data.clone(),
            width: init.w,
            height: init.h,
            ..Frame::default()
        };
        if st.measure(&f)?.is_some() {
            st.tally()?;
        }
    }
    st.prune(PRUNE_SHARE);
    let mut last = steady::Motion::default();
    for data in init.data.iter_mut() {
        let mut f = Frame {
            data: std::mem::take(data),
            width: init.w,
            height: init.h,
            ..Frame::default()
        };
        let m = st.measure(&f)?;
        last = m.unwrap_or(last);
        st.undo(&mut f, last)?;
        *data = f.data;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(frames: u64, duration_s: f64) -> crate::video::VideoInfo {
        crate::video::VideoInfo {
            width: 3840,
            height: 2160,
            frames_header: Some(frames),
            duration_s: Some(duration_s),
            codec: "h264".into(),
            luma_plane: true,
        }
    }

    #[test]
    fn a_large_working_side_thins_the_look_to_its_byte_budget() {
        // The default side: a 640 x 640 look of 300 frames (123 MB) is kept whole.
        assert_eq!(look_stride(&info(6000, 50.0), 640 * 640), 1);
        // 4K at full size, 60 frames/s: 150 frames of 8.3 MB; 160 MiB hold 20, fewer
        // than the 25 of one every tenth of a second, so 25 are kept: every 6th frame.
        let k4 = 3840 * 2160;
        assert_eq!(look_stride(&info(3000, 50.0), k4), 6);
        assert!((150usize).div_ceil(6) * k4 <= 2 * LOOK_MAX_BYTES);
        // Small frames at a high rate are never thinned below one a frame.
        assert_eq!(look_stride(&info(24_000, 100.0), 320 * 240), 1);
        // No header: the look's largest count (300 frames) is assumed.
        let none = crate::video::VideoInfo {
            frames_header: None,
            ..info(0, 1.0)
        };
        assert_eq!(look_stride(&none, k4), 12);
    }
}
