//! Line spectra for the tests that read a pitch or a rate: a Hann-windowed magnitude
//! spectrum over a whole take, and its peaks refined by a parabola through the log
//! magnitudes of the peak bin and its two neighbours (J. O. Smith, *Spectral Audio Signal
//! Processing*, "Quadratic Interpolation of Spectral Peaks": on a Hann window the vertex
//! lies within a few hundredths of a bin of the true frequency).

use realfft::RealFftPlanner;

/// Magnitude spectrum of `x` under a Hann window over the whole take: bin k lies at
/// k·f_s/len Hz (`len` = `x.len()`).
pub fn magnitude<T: Copy + Into<f64>>(x: &[T]) -> Vec<f64> {
    let n = x.len();
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut input: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let w = 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / n as f64).cos();
            v.into() * w
        })
        .collect();
    let mut out = fft.make_output_vec();
    fft.process(&mut input, &mut out)
        .expect("a forward FFT of its own planned size");
    out.iter().map(|c| c.norm()).collect()
}

/// The bins from `lo_hz` to `hi_hz` at a bin width `df_hz` (each with a neighbour either side).
fn bins(spec: &[f64], df_hz: f64, lo_hz: f64, hi_hz: f64) -> std::ops::RangeInclusive<usize> {
    let a = (lo_hz / df_hz) as usize + 1;
    let b = ((hi_hz / df_hz) as usize).min(spec.len().saturating_sub(2));
    assert!(a <= b, "no bins between {lo_hz} and {hi_hz} Hz");
    a..=b
}

/// Bin `k` refined by the parabola through the log magnitudes of `k − 1`, `k`, `k + 1`, in Hz.
fn refined_hz(spec: &[f64], k: usize, df_hz: f64) -> f64 {
    let ln = |i: usize| spec[i].max(1e-300).ln();
    let (l, c, r) = (ln(k - 1), ln(k), ln(k + 1));
    let d = 0.5 * (l - r) / (l - 2.0 * c + r);
    (k as f64 + if d.is_finite() { d } else { 0.0 }) * df_hz
}

/// The strongest peak of `spec` (bin width `df_hz`) between `lo_hz` and `hi_hz`: its
/// refined frequency (Hz) and its bin's magnitude.
pub fn peak_hz(spec: &[f64], df_hz: f64, lo_hz: f64, hi_hz: f64) -> (f64, f64) {
    let k = bins(spec, df_hz, lo_hz, hi_hz)
        .max_by(|&i, &j| spec[i].total_cmp(&spec[j]))
        .expect("a non-empty range");
    (refined_hz(spec, k, df_hz), spec[k])
}

/// The fundamental of `spec` (bin width `df_hz`): the lowest local peak above `lo_hz`
/// within 20 dB of the strongest peak below `hi_hz` (a partial's harmonics may outweigh
/// it), refined; with its bin's magnitude.
pub fn fundamental_hz(spec: &[f64], df_hz: f64, lo_hz: f64, hi_hz: f64) -> (f64, f64) {
    let (_, top) = peak_hz(spec, df_hz, lo_hz, hi_hz);
    let range = bins(spec, df_hz, lo_hz, hi_hz);
    let first = *range.start();
    let k = range
        .into_iter()
        .find(|&k| spec[k] >= 0.1 * top && spec[k] >= spec[k - 1] && spec[k] >= spec[k + 1])
        .unwrap_or(first);
    (refined_hz(spec, k, df_hz), spec[k])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine between two bins is read within 0.05 bin; its fundamental under a louder
    /// second harmonic is still the sine.
    #[test]
    fn a_tone_between_bins_is_read_within_a_twentieth_of_a_bin() {
        let (fs, n) = (48_000.0, 48_000usize);
        let f0 = 440.37;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                (std::f64::consts::TAU * f0 * t).sin()
                    + 2.0 * (std::f64::consts::TAU * 2.0 * f0 * t).sin()
            })
            .collect();
        let s = magnitude(&x);
        let df = fs / n as f64;
        let (top, _) = peak_hz(&s, df, 100.0, 2_000.0);
        assert!((top - 2.0 * f0).abs() < 0.05 * df, "{top}");
        let (f, _) = fundamental_hz(&s, df, 100.0, 2_000.0);
        assert!((f - f0).abs() < 0.05 * df, "{f}");
    }
}
