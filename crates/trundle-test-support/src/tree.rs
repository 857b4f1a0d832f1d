//! The repository's own files, for the tests that hold the docs and the layout to the code
//! (`tests/docs_links.rs`, `tests/architecture.rs`, `tests/layers.rs` in trundle-dsp).

use std::path::{Path, PathBuf};

/// The workspace root (this crate sits two levels below it).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every file ending in `.ext` under `dir`, folders `target` and `.git` skipped, sorted. A
/// folder that cannot be read is passed over (a missing `xtask/` is not a test failure;
/// the callers assert how many files they read).
pub fn files_with_extension(dir: &Path, ext: &str) -> Vec<PathBuf> {
    fn walk(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
                if !matches!(name.as_deref(), Some("target" | ".git")) {
                    walk(&path, ext, out);
                }
            } else if path.extension().is_some_and(|x| x == ext) {
                out.push(path);
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, ext, &mut out);
    out.sort();
    out
}

/// Every Rust file of the workspace: `.rs` under `crates/`, `tests/` and `xtask/`, sorted.
pub fn workspace_rust_files() -> Vec<PathBuf> {
    let root = workspace_root();
    let mut out: Vec<PathBuf> = ["crates", "tests", "xtask"]
        .iter()
        .flat_map(|top| files_with_extension(&root.join(top), "rs"))
        .collect();
    out.sort();
    out
}

/// README.md and every `.md` under `docs/`, sorted.
pub fn doc_pages() -> Vec<PathBuf> {
    let root = workspace_root();
    let mut out = vec![root.join("README.md")];
    out.extend(files_with_extension(&root.join("docs"), "md"));
    out.sort();
    out
}
