//! Scene presets: versioned JSON files shared by the plugin and the CLI.
//!
//! (Behind the `presets` feature: the model itself has no file-format dependency.)
//!
//! ```json
//! {
//!   "trundle_preset": 1,
//!   "name": "Ball on a wooden table",
//!   "description": "…",
//!   "params": { "size": 0.4, "velocity": 0.5, "shape": "plate", "modes": 32 }
//! }
//! ```
//!
//! * `trundle_preset` is the format version. A file from a newer Trundle is refused with a
//!   clear error (its meaning cannot be guessed); older versions are migrated by
//!   [`MIGRATIONS`], a version-keyed table (after OctaSine).
//! * `params` maps stable parameter keys ([`crate::params::PARAMS`]) to numbers, or to
//!   variant names for enumerations. Missing keys take their defaults; unknown keys,
//!   non-finite, out-of-range or non-whole values are errors naming the key — a preset is
//!   never loaded half-right.
//! * Every `presets/*.json` of the repository is embedded at build time
//!   ([`BUILTIN_PRESETS`]), so a plugin bundle is self-contained.

use crate::params::{spec_by_key, ParamError, ParamKind, Params, PARAMS};
use core::fmt;
use serde_json::{Map, Value};

include!(concat!(env!("OUT_DIR"), "/builtin_presets.rs"));

/// The preset format version this build writes and reads.
pub const PRESET_VERSION: u64 = 1;

/// Name of the preset used when none is given.
pub const DEFAULT_PRESET: &str = "default";

/// A migration step: turns the `params` object of version `from` into version `from + 1`.
pub type Migration = fn(&mut Map<String, Value>);

/// Migrations, keyed by the version they upgrade from. Empty while only version 1 exists;
/// a later version that renames or rescales a parameter adds its step here.
pub static MIGRATIONS: &[(u64, Migration)] = &[];

/// A loaded preset.
#[derive(Clone, Debug, PartialEq)]
pub struct Preset {
    /// Display name.
    pub name: String,
    /// What the scene is, for people.
    pub description: String,
    /// The full parameter set (defaults for keys the file does not mention).
    pub params: Params,
}

/// Why a preset was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum PresetError {
    /// Not JSON, or not an object.
    Syntax(String),
    /// A required field is missing or of the wrong type.
    Field(&'static str),
    /// Written by a newer format version.
    FutureVersion {
        /// The file's version.
        found: u64,
    },
    /// A parameter value was refused.
    Param(ParamError),
    /// No built-in preset of that name.
    UnknownBuiltin(String),
}

impl fmt::Display for PresetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PresetError::Syntax(e) => write!(f, "not a valid preset file: {e}"),
            PresetError::Field(name) => write!(f, "preset field '{name}' is missing or has the wrong type"),
            PresetError::FutureVersion { found } => write!(
                f,
                "preset format version {found} is newer than this Trundle understands (version {PRESET_VERSION}); update Trundle"
            ),
            PresetError::Param(e) => write!(f, "{e}"),
            PresetError::UnknownBuiltin(n) => {
                write!(f, "no built-in preset '{n}' (available: ")?;
                for (i, (stem, _)) in BUILTIN_PRESETS.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{stem}")?;
                }
                write!(f, ")")
            }
        }
    }
}

impl std::error::Error for PresetError {}

impl From<ParamError> for PresetError {
    fn from(e: ParamError) -> Self {
        PresetError::Param(e)
    }
}

impl Preset {
    /// Parse a preset from JSON text (see the module docs for the rules).
    pub fn from_json(text: &str) -> Result<Self, PresetError> {
        let value: Value =
            serde_json::from_str(text).map_err(|e| PresetError::Syntax(e.to_string()))?;
        let obj = value
            .as_object()
            .ok_or_else(|| PresetError::Syntax("the top level is not an object".into()))?;
        for key in obj.keys() {
            if !matches!(
                key.as_str(),
                "trundle_preset" | "name" | "description" | "params"
            ) {
                return Err(PresetError::Syntax(format!("unknown field '{key}'")));
            }
        }
        let version = obj
            .get("trundle_preset")
            .and_then(Value::as_u64)
            .ok_or(PresetError::Field("trundle_preset"))?;
        if version > PRESET_VERSION || version == 0 {
            return Err(PresetError::FutureVersion { found: version });
        }
        let name = obj
            .get("name")
            .and_then(Value::as_str)
            .ok_or(PresetError::Field("name"))?
            .to_string();
        let description = match obj.get("description") {
            None => String::new(),
            Some(v) => v
                .as_str()
                .ok_or(PresetError::Field("description"))?
                .to_string(),
        };
        let mut map = match obj.get("params") {
            None => Map::new(),
            Some(v) => v.as_object().ok_or(PresetError::Field("params"))?.clone(),
        };
        for (from, step) in MIGRATIONS {
            if *from >= version {
                step(&mut map);
            }
        }
        let mut params = Params::default();
        for (key, v) in &map {
            let spec = spec_by_key(key).ok_or_else(|| ParamError::UnknownId(key.clone()))?;
            let value = match v {
                Value::Number(n) => {
                    spec.validate(n.as_f64().ok_or(ParamError::NotFinite { key: spec.key })?)?
                }
                Value::String(s) if matches!(spec.kind, ParamKind::Enum(_)) => spec.parse(s)?,
                other => {
                    return Err(ParamError::Unparsable {
                        key: spec.key,
                        text: other.to_string(),
                    }
                    .into())
                }
            };
            params.set(spec.id, value)?;
        }
        Ok(Self {
            name,
            description,
            params,
        })
    }

    /// Serialize to the current format (every parameter written; enums by name).
    pub fn to_json(&self) -> String {
        let mut params = Map::new();
        for (spec, v) in self.params.iter() {
            let value = match spec.kind {
                ParamKind::Enum(names) => Value::String(names[v as usize].to_string()),
                ParamKind::Int => Value::from(v as i64),
                ParamKind::Float { .. } => Value::from(v),
            };
            params.insert(spec.key.to_string(), value);
        }
        let mut top = Map::new();
        top.insert("trundle_preset".into(), Value::from(PRESET_VERSION));
        top.insert("name".into(), Value::String(self.name.clone()));
        top.insert(
            "description".into(),
            Value::String(self.description.clone()),
        );
        top.insert("params".into(), Value::Object(params));
        serde_json::to_string_pretty(&Value::Object(top)).expect("a JSON value always serializes")
    }

    /// A built-in preset by file stem (e.g. `"default"`).
    pub fn builtin(name: &str) -> Result<Self, PresetError> {
        let (_, text) = BUILTIN_PRESETS
            .iter()
            .find(|(stem, _)| *stem == name)
            .ok_or_else(|| PresetError::UnknownBuiltin(name.to_string()))?;
        Self::from_json(text)
    }
}

/// Number of parameters a preset can hold (for the docs and tests).
pub fn parameter_count() -> usize {
    PARAMS.len()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::ParamId;

    #[test]
    fn every_builtin_preset_loads_and_round_trips() {
        assert!(!BUILTIN_PRESETS.is_empty());
        assert!(BUILTIN_PRESETS.iter().any(|(s, _)| *s == DEFAULT_PRESET));
        for (stem, _) in BUILTIN_PRESETS {
            let p = Preset::builtin(stem).unwrap_or_else(|e| panic!("{stem}: {e}"));
            assert!(!p.name.is_empty() && !p.description.is_empty(), "{stem}");
            let again = Preset::from_json(&p.to_json()).unwrap();
            assert_eq!(again, p, "{stem}");
        }
    }

    #[test]
    fn bad_files_give_clear_errors() {
        let e = |t: &str| Preset::from_json(t).unwrap_err().to_string();
        assert!(e("").contains("not a valid preset"));
        assert!(e("[1,2]").contains("not an object"));
        assert!(e(r#"{"trundle_preset": 99, "name": "x"}"#).contains("newer"));
        assert!(e(r#"{"trundle_preset": 1}"#).contains("'name'"));
        assert!(
            e(r#"{"trundle_preset": 1, "name": "x", "params": {"bogus": 1}}"#)
                .contains("unknown parameter 'bogus'")
        );
        assert!(
            e(r#"{"trundle_preset": 1, "name": "x", "params": {"size": 7}}"#)
                .contains("out of range")
        );
        assert!(
            e(r#"{"trundle_preset": 1, "name": "x", "params": {"shape": "cube"}}"#)
                .contains("no variant 'cube'")
        );
        assert!(
            e(r#"{"trundle_preset": 1, "name": "x", "params": {"size": "big"}}"#).contains("size")
        );
        assert!(e(r#"{"trundle_preset": 1, "name": "x", "extra": 1}"#).contains("unknown field"));
        let p =
            Preset::from_json(r#"{"trundle_preset": 1, "name": "x", "params": {"shape": "bar"}}"#)
                .unwrap();
        assert_eq!(p.params.get(ParamId::Shape), 1.0);
        assert_eq!(
            p.params.get(ParamId::Size),
            Params::default().get(ParamId::Size)
        );
    }
}
