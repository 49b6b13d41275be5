//! The twin lies in known ways, and the verdict says so: a wrong pendulum length, viscous
//! damping instead of rolling friction, a corrupted turning point (dropped, and said), a
//! detector whose scale grows with the swing, angles in degrees and an absurd length. Each gives `suspect` with the named check (or
//! a clear refusal), and `rollfric check` exits 1 on an unaccepted `suspect`.

mod common;

use common::root;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn rollfric(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rollfric"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run rollfric")
}

/// The glass experiment's geometry (d = 0.1774 m), measured from a CSV: no reference, no
/// synthetic truth. `d_m` and extra top-level keys are the test's.
fn yaml(dir: &Path, name: &str, d_m: &str, extra: &str) -> PathBuf {
    let text = format!(
        "name: {name}
geometry:
  incline: {{ h_m: 0.142, l_m: 1.500 }}
  pendulum: {{ d_m: {d_m} }}
  ball: {{ radius_m: 0.03175, mass_kg: 1.0458 }}
angles: {name}.csv
{extra}"
    );
    let p = dir.join(format!("{name}.yaml"));
    std::fs::write(&p, text).unwrap();
    p
}

/// The glass twin's angles, 80 s at 25 frames/s with 0.05 deg of noise, as `t_s,angle_rad`.
fn simulated(dir: &Path) -> Vec<(f64, f64)> {
    let csv = dir.join("twin.csv");
    let exp = dir.join("twin.yaml");
    std::fs::write(&exp, common::GLASS_TWIN_YAML).unwrap();
    let out = rollfric(&[
        "simulate",
        exp.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let mut f = l.split(',');
            let t = f.next().unwrap().parse().unwrap();
            let a = f.next().unwrap().parse().unwrap();
            (t, a)
        })
        .collect()
}

fn write_csv(path: &Path, rows: &[(f64, f64)]) {
    let mut s = String::from("t_s,angle_rad\n");
    for (t, a) in rows {
        s.push_str(&format!("{t:.6},{a:.9}\n"));
    }
    std::fs::write(path, s).unwrap();
}

fn fit_json(exp: &Path) -> serde_json::Value {
    let out = rollfric(&["fit", exp.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// A real clip's experiment in `dir`: a plausible geometry (incline 5 deg, r = 12.7 mm,
/// m = 67 g) with pendulum length `d_m`, the clip's video measured.
fn clip_yaml(dir: &Path, clip: &Path, d_m: &str, video_extra: &str) -> PathBuf {
    let p = dir.join(format!("clip-{}.yaml", d_m.replace('.', "_")));
    std::fs::write(
        &p,
        format!(
            "geometry:
  incline: {{ angle_deg: 5 }}
  pendulum: {{ d_m: {d_m} }}
  ball: {{ radius_m: 0.0127, mass_kg: 0.067 }}
video: {{ path: {}{video_extra} }}
",
            clip.display()
        ),
    )
    .unwrap();
    p
}

fn warned(j: &serde_json::Value) -> Vec<String> {
    j["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["check"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn the_twin_as_it_is_is_ok() {
    let d = tempfile::tempdir().unwrap();
    write_csv(&d.path().join("good.csv"), &simulated(d.path()));
    let j = fit_json(&yaml(d.path(), "good", "0.1774", ""));
    assert_eq!(j["verdict"], "ok", "{j}");
    assert_eq!(j["warnings"], serde_json::json!([]));
}

#[test]
fn a_wrong_length_is_suspect_and_check_exits_1_unless_accepted() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    write_csv(&dir.join("long.csv"), &simulated(dir));
    let exp = yaml(dir, "long", "0.25", "");
    let j = fit_json(&exp);
    assert_eq!(j["verdict"], "suspect", "{j}");
    assert_eq!(warned(&j), ["period"], "{j}");
    let w = &j["warnings"][0];
    assert!(
        w["value"].as_f64().unwrap() > 0.2 && w["limit"] == 0.1,
        "{w}"
    );
    let out = rollfric(&["fit", exp.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("verdict          suspect (period)"), "{text}");

    // Built and checked: the page is "measured" (nothing to compare with) and suspect.
    std::fs::write(dir.join("manifest.yaml"), "experiments: [long.yaml]\n").unwrap();
    let build = |out: &str| {
        let o = rollfric(&[
            "build",
            "--manifest",
            dir.join("manifest.yaml").to_str().unwrap(),
            "--out",
            dir.join(out).to_str().unwrap(),
            "--cache",
            dir.join("cache").to_str().unwrap(),
            "-q",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let c = rollfric(&[
            "check",
            "--summary",
            dir.join(out).join("summary.json").to_str().unwrap(),
        ]);
        let page = std::fs::read_to_string(dir.join(out).join("long.html")).unwrap();
        (c, page)
    };
    let (c, page) = build("r1");
    let text = String::from_utf8_lossy(&c.stdout);
    assert_eq!(c.status.code(), Some(1), "{text}");
    assert!(
        text.contains("long                   verdict suspect (period)"),
        "{text}"
    );
    assert!(text.contains("measured: no reference"), "{text}");
    assert!(page.contains("Verdict: suspect (period)"), "{page}");
    assert!(
        page.contains("measured (nothing to compare with)"),
        "{page}"
    );
    assert!(!page.contains("within tolerances"), "{page}");

    yaml(
        dir,
        "long",
        "0.25",
        "accept: [{check: period, reason: \"the length was not measured yet\"}]\n",
    );
    let (c, page) = build("r2");
    let text = String::from_utf8_lossy(&c.stdout);
    assert_eq!(c.status.code(), Some(0), "{text}");
    assert!(
        text.contains("accepted because: the length was not measured yet"),
        "{text}"
    );
    assert!(
        page.contains("(accepted: the length was not measured yet)"),
        "{page}"
    );
}

#[test]
fn viscous_damping_is_suspect_by_its_envelope() {
    let d = tempfile::tempdir().unwrap();
    // The glass pendulum's small-angle frequency, damped exponentially (tau = 30 s)
    // instead of linearly, with 0.05 deg of noise.
    let (r, dd, sin_a) = (0.03175f64, 0.1774f64, 0.142 / 1.5);
    let l = (dd * dd - r * r).sqrt();
    let w = (5.0 * 9.81 * sin_a / (7.0 * l)).sqrt();
    let mut seed = 12345u64;
    let mut uniform = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let rows: Vec<(f64, f64)> = (0..2000)
        .map(|i| {
            let t = i as f64 / 25.0;
            let noise = (-2.0 * uniform().ln()).sqrt()
                * (std::f64::consts::TAU * uniform()).cos()
                * 0.05f64.to_radians();
            let a = 1.6 + 10f64.to_radians() * (-t / 30.0).exp() * (w * t).cos() + noise;
            (t, a)
        })
        .collect();
    write_csv(&d.path().join("viscous.csv"), &rows);
    let j = fit_json(&yaml(d.path(), "viscous", "0.1774", ""));
    assert_eq!(j["verdict"], "suspect", "{j}");
    assert!(warned(&j).contains(&"envelope".to_string()), "{j}");
    assert!(!warned(&j).contains(&"period".to_string()), "{j}");
}

#[test]
fn a_scale_that_grows_with_the_swing_is_suspect_by_its_halves() {
    let d = tempfile::tempdir().unwrap();
    let rows = simulated(d.path());
    // What a detector following the wire's shadow in a tilted view does: every angle
    // about the equilibrium scaled by 1 + 0.04 of its own size against the first swing's
    // (4 % large at the release, 2 % at half that swing). No turning point is an outlier
    // and the period is the pendulum's; only the envelope bends.
    let mut centred: Vec<f64> = rows.iter().map(|r| r.1).collect();
    centred.sort_by(f64::total_cmp);
    let eq = centred[centred.len() / 2];
    let a0 = rows.iter().map(|r| (r.1 - eq).abs()).fold(0.0, f64::max);
    let bent: Vec<(f64, f64)> = rows
        .iter()
        .map(|&(t, a)| (t, eq + (a - eq) * (1.0 + 0.04 * (a - eq).abs() / a0)))
        .collect();
    write_csv(&d.path().join("bent.csv"), &bent);
    let j = fit_json(&yaml(d.path(), "bent", "0.1774", ""));
    assert_eq!(j["verdict"], "suspect", "{j}");
    assert_eq!(warned(&j), ["halves"], "{j}");
    let w = &j["warnings"][0];
    assert!(w["value"].as_f64().unwrap() > 0.02, "{w}");
    assert!(w["reason"].as_str().unwrap().contains("later half"), "{w}");
    // The twin as it is: its halves agree well within the limit.
    write_csv(&d.path().join("good.csv"), &rows);
    let good = fit_json(&yaml(d.path(), "good", "0.1774", ""));
    let h = good["budget"]["angles"]["halves_m"].as_array().unwrap();
    let (e, l) = (h[0].as_f64().unwrap(), h[1].as_f64().unwrap());
    assert!((e / l - 1.0).abs() < 0.01, "{good}");
}

#[test]
fn a_corrupted_turning_point_is_dropped_and_suspect_by_its_outliers_check() {
    let d = tempfile::tempdir().unwrap();
    let mut rows = simulated(d.path());
    // Push the nine samples around the maximum near t = 20 s up by 3 degrees.
    let near = rows
        .iter()
        .enumerate()
        .filter(|(_, (t, _))| (t - 20.0).abs() < 1.2)
        .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
        .unwrap()
        .0;
    for row in &mut rows[near - 4..=near + 4] {
        row.1 += 3f64.to_radians();
    }
    write_csv(&d.path().join("bad.csv"), &rows);
    let j = fit_json(&yaml(d.path(), "bad", "0.1774", ""));
    // The fit drops it (so the residual agrees with the noise again) and says so.
    assert_eq!(j["verdict"], "suspect", "{j}");
    assert_eq!(warned(&j), ["outliers"], "{j}");
    let o = &j["outliers"];
    assert_eq!(o.as_array().unwrap().len(), 1, "{j}");
    assert!(
        (o[0]["t_s"].as_f64().unwrap() - rows[near].0).abs() < 0.1,
        "{o}"
    );
    assert_eq!(o[0]["dropped"], true, "{o}");
}

#[test]
fn degrees_and_absurd_lengths_are_refused() {
    let d = tempfile::tempdir().unwrap();
    let rows: Vec<(f64, f64)> = simulated(d.path())
        .into_iter()
        .map(|(t, a)| (t, a.to_degrees()))
        .collect();
    write_csv(&d.path().join("deg.csv"), &rows);
    let out = rollfric(&["fit", yaml(d.path(), "deg", "0.1774", "").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("are these degrees?"),
        "{err}"
    );

    let out = rollfric(&["fit", yaml(d.path(), "deg", "1e300", "").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("`geometry.pendulum.d_m` = 1e300 m"),
        "{err}"
    );
}

/// The real green-screen clip with a plausible but wrong YAML (the first case):
/// its period says the string is ~3 cm, not 20 cm, so it is `suspect` (period); with the
/// length its period implies, the period check agrees.
#[test]
fn the_real_clip_with_a_wrong_length_is_suspect() {
    let Some(clip) = common::fixture("sborquez_video1_greenscreen.mp4") else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let exp = |d_m: &str| clip_yaml(d.path(), &clip, d_m, "");
    let j = fit_json(&exp("0.20"));
    assert_eq!(j["verdict"], "suspect", "{j}");
    assert!(warned(&j).contains(&"period".to_string()), "{j}");
    // With the length its period implies, what is true of a string pendulum in air:
    // its envelope bends as air damping does, and the halves of its turning points
    // disagree.
    let j = fit_json(&exp("0.0296"));
    assert_eq!(warned(&j), ["halves"], "{j}");
}

/// A twin's video measured about a pivot given 20 px too high (along the wire, which
/// hangs nearly straight down): farther than the detector's refinement may move it, so
/// every angle's swing is scaled and s_r is wrong by over 5 %. The wire's own direction
/// (each frame's free line fit) disagrees with the angles about that pivot, and the
/// verdict is `suspect` (pivot); about the pivot the detector finds itself, it agrees.
#[test]
fn the_split_screen_clip_with_a_plausible_yaml_is_suspect() {
    // The case: the split-screen clip with a plausible YAML (incline 5 deg,
    // d = 0.20 m, r = 12.7 mm, m = 67 g) once gave an s_r whose interval included zero,
    // reported as a measurement. Its interval is flagged, and so is its period.
    let Some(clip) = common::fixture("sborquez_video2_splitscreen.mp4") else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    // Its right panel (two pendulums swing in the frame: one is chosen).
    let j = fit_json(&clip_yaml(
        d.path(),
        &clip,
        "0.20",
        ", roi: [240, 0, 240, 360]",
    ));
    assert_eq!(j["verdict"], "suspect", "{j}");
    let w = warned(&j);
    assert!(
        w.contains(&"interval".to_string()) && w.contains(&"period".to_string()),
        "{j}"
    );
}

#[test]
fn a_pivot_off_along_the_wire_is_suspect() {
    if !common::need_ffmpeg() {
        return;
    }
    let d = tempfile::tempdir().unwrap();
    let twin = |name: &str, video: &str| common::short_glass_twin(name, "3.714e-6", video);
    let build = |names: &[&str]| {
        let list: String = names.iter().map(|n| format!("  - {n}.yaml\n")).collect();
        std::fs::write(
            d.path().join("manifest.yaml"),
            format!("title: pivot\nexperiments:\n{list}"),
        )
        .unwrap();
        // A suspect or missed twin makes the build exit 1, as a failure does; only a
        // failure is named FAILED.
        let out = common::rollfric(&common::BUILD_INTO_REPORTS, d.path());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            matches!(out.status.code(), Some(0 | 1)) && !err.contains("FAILED"),
            "{}: {err}",
            out.status
        );
    };
    let read = |name: &str, file: &str| -> serde_json::Value {
        serde_json::from_slice(
            &std::fs::read(d.path().join("cache").join(name).join(file)).unwrap(),
        )
        .unwrap()
    };
    std::fs::write(d.path().join("found.yaml"), twin("found", "")).unwrap();
    build(&["found"]);
    let found = read("found", "result.json");
    let pivot = &found["detection"]["pivot_px"];
    let (x, y) = (pivot[0].as_f64().unwrap(), pivot[1].as_f64().unwrap());
    let scale = found["detection"]["swing_scale"].as_f64().unwrap();
    assert!((scale - 1.0).abs() < 0.005, "{scale}");
    assert_eq!(found["verdict"], "ok", "{found}");

    let given = format!("video: {{ pivot: [{x:.2}, {:.2}] }}\n", y - 20.0);
    std::fs::write(d.path().join("given.yaml"), twin("given", &given)).unwrap();
    build(&["found", "given"]);
    let r = read("given", "result.json");
    let s_r = r["results"]["s_r_m"].as_f64().unwrap();
    assert!(
        (s_r / 3.714e-6 - 1.0).abs() > 0.05,
        "the wrong pivot should spoil s_r: {s_r}"
    );
    assert_eq!(r["verdict"], "suspect", "{r}");
    let w = &r["warnings"][0];
    assert_eq!(w["check"], "pivot", "{r}");
    assert!(w["value"].as_f64().unwrap() > 0.05, "{w}");
    assert!(w["reason"].as_str().unwrap().contains("video.pivot"), "{w}");
}
