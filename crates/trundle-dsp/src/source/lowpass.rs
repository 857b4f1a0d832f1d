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
//! cutoff modulation. Coefficients are updated per chunk (when the cutoff moved); the
//! filter runs four samples at a time from its state-space form ([`Lowpass`]).

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

/// Samples the low-pass computes at once (see [`Lowpass`]).
pub const LOWPASS_BLOCK: usize = 4;

/// Two-pole TPT state-variable low-pass (CMMR §3.4's velocity low-pass), Butterworth.
///
/// The TPT SVF with g = tan(π·f_c/f_s), k = √2, a₁ = 1/(1 + g(g + k)), a₂ = g·a₁,
/// a₃ = g²·a₁ is the linear state-space system (state s = (ic₁, ic₂))
///
/// ```text
/// s' = A·s + B·x,  A = [[2a₁ − 1, −2a₂], [2a₂, 1 − 2a₃]],  B = (2a₂, 2a₃)
/// y  = C·s + D·x,  C = (a₂, 1 − a₃),                        D = a₃
/// ```
///
/// evaluated here [`LOWPASS_BLOCK`] samples at a time: y_j = C·Aʲ·s + Σ_{i≤j} h_{j−i}·x_i
/// (h₀ = D, h_m = C·A^{m−1}·B) and s' = A⁴·s + Σᵢ A^{3−i}·B·x_i, with the matrices computed
/// in f64 when the cutoff changes. Same filter, same state, no recursion inside a block:
/// the four outputs and the new state are independent sums the compiler vectorizes.
///
/// # Allocation
/// None.
#[derive(Clone, Debug)]
pub struct Lowpass {
    ic1: f32,
    ic2: f32,
    /// The (clamped cutoff, sample rate) the coefficients are for.
    tuned: (f64, f64),
    /// One sample: (A₀₀, A₀₁, A₁₀, A₁₁, B₀, B₁, C₀, C₁, D).
    step: [f32; 9],
    /// The block: lanes 0–3 are the outputs y₀…y₃, lanes 4, 5 the new state (ic₁, ic₂);
    /// rows: the coefficient of ic₁, of ic₂, then of x₀…x₃.
    block: [[f32; 8]; 2 + LOWPASS_BLOCK],
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
            tuned: (f64::NAN, f64::NAN),
            step: [0.0; 9],
            block: [[0.0; 8]; 2 + LOWPASS_BLOCK],
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

    /// Set the cutoff; capped at 0.45·f_s, floored at 10 Hz. Costs nothing when the cutoff
    /// did not move.
    pub fn set_cutoff(&mut self, cutoff_hz: f64, sample_rate_hz: f64) {
        let fc = cutoff_hz.clamp(10.0, 0.45 * sample_rate_hz);
        if (fc, sample_rate_hz) == self.tuned {
            return;
        }
        self.tuned = (fc, sample_rate_hz);
        let g = (core::f64::consts::PI * fc / sample_rate_hz).tan();
        let k = core::f64::consts::SQRT_2; // 1/Q, Butterworth
        let a1 = 1.0 / (1.0 + g * (g + k));
        let (a2, a3) = (g * a1, g * g * a1);
        let a = [[2.0 * a1 - 1.0, -2.0 * a2], [2.0 * a2, 1.0 - 2.0 * a3]];
        let b = [2.0 * a2, 2.0 * a3];
        let c = [a2, 1.0 - a3];
        let d = a3;
        self.step = [
            a[0][0], a[0][1], a[1][0], a[1][1], b[0], b[1], c[0], c[1], d,
        ]
        .map(|v| v as f32);
        let mul = |m: [[f64; 2]; 2], v: [f64; 2]| {
            [
                m[0][0] * v[0] + m[0][1] * v[1],
                m[1][0] * v[0] + m[1][1] * v[1],
            ]
        };
        let row_mul = |r: [f64; 2], m: [[f64; 2]; 2]| {
            [
                r[0] * m[0][0] + r[1] * m[1][0],
                r[0] * m[0][1] + r[1] * m[1][1],
            ]
        };
        // C·Aʲ (the outputs' dependence on the state) and Aʲ·B (an input's on the state
        // j samples later), j = 0…4.
        let mut ca = [[0.0f64; 2]; LOWPASS_BLOCK + 1];
        let mut ab = [[0.0f64; 2]; LOWPASS_BLOCK + 1];
        ca[0] = c;
        ab[0] = b;
        for j in 1..=LOWPASS_BLOCK {
            ca[j] = row_mul(ca[j - 1], a);
            ab[j] = mul(a, ab[j - 1]);
        }
        // A⁴.
        let mut a4 = [[1.0, 0.0], [0.0, 1.0]];
        for _ in 0..LOWPASS_BLOCK {
            a4 = [
                [
                    a[0][0] * a4[0][0] + a[0][1] * a4[1][0],
                    a[0][0] * a4[0][1] + a[0][1] * a4[1][1],
                ],
                [
                    a[1][0] * a4[0][0] + a[1][1] * a4[1][0],
                    a[1][0] * a4[0][1] + a[1][1] * a4[1][1],
                ],
            ];
        }
        let h = |m: usize| {
            if m == 0 {
                d
            } else {
                ca[0][0] * ab[m - 1][0] + ca[0][1] * ab[m - 1][1]
            }
        };
        let mut block = [[0.0f64; 8]; 2 + LOWPASS_BLOCK];
        for j in 0..LOWPASS_BLOCK {
            block[0][j] = ca[j][0];
            block[1][j] = ca[j][1];
            for i in 0..=j {
                block[2 + i][j] = h(j - i);
            }
        }
        block[0][4] = a4[0][0];
        block[1][4] = a4[0][1];
        block[0][5] = a4[1][0];
        block[1][5] = a4[1][1];
        for i in 0..LOWPASS_BLOCK {
            let v = ab[LOWPASS_BLOCK - 1 - i];
            block[2 + i][4] = v[0];
            block[2 + i][5] = v[1];
        }
        self.block = block.map(|r| r.map(|v| v as f32));
    }

    /// Filter in place.
    pub fn process(&mut self, x: &mut [f32]) {
        let (mut ic1, mut ic2) = (self.ic1, self.ic2);
        let m = &self.block;
        let mut blocks = x.chunks_exact_mut(LOWPASS_BLOCK);
        for xs in &mut blocks {
            let mut acc = [0.0f32; 8];
            for (i, &xi) in xs.iter().enumerate() {
                for (a, &c) in acc.iter_mut().zip(&m[2 + i]) {
                    *a += c * xi;
                }
            }
            for ((a, &c1), &c2) in acc.iter_mut().zip(&m[0]).zip(&m[1]) {
                *a += c1 * ic1 + c2 * ic2;
            }
            xs.copy_from_slice(&acc[..LOWPASS_BLOCK]);
            ic1 = acc[4];
            ic2 = acc[5];
        }
        let [a00, a01, a10, a11, b0, b1, c0, c1, d] = self.step;
        for s in blocks.into_remainder() {
            let x = *s;
            *s = c0 * ic1 + c1 * ic2 + d * x;
            let n1 = a00 * ic1 + a01 * ic2 + b0 * x;
            ic2 = a10 * ic1 + a11 * ic2 + b1 * x;
            ic1 = n1;
        }
        // Keep the state out of the subnormal range and finite.
        let flush = |v: f32| {
            if v.is_finite() && v.abs() > crate::block::FLUSH_THRESHOLD {
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

    #[test]
    fn blocks_of_four_are_the_tpt_recursion() {
        // The state-space blocks against the TPT SVF sample by sample (f64), for a
        // crawling and a fast ball, in pieces of any length.
        let fs = 48_000.0;
        for &fc in &[500.0, 3_500.0, 20_000.0] {
            let mut f = Lowpass::new();
            f.set_cutoff(fc, fs);
            let x: Vec<f32> = (0..1_003)
                .map(|i| if i % 37 < 3 { 1.0 } else { 0.0 })
                .collect();
            let mut y = x.clone();
            let mut at = 0;
            for len in [64, 3, 17, 1, 64, 854] {
                f.process(&mut y[at..at + len]);
                at += len;
            }
            let g = (core::f64::consts::PI * f64::min(fc, 0.45 * fs) / fs).tan();
            let a1 = 1.0 / (1.0 + g * (g + core::f64::consts::SQRT_2));
            let (a2, a3) = (g * a1, g * g * a1);
            let (mut ic1, mut ic2) = (0f64, 0f64);
            for (&xi, &yi) in x.iter().zip(&y) {
                let v3 = f64::from(xi) - ic2;
                let v1 = a1 * ic1 + a2 * v3;
                let v2 = ic2 + a2 * ic1 + a3 * v3;
                ic1 = 2.0 * v1 - ic1;
                ic2 = 2.0 * v2 - ic2;
                assert!((f64::from(yi) - v2).abs() < 1e-5, "{fc}: {yi} vs {v2}");
            }
        }
    }
}
