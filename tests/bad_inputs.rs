//! A corpus of bad inputs, generated at test time in a temporary folder, each run through
//! the `rollfric` binary with its expected exit code and the words its error must say:
//! experiment YAML (bad keys, types, values, empty, binary, huge, nested, not UTF-8,
//! duplicate keys), manifests (missing, duplicated, escaping, empty), angle CSVs (empty,
//! NaN, unordered, wrong columns, huge, degrees), videos (empty, truncated, random bytes,
//! a still image, no wire, audio only) and flags (out of range, conflicting).
//!
//! Every case: no panic, the expected non-zero exit code, a short standard error (one
//! line for our own errors, the usage note of a flag the parser refuses) that names the
//! file, key or flag.

mod common;
#[path = "bad_inputs/edges.rs"]
mod edges;

use common::{have_ffmpeg, need_ffmpeg, rollfric, root, simulate_csv};
use rollfric::rng::Rng;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Our own errors: exit 1 and one line. The flag parser's: exit 2 and its usage note.
const OURS: i32 = 1;
const USAGE: i32 = 2;

/// Cases that expose a fault not fixed yet: their checks are reported, not asserted.
/// Each entry is a case name; keep it empty when none.
const KNOWN_FAILURES: &[&str] = &[];

struct Case {
    name: String,
    args: Vec<String>,
    code: i32,
    /// Words the standard error must contain (the file, key or flag it names); for a
    /// case that succeeds, its standard output or error.
    needles: Vec<String>,
    /// Words the standard error must not contain (a quoted secret, a library's advice).
    never: Vec<String>,
    /// Files (relative to the case folder) whose bytes the command must leave as they
    /// were.
    unchanged: Vec<String>,
    /// A line of standard error for each of many experiments is expected.
    loud: bool,
}

fn case(name: impl Into<String>, args: &[&str], code: i32, needles: &[&str]) -> Case {
    Case {
        name: name.into(),
        args: args.iter().map(|s| s.to_string()).collect(),
        code,
        needles: needles.iter().map(|s| s.to_string()).collect(),
        never: Vec::new(),
        unchanged: Vec::new(),
        loud: false,
    }
}

impl Case {
    fn never(mut self, words: &[&str]) -> Self {
        self.never.extend(words.iter().map(|s| s.to_string()));
        self
    }

    fn loud(mut self) -> Self {
        self.loud = true;
        self
    }

    fn keeping(mut self, files: &[&str]) -> Self {
        self.unchanged.extend(files.iter().map(|s| s.to_string()));
        self
    }
}

fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) {
    std::fs::write(dir.join(name), bytes).unwrap();
}

/// The glass-fiber row measured from `angles.csv` (no twin): a valid experiment.
fn base_yaml() -> String {
    let text = std::fs::read_to_string(root().join("experiments/glass-fiber-fabric.yaml"))
        .unwrap()
        .split("\nsynthetic:")
        .next()
        .unwrap()
        .to_string();
    text + "\nangles: angles.csv\n"
}

fn ffmpeg(dir: &Path, args: &[&str]) {
    let st = Command::new("ffmpeg")
        .args(["-v", "error", "-y"])
        .args(args)
        .current_dir(dir)
        .status()
        .unwrap();
    assert!(st.success(), "ffmpeg {args:?}");
}

/// `ffmpeg -f lavfi -i SOURCE ARGS...` in `dir`: a test clip from a generated source.
fn lavfi(dir: &Path, source: &str, args: &[&str]) {
    let all: Vec<&str> = ["-f", "lavfi", "-i", source]
        .into_iter()
        .chain(args.iter().copied())
        .collect();
    ffmpeg(dir, &all);
}

/// YAML cases: each `rollfric fit <file>` fails naming the file and the key.
fn yaml_cases(dir: &Path, out: &mut Vec<Case>) {
    let base = base_yaml();
    let mut n = 0;
    let mut add = |out: &mut Vec<Case>, text: &[u8], needles: &[&str]| {
        n += 1;
        let file = format!("y{n:03}.yaml");
        write(dir, &file, text);
        let mut needles = needles.to_vec();
        needles.push(&file);
        out.push(case(
            format!("yaml {file}"),
            &["fit", &file],
            OURS,
            &needles,
        ));
    };
    // Each number of the file, given a value it cannot take.
    let keys = [
        ("d_m: 0.1712", "d_m"),
        ("radius_m: 0.03175", "radius_m"),
        ("mass_kg: 1.0458", "mass_kg"),
        ("h_m: 0.142", "h_m"),
        ("l_m: 1.500", "l_m"),
        ("beta: 1", "beta"),
        ("period_s: 205.3", "period_s"),
        ("wire_length_m: 0.2", "wire_length_m"),
        ("psi0_max_deg: 15", "psi0_max_deg"),
        ("mu: 0.35", "mu"),
    ];
    let values = ["abc", "-1", "1e400", ".nan", "-.inf", "[1, 2]", "{a: 1}"];
    for (orig, key) in keys {
        assert!(base.contains(orig), "{orig}");
        for v in values {
            let text = base.replace(orig, &format!("{key}: {v}"));
            add(out, text.as_bytes(), &[key]);
        }
    }
    // Values out of their range.
    for (orig, bad, key) in [
        ("d_m: 0.1712", "d_m: 0", "d_m"),
        ("d_m: 0.1712", "d_m: 1e9", "d_m"),
        ("radius_m: 0.03175", "radius_m: 0", "radius_m"),
        ("h_m: 0.142", "h_m: 2.0", "h_m"),
        ("beta: 1", "beta: 7", "beta"),
        ("beta: 1", "beta: fancy", "beta"),
        ("psi0_max_deg: 15", "psi0_max_deg: 95", "psi0_max_deg"),
        ("mass_kg: 1.0458", "mass_kg: 0", "mass_kg"),
    ] {
        add(out, base.replace(orig, bad).as_bytes(), &[key]);
    }
    // Unknown keys, at the top and inside blocks.
    for (orig, bad, key) in [
        ("geometry:", "geometri:", "geometri"),
        ("model:", "modle:", "modle"),
        ("d_m: 0.1712", "length_m: 0.1712", "length_m"),
        ("radius_m:", "radius:", "radius"),
        ("mu: 0.35", "muu: 0.35", "muu"),
    ] {
        add(out, base.replace(orig, bad).as_bytes(), &[key]);
    }
    // Names that cannot name output files.
    for bad in ["a/b", "../up", "\"\"", "x y", "é"] {
        let text = base.replace("name: glass-fiber-fabric", &format!("name: {bad}"));
        add(out, text.as_bytes(), &["name"]);
    }
    // Duplicate keys.
    add(
        out,
        format!("{base}name: again\n").as_bytes(),
        &["name", "twice"],
    );
    let text = base.replace("d_m: 0.1712", "d_m: 0.1712, d_m: 0.2");
    add(out, text.as_bytes(), &["d_m", "twice"]);
    // Not a mapping, empty, binary, not UTF-8, huge, nested, aliases.
    add(out, b"", &[]);
    add(out, b"   \n\n", &[]);
    add(out, b"- a\n- b\n", &[]);
    add(out, b"just words", &[]);
    let mut rng = Rng::new(5);
    let bin: Vec<u8> = (0..4096).map(|_| rng.next_u64() as u8).collect();
    add(out, &bin, &[]);
    let latin1 = base
        .replace("Glass fiber", "Glas\u{e9}")
        .replace('\u{e9}', "\u{0}");
    let mut bytes = latin1.into_bytes();
    let at = bytes.iter().position(|&b| b == 0).unwrap();
    bytes[at] = 0xE9; // é in Latin-1
    add(out, &bytes, &["UTF-8"]);
    let huge = format!("name: x\nnotes: {}\n:", "z".repeat(10 << 20));
    add(out, huge.as_bytes(), &[]);
    add(
        out,
        format!("geometry: {}1{}", "[".repeat(100_000), "]".repeat(100_000)).as_bytes(),
        &[],
    );
    add(
        out,
        format!("geometry: {}", "{a: ".repeat(50_000)).as_bytes(),
        &[],
    );
    let mut laughs = String::from("a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n");
    for k in 1..12 {
        let p = k - 1;
        laughs.push_str(&format!(
            "a{k}: &a{k} [*a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}]\n"
        ));
    }
    add(out, laughs.as_bytes(), &[]);
    add(
        out,
        base.replace("  pendulum", "\tpendulum").as_bytes(),
        &[],
    );
    // Angles and videos it names that are not there.
    for (file, needle) in [("y-nowhere.yaml", "nowhere.csv"), ("y-folder.yaml", "sub")] {
        write(
            dir,
            file,
            base.replace("angles: angles.csv", &format!("angles: {needle}")),
        );
        out.push(case(
            format!("yaml {file}"),
            &["fit", file],
            OURS,
            &[needle],
        ));
    }
    let text = base.replace("angles: angles.csv", "video: { path: nowhere.mp4 }");
    add(out, text.as_bytes(), &["nowhere.mp4"]);
    // A twin past its budgets.
    let twin = |extra: &str| {
        base.replace("angles: angles.csv", "")
            + &format!("synthetic: {{ s_r_m: 5e-5, psi0_deg: 10, {extra} }}\n")
    };
    add(out, twin("fps: 1e9, duration_s: 1e9").as_bytes(), &["fps"]);
    add(
        out,
        twin("fps: 25, duration_s: 1e9").as_bytes(),
        &["duration_s"],
    );
    add(out, twin("fps: -25").as_bytes(), &["fps"]);
    add(out, twin("fps: 25, width: 0").as_bytes(), &["width"]);
    add(
        out,
        twin("fps: 25, width: 100000, height: 100000").as_bytes(),
        &["width"],
    );
}

/// Angle CSV cases: `rollfric fit ok.yaml --angles <file>` fails naming the file.
fn csv_cases(dir: &Path, out: &mut Vec<Case>) {
    let good = std::fs::read_to_string(dir.join("angles.csv")).unwrap();
    let rows: Vec<&str> = good.lines().skip(1).collect();
    let map = |f: &dyn Fn(f64, f64) -> (f64, f64)| {
        let mut s = String::from("t_s,angle_rad\n");
        for r in &rows {
            let (t, a) = r.split_once(',').unwrap();
            let (t, a) = f(t.parse().unwrap(), a.parse().unwrap());
            s.push_str(&format!("{t},{a}\n"));
        }
        s
    };
    let mut unordered: Vec<&str> = rows.clone();
    unordered.swap(10, 20);
    let mut rng = Rng::new(7);
    let bin: Vec<u8> = (0..2048).map(|_| rng.next_u64() as u8).collect();
    let cases: Vec<(&str, Vec<u8>, &[&str])> = vec![
        ("empty", vec![], &["empty"]),
        ("blank", b"\n\n  \n".to_vec(), &["empty"]),
        ("header-only", b"t_s,angle_rad\n".to_vec(), &["no data"]),
        ("nan", good.replacen(",", ",nan_", 1).into_bytes(), &["t_s"]),
        (
            "nan-angle",
            format!("t_s,angle_rad\n{}\n0.9,NaN\n", rows[..20].join("\n")).into_bytes(),
            &["angle_rad", "NaN"],
        ),
        (
            "inf-angle",
            format!("t_s,angle_rad\n{}\n0.9,inf\n", rows[..20].join("\n")).into_bytes(),
            &["angle_rad"],
        ),
        (
            "unordered",
            format!("t_s,angle_rad\n{}\n", unordered.join("\n")).into_bytes(),
            &["t_s", "does not increase"],
        ),
        (
            "repeated-time",
            format!("t_s,angle_rad\n{}\n{}\n", rows[..5].join("\n"), rows[4]).into_bytes(),
            &["t_s", "does not increase"],
        ),
        (
            "wrong-columns",
            good.replacen("t_s,angle_rad", "time,angle", 1).into_bytes(),
            &["t_s"],
        ),
        (
            "no-angle-column",
            good.replacen("t_s,angle_rad", "t_s,angle_deg", 1)
                .into_bytes(),
            &["angle_rad"],
        ),
        (
            "ragged",
            format!("t_s,angle_rad\n{}\n9,1,2\n", rows[..5].join("\n")).into_bytes(),
            &["line"],
        ),
        (
            "bad-status",
            b"t_s,angle_rad,status\n0,1,fine\n".to_vec(),
            &["status"],
        ),
        (
            "all-missing",
            b"t_s,angle_rad,status\n0,,missing\n1,,missing\n".to_vec(),
            &["no data"],
        ),
        ("huge", map(&|t, _| (t, 1e300)).into_bytes(), &[]),
        ("x1e5", map(&|t, a| (t, a * 1e5)).into_bytes(), &[]),
        ("x1e6", map(&|t, a| (t, a * 1e6)).into_bytes(), &[]),
        (
            "degrees",
            map(&|t, a| (t, a.to_degrees())).into_bytes(),
            &["degrees"],
        ),
        ("constant", map(&|t, _| (t, 1.5)).into_bytes(), &[]),
        (
            "times-x1e12",
            map(&|t, a| (t * 1e12, a)).into_bytes(),
            &["periods"],
        ),
        (
            "few-rows",
            format!("t_s,angle_rad\n{}\n", rows[..4].join("\n")).into_bytes(),
            &[],
        ),
        ("binary", bin, &[]),
        (
            "not-utf8",
            b"t_s,angle_rad\n0,1\n\xff\xfe,2\n".to_vec(),
            &[],
        ),
        (
            "long-line",
            format!("t_s,angle_rad\n0,{}\n", "9".repeat(1 << 20)).into_bytes(),
            &["line 2"],
        ),
        (
            "quoted-newline",
            b"t_s,angle_rad\n\"0\n1\",2\n".to_vec(),
            &["t_s"],
        ),
    ];
    for (name, bytes, needles) in cases {
        let file = format!("c-{name}.csv");
        write(dir, &file, bytes);
        let mut needles = needles.to_vec();
        needles.push(&file);
        out.push(case(
            format!("csv {name}"),
            &["fit", "ok.yaml", "--angles", &file],
            OURS,
            &needles,
        ));
    }
    out.push(case(
        "csv absent",
        &["fit", "ok.yaml", "--angles", "absent.csv"],
        OURS,
        &["absent.csv"],
    ));
    out.push(case(
        "csv a folder",
        &["fit", "ok.yaml", "--angles", "sub"],
        OURS,
        &["sub"],
    ));
}

/// Manifest cases: `rollfric build --manifest <file>` fails naming the manifest or the
/// entry; a failing experiment fails alone (exit 1, its reason said).
fn manifest_cases(dir: &Path, out: &mut Vec<Case>) {
    let build = |m: &str, o: &str| -> Vec<String> {
        [
            "build",
            "-q",
            "--no-wait",
            "--manifest",
            m,
            "--out",
            o,
            "--cache",
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([format!("{o}-cache")])
        .collect()
    };
    let manifests: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "empty-list",
            "title: t\nexperiments: []\n".into(),
            vec!["experiments"],
        ),
        ("no-list", "title: t\n".into(), vec!["experiments"]),
        (
            "not-a-list",
            "title: t\nexperiments: ok.yaml\n".into(),
            vec!["experiments"],
        ),
        (
            "unknown-key",
            "title: t\nexperimnts: [ok.yaml]\n".into(),
            vec!["experimnts"],
        ),
        ("empty", String::new(), vec![]),
        ("binary", "\u{1}\u{2}\u{3}: [\u{7f}".into(), vec![]),
        (
            "missing-entry",
            "title: t\nexperiments: [gone.yaml]\n".into(),
            vec!["gone.yaml"],
        ),
        (
            "duplicated",
            "title: t\nexperiments: [ok.yaml, ok.yaml]\n".into(),
            vec!["ok.yaml"],
        ),
        (
            "duplicated-spelling",
            "title: t\nexperiments: [ok.yaml, ./ok.yaml]\n".into(),
            vec!["ok.yaml"],
        ),
        (
            "escaping",
            "title: t\nexperiments: [../../../../../../etc/passwd]\n".into(),
            vec!["passwd"],
        ),
        (
            "absolute",
            "title: t\nexperiments: [/etc/passwd]\n".into(),
            vec!["passwd"],
        ),
        (
            "a-folder",
            "title: t\nexperiments: [sub]\n".into(),
            vec!["sub"],
        ),
        (
            "bad-experiment",
            "title: t\nexperiments: [y001.yaml]\n".into(),
            vec!["y001.yaml"],
        ),
        (
            "same-name",
            "title: t\nexperiments: [ok.yaml, ok-copy.yaml]\n".into(),
            vec!["ok-copy.yaml"],
        ),
        (
            "name-index",
            "title: t\nexperiments: [index.yaml]\n".into(),
            vec!["index"],
        ),
    ];
    for (name, text, needles) in manifests {
        let file = format!("m-{name}.yaml");
        write(dir, &file, text);
        let mut needles = needles.clone();
        if ![
            "bad-experiment",
            "same-name",
            "name-index",
            "escaping",
            "absolute",
            "missing-entry",
            "a-folder",
            "duplicated",
            "duplicated-spelling",
        ]
        .contains(&name)
        {
            needles.push(&file);
        }
        let args = build(&file, &format!("out-{name}"));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        out.push(case(format!("manifest {name}"), &args, OURS, &needles));
    }
    let args = build("m-absent.yaml", "out-absent");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    out.push(case("manifest absent", &args, OURS, &["m-absent.yaml"]));
    // Outputs that would overwrite inputs.
    write(dir, "m-good.yaml", "title: t\nexperiments: [ok.yaml]\n");
    out.push(case(
        "build into the experiments folder",
        &["build", "-q", "--manifest", "m-good.yaml", "--out", "."],
        OURS,
        &["--out"],
    ));
}

/// Video cases: `rollfric detect <video> -o a.csv` fails naming the video.
fn video_cases(dir: &Path, out: &mut Vec<Case>) {
    let mut rng = Rng::new(9);
    let random: Vec<u8> = (0..200_000).map(|_| rng.next_u64() as u8).collect();
    write(dir, "v-empty.mp4", b"");
    write(dir, "v-random.mp4", &random);
    write(dir, "v-random.avi", &random);
    write(dir, "v-text.mp4", "this is not a video\n");
    let mut files = vec![
        ("v-empty.mp4", vec!["v-empty.mp4"]),
        ("v-random.mp4", vec!["v-random.mp4"]),
        ("v-random.avi", vec!["v-random.avi"]),
        ("v-text.mp4", vec!["v-text.mp4"]),
        ("v-absent.mp4", vec!["v-absent.mp4"]),
        ("sub", vec!["sub"]),
    ];
    if have_ffmpeg() {
        // A still image, a clip with nothing to find, audio only, a truncated clip.
        lavfi(
            dir,
            "testsrc=s=320x240:d=1",
            &["-frames:v", "1", "v-still.png"],
        );
        lavfi(
            dir,
            "testsrc=s=320x240:d=1",
            &["-frames:v", "1", "v-still.jpg"],
        );
        lavfi(
            dir,
            "color=c=gray:s=320x240:d=2:r=25",
            &["-c:v", "libx264", "-pix_fmt", "yuv420p", "v-gray.mp4"],
        );
        lavfi(
            dir,
            "testsrc=s=320x240:d=2:r=25",
            &["-c:v", "libx264", "-pix_fmt", "yuv420p", "v-pattern.mp4"],
        );
        lavfi(dir, "sine=f=440:d=2", &["-c:a", "aac", "v-audio.mp4"]);
        lavfi(dir, "sine=f=440:d=2", &["v-audio.wav"]);
        let clip = std::fs::read(dir.join("v-pattern.mp4")).unwrap();
        write(dir, "v-half.mp4", &clip[..clip.len() / 2]);
        write(dir, "v-head.mp4", &clip[..200.min(clip.len())]);
        for f in [
            "v-still.png",
            "v-still.jpg",
            "v-gray.mp4",
            "v-audio.mp4",
            "v-audio.wav",
            "v-half.mp4",
            "v-head.mp4",
        ] {
            files.push((f, vec![f]));
        }
    }
    for (file, needles) in files {
        let needles: Vec<&str> = needles.to_vec();
        let csv = format!("{file}.csv");
        out.push(case(
            format!("video {file}"),
            &["detect", file, "-o", &csv],
            OURS,
            &needles,
        ));
    }
    if have_ffmpeg() {
        out.push(case(
            "video pattern over itself",
            &["detect", "v-pattern.mp4", "-o", "v-pattern.mp4"],
            OURS,
            &["v-pattern.mp4"],
        ));
        out.push(case(
            "video frames past its end",
            &[
                "detect",
                "v-pattern.mp4",
                "-o",
                "f.csv",
                "--frames",
                "500,900",
            ],
            OURS,
            &["500..900"],
        ));
    }
}

/// Flag cases: out of range, malformed, conflicting.
fn flag_cases(out: &mut Vec<Case>, video: bool) {
    let detect = |flag: &str, v: &str, code: i32, needle: &str| {
        case(
            format!("flag detect {flag} {v}"),
            &[
                "detect",
                "v-pattern.mp4",
                "-o",
                "flags.csv",
                &format!("{flag}={v}"),
            ],
            code,
            &[needle],
        )
    };
    if video {
        flag_video_cases(out, detect);
    }
    flag_model_cases(out);
}

fn flag_video_cases(out: &mut Vec<Case>, detect: impl Fn(&str, &str, i32, &str) -> Case) {
    for v in ["1,2,3", "10,10,0,0", "1,2,3,4,5"] {
        out.push(detect("--roi", v, OURS, "--roi"));
    }
    // Checked against the frame with the experiment's `video.roi`: the message says that key.
    out.push(detect("--roi", "0,0,1000000,1000000", OURS, "roi"));
    for v in ["-1,0,10,10", "a,b,c,d", "1.5,0,10,10"] {
        out.push(detect("--roi", v, USAGE, "--roi"));
    }
    for v in ["5,2", "1", "1,2,3"] {
        out.push(detect("--frames", v, OURS, "--frames"));
    }
    for v in ["-1,5", "x,y"] {
        out.push(detect("--frames", v, USAGE, "--frames"));
    }
    for v in ["nan,nan", "1", "inf,0", "1,2,3"] {
        out.push(detect("--pivot", v, OURS, "--pivot"));
    }
    out.push(detect("--pivot", "a,b", USAGE, "--pivot"));
    out.push(detect(
        "--experiment",
        "no-such-experiment",
        OURS,
        "no-such-experiment",
    ));
}

fn flag_model_cases(out: &mut Vec<Case>) {
    let simulate = |flag: &str, v: &str, code: i32| {
        case(
            format!("flag simulate {flag} {v}"),
            &[
                "simulate",
                "twin.yaml",
                "-o",
                "sim.csv",
                &format!("{flag}={v}"),
            ],
            code,
            &[flag],
        )
    };
    for v in ["-1", "0", "nan", "inf", "1e9", "1e7"] {
        out.push(simulate("--fps", v, OURS));
    }
    for v in ["-1", "0", "nan", "1e9"] {
        out.push(simulate("--duration", v, OURS));
    }
    for v in ["-1", "nan", "inf"] {
        out.push(simulate("--noise-deg", v, OURS));
    }
    out.push(simulate("--fps", "fast", USAGE));
    out.push(simulate("--seed", "-1", USAGE));
    let fit = |v: &str, code: i32| {
        case(
            format!("flag fit --beta {v}"),
            &["fit", "ok.yaml", &format!("--beta={v}")],
            code,
            &["beta"],
        )
    };
    for v in ["7", "-1", "nan", "x", "0"] {
        out.push(fit(v, OURS));
    }
    for (args, needle) in [
        (&["build", "-j", "0"][..], "-j"),
        (&["build", "--jobs=-1"][..], "--jobs"),
        (&["build", "-j", "70000"][..], "-j"),
        (&["build", "--jobs", "many"][..], "--jobs"),
        (&["build", "--bogus"][..], "--bogus"),
        (&["detect", "v-random.mp4"][..], "--output"),
        (&["fit"][..], "EXPERIMENT"),
        (&["nonsense"][..], "nonsense"),
        (&["simulate", "twin.yaml", "-o"][..], "-o"),
    ] {
        out.push(case(
            format!("flag {}", args.join(" ")),
            args,
            USAGE,
            &[needle],
        ));
    }
    out.push(case(
        "flag simulate -o into a folder",
        &["simulate", "twin.yaml", "-o", "sub"],
        OURS,
        &["sub"],
    ));
    out.push(case(
        "flag simulate an absent experiment",
        &["simulate", "absent-exp", "-o", "x.csv"],
        OURS,
        &["absent-exp"],
    ));
}

/// Runs every case (two at a time) and asserts all of them, but the known failures.
#[test]
fn bad_inputs_fail_cleanly_naming_what_is_wrong() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let start = Instant::now();
    std::fs::create_dir(dir.join("sub")).unwrap();
    simulate_csv("glass-fiber-fabric", &dir.join("angles.csv"), 16.0);
    let base = base_yaml();
    write(dir, "ok.yaml", &base);
    write(dir, "ok-copy.yaml", &base);
    std::fs::copy(
        root().join("experiments/glass-fiber-fabric.yaml"),
        dir.join("twin.yaml"),
    )
    .unwrap();
    write(
        dir,
        "index.yaml",
        base.replace("name: glass-fiber-fabric", "name: index"),
    );
    let mut cases = Vec::new();
    yaml_cases(dir, &mut cases);
    csv_cases(dir, &mut cases);
    manifest_cases(dir, &mut cases);
    let video = need_ffmpeg();
    if video {
        video_cases(dir, &mut cases);
    }
    flag_cases(&mut cases, video);
    edges::cases(dir, &mut cases, video);
    println!("{} cases generated in {:?}", cases.len(), start.elapsed());
    assert!(cases.len() >= 250, "{} cases", cases.len());

    let results: Vec<(String, Option<String>, String)> = std::thread::scope(|s| {
        let (a, b) = cases.split_at(cases.len() / 2);
        let h: Vec<_> = [a, b]
            .into_iter()
            .map(|half| {
                s.spawn(move || {
                    half.iter()
                        .map(|c| {
                            let (why, said) = run(c, dir);
                            (c.name.clone(), why, said)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        h.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    let mut failed = Vec::new();
    let mut known = Vec::new();
    let said: Vec<(String, String)> = results
        .iter()
        .map(|(name, _, said)| (name.clone(), redact(said, dir)))
        .collect();
    failed.extend(edges::messages_as_recorded(&said, video));
    for (name, res, _) in results {
        match (res, KNOWN_FAILURES.contains(&name.as_str())) {
            (Some(why), false) => failed.push(format!("{name}: {why}")),
            (Some(why), true) => known.push(format!("{name}: {why}")),
            (None, true) => failed.push(format!("{name}: listed as a known failure but passes")),
            (None, false) => {}
        }
    }
    println!(
        "{} cases in {:?}: {} failed, {} known failures",
        cases.len(),
        start.elapsed(),
        failed.len(),
        known.len()
    );
    for k in &known {
        println!("known failure: {k}");
    }
    assert!(
        failed.is_empty(),
        "{} of {} cases failed:\n{}",
        failed.len(),
        cases.len(),
        failed.join("\n")
    );
}

/// A message as recorded: the case folder's path and the process ids of temporary
/// names taken out.
fn redact(said: &str, dir: &Path) -> String {
    let mut s = said.to_string();
    for d in [std::fs::canonicalize(dir).ok(), Some(dir.to_path_buf())]
        .into_iter()
        .flatten()
    {
        s = s.replace(&d.display().to_string(), "$DIR");
    }
    s
}

/// One case's run: `None` when every check holds, else what did not; and the first
/// line of its standard error (for a case that fails: its message).
fn run(c: &Case, dir: &Path) -> (Option<String>, String) {
    let before: Vec<Option<Vec<u8>>> = c
        .unchanged
        .iter()
        .map(|f| std::fs::read(dir.join(f)).ok())
        .collect();
    let t = Instant::now();
    let out = rollfric(&c.args, dir);
    let took = t.elapsed();
    let err = String::from_utf8_lossy(&out.stderr);
    let shown: String = err.chars().take(400).collect();
    let mut why = Vec::new();
    if err.contains("panicked") || err.contains("RUST_BACKTRACE") {
        why.push("a panic".to_string());
    }
    match out.status.code() {
        Some(code) if code == c.code => {}
        code => why.push(format!("exit {code:?}, expected {}", c.code)),
    }
    let lines = err.trim_end().lines().count();
    // The parser's usage note; a build's line per failed experiment.
    let max_lines = match c.args[0].as_str() {
        _ if c.code == USAGE => 8,
        "build" => 3,
        _ => 1,
    };
    if (lines == 0 && c.code != 0) || (lines > max_lines && !c.loud) {
        why.push(format!(
            "{lines} lines of standard error (at most {max_lines})"
        ));
    }
    if err.len() > 2048 && !c.loud {
        why.push(format!("{} bytes of standard error", err.len()));
    }
    let said = if c.code == 0 {
        format!("{err}{}", String::from_utf8_lossy(&out.stdout))
    } else {
        err.to_string()
    };
    for n in &c.needles {
        if !said.contains(n.as_str()) {
            why.push(format!("does not say `{n}`"));
        }
    }
    for n in &c.never {
        if err.contains(n.as_str()) {
            why.push(format!("says `{n}`"));
        }
    }
    for (f, old) in c.unchanged.iter().zip(before) {
        if std::fs::read(dir.join(f)).ok() != old {
            why.push(format!("changed {f}"));
        }
    }
    if took.as_secs() > 60 {
        why.push(format!("took {took:?}"));
    }
    let first = if c.code == 0 {
        "(succeeds)".to_string()
    } else {
        err.lines().next().unwrap_or("").to_string()
    };
    let why =
        (!why.is_empty()).then(|| format!("{} ({}): {shown}", why.join(", "), c.args.join(" ")));
    (why, first)
}
