//! What can go wrong when embedding Trundle: one error type for the whole runtime, each
//! variant saying what was refused (nothing changed when an error is returned).

use std::fmt;
use trundle_dsp::params::ParamError;
use trundle_dsp::scene::preset::PresetError;

/// Why a runtime call was refused. Every call that returns it changed nothing.
#[derive(Clone, Debug, PartialEq)]
pub enum RuntimeError {
    /// The preset (a built-in name or JSON text) could not be loaded.
    Preset(String),
    /// A parameter was refused: unknown key, out of range, not a number.
    Param(String),
    /// The sample rate is outside the core's range (Hz).
    SampleRate(f64),
    /// The two channel buffers differ in length (left, right).
    BufferSizes(usize, usize),
    /// A contact frame or a setting carries a value the runtime cannot use (what, value).
    BadValue(&'static str, f64),
    /// A contact names something the stream does not know (what, its id).
    Unknown(&'static str, u64),
    /// The same thing given twice where once is allowed (what, its id).
    Duplicate(&'static str, u64),
    /// A pool sized at construction is full (what, its capacity).
    Full(&'static str, usize),
}

impl fmt::Display for RuntimeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Preset(e) => write!(f, "preset: {e}"),
            Self::Param(e) => write!(f, "parameter: {e}"),
            Self::SampleRate(hz) => write!(
                f,
                "sample rate {hz} Hz is out of range ({}–{} Hz)",
                trundle_dsp::block::MIN_SAMPLE_RATE_HZ,
                trundle_dsp::block::MAX_SAMPLE_RATE_HZ
            ),
            Self::BufferSizes(l, r) => {
                write!(
                    f,
                    "left and right buffers differ in length ({l} and {r} frames)"
                )
            }
            Self::BadValue(what, v) => write!(f, "{what} must be finite and in range, got {v}"),
            Self::Unknown(what, id) => write!(f, "unknown {what} {id}"),
            Self::Duplicate(what, id) => write!(f, "{what} {id} given twice"),
            Self::Full(what, n) => write!(f, "no room for another {what} (capacity {n})"),
        }
    }
}

impl std::error::Error for RuntimeError {}

impl From<ParamError> for RuntimeError {
    fn from(e: ParamError) -> Self {
        Self::Param(e.to_string())
    }
}

impl From<PresetError> for RuntimeError {
    fn from(e: PresetError) -> Self {
        Self::Preset(e.to_string())
    }
}
