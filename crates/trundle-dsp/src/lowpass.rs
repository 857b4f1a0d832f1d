//! The velocity low-pass and the loudness law.
//!
//! CMJ ("Navigation strategy": "low-pass filtered with a cutoff frequency that is directly
//! related to the relative transversal velocity") and CMMR §3.4, after van den Doel et al.
//! Trundle's laws (monotonic, documented here, tested in `tests/engine.rs`):
//!
//! * cutoff f_c(V) = 500 Hz · 50^V — 500 Hz for a crawling ball, 3.5 kHz at V = 0.5,
//!   25 kHz at V = 1 (so a full-speed ball is unfiltered at 44.1/48 kHz). The filter runs
//!   with f_c capped at 0.45·f_s, where it is transparent in the audible band.
//! * loudness gain L(V) = √V: V = 0 is a ball at rest — silence — and loudness grows with
//!   speed (the kinetic energy goes with V², the radiated amplitude here with √V, a
//!   compromise that keeps slow balls audible; −10 dB at V = 0.1).
//! * size gain G(S) = (S/0.4)^−¾ ([`size_gain`]): the pulse law makes a ball's pulses last,
//!   and so carry low-frequency amplitude, in proportion to its size S (t₀ ∝ S, TASLP eq 16):
//!   alone it would make the largest ball 20 dB louder than the smallest in the object's low
//!   modes. A quarter of that is kept — big balls are louder, by 5 dB per decade of size — so
//!   the whole size × speed range stays in a mixing range (at its loudest corner, S 1 and
//!   V 1, the sound peaks just under the safety limiter's −1 dBFS, `tests/levels.rs`). 1 at
//!   the default size 0.4.
//!
//! The filter is a 2-pole state-variable filter in the topology-preserving form
//! (Zavalishin), Butterworth damping: unconditionally stable and click-free under fast
//! cutoff modulation. Coefficients are updated per chunk.

/// Cutoff at V = 0 (Hz).
pub const CUTOFF_MIN_HZ: f64 = 500.0;
/// Cutoff ratio between V = 1 and V = 0.
pub const CUTOFF_SPAN: f64 = 50.0;

/// f_c(V) = 500 Hz · 50^V.
#[inline]
pub fn cutoff_hz(velocity: f64) -> f64 {
    CUTOFF_MIN_HZ * CUTOFF_SPAN.powf(velocity.clamp(0.0, 1.0))
}

/// L(V) = √V, the force's loudness gain for velocity V (0 = silence).
#[inline]
pub fn loudness(velocity: f64) -> f64 {
    velocity.clamp(0.0, 1.0).sqrt()
}

/// G(S) = (S/0.4)^−¾, the force's gain for ball size S (module docs).
#[inline]
pub fn size_gain(size: f64) -> f64 {
    (size.clamp(0.1, 1.0) / 0.4).powf(-0.75)
}

/// Two-pole TPT state-variable low-pass.
///
/// # Allocation
/// None.
#[derive(Clone, Debug)]
pub struct Lowpass {
    ic1: f32,
    ic2: f32,
    a1: f32,
    a2: f32,
    a3: f32,
}

impl Default for Lowpass {
    fn default() -> Self {
        Self::new()
    }
}

impl Lowpass {
    /// A filter with a wide-open cutoff (call [`set_cutoff`](Self::set_cutoff)).
    pub fn new() -> Self {
        let mut f = Self {
            ic1: 0.0,
            ic2: 0.0,
            a1: 0.0,
            a2: 0.0,
            a3: 0.0,
        };
        f.set_cutoff(20_000.0, 48_000.0);
        f
    }

    /// Clear the state (real-time safe).
    pub fn reset(&mut self) {
        self.ic1 = 0.0;
        self.ic2 = 0.0;
    }

    /// True when the filter holds no state (its output for silence is silence).
    pub fn is_silent(&self) -> bool {
        self.ic1 == 0.0 && self.ic2 == 0.0
    }

    /// Set the cutoff; capped at 0.45·f_s, floored at 10 Hz.
    pub fn set_cutoff(&mut self, cutoff_hz: f64, sample_rate_hz: f64) {
        let fc = cutoff_hz.clamp(10.0, 0.45 * sample_rate_hz);
        let g = (core::f64::consts::PI * fc / sample_rate_hz).tan();
        let k = core::f64::consts::SQRT_2; // 1/Q, Butterworth
        let a1 = 1.0 / (1.0 + g * (g + k));
        self.a1 = a1 as f32;
        self.a2 = (g * a1) as f32;
        self.a3 = (g * g * a1) as f32;
    }

    /// Filter in place.
    pub fn process(&mut self, x: &mut [f32]) {
        let (a1, a2, a3) = (self.a1, self.a2, self.a3);
        let (mut ic1, mut ic2) = (self.ic1, self.ic2);
        for s in x.iter_mut() {
            let v3 = *s - ic2;
            let v1 = a1 * ic1 + a2 * v3;
            let v2 = ic2 + a2 * ic1 + a3 * v3;
            ic1 = 2.0 * v1 - ic1;
            ic2 = 2.0 * v2 - ic2;
            *s = v2;
        }
        // Keep the state out of the subnormal range and finite.
        let flush = |v: f32| {
            if v.is_finite() && v.abs() > crate::FLUSH_THRESHOLD {
                v
            } else {
                0.0
            }
        };
        self.ic1 = flush(ic1);
        self.ic2 = flush(ic2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn laws_are_monotonic_and_silent_at_rest() {
        assert_eq!(loudness(0.0), 0.0);
        assert!((cutoff_hz(0.0) - 500.0).abs() < 1e-9);
        assert!((cutoff_hz(1.0) - 25_000.0).abs() < 1e-6);
        let mut last = (0.0, 0.0);
        for i in 1..=100 {
            let v = i as f64 / 100.0;
            let now = (cutoff_hz(v), loudness(v));
            assert!(now.0 > last.0 && now.1 > last.1);
            last = now;
        }
    }

    #[test]
    fn response_is_butterworth_at_the_cutoff() {
        let fs = 48_000.0;
        for &fc in &[500.0, 3_000.0] {
            let mut f = Lowpass::new();
            f.set_cutoff(fc, fs);
            let n = 48_000;
            let mut x: Vec<f32> = (0..n)
                .map(|i| (core::f64::consts::TAU * fc * i as f64 / fs).sin() as f32)
                .collect();
            f.process(&mut x);
            let rms = (x[n / 2..].iter().map(|v| (*v as f64).powi(2)).sum::<f64>()
                / (n / 2) as f64)
                .sqrt();
            // −3 dB at the cutoff: amplitude 1/√2, RMS 1/2.
            assert!((rms - 0.5).abs() < 0.01, "{fc}: {rms}");
            let mut dc = vec![1.0f32; 4_800];
            f.process(&mut dc);
            assert!((dc[4_799] - 1.0).abs() < 1e-4);
        }
    }
}
