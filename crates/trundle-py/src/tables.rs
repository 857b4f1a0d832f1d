//! What there is to render and to set: the built-in presets and the parameter table, as
//! Python lists.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use trundle_dsp::params::{ParamKind, PARAMS};
use trundle_dsp::scene::preset::BUILTIN_PRESETS;

/// The built-in presets' names, as `trundle presets` lists them.
#[pyfunction]
pub fn presets() -> Vec<&'static str> {
    BUILTIN_PRESETS.iter().map(|(name, _)| *name).collect()
}

/// The parameter table, one dict per parameter: `key`, `name`, `unit`, `min`, `max`,
/// `default`, `kind` (`"float"`, `"int"` or `"choice"`), `choices` (the variant names, or
/// `None`) and `doc`, as `trundle params` lists them.
#[pyfunction]
pub fn parameters(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    PARAMS
        .iter()
        .map(|spec| {
            let row = PyDict::new(py);
            row.set_item("key", spec.key)?;
            row.set_item("name", spec.name)?;
            row.set_item("unit", spec.unit)?;
            row.set_item("min", spec.min)?;
            row.set_item("max", spec.max)?;
            row.set_item("default", spec.default)?;
            let (kind, choices) = match spec.kind {
                ParamKind::Float { .. } => ("float", None),
                ParamKind::Int => ("int", None),
                ParamKind::Enum(names) => ("choice", Some(names.to_vec())),
            };
            row.set_item("kind", kind)?;
            row.set_item("choices", choices)?;
            row.set_item("doc", spec.doc)?;
            Ok(row)
        })
        .collect()
}
