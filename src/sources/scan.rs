//! Which source files each top-level module depends on, read off the code itself.
//!
//! A top-level module is `src/<m>.rs` or the folder `src/<m>/`. Its files depend on the
//! modules they name as `crate::<m>` (also inside `use crate::{a, b::c}`), and on the
//! files they embed with `include_str!` / `include_bytes!` (the templates); unit tests
//! (after a file's `#[cfg(test)]`, or a `tests.rs` file) name no dependency. A module's closure is itself
//! plus, transitively, every module it names; its hash covers every file of the
//! closure (path and bytes, in path order) and `Cargo.lock` (dependency versions). The
//! build script hashes each module this way, so a stage's cache key covers every
//! source file that can change its output and no list is kept by hand.
//!
//! This file is compiled twice: by `build.rs` (with `#[path]`) and as
//! `rollfric::sources::scan`, so that tests can run it on an edited copy of the tree.

use sha2::{Digest, Sha256};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The files of one top-level module and the modules and files they reference.
#[derive(Debug, Default)]
pub struct Module {
    /// Its own `.rs` files.
    pub files: BTreeSet<PathBuf>,
    /// Top-level modules named as `crate::<m>`.
    pub uses: BTreeSet<String>,
    /// Files embedded with `include_str!` / `include_bytes!`.
    pub embeds: BTreeSet<PathBuf>,
}

/// Every top-level module under `src`, by name (`lib.rs` and `main.rs` are not modules).
pub fn modules(src: &Path) -> std::io::Result<BTreeMap<String, Module>> {
    let mut out = BTreeMap::new();
    for e in std::fs::read_dir(src)? {
        let p = e?.path();
        let Some(stem) = p.file_stem().and_then(|s| s.to_str()).map(str::to_string) else {
            continue;
        };
        let mut files = BTreeSet::new();
        if p.is_dir() {
            rs_files(&p, &mut files)?;
        } else if p.extension().is_some_and(|x| x == "rs") && stem != "lib" && stem != "main" {
            files.insert(p.clone());
        } else {
            continue;
        }
        let m: &mut Module = out.entry(stem).or_default();
        m.files.extend(files);
    }
    for m in out.values_mut() {
        for f in m.files.clone() {
            let text = std::fs::read_to_string(&f)?;
            // The unit tests (this code base keeps them last, after `#[cfg(test)]`, or
            // in a `tests.rs` of their own, declared `#[cfg(test)] mod tests;`, and its
            // `tests/` folder) change no output: what they name is not a dependency.
            let in_tests = f
                .strip_prefix(src)
                .is_ok_and(|r| r.components().any(|c| c.as_os_str() == "tests"));
            let text = if in_tests || f.file_name().is_some_and(|n| n == "tests.rs") {
                ""
            } else {
                text.split("\n#[cfg(test)]").next().unwrap_or("")
            };
            let code = strip_comments(text);
            m.uses.extend(crate_paths(&code));
            for rel in embeds(&code) {
                let dir = f.parent().unwrap_or(Path::new("."));
                m.embeds.insert(normalize(&dir.join(rel)));
            }
        }
    }
    Ok(out)
}

fn rs_files(dir: &Path, out: &mut BTreeSet<PathBuf>) -> std::io::Result<()> {
    for e in std::fs::read_dir(dir)? {
        let p = e?.path();
        if p.is_dir() {
            rs_files(&p, out)?;
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.insert(p);
        }
    }
    Ok(())
}

/// `a/b/../c` -> `a/c`, `a/./b` -> `a/b`, without looking at the file system.
pub fn normalize(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

/// The code without `//` comments (doc comments name modules in prose and links).
fn strip_comments(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            // A `//` inside a string literal (a URL) is rare in this code; cutting the
            // line there can only drop references, and the test below would catch a
            // dropped module.
            Some(i) if !l[..i].contains('"') => &l[..i],
            _ => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn ident_at(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The top-level modules named after `crate::`, including the grouped form.
fn crate_paths(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = code[i + 7..].trim_start();
        if let Some(group) = rest.strip_prefix('{') {
            // `crate::{a, b::{c, d}, e}`: the first identifier of each top-level item.
            let mut depth = 0;
            let mut item_start = true;
            for (j, ch) in group.char_indices() {
                match ch {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => item_start = true,
                    c if item_start && !c.is_whitespace() => {
                        let id = ident_at(&group[j..]);
                        if !id.is_empty() {
                            out.insert(id.to_string());
                        }
                        item_start = false;
                    }
                    _ => {}
                }
            }
        } else {
            let id = ident_at(rest);
            if !id.is_empty() {
                out.insert(id.to_string());
            }
        }
    }
    out
}

/// The paths given to `include_str!` / `include_bytes!`.
fn embeds(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    // Spelled in two pieces, so that this file does not embed its own pattern.
    for mac in [concat!("include_str", "!("), concat!("include_bytes", "!(")] {
        for (i, _) in code.match_indices(mac) {
            let rest = code[i + mac.len()..].trim_start();
            if let Some(r) = rest.strip_prefix('"') {
                if let Some(end) = r.find('"') {
                    out.push(r[..end].to_string());
                }
            }
        }
    }
    out
}

/// The modules `root` depends on, itself included (names that are not modules of
/// `src`, such as `crate::fit` spelled in a macro, are ignored).
pub fn closure(mods: &BTreeMap<String, Module>, root: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut todo = vec![root.to_string()];
    while let Some(m) = todo.pop() {
        if !mods.contains_key(&m) || !seen.insert(m.clone()) {
            continue;
        }
        todo.extend(mods[&m].uses.iter().cloned());
    }
    seen
}

/// The files of `root`'s closure: its modules' source and embedded files.
pub fn closure_files(mods: &BTreeMap<String, Module>, root: &str) -> BTreeSet<PathBuf> {
    let mut files = BTreeSet::new();
    for m in closure(mods, root) {
        files.extend(mods[&m].files.iter().cloned());
        files.extend(mods[&m].embeds.iter().cloned());
    }
    files
}

/// SHA-256 (hex) of `root`'s closure under the crate folder `dir`: each file's path
/// relative to `dir` and its bytes, then `Cargo.lock`.
pub fn closure_hash(
    dir: &Path,
    mods: &BTreeMap<String, Module>,
    root: &str,
) -> std::io::Result<String> {
    let mut h = Sha256::new();
    let mut files: Vec<PathBuf> = closure_files(mods, root).into_iter().collect();
    files.push(dir.join("Cargo.lock"));
    for f in files {
        let rel = f
            .strip_prefix(dir)
            .unwrap_or(&f)
            .to_string_lossy()
            .replace('\\', "/");
        let bytes = std::fs::read(&f)
            .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", f.display())))?;
        h.update(rel.as_bytes());
        h.update([0]);
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(&bytes);
    }
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

/// Rust source of the table the build script writes: every module's closure hash.
pub fn table(dir: &Path) -> std::io::Result<String> {
    let mods = modules(&dir.join("src"))?;
    let mut o = String::from(
        "/// Closure hash of every top-level module (generated by build.rs).\n\
         pub const MODULE_HASHES: &[(&str, &str)] = &[\n",
    );
    for name in mods.keys() {
        o.push_str(&format!(
            "    ({name:?}, {:?}),\n",
            closure_hash(dir, &mods, name)?
        ));
    }
    o.push_str("];\n");
    Ok(o)
}
