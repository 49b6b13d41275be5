//! `rollfric init VIDEO`: a newcomer's first experiment file. The video is measured once
//! (as `build` will measure it), and what that finds (the wire's polarity, pivot and
//! region, the release from a held start, the period) is written into a commented YAML
//! beside the video, with every geometry key left for the rig's own measurements.

use crate::config::Manifest;
use crate::detect::{self, DetectOptions, Status, VideoInput};
use crate::fit;
use crate::fsutil;
use crate::series::AngleSeries;
use anyhow::{bail, Context, Result};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The flags of `rollfric init` (defined here only).
#[derive(clap::Args)]
pub struct InitArgs {
    /// The video of the pendulum.
    video: PathBuf,
    /// Where to write the experiment file. Default: beside the video, `<video stem>.yaml`.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also list the new file in this manifest (appended to its `experiments:` list; a
    /// manifest that does not exist yet is made).
    #[arg(long)]
    manifest: Option<PathBuf>,
    /// Region of interest `x,y,width,height` (px): which pendulum, when the frame holds
    /// more than one (written into the file's `video.roi`).
    #[arg(long, value_delimiter = ',')]
    roi: Option<Vec<u32>>,
    /// Pivot `x,y` (px; may lie outside the frame): which pendulum, when the frame holds
    /// more than one (written into the file's `video.pivot`).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pivot: Option<Vec<f64>>,
    /// Replace an existing experiment file.
    #[arg(long)]
    force: bool,
}

/// What the measurement of the video found, for the file's comments.
struct Found {
    frames: usize,
    duration_s: f64,
    width: u32,
    height: u32,
    dark: bool,
    pivot: [f64; 2],
    roi: [u32; 4],
    /// The region and the pivot `--roi` and `--pivot` gave, if any.
    given_roi: Option<[u32; 4]>,
    given_pivot: Option<[f64; 2]>,
    ok_share: f64,
    /// (frame, time s, held for s) of a release from a held start.
    release: Option<(u64, f64, f64)>,
    /// The full swing as the fit measures it (twice the half-swing time), s.
    period_s: Option<f64>,
    /// A suspect detection: its label (`suspect (period, stalls)`) and each failed
    /// check's `name: reason`.
    suspect: Option<(String, Vec<String>)>,
    /// What the video's straight lines say of the lens.
    lens: LensSeen,
}

/// The lens as the video's own straight lines show it (`rollfric lens`'s fit).
#[derive(Debug, Clone, PartialEq)]
enum LensSeen {
    /// Not fitted: the reason (too few straight lines, most often).
    Unknown(String),
    /// The lines are straight as far as they show (`k1`, `u_k1`: not worth giving).
    Straight(f64, f64),
    /// They bend: the fitted `k1`, `u_k1`, and the straight lines in a frame (median).
    Bent(f64, f64, usize),
}

/// The lens of `video` from its own straight lines.
fn lens_seen(video: &Path) -> LensSeen {
    match crate::lens::plumb::fit_video(video, 5, 10) {
        Ok(f) if crate::lens::plumb::worth_giving(f.k1, f.u_k1) => {
            let mut lines: Vec<f64> = f.frames.iter().map(|(_, p)| p.lines as f64).collect();
            LensSeen::Bent(
                f.k1,
                f.u_k1,
                crate::numerics::upper_median(&mut lines) as usize,
            )
        }
        Ok(f) => LensSeen::Straight(f.k1, f.u_k1),
        Err(e) => LensSeen::Unknown(format!("{e:#}")),
    }
}

pub fn init(a: InitArgs) -> Result<String> {
    let out = match &a.output {
        Some(o) => o.clone(),
        None => a.video.with_extension("yaml"),
    };
    let mut inputs = vec![("the video", a.video.as_path())];
    if let Some(m) = &a.manifest {
        inputs.push(("the manifest", m.as_path()));
    }
    for (what, input) in inputs {
        if crate::clobber::same_file(&out, input) {
            bail!(
                "-o {}: that is {what} ({}); the experiment file would replace it",
                out.display(),
                input.display()
            );
        }
    }
    if out.exists() && !a.force {
        bail!(
            "{}: already exists; give another `-o`, or `--force` to replace it",
            out.display()
        );
    }
    if a.video.extension().is_some_and(|e| e == "yaml") {
        bail!("{}: expected a video, not a YAML file", a.video.display());
    }
    let mut opts = DetectOptions::default();
    match a.roi.as_deref() {
        None => {}
        Some(&[x, y, w, h]) if w > 0 && h > 0 => {
            opts.roi = Some(crate::video::Roi { x, y, w, h });
        }
        Some(v) => {
            bail!("--roi: expected x,y,width,height (px, width and height at least 1), got {v:?}")
        }
    }
    match a.pivot.as_deref() {
        None => {}
        Some(&[x, y]) if x.is_finite() && y.is_finite() => opts.pivot = Some([x, y]),
        Some(v) => bail!("--pivot: expected x,y (px), got {v:?}"),
    }
    let mut found = measure(&a.video, &opts)?;
    found.lens = lens_seen(&a.video);
    let dir = out.parent().filter(|p| !p.as_os_str().is_empty());
    let video_rel = relative_to(&a.video, dir.unwrap_or(Path::new(".")))?;
    let name = out
        .file_stem()
        .and_then(|s| s.to_str())
        .context("the output file needs a name")?
        .to_string();
    let text = yaml(&name, &video_rel, &found);
    fsutil::write_atomic(&out, text.as_bytes())?;
    let mut msg = format!(
        "{}: {} frames, {} wire, the wire found in {:.0} % of them; wrote {}: fill in its \
         `geometry` (every value marked FILL IN), then `rollfric fit {}`\n",
        a.video.display(),
        found.frames,
        if found.dark { "dark" } else { "light" },
        100.0 * found.ok_share,
        out.display(),
        out.display()
    );
    if let Some((label, reasons)) = &found.suspect {
        let _ = writeln!(
            msg,
            "{}: detection {label}: {}; a result from it will be suspect (warning \
             `detection`) until the wire is followed: draw a frame's steps (`rollfric detect \
             {} -o angles.csv --steps N`), then run `init` again with `--roi` or `--pivot` \
             (and `--force` to replace the file)",
            a.video.display(),
            reasons.join("; "),
            a.video.display()
        );
    }
    if let LensSeen::Bent(k1, u, _) = found.lens {
        let _ = writeln!(
            msg,
            "{}: its straight lines bend as through a wide lens (k1 = {k1:.4} +- {u:.4}): \
             the file gives it as `video.lens`; a ruled sheet filmed with the same camera \
             calibrates it better (`rollfric lens`)",
            a.video.display()
        );
    }
    if let Some(m) = &a.manifest {
        if add_to_manifest(m, &out)? {
            let _ = writeln!(msg, "{}: lists {} now", m.display(), out.display());
        } else {
            let _ = writeln!(msg, "{}: lists {} already", m.display(), out.display());
        }
    }
    Ok(msg)
}

/// Measure the video as `build` would (with `opts`: a region or a pivot, or none), and
/// the series as `fit` would.
fn measure(video: &Path, opts: &DetectOptions) -> Result<Found> {
    let file = detect::VideoFile::open(video)?;
    let d = detect::detect_from(&file, opts)?;
    let rows: Vec<_> = d
        .rows
        .iter()
        .filter(|r| r.angle_rad.is_some() && r.status != Status::Missing)
        .collect();
    let series = AngleSeries::new(
        rows.iter().map(|r| r.t_s).collect(),
        rows.iter().filter_map(|r| r.angle_rad).collect(),
    );
    // Turning points, period and a held start's release, as the fit measures them; a
    // series too irregular to fit leaves them out of the comments.
    let m = fit::measure(&series).ok();
    let release = m.as_ref().and_then(|m| m.release.as_ref()).map(|r| {
        let frame = rows.get(r.frame).map_or(0, |row| row.frame);
        (frame, r.t_s, r.held_s)
    });
    let first = d.rows.first().map_or(0.0, |r| r.t_s);
    let last = d.rows.last().map_or(0.0, |r| r.t_s);
    let info = file.info();
    Ok(Found {
        frames: d.rows.len(),
        duration_s: last - first,
        width: info.width,
        height: info.height,
        dark: d.dark_wire,
        pivot: d.pivot_px,
        roi: d.roi,
        given_roi: opts.roi.map(|r| [r.x, r.y, r.w, r.h]),
        given_pivot: opts.pivot,
        ok_share: d.count(Status::Ok) as f64 / d.rows.len().max(1) as f64,
        release,
        period_s: m.map(|m| m.period_s),
        lens: LensSeen::Unknown(String::new()),
        suspect: (d.verdict.verdict != crate::verdict::Status::Ok).then(|| {
            (
                d.verdict.label(),
                d.verdict
                    .failed()
                    .map(|c| format!("{}: {}", c.check, c.reason))
                    .collect(),
            )
        }),
    })
}

/// `path` relative to `dir` when it lies under it, else as given (made absolute).
fn relative_to(path: &Path, dir: &Path) -> Result<String> {
    let p =
        std::fs::canonicalize(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let d =
        std::fs::canonicalize(dir).with_context(|| format!("{}: no such folder", dir.display()))?;
    // Inside the folder, or beside it with `..` steps (a manifest in `experiments/`
    // listing `../my-video.yaml`), so that the files move together; else absolute.
    let rel = match p.strip_prefix(&d) {
        Ok(r) => r.to_path_buf(),
        Err(_) => crate::build::pathdiff(&d, &p).map_or(p, PathBuf::from),
    };
    rel.to_str()
        .map(str::to_string)
        .with_context(|| format!("{}: the path is not UTF-8", rel.display()))
}

/// A YAML scalar in double quotes (escaping what YAML needs).
fn quoted(s: &str) -> String {
    serde_json::to_string(s).expect("a string is JSON")
}

/// The experiment file, with its comments.
fn yaml(name: &str, video: &str, f: &Found) -> String {
    let mut y = String::new();
    let _ = writeln!(
        y,
        "# Experiment for {video}, written by `rollfric init`.\n\
         # 1. Fill in every value marked FILL IN under `geometry` (measured on the rig; each\n\
         #    comment says how). Until then `rollfric fit` and `build` refuse this file.\n\
         # 2. `rollfric fit {name}.yaml` measures s_r; `rollfric build` builds the reports\n\
         #    of the experiments its manifest lists (`rollfric init --manifest` adds one).\n\
         # Every key, its unit and default: docs/experiment.md (or `rollfric schema`).\n"
    );
    let _ = writeln!(y, "name: {}", quoted(name));
    let _ = writeln!(
        y,
        "# The plate's material, as the report's tables name it.\nmaterial: {}",
        quoted(name)
    );
    let _ = writeln!(
        y,
        "notes: {}\n",
        quoted(&format!(
            "Lab recording {video} ({}x{} px, {} frames over {:.1} s).",
            f.width, f.height, f.frames, f.duration_s
        ))
    );
    y.push_str(
        "geometry:\n  incline:\n\
         \x20   # The plate's ends: the height difference h between them and the plate's\n\
         \x20   # length l, m (alpha = asin(h / l), Eq. 36). Measure h with a ruler from the\n\
         \x20   # table to the plate's top face at each end.\n\
         \x20   h_m: null   # FILL IN\n\
         \x20   l_m: null   # FILL IN\n\
         \x20   # Or the inclination itself, degrees (a digital level on the plate), instead:\n\
         \x20   # angle_deg: null\n\
         \x20 pendulum:\n\
         \x20   # d: from the fulcrum (where the wire is held) to the ball's centre, m. Or\n\
         \x20   # `contact_length_m`: from the fulcrum to the ball's contact point (Eq. 37).\n",
    );
    if let Some(t) = f.period_s {
        // Small-angle period of a solid ball rolling on the incline: omega_0^2 =
        // 5 g sin(alpha) / (7 L) (ERRATA §2), so L = 5 g sin(alpha) T^2 / (28 pi^2).
        let l_per_sin = 5.0 * 9.81 * t * t / (28.0 * std::f64::consts::PI.powi(2));
        let _ = writeln!(
            y,
            "    # The video's full swing takes {t:.3} s: a solid ball on an incline alpha then\n\
             \x20   # hangs L = {l_per_sin:.4} m x sin(alpha) from its contact point (small swings,\n\
             \x20   # ERRATA §2); the fit's `period` check compares that with d."
        );
    }
    y.push_str(
        "    d_m: null   # FILL IN\n\
         \x20 ball:\n\
         \x20   radius_m: null   # FILL IN: half the diameter from a caliper, m\n\
         \x20   mass_kg: null    # FILL IN: a balance, kg (or `density_kg_m3` instead)\n\
         \x20 # g_m_s2: 9.81     # local gravity, m/s^2\n\n",
    );
    let polarity = if f.dark { "dark" } else { "light" };
    let pivot = format!("[{:.1}, {:.1}]", f.pivot[0], f.pivot[1]);
    let [x, yy, w, h] = f.roi;
    let roi = format!("[{x}, {yy}, {w}, {h}]");
    let _ = writeln!(
        y,
        "video:\n  path: {}\n  # The detector found a {polarity} wire; it looks again on every build.\n  \
         polarity: {polarity}\n  \
         # It found the pivot at {pivot} px and worked in the region {roi}\n  \
         # (x, y, width, height, px). Give them here only if a build finds them wrong:\n  \
         # pivot: {pivot}\n  \
         # roi: {roi}",
        quoted(video)
    );
    if let Some([x, yy, w, h]) = f.given_roi {
        let _ = writeln!(
            y,
            "  # Given to `init` (--roi): the pendulum measured, of those in the frame.\n  \
             roi: [{x}, {yy}, {w}, {h}]"
        );
    }
    if let Some([px, py]) = f.given_pivot {
        let _ = writeln!(
            y,
            "  # Given to `init` (--pivot): the pendulum measured, of those in the frame.\n  \
             pivot: [{px}, {py}]"
        );
    }
    if let Some((label, reasons)) = &f.suspect {
        let _ = writeln!(
            y,
            "  # CAUTION: the detection is {label}: it may not have followed a wire.\n  \
             # A result from this file will be suspect (warning `detection`) until it does."
        );
        for r in reasons {
            let one_line: String = r
                .chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect();
            let _ = writeln!(y, "  #   {one_line}");
        }
        y.push_str(
            "  # `rollfric detect VIDEO -o angles.csv --steps N` draws what it saw in frame N;\n\
             \x20 # give `roi` or `pivot` above to say where the wire is.\n",
        );
    }
    match &f.lens {
        &LensSeen::Bent(k1, u, lines) => {
            let _ = writeln!(
                y,
                "  # The video's straight lines ({lines} in a frame) bend as through a wide \
                 lens,\n  # k1 = {k1:.4} +- {u:.4} as `rollfric lens` fits it from them: every \
                 angle is measured\n  # through it. A ruled sheet filmed with the same camera \
                 and zoom calibrates\n  # it better (`rollfric lens sheet.mp4`).\n  \
                 lens: {{k1: {k1:.4}, u_k1: {:.4}}}",
                u.max(0.0001)
            );
        }
        &LensSeen::Straight(k1, u) => {
            let _ = writeln!(
                y,
                "  # The video's straight lines are straight as far as they show (the lens \
                 fit\n  # gives k1 = {k1:.4} +- {u:.4}): no lens given."
            );
        }
        LensSeen::Unknown(why) => {
            let why: String = why
                .chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect();
            let _ = writeln!(
                y,
                "  # The lens could not be checked from the video ({why}).\n  # A wide \
                 lens (a phone's 0.5x) scales the swing: film a ruled sheet with the\n  # \
                 same camera and give `lens` (`rollfric lens sheet.mp4`)."
            );
        }
    }
    match f.release {
        Some((frame, t, held)) => {
            let _ = writeln!(
                y,
                "  # The ball is held still for {held:.2} s, then let go at {t:.3} s (frame \
                 {frame}):\n  # the fit starts there; the frames before are reported, not fitted."
            );
        }
        None => y.push_str("  # No held start: the ball moves from the first frame.\n"),
    }
    y.push_str(
        "  # A frame the detector got wrong: two points on the wire, px, per frame number\n\
         \x20 # (the build's review page, reports/<name>/review.html, writes them as you click):\n\
         \x20 # marks:\n\
         \x20 #   120: [[412.0, 96.0], [431.5, 310.0]]\n",
    );
    y
}

/// Append `exp` to the manifest's `experiments:` list, keeping the file's text (and
/// comments); an empty `experiments: []` becomes a block list. Refuse when the list is
/// not a block list at the end of the file. Returns whether it added `exp` (a manifest
/// that lists it already is left as it is).
fn add_to_manifest(manifest: &Path, exp: &Path) -> Result<bool> {
    if !manifest.exists() {
        // A first manifest: made, listing the new file.
        let dir = manifest.parent().filter(|p| !p.as_os_str().is_empty());
        if let Some(d) = dir {
            std::fs::create_dir_all(d)
                .with_context(|| format!("{}: cannot create folder", d.display()))?;
        }
        let rel = relative_to(exp, dir.unwrap_or(Path::new(".")))?;
        let text = format!(
            "# The experiments of the report set (`rollfric build --manifest {}`).\n\
             title: Rolling friction\nexperiments:\n  - {}\n",
            manifest.display(),
            quoted(&rel)
        );
        Manifest::load_text(manifest, &text)?;
        fsutil::write_atomic(manifest, text.as_bytes())?;
        return Ok(true);
    }
    let text = fsutil::read_text_limited(manifest, fsutil::MAX_YAML_BYTES)?;
    let lines: Vec<&str> = text.lines().collect();
    // `experiments: []`, the list of a manifest not yet listing anything.
    let empty = lines.iter().position(|l| {
        let l = l.split('#').next().unwrap_or("").trim_end();
        l.strip_prefix("experiments:")
            .is_some_and(|v| v.trim().replace(' ', "") == "[]")
    });
    let listed = match Manifest::load(manifest) {
        Ok((_, listed)) => listed,
        Err(_) if empty.is_some() => Vec::new(),
        Err(e) => return Err(e),
    };
    let dir = manifest.parent().filter(|p| !p.as_os_str().is_empty());
    let rel = relative_to(exp, dir.unwrap_or(Path::new(".")))?;
    let canon = std::fs::canonicalize(exp)?;
    if listed
        .iter()
        .any(|p| std::fs::canonicalize(p).is_ok_and(|p| p == canon))
    {
        return Ok(false);
    }
    if let (Some(i), true) = (empty, listed.is_empty()) {
        let mut new: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        new[i] = format!("experiments:\n  - {}", quoted(&rel));
        let new = new.join("\n") + "\n";
        Manifest::load_text(manifest, &new)?;
        fsutil::write_atomic(manifest, new.as_bytes())?;
        return Ok(true);
    }
    let last = lines
        .iter()
        .rposition(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (last, indent) = last
        .and_then(|i| {
            let l = lines[i];
            let t = l.trim_start();
            t.starts_with("- ").then(|| (i, &l[..l.len() - t.len()]))
        })
        .with_context(|| {
            format!(
                "{}: its `experiments:` list is not a block list (`  - file.yaml` lines) at the \
                 end of the file; add `{rel}` to it by hand",
                manifest.display()
            )
        })?;
    let mut new = lines[..=last].join("\n");
    let _ = write!(new, "\n{indent}- {}\n", quoted(&rel));
    for l in &lines[last + 1..] {
        let _ = writeln!(new, "{l}");
    }
    // The edited manifest must list exactly one more file, the new one.
    let now: Manifest = serde_saphyr::from_str(&new)
        .with_context(|| format!("{}: the edited manifest does not read", manifest.display()))?;
    if now.experiments.len() != listed.len() + 1 {
        bail!(
            "{}: appending `{rel}` did not add it to `experiments:`; add it by hand",
            manifest.display()
        );
    }
    fsutil::write_atomic(manifest, new.as_bytes())?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Experiment;

    /// The geometry a user fills in.
    fn fill(text: &str) -> String {
        text.replace("h_m: null", "h_m: 0.142")
            .replace("l_m: null", "l_m: 1.5")
            .replace("d_m: null", "d_m: 0.2")
            .replace("radius_m: null", "radius_m: 0.0127")
            .replace("mass_kg: null", "mass_kg: 0.067")
    }

    fn found() -> Found {
        Found {
            frames: 300,
            duration_s: 9.97,
            width: 640,
            height: 480,
            dark: true,
            pivot: [320.5, -12.0],
            roi: [100, 0, 440, 400],
            given_roi: None,
            given_pivot: None,
            ok_share: 0.99,
            release: Some((31, 1.03, 1.0)),
            period_s: Some(1.334),
            suspect: None,
            lens: LensSeen::Unknown("too few straight lines".into()),
        }
    }

    #[test]
    fn the_file_refuses_until_filled_in_then_loads() {
        let d = tempfile::tempdir().unwrap();
        let text = yaml("green", "green video.mp4", &found());
        let p = d.path().join("green.yaml");
        std::fs::write(&p, &text).unwrap();
        let e = format!("{:#}", Experiment::load(&p).unwrap_err());
        assert!(e.contains("green.yaml"), "{e}");
        std::fs::write(&p, fill(&text)).unwrap();
        let exp = Experiment::load(&p).expect("filled in, it loads");
        assert_eq!(exp.name, "green");
        assert!(text.contains("L = 0.3159 m x sin(alpha)"), "{text}");
        assert!(text.contains("let go at 1.030 s (frame 31)"), "{text}");
        assert!(text.contains("polarity: dark"));
        assert!(!text.contains("CAUTION"), "{text}");
    }

    /// A lens the video's lines show bent is given (`video.lens`) and the file loads with
    /// it; straight lines, or too few, are said in a comment and give none.
    #[test]
    fn a_lens_the_lines_show_is_given_and_straight_lines_are_said() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("wide.yaml");
        let bent = Found {
            lens: LensSeen::Bent(-0.2301, 0.0011, 5),
            ..found()
        };
        let text = yaml("wide", "wide.mp4", &bent);
        assert!(text.contains("lens: {k1: -0.2301, u_k1: 0.0011}"), "{text}");
        std::fs::write(&p, fill(&text)).unwrap();
        let exp = Experiment::load(&p).expect("loads with its lens");
        let lens = exp
            .file
            .video
            .as_ref()
            .and_then(|v| v.lens)
            .expect("video.lens");
        assert_eq!((lens.k1, lens.u_k1), (-0.2301, 0.0011));
        for (seen, says) in [
            (
                LensSeen::Straight(-0.01, 0.02),
                "straight as far as they show",
            ),
            (
                LensSeen::Unknown("too few straight lines".into()),
                "could not be checked from the video (too few straight lines)",
            ),
        ] {
            let text = yaml(
                "plain",
                "plain.mp4",
                &Found {
                    lens: seen,
                    ..found()
                },
            );
            assert!(text.contains(says), "{text}");
            std::fs::write(&p, fill(&text)).unwrap();
            let exp = Experiment::load(&p).expect("loads");
            assert!(exp.file.video.as_ref().and_then(|v| v.lens).is_none());
        }
    }

    /// A suspect detection is said in the file, each failed check on a comment line of
    /// its own, and the file still loads once filled in.
    #[test]
    fn a_suspect_detection_is_said_in_the_file() {
        let d = tempfile::tempdir().unwrap();
        let f = Found {
            suspect: Some((
                "suspect (period)".into(),
                vec!["period: varies by 80 %\nswing to swing".into()],
            )),
            ..found()
        };
        let text = yaml("rope", "rope.mp4", &f);
        assert!(
            text.contains("# CAUTION: the detection is suspect (period)"),
            "{text}"
        );
        assert!(
            text.contains("  #   period: varies by 80 % swing to swing\n"),
            "{text}"
        );
        let p = d.path().join("rope.yaml");
        std::fs::write(&p, fill(&text)).unwrap();
        Experiment::load(&p).expect("filled in, it loads");
    }

    #[test]
    fn appends_to_a_block_list_once_and_fills_an_empty_one() {
        let d = tempfile::tempdir().unwrap();
        let m = d.path().join("manifest.yaml");
        std::fs::write(&m, "# the set\ntitle: t\nexperiments:\n  - a.yaml\n# end\n").unwrap();
        std::fs::write(d.path().join("a.yaml"), "").unwrap();
        std::fs::write(d.path().join("b.yaml"), "").unwrap();
        assert!(add_to_manifest(&m, &d.path().join("b.yaml")).unwrap());
        let text = std::fs::read_to_string(&m).unwrap();
        assert_eq!(
            text,
            "# the set\ntitle: t\nexperiments:\n  - a.yaml\n  - \"b.yaml\"\n# end\n"
        );
        // A second time (`init --force` again): listed already, the file as it was.
        assert!(!add_to_manifest(&m, &d.path().join("b.yaml")).unwrap());
        assert_eq!(std::fs::read_to_string(&m).unwrap(), text);
        // No manifest yet: one is made, listing the file from its own folder.
        let first = d.path().join("experiments/manifest.yaml");
        assert!(add_to_manifest(&first, &d.path().join("b.yaml")).unwrap());
        let (_, listed) = Manifest::load(&first).unwrap();
        assert_eq!(listed, [d.path().join("experiments/../b.yaml")]);
        std::fs::write(&m, "title: t\nexperiments: [ ]  # none yet\n").unwrap();
        assert!(add_to_manifest(&m, &d.path().join("b.yaml")).unwrap());
        let text = std::fs::read_to_string(&m).unwrap();
        assert_eq!(text, "title: t\nexperiments:\n  - \"b.yaml\"\n");
        std::fs::write(&m, "experiments: [a.yaml]\ntitle: t\n").unwrap();
        let e = add_to_manifest(&m, &d.path().join("b.yaml")).unwrap_err();
        assert!(format!("{e:#}").contains("by hand"), "{e:#}");
    }
}
