//! The safety limiter's meter: what the audio thread tells the editor about the limiter.
//!
//! ```text
//! audio thread ── record (once per block, wait-free) ──► LimiterMeter ── take (per frame) ──► editor
//! ```
//!
//! * The audio thread publishes the deepest gain reduction of each block as a positive
//!   number of decibels (f32 bits in an [`AtomicU32`]). Positive f32 values order like their
//!   bit patterns, so "the deepest since the editor last looked" is one `fetch_max`: no lock,
//!   no loop, no allocation.
//! * The editor takes (and clears) that value once per frame and applies its own ballistics
//!   ([`Ballistics`]): an instant attack, a hold, then a fall, so a single limited impact
//!   stays visible long enough to be seen.
//! * The count of samples the limiter has reduced since the last reset and its latency are
//!   published too (relaxed stores: each value stands alone).

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

/// A reduction shallower than this (dB) is not shown as the limiter acting.
///
/// The limiter's release is a one-pole in f32 that can settle a hair under unity gain
/// (≈ 0.001 dB) after it has acted; that is not audible and not "acting".
pub const ACTING_DB: f32 = 0.01;

/// The limiter's state as the audio thread last published it.
#[derive(Debug)]
pub struct LimiterMeter {
    /// Deepest reduction since the editor last took it: positive dB as f32 bits.
    reduction_db_bits: AtomicU32,
    /// Samples the limiter has reduced since the last reset.
    touched: AtomicU64,
    /// The latency reported to the host, samples.
    latency: AtomicU32,
}

impl Default for LimiterMeter {
    fn default() -> Self {
        Self {
            reduction_db_bits: AtomicU32::new(0f32.to_bits()),
            touched: AtomicU64::new(0),
            latency: AtomicU32::new(0),
        }
    }
}

impl LimiterMeter {
    /// Audio thread: one block's deepest gain reduction (`gain_db` ≤ 0, as
    /// `Limiter::gain_reduction_db` returns it) and the limiter's touched-sample count.
    /// Wait-free.
    pub fn record(&self, gain_db: f32, touched: u64) {
        let reduction = if gain_db.is_finite() {
            (-gain_db).max(0.0)
        } else {
            0.0
        };
        self.reduction_db_bits
            .fetch_max(reduction.to_bits(), Ordering::Relaxed);
        self.touched.store(touched, Ordering::Relaxed);
    }

    /// Audio thread: the limiter was reset (its count restarts).
    pub fn reset(&self) {
        self.touched.store(0, Ordering::Relaxed);
    }

    /// GUI thread: the deepest reduction (positive dB; 0 = none) since the last call, and
    /// clear it.
    pub fn take_reduction_db(&self) -> f32 {
        f32::from_bits(self.reduction_db_bits.swap(0, Ordering::Relaxed))
    }

    /// Samples the limiter has reduced since its last reset.
    pub fn touched(&self) -> u64 {
        self.touched.load(Ordering::Relaxed)
    }

    /// Record the latency reported to the host (samples).
    pub fn set_latency(&self, samples: u32) {
        self.latency.store(samples, Ordering::Relaxed);
    }

    /// The latency reported to the host (samples).
    pub fn latency(&self) -> u32 {
        self.latency.load(Ordering::Relaxed)
    }
}

/// The editor's display of the reduction: instant attack, [`HOLD_S`] hold, then a fall of
/// [`FALL_DB_PER_S`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Ballistics {
    shown_db: f32,
    held_s: f32,
}

/// How long a reduction stays shown at its depth, seconds.
pub const HOLD_S: f32 = 0.6;
/// How fast the shown reduction falls after the hold, dB per second.
pub const FALL_DB_PER_S: f32 = 20.0;

impl Ballistics {
    /// Advance by `dt_s` seconds with the newest reduction `reduction_db` (positive dB);
    /// returns the reduction to show.
    pub fn update(&mut self, reduction_db: f32, dt_s: f32) -> f32 {
        let dt = if dt_s.is_finite() { dt_s.max(0.0) } else { 0.0 };
        if reduction_db >= self.shown_db {
            self.shown_db = reduction_db;
            self.held_s = 0.0;
        } else if self.held_s < HOLD_S {
            self.held_s += dt;
        } else {
            self.shown_db = (self.shown_db - FALL_DB_PER_S * dt).max(reduction_db);
        }
        self.shown_db
    }

    /// Whether the limiter is shown as acting.
    pub fn acting(&self) -> bool {
        self.shown_db >= ACTING_DB
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_deepest_reduction_since_the_last_look_is_kept_and_cleared() {
        let m = LimiterMeter::default();
        assert_eq!(m.take_reduction_db(), 0.0);
        m.record(-0.5, 10);
        m.record(-6.0, 300);
        m.record(0.0, 300);
        m.record(f32::NAN, 300);
        assert_eq!(m.take_reduction_db(), 6.0);
        assert_eq!(m.take_reduction_db(), 0.0);
        assert_eq!(m.touched(), 300);
        m.reset();
        assert_eq!(m.touched(), 0);
        m.set_latency(72);
        assert_eq!(m.latency(), 72);
    }

    #[test]
    fn a_reduction_shows_at_once_holds_then_falls() {
        let mut b = Ballistics::default();
        assert!(!b.acting());
        assert_eq!(b.update(3.0, 1.0 / 60.0), 3.0);
        assert!(b.acting());
        // Held for HOLD_S.
        let mut t = 0.0;
        while t < HOLD_S - 0.02 {
            assert_eq!(b.update(0.0, 1.0 / 60.0), 3.0);
            t += 1.0 / 60.0;
        }
        // Then falls at FALL_DB_PER_S, to nothing within 3 dB / 20 dB/s + the hold.
        for _ in 0..30 {
            b.update(0.0, 1.0 / 60.0);
        }
        assert_eq!(b.update(0.0, 1.0 / 60.0), 0.0);
        assert!(!b.acting());
        // A settled hair under unity gain is not "acting".
        b.update(0.001, 1.0 / 60.0);
        assert!(!b.acting());
    }
}
