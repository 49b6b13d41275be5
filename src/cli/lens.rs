//! `rollfric lens VIDEO`: the lens's radial distortion fitted from the straight lines a
//! video shows (a ruled or gridded sheet filmed with the same camera and zoom), for
//! `video.lens`.

use crate::lens::plumb;
use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::path::PathBuf;

/// The flags of `rollfric lens` (defined here only).
#[derive(clap::Args)]
pub struct LensArgs {
    /// A video (or a still picture) of straight lines: a ruled or gridded sheet that
    /// fills the frame, filmed with the camera, lens and zoom of the experiment.
    video: PathBuf,
    /// How many frames to fit, each on its own (every `--every`th from the first).
    #[arg(long, default_value_t = 5)]
    frames: usize,
    /// Take every this many frames.
    #[arg(long, default_value_t = 10)]
    every: usize,
    /// Print the fit as JSON.
    #[arg(long)]
    json: bool,
}

/// `lens --json`'s output.
#[derive(serde::Serialize)]
struct Json<'a> {
    kind: &'static str,
    video: String,
    #[serde(flatten)]
    fit: &'a plumb::VideoFit,
}

pub fn lens(a: LensArgs) -> Result<String> {
    if a.frames == 0 || a.every == 0 {
        bail!(
            "--frames {} --every {}: expected 1 or more",
            a.frames,
            a.every
        );
    }
    let fit = plumb::fit_video(&a.video, a.frames, a.every).map_err(|e| {
        anyhow::anyhow!(
            "{e:#}\nA wide lens that cannot be calibrated can be declared unknown, under \
             `video:`: `lens: {{k1: 0, u_k1: {}}}`: the angles are then taken as seen, its \
             distortion enters s_r's budget, and the `scale` checks say whether it matters \
             where the wire is",
            crate::lens::UNKNOWN_U_K1
        )
    })?;
    let path = a.video.display();
    if a.json {
        let j = Json {
            kind: "rollfric lens",
            video: path.to_string(),
            fit: &fit,
        };
        return serde_json::to_string_pretty(&j).context("writing the fit as JSON");
    }
    let mid = |mut v: Vec<f64>| crate::numerics::upper_median(&mut v);
    let each = |f: fn(&plumb::Plumb) -> f64| mid(fit.frames.iter().map(|(_, p)| f(p)).collect());
    let (k1, u_k1) = (fit.k1, fit.u_k1);
    let mut out = format!(
        "{path}: {}x{}, {} frame(s) fitted, {} straight lines in each (median): k1 = \
         {k1:.4} +- {u_k1:.4}; the lines scatter {:.2} px (RMS) about straight through \
         this lens, {:.2} px through an undistorted view\n",
        fit.width,
        fit.height,
        fit.frames.len(),
        each(|p| p.lines as f64),
        each(|p| p.rms_px),
        each(|p| p.rms_straight_px),
    );
    let faint: Vec<f64> = fit
        .frames
        .iter()
        .filter(|(_, p)| p.faint())
        .map(|(_, p)| p.edge_times)
        .collect();
    if let Some(lowest) = faint.iter().copied().reduce(f64::min) {
        writeln!(
            out,
            "  {} of the frames fitted from faint edges (down to {lowest} times the \
             picture's noise, not {}): a sharper, darker grid fits the lens more surely",
            faint.len(),
            plumb::EDGE_TIMES_QUANTILE[0]
        )
        .unwrap();
    }
    if let Some(r) = fit.refused.first() {
        let more = match fit.refused.len() {
            1 => String::new(),
            n => format!(" (and {} more frames)", n - 1),
        };
        writeln!(out, "  not fitted: {r}{more}").unwrap();
    }
    if plumb::worth_giving(k1, u_k1) {
        write!(
            out,
            "For the experiment file (under `video:`), with this camera, lens and zoom:\n  \
             lens: {{k1: {k1:.4}, u_k1: {:.4}}}\n",
            u_k1.max(0.0001)
        )
        .unwrap();
    } else {
        writeln!(
            out,
            "Not a lens to give: the coefficient is under three times its uncertainty or \
             under 0.03 (the lines are straight as far as they show)."
        )
        .unwrap();
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_picture_fitted_from_faint_edges_says_so() {
        if !crate::video::need_ffmpeg() {
            return;
        }
        // The faint, soft grid of `plumb`'s tests, as a photo of it.
        let (w, h) = (640, 480);
        let seen_through = crate::lens::Lens::new(-0.08, 0.0, w as u32, h as u32);
        let data = plumb::tests::ruled(w, h, &seen_through, (10.0, 0.47), (24.0, 3.0), 3.0, 7);
        let dir = tempfile::tempdir().unwrap();
        let photo = dir.path().join("sheet.png");
        let png = crate::picture::encode(w, h, crate::picture::Layout::Grey, &data).unwrap();
        std::fs::write(&photo, png).unwrap();
        let out = lens(LensArgs {
            video: photo,
            frames: 5,
            every: 10,
            json: false,
        })
        .unwrap();
        assert!(out.contains("1 frame(s) fitted"), "{out}");
        assert!(
            out.contains("1 of the frames fitted from faint edges (down to 3 times"),
            "{out}"
        );
        assert!(out.contains("lens: {k1: -0.08"), "{out}");
    }
}
