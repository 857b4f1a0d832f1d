//! Reading a small text file with a size cap, and the errors of the file readers.
//!
//! A capped read stops after `cap + 1` bytes, so a wrong path (`/dev/zero`, a recording
//! given where an object file belongs) costs at most the cap in memory and time.

use std::fmt;
use std::fs::File;
use std::io::{self, Read};
use std::path::{Path, PathBuf};

/// Largest object file read: 16 MiB (a fitted object of 2000 modes is about 300 KiB).
pub const MAX_OBJECT_BYTES: u64 = 16 << 20;

/// Largest preset file read: 1 MiB (presets are a few hundred bytes, a few hundred KiB with
/// an embedded fitted object; the cap stops `/dev/zero` or a recording given by mistake).
pub const MAX_PRESET_BYTES: u64 = 1 << 20;

/// What kind of file a reader expected (its name in messages and its size cap).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A fitted object (`*.object.json`).
    Object,
    /// A preset file.
    Preset,
}

impl FileKind {
    /// "object file" / "preset file".
    pub fn noun(self) -> &'static str {
        match self {
            FileKind::Object => "object file",
            FileKind::Preset => "preset file",
        }
    }

    /// "an object file" / "a preset file".
    pub fn name(self) -> &'static str {
        match self {
            FileKind::Object => "an object file",
            FileKind::Preset => "a preset file",
        }
    }

    /// The largest file of this kind read (bytes).
    pub fn max_bytes(self) -> u64 {
        match self {
            FileKind::Object => MAX_OBJECT_BYTES,
            FileKind::Preset => MAX_PRESET_BYTES,
        }
    }

    /// The cap as people read it: "16 MiB", "1024 KiB".
    pub fn cap_text(self) -> String {
        match self {
            FileKind::Object => format!("{} MiB", self.max_bytes() >> 20),
            FileKind::Preset => format!("{} KiB", self.max_bytes() >> 10),
        }
    }
}

/// What is wrong with a file (without its name: [`FileError`] adds it).
#[derive(Debug)]
pub enum Problem {
    /// The file cannot be opened (missing, no permission).
    Open(io::Error),
    /// The path is a folder.
    Folder,
    /// Reading failed part-way.
    Read(io::Error),
    /// Larger than the kind's cap.
    TooLarge(FileKind),
    /// Not UTF-8 text.
    NotUtf8(FileKind),
    /// Not JSON (the parser's message).
    Json(FileKind, String),
    /// JSON, but a field or value is refused (the model's message, naming the field).
    Values(String),
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Problem::Open(e) => write!(f, "cannot open: {e}"),
            Problem::Folder => write!(f, "is a folder"),
            Problem::Read(e) => write!(f, "cannot read: {e}"),
            Problem::TooLarge(kind) => {
                write!(f, "larger than {}: not {}", kind.cap_text(), kind.name())
            }
            Problem::NotUtf8(kind) => write!(f, "not UTF-8 text: not {}", kind.name()),
            Problem::Json(kind, e) => write!(f, "not a valid {} (JSON: {e})", kind.noun()),
            Problem::Values(e) => write!(f, "{e}"),
        }
    }
}

/// A file that could not be read as what it should be: the file and the problem.
#[derive(Debug)]
pub struct FileError {
    /// The file as given.
    pub path: PathBuf,
    /// What is wrong with it.
    pub problem: Problem,
}

impl FileError {
    /// The error of `problem` in `path`.
    pub fn new(path: &Path, problem: Problem) -> Self {
        Self {
            path: path.to_path_buf(),
            problem,
        }
    }
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {}",
            quote(&self.path.display().to_string()),
            self.problem
        )
    }
}

impl std::error::Error for FileError {}

/// Quote user-supplied text for an error message (control characters escaped).
pub fn quote(text: &str) -> String {
    let mut s = String::with_capacity(text.len() + 2);
    s.push('\'');
    for c in text.chars() {
        if c.is_control() {
            s.extend(c.escape_default());
        } else {
            s.push(c);
        }
    }
    s.push('\'');
    s
}

/// Read `path` as UTF-8 text of at most `kind`'s cap ([`FileKind::max_bytes`]).
pub fn read_capped_text(path: &Path, kind: FileKind) -> Result<String, FileError> {
    let fail = |problem| FileError::new(path, problem);
    if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
        return Err(fail(Problem::Folder));
    }
    let file = File::open(path).map_err(|e| fail(Problem::Open(e)))?;
    let cap = kind.max_bytes();
    let mut bytes = Vec::new();
    file.take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(Problem::Read(e)))?;
    if bytes.len() as u64 > cap {
        return Err(fail(Problem::TooLarge(kind)));
    }
    String::from_utf8(bytes).map_err(|_| fail(Problem::NotUtf8(kind)))
}
