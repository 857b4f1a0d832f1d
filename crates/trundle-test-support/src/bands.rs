//! Third-octave band levels and the distance between two spectra: the tests' one band
//! measure.
//!
//! The bands and their energy are the model's brick-wall measure,
//! [`trundle_dsp::analysis::third_octave::brick_wall_energies`] (FFT bins summed inside each
//! band, so a band holds nothing of its neighbours; see that module for why the tests use it
//! rather than the model's overlapping band-pass measure).

use trundle_dsp::analysis::third_octave::brick_wall_energies;
pub use trundle_dsp::analysis::third_octave::centres_between_hz;

/// Centres (Hz) of the bands [`third_octave_db`] returns, 50 Hz … 16 kHz.
pub fn centres_hz() -> Vec<f64> {
    centres_between_hz(50.0, 16_000.0)
}

/// Energy per third-octave band of `x` sampled at `sample_rate_hz`, for the bands centred
/// from `lo_hz` to `hi_hz` ([`centres_between_hz`]); see the module docs.
pub fn third_octave_energy_between<T: Copy + Into<f64>>(
    x: &[T],
    sample_rate_hz: f64,
    lo_hz: f64,
    hi_hz: f64,
) -> Vec<f64> {
    brick_wall_energies(x, sample_rate_hz, lo_hz, hi_hz)
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
