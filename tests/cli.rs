//! End-to-end tests of the `rollfric` binary: simulate -> fit on every experiment, a CSV
//! from an independent simulator, and the failure paths.

mod common;

use common::{need_python3, rollfric, rollfric_ok, root};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tmpdir() -> tempfile::TempDir {
    tempfile::tempdir().expect("temp dir")
}

const EXPERIMENTS: [&str; 8] = [
    "steel",
    "glass",
    "aluminum",
    "copper",
    "polycarbonate",
    "carbon-fiber",
    "glass-fiber-fabric",
    "glass-d140",
];

/// `fit --json` on a CSV, as a JSON value.
fn fit_json(experiment: &str, csv: &Path) -> serde_json::Value {
    let (out, _) = rollfric_ok(
        &[
            "fit",
            experiment,
            "--angles",
            csv.to_str().unwrap(),
            "--json",
        ],
        &root(),
    );
    serde_json::from_str(&out).expect("one JSON object")
}

fn truth_s_r(experiment: &str) -> f64 {
    let text =
        std::fs::read_to_string(root().join(format!("experiments/{experiment}.yaml"))).unwrap();
    let synth = &text[text.find("synthetic:").expect("synthetic block")..];
    let line = synth
        .lines()
        .find(|l| l.trim_start().starts_with("s_r_m:"))
        .unwrap();
    line.split(':').nth(1).unwrap().trim().parse().unwrap()
}

fn simulate(experiment: &str, csv: &Path, noise_deg: &str, seed: &str) {
    rollfric_ok(
        &[
            "simulate",
            experiment,
            "-o",
            csv.to_str().unwrap(),
            "--fps",
            "60",
            "--noise-deg",
            noise_deg,
            "--seed",
            seed,
        ],
        &root(),
    );
}

#[test]
fn simulate_then_fit_recovers_s_r_for_every_experiment() {
    let dir = tmpdir();
    for exp in EXPERIMENTS {
        let truth = truth_s_r(exp);
        for (noise, tol) in [("0", 1e-3), ("0.05", 5e-3)] {
            let csv = dir.path().join(format!("{exp}-{noise}.csv"));
            simulate(exp, &csv, noise, "11");
            let j = fit_json(exp, &csv);
            let s_r = j["s_r_m"].as_f64().unwrap();
            let dev = (s_r - truth) / truth;
            assert!(
                dev.abs() < tol,
                "{exp} noise {noise} deg: s_r {s_r:e} vs truth {truth:e} ({:+.3} %)",
                100.0 * dev
            );
            let ci = j["s_r_ci95_m"].as_array().unwrap();
            assert!(ci[0].as_f64().unwrap() < s_r && s_r < ci[1].as_f64().unwrap());
        }
    }
}

#[test]
fn fit_json_has_every_documented_field() {
    let dir = tmpdir();
    let csv = dir.path().join("glass.csv");
    simulate("glass", &csv, "0.05", "3");
    let j = fit_json("glass", &csv);
    for key in [
        "s_r_m",
        "s_r_ci95_m",
        "mu_r",
        "a_rad_s",
        "psi_eq_rad",
        "psi_eq_paper_rad",
        "beta",
        "n_extremes",
        "period_s",
        "d_from_period_m",
        "max_t_over_n",
    ] {
        assert!(!j[key].is_null(), "missing `{key}` in {j}");
    }
    // The camera's rest angle (91.7 deg) is the equilibrium; the paper's estimator is
    // biased by the decay (ERRATA §5), the envelope fit is not.
    let eq = j["psi_eq_rad"].as_f64().unwrap().to_degrees();
    assert!((eq - 91.7).abs() < 0.01, "{eq}");
    let d = j["d_from_period_m"].as_f64().unwrap();
    assert!((d - 0.1774).abs() < 0.002, "{d}");
}

#[test]
fn simulate_writes_the_documented_csv() {
    let dir = tmpdir();
    let csv = dir.path().join("a.csv");
    simulate("copper", &csv, "0", "1");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t_s,angle_rad"));
    let first: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    // Released at psi0 = 10 deg from the rest angle 91.7 deg.
    assert_eq!(first[0], 0.0);
    assert!((first[1].to_degrees() - (91.7 - 10.0)).abs() < 1e-6);
}

/// The independent reference simulator (plain Python, RK4 with its own event handling
/// and its own CSV conventions: extra columns, 30 fps, offset and flipped sign).
#[test]
fn fits_a_csv_from_an_independent_simulator() {
    if !need_python3() {
        return;
    }
    let dir = tmpdir();
    let script = root().join("tests/reference_sim/conical_pendulum.py");
    // Steel's geometry (d = 0.2276 m) is the simulator's default.
    for (s_r, noise, seed) in [("4.508e-6", "0", "7"), ("2.0e-5", "0.05", "3")] {
        let csv = dir.path().join(format!("ref-{s_r}.csv"));
        let out = Command::new("python3")
            .arg(&script)
            .args(["--s-r", s_r, "--noise-deg", noise, "--seed", seed, "-o"])
            .arg(&csv)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let j = fit_json("steel", &csv);
        let truth: f64 = s_r.parse().unwrap();
        let got = j["s_r_m"].as_f64().unwrap();
        assert!(
            ((got - truth) / truth).abs() < 0.01,
            "reference simulator s_r {truth:e}, fitted {got:e}"
        );
    }
}

#[test]
fn torsion_prints_the_appendix_numbers() {
    let (out, _) = rollfric_ok(&["torsion", "steel", "--s-r", "4.5e-6", "--json"], &root());
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let k_t = j["k_t_n_m_per_rad"].as_f64().unwrap();
    assert!((k_t - 3.95e-7).abs() < 0.005e-7, "{k_t}");
    let ratio = j["ratio_pct"].as_f64().unwrap();
    assert!(ratio > 0.5 && ratio < 3.0, "{ratio}");
}

// ---- failure paths: non-zero exit, one line naming the file and the problem ----

fn assert_fails_with(out: &Output, file: &str, needle: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "should fail: {err}");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected:\n{err}"
    );
    assert!(err.contains(file), "should name {file}: {err}");
    assert!(err.contains(needle), "should say `{needle}`: {err}");
    assert!(
        !err.contains("panicked") && !err.contains("backtrace"),
        "{err}"
    );
}

fn glass_with(dir: &Path, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("experiments/glass.yaml")).unwrap();
    assert!(text.contains(from), "fixture text `{from}`");
    let path = dir.join("bad.yaml");
    std::fs::write(&path, text.replace(from, to)).unwrap();
    path
}

#[test]
fn fails_on_unknown_key() {
    let dir = tmpdir();
    let f = glass_with(dir.path(), "  fps: 25", "  fps: 25\n  fsp: 25");
    let out = rollfric(&["fit", f.to_str().unwrap()], &root());
    assert_fails_with(&out, "bad.yaml", "unknown field `fsp`");
}

#[test]
fn fails_when_wire_is_shorter_than_the_radius() {
    let dir = tmpdir();
    let f = glass_with(dir.path(), "d_m: 0.1774", "d_m: 0.02");
    let out = rollfric(&["fit", f.to_str().unwrap()], &root());
    assert_fails_with(
        &out,
        "bad.yaml",
        "`geometry.pendulum.d_m` = 0.02 m must exceed",
    );
}

#[test]
fn fails_on_negative_or_zero_values() {
    let dir = tmpdir();
    for (from, to, needle) in [
        (
            "mass_kg: 1.0458",
            "mass_kg: -1.0",
            "`geometry.ball.mass_kg` = -1",
        ),
        (
            "radius_m: 0.03175",
            "radius_m: 0",
            "`geometry.ball.radius_m` = 0",
        ),
        ("  fps: 25", "  fps: 0", "`synthetic.fps` = 0"),
        ("period_s: 205.3", "period_s: -5", "`torsion.period_s` = -5"),
    ] {
        let f = glass_with(dir.path(), from, to);
        let out = rollfric(&["fit", f.to_str().unwrap()], &root());
        assert_fails_with(&out, "bad.yaml", needle);
    }
}

#[test]
fn fails_on_missing_empty_or_nan_csv() {
    let dir = tmpdir();
    let missing = dir.path().join("nothing.csv");
    let out = rollfric(
        &["fit", "glass", "--angles", missing.to_str().unwrap()],
        &root(),
    );
    assert_fails_with(&out, "nothing.csv", "no such file");

    let empty = dir.path().join("empty.csv");
    std::fs::write(&empty, "").unwrap();
    let out = rollfric(
        &["fit", "glass", "--angles", empty.to_str().unwrap()],
        &root(),
    );
    assert_fails_with(&out, "empty.csv", "empty");

    let nan = dir.path().join("nan.csv");
    std::fs::write(&nan, "t_s,angle_rad\n0.0,1.5\n0.1,NaN\n").unwrap();
    let out = rollfric(
        &["fit", "glass", "--angles", nan.to_str().unwrap()],
        &root(),
    );
    assert_fails_with(&out, "nan.csv", "line 3: `angle_rad` = NaN");
}

#[test]
fn fails_with_too_few_turning_points() {
    let dir = tmpdir();
    let csv = dir.path().join("short.csv");
    // Three seconds: about one turning point.
    rollfric_ok(
        &[
            "simulate",
            "glass",
            "-o",
            csv.to_str().unwrap(),
            "--duration",
            "3",
        ],
        &root(),
    );
    let out = rollfric(
        &["fit", "glass", "--angles", csv.to_str().unwrap()],
        &root(),
    );
    assert_fails_with(&out, "short.csv", "turning point");
}

#[test]
fn fails_on_a_missing_experiment_file() {
    let out = rollfric(&["fit", "experiments/nonexistent.yaml"], &root());
    assert_fails_with(&out, "nonexistent.yaml", "no such file");
}

/// `docs/experiment.md` is what `rollfric schema` prints: a key added to (or documented
/// differently in) the config structs without regenerating the page fails here.
#[test]
fn the_key_reference_in_docs_is_current() {
    let (out, _) = rollfric_ok(&["schema"], &root());
    let path = root().join("docs/experiment.md");
    let docs = std::fs::read_to_string(&path).expect("docs/experiment.md");
    assert!(
        docs == out,
        "{} is not what `rollfric schema` prints: run `rollfric schema > docs/experiment.md`",
        path.display()
    );
}

/// `docs/tuning.md` is what `rollfric tuning --markdown` prints: a knob added to or
/// changed in `src/detect/tuning/` without regenerating the page fails here.
#[test]
fn the_tuning_table_in_docs_is_current() {
    let (out, _) = rollfric_ok(&["tuning", "--markdown"], &root());
    let path = root().join("docs/tuning.md");
    let docs = std::fs::read_to_string(&path).expect("docs/tuning.md");
    assert!(
        docs == out,
        "{} is not what `rollfric tuning --markdown` prints: run \
         `rollfric tuning --markdown > docs/tuning.md`",
        path.display()
    );
}

/// `rollfric tuning` prints one aligned line per knob after its header.
#[test]
fn tuning_prints_every_knob() {
    let (out, _) = rollfric_ok(&["tuning"], &root());
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].starts_with("name"), "{}", lines[0]);
    assert!(lines.len() > 100, "{} lines", lines.len());
    assert!(
        lines.iter().any(|l| l.starts_with("FREE_STRIP_HALF ")),
        "{out}"
    );
}

/// `rollfric schema --json` is a JSON Schema with the experiment's top-level keys.
#[test]
fn schema_json_lists_the_top_level_keys() {
    let (out, _) = rollfric_ok(&["schema", "--json"], &root());
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let props = v["properties"].as_object().expect("properties");
    for key in ["geometry", "video", "synthetic", "accept", "tolerances"] {
        assert!(props.contains_key(key), "{key} missing");
    }
    assert_eq!(v["additionalProperties"], serde_json::Value::Bool(false));
}
