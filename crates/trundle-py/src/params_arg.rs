//! The `params` argument: parameter keys and values, applied in order like `trundle render
//! --set KEY=VALUE` (a string is parsed as the command parses it, units and variant names
//! included; a number is the value itself).

use crate::value_error;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyString};
use trundle_dsp::params::spec_by_key;
use trundle_runtime::PresetRenderer;

/// Set one parameter from Python: `value` a `str` (the parameter table's text: `"off"`,
/// `"0.3 m/s"`, `"25 %"`) or an `int`/`float`. The seed is refused here: it is an argument
/// of its own, so a render cannot be given two. A refused value raises `ValueError` and
/// changes nothing.
pub fn set_from_py(
    renderer: &mut PresetRenderer,
    key: &str,
    value: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let spec = spec_by_key(key).ok_or_else(|| value_error(format!("unknown parameter {key:?}")))?;
    if spec.key == "seed" {
        return Err(value_error(
            "the seed is not a parameter here: give it as the seed argument",
        ));
    }
    if value.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "parameter {key:?}: give a number or text (e.g. \"on\"/\"off\"), not a bool"
        )));
    }
    let result = if let Ok(text) = value.cast::<PyString>() {
        renderer.set_param_text(key, &text.to_cow()?)
    } else if let Ok(number) = value.extract::<f64>() {
        renderer.set_param(spec.id, number)
    } else {
        return Err(PyTypeError::new_err(format!(
            "parameter {key:?}: give a number or text, not {}",
            value.get_type().name()?
        )));
    };
    result.map_err(value_error)
}

/// Apply a `params` dict in its order (a later key wins, as a later `--set` does). Keys
/// must be `str`.
pub fn set_all_from_py(renderer: &mut PresetRenderer, params: &Bound<'_, PyDict>) -> PyResult<()> {
    for (key, value) in params.iter() {
        let key = key
            .cast::<PyString>()
            .map_err(|_| PyTypeError::new_err("params keys must be str (parameter keys)"))?
            .to_cow()?
            .into_owned();
        set_from_py(renderer, &key, &value)?;
    }
    Ok(())
}
