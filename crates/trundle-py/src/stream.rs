//! `ContactStream`: a physics engine's contacts, frame by frame, in; one continuous,
//! positioned sound per touching pair out, as numpy arrays (`trundle_runtime::ContactStream`
//! with Python's arguments around it).

use crate::contact::{Contact, Listener, Material};
use crate::params_arg::set_all_from_py;
use crate::value_error;
use numpy::{PyArray2, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};
use trundle_runtime as rt;
use trundle_runtime::{ContactStream as Stream, EndReason, EventKind, StreamSettings};

/// A physics engine's contacts in, one continuous sound per touching pair out.
///
/// `ContactStream(materials=None, sample_rate=48000, frame_rate=60, max_pairs=64,
/// max_voices=8, seed=1, impact_gain=0.2, params=None, listener=None, hold=None,
/// mapping=None)`. `materials` lists what bodies are made of (`Material`s, or the names
/// `"wood"`, `"metal"`, `"glass"`; default `["wood"]`), indexed by `Contact.materials`.
/// `params` are the controls every voice starts from (as `render`'s). `hold` (keys
/// `dropout_frames`, `linger_frames`, `rest_frames`) and `mapping` (keys `impact_speed_m_s`,
/// `rest_speed_m_s`, `rub_slip`, `full_size_radius_m`, `reference_load_n`, `speed_scale`)
/// override the runtime's defaults. Each physics frame: `update(contacts)`, then
/// `render(frames)` for the audio until the next frame.
#[pyclass(module = "trundle")]
pub struct ContactStream {
    inner: Stream,
    left: Vec<f32>,
    right: Vec<f32>,
    contacts: Vec<rt::Contact>,
}

/// Frames of the scratch buffers interleaved into the output.
const SCRATCH_FRAMES: usize = 4096;

#[pymethods]
impl ContactStream {
    #[new]
    #[pyo3(signature = (materials = None, sample_rate = 48_000.0, frame_rate = 60.0, max_pairs = 64, max_voices = 8, seed = 1, impact_gain = 0.2, params = None, listener = None, hold = None, mapping = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        materials: Option<&Bound<'_, PyAny>>,
        sample_rate: f64,
        frame_rate: f64,
        max_pairs: usize,
        max_voices: usize,
        seed: i64,
        impact_gain: f64,
        params: Option<&Bound<'_, PyDict>>,
        listener: Option<PyRef<'_, Listener>>,
        hold: Option<&Bound<'_, PyDict>>,
        mapping: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let materials = match materials {
            Some(list) => materials_from_py(list)?,
            None => vec![rt::Material::wood()],
        };
        let mut settings = StreamSettings {
            sample_rate_hz: sample_rate,
            frame_rate_hz: frame_rate,
            max_pairs,
            max_voices,
            seed: u64::try_from(seed)
                .map_err(|_| value_error(format!("seed must be 0 or more, got {seed}")))?,
            impact_gain,
            ..StreamSettings::default()
        };
        if let Some(params) = params {
            set_all_from_py(&mut settings.base, params)?;
        }
        if let Some(listener) = listener {
            settings.listener = listener.inner;
        }
        if let Some(hold) = hold {
            hold_from_py(&mut settings.hold, hold)?;
        }
        if let Some(mapping) = mapping {
            mapping_from_py(&mut settings.mapping, mapping)?;
        }
        let inner = Stream::new(settings, &materials).map_err(value_error)?;
        Ok(Self {
            inner,
            left: vec![0.0; SCRATCH_FRAMES],
            right: vec![0.0; SCRATCH_FRAMES],
            contacts: Vec::with_capacity(max_pairs),
        })
    }

    /// One physics frame: every `Contact` touching now (an iterable). All are checked
    /// first: a bad one (NaN, negative radius, unknown material, a pair given twice, more
    /// pairs than `max_pairs`) raises `ValueError` and nothing changes.
    fn update(&mut self, contacts: &Bound<'_, PyAny>) -> PyResult<()> {
        self.contacts.clear();
        for item in contacts.try_iter()? {
            let item = item?;
            let contact = item
                .cast::<Contact>()
                .map_err(|_| PyTypeError::new_err("update takes an iterable of trundle.Contact"))?;
            self.contacts.push(contact.borrow().inner);
        }
        self.inner.update(&self.contacts).map_err(value_error)
    }

    /// The next `frames` stereo frames, float32 of shape `(frames, 2)` (the GIL released
    /// while they render).
    fn render<'py>(
        &mut self,
        py: Python<'py>,
        frames: usize,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let array = crate::renderer::empty_stereo(py, frames)?;
        {
            let mut view = array.readwrite();
            let out = view
                .as_slice_mut()
                .map_err(|e| value_error(format!("output array: {e}")))?;
            let Self {
                inner, left, right, ..
            } = self;
            py.detach(|| {
                for block in out.chunks_mut(2 * SCRATCH_FRAMES) {
                    let n = block.len() / 2;
                    let (l, r) = (&mut left[..n], &mut right[..n]);
                    inner.render(l, r)?;
                    crate::renderer::interleave(block, l, r);
                }
                Ok::<_, rt::RuntimeError>(())
            })
            .map_err(value_error)?;
        }
        Ok(array)
    }

    /// The voice log since the last call, oldest first: dicts with `frame` (the physics
    /// frame), `voice` (numbered in start order, never reused), `pair`, `body` and `kind`:
    /// `"start"`, `"impact"` (with `speed_m_s`), `"roll"`, `"rub"` (the action changed) or
    /// `"end"` (with `reason`: `"rest"`, `"lost"`, `"removed"`).
    fn events<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let mut list = Vec::new();
        self.inner.drain_events(|e| list.push(*e));
        let out = PyList::empty(py);
        for e in list {
            let d = PyDict::new(py);
            d.set_item("frame", e.frame)?;
            d.set_item("voice", e.voice)?;
            d.set_item("pair", e.pair)?;
            d.set_item("body", e.body)?;
            match e.kind {
                EventKind::Start => d.set_item("kind", "start")?,
                EventKind::Impact(speed) => {
                    d.set_item("kind", "impact")?;
                    d.set_item("speed_m_s", speed)?;
                }
                EventKind::Motion(kind) => d.set_item("kind", kind.name())?,
                EventKind::End(reason) => {
                    d.set_item("kind", "end")?;
                    d.set_item(
                        "reason",
                        match reason {
                            EndReason::Rest => "rest",
                            EndReason::Lost => "lost",
                            EndReason::Removed => "removed",
                        },
                    )?;
                }
            }
            out.append(d)?;
        }
        Ok(out)
    }

    /// End the voice of `pair` now (it rings out); an unknown pair raises `ValueError`.
    fn remove_pair(&mut self, pair: u64) -> PyResult<()> {
        self.inner.remove_pair(pair).map_err(value_error)
    }

    /// Move the listener (the image follows from the next frame).
    fn set_listener(&mut self, listener: PyRef<'_, Listener>) -> PyResult<()> {
        self.inner.set_listener(listener.inner).map_err(value_error)
    }

    /// Voices started since construction (one per touching pair, however long it touched).
    #[getter]
    fn voices_started(&self) -> u64 {
        self.inner.voices_started()
    }

    /// Voices sounding now (their own contact, ringing out, or the crowd's).
    #[getter]
    fn voices_sounding(&self) -> usize {
        self.inner.voices_sounding()
    }

    /// Contacts merged into the crowd voice in the last frame (beyond `max_voices`).
    #[getter]
    fn crowd_count(&self) -> usize {
        self.inner.crowd_count()
    }

    /// Events lost because `events()` was not called in time.
    #[getter]
    fn dropped_events(&self) -> u64 {
        self.inner.dropped_events()
    }

    /// The audio sample rate (Hz).
    #[getter]
    fn sample_rate(&self) -> f64 {
        self.inner.settings().sample_rate_hz
    }

    /// Physics frames per second.
    #[getter]
    fn frame_rate(&self) -> f64 {
        self.inner.settings().frame_rate_hz
    }
}

/// The stream's materials from a list of `Material`s or names.
fn materials_from_py(list: &Bound<'_, PyAny>) -> PyResult<Vec<rt::Material>> {
    let mut out = Vec::new();
    for item in list.try_iter()? {
        let item = item?;
        if let Ok(m) = item.cast::<Material>() {
            out.push(m.borrow().inner);
        } else if let Ok(name) = item.cast::<PyString>() {
            out.push(match &*name.to_cow()? {
                "wood" => rt::Material::wood(),
                "metal" => rt::Material::metal(),
                "glass" => rt::Material::glass(),
                other => {
                    return Err(value_error(format!(
                        "unknown material {other:?}: give \"wood\", \"metal\", \"glass\" or a trundle.Material"
                    )))
                }
            });
        } else {
            return Err(PyTypeError::new_err(
                "materials must be trundle.Material objects or names",
            ));
        }
    }
    Ok(out)
}

/// Each `(key, value)` of a settings dict, the key as text.
fn entries<'py>(d: &Bound<'py, PyDict>) -> PyResult<Vec<(String, Bound<'py, PyAny>)>> {
    d.iter()
        .map(|(k, v)| {
            let k = k
                .cast::<PyString>()
                .map_err(|_| PyTypeError::new_err("settings keys must be str"))?
                .to_cow()?
                .into_owned();
            Ok((k, v))
        })
        .collect()
}

fn hold_from_py(hold: &mut rt::Hold, d: &Bound<'_, PyDict>) -> PyResult<()> {
    for (key, value) in entries(d)? {
        let v: u32 = value.extract()?;
        match key.as_str() {
            "dropout_frames" => hold.dropout_frames = v,
            "linger_frames" => hold.linger_frames = v,
            "rest_frames" => hold.rest_frames = v,
            _ => return Err(value_error(format!("unknown hold setting {key:?}"))),
        }
    }
    Ok(())
}

fn mapping_from_py(mapping: &mut rt::Mapping, d: &Bound<'_, PyDict>) -> PyResult<()> {
    for (key, value) in entries(d)? {
        let v: f64 = value.extract()?;
        let field = match key.as_str() {
            "impact_speed_m_s" => &mut mapping.impact_speed_m_s,
            "rest_speed_m_s" => &mut mapping.rest_speed_m_s,
            "rub_slip" => &mut mapping.rub_slip,
            "full_size_radius_m" => &mut mapping.full_size_radius_m,
            "reference_load_n" => &mut mapping.reference_load_n,
            "speed_scale" => &mut mapping.speed_scale,
            _ => return Err(value_error(format!("unknown mapping setting {key:?}"))),
        };
        *field = v;
    }
    Ok(())
}
