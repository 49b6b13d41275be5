//! The plan: the motion, the geometry and the spoiled frames (no pixels).

use super::look::Look;
use super::room::Walker;
use super::vfr::Vfr;
use super::TruthRow;
use crate::config::{Experiment, Synthetic};
use crate::lens::Lens;
use crate::plane::{self, Homography};
use crate::rng::Rng;
use crate::simulate;
use anyhow::{ensure, Context, Result};

/// Sub-times of the exposure averaged for motion blur.
pub(super) const SUBSAMPLES: usize = 7;
/// Exposure as a fraction of the frame interval.
pub(super) const EXPOSURE: f64 = 0.5;
/// Kept clear of spoiled frames at each end of the video, s.
const SPOIL_MARGIN_S: f64 = 2.0;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Spoil {
    None,
    /// Frame `k` of `n` of a hand passing.
    Hand {
        k: u8,
        n: u8,
        event: u16,
    },
    Flash,
    Duplicate,
    /// A person walking through covers the wire (`synthetic.room.walker_s`).
    Walker,
}

impl Spoil {
    fn tag(self) -> &'static str {
        match self {
            Spoil::None => "none",
            Spoil::Hand { .. } => "hand",
            Spoil::Flash => "flash",
            Spoil::Duplicate => "duplicate",
            Spoil::Walker => "walker",
        }
    }
}

/// Independent, decorrelated seeds for the render's random streams.
pub(super) fn stream(seed: u64, k: u64) -> u64 {
    Rng::new(seed ^ k.wrapping_mul(0xD1B5_4A32_D192_ED03)).next_u64()
}

pub(super) struct Plan {
    pub(super) s: Synthetic,
    pub(super) look: Look,
    /// Where things are in the scene as drawn, before any mirroring.
    pub(super) geo: Geometry,
    /// The wire's rest angle as the image shows it (mirrored if `s.mirror`), rad; with a
    /// tilted camera, the plate's (the truth's).
    pub(super) image_rest: f64,
    /// The tilted camera's view (`camera_tilt_deg`): the untilted view's pixels (where
    /// `geo` places things, the plate's own frame for the truth) to the image's.
    pub(super) view: Option<Homography>,
    pub(super) fps: f64,
    /// Each frame's own time, with `vfr_jitter`.
    pub(super) vfr: Option<Vfr>,
    /// The lens's distortion (`lens_k1`).
    pub(super) lens: Option<Lens>,
    /// A person walking through (`room.walker_s`).
    pub(super) walker: Option<Walker>,
    trajectory: crate::physics::ode::Trajectory,
    /// Every frame's truth, the dropped ones' too (see [`Plan::written_truth`]).
    pub(super) truth: Vec<TruthRow>,
    pub(super) spoils: Vec<Spoil>,
    /// The frames the recorder drops (`dropped_share`): rendered as nothing, written as a
    /// repeat that FFmpeg's `select` drops.
    pub(super) dropped: Vec<bool>,
}

impl Plan {
    pub(super) fn new(exp: &Experiment, duration_s: Option<f64>) -> Result<Self> {
        let s =
            exp.file.synthetic.clone().with_context(|| {
                format!("{}: no `synthetic:` block to render", exp.path.display())
            })?;
        if let Some(d) = duration_s {
            ensure!(
                d.is_finite() && d > 0.0,
                "duration {d} s: expected a positive number"
            );
        }
        let mut cam = simulate::camera_of(exp)?;
        cam.duration_s = duration_s.or(cam.duration_s);
        cam.noise_rad = 0.0;
        let rec = simulate::record(exp, &cam)?;
        let look = Look::of(s.style);
        let rest_deg = wrap_deg(s.rest_angle_deg + look.turn_deg);
        let theta_rest = rest_deg.to_radians();
        let geo = Geometry::new(
            s.width as usize,
            s.height as usize,
            theta_rest,
            s.psi0_deg.to_radians(),
            exp.pendulum.r / exp.pendulum.d,
            s.wire_width_px,
            s.pivot_frac,
        )?;
        let view = match s.camera_tilt_deg.filter(|&t| t > 0.0) {
            Some(t) => Some(tilted(&geo, &s, t)?),
            None => None,
        };
        // The image's own rest angle and sense of rotation: mirrored, `pi - theta`.
        let image_rest = if s.mirror {
            wrap_deg(180.0 - rest_deg).to_radians()
        } else {
            theta_rest
        };
        // Dropped frames leave gaps in the times, which the file carries as a variable
        // rate's (whole milliseconds).
        let dropping = s.dropped_share.is_some_and(|p| p > 0.0);
        let vfr = match s.vfr_jitter.filter(|&j| j > 0.0) {
            Some(j) => Some(Vfr::new(j, s.fps, s.seed)),
            None => dropping.then(|| Vfr::new(0.0, s.fps, s.seed)),
        };
        let times: Vec<f64> = match &vfr {
            Some(v) => (0..rec.series.t.len()).map(|k| v.ms(k) / 1000.0).collect(),
            None => rec.series.t.clone(),
        };
        let n = times.len();
        let mut spoils = if s.clean {
            vec![Spoil::None; n]
        } else {
            plan_spoils(
                s.spoiled_frames as usize,
                n,
                s.fps,
                &mut Rng::new(stream(s.seed, 2)),
            )
        };
        let lens = s
            .lens_k1
            .filter(|&k| k != 0.0)
            .map(|k| Lens::new(k, 0.0, geo.w as u32, geo.h as u32));
        let walker = s
            .room
            .and_then(|r| r.walker_s)
            .map(|t0| Walker::new(t0, geo.w, geo.h, s.seed));
        // The frames whose wire the walker covers (anywhere along it, at 5 % or more).
        if let Some(wk) = &walker {
            for (k, &t) in times.iter().enumerate() {
                let th = geo.theta_rest - rec.trajectory.state(t)[0];
                let covered = (0..=20).any(|j| {
                    let f = geo.d_px * j as f64 / 20.0;
                    let p = [geo.pivot[0] + f * th.cos(), geo.pivot[1] + f * th.sin()];
                    let q = view.map_or(p, |v| v.apply(p));
                    wk.alpha(q[0], q[1], t) >= 0.05
                });
                if covered && spoils[k] == Spoil::None {
                    spoils[k] = Spoil::Walker;
                }
            }
        }
        let dropped = match s.dropped_share.filter(|&p| p > 0.0) {
            Some(p) => plan_drops(p, &spoils, &mut Rng::new(stream(s.seed, 9))),
            None => vec![false; n],
        };
        let truth = times
            .iter()
            .zip(&spoils)
            .map(|(&t, sp)| {
                let psi = rec.trajectory.state(t)[0];
                TruthRow {
                    t_s: t,
                    angle_rad: if s.mirror {
                        image_rest + psi
                    } else {
                        theta_rest - psi
                    },
                    spoiled: sp.tag(),
                }
            })
            .collect();
        Ok(Self {
            fps: s.fps,
            s,
            look,
            geo,
            image_rest,
            view,
            vfr,
            lens,
            walker,
            trajectory: rec.trajectory,
            truth,
            spoils,
            dropped,
        })
    }

    /// The FFmpeg filters that give the written frames their times and drop the dropped
    /// ones (`None` at a constant rate with none dropped). `select` comes after `setpts`,
    /// so that both count every frame piped in (`N`, `n`).
    pub(super) fn filters(&self) -> Option<String> {
        let times = self.vfr.as_ref()?.filters();
        let gone: Vec<String> = (0..self.dropped.len())
            .filter(|&k| self.dropped[k])
            .map(|k| format!("eq(n\\,{k})"))
            .collect();
        Some(if gone.is_empty() {
            times
        } else {
            format!("{times},select=not({})", balanced_sum(&gone))
        })
    }

    /// The truth of the frames written (the dropped ones left out).
    pub(super) fn written_truth(&self) -> Vec<TruthRow> {
        self.truth
            .iter()
            .zip(&self.dropped)
            .filter(|(_, &d)| !d)
            .map(|(r, _)| r.clone())
            .collect()
    }

    /// Angle of the wire at time `t` in the scene as drawn (before any mirroring).
    pub(super) fn theta(&self, t: f64) -> f64 {
        self.geo.theta_rest - self.trajectory.state(t)[0]
    }

    /// The pivot as the image shows it (mirrored if `s.mirror`, through the tilted
    /// camera's view), px.
    pub(super) fn image_pivot(&self) -> [f64; 2] {
        let p = self.to_image(self.geo.pivot);
        if self.s.mirror {
            [(self.geo.w - 1) as f64 - p[0], p[1]]
        } else {
            p
        }
    }
}

impl Plan {
    /// A point of the untilted view in the image (before any mirroring): through the
    /// tilted camera's view and the lens.
    pub(super) fn to_image(&self, p: [f64; 2]) -> [f64; 2] {
        let q = self.view.map_or(p, |v| v.apply(p));
        self.lens.map_or(q, |l| l.distort(q))
    }

    /// Protractor marks a user could pick for `video.calibration`: the fulcrum, both
    /// ends of the base line and the outer ticks at 30, 60, 90, 120 and 150 degrees,
    /// each `(image px, plate mm)`, those at least 2 px inside the frame. Plate
    /// coordinates are the untilted view's axes (x right, y down, the truth's), from
    /// the fulcrum, with the protractor's radius taken as 60 mm; image points are
    /// rounded to 0.1 px, as a mark picked on a zoomed picture.
    pub(super) fn calibration_points(&self) -> Vec<([f64; 2], [f64; 2])> {
        let g = &self.geo;
        let rot = g.theta_rest - std::f64::consts::FRAC_PI_2;
        let mm = 60.0 / g.rp;
        let mut marks = vec![(0.0, 0.0), (0.0, g.rp), (180.0, g.rp)];
        marks.extend([30.0, 60.0, 90.0, 120.0, 150.0].map(|a| (a, 0.975 * g.rp)));
        marks
            .into_iter()
            .filter_map(|(a, r): (f64, f64)| {
                let a = a.to_radians() + rot;
                let off = [r * a.cos(), r * a.sin()];
                let q = self.to_image([g.pivot[0] + off[0], g.pivot[1] + off[1]]);
                let q = q.map(|v| (v * 10.0).round() / 10.0);
                let inside = q[0] >= 2.0
                    && q[1] >= 2.0
                    && q[0] <= g.w as f64 - 3.0
                    && q[1] <= g.h as f64 - 3.0;
                inside.then(|| (q, off.map(|v| (v * mm * 100.0).round() / 100.0)))
            })
            .collect()
    }
}

/// The tilted camera's view of `g` (`camera_tilt_deg` = `tilt`), zoomed out about the
/// frame's centre until the ball's swing lies 3 % inside the frame.
fn tilted(g: &Geometry, s: &Synthetic, tilt: f64) -> Result<Homography> {
    let (w, h) = (g.w as f64, g.h as f64);
    let f = s.camera_focal_px.unwrap_or(1.2 * w);
    let centre = [w / 2.0, h / 2.0];
    let view = plane::tilted_view(
        f,
        tilt.to_radians(),
        s.tilt_axis_deg.unwrap_or(0.0).to_radians(),
        centre,
        centre,
    );
    // The ball's outline over the swing.
    let amp = s.psi0_deg.to_radians() + 3f64.to_radians();
    let mut pts = Vec::new();
    for j in 0..=32 {
        let th = g.theta_rest - amp + 2.0 * amp * j as f64 / 32.0;
        let c = [
            g.pivot[0] + g.d_px * th.cos(),
            g.pivot[1] + g.d_px * th.sin(),
        ];
        for k in 0..16 {
            let a = std::f64::consts::TAU * k as f64 / 16.0;
            let r = 1.3 * g.ball_r;
            pts.push([c[0] + r * a.cos(), c[1] + r * a.sin()]);
        }
    }
    let horizon = || {
        anyhow::anyhow!(
            "`synthetic.camera_tilt_deg` = {tilt} with `synthetic.camera_focal_px` = {f}: the \
             frame reaches too near the plate's horizon (a longer focal length or less tilt)"
        )
    };
    // The swing in front of the camera, its depths within a factor 3 of each other.
    let (d_lo, d_hi) = pts.iter().fold((f64::MAX, f64::MIN), |(a, b), &p| {
        (a.min(view.w(p)), b.max(view.w(p)))
    });
    if !(d_lo > 0.0 && d_hi < 3.0 * d_lo) {
        return Err(horizon());
    }
    let mut zoom = 1.0f64;
    for p in pts {
        let q = view.apply(p);
        for (axis, size) in [w, h].into_iter().enumerate() {
            let (lo, hi, c) = (0.03 * size, 0.97 * size, centre[axis]);
            let d = q[axis] - c;
            if d > 0.0 {
                zoom = zoom.min((hi - c) / d);
            } else if d < 0.0 {
                zoom = zoom.min((lo - c) / d);
            }
        }
    }
    ensure!(
        zoom > 0.2,
        "`synthetic.camera_tilt_deg` = {tilt}: the tilted view cannot keep the ball's swing in the frame"
    );
    let shrink = Homography {
        m: nalgebra::Matrix3::new(
            zoom,
            0.0,
            (1.0 - zoom) * centre[0],
            0.0,
            zoom,
            (1.0 - zoom) * centre[1],
            0.0,
            0.0,
            1.0,
        ),
    };
    let out = shrink.after(&view);
    // The whole frame well on the near side of the plate's horizon: the back-mapped
    // corners' depths within a factor 3 of each other.
    let back = out
        .inverse()
        .context("`synthetic.camera_tilt_deg`: the tilted view is singular")?;
    let depths: Vec<f64> = [[0.0, 0.0], [w, 0.0], [0.0, h], [w, h]]
        .iter()
        .map(|&c| back.w(c) / back.w(centre))
        .collect();
    let (lo, hi) = depths
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &d| (a.min(d), b.max(d)));
    if !(lo > 0.0 && lo > hi / 3.0) {
        return Err(horizon());
    }
    Ok(out)
}

/// `deg` taken into (-180, 180] (returned as is when it already lies there).
pub(super) fn wrap_deg(deg: f64) -> f64 {
    if deg > -180.0 && deg <= 180.0 {
        return deg;
    }
    let r = deg.rem_euclid(360.0);
    if r > 180.0 {
        r - 360.0
    } else {
        r
    }
}

/// `n` spoiling events (hand, flash, duplicate, in turn) at pseudo-random frames, one
/// per equal slot of the video between margins of 2 s (less for short videos), away
/// from the slot's edges so that events stay apart. A hand covers 1 to 3 frames.
/// `terms` summed as a balanced tree of parenthesised halves: FFmpeg's expression parser
/// recurses once per `+` of a flat sum, and a long one (78 dropped frames) is refused.
fn balanced_sum(terms: &[String]) -> String {
    match terms {
        [] => "0".to_string(),
        [one] => one.clone(),
        _ => {
            let (a, b) = terms.split_at(terms.len() / 2);
            format!("({})+({})", balanced_sum(a), balanced_sum(b))
        }
    }
}

/// The frames dropped at a share `p`: each frame with that chance, but not the first or
/// the last, a spoiled one, or the one before a duplicated frame.
fn plan_drops(p: f64, spoils: &[Spoil], rng: &mut Rng) -> Vec<bool> {
    let n = spoils.len();
    (0..n)
        .map(|k| {
            let u = rng.uniform();
            k > 0
                && k + 1 < n
                && spoils[k] == Spoil::None
                && spoils[k + 1] != Spoil::Duplicate
                && u < p
        })
        .collect()
}

fn plan_spoils(n: usize, frames: usize, fps: f64, rng: &mut Rng) -> Vec<Spoil> {
    let mut out = vec![Spoil::None; frames];
    if n == 0 {
        return out;
    }
    let margin = ((SPOIL_MARGIN_S * fps).round() as usize)
        .min(frames / 5)
        .max(1);
    let usable = frames.saturating_sub(2 * margin);
    let fit = n.min(usable / 5);
    if fit < n {
        eprintln!("synth: only {fit} of {n} spoiling events fit in a video of {frames} frames");
    }
    if fit == 0 {
        return out;
    }
    let slot = usable as f64 / fit as f64;
    for (k, kind) in (0..fit).map(|k| (k, k % 3)) {
        let len = if kind == 0 {
            1 + (rng.uniform() * 3.0) as usize
        } else {
            1
        };
        let lo = margin as f64 + (k as f64 + 0.25) * slot;
        let hi = margin as f64 + (k as f64 + 0.75) * slot - len as f64;
        let start = (lo + rng.uniform() * (hi - lo).max(0.0)).round() as usize;
        for j in 0..len {
            out[start + j] = match kind {
                0 => Spoil::Hand {
                    k: j as u8,
                    n: len as u8,
                    event: k as u16,
                },
                1 => Spoil::Flash,
                _ => Spoil::Duplicate,
            };
        }
    }
    out
}

/// Where things are in the image, px.
#[derive(Clone, Debug)]
pub(super) struct Geometry {
    pub(super) w: usize,
    pub(super) h: usize,
    pub(super) pivot: [f64; 2],
    /// Pivot to the wire's end (the ball's centre).
    pub(super) d_px: f64,
    pub(super) ball_r: f64,
    /// Protractor radius.
    pub(super) rp: f64,
    pub(super) screw_r: f64,
    pub(super) wire_w: f64,
    pub(super) theta_rest: f64,
}

impl Geometry {
    /// Wire length 60 % of the frame height when the swing (plus 3 degrees) with the
    /// ball fits, shorter otherwise; the swing's bounding box is centred in the frame,
    /// or the pivot is at `pivot_frac` of the width and height (then the ball's swing
    /// is kept 3 % inside the frame's edges, and at least half of the wire must be in
    /// the frame). The wire's width is `wire_w`, by default `h / 288` within 2 to 3 px.
    fn new(
        w: usize,
        h: usize,
        theta_rest: f64,
        psi0: f64,
        ball_ratio: f64,
        wire_w: Option<f64>,
        pivot_frac: Option<[f64; 2]>,
    ) -> Result<Self> {
        let amp = psi0 + 3f64.to_radians();
        let reach = ball_ratio * 1.3;
        let (wf, hf) = (w as f64, h as f64);
        let (pivot, d_px) = match pivot_frac {
            None => {
                let (mut x0, mut x1, mut y0, mut y1) = (-0.1f64, 0.1f64, -0.1f64, 0.1f64);
                for j in 0..=64 {
                    let th = theta_rest - amp + 2.0 * amp * j as f64 / 64.0;
                    let (cx, cy) = (th.cos(), th.sin());
                    x0 = x0.min(cx - reach);
                    x1 = x1.max(cx + reach);
                    y0 = y0.min(cy - reach);
                    y1 = y1.max(cy + reach);
                }
                let d_px = (0.6 * hf)
                    .min(0.94 * wf / (x1 - x0))
                    .min(0.94 * hf / (y1 - y0));
                let pivot = [
                    wf / 2.0 - d_px * (x0 + x1) / 2.0,
                    hf / 2.0 - d_px * (y0 + y1) / 2.0,
                ];
                (pivot, d_px)
            }
            Some([fx, fy]) => placed(w, h, [fx * wf, fy * hf], theta_rest, amp, reach)
                .with_context(|| format!("`synthetic.pivot_frac` = [{fx}, {fy}] at {w}x{h} px"))?,
        };
        Ok(Self {
            w,
            h,
            pivot,
            d_px,
            ball_r: ball_ratio * d_px,
            rp: 0.45 * d_px,
            screw_r: (0.028 * d_px).max(2.5),
            wire_w: wire_w.unwrap_or((hf / 288.0).clamp(2.0, 3.0)),
            theta_rest,
        })
    }
}

/// The wire's length for a pivot placed at `pivot` (px, possibly outside the frame):
/// the longest, up to 60 % of the height, that keeps the ball's swing (directions
/// `theta_rest +- amp`, `reach` wire lengths around its end) 3 % inside the frame's
/// edges, if one does and then leaves at least half of the wire in the frame.
fn placed(
    w: usize,
    h: usize,
    pivot: [f64; 2],
    theta_rest: f64,
    amp: f64,
    reach: f64,
) -> Result<([f64; 2], f64)> {
    let size = [w as f64, h as f64];
    let (mut lo_d, mut hi_d) = (0.0f64, 0.6 * size[1]);
    for j in 0..=64 {
        let th = theta_rest - amp + 2.0 * amp * j as f64 / 64.0;
        for (axis, u) in [th.cos(), th.sin()].into_iter().enumerate() {
            let (lo, hi, p) = (0.03 * size[axis], 0.97 * size[axis], pivot[axis]);
            // The ball's far side, p + d (u + reach), at most `hi`...
            let a = u + reach;
            if a > 0.0 {
                hi_d = hi_d.min((hi - p) / a);
            } else if p > hi {
                lo_d = lo_d.max((p - hi) / -a);
            }
            // ... and its near side, p + d (u - reach), at least `lo`.
            let b = u - reach;
            if b < 0.0 {
                hi_d = hi_d.min((p - lo) / -b);
            } else if p < lo {
                lo_d = lo_d.max((lo - p) / b);
            }
        }
    }
    let least = 0.1 * size[0].min(size[1]);
    ensure!(
        hi_d >= lo_d && hi_d >= least,
        "the ball's swing cannot be kept in the frame with a wire of {least:.0} px or more"
    );
    let d = hi_d;
    // The share of the wire in the frame, at rest and at both ends of the swing.
    for th in [theta_rest - amp, theta_rest, theta_rest + amp] {
        let inside = (0..=200)
            .filter(|&k| {
                let f = d * k as f64 / 200.0;
                let (x, y) = (pivot[0] + f * th.cos(), pivot[1] + f * th.sin());
                (0.0..size[0]).contains(&x) && (0.0..size[1]).contains(&y)
            })
            .count();
        ensure!(
            inside >= 100,
            "only {:.0} % of the wire would be in the frame; expected at least half",
            inside as f64 / 2.01
        );
    }
    Ok((pivot, d))
}
