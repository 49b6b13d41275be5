//! The links of README.md and of every page under docs/: a relative link must name a
//! file or folder that exists (its `#anchor` aside), so that a page read on a forge
//! never leads nowhere. Links to other sites are not followed (no network here).

mod common;

use std::path::{Path, PathBuf};

/// The targets of the Markdown links `[text](target)` of `text`, outside code spans
/// and fenced code blocks.
fn link_targets(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Code spans hold no links.
        let plain: String = line
            .split('`')
            .enumerate()
            .filter(|(i, _)| i % 2 == 0)
            .map(|(_, s)| s)
            .collect::<Vec<_>>()
            .join(" ");
        let mut rest = plain.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push(after[..end].trim().to_string());
            rest = &after[end..];
        }
    }
    out
}

/// The relative targets of `page` that name nothing, as `page: target` lines.
fn broken(page: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(page).unwrap();
    let dir = page.parent().unwrap();
    link_targets(&text)
        .into_iter()
        .filter(|t| !t.contains("://") && !t.starts_with("mailto:") && !t.starts_with('#'))
        .filter(|t| {
            let path = t.split('#').next().unwrap_or("");
            !dir.join(path).exists()
        })
        .map(|t| format!("{}: {t}", page.display()))
        .collect()
}

fn pages() -> Vec<PathBuf> {
    let root = common::root();
    let mut pages = vec![root.join("README.md")];
    let mut stack = vec![root.join("docs")];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "md") {
                pages.push(p);
            }
        }
    }
    pages
}

#[test]
fn every_relative_link_of_the_readme_and_the_docs_names_a_file() {
    let pages = pages();
    assert!(pages.len() >= 2, "{pages:?}");
    let bad: Vec<String> = pages.iter().flat_map(|p| broken(p)).collect();
    assert!(bad.is_empty(), "broken links:\n{}", bad.join("\n"));
}

#[test]
fn a_broken_link_is_found_and_code_is_not_read_for_links() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("there.md"), "# there\n").unwrap();
    let page = d.path().join("page.md");
    std::fs::write(
        &page,
        "[ok](there.md) [anchor](there.md#x) [site](https://example.org) [gone](gone.md)\n\
         `[not a link](nowhere.md)`\n```\n[nor this](nowhere.md)\n```\n",
    )
    .unwrap();
    let bad = broken(&page);
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(bad[0].ends_with(": gone.md"), "{bad:?}");
}
