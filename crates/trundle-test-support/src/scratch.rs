//! Scratch folders: fresh and empty when made, removed when the test passes (kept, and
//! named on standard error, when it fails, for a look at what was written).

use std::fs;
use std::ops::Deref;
use std::path::{Path, PathBuf};

/// A fresh, empty folder `trundle-tests/<test file>/<name>-<process id>` under the system's
/// temporary directory; removed on drop unless the thread is panicking.
#[derive(Debug)]
pub struct Scratch {
    path: PathBuf,
}

/// A fresh scratch folder `name` of the running test file (named for the test executable,
/// `presets` for `tests/presets.rs`); `name` must be unique within the file.
pub fn scratch(name: &str) -> Scratch {
    let exe = std::env::current_exe().expect("the test executable's path");
    let stem = exe.file_stem().and_then(|s| s.to_str()).unwrap_or("test");
    let group = stem.split('-').next().unwrap_or(stem);
    let path = std::env::temp_dir()
        .join("trundle-tests")
        .join(group)
        .join(format!("{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&path);
    fs::create_dir_all(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    Scratch { path }
}

impl Scratch {
    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("scratch folder kept: {}", self.path.display());
        } else {
            let _ = fs::remove_dir_all(&self.path);
        }
    }
}
