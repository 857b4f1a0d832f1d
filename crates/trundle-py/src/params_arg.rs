//! The `params` argument: parameter keys and values, applied in order like `trundle render
//! --set KEY=VALUE` (a string is parsed as the command parses it, units and variant names
//! included; a number is the value itself).

use crate::value_error;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyString};
use trundle_dsp::params::{spec_by_key, ParamSpec};
use trundle_dsp::Params;
use trundle_runtime::{PresetRenderer, RuntimeError};

/// A parameter value as Python gives it.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValue {
    /// Text in the parameter table's format (`"off"`, `"0.3 m/s"`, `"25 %"`).
    Text(String),
    /// The value itself (a choice's index).
    Number(f64),
}

/// What a parameter can be set on.
pub trait SetParam {
    /// Set `spec`'s parameter to `value`; a refused value changes nothing.
    fn set_value(&mut self, spec: &ParamSpec, value: &ParamValue) -> Result<(), RuntimeError>;
}

impl SetParam for PresetRenderer {
    fn set_value(&mut self, spec: &ParamSpec, value: &ParamValue) -> Result<(), RuntimeError> {
        match value {
            ParamValue::Text(text) => self.set_param_text(spec.key, text),
            ParamValue::Number(v) => self.set_param(spec.id, *v),
        }
    }
}

impl SetParam for Params {
    fn set_value(&mut self, spec: &ParamSpec, value: &ParamValue) -> Result<(), RuntimeError> {
        match value {
            ParamValue::Text(text) => self.set_text(spec.key, text)?,
            ParamValue::Number(v) => self.set(spec.id, *v)?,
        }
        Ok(())
    }
}

/// A Python value as a [`ParamValue`] of `key`: a `str` or an `int`/`float` (a `bool`, a
/// list… raise `TypeError`).
pub fn value_from_py(key: &str, value: &Bound<'_, PyAny>) -> PyResult<ParamValue> {
    if value.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "parameter {key:?}: give a number or text (e.g. \"on\"/\"off\"), not a bool"
        )));
    }
    if let Ok(text) = value.cast::<PyString>() {
        Ok(ParamValue::Text(text.to_cow()?.into_owned()))
    } else if let Ok(number) = value.extract::<f64>() {
        Ok(ParamValue::Number(number))
    } else {
        Err(PyTypeError::new_err(format!(
            "parameter {key:?}: give a number or text, not {}",
            value.get_type().name()?
        )))
    }
}

/// Set one parameter from Python. The seed is refused here: it is an argument of its own,
/// so nothing can be given two. A refused value raises `ValueError` and changes nothing.
pub fn set_from_py(
    target: &mut impl SetParam,
    key: &str,
    value: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let spec = spec_by_key(key).ok_or_else(|| value_error(format!("unknown parameter {key:?}")))?;
    if spec.key == "seed" {
        return Err(value_error(
            "the seed is not a parameter here: give it as the seed argument",
        ));
    }
    let value = value_from_py(key, value)?;
    target.set_value(spec, &value).map_err(value_error)
}

/// Apply a `params` dict in its order (a later key wins, as a later `--set` does). Keys
/// must be `str`.
pub fn set_all_from_py(target: &mut impl SetParam, params: &Bound<'_, PyDict>) -> PyResult<()> {
    for (key, value) in params.iter() {
        let key = key
            .cast::<PyString>()
            .map_err(|_| PyTypeError::new_err("params keys must be str (parameter keys)"))?
            .to_cow()?
            .into_owned();
        set_from_py(target, &key, &value)?;
    }
    Ok(())
}
