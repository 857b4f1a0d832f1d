//! Which table rows the editor draws where (each row's place in the table says it).

use trundle_dsp::params::{Panel, Section};
use trundle_dsp::{ParamId, PARAMS};

/// Whether table row `id` is an enumeration.
pub(super) fn is_enum(id: ParamId) -> bool {
    matches!(id.spec().kind, trundle_dsp::params::ParamKind::Enum(_))
}

/// How many values table row `id` offers in the plugin (an enumeration's variants up to
/// the plugin's range; `quality` stops at `ultra`).
pub(super) fn variants(id: ParamId) -> usize {
    let (lo, hi) = crate::params::plugin_range(id.spec());
    (hi - lo) as usize + 1
}

/// The rows a panel's section draws, in table order: each row's place says where it goes.
pub(super) fn placed(panel: Panel, section: Section) -> Vec<ParamId> {
    PARAMS
        .iter()
        .filter(|spec| spec.place.panel == panel && spec.place.section == section)
        .map(|spec| spec.id)
        .collect()
}
