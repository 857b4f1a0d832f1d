//! The force's coupling into the object: a DC blocker.
//!
//! The interaction force is a train of positive pulses: its mean is the ball's static load
//! (and its slow AM envelope), which deflects the object but radiates no sound. A
//! Mathews–Smith mode fed with a DC input responds with a static offset of about
//! 1/(2π·f·τ) of its resonant gain — for the low, short-lived modes of a large wooden
//! object that offset approaches the sound's own RMS (measured: −0.8 dB re RMS for the
//! bowling-lane preset). Trundle therefore feeds the object with the force minus its
//! slowly varying mean: a one-pole high-pass at [`DC_BLOCK_HZ`], well below the lowest
//! mode the object sounds (10 Hz) and below hearing. The raw force output (`output =
//! force`) is not filtered: it stays the model's force for analysis.

use crate::params::Params;
use crate::stage::Stage;

/// Corner frequency of the DC blocker (Hz).
pub const DC_BLOCK_HZ: f64 = 5.0;

/// Samples the DC blocker computes at once (see [`DcBlock`]).
pub const DC_BLOCK_BLOCK: usize = 4;

/// One-pole DC blocker y\[n\] = x\[n\] − x\[n−1\] + R·y\[n−1\], R = exp(−2π·f_c/f_s).
///
/// Evaluated [`DC_BLOCK_BLOCK`] samples at a time: with uₙ = x\[n\] − x\[n−1\],
/// y_j = Σ_{i≤j} R^{j−i}·u_i + R^{j+1}·y₋₁ (the same recursion unrolled, the powers of R
/// computed in f64), so the four outputs are independent sums the compiler vectorizes.
///
/// # Allocation
/// None.
#[derive(Clone, Debug, Default)]
pub struct DcBlock {
    x1: f32,
    y1: f32,
    r: f32,
    /// Row 0: R^{j+1} (the previous output's weight in y_j); row 1 + i: R^{j−i} for j ≥ i
    /// (u_i's weight in y_j), 0 above the diagonal.
    powers: [[f32; DC_BLOCK_BLOCK]; 1 + DC_BLOCK_BLOCK],
}

impl DcBlock {
    /// A blocker for `sample_rate_hz`.
    pub fn new(sample_rate_hz: f64) -> Self {
        let mut d = Self::default();
        d.set_sample_rate(sample_rate_hz);
        d
    }

    /// Recompute the pole for a new sample rate (keeps the state).
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        let r = (-core::f64::consts::TAU * DC_BLOCK_HZ / sample_rate_hz).exp();
        self.r = r as f32;
        for j in 0..DC_BLOCK_BLOCK {
            self.powers[0][j] = r.powi(j as i32 + 1) as f32;
            for i in 0..DC_BLOCK_BLOCK {
                self.powers[1 + i][j] = if j >= i {
                    r.powi((j - i) as i32) as f32
                } else {
                    0.0
                };
            }
        }
    }

    /// Clear the state (real-time safe).
    pub fn reset(&mut self) {
        self.x1 = 0.0;
        self.y1 = 0.0;
    }

    /// Filter `x` into `out` (same length).
    pub fn process(&mut self, x: &[f32], out: &mut [f32]) {
        let (mut x1, mut y1, r) = (self.x1, self.y1, self.r);
        let n = x.len().min(out.len());
        let (x, out) = (&x[..n], &mut out[..n]);
        let p = &self.powers;
        let mut xs = x.chunks_exact(DC_BLOCK_BLOCK);
        let mut os = out.chunks_exact_mut(DC_BLOCK_BLOCK);
        for (xb, ob) in (&mut xs).zip(&mut os) {
            let mut u = [0.0f32; DC_BLOCK_BLOCK];
            for (j, uj) in u.iter_mut().enumerate() {
                *uj = xb[j] - if j == 0 { x1 } else { xb[j - 1] };
            }
            let mut acc = [0.0f32; DC_BLOCK_BLOCK];
            for (i, &ui) in u.iter().enumerate() {
                for (a, &c) in acc.iter_mut().zip(&p[1 + i]) {
                    *a += c * ui;
                }
            }
            for (a, &c) in acc.iter_mut().zip(&p[0]) {
                *a += c * y1;
            }
            ob.copy_from_slice(&acc);
            x1 = xb[DC_BLOCK_BLOCK - 1];
            y1 = acc[DC_BLOCK_BLOCK - 1];
        }
        for (o, &xi) in os.into_remainder().iter_mut().zip(xs.remainder()) {
            let y = xi - x1 + r * y1;
            x1 = xi;
            y1 = y;
            *o = y;
        }
        self.x1 = x1;
        self.y1 = if y1.is_finite() && y1.abs() > crate::block::FLUSH_THRESHOLD {
            y1
        } else {
            0.0
        };
    }
}

impl Stage for DcBlock {
    /// The chunk of force in, the force the object hears out.
    type Io<'a> = (&'a [f32], &'a mut [f32]);

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        DcBlock::set_sample_rate(self, crate::block::sanitize_sample_rate(sample_rate_hz));
    }

    fn reset(&mut self, _seed: u64) {
        DcBlock::reset(self);
    }

    fn set_params(&mut self, _params: &Params) {}

    fn snap(&mut self) {}

    /// Its state is zero: a zero chunk in gives a zero chunk out.
    fn is_idle(&self) -> bool {
        self.x1 == 0.0 && self.y1 == 0.0
    }

    fn process(&mut self, (x, out): (&[f32], &mut [f32])) {
        DcBlock::process(self, x, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removes_dc_and_passes_audio() {
        let fs = 48_000.0;
        let mut d = DcBlock::new(fs);
        let n = 96_000;
        let x: Vec<f32> = (0..n)
            .map(|i| 0.5 + 0.1 * (core::f64::consts::TAU * 200.0 * i as f64 / fs).sin() as f32)
            .collect();
        let mut y = vec![0f32; n];
        d.process(&x, &mut y);
        let tail = &y[n / 2..];
        let mean = tail.iter().sum::<f32>() / tail.len() as f32;
        let peak = tail.iter().fold(0f32, |m, v| m.max(v.abs()));
        assert!(mean.abs() < 1e-3, "{mean}");
        assert!((peak - 0.1).abs() < 0.002, "{peak}");
    }

    #[test]
    fn blocks_of_four_are_the_recursion() {
        // Any length (remainders included), in pieces: the same as y = x − x₁ + R·y₁ sample
        // by sample, to f32 rounding.
        let fs = 48_000.0;
        let mut d = DcBlock::new(fs);
        let r = (-core::f64::consts::TAU * DC_BLOCK_HZ / fs).exp();
        let x: Vec<f32> = (0..1_003)
            .map(|i| ((i * 7_919) % 1_000) as f32 / 1_000.0 + 0.3)
            .collect();
        let mut y = vec![0f32; x.len()];
        let mut at = 0;
        for len in [64, 3, 17, 1, 64, 854] {
            d.process(&x[at..at + len], &mut y[at..at + len]);
            at += len;
        }
        let (mut x1, mut y1) = (0f64, 0f64);
        for (&xi, &yi) in x.iter().zip(&y) {
            y1 = f64::from(xi) - x1 + r * y1;
            x1 = f64::from(xi);
            assert!((f64::from(yi) - y1).abs() < 5e-5, "{yi} vs {y1}");
        }
    }
}
