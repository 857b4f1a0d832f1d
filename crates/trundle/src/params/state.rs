//! The check of a saved state before it is applied (see the `params` module docs): migrate
//! an older version, reject a newer or unreadable one, validate every parameter against the
//! table.

use super::version::{parse_version, OLDEST_STATE_VERSION, STATE_MIGRATIONS};
use super::version::{STATE_VERSION, STATE_VERSION_FIELD};
use super::{to_plugin_value, BYPASS_ID, RUN_ID};
use crate::body_eq_slot::{BodyEqSlot, BODY_EQ_FIELD};
use crate::object_slot::{ObjectSlot, OBJECT_FIELD};
use nice_plug::plugin::ParamValue;
use nice_plug::prelude::*;
use std::collections::BTreeMap;
use trundle_dsp::object::fitted::LoadedObject;
use trundle_dsp::params::{ParamKind, ParamSpec, PARAMS};

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
        if ![STATE_VERSION_FIELD, OBJECT_FIELD, BODY_EQ_FIELD].contains(&key.as_str()) {
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
    // A body EQ curve likewise (a corrupt or out-of-range one: no curve).
    let body_eq =
        state
            .fields
            .remove(BODY_EQ_FIELD)
            .and_then(|text| match BodyEqSlot::parse(&text) {
                Ok(_) => Some(text),
                Err(e) => {
                    report.push(format!("{e}: no body EQ curve plays"));
                    None
                }
            });
    state.fields.clear();
    state
        .fields
        .insert(STATE_VERSION_FIELD.into(), STATE_VERSION.to_string());
    if let (Some(text), None) = (object, &refusal) {
        state.fields.insert(OBJECT_FIELD.into(), text);
    }
    if let (Some(text), None) = (body_eq, &refusal) {
        state.fields.insert(BODY_EQ_FIELD.into(), text);
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
    use crate::params::plugin_range;
    use crate::params::{TableParam, TrundleParams};
    use std::sync::atomic::Ordering;
    use trundle_dsp::object::quality::Quality;
    use trundle_dsp::params::ParamEnum;
    use trundle_dsp::ParamId;

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
