//! The static background: the plate, the protractor, its block and the fulcrum screw,
//! drawn once per video in the plate's own frame and then turned into the image.

use super::look::{bgr, illumination, mix, pt, scale, to_u8, Look};
use super::plan::{stream, Geometry, Plan};
use super::room;
use crate::rng::Rng;
use anyhow::{Context, Result};
use opencv::core::{self, Mat, Point, Rect, Scalar, Size};
use opencv::imgproc;
use opencv::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

/// Smooth random field with about `cells` features across the larger side, ~N(0, 1).
fn smooth_field(w: i32, h: i32, cells: i32, rng: &mut Rng) -> Result<Vec<f32>> {
    let (gw, gh) = if w >= h {
        (cells + 3, (cells * h / w).max(1) + 3)
    } else {
        ((cells * w / h).max(1) + 3, cells + 3)
    };
    let mut small = Mat::new_rows_cols_with_default(gh, gw, core::CV_32FC1, Scalar::all(0.0))?;
    for v in small.data_typed_mut::<f32>()? {
        *v = rng.normal() as f32;
    }
    let mut big = Mat::default();
    imgproc::resize(
        &small,
        &mut big,
        Size::new(w, h),
        0.0,
        0.0,
        imgproc::INTER_CUBIC,
    )?;
    Ok(big.data_typed::<f32>()?.to_vec())
}

/// The plate, seen from above: smooth shading, grain (brushed or not), scratches, dust.
fn plate_texture(w: i32, h: i32, look: &Look, rng: &mut Rng) -> Result<Mat> {
    let lf1 = smooth_field(w, h, 4, rng)?;
    let lf2 = smooth_field(w, h, 14, rng)?;
    let n = (w * h) as usize;
    let mut grain = Mat::new_rows_cols_with_default(h, w, core::CV_32FC1, Scalar::all(0.0))?;
    for g in grain.data_typed_mut::<f32>()? {
        *g = (rng.uniform() + rng.uniform() - 1.0) as f32 * 1.7;
    }
    if look.brushed {
        let mut b = Mat::default();
        imgproc::blur(
            &grain,
            &mut b,
            Size::new(25, 1),
            Point::new(-1, -1),
            core::BORDER_REFLECT,
        )?;
        let mut g2 = Mat::default();
        b.convert_to(&mut g2, core::CV_32F, 5.0 * 0.75, 0.0)?;
        // keep some isotropic grain too
        for (a, b) in g2
            .data_typed_mut::<f32>()?
            .iter_mut()
            .zip(grain.data_typed::<f32>()?)
        {
            *a += 0.35 * b;
        }
        grain = g2;
    }
    let grain = grain.data_typed::<f32>()?;
    let mut img = Mat::new_rows_cols_with_default(h, w, core::CV_8UC3, Scalar::all(0.0))?;
    {
        let buf = img.data_bytes_mut()?;
        for i in 0..n {
            let shade = 1.0 + look.shading * (lf1[i] + 0.4 * lf2[i]);
            let g = look.grain * grain[i];
            for c in 0..3 {
                buf[3 * i + c] = to_u8(look.plate[c] * shade + g);
            }
        }
    }
    // Faint scratches and dust: static, so a detector of the moving wire ignores them.
    let diag = ((w * w + h * h) as f64).sqrt();
    for _ in 0..14 {
        let (x, y) = (rng.uniform() * w as f64, rng.uniform() * h as f64);
        let a = rng.uniform() * PI;
        let l = diag * (0.01 + 0.04 * rng.uniform());
        let k = if rng.uniform() < 0.5 { 0.93 } else { 1.06 };
        let c = scale(look.plate, k);
        imgproc::line(
            &mut img,
            pt(x, y),
            pt(x + l * a.cos(), y + l * a.sin()),
            bgr(c),
            1,
            imgproc::LINE_AA,
            4,
        )?;
    }
    for _ in 0..40 {
        let (x, y) = (rng.uniform() * w as f64, rng.uniform() * h as f64);
        let r = 0.6 + 1.4 * rng.uniform();
        let k = if rng.uniform() < 0.7 { 0.8 } else { 1.15 };
        imgproc::circle(
            &mut img,
            pt(x, y),
            (r * 16.0) as i32,
            bgr(scale(look.plate, k)),
            -1,
            imgproc::LINE_AA,
            4,
        )?;
    }
    Ok(img)
}

/// Protractor, its block and the fulcrum screw, on the plate canvas. The canvas is the
/// plate's frame: the wire at rest points along +y from the pivot `c`.
fn draw_instruments(canvas: &mut Mat, c: [f64; 2], g: &Geometry, look: &Look) -> Result<()> {
    let rp = g.rp;
    let (cx, cy) = (c[0], c[1]);
    let size = canvas.size()?;
    let block = |dx: f64, dy: f64| {
        Rect::new(
            (cx - 1.08 * rp + dx).round() as i32,
            (cy - 0.34 * rp + dy).round() as i32,
            (2.16 * rp).round() as i32,
            (0.30 * rp).round() as i32,
        )
    };
    // Soft shadows of the block and of the protractor's edge (light from the upper left).
    let mut shadow = Mat::new_size_with_default(size, core::CV_8UC1, Scalar::all(0.0))?;
    imgproc::rectangle(
        &mut shadow,
        block(0.03 * rp, 0.045 * rp),
        Scalar::all(255.0),
        -1,
        imgproc::LINE_8,
        0,
    )?;
    let (ox, oy) = (0.012 * rp, 0.018 * rp);
    imgproc::ellipse(
        &mut shadow,
        pt(cx + ox, cy + oy),
        Size::new((rp * 16.0) as i32, (rp * 16.0) as i32),
        0.0,
        0.0,
        180.0,
        Scalar::all(150.0),
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    let mut soft = Mat::default();
    let sig = (0.03 * rp).max(1.0);
    imgproc::gaussian_blur(
        &shadow,
        &mut soft,
        Size::new(0, 0),
        sig,
        sig,
        core::BORDER_REFLECT,
    )?;
    {
        let m = soft.data_bytes()?.to_vec();
        let buf = canvas.data_bytes_mut()?;
        for (i, &s) in m.iter().enumerate() {
            if s > 0 {
                let k = 1.0 - 0.4 * s as f32 / 255.0;
                for ch in 0..3 {
                    buf[3 * i + ch] = (buf[3 * i + ch] as f32 * k) as u8;
                }
            }
        }
    }
    // Protractor body: translucent plastic, a half disc plus the strip above its base.
    let mut over = canvas.clone();
    let axes = Size::new((rp * 16.0) as i32, (rp * 16.0) as i32);
    imgproc::ellipse(
        &mut over,
        pt(cx, cy),
        axes,
        0.0,
        0.0,
        180.0,
        bgr(look.body),
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    imgproc::rectangle(
        &mut over,
        Rect::new(
            (cx - rp).round() as i32,
            (cy - 0.07 * rp).round() as i32,
            (2.0 * rp).round() as i32,
            (0.07 * rp).round() as i32 + 1,
        ),
        bgr(look.body),
        -1,
        imgproc::LINE_AA,
        0,
    )?;
    let mut blended = Mat::default();
    core::add_weighted(
        &*canvas,
        1.0 - look.body_alpha,
        &over,
        look.body_alpha,
        0.0,
        &mut blended,
        -1,
    )?;
    *canvas = blended;
    let marks = bgr(look.marks);
    let rim = bgr(mix(look.body, look.marks, 0.5));
    imgproc::ellipse(
        canvas,
        pt(cx, cy),
        axes,
        0.0,
        0.0,
        180.0,
        rim,
        1,
        imgproc::LINE_AA,
        4,
    )?;
    // Base line and the centre mark.
    imgproc::line(
        canvas,
        pt(cx - rp, cy),
        pt(cx + rp, cy),
        marks,
        1,
        imgproc::LINE_AA,
        4,
    )?;
    let r0 = rp * 0.975;
    for k in 0..=180 {
        let a = (k as f64).to_radians();
        let len = rp
            * if k % 10 == 0 {
                0.12
            } else if k % 5 == 0 {
                0.08
            } else {
                0.045
            };
        let (u, v) = (a.cos(), a.sin());
        imgproc::line(
            canvas,
            pt(cx + r0 * u, cy + r0 * v),
            pt(cx + (r0 - len) * u, cy + (r0 - len) * v),
            marks,
            1,
            imgproc::LINE_AA,
            4,
        )?;
    }
    // Inner scale's ticks and arc.
    let ri = rp * 0.74;
    imgproc::ellipse(
        canvas,
        pt(cx, cy),
        Size::new((ri * 16.0) as i32, (ri * 16.0) as i32),
        0.0,
        0.0,
        180.0,
        marks,
        1,
        imgproc::LINE_AA,
        4,
    )?;
    // Numerals, outer scale 0..180 and inner scale 180..0, every 10 degrees.
    let font = imgproc::FONT_HERSHEY_SIMPLEX;
    let mut base = 0;
    let unit = imgproc::get_text_size("0", font, 1.0, 1, &mut base)?.height as f64;
    for (radius, height, inner) in [(rp * 0.80, 0.05 * rp, false), (rp * 0.66, 0.038 * rp, true)] {
        let fs = height / unit;
        let th = if fs > 0.9 { 2 } else { 1 };
        for k in (0..=180).step_by(10) {
            let label = if inner { 180 - k } else { k }.to_string();
            let sz = imgproc::get_text_size(&label, font, fs, th, &mut base)?;
            let a = (k as f64).to_radians();
            let (x, y) = (cx + radius * a.cos(), cy + radius * a.sin());
            imgproc::put_text(
                canvas,
                &label,
                Point::new(
                    (x - sz.width as f64 / 2.0).round() as i32,
                    (y + sz.height as f64 / 2.0).round() as i32,
                ),
                font,
                fs,
                marks,
                th,
                imgproc::LINE_AA,
                false,
            )?;
        }
    }
    // The block, with lit and shaded edges and two screws.
    let b = block(0.0, 0.0);
    imgproc::rectangle(canvas, b, bgr(look.block), -1, imgproc::LINE_8, 0)?;
    let e = ((0.015 * rp).round() as i32).max(1);
    let hi = bgr(scale(look.block, 1.3));
    let lo = bgr(scale(look.block, 0.6));
    let (x0, y0, x1, y1) = (b.x, b.y, b.x + b.width - 1, b.y + b.height - 1);
    imgproc::rectangle(
        canvas,
        Rect::new(x0, y0, b.width, e),
        hi,
        -1,
        imgproc::LINE_8,
        0,
    )?;
    imgproc::rectangle(
        canvas,
        Rect::new(x0, y0, e, b.height),
        hi,
        -1,
        imgproc::LINE_8,
        0,
    )?;
    imgproc::rectangle(
        canvas,
        Rect::new(x0, y1 - e + 1, b.width, e),
        lo,
        -1,
        imgproc::LINE_8,
        0,
    )?;
    imgproc::rectangle(
        canvas,
        Rect::new(x1 - e + 1, y0, e, b.height),
        lo,
        -1,
        imgproc::LINE_8,
        0,
    )?;
    for sx in [-0.85, 0.85] {
        screw(canvas, cx + sx * rp, cy - 0.19 * rp, 0.04 * rp, look.screw)?;
    }
    // The fulcrum.
    screw(canvas, cx, cy, g.screw_r, look.screw)?;
    Ok(())
}

/// A screw head: a disc with a lit rim and a slot.
fn screw(canvas: &mut Mat, x: f64, y: f64, r: f64, col: [f32; 3]) -> Result<()> {
    let rr = |r: f64| (r * 16.0).round() as i32;
    imgproc::circle(canvas, pt(x, y), rr(r), bgr(col), -1, imgproc::LINE_AA, 4)?;
    imgproc::circle(
        canvas,
        pt(x - 0.15 * r, y - 0.15 * r),
        rr(0.6 * r),
        bgr(scale(col, 1.5)),
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    imgproc::circle(
        canvas,
        pt(x, y),
        rr(0.55 * r),
        bgr(scale(col, 1.2)),
        -1,
        imgproc::LINE_AA,
        4,
    )?;
    let t = ((0.2 * r).round() as i32).max(1);
    imgproc::line(
        canvas,
        pt(x - 0.5 * r, y + 0.25 * r),
        pt(x + 0.5 * r, y - 0.25 * r),
        bgr(scale(col, 0.5)),
        t,
        imgproc::LINE_AA,
        4,
    )?;
    Ok(())
}

/// The static scene as the camera sees it: BGR bytes (lit, defocused) and the
/// illumination factor of every pixel.
pub(super) fn build_background(plan: &Plan, defocus: Option<f64>) -> Result<(Vec<u8>, Vec<f32>)> {
    let g = &plan.geo;
    let look = &plan.look;
    let mut rng = Rng::new(stream(plan.s.seed, 1));
    let (w, h) = (g.w as i32, g.h as i32);
    let rot = g.theta_rest - FRAC_PI_2;
    let (c, s) = (rot.cos(), rot.sin());
    // The frame's corners in the untilted view, then in the plate's frame (pivot at
    // the origin).
    let back = plan
        .view
        .map(|v| v.inverse().context("the tilted camera's view is singular"))
        .transpose()?;
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for (x, y) in [
        (0.0, 0.0),
        (w as f64, 0.0),
        (0.0, h as f64),
        (w as f64, h as f64),
    ] {
        let [x, y] = back.map_or([x, y], |b| b.apply([x, y]));
        let (dx, dy) = (x - g.pivot[0], y - g.pivot[1]);
        let (u, v) = (c * dx + s * dy, -s * dx + c * dy);
        lo = [lo[0].min(u), lo[1].min(v)];
        hi = [hi[0].max(u), hi[1].max(v)];
    }
    let cw = (hi[0] - lo[0]).ceil() as i32 + 8;
    let ch = (hi[1] - lo[1]).ceil() as i32 + 8;
    let cp = [-lo[0] + 4.0, -lo[1] + 4.0];
    let mut canvas = plate_texture(cw, ch, look, &mut rng)?;
    if let Some(room) = &plan.s.room {
        room::draw_board(&mut canvas, cp, g, look, room, plan.s.seed)?;
    }
    draw_instruments(&mut canvas, cp, g, look)?;
    if let Some(room) = &plan.s.room {
        room::draw_edges(&mut canvas, cp, g, look, room, plan.s.seed)?;
    }
    // The canvas to the untilted view: a turn about the pivot.
    let a = nalgebra::Matrix3::new(
        c,
        -s,
        g.pivot[0] - (c * cp[0] - s * cp[1]),
        s,
        c,
        g.pivot[1] - (s * cp[0] + c * cp[1]),
        0.0,
        0.0,
        1.0,
    );
    let rows = |t: &nalgebra::Matrix3<f64>, n: usize| -> Vec<[f64; 3]> {
        (0..n).map(|r| [t[(r, 0)], t[(r, 1)], t[(r, 2)]]).collect()
    };
    let mut img = Mat::default();
    let size = Size::new(w, h);
    match &plan.view {
        None => imgproc::warp_affine(
            &canvas,
            &mut img,
            &Mat::from_slice_2d(&rows(&a, 2))?,
            size,
            imgproc::INTER_LINEAR,
            core::BORDER_REFLECT,
            Scalar::all(0.0),
        )?,
        // Then the tilted camera's view.
        Some(v) => imgproc::warp_perspective(
            &canvas,
            &mut img,
            &Mat::from_slice_2d(&rows(&(v.m * a), 3))?,
            size,
            imgproc::INTER_LINEAR,
            core::BORDER_REFLECT,
            Scalar::all(0.0),
        )?,
    }
    let (wf, hf) = (w as f32, h as f32);
    let mut illum = Vec::with_capacity(g.w * g.h);
    for y in 0..g.h {
        for x in 0..g.w {
            illum.push(illumination(look.light, x as f32, y as f32, wf, hf));
        }
    }
    {
        let buf = img.data_bytes_mut()?;
        for (px, &k) in buf.chunks_exact_mut(3).zip(&illum) {
            for v in px {
                *v = to_u8(*v as f32 * k);
            }
        }
    }
    if let Some(sig) = defocus {
        let mut b = Mat::default();
        imgproc::gaussian_blur(
            &img,
            &mut b,
            Size::new(0, 0),
            sig,
            sig,
            core::BORDER_REFLECT,
        )?;
        img = b;
    }
    Ok((img.data_bytes()?.to_vec(), illum))
}
