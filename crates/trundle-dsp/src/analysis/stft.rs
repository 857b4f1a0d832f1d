//! Short-time Fourier transform, the one of the crate: Hann frames of ≈ 21 ms, power
//! spectra (feature `fit`: it needs an FFT). The fit's residual envelope and the CLI's
//! spectrogram read it.

use realfft::RealFftPlanner;

/// Short-time power spectra |X|² (Hann frames of ≈ 21 ms, a power of two of at least 64
/// samples, hop = frame / `overlap`; the last frames zero-padded): (frames × bins, frame
/// length, hop). The envelope fit uses overlap 2; `trundle fit-object --plot` draws them.
pub fn stft_power(x: &[f64], sample_rate_hz: f64, overlap: usize) -> (Vec<Vec<f64>>, usize, usize) {
    let len = ((0.021 * sample_rate_hz) as usize)
        .next_power_of_two()
        .max(64);
    let hop = (len / overlap.max(1)).max(1);
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(len);
    let win = hann(len);
    let mut buf = fft.make_input_vec();
    let mut spec = fft.make_output_vec();
    let mut out = Vec::new();
    let mut start = 0;
    while start < x.len() {
        for (i, b) in buf.iter_mut().enumerate() {
            *b = x.get(start + i).copied().unwrap_or(0.0) * win[i];
        }
        fft.process(&mut buf, &mut spec).expect("FFT sizes match");
        out.push(spec.iter().map(|c| c.norm_sqr()).collect());
        start += hop;
    }
    (out, len, hop)
}

/// The Hann window of `len` samples, periodic (0.5 − 0.5·cos(2πi/len)): the window every
/// spectrum of the crate is read through.
pub fn hann(len: usize) -> Vec<f64> {
    (0..len)
        .map(|i| 0.5 - 0.5 * (core::f64::consts::TAU * i as f64 / len as f64).cos())
        .collect()
}

/// Welch's power spectrum, summed over frames: |X|² of every whole Hann frame of `frame`
/// samples (hop `frame`/2) of `x`, added bin by bin; `frame`/2 + 1 bins, all 0 when `x`
/// holds no whole frame. Scale-free uses (a shape, a centroid) need no normalization.
pub fn welch_power(x: &[f64], frame: usize) -> Vec<f64> {
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(frame);
    let win = hann(frame);
    let mut buf = fft.make_input_vec();
    let mut spec = fft.make_output_vec();
    let mut power = vec![0.0; spec.len()];
    let mut start = 0;
    while start + frame <= x.len() {
        for (i, b) in buf.iter_mut().enumerate() {
            *b = x[start + i] * win[i];
        }
        fft.process(&mut buf, &mut spec).expect("FFT sizes match");
        for (p, c) in power.iter_mut().zip(&spec) {
            *p += c.norm_sqr();
        }
        start += frame / 2;
    }
    power
}
