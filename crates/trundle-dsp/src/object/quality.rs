//! The level of detail: the `quality` choice caps the explicit modes and the high band's
//! slots, sets the culling threshold and the physics engine's oversampling
//! (docs/MODEL.md "Speed and accuracy").

use crate::object::shape::{MAX_MODES, REFERENCE_MODES};

/// Most high-band slots any quality uses.
pub const HIGH_SLOTS_MAX: usize = 48;

pub use crate::params::Quality;

impl Quality {
    /// Largest number of explicit modes the object sounds.
    pub fn max_modes(self) -> usize {
        match self {
            Quality::Draft => 16,
            Quality::Normal => 64,
            Quality::High | Quality::Ultra => MAX_MODES,
            Quality::Reference => REFERENCE_MODES,
        }
    }

    /// Representative modes of the high band (0: none).
    pub fn high_slots(self) -> usize {
        match self {
            Quality::Draft => 8,
            Quality::Normal => 16,
            Quality::High => 24,
            Quality::Ultra => HIGH_SLOTS_MAX,
            Quality::Reference => 0,
        }
    }

    /// Modes whose level is this many dB below the loudest mode's get no input
    /// (−∞: no culling).
    pub fn cull_db(self) -> f64 {
        match self {
            Quality::Draft => -50.0,
            Quality::Normal => -70.0,
            Quality::High => -90.0,
            Quality::Ultra | Quality::Reference => f64::NEG_INFINITY,
        }
    }
}
