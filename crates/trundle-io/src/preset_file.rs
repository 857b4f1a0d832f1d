//! Preset files (the versioned JSON of `presets/*.json` and of the plugin's user presets):
//! read with a size cap, parsed and validated by the model ([`Preset::from_json`]).
//!
//! The same reader serves `trundle render --preset FILE` (and every command that takes a
//! preset) and the plugin's user preset browser.

use crate::file_error::{read_capped_text, FileError, FileKind, Problem};
use std::path::Path;
use trundle_dsp::scene::preset::Preset;

pub use crate::file_error::MAX_PRESET_BYTES;

/// Read and validate the preset file `path` (at most [`MAX_PRESET_BYTES`]); a preset the
/// model refuses (bad JSON included) is a [`Problem::Values`] error with its message.
pub fn read_preset_file(path: &Path) -> Result<Preset, FileError> {
    let text = read_capped_text(path, FileKind::Preset)?;
    Preset::from_json(&text).map_err(|e| FileError::new(path, Problem::Values(e.to_string())))
}
