//! Where a comparison is furthest off, beyond the four distances: the modulation cell and
//! the texture statistic that differ most, each with the envelope band(s) it belongs to
//! (`trundle compare`'s closing lines, docs/guide/compare.md).
//!
//! A band's envelope statistics are read on the envelope normalized by its own mean
//! (McDermott & Simoncelli 2011), so a band 40 dB under the loudest counts as much in the
//! texture distance as the loudest: the texture gap says how loud its bands are in the
//! recording, so a user can tell a failing sound from a failing murmur beside it.

use super::envelopes::envelope_edges_hz;
use super::modulation::MODULATION_CENTRES_HZ;
use super::Comparison;

/// The kinds of texture statistic, in the order of
/// [`super::statistics::TextureStats::values`].
pub const STATISTIC_KINDS: [&str; 4] = ["spread", "skewness", "kurtosis", "correlation"];

/// The modulation cell furthest off.
#[derive(Clone, Debug, PartialEq)]
pub struct ModulationGap {
    /// The envelope band (low, high edge, Hz).
    pub band_hz: (f64, f64),
    /// Centre of the modulation band (Hz).
    pub rate_hz: f64,
    /// Candidate − recording (dB).
    pub diff_db: f64,
}

/// The texture statistic furthest off.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureGap {
    /// Which statistic (one of [`STATISTIC_KINDS`]).
    pub kind: &'static str,
    /// The band it reads (low, high edge, Hz); two for a correlation.
    pub bands_hz: Vec<(f64, f64)>,
    /// Each of those bands' level in the recording (dB re its loudest envelope band).
    pub levels_db: Vec<f64>,
    /// The statistic's value in the recording.
    pub recording: f64,
    /// Its value in the candidate.
    pub candidate: f64,
    /// Candidate − recording in units of the recording's half-vs-half spread (the texture
    /// distance's unit).
    pub deviation_units: f64,
}

impl Comparison {
    /// The envelope bands the statistics were read on (low, high edge, Hz).
    fn envelope_bands_hz(&self) -> Vec<(f64, f64)> {
        let mut edges = envelope_edges_hz(self.reference.top_hz);
        edges.truncate(self.reference.stats.spread.len());
        edges
    }

    /// The level of each of `bands` in the recording's long-term spectrum (the power of the
    /// third-octave bands whose centres it holds), dB re the loudest.
    fn band_levels_db(&self, bands: &[(f64, f64)]) -> Vec<f64> {
        let s = &self.reference.spectrum;
        let power: Vec<f64> = bands
            .iter()
            .map(|&(lo, hi)| {
                s.centres_hz
                    .iter()
                    .zip(&s.levels_db)
                    .filter(|(&c, _)| c >= lo && c < hi)
                    .map(|(_, &l)| 10f64.powf(l / 10.0))
                    .sum::<f64>()
            })
            .collect();
        let top = power.iter().cloned().fold(0.0, f64::max);
        power
            .iter()
            .map(|&p| 10.0 * (p.max(1e-30) / top.max(1e-30)).log10())
            .collect()
    }

    /// The modulation cell whose candidate − recording difference is largest in size (`None`
    /// when no cell is defined in both).
    pub fn furthest_modulation(&self) -> Option<ModulationGap> {
        let bands = self.envelope_bands_hz();
        self.modulation_diff_db
            .iter()
            .zip(&bands)
            .flat_map(|(row, &band_hz)| {
                row.iter()
                    .zip(MODULATION_CENTRES_HZ)
                    .filter_map(move |(d, rate_hz)| {
                        d.map(|diff_db| ModulationGap {
                            band_hz,
                            rate_hz,
                            diff_db,
                        })
                    })
            })
            .max_by(|a, b| a.diff_db.abs().total_cmp(&b.diff_db.abs()))
    }

    /// The texture statistic whose deviation is largest in size (`None` with no statistic).
    pub fn furthest_texture(&self) -> Option<TextureGap> {
        let (i, &deviation_units) = self
            .texture_dev
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
        let bands = self.envelope_bands_hz();
        let levels = self.band_levels_db(&bands);
        let r = self.reference.stats.values();
        let c = self.candidate.stats.values();
        // `values()` tags each statistic with its kind; its place among its kind's picks the
        // band (a moment) or the pair of bands (a correlation, in (0,1), (0,2) … order).
        let (kind, recording) = *r.get(i)?;
        let place = i - r.iter().position(|v| v.0 == kind)?;
        let which = if STATISTIC_KINDS[kind] == "correlation" {
            let nb = bands.len();
            let (j, k) = (0..nb)
                .flat_map(|j| (j + 1..nb).map(move |k| (j, k)))
                .nth(place)?;
            vec![j, k]
        } else {
            vec![place]
        };
        Some(TextureGap {
            kind: STATISTIC_KINDS[kind],
            bands_hz: which
                .iter()
                .filter_map(|&b| bands.get(b).copied())
                .collect(),
            levels_db: which
                .iter()
                .filter_map(|&b| levels.get(b).copied())
                .collect(),
            recording,
            candidate: c.get(i)?.1,
            deviation_units,
        })
    }
}
