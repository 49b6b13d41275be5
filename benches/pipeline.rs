//! `make bench`: timing figures (medians of several runs), printed, not asserted.
//!
//! * one fit: turning points + equilibrium + s_r of a 60 fps angle series;
//! * one simulated 60 s camera series of the digital twin.

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

/// Video figures on one 1280x720 H.264 file, side by side in one run: decode only
/// (`ffmpeg -f null`), OpenCV `read()` only, OpenCV `read()` + grey, and the detector;
/// then the detector's peak memory on a 10 s and a 60 s cut of the same video.
fn video_bench(root: &Path) {
    use std::process::Command;
    let dir = root.join("target/bench");
    std::fs::create_dir_all(&dir).unwrap();
    let long = dir.join("twin-1280x720-60s.mp4");
    let short = dir.join("twin-1280x720-10s.mp4");
    if !long.exists() {
        // Render the glass twin at 1280x720, 60 fps, 60 s (MJPG is fast to write), then
        // encode it to H.264 with ffmpeg.
        let mut exp = Experiment::load(&root.join("experiments/glass.yaml")).unwrap();
        let s = exp.file.synthetic.as_mut().unwrap();
        s.width = 1280;
        s.height = 720;
        s.fps = 60.0;
        let avi = dir.join("twin-1280x720-60s.avi");
        rollfric::synth::render(&exp, &avi, Some(60.0), &mut |_, _| {}).unwrap();
        let st = Command::new("ffmpeg")
            .args(["-v", "error", "-y", "-i"])
            .arg(&avi)
            .args([
                "-c:v", "libx264", "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p",
            ])
            .arg(&long)
            .status()
            .unwrap();
        assert!(st.success());
        let _ = std::fs::remove_file(&avi);
    }
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
    let frames = {
        let mut cap = rollfric::video::OpenCvSource::open(&long, None).unwrap();
        let mut n = 0u64;
        while cap.read_only().unwrap() {
            n += 1;
        }
        n as f64
    };
    let decode = || {
        let st = Command::new("ffmpeg")
            .args(["-v", "error", "-i"])
            .arg(&long)
            .args(["-f", "null", "-"])
            .status()
            .unwrap();
        assert!(st.success());
    };
    let cv_read = || {
        let mut cap = rollfric::video::OpenCvSource::open(&long, None).unwrap();
        while cap.read_only().unwrap() {}
    };
    let cv_gray = || {
        use rollfric::video::FrameSource;
        let mut cap = rollfric::video::OpenCvSource::open(&long, None).unwrap();
        let mut f = rollfric::video::Frame {
            index: 0,
            t_s: 0.0,
            width: 0,
            height: 0,
            data: Vec::new(),
        };
        while cap.next_frame(&mut f).unwrap() {}
    };
    let csv = dir.join("angles.csv");
    let run_detect = |video: &Path| -> String {
        let out = Command::new(env!("CARGO_BIN_EXE_rollfric"))
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
    // Rounds of the four, back to back: the machine's load drifts, so each round's
    // ratios compare runs seconds apart, and the figures are medians over the rounds.
    const ROUNDS: usize = 5;
    let time = |f: &mut dyn FnMut()| {
        let t = Instant::now();
        f();
        t.elapsed().as_secs_f64()
    };
    // rounds[r][k]: seconds of run k (decode, read, read + grey, detector) in round r.
    let rounds: Vec<[f64; 4]> = (0..ROUNDS)
        .map(|_| {
            [
                time(&mut || decode()),
                time(&mut || cv_read()),
                time(&mut || cv_gray()),
                time(&mut || {
                    run_detect(&long);
                }),
            ]
        })
        .collect();
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let fps = |k: usize| frames / median(rounds.iter().map(|r| r[k]).collect());
    let ratios = |k: usize| -> Vec<f64> { rounds.iter().map(|r| r[0] / r[k]).collect() };
    println!(
        "video 1280x720 H.264, {frames:.0} frames (60 s at 60 fps), {ROUNDS} rounds of the four \
         back to back; frames/s (median) and, per round, the ratio to that round's decode-only \
         run (median, min-max):"
    );
    let spread = |k: usize| {
        let v = ratios(k);
        (
            v.iter().copied().fold(f64::MAX, f64::min),
            v.iter().copied().fold(f64::MIN, f64::max),
        )
    };
    println!("  decode only (ffmpeg -f null)      {:>7.0}", fps(0));
    for (k, name) in [
        (1, "OpenCV read() only          "),
        (2, "OpenCV read() + BGR->grey   "),
        (3, "detector (rollfric detect)  "),
    ] {
        let (lo, hi) = spread(k);
        println!(
            "  {name}      {:>7.0}  ({:.2}x decode, {lo:.2}-{hi:.2})",
            fps(k),
            median(ratios(k))
        );
    }
    let peak = |msg: &str| -> String {
        msg.split("peak memory ")
            .nth(1)
            .and_then(|s| s.split(')').next())
            .unwrap_or("?")
            .to_string()
    };
    let m10 = peak(&run_detect(&short));
    let m60 = peak(&run_detect(&long));
    println!("  detector peak memory: 10 s video {m10}, 60 s video {m60}");
}
