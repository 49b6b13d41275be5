//! What a build or a detection may touch: only its own files, one build per folder at a
//! time, names that cannot overwrite each other's pages.

mod common;

use common::{rollfric, root, simulate_csv};
use std::path::Path;

/// A folder with `manifest.yaml` listing `names` (file stems), each the glass-fiber row
/// measured from one small angle CSV, with its `name:` as given.
fn setup(dir: &Path, experiments: &[(&str, &str)]) {
    let yaml = std::fs::read_to_string(root().join("experiments/glass-fiber-fabric.yaml"))
        .unwrap()
        .split("\nsynthetic:")
        .next()
        .unwrap()
        .to_string();
    simulate_csv("glass-fiber-fabric", &dir.join("angles.csv"), 16.0);
    let mut list = String::new();
    for (file, name) in experiments {
        let text = yaml.replace("name: glass-fiber-fabric", &format!("name: {name}"))
            + "\nangles: angles.csv\n";
        std::fs::write(dir.join(file), text).unwrap();
        list.push_str(&format!("  - {file}\n"));
    }
    std::fs::write(
        dir.join("manifest.yaml"),
        format!("title: edges\nexperiments:\n{list}"),
    )
    .unwrap();
}

/// `rollfric build` of the folder's manifest into `out/` and `cache/`.
const BUILD: [&str; 8] = [
    "build",
    "-q",
    "--manifest",
    "manifest.yaml",
    "--out",
    "out",
    "--cache",
    "cache",
];

fn build(dir: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = BUILD.to_vec();
    args.extend_from_slice(extra);
    rollfric(&args, dir)
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("out/summary.json")).unwrap()).unwrap()
}

#[test]
fn colliding_names_are_refused_naming_both_files() {
    let d = tempfile::tempdir().unwrap();
    setup(
        d.path(),
        &[
            ("a.yaml", "same"),
            ("b.yaml", "same"),
            ("c.yaml", "index"),
            ("d.yaml", "fine"),
        ],
    );
    let out = build(d.path(), &[]);
    assert!(!out.status.success());
    let s = summary(d.path());
    let e = |i: usize| s["experiments"][i].clone();
    assert_eq!(e(0)["status"], "failed");
    assert!(e(0)["error"]
        .as_str()
        .unwrap()
        .contains("a.yaml: the experiment name `same` is also that of b.yaml"));
    assert!(e(1)["error"]
        .as_str()
        .unwrap()
        .contains("b.yaml: the experiment name `same` is also that of a.yaml"));
    assert!(e(2)["error"]
        .as_str()
        .unwrap()
        .contains("`index` is the reports' own"));
    assert_eq!(e(3)["status"], "ok", "the others still build");
    let index = std::fs::read_to_string(d.path().join("out/index.md")).unwrap();
    assert!(
        index.starts_with("# edges"),
        "the index is the index: {}",
        &index[..40.min(index.len())]
    );
    assert!(
        !d.path().join("out/same.html").exists(),
        "no page for a colliding name"
    );
}

#[test]
fn the_same_file_listed_twice_is_refused() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "a")]);
    std::fs::write(
        d.path().join("manifest.yaml"),
        "title: twice\nexperiments:\n  - a.yaml\n  - a.yaml\n",
    )
    .unwrap();
    let out = build(d.path(), &["-j", "2"]);
    assert!(!out.status.success());
    let s = summary(d.path());
    for i in 0..2 {
        assert!(s["experiments"][i]["error"]
            .as_str()
            .unwrap()
            .contains("is also that of a.yaml"));
    }
}

#[test]
fn a_build_removes_only_its_own_dead_temporaries() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "a")]);
    let out = d.path().join("out");
    std::fs::create_dir_all(out.join("sub")).unwrap();
    let users = [
        ".thesis.tmpl",
        ".notes.tmp",
        "sub/.draft.tmp2",
        ".a.html.tmp123",
    ];
    for f in users {
        std::fs::write(out.join(f), "mine").unwrap();
    }
    // A temporary of a process that is not running (pids stay below 2^22 on Linux).
    let stale = out.join(".rollfric-4194303-a.html.tmp");
    std::fs::write(&stale, "left by a killed build").unwrap();
    let o = build(d.path(), &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in users {
        assert_eq!(
            std::fs::read_to_string(out.join(f)).unwrap(),
            "mine",
            "{f} kept"
        );
    }
    assert!(!stale.exists(), "a dead build's temporary is removed");
}

#[test]
fn a_second_build_of_the_same_folders_waits_or_refuses() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "a")]);
    std::fs::create_dir_all(d.path().join("cache")).unwrap();
    // Another build holds the cache folder.
    let held = std::fs::File::open(d.path().join("cache")).unwrap();
    held.lock().unwrap();
    let o = build(d.path(), &["--no-wait"]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("another rollfric build is using this folder"),
        "{err}"
    );
    let mut waiting = common::command(d.path())
        .args(BUILD)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Read its messages as they come: no sleep that a loaded machine could outlast.
    let stderr = waiting.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = std::thread::spawn(move || {
        use std::io::BufRead;
        let mut all = String::new();
        for line in std::io::BufReader::new(stderr).lines() {
            let line = line.unwrap();
            all.push_str(&line);
            all.push('\n');
            let _ = tx.send(line);
        }
        all
    });
    let said_waiting = loop {
        match rx.recv_timeout(std::time::Duration::from_secs(120)) {
            Ok(line) if line.contains("waiting for it to finish") => break true,
            Ok(_) => continue,
            Err(_) => break false,
        }
    };
    assert!(said_waiting, "it says it waits while the folder is held");
    assert!(
        waiting.try_wait().unwrap().is_none(),
        "it waits while the folder is held"
    );
    held.unlock().unwrap();
    let status = waiting.wait().unwrap();
    let err = reader.join().unwrap();
    assert!(status.success(), "{err}");
}

#[test]
fn detect_refuses_to_write_over_its_video() {
    let d = tempfile::tempdir().unwrap();
    let video = d.path().join("v.mp4");
    std::fs::write(&video, b"not really a video").unwrap();
    let o = rollfric(&["detect", "v.mp4", "-o", "./v.mp4"], d.path());
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("that is the video (v.mp4), an input"), "{err}");
    assert_eq!(std::fs::read(&video).unwrap(), b"not really a video");
}

#[test]
fn a_build_refuses_to_write_into_the_experiments_folder() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "a")]);
    let o = rollfric(
        &[
            "build",
            "-q",
            "--manifest",
            "manifest.yaml",
            "--out",
            ".",
            "--cache",
            "cache",
        ],
        d.path(),
    );
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("is the manifest's own folder"), "{err}");
}

#[test]
fn zero_jobs_is_refused() {
    let o = rollfric(&["build", "-j", "0"], &root());
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("-j"));
}

#[test]
fn detect_flags_out_of_range_are_refused_in_our_words() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("v.mp4"), b"x").unwrap();
    for (args, needle) in [
        (
            ["--roi", "10,10,0,0"],
            "--roi 10,10,0,0: the width and height must be at least 1 px",
        ),
        (
            ["--pivot", "nan,nan"],
            "--pivot NaN,NaN: expected two finite numbers",
        ),
    ] {
        let o = rollfric(
            &["detect", "v.mp4", "-o", "a.csv", args[0], args[1]],
            d.path(),
        );
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{err}");
    }
}

#[test]
fn a_quiet_build_still_says_why_an_experiment_failed() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "a"), ("b.yaml", "index")]);
    let o = build(d.path(), &[]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("FAILED b: b.yaml: the experiment name `index`")
            && err.contains("is the reports' own"),
        "{err}"
    );
}

#[test]
fn an_impossible_twin_fails_alone_before_allocating() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "a"), ("b.yaml", "b")]);
    let huge = std::fs::read_to_string(root().join("experiments/glass-fiber-fabric.yaml"))
        .unwrap()
        .replace("name: glass-fiber-fabric", "name: huge")
        .replace("  fps: 25\n", "  fps: 1e9\n  duration_s: 1e9\n");
    assert!(huge.contains("fps: 1e9"), "fixture changed");
    std::fs::write(d.path().join("huge.yaml"), huge).unwrap();
    std::fs::write(
        d.path().join("manifest.yaml"),
        "title: budgets\nexperiments:\n  - a.yaml\n  - huge.yaml\n  - b.yaml\n",
    )
    .unwrap();
    let o = build(d.path(), &[]);
    assert!(!o.status.success());
    let s = summary(d.path());
    assert_eq!(s["experiments"][0]["status"], "ok");
    assert_eq!(s["experiments"][2]["status"], "ok");
    let e = s["experiments"][1]["error"].as_str().unwrap();
    assert!(
        e.contains("`synthetic.fps` = 1000000000 frames/s: expected more than 0 and at most 1000"),
        "{e}"
    );
    assert!(d.path().join("out/index.html").exists());
    for (args, needle) in [
        (
            vec!["simulate", "glass", "-o", "x.csv", "--fps", "1e7"],
            "`--fps` = 10000000",
        ),
        (
            vec![
                "simulate",
                "glass",
                "-o",
                "x.csv",
                "--fps",
                "1000",
                "--duration",
                "3000",
            ],
            "at most 200000 frames",
        ),
    ] {
        let o = rollfric(&args, &root());
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{err}");
    }
}

#[test]
fn a_video_is_judged_by_its_bytes_not_its_name() {
    if !common::need_ffmpeg() {
        return;
    }
    let d = tempfile::tempdir().unwrap();
    // A swinging dark line on a light background, 3 s.
    let src = "color=c=white:s=160x120:r=25:d=3,geq=lum='if(lt(abs((X-80)*cos(0.3*sin(2*PI*T/1.5))-(Y)*sin(0.3*sin(2*PI*T/1.5))),1.5),30,220)':cb=128:cr=128";
    lavfi_clip(
        d.path(),
        "mir.mp4",
        src,
        &["-c:v", "libx264", "-pix_fmt", "yuv420p"],
    );
    let named = "mirror-error-invalid-truncated.mp4";
    std::fs::copy(d.path().join("mir.mp4"), d.path().join(named)).unwrap();
    let a = rollfric(&["detect", "mir.mp4", "-o", "a.csv"], d.path());
    let b = rollfric(&["detect", named, "-o", "b.csv"], d.path());
    assert_eq!(
        a.status.success(),
        b.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&a.stderr),
        String::from_utf8_lossy(&b.stderr)
    );
    assert!(b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
    assert_eq!(
        std::fs::read(d.path().join("a.csv")).unwrap(),
        std::fs::read(d.path().join("b.csv")).unwrap()
    );
}

#[test]
fn messages_quote_input_briefly_and_in_our_words() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("dup.yaml"),
        "geometry:\n  incline: { angle_deg: 5 }\n  pendulum: { d_m: 0.2 }\n  pendulum: { d_m: 0.3 }\n",
    )
    .unwrap();
    let o = rollfric(&["fit", "dup.yaml"], d.path());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("the key `pendulum` is given twice"), "{err}");
    assert!(!err.contains("DuplicateKeyPolicy"), "{err}");
    std::fs::write(
        d.path().join("big.yaml"),
        format!("x: {}\n", "a".repeat(1 << 20)),
    )
    .unwrap();
    let o = rollfric(&["fit", "big.yaml"], d.path());
    assert!(!o.status.success());
    assert!(o.stderr.len() < 1000, "{} bytes of error", o.stderr.len());
}

#[test]
fn frames_beyond_the_video_are_named() {
    if !common::need_ffmpeg() {
        return;
    }
    let d = tempfile::tempdir().unwrap();
    lavfi_clip(
        d.path(),
        "v.mp4",
        "testsrc2=duration=1:size=160x120:rate=10",
        &["-c:v", "libx264", "-pix_fmt", "yuv420p"],
    );
    let o = rollfric(
        &["detect", "v.mp4", "-o", "a.csv", "--frames", "500,900"],
        d.path(),
    );
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("frames 500..900 asked for, but the video has only 10 (0..9)"),
        "{err}"
    );
}

#[test]
fn a_video_too_large_to_hold_is_refused_before_decoding() {
    if !common::need_ffmpeg() {
        return;
    }
    let d = tempfile::tempdir().unwrap();
    lavfi_clip(
        d.path(),
        "big.avi",
        "color=c=gray:s=8200x8200:r=1:d=1",
        &["-c:v", "mjpeg", "-q:v", "10"],
    );
    let o = rollfric(&["detect", "big.avi", "-o", "a.csv"], d.path());
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("big.avi: the frames are 8200 x 8200 px; the detector takes at most"),
        "{err}"
    );
}

#[test]
fn a_huge_input_file_is_refused_before_it_is_read() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "a")]);
    // Sparse: no disk is used, but the size is what a reader would have to hold.
    let f = std::fs::File::create(d.path().join("angles.csv")).unwrap();
    f.set_len(300 << 20).unwrap();
    let o = rollfric(&["fit", "a.yaml"], d.path());
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("angles.csv: 314572800 bytes; at most 268435456 bytes"),
        "{err}"
    );
    let y = std::fs::File::create(d.path().join("big.yaml")).unwrap();
    y.set_len(20 << 20).unwrap();
    let o = rollfric(&["fit", "big.yaml"], d.path());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("big.yaml: 20971520 bytes; at most 16777216 bytes"),
        "{err}"
    );
}

#[test]
fn a_missing_angles_file_names_the_experiment_that_points_at_it() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "a")]);
    std::fs::remove_file(d.path().join("angles.csv")).unwrap();
    let o = rollfric(&["fit", "a.yaml"], d.path());
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("a.yaml: `angles` = angles.csv: ") && err.contains("angles.csv: no such file"),
        "{err}"
    );
}

/// Encode the ffmpeg `lavfi` source `src` into `dir/name` with the codec `args`.
fn lavfi_clip(dir: &Path, name: &str, src: &str, args: &[&str]) {
    let st = std::process::Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-f", "lavfi", "-i", src])
        .args(args)
        .arg(dir.join(name))
        .status()
        .unwrap();
    assert!(st.success(), "ffmpeg could not make {name}");
}

/// The cells of a Markdown table row: `|` not escaped by a backslash, less one.
fn cells(row: &str) -> usize {
    let b = row.as_bytes();
    (0..b.len())
        .filter(|&i| b[i] == b'|' && (i == 0 || b[i - 1] != b'\\'))
        .count()
        .saturating_sub(1)
}

#[test]
fn text_in_an_experiment_file_cannot_forge_or_break_a_page() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "evil")]);
    let file = d.path().join("a.yaml");
    let forged = "Glass | 9.999e-6 ± 1e-9 | 3.714e-6 | +0.00 %";
    let script = "<script>alert(1)</script><img src=x onerror=alert(2)>";
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace(
            "material: Glass fiber fabric over glass plate",
            &format!("material: \"{forged}\""),
        )
        .replace("source: Table 1", &format!("source: \"{script}\""))
        .replace("notes: >-\n", &format!("notes: >-\n  {script} | a | b |\n"));
    std::fs::write(&file, text).unwrap();
    let manifest = d.path().join("manifest.yaml");
    let m = std::fs::read_to_string(&manifest)
        .unwrap()
        .replace("title: edges", "title: \"Steel <!-- | x\"");
    std::fs::write(&manifest, m).unwrap();
    let o = build(d.path(), &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for page in ["out/index.md", "out/evil.md"] {
        let md = std::fs::read_to_string(d.path().join(page)).unwrap();
        assert!(
            !md.contains("<script") && !md.contains("<img") && !md.contains("<!--"),
            "{page}"
        );
        // Every row of every table keeps the cells of its header.
        let mut header = None;
        for line in md.lines() {
            if !line.starts_with('|') {
                header = None;
                continue;
            }
            match header {
                None => header = Some(cells(line)),
                Some(n) => assert_eq!(cells(line), n, "{page}: {line}"),
            }
        }
    }
    // Table 1's row holds the measured value, not the forged one.
    let index = std::fs::read_to_string(d.path().join("out/index.md")).unwrap();
    let row = index.lines().find(|l| l.contains("](evil.md)")).unwrap();
    assert!(row.contains("Glass \\| 9.999e-6"), "{row}");
    assert!(row.contains("5.3"), "{row}");
    for page in ["out/index.html", "out/evil.html"] {
        let html = std::fs::read_to_string(d.path().join(page)).unwrap();
        assert!(
            !html.contains("<script>alert") && !html.contains("<img src=x"),
            "{page}"
        );
    }
}

#[test]
fn a_wider_tolerance_is_said_on_its_page_and_in_the_summary() {
    let d = tempfile::tempdir().unwrap();
    setup(d.path(), &[("a.yaml", "wide")]);
    let file = d.path().join("a.yaml");
    let text = std::fs::read_to_string(&file).unwrap()
        + "tolerances: { period_rel: 100, reason: \"d was not measured yet\" }\n";
    std::fs::write(&file, text).unwrap();
    let o = build(d.path(), &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(d.path().join("out/wide.md")).unwrap();
    assert!(
        md.contains("**Tolerances wider than their defaults:** period_rel 100 (default 0.1). Reason given: d was not measured yet"),
        "{md}"
    );
    let s = summary(d.path());
    assert_eq!(
        s["experiments"][0]["result"]["tolerances"]["reason"],
        "d was not measured yet"
    );
}
