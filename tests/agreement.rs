//! `rollfric fit` and `rollfric build` go through the same pipeline, so on the same
//! inputs they give the same verdict: the same refusal with the same reason, or the
//! same number.

mod common;

use common::rollfric as run;
use std::path::{Path, PathBuf};

fn experiments() -> PathBuf {
    common::root().join("experiments")
}

/// A folder with `exp.yaml` (the glass-fiber row measured from `angles.csv`), its
/// manifest, and `angles.csv` simulated from the twin.
fn setup() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    let yaml = std::fs::read_to_string(experiments().join("glass-fiber-fabric.yaml")).unwrap();
    let yaml = yaml.replace("name: glass-fiber-fabric", "name: exp") + "angles: angles.csv\n";
    std::fs::write(d.path().join("exp.yaml"), yaml).unwrap();
    std::fs::write(
        d.path().join("manifest.yaml"),
        "title: agreement\nexperiments:\n  - exp.yaml\n",
    )
    .unwrap();
    let out = run(
        &[
            "simulate",
            "exp.yaml",
            "-o",
            "angles.csv",
            "--duration",
            "20",
        ],
        d.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    d
}

/// The verdicts of `fit` and `build` on the folder: `Ok(s_r)` or `Err(message)`.
fn verdicts(dir: &Path) -> (Result<f64, String>, Result<f64, String>) {
    let fit = run(&["fit", "exp.yaml", "--json"], dir);
    let fit = if fit.status.success() {
        let v: serde_json::Value = serde_json::from_slice(&fit.stdout).unwrap();
        Ok(v["s_r_m"].as_f64().unwrap())
    } else {
        Err(String::from_utf8_lossy(&fit.stderr).into_owned())
    };
    let build = run(&common::BUILD_INTO_REPORTS, dir);
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("reports/summary.json")).unwrap()).unwrap();
    let e = &summary["experiments"][0];
    let build_verdict = match e["status"].as_str().unwrap() {
        "ok" => {
            assert!(
                build.status.success(),
                "a built experiment within tolerance"
            );
            Ok(e["result"]["results"]["s_r_m"].as_f64().unwrap())
        }
        "failed" => {
            assert!(
                !build.status.success(),
                "a failed experiment fails the build"
            );
            Err(e["error"].as_str().unwrap().to_string())
        }
        s => panic!("status {s}"),
    };
    (fit, build_verdict)
}

/// Both refuse, and both name `needle`.
fn assert_both_refuse(dir: &Path, needle: &str) {
    let (fit, build) = verdicts(dir);
    let fit = fit.expect_err("fit must refuse");
    let build = build.expect_err("build must refuse");
    assert!(fit.contains(needle), "fit says: {fit}");
    assert!(build.contains(needle), "build says: {build}");
}

/// Rewrite the data rows of `angles.csv` (the header stays).
fn edit_rows(dir: &Path, f: impl Fn(Vec<String>) -> Vec<String>) {
    let p = dir.join("angles.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    let mut lines = text.lines().map(str::to_string);
    let header = lines.next().unwrap();
    let rows = f(lines.collect());
    std::fs::write(&p, format!("{header}\n{}\n", rows.join("\n"))).unwrap();
}

#[test]
fn fit_and_build_agree_on_a_good_csv() {
    let d = setup();
    let (fit, build) = verdicts(d.path());
    let (fit, build) = (fit.unwrap(), build.unwrap());
    assert_eq!(
        fit.to_bits(),
        build.to_bits(),
        "fit {fit:e}, build {build:e}"
    );
}

#[test]
fn both_refuse_a_csv_with_every_row_twice() {
    let d = setup();
    edit_rows(d.path(), |rows| {
        rows.iter().flat_map(|r| [r.clone(), r.clone()]).collect()
    });
    assert_both_refuse(d.path(), "line 3: `t_s` = 0 does not increase");
}

#[test]
fn both_refuse_a_csv_with_a_nan() {
    let d = setup();
    edit_rows(d.path(), |mut rows| {
        let t = rows[9].split(',').next().unwrap().to_string();
        rows[9] = format!("{t},NaN");
        rows
    });
    assert_both_refuse(
        d.path(),
        "line 11: `angle_rad` = NaN is not a finite number",
    );
}

#[test]
fn both_refuse_a_csv_with_times_out_of_order() {
    let d = setup();
    edit_rows(d.path(), |mut rows| {
        rows.swap(20, 21);
        rows
    });
    assert_both_refuse(d.path(), "line 23: `t_s` =");
}

#[test]
fn both_refuse_a_yaml_that_is_not_utf8() {
    let d = setup();
    let p = d.path().join("exp.yaml");
    let text = std::fs::read_to_string(&p).unwrap();
    let mut bytes = Vec::new();
    for line in text.split_inclusive('\n') {
        if line.starts_with("material:") {
            // A Latin-1 e-acute: one byte 0xe9, not UTF-8.
            bytes.extend_from_slice(b"material: Tejido de fibra de vidrio (\xe9)\n");
        } else {
            bytes.extend_from_slice(line.as_bytes());
        }
    }
    std::fs::write(&p, bytes).unwrap();
    assert_both_refuse(d.path(), "exp.yaml: not UTF-8 text (invalid byte at offset");
}
