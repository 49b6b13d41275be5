//! The one writer of the reports folder: every report file goes through here, written
//! atomically and only when its bytes changed (an unchanged file keeps its time).

use crate::fsutil;
use crate::hash;
use crate::pipeline::{ExperimentResult, PageFile};
use crate::report::OutputFile;
use anyhow::Result;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Writes report files under one folder and counts those it rewrote.
pub struct Writer {
    out: PathBuf,
    written: AtomicUsize,
}

impl Writer {
    pub fn new(out: &Path) -> Self {
        Self {
            out: out.to_path_buf(),
            written: AtomicUsize::new(0),
        }
    }

    /// Write `files`; returns each one's path and hash, for the cache's record.
    pub fn write(&self, files: &[OutputFile]) -> Result<Vec<PageFile>> {
        let mut pages = Vec::with_capacity(files.len());
        for f in files {
            if fsutil::write_if_changed(&self.out.join(&f.path), &f.bytes)? {
                self.written.fetch_add(1, Ordering::Relaxed);
            }
            pages.push(PageFile {
                path: f.path.clone(),
                sha256: hash::sha256(&f.bytes),
            });
        }
        Ok(pages)
    }

    /// Whether every page file of a cached result is there with its recorded bytes.
    pub fn intact(&self, r: &ExperimentResult) -> bool {
        !r.pages.is_empty()
            && r.pages.iter().all(|f| {
                std::fs::read(self.out.join(&f.path)).is_ok_and(|b| hash::sha256(&b) == f.sha256)
            })
    }

    /// Report files rewritten so far.
    pub fn written(&self) -> usize {
        self.written.load(Ordering::Relaxed)
    }
}

/// Remove the temporary files that builds killed before renaming them left behind
/// ([`fsutil::temp_path`]: `.rollfric-<pid>-...tmp`, of a process no longer running),
/// `depth` folders deep. Nothing else is touched.
pub fn remove_stale_temporaries(dir: &Path, depth: usize) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if p.is_dir() {
            if depth > 1 {
                remove_stale_temporaries(&p, depth - 1);
            }
        } else if let Some(pid) = fsutil::temp_owner(&name) {
            if pid != std::process::id() && !fsutil::process_alive(pid) {
                let _ = std::fs::remove_file(&p);
            }
        }
    }
}

/// A path as the reports show it: relative to the manifest's folder when inside it,
/// else its file name (no absolute paths in the reports).
pub fn relative(root: &Path, p: &Path) -> String {
    // As spelled first (a video reached through a link keeps the link's name), then
    // with links resolved (the manifest's folder itself may be spelled through one).
    let lexical = |q: &Path| std::path::absolute(q).map(|a| crate::sources::scan::normalize(&a));
    if let (Ok(r), Ok(a)) = (lexical(root), lexical(p)) {
        if let Ok(rel) = a.strip_prefix(&r) {
            return rel.display().to_string();
        }
    }
    let abs = |q: &Path| std::fs::canonicalize(q).unwrap_or_else(|_| q.to_path_buf());
    let (r, a) = (abs(root), abs(p));
    match a.strip_prefix(&r) {
        Ok(rel) => rel.display().to_string(),
        Err(_) => pathdiff(&r, &a).unwrap_or_else(|| {
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        }),
    }
}

/// `text` (an error message) with the manifest folder `root` taken off the paths it
/// names, as given and as an absolute path: the reports name files relative to it.
pub fn unrooted(root: &Path, text: &str) -> String {
    let mut out = text.to_string();
    let mut prefixes = vec![root.to_path_buf()];
    if let Ok(abs) = std::fs::canonicalize(root) {
        prefixes.push(abs);
    }
    for p in prefixes {
        let p = p.display().to_string();
        if !p.is_empty() {
            out = out.replace(&format!("{p}/"), "");
        }
    }
    out
}

/// `a` relative to `base` with `..` steps, when they share a first component.
fn pathdiff(base: &Path, a: &Path) -> Option<String> {
    let b: Vec<_> = base.components().collect();
    let t: Vec<_> = a.components().collect();
    let common = b.iter().zip(&t).take_while(|(x, y)| x == y).count();
    if common <= 1 {
        return None;
    }
    let mut s: Vec<String> = vec!["..".into(); b.len() - common];
    s.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    Some(s.join("/"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_paths_are_relative_to_the_manifest() {
        let d = tempfile::tempdir().unwrap();
        let root = d.path().join("experiments");
        std::fs::create_dir_all(root.join("videos")).unwrap();
        std::fs::write(root.join("videos/a.mp4"), b"x").unwrap();
        assert_eq!(relative(&root, &root.join("videos/a.mp4")), "videos/a.mp4");
        std::fs::create_dir_all(d.path().join("other")).unwrap();
        std::fs::write(d.path().join("other/b.mp4"), b"x").unwrap();
        assert_eq!(
            relative(&root, &d.path().join("other/b.mp4")),
            "../other/b.mp4"
        );
    }

    #[test]
    fn error_messages_name_files_relative_to_the_manifest() {
        let d = tempfile::tempdir().unwrap();
        let root = d.path().join("exp");
        std::fs::create_dir_all(&root).unwrap();
        let abs = std::fs::canonicalize(&root).unwrap();
        let msg = format!(
            "{}/a.csv: line 4; {}/b.yaml: bad",
            root.display(),
            abs.display()
        );
        assert_eq!(unrooted(&root, &msg), "a.csv: line 4; b.yaml: bad");
        assert_eq!(unrooted(Path::new(""), "x/a.csv"), "x/a.csv");
    }

    #[test]
    fn a_linked_video_keeps_the_name_it_was_given() {
        let d = tempfile::tempdir().unwrap();
        let root = d.path().join("experiments");
        std::fs::create_dir_all(root.join("videos")).unwrap();
        std::fs::create_dir_all(d.path().join("store")).unwrap();
        std::fs::write(d.path().join("store/real.mp4"), b"x").unwrap();
        std::os::unix::fs::symlink(
            d.path().join("store/real.mp4"),
            root.join("videos/link.mp4"),
        )
        .unwrap();
        assert_eq!(
            relative(&root, &root.join("videos/link.mp4")),
            "videos/link.mp4"
        );
        assert_eq!(
            relative(&root.join("."), &root.join("./videos/../videos/link.mp4")),
            "videos/link.mp4"
        );
    }

    #[test]
    fn rewrites_only_changed_files() {
        let d = tempfile::tempdir().unwrap();
        let w = Writer::new(d.path());
        let f = OutputFile::new("a/b.txt", "x");
        let pages = w.write(std::slice::from_ref(&f)).unwrap();
        assert_eq!(w.written(), 1);
        w.write(std::slice::from_ref(&f)).unwrap();
        assert_eq!(w.written(), 1, "same bytes: not rewritten");
        assert_eq!(pages[0].sha256, hash::sha256(b"x"));
    }
}
