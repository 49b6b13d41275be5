//! Helpers shared by the integration tests (each test crate uses some of them).
#![allow(dead_code)]

use std::process::Command;

/// Whether the `ffmpeg` program runs here (`make test` installs it; without it the
/// video tests say SKIPPED).
pub fn have_ffmpeg() -> bool {
    Command::new("ffmpeg").arg("-version").output().is_ok()
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
