//! Amplitude modulation of the force by the ball's asymmetry.
//!
//! TASLP eq 7, 8, 17 (CMJ eq 4, 5): f_out(t) = [1 + m·sin(2πν_m t)]·f_in(t) with
//! ν_m = 3·V/S Hz and depth m ∈ [0, 1] (the "asymmetry" control; the paper's natural value
//! is 0.3). The phase is kept in f64 and wrapped every block, so it does not drift over
//! hours of rendering, and it is continuous when ν_m changes (no clicks when V or S move).

use crate::block::CHUNK;

/// The modulation frequency of TASLP eq 17: ν_m = 3·V/S Hz (S floored at 0.1).
#[inline]
pub fn rate_hz(velocity: f64, size: f64) -> f64 {
    3.0 * velocity.max(0.0) / size.max(0.1)
}

pub use crate::params::AsymmetryLaw;

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
/// Evaluation (TASLP eq 7, the same product, evaluated per block): within a block of at
/// most [`CHUNK`] samples the phase is θₖ = θ₀ + k·r₀ + dr·k(k+1)/2 (the rate ramps
/// linearly, rₖ = r₀ + k·dr cycles per sample). sin 2πθₖ = Im(e^{i2πθ₀}·Tₖ) with the turns
/// Tₖ = e^{i2π(k·r₀ + dr·k(k+1)/2)}: one `sin_cos` of the exact phase per block and a table
/// of turns that depends only on (r₀, dr) — built by a chirped phasor (two complex
/// products a sample) when the rate moves, kept while it does not (the steady roll). Each
/// sample then costs one complex-by-real product, with no dependency between samples.
///
/// # Allocation
/// None (the turn table is an inline array).
#[derive(Clone, Debug)]
pub struct Modulator {
    /// Phase in cycles, in [0, 1).
    phase: f64,
    /// Re Tₖ for k = 1..=len (index k − 1).
    turn_re: [f64; CHUNK],
    /// Im Tₖ.
    turn_im: [f64; CHUNK],
    /// (r₀, dr, len) the table holds; NaN = empty.
    turn_for: (f64, f64, usize),
}

impl Default for Modulator {
    fn default() -> Self {
        Self {
            phase: 0.0,
            turn_re: [0.0; CHUNK],
            turn_im: [0.0; CHUNK],
            turn_for: (f64::NAN, f64::NAN, 0),
        }
    }
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
        self.apply_scaled(x, (1.0, 1.0), depth, rate_per_sample);
    }

    /// [`apply`](Self::apply) with a gain L ramping linearly from `gain.0` to `gain.1`
    /// over the block applied first, in the same pass: xₖ ← (xₖ·Lₖ)·(1 + mₖ·sin 2πθₖ)
    /// (the source's loudness L(V), CMMR §3.4, then the AM, TASLP eq 7). A constant gain of
    /// 1 is not multiplied.
    pub fn apply_scaled(
        &mut self,
        x: &mut [f32],
        gain: (f32, f32),
        depth: (f32, f32),
        rate_per_sample: (f64, f64),
    ) {
        let n = x.len();
        if n == 0 {
            return;
        }
        let inv = 1.0 / n as f64;
        if depth.0 == 0.0 && depth.1 == 0.0 {
            // Nothing to modulate: only the gain, and the phase advances (the stage costs
            // nothing at m = 0).
            scale(x, gain);
            let mean_rate = 0.5 * (rate_per_sample.0 + rate_per_sample.1);
            self.phase = (self.phase + mean_rate * n as f64).rem_euclid(1.0);
            return;
        }
        let dd = (depth.1 - depth.0) * inv as f32;
        let dl = (gain.1 - gain.0) * inv as f32;
        let dr = (rate_per_sample.1 - rate_per_sample.0) * inv;
        let mut done = 0;
        while done < n {
            let len = (n - done).min(CHUNK);
            let o = done as f64;
            let r0 = rate_per_sample.0 + o * dr;
            let key = (r0, dr, len);
            if key != self.turn_for {
                self.build_turns(r0, dr, len);
                self.turn_for = key;
            }
            let (zs, zc) = (core::f64::consts::TAU * self.phase).sin_cos();
            let (m0, l0) = (depth.0 + done as f32 * dd, gain.0 + done as f32 * dl);
            let block = &mut x[done..done + len];
            let turns = self.turn_re[..len].iter().zip(&self.turn_im[..len]);
            if dd == 0.0 && dl == 0.0 {
                // The steady roll: constant depth and gain.
                let (m, l) = (depth.1, gain.1);
                for (s, (&tr, &ti)) in block.iter_mut().zip(turns) {
                    let sin = (zc * ti + zs * tr) as f32;
                    *s = (*s * l) * (1.0 + m * sin);
                }
            } else {
                for (k, (s, (&tr, &ti))) in block.iter_mut().zip(turns).enumerate() {
                    let kf = (k + 1) as f32;
                    let (m, l) = (m0 + kf * dd, l0 + kf * dl);
                    let sin = (zc * ti + zs * tr) as f32;
                    *s = (*s * l) * (1.0 + m * sin);
                }
            }
            let lf = len as f64;
            self.phase = (self.phase + lf * r0 + dr * (0.5 * lf * (lf + 1.0))).rem_euclid(1.0);
            done += len;
        }
    }

    /// Tₖ = e^{i2π(k·r₀ + dr·k(k+1)/2)} for k = 1..=len by a chirped phasor: with
    /// wₖ = e^{i2π(r₀ + k·dr)}, Tₖ = Tₖ₋₁·wₖ and wₖ = wₖ₋₁·e^{i2π·dr} (three `sin_cos`;
    /// rounding ≈ 10⁻¹⁶ per step, restarted every block). Not inlined: inlined, the
    /// compiler hoisted its `sin_cos` into every call of [`apply_scaled`](Self::apply_scaled).
    #[inline(never)]
    fn build_turns(&mut self, r0: f64, dr: f64, len: usize) {
        let tau = core::f64::consts::TAU;
        let (ws, wc) = (tau * r0).sin_cos();
        let (mut wr, mut wi) = (wc, ws);
        let (mut zr, mut zi) = (1.0f64, 0.0f64);
        if dr == 0.0 {
            for (re, im) in self.turn_re[..len].iter_mut().zip(&mut self.turn_im[..len]) {
                let nzr = zr * wr - zi * wi;
                zi = zr * wi + zi * wr;
                zr = nzr;
                *re = zr;
                *im = zi;
            }
            return;
        }
        let (cs, cc) = (tau * dr).sin_cos();
        for (re, im) in self.turn_re[..len].iter_mut().zip(&mut self.turn_im[..len]) {
            let nwr = wr * cc - wi * cs;
            wi = wr * cs + wi * cc;
            wr = nwr;
            let nzr = zr * wr - zi * wi;
            zi = zr * wi + zi * wr;
            zr = nzr;
            *re = zr;
            *im = zi;
        }
    }
}

/// xₖ ← xₖ·Lₖ with L ramping linearly from `gain.0` (exclusive) to `gain.1` over the block;
/// a constant 1 is skipped.
fn scale(x: &mut [f32], gain: (f32, f32)) {
    let (l0, l1) = gain;
    if l0 == l1 {
        if l1 != 1.0 {
            x.iter_mut().for_each(|s| *s *= l1);
        }
        return;
    }
    let d = (l1 - l0) / x.len() as f32;
    for (k, s) in x.iter_mut().enumerate() {
        *s *= l0 + (k + 1) as f32 * d;
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
