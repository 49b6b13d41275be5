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
    CONVERGED_PX, EST_SIDE, EXPLAINS, EXPLAIN_PX, ITERATIONS, LEVEL_SPREAD, MAX_GAIN, MAX_POINTS,
    MAX_RESIDUAL, MAX_SHIFT, MAX_TURN_DEG, MEASURE_PX, MIN_GRADIENT, MIN_INFO, RESTART, SMOOTH_PX,
    TUKEY_LEVELS,
};
use crate::video::Frame;
use anyhow::Result;
use opencv::core::{self, Mat, Scalar, Size};
use opencv::imgproc;
use opencv::prelude::*;

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
    fn new(img: &Mat, shrink: f64) -> Result<Self> {
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
        // The strongest gradients, when there are many.
        if points.len() > MAX_POINTS {
            let g2 = |p: &Point| p.jac[0] * p.jac[0] + p.jac[1] * p.jac[1];
            points.select_nth_unstable_by(MAX_POINTS, |a, b| g2(b).total_cmp(&g2(a)));
            points.truncate(MAX_POINTS);
        }
        Ok(Self {
            w,
            h,
            shrink,
            points,
        })
    }
}

/// The first frame's scales and the scratch the measurement reuses.
pub(super) struct Steady {
    size: (usize, usize),
    /// Frame px per px of the measuring scale.
    shrink: f64,
    levels: [Level; 2],
    small: Mat,
    smooth: Mat,
    coarse: Mat,
    warped: Mat,
    /// The last measured motion, where the next frame's measurement starts.
    recent: Motion,
    /// Tukey's loss of the last measured frame, aligned.
    loss: f64,
}

impl Steady {
    /// The first frame as the reference; later frames are measured against it.
    pub(super) fn new(first: &Frame) -> Result<Self> {
        let (w, h) = (first.width, first.height);
        let shrink = (w.max(h) as f64 / EST_SIDE).max(1.0);
        let mut small = Mat::default();
        let mut smooth = Mat::default();
        let mut coarse = Mat::default();
        prepare(first, shrink, &mut small, &mut smooth, &mut coarse)?;
        let levels = [
            Level::new(&coarse, 2.0 * shrink)?,
            Level::new(&smooth, shrink)?,
        ];
        Ok(Self {
            size: (w, h),
            shrink,
            levels,
            small,
            smooth,
            coarse,
            warped: Mat::default(),
            recent: Motion::default(),
            loss: f64::INFINITY,
        })
    }

    /// The motion of `f` against the first frame, or none when the frame cannot be
    /// aligned onto it (a plain wall has nothing to align; a frame that differs
    /// throughout, a flash or a cut, is not the same scene).
    pub(super) fn measure(&mut self, f: &Frame) -> Result<Option<Motion>> {
        if (f.width, f.height) != self.size {
            return Ok(None);
        }
        prepare(
            f,
            self.shrink,
            &mut self.small,
            &mut self.smooth,
            &mut self.coarse,
        )?;
        // From the previous frame's motion; when that leaves more pixels off than the
        // previous frame's did (by `RESTART`), from none too, and the one that leaves
        // fewer off is kept: an alignment that went astray (pulled along by the ball
        // over a few frames) is not followed on from frame to frame.
        let (mut m, mut residual, mut loss) = self.align_from(self.recent)?;
        if self.recent != Motion::default() && (loss.is_nan() || loss > RESTART * self.loss) {
            let (m0, r0, l0) = self.align_from(Motion::default())?;
            if l0 < loss {
                (m, residual, loss) = (m0, r0, l0);
            }
        }
        let Some(m) = m else {
            return Ok(None);
        };
        if !self.plausible(m, residual) {
            return Ok(None);
        }
        self.recent = m;
        self.loss = loss;
        Ok(Some(m))
    }

    /// The alignment of the prepared frame from motion `start`: the motion (none when
    /// the scene cannot fix it), the weighted RMS difference and Tukey's loss.
    fn align_from(&mut self, start: Motion) -> Result<(Option<Motion>, f64, f64)> {
        let mut m = start;
        let (mut residual, mut loss) = (f64::INFINITY, f64::INFINITY);
        for (k, level) in self.levels.iter().enumerate() {
            let img = if k == 0 { &self.coarse } else { &self.smooth };
            for _ in 0..ITERATIONS {
                let (step, r, l) = align_step(level, img, m, MEASURE_PX)?;
                residual = r;
                loss = l;
                let Some(step) = step else {
                    return Ok((None, residual, loss));
                };
                m.dx += step.dx;
                m.dy += step.dy;
                m.rot_rad += step.rot_rad;
                let at_level = Motion {
                    dx: step.dx / level.shrink,
                    dy: step.dy / level.shrink,
                    ..step
                };
                if at_level.reach(f64::from(level.w), f64::from(level.h)) < CONVERGED_PX {
                    break;
                }
            }
        }
        Ok((Some(m), residual, loss))
    }

    /// Whether the motion last measured explains the frame better than none: the pixels
    /// that differ from the first frame (Tukey's loss) fewer by [`EXPLAINS`]. A motion
    /// that does not is the moving wire's or the ball's pull on a plain scene, not the
    /// camera's.
    pub(super) fn explains(&mut self) -> Result<bool> {
        let (moved, still) = self.losses()?;
        Ok(moved < EXPLAINS * still)
    }

    /// The loss of the frame last measured at its motion and at none.
    fn losses(&mut self) -> Result<(f64, f64)> {
        let (level, img) = (&self.levels[1], &self.smooth);
        let (_, _, moved) = align_step(level, img, self.recent, EXPLAIN_PX)?;
        let (_, _, still) = align_step(level, img, Motion::default(), EXPLAIN_PX)?;
        if std::env::var_os("ROLLFRIC_DEBUG").is_some() {
            eprintln!(
                "steady: {:?}: the frame's loss {moved:.3} aligned, {still:.3} not ({:.2})",
                self.recent,
                moved / still
            );
        }
        Ok((moved, still))
    }

    /// The motion of `f` measured from no motion (for frames far apart, as the first
    /// look's glances are: the previous one's motion is no guide).
    pub(super) fn glance(&mut self, f: &Frame) -> Result<Option<Motion>> {
        self.recent = Motion::default();
        self.loss = f64::INFINITY;
        self.measure(f)
    }

    /// Whether a measured motion can be the camera's (see [`MAX_SHIFT`]) and aligns the
    /// frame well enough ([`MAX_RESIDUAL`]).
    fn plausible(&self, m: Motion, residual: f64) -> bool {
        let side = self.size.0.max(self.size.1) as f64;
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

/// `f` shrunk `shrink` times (block means) as floats at a common level and contrast,
/// smoothed, into `smooth`, and that shrunk twice more into `coarse`.
fn prepare(
    f: &Frame,
    shrink: f64,
    small: &mut Mat,
    smooth: &mut Mat,
    coarse: &mut Mat,
) -> Result<()> {
    let m = Mat::new_rows_cols_with_data(f.height as i32, f.width as i32, &f.data)?;
    let (sw, sh) = (
        ((f.width as f64 / shrink).round() as i32).max(1),
        ((f.height as f64 / shrink).round() as i32).max(1),
    );
    let size = Size::new(sw, sh);
    let mut shrunk = Mat::default();
    if size.width < f.width as i32 {
        imgproc::resize(&m, &mut shrunk, size, 0.0, 0.0, imgproc::INTER_AREA)?;
    } else {
        shrunk = m.try_clone()?;
    }
    // At a common level and contrast (the lights drift, a camera's exposure follows the
    // scene): the median grey brought to 128 and the quartiles' spread to
    // `LEVEL_SPREAD`, which a moving wire, ball or rod hardly moves.
    let mut hist = [0usize; 256];
    let bytes = shrunk.data_bytes()?;
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
    shrunk.convert_to(small, core::CV_32F, gain, 128.0 - gain * median)?;
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

/// One Gauss-Newton step of the alignment at `level`: the frame `img` (at the level's
/// scale) read through motion `m` at the first frame's informative pixels, their
/// difference from the first frame, and the change of `m` that best removes it (none
/// when the scene holds too little to fix it); with the weighted RMS difference, grey
/// levels, and Tukey's loss per pixel.
fn align_step(
    level: &Level,
    img: &Mat,
    m: Motion,
    tolerance_px: f32,
) -> Result<(Option<Motion>, f64, f64)> {
    let (c, s) = (m.rot_rad.cos() as f32, m.rot_rad.sin() as f32);
    let (cx, cy) = (0.5 * (level.w as f32 - 1.0), 0.5 * (level.h as f32 - 1.0));
    let (tx, ty) = ((m.dx / level.shrink) as f32, (m.dy / level.shrink) as f32);
    let cur = img.data_typed::<f32>()?;
    let wu = level.w as usize;
    let (xmax, ymax) = (level.w as f32 - 1.001, level.h as f32 - 1.001);
    let mut hm = [[0.0f64; 3]; 3];
    let mut g = [0.0f64; 3];
    let (mut sum_w, mut sum_we2) = (0.0f64, 0.0f64);
    // Tukey's loss, summed, and the pixels it is summed over.
    let (mut loss, mut count) = (0.0f64, 0.0f64);
    for p in &level.points {
        // Where the frame shows the first frame's pixel p: c + R (p - c) + t.
        let (ux, uy) = (p.x - cx, p.y - cy);
        let qx = cx + c * ux - s * uy + tx;
        let qy = cy + s * ux + c * uy + ty;
        if !(qx >= 0.0 && qy >= 0.0 && qx < xmax && qy < ymax) {
            continue;
        }
        let (x0, y0) = (qx as usize, qy as usize);
        let (fx, fy) = (qx - x0 as f32, qy - y0 as f32);
        let i = y0 * wu + x0;
        let top = cur[i] + fx * (cur[i + 1] - cur[i]);
        let bottom = cur[i + wu] + fx * (cur[i + wu + 1] - cur[i + wu]);
        let e = top + fy * (bottom - top) - p.grey;
        // Tukey's biweight: a pixel far off weighs nothing.
        let u = e / (TUKEY_LEVELS + tolerance_px * p.gradient);
        // `v = 1 - u^2`: the weight is `v^2`, the loss `1 - v^3` (a power function
        // here was a twentieth of a still clip's whole detection).
        let v = if u.abs() < 1.0 { 1.0 - u * u } else { 0.0 };
        let w = v * v;
        let kept = v * w;
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
        sum_w += w;
        sum_we2 += w * e * e;
        loss += 1.0 - f64::from(kept);
        count += 1.0;
    }
    if count < 1.0 {
        return Ok((None, f64::INFINITY, f64::INFINITY));
    }
    let residual = (sum_we2 / sum_w.max(1.0)).sqrt();
    // In units where a turn counts as the shift it gives at the frame's half side, per
    // pixel of the frame (the informative ones weighed, the plain ones holding none):
    // the information the scene holds on each direction of motion (grey levels squared
    // per px squared).
    let r = 0.5 * f64::from(level.w.max(level.h));
    let n = f64::from(level.w * level.h) * (sum_w / count).max(1e-3);
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
    if fixed == 0 {
        return Ok((None, residual, loss / count.max(1.0)));
    }
    let d = nalgebra::Vector3::new(d[0], d[1], d[2] / r);
    Ok((
        Some(Motion {
            dx: d[0] * level.shrink,
            dy: d[1] * level.shrink,
            rot_rad: d[2],
        }),
        residual,
        loss / count.max(1.0),
    ))
}

/// The `size` part of `f` at `origin` (frame px), as the first frame would show it
/// under motion `m`, into `out` (8-bit, `size`).
pub(super) fn warp_into(
    f: &Frame,
    m: Motion,
    origin: (usize, usize),
    size: (usize, usize),
    out: &mut Mat,
) -> Result<()> {
    let src = Mat::new_rows_cols_with_data(f.height as i32, f.width as i32, &f.data)?;
    // Output pixel q (of the part) is the first frame's p = q + origin, seen in `f` at
    // c + R (p - c) + t = R q + (R origin + c - R c + t).
    let (c, s) = (m.rot_rad.cos(), m.rot_rad.sin());
    let (cx, cy) = (0.5 * (f.width as f64 - 1.0), 0.5 * (f.height as f64 - 1.0));
    let (ox, oy) = (origin.0 as f64, origin.1 as f64);
    let bx = c * (ox - cx) - s * (oy - cy) + cx + m.dx;
    let by = s * (ox - cx) + c * (oy - cy) + cy + m.dy;
    let a = Mat::from_slice_2d(&[[c, -s, bx], [s, c, by]])?;
    imgproc::warp_affine(
        &src,
        out,
        &a,
        Size::new(size.0 as i32, size.1 as i32),
        imgproc::INTER_LINEAR | imgproc::WARP_INVERSE_MAP,
        core::BORDER_REPLICATE,
        Scalar::default(),
    )?;
    Ok(())
}

/// The bytes of an 8-bit picture.
pub(super) fn bytes(m: &Mat) -> Result<&[u8]> {
    Ok(m.data_bytes()?)
}

mod follow;
#[cfg(test)]
mod tests;

pub use follow::CameraMotion;
pub(super) use follow::{Followed, Late};
