//! # Trundle cross-crate tests: a CLAP host
//!
//! The support code for `tests/clap_host.rs`: a small CLAP host built on `clack-host` that
//! loads the **built bundle** (`target/bundled/Trundle.clap`) and drives it the way a DAW
//! does — entry, factory, one plugin instance per track, host callbacks serviced on the main
//! thread, audio processed on a separate audio thread, parameters, automation events,
//! transport, state save/load.
//!
//! * [`bundle`] finds the bundle and (re)builds it with `cargo xtask bundle trundle
//!   --release` when it is missing or older than the plugin's sources.
//! * [`Host`] / [`Instance`] are the host: [`Instance::render`] processes a list of
//!   [`Block`]s (any sizes, parameter events at sample offsets, a transport per block) and
//!   returns both output channels.
//!
//! The host fills every output buffer with NaN before each `process` call, so a sample the
//! plugin does not write shows up as a non-finite output: [`Instance::render`] fails on it.

pub mod bundle;
pub mod check;
mod handlers;
mod instance;
mod process;

pub use handlers::{Host, MainThread, Shared};
pub use instance::{Bundle, Instance};
pub use process::{Block, NoteExpression, Transport};

use clack_extensions::params::ParamInfoFlags;
pub use clack_host::events::event_types::NoteExpressionType;
use clack_host::prelude::ClapId;

/// One parameter as the host sees it (`clap_param_info`).
#[derive(Clone, Debug)]
pub struct ParamDesc {
    /// CLAP parameter ID.
    pub id: ClapId,
    /// Display name.
    pub name: String,
    /// Module path (group).
    pub module: String,
    /// Smallest CLAP value.
    pub min: f64,
    /// Largest CLAP value.
    pub max: f64,
    /// Default CLAP value.
    pub default: f64,
    /// CLAP flags.
    pub flags: ParamInfoFlags,
}

/// What went wrong in the host.
#[derive(Debug)]
pub struct HostError(pub String);

impl std::fmt::Display for HostError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for HostError {}

pub(crate) fn err(e: impl std::fmt::Display) -> HostError {
    HostError(e.to_string())
}

/// The plugin's CLAP ID.
pub const PLUGIN_ID: &str = "org.trundle.trundle";

/// nice-plug's CLAP parameter ID for a stable string ID: a Rabin fingerprint of the string
/// with the top bit cleared (`nice_plug::wrapper::util::hash_param_id`). A DAW stores this
/// number in its automation lanes, so it must stay a pure function of the stable key.
pub fn clap_param_id(key: &str) -> u32 {
    let mut hash: u32 = 0;
    for b in key.bytes() {
        hash = hash.wrapping_mul(31).wrapping_add(u32::from(b));
    }
    hash & !(1 << 31)
}
