//! The `preset` argument: a built-in preset's name, a preset as JSON text, or a preset file
//! (a `str` naming a file as `trundle render --preset` does, or any `os.PathLike`).

use crate::value_error;
use pyo3::prelude::*;
use pyo3::types::PyString;
use std::path::{Path, PathBuf};
use trundle_dsp::scene::preset::DEFAULT_PRESET;
use trundle_io::preset_file::read_preset_file;
use trundle_runtime::{load_preset, Preset};

/// Whether a preset given as text names a file: the command's rule (`trundle render
/// --preset`), a path separator or a `.json` ending. JSON text (first non-blank character
/// `{`) never does.
pub fn names_a_file(text: &str) -> bool {
    !text.trim_start().starts_with('{')
        && (text.contains('/')
            || text.contains(std::path::MAIN_SEPARATOR)
            || text.ends_with(".json"))
}

/// The preset a Python value stands for (`None`: the default preset); a name, text or file the model refuses raises
/// `ValueError` with its reason (a file's errors name the file, as the command's do).
///
/// # Allocation
/// Allocates and may read a file (at most `trundle_io`'s preset cap, 1 MiB).
pub fn preset_from_py(value: Option<&Bound<'_, PyAny>>) -> PyResult<Preset> {
    let Some(value) = value else {
        return load_preset(DEFAULT_PRESET).map_err(value_error);
    };
    if let Ok(text) = value.cast::<PyString>() {
        let text = text.to_cow()?;
        let text: &str = &text;
        return if names_a_file(text) {
            preset_from_file(Path::new(text))
        } else {
            load_preset(text).map_err(|e| {
                value_error(format!(
                    "{e}; to load a file, give a path containing '/' or ending in .json"
                ))
            })
        };
    }
    let path: PathBuf = value.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(
            "preset must be a str (a built-in name, JSON text or a path) or an os.PathLike",
        )
    })?;
    preset_from_file(&path)
}

fn preset_from_file(path: &Path) -> PyResult<Preset> {
    read_preset_file(path).map_err(|e| value_error(format!("preset: {e}")))
}
