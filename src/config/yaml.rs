//! Reading YAML: which keys make a file an experiment file or a manifest, and the
//! parser's errors on one line, with the offending line quoted and bounded.

/// Top-level keys by which a file is known for an experiment file (or a manifest): one
/// of them at the start of a line.
pub(super) const EXPERIMENT_KEYS: &[&str] = &[
    "name",
    "material",
    "geometry",
    "air",
    "video",
    "angles",
    "synthetic",
];
pub(super) const MANIFEST_KEYS: &[&str] = &["title", "experiments"];

/// Whether `text` has one of `keys` at the start of a line (`key:`).
pub(super) fn has_top_key(text: &str, keys: &[&str]) -> bool {
    text.lines().any(|l| {
        l.split_once(':')
            .is_some_and(|(k, _)| keys.contains(&k.trim_end()))
    })
}

/// The parser's message on one line: its first line, plus the offending source line.
/// A file with none of the top-level `keys` of `what` it should be is not quoted: it is
/// refused as not such a file (a manifest listing `/etc/passwd` must not copy its lines
/// into the reports).
pub(super) fn yaml_error(
    e: &serde_saphyr::Error,
    text: &str,
    keys: &[&str],
    what: &str,
) -> anyhow::Error {
    if !has_top_key(text, keys) {
        return anyhow::anyhow!(
            "not {what}: none of its keys ({}) is in it",
            keys.iter()
                .map(|k| format!("`{k}:`"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let msg = e.to_string();
    let first = msg.lines().next().unwrap_or("").trim();
    let first = first.strip_prefix("error: ").unwrap_or(first);
    let src = first
        .strip_prefix("line ")
        .and_then(|r| r.split_whitespace().next())
        .and_then(|n| n.parse::<usize>().ok())
        .and_then(|n| text.lines().nth(n.saturating_sub(1)))
        .map(|l| format!(" (in `{}`)", excerpt(l.trim(), 120)))
        .unwrap_or_default();
    // The parser's advice on its own options is not ours to give.
    if first.contains("multiple YAML documents") {
        return anyhow::anyhow!(
            "{}: a second YAML document (after `---`); {what} is one document",
            first.split(':').next().unwrap_or("")
        );
    }
    if first.contains("budget breached") {
        return anyhow::anyhow!(
            "too many YAML nodes or aliases (nested or repeated anchors); {what} is a short, \
             flat file"
        );
    }
    let first = match first.split_once("duplicate mapping key: ") {
        Some((at, rest)) => {
            let key = rest
                .split(|c: char| c == ',' || c.is_whitespace())
                .next()
                .unwrap_or("");
            format!("{at}the key `{key}` is given twice")
        }
        None => first.to_string(),
    };
    // Room for the list of valid keys, not for a huge quoted value (in bytes: a key of
    // two-byte letters must not double the message).
    anyhow::anyhow!("{}{src}", excerpt_bytes(&first, 400))
}

/// At most about `max` bytes of `s`, cut at a character boundary, with what was left out.
pub(super) fn excerpt_bytes(s: &str, max: usize) -> String {
    if s.len() <= max {
        return s.to_string();
    }
    let mut i = max;
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    format!("{}... ({} more bytes)", &s[..i], s.len() - i)
}

/// At most `max` characters of quoted input (a huge one-line file is not echoed whole).
pub(crate) fn excerpt(s: &str, max: usize) -> String {
    match s.char_indices().nth(max) {
        Some((i, _)) => format!("{}... ({} more bytes)", &s[..i], s.len() - i),
        None => s.to_string(),
    }
}

/// Quoted input on one short line: control characters escaped, at most `max` characters.
pub(crate) fn quoted(s: &str, max: usize) -> String {
    excerpt(&s.escape_debug().to_string(), max)
}
