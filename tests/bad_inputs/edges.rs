//! The corpus's hard edges: outputs that would replace a user's file, text that would
//! forge or break a page, numbers a check should have caught, and messages that must be
//! in the user's words. And the record of every case's exact message
//! (`tests/golden/bad-inputs.txt`), which a changed message must change with it.

use super::{base_yaml, case, lavfi, write, Case, OURS};
use crate::common::{rollfric, root};
use std::path::Path;

/// Every case of this file (the video ones only with `video`).
pub fn cases(dir: &Path, out: &mut Vec<Case>, video: bool) {
    output_cases(dir, out, video);
    page_cases(dir, out);
    check_cases(dir, out);
    message_cases(dir, out, video);
}

/// A copy of the corpus's valid experiment with `from` replaced by `to`, as `file`.
fn variant(dir: &Path, file: &str, from: &str, to: &str) {
    let base = base_yaml();
    assert!(base.contains(from), "{from}");
    write(dir, file, base.replacen(from, to, 1));
}

/// A manifest `file` listing `entries`.
fn manifest(dir: &Path, file: &str, entries: &[&str]) {
    write(
        dir,
        file,
        format!("title: t\nexperiments: [{}]\n", entries.join(", ")),
    );
}

/// `build` of `manifest` into `out`, with its own cache.
fn build(manifest: &str, out: &str) -> Vec<String> {
    [
        "build",
        "-q",
        "--no-wait",
        "--manifest",
        manifest,
        "--out",
        out,
        "--cache",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([format!("{out}-cache")])
    .collect()
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// Outputs that are inputs, other outputs or a user's files of another kind.
fn output_cases(dir: &Path, out: &mut Vec<Case>, video: bool) {
    write(
        dir,
        "thesis.txt",
        "Chapter 1. The rolling resistance of steel.\n",
    );
    if video {
        let v = "v-pattern.mp4";
        for (name, target, keep) in [
            ("a text file", "thesis.txt", "thesis.txt"),
            ("an experiment file", "ok.yaml", "ok.yaml"),
            ("another video", "v-gray.mp4", "v-gray.mp4"),
        ] {
            out.push(
                case(
                    format!("output detect -o {name}"),
                    &["detect", v, "-o", target],
                    OURS,
                    &[target, "--force"],
                )
                .keeping(&[keep]),
            );
        }
        for force in [false, true] {
            let mut args = vec!["detect", v, "--experiment", "twin.yaml", "-o", "twin.yaml"];
            if force {
                args.push("--force");
            }
            out.push(
                case(
                    format!("output detect -o its experiment (force {force})"),
                    &args,
                    OURS,
                    &["twin.yaml", "an input"],
                )
                .keeping(&["twin.yaml"]),
            );
        }
        out.push(
            case(
                "output init -o its video --force",
                &["init", v, "-o", v, "--force"],
                OURS,
                &[v, "that is the video"],
            )
            .keeping(&[v]),
        );
        out.push(
            case(
                "output init -o its manifest",
                &[
                    "init",
                    v,
                    "-o",
                    "m-good.yaml",
                    "--manifest",
                    "m-good.yaml",
                    "--force",
                ],
                OURS,
                &["m-good.yaml", "the manifest"],
            )
            .keeping(&["m-good.yaml"]),
        );
        out.push(
            case(
                "output synth -o a user's video",
                &["synth", "twin.yaml", "-o", v],
                OURS,
                &[v, "not a twin's video"],
            )
            .keeping(&[v]),
        );
    }
    for (name, args, needles, keep) in [
        (
            "simulate -o its experiment",
            &["simulate", "twin.yaml", "-o", "twin.yaml"][..],
            &["twin.yaml", "an input"][..],
            "twin.yaml",
        ),
        (
            "simulate -o a text file",
            &["simulate", "twin.yaml", "-o", "thesis.txt"],
            &["thesis.txt", "not an angle CSV"],
            "thesis.txt",
        ),
        (
            "synth --truth its experiment",
            &["synth", "twin.yaml", "-o", "t.mp4", "--truth", "twin.yaml"],
            &["--truth twin.yaml", "an input"],
            "twin.yaml",
        ),
        (
            "synth -o and --truth one file",
            &["synth", "twin.yaml", "-o", "t.mp4", "--truth", "t.mp4"],
            &["the same file"],
            "thesis.txt",
        ),
        (
            "synth -o a text file",
            &["synth", "twin.yaml", "-o", "thesis.txt"],
            &["thesis.txt"],
            "thesis.txt",
        ),
        (
            "synth --truth a text file",
            &[
                "synth",
                "twin.yaml",
                "-o",
                "t2.mp4",
                "--truth",
                "thesis.txt",
            ],
            &["thesis.txt", "truth CSV"],
            "thesis.txt",
        ),
    ] {
        out.push(case(format!("output {name}"), args, OURS, needles).keeping(&[keep]));
    }
    // `name:` that is the reports' own, in any case.
    for (file, name) in [("n-readme.yaml", "README"), ("n-readme2.yaml", "readme")] {
        variant(
            dir,
            file,
            "name: glass-fiber-fabric",
            &format!("name: {name}"),
        );
        let m = format!("m-{file}");
        manifest(dir, &m, &[file]);
        let o = format!("out-{name}");
        std::fs::create_dir_all(dir.join(&o)).unwrap();
        write(dir, &format!("{o}/README.md"), "# Our reports\n");
        let args = build(&m, &o);
        out.push(
            case(
                format!("output name: {name}"),
                &strs(&args),
                OURS,
                &[name, "README.md"],
            )
            .keeping(&[&format!("{o}/README.md")]),
        );
    }
    // An experiment's reports or cache folder linked elsewhere.
    manifest(dir, "m-linked.yaml", &["ok.yaml"]);
    for (what, out_dir, linked) in [
        ("reports", "out-linked", "out-linked/glass-fiber-fabric"),
        (
            "cache",
            "out-linked2",
            "out-linked2-cache/glass-fiber-fabric",
        ),
    ] {
        let elsewhere = format!("elsewhere-{what}");
        std::fs::create_dir_all(dir.join(&elsewhere)).unwrap();
        write(dir, &format!("{elsewhere}/precious.txt"), "keep me\n");
        std::fs::create_dir_all(dir.join(linked).parent().unwrap()).unwrap();
        std::os::unix::fs::symlink(dir.join(&elsewhere), dir.join(linked)).unwrap();
        let args = build("m-linked.yaml", out_dir);
        out.push(
            case(
                format!("output a linked {what} folder"),
                &strs(&args),
                OURS,
                &["symbolic link"],
            )
            .keeping(&[&format!("{elsewhere}/precious.txt")]),
        );
    }
}

/// Text that would forge or break a page, or is too long to echo.
fn page_cases(dir: &Path, out: &mut Vec<Case>) {
    let huge = "x".repeat(10 << 20);
    let long = "y".repeat(5000);
    for (name, from, to, needles) in [
        (
            "a 10 MB material",
            "material: Glass fiber fabric over glass plate",
            format!("material: \"{huge}\""),
            &["`material`", "10485760 characters"][..],
        ),
        (
            "a 5000-character reference source",
            "source: Table 1",
            format!("source: \"{long}\""),
            &["`reference.source`", "at most 120"][..],
        ),
        (
            "a 250-character name",
            "name: glass-fiber-fabric",
            format!("name: {}", "n".repeat(250)),
            &["`name`", "at most 64"][..],
        ),
    ] {
        let file = format!("p-{}.yaml", name.replace(' ', "-"));
        variant(dir, &file, from, &to);
        out.push(
            case(format!("page {name}"), &["fit", &file], OURS, needles).never(&[&"x".repeat(100)]),
        );
    }
    // Paragraphs: an accepted warning's reason, a wider tolerance's reason.
    for (name, tail, key) in [
        (
            "an accept reason",
            format!("accept: [{{check: period, reason: \"{long}\"}}]\n"),
            "`accept[0].reason`",
        ),
        (
            "a tolerance reason",
            format!("tolerances: {{ period_rel: 1, reason: \"{long}\" }}\n"),
            "`tolerances.reason`",
        ),
    ] {
        let file = format!("p-long-{}.yaml", name.replace(' ', "-"));
        write(dir, &file, format!("{}{tail}", base_yaml()));
        out.push(
            case(
                format!("page 5000 characters of {name}"),
                &["fit", &file],
                OURS,
                &[key, "at most 4000"],
            )
            .never(&["yyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyy"]),
        );
    }
    // The manifest's title, and a manifest that lists a file of another kind.
    write(
        dir,
        "m-long-title.yaml",
        format!("title: \"{huge}\"\nexperiments: [ok.yaml]\n"),
    );
    let args = build("m-long-title.yaml", "out-long-title");
    out.push(
        case(
            "page a 10 MB title",
            &strs(&args),
            OURS,
            &["`title`", "at most 120"],
        )
        .never(&[&"x".repeat(100)]),
    );
    manifest(dir, "m-passwd.yaml", &["/etc/passwd"]);
    let args = build("m-passwd.yaml", "out-passwd");
    out.push(
        case(
            "page a manifest listing /etc/passwd",
            &strs(&args),
            OURS,
            &["not an experiment file"],
        )
        .never(&["root:", "/bin/"]),
    );
    // The same file listed 20 000 times: short errors, in seconds.
    let many = vec!["ok.yaml"; 20_000];
    manifest(dir, "m-many.yaml", &many);
    let args = build("m-many.yaml", "out-many");
    out.push(
        case(
            "page one file listed 20000 times",
            &strs(&args),
            OURS,
            &["and 19996 more"],
        )
        .loud(),
    );
}

/// Numbers a check must catch, and summaries `check` must refuse.
fn check_cases(dir: &Path, out: &mut Vec<Case>) {
    for (name, from, to, needles) in [
        (
            "diameter as radius",
            "radius_m: 0.03175",
            "radius_m: 0.0635",
            &["`geometry.ball`", "975 kg/m^3", "the diameter"][..],
        ),
        (
            "a radius ten times too small",
            "radius_m: 0.03175",
            "radius_m: 0.003175",
            &["`geometry.ball`", "in grams"][..],
        ),
        (
            "a steel ball called glass",
            "mass_kg: 1.0458",
            "mass_kg: 1.0458, material: glass",
            &["a glass ball has 2400 to 2800"][..],
        ),
        (
            "a ball of an unknown material",
            "mass_kg: 1.0458",
            "mass_kg: 1.0458, material: unobtainium",
            &["`geometry.ball.material`", "`other`"][..],
        ),
        (
            "a radius of 1e-9 m",
            "radius_m: 0.03175",
            "radius_m: 1e-9",
            &["radius of 1e-9 m"][..],
        ),
        (
            "a contact length of 1e-6 m",
            "d_m: 0.1712",
            "contact_length_m: 1e-6",
            &[
                "`geometry.pendulum.contact_length_m` = 1e-6 m",
                "standard uncertainty",
            ][..],
        ),
    ] {
        let file = format!("c-{}.yaml", name.replace(' ', "-"));
        variant(dir, &file, from, to);
        out.push(case(format!("number {name}"), &["fit", &file], OURS, needles).never(&["e-4 m:"]));
    }
    // Each tolerance widened with no reason; with one, the file is taken.
    for (key, wide) in [
        ("reference_rel", "1"),
        ("truth_rel", "1"),
        ("period_rel", "100"),
        ("residual_factor", "1000"),
        ("envelope_aicc", "1e6"),
        ("halves_rel", "100"),
        ("interval_rel", "10"),
        ("outliers", "3"),
        ("pivot_rel", "1"),
    ] {
        let file = format!("c-wide-{key}.yaml");
        write(
            dir,
            &file,
            format!("{}tolerances: {{ {key}: {wide} }}\n", base_yaml()),
        );
        out.push(case(
            format!("number a wider {key} with no reason"),
            &["fit", &file],
            OURS,
            &[&format!("`tolerances.{key}`"), "tolerances.reason"],
        ));
    }
    write(
        dir,
        "c-wide-said.yaml",
        format!(
            "{}tolerances: {{ period_rel: 100, reason: \"d not measured yet\" }}\n",
            base_yaml()
        ),
    );
    out.push(case(
        "number a wider tolerance with its reason",
        &["fit", "c-wide-said.yaml"],
        0,
        &["s_r"],
    ));
    // Out of range on the command line.
    for (name, args, needles) in [
        (
            "simulate --noise-deg 1e300",
            &[
                "simulate",
                "twin.yaml",
                "-o",
                "n.csv",
                "--noise-deg",
                "1e300",
            ][..],
            &["`--noise-deg` = 1e300 deg", "from 0 to 10"][..],
        ),
        (
            "simulate --noise-deg 11",
            &["simulate", "twin.yaml", "-o", "n.csv", "--noise-deg", "11"],
            &["--noise-deg"],
        ),
        (
            "torsion --s-r 1e300",
            &["torsion", "twin.yaml", "--s-r", "1e300"],
            &["`--s-r` = 1e300 m", "from 0 to 0.01"],
        ),
        (
            "torsion --s-r 0.5",
            &["torsion", "twin.yaml", "--s-r", "0.5"],
            &["--s-r"],
        ),
    ] {
        out.push(case(format!("number {name}"), args, OURS, needles));
    }
    // Summaries `check` must refuse: a real one, edited.
    manifest(dir, "m-summary.yaml", &["ok.yaml"]);
    let built = rollfric(&build("m-summary.yaml", "out-summary"), dir);
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let good: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("out-summary/summary.json")).unwrap())
            .unwrap();
    type Edit = fn(&mut serde_json::Value);
    let edits: [(&str, Edit, &str); 9] = [
        (
            "failed with a result",
            |s| s["experiments"][0]["status"] = "failed".into(),
            "status `failed` with a result",
        ),
        (
            "ok with no result",
            |s| s["experiments"][0]["result"] = serde_json::Value::Null,
            "status `ok` with no result",
        ),
        (
            "no verdict",
            |s| {
                s["experiments"][0]["result"]
                    .as_object_mut()
                    .unwrap()
                    .remove("verdict");
            },
            "no `verdict`",
        ),
        (
            "suspect with no warnings",
            |s| s["experiments"][0]["result"]["verdict"] = "suspect".into(),
            "verdict `suspect` with 0 warning(s)",
        ),
        (
            "comparisons deleted",
            |s| s["experiments"][0]["result"]["checks"] = serde_json::json!([]),
            "0 comparison(s) where its reference and synthetic truth call for 3",
        ),
        (
            "a tolerance loosened",
            |s| s["experiments"][0]["result"]["checks"][0]["tolerance_rel"] = 100.0.into(),
            "is not the result's own",
        ),
        (
            "a value edited",
            |s| s["experiments"][0]["result"]["checks"][1]["value"] = 1.0.into(),
            "is not the result's own",
        ),
        (
            "a warning of no check",
            |s| {
                s["experiments"][0]["result"]["verdict"] = "suspect".into();
                s["experiments"][0]["result"]["warnings"] = serde_json::json!([
                    {"check": "luck", "value": 1.0, "limit": 0.0, "reason": "r"}
                ]);
            },
            "no known check (`luck`)",
        ),
        (
            "a widened tolerance with no reason",
            |s| s["experiments"][0]["result"]["tolerances"]["period_rel"] = 100.0.into(),
            "`tolerances.period_rel` is wider than its default",
        ),
    ];
    for (k, (name, edit, needle)) in edits.into_iter().enumerate() {
        let mut s = good.clone();
        edit(&mut s);
        let file = format!("s-{k}.json");
        write(dir, &file, serde_json::to_vec(&s).unwrap());
        out.push(case(
            format!("summary {name}"),
            &["check", "--summary", &file],
            OURS,
            &[&file, needle, "build it again"],
        ));
    }
    write(dir, "s-not-json.json", "{\"title\": ");
    out.push(case(
        "summary not JSON",
        &["check", "--summary", "s-not-json.json"],
        OURS,
        &["s-not-json.json", "not a rollfric summary"],
    ));
}

/// Messages that were unclear: library or ffmpeg wording, temporary names, "does not
/// exist" for what exists.
fn message_cases(dir: &Path, out: &mut Vec<Case>, video: bool) {
    let fifo = dir.join("fifo.yaml");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    assert!(made, "mkfifo");
    for (name, args, needles) in [
        (
            "fit a FIFO",
            &["fit", "fifo.yaml"][..],
            &["fifo.yaml", "not a regular file"][..],
        ),
        (
            "fit /dev/zero",
            &["fit", "/dev/zero"],
            &["/dev/zero", "not a regular file"],
        ),
        ("fit a folder", &["fit", "."], &["is a folder"]),
        (
            "detect a FIFO",
            &["detect", "fifo.yaml", "-o", "x.csv"],
            &["fifo.yaml", "not a regular file"],
        ),
        (
            "detect /dev/zero",
            &["detect", "/dev/zero", "-o", "x.csv"],
            &["not a regular file"],
        ),
        (
            "detect a folder",
            &["detect", "sub", "-o", "x.csv"],
            &["sub", "is a folder"],
        ),
        (
            "fit --angles a FIFO",
            &["fit", "ok.yaml", "--angles", "fifo.yaml"],
            &["not a regular file"],
        ),
        (
            "build a FIFO manifest",
            &[
                "build",
                "-q",
                "--manifest",
                "fifo.yaml",
                "--out",
                "out-fifo",
            ],
            &["not a regular file"],
        ),
        (
            "synth -o an unknown extension",
            &["synth", "twin.yaml", "-o", "t.xyz"],
            &["t.xyz", "expected a video file name"],
        ),
        (
            "fit a missing file",
            &["fit", "nothing-here.yaml"],
            &["nothing-here.yaml", "no such file"],
        ),
    ] {
        out.push(case(format!("message {name}"), args, OURS, needles).never(&[".rollfric-"]));
    }
    // Two YAML documents in one file.
    write(
        dir,
        "two-docs.yaml",
        format!("{}---\nname: again\n", base_yaml()),
    );
    out.push(
        case(
            "message two YAML documents",
            &["fit", "two-docs.yaml"],
            OURS,
            &["second YAML document"],
        )
        .never(&["from_str_multiple"]),
    );
    // Clock times (seconds since 1970) are fitted from the first frame.
    let csv = std::fs::read_to_string(dir.join("angles.csv")).unwrap();
    let mut epoch = String::new();
    for (i, l) in csv.lines().enumerate() {
        if i == 0 {
            epoch.push_str(l);
        } else {
            let (t, rest) = l.split_once(',').unwrap();
            let t: f64 = t.parse().unwrap();
            epoch.push_str(&format!("{:.6},{rest}", t + 1.7e9));
        }
        epoch.push('\n');
    }
    write(dir, "epoch.csv", epoch);
    out.push(case(
        "message clock times",
        &["fit", "ok.yaml", "--angles", "epoch.csv"],
        0,
        &["turning points"],
    ));
    if video {
        video_message_cases(dir, out);
    }
}

/// The video cases among the messages: an RGB video, a PNG named `.mp4`, a twin's
/// pivot given far off, `init` into a manifest twice and into an empty one, and a
/// fast twin (past the frame count where frames were once dropped).
fn video_message_cases(dir: &Path, out: &mut Vec<Case>) {
    lavfi(
        dir,
        "testsrc=s=320x240:d=2:r=25",
        &["-c:v", "png", "v-rgb.mov"],
    );
    std::fs::copy(dir.join("v-still.png"), dir.join("v-png.mp4")).unwrap();
    for (name, file, needles) in [
        (
            "an RGB video",
            "v-rgb.mov",
            &["v-rgb.mov", "no moving wire"][..],
        ),
        (
            "a PNG named .mp4",
            "v-png.mp4",
            &["v-png.mp4", "too few frames (1)"],
        ),
    ] {
        out.push(
            case(
                format!("message {name}"),
                &["detect", file, "-o", "x.csv"],
                OURS,
                needles,
            )
            .never(&["damaged", "Requested planes", "reinitializing"]),
        );
    }
    out.push(
        case(
            "message audio only",
            &["detect", "v-audio.mp4", "-o", "x.csv"],
            OURS,
            &["no video stream"],
        )
        .never(&["Stream map"]),
    );
    // A short twin, and one at 240 frames/s for 9 s (2161 frames, past 500 000 / fps).
    let twin = std::fs::read_to_string(root().join("experiments/glass-fiber-fabric.yaml"))
        .unwrap()
        .replace("width: 960", "width: 480")
        .replace("height: 540", "height: 270");
    write(
        dir,
        "tw.yaml",
        twin.replace("name: glass-fiber-fabric", "name: tw"),
    );
    write(
        dir,
        "tw240.yaml",
        twin.replace("name: glass-fiber-fabric", "name: tw240")
            .replace("fps: 25", "fps: 240"),
    );
    let synth = |exp: &str, video: &str, secs: &str| {
        let o = rollfric(&["synth", exp, "-o", video, "--duration", secs], dir);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert!(o.status.success(), "{err}");
        err
    };
    let said = synth("tw.yaml", "tw.mp4", "8");
    synth("tw240.yaml", "tw240.mp4", "9");
    out.push(case(
        "message a 240 fps twin past 500000 / fps frames",
        &["detect", "tw240.mp4", "-o", "tw240.csv"],
        0,
        &["2161 frames"],
    ));
    // The rendered pivot, from `pivot (x, y) px`.
    let pivot = said
        .split("pivot (")
        .nth(1)
        .and_then(|s| s.split(')').next())
        .unwrap();
    let (x, y) = pivot.split_once(", ").unwrap();
    let off = format!("{:.1},{y}", x.parse::<f64>().unwrap() + 60.0);
    out.push(case(
        "message a pivot given 60 px off",
        &["detect", "tw.mp4", "-o", "x.csv", "--pivot", &off],
        OURS,
        &["the given pivot", "video.pivot"],
    ));
    write(
        dir,
        "m-init.yaml",
        "title: t\nexperiments:\n  - tw-a.yaml\n",
    );
    write(dir, "tw-a.yaml", "");
    out.push(
        case(
            "message init into a manifest listing it already",
            &[
                "init",
                "tw.mp4",
                "-o",
                "tw-a.yaml",
                "--manifest",
                "m-init.yaml",
                "--force",
            ],
            0,
            &["lists tw-a.yaml already"],
        )
        .keeping(&["m-init.yaml"]),
    );
    write(dir, "m-init-empty.yaml", "title: t\nexperiments: []\n");
    out.push(case(
        "message init into an empty manifest",
        &[
            "init",
            "tw.mp4",
            "-o",
            "tw-b.yaml",
            "--manifest",
            "m-init-empty.yaml",
        ],
        0,
        &["lists tw-b.yaml now"],
    ));
}

/// The record of every failing case's message: `tests/golden/bad-inputs.txt`, one
/// `name<TAB>message` line a case. Returns a line for each case whose message differs
/// from the record, is not recorded, or is recorded for no case (without `video`, the
/// video cases' records are not asked for). `ROLLFRIC_BLESS=1` writes the record anew.
pub fn messages_as_recorded(said: &[(String, String)], video: bool) -> Vec<String> {
    let path = root().join("tests/golden/bad-inputs.txt");
    let mut now: Vec<(String, String)> = said.to_vec();
    now.sort();
    let text: String = now.iter().map(|(n, m)| format!("{n}\t{m}\n")).collect();
    if std::env::var_os("ROLLFRIC_BLESS").is_some() {
        std::fs::write(&path, &text).unwrap();
        return Vec::new();
    }
    let recorded = std::fs::read_to_string(&path).unwrap_or_default();
    let old: std::collections::BTreeMap<&str, &str> = recorded
        .lines()
        .filter_map(|l| l.split_once('\t'))
        .collect();
    let mut wrong = Vec::new();
    for (n, m) in &now {
        match old.get(n.as_str()) {
            Some(o) if o == m => {}
            Some(o) => wrong.push(format!("{n}: says `{m}`, recorded `{o}`")),
            None => wrong.push(format!("{n}: no recorded message (says `{m}`)")),
        }
    }
    if video {
        for n in old.keys() {
            if !now.iter().any(|(m, _)| m == n) {
                wrong.push(format!("{n}: recorded, but no such case"));
            }
        }
    }
    if !wrong.is_empty() {
        wrong.push(
            "(after an intended change of messages: ROLLFRIC_BLESS=1 cargo test --release \
             --test bad_inputs, and review tests/golden/bad-inputs.txt's diff)"
                .to_string(),
        );
    }
    wrong
}
