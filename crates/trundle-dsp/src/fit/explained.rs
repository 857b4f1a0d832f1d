//! How much of a recording a fit explains, band by band (issue #26, "honest fits").
//!
//! Per third-octave band (IEC 61260 centres, brick-wall bands of the whole fitted decay:
//! [`brick_wall_energies`], so a band holds what lies in it): the recording's energy, the
//! residual's (recording − modes), and the explained level, residual ÷ recording in dB
//! (−20 dB: the modes explain 99 % of the band; 0 dB: nothing; above 0: the modes add more
//! than they explain). A fit whose overall residual is at or above [`POOR_FIT_DB`] explains
//! nothing and is refused by `trundle fit-object` (unless `--keep-poor-fit`) and by the
//! plugin's Load….

use crate::analysis::third_octave::{brick_wall_energies, centres_between_hz};

/// Overall residual (dB re the recording) at or above which a fit explains nothing.
pub const POOR_FIT_DB: f64 = 0.0;

/// One third-octave band of [`explained_by_band`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandExplained {
    /// Band centre (Hz).
    pub centre_hz: f64,
    /// The recording's energy in the band relative to its whole energy (dB).
    pub recording_db: f64,
    /// The residual's energy in the band relative to the recording's whole energy (dB).
    pub residual_db: f64,
    /// Residual ÷ recording in the band (dB): below 0 the modes explain part of it.
    pub explained_db: f64,
}

/// Whether a fit with this overall residual (dB) explains nothing (NaN counts as poor).
pub fn is_poor(residual_db: f64) -> bool {
    residual_db.is_nan() || residual_db >= POOR_FIT_DB
}

/// The message a poor fit is refused with (`what` names the recording).
pub fn poor_fit_message(what: &str, residual_db: f64) -> String {
    format!(
        "{what}: the fit explains nothing: its residual is {residual_db:+.1} dB re the recording (at or above {POOR_FIT_DB} dB: the modes add as much energy as they explain); not a resonant strike?"
    )
}

/// The bands of `recording` and `model` (the modes' resynthesis, as long), 20 Hz …
/// min(20 kHz, 0.45·f_s), that hold recording energy.
///
/// # Allocation
/// Allocates (an analysis).
pub fn explained_by_band(
    recording: &[f64],
    model: &[f64],
    sample_rate_hz: f64,
) -> Vec<BandExplained> {
    let fs = sample_rate_hz;
    let top = 20_000f64.min(0.45 * fs);
    let n = recording.len().min(model.len());
    let residual: Vec<f64> = recording[..n]
        .iter()
        .zip(&model[..n])
        .map(|(a, b)| a - b)
        .collect();
    let rec = brick_wall_energies(&recording[..n], fs, 20.0, top);
    let res = brick_wall_energies(&residual, fs, 20.0, top);
    let total = rec.iter().sum::<f64>().max(1e-300);
    let db = |v: f64| 10.0 * v.max(1e-30).log10();
    centres_between_hz(20.0, top)
        .iter()
        .zip(rec.iter().zip(&res))
        .filter(|(_, (&r, _))| r > 0.0)
        .map(|(&c, (&r, &e))| BandExplained {
            centre_hz: c,
            recording_db: db(r / total),
            residual_db: db(e / total),
            explained_db: db(e / r),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_band_the_model_matches_is_explained_and_one_it_misses_is_not() {
        let fs = 48_000.0;
        let tone = |f: f64| -> Vec<f64> {
            (0..24_000)
                .map(|i| {
                    let t = i as f64 / fs;
                    (-t / 0.1).exp() * (core::f64::consts::TAU * f * t).sin()
                })
                .collect()
        };
        let (a, b) = (tone(500.0), tone(4000.0));
        let x: Vec<f64> = a.iter().zip(&b).map(|(p, q)| p + q).collect();
        let bands = explained_by_band(&x, &a, fs);
        let at = |f: f64| {
            bands
                .iter()
                .min_by(|p, q| (p.centre_hz - f).abs().total_cmp(&(q.centre_hz - f).abs()))
                .unwrap()
                .explained_db
        };
        // 500 Hz is the model's (what is left there is the 4 kHz tone's skirt, ≈ 60 dB
        // down); 4 kHz is all residual (the 500 Hz skirt changes it by far less than 0.1 dB).
        assert!(at(500.0) < -40.0, "{bands:?}");
        assert!(at(4000.0).abs() < 0.1, "{bands:?}");
        assert!(is_poor(0.0) && is_poor(f64::NAN) && !is_poor(-0.1));
    }
}
