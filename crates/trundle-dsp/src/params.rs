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
        /// Shown (and typed) as a percentage of 1: 0.25 reads "25 %".
        percent: bool,
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

/// A parameter whose value is one of a few named variants (shape, output, engine…).
///
/// The variants' names live with the enum (one `impl` beside each enum), the table's
/// [`ParamKind::Enum`] rows take them from there, and [`Params`] hands out typed values
/// ([`Params::shape`], [`Params::engine`], …), so no code converts an index by hand.
///
/// **The one rule for a bad index**: [`ParamEnum::from_index`] clamps it to the nearest
/// variant (an index past the end is the last variant). A validated [`Params`] never holds
/// one; hosts' values are clamped into the table's range before they get here.
pub trait ParamEnum: Copy + Sized + PartialEq + 'static {
    /// Every variant, in index order (the order of [`ParamEnum::NAMES`]).
    const VARIANTS: &'static [Self];
    /// The stable names (presets, `--set`, plugin text), in index order.
    const NAMES: &'static [&'static str];
    /// The table row holding this enumeration.
    const ID: ParamId;

    /// The variant with index `i` (clamped: see the trait docs).
    fn from_index(i: usize) -> Self {
        Self::VARIANTS[i.min(Self::VARIANTS.len() - 1)]
    }

    /// The variant stored as the table value `v` (rounded; non-finite or negative → first).
    fn from_value(v: f64) -> Self {
        let i = if v.is_finite() && v > 0.0 {
            v.round() as usize
        } else {
            0
        };
        Self::from_index(i)
    }

    /// This variant's index (its value in a [`Params`] set and in presets).
    fn index(self) -> usize {
        Self::VARIANTS
            .iter()
            .position(|&v| v == self)
            .expect("VARIANTS lists every variant")
    }

    /// This variant's stable name.
    fn name(self) -> &'static str {
        Self::NAMES[self.index()]
    }
}

/// What the voice outputs: the object's sound, or the raw interaction force (TASLP Fig. 5:
/// the force is the quantity the analysis works on).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Output {
    /// The object excited by the force (the sound).
    #[default]
    Object,
    /// The interaction force itself, before the position stage and the object.
    Force,
}

impl ParamEnum for Output {
    const VARIANTS: &'static [Self] = &[Output::Object, Output::Force];
    const NAMES: &'static [&'static str] = &["object", "force"];
    const ID: ParamId = ParamId::Output;
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
    /// One-line documentation with the paper reference.
    pub doc: &'static str,
}

const FLOAT: ParamKind = ParamKind::Float {
    log: false,
    percent: false,
};
const LOG: ParamKind = ParamKind::Float {
    log: true,
    percent: false,
};
const PERCENT: ParamKind = ParamKind::Float {
    log: false,
    percent: true,
};

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
        kind: PERCENT,
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
        kind: PERCENT,
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
        kind: ParamKind::Enum(<crate::shape::Shape as ParamEnum>::NAMES),
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
        kind: ParamKind::Enum(<Output as ParamEnum>::NAMES),
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
        kind: ParamKind::Enum(<crate::modulation::AsymmetryLaw as ParamEnum>::NAMES),
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
        kind: PERCENT,
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
        kind: ParamKind::Enum(<crate::space::Trajectory as ParamEnum>::NAMES),
        doc: "manual = the ball stays at position_x/y; line = back and forth across the object through that point; circle = around the centre through that point; the ball moves at velocity V m/s (CMMR §3.3)",
    },    ParamSpec {
        id: ParamId::Engine,
        key: "engine",
        name: "Engine",
        unit: "",
        min: 0.0,
        max: 1.0,
        default: 0.0,
        kind: ParamKind::Enum(<crate::engine::Engine as ParamEnum>::NAMES),
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
        kind: ParamKind::Enum(<crate::object::Quality as ParamEnum>::NAMES),
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

    /// Parse text as a value, refusing what is not valid (`--set`, presets, tests).
    ///
    /// Accepted: a number (`0.5`, `-6`, `1e-3`, a Unicode minus `−6`); a number with the
    /// row's unit, with or without a space and with an SI prefix (`0.5 m/s`, `-6 dB`,
    /// `50 cm` for a row in metres, `500 mm/s`); a percentage on any 0…1 row (`25 %`);
    /// a factor on a `x` row (`×2`, `2x`); for an enumeration its variant name, any case,
    /// or its index. The result is validated: never clamped.
    pub fn parse(&self, text: &str) -> Result<f64, ParamError> {
        let v = self.read(text)?;
        self.validate(v)
    }

    /// Parse text typed into a host or the editor: as [`ParamSpec::parse`], but a value
    /// outside the range is clamped into it (what a user typing "200 %" into a 0…1 knob
    /// expects), and an integer or enumeration value is rounded.
    pub fn parse_clamped(&self, text: &str) -> Result<f64, ParamError> {
        let v = self.read(text)?;
        let v = v.clamp(self.min, self.max);
        Ok(match self.kind {
            ParamKind::Float { .. } => v,
            _ => v.round(),
        })
    }

    /// Read a number (with unit, prefix or percent) or a variant name; unvalidated.
    fn read(&self, text: &str) -> Result<f64, ParamError> {
        let t = text.trim();
        if let ParamKind::Enum(names) = self.kind {
            if let Some(i) = names.iter().position(|n| n.eq_ignore_ascii_case(t)) {
                return Ok(i as f64);
            }
        }
        // A plain number, including "nan" and "inf" (which validation then refuses by name).
        if let Ok(v) = t.parse::<f64>() {
            return Ok(v);
        }
        let unparsable = || ParamError::Unparsable {
            key: self.key,
            text: t.to_string(),
        };
        // Split into the number and what follows it.
        let t_norm = t.replace('\u{2212}', "-");
        let t_norm = t_norm.trim_start_matches('×').trim();
        let end = t_norm
            .char_indices()
            .find(|&(i, c)| {
                !(c.is_ascii_digit()
                    || c == '.'
                    || ((c == '-' || c == '+') && (i == 0 || t_norm[..i].ends_with(['e', 'E'])))
                    || ((c == 'e' || c == 'E')
                        && i > 0
                        && t_norm[i + 1..]
                            .starts_with(|d: char| d.is_ascii_digit() || d == '-' || d == '+')))
            })
            .map_or(t_norm.len(), |(i, _)| i);
        let (number, rest) = t_norm.split_at(end);
        let Ok(value) = number.parse::<f64>() else {
            return Err(match self.kind {
                ParamKind::Enum(names) => ParamError::UnknownVariant {
                    key: self.key,
                    name: t.to_string(),
                    allowed: names,
                },
                _ => unparsable(),
            });
        };
        let suffix = rest.trim();
        if suffix.is_empty() {
            return Ok(value);
        }
        if suffix == "%"
            && self.min >= 0.0
            && self.max <= 1.0
            && !matches!(self.kind, ParamKind::Enum(_))
        {
            return Ok(value / 100.0);
        }
        if self.unit == "x" && suffix.eq_ignore_ascii_case("x") {
            return Ok(value);
        }
        if !self.unit.is_empty() {
            if let Some(prefix) = suffix.strip_suffix(self.unit) {
                let scale = match prefix {
                    "" => Some(1.0),
                    "k" => Some(1e3),
                    "c" => Some(1e-2),
                    "m" => Some(1e-3),
                    "µ" | "u" => Some(1e-6),
                    _ => None,
                };
                if let Some(scale) = scale {
                    return Ok(value * scale);
                }
            }
            if suffix.eq_ignore_ascii_case(self.unit) {
                return Ok(value);
            }
        }
        Err(unparsable())
    }

    /// Format a value for people — the one formatter of the plugin's host text, the editor
    /// and the CLI: an enumeration by name, an integer without decimals, a 0…1 percentage
    /// row as "25 %", a factor as "×2.000", the rest with the row's unit ("0.500 m/s"),
    /// always with [`ParamSpec::decimals`] decimals.
    ///
    /// The plugin quantizes each continuous parameter to [`ParamSpec::step`], the resolution
    /// of this text, so every value it can hold reads back ([`ParamSpec::parse`]) as
    /// exactly itself: value → text → value is exact and text → value → text stable.
    pub fn format(&self, value: f64) -> String {
        match self.kind {
            ParamKind::Enum(names) => {
                let i = if value.is_finite() && value > 0.0 {
                    (value.round() as usize).min(names.len() - 1)
                } else {
                    0
                };
                names[i].to_string()
            }
            ParamKind::Int => format!("{}", value.round() as i64),
            ParamKind::Float { percent, .. } => {
                let d = self.decimals();
                if percent {
                    format!("{:.*} %", d.saturating_sub(2), value * 100.0)
                } else if self.unit == "x" {
                    format!("×{value:.d$}")
                } else if self.unit.is_empty() {
                    format!("{value:.d$}")
                } else {
                    format!("{value:.d$} {}", self.unit)
                }
            }
        }
    }

    /// Decimals of a continuous value's text: 1 on a range wider than 50 units (gain in dB),
    /// 2 on one wider than 5, otherwise 3 (logarithmic rows too: 0.050 … 5.000 m); a
    /// percentage row in whole percent (2 decimals of its 0…1 value); none for integers and
    /// enumerations.
    pub fn decimals(&self) -> usize {
        match self.kind {
            // Whole percent: "25 %".
            ParamKind::Float { percent: true, .. } => 2,
            ParamKind::Float { log: false, .. } => {
                let span = self.max - self.min;
                if span >= 50.0 {
                    1
                } else if span >= 5.0 {
                    2
                } else {
                    3
                }
            }
            ParamKind::Float { log: true, .. } => 3,
            _ => 0,
        }
    }

    /// The resolution of the text, 10^−[`ParamSpec::decimals`]: the step a host parameter
    /// is quantized to so that its text is exact.
    pub fn step(&self) -> f64 {
        10f64.powi(-(self.decimals() as i32))
    }

    /// A host value quantized to [`ParamSpec::step`] the way the plugin framework does it
    /// (in f32: `round(v / step)·step`), inside the range; integers and enumerations rounded.
    pub fn quantize(&self, v: f32) -> f32 {
        let q = match self.kind {
            ParamKind::Float { .. } => {
                let step = self.step() as f32;
                (v / step).round() * step
            }
            _ => v.round(),
        };
        q.clamp(self.min as f32, self.max as f32)
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
    pub fn variant<E: ParamEnum>(&self) -> E {
        E::from_value(self.get(E::ID))
    }
    /// Set an enumeration parameter from its typed value.
    pub fn set_variant<E: ParamEnum>(&mut self, v: E) {
        self.values[E::ID as usize] = v.index() as f64;
    }
    /// Object shape.
    pub fn shape(&self) -> crate::shape::Shape {
        self.variant()
    }
    /// What the voice outputs.
    pub fn output(&self) -> Output {
        self.variant()
    }
    /// Which engine makes the force.
    pub fn engine(&self) -> crate::engine::Engine {
        self.variant()
    }
    /// The accuracy/cost budget.
    pub fn quality(&self) -> crate::object::Quality {
        self.variant()
    }
    /// The ball's path.
    pub fn trajectory(&self) -> crate::space::Trajectory {
        self.variant()
    }
    /// How the AM depth follows the speed.
    pub fn asymmetry_law(&self) -> crate::modulation::AsymmetryLaw {
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

    /// Values a host can hold for a row: the ends, the default, and a sweep, quantized to
    /// the row's step as the plugin quantizes them (f32, as hosts store values).
    fn host_values(spec: &ParamSpec) -> Vec<f32> {
        let mut v = vec![spec.min, spec.max, spec.default];
        for k in 1..200 {
            let t = k as f64 / 200.0;
            v.push(match spec.kind {
                ParamKind::Float { log: true, .. } => spec.min * (spec.max / spec.min).powf(t),
                _ => spec.min + t * (spec.max - spec.min),
            });
        }
        v.push(1.0 / 3.0);
        v.push(2.0f64.sqrt() - 1.0);
        v.into_iter()
            .filter(|x| (spec.min..=spec.max).contains(x))
            .map(|x| spec.quantize(x as f32))
            .collect()
    }

    #[test]
    fn every_value_round_trips_through_its_text_exactly() {
        // value → text → value must give back the very f32 a host holds (after the same
        // quantization the plugin applies to every value it receives), and the text of that
        // value must be the same text (what the CLAP validator's param-conversions test
        // checks), for every row: enums, the seed, integers, floats.
        for spec in PARAMS.iter() {
            for v in host_values(spec) {
                let text = spec.format(f64::from(v));
                let back = spec
                    .parse(&text)
                    .unwrap_or_else(|e| panic!("{}: {v} -> {text:?} -> {e}", spec.key));
                assert_eq!(
                    spec.quantize(back as f32),
                    v,
                    "{}: {v} -> {text:?} -> {back}",
                    spec.key
                );
                assert_eq!(spec.format(back), text, "{}", spec.key);
                assert_eq!(spec.parse_clamped(&text), Ok(back), "{}", spec.key);
            }
        }
        // The largest seed survives (2^24 - 1 is exact in an f32).
        let seed = ParamId::Seed.spec();
        assert_eq!(seed.format(16_777_215.0), "16777215");
        assert_eq!(seed.parse("16777215"), Ok(16_777_215.0));
    }

    #[test]
    fn typed_text_is_read_with_and_without_units() {
        let ok = |key: &str, text: &str, want: f64| {
            let spec = spec_by_key(key).unwrap();
            let got = spec
                .parse(text)
                .unwrap_or_else(|e| panic!("{key} {text:?}: {e}"));
            assert!(
                (got - want).abs() < 1e-12,
                "{key} {text:?} -> {got}, want {want}"
            );
        };
        ok("velocity", "0.5", 0.5);
        ok("velocity", ".5", 0.5);
        ok("velocity", "0.5 m/s", 0.5);
        ok("velocity", "0.5m/s", 0.5);
        ok("velocity", "500 mm/s", 0.5);
        ok("velocity", "25 cm/s", 0.25);
        ok("roughness", "25 %", 0.25);
        ok("roughness", "25%", 0.25);
        ok("roughness", "0.25", 0.25);
        ok("asymmetry", "30 %", 0.3);
        ok("asymmetry", "30.5 %", 0.305);
        ok("gain_db", "-6 dB", -6.0);
        ok("gain_db", "\u{2212}6 dB", -6.0);
        ok("gain_db", "-6db", -6.0);
        ok("gain_db", "-6", -6.0);
        ok("object_size", "50 cm", 0.5);
        ok("object_size", "1.2 m", 1.2);
        ok("object_size", "120 mm", 0.12);
        ok("decay", "×2", 2.0);
        ok("decay", "2x", 2.0);
        ok("decay", "2", 2.0);
        ok("sharpness", "1e0", 1.0);
        ok("shape", "Bar", 1.0);
        ok("shape", "1", 1.0);
        ok("quality", "ULTRA", 3.0);
        ok("seed", "123456", 123_456.0);
        ok("modes", "64", 64.0);

        let err = |key: &str, text: &str| spec_by_key(key).unwrap().parse(text).unwrap_err();
        assert!(matches!(
            err("velocity", "0.5 kg"),
            ParamError::Unparsable { .. }
        ));
        assert!(matches!(
            err("velocity", "fast"),
            ParamError::Unparsable { .. }
        ));
        assert!(matches!(
            err("roughness", "150 %"),
            ParamError::OutOfRange { .. }
        ));
        assert!(matches!(err("size", "nan"), ParamError::NotFinite { .. }));
        assert!(matches!(
            err("shape", "cube"),
            ParamError::UnknownVariant { .. }
        ));
        assert!(matches!(err("modes", "3.5"), ParamError::NotWhole { .. }));
        // A percentage only where the row is a 0…1 amount.
        assert!(matches!(
            err("gain_db", "50 %"),
            ParamError::Unparsable { .. }
        ));
        // Hosts and the editor clamp instead of refusing.
        let r = spec_by_key("roughness").unwrap();
        assert_eq!(r.parse_clamped("150 %"), Ok(1.0));
        assert_eq!(spec_by_key("modes").unwrap().parse_clamped("3.4"), Ok(3.0));
    }

    #[test]
    fn enums_are_typed_with_one_rule_for_a_bad_index() {
        use crate::engine::Engine;
        use crate::object::Quality;
        use crate::shape::Shape;
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
