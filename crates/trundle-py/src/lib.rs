//! Trundle for Python: the compiled `trundle._native` module under the `trundle` package
//! (`python/trundle/__init__.py` is the documented face).
//!
//! A thin layer over `trundle-runtime`: no render loop or contact logic of its own. What it adds is what
//! Python needs: arguments taken from Python values (a preset by name, JSON text or path; a
//! `params` dict like `trundle render --set`), the runtime's errors raised as `ValueError`
//! with the runtime's message, and samples returned as numpy arrays, rendered with the GIL
//! released.
//!
//! | module | what it does |
//! |---|---|
//! | [`preset_arg`] | the `preset` argument: a built-in name, JSON text or a file |
//! | [`params_arg`] | the `params` argument: a dict of keys and values, set in order |
//! | [`renderer`] | `Renderer` (a preset streamed block by block) and `render` |
//! | [`contact`] | `Contact`, `Material`, `Listener`: the contact stream's records |
//! | [`stream`] | `ContactStream`: contacts per physics frame in, numpy audio and a voice log out |
//! | [`compare`] | `compare`: the four measures of `trundle compare` on numpy arrays |
//! | [`tables`] | `presets()` and `parameters()`: the built-in presets and the parameter table |

pub mod compare;
pub mod contact;
pub mod params_arg;
pub mod preset_arg;
pub mod renderer;
pub mod stream;
pub mod tables;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A refused argument or call as Python's `ValueError`, with the runtime's message.
pub(crate) fn value_error(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// The compiled half of the `trundle` package.
#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<renderer::Renderer>()?;
    m.add_function(wrap_pyfunction!(renderer::render, m)?)?;
    m.add_class::<stream::ContactStream>()?;
    m.add_class::<contact::Contact>()?;
    m.add_class::<contact::Material>()?;
    m.add_class::<contact::Listener>()?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(tables::presets, m)?)?;
    m.add_function(wrap_pyfunction!(tables::parameters, m)?)?;
    Ok(())
}
