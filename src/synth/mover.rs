//! The moving parts: the wire and the ball, drawn per frame inside their bounding box.

use super::look::{mix, scale, to_u8, Look};
use super::plan::Geometry;
use crate::config::WireShadow;
use crate::plane::Homography;

/// `erf` (Abramowitz & Stegun 7.1.26, |error| < 1.5e-7).
fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let y = 1.0
        - t * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))))
            * (-x * x).exp();
    y.copysign(x)
}

/// A function tabulated on `[lo, lo + (n-1)/inv]`, clamped at both ends.
struct Table {
    lo: f32,
    inv: f32,
    v: Vec<f32>,
}

impl Table {
    fn new(lo: f64, hi: f64, steps_per_unit: f64, f: impl Fn(f64) -> f64) -> Self {
        let n = ((hi - lo) * steps_per_unit).ceil() as usize + 2;
        Self {
            lo: lo as f32,
            inv: steps_per_unit as f32,
            v: (0..n)
                .map(|i| f(lo + i as f64 / steps_per_unit) as f32)
                .collect(),
        }
    }

    #[inline]
    fn at(&self, x: f32) -> f32 {
        let i = ((x - self.lo) * self.inv).max(0.0) as usize;
        self.v[i.min(self.v.len() - 1)]
    }
}

/// The ball's shadow on the plate, in units of the ball's radius: centre offset x and y,
/// radius, softness, depth.
const SHADOW: [f32; 5] = [0.08, 0.12, 1.0, 0.12, 0.38];

/// Cells per side of the ball's shading table.
const BALL_TAB: usize = 160;

/// A steel ball seen from above: darker towards the rim, a sharp highlight and a broad
/// sheen towards the light (upper left).
fn ball_table(base: [f32; 3]) -> Vec<[f32; 3]> {
    let mut t = Vec::with_capacity(BALL_TAB * BALL_TAB);
    for iy in 0..BALL_TAB {
        for ix in 0..BALL_TAB {
            let q = |i: usize| (i as f64 + 0.5) / (BALL_TAB / 2) as f64 - 1.0;
            let (qx, qy) = (q(ix), q(iy));
            let z = (1.0 - qx * qx - qy * qy).max(0.0).sqrt();
            let tone = 0.32 + 0.68 * z;
            let h2 = (qx + 0.32).powi(2) + (qy + 0.38).powi(2);
            let spec = 230.0 * (-h2 * 28.0).exp() + 40.0 * (-h2 * 3.0).exp();
            t.push(base.map(|c| (c as f64 * tone + spec) as f32));
        }
    }
    t
}

/// The wire's shadow on the plate: a blurred line from the pivot, at an angle from the
/// wire.
struct ShadowLine {
    /// Angle from the wire (before mirroring; in the untilted view), rad.
    offset: f64,
    /// Darkening per unit of coverage: `strength / profile(0)`, so that the shadow's
    /// middle takes `strength` of the plate's brightness, at most `lamp_share` (the
    /// light a wire of its width can block).
    k: f32,
    /// Coverage against distance from its axis, px.
    profile: Table,
    /// Distance beyond which it covers nothing, px.
    reach: f64,
    acc: Vec<f32>,
}

/// Draws the wire and the ball into a frame that holds the background.
pub(super) struct Mover {
    w: usize,
    h: usize,
    /// The pivot in the image.
    pivot: [f64; 2],
    /// The pivot in the untilted view (the same as `pivot` without `view`).
    plate_pivot: [f64; 2],
    /// The tilted camera's view: the untilted view's pixels to the image's.
    view: Option<Homography>,
    d_px: f64,
    ball_r: f64,
    screw_r: f64,
    wire: [f32; 3],
    /// The wire's share of its colour where it covers a pixel fully (`wire_contrast`).
    contrast: f32,
    /// The ball's shaded colour on a `BALL_TAB` square grid over `[-1, 1]^2` (units of
    /// its radius), before illumination.
    ball_tab: Vec<[f32; 3]>,
    /// Wire coverage against distance from its axis, px.
    profile: Table,
    /// Distance beyond which the wire covers nothing, px.
    reach: f64,
    /// Standard normal CDF on [-5, 5].
    cdf: Table,
    /// Edge blur of the ball, px.
    sigma: f64,
    acc: Vec<f32>,
    shadow: Option<ShadowLine>,
}

impl Mover {
    pub(super) fn new(
        g: &Geometry,
        view: Option<Homography>,
        look: &Look,
        sigma: f64,
        contrast: f64,
        shadow: Option<WireShadow>,
    ) -> Self {
        let hw = g.wire_w / 2.0;
        let shadow = shadow.map(|sh| {
            let s = sigma.hypot(sh.blur_px);
            let s2 = s * std::f64::consts::SQRT_2;
            let reach = hw + 4.0 * s + 0.5;
            let f = move |d: f64| 0.5 * (erf((hw - d) / s2) + erf((hw + d) / s2));
            // The darkening per unit of the blurred wire's coverage is the share of the
            // plate's light that the lamp casting it gives: at most `lamp_share`.
            let k = (sh.strength / f(0.0)).min(sh.lamp_share.unwrap_or(f64::INFINITY));
            ShadowLine {
                offset: sh.angle_deg.to_radians(),
                k: k as f32,
                profile: Table::new(0.0, reach, 64.0, f),
                reach,
                acc: Vec::new(),
            }
        });
        let s2 = sigma * std::f64::consts::SQRT_2;
        let reach = hw + 4.0 * sigma + 0.5;
        // With a tilted view the ball and the screw are drawn at their local scale.
        let at_pivot = view.map_or(1.0, |v| v.local_scale(g.pivot));
        Self {
            w: g.w,
            h: g.h,
            pivot: view.map_or(g.pivot, |v| v.apply(g.pivot)),
            plate_pivot: g.pivot,
            view,
            d_px: g.d_px,
            ball_r: g.ball_r,
            screw_r: g.screw_r * at_pivot,
            wire: look.wire,
            contrast: contrast as f32,
            ball_tab: ball_table(look.ball),
            profile: Table::new(0.0, reach, 64.0, |d| {
                0.5 * (erf((hw - d) / s2) + erf((hw + d) / s2))
            }),
            reach,
            cdf: Table::new(-5.0, 5.0, 64.0, |z| {
                0.5 * (1.0 + erf(z / std::f64::consts::SQRT_2))
            }),
            sigma,
            acc: Vec::new(),
            shadow,
        }
    }

    /// Composite the ball (at `theta_mid`) and the wire (averaged over `thetas`) over the
    /// background already in `frame`, lit by `illum`, in the rows `rows` (a rolling
    /// shutter's band) or all.
    pub(super) fn draw(
        &mut self,
        frame: &mut [u8],
        bg: &[u8],
        illum: &[f32],
        thetas: &[f64],
        theta_mid: f64,
        rows: Option<(usize, usize)>,
    ) {
        let [px, py] = self.pivot;
        let [qx, qy] = self.plate_pivot;
        let view = self.view;
        // The wire's end in the untilted view, and in the image.
        let plate_end = |th: f64| [qx + self.d_px * th.cos(), qy + self.d_px * th.sin()];
        let end = |th: f64| view.map_or(plate_end(th), |v| v.apply(plate_end(th)));
        let c = end(theta_mid);
        let r = view.map_or(self.ball_r, |v| {
            self.ball_r * v.local_scale(plate_end(theta_mid))
        });
        let ball_reach = 1.6 * r + 4.0 * self.sigma + 2.0;
        let (mut x0, mut x1) = (c[0] - ball_reach, c[0] + ball_reach);
        let (mut y0, mut y1) = (c[1] - ball_reach, c[1] + ball_reach);
        for &th in thetas {
            let e = end(th);
            x0 = x0.min(px.min(e[0]) - self.reach);
            x1 = x1.max(px.max(e[0]) + self.reach);
            y0 = y0.min(py.min(e[1]) - self.reach);
            y1 = y1.max(py.max(e[1]) + self.reach);
        }
        if let Some(sh) = &self.shadow {
            for &th in thetas {
                let e = end(th + sh.offset);
                x0 = x0.min(px.min(e[0]) - sh.reach);
                x1 = x1.max(px.max(e[0]) + sh.reach);
                y0 = y0.min(py.min(e[1]) - sh.reach);
                y1 = y1.max(py.max(e[1]) + sh.reach);
            }
        }
        let clip = |v: f64, n: usize| (v.max(0.0) as usize).min(n);
        let (rx0, rx1) = (clip(x0.floor(), self.w), clip(x1.ceil() + 1.0, self.w));
        let (ry0, ry1) = (clip(y0.floor(), self.h), clip(y1.ceil() + 1.0, self.h));
        let (ry0, ry1) = rows.map_or((ry0, ry1), |(a, b)| (ry0.max(a), ry1.min(b)));
        if rx0 >= rx1 || ry0 >= ry1 {
            return;
        }
        let rw = rx1 - rx0;
        let n = rw * (ry1 - ry0);
        if self.acc.len() < n {
            self.acc.resize(n, 0.0);
        }
        let acc = &mut self.acc[..n];
        acc.fill(0.0);
        let weight = 1.0 / thetas.len() as f32;
        for &th in thetas {
            let e = end(th);
            raster_segment(
                acc,
                [rx0, rx1, ry0, ry1],
                self.pivot,
                e,
                self.reach,
                &self.profile,
                weight,
            );
        }
        let wire_shadow = match &mut self.shadow {
            Some(sh) => {
                if sh.acc.len() < n {
                    sh.acc.resize(n, 0.0);
                }
                let sacc = &mut sh.acc[..n];
                sacc.fill(0.0);
                for &th in thetas {
                    raster_segment(
                        sacc,
                        [rx0, rx1, ry0, ry1],
                        self.pivot,
                        end(th + sh.offset),
                        sh.reach,
                        &sh.profile,
                        weight,
                    );
                }
                Some((&sh.acc[..n], sh.k))
            }
            None => None,
        };
        // The ball and its shadow (light from the upper left of the image), in units of
        // the ball's radius around its centre.
        let bx = [(c[0] - ball_reach) as f32, (c[0] + ball_reach) as f32];
        let by = [(c[1] - ball_reach) as f32, (c[1] + ball_reach) as f32];
        let inv_r = 1.0 / r as f32;
        let edge = 4.0 * self.sigma as f32 * inv_r;
        let (in2, out2) = ((1.0 - edge).max(0.0).powi(2), (1.0 + edge).powi(2));
        let k_edge = r as f32 / (self.sigma as f32).max(0.3);
        let s_out2 = (SHADOW[2] + 3.5 * SHADOW[3]).powi(2);
        let screw2 = (self.screw_r as f32 + 0.5).powi(2);
        let (cx, cy) = (c[0] as f32, c[1] as f32);
        let (pxf, pyf) = (px as f32, py as f32);
        let cell =
            |q: f32| (((q + 1.0) * (BALL_TAB / 2) as f32).max(0.0) as usize).min(BALL_TAB - 1);
        for y in ry0..ry1 {
            let yf = y as f32;
            let row = &acc[(y - ry0) * rw..(y - ry0 + 1) * rw];
            let srow = wire_shadow.map(|(a, _)| &a[(y - ry0) * rw..(y - ry0 + 1) * rw]);
            let ball_row = yf >= by[0] && yf <= by[1];
            let qy = (yf - cy) * inv_r;
            for (x, &cov) in (rx0..rx1).zip(row) {
                let xf = x as f32;
                let (mut cb, mut shadow, mut qx) = (0.0f32, 0.0f32, 0.0f32);
                if ball_row && xf >= bx[0] && xf <= bx[1] {
                    qx = (xf - cx) * inv_r;
                    let rho2 = qx * qx + qy * qy;
                    cb = if rho2 <= in2 {
                        1.0
                    } else if rho2 >= out2 {
                        0.0
                    } else {
                        self.cdf.at((1.0 - rho2.sqrt()) * k_edge)
                    };
                    if cb < 0.999 {
                        let (sx, sy) = (qx - SHADOW[0], qy - SHADOW[1]);
                        let s2 = sx * sx + sy * sy;
                        if s2 < s_out2 {
                            shadow = self.cdf.at((SHADOW[2] - s2.sqrt()) / SHADOW[3]);
                        }
                    }
                }
                let ws = srow.map_or(0.0, |r| r[x - rx0]);
                if cov <= 1e-4 && cb <= 1e-4 && shadow <= 1e-4 && ws <= 1e-4 {
                    continue;
                }
                let j = y * self.w + x;
                let il = illum[j];
                let k = 3 * j;
                let mut p = [bg[k] as f32, bg[k + 1] as f32, bg[k + 2] as f32];
                // The screw's head hides the wire, and the wire's shadow, near the pivot.
                let under_screw = || {
                    let (dx, dy) = (xf - pxf, yf - pyf);
                    let d2 = dx * dx + dy * dy;
                    if d2 >= screw2 {
                        1.0
                    } else {
                        (d2.sqrt() - self.screw_r as f32 + 0.5).clamp(0.0, 1.0)
                    }
                };
                if ws > 1e-4 {
                    let dark = wire_shadow.map_or(0.0, |(_, k)| k) * ws * under_screw();
                    p = scale(p, 1.0 - dark.min(1.0));
                }
                if shadow > 1e-4 {
                    p = scale(p, 1.0 - SHADOW[4] * shadow);
                }
                if cb > 1e-4 {
                    let col = self.ball_tab[cell(qy) * BALL_TAB + cell(qx)];
                    p = mix(p, scale(col, il), cb);
                }
                if cov > 1e-4 {
                    let k = cov.min(1.0) * under_screw() * self.contrast;
                    p = mix(p, scale(self.wire, il), k);
                }
                frame[k] = to_u8(p[0]);
                frame[k + 1] = to_u8(p[1]);
                frame[k + 2] = to_u8(p[2]);
            }
        }
    }
}

/// Add `weight * profile(distance to the segment a-b)` to `acc`, which covers
/// `[x0, x1) x [y0, y1)` of the image; only pixels within `reach` of the segment.
fn raster_segment(
    acc: &mut [f32],
    [x0, x1, y0, y1]: [usize; 4],
    a: [f64; 2],
    b: [f64; 2],
    reach: f64,
    profile: &Table,
    weight: f32,
) {
    let (vx, vy) = (b[0] - a[0], b[1] - a[1]);
    let len = (vx * vx + vy * vy).sqrt().max(1e-9);
    let (ux, uy) = (vx / len, vy / len);
    let rw = x1 - x0;
    let ya = (a[1].min(b[1]) - reach).floor().max(y0 as f64) as usize;
    let yb = ((a[1].max(b[1]) + reach).ceil() as usize + 1).min(y1);
    let (sx0, sx1) = (a[0].min(b[0]) - reach, a[0].max(b[0]) + reach);
    let steep = uy.abs() > 0.2;
    let reach2 = (reach * reach) as f32;
    let (ax, ay, ux32, uy32, len32) = (a[0] as f32, a[1] as f32, ux as f32, uy as f32, len as f32);
    for y in ya..yb {
        let yf = y as f64;
        let (mut xa, mut xb) = (sx0, sx1);
        if steep {
            let xc = a[0] + (yf - a[1]) * ux / uy;
            let half = reach / uy.abs() + 1.0;
            xa = xa.max(xc - half);
            xb = xb.min(xc + half);
        }
        let xa = (xa.floor().max(x0 as f64)) as usize;
        let xb = ((xb.ceil() + 1.0).max(0.0) as usize).min(x1);
        let row = &mut acc[(y - y0) * rw..(y - y0 + 1) * rw];
        let dy = y as f32 - ay;
        for x in xa..xb {
            let dx = x as f32 - ax;
            let t = (dx * ux32 + dy * uy32).clamp(0.0, len32);
            let (ex, ey) = (dx - t * ux32, dy - t * uy32);
            let d2 = ex * ex + ey * ey;
            if d2 < reach2 {
                row[x - x0] += weight * profile.at(d2.sqrt());
            }
        }
    }
}
