//! The reports: per-experiment pages, the index with Table 1 reproduced, `summary.json`,
//! and `rollfric check`.
//!
//! Rendering is pure: every function here returns [`OutputFile`]s (a path under the
//! reports folder and its bytes) and writes nothing; the build's writer owns `reports/`.
//! Pages are rendered by tera from the templates in `templates/` (compiled into the
//! binary, so a report never depends on where the tool runs from) in HTML and
//! Markdown. Every number on them is computed from the inputs; published values
//! appear only in the `reference` columns. Nothing machine-specific is rendered: paths
//! are relative to the manifest and there are no dates, so the same inputs give the same
//! bytes.

mod budget;
mod experiment;
pub mod figures;
mod index;
pub mod plot;
mod review;
mod rows;
mod series;
mod summary;

pub use budget::fmt_expanded;
pub use experiment::experiment_pages;
pub use index::index_pages;
pub use rows::torsion_rows;
pub use summary::{check, Entry, EntryStatus, Outcome, Summary};

use anyhow::{Context, Result};
use serde::Serialize;

/// One file of the reports: its path under the reports folder and its bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputFile {
    pub path: String,
    pub bytes: Vec<u8>,
}

impl OutputFile {
    pub fn new(path: impl Into<String>, bytes: impl Into<Vec<u8>>) -> Self {
        Self {
            path: path.into(),
            bytes: bytes.into(),
        }
    }
}

/// The templates, compiled in.
const TEMPLATES: &[(&str, &str)] = &[
    ("style.css", include_str!("../../templates/style.css")),
    (
        "index.html",
        include_str!("../../templates/index.html.tera"),
    ),
    ("index.md", include_str!("../../templates/index.md.tera")),
    (
        "experiment.html",
        include_str!("../../templates/experiment.html.tera"),
    ),
    (
        "experiment.md",
        include_str!("../../templates/experiment.md.tera"),
    ),
    (
        "review.html",
        include_str!("../../templates/review.html.tera"),
    ),
];

/// The templates, every value escaped for its page: HTML's escape for the HTML pages,
/// [`escape_markdown`] for the Markdown ones.
fn templates() -> Result<tera::Tera> {
    let mut t = tera::Tera::default();
    t.add_raw_templates(TEMPLATES.iter().copied())
        .context("templates")?;
    t.autoescape_on(vec![".html"]);
    Ok(t)
}

fn markdown_templates() -> Result<tera::Tera> {
    let mut t = templates()?;
    t.autoescape_on(vec![".md"]);
    t.set_escape_fn(escape_markdown);
    Ok(t)
}

/// A value as plain text in a Markdown page: `<` as an entity (no tag, comment or script
/// of a value's survives a renderer), `|` escaped (a value cannot add cells to a table
/// row, or forge one) and line ends as spaces (nor end a row or a paragraph).
pub fn escape_markdown(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("&lt;"),
            '|' => out.push_str("\\|"),
            '\r' | '\n' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Render `view` with the HTML and the Markdown template `name` into `<stem>.html` and
/// `<stem>.md`.
fn render_pair<T: Serialize>(name: &str, stem: &str, view: &T) -> Result<[OutputFile; 2]> {
    let ctx = tera::Context::from_serialize(view)?;
    let page = |tera: tera::Tera, ext: &str| -> Result<OutputFile> {
        let bytes = tera
            .render(&format!("{name}.{ext}"), &ctx)
            .with_context(|| format!("template `{name}.{ext}`"))?;
        Ok(OutputFile::new(format!("{stem}.{ext}"), bytes))
    };
    Ok([
        page(templates()?, "html")?,
        page(markdown_templates()?, "md")?,
    ])
}

/// Key-value rows of a page's tables (already formatted).
#[derive(Serialize)]
struct Kv {
    k: String,
    v: String,
}

fn kv(k: &str, v: String) -> Kv {
    Kv { k: k.into(), v }
}

fn fmt_sci(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return "-".into();
    }
    format!("{v:.digits$e}")
}

fn fmt_pct(v: f64) -> String {
    if !v.is_finite() {
        return "-".into();
    }
    format!("{:+.2} %", 100.0 * v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells of a Markdown table row: split at the `|` not escaped by a backslash.
    fn cells(row: &str) -> usize {
        let b = row.as_bytes();
        (0..b.len())
            .filter(|&i| b[i] == b'|' && (i == 0 || b[i - 1] != b'\\'))
            .count()
            - 1
    }

    #[test]
    fn a_value_cannot_forge_a_row_or_bring_a_tag_into_a_markdown_page() {
        let forged = "Glass | 9.999e-6 ± 1e-9 | 3.714e-6 | +0.00 %";
        let row = format!("| {} | 3.7156e-6 |", escape_markdown(forged));
        assert_eq!(cells(&row), 2, "{row}");
        for evil in [
            "<script>alert(1)</script>",
            "<img src=x onerror=alert(1)>",
            "Steel <!--",
        ] {
            let e = escape_markdown(evil);
            assert!(!e.contains('<'), "{e}");
        }
        assert_eq!(escape_markdown("a\nb\r\nc"), "a b  c");
        // Ordinary text passes as it is.
        assert_eq!(
            escape_markdown("Steel -> 4.5e-6 m, > 1000"),
            "Steel -> 4.5e-6 m, > 1000"
        );
    }

    #[test]
    fn the_markdown_pages_escape_every_value_and_the_html_pages_theirs() {
        let mut t = tera::Tera::default();
        t.add_raw_template("x.md", "| {{ v }} |").unwrap();
        t.add_raw_template("x.html", "<p>{{ v }}</p>").unwrap();
        let mut ctx = tera::Context::new();
        ctx.insert("v", "a | <b>");
        let mut md = markdown_templates().unwrap();
        md.extend(&t).unwrap();
        assert_eq!(md.render("x.md", &ctx).unwrap(), "| a \\| &lt;b> |");
        let mut html = templates().unwrap();
        html.extend(&t).unwrap();
        assert_eq!(html.render("x.html", &ctx).unwrap(), "<p>a | &lt;b&gt;</p>");
    }
}
