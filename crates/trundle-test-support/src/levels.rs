//! Levels of rendered samples (±1 full scale): peak, RMS, in dB; interleaved frames split
//! into channels; the safety limiter's ceiling.

use trundle_dsp::scene::limiter::Limiter;

/// Largest magnitude.
pub fn peak(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// [`peak`] in dB re full scale.
pub fn peak_db(x: &[f64]) -> f64 {
    20.0 * peak(x).log10()
}

/// RMS in dB re full scale.
pub fn rms_db(x: &[f64]) -> f64 {
    10.0 * (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).log10()
}

/// Interleaved samples split into `n` channels (panics unless they are whole frames).
pub fn channels(x: &[f64], n: usize) -> Vec<Vec<f64>> {
    assert_eq!(x.len() % n, 0, "whole frames");
    (0..n)
        .map(|c| x.iter().skip(c).step_by(n).copied().collect())
        .collect()
}

/// The safety limiter's ceiling, −1 dBFS, as the f32 it is applied as.
pub fn ceiling() -> f64 {
    f64::from(Limiter::new(48_000.0).ceiling())
}
