//! Whole-sound changes: the live parameters as one [`Params`](struct@Params) snapshot, and
//! applying a snapshot back (presets, A/B switches, randomize) as host gestures.

use super::gesture;
use super::state::*;
use crate::compare::Slot;
use crate::params::{to_plugin_value, TableParam};
use crate::randomize::{randomize, Rng};
use nice_plug::prelude::*;
use trundle_dsp::{Params, PARAMS};

/// Whether a parameter holding `have` holds the table value `want`: equal up to the
/// plugin's step (a float is snapped to its step, so `action_y` = −√3/2 is held as −0.866)
/// and f32 rounding.
pub(super) fn holds(spec: &trundle_dsp::params::ParamSpec, want: f64, have: f64) -> bool {
    let tolerance = match spec.kind {
        trundle_dsp::params::ParamKind::Float { .. } => 0.5 * spec.step(),
        _ => 0.0,
    };
    (want - have).abs() <= tolerance + 1e-5 * (spec.max - spec.min)
}

impl TrundleEditor {
    /// The live (unmodulated) table values, floats rounded to their text's decimals (the
    /// plugin's step), so a saved preset reads "0.73", not the f32's "0.7300000190734863".
    pub(super) fn live_params(&self) -> Params {
        let mut out = Params::default();
        for spec in PARAMS.iter() {
            let v = match self.params.get(spec.id) {
                TableParam::Float(p) => {
                    // Through the text's decimals: the shortest f64 of the shown value.
                    let v = f64::from(p.unmodulated_plain_value());
                    let d = spec.decimals();
                    format!("{v:.d$}").parse().unwrap_or(v)
                }
                TableParam::Int(p) => f64::from(p.unmodulated_plain_value()),
            };
            out.set_clamped(spec.id, v);
        }
        out
    }

    /// Whether the live values are what applying `target` gives.
    pub(super) fn live_equals(&self, target: &Params) -> bool {
        PARAMS.iter().all(|spec| {
            let (want, _) = to_plugin_value(spec, target.get(spec.id));
            holds(spec, want, self.params.get(spec.id).value())
        })
    }

    /// Set every parameter whose value differs from `target` as one gesture of its own
    /// (begin/set/end), so the host's undo and automation see the change. A value the
    /// plugin does not offer (quality `reference`, offline only) becomes its nearest
    /// (`ultra`), with the reason logged under `what`.
    pub(super) fn apply(&self, target: &Params, setter: &ParamSetter, what: &str) {
        for spec in PARAMS.iter() {
            let (v, why) = to_plugin_value(spec, target.get(spec.id));
            if let Some(why) = why {
                nice_warn!("Trundle {what}: {why}");
            }
            match self.params.get(spec.id) {
                TableParam::Float(p) => {
                    if !holds(spec, v, f64::from(p.unmodulated_plain_value())) {
                        gesture::set_once(setter, p, spec.quantize(v as f32));
                    }
                }
                TableParam::Int(p) => {
                    if !holds(spec, v, f64::from(p.unmodulated_plain_value())) {
                        gesture::set_once(setter, p, v.round() as i32);
                    }
                }
            }
        }
    }

    /// Switch the A/B compare to `slot`, applying its snapshot.
    pub(super) fn switch_slot(&mut self, slot: Slot, setter: &ParamSetter) {
        let live = self.live_params();
        let target = self.ab.switch_to(slot, &live);
        self.apply(&target, setter, &format!("compare slot {}", slot.name()));
    }

    /// Randomize the unlocked groups (seeded from the clock).
    pub(super) fn randomize(&mut self, setter: &ParamSetter) {
        let seed = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64);
        let target = randomize(&self.live_params(), &self.locks, &mut Rng::new(seed));
        self.apply(&target, setter, "randomize");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::TrundleParams;
    use trundle_dsp::scene::preset::{Preset, BUILTIN_PRESETS};
    use trundle_dsp::ParamId;

    #[test]
    fn every_builtin_preset_reads_as_itself_once_loaded() {
        // What a parameter holds after `apply`: the value snapped to its step through the
        // normalized value the host sees. The "(edited)" mark must not appear right after a
        // load (the default action_y, −√3/2, is off the step grid).
        let params = TrundleParams::default();
        for (stem, json) in BUILTIN_PRESETS.iter() {
            let preset = Preset::from_json(json).unwrap();
            for spec in PARAMS.iter() {
                let (v, _) = to_plugin_value(spec, preset.params.get(spec.id));
                let held = match params.get(spec.id) {
                    TableParam::Float(p) => {
                        f64::from(p.preview_plain(p.preview_normalized(spec.quantize(v as f32))))
                    }
                    TableParam::Int(p) => {
                        f64::from(p.preview_plain(p.preview_normalized(v.round() as i32)))
                    }
                };
                assert!(
                    holds(spec, v, held),
                    "{stem}: {} {v} held as {held}",
                    spec.key
                );
            }
        }
    }

    #[test]
    fn a_changed_value_is_not_held() {
        let spec = ParamId::Velocity.spec();
        assert!(holds(spec, 0.5, 0.5));
        assert!(!holds(spec, 0.5, 0.501));
        let modes = ParamId::Modes.spec();
        assert!(holds(modes, 32.0, 32.0));
        assert!(!holds(modes, 32.0, 33.0));
    }
}
