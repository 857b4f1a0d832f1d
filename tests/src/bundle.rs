//! Finding — and when needed building — the plugin bundle the host tests load.
//!
//! * The bundle is `<target>/bundled/Trundle.clap`, `<target>` being `CARGO_TARGET_DIR`
//!   when set (a relative path is taken from the workspace root) and `target/` in the
//!   workspace otherwise. `TRUNDLE_CLAP_BUNDLE=<path>` tests another bundle as it is (an
//!   installed one, say) and never builds.
//! * It is rebuilt with `cargo xtask bundle trundle --release`, run with the same `cargo`
//!   that runs the tests (`env!("CARGO")`) from the workspace root, when it is missing or
//!   older than any file it is built from (both plugin crates, the presets embedded in it,
//!   the manifests, `Cargo.lock`, `bundler.toml`, `xtask/`).
//!
//! ## Why the nested cargo does not deadlock
//!
//! Cargo holds its build-directory lock only while it compiles: `cargo test` releases it
//! before it runs the test binaries, as `cargo run` does before it runs the program (the
//! xtask itself relies on that when it calls `cargo build`). Checked with cargo 1.95: a
//! stale bundle rebuilt from inside `cargo test --workspace --locked` (test profile,
//! `target/debug`) and from inside `cargo test --release` (the very `target/release` the
//! nested build uses) — both finish, ~20 s for an incremental plugin rebuild. What can
//! happen is *waiting*: another cargo working in the same target directory makes the nested
//! one print "Blocking waiting for file lock" until it is done. A watchdog
//! ([`BUILD_TIMEOUT`], override with `TRUNDLE_BUNDLE_TIMEOUT_S`) turns a build that never
//! finishes into a test failure that says so, instead of a hung test run.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant, SystemTime};

/// Longest a nested bundle build may take before the test fails.
pub const BUILD_TIMEOUT: Duration = Duration::from_secs(40 * 60);

/// The workspace root (the parent of this crate).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ lives inside the workspace")
        .to_path_buf()
}

/// Cargo's target directory, as the nested `cargo xtask` will resolve it.
pub fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) if !dir.is_empty() => {
            let dir = PathBuf::from(dir);
            if dir.is_absolute() {
                dir
            } else {
                workspace_root().join(dir)
            }
        }
        _ => workspace_root().join("target"),
    }
}

/// Where `cargo xtask bundle trundle` writes the CLAP bundle on this platform.
pub fn clap_bundle_path() -> PathBuf {
    target_dir().join("bundled").join("Trundle.clap")
}

/// Where `cargo xtask bundle trundle` writes the VST3 bundle (a directory).
pub fn vst3_bundle_path() -> PathBuf {
    target_dir().join("bundled").join("Trundle.vst3")
}

/// The files and directories the bundle is built from.
pub fn bundle_inputs() -> Vec<PathBuf> {
    let root = workspace_root();
    [
        "crates/trundle/src",
        "crates/trundle/build.rs",
        "crates/trundle/Cargo.toml",
        "crates/trundle-dsp/src",
        "crates/trundle-dsp/build.rs",
        "crates/trundle-dsp/Cargo.toml",
        "presets",
        "xtask",
        "bundler.toml",
        "Cargo.toml",
        "Cargo.lock",
    ]
    .iter()
    .map(|p| root.join(p))
    .collect()
}

/// The newest modification time under `paths` (recursively) and the file that has it.
pub fn newest_input(paths: &[PathBuf]) -> Option<(SystemTime, PathBuf)> {
    fn walk(path: &Path, best: &mut Option<(SystemTime, PathBuf)>) {
        let Ok(meta) = std::fs::metadata(path) else {
            return;
        };
        if meta.is_dir() {
            if let Ok(entries) = std::fs::read_dir(path) {
                for e in entries.flatten() {
                    walk(&e.path(), best);
                }
            }
        } else if let Ok(t) = meta.modified() {
            if best.as_ref().is_none_or(|(b, _)| t > *b) {
                *best = Some((t, path.to_path_buf()));
            }
        }
    }
    let mut best = None;
    for p in paths {
        walk(p, &mut best);
    }
    best
}

/// Why the bundle needs (re)building, or `None` when it is up to date.
pub fn rebuild_reason(bundle: &Path) -> Option<String> {
    let Ok(built) = std::fs::metadata(bundle).and_then(|m| m.modified()) else {
        return Some(format!("{} does not exist", bundle.display()));
    };
    match newest_input(&bundle_inputs()) {
        Some((t, path)) if t > built => Some(format!(
            "{} is newer than {}",
            path.display(),
            bundle.display()
        )),
        _ => None,
    }
}

/// Run `cargo xtask bundle trundle --release` in the workspace root, streaming its output
/// to stderr, and fail after `timeout`.
pub fn build_bundle(timeout: Duration) -> Result<(), String> {
    let cargo = env!("CARGO");
    eprintln!("[trundle-tests] building the bundle: {cargo} xtask bundle trundle --release");
    let started = Instant::now();
    let mut child = Command::new(cargo)
        .args(["xtask", "bundle", "trundle", "--release"])
        .current_dir(workspace_root())
        // The test's own package variables must not leak into the nested build.
        .env_remove("CARGO_MANIFEST_DIR")
        .env_remove("CARGO_MANIFEST_PATH")
        .env_remove("CARGO_PKG_NAME")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("could not run {cargo}: {e}"))?;
    let stderr = child.stderr.take().expect("piped");
    let echo = std::thread::spawn(move || {
        let mut blocked = false;
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            blocked |= line.contains("Blocking waiting for file lock");
            eprintln!("[xtask] {line}");
        }
        blocked
    });
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if started.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            let blocked = echo.join().unwrap_or(false);
            return Err(format!(
                "`cargo xtask bundle trundle --release` did not finish in {timeout:?}{}",
                if blocked {
                    " (it was waiting for a cargo file lock held by another build)"
                } else {
                    ""
                }
            ));
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let _ = echo.join();
    if status.success() {
        eprintln!(
            "[trundle-tests] bundle built in {:.0} s",
            started.elapsed().as_secs_f64()
        );
        Ok(())
    } else {
        Err(format!(
            "`cargo xtask bundle trundle --release` failed ({status})"
        ))
    }
}

/// The CLAP bundle to test, built first if it is missing or stale. Only one test builds;
/// the others wait for it.
pub fn ensure_clap_bundle() -> Result<PathBuf, String> {
    static BUILD: Mutex<()> = Mutex::new(());
    if let Some(path) = std::env::var_os("TRUNDLE_CLAP_BUNDLE") {
        return Ok(PathBuf::from(path));
    }
    let _guard = BUILD.lock().unwrap_or_else(|e| e.into_inner());
    let bundle = clap_bundle_path();
    if let Some(why) = rebuild_reason(&bundle) {
        eprintln!("[trundle-tests] rebuilding: {why}");
        let timeout = std::env::var("TRUNDLE_BUNDLE_TIMEOUT_S")
            .ok()
            .and_then(|s| s.parse().ok())
            .map(Duration::from_secs)
            .unwrap_or(BUILD_TIMEOUT);
        build_bundle(timeout)?;
        if !bundle.exists() {
            return Err(format!(
                "the build succeeded but {} does not exist",
                bundle.display()
            ));
        }
        if let Some(why) = rebuild_reason(&bundle) {
            // Sources edited while it built: test what was built, and say so.
            eprintln!("[trundle-tests] note: still stale after building ({why})");
        }
    }
    Ok(bundle)
}
