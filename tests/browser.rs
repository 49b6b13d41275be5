//! Headless-browser check of the HTML reports: every `<img>` figure loads, the pages log
//! no JavaScript or console error, and full-page screenshots are left for a person to
//! look at (`target/screenshots/index.png` and `target/screenshots/<page>.png`, the
//! material page's review page too). A second test uses a review page as a person would:
//! it clicks the wire on a flagged frame and rebuilds with the marks the page wrote.
//!
//! It drives Debian's `chromium` through `chromedriver`'s W3C WebDriver JSON API with a
//! small std-only HTTP/1.1 client; `make deps` installs both (`chromium chromium-driver`).
//! Before the reports, the same browser session judges a few fake pages (a missing
//! figure, a thrown error, a `console.error`, no figure at all) to prove the checks bite.
//!
//! Environment:
//! - `ROLLFRIC_REPORTS`: check this report folder instead of building a small one
//!   (`rollfric build` of one experiment into `target/browser/reports`).
//! - `ROLLFRIC_BROWSER_PAGE`: the material page checked besides `index.html`
//!   (default `glass-fiber-fabric.html`), relative to the report folder.
//! - `ROLLFRIC_CHROMIUM`, `ROLLFRIC_CHROMEDRIVER`: other browser / driver binaries.

mod common;

use common::{rollfric, root};
use serde_json::{json, Value};
use std::ffi::OsStr;
use std::fs;
use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Longest wait for one HTTP answer of chromedriver (a page load included).
const HTTP_TIMEOUT: Duration = Duration::from_secs(60);
/// Longest wait for chromedriver to answer `/status` with `ready`.
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
const MAX_SHOT_HEIGHT: f64 = 16_000.0;
const DEFAULT_PAGE: &str = "glass-fiber-fabric.html";
const MAKE_DEPS: &str = "run `make deps` (the Makefile installs the Debian packages \
                         chromium and chromium-driver), or point ROLLFRIC_CHROMIUM / \
                         ROLLFRIC_CHROMEDRIVER at them";

// ---------------------------------------------------------------------------------------
// The test.

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
        browser.port,
        started.elapsed().as_secs_f64()
    );

    self_check(&browser);

    let shots = root().join("target/screenshots");
    fs::create_dir_all(&shots).unwrap_or_else(|e| panic!("create {}: {e}", shots.display()));
    let mut failures = Vec::new();
    for (file, stem) in &pages {
        let path = reports.join(file);
        let seen = browser.observe(&path);
        let shot = shots.join(format!("{stem}.png"));
        match browser.screenshot(&shot) {
            Ok((w, h)) => println!("screenshot {} ({w}x{h} px)", shot.display()),
            Err(e) => failures.push(format!("{file}: screenshot failed: {e}")),
        }
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

/// Fake pages in a temporary folder, judged in the same session: the good one must pass,
/// each broken one must fail for its own reason.
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
        let (w, h) = browser
            .screenshot(&path)
            .unwrap_or_else(|e| panic!("screenshot {}: {e}", path.display()));
        println!("screenshot {} ({w}x{h} px)", path.display());
    };
    let seen = browser.observe(&page);
    verdict(&seen).unwrap_or_else(|e| panic!("{}:\n{e}", page.display()));
    shot("review.png");
    let data =
        browser.script("return JSON.parse(document.getElementById('review-data').textContent)");
    let frames = data["frames"].as_array().expect("frames").clone();
    let pictured: Vec<&Value> = frames.iter().filter(|f| f["picture"].is_string()).collect();
    assert!(
        pictured.len() >= 10,
        "the split-screen clip has about 20 flagged frames, the page pictures {}",
        pictured.len()
    );
    // The first flagged frame with a picture that the gate rejected (not a repeat):
    // reached from the first frame with the right arrow key.
    let target_index = frames
        .iter()
        .position(|f| f["picture"].is_string() && f["flag"] == json!("gate"))
        .expect("a frame the gate flagged");
    let target = frames[target_index].clone();
    let frame_no = target["frame"].as_u64().unwrap();
    let start = frames
        .iter()
        .position(|f| f["picture"].is_string())
        .unwrap();
    let info = || browser.script("return document.getElementById('info').textContent");
    assert!(
        info().as_str().unwrap().starts_with(&format!(
            "Frame {} ",
            frames[start]["frame"].as_u64().unwrap()
        )),
        "{}",
        info()
    );
    for _ in start..target_index {
        browser.key("\u{E014}"); // ArrowRight
    }
    browser.key("\u{E014}");
    browser.key("\u{E012}"); // ArrowLeft: one past, and back
    assert!(
        info()
            .as_str()
            .unwrap()
            .starts_with(&format!("Frame {frame_no} ")),
        "after {} right arrows and a left one: {}",
        target_index - start + 1,
        info()
    );

    // Two points 0.8 deg off the angle the series has for this frame (so that the
    // manual angle cannot come from the detector), at whole CSS pixels of the viewport.
    let [rx, ry, rw, rh] = [0, 1, 2, 3].map(|i| data["region"][i].as_f64().unwrap());
    let [px, py] = [0, 1].map(|i| data["pivot"][i].as_f64().unwrap());
    let (w, h) = (
        target["width"].as_f64().unwrap(),
        target["height"].as_f64().unwrap(),
    );
    let rect = browser.script(
        "const e = document.getElementById('overlay'); e.scrollIntoView({block: 'center'}); \
         const r = e.getBoundingClientRect(); return [r.left, r.top, r.width, r.height];",
    );
    let [left, top, width, height] = [0, 1, 2, 3].map(|i| rect[i].as_f64().unwrap());
    let a = (target["angle_deg"].as_f64().unwrap() + 0.8).to_radians();
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
    let block = browser
        .script("return document.getElementById('yaml').value")
        .as_str()
        .unwrap()
        .to_string();
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
    let copied = browser.script("return document.getElementById('copied').textContent");
    assert!(copied.as_str().is_some_and(|s| !s.is_empty()), "{copied}");
    shot("review-marked.png");
    println!(
        "marked frame {frame_no} at {clicked_deg:.3} deg (the series had {:.3} deg):\n{block}",
        target["angle_deg"].as_f64().unwrap()
    );

    // The block under `video:` in the experiment, and a rebuild.
    let marked = filled.replacen("video:\n", &format!("video:\n{block}"), 1);
    assert_ne!(marked, filled, "no `video:` line in {}", yaml.display());
    fs::write(&yaml, marked).unwrap();
    build();
    let seen = browser.observe(&page);
    verdict(&seen).unwrap_or_else(|e| panic!("{} after the rebuild:\n{e}", page.display()));
    let data =
        browser.script("return JSON.parse(document.getElementById('review-data').textContent)");
    let after = data["frames"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["frame"].as_u64() == Some(frame_no))
        .unwrap_or_else(|| panic!("frame {frame_no} left the review page"))
        .clone();
    let measured = after["angle_deg"].as_f64().unwrap();
    assert_eq!(after["status"], json!("manual"), "{after}");
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

#[derive(Debug, Clone, PartialEq)]
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

/// The `<img>` list returned by [`IMAGES_SCRIPT`].
fn parse_images(v: &Value) -> Result<Vec<Img>, String> {
    let list = v
        .as_array()
        .ok_or_else(|| format!("image list is not an array: {v}"))?;
    Ok(list
        .iter()
        .map(|i| Img {
            src: i["src"].as_str().unwrap_or("").to_string(),
            complete: i["complete"].as_bool().unwrap_or(false),
            natural_width: i["naturalWidth"].as_u64().unwrap_or(0),
        })
        .collect())
}

/// The entries of chromedriver's browser log as `LEVEL source: message`.
fn parse_log(v: &Value) -> Vec<String> {
    v.as_array()
        .map(|entries| {
            entries
                .iter()
                .map(|e| {
                    format!(
                        "{} {}: {}",
                        e["level"].as_str().unwrap_or("?"),
                        e["source"].as_str().unwrap_or("?"),
                        e["message"].as_str().unwrap_or("")
                    )
                })
                .collect()
        })
        .unwrap_or_default()
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
    let manifest = work.join("manifest.yaml");
    fs::write(
        &manifest,
        format!("title: Browser test\nexperiments:\n  - {quoted}\n"),
    )
    .unwrap_or_else(|e| panic!("write {}: {e}", manifest.display()));
    let out = work.join("reports");
    if out.exists() {
        fs::remove_dir_all(&out).unwrap_or_else(|e| panic!("clear {}: {e}", out.display()));
    }
    let cache = work.join("cache");
    let started = Instant::now();
    let run = rollfric(
        &[
            OsStr::new("build"),
            OsStr::new("--manifest"),
            manifest.as_os_str(),
            OsStr::new("--out"),
            out.as_os_str(),
            OsStr::new("--cache"),
            cache.as_os_str(),
        ],
        &root(),
    );
    assert!(
        run.status.success(),
        "rollfric build --manifest {} --out {} --cache {} failed ({}):\n--- stdout\n{}\n--- stderr\n{}",
        manifest.display(),
        out.display(),
        cache.display(),
        run.status,
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    println!(
        "built the reports into {} in {:.1} s",
        out.display(),
        started.elapsed().as_secs_f64()
    );
    out
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("bind a free local port")
}

fn file_url(path: &Path) -> String {
    let abs = fs::canonicalize(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut url = String::from("file://");
    for b in abs.to_string_lossy().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => {
                url.push(b as char)
            }
            _ => url.push_str(&format!("%{b:02X}")),
        }
    }
    url
}

// ---------------------------------------------------------------------------------------
// chromedriver and its session. Dropping the `Browser` deletes the session (chromium
// quits) and kills chromedriver, also when a check panics.

struct Browser {
    port: u16,
    child: Child,
    session: Option<String>,
    /// chromium's own process id, killed if the session cannot be deleted.
    chromium_pid: Option<u64>,
    version: String,
    log_path: PathBuf,
    /// Chromium's fresh profile; a field, so it is removed only after chromium quits.
    _profile: tempfile::TempDir,
}

impl Browser {
    fn start(chromium: &Path, chromedriver: &Path) -> Browser {
        let port = free_port();
        let log_path = root().join("target/browser/chromedriver.log");
        if let Some(dir) = log_path.parent() {
            fs::create_dir_all(dir).unwrap_or_else(|e| panic!("create {}: {e}", dir.display()));
        }
        let log = fs::File::create(&log_path)
            .unwrap_or_else(|e| panic!("create {}: {e}", log_path.display()));
        let child = Command::new(chromedriver)
            .arg(format!("--port={port}"))
            .stdin(Stdio::null())
            .stdout(log.try_clone().expect("clone log file"))
            .stderr(log)
            .spawn()
            .unwrap_or_else(|e| panic!("start {}: {e}; {MAKE_DEPS}", chromedriver.display()));
        let profile = tempfile::Builder::new()
            .prefix("rollfric-chromium-")
            .tempdir()
            .expect("temp dir for the chromium profile");
        let mut browser = Browser {
            port,
            child,
            session: None,
            chromium_pid: None,
            version: String::new(),
            log_path,
            _profile: profile,
        };
        browser.wait_ready();
        browser.open_session(chromium);
        browser
    }

    fn driver_log(&self) -> String {
        let text = fs::read_to_string(&self.log_path).unwrap_or_default();
        let tail: Vec<&str> = text.lines().rev().take(30).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        format!(
            "--- {} (tail)\n{}",
            self.log_path.display(),
            tail.join("\n")
        )
    }

    fn wait_ready(&mut self) {
        let start = Instant::now();
        let mut last = String::from("no answer yet");
        while start.elapsed() < DRIVER_START_TIMEOUT {
            if let Ok(Some(status)) = self.child.try_wait() {
                panic!(
                    "chromedriver exited at start ({status})\n{}",
                    self.driver_log()
                );
            }
            match http(self.port, "GET", "/status", None, Duration::from_secs(5)) {
                Ok((200, v)) if v["value"]["ready"] == json!(true) => return,
                Ok((code, v)) => last = format!("HTTP {code}: {v}"),
                Err(e) => last = e,
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        panic!(
            "chromedriver on port {} not ready after {} s (last: {last})\n{}",
            self.port,
            DRIVER_START_TIMEOUT.as_secs(),
            self.driver_log()
        );
    }

    fn open_session(&mut self, chromium: &Path) {
        let mut args: Vec<String> = CHROMIUM_FLAGS.iter().map(|s| s.to_string()).collect();
        args.push(format!(
            "--user-data-dir={}",
            self._profile.path().display()
        ));
        let caps = json!({"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "pageLoadStrategy": "normal",
            "timeouts": {"pageLoad": 50_000, "script": 40_000, "implicit": 0},
            "goog:chromeOptions": {"binary": chromium.to_string_lossy(), "args": args},
            "goog:loggingPrefs": {"browser": "ALL"},
        }}});
        let v = match self.call("POST", "/session", Some(&caps)) {
            Ok(v) => v,
            Err(e) => panic!(
                "chromedriver could not start {}: {e}\n(does `{} --headless --no-sandbox \
                 --dump-dom about:blank` work?)\n{}",
                chromium.display(),
                chromium.display(),
                self.driver_log()
            ),
        };
        let id = v["sessionId"]
            .as_str()
            .unwrap_or_else(|| panic!("no sessionId in {v}"));
        self.session = Some(id.to_string());
        self.chromium_pid = v["capabilities"]["goog:processID"].as_u64();
        self.version = v["capabilities"]["browserVersion"]
            .as_str()
            .unwrap_or("?")
            .to_string();
    }

    /// One WebDriver command: its `value`, or the driver's error.
    fn call(&self, method: &str, path: &str, body: Option<&Value>) -> Result<Value, String> {
        let (code, v) = http(self.port, method, path, body, HTTP_TIMEOUT)?;
        if code == 200 {
            return Ok(v["value"].clone());
        }
        let err = &v["value"];
        Err(format!(
            "{method} {path}: HTTP {code} {}: {}",
            err["error"].as_str().unwrap_or("?"),
            err["message"].as_str().unwrap_or(&v.to_string())
        ))
    }

    /// A command of the open session (`suffix` starts with `/`).
    fn session_call(
        &self,
        method: &str,
        suffix: &str,
        body: Option<&Value>,
    ) -> Result<Value, String> {
        let id = self.session.as_deref().ok_or("no WebDriver session")?;
        self.call(method, &format!("/session/{id}{suffix}"), body)
    }

    fn cdp(&self, cmd: &str, params: Value) -> Result<Value, String> {
        self.session_call(
            "POST",
            "/goog/cdp/execute",
            Some(&json!({"cmd": cmd, "params": params})),
        )
    }

    /// Load a page, wait for it and its images, and drain the browser log.
    fn observe(&self, page: &Path) -> Observation {
        let url = file_url(page);
        let ok = |what: &str, r: Result<Value, String>| {
            r.unwrap_or_else(|e| panic!("{what} on {url}: {e}\n{}", self.driver_log()))
        };
        ok(
            "navigate",
            self.session_call("POST", "/url", Some(&json!({"url": url}))),
        );
        let start = Instant::now();
        loop {
            let state = ok(
                "read document.readyState",
                self.session_call(
                    "POST",
                    "/execute/sync",
                    Some(&json!({"script": "return document.readyState", "args": []})),
                ),
            );
            if state == json!("complete") {
                break;
            }
            assert!(
                start.elapsed() < HTTP_TIMEOUT,
                "{url}: document.readyState still {state} after {} s",
                HTTP_TIMEOUT.as_secs()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        let images = ok(
            "list the images",
            self.session_call(
                "POST",
                "/execute/async",
                Some(&json!({"script": IMAGES_SCRIPT, "args": []})),
            ),
        );
        let images = parse_images(&images).unwrap_or_else(|e| panic!("{url}: {e}"));
        // chromedriver (W3C mode) serves the legacy log endpoint under /se/log; each read
        // returns the entries logged since the previous one.
        let log = ok(
            "read the browser log",
            self.session_call("POST", "/se/log", Some(&json!({"type": "browser"}))),
        );
        Observation {
            images,
            log: parse_log(&log),
        }
    }

    /// Run `js` in the page (WebDriver "execute sync"); its return value.
    fn script(&self, js: &str) -> Value {
        self.session_call(
            "POST",
            "/execute/sync",
            Some(&json!({"script": js, "args": []})),
        )
        .unwrap_or_else(|e| panic!("script {js:?}: {e}\n{}", self.driver_log()))
    }

    /// Press and release one key (a WebDriver key value, e.g. `\u{E014}` ArrowRight).
    fn key(&self, key: &str) {
        let actions = json!({"actions": [{"type": "key", "id": "keyboard", "actions": [
            {"type": "keyDown", "value": key}, {"type": "keyUp", "value": key}]}]});
        self.session_call("POST", "/actions", Some(&actions))
            .unwrap_or_else(|e| panic!("key {key:?}: {e}"));
    }

    /// A left click at viewport CSS pixel `(x, y)`.
    fn click_at(&self, x: f64, y: f64) {
        let actions = json!({"actions": [{"type": "pointer", "id": "mouse",
            "parameters": {"pointerType": "mouse"}, "actions": [
            {"type": "pointerMove", "duration": 0, "origin": "viewport", "x": x as i64, "y": y as i64},
            {"type": "pointerDown", "button": 0}, {"type": "pointerUp", "button": 0}]}]});
        self.session_call("POST", "/actions", Some(&actions))
            .unwrap_or_else(|e| panic!("click at ({x}, {y}): {e}"));
    }

    /// A full-page PNG of the current page (DevTools `Page.captureScreenshot` beyond the
    /// viewport; the plain WebDriver viewport screenshot if that fails). Returns its size.
    fn screenshot(&self, path: &Path) -> Result<(u32, u32), String> {
        let data = match self.full_page_png() {
            Ok(data) => data,
            Err(e) => {
                println!("full-page screenshot failed ({e}); taking the viewport only");
                let v = self.session_call("GET", "/screenshot", None)?;
                v.as_str().ok_or("screenshot is not a string")?.to_string()
            }
        };
        let png = base64_decode(&data)?;
        let size = png_size(&png).ok_or("the screenshot is not a PNG")?;
        if let Some(dir) = path.parent() {
            fs::create_dir_all(dir).map_err(|e| format!("create {}: {e}", dir.display()))?;
        }
        fs::write(path, &png).map_err(|e| format!("write {}: {e}", path.display()))?;
        Ok(size)
    }

    fn full_page_png(&self) -> Result<String, String> {
        let m = self.cdp("Page.getLayoutMetrics", json!({}))?;
        let size = if m["cssContentSize"].is_object() {
            &m["cssContentSize"]
        } else {
            &m["contentSize"]
        };
        let (w, h) = (size["width"].as_f64(), size["height"].as_f64());
        let (w, h) = w.zip(h).ok_or_else(|| format!("no content size in {m}"))?;
        let clip = json!({"x": 0, "y": 0, "width": w.ceil(), "height": h.ceil().min(MAX_SHOT_HEIGHT), "scale": 1});
        let shot = self.cdp(
            "Page.captureScreenshot",
            json!({"format": "png", "captureBeyondViewport": true, "clip": clip}),
        )?;
        shot["data"]
            .as_str()
            .map(str::to_string)
            .ok_or_else(|| "no data in Page.captureScreenshot".to_string())
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let mut quit = self.session.is_none();
        if let Some(id) = self.session.take() {
            let path = format!("/session/{id}");
            quit = matches!(
                http(self.port, "DELETE", &path, None, Duration::from_secs(15)),
                Ok((200, _))
            );
        }
        if !quit {
            // The session could not be closed: end the chromium this test started.
            if let Some(pid) = self.chromium_pid {
                let _ = Command::new("kill")
                    .args(["-KILL", &pid.to_string()])
                    .status();
            }
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

// ---------------------------------------------------------------------------------------
// A minimal HTTP/1.1 client for chromedriver's JSON API.

fn http(
    port: u16,
    method: &str,
    path: &str,
    body: Option<&Value>,
    timeout: Duration,
) -> Result<(u16, Value), String> {
    let addr = SocketAddr::from(([127, 0, 0, 1], port));
    let what = format!("{method} http://127.0.0.1:{port}{path}");
    let mut stream = TcpStream::connect_timeout(&addr, Duration::from_secs(5))
        .map_err(|e| format!("{what}: connect: {e}"))?;
    stream
        .set_read_timeout(Some(timeout))
        .and_then(|()| stream.set_write_timeout(Some(timeout)))
        .map_err(|e| format!("{what}: {e}"))?;
    let body = body.map(Value::to_string).unwrap_or_default();
    let request = format!(
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nAccept: application/json\r\n\
         Content-Type: application/json; charset=utf-8\r\nContent-Length: {}\r\n\
         Connection: close\r\n\r\n{body}",
        body.len()
    );
    stream
        .write_all(request.as_bytes())
        .map_err(|e| format!("{what}: send: {e}"))?;
    let (code, bytes) = read_response(&mut BufReader::new(stream))
        .map_err(|e| format!("{what}: {e} (timeout {} s)", timeout.as_secs()))?;
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Ok((code, Value::Null));
    }
    let v = serde_json::from_slice(&bytes).map_err(|e| {
        let text = String::from_utf8_lossy(&bytes);
        format!(
            "{what}: HTTP {code}, not JSON ({e}): {}",
            &text[..text.len().min(500)]
        )
    })?;
    Ok((code, v))
}

/// Status code and body of one HTTP/1.1 response (Content-Length, chunked, or to EOF).
fn read_response(r: &mut impl BufRead) -> Result<(u16, Vec<u8>), String> {
    let mut line = String::new();
    r.read_line(&mut line)
        .map_err(|e| format!("read status: {e}"))?;
    let code = line
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse::<u16>().ok())
        .ok_or_else(|| format!("bad status line {line:?}"))?;
    let (mut length, mut chunked) = (None, false);
    loop {
        line.clear();
        r.read_line(&mut line)
            .map_err(|e| format!("read headers: {e}"))?;
        let header = line.trim_end();
        if header.is_empty() {
            break;
        }
        if let Some((name, value)) = header.split_once(':') {
            let (name, value) = (name.trim().to_ascii_lowercase(), value.trim());
            if name == "content-length" {
                length = Some(
                    value
                        .parse::<usize>()
                        .map_err(|e| format!("Content-Length: {e}"))?,
                );
            } else if name == "transfer-encoding" && value.to_ascii_lowercase().contains("chunked")
            {
                chunked = true;
            }
        }
    }
    let mut body = Vec::new();
    if chunked {
        loop {
            line.clear();
            r.read_line(&mut line)
                .map_err(|e| format!("read chunk size: {e}"))?;
            let hex = line.trim().split(';').next().unwrap_or("");
            let n =
                usize::from_str_radix(hex, 16).map_err(|e| format!("chunk size {hex:?}: {e}"))?;
            if n == 0 {
                break;
            }
            let at = body.len();
            body.resize(at + n, 0);
            r.read_exact(&mut body[at..])
                .map_err(|e| format!("read chunk: {e}"))?;
            line.clear();
            r.read_line(&mut line)
                .map_err(|e| format!("read chunk end: {e}"))?;
        }
    } else if let Some(n) = length {
        body.resize(n, 0);
        r.read_exact(&mut body)
            .map_err(|e| format!("read body: {e}"))?;
    } else {
        r.read_to_end(&mut body)
            .map_err(|e| format!("read body: {e}"))?;
    }
    Ok((code, body))
}

/// Standard base64 (padding and whitespace allowed).
fn base64_decode(text: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in text.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            b'=' => break,
            c if c.is_ascii_whitespace() => continue,
            c => return Err(format!("bad base64 byte {c:#04x}")),
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Ok(out)
}

/// Width and height of a PNG, from its IHDR chunk.
fn png_size(png: &[u8]) -> Option<(u32, u32)> {
    if png.len() < 24 || &png[..8] != b"\x89PNG\r\n\x1a\n" || &png[12..16] != b"IHDR" {
        return None;
    }
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    Some((be(&png[16..20]), be(&png[20..24])))
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
    let imgs = parse_images(&json!([
        {"src": "file:///a.svg", "complete": true, "naturalWidth": 300},
        {"src": "file:///b.svg", "complete": true, "naturalWidth": 0},
    ]))
    .unwrap();
    assert_eq!(imgs.len(), 2);
    assert_eq!(imgs[0].natural_width, 300);
    assert!(parse_images(&json!(null)).is_err());
    let log = parse_log(&json!([
        {"level": "SEVERE", "source": "network", "message": "x.svg - Failed to load resource", "timestamp": 1},
    ]));
    assert_eq!(log, ["SEVERE network: x.svg - Failed to load resource"]);
}

#[test]
fn http_responses_parse() {
    let fixed = b"HTTP/1.1 200 OK\r\nContent-Length: 13\r\ncontent-type: application/json\r\n\r\n{\"value\":nul}trailing";
    let (code, body) = read_response(&mut &fixed[..]).unwrap();
    assert_eq!((code, body.as_slice()), (200, &b"{\"value\":nul}"[..]));
    let chunked = b"HTTP/1.1 404 Not Found\r\nTransfer-Encoding: chunked\r\n\r\n4\r\nWiki\r\n5;x=y\r\npedia\r\n0\r\n\r\n";
    let (code, body) = read_response(&mut &chunked[..]).unwrap();
    assert_eq!((code, body.as_slice()), (404, &b"Wikipedia"[..]));
    let to_eof = b"HTTP/1.0 500 Oops\r\n\r\nall of it";
    assert_eq!(read_response(&mut &to_eof[..]).unwrap().1, b"all of it");
    assert!(read_response(&mut &b"garbage\r\n\r\n"[..]).is_err());
}

#[test]
fn base64_and_png_header() {
    assert_eq!(base64_decode("").unwrap(), b"");
    assert_eq!(base64_decode("Zg==").unwrap(), b"f");
    assert_eq!(base64_decode("Zm8=").unwrap(), b"fo");
    assert_eq!(base64_decode("Zm9v").unwrap(), b"foo");
    assert_eq!(base64_decode("Zm9vYmFy\n").unwrap(), b"foobar");
    assert_eq!(base64_decode("+/+/").unwrap(), [0xfb, 0xff, 0xbf]);
    assert!(base64_decode("Zm9v!").is_err());
    // A 1x1 PNG, base64 as chromedriver sends it.
    let png = base64_decode(
        "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR4nGP4z8DwHwAFAAH/iZk9HQAAAABJRU5ErkJggg==",
    )
    .unwrap();
    assert_eq!(png_size(&png), Some((1, 1)));
    assert_eq!(png_size(b"GIF89a"), None);
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
