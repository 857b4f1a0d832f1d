//! Crash-safe file output: write to a temporary file in the destination folder, then rename
//! it into place.
//!
//! A crash, a kill or a full disk never leaves a half-written file under the final name:
//! until [`TempFile::persist`] succeeds, the destination is untouched (an existing file
//! keeps its old contents). The temporary file is hidden (`.NAME.PID.N.tmp`), lives in the
//! same folder as the destination (so the rename is atomic: same filesystem) and is removed
//! when the guard is dropped without being persisted. Only a hard kill (`SIGKILL`, power
//! loss) can leave such a hidden file behind — never a damaged destination.
//!
//! Without overwrite permission the final step is `link(2)` + `unlink(2)`, which fails if
//! the destination appeared meanwhile, instead of `rename(2)`, which would replace it: the
//! "never overwrite without `--force`" promise holds even against a file created during a
//! long render. On filesystems without hard links it falls back to check-then-rename.

use std::fs::{self, File, OpenOptions};
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// The folder a path lives in (`.` for a bare file name).
pub fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// A temporary file that is removed on drop unless persisted.
#[derive(Debug)]
pub struct TempFile {
    path: PathBuf,
    armed: bool,
}

/// Why [`TempFile::persist`] failed.
#[derive(Debug)]
pub enum PersistError {
    /// The destination exists and overwriting was not allowed.
    Exists,
    /// Any other I/O error.
    Io(io::Error),
}

static COUNTER: AtomicU32 = AtomicU32::new(0);

/// Longest part of the destination's name kept in the temporary name (file names are
/// limited to 255 bytes on most filesystems).
const NAME_KEEP: usize = 96;

impl TempFile {
    /// Create a new, empty temporary file next to `dest` (same folder), opened for reading
    /// and writing. `tag` tells temporary files of one destination apart (`"tmp"`,
    /// `"spool"`).
    pub fn create_beside(dest: &Path, tag: &str) -> io::Result<(TempFile, File)> {
        let dir = parent_dir(dest);
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "out".to_string());
        let mut short = String::new();
        for c in name.chars() {
            if short.len() + c.len_utf8() > NAME_KEEP {
                break;
            }
            short.push(c);
        }
        let pid = std::process::id();
        for _ in 0..1000 {
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let path = dir.join(format!(".{short}.{pid}.{n}.{tag}"));
            match OpenOptions::new()
                .read(true)
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(file) => return Ok((TempFile { path, armed: true }, file)),
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
        Err(io::Error::new(
            io::ErrorKind::AlreadyExists,
            "could not find a free temporary file name",
        ))
    }

    /// The temporary file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Move the (complete, synced) temporary file to `dest`. With `overwrite` an existing
    /// destination is replaced atomically; without it an existing destination is an error
    /// and stays untouched.
    pub fn persist(mut self, dest: &Path, overwrite: bool) -> Result<(), PersistError> {
        if overwrite {
            fs::rename(&self.path, dest).map_err(PersistError::Io)?;
        } else {
            match fs::hard_link(&self.path, dest) {
                Ok(()) => {
                    // The data is in place under both names; dropping the temporary name
                    // can only fail harmlessly (the guard below retries on drop).
                    if fs::remove_file(&self.path).is_ok() {
                        self.armed = false;
                    }
                    sync_dir(parent_dir(dest));
                    return Ok(());
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                    return Err(PersistError::Exists)
                }
                Err(_) => {
                    // No hard links here (FAT, some network filesystems): check, then rename.
                    if fs::symlink_metadata(dest).is_ok() {
                        return Err(PersistError::Exists);
                    }
                    fs::rename(&self.path, dest).map_err(PersistError::Io)?;
                }
            }
        }
        self.armed = false;
        sync_dir(parent_dir(dest));
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if self.armed {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Make a rename durable (best effort: not every platform can sync a folder).
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "trundle-atomic-{name}-{}-{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn persist_moves_into_place_and_leaves_nothing_behind() {
        let d = scratch("persist");
        let dest = d.join("a.wav");
        let (t, mut f) = TempFile::create_beside(&dest, "tmp").unwrap();
        f.write_all(b"new").unwrap();
        drop(f);
        t.persist(&dest, false).unwrap();
        assert_eq!(fs::read(&dest).unwrap(), b"new");
        assert_eq!(entries(&d), vec!["a.wav"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn no_overwrite_without_permission_and_overwrite_with_it() {
        let d = scratch("exists");
        let dest = d.join("a.wav");
        fs::write(&dest, b"old").unwrap();
        let (t, mut f) = TempFile::create_beside(&dest, "tmp").unwrap();
        f.write_all(b"new").unwrap();
        assert!(matches!(t.persist(&dest, false), Err(PersistError::Exists)));
        assert_eq!(fs::read(&dest).unwrap(), b"old");
        assert_eq!(
            entries(&d),
            vec!["a.wav"],
            "the failed temp file is removed"
        );
        let (t, mut f) = TempFile::create_beside(&dest, "tmp").unwrap();
        f.write_all(b"new").unwrap();
        t.persist(&dest, true).unwrap();
        assert_eq!(fs::read(&dest).unwrap(), b"new");
        assert_eq!(entries(&d), vec!["a.wav"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn dropped_guard_removes_the_temporary_file() {
        let d = scratch("drop");
        let dest = d.join("x".repeat(250));
        let (t, _f) = TempFile::create_beside(&dest, "spool").unwrap();
        assert!(t.path().exists());
        drop(t);
        assert!(entries(&d).is_empty());
        fs::remove_dir_all(&d).unwrap();
    }
}
