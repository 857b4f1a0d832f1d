//! Band envelopes, the periphery the texture measures listen through (McDermott & Simoncelli
//! 2011, "Sound texture perception via statistics of the auditory periphery", Neuron 71,
//! §Experimental Procedures: a cochlear filter bank, Hilbert envelopes, compression by a
//! power of 0.3, envelopes downsampled to 400 Hz).
//!
//! Here the bank is [`ENVELOPE_BANDS`] brick-wall bands, log-spaced from 100 Hz to 12.7 kHz
//! (≈ 1.2 octaves each, [`BAND_EDGES_HZ`]): coarser than the paper's 30 ERB bands, as the
//! judge of issue #25 specifies six, and wide enough that each holds many partials of a
//! rolling or rubbing sound. Each band is cut out of the whole signal's spectrum and its
//! analytic signal formed from the band's bins alone: shifted down to start at 0 Hz, they are
//! inverse-transformed at a length of at least four times the band's width (the magnitude
//! does not change with the shift, and the squared magnitude holds at most twice the band's
//! width) and at least [`POINTS_PER_FRAME`] points per envelope frame, so the magnitude is
//! computed exactly at every D-th sample (D a power of two, 4 at 48 kHz) instead of at every
//! sample. The magnitude, compressed, is averaged into [`ENVELOPE_RATE_HZ`] frames.

use std::cell::RefCell;

use realfft::num_complex::Complex;
use realfft::RealFftPlanner;
use rustfft::FftPlanner;

use super::compress::Compressor;

thread_local! {
    /// One planner per thread, shared with the long-term spectrum: `trundle match` analyses
    /// hundreds of candidates of the same length, and a plan's twiddle factors are worth
    /// computing once.
    pub(super) static PLANNER: RefCell<RealFftPlanner<f64>> = RefCell::new(RealFftPlanner::new());
    /// The bands' short complex inverse transforms, one planner per thread likewise.
    static COMPLEX_PLANNER: RefCell<FftPlanner<f64>> = RefCell::new(FftPlanner::new());
}

/// Number of envelope bands.
pub const ENVELOPE_BANDS: usize = 6;
/// Edges of the envelope bands (Hz): about 100 Hz × 127^{k/6}, k = 0 … 6.
pub const BAND_EDGES_HZ: [f64; ENVELOPE_BANDS + 1] =
    [100.0, 224.0, 502.0, 1125.0, 2520.0, 5650.0, 12700.0];
/// Rate of the envelopes (Hz), as the paper's.
pub const ENVELOPE_RATE_HZ: f64 = 400.0;
/// The compressive exponent applied to each envelope sample (the paper's 0.3).
pub const COMPRESSION: f64 = 0.3;
/// Fewest magnitude points averaged into one envelope frame (30 of a 2.5 ms frame's 120
/// samples at 48 kHz). Measured on the texture corpus's matches against every sample's
/// magnitude: the modulation distance moves by at most 0.03 dB (0.1 dB with 8 points, on
/// the bowed strings), the texture distance by at most 0.01 units, for 3 % more time.
pub const POINTS_PER_FRAME: f64 = 16.0;

/// A signal's band envelopes.
#[derive(Clone, Debug, PartialEq)]
pub struct BandEnvelopes {
    /// `(low, high)` edges of each band analysed (Hz); bands above `top_hz` are left out and
    /// the top one is cut at `top_hz`.
    pub edges_hz: Vec<(f64, f64)>,
    /// One compressed envelope per band, at [`ENVELOPE_RATE_HZ`].
    pub bands: Vec<Vec<f64>>,
}

impl BandEnvelopes {
    /// Duration of the envelopes (s).
    pub fn duration_s(&self) -> f64 {
        self.bands.first().map_or(0.0, |b| b.len() as f64) / ENVELOPE_RATE_HZ
    }

    /// The envelopes of frames `from..to` (the halves of a recording).
    pub fn slice(&self, from: usize, to: usize) -> Self {
        Self {
            edges_hz: self.edges_hz.clone(),
            bands: self
                .bands
                .iter()
                .map(|b| b[from.min(b.len())..to.min(b.len())].to_vec())
                .collect(),
        }
    }

    /// Frames per band.
    pub fn frames(&self) -> usize {
        self.bands.first().map_or(0, Vec::len)
    }
}

/// The bands analysed when nothing above `top_hz` is to be compared: every band of
/// [`BAND_EDGES_HZ`] whose lower edge is at most `top_hz` / 1.5, the top one cut at `top_hz`.
pub fn envelope_edges_hz(top_hz: f64) -> Vec<(f64, f64)> {
    (0..ENVELOPE_BANDS)
        .filter(|&i| BAND_EDGES_HZ[i] * 1.5 <= top_hz)
        .map(|i| (BAND_EDGES_HZ[i], BAND_EDGES_HZ[i + 1].min(top_hz)))
        .collect()
}

/// Band envelopes of `x` (sampled at `sample_rate_hz`) for the bands up to `top_hz`
/// ([`envelope_edges_hz`]). Allocates: an analysis, never on the audio path.
pub fn band_envelopes(x: &[f64], sample_rate_hz: f64, top_hz: f64) -> BandEnvelopes {
    let edges_hz = envelope_edges_hz(top_hz.min(0.5 * sample_rate_hz));
    let n = x.len().max(2).next_power_of_two();
    let forward = PLANNER.with(|p| p.borrow_mut().plan_fft_forward(n));
    let compressor = Compressor::new();
    let mut buf = forward.make_input_vec();
    buf[..x.len()].copy_from_slice(x);
    let mut spec = forward.make_output_vec();
    forward
        .process(&mut buf, &mut spec)
        .expect("buffers from the plan");
    let bin_hz = sample_rate_hz / n as f64;
    let frame = sample_rate_hz / ENVELOPE_RATE_HZ;
    let frames = (x.len() as f64 / frame).floor() as usize;
    // Points are taken every `step` samples: the largest power of two that leaves
    // POINTS_PER_FRAME in a frame.
    let max_step = 1usize << (frame / POINTS_PER_FRAME).max(1.0).log2().floor() as u32;
    let last = spec.len() - 1;
    let bands = edges_hz
        .iter()
        .map(|&(lo, hi)| {
            // The band's bins (never DC nor Nyquist, as the real spectrum's band needs).
            let k_lo = ((lo / bin_hz).ceil() as usize).max(1);
            let k_hi = ((hi / bin_hz).ceil() as usize).min(last).max(k_lo);
            let width = k_hi - k_lo;
            let m = (n / max_step).max((4 * width).next_power_of_two()).min(n);
            let step = n / m;
            let fft = COMPLEX_PLANNER.with(|p| p.borrow_mut().plan_fft_inverse(m));
            let mut z = vec![Complex::new(0.0, 0.0); m];
            z[..width].copy_from_slice(&spec[k_lo..k_hi]);
            fft.process(&mut z);
            // The real inverse of the band alone is 2·Re of this sum and its Hilbert
            // transform 2·Im, both unscaled: the magnitude squared is 4|z|²/n².
            let scale2 = 4.0 / (n as f64 * n as f64);
            (0..frames)
                .map(|f| {
                    let a = (f as f64 * frame) as usize;
                    let b = (((f + 1) as f64 * frame) as usize).min(x.len());
                    let (p, q) = (a.div_ceil(step), b.div_ceil(step));
                    let sum: f64 = z[p..q]
                        .iter()
                        .map(|c| compressor.of_squared(scale2 * c.norm_sqr()))
                        .sum();
                    sum / (q - p).max(1) as f64
                })
                .collect()
        })
        .collect();
    BandEnvelopes { edges_hz, bands }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine's envelope in its band is its amplitude (compressed); other bands are empty.
    #[test]
    fn a_sine_sits_in_its_band_with_its_amplitude() {
        let fs = 48_000.0;
        let x: Vec<f64> = (0..48_000)
            .map(|i| 0.5 * (core::f64::consts::TAU * 1000.0 * i as f64 / fs).sin())
            .collect();
        let env = band_envelopes(&x, fs, 20_000.0);
        assert_eq!(env.bands.len(), ENVELOPE_BANDS);
        assert_eq!(env.frames(), 400);
        let mid = &env.bands[2][40..360];
        let mean = mid.iter().sum::<f64>() / mid.len() as f64;
        // The Hilbert envelope of a steady sine is its amplitude: 0.5^0.3 ≈ 0.812 (1 %:
        // the brick-wall band's edge ripple at the ends is excluded above).
        assert!((mean / 0.5f64.powf(0.3) - 1.0).abs() < 0.01, "{mean}");
        // Two bands up, only the rectangular window's leakage: under −80 dB (compression
        // undone).
        let leak = env.bands[4][200].powf(1.0 / COMPRESSION) / 0.5;
        assert!(leak < 1e-4, "{leak}");
    }

    /// A low sample rate drops the bands it cannot hold.
    #[test]
    fn bands_stop_below_nyquist() {
        let e = envelope_edges_hz(3000.0);
        assert_eq!(e.len(), 4);
        assert_eq!(e.last().map(|b| b.1), Some(2520.0));
    }
}
