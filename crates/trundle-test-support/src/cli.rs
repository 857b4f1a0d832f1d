//! The `trundle` binary, run in a folder, and what it printed.
//!
//! The binary is found next to the test executable's folder (Cargo puts integration tests
//! in `target/<profile>/deps/` and the package's binaries in `target/<profile>/`, and builds
//! the binaries before the integration tests of their package), as `assert_cmd` does.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `trundle` binary under test (panics if it was not built).
pub fn bin() -> PathBuf {
    let exe = std::env::current_exe().expect("the test executable's path");
    let dir = exe
        .parent()
        .and_then(Path::parent)
        .expect("target/<profile>");
    let path = dir.join(format!("trundle{}", std::env::consts::EXE_SUFFIX));
    assert!(
        path.is_file(),
        "{} not found: the trundle binary is built by `cargo test -p trundle-cli`",
        path.display()
    );
    path
}

/// Run `trundle args…` in `dir`.
pub fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(bin())
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the trundle binary runs")
}

/// Its standard output as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Its standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Run and require success; returns stdout.
pub fn ok(dir: &Path, args: &[&str]) -> String {
    let o = run(dir, args);
    assert!(
        o.status.success(),
        "trundle {args:?} failed: {}",
        stderr(&o)
    );
    stdout(&o)
}

/// Run, require success, parse stdout as one JSON value.
pub fn json(dir: &Path, args: &[&str]) -> serde_json::Value {
    serde_json::from_str(&ok(dir, args)).unwrap()
}

/// The folder's entries, sorted (to prove nothing stray, such as temporary files, was left).
pub fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The number before `word` in a summary line ("1069 impacts" → 1069).
pub fn number_before(line: &str, word: &str) -> u64 {
    let i = line
        .find(word)
        .unwrap_or_else(|| panic!("no '{word}' in {line}"));
    line[..i]
        .trim_end()
        .rsplit(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap()
}
