//! Band splitting for the subspace analysis: heterodyne, low-pass, decimate.
//!
//! Each analysis band is an interval [lo, hi) of the spectrum (width B). The real signal is
//! shifted down by the band centre f_c (x\[n\]·e^{−i2πf_c n/f_s}), low-passed by a linear-phase
//! Kaiser-windowed sinc (flat to ±0.75·B, stop band from f_d − 0.75·B, 80 dB) and kept every
//! D-th sample (f_d = f_s/D ≈ 4·B). A damped exponential c·zⁿ through any FIR filter stays a
//! damped exponential once the filter has left the onset, with its amplitude multiplied by
//! the filter's response evaluated *at the pole*, G(z) = Σⱼ hⱼ z^{j−h} ([`BandSignal::gain_at`]);
//! so the decimated band signal is exactly a smaller sum of damped exponentials, which is
//! what the subspace method of [`super::subspace`] needs (Roy & Kailath 1989 and Hua &
//! Sarkar 1990 both assume it). Aliases of the stop band and the negative-frequency images
//! of the real signal land outside the accepted interval, and modes found there are
//! discarded (they belong to a neighbouring band).

use core::f64::consts::{PI, TAU};
use nalgebra::Complex;

/// One analysis band: accepted interval [lo_hz, hi_hz).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// Lower edge of the accepted interval (Hz).
    pub lo_hz: f64,
    /// Upper edge of the accepted interval (Hz).
    pub hi_hz: f64,
}

impl Band {
    /// Centre frequency (Hz).
    pub fn centre_hz(&self) -> f64 {
        0.5 * (self.lo_hz + self.hi_hz)
    }
    /// Width B (Hz).
    pub fn width_hz(&self) -> f64 {
        self.hi_hz - self.lo_hz
    }
}

/// The band layout over [min_hz, max_hz): width B = min(0.6·lo, max(150 Hz, 0.25·lo)) —
/// narrow where the negative-frequency image is near (low frequencies), 150 Hz in the
/// low-mid range where modes of real objects crowd, a quarter of an octave-ish above.
pub fn layout(min_hz: f64, max_hz: f64) -> Vec<Band> {
    let mut out = Vec::new();
    let mut lo = min_hz;
    while lo < max_hz - 1e-9 {
        let w = (0.6 * lo).min((0.25 * lo).max(150.0));
        let hi = (lo + w).min(max_hz);
        // Avoid a sliver at the top: merge it into the last band.
        let hi = if max_hz - hi < 0.3 * w { max_hz } else { hi };
        out.push(Band {
            lo_hz: lo,
            hi_hz: hi,
        });
        lo = hi;
    }
    out
}

/// A heterodyned, filtered, decimated band.
#[derive(Clone, Debug)]
pub struct BandSignal {
    /// The band.
    pub band: Band,
    /// Decimation factor D.
    pub decimation: usize,
    /// Index of the first decimated sample whose filter window lies wholly inside the
    /// signal (earlier ones are the filter's transient).
    pub start: usize,
    /// The decimated complex samples y\[m\] (time m·D from the start of the free decay).
    pub samples: Vec<Complex<f64>>,
    taps: Vec<f64>,
    sample_rate_hz: f64,
}

fn bessel_i0(x: f64) -> f64 {
    let mut sum = 1.0;
    let mut term = 1.0;
    let q = 0.25 * x * x;
    for k in 1..200 {
        term *= q / (k * k) as f64;
        sum += term;
        if term < sum * 1e-17 {
            break;
        }
    }
    sum
}

/// Kaiser-windowed sinc low-pass, `len` taps (odd), cutoff `cut` in cycles per sample,
/// β = 7.857 (80 dB stop band; Kaiser's formula β = 0.1102·(A − 8.7)).
fn lowpass_taps(len: usize, cut: f64) -> Vec<f64> {
    let beta = 0.1102 * (80.0 - 8.7);
    let half = (len - 1) as f64 / 2.0;
    let norm = bessel_i0(beta);
    let mut h: Vec<f64> = (0..len)
        .map(|j| {
            let t = j as f64 - half;
            let sinc = if t == 0.0 {
                2.0 * cut
            } else {
                (TAU * cut * t).sin() / (PI * t)
            };
            let r = if half > 0.0 { t / half } else { 0.0 };
            sinc * bessel_i0(beta * (1.0 - r * r).max(0.0).sqrt()) / norm
        })
        .collect();
    let dc: f64 = h.iter().sum();
    h.iter_mut().for_each(|v| *v /= dc);
    h
}

/// Distance (Hz, wrapped to ±f_s/2) of the baseband image −f − f_c.
fn image_offset_hz(f: f64, fc: f64, fs: f64) -> f64 {
    let v = (-f - fc).rem_euclid(fs);
    v.min(fs - v)
}

impl BandSignal {
    /// Split out `band` of `x` (samples from the onset) at `sample_rate_hz`, keeping at most
    /// `max_len` decimated samples. `None` when the signal is too short for the band's filter
    /// (fewer than 32 decimated samples after the filter's transient) or the band cannot be
    /// separated from its image.
    ///
    /// # Allocation
    /// Allocates the filter and the output.
    pub fn new(x: &[f64], sample_rate_hz: f64, band: Band, max_len: usize) -> Option<Self> {
        let fs = sample_rate_hz;
        let b = band.width_hz();
        let fc = band.centre_hz();
        let pass = 0.75 * b;
        // The nearest image of the accepted interval must fall in the stop band.
        let img = image_offset_hz(band.lo_hz, fc, fs).min(image_offset_hz(band.hi_hz, fc, fs));
        let mut fd = (4.0 * b).min(img + pass).min(fs);
        if fd < 1.75 * b {
            return None;
        }
        let decimation = ((fs / fd).floor() as usize).max(1);
        fd = fs / decimation as f64;
        let stop = (fd - pass).min(0.5 * fs);
        let transition = (stop - pass).max(1e-3 * fs);
        // Kaiser's length estimate for 80 dB: N = (A − 8)/(2.285·Δω).
        let mut len = ((80.0 - 8.0) / (2.285 * TAU * transition / fs)).ceil() as usize + 1;
        len |= 1;
        let taps = lowpass_taps(len, 0.5 * (pass + stop) / fs);
        let half = (len - 1) / 2;
        // Decimated samples from n = 0: the first ⌈h/D⌉ are the filter's transient (the
        // window reaches before the free decay), modelled exactly by [`Self::basis`].
        let steady = half.div_ceil(decimation);
        if x.len() < half + 1 + (steady + 32) * decimation {
            return None;
        }
        let count = ((x.len() - half - 1) / decimation + 1).min(max_len + steady);
        if count < steady + 32 {
            return None;
        }
        let w = TAU * fc / fs;
        let last = ((count - 1) * decimation + half).min(x.len() - 1);
        let shifted: Vec<Complex<f64>> = x[..=last]
            .iter()
            .enumerate()
            .map(|(n, &v)| {
                let (s, c) = (w * n as f64).sin_cos();
                Complex::new(v * c, -v * s)
            })
            .collect();
        let samples = (0..count)
            .map(|m| {
                let n = m * decimation;
                let j0 = half.saturating_sub(n);
                let mut acc = Complex::new(0.0, 0.0);
                for j in j0..len {
                    acc += shifted[n + j - half] * taps[j];
                }
                acc
            })
            .collect();
        let start = steady;
        Some(Self {
            band,
            decimation,
            start,
            samples,
            taps,
            sample_rate_hz: fs,
        })
    }

    /// The band's decimated sample rate f_s/D (Hz).
    pub fn rate_hz(&self) -> f64 {
        self.sample_rate_hz / self.decimation as f64
    }

    /// What a unit exponential zⁿ (n ≥ 0, zero before) becomes at decimated sample m:
    /// z^{mD}·Σ_{j ≥ h − mD} hⱼ z^{j−h} (the full response [`Self::gain_at`] once the window
    /// is inside the signal).
    pub fn basis(&self, z: Complex<f64>, m: usize, full_gain: Complex<f64>) -> Complex<f64> {
        let n = m * self.decimation;
        let half = (self.taps.len() - 1) / 2;
        let zn = z.powi(n as i32);
        if n >= half {
            return zn * full_gain;
        }
        let mut acc = Complex::new(0.0, 0.0);
        let mut p = z.powi(-(n as i32));
        for j in half - n..self.taps.len() {
            acc += p * self.taps[j];
            p *= z;
        }
        zn * acc
    }

    /// The centred filter's response at the full-rate baseband pole z:
    /// G(z) = Σⱼ hⱼ·z^{j−h} (exact for a damped exponential after the transient).
    pub fn gain_at(&self, z: Complex<f64>) -> Complex<f64> {
        let half = (self.taps.len() - 1) / 2;
        let zinv = Complex::new(1.0, 0.0) / z;
        // Horner from both ends around the centre.
        let mut acc = Complex::new(0.0, 0.0);
        let mut p = Complex::new(1.0, 0.0);
        acc += p * self.taps[half];
        let mut q = Complex::new(1.0, 0.0);
        for k in 1..=half {
            p *= z;
            q *= zinv;
            acc += p * self.taps[half + k] + q * self.taps[half - k];
        }
        acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_tiles_the_range_without_gaps() {
        let b = layout(50.0, 20_000.0);
        assert_eq!(b[0].lo_hz, 50.0);
        assert_eq!(b.last().unwrap().hi_hz, 20_000.0);
        for w in b.windows(2) {
            assert_eq!(w[0].hi_hz, w[1].lo_hz);
        }
        assert!(b.len() < 40, "{} bands", b.len());
    }

    #[test]
    fn a_damped_exponential_passes_with_the_gain_at_its_pole() {
        let fs = 48_000.0;
        let (f, tau) = (1234.5, 0.05);
        let x: Vec<f64> = (0..24_000)
            .map(|n| {
                let t = n as f64 / fs;
                (-t / tau).exp() * (TAU * f * t + 0.3).cos()
            })
            .collect();
        let band = layout(50.0, 20_000.0)
            .into_iter()
            .find(|b| b.lo_hz <= f && f < b.hi_hz)
            .unwrap();
        let s = BandSignal::new(&x, fs, band, 400).unwrap();
        let zb = Complex::from_polar((-1.0 / (tau * fs)).exp(), TAU * (f - band.centre_hz()) / fs);
        let g = s.gain_at(zb);
        // Positive-frequency half of the cosine: ½e^{i0.3}; the image is > 80 dB down once
        // the window is inside the signal (a truncated window lets it through, so the
        // transient samples are checked against the basis with the image included).
        let image = Complex::from_polar(
            (-1.0 / (tau * fs)).exp(),
            TAU * (-f - band.centre_hz()) / fs,
        );
        for (m, y) in s.samples.iter().enumerate() {
            let want = Complex::from_polar(0.5, 0.3) * s.basis(zb, m, g)
                + Complex::from_polar(0.5, -0.3) * s.basis(image, m, s.gain_at(image));
            if m >= s.start {
                let n = (m * s.decimation) as i32;
                let steady = Complex::from_polar(0.5, 0.3) * g * zb.powi(n);
                assert!((y - steady).norm() < 1e-4 * steady.norm().max(1e-3), "{m}");
            }
            assert!(
                (y - want).norm() < 1e-4 * want.norm().max(1e-3),
                "{m}: {y} vs {want}"
            );
        }
    }
}
