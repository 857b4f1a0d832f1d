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
//! field `state_version` ([`STATE_VERSION`]). Before a state is applied, [`check_state`]
//! (called from `Plugin::filter_state`) makes it exactly one this build understands, so a
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

use crate::object_slot::{ObjectSlot, OBJECT_FIELD};
use nice_plug::plugin::ParamValue;
use nice_plug::prelude::*;
use nice_plug_egui::EguiEditorState;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use trundle_dsp::object::fitted::LoadedObject;
use trundle_dsp::params::{ParamEnum, ParamKind, ParamSpec, Quality, PARAMS};
use trundle_dsp::ParamId;

/// Version of the saved state (bumped when the meaning of a saved parameter or field
/// changes; a step is then added to [`STATE_MIGRATIONS`]).
pub const STATE_VERSION: u32 = 1;

/// Name of the persisted field holding [`STATE_VERSION`].
pub const STATE_VERSION_FIELD: &str = "state_version";

/// Stable ID of the plugin-only transport parameter.
pub const RUN_ID: &str = "run";
/// Stable ID of the host bypass parameter.
pub const BYPASS_ID: &str = "bypass";

/// A state migration step: turns the saved parameters of version `from` into version
/// `from + 1`, pushing a line per change onto the report.
pub type StateMigration = fn(&mut BTreeMap<String, ParamValue>, &mut Vec<String>);

/// State migrations, keyed by the version they upgrade from (applied in order). Empty while
/// only version 1 exists; a version that renames or rescales a parameter adds its step here.
pub static STATE_MIGRATIONS: &[(u32, StateMigration)] = &[];

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
        if version != STATE_VERSION {
            nice_warn!(
                "Trundle state: persisted fields of version {version} applied without migration \
                 (this build writes version {STATE_VERSION})"
            );
        }
    }
}

/// Oldest state version this build can read (migrations start here).
const OLDEST_STATE_VERSION: u32 = 1;

/// Parse the persisted version field (nice-plug stores fields as JSON text; ours is a plain
/// number).
fn parse_version(text: &str) -> Result<u32, String> {
    text.trim()
        .parse::<u32>()
        .map_err(|_| format!("'{STATE_VERSION_FIELD}' field {text:?} is not a version number"))
}

/// What a saved parameter must hold.
#[derive(Clone, Copy)]
enum Expect {
    /// A row of the table.
    Table(&'static ParamSpec),
    /// `run`: 0 or 1.
    Run,
    /// `bypass`: a boolean.
    Bypass,
}

impl Expect {
    fn of(key: &str) -> Option<Self> {
        match key {
            RUN_ID => Some(Expect::Run),
            BYPASS_ID => Some(Expect::Bypass),
            _ => PARAMS.iter().find(|s| s.key == key).map(Expect::Table),
        }
    }

    fn default_value(self) -> ParamValue {
        match self {
            Expect::Table(spec) => match spec.kind {
                ParamKind::Float { .. } => ParamValue::F32(spec.default as f32),
                ParamKind::Int | ParamKind::Enum(_) => ParamValue::I32(spec.default as i32),
            },
            Expect::Run => ParamValue::I32(0),
            Expect::Bypass => ParamValue::Bool(false),
        }
    }

    /// The value to load for `v`, with a note when it had to be converted; or why it is
    /// refused.
    fn check(self, v: &ParamValue) -> Result<(ParamValue, Option<String>), String> {
        let whole = |x: f32| x.is_finite() && x.fract() == 0.0 && x.abs() < 2_147_483_648.0;
        match self {
            Expect::Table(spec) => {
                let (lo, hi) = (spec.min, spec.max);
                let in_range = |x: f64| x.is_finite() && x >= lo && x <= hi;
                // A value of the table's range the plugin does not offer (`reference`).
                let narrowed = |i: i32, note: Option<String>| {
                    let (v, why) = to_plugin_value(spec, f64::from(i));
                    let note = match (note, why) {
                        (Some(a), Some(b)) => Some(format!("{a}; {b}")),
                        (a, b) => a.or(b),
                    };
                    (ParamValue::I32(v as i32), note)
                };
                match (spec.kind, v) {
                    (ParamKind::Float { .. }, ParamValue::F32(x)) => {
                        // The range bounds as the f32 the parameter itself stores.
                        let x64 = f64::from(*x);
                        if x.is_finite() && *x >= lo as f32 && *x <= hi as f32 {
                            Ok((ParamValue::F32(*x), None))
                        } else {
                            Err(format!("value {x64} is outside {lo}..={hi}"))
                        }
                    }
                    (ParamKind::Float { .. }, ParamValue::I32(i)) if in_range(f64::from(*i)) => {
                        Ok((
                            ParamValue::F32(*i as f32),
                            Some(format!("integer {i} read as a float")),
                        ))
                    }
                    (ParamKind::Int | ParamKind::Enum(_), ParamValue::I32(i)) => {
                        if in_range(f64::from(*i)) {
                            Ok(narrowed(*i, None))
                        } else {
                            Err(format!("value {i} is outside {lo}..={hi}"))
                        }
                    }
                    (ParamKind::Int | ParamKind::Enum(_), ParamValue::F32(x))
                        if whole(*x) && in_range(f64::from(*x)) =>
                    {
                        Ok(narrowed(
                            *x as i32,
                            Some(format!("whole float {x} read as an integer")),
                        ))
                    }
                    (ParamKind::Enum(_), ParamValue::String(name)) => match spec.parse(name) {
                        Ok(index) => Ok(narrowed(
                            index as i32,
                            Some(format!("variant name {name:?} read as index {index}")),
                        )),
                        Err(e) => Err(e.to_string()),
                    },
                    (_, other) => Err(format!("value {other:?} has the wrong type")),
                }
            }
            Expect::Run => match v {
                ParamValue::I32(i @ (0 | 1)) => Ok((ParamValue::I32(*i), None)),
                ParamValue::F32(x) if *x == 0.0 || *x == 1.0 => Ok((
                    ParamValue::I32(*x as i32),
                    Some(format!("whole float {x} read as an integer")),
                )),
                other => Err(format!("value {other:?} is not 0 or 1")),
            },
            Expect::Bypass => match v {
                ParamValue::Bool(b) => Ok((ParamValue::Bool(*b), None)),
                ParamValue::I32(i @ (0 | 1)) => Ok((
                    ParamValue::Bool(*i == 1),
                    Some(format!("integer {i} read as a boolean")),
                )),
                other => Err(format!("value {other:?} is not a boolean")),
            },
        }
    }
}

/// Every saved parameter at its default: what a rejected state loads.
pub fn default_state_params() -> BTreeMap<String, ParamValue> {
    PARAMS
        .iter()
        .map(|s| s.key)
        .chain([RUN_ID, BYPASS_ID])
        .map(|key| {
            let e = Expect::of(key).expect("every listed key is known");
            (key.to_string(), e.default_value())
        })
        .collect()
}

/// Make a saved state one this build understands (see the module docs): migrate an older
/// version, reject a newer or unreadable one (every parameter at its default), validate
/// every parameter, fill in missing ones with defaults. Returns one line per change, with
/// its reason, for the log; an empty report means the state was loaded as saved.
///
/// # Allocation
/// Allocates (strings, maps): runs where nice-plug loads state, never in `process`.
pub fn check_state(state: &mut PluginState) -> Vec<String> {
    let mut report = Vec::new();
    let version = match state.fields.get(STATE_VERSION_FIELD) {
        None => {
            report.push(format!(
                "no '{STATE_VERSION_FIELD}' field: read as version {OLDEST_STATE_VERSION}"
            ));
            Ok(OLDEST_STATE_VERSION)
        }
        Some(text) => parse_version(text),
    };
    let refusal = match &version {
        Err(why) => Some(why.clone()),
        Ok(v) if *v > STATE_VERSION => Some(format!(
            "written by a newer Trundle (state version {v}; this build reads versions \
             {OLDEST_STATE_VERSION} to {STATE_VERSION}), whose meaning cannot be guessed"
        )),
        Ok(v) if *v < OLDEST_STATE_VERSION => Some(format!(
            "state version {v} is older than any Trundle release (oldest {OLDEST_STATE_VERSION})"
        )),
        Ok(_) => None,
    };
    for key in state.fields.keys() {
        if key != STATE_VERSION_FIELD && key != OBJECT_FIELD {
            report.push(format!("unknown persisted field '{key}' ignored"));
        }
    }
    // A fitted object is kept only if it reads and prepares (a corrupt one: the recipe).
    let object = state.fields.remove(OBJECT_FIELD).and_then(|text| {
        match ObjectSlot::parse(&text).and_then(|f| LoadedObject::new(f).map(|_| ())) {
            Ok(()) => Some(text),
            Err(e) => {
                report.push(format!(
                    "fitted object unusable ({e}): the recipe object plays"
                ));
                None
            }
        }
    });
    state.fields.clear();
    state
        .fields
        .insert(STATE_VERSION_FIELD.into(), STATE_VERSION.to_string());
    if let (Some(text), None) = (object, &refusal) {
        state.fields.insert(OBJECT_FIELD.into(), text);
    }

    if let Some(why) = refusal {
        report.push(format!(
            "state rejected, every parameter at its default: {why}"
        ));
        state.params = default_state_params();
        return report;
    }
    let version = version.unwrap_or(OLDEST_STATE_VERSION);
    for (from, step) in STATE_MIGRATIONS {
        if *from >= version {
            step(&mut state.params, &mut report);
        }
    }

    let mut checked = BTreeMap::new();
    for (key, value) in std::mem::take(&mut state.params) {
        let Some(expect) = Expect::of(&key) else {
            report.push(format!("unknown parameter '{key}' ignored"));
            continue;
        };
        let value = match expect.check(&value) {
            Ok((v, None)) => v,
            Ok((v, Some(note))) => {
                report.push(format!("parameter '{key}': {note}"));
                v
            }
            Err(why) => {
                let d = expect.default_value();
                report.push(format!("parameter '{key}': {why}; default {d:?} loaded"));
                d
            }
        };
        checked.insert(key, value);
    }
    for (key, default) in default_state_params() {
        if let std::collections::btree_map::Entry::Vacant(slot) = checked.entry(key) {
            report.push(format!(
                "parameter '{}' missing; default {default:?} loaded",
                slot.key()
            ));
            slot.insert(default);
        }
    }
    state.params = checked;
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    fn saved() -> PluginState {
        PluginState {
            version: "0.1.0".into(),
            params: default_state_params(),
            fields: [(STATE_VERSION_FIELD.to_string(), STATE_VERSION.to_string())].into(),
        }
    }

    fn f32_of(state: &PluginState, key: &str) -> f32 {
        match state.params[key] {
            ParamValue::F32(x) => x,
            ref other => panic!("{key}: {other:?}"),
        }
    }

    fn i32_of(state: &PluginState, key: &str) -> i32 {
        match state.params[key] {
            ParamValue::I32(x) => x,
            ref other => panic!("{key}: {other:?}"),
        }
    }

    #[test]
    fn a_current_state_loads_unchanged() {
        let mut s = saved();
        s.params.insert("velocity".into(), ParamValue::F32(0.75));
        s.params.insert("seed".into(), ParamValue::I32(12_345_678));
        s.params.insert(BYPASS_ID.into(), ParamValue::Bool(true));
        let report = check_state(&mut s);
        assert!(report.is_empty(), "{report:?}");
        assert_eq!(f32_of(&s, "velocity"), 0.75);
        assert_eq!(i32_of(&s, "seed"), 12_345_678);
        assert!(matches!(s.params[BYPASS_ID], ParamValue::Bool(true)));
        assert_eq!(s.params.len(), PARAMS.len() + 2);
    }

    #[test]
    fn a_future_version_is_rejected_with_defaults_and_a_reason() {
        let mut s = saved();
        s.params.insert("velocity".into(), ParamValue::F32(0.9));
        s.fields
            .insert(STATE_VERSION_FIELD.into(), (STATE_VERSION + 1).to_string());
        let report = check_state(&mut s);
        assert!(
            report.iter().any(|l| l.contains("newer Trundle")),
            "{report:?}"
        );
        assert_eq!(f32_of(&s, "velocity"), 0.5);
        assert_eq!(s.fields[STATE_VERSION_FIELD], STATE_VERSION.to_string());
        // The persisted field then reads as the current version.
        let p = TrundleParams::default();
        p.deserialize_fields(&s.fields);
        assert_eq!(p.state_version.load(Ordering::Relaxed), STATE_VERSION);
    }

    #[test]
    fn a_corrupt_version_field_is_rejected_with_defaults() {
        for garbage in ["\"one\"", "-1", "1.5", "", "99999999999"] {
            let mut s = saved();
            s.params.insert("roughness".into(), ParamValue::F32(0.1));
            s.fields.insert(STATE_VERSION_FIELD.into(), garbage.into());
            let report = check_state(&mut s);
            assert!(
                report.iter().any(|l| l.contains("rejected")),
                "{garbage}: {report:?}"
            );
            assert_eq!(f32_of(&s, "roughness"), 0.5, "{garbage}");
        }
        // deserialize_fields alone (state that skipped the check) never panics and records
        // an unreadable version as 0.
        let p = TrundleParams::default();
        p.deserialize_fields(&[(STATE_VERSION_FIELD.to_string(), "x".to_string())].into());
        assert_eq!(p.state_version.load(Ordering::Relaxed), 0);
    }

    #[test]
    fn corrupt_parameters_fall_back_to_defaults_one_by_one() {
        let mut s = saved();
        s.params
            .insert("velocity".into(), ParamValue::F32(f32::NAN));
        s.params.insert("roughness".into(), ParamValue::F32(7.0));
        s.params.insert("size".into(), ParamValue::Bool(true));
        s.params.insert("modes".into(), ParamValue::I32(100_000));
        s.params.insert(RUN_ID.into(), ParamValue::I32(5));
        s.params
            .insert(BYPASS_ID.into(), ParamValue::String("yes".into()));
        s.params.insert("sharpness".into(), ParamValue::F32(3.0));
        s.params.remove("decay");
        s.params.insert("wobble".into(), ParamValue::F32(1.0));
        s.fields.insert("editor-state".into(), "{}".into());
        let report = check_state(&mut s);
        for key in ["velocity", "roughness", "size", "modes", RUN_ID, BYPASS_ID] {
            assert!(
                report
                    .iter()
                    .any(|l| l.contains(&format!("'{key}'")) && l.contains("default")),
                "{key}: {report:?}"
            );
        }
        assert!(report.iter().any(|l| l.contains("'decay' missing")));
        assert!(report
            .iter()
            .any(|l| l.contains("unknown parameter 'wobble'")));
        assert!(report.iter().any(|l| l.contains("'editor-state'")));
        assert_eq!(f32_of(&s, "velocity"), 0.5);
        assert_eq!(f32_of(&s, "roughness"), 0.5);
        assert_eq!(f32_of(&s, "size"), 0.4);
        assert_eq!(i32_of(&s, "modes"), 32);
        assert_eq!(f32_of(&s, "decay"), 1.0);
        assert_eq!(i32_of(&s, RUN_ID), 0);
        assert!(matches!(s.params[BYPASS_ID], ParamValue::Bool(false)));
        // A valid value next to corrupt ones survives.
        assert_eq!(f32_of(&s, "sharpness"), 3.0);
        assert!(!s.params.contains_key("wobble"));
        assert_eq!(s.fields.len(), 1);
    }

    #[test]
    fn exact_type_changes_are_converted() {
        let mut s = saved();
        s.params
            .insert("shape".into(), ParamValue::String("bar".into()));
        s.params.insert("modes".into(), ParamValue::F32(64.0));
        s.params.insert("gain_db".into(), ParamValue::I32(-6));
        s.params.insert(BYPASS_ID.into(), ParamValue::I32(1));
        let report = check_state(&mut s);
        assert_eq!(report.len(), 4, "{report:?}");
        assert_eq!(i32_of(&s, "shape"), 1);
        assert_eq!(i32_of(&s, "modes"), 64);
        assert_eq!(f32_of(&s, "gain_db"), -6.0);
        assert!(matches!(s.params[BYPASS_ID], ParamValue::Bool(true)));
        // Not exact: refused.
        let mut s = saved();
        s.params.insert("modes".into(), ParamValue::F32(64.5));
        s.params
            .insert("shape".into(), ParamValue::String("teapot".into()));
        let report = check_state(&mut s);
        assert_eq!(i32_of(&s, "modes"), 32, "{report:?}");
        assert_eq!(i32_of(&s, "shape"), 2, "{report:?}");
    }

    #[test]
    fn a_state_without_version_is_read_as_the_oldest_and_validated() {
        let mut s = saved();
        s.fields.clear();
        s.params.insert("asymmetry".into(), ParamValue::F32(0.6));
        let report = check_state(&mut s);
        assert_eq!(report.len(), 1, "{report:?}");
        assert_eq!(f32_of(&s, "asymmetry"), 0.6);
    }

    #[test]
    fn a_reference_quality_state_loads_as_ultra_with_a_reason() {
        let reference = Quality::Reference.index() as i32;
        let ultra = Quality::Ultra.index() as i32;
        for saved_as in [
            ParamValue::I32(reference),
            ParamValue::F32(reference as f32),
            ParamValue::String("reference".into()),
        ] {
            let mut s = saved();
            s.params.insert("quality".into(), saved_as.clone());
            let report = check_state(&mut s);
            assert_eq!(i32_of(&s, "quality"), ultra, "{saved_as:?}");
            assert!(
                report
                    .iter()
                    .any(|l| l.contains("'quality'") && l.contains("offline only")),
                "{saved_as:?}: {report:?}"
            );
        }
        // Every quality the plugin offers loads as saved, silently.
        for q in 0..=ultra {
            let mut s = saved();
            s.params.insert("quality".into(), ParamValue::I32(q));
            assert!(check_state(&mut s).is_empty());
            assert_eq!(i32_of(&s, "quality"), q);
        }
    }

    #[test]
    fn the_plugin_quality_stops_at_ultra() {
        let spec = ParamId::Quality.spec();
        assert_eq!(plugin_range(spec), (0.0, 3.0));
        assert_eq!(spec.max, 4.0, "the table still has 'reference'");
        let p = TrundleParams::default();
        let TableParam::Int(q) = p.get(ParamId::Quality) else {
            panic!("quality is an enumeration");
        };
        assert_eq!(q.preview_plain(1.0), 3);
        assert_eq!(q.normalized_value_to_string(1.0, true), "ultra");
        // Typed 'reference' reads as the top of the plugin's range.
        let n = q.string_to_normalized_value("reference").unwrap();
        assert_eq!(q.preview_plain(n), 3);
        // Every other row keeps the table's range.
        for spec in PARAMS.iter().filter(|s| s.id != ParamId::Quality) {
            assert_eq!(plugin_range(spec), (spec.min, spec.max), "{}", spec.key);
            assert_eq!(to_plugin_value(spec, spec.max), (spec.max, None));
        }
        let (v, why) = to_plugin_value(spec, 4.0);
        assert_eq!(v, 3.0);
        assert!(why.unwrap().contains("'reference'"));
    }

    #[test]
    fn the_state_round_trips_through_json_and_the_check() {
        // What nice-plug writes for a default instance passes the check untouched.
        let p = TrundleParams::default();
        let mut s = saved();
        s.fields = p.serialize_fields();
        let json = serde_json::to_string(&s).unwrap();
        let mut back: PluginState = serde_json::from_str(&json).unwrap();
        assert!(check_state(&mut back).is_empty());
        assert_eq!(back.params.len(), p.param_map().len());
    }
}
