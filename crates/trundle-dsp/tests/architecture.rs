//! docs/ARCHITECTURE.md's module map is the code's: every module it lists exists, and every
//! source file of the workspace (`*.rs` under `crates/*/src`, `xtask/src`, `tests/src`) is
//! listed. The map is read from the page itself, so a new module means one row there.
//!
//! The docs cite the layout as it is, too: every repository path in a code span of README.md
//! or docs/**/*.md (`crates/…`, `docs/…`, `presets/…`, `xtask/…`, `.ci/…`) exists, and so does
//! every module file docs/MODEL.md names (`source/series.rs`, relative to trundle-dsp's
//! `src/`; `tests/x.rs`, to its `tests/`).
//!
//! The page's "## Modules" section holds one `### `folder/`` heading per source root and
//! tables whose first cell names paths under it in backticks: `file.rs` lists that file,
//! `folder/` lists the `.rs` files directly in that folder (a folder of private helpers, the
//! editor's widgets); a cell may name several.

use std::collections::BTreeSet;
use std::path::Path;

use trundle_test_support::tree::workspace_root as root;

/// The backticked spans of a piece of Markdown: `` `a` and `b` `` → ["a", "b"].
fn code_spans(text: &str) -> Vec<&str> {
    text.split('`').skip(1).step_by(2).collect()
}

/// The paths the "## Modules" section lists, relative to the workspace root (folders end
/// in `/`), in page order.
fn listed(page: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_section = false;
    let mut base: Option<String> = None;
    let mut fence = false;
    for line in page.lines() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
        }
        if fence {
            continue;
        }
        if let Some(h) = line.strip_prefix("## ") {
            in_section = h.trim().starts_with("Modules");
            base = None;
            continue;
        }
        if !in_section {
            continue;
        }
        if let Some(h) = line.strip_prefix("### ") {
            base = code_spans(h)
                .into_iter()
                .find(|s| s.ends_with('/'))
                .map(str::to_owned);
            assert!(
                base.is_some(),
                "a heading in Modules without a `folder/`: {line}"
            );
            continue;
        }
        let Some(row) = line.trim_start().strip_prefix('|') else {
            continue;
        };
        let first_cell = row.split('|').next().unwrap_or("");
        for path in code_spans(first_cell) {
            let base = base
                .as_deref()
                .unwrap_or_else(|| panic!("a module row before any `### folder/` heading: {line}"));
            out.push(format!("{base}{path}"));
        }
    }
    out
}

/// Every `*.rs` under the workspace's source roots, relative to the root, with `/`.
fn source_files() -> BTreeSet<String> {
    fn walk(dir: &Path, out: &mut BTreeSet<String>) {
        for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|x| x == "rs") {
                let rel = path.strip_prefix(root()).expect("under the root");
                let parts: Vec<_> = rel.iter().map(|p| p.to_string_lossy()).collect();
                out.insert(parts.join("/"));
            }
        }
    }
    let mut roots = Vec::new();
    for entry in std::fs::read_dir(root().join("crates")).expect("crates/") {
        let src = entry.expect("a crate folder").path().join("src");
        if src.is_dir() {
            roots.push(src);
        }
    }
    roots.extend(["xtask/src", "tests/src"].map(|r| root().join(r)));
    let mut out = BTreeSet::new();
    for r in roots {
        walk(&r, &mut out);
    }
    out
}

/// Whether a listed entry covers a source file: the file itself, or a folder entry for the
/// folder the file is directly in.
fn covers(entry: &str, file: &str) -> bool {
    match entry.strip_suffix('/') {
        Some(folder) => file
            .strip_prefix(folder)
            .and_then(|rest| rest.strip_prefix('/'))
            .is_some_and(|name| !name.contains('/')),
        None => entry == file,
    }
}

fn page() -> String {
    std::fs::read_to_string(root().join("docs/ARCHITECTURE.md")).expect("docs/ARCHITECTURE.md")
}

#[test]
fn every_module_the_map_lists_exists() {
    let entries = listed(&page());
    assert!(entries.len() > 20, "only {} modules parsed", entries.len());
    let mut seen = BTreeSet::new();
    let mut problems = Vec::new();
    for e in &entries {
        if !seen.insert(e) {
            problems.push(format!("{e}: listed twice"));
        }
        let path = root().join(e);
        let ok = if e.ends_with('/') {
            path.is_dir()
        } else {
            path.is_file()
        };
        if !ok {
            problems.push(format!(
                "{e}: no such {}",
                if e.ends_with('/') { "folder" } else { "file" }
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "docs/ARCHITECTURE.md lists what is not there:\n  {}",
        problems.join("\n  ")
    );
}

#[test]
fn every_module_is_in_the_map() {
    let entries = listed(&page());
    let files = source_files();
    let unlisted: Vec<&String> = files
        .iter()
        .filter(|f| !entries.iter().any(|e| covers(e, f)))
        .collect();
    println!(
        "{} source files, {} map entries",
        files.len(),
        entries.len()
    );
    assert!(
        unlisted.is_empty(),
        "docs/ARCHITECTURE.md's Modules section does not list:\n  {}",
        unlisted
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n  ")
    );
}

#[test]
fn the_map_is_read_as_documented() {
    let page = "## Modules\n\n### `crates/a/src/`\n\n| module | what |\n|---|---|\n\
                | `lib.rs` | root |\n| `x/`, `y.rs` | two |\n\n```text\n| `no.rs` |\n```\n\
                ## Next\n\n| `not.rs` | outside |\n";
    assert_eq!(
        listed(page),
        [
            "crates/a/src/lib.rs",
            "crates/a/src/x/",
            "crates/a/src/y.rs"
        ]
    );
    assert!(covers("crates/a/src/x/", "crates/a/src/x/b.rs"));
    assert!(!covers("crates/a/src/x/", "crates/a/src/x/c/d.rs"));
    assert!(!covers("crates/a/src/x/", "crates/a/src/xy/b.rs"));
    assert!(covers("crates/a/src/y.rs", "crates/a/src/y.rs"));
}

/// The code spans of a page outside fenced code blocks.
fn prose_code_spans(page: &str) -> Vec<String> {
    let mut fence = false;
    let mut out = Vec::new();
    for line in page.lines() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
            continue;
        }
        if !fence {
            out.extend(code_spans(line).into_iter().map(str::to_owned));
        }
    }
    out
}

use trundle_test_support::tree::doc_pages;

/// A code span that names a path from the workspace root: its first word, when it starts
/// with a top-level folder and holds no pattern (`*`, `{n}`, `…`).
fn root_path(span: &str) -> Option<&str> {
    let word = span.split_whitespace().next()?;
    let top = ["crates/", "docs/", "presets/", "xtask/", ".ci/"];
    (top.iter().any(|t| word.starts_with(t)) && !word.contains(['*', '{', '…', '$']))
        .then_some(word)
}

/// A code span of MODEL.md that names a file of trundle-dsp: `folder/file.rs`, `file.rs`,
/// `folder/`, or `tests/file.rs`.
fn model_path(span: &str) -> Option<&str> {
    let ok = !span.is_empty()
        && (span.ends_with(".rs") || span.ends_with('/'))
        && span
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || "_/.".contains(c));
    ok.then_some(span)
}

#[test]
fn every_path_the_docs_cite_exists() {
    let mut missing = Vec::new();
    let mut checked = 0;
    for page in doc_pages() {
        let text = std::fs::read_to_string(&page).expect("a readable page");
        let name = page
            .strip_prefix(root())
            .unwrap_or(&page)
            .display()
            .to_string();
        let is_model = page.ends_with("docs/MODEL.md");
        for span in prose_code_spans(&text) {
            let path = if let Some(p) = root_path(&span) {
                root().join(p)
            } else if let Some(p) = model_path(&span).filter(|_| is_model) {
                let dsp = root().join("crates/trundle-dsp");
                if p.starts_with("tests/") {
                    dsp.join(p)
                } else {
                    dsp.join("src").join(p)
                }
            } else {
                continue;
            };
            checked += 1;
            if !path.exists() {
                missing.push(format!("{name}: `{span}`"));
            }
        }
    }
    println!("{checked} cited paths checked");
    assert!(
        missing.is_empty(),
        "the docs cite paths that are not there:\n  {}",
        missing.join("\n  ")
    );
}

#[test]
fn cited_paths_are_recognized() {
    assert_eq!(
        root_path("crates/trundle/src/editor/"),
        Some("crates/trundle/src/editor/")
    );
    assert_eq!(root_path("docs/MODEL.md §N"), Some("docs/MODEL.md"));
    assert_eq!(root_path("presets/*.json"), None);
    assert_eq!(root_path("trundle render"), None);
    assert_eq!(model_path("source/series.rs"), Some("source/series.rs"));
    assert_eq!(model_path("physics/"), Some("physics/"));
    assert_eq!(model_path("object::long_bank::LongBank"), None);
    assert_eq!(model_path("cargo test"), None);
}
