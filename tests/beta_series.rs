//! `beta` from twins of one pair at four normal forces: recovered within 0.05 and its
//! 95 % interval holds the truth, for each of the usual exponents (two randomised
//! series each; `cargo run --release --example beta_series` runs thirty).

mod beta_twins;

#[test]
fn beta_is_recovered_from_four_normal_forces() {
    let mut lines = Vec::new();
    let mut bad = Vec::new();
    for (i, beta) in [1.0, 4.0 / 3.0, 1.5, 1.0, 4.0 / 3.0, 1.5]
        .into_iter()
        .enumerate()
    {
        let o = beta_twins::series(i as u64, beta, beta_twins::Lever::Balls).unwrap();
        let s = &o.series;
        let line = format!(
            "series {i}: beta {:.3} (true {:.3}), 95 % {:.3} .. {:.3}, s_r {:.4e} (true {:.4e}); {}",
            s.beta, beta, s.beta_interval95[0], s.beta_interval95[1], s.s_r, o.s_r_true, s.verdict
        );
        if (s.beta - beta).abs() > 0.05
            || !(s.beta_interval95[0] <= beta && beta <= s.beta_interval95[1])
            || (s.s_r / o.s_r_true - 1.0).abs() > 0.05
        {
            bad.push(line.clone());
        }
        lines.push(line);
    }
    println!("{}", lines.join("\n"));
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// Four inclines of 3 to 12 deg change the normal force by under 1 %: the series says
/// it cannot tell the exponents apart rather than picking one.
#[test]
fn inclines_alone_cannot_tell_beta() {
    let o = beta_twins::series(7, 4.0 / 3.0, beta_twins::Lever::Inclines).unwrap();
    let s = &o.series;
    assert!(s.n_span_pct < 1.0, "{}", s.n_span_pct);
    assert!(s.verdict.contains("cannot tell"), "{}", s.verdict);
    assert!(s.beta_interval95[0] <= 4.0 / 3.0 && 4.0 / 3.0 <= s.beta_interval95[1]);
}
