//! The alignment's arithmetic: a frame prepared for it, its steps at one scale (the
//! light refitted at each, see `light.rs`), its reading through a motion, and the noise
//! left once aligned.

use super::light::{Light, Sums};
use super::{Level, Motion, Point};
use crate::detect::tuning::{
    AHEAD_AITKEN, AHEAD_COS, AHEAD_MAX, AHEAD_RATIO, CONVERGED_PX, EXPLAIN_PX, ITERATIONS,
    LEVEL_SPREAD, MAX_GAIN, MEASURE_PX, MIN_INFO, SMOOTH_PX, TUKEY_LEVELS,
};
use crate::video::Frame;
use anyhow::Result;
use opencv::core::{self, Mat, Size};
use opencv::imgproc;
use opencv::prelude::*;

/// `f` shrunk `shrink` times (block means, bilinear past the factor's whole part) as
/// floats, smoothed, into `smooth`, and that shrunk twice more into `coarse`; at the
/// first frame's level and contrast `norm` (a gain and an offset), which the first frame
/// sets. Each frame's own light is fitted in the alignment ([`Light`]): a frame's own
/// level and contrast would move with a person walking through it.
pub(super) fn prepare(
    f: &Frame,
    shrink: f64,
    norm: &mut Option<(f64, f64)>,
    small: &mut Mat,
    smooth: &mut Mat,
    coarse: &mut Mat,
) -> Result<()> {
    let m = Mat::new_rows_cols_with_data(f.height as i32, f.width as i32, &f.data)?;
    let (sw, sh) = (
        ((f.width as f64 / shrink).round() as i32).max(1),
        ((f.height as f64 / shrink).round() as i32).max(1),
    );
    // Block means by the whole part of the factor, then bilinear to the size: OpenCV's
    // block means at a factor that is not whole (2.67 for a 1280x720 frame) took a fifth
    // of a moving camera's whole detection.
    // The part a whole factor divides is centred (up to k - 1 rows and columns left
    // out, half on each side), so the level's centre stays the frame's within half a
    // pixel; a side shorter than the factor is not cut.
    let k = (shrink.floor() as i32)
        .min(f.width as i32)
        .min(f.height as i32)
        .max(1);
    let means = if k > 1 {
        let (bw, bh) = (f.width as i32 / k, f.height as i32 / k);
        let (x0, y0) = (
            (f.width as i32 - bw * k) / 2,
            (f.height as i32 - bh * k) / 2,
        );
        let part = Mat::roi(&m, core::Rect::new(x0, y0, bw * k, bh * k))?;
        Some(resized(&part, Size::new(bw, bh), imgproc::INTER_AREA)?)
    } else {
        None
    };
    // Under twice, bilinear as well: it reads every pixel at a factor under 2, and the
    // smoothing below follows (OpenCV's area means at 1.33, a 640x480 frame's factor,
    // took a fifth of a hand-held twin's whole detection); the frame copied only when it
    // is small enough already.
    let size = Size::new(sw, sh);
    let shrunk = match means {
        Some(b) if (b.cols(), b.rows()) == (sw, sh) => b,
        Some(b) => resized(&b, size, imgproc::INTER_LINEAR)?,
        None if (f.width as i32, f.height as i32) == (sw, sh) => m.try_clone()?,
        None => resized(&m, size, imgproc::INTER_LINEAR)?,
    };
    // The first frame's median grey brought to 128 and its quartiles' spread to
    // `LEVEL_SPREAD` (a plain wall's faint shading made as telling as a textured scene).
    let (gain, offset) = match *norm {
        Some(n) => n,
        None => *norm.insert(spread_of(&shrunk)?),
    };
    shrunk.convert_to(small, core::CV_32F, gain, offset)?;
    imgproc::gaussian_blur(
        &*small,
        smooth,
        Size::new(0, 0),
        SMOOTH_PX,
        SMOOTH_PX,
        core::BORDER_REPLICATE,
    )?;
    imgproc::resize(
        &*smooth,
        coarse,
        Size::new((sw / 2).max(1), (sh / 2).max(1)),
        0.0,
        0.0,
        imgproc::INTER_AREA,
    )?;
    Ok(())
}

/// `src` resized to `size` by interpolation `how`.
fn resized(src: &impl core::ToInputArray, size: Size, how: i32) -> Result<Mat> {
    let mut out = Mat::default();
    imgproc::resize(src, &mut out, size, 0.0, 0.0, how)?;
    Ok(out)
}

/// The gain and offset that bring `m`'s median grey to 128 and its quartiles' spread to
/// [`LEVEL_SPREAD`] (by a gain within [`MAX_GAIN`]).
fn spread_of(m: &Mat) -> Result<(f64, f64)> {
    let mut hist = [0usize; 256];
    let bytes = m.data_bytes()?;
    for &v in bytes {
        hist[usize::from(v)] += 1;
    }
    let quantile = |q: f64| {
        let mut below = 0usize;
        for (v, &n) in hist.iter().enumerate() {
            below += n;
            if below as f64 >= q * bytes.len() as f64 {
                return v as f64;
            }
        }
        255.0
    };
    let median = quantile(0.5);
    let spread = quantile(0.75) - quantile(0.25);
    let gain = (LEVEL_SPREAD / spread.max(1.0)).clamp(1.0 / MAX_GAIN, MAX_GAIN);
    Ok((gain, 128.0 - gain * median))
}

/// One Gauss-Newton step of the alignment at `level`: the frame `img` (at the level's
/// scale) read through motion `m` at the first frame's informative pixels, their
/// difference from the first frame, and the change of `m` that best removes it (none
/// when the scene holds too little to fix it); with the weighted RMS difference, grey
/// levels, Tukey's loss per pixel, and whether the turn was held. A direction the scene
/// does not fix is taken back to no motion; as `hold` says, the turn may instead be taken
/// back to none and the shift fitted with it held ([`shift_with_turn_held`]).
pub(super) fn align_step(
    level: &Level,
    img: &Mat,
    m: Motion,
    tukey: Tukey,
    light: &mut Light,
    hold: Hold,
    scratch: &mut Scratch,
) -> Result<Step> {
    let at = Reader::new(level, img, m)?;
    // Each pixel read once, with its difference from the first frame; then Tukey's
    // weights of them all in one pass (the division in lanes); then the sums in two
    // passes of fewer running totals each (the eighteen of one pass spilled out of the
    // registers), each total summed in the pixels' order as one pass would.
    let r = scratch;
    r.room(level.points.len());
    let mut n = 0;
    for (i, p) in level.points.iter().enumerate() {
        let Some(grey) = at.grey(p) else {
            continue;
        };
        r.i[n] = i as u32;
        r.grey[n] = grey;
        r.e[n] = light.gain * grey + light.offset - p.grey;
        r.w[n] = tukey.times * (TUKEY_LEVELS + tukey.px * p.gradient);
        n += 1;
    }
    let (i, grey, e) = (&r.i[..n], &r.grey[..n], &r.e[..n]);
    let (w, kept) = (&mut r.w[..n], &mut r.kept[..n]);
    // Tukey's biweight: a pixel far off weighs nothing. The weight is `v^2`, the loss
    // `1 - v^3`.
    for ((w, kept), &e) in w.iter_mut().zip(kept.iter_mut()).zip(e) {
        let v = biweight(e, *w);
        *w = v * v;
        *kept = v * *w;
    }
    let (w, kept) = (&*w, &*kept);
    let mut hm = [[0.0f64; 3]; 3];
    let mut g = [0.0f64; 3];
    for ((&i, &w), &e) in i.iter().zip(w).zip(e) {
        let p = &level.points[i as usize];
        let (j0, j1, j2) = (
            f64::from(p.jac[0]),
            f64::from(p.jac[1]),
            f64::from(p.jac[2]),
        );
        let (w, e) = (f64::from(w), f64::from(e));
        hm[0][0] += w * j0 * j0;
        hm[0][1] += w * j0 * j1;
        hm[0][2] += w * j0 * j2;
        hm[1][1] += w * j1 * j1;
        hm[1][2] += w * j1 * j2;
        hm[2][2] += w * j2 * j2;
        g[0] += w * j0 * e;
        g[1] += w * j1 * e;
        g[2] += w * j2 * e;
    }
    // The weighted sums that fit the light anew (see `Light`).
    let mut sums = Sums::default();
    let (mut sum_w, mut sum_we2) = (0.0f64, 0.0f64);
    // Tukey's loss, summed, and the pixels it is summed over.
    let (mut loss, mut count) = (0.0f64, 0.0f64);
    for ((((&i, &w), &e), &grey), &kept) in i.iter().zip(w).zip(e).zip(grey).zip(kept) {
        let p = &level.points[i as usize];
        let (w, e) = (f64::from(w), f64::from(e));
        let (gi, gr) = (f64::from(grey), f64::from(p.grey));
        sums.add(w, gi, gr);
        sum_w += w;
        sum_we2 += w * e * e;
        loss += 1.0 - f64::from(kept);
        count += 1.0;
    }
    if count < 1.0 {
        return Ok(Step {
            motion: None,
            residual: f64::INFINITY,
            loss: f64::INFINITY,
            held: false,
            turn_fixed: false,
        });
    }
    light.refit(&sums);
    let residual = (sum_we2 / sum_w.max(1.0)).sqrt();
    // In units where a turn counts as the shift it gives at the frame's half side, per
    // pixel of the frame (the informative ones weighed, the plain ones holding none):
    // the information the scene holds on each direction of motion (grey levels squared
    // per px squared).
    let r = 0.5 * f64::from(level.w.max(level.h));
    let n = f64::from(level.w * level.h) / level.each * (sum_w / count).max(1e-3);
    let hn = nalgebra::Matrix3::new(
        hm[0][0],
        hm[0][1],
        hm[0][2] / r,
        hm[0][1],
        hm[1][1],
        hm[1][2] / r,
        hm[0][2] / r,
        hm[1][2] / r,
        hm[2][2] / (r * r),
    ) / n;
    let gn = nalgebra::Vector3::new(g[0], g[1], g[2] / r) / n;
    let now = nalgebra::Vector3::new(m.dx / level.shrink, m.dy / level.shrink, m.rot_rad * r);
    let eig = hn.symmetric_eigen();
    // Along a direction the scene fixes, the Gauss-Newton step; along one it does not (a
    // plain wall, a single straight edge along itself), back to no motion: the frame is
    // not moved on a guess.
    let mut d = nalgebra::Vector3::zeros();
    let mut fixed = 0;
    for k in 0..3 {
        let v = eig.eigenvectors.column(k);
        let along = if eig.eigenvalues[k] >= MIN_INFO {
            fixed += 1;
            -v.dot(&gn) / eig.eigenvalues[k]
        } else {
            -v.dot(&now)
        };
        d += v * along;
    }
    // A turn the scene fixes poorly while it fixes the shift: the direction it does not
    // fix mixes the turn with a shift (the texture lies to one side of the centre), and
    // taking it back to no motion takes part of the shift with it into a turn.
    let mut held = false;
    if hold.is_kept() || (hold != Hold::No && fixed == 2) {
        let turn = if hold.as_is() { 0.0 } else { -now[2] };
        if let Some(step) = shift_with_turn_held(&hn, &gn, &now, turn, hold.is_kept()) {
            d = step;
            held = true;
        }
    }
    if fixed == 0 {
        return Ok(Step {
            motion: None,
            residual,
            loss: loss / count.max(1.0),
            held: false,
            turn_fixed: false,
        });
    }
    let d = nalgebra::Vector3::new(d[0], d[1], d[2] / r);
    Ok(Step {
        motion: Some(Motion {
            dx: d[0] * level.shrink,
            dy: d[1] * level.shrink,
            rot_rad: d[2],
        }),
        residual,
        loss: loss / count.max(1.0),
        held,
        turn_fixed: fixed == 3 && !held,
    })
}

/// The alignment at `level` (of the prepared frame `img`) from motion `start`: see
/// [`super::Steady::at_level`]; Tukey's scale widened `widen` times.
pub(super) fn iterate(
    level: &Level,
    img: &Mat,
    start: Motion,
    mut hold: Hold,
    light: &mut Light,
    widen: f32,
    scratch: &mut Scratch,
) -> Result<Step> {
    let mut m = start;
    let mut last: Option<Step> = None;
    // A frame steadied goes further along a run of steps that keep their direction
    // (see [`AHEAD_COS`]); a glance steps as it is.
    let extrapolate = hold != Hold::No;
    let (mut before, mut ahead) = (None, 0.0);
    // Where a step went further: the motion it reached itself, the loss where it began.
    let mut went: Option<(Motion, f64)> = None;
    let (w, h) = (f64::from(level.w), f64::from(level.h));
    for _ in 0..ITERATIONS {
        let step = align_step(level, img, m, Tukey::measuring(widen), light, hold, scratch)?;
        let Some(d) = step.motion else {
            return Ok(step);
        };
        // Going further is taken back where it left more pixels off (0.0196, not 0.0249 deg).
        if let Some((back, loss)) = went.take() {
            if step.loss > loss {
                m = back;
                last.iter_mut().for_each(|l| l.motion = Some(back));
                before = None;
                ahead = 0.0;
                continue;
            }
        }
        if step.held {
            hold = hold.kept();
        }
        // The step in the level's px, its turn as the shift it gives at the corners.
        let at_level = Motion {
            dx: d.dx / level.shrink,
            dy: d.dy / level.shrink,
            ..d
        };
        let v = nalgebra::Vector3::new(at_level.dx, at_level.dy, d.rot_rad * 0.5 * w.hypot(h));
        ahead = match before {
            Some(u) if extrapolate => further(&v, &u, ahead),
            _ => 0.0,
        };
        before = Some(v);
        if ahead > 0.0 {
            went = Some((
                Motion {
                    dx: m.dx + d.dx,
                    dy: m.dy + d.dy,
                    rot_rad: m.rot_rad + d.rot_rad,
                },
                step.loss,
            ));
        }
        m.dx += d.dx * (1.0 + ahead);
        m.dy += d.dy * (1.0 + ahead);
        m.rot_rad += d.rot_rad * (1.0 + ahead);
        let done = at_level.reach(w, h) < CONVERGED_PX;
        last = Some(Step {
            motion: Some(m),
            ..step
        });
        if done {
            break;
        }
    }
    Ok(last.expect("at least one iteration"))
}

/// How much further than step `v` (px of the level, the turn as the shift it gives at
/// the corners) to go after step `u` went `ahead` times further than itself: where the
/// steps keep their direction ([`AHEAD_COS`]) and shrink, the rest of their geometric
/// run (Aitken's extrapolation, at most [`AHEAD_AITKEN`] times); where they do not
/// shrink, twice as far as the last went (at most [`AHEAD_MAX`] times); where they
/// turn, none.
pub(super) fn further(v: &nalgebra::Vector3<f64>, u: &nalgebra::Vector3<f64>, ahead: f64) -> f64 {
    let (nv, nu) = (v.norm(), u.norm());
    // A step after none (`nu` 0) does not keep its direction.
    if v.dot(u) <= AHEAD_COS * nv * nu {
        return 0.0;
    }
    let ratio = nv / nu;
    if ratio < AHEAD_RATIO {
        (ratio / (1.0 - ratio)).min(AHEAD_AITKEN)
    } else {
        (2.0 * ahead).clamp(1.0, AHEAD_MAX)
    }
}

/// Tukey's scale of a step of the alignment ([`align_step`]): `times` ([`TUKEY_LEVELS`]
/// widened by `px` times the pixel's gradient).
#[derive(Clone, Copy, Debug)]
pub(super) struct Tukey {
    pub(super) px: f32,
    pub(super) times: f32,
}

impl Tukey {
    /// The measurement's ([`MEASURE_PX`]), widened `times` for a noisy scene.
    pub(super) fn measuring(times: f32) -> Self {
        Self {
            px: MEASURE_PX,
            times,
        }
    }

    /// Whether the camera moved ([`EXPLAIN_PX`]).
    pub(super) fn explaining() -> Self {
        Self {
            px: EXPLAIN_PX,
            times: 1.0,
        }
    }
}

/// The pixels of a level a step of the alignment read (see [`align_step`]), kept
/// between steps so that their room is not asked for again: each one's index among the
/// level's points, its grey in the frame, its difference from the first frame, Tukey's
/// weight (its scale until weighed), and what Tukey's loss keeps of it.
#[derive(Default)]
pub(super) struct Scratch {
    i: Vec<u32>,
    grey: Vec<f32>,
    e: Vec<f32>,
    w: Vec<f32>,
    kept: Vec<f32>,
}

impl Scratch {
    /// Room for `n` pixels in each.
    fn room(&mut self, n: usize) {
        if self.i.len() < n {
            self.i.resize(n, 0);
            self.grey.resize(n, 0.0);
            self.e.resize(n, 0.0);
            self.w.resize(n, 0.0);
            self.kept.resize(n, 0.0);
        }
    }
}

/// What a step of the alignment ([`align_step`]) found.
pub(super) struct Step {
    /// The change of the motion; none when the scene holds too little to fix it.
    pub(super) motion: Option<Motion>,
    /// The weighted RMS difference, grey levels.
    pub(super) residual: f64,
    /// Tukey's loss per pixel.
    pub(super) loss: f64,
    /// Whether the turn was held (at none, or as it was: see [`Hold`]).
    pub(super) held: bool,
    /// Whether the scene fixed every direction of motion, the turn too.
    pub(super) turn_fixed: bool,
}

/// The Gauss-Newton step (information `hn`, gradient `gn`, in the scaled units of
/// [`align_step`]) with the turn taken back to none from `now` and the shift fitted
/// given that turn; when the scene does not fix both directions of shift
/// ([`MIN_INFO`]), none, or with `kept` (the turn held at an earlier step) the shift
/// fitted along the direction the scene fixes and taken back to none along the other.
fn shift_with_turn_held(
    hn: &nalgebra::Matrix3<f64>,
    gn: &nalgebra::Vector3<f64>,
    now: &nalgebra::Vector3<f64>,
    turn: f64,
    kept: bool,
) -> Option<nalgebra::Vector3<f64>> {
    let hs = hn.fixed_view::<2, 2>(0, 0).into_owned();
    let rhs = -(gn.fixed_rows::<2>(0) + hn.fixed_view::<2, 1>(0, 2) * turn);
    let shift = if hs.symmetric_eigenvalues().min() >= MIN_INFO {
        hs.try_inverse()? * rhs
    } else if kept {
        let eig = hs.symmetric_eigen();
        let mut shift = nalgebra::Vector2::zeros();
        for k in 0..2 {
            let v = eig.eigenvectors.column(k);
            shift += v * if eig.eigenvalues[k] >= MIN_INFO {
                v.dot(&rhs) / eig.eigenvalues[k]
            } else {
                -v.dot(&now.fixed_rows::<2>(0))
            };
        }
        shift
    } else {
        return None;
    };
    Some(nalgebra::Vector3::new(shift[0], shift[1], turn))
}

/// Whether a step of the alignment may hold the turn at none (see [`align_step`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Hold {
    /// Never: every direction the scene fixes is fitted (a glance).
    No,
    /// Where the scene fixes the shift but not the turn (a frame steadied).
    WhereUnfixed,
    /// Always: an earlier step at the same scale held it. A scene that fixes the shift
    /// barely (its weaker direction near [`MIN_INFO`]) held it at one step and not at the
    /// next, and the steps swung the turn in and out to the last iteration (a hand-held
    /// twin: 0.44 deg of turn and 0.8 px of shift, back and forth; the measuring scale
    /// ran all its iterations in 140 of 320 alignments sampled), the motion kept
    /// depending on which step was the last.
    Kept,
    /// Where the scene fixes the shift but not the turn, the turn kept as it is (the
    /// coarser scale fixed it), not taken back to none.
    AsIs,
    /// Always, as it is.
    KeptAsIs,
}

impl Hold {
    /// The hold of the steps after one that held the turn.
    pub(super) fn kept(self) -> Self {
        match self {
            Hold::AsIs | Hold::KeptAsIs => Hold::KeptAsIs,
            _ => Hold::Kept,
        }
    }

    fn is_kept(self) -> bool {
        matches!(self, Hold::Kept | Hold::KeptAsIs)
    }

    /// Whether the turn is held as it is, not taken back to none.
    pub(super) fn as_is(self) -> bool {
        matches!(self, Hold::AsIs | Hold::KeptAsIs)
    }
}

/// Tukey's biweight of a difference `e` at `scale`: `v = 1 - (e / scale)^2` within the
/// scale, 0 beyond (the weight is `v^2`, the loss `1 - v^3`; a power function here was a
/// twentieth of a still clip's whole detection).
#[inline]
pub(super) fn biweight(e: f32, scale: f32) -> f32 {
    let u = e / scale;
    if u.abs() < 1.0 {
        1.0 - u * u
    } else {
        0.0
    }
}

/// Reads the frame (at a level's scale) where it shows the first frame's pixels under a
/// motion: the first frame's `p` is seen at `c + R (p - c) + t`.
pub(super) struct Reader<'a> {
    cur: &'a [f32],
    wu: usize,
    c: f32,
    s: f32,
    cx: f32,
    cy: f32,
    tx: f32,
    ty: f32,
    xmax: f32,
    ymax: f32,
}

impl<'a> Reader<'a> {
    pub(super) fn new(level: &Level, img: &'a Mat, m: Motion) -> Result<Self> {
        Ok(Self {
            cur: img.data_typed::<f32>()?,
            wu: level.w as usize,
            c: m.rot_rad.cos() as f32,
            s: m.rot_rad.sin() as f32,
            cx: 0.5 * (level.w as f32 - 1.0),
            cy: 0.5 * (level.h as f32 - 1.0),
            tx: (m.dx / level.shrink) as f32,
            ty: (m.dy / level.shrink) as f32,
            xmax: level.w as f32 - 1.001,
            ymax: level.h as f32 - 1.001,
        })
    }

    /// The frame's grey (bilinear) where it shows `p`, none outside it.
    #[inline(always)]
    pub(super) fn grey(&self, p: &Point) -> Option<f32> {
        let (ux, uy) = (p.x - self.cx, p.y - self.cy);
        let qx = self.cx + self.c * ux - self.s * uy + self.tx;
        let qy = self.cy + self.s * ux + self.c * uy + self.ty;
        if !(qx >= 0.0 && qy >= 0.0 && qx < self.xmax && qy < self.ymax) {
            return None;
        }
        let (x0, y0) = (qx as usize, qy as usize);
        let (fx, fy) = (qx - x0 as f32, qy - y0 as f32);
        let wu = self.wu;
        // The four neighbours through one slice (one bounds check, not four).
        let i = y0 * wu + x0;
        let q = self.cur.get(i..i + wu + 2)?;
        let top = q[0] + fx * (q[1] - q[0]);
        let bottom = q[wu] + fx * (q[wu + 1] - q[wu]);
        Some(top + fy * (bottom - top))
    }
}

/// The median of the first frame's pixels' differences from the frame through motion
/// `m` at `light`, each a share of its Tukey scale at [`MEASURE_PX`] (see `NOISE_SHARE`),
/// into `u`'s room.
pub(super) fn noise_share(
    level: &Level,
    img: &Mat,
    m: Motion,
    light: Light,
    u: &mut Vec<f32>,
) -> Result<f32> {
    let at = Reader::new(level, img, m)?;
    u.clear();
    u.extend(level.points.iter().filter_map(|p| {
        let g = at.grey(p)?;
        let e = light.gain * g + light.offset - p.grey;
        Some(e.abs() / (TUKEY_LEVELS + MEASURE_PX * p.gradient))
    }));
    if u.is_empty() {
        return Ok(0.0);
    }
    let k = u.len() / 2;
    Ok(*u.select_nth_unstable_by(k, f32::total_cmp).1)
}
