//! Impulsiveness: how much of the sound is in rare loud moments. Two numbers a sound designer
//! reads: the waveform's kurtosis (3 for Gaussian noise, a steady rub; tens for sparse clicks)
//! and its crest factor over 100 ms windows (peak over RMS, the median over windows, in dB).
//! Both are level-independent.

/// Length of a crest-factor window (s).
pub const CREST_WINDOW_S: f64 = 0.1;

/// Kurtosis of `x` about its mean (3 for a Gaussian; 3 for silence by convention).
pub fn kurtosis(x: &[f64]) -> f64 {
    let n = x.len().max(1) as f64;
    let mean = x.iter().sum::<f64>() / n;
    let (mut m2, mut m4) = (0.0, 0.0);
    for &v in x {
        let d2 = (v - mean) * (v - mean);
        m2 += d2;
        m4 += d2 * d2;
    }
    if m2 <= 1e-300 {
        3.0
    } else {
        (m4 / n) / ((m2 / n) * (m2 / n))
    }
}

/// Median crest factor (dB) of the [`CREST_WINDOW_S`] windows of `x` that are not silent
/// (RMS at least 60 dB under the loudest window's); 0 for silence.
pub fn crest_factor_db(x: &[f64], sample_rate_hz: f64) -> f64 {
    let w = ((CREST_WINDOW_S * sample_rate_hz) as usize).max(1);
    let windows: Vec<(f64, f64)> = x
        .chunks(w)
        .filter(|c| c.len() * 2 >= w || x.len() < w)
        .map(|c| {
            let peak = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let rms = (c.iter().map(|v| v * v).sum::<f64>() / c.len() as f64).sqrt();
            (peak, rms)
        })
        .collect();
    let loudest = windows.iter().fold(0.0f64, |m, w| m.max(w.1));
    let mut crest: Vec<f64> = windows
        .iter()
        .filter(|w| w.1 > 1e-3 * loudest && w.1 > 0.0)
        .map(|w| 20.0 * (w.0 / w.1).log10())
        .collect();
    if crest.is_empty() {
        return 0.0;
    }
    crest.sort_by(f64::total_cmp);
    crest[crest.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sine_has_kurtosis_one_and_a_half_and_crest_three_db() {
        let fs = 48_000.0;
        let x: Vec<f64> = (0..48_000)
            .map(|i| (core::f64::consts::TAU * 500.0 * i as f64 / fs).sin())
            .collect();
        assert!((kurtosis(&x) - 1.5).abs() < 1e-3);
        assert!((crest_factor_db(&x, fs) - 3.0103).abs() < 0.01);
    }
}
