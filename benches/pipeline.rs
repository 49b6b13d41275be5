//! `make bench`: timing figures (medians of several runs), printed, not asserted.
//!
//! * one fit: turning points + equilibrium + s_r of a 60 fps angle series;
//! * one simulated 60 s camera series of the digital twin;
//! * `make reports` from scratch and unchanged;
//! * the detector against the decoder (`ffmpeg -f null`) on six twins, paired rounds;
//! * 48 short twins through `rollfric build -j 2` and through `snakemake --cores 2`
//!   (the generated Snakefile), paired rounds from an empty cache.

use rollfric::config::Experiment;
use rollfric::fit::{self, FitOptions};
use rollfric::simulate;
use std::path::Path;
use std::time::{Duration, Instant};

fn median_of<F: FnMut()>(runs: usize, mut f: F) -> Duration {
    let mut v: Vec<Duration> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .collect();
    v.sort();
    v[runs / 2]
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    println!(
        "rollfric {} benchmarks (median of runs)",
        env!("CARGO_PKG_VERSION")
    );
    for name in ["steel", "glass", "glass-fiber-fabric"] {
        let exp = Experiment::load(&root.join(format!("experiments/{name}.yaml"))).unwrap();
        let mut cam = simulate::camera_of(&exp).unwrap();
        cam.duration_s = Some(60.0);
        let sim = median_of(7, || {
            std::hint::black_box(simulate::record(&exp, &cam).unwrap());
        });
        let cam = simulate::camera_of(&exp).unwrap();
        let series = simulate::record(&exp, &cam).unwrap().series;
        let mut m = None;
        let measure = median_of(9, || {
            m = Some(fit::analyze(&exp.pendulum, &series, exp.beta).unwrap());
        });
        let m = m.unwrap();
        let fit_only = median_of(9, || {
            std::hint::black_box(fit::fit(&exp.pendulum, &m, &FitOptions::default()).unwrap());
        });
        let whole = median_of(9, || {
            let m = fit::analyze(&exp.pendulum, &series, exp.beta).unwrap();
            std::hint::black_box(fit::fit(&exp.pendulum, &m, &FitOptions::default()).unwrap());
        });
        println!(
            "{name:<20} one fit {:>7.2} ms  (turning points {:>6.2} ms, s_r {:>6.2} ms; {} samples, {} extremes)  simulate 60 s at {} fps {:>6.2} ms",
            ms(whole),
            ms(measure),
            ms(fit_only),
            series.len(),
            m.extremes.len(),
            cam.fps,
            ms(sim)
        );
    }
    if std::env::var_os("ROLLFRIC_BENCH_NO_REPORTS").is_none() {
        reports_bench(root);
    }
    if std::env::var_os("ROLLFRIC_BENCH_NO_VIDEO").is_none() {
        video_bench(root);
    }
    if std::env::var_os("ROLLFRIC_BENCH_NO_SCALE").is_none() {
        scale_bench(root);
    }
}

/// Twins of the scale benchmark, and its paired rounds.
const SCALE_TWINS: usize = 48;
const SCALE_ROUNDS: usize = 2;

/// Many short videos: 48 twins (6 s at 25 frames/s, 320x240, on a 19.5 deg incline so
/// that a 1.7 s period gives the fit its turning points; s_r varied) built from an
/// empty cache by `rollfric build -j 2` and by `snakemake --cores 2` on the Snakefile
/// `rollfric workflow snakemake` writes (the Snakemake `make snakemake` installs, or
/// `ROLLFRIC_SNAKEMAKE`), alternating which goes first; both walls (median) and their
/// ratio per round (goal: Snakemake within 1.3x of the build).
fn scale_bench(root: &Path) {
    use std::process::Command;
    let smk = std::env::var_os("ROLLFRIC_SNAKEMAKE")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| root.join("target/snakemake/bin/snakemake"));
    if Command::new(&smk).arg("--version").output().is_err() {
        println!(
            "scale: {} not found (make snakemake installs it); skipped",
            smk.display()
        );
        return;
    }
    let dir = root.join("target/bench-scale");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut list = String::from("title: Scale benchmark\nexperiments:\n");
    for k in 0..SCALE_TWINS {
        let s_r = 3e-6 + 1e-7 * k as f64;
        std::fs::write(
            dir.join(format!("t{k:02}.yaml")),
            format!(
                "name: t{k:02}\ngeometry:\n  incline: {{ h_m: 0.5, l_m: 1.500 }}\n  pendulum: {{ d_m: 0.1774 }}\n  ball: {{ radius_m: 0.03175, mass_kg: 1.0458 }}\nsynthetic: {{ s_r_m: {s_r:e}, psi0_deg: 10, duration_s: 6, fps: 25, width: 320, height: 240, seed: {k} }}\n"
            ),
        )
        .unwrap();
        list += &format!("  - t{k:02}.yaml\n");
    }
    std::fs::write(dir.join("manifest.yaml"), list).unwrap();
    let bin = env!("CARGO_BIN_EXE_rollfric");
    let o = Command::new(bin)
        .current_dir(&dir)
        .args(["workflow", "snakemake", "--manifest", "manifest.yaml"])
        .args(["--out", "reports-smk", "--cache", "cache-smk"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let timed = |cmd: &mut Command, clear: &[&str]| -> f64 {
        for c in clear {
            let _ = std::fs::remove_dir_all(dir.join(c));
        }
        let t = Instant::now();
        let o = cmd.current_dir(&dir).output().unwrap();
        let secs = t.elapsed().as_secs_f64();
        // A build exits 1 when a short twin misses its tolerance: timed all the same;
        // a failed experiment would time less than the work.
        let said = String::from_utf8_lossy(&o.stderr);
        assert!(
            o.status.code().is_some_and(|c| c <= 1) && !said.contains("FAILED"),
            "{cmd:?} failed: {said}"
        );
        secs
    };
    let build = || {
        timed(
            Command::new(bin).args([
                "build",
                "-q",
                "-j",
                "2",
                "--manifest",
                "manifest.yaml",
                "--out",
                "reports-build",
                "--cache",
                "cache-build",
            ]),
            &["reports-build", "cache-build"],
        )
    };
    let snakemake = || {
        timed(
            Command::new(&smk)
                .args(["--cores", "2", "--config"])
                .arg(format!("rollfric={bin}")),
            &["reports-smk", "cache-smk", ".snakemake"],
        )
    };
    let (mut b, mut s, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
    for round in 0..SCALE_ROUNDS {
        let (x, y) = if round % 2 == 0 {
            let x = build();
            (x, snakemake())
        } else {
            let y = snakemake();
            (build(), y)
        };
        b.push(x);
        s.push(y);
        ratio.push(y / x);
    }
    let med = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (lo, hi) = ratio
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &r| (l.min(r), h.max(r)));
    println!(
        "scale: {SCALE_TWINS} twins of 6 s from an empty cache: rollfric build -j 2 {:.1} s, snakemake --cores 2 {:.1} s (median of {SCALE_ROUNDS} paired rounds); snakemake / build {:.2} (range {lo:.2}..{hi:.2}; goal <= 1.3)",
        med(&mut b),
        med(&mut s),
        med(&mut ratio)
    );
}

/// `make reports` from scratch, compile excluded: `rollfric build` of the whole manifest
/// with an empty cache and output folder (every twin rendered, detected, fitted and
/// drawn), then the same build again with nothing changed.
fn reports_bench(root: &Path) {
    use std::process::Command;
    let dir = root.join("target/bench");
    let (out, cache) = (dir.join("reports"), dir.join("reports-cache"));
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&cache);
    let run = || {
        let t = Instant::now();
        let o = Command::new(env!("CARGO_BIN_EXE_rollfric"))
            .current_dir(root)
            .args(["build", "-q", "--out"])
            .arg(&out)
            .arg("--cache")
            .arg(&cache)
            .output()
            .unwrap();
        let secs = t.elapsed().as_secs_f64();
        assert!(
            o.status.success(),
            "rollfric build failed: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        (secs, String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let (cold, line) = run();
    let (warm, _) = run();
    println!(
        "make reports from scratch (compile excluded): {cold:.1} s (target <= 60 s) on {} cores; unchanged rebuild {warm:.2} s (target < 1 s)\n  {line}",
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
}

/// One twin of the video benchmark.
struct BenchVideo {
    /// The experiment rendered (its own scene and seed), at this size, rate and length.
    experiment: &'static str,
    width: u32,
    height: u32,
    fps: f64,
    seconds: f64,
    /// H.264 (`.mp4`, encoded by ffmpeg from the rendered MJPG) or MJPG (`.avi`).
    h264: bool,
}

/// The detector against the decoder on six twins from 640x480 to 1920x1080, MJPG and
/// H.264, 25 to 60 frames/s, 12 to 80 s.
const VIDEOS: [BenchVideo; 6] = [
    BenchVideo {
        experiment: "glass",
        width: 640,
        height: 480,
        fps: 30.0,
        seconds: 80.0,
        h264: true,
    },
    BenchVideo {
        experiment: "glass",
        width: 960,
        height: 540,
        fps: 25.0,
        seconds: 12.0,
        h264: false,
    },
    BenchVideo {
        experiment: "steel",
        width: 1280,
        height: 720,
        fps: 30.0,
        seconds: 49.0,
        h264: true,
    },
    BenchVideo {
        experiment: "glass",
        width: 1280,
        height: 720,
        fps: 60.0,
        seconds: 69.0,
        h264: false,
    },
    BenchVideo {
        experiment: "glass",
        width: 1280,
        height: 720,
        fps: 60.0,
        seconds: 60.0,
        h264: true,
    },
    BenchVideo {
        experiment: "steel",
        width: 1920,
        height: 1080,
        fps: 25.0,
        seconds: 60.0,
        h264: true,
    },
];

impl BenchVideo {
    /// What the table calls it.
    fn label(&self) -> String {
        format!(
            "{}x{} {} {} fps {} s",
            self.width,
            self.height,
            if self.h264 { "H.264" } else { "MJPG" },
            self.fps,
            self.seconds
        )
    }

    /// Its file name under `target/bench`.
    fn file(&self) -> String {
        format!(
            "twin-{}x{}-{}fps-{}s.{}",
            self.width,
            self.height,
            self.fps,
            self.seconds,
            if self.h264 { "mp4" } else { "avi" }
        )
    }
}

/// Render a benchmark twin (once; later runs reuse the file).
fn bench_video(root: &Path, dir: &Path, v: &BenchVideo) -> std::path::PathBuf {
    use std::process::Command;
    let out = dir.join(v.file());
    if out.exists() {
        return out;
    }
    let mut exp =
        Experiment::load(&root.join(format!("experiments/{}.yaml", v.experiment))).unwrap();
    let s = exp.file.synthetic.as_mut().unwrap();
    s.width = v.width;
    s.height = v.height;
    s.fps = v.fps;
    let avi = dir.join(format!("{}.rendering.avi", v.file()));
    rollfric::synth::render(&exp, &avi, Some(v.seconds), &mut |_, _| {}).unwrap();
    if v.h264 {
        let st = Command::new("ffmpeg")
            .args(["-v", "error", "-y", "-i"])
            .arg(&avi)
            .args([
                "-c:v", "libx264", "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p",
            ])
            .arg(&out)
            .status()
            .unwrap();
        assert!(st.success());
        let _ = std::fs::remove_file(&avi);
    } else {
        std::fs::rename(&avi, &out).unwrap();
    }
    out
}

/// What `rollfric detect` says of its own run: peak memory (MiB) and CPU besides the
/// decoder (s), from its summary line.
fn detect_figures(stderr: &str) -> (f64, f64) {
    let after = |key: &str| -> f64 {
        stderr
            .rsplit(key)
            .next()
            .and_then(|s| s.split_whitespace().next())
            .and_then(|s| s.trim_end_matches([',', ')']).parse().ok())
            .unwrap_or(f64::NAN)
    };
    (after("peak memory "), after("CPU besides the decoder "))
}

/// The part of `rollfric detect`'s CPU besides the decoder spent before its streaming
/// pass (the first look and its geometry, s), from its summary line: `... CPU besides the
/// decoder 0.61 s, 0.15 s of it before the pass)`.
fn cpu_before_pass(stderr: &str) -> f64 {
    stderr
        .rsplit("CPU besides the decoder ")
        .next()
        .and_then(|s| s.split_once(" s, "))
        .and_then(|(_, s)| s.split_once(" s of it before the pass"))
        .and_then(|(s, _)| s.parse().ok())
        .unwrap_or(f64::NAN)
}

/// How many frames `rollfric detect` says it read, from its summary line.
fn frames_of(stderr: &str) -> f64 {
    stderr
        .rsplit(" frames in ")
        .nth(1)
        .and_then(|s| s.rsplit(": ").next())
        .and_then(|s| s.parse().ok())
        .unwrap_or(f64::NAN)
}

/// Video figures: per twin, rounds of decode only (`ffmpeg -f null`, the floor) and the
/// detector back to back, alternating which goes first; the walls (median), the ratio
/// decode-only / detector of each round (median and range: 1 means the detector keeps
/// the decoder's pace), the detector's own CPU per frame besides the decoder, the same
/// less its part before the first streaming pass (the summary line's whole less its
/// `of it before the pass`: the process's own start and the files written count in the
/// pass's), and its peak memory. Then the peak memory on a 10 s and a 60 s 1920x1080 video.
fn video_bench(root: &Path) {
    use std::process::Command;
    let dir = root.join("target/bench");
    std::fs::create_dir_all(&dir).unwrap();
    let rounds: usize = std::env::var("ROLLFRIC_BENCH_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3);
    let csv = dir.join("angles.csv");
    let decode = |video: &Path| {
        let st = Command::new("ffmpeg")
            .args(["-v", "error", "-i"])
            .arg(video)
            .args(["-f", "null", "-"])
            .status()
            .unwrap();
        assert!(st.success());
    };
    let run_detect_with = |bin: &Path, video: &Path| -> String {
        let out = Command::new(bin)
            .arg("detect")
            .arg(video)
            .arg("-o")
            .arg(&csv)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stderr).to_string()
    };
    let this_build = Path::new(env!("CARGO_BIN_EXE_rollfric"));
    let run_detect = |video: &Path| run_detect_with(this_build, video);
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!(
        "video: decode only (ffmpeg -f null) and the detector (rollfric detect), {rounds} paired \
         rounds per video; ratio = decode-only wall / detector wall per round (goal >= 0.8)"
    );
    println!(
        "  {:<34} {:>6}  {:>8}  {:>8}  {:>17}  {:>9}  {:>10}  {:>8}",
        "video",
        "frames",
        "decode s",
        "detect s",
        "ratio (min-max)",
        "CPU us/fr",
        "pass us/fr",
        "peak MiB"
    );
    for v in &VIDEOS {
        let path = bench_video(root, &dir, v);
        let mut walls = Vec::new();
        let mut last = String::new();
        for r in 0..rounds {
            let time_decode = || {
                let t = Instant::now();
                decode(&path);
                t.elapsed().as_secs_f64()
            };
            let mut time_detect = || {
                let t = Instant::now();
                last = run_detect(&path);
                t.elapsed().as_secs_f64()
            };
            walls.push(if r % 2 == 0 {
                let d = time_decode();
                (d, time_detect())
            } else {
                let t = time_detect();
                (time_decode(), t)
            });
        }
        let frames = frames_of(&last);
        let (peak, cpu) = detect_figures(&last);
        let before = cpu_before_pass(&last);
        let ratios: Vec<f64> = walls.iter().map(|(d, t)| d / t).collect();
        let lo = ratios.iter().copied().fold(f64::MAX, f64::min);
        let hi = ratios.iter().copied().fold(f64::MIN, f64::max);
        println!(
            "  {:<34} {frames:>6.0}  {:>8.2}  {:>8.2}  {:>5.2} ({lo:.2}-{hi:.2})  {:>9.0}  {:>10.0}  \
             {peak:>8.0}",
            v.label(),
            median(walls.iter().map(|w| w.0).collect()),
            median(walls.iter().map(|w| w.1).collect()),
            median(ratios),
            cpu / frames * 1e6,
            (cpu - before) / frames * 1e6,
        );
    }
    // Memory is flat in the video's length: the last twin (1920x1080, 60 s) and its
    // first 10 s.
    let long = dir.join(VIDEOS[5].file());
    let short = dir.join("twin-1920x1080-25fps-10s.mp4");
    if !short.exists() {
        let st = Command::new("ffmpeg")
            .args(["-v", "error", "-y", "-i"])
            .arg(&long)
            .args(["-t", "10", "-c", "copy"])
            .arg(&short)
            .status()
            .unwrap();
        assert!(st.success());
    }
    let (m10, _) = detect_figures(&run_detect(&short));
    let (m60, _) = detect_figures(&run_detect(&long));
    println!("  detector peak memory at 1920x1080: 10 s video {m10:.0} MiB, 60 s video {m60:.0} MiB (goal <= 150 MiB, flat)");
    // Against an earlier build (`make bench-baseline`): the same twins (still cameras),
    // each build's CPU besides the decoder as its summary line gives it.
    if let Some(base) = std::env::var_os("ROLLFRIC_BENCH_BASELINE") {
        let base = Path::new(&base);
        println!(
            "still cameras against {}: the detector's CPU besides the decoder, {rounds} paired \
             rounds per video (which build first alternating), medians; ratio = this build / \
             baseline (goal <= 1.10)",
            base.display()
        );
        println!(
            "  {:<34} {:>6}  {:>10}  {:>10}  {:>6}",
            "video", "frames", "baseline s", "this s", "ratio"
        );
        for v in &VIDEOS {
            let path = dir.join(v.file());
            let (mut b, mut t) = (Vec::new(), Vec::new());
            let mut frames = f64::NAN;
            for r in 0..rounds {
                let mut cpu = |bin: &Path| {
                    let said = run_detect_with(bin, &path);
                    frames = frames_of(&said);
                    detect_figures(&said).1
                };
                if r % 2 == 0 {
                    b.push(cpu(base));
                    t.push(cpu(this_build));
                } else {
                    t.push(cpu(this_build));
                    b.push(cpu(base));
                }
            }
            let (b, t) = (median(b), median(t));
            println!(
                "  {:<34} {frames:>6.0}  {b:>10.2}  {t:>10.2}  {:>6.2}",
                v.label(),
                t / b
            );
        }
    }
}
