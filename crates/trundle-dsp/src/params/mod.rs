//! The one parameter table: stable IDs, ranges, defaults, units and documentation.
//!
//! Everything that names a parameter — the plugin's parameters, the CLI's `--set ID=VALUE`,
//! preset files, the editor, the tests — reads [`PARAMS`]. IDs are short, stable and never
//! renamed once presets exist (the core ones `size`, `velocity`, `roughness`, `asymmetry`,
//! `sharpness` come from the papers' controls).
//!
//! Values are stored as `f64` in a [`Params`] set. Enumerations are stored as the index of
//! their variant; integer parameters as whole numbers. [`Params::set`] validates (finite,
//! inside the range, whole where it must be) and never clamps silently: out-of-range input
//! is an error naming the parameter and its range.
//!
//! The module is a leaf of the crate: it imports nothing of the model.
//!
//! * `table.rs` declares every control once (`schema!`): its Rust name, key, name, unit,
//!   values, default, place in the editor ([`place`]), randomize group and documentation.
//!   [`ParamId`], [`PARAMS`], [`PARAM_COUNT`] and the choice rows' link to their
//!   enumerations ([`ChoiceRow`]) are generated from it.
//! * [`choice`] declares the choice enumerations (shape, engine, gesture…) with their
//!   stable names; a choice row's names and range come from its enumeration.
//! * `text.rs` formats and parses values (units, percentages, variant names).
//!
//! Adding a scalar control is one row in `table.rs` (plus the code that uses it); adding a
//! variant to a choice is one line in its enumeration in [`choice`] (plus its `match`
//! arms in the module that models it).

use core::fmt;

pub mod choice;
pub mod place;
#[macro_use]
mod schema;
mod table;
mod text;
mod values;

pub use choice::{
    AsymmetryLaw, BallMaterial, Engine, GestureKind, Limiting, Output, ParamEnum, Quality, RubBody,
    Shape, Trajectory,
};
pub use place::{Group, Page, Panel, Place, Section};
pub use table::{ChoiceRow, ParamId, Values, PARAMS, PARAM_COUNT};

/// How a parameter's value is interpreted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamKind {
    /// A continuous value; `log` asks editors for a logarithmic (skewed) control.
    Float {
        /// Display and automate on a logarithmic scale.
        log: bool,
        /// Shown (and typed) as a percentage of 1: 0.25 reads "25 %".
        percent: bool,
    },
    /// A whole number in `[min, max]`.
    Int,
    /// One of the named variants; the value is the variant's index.
    Enum(&'static [&'static str]),
}

/// The description of one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// Which parameter.
    pub id: ParamId,
    /// Stable short ID used in presets, `--set`, plugin state and automation.
    pub key: &'static str,
    /// Human-readable name.
    pub name: &'static str,
    /// Unit shown after the value ("" for none).
    pub unit: &'static str,
    /// Smallest allowed value.
    pub min: f64,
    /// Largest allowed value.
    pub max: f64,
    /// Default value.
    pub default: f64,
    /// Interpretation of the value.
    pub kind: ParamKind,
    /// Where the plugin's editor draws it.
    pub place: Place,
    /// The randomize group it is drawn and locked with (`None`: randomize leaves it alone).
    pub group: Option<Group>,
    /// One-line documentation with the paper reference.
    pub doc: &'static str,
}

/// Look a parameter up by its stable key.
pub fn spec_by_key(key: &str) -> Option<&'static ParamSpec> {
    PARAMS.iter().find(|p| p.key == key)
}

impl ParamId {
    /// The parameter's row in [`PARAMS`].
    pub fn spec(self) -> &'static ParamSpec {
        &PARAMS[self as usize]
    }
    /// The stable key.
    pub fn key(self) -> &'static str {
        self.spec().key
    }
}

/// Why a parameter value was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamError {
    /// No parameter has this key.
    UnknownId(String),
    /// NaN or infinite.
    NotFinite {
        /// Parameter key.
        key: &'static str,
    },
    /// Outside `[min, max]`.
    OutOfRange {
        /// Parameter key.
        key: &'static str,
        /// The refused value.
        value: f64,
        /// Smallest allowed.
        min: f64,
        /// Largest allowed.
        max: f64,
    },
    /// An integer or enum parameter got a fractional value.
    NotWhole {
        /// Parameter key.
        key: &'static str,
        /// The refused value.
        value: f64,
    },
    /// An enum parameter got a name that is not one of its variants.
    UnknownVariant {
        /// Parameter key.
        key: &'static str,
        /// The refused name.
        name: String,
        /// The allowed names.
        allowed: &'static [&'static str],
    },
    /// A value that is neither a number nor a variant name.
    Unparsable {
        /// Parameter key.
        key: &'static str,
        /// The refused text.
        text: String,
    },
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamError::UnknownId(k) => {
                write!(f, "unknown parameter '{k}' (known: ")?;
                for (i, p) in PARAMS.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{}", p.key)?;
                }
                write!(f, ")")
            }
            ParamError::NotFinite { key } => write!(f, "parameter '{key}' must be a finite number"),
            ParamError::OutOfRange {
                key,
                value,
                min,
                max,
            } => write!(
                f,
                "parameter '{key}' = {value} is out of range [{min}, {max}]"
            ),
            ParamError::NotWhole { key, value } => {
                write!(f, "parameter '{key}' = {value} must be a whole number")
            }
            ParamError::UnknownVariant { key, name, allowed } => write!(
                f,
                "parameter '{key}' has no variant '{name}' (allowed: {})",
                allowed.join(", ")
            ),
            ParamError::Unparsable { key, text } => {
                write!(f, "parameter '{key}': cannot read '{text}' as a value")
            }
        }
    }
}

impl std::error::Error for ParamError {}

impl ParamSpec {
    /// Validate a numeric value for this parameter (no clamping).
    pub fn validate(&self, value: f64) -> Result<f64, ParamError> {
        if !value.is_finite() {
            return Err(ParamError::NotFinite { key: self.key });
        }
        if value < self.min || value > self.max {
            return Err(ParamError::OutOfRange {
                key: self.key,
                value,
                min: self.min,
                max: self.max,
            });
        }
        match self.kind {
            ParamKind::Int | ParamKind::Enum(_) if value.fract() != 0.0 => {
                Err(ParamError::NotWhole {
                    key: self.key,
                    value,
                })
            }
            _ => Ok(value),
        }
    }
}

/// A complete, validated parameter set (values in the units of [`PARAMS`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    values: [f64; PARAM_COUNT],
}

impl Default for Params {
    fn default() -> Self {
        let mut values = [0.0; PARAM_COUNT];
        for (v, p) in values.iter_mut().zip(PARAMS.iter()) {
            *v = p.default;
        }
        Self { values }
    }
}

impl Params {
    /// The value of a parameter.
    #[inline]
    pub fn get(&self, id: ParamId) -> f64 {
        self.values[id as usize]
    }

    /// Set a parameter, refusing non-finite, out-of-range or non-whole values.
    pub fn set(&mut self, id: ParamId, value: f64) -> Result<(), ParamError> {
        self.values[id as usize] = id.spec().validate(value)?;
        Ok(())
    }

    /// Set a parameter, clamping into range and replacing non-finite input by the current
    /// value. For hosts and automation, where refusing is not an option; it never produces
    /// a value outside the table.
    pub fn set_clamped(&mut self, id: ParamId, value: f64) {
        let s = id.spec();
        if !value.is_finite() {
            return;
        }
        let mut v = value.clamp(s.min, s.max);
        if !matches!(s.kind, ParamKind::Float { .. }) {
            v = v.round();
        }
        self.values[id as usize] = v;
    }

    /// Set a parameter by key from text (`--set key=value`, preset loaders).
    pub fn set_text(&mut self, key: &str, text: &str) -> Result<(), ParamError> {
        let spec = spec_by_key(key).ok_or_else(|| ParamError::UnknownId(key.to_string()))?;
        let v = spec.parse(text)?;
        self.values[spec.id as usize] = v;
        Ok(())
    }

    /// Set a parameter by key from a number.
    pub fn set_key(&mut self, key: &str, value: f64) -> Result<(), ParamError> {
        let spec = spec_by_key(key).ok_or_else(|| ParamError::UnknownId(key.to_string()))?;
        self.set(spec.id, value)
    }

    /// Ball size S.
    pub fn size(&self) -> f64 {
        self.get(ParamId::Size)
    }
    /// Velocity V.
    pub fn velocity(&self) -> f64 {
        self.get(ParamId::Velocity)
    }
    /// Roughness ρ.
    pub fn roughness(&self) -> f64 {
        self.get(ParamId::Roughness)
    }
    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.get(ParamId::Modes) as usize
    }
    /// Seed.
    pub fn seed(&self) -> u64 {
        self.get(ParamId::Seed) as u64
    }
    /// Output gain as a linear factor.
    pub fn gain_linear(&self) -> f64 {
        10f64.powf(self.get(ParamId::GainDb) / 20.0)
    }
    /// True when the raw force is the output.
    pub fn force_only(&self) -> bool {
        self.output() == Output::Force
    }
    /// The typed value of an enumeration parameter.
    pub fn variant<E: ChoiceRow>(&self) -> E {
        E::from_value(self.get(E::ID))
    }
    /// Set an enumeration parameter from its typed value.
    pub fn set_variant<E: ChoiceRow>(&mut self, v: E) {
        self.values[E::ID as usize] = v.index() as f64;
    }
    /// Object shape.
    pub fn shape(&self) -> Shape {
        self.variant()
    }
    /// What the voice outputs.
    pub fn output(&self) -> Output {
        self.variant()
    }
    /// Which engine makes the force.
    pub fn engine(&self) -> Engine {
        self.variant()
    }
    /// What the ball is made of.
    pub fn ball_material(&self) -> BallMaterial {
        self.variant()
    }
    /// What rubs the object in the friction contact.
    pub fn rub_body(&self) -> RubBody {
        self.variant()
    }
    /// The gesture (roll, drop, spin).
    pub fn gesture(&self) -> GestureKind {
        self.variant()
    }
    /// Whether the output safety limiter acts.
    pub fn limiting(&self) -> Limiting {
        self.variant()
    }
    /// The stereo width (0 = mono … 1).
    pub fn width(&self) -> f64 {
        self.get(ParamId::Width)
    }
    /// The accuracy/cost budget.
    pub fn quality(&self) -> Quality {
        self.variant()
    }
    /// The ball's path.
    pub fn trajectory(&self) -> Trajectory {
        self.variant()
    }
    /// How the AM depth follows the speed.
    pub fn asymmetry_law(&self) -> AsymmetryLaw {
        self.variant()
    }
    /// The hardest steady scene the table allows, for soak tests (`trundle soak`,
    /// `tests/soak.rs`): the longest-ringing material (between metal and glass on the disk),
    /// decay ×30 (modes ring up to the 60 s bound), the largest object (20 Hz first mode),
    /// every mode (256) of the densest low series (string), the fastest, most asymmetric
    /// ball. A test that cannot afford 256 modes lowers `modes` itself, visibly.
    pub fn extreme() -> Params {
        let mut p = Params::default();
        for (id, v) in [
            (ParamId::MaterialX, -0.5),
            (ParamId::MaterialY, 0.866),
            (ParamId::Decay, 30.0),
            (ParamId::ObjectSize, 5.0),
            (ParamId::Modes, 256.0),
            (ParamId::Shape, 0.0),
            (ParamId::Velocity, 1.0),
            (ParamId::Asymmetry, 1.0),
        ] {
            p.set(id, v).expect("the extreme scene is inside the table");
        }
        p
    }

    /// Iterate over `(spec, value)`.
    pub fn iter(&self) -> impl Iterator<Item = (&'static ParamSpec, f64)> + '_ {
        PARAMS.iter().zip(self.values.iter().copied())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_indexed_by_id_and_keys_are_unique() {
        for (i, p) in PARAMS.iter().enumerate() {
            assert_eq!(p.id as usize, i, "{} out of order", p.key);
            assert!(p.min <= p.default && p.default <= p.max, "{}", p.key);
            assert!(!p.doc.is_empty());
            assert_eq!(
                PARAMS.iter().filter(|q| q.key == p.key).count(),
                1,
                "duplicate key {}",
                p.key
            );
            assert!(p.key.bytes().all(|b| b.is_ascii_lowercase() || b == b'_'));
        }
    }

    #[test]
    fn set_refuses_bad_values_and_keeps_the_old_one() {
        let mut p = Params::default();
        assert!(matches!(
            p.set(ParamId::Size, f64::NAN),
            Err(ParamError::NotFinite { .. })
        ));
        assert!(matches!(
            p.set(ParamId::Size, 2.0),
            Err(ParamError::OutOfRange { .. })
        ));
        assert!(matches!(
            p.set(ParamId::Modes, 3.5),
            Err(ParamError::NotWhole { .. })
        ));
        assert!(matches!(
            p.set_text("nope", "1"),
            Err(ParamError::UnknownId(_))
        ));
        assert!(matches!(
            p.set_text("shape", "cube"),
            Err(ParamError::UnknownVariant { .. })
        ));
        assert_eq!(p, Params::default());
        p.set_text("shape", "Shell").unwrap();
        assert_eq!(p.get(ParamId::Shape), 3.0);
        p.set_clamped(ParamId::Velocity, f64::INFINITY);
        assert_eq!(p.velocity(), 0.5);
        p.set_clamped(ParamId::Velocity, 7.0);
        assert_eq!(p.velocity(), 1.0);
    }

    #[test]
    fn enums_are_typed_with_one_rule_for_a_bad_index() {
        let mut p = Params::default();
        assert_eq!(p.shape(), Shape::Plate);
        assert_eq!(p.output(), Output::Object);
        p.set_text("shape", "shell").unwrap();
        p.set_text("engine", "physics").unwrap();
        assert_eq!(p.shape(), Shape::Shell);
        assert_eq!(p.engine(), Engine::Physics);
        p.set_variant(Quality::Draft);
        assert_eq!(p.get(ParamId::Quality), 0.0);
        // Every enumeration row takes its names from its enum, in index order.
        assert_eq!(ParamId::Shape.spec().kind, ParamKind::Enum(Shape::NAMES));
        for (i, s) in Shape::VARIANTS.iter().enumerate() {
            assert_eq!(s.index(), i);
            assert_eq!(s.name(), Shape::NAMES[i]);
        }
        // The one rule: clamp to the nearest variant.
        assert_eq!(Shape::from_index(99), Shape::Shell);
        assert_eq!(Quality::from_value(-3.0), Quality::Draft);
        assert_eq!(Quality::from_value(f64::NAN), Quality::Draft);
        assert_eq!(Engine::from_value(0.6), Engine::Physics);
    }
}
