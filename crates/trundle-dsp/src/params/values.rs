//! A row's values: its range and its kind (linear, logarithmic, percentage, whole number or
//! choice), built by the constructors the parameter table ([`super::table`]) uses.

use super::choice::ParamEnum;
use super::ParamKind;

/// A row's range and kind, built by the parameter table's constructors (`float`, `log`,
/// `percent`, `int`, `choice`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Values {
    /// Smallest allowed value.
    pub min: f64,
    /// Largest allowed value.
    pub max: f64,
    /// Interpretation of the value.
    pub kind: ParamKind,
}

/// A continuous value in `[min, max]`, on a linear control.
pub const fn float(min: f64, max: f64) -> Values {
    Values {
        min,
        max,
        kind: ParamKind::Float {
            log: false,
            percent: false,
        },
    }
}

/// A continuous value in `[min, max]`, on a logarithmic control.
pub const fn log(min: f64, max: f64) -> Values {
    Values {
        min,
        max,
        kind: ParamKind::Float {
            log: true,
            percent: false,
        },
    }
}

/// An amount in `[min, max]` (within 0…1), shown as a percentage.
pub const fn percent(min: f64, max: f64) -> Values {
    Values {
        min,
        max,
        kind: ParamKind::Float {
            log: false,
            percent: true,
        },
    }
}

/// A whole number in `[min, max]`.
pub const fn int(min: f64, max: f64) -> Values {
    Values {
        min,
        max,
        kind: ParamKind::Int,
    }
}

/// One of the variants of `E`: names and range `0 ..= COUNT − 1` from the enumeration.
pub const fn choice<E: ParamEnum>() -> Values {
    Values {
        min: 0.0,
        max: (E::COUNT - 1) as f64,
        kind: ParamKind::Enum(E::NAMES),
    }
}
