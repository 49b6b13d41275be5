//! Helpers shared by the integration tests (each test crate uses some of them): running
//! the `rollfric` binary, the real fixtures, and the summary line's numbers.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

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

fn shown<S: AsRef<OsStr>>(args: &[S]) -> String {
    let args: Vec<_> = args.iter().map(|a| a.as_ref().to_string_lossy()).collect();
    args.join(" ")
}

/// A real camera clip of `../shared/fixtures/real/` (read in place: the clips carry no
/// licence to redistribute), or `None`, saying SKIPPED, when it is absent.
pub fn fixture(name: &str) -> Option<PathBuf> {
    let p = root().join("../shared/fixtures/real").join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "SKIPPED: {} is absent (the real fixtures live in ../shared)",
            p.display()
        );
        None
    }
}

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
