//! The review page of one experiment (`<name>/review.html`): every flagged frame (and
//! the frame after a release from rest) as the detector's pass kept it, with the
//! detected (red) and predicted (green) lines drawn over it; a click on two points of
//! the wire marks it, and the page builds the `video.marks` block of the experiment
//! live (copy and download). One self-contained file and its pictures
//! (`<name>/review/frame-NNNNNN.png`): no external script, it works from `file://`.
//!
//! Coordinates: a picture of `w x h` px shows the region `[x, y, rw, rh]` of the full
//! frame; a point `u` px from the picture's left edge lies at `x + u rw / w - 1/2` in
//! full-frame pixels whose centres are whole numbers (the detector's and the marks'
//! convention), and likewise down.

use super::OutputFile;
use crate::config::Experiment;
use crate::detect::summary::{DetectionSummary, ReviewPicture};
use crate::fit::FitResult;
use crate::series::AngleRow;
use anyhow::{Context, Result};
use serde::Serialize;
use std::collections::BTreeMap;

/// What the page's script reads (embedded as JSON).
#[derive(Serialize)]
struct ReviewData<'a> {
    name: &'a str,
    material: &'a str,
    /// The experiment file, as the reports name it.
    experiment_file: &'a str,
    /// The region of interest `[x, y, w, h]` and the pivot, full-frame px.
    region: [u32; 4],
    pivot: [f64; 2],
    /// The experiment's `video.marks`, by frame number.
    marks: BTreeMap<String, [[f64; 2]; 2]>,
    frames: Vec<FrameView>,
    limits: Limits,
}

#[derive(Serialize)]
struct Limits {
    flagged: usize,
    hold: usize,
    side: usize,
}

/// One frame of the page.
#[derive(Serialize)]
struct FrameView {
    frame: u64,
    t_s: f64,
    status: &'static str,
    /// The gate's reason, `-` when none (a frame flagged after the pass, or marked).
    flag: &'static str,
    /// The angle in the angle series (corrected, marked, or as detected), degrees.
    angle_deg: Option<f64>,
    detected_deg: Option<f64>,
    predicted_deg: Option<f64>,
    quality: Option<f64>,
    /// The picture, relative to the page, and its size.
    picture: Option<String>,
    width: usize,
    height: usize,
    release: bool,
}

/// The page and its pictures, under `<name>/`.
pub(super) fn review_files(
    exp: &Experiment,
    experiment_file: &str,
    d: &DetectionSummary,
    fit: &FitResult,
    rows: &[AngleRow],
    pictures: &[(ReviewPicture, Vec<u8>)],
) -> Result<Vec<OutputFile>> {
    let pic = |frame: u64| pictures.iter().find(|(p, _)| p.frame == frame);
    // The angle series' row of a frame, by its time (the CSV keeps 6 decimals).
    let row_at = |t: f64| rows.iter().find(|r| (r.t_s - t).abs() < 5e-6);
    let mut frames: BTreeMap<u64, FrameView> = BTreeMap::new();
    let view = |frame: u64, t_s: f64, flag: &'static str, release: bool| {
        let p = pic(frame).map(|(p, _)| p);
        let row = row_at(t_s);
        FrameView {
            frame,
            t_s,
            status: row.map_or("missing", |r| r.status.as_str()),
            flag,
            angle_deg: row.and_then(|r| r.angle_rad).map(f64::to_degrees),
            detected_deg: p.and_then(|p| p.detected_rad).map(f64::to_degrees),
            predicted_deg: p.and_then(|p| p.predicted_rad).map(f64::to_degrees),
            quality: p.map(|p| p.quality),
            picture: p.map(|p| format!("review/{}", p.file)),
            width: p.map_or(0, |p| p.width),
            height: p.map_or(0, |p| p.height),
            release,
        }
    };
    for f in &d.flagged {
        let flag = f.flag.map_or("-", |f| f.as_str());
        frames.insert(f.frame, view(f.frame, f.t_s, flag, false));
    }
    // The release frame: the first row after the release (rows are consecutive frames
    // from the first one measured).
    if let Some(r) = &fit.release {
        let first = exp
            .file
            .video
            .as_ref()
            .and_then(|v| v.frames)
            .map_or(0, |f| f[0]);
        if let Some(i) = rows.iter().position(|row| row.t_s > r.t_s) {
            let frame = first + i as u64;
            let t = rows[i].t_s;
            let flag = frames.get(&frame).map_or("-", |f| f.flag);
            frames.insert(frame, view(frame, t, flag, true));
        }
    }
    let marks = exp
        .file
        .video
        .as_ref()
        .map(|v| v.marks.iter().map(|(k, m)| (k.to_string(), *m)).collect())
        .unwrap_or_default();
    let data = ReviewData {
        name: &exp.name,
        material: &exp.material,
        experiment_file,
        region: d.roi,
        pivot: d.pivot_px,
        marks,
        frames: frames.into_values().collect(),
        limits: Limits {
            flagged: crate::detect::tuning::MAX_FLAGGED,
            hold: crate::detect::tuning::HOLD_FRAMES,
            side: crate::detect::tuning::MAX_SIDE,
        },
    };
    let json = script_json(&data)?;
    let mut ctx = tera::Context::new();
    ctx.insert("name", &exp.name);
    ctx.insert("material", &exp.material);
    ctx.insert("data", &json);
    ctx.insert("pictures", &pictures.len());
    ctx.insert("flagged", &d.flagged.len());
    ctx.insert("limits", &data.limits);
    ctx.insert("camera", &d.camera.map(|c| c.describe()));
    ctx.insert(
        "camera_from",
        &d.camera.and_then(|c| c.from_s).map(|t| format!("{t:.1}")),
    );
    ctx.insert("verdict", &d.verdict.as_ref().map(|v| v.label()));
    ctx.insert("seen", &d.verdict.as_ref().map(|v| v.seen.describe()));
    ctx.insert(
        "failed",
        &d.verdict.as_ref().map_or(Vec::new(), |v| {
            v.failed()
                .map(|c| format!("{}: {}", c.check, c.reason))
                .collect::<Vec<_>>()
        }),
    );
    let html = super::templates()?
        .render("review.html", &ctx)
        .context("template `review.html`")?;
    let mut files: Vec<OutputFile> = pictures
        .iter()
        .map(|(p, png)| OutputFile::new(format!("{}/review/{}", exp.name, p.file), png.clone()))
        .collect();
    files.push(OutputFile::new(format!("{}/review.html", exp.name), html));
    Ok(files)
}

/// `data` as JSON to embed in a `<script>` element: `</` would end the element, and
/// `<!--` would turn the script's parsing state (the page would lose its script), so
/// both are escaped (JSON reads `<\/` as `</` and `\u003c` as `<`).
fn script_json<T: Serialize>(data: &T) -> Result<String> {
    Ok(serde_json::to_string(data)?
        .replace("</", "<\\/")
        .replace("<!--", "\\u003c!--"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_json_cannot_end_its_script_or_open_a_comment() {
        let evil = "Steel <!--<script></script>";
        let json = script_json(&serde_json::json!({ "material": evil })).unwrap();
        assert!(!json.contains("<!--") && !json.contains("</"), "{json}");
        let back: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(back["material"], evil);
    }

    /// A camera found moving after the first look: the page says which pictures are
    /// steadied, not every one.
    #[test]
    fn a_camera_found_moving_late_is_said_steadied_from_then_on() {
        let render = |from: Option<&str>| {
            let mut ctx = tera::Context::new();
            for k in ["name", "material", "data"] {
                ctx.insert(k, "x");
            }
            ctx.insert("pictures", &0);
            ctx.insert("flagged", &0);
            let limits = Limits {
                flagged: 1,
                hold: 1,
                side: 1,
            };
            ctx.insert("limits", &limits);
            ctx.insert("camera", &Some("RMS 1.00 px and 0.100 deg, at most 2.0 px"));
            ctx.insert("camera_from", &from);
            ctx.insert("verdict", &None::<String>);
            ctx.insert("seen", &None::<String>);
            ctx.insert("failed", &Vec::<String>::new());
            super::super::templates()
                .unwrap()
                .render("review.html", &ctx)
                .unwrap()
        };
        let late = render(Some("12.0"));
        assert!(
            late.contains("each picture from 12.0 s on is steadied onto the video's first frame"),
            "{late}"
        );
        let all = render(None);
        assert!(
            all.contains("each picture is steadied onto the video's first frame"),
            "{all}"
        );
    }
}
