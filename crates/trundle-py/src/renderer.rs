//! `Renderer`, a preset rendered as a stream into numpy arrays, and `render`, a whole
//! render in one call: both are `trundle_runtime::PresetRenderer` (the command's render
//! path), with Python's arguments and arrays around it.
//!
//! The output is the engine's level as the preset sets it: no normalization, and the safety
//! limiter only when the preset's `limiter` is on (then its look-ahead delay is in the
//! output, as in the plugin). With `params={"limiter": "off"}` the samples equal those of
//! `trundle render --seconds S --seed N --no-normalize --set limiter=off --format f32`.

use crate::params_arg::{set_all_from_py, set_from_py};
use crate::preset_arg::preset_from_py;
use crate::value_error;
use numpy::{PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use trundle_runtime::PresetRenderer;

/// Longest render of one call (s): the command's `--seconds` limit.
pub const MAX_SECONDS: f64 = 86_400.0;

/// Frames rendered between two looks for Ctrl-C (the GIL is released while they render).
const FRAMES_PER_SLICE: usize = 1 << 16;

/// Frames of the left and right scratch buffers interleaved into the array.
const SCRATCH_FRAMES: usize = 4096;

/// A preset rendered block after block, for streaming and for changing parameters between
/// blocks.
///
/// `Renderer(preset="default", seed=1, sample_rate=48000, params=None)`: `preset` is a
/// built-in name (see `presets()`), JSON text or a preset file (a path containing `/` or
/// ending in `.json`, or an `os.PathLike`); `params` a dict of parameter keys and values
/// applied in order like `trundle render --set` (see `parameters()`). Bad arguments raise
/// `ValueError` with the reason.
#[pyclass(module = "trundle")]
pub struct Renderer {
    inner: PresetRenderer,
    left: Vec<f32>,
    right: Vec<f32>,
}

#[pymethods]
impl Renderer {
    #[new]
    #[pyo3(
        signature = (preset = None, seed = 1, sample_rate = 48_000.0, params = None),
        text_signature = "(preset='default', seed=1, sample_rate=48000, params=None)"
    )]
    fn new(
        preset: Option<&Bound<'_, PyAny>>,
        seed: i64,
        sample_rate: f64,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let preset = preset_from_py(preset)?;
        let seed = u64::try_from(seed)
            .map_err(|_| value_error(format!("seed must be 0 or more, got {seed}")))?;
        let mut inner = PresetRenderer::new(&preset, sample_rate, seed).map_err(value_error)?;
        if let Some(params) = params {
            set_all_from_py(&mut inner, params)?;
        }
        Ok(Self {
            inner,
            left: vec![0.0; SCRATCH_FRAMES],
            right: vec![0.0; SCRATCH_FRAMES],
        })
    }

    /// Set one parameter: `value` a number, or text as `trundle render --set` takes it
    /// (`"off"`, `"0.3 m/s"`). Before the first frame the render starts from it; later the
    /// sound glides to it. A refused value raises `ValueError` and changes nothing.
    fn set(&mut self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        set_from_py(&mut self.inner, key, value)
    }

    /// The next `frames` stereo frames as a float32 array of shape `(frames, 2)` (left,
    /// right); the render continues where the last call stopped.
    fn render<'py>(
        &mut self,
        py: Python<'py>,
        frames: usize,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let array = empty_stereo(py, frames)?;
        {
            let mut view = array.readwrite();
            let out = view
                .as_slice_mut()
                .map_err(|e| value_error(format!("output array: {e}")))?;
            self.render_into(py, out)?;
        }
        Ok(array)
    }

    /// Frames rendered so far.
    #[getter]
    fn frames_done(&self) -> u64 {
        self.inner.frames_done()
    }

    /// The sample rate (Hz).
    #[getter]
    fn sample_rate(&self) -> f64 {
        self.inner.sample_rate_hz()
    }

    /// The safety limiter's delay (frames) when `limiter` is on, else 0.
    #[getter]
    fn latency_frames(&self) -> usize {
        self.inner.latency_frames()
    }

    /// A parameter's current value (a choice as its index), by key.
    fn get(&self, key: &str) -> PyResult<f64> {
        let spec = trundle_dsp::params::spec_by_key(key)
            .ok_or_else(|| value_error(format!("unknown parameter {key:?}")))?;
        Ok(self.inner.params().get(spec.id))
    }

    fn __repr__(&self) -> String {
        format!(
            "Renderer(sample_rate={}, frames_done={})",
            self.inner.sample_rate_hz(),
            self.inner.frames_done()
        )
    }
}

impl Renderer {
    /// Render into `out` (interleaved stereo frames) slice by slice, the GIL released while
    /// a slice renders and Ctrl-C looked for between slices.
    fn render_into(&mut self, py: Python<'_>, out: &mut [f32]) -> PyResult<()> {
        for slice in out.chunks_mut(2 * FRAMES_PER_SLICE) {
            let Self { inner, left, right } = self;
            py.detach(|| {
                for frames in slice.chunks_mut(2 * SCRATCH_FRAMES) {
                    let n = frames.len() / 2;
                    let (l, r) = (&mut left[..n], &mut right[..n]);
                    inner.render(l, r)?;
                    interleave(frames, l, r);
                }
                Ok::<_, trundle_runtime::RuntimeError>(())
            })
            .map_err(value_error)?;
            py.check_signals()?;
        }
        Ok(())
    }
}

/// `left` and `right` into `out` as interleaved frames (`out.len()` = 2 × their length).
pub(crate) fn interleave(out: &mut [f32], left: &[f32], right: &[f32]) {
    for ((frame, &a), &b) in out.chunks_exact_mut(2).zip(left).zip(right) {
        frame[0] = a;
        frame[1] = b;
    }
}

/// A new, uninitialized float32 array of `frames` stereo frames, through numpy (so a size
/// that does not fit in memory raises `MemoryError` instead of aborting).
pub(crate) fn empty_stereo(py: Python<'_>, frames: usize) -> PyResult<Bound<'_, PyArray2<f32>>> {
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float32")?)?;
    let shape = PyTuple::new(py, [frames, 2])?;
    let array = numpy.getattr("empty")?.call((shape,), Some(&kwargs))?;
    Ok(array.cast_into::<PyArray2<f32>>()?)
}

/// Frames in `seconds` at `sample_rate_hz`, as the command counts them (rounded); refuses
/// non-finite, non-positive, too long or shorter than one frame.
pub fn frames_for(seconds: f64, sample_rate_hz: f64) -> Result<usize, String> {
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= MAX_SECONDS) {
        return Err(format!(
            "seconds must be more than 0 and at most {MAX_SECONDS}, got {seconds}"
        ));
    }
    let frames = (seconds * sample_rate_hz).round();
    if frames.is_nan() || frames < 1.0 {
        return Err(format!(
            "seconds={seconds} is shorter than one frame at {sample_rate_hz} Hz"
        ));
    }
    Ok(frames as usize)
}

/// `seconds` of `preset` as a float32 array of shape `(frames, 2)` (left, right), frames =
/// round(seconds × sample_rate). The engine's level, no normalization; the safety limiter
/// only if the preset's `limiter` is on. See `Renderer` for the arguments.
#[pyfunction]
#[pyo3(
    signature = (preset = None, seconds = 2.0, seed = 1, sample_rate = 48_000.0, params = None),
    text_signature = "(preset='default', seconds=2.0, seed=1, sample_rate=48000, params=None)"
)]
pub fn render<'py>(
    py: Python<'py>,
    preset: Option<&Bound<'py, PyAny>>,
    seconds: f64,
    seed: i64,
    sample_rate: f64,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let mut renderer = Renderer::new(preset, seed, sample_rate, params)?;
    let frames = frames_for(seconds, sample_rate).map_err(value_error)?;
    renderer.render(py, frames)
}
