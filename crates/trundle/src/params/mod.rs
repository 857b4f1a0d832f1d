//! The plugin's parameters, generated from the one table (`trundle_dsp::PARAMS`).
//!
//! Every row of the table becomes one nice-plug parameter with the row's key as its stable
//! ID, the row's range, default and unit: floats as [`FloatParam`] (log-skewed where the
//! table says so), integers and enumerations as [`IntParam`] (enumerations show their variant
//! names; the stored value is the variant index, as in presets). No number is retyped here,
//! so the plugin, the CLI, the presets and the tests cannot disagree. Two plugin-only
//! parameters follow: `run` (transport behaviour) and `bypass`.
//!
//! One row is narrower in the plugin than in the table: `quality` offers draft…ultra only
//! (0..=3, [`plugin_range`]). Its fifth variant, `reference` (every mode of the shape
//! explicit, thousands of them), is for offline renders; a saved state, a preset or typed
//! text asking for it gets `ultra`, with a logged reason ([`to_plugin_value`]).
//!
//! `Params` is implemented by hand (nice-plug allows it) because the parameter list is data.
//!
//! # Saved state
//!
//! nice-plug saves every parameter's plain value under its stable ID, plus our persisted
//! field `state_version` ([`STATE_VERSION`]). Before a state is applied, [`check_state`](state::check_state)
//! ([`state::check_state`], called from `Plugin::filter_state`) makes it exactly one this build understands, so a
//! restored state always means one definite sound:
//!
//! * **older versions** are migrated by [`STATE_MIGRATIONS`], a version-keyed table (empty
//!   while only version 1 exists), as presets are;
//! * **a newer version**, or a version field that is not a number, cannot be interpreted:
//!   the state is rejected and every parameter takes its default (the meaning of a newer
//!   state cannot be guessed — the same rule as for preset files);
//! * **each parameter** is validated against the table: a missing parameter takes its
//!   default (so a restore never inherits the value the instance happened to have), an
//!   unknown one is dropped, a value of the wrong type is converted when that is exact (an
//!   integer for a float, a variant name or a whole float for an enumeration) and otherwise,
//!   like a non-finite or out-of-range value, replaced by the default.
//!
//! Every change is logged with its reason (`nice_warn!`). A state that is not valid JSON at
//! all never reaches us: nice-plug refuses it, the host is told the load failed and the
//! instance keeps its current values.
//!
//! Two persisted fields carry more than numbers: the fitted object (`object`,
//! [`crate::object_slot`]) and the body EQ curve (`body_eq`, [`crate::body_eq_slot`]). Each
//! is validated by `check_state`; an unusable one is dropped with a logged reason (the
//! recipe object, no curve) and the rest of the state loads.
//!
//! The parameter wrapper lives here; the saved state's version and migrations in
//! `params/version.rs`; the check of a saved state in `params/state.rs`.

pub mod state;
mod version;

use crate::body_eq_slot::{BodyEqSlot, BODY_EQ_FIELD};
use crate::object_slot::{ObjectSlot, OBJECT_FIELD};
use nice_plug::prelude::*;
use nice_plug_egui::EguiEditorState;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use trundle_dsp::object::quality::Quality;
use trundle_dsp::params::{ParamEnum, ParamKind, ParamSpec, PARAMS};
use trundle_dsp::ParamId;
use version::parse_version;
pub use version::{StateMigration, STATE_MIGRATIONS, STATE_VERSION, STATE_VERSION_FIELD};

/// Stable ID of the plugin-only transport parameter.
pub const RUN_ID: &str = "run";
/// Stable ID of the host bypass parameter.
pub const BYPASS_ID: &str = "bypass";

/// One table parameter as a nice-plug parameter.
pub enum TableParam {
    /// A continuous parameter.
    Float(FloatParam),
    /// An integer or enumeration parameter.
    Int(IntParam),
}

impl TableParam {
    /// The current (unsmoothed) plain value as f64, in the table's units.
    pub fn value(&self) -> f64 {
        match self {
            TableParam::Float(p) => f64::from(p.value()),
            TableParam::Int(p) => f64::from(p.value()),
        }
    }

    fn ptr(&self) -> ParamPtr {
        match self {
            TableParam::Float(p) => p.as_ptr(),
            TableParam::Int(p) => p.as_ptr(),
        }
    }
}

/// Names of the `run` parameter's values, in index order.
pub const RUN_NAMES: [&str; 2] = ["with transport", "always"];

/// Text of a `run` value.
pub fn format_run(v: i32) -> String {
    RUN_NAMES[v.clamp(0, 1) as usize].to_string()
}

/// A `run` value from text: its name (any case) or its index.
pub fn parse_run(text: &str) -> Option<i32> {
    let t = text.trim();
    RUN_NAMES
        .iter()
        .position(|n| n.eq_ignore_ascii_case(t))
        .map(|i| i as i32)
        .or_else(|| t.parse::<i32>().ok().filter(|i| (0..=1).contains(i)))
}

/// The quality the plugin offers at most: `ultra`. `reference` is offline only.
pub const PLUGIN_QUALITY_MAX: Quality = Quality::Ultra;

/// The range (in the table's units) a table row has as a plugin parameter: the table's,
/// except `quality`, which stops at [`PLUGIN_QUALITY_MAX`].
pub fn plugin_range(spec: &ParamSpec) -> (f64, f64) {
    match spec.id {
        ParamId::Quality => (spec.min, PLUGIN_QUALITY_MAX.index() as f64),
        _ => (spec.min, spec.max),
    }
}

/// A table value (from a preset or a saved state) as the plugin can hold it, with the
/// reason when it had to change: a quality above [`PLUGIN_QUALITY_MAX`] (`reference`) is
/// offline only and becomes `ultra`. Other values pass unchanged.
pub fn to_plugin_value(spec: &ParamSpec, v: f64) -> (f64, Option<String>) {
    let (_, hi) = plugin_range(spec);
    if spec.id == ParamId::Quality && v > hi {
        let name = |x: f64| Quality::from_value(x).name();
        let reason = format!(
            "quality '{}' is offline only (every mode explicit, thousands of them: `trundle \
             render`); '{}' loaded",
            name(v),
            name(hi)
        );
        return (hi, Some(reason));
    }
    (v, None)
}

fn make(spec: &'static ParamSpec) -> TableParam {
    let (_, plugin_max) = plugin_range(spec);
    match spec.kind {
        ParamKind::Float { log, .. } => {
            let (min, max) = (spec.min as f32, spec.max as f32);
            let range = if log {
                // Skew so the geometric mean sits mid-travel: a logarithmic control.
                let mid = (spec.min * spec.max).sqrt();
                let x = (mid - spec.min) / (spec.max - spec.min);
                FloatRange::Skewed {
                    min,
                    max,
                    factor: (0.5f64.ln() / x.ln()) as f32,
                }
            } else {
                FloatRange::Linear { min, max }
            };
            let mut param = FloatParam::new(spec.name, spec.default as f32, range);
            // Size, velocity and roughness are each ball's own: CLAP poly modulation.
            if let Some(id) = crate::expression::poly_modulation_id(spec.key) {
                param = param.with_poly_modulation_id(id);
            }
            TableParam::Float(
                param
                    // Quantized to the text's resolution, so every value reads back exactly.
                    .with_step_size(spec.step() as f32)
                    .with_value_to_string(Arc::new(move |v| spec.format(f64::from(v))))
                    // Text reads as the value the plugin will hold (on the step grid), so a
                    // host that sets the value it read back from text sees it unchanged.
                    .with_string_to_value(Arc::new(move |s| {
                        spec.parse_clamped(s).ok().map(|v| spec.quantize(v as f32))
                    })),
            )
        }
        ParamKind::Int | ParamKind::Enum(_) => TableParam::Int(
            IntParam::new(
                spec.name,
                spec.default as i32,
                IntRange::Linear {
                    min: spec.min as i32,
                    max: plugin_max as i32,
                },
            )
            .with_value_to_string(Arc::new(move |v| spec.format(f64::from(v))))
            // Typed text beyond the plugin's range (`reference`) reads as its top.
            .with_string_to_value(Arc::new(move |s| {
                spec.parse_clamped(s).ok().map(|v| v.min(plugin_max) as i32)
            })),
        ),
    }
}

/// All of the plugin's parameters and persisted fields.
pub struct TrundleParams {
    /// One parameter per row of `PARAMS`, in table order.
    pub table: Vec<TableParam>,
    /// `run`: 0 = roll while the host transport plays, 1 = always roll.
    pub run: IntParam,
    /// `bypass`: the host's bypass switch (fades out and back in, never clicks).
    pub bypass: BoolParam,
    /// The editor's window state.
    pub editor_state: Arc<EguiEditorState>,
    /// Version of the persisted fields the state was written with.
    pub state_version: AtomicU32,
    /// The fitted object played instead of the recipe one, saved in the state (field
    /// [`OBJECT_FIELD`]: the object file's JSON).
    pub object: Arc<ObjectSlot>,
    /// The body EQ curve the `body_eq` amount scales, saved in the state (field
    /// [`BODY_EQ_FIELD`]).
    pub body_eq: Arc<BodyEqSlot>,
}

impl Default for TrundleParams {
    fn default() -> Self {
        Self {
            table: PARAMS.iter().map(make).collect(),
            run: IntParam::new("Run", 0, IntRange::Linear { min: 0, max: 1 })
                .with_value_to_string(Arc::new(format_run))
                .with_string_to_value(Arc::new(parse_run)),
            bypass: BoolParam::new("Bypass", false).make_bypass(),
            editor_state: EguiEditorState::from_size(
                nice_plug::editor::dpi::LogicalSize::<f64>::new(880.0, 600.0),
                1.0,
            ),
            state_version: AtomicU32::new(STATE_VERSION),
            object: Arc::new(ObjectSlot::default()),
            body_eq: Arc::new(BodyEqSlot::default()),
        }
    }
}

impl TrundleParams {
    /// The parameter of table row `id`.
    pub fn get(&self, id: trundle_dsp::ParamId) -> &TableParam {
        &self.table[id as usize]
    }

    /// Map every parameter onto a DSP parameter set (values clamped into the table's
    /// ranges; the host can only send in-range normalized values anyway).
    pub fn to_dsp(&self, out: &mut trundle_dsp::Params) {
        for (spec, p) in PARAMS.iter().zip(&self.table) {
            out.set_clamped(spec.id, p.value());
        }
    }
}

// SAFETY: every pointer handed out points into `self.table`, `self.run` or `self.bypass`,
// which live as long as the `Arc<TrundleParams>` the wrapper keeps; the Vec is never resized
// after construction.
unsafe impl Params for TrundleParams {
    fn param_map(&self) -> Vec<(String, ParamPtr, String)> {
        let mut map: Vec<(String, ParamPtr, String)> = PARAMS
            .iter()
            .zip(&self.table)
            .map(|(spec, p)| (spec.key.to_string(), p.ptr(), String::new()))
            .collect();
        map.push((RUN_ID.into(), self.run.as_ptr(), String::new()));
        map.push((BYPASS_ID.into(), self.bypass.as_ptr(), String::new()));
        map
    }

    fn serialize_fields(&self) -> BTreeMap<String, String> {
        let mut m = BTreeMap::new();
        m.insert(STATE_VERSION_FIELD.into(), STATE_VERSION.to_string());
        if let Some(text) = self.object.to_state_text() {
            m.insert(OBJECT_FIELD.into(), text);
        }
        if let Some(text) = self.body_eq.to_state_text() {
            m.insert(BODY_EQ_FIELD.into(), text);
        }
        m
    }

    fn deserialize_fields(&self, serialized: &BTreeMap<String, String>) {
        // `check_state` (run first, from `Plugin::filter_state`) has already migrated or
        // rejected the state, so the version read here is the current one; anything else
        // means the state bypassed that check, which is logged.
        let version = serialized
            .get(STATE_VERSION_FIELD)
            .and_then(|v| parse_version(v).ok())
            .unwrap_or(0);
        self.state_version.store(version, Ordering::Relaxed);
        // The state's object (checked by `check_state`), or the recipe object: a state
        // without one restores the recipe.
        let object = serialized.get(OBJECT_FIELD).map(|t| ObjectSlot::parse(t));
        let applied = match object {
            Some(Ok(file)) => self.object.set(Some(file)),
            Some(Err(e)) => Err(e),
            None => self.object.set(None),
        };
        if let Err(e) = applied {
            nice_warn!(
                "Trundle state: its fitted object is unusable ({e}); the recipe object plays"
            );
            self.object.clear();
        }
        // The state's body EQ curve (checked by `check_state`), or none.
        match serialized.get(BODY_EQ_FIELD).map(|t| BodyEqSlot::parse(t)) {
            Some(Ok(curve)) => self.body_eq.set(Some(curve)),
            Some(Err(e)) => {
                nice_warn!("Trundle state: its body EQ curve is unusable ({e}); no curve plays");
                self.body_eq.clear();
            }
            None => self.body_eq.set(None),
        }
        if version != STATE_VERSION {
            nice_warn!(
                "Trundle state: persisted fields of version {version} applied without migration \
                 (this build writes version {STATE_VERSION})"
            );
        }
    }
}
