//! Golden reports (as mdBook keeps `expected/` trees for its test books): each case under
//! `tests/golden/` is built and its whole reports tree compared with `expected/`, byte
//! for byte after redaction. A differing, missing or stale expected file fails; set
//! `ROLLFRIC_BLESS=1` to regenerate `expected/` after an intended change.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn cases() -> PathBuf {
    common::root().join("tests/golden")
}

/// Every file under `dir`, by path relative to it (`/`-separated).
fn tree(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(base: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(base, &p, out);
            } else {
                let rel = p
                    .strip_prefix(base)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// What varies with the tool's version, replaced by a fixed token.
fn redact(bytes: &[u8]) -> Vec<u8> {
    let version = concat!("rollfric ", env!("CARGO_PKG_VERSION"));
    match std::str::from_utf8(bytes) {
        Ok(text) => text.replace(version, "rollfric [VERSION]").into_bytes(),
        Err(_) => bytes.to_vec(),
    }
}

/// The differences between a generated tree and the expected one, one line each.
fn differences(
    got: &BTreeMap<String, Vec<u8>>,
    expected: &BTreeMap<String, Vec<u8>>,
) -> Vec<String> {
    let mut out = Vec::new();
    for (path, bytes) in got {
        match expected.get(path) {
            None => out.push(format!("{path}: generated but not expected (new file)")),
            Some(e) if e != bytes => {
                let at = e
                    .iter()
                    .zip(bytes)
                    .position(|(a, b)| a != b)
                    .unwrap_or(e.len().min(bytes.len()));
                out.push(format!("{path}: differs from expected at byte {at}"));
            }
            Some(_) => {}
        }
    }
    for path in expected.keys().filter(|p| !got.contains_key(*p)) {
        out.push(format!(
            "{path}: expected but not generated (stale expected file)"
        ));
    }
    out
}

/// Build case `name` into a temporary folder; its redacted reports tree.
fn build(name: &str) -> BTreeMap<String, Vec<u8>> {
    let case = cases().join(name);
    let tmp = tempfile::tempdir().unwrap();
    let out = common::rollfric(
        &[
            "build".as_ref(),
            "-q".as_ref(),
            "-j".as_ref(),
            "1".as_ref(),
            "--manifest".as_ref(),
            case.join("experiments/manifest.yaml").as_os_str(),
            "--out".as_ref(),
            tmp.path().join("reports").as_os_str(),
            "--cache".as_ref(),
            tmp.path().join("cache").as_os_str(),
        ],
        tmp.path(),
    );
    // The case includes a failing experiment, so the build exits 1; it must still write
    // every report.
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        tmp.path().join("reports/summary.json").exists(),
        "no summary: {stderr}"
    );
    tree(&tmp.path().join("reports"))
        .into_iter()
        .map(|(p, b)| (p, redact(&b)))
        .collect()
}

fn check_case(name: &str) {
    let got = build(name);
    let expected_dir = cases().join(name).join("expected");
    if std::env::var_os("ROLLFRIC_BLESS").is_some_and(|v| !v.is_empty() && v != "0") {
        let _ = std::fs::remove_dir_all(&expected_dir);
        for (path, bytes) in &got {
            let p = expected_dir.join(path);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, bytes).unwrap();
        }
        eprintln!(
            "blessed {} files into {}",
            got.len(),
            expected_dir.display()
        );
        return;
    }
    let diff = differences(&got, &tree(&expected_dir));
    assert!(
        diff.is_empty(),
        "case `{name}`: the reports differ from tests/golden/{name}/expected \
         (ROLLFRIC_BLESS=1 regenerates it after an intended change):\n  {}",
        diff.join("\n  ")
    );
}

#[test]
fn csv_set_reports_match_the_expected_tree() {
    check_case("csv-set");
}

#[test]
fn the_comparison_fails_on_one_changed_byte_a_missing_and_a_stale_file() {
    let expected = tree(&cases().join("csv-set/expected"));
    assert!(expected.len() > 10, "the expected tree is there");
    assert!(differences(&expected, &expected).is_empty());
    let (path, bytes) = expected.iter().find(|(p, _)| p.ends_with(".html")).unwrap();
    let mut changed = expected.clone();
    let mut b = bytes.clone();
    let mid = b.len() / 2;
    b[mid] ^= 1;
    changed.insert(path.clone(), b);
    let d = differences(&changed, &expected);
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("differs from expected"), "{d:?}");
    let mut missing = expected.clone();
    missing.remove(path);
    assert!(differences(&missing, &expected)[0].contains("stale expected file"));
    let mut extra = expected.clone();
    extra.insert("new.svg".into(), b"x".to_vec());
    assert!(differences(&extra, &expected)[0].contains("new file"));
}

#[test]
fn redaction_replaces_only_the_version() {
    let v = concat!("rollfric ", env!("CARGO_PKG_VERSION"));
    assert_eq!(
        redact(format!("made by {v}; rollfric check").as_bytes()),
        b"made by rollfric [VERSION]; rollfric check"
    );
}
