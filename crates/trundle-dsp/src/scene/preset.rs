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
//! * `automation` (optional) holds keyframe lanes for offline renders — a scene that moves:
//!   `{"action_x": [[0, -0.5], [4, 1.0]], ...}`, each point `[time_s, value]`, times
//!   non-decreasing, values validated like `params`, linear in between and held before the
//!   first and after the last point. The CLI renders them; in a DAW the host's automation
//!   plays this role and the plugin loads the lanes' first values.
//! * `balls` (optional) lists extra balls for offline renders, started and stopped like
//!   notes ([`crate::scene::balls`]): `[{"note": 60, "velocity": 0.7, "start_s": 0, "stop_s": 2}]`
//!   (note 0–127: pitch → size; velocity 0–1 → speed; `stop_s` optional = until the end).
//!   In a DAW, MIDI notes play this role.
//! * `object` (optional) replaces the recipe object (shape × material × size) by a fitted
//!   one, inline: the content of a `*.object.json` file (`trundle fit-object`,
//!   [`crate::object::fitted`]), validated like the file. Inline rather than a path, so a
//!   preset is one self-contained file and the presets embedded in the binary carry their
//!   object. The material, decay, size and width controls then act on it as modifiers
//!   ([`crate::object::fitted`]).
//! * `body_eq` (optional) is the object's body EQ curve ([`crate::scene::body_eq`]):
//!   `{"bands_hz": [...], "gain_db": [...]}`, gains (±40 dB) at increasing centres,
//!   interpolated onto the third-octave bands; the `body_eq` control sets how much plays.
//!   Absent = no curve (the model's own spectrum). `trundle match` writes it.
//! * `take` (optional) gives an offline render a finite take's edges ([`crate::scene::take`]):
//!   `{"pre_roll_s": 1, "fade_in_s": 0.4, "fade_out_s": 0.3}`, the scene run for `pre_roll_s`
//!   before the first sample, linear fades of 0–60 s at the render's start and end, each
//!   optional. `trundle match` writes it (a friction match's pre-roll, a recording's
//!   fades); the plugin and the runtime, which play on from the first touch without an
//!   end, ignore it.
//! * `match` (optional) is what `trundle match` recorded: the recording, the distance at the
//!   seeds it was validated at, each measure's value and verdict (docs/guide/match.md). Kept as
//!   written; it does not change the sound.
//! * Every `presets/*.json` of the repository is embedded at build time
//!   ([`BUILTIN_PRESETS`]), so a plugin bundle is self-contained.

use crate::object::fitted::{self, LoadedObject, ObjectFile};
use crate::params::{spec_by_key, ParamError, ParamId, ParamKind, ParamSpec, Params, PARAMS};
use crate::scene::body_eq::{self, BodyEqCurve};
use crate::scene::take::Take;
use core::fmt;
use serde_json::{Map, Value};
use std::sync::Arc;

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
    /// Keyframe lanes (empty for a static scene).
    pub automation: Vec<Lane>,
    /// Extra balls of the scene (empty for one ball).
    pub balls: Vec<BallNote>,
    /// A fitted object replacing the recipe object (`None`: the recipe).
    pub object: Option<ObjectFile>,
    /// The body EQ curve (`None`: no curve, the model's own spectrum).
    pub body_eq: Option<Arc<BodyEqCurve>>,
    /// How an offline render takes the scene: its pre-roll and fades (`None`: none;
    /// [`Take`]).
    pub take: Option<Take>,
    /// What `trundle match` recorded of how close the preset came to its recording (the
    /// `"match"` object, kept as written; `None`: not a match).
    pub matched: Option<Value>,
}

/// One extra ball of a scene: a note held from `start_s` to `stop_s`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallNote {
    /// Note number 0–127 (pitch → ball size, see [`crate::scene::balls`]).
    pub note: u8,
    /// Note velocity 0–1 (→ ball speed).
    pub velocity: f64,
    /// When the ball starts rolling (s).
    pub start_s: f64,
    /// When it stops (s); `None` = it rolls to the end of the render.
    pub stop_s: Option<f64>,
}

/// Most extra balls a preset may list.
pub const MAX_PRESET_BALLS: usize = 1024;

/// One automated parameter: keyframes `(time_s, value)`, linear in between.
#[derive(Clone, Debug, PartialEq)]
pub struct Lane {
    /// The parameter.
    pub id: ParamId,
    /// Keyframes, times non-decreasing.
    pub points: Vec<(f64, f64)>,
}

impl Lane {
    /// The lane's value at `time_s` (held outside the keyframes; enumerations and integers
    /// step at the next keyframe instead of gliding).
    pub fn value_at(&self, time_s: f64) -> f64 {
        let p = &self.points;
        if time_s <= p[0].0 {
            return p[0].1;
        }
        for w in p.windows(2) {
            let ((t0, v0), (t1, v1)) = (w[0], w[1]);
            if time_s < t1 {
                if !matches!(self.id.spec().kind, ParamKind::Float { .. }) || t1 <= t0 {
                    return v0;
                }
                return v0 + (v1 - v0) * (time_s - t0) / (t1 - t0);
            }
        }
        p[p.len() - 1].1
    }
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
    /// A malformed automation lane.
    Automation(String),
    /// A malformed ball list.
    Balls(String),
    /// A malformed fitted object.
    Object(String),
    /// A malformed body EQ curve.
    BodyEq(String),
    /// A malformed take.
    Take(String),
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
            PresetError::Automation(e) => write!(f, "automation: {e}"),
            PresetError::Balls(e) => write!(f, "balls: {e}"),
            PresetError::Object(e) => write!(f, "object: {e}"),
            PresetError::BodyEq(e) => write!(f, "body_eq: {e}"),
            PresetError::Take(e) => write!(f, "take: {e}"),
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
                "trundle_preset"
                    | "name"
                    | "description"
                    | "params"
                    | "automation"
                    | "balls"
                    | "object"
                    | "body_eq"
                    | "take"
                    | "match"
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
            params.set(spec.id, value_from_json(spec, v)?)?;
        }
        let automation = match obj.get("automation") {
            None => Vec::new(),
            Some(v) => parse_automation(v)?,
        };
        let balls = match obj.get("balls") {
            None => Vec::new(),
            Some(v) => parse_balls(v)?,
        };
        let object = match obj.get("object") {
            None => None,
            Some(v) => {
                let (object, source) = fitted::from_json(v).map_err(PresetError::Object)?;
                Some(ObjectFile { object, source })
            }
        };
        let body_eq = match obj.get("body_eq") {
            None => None,
            Some(v) => Some(Arc::new(
                body_eq::json::from_json(v).map_err(PresetError::BodyEq)?,
            )),
        };
        let take = match obj.get("take") {
            None => None,
            Some(v) => Some(parse_take(v)?),
        };
        let matched = match obj.get("match") {
            None => None,
            Some(v) if v.is_object() => Some(v.clone()),
            Some(_) => return Err(PresetError::Field("match")),
        };
        // A static load (the plugin) takes each lane's first value.
        for lane in &automation {
            params.set(lane.id, lane.points[0].1)?;
        }
        Ok(Self {
            name,
            description,
            params,
            automation,
            balls,
            object,
            body_eq,
            take,
            matched,
        })
    }

    /// The preset's fitted object prepared for a voice (`None` for the recipe object).
    ///
    /// # Allocation
    /// Allocates: call off the audio thread.
    pub fn loaded_object(&self) -> Result<Option<Arc<LoadedObject>>, PresetError> {
        match &self.object {
            None => Ok(None),
            Some(file) => LoadedObject::shared(file.clone())
                .map(Some)
                .map_err(PresetError::Object),
        }
    }

    /// A voice playing the preset's parameters and its fitted object, if it has one (an
    /// object that fails validation — only possible for a preset built in code — is left
    /// out: the recipe plays).
    ///
    /// # Allocation
    /// Allocates (a new voice).
    pub fn new_voice(&self, sample_rate_hz: f64) -> crate::scene::voice::Voice {
        let mut voice = crate::scene::voice::Voice::new(sample_rate_hz, &self.params);
        if let Ok(Some(o)) = self.loaded_object() {
            voice.set_loaded_object(Some(o));
            voice.reset();
        }
        voice.set_body_eq(self.body_eq.clone());
        voice
    }

    /// The extra balls as note events at their samples (`start_s`, `stop_s` rounded to
    /// samples at `sample_rate_hz`), sorted by sample; a note off and on of one note at one
    /// sample keep the file's order. For [`crate::scene::events::Scene`].
    ///
    /// # Allocation
    /// Allocates the list.
    pub fn note_events(&self, sample_rate_hz: f64) -> Vec<(u64, crate::scene::events::VoiceEvent)> {
        use crate::scene::events::VoiceEvent;
        let mut events = Vec::with_capacity(2 * self.balls.len());
        for b in &self.balls {
            events.push((
                (b.start_s * sample_rate_hz).round() as u64,
                VoiceEvent::NoteOn {
                    note: b.note,
                    velocity: b.velocity,
                },
            ));
            if let Some(stop) = b.stop_s {
                events.push((
                    (stop * sample_rate_hz).round() as u64,
                    VoiceEvent::NoteOff { note: b.note },
                ));
            }
        }
        events.sort_by_key(|e| e.0);
        events
    }

    /// The parameters at `time_s` of the scene: `params` with every lane applied.
    pub fn params_at(&self, time_s: f64) -> Params {
        let mut p = self.params;
        for lane in &self.automation {
            p.set_clamped(lane.id, lane.value_at(time_s));
        }
        p
    }

    /// Serialize to the current format (every parameter written; enums by name).
    pub fn to_json(&self) -> String {
        let mut params = Map::new();
        for (spec, v) in self.params.iter() {
            params.insert(spec.key.to_string(), value_to_json(spec, v));
        }
        let mut top = Map::new();
        top.insert("trundle_preset".into(), Value::from(PRESET_VERSION));
        top.insert("name".into(), Value::String(self.name.clone()));
        top.insert(
            "description".into(),
            Value::String(self.description.clone()),
        );
        top.insert("params".into(), Value::Object(params));
        if !self.automation.is_empty() {
            let mut lanes = Map::new();
            for lane in &self.automation {
                let spec = lane.id.spec();
                let points = lane
                    .points
                    .iter()
                    .map(|&(t, v)| Value::Array(vec![Value::from(t), value_to_json(spec, v)]))
                    .collect();
                lanes.insert(spec.key.to_string(), Value::Array(points));
            }
            top.insert("automation".into(), Value::Object(lanes));
        }
        if !self.balls.is_empty() {
            let list = self
                .balls
                .iter()
                .map(|b| {
                    let mut m = Map::new();
                    m.insert("note".into(), Value::from(b.note));
                    m.insert("velocity".into(), Value::from(b.velocity));
                    m.insert("start_s".into(), Value::from(b.start_s));
                    if let Some(t) = b.stop_s {
                        m.insert("stop_s".into(), Value::from(t));
                    }
                    Value::Object(m)
                })
                .collect();
            top.insert("balls".into(), Value::Array(list));
        }
        if let Some(o) = &self.object {
            top.insert("object".into(), fitted::to_json(&o.object, &o.source));
        }
        if let Some(c) = &self.body_eq {
            top.insert("body_eq".into(), body_eq::json::to_json(c));
        }
        if let Some(t) = &self.take {
            top.insert("take".into(), take_to_json(t));
        }
        if let Some(m) = &self.matched {
            top.insert("match".into(), m.clone());
        }
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

/// Most keyframes one lane may hold.
pub const MAX_KEYFRAMES: usize = 4096;

/// A parameter value from JSON: a number (validated, never clamped) or, for an enumeration,
/// a variant name.
fn value_from_json(spec: &ParamSpec, v: &Value) -> Result<f64, ParamError> {
    match v {
        Value::Number(n) => {
            spec.validate(n.as_f64().ok_or(ParamError::NotFinite { key: spec.key })?)
        }
        Value::String(s) if matches!(spec.kind, ParamKind::Enum(_)) => spec.parse(s),
        other => Err(ParamError::Unparsable {
            key: spec.key,
            text: other.to_string(),
        }),
    }
}

/// A parameter value as JSON: enumerations by name, integers as integers.
fn value_to_json(spec: &ParamSpec, v: f64) -> Value {
    match spec.kind {
        ParamKind::Enum(names) => Value::String(names[v as usize].to_string()),
        ParamKind::Int => Value::from(v as i64),
        ParamKind::Float { .. } => Value::from(v),
    }
}

fn parse_automation(v: &Value) -> Result<Vec<Lane>, PresetError> {
    let bad = |m: String| PresetError::Automation(m);
    let obj = v
        .as_object()
        .ok_or_else(|| bad("must be an object of lanes".into()))?;
    let mut lanes = Vec::new();
    for (key, pts) in obj {
        let spec = spec_by_key(key).ok_or_else(|| ParamError::UnknownId(key.clone()))?;
        if matches!(spec.id, ParamId::Seed | ParamId::Modes | ParamId::Shape) {
            return Err(bad(format!(
                "'{key}' cannot be automated in a preset (it restarts or rebuilds the scene)"
            )));
        }
        let arr = pts
            .as_array()
            .filter(|a| !a.is_empty() && a.len() <= MAX_KEYFRAMES)
            .ok_or_else(|| {
                bad(format!(
                    "'{key}' must be a list of 1 to {MAX_KEYFRAMES} [time_s, value] points"
                ))
            })?;
        let mut points = Vec::with_capacity(arr.len());
        for p in arr {
            let pair = p
                .as_array()
                .filter(|a| a.len() == 2)
                .ok_or_else(|| bad(format!("'{key}': each point is [time_s, value]")))?;
            let t = pair[0]
                .as_f64()
                .filter(|t| t.is_finite() && *t >= 0.0)
                .ok_or_else(|| {
                    bad(format!(
                        "'{key}': time {} is not a time in seconds ≥ 0",
                        pair[0]
                    ))
                })?;
            if points.last().is_some_and(|&(t0, _): &(f64, f64)| t < t0) {
                return Err(bad(format!("'{key}': times must not go backwards ({t} s)")));
            }
            points.push((t, value_from_json(spec, &pair[1])?));
        }
        lanes.push(Lane {
            id: spec.id,
            points,
        });
    }
    Ok(lanes)
}

/// A take as a preset writes it (and `trundle match` reports it):
/// `{"pre_roll_s": s, "fade_in_s": s, "fade_out_s": s}`.
pub fn take_to_json(t: &Take) -> Value {
    let mut m = Map::new();
    m.insert("pre_roll_s".into(), Value::from(t.pre_roll_s));
    m.insert("fade_in_s".into(), Value::from(t.fade_in_s));
    m.insert("fade_out_s".into(), Value::from(t.fade_out_s));
    Value::Object(m)
}

/// A take: `{"pre_roll_s": s, "fade_in_s": s, "fade_out_s": s}`, each optional (0), nothing
/// else.
fn parse_take(v: &Value) -> Result<Take, PresetError> {
    let obj = v
        .as_object()
        .ok_or_else(|| PresetError::Take("must be an object".into()))?;
    let mut edges = [0.0; 3];
    for (key, value) in obj {
        let slot = match key.as_str() {
            "pre_roll_s" => &mut edges[0],
            "fade_in_s" => &mut edges[1],
            "fade_out_s" => &mut edges[2],
            _ => return Err(PresetError::Take(format!("unknown field '{key}'"))),
        };
        *slot = value
            .as_f64()
            .ok_or_else(|| PresetError::Take(format!("{key} must be a number")))?;
    }
    Take::new(edges[0], edges[1], edges[2]).map_err(|e| PresetError::Take(e.to_string()))
}

fn parse_balls(v: &Value) -> Result<Vec<BallNote>, PresetError> {
    let bad = PresetError::Balls;
    let arr = v
        .as_array()
        .filter(|a| a.len() <= MAX_PRESET_BALLS)
        .ok_or_else(|| {
            bad(format!(
                "must be a list of at most {MAX_PRESET_BALLS} balls"
            ))
        })?;
    let mut out = Vec::with_capacity(arr.len());
    for (i, b) in arr.iter().enumerate() {
        let o = b
            .as_object()
            .ok_or_else(|| bad(format!("ball {i} is not an object")))?;
        for k in o.keys() {
            if !matches!(k.as_str(), "note" | "velocity" | "start_s" | "stop_s") {
                return Err(bad(format!("ball {i}: unknown field '{k}'")));
            }
        }
        let num = |k: &str| o.get(k).and_then(Value::as_f64).filter(|x| x.is_finite());
        let note = num("note")
            .filter(|n| (0.0..=127.0).contains(n) && n.fract() == 0.0)
            .ok_or_else(|| bad(format!("ball {i}: 'note' must be a whole number 0–127")))?;
        let velocity = num("velocity")
            .filter(|v| (0.0..=1.0).contains(v))
            .ok_or_else(|| bad(format!("ball {i}: 'velocity' must be a number 0–1")))?;
        let start_s = match o.get("start_s") {
            None => 0.0,
            Some(_) => num("start_s")
                .filter(|t| *t >= 0.0)
                .ok_or_else(|| bad(format!("ball {i}: 'start_s' must be a time ≥ 0")))?,
        };
        let stop_s = match o.get("stop_s") {
            None => None,
            Some(_) => Some(
                num("stop_s")
                    .filter(|t| *t >= start_s)
                    .ok_or_else(|| bad(format!("ball {i}: 'stop_s' must be a time ≥ start_s")))?,
            ),
        };
        out.push(BallNote {
            note: note as u8,
            velocity,
            start_s,
            stop_s,
        });
    }
    Ok(out)
}

/// Number of parameters a preset can hold (for the docs and tests).
pub fn parameter_count() -> usize {
    PARAMS.len()
}

#[cfg(test)]
mod tests;
