//! Third-octave bands, the one definition of the crate: base-2 centres 1000·2^{k/3} Hz,
//! k = −17 … 13 (20 Hz … 20 kHz, IEC 61260), edges a sixth of an octave either side, and the
//! band-energy measure a fitted object's spectrum and its played modes are compared with
//! (two cascaded RBJ band-pass biquads per band).
//!
//! Two measures of a band's energy, for two jobs:
//! * [`band_energies`], band-pass biquads whose skirts overlap: what a fitted object's band
//!   part is tuned to and compared with (the model's measure).
//! * `brick_wall_energies` (feature `fit`), the sum of |X(f)|² over the FFT bins inside
//!   each band: a band holds what lies in it and nothing of its neighbours, so it tells a
//!   strike's noise from the modes' skirts where the overlapping filters cannot (measured
//!   0.55 against 0.64 dB where the brick-wall bands read 2.4 against 6.3 dB). The tests
//!   measure with it. An analysis only: nothing of the audio path calls it.

/// Third-octave bands of the envelope: centres 1000·2^{k/3} Hz, k = −17 … 13 (20 Hz … 20 kHz).
pub const BANDS: usize = 31;

/// Band index (0 … [`BANDS`] − 1) of a frequency: the nearest third-octave centre.
pub fn band_index(freq_hz: f64) -> usize {
    let k = (3.0 * (freq_hz.max(1.0) / 1000.0).log2()).round() + 17.0;
    k.clamp(0.0, (BANDS - 1) as f64) as usize
}

/// Centre frequency of band `i` (Hz).
pub fn band_centre_hz(i: usize) -> f64 {
    1000.0 * 2f64.powf((i as f64 - 17.0) / 3.0)
}

/// Lower and upper edges of band `i` (Hz): the centre ×2^{∓1/6}.
pub fn band_edges_hz(i: usize) -> (f64, f64) {
    let centre = band_centre_hz(i);
    (
        centre * 2f64.powf(-1.0 / 6.0),
        centre * 2f64.powf(1.0 / 6.0),
    )
}

/// Energy per third-octave band ([`BANDS`], 4·∫y²dt: the a²τ measure) of `x`, its last 30 %
/// faded out (half Hann: a decay cut mid-ring would leak differently for every phase at the
/// cut), through two cascaded RBJ band-pass biquads (Q of a third-octave) per band; bands at
/// or above 0.45·f_s are 0. The one measure of a fitted object's spectrum
/// ([`crate::object::fitted::FittedObject::spectrum`]) and of its played modes.
pub fn band_energies(x: &[f64], sample_rate_hz: f64) -> [f64; BANDS] {
    use core::f64::consts::{PI, TAU};
    let fs = sample_rate_hz;
    let len = x.len();
    let fade = len * 7 / 10;
    let xt: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(n, &v)| {
            if n < fade {
                v
            } else {
                v * 0.5 * (1.0 + (PI * (n - fade) as f64 / (len - fade) as f64).cos())
            }
        })
        .collect();
    let mut out = [0.0; BANDS];
    let q = 1.0 / (2f64.powf(1.0 / 6.0) - 2f64.powf(-1.0 / 6.0));
    for (i, e_out) in out.iter_mut().enumerate() {
        let f0 = band_centre_hz(i);
        if f0 >= 0.45 * fs {
            break;
        }
        let w0 = TAU * f0 / fs;
        let alpha = w0.sin() / (2.0 * q);
        let a0 = 1.0 + alpha;
        let (b0, b2, a1, a2) = (
            alpha / a0,
            -alpha / a0,
            -2.0 * w0.cos() / a0,
            (1.0 - alpha) / a0,
        );
        let mut st = [[0.0f64; 4]; 2];
        let mut e = 0.0;
        for &v in &xt {
            let mut y = v;
            for s in st.iter_mut() {
                let out = b0 * y + b2 * s[1] - a1 * s[2] - a2 * s[3];
                s[1] = s[0];
                s[0] = y;
                s[3] = s[2];
                s[2] = out;
                y = out;
            }
            e += y * y;
        }
        *e_out = 4.0 * e / fs;
    }
    out
}

/// Centres (Hz) of the third-octave bands 1000·2^{k/3}, k = −30 … 14, from `lo_hz` to
/// `hi_hz`, both nominal centres included (50, 12 500 and 16 000 Hz stand for 49.6, 12 699
/// and 16 000): the bands `brick_wall_energies` (feature `fit`) measures.
pub fn centres_between_hz(lo_hz: f64, hi_hz: f64) -> Vec<f64> {
    (-30..=14)
        .map(|k| 1000.0 * 2f64.powf(f64::from(k) / 3.0))
        .filter(|&c| c >= 0.98 * lo_hz && c <= 1.02 * hi_hz)
        .collect()
}

/// Brick-wall energy per third-octave band of `x` sampled at `sample_rate_hz`, for the
/// bands centred from `lo_hz` to `hi_hz` ([`centres_between_hz`]): the sum of |X(f)|² over
/// the bins inside each band's edges (a sixth of an octave either side), X the spectrum of
/// the whole signal (zero-padded to a power of two) with its last 30 % faded out by a half
/// Hann (a decay cut mid-ring would leak differently for every phase at the cut). See the
/// module docs for when to use it rather than [`band_energies`]. Allocates: an analysis,
/// never called from the audio path.
#[cfg(feature = "fit")]
pub fn brick_wall_energies<T: Copy + Into<f64>>(
    x: &[T],
    sample_rate_hz: f64,
    lo_hz: f64,
    hi_hz: f64,
) -> Vec<f64> {
    use realfft::RealFftPlanner;
    let n = x.len().next_power_of_two();
    let fade = x.len() * 7 / 10;
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut buf = fft.make_input_vec();
    for (i, (b, &v)) in buf.iter_mut().zip(x).enumerate() {
        let w = if i < fade {
            1.0
        } else {
            let u = (i - fade) as f64 / (x.len() - fade) as f64;
            0.5 * (1.0 + (core::f64::consts::PI * u).cos())
        };
        *b = v.into() * w;
    }
    let mut spec = fft.make_output_vec();
    fft.process(&mut buf, &mut spec)
        .expect("buffers from the plan");
    let bin_hz = sample_rate_hz / n as f64;
    centres_between_hz(lo_hz, hi_hz)
        .iter()
        .map(|&c| {
            let (lo, hi) = (c * 2f64.powf(-1.0 / 6.0), c * 2f64.powf(1.0 / 6.0));
            spec.iter()
                .enumerate()
                .filter(|(i, _)| (lo..hi).contains(&(*i as f64 * bin_hz)))
                .map(|(_, v)| v.norm_sqr())
                .sum()
        })
        .collect()
}
