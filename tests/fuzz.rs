//! Property tests of the readers and the fit on mutated input: the experiment YAML
//! reader, the angle-CSV reader and the analysis of arbitrary finite angle series. For
//! every input: no panic, each call within a time budget, and an error (when there is
//! one) on a single line of at most `MAX_ERROR_BYTES`.
//!
//! The inputs are the files of `experiments/` and the simulator's CSVs, mutated byte by
//! byte and line by line by a deterministic generator (`rollfric::rng::Rng`), so that a
//! failure names a seed that reproduces it. `make check` runs a short pass;
//! `ROLLFRIC_FUZZ_ITERS=200000 make fuzz` (or the variable alone with `cargo test --test
//! fuzz`) a longer one, and `ROLLFRIC_FUZZ_SEED` starts from another seed.

use rollfric::config::Experiment;
use rollfric::pipeline::{self, Angles, Overrides, Source};
use rollfric::rng::Rng;
use rollfric::series::{AngleRow, AngleTable, Status};
use rollfric::simulate;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

/// The longest one call may take.
const CALL_BUDGET: Duration = Duration::from_secs(2);
/// A call still running after this long is a hang: the test stops waiting for it.
const HANG: Duration = Duration::from_secs(30);
/// The longest error message (its `{:#}` form).
const MAX_ERROR_BYTES: usize = 1024;
/// The highest peak resident memory of the whole test process, MB.
const MEMORY_BUDGET_MB: f64 = 1500.0;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// How many inputs each target tries (`ROLLFRIC_FUZZ_ITERS`, default `default`).
fn iterations(default: usize) -> usize {
    std::env::var("ROLLFRIC_FUZZ_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn base_seed() -> u64 {
    std::env::var("ROLLFRIC_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(12)
}

/// What a run of one target found.
#[derive(Default)]
struct Report {
    tried: usize,
    errors: usize,
    slowest: Duration,
    slowest_input: String,
    failures: Vec<String>,
}

/// The call in progress (its start and a description), for the watchdog.
type Current = Arc<Mutex<Option<(Instant, String)>>>;

/// Run `n` inputs of `target` (each from its own seed) on a worker thread, while this
/// thread watches for a call that hangs. `make` builds the input of a seed and a short
/// description of it; `call` runs it.
fn run<I, M, C>(target: &str, n: usize, make: M, call: C) -> Report
where
    I: Send + 'static,
    M: Fn(u64) -> (I, String) + Send + 'static,
    C: Fn(I) -> anyhow::Result<()> + Send + 'static,
{
    let current: Current = Arc::new(Mutex::new(None));
    let (tx, rx) = mpsc::channel();
    let seed0 = base_seed();
    let cur = current.clone();
    let worker = std::thread::spawn(move || {
        let mut r = Report::default();
        for k in 0..n as u64 {
            let seed = seed0.wrapping_mul(1_000_003).wrapping_add(k);
            let (input, what) = make(seed);
            let what = format!("seed {seed}: {what}");
            *cur.lock().unwrap() = Some((Instant::now(), what.clone()));
            let start = Instant::now();
            let out = catch_unwind(AssertUnwindSafe(|| call(input)));
            let took = start.elapsed();
            *cur.lock().unwrap() = None;
            r.tried += 1;
            if took > r.slowest {
                r.slowest = took;
                r.slowest_input = what.clone();
            }
            if took > CALL_BUDGET {
                r.failures.push(format!("{what}: took {took:?}"));
            }
            match out {
                Err(p) => {
                    let msg = p
                        .downcast_ref::<String>()
                        .map(String::as_str)
                        .or_else(|| p.downcast_ref::<&str>().copied())
                        .unwrap_or("?");
                    r.failures.push(format!("{what}: PANIC {msg}"));
                }
                Ok(Err(e)) => {
                    r.errors += 1;
                    let m = format!("{e:#}");
                    if m.contains('\n') || m.len() > MAX_ERROR_BYTES {
                        let head: String = m.chars().take(200).collect();
                        r.failures.push(format!(
                            "{what}: error of {} bytes on {} lines: {head:?}",
                            m.len(),
                            m.lines().count()
                        ));
                    }
                }
                Ok(Ok(())) => {}
            }
        }
        let _ = tx.send(());
        r
    });
    loop {
        match rx.recv_timeout(Duration::from_millis(200)) {
            Ok(()) | Err(mpsc::RecvTimeoutError::Disconnected) => break,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if let Some((t, what)) = current.lock().unwrap().clone() {
                    assert!(
                        t.elapsed() < HANG,
                        "{target}: a call hangs (over {HANG:?}): {what}"
                    );
                }
            }
        }
    }
    let r = worker.join().expect("the fuzz worker");
    println!(
        "{target}: {} inputs tried, {} errors, {} failures (panics, slow calls, long \
         errors), slowest call {:?} ({}), peak memory {:.0} MB",
        r.tried,
        r.errors,
        r.failures.len(),
        r.slowest,
        r.slowest_input,
        peak_memory_mb()
    );
    let panics = r.failures.iter().filter(|f| f.contains("PANIC")).count();
    println!("{target}: {panics} panics");
    r
}

fn check(target: &str, r: &Report) {
    let mb = peak_memory_mb();
    assert!(
        mb < MEMORY_BUDGET_MB,
        "{target}: peak memory {mb:.0} MB over {MEMORY_BUDGET_MB} MB"
    );
    assert!(
        r.failures.is_empty(),
        "{target}: {} of {} inputs failed; first ones:\n{}",
        r.failures.len(),
        r.tried,
        r.failures
            .iter()
            .take(10)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// The process's peak resident memory (`VmHWM`), MB; 0 where it is not known.
fn peak_memory_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.split_whitespace().next()?.parse::<f64>().ok())
        })
        .map_or(0.0, |kb| kb / 1024.0)
}

// ---------------------------------------------------------------------------------------
// The generator: byte-wise and line-wise mutations.

fn pick<'a, T>(rng: &mut Rng, xs: &'a [T]) -> &'a T {
    &xs[below(rng, xs.len())]
}

fn below(rng: &mut Rng, n: usize) -> usize {
    if n == 0 {
        0
    } else {
        (rng.next_u64() % n as u64) as usize
    }
}

/// Values that break readers: huge, tiny, negative, not numbers, other types, unicode.
const NASTY: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1e9",
    "-1e9",
    "1e300",
    "1e400",
    "-1e400",
    "1e-320",
    "4.9e-324",
    "99999999999999999999999999",
    "18446744073709551616",
    "-9223372036854775809",
    "nan",
    "NaN",
    ".nan",
    "inf",
    "-inf",
    ".inf",
    "-.inf",
    "0x10",
    "1_000",
    "~",
    "null",
    "true",
    "no",
    "''",
    "\"\"",
    "[]",
    "{}",
    "[1, 2, 3]",
    "{a: 1}",
    "!!binary aGVsbG8=",
    "&a [*a]",
    "*nothing",
    "|",
    ">-",
    "é",
    "💥",
    "\u{202e}evil",
    "\u{0}",
    "\t",
    ",",
    ":",
    "- x",
    "? x",
    "ok",
    "missing",
    "manual",
    "corrected",
    "%YAML 1.2",
    "---",
    "...",
];

/// One mutation of `text`, described.
fn mutate(rng: &mut Rng, text: &str) -> (String, String) {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let n = lines.len();
    let kind = below(rng, 16);
    let what = match kind {
        0 if n > 0 => {
            let i = below(rng, n);
            lines.remove(i);
            format!("drop line {i}")
        }
        1 if n > 0 => {
            let i = below(rng, n);
            let l = lines[i].clone();
            let times = 1 + below(rng, 3);
            for _ in 0..times {
                lines.insert(i, l.clone());
            }
            format!("duplicate line {i} x{times}")
        }
        2 if n > 1 => {
            let (i, j) = (below(rng, n), below(rng, n));
            lines.swap(i, j);
            format!("swap lines {i} and {j}")
        }
        3..=5 if n > 0 => {
            // Replace a token (a number, a word, a value after `:` or `,`) with a nasty one.
            let i = below(rng, n);
            let v = pick(rng, NASTY).to_string();
            let l = &lines[i];
            let cuts: Vec<usize> = l
                .char_indices()
                .filter(|(_, c)| matches!(c, ':' | ',' | ' '))
                .map(|(k, _)| k + 1)
                .collect();
            let at = if cuts.is_empty() {
                0
            } else {
                *pick(rng, &cuts)
            };
            let end = l[at..]
                .find([',', ' ', '}', ']'])
                .map_or(l.len(), |e| at + e.max(1).min(l.len() - at));
            lines[i] = format!("{}{v}{}", &l[..at], &l[end..]);
            format!("line {i}: token at {at} -> {v:?}")
        }
        6 if n > 0 => {
            let i = below(rng, n);
            let f = *pick(rng, &[1e5, 1e6, 1e12, -1.0, 1e-9, 57.29577951308232]);
            lines[i] = scale_numbers(&lines[i], f);
            format!("line {i}: numbers x{f}")
        }
        7 => {
            let f = *pick(rng, &[1e3, 1e5, 1e6, 1e15, -1.0, 57.29577951308232, 0.0]);
            for l in lines.iter_mut() {
                *l = scale_numbers(l, f);
            }
            format!("all numbers x{f}")
        }
        8 => {
            let len = *pick(rng, &[1_000, 100_000, 1_000_000]);
            let ch = *pick(rng, &['a', '9', ' ', '[', '{', '-', ',', 'é']);
            let line: String = std::iter::repeat_n(ch, len).collect();
            let i = below(rng, n + 1);
            lines.insert(i, line);
            format!("insert a line of {len} x {ch:?} at {i}")
        }
        9 => {
            let depth = *pick(rng, &[100, 1_000, 10_000, 100_000]);
            let (open, close) = *pick(rng, &[("[", "]"), ("{a: ", "}"), ("- ", "")]);
            let nested = if open == "- " {
                (0..depth.min(2_000))
                    .map(|d| format!("{}- x", " ".repeat(2 * d)))
                    .collect::<Vec<_>>()
                    .join("\n")
            } else {
                format!("key: {}1{}", open.repeat(depth), close.repeat(depth))
            };
            let i = below(rng, n + 1);
            lines.insert(i, nested);
            format!("insert nesting {open:?} x{depth} at {i}")
        }
        10 => {
            // A billion laughs: aliases of aliases.
            let mut s = String::from("a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n");
            for k in 1..10 {
                let p = k - 1;
                s.push_str(&format!(
                    "a{k}: &a{k} [*a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}]\n"
                ));
            }
            lines.push(s);
            "append nested aliases".into()
        }
        11 => {
            let i = below(rng, n + 1);
            let mut b = vec![0u8; 1 + below(rng, 64)];
            for x in b.iter_mut() {
                *x = rng.next_u64() as u8;
            }
            lines.insert(i, String::from_utf8_lossy(&b).into_owned());
            format!("insert {} random bytes at line {i}", b.len())
        }
        12 => {
            let keep = below(rng, text.len() + 1);
            let mut k = keep;
            while !text.is_char_boundary(k) {
                k -= 1;
            }
            return (text[..k].to_string(), format!("truncate at byte {k}"));
        }
        13 if n > 0 => {
            let i = below(rng, n);
            let indent = *pick(rng, &["", "  ", "\t", "    ", " "]);
            lines[i] = format!("{indent}{}", lines[i].trim_start());
            format!("line {i}: indent {indent:?}")
        }
        _ => {
            // Flip, insert or delete single bytes.
            let mut b = text.as_bytes().to_vec();
            let edits = 1 + below(rng, 8);
            for _ in 0..edits {
                let at = below(rng, b.len() + 1);
                match below(rng, 3) {
                    0 if at < b.len() => b[at] ^= 1 << below(rng, 8),
                    1 => b.insert(at, rng.next_u64() as u8),
                    _ if at < b.len() => {
                        b.remove(at);
                    }
                    _ => {}
                }
            }
            return (
                String::from_utf8_lossy(&b).into_owned(),
                format!("{edits} byte edits"),
            );
        }
    };
    let mut out = lines.join("\n");
    if text.ends_with('\n') {
        out.push('\n');
    }
    (out, what)
}

/// `line` with every number multiplied by `f`.
fn scale_numbers(line: &str, f: f64) -> String {
    let mut out = String::new();
    let mut tok = String::new();
    let flush = |tok: &mut String, out: &mut String| {
        match tok.parse::<f64>() {
            Ok(v) if tok.chars().any(|c| c.is_ascii_digit()) => out.push_str(&format!("{}", v * f)),
            _ => out.push_str(tok),
        }
        tok.clear();
    };
    for c in line.chars() {
        if c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+') {
            tok.push(c);
        } else {
            flush(&mut tok, &mut out);
            out.push(c);
        }
    }
    flush(&mut tok, &mut out);
    out
}

/// Up to `max` mutations in a row.
fn mutated(rng: &mut Rng, text: &str, max: usize) -> (String, String) {
    let rounds = 1 + below(rng, max);
    let mut s = text.to_string();
    let mut what = Vec::new();
    for _ in 0..rounds {
        let (t, w) = mutate(rng, &s);
        s = t;
        what.push(w);
    }
    (s, what.join("; "))
}

// ---------------------------------------------------------------------------------------
// The seeds: the experiments of the repository and the simulator's CSVs.

fn experiment_files() -> Vec<(PathBuf, String)> {
    let mut v: Vec<_> = std::fs::read_dir(root().join("experiments"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml") && !p.ends_with("manifest.yaml"))
        .map(|p| {
            let t = std::fs::read_to_string(&p).unwrap();
            (p, t)
        })
        .collect();
    v.sort();
    assert!(v.len() >= 3, "the experiments of experiments/");
    v
}

fn experiment(name: &str) -> Experiment {
    Experiment::load(&root().join("experiments").join(format!("{name}.yaml"))).unwrap()
}

/// The simulator's angle table of `name` over `duration_s` (the first seconds suffice).
fn simulated(name: &str, duration_s: f64) -> AngleTable {
    let exp = experiment(name);
    let mut cam = simulate::camera_of(&exp).unwrap();
    cam.duration_s = Some(duration_s);
    let rec = simulate::record(&exp, &cam).unwrap();
    let s = rec.series;
    AngleTable {
        rows: s
            .t
            .iter()
            .zip(&s.angle)
            .map(|(&t, &a)| AngleRow {
                t_s: t,
                angle_rad: Some(a),
                status: Status::Ok,
            })
            .collect(),
    }
}

/// The CSV the detector writes (with `status` and `quality` columns), some rows missing.
fn detector_csv(table: &AngleTable, rng: &mut Rng) -> String {
    let mut s = String::from("t_s,angle_rad,status,quality\n");
    for r in &table.rows {
        let st = *pick(
            rng,
            &["ok", "ok", "ok", "ok", "corrected", "manual", "missing"],
        );
        let a = if st == "missing" {
            String::new()
        } else {
            format!("{:.9}", r.angle_rad.unwrap())
        };
        s.push_str(&format!("{:.6},{a},{st},0.9\n", r.t_s));
    }
    s
}

// ---------------------------------------------------------------------------------------
// The targets.

#[test]
fn the_experiment_reader_survives_mutated_yaml() {
    let seeds = Arc::new(experiment_files());
    let n = iterations(5_000);
    let s = seeds.clone();
    let r = run(
        "yaml",
        n,
        move |seed| {
            let mut rng = Rng::new(seed);
            let (path, text) = pick(&mut rng, &s).clone();
            let (t, what) = mutated(&mut rng, &text, 4);
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            ((path, t), format!("{name}: {what}"))
        },
        |(path, text): (PathBuf, String)| Experiment::parse(&path, &text).map(drop),
    );
    check("yaml", &r);
}

#[test]
fn the_angle_csv_reader_survives_mutated_csv() {
    let mut rng = Rng::new(base_seed());
    let tables = [
        simulated("glass-fiber-fabric", 12.0),
        simulated("steel", 6.0),
    ];
    let texts: Arc<Vec<String>> = Arc::new(vec![
        rollfric::series::AngleSeries::new(
            tables[0].series().t.clone(),
            tables[0].series().angle.clone(),
        )
        .to_csv(),
        detector_csv(&tables[1], &mut rng),
    ]);
    let n = iterations(5_000);
    let r = run(
        "csv",
        n,
        move |seed| {
            let mut rng = Rng::new(seed);
            let text = pick(&mut rng, &texts).clone();
            mutated(&mut rng, &text, 4)
        },
        |text: String| AngleTable::parse_csv(&text).map(drop),
    );
    check("csv", &r);
}

/// One arbitrary finite series made from a simulated one: scaled, shifted, cut,
/// decimated, spiked, flattened, reversed or replaced by noise; times strictly increase
/// (what the CSV reader guarantees).
fn mutated_series(rng: &mut Rng, base: &AngleTable) -> (AngleTable, String) {
    let s = base.series();
    let (mut t, mut a) = (s.t, s.angle);
    let mut what = Vec::new();
    for _ in 0..1 + below(rng, 3) {
        match below(rng, 12) {
            0 => {
                let f = *pick(
                    rng,
                    &[
                        0.0,
                        1e-12,
                        1e-3,
                        -1.0,
                        10.0,
                        57.29577951308232,
                        1e3,
                        1e5,
                        1e6,
                        1e12,
                        1e300,
                    ],
                );
                a.iter_mut().for_each(|x| *x *= f);
                what.push(format!("angles x{f}"));
            }
            1 => {
                let c = *pick(rng, &[-1e6, -3.0, 0.5, 3.0, 1e9, 1e300]);
                a.iter_mut().for_each(|x| *x += c);
                what.push(format!("angles +{c}"));
            }
            2 => {
                let f = *pick(rng, &[1e-9, 1e-3, 0.1, 10.0, 1e6, 1e12]);
                t.iter_mut().for_each(|x| *x *= f);
                what.push(format!("times x{f}"));
            }
            3 => {
                let keep = below(rng, t.len() + 1);
                t.truncate(keep);
                a.truncate(keep);
                what.push(format!("first {keep} rows"));
            }
            4 if !t.is_empty() => {
                let from = below(rng, t.len());
                t.drain(..from);
                a.drain(..from);
                what.push(format!("from row {from}"));
            }
            5 => {
                let step = 1 + below(rng, 50);
                t = t.iter().step_by(step).copied().collect();
                a = a.iter().step_by(step).copied().collect();
                what.push(format!("every {step}th row"));
            }
            6 => {
                let k = below(rng, 20);
                for _ in 0..k {
                    let i = below(rng, a.len());
                    if i < a.len() {
                        a[i] = *pick(rng, &[1e6, -1e6, 1e300, 0.0, f64::MIN_POSITIVE]);
                    }
                }
                what.push(format!("{k} spikes"));
            }
            7 => {
                let c = *pick(rng, &[0.0, 1.0, -1e300]);
                a.iter_mut().for_each(|x| *x = c);
                what.push(format!("constant {c}"));
            }
            8 => {
                let sd = *pick(rng, &[1e-6, 1e-2, 1.0, 1e6]);
                a.iter_mut().for_each(|x| *x = rng.normal() * sd);
                what.push(format!("pure noise sd {sd}"));
            }
            9 => {
                a.reverse();
                what.push("angles reversed".into());
            }
            10 => {
                // Times with random gaps (still increasing).
                let mut acc = 0.0;
                for x in t.iter_mut() {
                    acc += *pick(rng, &[1e-9, 1e-3, 0.04, 1.0, 100.0]);
                    *x = acc;
                }
                what.push("random time gaps".into());
            }
            _ => {
                let sd = *pick(rng, &[1e-4, 1e-2, 0.3]);
                a.iter_mut().for_each(|x| *x += rng.normal() * sd);
                what.push(format!("noise sd {sd}"));
            }
        }
    }
    // Keep the reader's contract: finite values, strictly increasing times.
    let mut rows: Vec<AngleRow> = Vec::with_capacity(t.len());
    for (&ti, &ai) in t.iter().zip(&a) {
        if !ti.is_finite() || !ai.is_finite() || rows.last().is_some_and(|r| ti <= r.t_s) {
            continue;
        }
        rows.push(AngleRow {
            t_s: ti,
            angle_rad: Some(ai),
            status: Status::Ok,
        });
    }
    (AngleTable { rows }, what.join("; "))
}

#[test]
fn the_fit_survives_arbitrary_finite_series() {
    let cases: Arc<Vec<(Experiment, AngleTable)>> = Arc::new(vec![
        (
            experiment("glass-fiber-fabric"),
            simulated("glass-fiber-fabric", 16.0),
        ),
        (experiment("steel"), simulated("steel", 10.0)),
    ]);
    let c = cases.clone();
    let n = iterations(2_000);
    let r = run(
        "fit",
        n,
        move |seed| {
            let mut rng = Rng::new(seed);
            let k = below(&mut rng, c.len());
            let (table, what) = mutated_series(&mut rng, &c[k].1);
            let what = format!("{}: {} rows; {what}", c[k].0.name, table.rows.len());
            ((k, table), what)
        },
        move |(k, table): (usize, AngleTable)| {
            let exp = &cases[k].0;
            let angles = Angles {
                source: Source::Csv(Path::new("fuzz.csv").to_path_buf()),
                table,
                detection: None,
            };
            pipeline::analyze(exp, &angles, Overrides::default()).map(drop)
        },
    );
    check("fit", &r);
}

/// The two faults the fit's fuzzing found, as fixed cases: times in a wrong unit (the
/// model would be integrated over 1e12 s; it hung) and a table with no angle (it
/// panicked on the median of nothing).
#[test]
fn the_fit_refuses_what_it_cannot_model_in_our_words() {
    let exp = experiment("steel");
    let mut table = simulated("steel", 10.0);
    table.rows.iter_mut().for_each(|r| r.t_s *= 1e12);
    let fit = |table: AngleTable| {
        let angles = Angles {
            source: Source::Csv(Path::new("a.csv").to_path_buf()),
            table,
            detection: None,
        };
        let start = Instant::now();
        let e = pipeline::analyze(&exp, &angles, Overrides::default())
            .map(drop)
            .unwrap_err();
        assert!(start.elapsed() < CALL_BUDGET, "{:?}", start.elapsed());
        format!("{e:#}")
    };
    let e = fit(table);
    assert!(e.contains("periods of the pendulum"), "{e}");
    assert!(e.contains("a.csv"), "{e}");
    let e = fit(AngleTable::default());
    assert!(e.contains("no angles to fit"), "{e}");
}

/// A huge quoted value in an angle CSV is cut to an excerpt on one line.
#[test]
fn the_csv_reader_quotes_briefly() {
    let long = "9".repeat(100_000);
    for text in [
        format!("{long},angle_rad\n0,1\n"),
        format!("t_s,angle_rad\n0,x{long}\n"),
        "t_s,angle_rad,status\n0,1,\"a\nb\"\n".to_string(),
    ] {
        let e = format!("{:#}", AngleTable::parse_csv(&text).unwrap_err());
        assert!(e.len() < 300 && !e.contains('\n'), "{e}");
    }
}

/// A huge value of a key the reader quotes (found by a long run) is cut to an excerpt.
#[test]
fn the_experiment_reader_quotes_briefly() {
    let long = ",".repeat(1_000_000);
    let base = std::fs::read_to_string(root().join("experiments/glass.yaml")).unwrap();
    for (from, to) in [
        ("name: glass", format!("name: glass {long}")),
        ("beta: 1", format!("beta: x{long}")),
        ("name: glass", "name: \"a\\nb\"".to_string()),
    ] {
        let text = base.replace(from, &to);
        let e = format!(
            "{:#}",
            Experiment::parse(Path::new("g.yaml"), &text).unwrap_err()
        );
        assert!(e.len() < 400 && !e.contains('\n'), "{e}");
    }
}
