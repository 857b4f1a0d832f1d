//! `compare(recording, candidate, ...)`: the judge of `trundle compare` (the four measures of
//! `trundle_dsp::analysis::compare`, docs/guide/compare.md) on numpy arrays, for notebooks
//! and dataset pipelines. No measure of its own: the arrays are mixed to mono (as the command
//! reads files) and handed to the same function.

use crate::value_error;
use numpy::{PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use trundle_dsp::analysis::compare::{compare as judge, Verdict};

/// A 1-D array (mono) or a 2-D array of shape (frames, channels), mixed to mono.
fn mono(x: &PyReadonlyArrayDyn<'_, f64>, which: &str) -> PyResult<Vec<f64>> {
    let view = x.as_array();
    match x.ndim() {
        1 => Ok(view.iter().copied().collect()),
        2 => {
            let (frames, channels) = (x.shape()[0], x.shape()[1]);
            if channels == 0 {
                return Err(value_error(format!("{which} has no channels")));
            }
            Ok((0..frames)
                .map(|i| (0..channels).map(|c| view[[i, c]]).sum::<f64>() / channels as f64)
                .collect())
        }
        n => Err(value_error(format!(
            "{which} must be 1-D (mono) or 2-D (frames, channels), not {n}-D"
        ))),
    }
}

fn verdict<'py>(py: Python<'py>, v: &Verdict) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("value", v.value)?;
    d.set_item("limit", v.limit)?;
    d.set_item("passed", v.passed)?;
    Ok(d)
}

/// Judge `candidate` against `recording` by the four measures of `trundle compare`: a dict
/// with `passed`, `measures_passed`, `loss` and, per measure (`spectrum`, `modulation`,
/// `texture`, `kurtosis_ratio`, `crest_db`), its value, limit and verdict. Arrays are float
/// (any float dtype is converted), mono or (frames, channels); rates in Hz
/// (`candidate_rate` defaults to `recording_rate`). Raises `ValueError` for a sound under
/// 0.5 s, silent or non-finite, or an unusable rate.
#[pyfunction]
#[pyo3(signature = (recording, candidate, recording_rate, candidate_rate = None))]
pub fn compare<'py>(
    py: Python<'py>,
    recording: PyReadonlyArrayDyn<'py, f64>,
    candidate: PyReadonlyArrayDyn<'py, f64>,
    recording_rate: f64,
    candidate_rate: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let r = mono(&recording, "recording")?;
    let c = mono(&candidate, "candidate")?;
    let c_rate = candidate_rate.unwrap_or(recording_rate);
    let cmp = py
        .detach(|| judge(&r, recording_rate, &c, c_rate))
        .map_err(value_error)?;
    let d = PyDict::new(py);
    d.set_item("passed", cmp.passed())?;
    d.set_item("measures_passed", cmp.measures_passed())?;
    d.set_item("loss", cmp.loss())?;
    d.set_item("top_hz", cmp.reference.top_hz)?;
    d.set_item("spectrum", verdict(py, &cmp.spectrum)?)?;
    d.set_item("modulation", verdict(py, &cmp.modulation)?)?;
    d.set_item("texture", verdict(py, &cmp.texture)?)?;
    d.set_item("kurtosis_ratio", verdict(py, &cmp.kurtosis)?)?;
    d.set_item("crest_db", verdict(py, &cmp.crest)?)?;
    d.set_item("impulsiveness_passed", cmp.impulsiveness_passed())?;
    Ok(d)
}
