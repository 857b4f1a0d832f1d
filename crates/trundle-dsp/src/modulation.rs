//! Amplitude modulation of the force by the ball's asymmetry.
//!
//! TASLP eq 7, 8, 17 (CMJ eq 4, 5): f_out(t) = [1 + m·sin(2πν_m t)]·f_in(t) with
//! ν_m = 3·V/S Hz and depth m ∈ [0, 1] (the "asymmetry" control; the paper's natural value
//! is 0.3). The phase is kept in f64 and wrapped every sample, so it does not drift over
//! hours of rendering, and it is continuous when ν_m changes (no clicks when V or S move).

use crate::params::{ParamEnum, ParamId};

/// The modulation frequency of TASLP eq 17: ν_m = 3·V/S Hz (S floored at 0.1).
#[inline]
pub fn rate_hz(velocity: f64, size: f64) -> f64 {
    3.0 * velocity.max(0.0) / size.max(0.1)
}

/// How the modulation depth follows the ball's motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AsymmetryLaw {
    /// Depth m whatever the speed (TASLP eq 7, CMMR's asymmetry control).
    #[default]
    Constant,
    /// Rath (DAFx 2003 §5, eq 4): the force term of an off-centre mass is the second
    /// derivative of a sinusoidal height, so it grows with the square of the angular speed,
    /// (v/R)² ∝ ν_m². Depth m·(ν_m/ν_ref)², capped at 1, with ν_ref = 3.75 Hz (the AM rate
    /// of the default V = 0.5, S = 0.4, where both laws agree).
    Speed2,
}

impl ParamEnum for AsymmetryLaw {
    const VARIANTS: &'static [Self] = &[AsymmetryLaw::Constant, AsymmetryLaw::Speed2];
    const NAMES: &'static [&'static str] = &["constant", "speed2"];
    const ID: ParamId = ParamId::AsymmetryLaw;
}

/// AM rate (Hz) at which [`AsymmetryLaw::Speed2`] gives depth m.
pub const SPEED2_REFERENCE_HZ: f64 = 3.75;

/// Modulation depth for set depth `m`, velocity V and size S under `law` (in [0, 1]).
#[inline]
pub fn depth_at(law: AsymmetryLaw, m: f64, velocity: f64, size: f64) -> f64 {
    match law {
        AsymmetryLaw::Constant => m,
        AsymmetryLaw::Speed2 => {
            let k = rate_hz(velocity, size) / SPEED2_REFERENCE_HZ;
            (m * k * k).min(1.0)
        }
    }
}

/// A sinusoidal amplitude modulator with a continuous phase.
///
/// # Allocation
/// None.
#[derive(Clone, Debug, Default)]
pub struct Modulator {
    /// Phase in cycles, in [0, 1).
    phase: f64,
}

impl Modulator {
    /// A modulator at phase 0.
    pub fn new() -> Self {
        Self::default()
    }

    /// Back to phase 0 (real-time safe).
    pub fn reset(&mut self) {
        self.phase = 0.0;
    }

    /// Current phase in cycles.
    pub fn phase(&self) -> f64 {
        self.phase
    }

    /// Multiply `x` by 1 + m·sin(2πν_m t), with m and ν_m ramping linearly over the block
    /// from their start to their end values (per-sample interpolation: no zipper noise).
    /// `rate_per_sample` is ν_m/fs in cycles per sample.
    pub fn apply(&mut self, x: &mut [f32], depth: (f32, f32), rate_per_sample: (f64, f64)) {
        let n = x.len();
        if n == 0 {
            return;
        }
        let inv = 1.0 / n as f64;
        if depth.0 == 0.0 && depth.1 == 0.0 {
            // Nothing to multiply: only the phase advances (stage costs nothing at m = 0).
            let mean_rate = 0.5 * (rate_per_sample.0 + rate_per_sample.1);
            self.phase = (self.phase + mean_rate * n as f64).rem_euclid(1.0);
            return;
        }
        let dd = (depth.1 - depth.0) * inv as f32;
        let dr = (rate_per_sample.1 - rate_per_sample.0) * inv;
        let mut m = depth.0;
        // sin(2π·phaseₖ) from a chirped phasor instead of a `sin` per sample: with
        // rₖ = r₀ + k·dr and phaseₖ = phaseₖ₋₁ + rₖ, zₖ = e^{i2π·phaseₖ} = zₖ₋₁·wₖ and
        // wₖ = e^{i2π·rₖ} = wₖ₋₁·e^{i2π·dr}. Three `sin_cos` per block; the phasor restarts
        // from the exact f64 phase every block, so its rounding (≈ 10⁻¹⁶ per sample) never
        // accumulates past one block and the phase itself is kept exactly as before.
        let tau = core::f64::consts::TAU;
        let (zs, zc) = (tau * self.phase).sin_cos();
        let (ws, wc) = (tau * rate_per_sample.0).sin_cos();
        let (cs, cc) = (tau * dr).sin_cos();
        let (mut zr, mut zi) = (zc, zs);
        let (mut wr, mut wi) = (wc, ws);
        let mut r = rate_per_sample.0;
        for s in x.iter_mut() {
            m += dd;
            r += dr;
            self.phase += r;
            if self.phase >= 1.0 {
                self.phase -= 1.0;
            }
            let nwr = wr * cc - wi * cs;
            wi = wr * cs + wi * cc;
            wr = nwr;
            let nzr = zr * wr - zi * wi;
            zi = zr * wi + zi * wr;
            zr = nzr;
            let g = 1.0 + m * zi as f32;
            *s *= g;
        }
        self.phase = self.phase.rem_euclid(1.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modulates_at_the_set_rate_and_depth() {
        let mut m = Modulator::new();
        let fs = 48_000.0;
        let rate = rate_hz(0.5, 0.25); // 6 Hz
        assert!((rate - 6.0).abs() < 1e-12);
        let mut x = vec![1.0f32; 48_000];
        m.apply(&mut x, (0.3, 0.3), (rate / fs, rate / fs));
        let max = x.iter().cloned().fold(f32::MIN, f32::max);
        let min = x.iter().cloned().fold(f32::MAX, f32::min);
        assert!((max - 1.3).abs() < 1e-3 && (min - 0.7).abs() < 1e-3);
        // 6 cycles in one second: the phase is back to ≈ 0.
        assert!(m.phase() < 1e-6 || m.phase() > 1.0 - 1e-6, "{}", m.phase());
    }

    #[test]
    fn the_phasor_matches_sin_of_the_phase() {
        // A chirping rate over a long block: the product equals 1 + m·sin(2π·phase) to f32
        // rounding.
        let mut m = Modulator::new();
        let mut x = vec![1.0f32; 4096];
        let (r0, r1) = (3.0 / 48_000.0, 40.0 / 48_000.0);
        m.apply(&mut x, (0.5, 0.5), (r0, r1));
        let mut phase = 0.0f64;
        let dr = (r1 - r0) / 4096.0;
        let mut r = r0;
        for v in &x {
            r += dr;
            phase = (phase + r).rem_euclid(1.0);
            let want = 1.0 + 0.5 * (core::f64::consts::TAU * phase).sin();
            assert!((f64::from(*v) - want).abs() < 1e-6);
        }
    }

    #[test]
    fn zero_depth_is_identity_and_keeps_the_phase_running() {
        let mut m = Modulator::new();
        let mut x = vec![0.5f32; 100];
        m.apply(&mut x, (0.0, 0.0), (0.01, 0.01));
        assert!(x.iter().all(|&v| v == 0.5));
        assert!((m.phase() - 1.0f64.rem_euclid(1.0)).abs() < 1e-9 || m.phase() < 1e-9);
    }
}
