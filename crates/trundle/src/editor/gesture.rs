//! How a control talks to the host: one begin/set/end gesture per drag (kept in egui's
//! temporary memory under the control's id) or per one-shot change, the drag speeds, and
//! the reset modifier.

use egui::Id;
use nice_plug::prelude::*;

/// Normalized change per point of vertical drag (a full turn is 200 points at scale 1).
pub(super) const COARSE_PER_PT: f32 = 1.0 / 200.0;
/// Normalized change per point with shift held (ten times finer).
pub(super) const FINE_PER_PT: f32 = COARSE_PER_PT / 10.0;
/// Normalized change per point of mouse wheel.
pub(super) const WHEEL_PER_PT: f32 = 1.0 / 1_000.0;

/// A drag gesture in progress, kept in egui's temporary memory under the widget's id.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Gesture {
    pub(super) active: bool,
    /// The unsnapped normalized value the drag has reached (integer parameters step only
    /// when it crosses a step).
    pub(super) normalized: f32,
}

/// The drag gesture in progress on control `id` (none: inactive).
pub(super) fn gesture(ui: &egui::Ui, id: Id) -> Gesture {
    ui.data(|d| d.get_temp(id)).unwrap_or_default()
}

/// Keep control `id`'s drag gesture for the next frame.
pub(super) fn store_gesture(ui: &egui::Ui, id: Id, g: Gesture) {
    ui.data_mut(|d| d.insert_temp(id, g));
}

/// Whether the reset modifier is held: ctrl/cmd or alt (a click with it resets to the
/// default).
pub(super) fn reset_modifier(ui: &egui::Ui) -> bool {
    ui.input(|i| i.modifiers.command || i.modifiers.ctrl || i.modifiers.alt)
}

/// Set `param` to `plain` as one complete gesture (begin/set/end).
pub(super) fn set_once<P: Param>(setter: &ParamSetter, param: &P, plain: P::Plain) {
    setter.begin_set_parameter(param);
    setter.set_parameter(param, plain);
    setter.end_set_parameter(param);
}
