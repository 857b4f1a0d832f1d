//! The house rules of docs/ARCHITECTURE.md ("Layers"), held to the code:
//!
//! * inside `trundle-dsp` a module names only its own layer or a lower one (`crate::…` paths
//!   in code, not in comments): block, smooth → params → stage → analysis → object → source →
//!   physics → scene → fit;
//! * no source file of the workspace is over 700 lines.
//!
//! Import circles of more than two files are kept out by the same order (a circle has to
//! cross a layer upwards unless it stays inside one folder).

use trundle_test_support::tree::{files_with_extension, workspace_root, workspace_rust_files};

/// The layers, lowest first; a top-level module of `trundle-dsp/src` per name.
const LAYERS: &[&[&str]] = &[
    &["block", "smooth"],
    &["params"],
    &["stage"],
    &["analysis"],
    &["object"],
    &["source"],
    &["physics"],
    &["scene"],
    &["fit"],
];

/// The longest source file the house allows (lines).
const MAX_LINES: usize = 700;

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

/// The top-level modules a line of code names as `crate::name`.
fn crate_paths(line: &str) -> Vec<&str> {
    line.match_indices("crate::")
        .filter(|(i, _)| {
            // `my_crate::`, `$crate::` or `a::crate::` are not this crate's paths.
            let before = line[..*i].chars().next_back();
            !before.is_some_and(|c| c.is_alphanumeric() || matches!(c, '_' | '$' | ':'))
        })
        .map(|(i, m)| {
            let rest = &line[i + m.len()..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            &rest[..end]
        })
        .collect()
}

#[test]
fn no_module_names_a_layer_above_its_own() {
    let src = workspace_root().join("crates/trundle-dsp/src");
    let files = files_with_extension(&src, "rs");
    assert!(files.len() > 50, "read {} files under {src:?}", files.len());
    let mut upward = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&src).unwrap();
        let top = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let top = top.trim_end_matches(".rs");
        let Some(own) = layer_of(top) else {
            assert_eq!(
                top, "lib",
                "{rel:?} is in no layer: add it to LAYERS and the page"
            );
            continue;
        };
        let text = std::fs::read_to_string(file).unwrap();
        for (n, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("//") {
                continue;
            }
            for module in crate_paths(line) {
                match layer_of(module) {
                    Some(l) if l > own => {
                        upward.push(format!("{}:{}: crate::{module}", rel.display(), n + 1))
                    }
                    _ => {}
                }
            }
        }
    }
    assert!(
        upward.is_empty(),
        "modules that name a layer above their own (docs/ARCHITECTURE.md \"Layers\"):\n  {}",
        upward.join("\n  ")
    );
}

#[test]
fn the_path_reader_sees_crate_paths_only() {
    assert_eq!(
        crate_paths("use crate::scene::voice; x::crate::no; $crate::no"),
        ["scene"]
    );
    assert_eq!(
        crate_paths("f(crate::block::CHUNK, crate::params::X)"),
        ["block", "params"]
    );
}

#[test]
fn no_source_file_is_over_700_lines() {
    let root = workspace_root();
    let files = workspace_rust_files();
    assert!(files.len() > 100, "read {} files", files.len());
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let lines = std::fs::read_to_string(f).ok()?.lines().count();
            (lines > MAX_LINES)
                .then(|| format!("{} ({lines})", f.strip_prefix(&root).unwrap().display()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "over {MAX_LINES} lines (split by what they model): {long:?}"
    );
}
