//! Whole-sound changes: the live parameters as one [`Params`] snapshot, and applying a
//! snapshot back (presets, A/B switches, randomize) as host gestures.

use super::*;
use crate::compare::Slot;
use crate::randomize::{randomize, Rng};

/// Which preset is loaded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum PresetRef {
    /// A built-in preset (an index into the editor's built-in list).
    Builtin(usize),
    /// A user preset (its file name in the store).
    User(String),
}

/// The preset last loaded and the values it loaded (to tell "edited").
#[derive(Clone, Debug)]
pub(super) struct Loaded {
    pub(super) source: PresetRef,
    pub(super) name: String,
    pub(super) params: Params,
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
            let have = self.params.get(spec.id).value();
            (want - have).abs() <= 1e-5 * (spec.max - spec.min)
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
                    let v = spec.quantize(v as f32);
                    if p.unmodulated_plain_value() != v {
                        widgets::set_once(setter, p, v);
                    }
                }
                TableParam::Int(p) => {
                    let v = v.round() as i32;
                    if p.unmodulated_plain_value() != v {
                        widgets::set_once(setter, p, v);
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
