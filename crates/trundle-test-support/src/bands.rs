//! Third-octave band levels and the distance between two spectra: the tests' one band
//! measure.
//!
//! Bands are centred at 1000·2^{k/3} Hz with edges a sixth of an octave either side; a
//! band's energy is the sum of |X(f)|² over the bins inside it, X the spectrum of the whole
//! signal (zero-padded to a power of two) with its last 30 % faded out by a half Hann (a
//! decay cut mid-ring would leak differently for every phase at the cut). The bands are
//! brick-wall, so a band holds what lies in it and nothing of its neighbours: the model's
//! own band measure (`trundle_dsp::object::fitted::band_energies`, band-pass biquads whose
//! skirts overlap) is what the fitted object's band part is tuned to, and it cannot tell a
//! strike's noise from the modes' skirts (measured 0.55 against 0.64 dB where these bands
//! read 2.4 against 6.3 dB), so the tests measure with this one.

use realfft::RealFftPlanner;

/// Centres (Hz) of the bands [`third_octave_db`] returns, 50 Hz … 16 kHz.
pub fn centres_hz() -> Vec<f64> {
    centres_between_hz(50.0, 16_000.0)
}

/// Centres (Hz) of the third-octave bands from `lo_hz` to `hi_hz`, both nominal centres
/// included (50, 12 500 and 16 000 Hz stand for 49.6, 12 699 and 16 000).
pub fn centres_between_hz(lo_hz: f64, hi_hz: f64) -> Vec<f64> {
    (-30..=14)
        .map(|k| 1000.0 * 2f64.powf(f64::from(k) / 3.0))
        .filter(|&c| c >= 0.98 * lo_hz && c <= 1.02 * hi_hz)
        .collect()
}

/// Energy per third-octave band of `x` sampled at `sample_rate_hz`, for the bands centred
/// from `lo_hz` to `hi_hz` ([`centres_between_hz`]); see the module docs.
pub fn third_octave_energy_between<T: Copy + Into<f64>>(
    x: &[T],
    sample_rate_hz: f64,
    lo_hz: f64,
    hi_hz: f64,
) -> Vec<f64> {
    let n = x.len().next_power_of_two();
    let fade = x.len() * 7 / 10;
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut buf = fft.make_input_vec();
    for (i, (b, &v)) in buf.iter_mut().zip(x).enumerate() {
        let w = if i < fade {
            1.0
        } else {
            let u = (i - fade) as f64 / (x.len() - fade) as f64;
            0.5 * (1.0 + (std::f64::consts::PI * u).cos())
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

/// Energy per third-octave band 50 Hz … 16 kHz ([`centres_hz`]) of `x`.
pub fn third_octave_energy<T: Copy + Into<f64>>(x: &[T], sample_rate_hz: f64) -> Vec<f64> {
    third_octave_energy_between(x, sample_rate_hz, 50.0, 16_000.0)
}

/// [`third_octave_energy_between`] in dB (floored at −300 dB).
pub fn third_octave_db_between<T: Copy + Into<f64>>(
    x: &[T],
    sample_rate_hz: f64,
    lo_hz: f64,
    hi_hz: f64,
) -> Vec<f64> {
    third_octave_energy_between(x, sample_rate_hz, lo_hz, hi_hz)
        .iter()
        .map(|&e| 10.0 * e.max(1e-30).log10())
        .collect()
}

/// Energy per third-octave band 50 Hz … 16 kHz of `x`, in dB.
pub fn third_octave_db<T: Copy + Into<f64>>(x: &[T], sample_rate_hz: f64) -> Vec<f64> {
    third_octave_db_between(x, sample_rate_hz, 50.0, 16_000.0)
}

/// RMS difference (dB) of the third-octave spectra ([`third_octave_db`]) of `a` and `b`.
/// With `TRUNDLE_BANDS` set in the environment it prints the bands (centre, `a`, `b`,
/// difference) for a diagnosis.
pub fn third_octave_distance_db(a: &[f64], b: &[f64], sample_rate_hz: f64) -> f64 {
    let (sa, sb) = (
        third_octave_db(a, sample_rate_hz),
        third_octave_db(b, sample_rate_hz),
    );
    if std::env::var_os("TRUNDLE_BANDS").is_some() {
        for ((c, x), y) in centres_hz().iter().zip(&sa).zip(&sb) {
            println!("  {c:8.0} {x:7.1} {y:7.1} {:+6.1}", y - x);
        }
    }
    (sa.iter()
        .zip(&sb)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        / sa.len() as f64)
        .sqrt()
}
