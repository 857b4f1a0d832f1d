//! Fitted object files (`*.object.json`, written by `trundle fit-object`): read with a
//! size cap, parsed and validated by the model ([`fitted::from_json`]).
//!
//! The same reader serves `trundle render --object`, `trundle fit-roll --object` and the
//! plugin's Load… ([`read_object_file`]); the plugin's saved state, which carries the
//! object file's text, goes through [`parse_object_text`].

use crate::file_error::{read_capped_text, FileError, FileKind, Problem};
use std::path::Path;
use std::sync::Arc;
use trundle_dsp::object::fitted::{self, LoadedObject, ObjectFile};

pub use crate::file_error::MAX_OBJECT_BYTES;

/// Parse an object file's text: the object, or why it is unusable ([`Problem::Json`] or
/// [`Problem::Values`], the latter naming the field at fault).
pub fn parse_object_text(text: &str) -> Result<ObjectFile, Problem> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| Problem::Json(FileKind::Object, e.to_string()))?;
    let (object, source) = fitted::from_json(&value).map_err(Problem::Values)?;
    Ok(ObjectFile { object, source })
}

/// Read and validate the object file `path` (at most [`MAX_OBJECT_BYTES`]).
pub fn read_object_file(path: &Path) -> Result<ObjectFile, FileError> {
    let text = read_capped_text(path, FileKind::Object)?;
    parse_object_text(&text).map_err(|p| FileError::new(path, p))
}

/// Read the object file `path` and prepare it for the voice ([`LoadedObject::shared`]);
/// an object the voice refuses is a [`Problem::Values`] error.
pub fn read_loaded_object(path: &Path) -> Result<Arc<LoadedObject>, FileError> {
    let file = read_object_file(path)?;
    LoadedObject::shared(file).map_err(|e| FileError::new(path, Problem::Values(e)))
}
