//! Every file read and write goes through here, so that each error names its path and
//! every write is atomic (a temporary file in the same folder, then a rename).

use anyhow::{Context, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Read a whole text file; the error names the file.
pub fn read_to_string(path: &Path) -> Result<String> {
    regular_file(path)?;
    std::fs::read_to_string(path).with_context(|| format!("{}: cannot read", path.display()))
}

/// Refuse what is not a regular file, in words: a folder, a FIFO or a device (which
/// may never end, as `/dev/zero`), or nothing at all. Returns the file's size.
pub fn regular_file(path: &Path) -> Result<u64> {
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            anyhow::bail!("{}: no such file", path.display())
        }
        Err(e) => return Err(e).with_context(|| format!("{}: cannot read", path.display())),
    };
    if meta.is_dir() {
        anyhow::bail!("{}: is a folder, not a file", path.display());
    }
    if !meta.is_file() {
        anyhow::bail!(
            "{}: is not a regular file (a FIFO, socket or device); give a file",
            path.display()
        );
    }
    Ok(meta.len())
}

/// The largest experiment or manifest file read, bytes.
pub const MAX_YAML_BYTES: u64 = 16 << 20;
/// The largest angle CSV read, bytes (about 8 million frames: 90 hours at 25 frames/s).
pub const MAX_CSV_BYTES: u64 = 256 << 20;

/// Read a whole file of at most `max` bytes (checked before it is read, so a huge input
/// is refused instead of exhausting memory); the error names the file and the limit.
pub fn read_limited(path: &Path, max: u64) -> Result<Vec<u8>> {
    let len = regular_file(path)?;
    if len > max {
        anyhow::bail!(
            "{}: {len} bytes; at most {max} bytes are read from such a file",
            path.display()
        );
    }
    std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))
}

/// [`read_limited`] as UTF-8 text.
pub fn read_text_limited(path: &Path, max: u64) -> Result<String> {
    String::from_utf8(read_limited(path, max)?).map_err(|e| {
        anyhow::anyhow!(
            "{}: not UTF-8 text (invalid byte at offset {})",
            path.display(),
            e.utf8_error().valid_up_to()
        )
    })
}

/// Whether `path` (followed through symbolic links) is something other than a regular
/// file or a folder: a device such as `/dev/null`, a FIFO, a socket, or a link to one
/// (`/dev/stdout`). Output to it is written through: renaming a temporary file onto it
/// would replace the device node itself (as root, `/dev/null` for the whole machine).
pub fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Write `bytes` to `path` atomically: readers see the old file or the new one, never a
/// torn one. Creates the parent folder when missing. A device or FIFO ([`is_special`])
/// is written through instead.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    if is_special(path) {
        return std::fs::write(path, bytes)
            .with_context(|| format!("{}: cannot write", path.display()));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create folder", dir.display()))?;
    if path.file_name().is_none() {
        anyhow::bail!("{}: not a file path", path.display());
    }
    let tmp = temp_path(path, false);
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    };
    write()
        .map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            anyhow::Error::new(e)
        })
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// The temporary name `path` is written through before it is renamed into place:
/// `.rollfric-<pid>-<name>.tmp` in the same folder (with `keep_ext`,
/// `.rollfric-<pid>-<stem>.tmp.<ext>`, for writers that choose a format by extension).
/// Only rollfric makes such names, so a clean-up can never take a user's file.
pub fn temp_path(path: &Path, keep_ext: bool) -> PathBuf {
    let dir = path.parent().unwrap_or(Path::new(""));
    let pid = std::process::id();
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    match (keep_ext, path.extension()) {
        (true, Some(ext)) => {
            let stem = path.file_stem().unwrap_or_default().to_string_lossy();
            dir.join(format!(
                ".rollfric-{pid}-{stem}.tmp.{}",
                ext.to_string_lossy()
            ))
        }
        _ => dir.join(format!(".rollfric-{pid}-{name}.tmp")),
    }
}

/// The process that made temporary file `name` (see [`temp_path`]), if it is one.
pub fn temp_owner(name: &str) -> Option<u32> {
    let rest = name.strip_prefix(".rollfric-")?;
    let (pid, rest) = rest.split_once('-')?;
    if !(rest.ends_with(".tmp") || rest.contains(".tmp.")) {
        return None;
    }
    pid.parse().ok()
}

/// Whether process `pid` is running (Linux `/proc`; elsewhere, assumed running). A
/// process that has ended but not been reaped (a zombie, state `Z`, or `X`) is not: a
/// job killed with its whole process group is reparented to an init that may be slow to
/// reap it, or never does, and its temporary files would be kept for ever.
pub fn process_alive(pid: u32) -> bool {
    if !Path::new("/proc/self").exists() {
        return true;
    }
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
        return false;
    };
    // `pid (comm) state ...`: the command may hold spaces and parentheses itself.
    let state = stat
        .rsplit_once(')')
        .and_then(|(_, rest)| rest.trim_start().chars().next());
    !matches!(state, Some('Z' | 'X'))
}

/// Write `bytes` atomically unless the file already holds exactly them (an unchanged
/// output keeps its bytes and its modification time). Returns whether it wrote.
pub fn write_if_changed(path: &Path, bytes: &[u8]) -> Result<bool> {
    if std::fs::read(path).is_ok_and(|old| old == bytes) {
        return Ok(false);
    }
    write_atomic(path, bytes)?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ended_process_not_yet_reaped_is_not_running() {
        assert!(process_alive(std::process::id()));
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        // Not waited for: once it has ended it stays a zombie until reaped.
        let stat = format!("/proc/{pid}/stat");
        let ended = (0..200).any(|_| {
            std::thread::sleep(std::time::Duration::from_millis(10));
            std::fs::read_to_string(&stat).is_ok_and(|s| s.contains(") Z"))
        });
        assert!(ended, "`true` did not end within 2 s");
        assert!(!process_alive(pid), "a zombie taken for a running process");
        child.wait().unwrap();
        assert!(!process_alive(pid));
    }

    #[test]
    fn a_fifo_is_written_through_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("out.csv");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read(&fifo).unwrap())
        };
        write_atomic(&fifo, b"t_s,angle_rad\n").unwrap();
        // Still the FIFO (a rename would have put a regular file in its place, and the
        // reader would wait for ever: the test then hangs instead of passing).
        let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
        assert!(kind.is_fifo(), "{kind:?}");
        assert_eq!(reader.join().unwrap(), b"t_s,angle_rad\n");
        assert!(is_special(&fifo) && !is_special(dir.path()));
        assert!(!is_special(&dir.path().join("missing")));
    }

    #[test]
    fn temporary_names_are_rollfric_s_own() {
        let pid = std::process::id();
        let t = temp_path(Path::new("out/a.html"), false);
        assert_eq!(t, Path::new(&format!("out/.rollfric-{pid}-a.html.tmp")));
        let v = temp_path(Path::new("c/twin.avi"), true);
        assert_eq!(v, Path::new(&format!("c/.rollfric-{pid}-twin.tmp.avi")));
        for p in [&t, &v] {
            let name = p.file_name().unwrap().to_str().unwrap();
            assert_eq!(temp_owner(name), Some(pid));
        }
        for user in [
            ".thesis.tmpl",
            ".notes.tmp",
            ".draft.tmp2",
            ".a.html.tmp123",
            "x.tmp",
        ] {
            assert_eq!(temp_owner(user), None, "{user}");
        }
        assert!(process_alive(pid));
    }
}
