//! A frame warped back onto the first by its motion.

use super::Motion;
use crate::video::Frame;
use anyhow::Result;
use opencv::core::{self, Mat, Scalar, Size};
use opencv::imgproc;
use opencv::prelude::*;

/// The `size` part of `f` at `origin` (frame px), as the first frame would show it
/// under motion `m`, into `out` (8-bit, `size`).
pub(in crate::detect) fn warp_into(
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
pub(in crate::detect) fn bytes(m: &Mat) -> Result<&[u8]> {
    Ok(m.data_bytes()?)
}
