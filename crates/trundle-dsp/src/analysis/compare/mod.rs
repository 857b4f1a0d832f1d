//! How close is a sound to a recording, as a listener judges textures: four measures, each
//! with its limit (the judge of issue #25; `trundle compare`, and the loss `trundle match`
//! minimizes).
//!
//! | measure | what it hears | distance | limit |
//! |---|---|---|---|
//! | [`spectrum`] | colour: long-term third-octave levels | RMS of level differences | [`SPECTRUM_LIMIT_DB`] |
//! | [`modulation`] | rhythm and flutter: 0.5–64 Hz modulation of six band envelopes | RMS of dB differences | [`MODULATION_LIMIT_DB`] |
//! | [`statistics`] | texture: envelope spread, skewness, kurtosis, cross-band correlation (McDermott & Simoncelli 2011) | mean deviation in units of the recording's half-vs-half spread | [`TEXTURE_LIMIT`] |
//! | [`impulsiveness`] | clicks over hiss: waveform kurtosis and 100 ms crest factor | ratio; dB difference | ×/÷[`KURTOSIS_LIMIT_RATIO`], [`CREST_LIMIT_DB`] |
//!
//! Both sounds are analysed up to the lower of their Nyquist frequencies (and 20 kHz), so a
//! 22 kHz recording is compared with a 48 kHz render on what both hold. Everything is level-
//! independent: a candidate needs no gain matching. Stereo is compared as its mono mix (the
//! caller's).

mod compress;
pub mod envelopes;
pub mod furthest;
pub mod impulsiveness;
pub mod modulation;
pub mod noise;
pub mod spectrum;
pub mod statistics;

use envelopes::{band_envelopes, BandEnvelopes};
use modulation::{modulation_distance_db, modulation_spectrum, ModulationSpectrum};
use spectrum::{long_term_spectrum, spectrum_distance_db, LongTermSpectrum};
use statistics::{texture_distance, texture_stats, TextureStats};

/// Long-term spectrum limit (dB, RMS over third-octave bands).
pub const SPECTRUM_LIMIT_DB: f64 = 3.5;
/// Modulation spectrum limit (dB, RMS over envelope × modulation bands).
pub const MODULATION_LIMIT_DB: f64 = 3.5;
/// Texture statistics limit (mean deviation in half-vs-half units).
pub const TEXTURE_LIMIT: f64 = 1.0;
/// Waveform kurtosis limit: the candidate's within ×/÷ this of the recording's.
pub const KURTOSIS_LIMIT_RATIO: f64 = 2.0;
/// 100 ms crest factor limit (dB).
pub const CREST_LIMIT_DB: f64 = 3.0;
/// Highest frequency compared (Hz).
pub const TOP_HZ: f64 = 20_000.0;
/// Shortest sound compared (s): the halves of a recording need a few envelope periods.
pub const MIN_SECONDS: f64 = 0.5;

/// Everything the measures read of one sound, up to `top_hz`.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// Duration (s).
    pub duration_s: f64,
    /// Highest frequency analysed (Hz).
    pub top_hz: f64,
    /// Long-term third-octave spectrum.
    pub spectrum: LongTermSpectrum,
    /// Modulation spectrum of the band envelopes.
    pub modulation: ModulationSpectrum,
    /// Texture statistics of the band envelopes.
    pub stats: TextureStats,
    /// Units of each statistic: the expected half-vs-half spread ([`statistics::units`]).
    pub units: Vec<f64>,
    /// Waveform kurtosis.
    pub kurtosis: f64,
    /// Median 100 ms crest factor (dB).
    pub crest_db: f64,
}

/// Why two sounds cannot be compared.
#[derive(Clone, Debug, PartialEq)]
pub enum CompareError {
    /// Shorter than [`MIN_SECONDS`].
    TooShort {
        /// Which sound ("recording" or "candidate").
        which: &'static str,
        /// Its length (s).
        seconds: f64,
    },
    /// Sample rate not finite or under 8 kHz.
    SampleRate(f64),
    /// Non-finite samples or silence.
    NoSignal(&'static str),
}

impl core::fmt::Display for CompareError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CompareError::TooShort { which, seconds } => write!(
                f,
                "the {which} is {seconds:.2} s long; comparing needs at least {MIN_SECONDS} s"
            ),
            CompareError::SampleRate(r) => {
                write!(f, "sample rate {r} Hz is not usable (8 kHz or more)")
            }
            CompareError::NoSignal(which) => {
                write!(f, "the {which} is silent or holds non-finite samples")
            }
        }
    }
}

impl std::error::Error for CompareError {}

/// The profile of `x` at `sample_rate_hz` analysed up to `top_hz`.
pub fn profile(
    x: &[f64],
    sample_rate_hz: f64,
    top_hz: f64,
    which: &'static str,
) -> Result<Profile, CompareError> {
    if !(sample_rate_hz.is_finite() && sample_rate_hz >= 8000.0) {
        return Err(CompareError::SampleRate(sample_rate_hz));
    }
    let seconds = x.len() as f64 / sample_rate_hz;
    if seconds < MIN_SECONDS {
        return Err(CompareError::TooShort { which, seconds });
    }
    if x.iter().any(|v| !v.is_finite()) || x.iter().all(|&v| v == 0.0) {
        return Err(CompareError::NoSignal(which));
    }
    let top_hz = top_hz.min(TOP_HZ).min(0.5 * sample_rate_hz);
    let env: BandEnvelopes = band_envelopes(x, sample_rate_hz, top_hz);
    let units = statistics::units(&env);
    Ok(Profile {
        duration_s: seconds,
        top_hz,
        spectrum: long_term_spectrum(x, sample_rate_hz, top_hz),
        modulation: modulation_spectrum(&env),
        stats: texture_stats(&env),
        units,
        kurtosis: impulsiveness::kurtosis(x),
        crest_db: impulsiveness::crest_factor_db(x, sample_rate_hz),
    })
}

/// One measure's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Verdict {
    /// The distance (or, for kurtosis, the ratio candidate ÷ recording).
    pub value: f64,
    /// Its limit.
    pub limit: f64,
    /// Within the limit.
    pub passed: bool,
}

/// A candidate judged against a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The recording's profile.
    pub reference: Profile,
    /// The candidate's profile.
    pub candidate: Profile,
    /// Long-term spectrum (dB RMS).
    pub spectrum: Verdict,
    /// Per-band spectrum differences, candidate − recording (dB; `None`: not compared).
    pub spectrum_diff_db: Vec<Option<f64>>,
    /// Modulation spectrum (dB RMS).
    pub modulation: Verdict,
    /// Per-cell modulation differences (dB).
    pub modulation_diff_db: ModulationSpectrum,
    /// Texture statistics (mean deviation, half-vs-half units).
    pub texture: Verdict,
    /// Each statistic's deviation in its unit, in [`TextureStats::values`]' order.
    pub texture_dev: Vec<f64>,
    /// Waveform kurtosis ratio candidate ÷ recording.
    pub kurtosis: Verdict,
    /// Crest factor difference candidate − recording (dB).
    pub crest: Verdict,
}

impl Comparison {
    /// Impulsiveness passes when both kurtosis and crest factor do.
    pub fn impulsiveness_passed(&self) -> bool {
        self.kurtosis.passed && self.crest.passed
    }

    /// All four measures pass.
    pub fn passed(&self) -> bool {
        self.spectrum.passed
            && self.modulation.passed
            && self.texture.passed
            && self.impulsiveness_passed()
    }

    /// How many of the four measures pass.
    pub fn measures_passed(&self) -> usize {
        [
            self.spectrum.passed,
            self.modulation.passed,
            self.texture.passed,
            self.impulsiveness_passed(),
        ]
        .iter()
        .filter(|&&p| p)
        .count()
    }

    /// One number for a search to minimize: each measure's distance over its limit (kurtosis
    /// as |log ratio| over log of its limit), the worst of them and their mean blended, so
    /// that a candidate passes all four exactly when the worst is ≤ 1.
    pub fn loss(&self) -> f64 {
        let parts = [
            self.spectrum.value / self.spectrum.limit,
            self.modulation.value / self.modulation.limit,
            self.texture.value / self.texture.limit,
            self.kurtosis.value.ln().abs() / self.kurtosis.limit.ln(),
            self.crest.value.abs() / self.crest.limit,
        ];
        let worst = parts.iter().cloned().fold(0.0, f64::max);
        let mean = parts.iter().sum::<f64>() / parts.len() as f64;
        0.5 * (worst + mean)
    }
}

/// Judge `candidate` against the recording `reference` (mono samples and their rates).
pub fn compare(
    reference: &[f64],
    reference_rate_hz: f64,
    candidate: &[f64],
    candidate_rate_hz: f64,
) -> Result<Comparison, CompareError> {
    let top = (0.5 * reference_rate_hz).min(0.5 * candidate_rate_hz);
    let r = profile(reference, reference_rate_hz, top, "recording")?;
    let c = profile(candidate, candidate_rate_hz, top, "candidate")?;
    Ok(compare_profiles(r, c))
}

/// Judge a candidate's profile against a recording's, both analysed to the same `top_hz`
/// (for a search that profiles the recording once).
pub fn compare_profiles(reference: Profile, candidate: Profile) -> Comparison {
    let (spectrum_diff_db, s) = spectrum_distance_db(&reference.spectrum, &candidate.spectrum);
    let (modulation_diff_db, m) =
        modulation_distance_db(&reference.modulation, &candidate.modulation);
    let (texture_dev, t) = texture_distance(&reference.stats, &candidate.stats, &reference.units);
    let k = candidate.kurtosis / reference.kurtosis.max(1e-12);
    let c = candidate.crest_db - reference.crest_db;
    let verdict = |value: f64, limit: f64, passed: bool| Verdict {
        value,
        limit,
        passed,
    };
    Comparison {
        spectrum: verdict(s, SPECTRUM_LIMIT_DB, s <= SPECTRUM_LIMIT_DB),
        spectrum_diff_db,
        modulation: verdict(m, MODULATION_LIMIT_DB, m <= MODULATION_LIMIT_DB),
        modulation_diff_db,
        texture: verdict(t, TEXTURE_LIMIT, t <= TEXTURE_LIMIT),
        texture_dev,
        kurtosis: verdict(
            k,
            KURTOSIS_LIMIT_RATIO,
            (1.0 / KURTOSIS_LIMIT_RATIO..=KURTOSIS_LIMIT_RATIO).contains(&k),
        ),
        crest: verdict(c, CREST_LIMIT_DB, c.abs() <= CREST_LIMIT_DB),
        reference,
        candidate,
    }
}
