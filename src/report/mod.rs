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

mod experiment;
pub mod figures;
mod index;
pub mod plot;
mod review;
mod summary;

pub use experiment::{experiment_pages, fmt_expanded, torsion_rows};
pub use index::index_pages;
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

fn templates() -> Result<tera::Tera> {
    let mut t = tera::Tera::default();
    t.add_raw_templates(TEMPLATES.iter().copied())
        .context("templates")?;
    t.autoescape_on(vec![".html"]);
    Ok(t)
}

/// Render `view` with the HTML and the Markdown template `name` into `<stem>.html` and
/// `<stem>.md`.
fn render_pair<T: Serialize>(name: &str, stem: &str, view: &T) -> Result<[OutputFile; 2]> {
    let tera = templates()?;
    let ctx = tera::Context::from_serialize(view)?;
    let page = |ext: &str| -> Result<OutputFile> {
        let bytes = tera
            .render(&format!("{name}.{ext}"), &ctx)
            .with_context(|| format!("template `{name}.{ext}`"))?;
        Ok(OutputFile::new(format!("{stem}.{ext}"), bytes))
    };
    Ok([page("html")?, page("md")?])
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
