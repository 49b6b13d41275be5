//! Content hashes: the stages' cache keys and the reports' provenance.
//!
//! A key is the SHA-256 of everything an output depends on: the bytes of its input
//! files, its parameters (as canonical JSON), the tool's version and the source of the
//! code that produces it ([`crate::sources`]).

use anyhow::{Context, Result};
use sha2::{Digest, Sha256};
use std::io::Read;
use std::path::Path;

/// The tool's version as it enters every key and the reports' provenance.
pub const TOOL: &str = concat!("rollfric ", env!("CARGO_PKG_VERSION"));

/// Accumulates the parts of a key.
pub struct Key(Sha256);

impl Key {
    /// A key for `stage`, salted with the tool's version.
    pub fn new(stage: &str) -> Self {
        let mut h = Sha256::new();
        h.update(TOOL.as_bytes());
        h.update([0]);
        h.update(stage.as_bytes());
        h.update([0]);
        Self(h)
    }

    /// Add a labelled part (the label keeps `("ab", "c")` apart from `("a", "bc")`).
    pub fn part(mut self, label: &str, bytes: &[u8]) -> Self {
        self.0.update(label.as_bytes());
        self.0.update((bytes.len() as u64).to_le_bytes());
        self.0.update(bytes);
        self
    }

    /// Add a value as canonical JSON.
    pub fn json<T: serde::Serialize>(self, label: &str, v: &T) -> Self {
        let text = serde_json::to_vec(v).unwrap_or_default();
        self.part(label, &text)
    }

    pub fn hex(self) -> String {
        hex(&self.0.finalize())
    }
}

/// Lower-case hexadecimal.
pub fn hex(bytes: &[u8]) -> String {
    use std::fmt::Write as _;
    bytes.iter().fold(String::new(), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

/// SHA-256 of bytes, hex.
pub fn sha256(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// SHA-256 of a file's bytes, hex, streamed (videos can be large).
pub fn sha256_file(path: &Path) -> Result<String> {
    let mut f =
        std::fs::File::open(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = f
            .read(&mut buf)
            .with_context(|| format!("{}: cannot read", path.display()))?;
        if n == 0 {
            break;
        }
        h.update(&buf[..n]);
    }
    Ok(hex(&h.finalize()))
}

/// Whether the stage whose key file is `key_file` is up to date with `key` and every
/// one of its `outputs` exists.
pub fn fresh(key_file: &Path, key: &str, outputs: &[&Path]) -> bool {
    std::fs::read_to_string(key_file).is_ok_and(|k| k.trim() == key)
        && outputs.iter().all(|p| p.exists())
}

/// Set `path`'s modification time to now (its content unchanged).
pub fn touch(path: &Path) -> Result<()> {
    std::fs::File::options()
        .append(true)
        .open(path)
        .and_then(|f| f.set_modified(std::time::SystemTime::now()))
        .with_context(|| format!("{}: cannot touch", path.display()))
}

/// Record that a stage's outputs now match `key` (written after the outputs, so a
/// process killed between the two leaves a stale key and the stage runs again).
pub fn record(key_file: &Path, key: &str) -> Result<()> {
    crate::fsutil::write_atomic(key_file, format!("{key}\n").as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_depend_on_every_part_and_its_boundaries() {
        let k = |a: &str, b: &str| {
            Key::new("s")
                .part("x", a.as_bytes())
                .part("y", b.as_bytes())
                .hex()
        };
        assert_eq!(k("ab", "c"), k("ab", "c"));
        assert_ne!(k("ab", "c"), k("a", "bc"));
        assert_ne!(Key::new("s").hex(), Key::new("t").hex());
        assert_eq!(
            sha256(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    #[test]
    fn a_stage_is_fresh_only_with_its_key_and_outputs() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("out.txt");
        let key = d.path().join("out.key");
        assert!(!fresh(&key, "k1", &[&out]));
        crate::fsutil::write_atomic(&out, b"x").unwrap();
        assert!(!fresh(&key, "k1", &[&out]), "no key recorded yet");
        record(&key, "k1").unwrap();
        assert!(fresh(&key, "k1", &[&out]));
        assert!(!fresh(&key, "k2", &[&out]), "another key");
        std::fs::remove_file(&out).unwrap();
        assert!(!fresh(&key, "k1", &[&out]), "output gone");
        assert_eq!(sha256_file(&key).unwrap(), sha256(b"k1\n"));
    }
}
