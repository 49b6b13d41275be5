//! `rollfric build` and `rollfric check` end to end on a small manifest: the cache, byte
//! reproducibility, isolation of a failing experiment, atomicity under a kill.

mod common;

use common::{command, rollfric, root, same_tree, snapshot};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Output;

fn experiments() -> PathBuf {
    root().join("experiments")
}

/// A manifest folder with two short twins (the glass-fiber row twice, with different
/// seeds and names) and, optionally, an experiment whose video is missing.
fn setup(dir: &Path, with_missing: bool) -> PathBuf {
    let base = std::fs::read_to_string(experiments().join("glass-fiber-fabric.yaml")).unwrap();
    let mk = |name: &str, seed: u32| {
        let text = base
            .replace("name: glass-fiber-fabric", &format!("name: {name}"))
            .replace("seed: 8", &format!("seed: {seed}"));
        assert!(text.contains(&format!("name: {name}")), "fixture changed");
        std::fs::write(dir.join(format!("{name}.yaml")), text).unwrap();
    };
    mk("fabric-a", 8);
    mk("fabric-b", 11);
    let mut list = vec!["fabric-a.yaml", "fabric-b.yaml"];
    if with_missing {
        // A lab experiment whose recording is not there.
        let text = base
            .replace("name: glass-fiber-fabric", "name: lab-run")
            .split("\nsynthetic:")
            .next()
            .unwrap()
            .to_string()
            + "\nvideo:\n  path: videos/lab-run.mp4\n";
        std::fs::write(dir.join("lab-run.yaml"), text).unwrap();
        list.push("lab-run.yaml");
    }
    let m = dir.join("manifest.yaml");
    let mut text = "title: Build test\nexperiments:\n".to_string();
    for l in list {
        text += &format!("  - {l}\n");
    }
    std::fs::write(&m, text).unwrap();
    m
}

fn build(m: &Path, out: &Path, cache: &Path) -> Output {
    rollfric(
        &[
            OsStr::new("build"),
            OsStr::new("--manifest"),
            m.as_os_str(),
            OsStr::new("--out"),
            out.as_os_str(),
            OsStr::new("--cache"),
            cache.as_os_str(),
        ],
        &root(),
    )
}

/// `rollfric check --summary <summary>`.
fn check(summary: &Path) -> Output {
    rollfric(
        &[
            OsStr::new("check"),
            OsStr::new("--summary"),
            summary.as_os_str(),
        ],
        &root(),
    )
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn build_caches_reproduces_and_reruns_only_what_changed() {
    let d = tempfile::tempdir().unwrap();
    let m = setup(d.path(), false);
    let (out, cache) = (d.path().join("reports"), d.path().join("cache"));
    let first = build(&m, &out, &cache);
    assert!(first.status.success(), "{}", stderr(&first));
    let files = snapshot(&out);
    // No chart's legend hides a plotted point or line (issue: figures a reviewer can read).
    let covered = common::legends_over_data(&out);
    assert!(
        covered.is_empty(),
        "legends over data:\n{}",
        covered.join("\n")
    );
    for f in [
        "index.html",
        "index.md",
        "summary.json",
        "fig19.svg",
        "fig2a.svg",
        "fig2b.svg",
        "fabric-a.html",
        "fabric-a.md",
        "fabric-a/fig11.png",
        "fabric-a/fig12.svg",
        "fabric-a/fig14a.svg",
        "fabric-a/fig14b.svg",
        "fabric-a/fig15.svg",
        "fabric-a/fig16a.svg",
        "fabric-a/fig16b.svg",
        "fabric-a/fig17.svg",
        "fabric-a/fig18.svg",
        "fabric-b.html",
    ] {
        assert!(files.contains_key(f), "{f} missing: {:?}", files.keys());
    }
    // Nothing machine-specific inside.
    let root = d.path().display().to_string();
    for (name, bytes) in &files {
        let text = String::from_utf8_lossy(bytes);
        assert!(
            !text.contains(&root),
            "{name} holds the absolute path {root}"
        );
    }
    let index = String::from_utf8_lossy(&files["index.html"]).into_owned();
    assert!(
        index.contains("SYNTHETIC"),
        "the index must say the inputs are synthetic"
    );

    // Unchanged: every experiment cached, no file rewritten, no byte changed (how long
    // that takes is `make bench`'s business).
    let second = build(&m, &out, &cache);
    assert!(second.status.success(), "{}", stderr(&second));
    let err = stderr(&second);
    assert_eq!(err.matches(": cached in").count(), 2, "{err}");
    assert_eq!(snapshot(&out), files, "an unchanged build changed bytes");
    let line = String::from_utf8_lossy(&second.stdout);
    assert!(line.contains("; 0 report files rewritten"), "{line}");

    // A new cache and output folder: the same bytes (the renders are deterministic).
    let (out2, cache2) = (d.path().join("reports2"), d.path().join("cache2"));
    assert!(build(&m, &out2, &cache2).status.success());
    assert_eq!(snapshot(&out2), files, "a clean rebuild differs");

    // Editing one file reruns that experiment only, and only its analysis (the edit
    // does not touch what the video depends on).
    let a = d.path().join("fabric-a.yaml");
    let text = std::fs::read_to_string(&a).unwrap();
    std::fs::write(&a, text.replace("notes: >-", "notes: >-\n  Edited.")).unwrap();
    let third = build(&m, &out, &cache);
    assert!(third.status.success());
    let err = stderr(&third);
    assert!(err.contains("fabric-a: analysis ran"), "{err}");
    assert!(err.contains("fabric-b: cached"), "{err}");
    assert!(
        !err.contains("synth:") && !err.contains("synth,"),
        "no render expected: {err}"
    );
    // A change to the twin's parameters renders it again.
    let text = std::fs::read_to_string(&a).unwrap();
    std::fs::write(&a, text.replace("seed: 8", "seed: 9")).unwrap();
    let fourth = build(&m, &out, &cache);
    let err = stderr(&fourth);
    assert!(
        err.contains("fabric-a: synth, detect, analysis ran"),
        "{err}"
    );
    assert!(err.contains("fabric-b: cached"), "{err}");

    // check passes on the summary, and fails when a value is off.
    let summary = out.join("summary.json");
    let ok = check(&summary);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stdout)
    );
    let mut s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&summary).unwrap()).unwrap();
    // The fitted s_r off by half, in the result and in every comparison of it (a
    // summary's comparisons must be its result's own, or `check` refuses the summary).
    let result = &mut s["experiments"][0]["result"];
    let v = result["results"]["s_r_m"].as_f64().unwrap();
    result["results"]["s_r_m"] = serde_json::json!(v * 1.5);
    for c in result["checks"].as_array_mut().unwrap() {
        if c["quantity"] == "s_r" {
            c["value"] = serde_json::json!(v * 1.5);
        }
    }
    let bad = d.path().join("bad.json");
    std::fs::write(&bad, serde_json::to_vec(&s).unwrap()).unwrap();
    let miss = check(&bad);
    assert_eq!(miss.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&miss.stdout).contains("MISS"),
        "{}",
        String::from_utf8_lossy(&miss.stderr)
    );
    // Only the comparison's value changed: the summary is refused as edited.
    s["experiments"][0]["result"]["results"]["s_r_m"] = serde_json::json!(v);
    std::fs::write(&bad, serde_json::to_vec(&s).unwrap()).unwrap();
    let edited = check(&bad);
    assert_eq!(edited.status.code(), Some(1));
    let err = String::from_utf8_lossy(&edited.stderr);
    assert!(err.contains("is not the result's own"), "{err}");
}

#[test]
fn a_missing_video_fails_only_its_experiment() {
    let d = tempfile::tempdir().unwrap();
    let m = setup(d.path(), true);
    let (out, cache) = (d.path().join("reports"), d.path().join("cache"));
    let o = build(&m, &out, &cache);
    assert_eq!(
        o.status.code(),
        Some(1),
        "a failed experiment must fail the build"
    );
    let err = stderr(&o);
    assert!(
        err.contains("lab-run: FAILED") && err.contains("videos/lab-run.mp4"),
        "{err}"
    );
    assert!(out.join("fabric-a.html").exists() && out.join("fabric-b.html").exists());
    let index = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(index.contains("Failed experiments") && index.contains("lab-run"));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let lab = summary["experiments"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["name"] == "lab-run")
        .unwrap();
    assert_eq!(lab["status"], "failed");
    let c = check(&out.join("summary.json"));
    assert_eq!(c.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&c.stdout).contains("lab-run"));
}

#[test]
fn a_killed_build_leaves_whole_files_and_the_next_build_completes() {
    let d = tempfile::tempdir().unwrap();
    let m = setup(d.path(), false);
    // Reference: an uninterrupted build.
    let (ref_out, ref_cache) = (d.path().join("ref"), d.path().join("ref-cache"));
    assert!(build(&m, &ref_out, &ref_cache).status.success());
    let reference = snapshot(&ref_out);
    let (out, cache) = (d.path().join("reports"), d.path().join("cache"));
    for delay_ms in [300u64, 1500, 3500] {
        let mut child = command(&root())
            .args(["build", "-q", "--manifest"])
            .arg(&m)
            .arg("--out")
            .arg(&out)
            .arg("--cache")
            .arg(&cache)
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let _ = child.kill();
        let _ = child.wait();
        // Whatever is there is whole: every page file is one the build would write.
        if out.exists() {
            for (name, bytes) in snapshot(&out) {
                if name.starts_with('.') || name.contains("/.") {
                    continue; // a temporary file of the killed writer
                }
                if let Some(want) = reference.get(&name) {
                    // Pages of a finished experiment are final; the index may list
                    // fewer experiments, but must be a whole document.
                    if name.ends_with(".svg") || name.ends_with(".png") {
                        assert_eq!(&bytes, want, "{name} torn after a kill at {delay_ms} ms");
                    } else if name.ends_with(".html") {
                        assert!(
                            String::from_utf8_lossy(&bytes)
                                .trim_end()
                                .ends_with("</html>"),
                            "{name} torn"
                        );
                    }
                }
            }
        }
    }
    let o = build(&m, &out, &cache);
    assert!(o.status.success(), "{}", stderr(&o));
    // The same files as the uninterrupted build, byte for byte, and no temporaries left.
    assert_eq!(snapshot(&out), reference, "the build after kills differs");
}

/// `rollfric stage synth|detect|analyze` of each experiment, then `rollfric report`, give
/// reports byte-identical to `rollfric build`'s; a stage whose key is current does
/// nothing; a stage whose predecessor is not current refuses, naming the command that
/// makes it current; `report` computes nothing (an experiment not analysed fails).
#[test]
fn stage_commands_and_report_make_the_builds_reports() {
    let d = tempfile::tempdir().unwrap();
    let m = setup(d.path(), false);
    let built = build(&m, &d.path().join("built"), &d.path().join("cache-built"));
    assert!(built.status.success(), "{}", stderr(&built));
    let (out, cache) = (d.path().join("staged"), d.path().join("cache-staged"));
    let run = |args: &[&str]| -> Output {
        let mut all: Vec<&OsStr> = args.iter().map(OsStr::new).collect();
        all.extend([
            OsStr::new("--manifest"),
            m.as_os_str(),
            OsStr::new("--out"),
            out.as_os_str(),
            OsStr::new("--cache"),
            cache.as_os_str(),
            OsStr::new("-q"),
        ]);
        rollfric(&all, &root())
    };
    let said = |o: &Output| String::from_utf8_lossy(&o.stdout).into_owned();
    // Out of order: refused, naming the stage to run first.
    let early = run(&["stage", "detect", "fabric-a"]);
    assert!(
        !early.status.success()
            && stderr(&early).contains("run `rollfric stage synth fabric-a` first"),
        "{}",
        stderr(&early)
    );
    // A report before the stages: both experiments fail, naming the stage to run.
    let report = run(&["report"]);
    assert!(said(&report).contains("2 failed"), "{}", said(&report));
    assert!(
        stderr(&report).contains("run `rollfric stage synth fabric-a` first"),
        "{}",
        stderr(&report)
    );
    // In order, by name and by file; each a no-op the second time.
    let file = d.path().join("fabric-b.yaml");
    for exp in ["fabric-a", file.to_str().unwrap()] {
        for stage in ["synth", "detect", "analyze"] {
            let first = run(&["stage", stage, exp]);
            assert!(first.status.success(), "{stage} {exp}: {}", stderr(&first));
            let ran = if stage == "analyze" {
                "analysis"
            } else {
                stage
            };
            assert!(
                said(&first).contains(&format!("{ran} ran")),
                "{}",
                said(&first)
            );
            let again = run(&["stage", stage, exp]);
            assert!(said(&again).contains("cached"), "{}", said(&again));
        }
    }
    let unknown = run(&["stage", "synth", "no-such-experiment"]);
    assert!(
        stderr(&unknown).contains("no experiment named or found at `no-such-experiment`"),
        "{}",
        stderr(&unknown)
    );
    let report = run(&["report"]);
    assert!(report.status.success(), "{}", stderr(&report));
    same_tree(
        &d.path().join("built"),
        &out,
        "build against stage + report",
    );
    // The build on the staged cache has nothing to do.
    let again = build(&m, &out, &cache);
    assert!(
        String::from_utf8_lossy(&again.stdout).contains("0 report files rewritten"),
        "{}",
        String::from_utf8_lossy(&again.stdout)
    );
}
