//! The saved state's version: the persisted field, its parser and the migrations from
//! older versions (see the `params` module docs).

use nice_plug::plugin::ParamValue;
use std::collections::BTreeMap;

/// Version of the saved state (bumped when the meaning of a saved parameter or field
/// changes; a step is then added to [`STATE_MIGRATIONS`]).
pub const STATE_VERSION: u32 = 1;

/// Name of the persisted field holding [`STATE_VERSION`].
pub const STATE_VERSION_FIELD: &str = "state_version";

/// A state migration step: turns the saved parameters of version `from` into version
/// `from + 1`, pushing a line per change onto the report.
pub type StateMigration = fn(&mut BTreeMap<String, ParamValue>, &mut Vec<String>);

/// State migrations, keyed by the version they upgrade from (applied in order). Empty while
/// only version 1 exists; a version that renames or rescales a parameter adds its step here.
pub static STATE_MIGRATIONS: &[(u32, StateMigration)] = &[];

/// Oldest state version this build can read (migrations start here).
pub(super) const OLDEST_STATE_VERSION: u32 = 1;

/// Parse the persisted version field (nice-plug stores fields as JSON text; ours is a plain
/// number).
pub(super) fn parse_version(text: &str) -> Result<u32, String> {
    text.trim()
        .parse::<u32>()
        .map_err(|_| format!("'{STATE_VERSION_FIELD}' field {text:?} is not a version number"))
}
