//! Headless-browser check of the HTML reports: every `<img>` figure loads, the pages log
//! no JavaScript or console error, and full-page screenshots are left for a person to
//! look at (`target/screenshots/index.png` and `target/screenshots/<page>.png`, the
//! material page's review page too). A second test uses a review page as a person would:
//! it clicks the wire on a flagged frame and rebuilds with the marks the page wrote.
//!
//! Debian's `chromium` runs headless under `chromedriver` (`make deps` installs both:
//! `chromium chromium-driver`), driven through the WebDriver client crate `fantoccini`;
//! the errors are chromedriver's browser log (`goog:loggingPrefs`), which also holds
//! failed loads. Before the reports, the same browser session judges a few fake pages (a
//! missing figure, a thrown error, a `console.error`, no figure at all) to prove the
//! checks bite. Without `chromium` or `chromedriver` the tests fail rather than skip,
//! whatever `ROLLFRIC_REQUIRE_TOOLS` says (the review test's real clip is a fixture: it
//! may skip, see `tests/common`).
//!
//! Environment:
//! - `ROLLFRIC_REPORTS`: check this report folder instead of building a small one
//!   (`rollfric build` of one experiment into `target/browser/reports`).
//! - `ROLLFRIC_BROWSER_PAGE`: the material page checked besides `index.html`
//!   (default `glass-fiber-fabric.html`), relative to the report folder.
//! - `ROLLFRIC_CHROMIUM`, `ROLLFRIC_CHROMEDRIVER`: other browser / driver binaries.

mod common;

use common::{rollfric_ok, root};
use fantoccini::actions::{
    InputSource, KeyAction, KeyActions, MouseActions, PointerAction, MOUSE_BUTTON_LEFT,
};
use fantoccini::key::Key;
use fantoccini::wd::WebDriverCompatibleCommand;
use fantoccini::{Client, ClientBuilder};
use hyper_util::client::legacy::connect::HttpConnector;
use serde::Deserialize;
use serde_json::{json, Value};
use std::ffi::OsStr;
use std::fmt::Display;
use std::fs;
use std::future::Future;
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Longest wait for one WebDriver command (a page load included).
const COMMAND_TIMEOUT: Duration = Duration::from_secs(60);
/// Longest wait for chromedriver to listen on its port.
const DRIVER_START_TIMEOUT: Duration = Duration::from_secs(30);
/// Chromium as root in a closed network: no sandbox, no GPU, and none of the background
/// connections (their refusals would otherwise show up as errors and delays).
const CHROMIUM_FLAGS: [&str; 10] = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-dev-shm-usage",
    "--window-size=1280,2000",
];
/// Tallest screenshot taken, CSS px (a longer page is cut there).
const MAX_SHOT_HEIGHT: u32 = 16_000;
const DEFAULT_PAGE: &str = "glass-fiber-fabric.html";
const MAKE_DEPS: &str = "run `make deps` (the Makefile installs the Debian packages \
                         chromium and chromium-driver), or point ROLLFRIC_CHROMIUM / \
                         ROLLFRIC_CHROMEDRIVER at them";

// ---------------------------------------------------------------------------------------
// The tests.

#[test]
fn reports_render_in_chromium() {
    let (chromium, chromedriver) = browser_binaries();
    let reports = reports_dir();
    let page = std::env::var("ROLLFRIC_BROWSER_PAGE").unwrap_or_else(|_| DEFAULT_PAGE.into());
    // The index, the material page and that page's review page.
    let review = format!("{}/review.html", page.trim_end_matches(".html"));
    let pages = ["index.html".to_string(), page, review].map(|p| {
        let stem = p.trim_end_matches(".html").replace(['/', '\\'], "_");
        (p, stem)
    });
    for (file, _) in &pages {
        let path = reports.join(file);
        assert!(
            path.is_file(),
            "{} is missing; the HTML files in {} are: {:?}",
            path.display(),
            reports.display(),
            html_files(&reports)
        );
    }

    let started = Instant::now();
    let browser = Browser::start(&chromium, &chromedriver);
    println!(
        "chromium {} via chromedriver on port {} ({:.1} s to start)",
        browser.version,
        browser.driver.port,
        started.elapsed().as_secs_f64()
    );

    self_check(&browser);

    let shots = root().join("target/screenshots");
    let mut failures = Vec::new();
    for (file, stem) in &pages {
        let path = reports.join(file);
        let seen = browser.observe(&path);
        let shot = shots.join(format!("{stem}.png"));
        let (w, h) = browser.screenshot(&shot);
        println!("screenshot {} ({w}x{h} px)", shot.display());
        for line in &seen.log {
            println!("  {file} browser log: {line}");
        }
        match verdict(&seen) {
            Ok(()) => println!(
                "{file}: {} images load, no severe log entry",
                seen.images.len()
            ),
            Err(e) => failures.push(format!("{} ({}):\n{e}", file, path.display())),
        }
    }
    println!(
        "browser checks took {:.1} s (report build excluded)",
        started.elapsed().as_secs_f64()
    );
    // `browser` is dropped on return or on this panic: the session is deleted and
    // chromedriver killed either way.
    assert!(
        failures.is_empty(),
        "the reports do not render cleanly in chromium:\n\n{}",
        failures.join("\n\n")
    );
}

/// The review page in use: on the split-screen clip's flagged frames (a build of the
/// experiment `rollfric init` wrote, its geometry filled in), the arrow keys move
/// between frames, two clicks at known pixels on a flagged frame mark the wire, the page
/// shows that angle and writes the `video.marks` block; that block put under `video:`
/// in the experiment file, a rebuild measures the frame `manual` at the clicked angle.
/// Screenshots: `target/screenshots/review*.png`.
#[test]
fn review_page_marks_a_frame_that_the_rebuild_measures() {
    let Some(clip) = common::fixture("sborquez_video2_splitscreen.mp4") else {
        return;
    };
    let (chromium, chromedriver) = browser_binaries();
    let work = root().join("target/browser/review");
    if work.exists() {
        fs::remove_dir_all(&work).unwrap_or_else(|e| panic!("clear {}: {e}", work.display()));
    }
    fs::create_dir_all(&work).unwrap();
    let yaml = work.join("split.yaml");
    common::rollfric_ok(
        &[
            OsStr::new("init"),
            clip.as_os_str(),
            OsStr::new("-o"),
            yaml.as_os_str(),
            // Two pendulums swing in the frame: the right panel's.
            OsStr::new("--roi"),
            OsStr::new("240,0,240,360"),
        ],
        &root(),
    );
    let filled = common::fill_init_geometry(&fs::read_to_string(&yaml).unwrap());
    fs::write(&yaml, &filled).unwrap();
    fs::write(
        work.join("manifest.yaml"),
        "title: review\nexperiments:\n  - split.yaml\n",
    )
    .unwrap();
    let build = || {
        common::rollfric_ok(&common::BUILD_INTO_REPORTS, &work);
    };
    build();
    let page = work.join("reports/split/review.html");
    let main_page = fs::read_to_string(work.join("reports/split.html")).unwrap();
    assert!(
        main_page.contains("href=\"split/review.html\""),
        "the experiment page does not link its review page"
    );

    let browser = Browser::start(&chromium, &chromedriver);
    let shots = root().join("target/screenshots");
    let shot = |name: &str| {
        let path = shots.join(name);
        let (w, h) = browser.screenshot(&path);
        println!("screenshot {} ({w}x{h} px)", path.display());
    };
    let seen = browser.observe(&page);
    verdict(&seen).unwrap_or_else(|e| panic!("{}:\n{e}", page.display()));
    shot("review.png");
    let data = browser.review_data();
    let frames = &data.frames;
    let pictured = frames.iter().filter(|f| f.picture.is_some()).count();
    assert!(
        pictured >= 10,
        "the split-screen clip has about 20 flagged frames, the page pictures {pictured}"
    );
    // The first flagged frame with a picture that the gate rejected (not a repeat):
    // reached from the first frame with a picture by the right arrow key.
    let start = frames.iter().position(|f| f.picture.is_some()).unwrap();
    let target_index = frames
        .iter()
        .position(|f| f.picture.is_some() && f.flag.as_deref() == Some("gate"))
        .expect("a frame the gate flagged");
    let target = &frames[target_index];
    let frame_no = target.frame;
    let info = || browser.text("info");
    let first = format!("Frame {} ", frames[start].frame);
    assert!(info().starts_with(&first), "{}", info());
    for _ in start..target_index {
        browser.key(Key::Right);
    }
    // One past, and back.
    browser.key(Key::Right);
    browser.key(Key::Left);
    assert!(
        info().starts_with(&format!("Frame {frame_no} ")),
        "after {} right arrows and a left one: {}",
        target_index - start + 1,
        info()
    );

    // Two points 0.8 deg off the angle the series has for this frame (so that the
    // manual angle cannot come from the detector), at whole CSS pixels of the viewport.
    let [rx, ry, rw, rh] = data.region;
    let [px, py] = data.pivot;
    let (w, h) = (target.width, target.height);
    let rect = browser.script(
        "const e = document.getElementById('overlay'); e.scrollIntoView({block: 'center'}); \
         const r = e.getBoundingClientRect(); return [r.left, r.top, r.width, r.height];",
    );
    let [left, top, width, height] = [0, 1, 2, 3].map(|i| rect[i].as_f64().unwrap());
    let series_deg = target.angle_deg.expect("the series' angle of the frame");
    let a = (series_deg + 0.8).to_radians();
    // Full-frame pixel (centres at whole numbers) -> viewport px, and back as the page
    // maps a click.
    let to_view = |x: f64, y: f64| {
        (
            left + (x + 0.5 - rx) / rw * width,
            top + (y + 0.5 - ry) / rh * height,
        )
    };
    let to_full = |cx: f64, cy: f64| {
        let r1 = |v: f64| (v * 10.0).round() / 10.0;
        (
            r1(rx + (cx - left) / width * w * rw / w - 0.5),
            r1(ry + (cy - top) / height * h * rh / h - 0.5),
        )
    };
    // Along the wire, the stretch inside the picture: from the pivot, radii where the
    // point lies in the region, 30 % and 80 % of the way.
    let inside: Vec<f64> = (0..4000)
        .map(|k| k as f64 * 0.5)
        .filter(|s| {
            let (x, y) = (px + s * a.cos(), py + s * a.sin());
            x > rx + 2.0 && x < rx + rw - 3.0 && y > ry + 2.0 && y < ry + rh - 3.0
        })
        .collect();
    let (s0, s1) = (inside[0], inside[inside.len() - 1]);
    let clicks: Vec<(f64, f64)> = [0.3, 0.8]
        .iter()
        .map(|f| {
            let s = s0 + f * (s1 - s0);
            let (cx, cy) = to_view(px + s * a.cos(), py + s * a.sin());
            (cx.round(), cy.round())
        })
        .collect();
    for &(cx, cy) in &clicks {
        browser.click_at(cx, cy);
    }
    let points: Vec<(f64, f64)> = clicks.iter().map(|&(x, y)| to_full(x, y)).collect();
    let (near, far) = if (points[0].0 - px).hypot(points[0].1 - py)
        <= (points[1].0 - px).hypot(points[1].1 - py)
    {
        (points[0], points[1])
    } else {
        (points[1], points[0])
    };
    let clicked_deg = (far.1 - near.1).atan2(far.0 - near.0).to_degrees();
    let same_deg = |x: f64, y: f64| ((x - y + 540.0).rem_euclid(360.0) - 180.0).abs();
    let shown: f64 = browser
        .script("return document.getElementById('angle').dataset.marked")
        .as_str()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no marked angle shown: {}", info()));
    assert!(
        same_deg(shown, clicked_deg) < 1e-6,
        "the page shows {shown} deg, the clicks make {clicked_deg} deg"
    );
    let block = browser.script("return document.getElementById('yaml').value");
    let block = block.as_str().expect("the YAML block");
    let line = format!(
        "    {frame_no}: [[{}, {}], [{}, {}]]",
        fmt1(points[0].0),
        fmt1(points[0].1),
        fmt1(points[1].0),
        fmt1(points[1].1)
    );
    assert!(
        block.contains(&line),
        "the YAML block lacks {line:?}:\n{block}"
    );
    browser.script("document.getElementById('copy').click(); return null");
    assert!(
        !browser.text("copied").is_empty(),
        "the copy button says nothing"
    );
    shot("review-marked.png");
    println!(
        "marked frame {frame_no} at {clicked_deg:.3} deg (the series had {series_deg:.3} deg):\n{block}"
    );

    // The block under `video:` in the experiment, and a rebuild.
    let marked = filled.replacen("video:\n", &format!("video:\n{block}"), 1);
    assert_ne!(marked, filled, "no `video:` line in {}", yaml.display());
    fs::write(&yaml, marked).unwrap();
    build();
    let seen = browser.observe(&page);
    verdict(&seen).unwrap_or_else(|e| panic!("{} after the rebuild:\n{e}", page.display()));
    let after = browser
        .review_data()
        .frames
        .into_iter()
        .find(|f| f.frame == frame_no)
        .unwrap_or_else(|| panic!("frame {frame_no} left the review page"));
    assert_eq!(after.status, "manual", "{after:?}");
    let measured = after.angle_deg.expect("the manual angle");
    assert!(
        same_deg(measured, clicked_deg) < 0.1,
        "frame {frame_no}: the rebuild measured {measured} deg, the clicks make {clicked_deg} deg"
    );
    // The build's angle CSV says the same (one row per frame from frame 0).
    let csv = fs::read_to_string(work.join("cache/split/angles.csv")).unwrap();
    let row: Vec<&str> = csv
        .lines()
        .nth(1 + frame_no as usize)
        .unwrap()
        .split(',')
        .collect();
    let csv_deg = row[1].parse::<f64>().unwrap().to_degrees();
    assert!(
        row[2] == "manual" && same_deg(csv_deg, clicked_deg) < 0.1,
        "angles.csv row of frame {frame_no}: {row:?}"
    );
    shot("review-after-rebuild.png");
    println!(
        "after the rebuild frame {frame_no} is manual at {measured:.3} deg ({:.4} deg from the clicks)",
        same_deg(measured, clicked_deg)
    );
}

/// A coordinate as the page writes it (one decimal, no trailing `.0` dropped by JS).
fn fmt1(v: f64) -> String {
    // JavaScript prints 301 for 301.0 and 301.5 for 301.5.
    if v.fract() == 0.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.1}")
    }
}

/// What the test reads of a review page's data.
#[derive(Debug, Deserialize)]
struct ReviewData {
    /// The region of interest in full-frame pixels: x, y, width, height.
    region: [f64; 4],
    pivot: [f64; 2],
    frames: Vec<ReviewFrame>,
}

#[derive(Debug, Deserialize)]
struct ReviewFrame {
    frame: u64,
    status: String,
    flag: Option<String>,
    /// The angle of the series (the build's) at this frame.
    angle_deg: Option<f64>,
    /// The picture's file and size in px (`None`, 0 and 0 when the page has none).
    picture: Option<String>,
    width: f64,
    height: f64,
}

/// Fake pages in a temporary folder, judged in the same session: the good one must pass,
/// each broken one must fail for its own reason.
fn self_check(browser: &Browser) {
    let dir = tempfile::tempdir().expect("temp dir");
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="120" height="60"><rect width="120" height="60" fill="teal"/></svg>"#;
    fs::write(dir.path().join("fig.svg"), svg).unwrap();
    fs::write(dir.path().join("not-an-image.svg"), "plain text").unwrap();
    let page = |name: &str, body: &str| {
        let path = dir.path().join(name);
        let html = format!(
            "<!doctype html><html><head><meta charset=utf-8></head><body>{body}</body></html>"
        );
        fs::write(&path, html).unwrap();
        path
    };
    let good = page(
        "good.html",
        r#"<img src="fig.svg"><script>console.log("fine")</script>"#,
    );
    let cases = [
        (
            page(
                "missing.html",
                r#"<img src="fig.svg"><img src="missing.svg">"#,
            ),
            "missing.svg",
        ),
        (
            page("garbage.html", r#"<img src="not-an-image.svg">"#),
            "not-an-image.svg",
        ),
        (
            page(
                "throws.html",
                r#"<img src="fig.svg"><script>null.x()</script>"#,
            ),
            "Uncaught TypeError",
        ),
        (
            page(
                "console.html",
                r#"<img src="fig.svg"><script>console.error("self-check boom")</script>"#,
            ),
            "self-check boom",
        ),
        (page("empty.html", "<p>no figure</p>"), "no <img>"),
    ];
    if let Err(e) = verdict(&browser.observe(&good)) {
        panic!("browser self-check: a clean fake page was judged broken:\n{e}");
    }
    for (path, expect) in &cases {
        match verdict(&browser.observe(path)) {
            Ok(()) => panic!(
                "browser self-check: broken fake page {} passed",
                path.display()
            ),
            Err(e) => assert!(
                e.contains(expect),
                "browser self-check: {} failed, but without naming {expect:?}:\n{e}",
                path.display()
            ),
        }
    }
    println!(
        "browser self-check: 1 clean and {} broken fake pages judged right",
        cases.len()
    );
}

// ---------------------------------------------------------------------------------------
// What is checked on a page (pure, unit-tested below).

/// One `<img>` as [`IMAGES_SCRIPT`] returns it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename_all = "camelCase")]
struct Img {
    src: String,
    complete: bool,
    natural_width: u64,
}

#[derive(Debug, Default)]
struct Observation {
    images: Vec<Img>,
    /// Browser log entries as `LEVEL source: message`.
    log: Vec<String>,
}

impl Observation {
    /// From the answers to [`IMAGES_SCRIPT`] and to a read of the browser log.
    fn from_answers(images: Value, log: Value) -> Result<Observation, serde_json::Error> {
        #[derive(Deserialize)]
        struct Entry {
            level: String,
            source: String,
            message: String,
        }
        let log: Vec<Entry> = serde_json::from_value(log)?;
        Ok(Observation {
            images: serde_json::from_value(images)?,
            log: log
                .into_iter()
                .map(|e| format!("{} {}: {}", e.level, e.source, e.message))
                .collect(),
        })
    }
}

/// `Ok` when the page shows at least one image, all of them loaded and decoded, and the
/// browser logged nothing SEVERE (uncaught errors, `console.error`, failed loads).
fn verdict(seen: &Observation) -> Result<(), String> {
    let mut problems = Vec::new();
    if seen.images.is_empty() {
        problems.push("no <img> on the page".to_string());
    }
    let broken: Vec<String> = seen
        .images
        .iter()
        .filter(|i| !(i.complete && i.natural_width > 0))
        .map(|i| {
            format!(
                "  {} (complete={}, naturalWidth={})",
                i.src, i.complete, i.natural_width
            )
        })
        .collect();
    if !broken.is_empty() {
        problems.push(format!(
            "{} of {} images did not load:\n{}",
            broken.len(),
            seen.images.len(),
            broken.join("\n")
        ));
    }
    let severe: Vec<&String> = seen
        .log
        .iter()
        .filter(|l| l.starts_with("SEVERE"))
        .collect();
    if !severe.is_empty() {
        let lines: Vec<String> = severe.iter().map(|l| format!("  {l}")).collect();
        problems.push(format!("severe browser log entries:\n{}", lines.join("\n")));
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("\n"))
    }
}

/// Async script: lazy images are made eager, every image is waited for (20 s at most),
/// then each one's src, `complete` and `naturalWidth` are returned.
const IMAGES_SCRIPT: &str = r#"
const done = arguments[arguments.length - 1];
const imgs = Array.from(document.images);
for (const i of imgs) { if (i.loading === "lazy") i.loading = "eager"; }
const settled = i => i.complete ? Promise.resolve() : new Promise(r => {
  i.addEventListener("load", r, { once: true });
  i.addEventListener("error", r, { once: true });
});
const limit = new Promise(r => setTimeout(r, 20000));
Promise.race([Promise.all(imgs.map(settled)), limit]).then(() => done(imgs.map(i => ({
  src: i.currentSrc || i.src || i.getAttribute("src") || "(no src)",
  complete: i.complete,
  naturalWidth: i.naturalWidth,
}))));
"#;

// ---------------------------------------------------------------------------------------
// Finding the browser and the reports.

fn browser_binaries() -> (PathBuf, PathBuf) {
    let chromium = std::env::var_os("ROLLFRIC_CHROMIUM")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/usr/bin/chromium"));
    let chromedriver = std::env::var_os("ROLLFRIC_CHROMEDRIVER")
        .map(PathBuf::from)
        .or_else(|| on_path("chromedriver"))
        .unwrap_or_else(|| PathBuf::from("/usr/bin/chromedriver"));
    for (what, path) in [("chromium", &chromium), ("chromedriver", &chromedriver)] {
        assert!(
            path.is_file(),
            "{what} not found at {}: the browser test needs it; {MAKE_DEPS}",
            path.display()
        );
    }
    (chromium, chromedriver)
}

fn on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// The HTML files under `dir` (two levels deep), relative to it, sorted.
fn html_files(dir: &Path) -> Vec<String> {
    fn walk(base: &Path, dir: &Path, depth: u32, out: &mut Vec<String>) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        for path in entries.filter_map(|e| e.ok()).map(|e| e.path()) {
            if path.is_dir() && depth > 0 {
                walk(base, &path, depth - 1, out);
            } else if path.extension().is_some_and(|x| x == "html") {
                let rel = path.strip_prefix(base).unwrap_or(&path);
                out.push(rel.to_string_lossy().into_owned());
            }
        }
    }
    let mut names = Vec::new();
    walk(dir, dir, 1, &mut names);
    names.sort();
    names
}

/// `ROLLFRIC_REPORTS`, or a one-experiment report set built now by the binary into
/// `target/browser/reports` (its cache in `target/browser/cache` is kept between runs).
fn reports_dir() -> PathBuf {
    if let Some(dir) = std::env::var_os("ROLLFRIC_REPORTS") {
        let dir = PathBuf::from(dir);
        assert!(
            dir.is_dir(),
            "ROLLFRIC_REPORTS={} is not a folder",
            dir.display()
        );
        println!(
            "checking the reports in {} (ROLLFRIC_REPORTS)",
            dir.display()
        );
        return dir;
    }
    let work = root().join("target/browser");
    fs::create_dir_all(&work).unwrap_or_else(|e| panic!("create {}: {e}", work.display()));
    let experiment = root().join("experiments/glass-fiber-fabric.yaml");
    assert!(experiment.is_file(), "{} is missing", experiment.display());
    // A JSON string is a YAML double-quoted scalar: any path is quoted right.
    let quoted = serde_json::to_string(&experiment.to_string_lossy()).unwrap();
    fs::write(
        work.join("manifest.yaml"),
        format!("title: Browser test\nexperiments:\n  - {quoted}\n"),
    )
    .unwrap();
    let out = work.join("reports");
    if out.exists() {
        fs::remove_dir_all(&out).unwrap_or_else(|e| panic!("clear {}: {e}", out.display()));
    }
    let started = Instant::now();
    rollfric_ok(&common::BUILD_INTO_REPORTS, &work);
    println!(
        "built the reports into {} in {:.1} s",
        out.display(),
        started.elapsed().as_secs_f64()
    );
    out
}

/// The `file://` URL of a page, percent-escaped.
fn file_url(path: &Path) -> String {
    let abs = fs::canonicalize(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    url::Url::from_file_path(&abs)
        .unwrap_or_else(|()| panic!("no file URL for {}", abs.display()))
        .into()
}

// ---------------------------------------------------------------------------------------
// chromedriver and a chromium session under it, driven with fantoccini from a runtime of
// the `Browser`'s own: the tests read as plain steps, and dropping the `Browser` (also
// when a check panics) can wait for the session's end (chromium quits) before
// chromedriver is killed.

/// A chromedriver on a free local port, its output in `target/browser/chromedriver.log`;
/// killed on drop.
struct Driver {
    child: Child,
    port: u16,
    log: PathBuf,
}

impl Driver {
    fn start(chromedriver: &Path) -> Driver {
        let port = TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .map(|a| a.port())
            .expect("bind a free local port");
        let log = root().join("target/browser/chromedriver.log");
        fs::create_dir_all(log.parent().unwrap()).unwrap();
        let out = fs::File::create(&log).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
        let child = Command::new(chromedriver)
            .arg(format!("--port={port}"))
            .stdin(Stdio::null())
            .stdout(out.try_clone().expect("clone log file"))
            .stderr(out)
            .spawn()
            .unwrap_or_else(|e| panic!("start {}: {e}; {MAKE_DEPS}", chromedriver.display()));
        let mut driver = Driver { child, port, log };
        let start = Instant::now();
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            if let Ok(Some(status)) = driver.child.try_wait() {
                panic!(
                    "chromedriver exited at start ({status})\n{}",
                    driver.log_tail()
                );
            }
            assert!(
                start.elapsed() < DRIVER_START_TIMEOUT,
                "chromedriver not listening on port {port} after {} s\n{}",
                DRIVER_START_TIMEOUT.as_secs(),
                driver.log_tail()
            );
            std::thread::sleep(Duration::from_millis(100));
        }
        driver
    }

    /// The last 30 lines of chromedriver's output, for a failure's message.
    fn log_tail(&self) -> String {
        let text = fs::read_to_string(&self.log).unwrap_or_default();
        let lines: Vec<&str> = text.lines().collect();
        let tail = lines[lines.len().saturating_sub(30)..].join("\n");
        format!("--- {} (tail)\n{tail}", self.log.display())
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

struct Browser {
    client: Client,
    rt: tokio::runtime::Runtime,
    version: String,
    /// chromium's own process id, killed if the session cannot be ended.
    chromium_pid: Option<u64>,
    driver: Driver,
    /// Chromium's fresh profile, removed after chromium quits (fields drop in order).
    _profile: tempfile::TempDir,
}

impl Browser {
    fn start(chromium: &Path, chromedriver: &Path) -> Browser {
        let driver = Driver::start(chromedriver);
        let profile = tempfile::Builder::new()
            .prefix("rollfric-chromium-")
            .tempdir()
            .expect("temp dir for the chromium profile");
        let mut args = CHROMIUM_FLAGS.map(String::from).to_vec();
        args.push(format!("--user-data-dir={}", profile.path().display()));
        let Value::Object(caps) = json!({
            "browserName": "chrome",
            "pageLoadStrategy": "normal",
            "timeouts": {"pageLoad": 50_000, "script": 40_000, "implicit": 0},
            "goog:chromeOptions": {"binary": chromium.to_string_lossy(), "args": args},
            "goog:loggingPrefs": {"browser": "ALL"},
        }) else {
            unreachable!()
        };
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a tokio runtime");
        let url = format!("http://127.0.0.1:{}", driver.port);
        let mut session = ClientBuilder::new(HttpConnector::new());
        session.capabilities(caps);
        let client = within(&rt, "open a session", session.connect(&url)).unwrap_or_else(|e| {
            panic!(
                "chromedriver could not start {}: {e}\n(does `{} --headless --no-sandbox \
                 --dump-dom about:blank` work?)\n{}",
                chromium.display(),
                chromium.display(),
                driver.log_tail()
            )
        });
        let caps = client.capabilities().cloned().unwrap_or_default();
        Browser {
            version: caps["browserVersion"].as_str().unwrap_or("?").to_string(),
            chromium_pid: caps.get("goog:processID").and_then(Value::as_u64),
            client,
            rt,
            driver,
            _profile: profile,
        }
    }

    /// The outcome of one exchange with chromedriver; a failure panics with the tail of
    /// chromedriver's log.
    fn run<T, E: Display>(&self, what: &str, exchange: impl Future<Output = Result<T, E>>) -> T {
        within(&self.rt, what, exchange)
            .unwrap_or_else(|e| panic!("{e}\n{}", self.driver.log_tail()))
    }

    /// Load a page (the "normal" load strategy returns once the document is complete),
    /// wait for its images, and drain the browser log.
    fn observe(&self, page: &Path) -> Observation {
        let url = file_url(page);
        self.run(&format!("open {url}"), self.client.goto(&url));
        let images = self.run(
            &format!("list the images of {url}"),
            self.client.execute_async(IMAGES_SCRIPT, vec![]),
        );
        let log = self.run("read the browser log", self.client.issue_cmd(BrowserLog));
        Observation::from_answers(images, log).unwrap_or_else(|e| panic!("{url}: {e}"))
    }

    /// Run `js` in the page; its return value.
    fn script(&self, js: &str) -> Value {
        self.run(&format!("script {js:?}"), self.client.execute(js, vec![]))
    }

    /// The text of the page's element `id`.
    fn text(&self, id: &str) -> String {
        let js = format!("return document.getElementById('{id}').textContent");
        let text = self.script(&js);
        text.as_str()
            .unwrap_or_else(|| panic!("#{id}: {text}"))
            .to_string()
    }

    /// A review page's own data (`<script id="review-data">`).
    fn review_data(&self) -> ReviewData {
        let data =
            self.script("return JSON.parse(document.getElementById('review-data').textContent)");
        serde_json::from_value(data).unwrap_or_else(|e| panic!("the review page's data: {e}"))
    }

    /// Press and release one key.
    fn key(&self, key: Key) {
        let press = KeyActions::new("keyboard".into())
            .then(KeyAction::Down { value: key.into() })
            .then(KeyAction::Up { value: key.into() });
        self.run(
            &format!("press {key:?}"),
            self.client.perform_actions(press),
        );
    }

    /// A left click at viewport CSS pixel `(x, y)`.
    fn click_at(&self, x: f64, y: f64) {
        let button = MOUSE_BUTTON_LEFT;
        let to = PointerAction::MoveTo {
            duration: None,
            x,
            y,
        };
        let click = MouseActions::new("mouse".into())
            .then(to)
            .then(PointerAction::Down { button })
            .then(PointerAction::Up { button });
        self.run(
            &format!("click at ({x}, {y})"),
            self.client.perform_actions(click),
        );
    }

    /// A full-page PNG of the current page into `path`: the window grown to the page's
    /// height (at most [`MAX_SHOT_HEIGHT`]) for the shot, then set back. Its size in px.
    fn screenshot(&self, path: &Path) -> (u32, u32) {
        let c = &self.client;
        let (w, h) = self.run("read the window size", c.get_window_size());
        let (w, h) = (w as u32, h as u32);
        let js = "const d = document.documentElement; \
                  return d.scrollHeight + window.outerHeight - window.innerHeight";
        let tall = self.script(js).as_u64().expect("a height") as u32;
        self.run(
            "grow the window",
            c.set_window_size(w, tall.min(MAX_SHOT_HEIGHT)),
        );
        let png = self.run("take a screenshot", c.screenshot());
        self.run("restore the window", c.set_window_size(w, h));
        let png_info = png::Decoder::new(std::io::Cursor::new(&png)).read_info();
        let info = png_info.unwrap_or_else(|e| panic!("the screenshot is no PNG: {e}"));
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, &png).unwrap_or_else(|e| panic!("write {}: {e}", path.display()));
        (info.info().width, info.info().height)
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let ended = within(&self.rt, "end the session", self.client.clone().close());
        if ended.is_err() {
            // The session could not be ended: end the chromium this test started.
            if let Some(pid) = self.chromium_pid {
                let _ = Command::new("kill")
                    .args(["-KILL", &pid.to_string()])
                    .status();
            }
        }
    }
}

/// `exchange` run to its end on `rt`, waited for at most [`COMMAND_TIMEOUT`].
fn within<T, E: Display>(
    rt: &tokio::runtime::Runtime,
    what: &str,
    exchange: impl Future<Output = Result<T, E>>,
) -> Result<T, String> {
    // The timer is made in the runtime, as tokio requires.
    match rt.block_on(async { tokio::time::timeout(COMMAND_TIMEOUT, exchange).await }) {
        Ok(outcome) => outcome.map_err(|e| format!("{what}: {e}")),
        Err(_) => Err(format!(
            "{what}: no answer in {} s",
            COMMAND_TIMEOUT.as_secs()
        )),
    }
}

/// A read of the browser log, the entries since the previous read: chromedriver keeps the
/// legacy log endpoint under `/se/log` in W3C mode, and fantoccini has no call for it.
#[derive(Debug)]
struct BrowserLog;

impl WebDriverCompatibleCommand for BrowserLog {
    fn endpoint(
        &self,
        base: &url::Url,
        session: Option<&str>,
    ) -> Result<url::Url, url::ParseError> {
        base.join(&format!("session/{}/se/log", session.unwrap_or_default()))
    }

    fn method_and_body(&self, _: &url::Url) -> (http::Method, Option<String>) {
        let body = json!({"type": "browser"}).to_string();
        (http::Method::POST, Some(body))
    }
}

// ---------------------------------------------------------------------------------------
// Unit tests of the pieces above that need no browser.

#[test]
fn verdict_names_broken_images_and_severe_entries() {
    let img = |src: &str, complete, natural_width| Img {
        src: src.into(),
        complete,
        natural_width,
    };
    let clean = Observation {
        images: vec![img("file:///r/fig.svg", true, 640)],
        log: vec![
            "INFO console-api: hello".into(),
            "WARNING other: meh".into(),
        ],
    };
    assert_eq!(verdict(&clean), Ok(()));
    let broken = Observation {
        images: vec![
            img("file:///r/fig.svg", true, 640),
            img("file:///r/missing.svg", true, 0),
            img("file:///r/slow.png", false, 0),
        ],
        log: vec!["SEVERE javascript: Uncaught TypeError: x".into()],
    };
    let e = verdict(&broken).unwrap_err();
    assert!(e.contains("2 of 3 images"), "{e}");
    assert!(
        e.contains("missing.svg") && e.contains("slow.png") && !e.contains("fig.svg"),
        "{e}"
    );
    assert!(e.contains("Uncaught TypeError"), "{e}");
    let e = verdict(&Observation::default()).unwrap_err();
    assert!(e.contains("no <img>"), "{e}");
}

#[test]
fn chromedriver_answers_parse() {
    let images = json!([
        {"src": "file:///a.svg", "complete": true, "naturalWidth": 300},
        {"src": "file:///b.svg", "complete": false, "naturalWidth": 0},
    ]);
    let log = json!([
        {"level": "SEVERE", "source": "network", "message": "x.svg - Failed to load resource", "timestamp": 1},
    ]);
    let seen = Observation::from_answers(images, log).unwrap();
    assert_eq!(seen.images.len(), 2);
    assert_eq!(seen.images[0].natural_width, 300);
    assert!(!seen.images[1].complete);
    assert_eq!(
        seen.log,
        ["SEVERE network: x.svg - Failed to load resource"]
    );
    assert!(Observation::from_answers(json!(null), json!([])).is_err());
}

#[test]
fn file_urls_are_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("a b#c.html");
    fs::write(&page, "").unwrap();
    let url = file_url(&page);
    assert!(url.starts_with("file:///"), "{url}");
    assert!(url.ends_with("/a%20b%23c.html"), "{url}");
}
