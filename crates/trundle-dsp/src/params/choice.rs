//! The choice enumerations of the parameter table: a leaf that knows nothing of the model.
//!
//! Each enumeration is declared once through [`choice!`](crate::params::choice) with its
//! variants and their stable names side by side; the macro yields the [`ParamEnum`]
//! implementation (`VARIANTS`, `NAMES`, `COUNT`, `from_index`, `index`, `name`) and the
//! inherent `ALL` and `value`. The table's choice rows take their names and their range
//! (`0 ..= COUNT − 1`) from here, so a new variant is one line in its enum and reachable
//! everywhere at once. What a variant *does* stays with the module that models it
//! (`shape`, `engine`, `gesture`, …), which imports the enum from here.

/// A parameter whose value is one of a few named variants (shape, output, engine…).
///
/// Declared with [`choice!`](crate::params::choice); the table's choice rows take their
/// names and range from it, and [`Params`](super::Params) hands out typed values
/// ([`Params::shape`](super::Params::shape), …), so no code converts an index by hand.
///
/// **The one rule for a bad index**: [`ParamEnum::from_index`] clamps it to the nearest
/// variant (an index past the end is the last variant). A validated `Params` never holds
/// one; hosts' values are clamped into the table's range before they get here.
pub trait ParamEnum: Copy + Sized + PartialEq + 'static {
    /// Every variant, in index order (the order of [`ParamEnum::NAMES`]).
    const VARIANTS: &'static [Self];
    /// The stable names (presets, `--set`, plugin text), in index order.
    const NAMES: &'static [&'static str];
    /// How many variants there are: the table row's range is `0 ..= COUNT − 1`.
    const COUNT: usize = Self::NAMES.len();

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

    /// This variant's index (its value in a `Params` set and in presets).
    fn index(self) -> usize;

    /// This variant's stable name.
    fn name(self) -> &'static str {
        Self::NAMES[self.index()]
    }
}

/// Declare a choice enumeration: its attributes, then each variant with its docs and its
/// stable name (`Variant = "name",`), in index order. Yields the enum, its [`ParamEnum`]
/// implementation and the inherent `ALL` (every variant) and `value` (the variant as a
/// table value, usable in constants such as a row's default).
macro_rules! choice {
    (
        $(#[$meta:meta])*
        pub enum $E:ident {
            $( $(#[$vmeta:meta])* $V:ident = $name:literal, )+
        }
    ) => {
        $(#[$meta])*
        pub enum $E {
            $( $(#[$vmeta])* $V, )+
        }

        impl $E {
            /// Every variant, in parameter-index order.
            pub const ALL: [$E; [$($name),+].len()] = [$($E::$V),+];

            /// This variant as a table value (its index).
            pub const fn value(self) -> f64 {
                self as usize as f64
            }
        }

        impl ParamEnum for $E {
            const VARIANTS: &'static [Self] = &Self::ALL;
            const NAMES: &'static [&'static str] = &[$($name),+];

            fn index(self) -> usize {
                self as usize
            }
        }
    };
}

choice! {
    /// What the voice outputs: the object's sound, or the raw interaction force (TASLP
    /// Fig. 5: the force is the quantity the analysis works on).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum Output {
        /// The object excited by the force (the sound).
        #[default]
        Object = "object",
        /// The interaction force itself, before the position stage and the object.
        Force = "force",
    }
}

choice! {
    /// An object shape (its modes: `crate::shape`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub enum Shape {
        /// Harmonic string (1-D).
        String = "string",
        /// Free–free bar (1-D).
        Bar = "bar",
        /// Rectangular plate (2-D).
        Plate = "plate",
        /// Shell: bowl, glass, bell (3-D).
        Shell = "shell",
    }
}

choice! {
    /// How the modulation depth follows the ball's motion (`crate::modulation`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum AsymmetryLaw {
        /// Depth m whatever the speed (TASLP eq 7, CMMR's asymmetry control).
        #[default]
        Constant = "constant",
        /// Rath (DAFx 2003 §5, eq 4): the force term of an off-centre mass is the second
        /// derivative of a sinusoidal height, so it grows with the square of the angular
        /// speed, (v/R)² ∝ ν_m². Depth m·(ν_m/ν_ref)², capped at 1, with ν_ref = 3.75 Hz (the
        /// AM rate of the default V = 0.5, S = 0.4, where both laws agree).
        Speed2 = "speed2",
    }
}

choice! {
    /// The ball's path (`crate::space`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum Trajectory {
        /// The ball stays at the set position (automate it to move it).
        #[default]
        Manual = "manual",
        /// Back and forth along x through the set position.
        Line = "line",
        /// Round the centre through the set position.
        Circle = "circle",
        /// Circling and spiralling down into a parabolic bowl: the radius shrinks from the
        /// set position's to 0 over the path time, the speed with it (docs/MODEL.md §11).
        Bowl = "bowl",
        /// Released from rest on a ramp: along the line, accelerating uniformly to V.
        Ramp = "ramp",
        /// Along the line, slowing uniformly from V to rest.
        SlowToStop = "slow-to-stop",
    }
}

choice! {
    /// Which engine makes the interaction force (`crate::engine`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Engine {
        /// The signal model: impact series → pulses → AM → low-pass (TASLP Fig. 5).
        Signal = "signal",
        /// The physics engine: Hunt–Crossley ball on a fractal surface (TASLP §II-A, §III).
        Physics = "physics",
    }
}

choice! {
    /// The accuracy/cost budget (the `quality` parameter): mode cap, high-band slots,
    /// culling threshold and the physics engine's oversampling (`crate::object`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum Quality {
        /// At most 16 modes, 8 high-band slots, culling at −50 dB, physics RK4 at one step
        /// per sample.
        Draft = "draft",
        /// At most 64 modes, 16 high-band slots, culling at −70 dB, automatic physics
        /// oversampling.
        Normal = "normal",
        /// Every requested mode (≤ 256), 24 high-band slots, culling at −90 dB, automatic
        /// physics oversampling.
        #[default]
        High = "high",
        /// Every requested mode, 48 high-band slots, no culling, physics RK4 at the maximum
        /// oversampling.
        Ultra = "ultra",
        /// Every mode of the shape's series below min(Nyquist, the high band's top)
        /// explicitly (up to the reference mode count), no high band, no culling: the judge
        /// the other qualities are measured against. Offline only (thousands of modes).
        Reference = "reference",
    }
}

choice! {
    /// Whether the output safety limiter acts (the `limiter` parameter, `crate::limiter`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum Limiting {
        /// The engine's level as is (the look-ahead delay stays: constant latency).
        Off = "off",
        /// Peaks above the ceiling are limited (the default).
        #[default]
        On = "on",
    }
}

choice! {
    /// What the ball is made of (the `ball_material` parameter; its solid and the Hertz
    /// contact it makes: `crate::contact`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum BallMaterial {
        /// A steel ball (bearing, cannonball).
        #[default]
        Steel = "steel",
        /// A glass marble.
        Glass = "glass",
        /// A pebble, a stone ball.
        Stone = "stone",
        /// A turned hard-wood ball.
        Hardwood = "hardwood",
        /// Rubber, urethane (a wheel, a rubber ball).
        Rubber = "rubber",
    }
}

choice! {
    /// The gesture of the scene (`crate::gesture`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum GestureKind {
        /// The ball rolls at V (the papers' scene).
        #[default]
        Roll = "roll",
        /// Drop → bounce → roll → settle.
        Drop = "drop",
        /// A settling spin (Euler's disk).
        Spin = "spin",
    }
}

choice! {
    /// What rubs the object in the stick-slip friction contact (the `rub_body` parameter;
    /// each variant's bristle and friction constants and their justification:
    /// `crate::physics::friction_body`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum RubBody {
        /// A wet fingertip (a finger round a wine glass's rim).
        #[default]
        Finger = "finger",
        /// A rubber sole or eraser.
        Rubber = "rubber",
        /// A stick of chalk.
        Chalk = "chalk",
        /// Dry steel on metal (a hinge pin, a scraper).
        Steel = "steel",
        /// Rosined horsehair (a bow).
        Rosin = "rosin",
    }
}
