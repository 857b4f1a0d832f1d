//! Gliding modes of a fitted object ([`crate::object::fitted::FitMode::glide_hz`]): a
//! membrane's pitch falls as its tension relaxes with the amplitude (tension modulation).
//!
//! A gliding mode k sounds at f = fₖ + Δfₖ·(|zₖ|²/|gₖ + ihₖ|²)^{τₖ/(2τgₖ)}, |zₖ| its phasor
//! state and gₖ + ihₖ its input gain: after a unit impulse |zₖ[n]|² = |gₖ + ihₖ|²·rₖ^{2n},
//! so the glide is Δfₖ·e^{−t/τgₖ}, the fitted law, exactly; a softer strike or a rolling ball
//! (a smaller state) glides less (a strike at half the force by 2^{−τₖ/τgₖ}), a harder one
//! as much as the recording (bounded by [`GLIDE_RATIO_MAX`]). The
//! pole angle is updated once per chunk (at most [`crate::block::CHUNK`] samples; the tom's
//! 6.7 Hz glide moves by under 0.1 Hz in a chunk at 48 kHz). Only gliding modes pay for
//! it: without one the list is empty and the bank runs exactly as before, bit for bit.

use super::*;

/// Most gliding modes played (the loudest first, as the fitted modes are ordered).
pub const GLIDES_MAX: usize = 16;

/// The amplitude ratio (|z|/a₀)² is bounded here: a strike as hard as the recorded one or
/// harder glides as recorded, never further (a rolling ball that builds up a large state
/// must not throw the pitch by several times Δf).
pub const GLIDE_RATIO_MAX: f64 = 1.0;

/// One gliding mode as played.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Glide {
    /// Bank slot.
    slot: usize,
    /// Frequency at rest fₖ (Hz, transposed).
    freq_hz: f64,
    /// Glide Δfₖ (Hz, transposed).
    glide_hz: f64,
    /// τₖ/τgₖ.
    exp: f64,
    /// Decay as played (s).
    decay_s: f64,
}

/// The gliding modes of the object in play (fixed capacity: no allocation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Glides {
    list: [Glide; GLIDES_MAX],
    len: usize,
}

impl Glides {
    /// Forget every glide (at each pole update).
    pub(super) fn clear(&mut self) {
        self.len = 0;
    }

    /// Add a gliding mode (ignored beyond [`GLIDES_MAX`]).
    pub(super) fn push(
        &mut self,
        slot: usize,
        freq_hz: f64,
        glide_hz: f64,
        exp: f64,
        decay_s: f64,
    ) {
        if self.len < GLIDES_MAX {
            self.list[self.len] = Glide {
                slot,
                freq_hz,
                glide_hz,
                exp,
                decay_s,
            };
            self.len += 1;
        }
    }
}

impl Object {
    /// Set each gliding mode's pole angle from its state (call before the bank runs a
    /// chunk). Real-time safe; nothing to do for an object without glide.
    pub(super) fn apply_glides(&mut self) {
        let nyquist = 0.5 * self.fs;
        for gl in &self.glides.list[..self.glides.len] {
            let k = gl.slot;
            if self.long_of[k] != NOT_LONG {
                continue;
            }
            let m = self.bank.mode(k);
            let a0 = f64::from(m.g).powi(2) + f64::from(m.h).powi(2);
            if a0 <= 0.0 {
                continue;
            }
            let (re, im) = self.bank.state(k);
            let ratio = (f64::from(re).powi(2) + f64::from(im).powi(2)) / a0;
            let f = gl.freq_hz + gl.glide_hz * ratio.min(GLIDE_RATIO_MAX).powf(0.5 * gl.exp);
            if !(f > 0.0 && f < nyquist) {
                continue;
            }
            let (c, s) = phasor_coeffs(f, gl.decay_s, self.fs);
            self.bank.set_mode(k, ModeCoeffs { c, s, ..m });
        }
    }
}
