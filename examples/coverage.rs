//! The coverage of `s_r`'s 95 % intervals on the robustness sweep's twins: every scene
//! kept by `ROBUSTNESS_KEEP=DIR make robustness` (its experiment file, detected angles,
//! truth and swing scale) fitted again as `rollfric fit` fits it, and its interval
//! compared with the twin's true `s_r`. Prints one line per scene, then the share of
//! scenes whose interval holds the truth and the median half-width, for the calibrated
//! interval (`s_r_interval95_m`) and for the least-squares one (`s_r_ci95_m`), over
//! every scene and over the scenes whose verdict is `ok`.
//!
//! `cargo run --release --example coverage -- DIR` (`make coverage` runs the sweep, then
//! this).

use anyhow::{Context, Result};
use rollfric::config::Experiment;
use rollfric::pipeline::{self, Angles, Overrides, Source};
use rollfric::series::AngleTable;
use std::path::Path;

/// One scene's intervals against its truth.
struct Row {
    err: f64,
    ok: bool,
    /// Half-widths relative to s_r, and whether each interval holds the truth:
    /// calibrated, least-squares.
    half: [f64; 2],
    holds: [bool; 2],
}

fn scene(dir: &Path) -> Result<Option<(String, Row)>> {
    let yaml = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "yaml"))
        .with_context(|| format!("{}: no experiment file", dir.display()))?;
    let exp = Experiment::load(&yaml)?;
    let csv = dir.join("angles.csv");
    let table = AngleTable::parse_csv(
        &std::fs::read_to_string(&csv).with_context(|| format!("{}", csv.display()))?,
    )?;
    let swing_scale = std::fs::read_to_string(dir.join("swing_scale.txt"))
        .ok()
        .and_then(|s| s.trim().parse::<f64>().ok());
    let angles = Angles {
        source: Source::Twin,
        table,
        detection: None,
    };
    let Ok(mut a) = pipeline::analyze(&exp, &angles, Overrides::default()) else {
        return Ok(None);
    };
    // As the build computes it, with the video's swing scale.
    let f = &mut a.fit;
    let u = rollfric::uncertainty::angle_uncertainty(&exp.pendulum, &a.measurement, f, swing_scale);
    f.s_r_interval95_m = u.interval95_m;
    let truth = a.truth_s_r_m.context("a twin without its truth")?;
    let s = f.s_r_m;
    let rel = |iv: [f64; 2]| (iv[1] - iv[0]) / 2.0 / s;
    let holds = |iv: [f64; 2]| iv[0] <= truth && truth <= iv[1];
    let row = Row {
        err: s / truth - 1.0,
        ok: !a.verdict.blocks(),
        half: [rel(f.s_r_interval95_m), rel(f.s_r_ci95_m)],
        holds: [holds(f.s_r_interval95_m), holds(f.s_r_ci95_m)],
    };
    let line = format!(
        "{:+8.3} % | {:6.3} % {:<5} | {:6.3} % {:<5} | stat {:.3} % drift {:.3} % scale {:.3} % | {} | {}",
        100.0 * row.err,
        100.0 * row.half[0],
        if row.holds[0] { "holds" } else { "MISS" },
        100.0 * row.half[1],
        if row.holds[1] { "holds" } else { "MISS" },
        100.0 * u.u_stat_m / s,
        100.0 * u.u_drift_m / s,
        100.0 * u.u_scale_m / s,
        swing_scale.map_or("-".to_string(), |x| format!("{x:.4}")),
        a.verdict.label(),
    );
    Ok(Some((line, row)))
}

fn main() -> Result<()> {
    let dir = std::env::args()
        .nth(1)
        .context("usage: coverage DIR (the sweep's ROBUSTNESS_KEEP folder)")?;
    let mut scenes: Vec<_> = std::fs::read_dir(&dir)
        .with_context(|| format!("{dir}: cannot read"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        // The detected scenes whose fit the sweep refused (`unfitted-NNN`) have nothing to cover.
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("scene-"))
        })
        .collect();
    scenes.sort();
    println!(
        "scene      s_r error | calibrated 95 %  | least squares    | the calibrated interval's parts (of s_r) | swing scale | verdict"
    );
    let mut rows = Vec::new();
    let mut refused = 0;
    for s in &scenes {
        let name = s.file_name().unwrap_or_default().to_string_lossy();
        match scene(s)? {
            Some((line, row)) => {
                println!("{name}  {line}");
                rows.push(row);
            }
            None => {
                refused += 1;
                println!("{name}  the fit refused it");
            }
        }
    }
    let median = |mut v: Vec<f64>| {
        if v.is_empty() {
            f64::NAN
        } else {
            rollfric::numerics::upper_median(&mut v)
        }
    };
    for (label, ok_only) in [("every scene fitted", false), ("scenes judged ok", true)] {
        let set: Vec<&Row> = rows.iter().filter(|r| !ok_only || r.ok).collect();
        let n = set.len();
        for (i, name) in [
            "calibrated (s_r_interval95_m)",
            "least squares (s_r_ci95_m)",
        ]
        .iter()
        .enumerate()
        {
            let held = set.iter().filter(|r| r.holds[i]).count();
            println!(
                "{label} ({n}): {name}: holds the truth in {held}/{n} ({:.1} %), median half-width {:.3} %",
                100.0 * held as f64 / n.max(1) as f64,
                100.0 * median(set.iter().map(|r| r.half[i]).collect())
            );
        }
    }
    println!(
        "{} scenes kept, {} fitted, {refused} refused by the fit",
        scenes.len(),
        rows.len()
    );
    Ok(())
}
