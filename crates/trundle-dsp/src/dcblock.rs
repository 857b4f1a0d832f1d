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

/// Corner frequency of the DC blocker (Hz).
pub const DC_BLOCK_HZ: f64 = 5.0;

/// One-pole DC blocker y[n] = x[n] − x[n−1] + R·y[n−1], R = exp(−2π·f_c/f_s).
///
/// # Allocation
/// None.
#[derive(Clone, Debug, Default)]
pub struct DcBlock {
    x1: f32,
    y1: f32,
    r: f32,
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
        self.r = (-core::f64::consts::TAU * DC_BLOCK_HZ / sample_rate_hz).exp() as f32;
    }

    /// Clear the state (real-time safe).
    pub fn reset(&mut self) {
        self.x1 = 0.0;
        self.y1 = 0.0;
    }

    /// Filter `x` into `out` (same length).
    pub fn process(&mut self, x: &[f32], out: &mut [f32]) {
        let (mut x1, mut y1, r) = (self.x1, self.y1, self.r);
        for (o, &xi) in out.iter_mut().zip(x) {
            let y = xi - x1 + r * y1;
            x1 = xi;
            y1 = y;
            *o = y;
        }
        self.x1 = x1;
        self.y1 = if y1.is_finite() && y1.abs() > crate::FLUSH_THRESHOLD {
            y1
        } else {
            0.0
        };
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
}
