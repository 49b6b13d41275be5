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

    /// Remove the files an earlier build wrote that this one did not (`current`, paths
    /// under the folder): the pages of an experiment dropped from the manifest, the
    /// review pictures of a video since replaced. Only files listed in the folder's
    /// record of what rollfric wrote ([`WRITTEN`]) are removed, with the folders they
    /// leave empty; the record is then replaced by `current`. Returns how many went.
    pub fn prune(&self, current: &[&str]) -> Result<usize> {
        let record = self.out.join(WRITTEN);
        let before = std::fs::read_to_string(&record).unwrap_or_default();
        let keep: std::collections::HashSet<&str> = current.iter().copied().collect();
        let mut removed = 0;
        for old in before.lines().filter(|l| !keep.contains(l)) {
            // Only plain relative paths, as this writer records them.
            let rel = Path::new(old);
            if old.is_empty()
                || rel.is_absolute()
                || rel
                    .components()
                    .any(|c| !matches!(c, std::path::Component::Normal(_)))
            {
                continue;
            }
            let path = self.out.join(rel);
            // Never through a link: a folder of the record turned into a link since
            // leads out of the reports folder.
            let linked = rel.ancestors().skip(1).any(|a| {
                !a.as_os_str().is_empty()
                    && std::fs::symlink_metadata(self.out.join(a))
                        .is_ok_and(|m| m.file_type().is_symlink())
            });
            if !linked && std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
                std::fs::remove_file(&path)
                    .map_err(anyhow::Error::new)
                    .map_err(|e| e.context(format!("{}: cannot remove", path.display())))?;
                removed += 1;
                let mut dir = path.parent();
                while let Some(d) = dir.filter(|d| *d != self.out) {
                    if std::fs::remove_dir(d).is_err() {
                        break;
                    }
                    dir = d.parent();
                }
            }
        }
        let mut list: Vec<&str> = current.to_vec();
        list.sort_unstable();
        list.dedup();
        fsutil::write_if_changed(&record, (list.join("\n") + "\n").as_bytes())?;
        Ok(removed)
    }
}

/// The file in the reports folder listing every file the last build wrote there (one
/// path a line), so that the next build can remove what it no longer writes.
pub const WRITTEN: &str = ".rollfric-written";

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
        // `.` (a manifest in the working folder) is no prefix to take off: every `../`
        // holds a `./`, and `../../etc` would read `....etc`.
        if !p.is_empty() && p != "." {
            out = out.replace(&format!("{p}/"), "");
        }
    }
    out
}

/// `a` relative to `base` with `..` steps, when they share a first component.
pub(crate) fn pathdiff(base: &Path, a: &Path) -> Option<String> {
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
        assert_eq!(
            unrooted(Path::new("."), "../../etc/passwd: not an experiment file"),
            "../../etc/passwd: not an experiment file"
        );
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

    #[test]
    fn a_build_removes_only_what_it_wrote_before_and_writes_no_more() {
        let top = tempfile::tempdir().unwrap();
        let d = top.path().join("reports");
        std::fs::create_dir(&d).unwrap();
        let d = tempfile::TempDir::new_in(&d).unwrap();
        let w = Writer::new(d.path());
        let files = [
            OutputFile::new("old.html", "o"),
            OutputFile::new("old/review/frame-000001.png", "p"),
            OutputFile::new("keep.html", "k"),
        ];
        w.write(&files).unwrap();
        std::fs::write(d.path().join("mine.txt"), "the user's").unwrap();
        // The first build with a record removes nothing it did not record.
        assert_eq!(
            w.prune(&["old.html", "old/review/frame-000001.png", "keep.html"])
                .unwrap(),
            0
        );
        assert_eq!(w.prune(&["keep.html"]).unwrap(), 2);
        assert!(!d.path().join("old.html").exists());
        assert!(!d.path().join("old").exists(), "emptied folders go too");
        assert!(d.path().join("keep.html").exists());
        assert!(d.path().join("mine.txt").exists());
        // A record naming a path outside the folder is not followed.
        let outside = d.path().parent().unwrap().join("outside.txt");
        std::fs::write(&outside, "x").unwrap();
        std::fs::write(d.path().join(WRITTEN), "../outside.txt\n").unwrap();
        assert_eq!(w.prune(&["keep.html"]).unwrap(), 0);
        assert!(outside.exists());
    }
}
