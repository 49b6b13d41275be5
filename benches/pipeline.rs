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
}
