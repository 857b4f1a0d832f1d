//! The object: a Mathews–Smith resonant filter bank.
//!
//! Mathews & Smith 2003, "Methods for synthesizing very high Q parametrically well behaved
//! two pole filters" (TASLP §I, CMJ "Object part"). Each mode k is a complex one-pole
//! ("phasor") filter
//!
//! ```text
//! zₖ[n] = gₖ·x[n] + pₖ·zₖ[n−1],   pₖ = rₖ·e^{iωₖ},   rₖ = exp(−1/(τₖ·f_s)),   y[n] = Σₖ Im zₖ[n]
//! ```
//!
//! so the impulse response of mode k is gₖ·rₖⁿ·sin(nωₖ): a decaying sine that starts at zero.
//! Because the state is a rotating phasor, changing ωₖ changes only the rotation rate — the
//! amplitude never jumps — and the recursion stays well conditioned at high Q and low
//! frequency, where direct-form biquads lose their precision.
//!
//! ## Precision and stability
//! Coefficients are computed in f64 and rounded to f32 so that the rounded pole never lies
//! outside the f64 pole: |p_f32| ≤ rₖ < 1, exactly (see [`phasor_coeffs`]). The bank is
//! therefore never unstable; at extreme Q × f_s (τ·f_s > 10⁷) f32 rounding shortens the
//! realized decay slightly instead of lengthening it. State below
//! [`crate::FLUSH_THRESHOLD`] is flushed to zero by [`ModalBank::flush`] (called by the voice
//! between chunks of at most [`crate::CHUNK`] samples), so a decayed object holds no
//! subnormal numbers.
//!
//! ## Layout
//! Struct of arrays (`re`, `im`, `c`, `s`, `g`), lanes padded to a multiple of [`LANES`] with
//! zero coefficients, processed sample-major with [`LANES`] independent accumulators so the
//! compiler can vectorize the mode loop.

/// Modes processed together; the bank's capacity is padded to a multiple of this.
pub const LANES: usize = 8;

/// Coefficients of one mode.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ModeCoeffs {
    /// Re p = r·cos ω.
    pub c: f32,
    /// Im p = r·sin ω.
    pub s: f32,
    /// Input gain g.
    pub g: f32,
}

/// Pole coefficients (r·cos ω, r·sin ω) in f32 for a mode at `freq_hz` with 1/e decay time
/// `decay_s` at `sample_rate_hz`, rounded so that |p_f32| ≤ r (never outside the exact pole).
pub fn phasor_coeffs(freq_hz: f64, decay_s: f64, sample_rate_hz: f64) -> (f32, f32) {
    let r = (-1.0 / (decay_s.max(1e-6) * sample_rate_hz)).exp();
    let w = core::f64::consts::TAU * freq_hz / sample_rate_hz;
    let (sw, cw) = w.sin_cos();
    let mut c = (r * cw) as f32;
    let mut s = (r * sw) as f32;
    let r2 = r * r;
    // Nudge towards the origin, one ulp at a time, until the rounded pole is inside.
    for _ in 0..8 {
        let m2 = (c as f64) * (c as f64) + (s as f64) * (s as f64);
        if m2 <= r2 {
            break;
        }
        c = toward_zero(c);
        s = toward_zero(s);
    }
    (c, s)
}

#[inline]
fn toward_zero(x: f32) -> f32 {
    if x == 0.0 {
        0.0
    } else {
        f32::from_bits(x.to_bits() - 1)
    }
}

/// A bank of Mathews–Smith phasor filters, f32 state, struct of arrays.
///
/// # Allocation
/// `new` allocates the arrays for `capacity` modes (rounded up to [`LANES`]); nothing else
/// allocates.
#[derive(Clone, Debug)]
pub struct ModalBank {
    re: Vec<f32>,
    im: Vec<f32>,
    c: Vec<f32>,
    s: Vec<f32>,
    g: Vec<f32>,
    active: usize,
}

impl ModalBank {
    /// A silent bank with room for `capacity` modes.
    pub fn new(capacity: usize) -> Self {
        let cap = capacity.max(1).div_ceil(LANES) * LANES;
        Self {
            re: vec![0.0; cap],
            im: vec![0.0; cap],
            c: vec![0.0; cap],
            s: vec![0.0; cap],
            g: vec![0.0; cap],
            active: 0,
        }
    }

    /// Capacity in modes (a multiple of [`LANES`]).
    pub fn capacity(&self) -> usize {
        self.re.len()
    }

    /// Zero the state (coefficients kept). Real-time safe.
    pub fn reset(&mut self) {
        self.re.iter_mut().for_each(|x| *x = 0.0);
        self.im.iter_mut().for_each(|x| *x = 0.0);
    }

    /// Set mode `k`'s coefficients (ignored beyond the capacity).
    #[inline]
    pub fn set_mode(&mut self, k: usize, m: ModeCoeffs) {
        if k < self.c.len() {
            self.c[k] = m.c;
            self.s[k] = m.s;
            self.g[k] = m.g;
        }
    }

    /// Mode `k`'s coefficients.
    pub fn mode(&self, k: usize) -> ModeCoeffs {
        ModeCoeffs {
            c: self.c[k],
            s: self.s[k],
            g: self.g[k],
        }
    }

    /// Process only the first `n` modes (rounded up to [`LANES`]); modes beyond must be
    /// silent (state zero) or they are frozen.
    pub fn set_active(&mut self, n: usize) {
        self.active = n.min(self.capacity());
    }

    /// Number of modes processed.
    pub fn active(&self) -> usize {
        self.active
    }

    /// Squared magnitude of mode `k`'s state.
    #[inline]
    pub fn energy(&self, k: usize) -> f32 {
        self.re[k] * self.re[k] + self.im[k] * self.im[k]
    }

    /// Flush decayed or non-finite state to zero (call between chunks).
    pub fn flush(&mut self) {
        let t2 = crate::FLUSH_THRESHOLD * crate::FLUSH_THRESHOLD;
        let n = self.active.div_ceil(LANES) * LANES;
        for k in 0..n {
            let e = self.re[k] * self.re[k] + self.im[k] * self.im[k];
            if e < t2 || !e.is_finite() {
                self.re[k] = 0.0;
                self.im[k] = 0.0;
            }
        }
    }

    /// Run the bank on `input`, writing Σ Im zₖ to `out` (overwritten). `input` and `out`
    /// must have the same length.
    pub fn process(&mut self, input: &[f32], out: &mut [f32]) {
        debug_assert_eq!(input.len(), out.len());
        let groups = self.active.div_ceil(LANES);
        out.iter_mut().for_each(|y| *y = 0.0);
        for gi in 0..groups {
            let o = gi * LANES;
            let mut re: [f32; LANES] = self.re[o..o + LANES].try_into().unwrap();
            let mut im: [f32; LANES] = self.im[o..o + LANES].try_into().unwrap();
            let c: [f32; LANES] = self.c[o..o + LANES].try_into().unwrap();
            let s: [f32; LANES] = self.s[o..o + LANES].try_into().unwrap();
            let g: [f32; LANES] = self.g[o..o + LANES].try_into().unwrap();
            for (x, y) in input.iter().zip(out.iter_mut()) {
                let mut acc = [0.0f32; LANES];
                for l in 0..LANES {
                    let nr = c[l] * re[l] - s[l] * im[l] + g[l] * *x;
                    let ni = s[l] * re[l] + c[l] * im[l];
                    re[l] = nr;
                    im[l] = ni;
                    acc[l] = ni;
                }
                *y += ((acc[0] + acc[1]) + (acc[2] + acc[3]))
                    + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
            }
            self.re[o..o + LANES].copy_from_slice(&re);
            self.im[o..o + LANES].copy_from_slice(&im);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounded_pole_never_lies_outside_the_exact_one() {
        for &fs in &[8_000.0, 48_000.0, 384_000.0] {
            for &f in &[20.0, 1_000.0, 0.499 * fs] {
                for &tau in &[0.2e-3, 0.1, 60.0] {
                    let (c, s) = phasor_coeffs(f, tau, fs);
                    let r = (-1.0 / (tau * fs)).exp();
                    let m2 = (c as f64).powi(2) + (s as f64).powi(2);
                    assert!(m2 <= r * r && m2 < 1.0, "{fs} {f} {tau}");
                }
            }
        }
    }

    #[test]
    fn impulse_response_is_a_decaying_sine() {
        let fs = 48_000.0;
        let (f, tau, g) = (1_000.0, 0.05, 0.5);
        let mut b = ModalBank::new(1);
        let (c, s) = phasor_coeffs(f, tau, fs);
        b.set_mode(0, ModeCoeffs { c, s, g });
        b.set_active(1);
        let mut x = vec![0.0f32; 4_800];
        x[0] = 1.0;
        let mut y = vec![0.0f32; 4_800];
        b.process(&x, &mut y);
        for (n, &v) in y.iter().enumerate() {
            let t = n as f64 / fs;
            let want = g as f64 * (-t / tau).exp() * (core::f64::consts::TAU * f * t).sin();
            assert!((v as f64 - want).abs() < 1e-5, "{n}: {v} vs {want}");
        }
    }

    #[test]
    fn flush_leaves_no_subnormal_state() {
        let mut b = ModalBank::new(8);
        let (c, s) = phasor_coeffs(440.0, 0.001, 48_000.0);
        b.set_mode(3, ModeCoeffs { c, s, g: 1.0 });
        b.set_active(8);
        let mut x = vec![0.0f32; 64];
        x[0] = 1.0;
        let mut y = vec![0.0f32; 64];
        for _ in 0..1_000 {
            b.process(&x, &mut y);
            b.flush();
            x[0] = 0.0;
        }
        for k in 0..8 {
            assert!(b.energy(k) == 0.0 || b.energy(k).is_normal());
        }
        assert_eq!(b.energy(3), 0.0);
    }
}
