//! Trundle's file layer: what the plugin and the `trundle` command read from disk, read
//! the same way by both.
//!
//! * [`object_file`]: fitted objects (`*.object.json`, written by `trundle fit-object`),
//!   at most [`object_file::MAX_OBJECT_BYTES`].
//! * [`preset_file`]: preset files (the versioned JSON of `presets/*.json`), at most
//!   [`preset_file::MAX_PRESET_BYTES`].
//! * [`recording`]: the one decoder for recordings — WAV, FLAC and OGG/Vorbis through
//!   symphonia, mixed to mono or kept per channel, at most
//!   [`recording::MAX_RECORDING_SECONDS`] long.
//!
//! Every error names the file and the problem ([`FileError`], [`recording::RecordingError`]):
//! missing, a folder, too large, not UTF-8, bad JSON, bad values. The model crate,
//! `trundle-dsp`, parses and validates the formats and does no file I/O; this crate brings
//! it the bytes. Nothing here is real-time safe: call it from the GUI, a worker thread or
//! the command, never from `process`.

pub mod file_error;
pub mod object_file;
pub mod preset_file;
pub mod recording;
#[cfg(feature = "test-files")]
pub mod test_files;

pub use file_error::{quote, FileError, FileKind, Problem};
