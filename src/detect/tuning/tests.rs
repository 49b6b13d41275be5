//! The table's own checks, and that no knob is declared outside the tuning module.

use super::*;
use std::path::Path;

#[test]
fn names_are_unique() {
    let mut names: Vec<&str> = KNOBS.iter().map(|k| k.name).collect();
    names.sort_unstable();
    let before = names.len();
    names.dedup();
    assert_eq!(names.len(), before, "a knob's name appears twice in KNOBS");
}

#[test]
fn every_knob_says_its_unit_stage_and_why() {
    assert!(KNOBS.len() > 100, "{} knobs", KNOBS.len());
    for k in KNOBS {
        assert!(!k.name.is_empty(), "{k:?}");
        for (field, s) in [
            ("unit", k.unit),
            ("stage", k.stage),
            ("what", k.what),
            ("chosen_by", k.chosen_by),
        ] {
            assert!(!s.trim().is_empty(), "{}: empty {field}", k.name);
            assert!(!s.contains('\n'), "{}: {field} spans lines", k.name);
        }
        assert!(k.value.is_finite(), "{}", k.name);
    }
}

/// The table holds each const's own value.
#[test]
fn values_are_the_constants() {
    let get = |n: &str| KNOBS.iter().find(|k| k.name == n).unwrap().value;
    assert_eq!(get("FREE_STRIP_HALF"), FREE_STRIP_HALF);
    assert_eq!(get("PAIR_MIN_VOTES"), PAIR_MIN_VOTES as f64);
    assert_eq!(get("COVERED_FULL"), (CELLS / 2) as f64);
    assert_eq!(get("MAX_FRAME_PIXELS"), 8192.0 * 8192.0);
}

/// Constants of `src/detect` that are no tuning choice, and so stay beside their code.
const NOT_KNOBS: &[(&str, &str)] = &[
    // Fixed by the 7x7 structuring element OpenCV's top-hat uses.
    ("morph.rs", "PAD"),
    ("track/evidence.rs", "TOPHAT_REACH"),
    // Memory-order runs and scan blocks: the same pixels at any size.
    ("geometry.rs", "RUN"),
    ("track/measure/strip.rs", "SCAN_BLOCK"),
    // Rounding guards, and a pixel's half width.
    ("track/measure/strip.rs", "WEDGE_TEST_SLACK"),
    ("steady/sweep.rs", "SURE_SLACK"),
    ("track/measure/strip.rs", "STRIP_EDGE"),
    // sqrt(70): a fourth difference's noise gain.
    ("judge/swing.rs", "D4_GAIN"),
    // A label: the faint look's stage number.
    ("geometry/faint.rs", "FAINT_STAGE"),
    // How large `detect --steps` draws its pictures: no measurement reads it.
    ("track/diag.rs", "STEPS_MIN_WIDTH"),
    // A block's width as a type's parameter: the shrink factor, whatever it is.
    ("shrink.rs", "K"),
];

/// The numeric constants declared in a source file (before its inline tests).
fn numeric_consts(text: &str) -> Vec<String> {
    const TYPES: [&str; 12] = [
        "f32", "f64", "usize", "isize", "u8", "u16", "u32", "u64", "i8", "i16", "i32", "i64",
    ];
    let code = text.split("#[cfg(test)]").next().unwrap_or("");
    let mut found = Vec::new();
    for line in code.lines() {
        let line = line.trim_start();
        if line.starts_with("//") {
            continue;
        }
        let Some(at) = line.find("const ") else {
            continue;
        };
        let rest = &line[at + "const ".len()..];
        let Some((name, ty)) = rest.split_once(':') else {
            continue;
        };
        let ty = ty.trim_start();
        let is_num = TYPES.iter().any(|t| {
            ty.starts_with(t) && !ty[t.len()..].starts_with(|c: char| c.is_alphanumeric())
        });
        if is_num
            && name
                .chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
        {
            found.push(name.to_string());
        }
    }
    found
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// A numeric constant declared in `src/detect` outside this module is a knob in the
/// wrong place, unless [`NOT_KNOBS`] names it: new knobs land here, with their figure.
#[test]
fn no_knob_outside_tuning() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/detect");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    let mut stray = Vec::new();
    let mut allowed_seen = Vec::new();
    for p in files {
        let rel = p
            .strip_prefix(&root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let file = rel.rsplit('/').next().unwrap();
        if rel == "tuning.rs"
            || rel.starts_with("tuning/")
            || file == "tests.rs"
            || file == "test_support.rs"
        {
            continue;
        }
        for name in numeric_consts(&std::fs::read_to_string(&p).unwrap()) {
            if NOT_KNOBS.contains(&(rel.as_str(), name.as_str())) {
                allowed_seen.push((rel.clone(), name));
            } else {
                stray.push(format!("src/detect/{rel}: {name}"));
            }
        }
    }
    assert!(
        stray.is_empty(),
        "numeric constants outside src/detect/tuning (declare them with knobs!, or list \
         them in NOT_KNOBS with the reason they are no choice): {stray:?}"
    );
    assert_eq!(
        allowed_seen.len(),
        NOT_KNOBS.len(),
        "NOT_KNOBS names a constant that is gone: {allowed_seen:?}"
    );
}

/// The scan sees a declaration, typed or visible in any way.
#[test]
fn the_scan_finds_a_declaration() {
    let text = "/// doc\npub(super) const LIMIT: f64 = 1.0;\n    const N: usize = 3;\nconst S: &str = \"\";\n#[cfg(test)]\nconst T: f64 = 0.0;\n";
    assert_eq!(numeric_consts(text), ["LIMIT", "N"]);
}
