//! The baseline of issue #25's judge: Gaussian noise shaped to a recording's long-term power
//! spectrum — the same colour, none of its modulation or texture. A candidate that is not
//! closer to the recording than this on modulation and texture has not heard the recording's
//! texture, only its spectrum (`trundle match` reports against it, `tests/match_corpus.rs`
//! holds matches to it).

use crate::analysis::stft::welch_power;
use rand::rngs::SmallRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use realfft::RealFftPlanner;

/// Frame length of the spectrum [`shaped_noise`] copies (samples): about 10 Hz resolution at
/// 44.1 kHz, finer than a third-octave band everywhere above 40 Hz.
pub const SHAPE_FRAME: usize = 4096;

/// Gaussian noise shaped to `x`'s long-term power spectrum: the issue #25 baseline ("plain
/// noise shaped to the clip's long-term spectrum"). The spectrum is Welch's (Hann frames of
/// [`SHAPE_FRAME`] samples, half overlapping, or the whole clip when shorter), interpolated to
/// the bins of white Gaussian noise of `len` samples (seeded), which it multiplies; the result
/// has `x`'s RMS. Same spectrum, none of the clip's modulation or texture.
pub fn shaped_noise(x: &[f64], len: usize, seed: u64) -> Vec<f64> {
    let frame = SHAPE_FRAME
        .min(x.len().max(2).next_power_of_two() / 2)
        .max(2);
    let psd = welch_power(x, frame);
    let mut planner = RealFftPlanner::<f64>::new();
    let n = len.max(2).next_power_of_two();
    let fwd = planner.plan_fft_forward(n);
    let inv = planner.plan_fft_inverse(n);
    let mut rng = SmallRng::seed_from_u64(seed);
    let mut noise: Vec<f64> = (0..n).map(|_| StandardNormal.sample(&mut rng)).collect();
    let mut nspec = fwd.make_output_vec();
    fwd.process(&mut noise, &mut nspec)
        .expect("FFT sizes match");
    let last = nspec.len() - 1;
    for (k, z) in nspec.iter_mut().enumerate() {
        // Bin k of n is at k/n of the rate; the PSD's bin j at j/frame.
        let pos = k as f64 * frame as f64 / n as f64;
        let j = (pos.floor() as usize).min(psd.len() - 1);
        let t = pos - j as f64;
        let p = psd[j] * (1.0 - t) + psd[(j + 1).min(psd.len() - 1)] * t;
        *z *= p.sqrt();
        if k == 0 || k == last {
            z.im = 0.0;
        }
    }
    let mut out = inv.make_output_vec();
    inv.process(&mut nspec, &mut out).expect("FFT sizes match");
    out.truncate(len);
    let rms = |v: &[f64]| (v.iter().map(|s| s * s).sum::<f64>() / v.len().max(1) as f64).sqrt();
    let gain = rms(x) / rms(&out).max(1e-300);
    out.iter_mut().for_each(|v| *v *= gain);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Noise shaped to low-passed noise keeps its level exactly and its colour: the share of
    /// power its first differences keep (a high-pass) within 10 % of the signal's (the
    /// spectrum is copied at 12 Hz resolution; the rest is the estimate's own scatter).
    #[test]
    fn shaped_noise_copies_the_colour_and_the_level() {
        let mut rng = SmallRng::seed_from_u64(7);
        let mut y = 0.0;
        let x: Vec<f64> = (0..48_000)
            .map(|_| {
                let w: f64 = StandardNormal.sample(&mut rng);
                y += 0.05 * (w - y);
                y
            })
            .collect();
        let n = shaped_noise(&x, 24_000, 1);
        assert_eq!(n.len(), 24_000);
        let rms = |v: &[f64]| (v.iter().map(|s| s * s).sum::<f64>() / v.len() as f64).sqrt();
        assert!((rms(&n) / rms(&x) - 1.0).abs() < 1e-9);
        // High-passed by first differences: a low-passed signal loses most of its power.
        let hf = |v: &[f64]| rms(&v.windows(2).map(|w| w[1] - w[0]).collect::<Vec<_>>()) / rms(v);
        assert!((hf(&n) / hf(&x) - 1.0).abs() < 0.1, "{} {}", hf(&n), hf(&x));
    }
}
