//! Helpers shared by the integration tests (each test crate uses some of them): running
//! the `rollfric` binary; the tools and fixtures a test needs, which it may skip without
//! on a developer's machine but not under `make test` or CI ([`require`]); the summary
//! line's numbers.
#![allow(dead_code)]

pub mod outcomes;
mod require;

pub use require::*;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `rollfric build` of `manifest.yaml` in the working folder into `reports/` and `cache/`.
pub const BUILD_INTO_REPORTS: [&str; 8] = [
    "build",
    "-q",
    "--manifest",
    "manifest.yaml",
    "--out",
    "reports",
    "--cache",
    "cache",
];

/// The glass twin as an experiment file: Table 1's glass geometry, 80 s at 25 frames/s
/// with 0.05 deg of angle noise, s_r = 3.714e-6 m.
pub const GLASS_TWIN_YAML: &str = "geometry:
  incline: { h_m: 0.142, l_m: 1.500 }
  pendulum: { d_m: 0.1774 }
  ball: { radius_m: 0.03175, mass_kg: 1.0458 }
synthetic: { s_r_m: 3.714e-6, psi0_deg: 10, duration_s: 80, fps: 25, angle_noise_deg: 0.05 }
";

/// Table 1's glass geometry as the `geometry:` block of an experiment file.
pub const GLASS_GEOMETRY: &str = "geometry:
  incline: { h_m: 0.142, l_m: 1.500 }
  pendulum: { d_m: 0.1774 }
  ball: { radius_m: 0.03175, mass_kg: 1.0458 }
";

/// A short glass twin as an experiment file: Table 1's glass geometry, 20 s at 25
/// frames/s, 640x360, 0.05 deg of angle noise, the given `s_r` (m) and `video` block
/// (its lines, or empty).
pub fn short_glass_twin(name: &str, s_r: &str, video: &str) -> String {
    format!(
        "name: {name}
{GLASS_GEOMETRY}{video}synthetic: {{ s_r_m: {s_r}, psi0_deg: 10, duration_s: 20, fps: 25, angle_noise_deg: 0.05, width: 640, height: 360 }}
"
    )
}

/// The RMS about their mean of angle differences (rad), in degrees: the scatter, not a
/// constant offset.
pub fn scatter_deg(diffs: &[f64]) -> f64 {
    let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
    (diffs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / diffs.len() as f64)
        .sqrt()
        .to_degrees()
}

/// Every file under `dir`, relative path -> bytes.
pub fn snapshot(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().display().to_string();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// Assert that folders `a` and `b` hold the same files with the same bytes (`what`
/// names the comparison in a failure).
pub fn same_tree(a: &Path, b: &Path, what: &str) {
    let (x, y) = (snapshot(a), snapshot(b));
    assert_eq!(
        x.keys().collect::<Vec<_>>(),
        y.keys().collect::<Vec<_>>(),
        "{what}: not the same files"
    );
    for (k, v) in &x {
        assert!(y[k] == *v, "{what}: {k} differs");
    }
}

/// The crate's folder (where `experiments/` and `tests/` are).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The `rollfric` binary under test, to run in `dir`.
pub fn command(dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rollfric"));
    c.current_dir(dir);
    c
}

/// Runs `rollfric args` in `dir` to the end; whatever its exit status.
pub fn rollfric<S: AsRef<OsStr>>(args: &[S], dir: &Path) -> Output {
    command(dir)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("run rollfric {}: {e}", shown(args)))
}

/// `rollfric detect VIDEO -o CSV --json JSON` with `extra` flags, its outputs in `dir`
/// named after the video: the summary's JSON (written on a refusal too), the command's
/// output and the CSV's path.
pub fn detect_json(
    video: &Path,
    extra: &[&str],
    dir: &Path,
) -> (serde_json::Value, Output, PathBuf) {
    let stem = video.file_stem().expect("a video file").to_string_lossy();
    let (csv, json) = (
        dir.join(format!("{stem}.csv")),
        dir.join(format!("{stem}.json")),
    );
    let mut args = vec![
        OsStr::new("detect"),
        video.as_os_str(),
        OsStr::new("-o"),
        csv.as_os_str(),
        OsStr::new("--json"),
        json.as_os_str(),
    ];
    args.extend(extra.iter().map(OsStr::new));
    let out = rollfric(&args, dir);
    let text = std::fs::read_to_string(&json).expect("the JSON summary is written");
    (serde_json::from_str(&text).unwrap(), out, csv)
}

/// Runs `rollfric args` in `dir`, asserts it succeeds (its standard error in the
/// message), and returns its standard output and standard error.
pub fn rollfric_ok<S: AsRef<OsStr>>(args: &[S], dir: &Path) -> (String, String) {
    let out = rollfric(args, dir);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    );
    assert!(
        out.status.success(),
        "rollfric {} failed ({}): {stderr}",
        shown(args),
        out.status
    );
    (stdout, stderr)
}

/// `rollfric simulate NAME -o CSV --duration SECONDS` (asserted to succeed): a twin's
/// angle series to fit.
pub fn simulate_csv(name: &str, csv: &Path, seconds: f64) {
    rollfric_ok(
        &[
            OsStr::new("simulate"),
            OsStr::new(name),
            OsStr::new("-o"),
            csv.as_os_str(),
            OsStr::new("--duration"),
            OsStr::new(&seconds.to_string()),
        ],
        &root(),
    );
}

/// Turning points of an angle series: their times (s) and amplitudes (deg) about the
/// symmetric-envelope equilibrium.
pub fn turning_amplitudes(s: &rollfric::series::AngleSeries) -> Vec<(f64, f64)> {
    let m = rollfric::fit::measure(s).expect("turning points");
    m.extremes
        .iter()
        .zip(&m.amplitudes)
        .map(|(e, a)| (e.t, a.to_degrees()))
        .collect()
}

fn shown<S: AsRef<OsStr>>(args: &[S]) -> String {
    let args: Vec<_> = args.iter().map(|a| a.as_ref().to_string_lossy()).collect();
    args.join(" ")
}

/// A real camera clip of `../shared/fixtures/real/` (read in place: the clips carry no
/// licence to redistribute), or `None` when it is absent and the test may skip
/// ([`require`]).
pub fn fixture(name: &str) -> Option<PathBuf> {
    let p = root().join("../shared/fixtures/real").join(name);
    let what = format!("the real fixture {}", p.display());
    let how = "the real camera clips are read in place from ../shared/fixtures/real, \
               beside the crate's folder; put them there";
    require(&what, how, p.exists()).then_some(p)
}

/// The experiment file `rollfric init` wrote (`text`), its geometry filled in as a lab
/// would: a 5 degree incline, a 12.7 mm, 67 g ball, and the pendulum length the clip's
/// period implies (from the file's own comment "hangs L = ... m x sin(alpha)").
pub fn fill_init_geometry(text: &str) -> String {
    let l_per_sin: f64 = text
        .split("hangs L = ")
        .nth(1)
        .and_then(|s| s.split(" m x sin(alpha)").next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no period in:\n{text}"));
    let l = l_per_sin * 5f64.to_radians().sin();
    let d = (l * l + 0.0127f64 * 0.0127).sqrt();
    text.replace("h_m: null", "# h_m")
        .replace("l_m: null", "# l_m")
        .replace("# angle_deg: null", "angle_deg: 5")
        .replace("d_m: null", &format!("d_m: {d:.4}"))
        .replace("radius_m: null", "radius_m: 0.0127")
        .replace("mass_kg: null", "mass_kg: 0.067")
}

/// Whether the `ffmpeg` program runs here.
pub fn have_ffmpeg() -> bool {
    Command::new("ffmpeg").arg("-version").output().is_ok()
}

/// Whether the test can go on: `ffmpeg` runs here, or it is missing and the test may
/// skip ([`require`]).
pub fn need_ffmpeg() -> bool {
    require("ffmpeg", MAKE_DEPS, have_ffmpeg())
}

/// Whether the test can go on: `python3` runs here, or it is missing and the test may
/// skip ([`require`]).
pub fn need_python3() -> bool {
    let present = Command::new("python3").arg("--version").output().is_ok();
    require("python3 (for tests/reference_sim)", MAKE_DEPS, present)
}

/// The numbers between `open` and `close` after the last `key` of a summary line,
/// e.g. `numbers_after(msg, "pivot (", ')')` of "... pivot (12.5, -3.0) px ...".
pub fn numbers_after<T: std::str::FromStr>(summary: &str, key: &str, close: char) -> Vec<T>
where
    T::Err: std::fmt::Debug,
{
    let (_, rest) = summary
        .rsplit_once(key)
        .unwrap_or_else(|| panic!("no `{key}` in {summary}"));
    let inner = rest.split(close).next().unwrap_or("");
    inner
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect()
}

/// The `pivot (x, y)` px a summary line reports.
pub fn pivot_in(summary: &str) -> (f64, f64) {
    let v: Vec<f64> = numbers_after(summary, "pivot (", ')');
    (v[0], v[1])
}

/// The plotted data a chart's legend box covers, one line per point: the markers
/// (circles, crosses) and the vertices and 1 px steps of the data lines (2 px wide)
/// drawn before the legend, within the box widened by the marker's extent. Empty when
/// the chart has no legend or it covers nothing. `svg` is a chart of `report::plot`.
pub fn data_under_legend(svg: &str) -> Vec<String> {
    let Some(at) = svg.find("stroke=\"#AAAAAA\"") else {
        return Vec::new();
    };
    let start = svg[..at].rfind("<rect").expect("the legend box is a rect");
    let attr = |el: &str, key: &str| -> Option<f64> {
        let k = format!(" {key}=\"");
        let i = el.find(&k)? + k.len();
        el[i..].split('"').next()?.parse().ok()
    };
    let legend = &svg[start..at];
    let (x, y) = (attr(legend, "x").unwrap(), attr(legend, "y").unwrap());
    let (w, h) = (
        attr(legend, "width").unwrap(),
        attr(legend, "height").unwrap(),
    );
    let under = |px: f64, py: f64, reach: f64| {
        px + reach >= x && px - reach <= x + w && py + reach >= y && py - reach <= y + h
    };
    let mut found = Vec::new();
    for el in svg[..start].split('<').skip(1) {
        let el = el.split('>').next().unwrap_or("");
        if el.starts_with("circle") {
            let (cx, cy, r) = (
                attr(el, "cx").unwrap(),
                attr(el, "cy").unwrap(),
                attr(el, "r").unwrap(),
            );
            if under(cx, cy, r) {
                found.push(format!("circle at ({cx}, {cy})"));
            }
        } else if (el.starts_with("polyline") || el.starts_with("line"))
            && el.contains("stroke-width=\"2\"")
        {
            let pts: Vec<(f64, f64)> = if el.starts_with("line") {
                vec![
                    (attr(el, "x1").unwrap(), attr(el, "y1").unwrap()),
                    (attr(el, "x2").unwrap(), attr(el, "y2").unwrap()),
                ]
            } else {
                let i = el.find("points=\"").unwrap() + 8;
                el[i..]
                    .split('"')
                    .next()
                    .unwrap()
                    .split_whitespace()
                    .filter_map(|p| {
                        let (a, b) = p.split_once(',')?;
                        Some((a.parse().ok()?, b.parse().ok()?))
                    })
                    .collect()
            };
            for seg in pts.windows(2) {
                let (a, b) = (seg[0], seg[1]);
                let n = (b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil().max(1.0) as usize;
                if let Some(k) = (0..=n).find(|&k| {
                    let t = k as f64 / n as f64;
                    under(a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1), 1.0)
                }) {
                    let t = k as f64 / n as f64;
                    found.push(format!(
                        "line through ({:.0}, {:.0})",
                        a.0 + t * (b.0 - a.0),
                        a.1 + t * (b.1 - a.1)
                    ));
                }
            }
        }
    }
    found
}

/// Every chart (`*.svg`) under `dir` whose legend covers plotted data, with what it
/// covers.
pub fn legends_over_data(dir: &Path) -> Vec<String> {
    let mut bad = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "svg") {
                let hidden = data_under_legend(&std::fs::read_to_string(&p).unwrap());
                if !hidden.is_empty() {
                    bad.push(format!(
                        "{}: {} covered ({})",
                        p.display(),
                        hidden.len(),
                        hidden[..hidden.len().min(3)].join(", ")
                    ));
                }
            }
        }
    }
    bad.sort();
    bad
}
