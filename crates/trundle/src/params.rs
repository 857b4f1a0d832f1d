//! The plugin's parameters, generated from the one table (`trundle_dsp::PARAMS`).
//!
//! Every row of the table becomes one nice-plug parameter with the row's key as its stable
//! ID, the row's range, default and unit: floats as [`FloatParam`] (log-skewed where the
//! table says so), integers and enumerations as [`IntParam`] (enumerations show their variant
//! names; the stored value is the variant index, as in presets). No number is retyped here,
//! so the plugin, the CLI, the presets and the tests cannot disagree. Two plugin-only
//! parameters follow: `run` (transport behaviour) and `bypass`.
//!
//! `Params` is implemented by hand (nice-plug allows it) because the parameter list is data.

use nice_plug::prelude::*;
use nice_plug_egui::EguiEditorState;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use trundle_dsp::params::{ParamKind, ParamSpec, PARAMS};

/// Version of the plugin's own persisted fields (bumped when their meaning changes).
pub const STATE_VERSION: u32 = 1;

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

/// How many decimals a value of this row is shown with.
fn decimals(spec: &ParamSpec) -> usize {
    let span = spec.max - spec.min;
    if span >= 50.0 {
        1
    } else if span >= 5.0 {
        2
    } else {
        3
    }
}

/// Format a value of `spec` the way people read it: units, percentages for 0…1 amounts.
pub fn format_value(spec: &ParamSpec, v: f64) -> String {
    match spec.kind {
        ParamKind::Enum(names) => names
            .get(v.round().max(0.0) as usize)
            .copied()
            .unwrap_or("?")
            .to_string(),
        ParamKind::Int => format!("{}", v.round() as i64),
        ParamKind::Float { .. } => {
            let pct = spec.unit.is_empty()
                && spec.min == 0.0
                && spec.max == 1.0
                && matches!(spec.key, "roughness" | "asymmetry" | "comb");
            if pct {
                format!("{:.0} %", v * 100.0)
            } else if spec.unit.is_empty() {
                format!("{v:.*}", decimals(spec))
            } else if spec.unit == "x" {
                format!("×{v:.2}")
            } else {
                format!("{v:.*} {}", decimals(spec), spec.unit)
            }
        }
    }
}

/// Parse text typed by a user (numbers with or without unit, percentages, variant names).
pub fn parse_value(spec: &ParamSpec, text: &str) -> Option<f64> {
    let t = text.trim().trim_start_matches('×');
    if let Ok(v) = spec.parse(t) {
        return Some(v);
    }
    let number: String = t
        .chars()
        .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E'))
        .collect();
    let v: f64 = number.parse().ok()?;
    let v = if t.ends_with('%') { v / 100.0 } else { v };
    v.is_finite().then(|| v.clamp(spec.min, spec.max))
}

fn make(spec: &'static ParamSpec) -> TableParam {
    match spec.kind {
        ParamKind::Float { log } => {
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
            TableParam::Float(
                FloatParam::new(spec.name, spec.default as f32, range)
                    .with_value_to_string(Arc::new(move |v| format_value(spec, f64::from(v))))
                    .with_string_to_value(Arc::new(move |s| {
                        parse_value(spec, s).map(|v| v as f32)
                    })),
            )
        }
        ParamKind::Int | ParamKind::Enum(_) => TableParam::Int(
            IntParam::new(
                spec.name,
                spec.default as i32,
                IntRange::Linear {
                    min: spec.min as i32,
                    max: spec.max as i32,
                },
            )
            .with_value_to_string(Arc::new(move |v| format_value(spec, f64::from(v))))
            .with_string_to_value(Arc::new(move |s| parse_value(spec, s).map(|v| v as i32))),
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
}

impl Default for TrundleParams {
    fn default() -> Self {
        Self {
            table: PARAMS.iter().map(make).collect(),
            run: IntParam::new("Run", 0, IntRange::Linear { min: 0, max: 1 }).with_value_to_string(
                Arc::new(|v| {
                    if v == 0 {
                        "with transport".into()
                    } else {
                        "always".into()
                    }
                }),
            ),
            bypass: BoolParam::new("Bypass", false).make_bypass(),
            editor_state: EguiEditorState::from_size(
                nice_plug::editor::dpi::LogicalSize::<f64>::new(880.0, 600.0),
                1.0,
            ),
            state_version: AtomicU32::new(STATE_VERSION),
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
        map.push(("run".into(), self.run.as_ptr(), String::new()));
        map.push(("bypass".into(), self.bypass.as_ptr(), String::new()));
        map
    }

    fn serialize_fields(&self) -> BTreeMap<String, String> {
        let mut m = BTreeMap::new();
        m.insert("state_version".into(), STATE_VERSION.to_string());
        m
    }

    fn deserialize_fields(&self, serialized: &BTreeMap<String, String>) {
        // A state from a newer plugin or a corrupt field is not fatal: parameters are restored
        // by the wrapper; our own fields fall back to defaults.
        let version = serialized
            .get("state_version")
            .and_then(|v| v.parse::<u32>().ok())
            .unwrap_or(0);
        self.state_version.store(version, Ordering::Relaxed);
        if version > STATE_VERSION {
            nice_warn!(
                "state written by a newer Trundle (version {version}); unknown fields ignored"
            );
        }
    }
}
