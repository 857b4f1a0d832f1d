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

use core::fmt;

/// How a parameter's value is interpreted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamKind {
    /// A continuous value; `log` asks editors for a logarithmic (skewed) control.
    Float {
        /// Display and automate on a logarithmic scale.
        log: bool,
    },
    /// A whole number in `[min, max]`.
    Int,
    /// One of the named variants; the value is the variant's index.
    Enum(&'static [&'static str]),
}

/// Identifies a parameter; the discriminant indexes [`PARAMS`] and [`Params`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(usize)]
pub enum ParamId {
    /// Ball size S.
    Size,
    /// Ball velocity V.
    Velocity,
    /// Surface roughness ρ.
    Roughness,
    /// Asymmetry m (AM depth).
    Asymmetry,
    /// Pulse sharpness ξ.
    Sharpness,
    /// Material disk x.
    MaterialX,
    /// Material disk y.
    MaterialY,
    /// Object size (m).
    ObjectSize,
    /// Object shape.
    Shape,
    /// Number of modes.
    Modes,
    /// Decay time multiplier.
    Decay,
    /// Output gain (dB).
    GainDb,
    /// Random seed.
    Seed,
    /// Output: the object's sound or the raw force.
    Output,
    /// Action disk x (rub–scratch–roll).
    ActionX,
    /// Action disk y.
    ActionY,
    /// How the AM depth follows the speed.
    AsymmetryLaw,
    /// Ball position on the object, x.
    PositionX,
    /// Ball position on the object, y.
    PositionY,
    /// Listening point, x.
    ListenX,
    /// Listening point, y.
    ListenY,
    /// Amount of position-dependent comb filtering.
    Comb,
    /// Ball trajectory.
    Trajectory,
    /// Which engine makes the force: signal model or physics (see [`crate::engine`]).
    Engine,
    /// Accuracy/cost budget: mode cap, culling, physics oversampling (see [`crate::object::Quality`]).
    Quality,
}

/// Names of the [`ParamId::Shape`] variants, in index order (see [`crate::shape::Shape`]).
pub const SHAPE_NAMES: &[&str] = &["string", "bar", "plate", "shell"];
/// Names of the [`ParamId::Output`] variants, in index order.
pub const OUTPUT_NAMES: &[&str] = &["object", "force"];
/// Names of the [`ParamId::AsymmetryLaw`] variants, in index order.
pub const ASYMMETRY_LAW_NAMES: &[&str] = &["constant", "speed2"];
/// Names of the [`ParamId::Trajectory`] variants, in index order.
pub const TRAJECTORY_NAMES: &[&str] = &["manual", "line", "circle"];
/// Names of the [`ParamId::Engine`] variants, in index order (see [`crate::engine::Engine`]).
pub const ENGINE_NAMES: &[&str] = &["signal", "physics"];
/// Names of the [`ParamId::Quality`] variants, in index order (see [`crate::object::Quality`]).
pub const QUALITY_NAMES: &[&str] = &["draft", "normal", "high", "ultra"];

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
    /// One-line documentation with the paper reference.
    pub doc: &'static str,
}

const FLOAT: ParamKind = ParamKind::Float { log: false };
const LOG: ParamKind = ParamKind::Float { log: true };

/// Number of parameters.
pub const PARAM_COUNT: usize = 25;

/// The parameter table, indexed by [`ParamId`].
pub const PARAMS: [ParamSpec; PARAM_COUNT] = [
    ParamSpec {
        id: ParamId::Size,
        key: "size",
        name: "Ball size",
        unit: "",
        min: 0.1,
        max: 1.0,
        default: 0.4,
        kind: FLOAT,
        doc: "Perceived ball size S (normalized radius); scales pulse duration t0 = 7.88e-4*S*A^-0.29 s (TASLP eq 16) and slows the AM (eq 17)",
    },
    ParamSpec {
        id: ParamId::Velocity,
        key: "velocity",
        name: "Velocity",
        unit: "m/s",
        min: 0.0,
        max: 1.0,
        default: 0.5,
        kind: FLOAT,
        doc: "Perceived ball velocity V: AM rate 3V/S Hz (TASLP eq 17), low-pass cutoff and loudness (CMMR §3.4); 0 = ball at rest, silence",
    },
    ParamSpec {
        id: ParamId::Roughness,
        key: "roughness",
        name: "Roughness",
        unit: "",
        min: 0.0,
        max: 1.0,
        default: 0.5,
        kind: FLOAT,
        doc: "Surface roughness rho: linear map between the columns of TASLP Table I (impact series statistics)",
    },
    ParamSpec {
        id: ParamId::Asymmetry,
        key: "asymmetry",
        name: "Asymmetry",
        unit: "",
        min: 0.0,
        max: 1.0,
        default: 0.3,
        kind: FLOAT,
        doc: "Ball asymmetry: amplitude modulation depth m (TASLP eq 7; the paper's natural value is 0.3)",
    },
    ParamSpec {
        id: ParamId::Sharpness,
        key: "sharpness",
        name: "Sharpness",
        unit: "",
        min: 0.5,
        max: 8.0,
        default: 1.0,
        kind: FLOAT,
        doc: "Pulse sharpness exponent xi (CMMR eq 3): 1 = raised cosine, larger = narrower, brighter impacts",
    },
    ParamSpec {
        id: ParamId::MaterialX,
        key: "material_x",
        name: "Material X",
        unit: "",
        min: -1.0,
        max: 1.0,
        default: 0.8,
        kind: FLOAT,
        doc: "Material disk x: wood at angle 0, metal at 2pi/3, glass at 4pi/3; inside the disk the anchors blend with their mean (Aramaki 2011, CMJ eqs 9-11)",
    },
    ParamSpec {
        id: ParamId::MaterialY,
        key: "material_y",
        name: "Material Y",
        unit: "",
        min: -1.0,
        max: 1.0,
        default: 0.0,
        kind: FLOAT,
        doc: "Material disk y (see material_x)",
    },
    ParamSpec {
        id: ParamId::ObjectSize,
        key: "object_size",
        name: "Object size",
        unit: "m",
        min: 0.05,
        max: 5.0,
        default: 1.0,
        kind: LOG,
        doc: "Characteristic length of the object; the first mode is f1 = 100 Hz * (1 m / size) (5 cm -> 2 kHz, 5 m -> 20 Hz)",
    },
    ParamSpec {
        id: ParamId::Shape,
        key: "shape",
        name: "Shape",
        unit: "",
        min: 0.0,
        max: 3.0,
        default: 2.0,
        kind: ParamKind::Enum(SHAPE_NAMES),
        doc: "Mode frequency series: string (harmonic, 1-D), bar (free-free beam, 1-D), plate (rectangular, 2-D), shell (bowl/glass ring modes with split doublets, 3-D)",
    },
    ParamSpec {
        id: ParamId::Modes,
        key: "modes",
        name: "Modes",
        unit: "",
        min: 1.0,
        max: 256.0,
        default: 32.0,
        kind: ParamKind::Int,
        doc: "Number of resonant modes of the object (quality/cost control); modes at or above Nyquist are dropped",
    },
    ParamSpec {
        id: ParamId::Decay,
        key: "decay",
        name: "Decay",
        unit: "x",
        min: 0.05,
        max: 30.0,
        default: 1.0,
        kind: LOG,
        doc: "Multiplier on every mode's decay time (the material sets the frequency dependence); decay times are bounded to 60 s",
    },
    ParamSpec {
        id: ParamId::GainDb,
        key: "gain_db",
        name: "Gain",
        unit: "dB",
        min: -60.0,
        max: 12.0,
        default: 0.0,
        kind: FLOAT,
        doc: "Output gain",
    },
    ParamSpec {
        id: ParamId::Seed,
        key: "seed",
        name: "Seed",
        unit: "",
        min: 0.0,
        max: 16_777_215.0,
        default: 1.0,
        kind: ParamKind::Int,
        doc: "Random seed: the same seed and parameters give the same samples (0 to 2^24 - 1, so a host parameter, an f32, holds every seed exactly)",
    },
    ParamSpec {
        id: ParamId::Output,
        key: "output",
        name: "Output",
        unit: "",
        min: 0.0,
        max: 1.0,
        default: 0.0,
        kind: ParamKind::Enum(OUTPUT_NAMES),
        doc: "object = the resonating object's sound; force = the raw interaction force before the object",
    },
    ParamSpec {
        id: ParamId::ActionX,
        key: "action_x",
        name: "Action X",
        unit: "",
        min: -1.0,
        max: 1.0,
        default: crate::source::ROLL_X,
        kind: FLOAT,
        doc: "Action disk x: rub at angle 0, scratch at 2pi/3, roll at 4pi/3 (the default); inside the disk the three parameter sets blend with their mean, densities as mixtures (CMJ eqs 8-11); points outside the circle are projected onto it",
    },
    ParamSpec {
        id: ParamId::ActionY,
        key: "action_y",
        name: "Action Y",
        unit: "",
        min: -1.0,
        max: 1.0,
        default: crate::source::ROLL_Y,
        kind: FLOAT,
        doc: "Action disk y (see action_x)",
    },
    ParamSpec {
        id: ParamId::AsymmetryLaw,
        key: "asymmetry_law",
        name: "Asymmetry law",
        unit: "",
        min: 0.0,
        max: 1.0,
        default: 0.0,
        kind: ParamKind::Enum(ASYMMETRY_LAW_NAMES),
        doc: "constant = AM depth m at every speed (TASLP eq 7); speed2 = depth grows with the square of the rolling rate, as Rath's off-centre-mass force (DAFx 2003 eq 4), equal to m at the default speed and size",
    },
    ParamSpec {
        id: ParamId::PositionX,
        key: "position_x",
        name: "Position X",
        unit: "",
        min: -1.0,
        max: 1.0,
        default: 0.3,
        kind: FLOAT,
        doc: "Ball position on the object, x (-1 and 1 are the edges); the start point of the line and circle trajectories (CMMR §3.3)",
    },
    ParamSpec {
        id: ParamId::PositionY,
        key: "position_y",
        name: "Position Y",
        unit: "",
        min: -1.0,
        max: 1.0,
        default: 0.2,
        kind: FLOAT,
        doc: "Ball position on the object, y (see position_x)",
    },
    ParamSpec {
        id: ParamId::ListenX,
        key: "listen_x",
        name: "Listen X",
        unit: "",
        min: -1.0,
        max: 1.0,
        default: -0.5,
        kind: FLOAT,
        doc: "Listening (pick-up) point on the object, x: the image-source delays are path differences to this point (CMMR §3.3)",
    },
    ParamSpec {
        id: ParamId::ListenY,
        key: "listen_y",
        name: "Listen Y",
        unit: "",
        min: -1.0,
        max: 1.0,
        default: -0.4,
        kind: FLOAT,
        doc: "Listening point, y (see listen_x)",
    },
    ParamSpec {
        id: ParamId::Comb,
        key: "comb",
        name: "Position amount",
        unit: "",
        min: 0.0,
        max: 1.0,
        default: 0.0,
        kind: FLOAT,
        doc: "Amount of position-dependent comb filtering from first-order image sources in the object's four edges (CMMR §3.3); 0 = off (and free)",
    },
    ParamSpec {
        id: ParamId::Trajectory,
        key: "trajectory",
        name: "Trajectory",
        unit: "",
        min: 0.0,
        max: 2.0,
        default: 0.0,
        kind: ParamKind::Enum(TRAJECTORY_NAMES),
        doc: "manual = the ball stays at position_x/y; line = back and forth across the object through that point; circle = around the centre through that point; the ball moves at velocity V m/s (CMMR §3.3)",
    },    ParamSpec {
        id: ParamId::Engine,
        key: "engine",
        name: "Engine",
        unit: "",
        min: 0.0,
        max: 1.0,
        default: 0.0,
        kind: ParamKind::Enum(ENGINE_NAMES),
        doc: "signal = the fast statistical model (TASLP Fig. 5); physics = a Hunt-Crossley ball on a fractal surface integrated by RK4 (TASLP §II-A, §III; Rath 2003), driven by the same size/velocity/roughness/asymmetry controls; switching crossfades over 20 ms",
    },
    ParamSpec {
        id: ParamId::Quality,
        key: "quality",
        name: "Quality",
        unit: "",
        min: 0.0,
        max: 3.0,
        default: 2.0,
        kind: ParamKind::Enum(QUALITY_NAMES),
        doc: "Cost budget: draft = at most 16 modes, modes 50 dB below the loudest culled, physics RK4 1x; normal = at most 64 modes, culling at -70 dB; high = every requested mode, culling at -90 dB; ultra = no culling, physics RK4 8x. Culled and capped modes ring out (no clicks)",
    },
];

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

    /// Parse text as a value: a number, or for enums a variant name (case-insensitive).
    pub fn parse(&self, text: &str) -> Result<f64, ParamError> {
        let t = text.trim();
        if let ParamKind::Enum(names) = self.kind {
            if let Some(i) = names.iter().position(|n| n.eq_ignore_ascii_case(t)) {
                return Ok(i as f64);
            }
            if t.parse::<f64>().is_err() {
                return Err(ParamError::UnknownVariant {
                    key: self.key,
                    name: t.to_string(),
                    allowed: names,
                });
            }
        }
        let v: f64 = t.parse().map_err(|_| ParamError::Unparsable {
            key: self.key,
            text: t.to_string(),
        })?;
        self.validate(v)
    }

    /// Format a value for people: enums by name, integers without decimals, the rest with
    /// the unit.
    pub fn format(&self, value: f64) -> String {
        match self.kind {
            ParamKind::Enum(names) => names
                .get(value.max(0.0) as usize)
                .copied()
                .unwrap_or("?")
                .to_string(),
            ParamKind::Int => format!("{}", value.round() as i64),
            ParamKind::Float { .. } => {
                if self.unit.is_empty() {
                    format!("{value:.3}")
                } else {
                    format!("{value:.3} {}", self.unit)
                }
            }
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
        self.get(ParamId::Output) == 1.0
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
}
