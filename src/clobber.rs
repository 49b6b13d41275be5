//! What a command's output may replace: never one of its own inputs, never another of
//! its outputs, and an existing file only when it is one rollfric wrote of the same
//! kind (an angle CSV over an angle CSV, a twin over a twin), unless `--force` names it.

use anyhow::{bail, Result};
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// The metadata comment every rendered twin carries (`synth`), by which a later `synth
/// -o` knows the file it would replace for one of its own.
pub const TWIN_MARK: &str = "rollfric digital twin";

/// The kinds of file a command writes, each known by its first bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `t_s,angle_rad[,status,quality]` (`detect`, `simulate`).
    Angles,
    /// `t_s,angle_rad,spoiled` (`synth --truth`).
    Truth,
    /// A twin's video (`synth`): it carries [`TWIN_MARK`].
    Twin,
    /// `detect --json`'s summary: it begins with [`DETECT_JSON_KIND`].
    DetectJson,
}

/// The first key of `detect --json`'s summary, by which an older one is known.
pub const DETECT_JSON_KIND: &str = "\"kind\": \"rollfric detect\"";

impl Kind {
    fn describe(self) -> &'static str {
        match self {
            Kind::Angles => "an angle CSV (t_s,angle_rad,...)",
            Kind::Truth => "a twin's truth CSV (t_s,angle_rad,spoiled)",
            Kind::Twin => "a twin's video rendered by `rollfric synth`",
            Kind::DetectJson => "a detection summary written by `rollfric detect --json`",
        }
    }

    /// Whether the existing file at `path` is of this kind, as rollfric writes it.
    fn holds(self, path: &Path) -> bool {
        match self {
            Kind::Angles => first_line(path)
                .is_some_and(|l| l == "t_s,angle_rad" || l == "t_s,angle_rad,status,quality"),
            Kind::Truth => first_line(path).is_some_and(|l| l == "t_s,angle_rad,spoiled"),
            Kind::Twin => carries_mark(path),
            Kind::DetectJson => head(path).is_some_and(|h| h.contains(DETECT_JSON_KIND)),
        }
    }
}

/// The first line of a file (at most 256 bytes read), without its line end.
fn first_line(path: &Path) -> Option<String> {
    Some(
        head(path)?
            .lines()
            .next()?
            .trim_end_matches('\r')
            .to_string(),
    )
}

/// The first 256 bytes of a file, as text.
fn head(path: &Path) -> Option<String> {
    let mut buf = [0u8; 256];
    let mut f = std::fs::File::open(path).ok()?;
    let n = f.read(&mut buf).ok()?;
    Some(String::from_utf8_lossy(&buf[..n]).into_owned())
}

/// Whether a video holds [`TWIN_MARK`] where a container keeps its metadata: the
/// header of an AVI (its first 64 KiB), the `moov` box of an MP4 or MOV (found by
/// walking the top-level boxes, so a long video is not read through), or the first 64
/// KiB or last MiB of a Matroska file.
fn carries_mark(path: &Path) -> bool {
    let Ok(mut f) = std::fs::File::open(path) else {
        return false;
    };
    let mark = TWIN_MARK.as_bytes();
    let holds = |bytes: &[u8]| bytes.windows(mark.len()).any(|w| w == mark);
    let mut head = vec![0u8; 64 << 10];
    let Ok(n) = read_full(&mut f, &mut head) else {
        return false;
    };
    head.truncate(n);
    if head.starts_with(b"RIFF") {
        return holds(&head);
    }
    let len = f.metadata().map(|m| m.len()).unwrap_or(0);
    if head.starts_with(&[0x1a, 0x45, 0xdf, 0xa3]) {
        // Matroska: its tags come at the start or, written last, near the end.
        let mut tail = vec![0u8; (1u64 << 20).min(len) as usize];
        return holds(&head)
            || (f.seek(SeekFrom::Start(len - tail.len() as u64)).is_ok()
                && read_full(&mut f, &mut tail).is_ok()
                && holds(&tail));
    }
    // MP4: boxes of (32-bit size, type), a size of 1 followed by a 64-bit size.
    let mut at = 0u64;
    for _ in 0..64 {
        let mut hdr = [0u8; 16];
        if f.seek(SeekFrom::Start(at)).is_err() || read_full(&mut f, &mut hdr).ok() != Some(16) {
            return false;
        }
        let size32 = u32::from_be_bytes(hdr[0..4].try_into().expect("4 bytes"));
        let size = match size32 {
            1 => u64::from_be_bytes(hdr[8..16].try_into().expect("8 bytes")),
            0 => len - at,
            s => u64::from(s),
        };
        if size < 8 || at.checked_add(size).is_none_or(|end| end > len) {
            return false;
        }
        if &hdr[4..8] == b"moov" {
            if size > 64 << 20 || f.seek(SeekFrom::Start(at)).is_err() {
                return false;
            }
            let mut moov = vec![0u8; size as usize];
            return read_full(&mut f, &mut moov).ok() == Some(moov.len()) && holds(&moov);
        }
        at += size;
    }
    false
}

fn read_full(f: &mut std::fs::File, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match f.read(&mut buf[got..])? {
            0 => break,
            k => got += k,
        }
    }
    Ok(got)
}

/// The same file, whether or not it exists yet: both paths' folders resolved (links
/// followed) and their names compared; an existing pair is compared by device and inode
/// (a hard link is the same file).
pub fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    if let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        return ma.dev() == mb.dev() && ma.ino() == mb.ino();
    }
    match (resolved(a), resolved(b)) {
        (Some(a), Some(b)) => a == b,
        _ => false,
    }
}

/// `path` with its folder resolved (the folder must exist).
fn resolved(path: &Path) -> Option<PathBuf> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(std::fs::canonicalize(dir).ok()?.join(path.file_name()?))
}

/// One output of a command: its flag (as the user wrote it), path and kind.
pub struct Output<'a> {
    pub flag: &'a str,
    pub path: &'a Path,
    pub kind: Kind,
}

/// Refuse an output that is one of `inputs` (named by what they are, e.g. `("the
/// video", path)`), that is another of `outputs`, or that exists and is not of its kind
/// (unless `force`). A device or FIFO (`/dev/null`, `/dev/stdout`) is written through
/// and may always be named.
pub fn check(outputs: &[Output], inputs: &[(&str, &Path)], force: bool) -> Result<()> {
    for (i, o) in outputs.iter().enumerate() {
        let shown = o.path.display();
        if let Ok(m) = std::fs::symlink_metadata(o.path) {
            if m.is_dir() {
                bail!("{} {shown}: is a folder; give a file name", o.flag);
            }
        }
        for (what, input) in inputs {
            if same_file(o.path, input) {
                bail!(
                    "{} {shown}: that is {what} ({}), an input; the output would replace it",
                    o.flag,
                    input.display()
                );
            }
        }
        for other in &outputs[i + 1..] {
            if same_file(o.path, other.path) {
                bail!(
                    "{} {shown} and {} {}: the same file; give each output its own name",
                    o.flag,
                    other.flag,
                    other.path.display()
                );
            }
        }
        if force || crate::fsutil::is_special(o.path) {
            continue;
        }
        if std::fs::symlink_metadata(o.path).is_ok() && !o.kind.holds(o.path) {
            bail!(
                "{} {shown}: already exists and is not {}; give another name, or --force to \
                 replace it",
                o.flag,
                o.kind.describe()
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn out<'a>(flag: &'a str, path: &'a Path, kind: Kind) -> Output<'a> {
        Output { flag, path, kind }
    }

    #[test]
    fn an_output_replaces_only_its_own_kind() {
        let d = tempfile::tempdir().unwrap();
        let p = |n: &str| d.path().join(n);
        std::fs::write(p("thesis.txt"), "Chapter 1\n").unwrap();
        std::fs::write(p("old.csv"), "t_s,angle_rad,status,quality\n0,0,ok,1\n").unwrap();
        std::fs::write(p("truth.csv"), "t_s,angle_rad,spoiled\n").unwrap();
        let new = p("new.csv");
        assert!(check(&[out("-o", &new, Kind::Angles)], &[], false).is_ok());
        assert!(check(&[out("-o", &p("old.csv"), Kind::Angles)], &[], false).is_ok());
        let e = check(&[out("-o", &p("thesis.txt"), Kind::Angles)], &[], false).unwrap_err();
        assert!(e.to_string().contains("not an angle CSV"), "{e}");
        assert!(check(&[out("-o", &p("thesis.txt"), Kind::Angles)], &[], true).is_ok());
        assert!(check(&[out("--truth", &p("old.csv"), Kind::Truth)], &[], false).is_err());
        assert!(check(&[out("--truth", &p("truth.csv"), Kind::Truth)], &[], false).is_ok());
        // Devices are written through.
        assert!(check(&[out("-o", Path::new("/dev/null"), Kind::Twin)], &[], false).is_ok());
    }

    #[test]
    fn an_output_is_never_an_input_or_another_output() {
        let d = tempfile::tempdir().unwrap();
        let csv = d.path().join("a.csv");
        std::fs::write(&csv, "t_s,angle_rad\n").unwrap();
        // Even with --force, and through another spelling of the same path.
        let other = d.path().join(".").join("a.csv");
        let e = check(
            &[out("-o", &other, Kind::Angles)],
            &[("the video", &csv)],
            true,
        );
        assert!(e.unwrap_err().to_string().contains("an input"));
        let t = d.path().join("t.mp4");
        let e = check(
            &[out("-o", &t, Kind::Twin), out("--truth", &t, Kind::Truth)],
            &[],
            true,
        );
        assert!(e.unwrap_err().to_string().contains("the same file"));
        // A hard link is the same file.
        let link = d.path().join("link.csv");
        std::fs::hard_link(&csv, &link).unwrap();
        assert!(same_file(&csv, &link));
    }

    #[test]
    fn a_twin_is_known_by_its_mark_in_either_container() {
        let d = tempfile::tempdir().unwrap();
        let mp4 = d.path().join("t.mp4");
        // ftyp, mdat (large), then moov with the mark, as ffmpeg lays out an MP4.
        let mut bytes = Vec::new();
        bytes.extend_from_slice(&16u32.to_be_bytes());
        bytes.extend_from_slice(b"ftypisom\0\0\0\0");
        bytes.extend_from_slice(&(8u32 + 100_000).to_be_bytes());
        bytes.extend_from_slice(b"mdat");
        bytes.extend(std::iter::repeat_n(0u8, 100_000));
        let moov = [b"udta comment ".as_slice(), TWIN_MARK.as_bytes()].concat();
        bytes.extend_from_slice(&(8 + moov.len() as u32).to_be_bytes());
        bytes.extend_from_slice(b"moov");
        bytes.extend_from_slice(&moov);
        std::fs::write(&mp4, &bytes).unwrap();
        assert!(carries_mark(&mp4));
        // The mark in the media data is not the container's.
        let n = bytes.len();
        bytes[n - moov.len() - 4..n - moov.len()].copy_from_slice(b"free");
        std::fs::write(&mp4, &bytes).unwrap();
        assert!(!carries_mark(&mp4));
        let avi = d.path().join("t.avi");
        std::fs::write(
            &avi,
            [b"RIFF....AVI LIST".as_slice(), TWIN_MARK.as_bytes()].concat(),
        )
        .unwrap();
        assert!(carries_mark(&avi));
        std::fs::write(&avi, b"RIFF....AVI LIST").unwrap();
        assert!(!carries_mark(&avi));
    }
}
