//! `beta` from thirty randomised series of twins of one pair at four normal forces
//! (ten each with beta = 1, 4/3 and 3/2; `tests/beta_twins` draws them): each series'
//! fitted beta, its 95 % interval and verdict, then how many were recovered within 0.05
//! and how many intervals held the truth; then three series on four inclines instead.
//!
//! `cargo run --release --example beta_series -- [SERIES]`

#[path = "../tests/beta_twins/mod.rs"]
mod beta_twins;

use anyhow::Result;

fn main() -> Result<()> {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(30);
    let (mut within, mut holds, mut favoured) = (0, 0, 0);
    println!(
        "series | true beta | fitted beta | 95 % interval | s_r / truth - 1 | Birge | verdict"
    );
    for i in 0..n {
        let beta = [1.0, 4.0 / 3.0, 1.5][(i % 3) as usize];
        let o = beta_twins::series(100 + i, beta, beta_twins::Lever::Balls)?;
        let s = &o.series;
        within += usize::from((s.beta - beta).abs() <= 0.05);
        holds += usize::from(s.beta_interval95[0] <= beta && beta <= s.beta_interval95[1]);
        favoured += usize::from(
            s.verdict
                .contains(&format!("favour beta = {}", rollfric::fit::beta_name(beta))),
        );
        println!(
            "{i:6} | {:9.3} | {:11.4} | {:.4} .. {:.4} | {:+.3} % | {:5.2} | {}",
            beta,
            s.beta,
            s.beta_interval95[0],
            s.beta_interval95[1],
            100.0 * (s.s_r / o.s_r_true - 1.0),
            s.birge_ratio.unwrap_or(f64::NAN),
            s.verdict
        );
    }
    println!(
        "{n} series: beta within 0.05 of the truth in {within}, the 95 % interval holds it in {holds}, the verdict names it in {favoured}"
    );
    println!("\nthe same pair on four inclines (3, 5.4, 8, 12 deg), one ball:");
    for i in 0..3 {
        let beta = [1.0, 4.0 / 3.0, 1.5][i as usize];
        let s = beta_twins::series(200 + i, beta, beta_twins::Lever::Inclines)?.series;
        println!(
            "true beta {beta:.3}: normal forces span {:.2} %, beta {:.3}, 95 % {:.2} .. {:.2}; {}",
            s.n_span_pct, s.beta, s.beta_interval95[0], s.beta_interval95[1], s.verdict
        );
    }
    Ok(())
}
