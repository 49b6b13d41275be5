//! When the air matters: the paper's ball (r = 31.75 mm, 1.0458 kg) on the paper's incline
//! (5.43 deg), released at 10 deg and filmed for 60 s at 60 frames/s, simulated in still
//! air at 20 degC (the sphere's drag curve) for a range of `s_r` and wire lengths `d`,
//! and fitted twice: with the air modelled (which recovers the truth) and without it, as
//! the paper fits. Prints the table and writes the figure of the bias without the air
//! against `s_r`, one line per `d` (docs/images/air-correction.svg).
//!
//! `cargo run --release --example air_correction -- [SVG]`

use anyhow::Result;
use rollfric::fit::{fit, measure, FitOptions};
use rollfric::physics::ode::{integrate, OdeOptions};
use rollfric::physics::{incline_from_h_l, Air, FrictionLaw, Pendulum};
use rollfric::report::plot::{render_svg, Chart, Rgb, Series};
use rollfric::series::AngleSeries;

/// The angles a camera records of `p` with `law` from a 10 deg release (no noise).
fn recorded(p: &Pendulum, law: &FrictionLaw, fps: f64, dur: f64) -> AngleSeries {
    let opts = OdeOptions {
        t_end: dur,
        ..OdeOptions::default()
    };
    let tr = integrate(p, law, 0.0, [10f64.to_radians(), 0.0], &opts);
    let t: Vec<f64> = (0..(dur * fps) as usize).map(|i| i as f64 / fps).collect();
    let a = t.iter().map(|&x| 1.5 - tr.state(x)[0]).collect();
    AngleSeries::new(t, a)
}

fn main() -> Result<()> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/images/air-correction.svg".into());
    let air = Air::at(20.0, 101_325.0);
    let s_rs = [
        1.0e-6, 1.5e-6, 2.0e-6, 3.0e-6, 4.0e-6, 6.0e-6, 8.0e-6, 12.0e-6, 16.0e-6,
    ];
    let ds = [0.1, 0.15, 0.2, 0.3, 0.4];
    let colors = [Rgb::BLUE, Rgb::GREEN, Rgb::ORANGE, Rgb::RED, Rgb::PURPLE];
    let mut chart = Chart::new(
        "The air's share: s_r fitted without the air, against the truth",
        "true s_r (1e-6 m)",
        "bias of s_r without the air (%)",
    );
    println!("d_m\ts_r_m\twith_air_pct\twithout_air_pct\tenergy_share_pct\tre_max");
    for (&d, color) in ds.iter().zip(colors) {
        let p = Pendulum::solid_ball(0.03175, 1.0458, d, incline_from_h_l(0.142, 1.5), 9.81)?
            .with_air(Some(air));
        let mut points = Vec::new();
        for &s_r in &s_rs {
            let law = FrictionLaw::new(s_r, 1.0);
            let m = measure(&recorded(&p, &law, 60.0, 60.0))?;
            let f = fit(&p, &m, &FitOptions::default())?;
            let a = f.air.expect("fitted in air");
            let with = 100.0 * (f.s_r_m - s_r) / s_r;
            let without = 100.0 * (a.s_r_without_air_m - s_r) / s_r;
            println!(
                "{d}\t{s_r:e}\t{with:+.4}\t{without:+.4}\t{:.4}\t{:.0}",
                a.energy_share_pct, a.reynolds_max
            );
            points.push((s_r * 1e6, without));
        }
        chart = chart.with(Series::line(&format!("d = {d} m"), color, points));
    }
    chart.x_range = Some((0.0, 16.5));
    std::fs::write(&out, render_svg(&chart)?)?;
    eprintln!("wrote {out}");
    Ok(())
}
