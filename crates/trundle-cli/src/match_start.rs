//! Where `trundle match` starts: first estimates of the texture controls read off the
//! recording's profile (the analysis `trundle compare` makes once), so that the search
//! begins near the recording's slow textures instead of at a steady, dull default.
//!
//! ```text
//! profile ─► modulation spectrum: a peak at 0.5–8 Hz all bands share ─► strokes at that rate
//!         ─► 0.5–1 Hz modulation 4 dB or more over the 4 Hz band         ─► slow wander (surges)
//!         ─► cross-band envelope correlation high, no peak, no surges   ─► bumpiness
//!         ─► envelope spread (σ/μ) over a steady noise's                ─► wander
//!         ─► waveform kurtosis over a Gaussian's                        ─► crackle
//!         ─► always: the contact's high band (micro), so a faster ball is brighter and the
//!            model's own spectrum, not the body EQ, carries the brightness
//! ```
//!
//! Each rule reads a statistic the corresponding control was made to move (docs/MODEL.md,
//! "Textures real contact has": strokes put a modulation peak at their rate, bumps raise
//! the cross-band correlation, wander the envelopes' spread and skew, crackle the kurtosis);
//! the thresholds are where a steady Trundle roll or rub sits (its spread 0.16, correlation
//! 0.29, kurtosis 3.6), so a recording no more textured than that starts without the control.
//! Strokes move every band together and spread the envelopes too, so a stroked recording's
//! strokes are read at least as deep as its cross-band correlation says, and the spread they
//! make is not taken for wander (as surges' correlation is not taken for bumps).
//! The search moves every one of them afterwards; these only choose where it begins.

use trundle_dsp::analysis::compare::modulation::MODULATION_CENTRES_HZ;
use trundle_dsp::analysis::compare::Profile;
use trundle_dsp::analysis::impacts::autocorrelation;
use trundle_dsp::object::material::Material;
use trundle_dsp::{ParamId, Params};

/// Micro-roughness every start has: half way, a high band that grows with speed.
pub const START_MICRO: f64 = 0.5;
/// A modulation peak this far (dB) over its neighbours, in the mean over the bands, reads as
/// strokes.
pub const STROKE_PEAK_DB: f64 = 2.0;
/// Mean cross-band envelope correlation over which bumps start (a steady roll's is 0.29).
pub const BUMPY_CORRELATION: f64 = 0.4;
/// Mean envelope spread σ/μ of a steady roll (docs/MODEL.md, wander): wander starts above.
pub const STEADY_SPREAD: f64 = 0.16;
/// Waveform kurtosis over which crackle starts (real rubs 3.6–4.7, a stylus 7.6).
pub const CRACKLY_KURTOSIS: f64 = 5.0;
/// How far (dB) the slowest modulation (the larger of the 0.5 and 1 Hz bands, mean over the
/// bands) must stand over the 4 Hz band to read as surges: every band swelling together over
/// seconds (passing traffic +8.6 dB, a cart on a dirt track +13.2; a steady noise's
/// envelope falls towards slow rates, and the other ten clips of the texture corpus sit at
/// −12.9 … +0.4 dB).
pub const SURGE_EXCESS_DB: f64 = 4.0;
/// The surges' rate is the fastest modulation band still within this many dB of the slowest's
/// power.
pub const SURGE_FALL_DB: f64 = 6.0;
/// Mean cross-band envelope correlation of a rub without strokes and with strokes at depth 1
/// (4 Hz, 6 s, measured): strokes move every band together, so a recording whose bands move
/// together more than that has its strokes read deeper than its modulation peak alone says.
pub const STROKE_CORRELATION: [f64; 2] = [0.34, 0.52];
/// Mean envelope spread σ/μ strokes at depth 1 add to a rub (0.167 → 0.230, the same
/// measurement): spread the strokes explain is not the wander's.
pub const STROKE_SPREAD: f64 = 0.063;

/// The slowest and fastest stroke rates the envelope's period is read at (Hz): hands saw,
/// file and scrub at 0.5–4 strokes per second; faster level swings of a bowed string are its
/// vibrato (5–8 Hz on the corpus's cello and viola), not strokes.
pub const STROKE_PERIOD_RATES_HZ: [f64; 2] = [0.5, 4.0];
/// Autocorrelation of the log envelope at one stroke period over which the recording reads
/// as stroked: the share of its level's variance that comes back every stroke. The corpus's
/// stroked clips read 0.69 (a blade held to a grindstone) and 0.77 (a hand saw); the others
/// stay under 0.4 at 0.5–4 Hz.
pub const STROKE_PERIOD_STRENGTH: f64 = 0.5;
/// The envelope's frames (s): 10 ms, fine enough for a 4 Hz stroke's rise.
const PERIOD_FRAME_S: f64 = 0.01;
/// The log envelope is floored this far (dB) under its 95th percentile, so silences between
/// strokes count as deep, not as the noise floor's own wobble.
const PERIOD_FLOOR_DB: f64 = 50.0;
/// A peak of the autocorrelation counts only if it stands this far over the lowest value at
/// shorter lags (a slow drift's smooth decline has no such peak).
const PERIOD_PROMINENCE: f64 = 0.15;

/// Every other stroke must be at least this much (dB) louder to read as push and pull.
const ALTERNATION_MIN_DB: f64 = 1.0;

/// A quiet frame lies this far (dB) under the envelope's 95th percentile: the body is off.
const LIFT_QUIET_DB: f64 = 25.0;
/// A stroked recording whose quiet frames make up more than this share has its strokes read
/// as lifted for that share (the corpus's blade on a grindstone: 0.36, the hand saw, which
/// never leaves the wood: 0.06).
const LIFT_QUIET_SHARE: f64 = 0.1;

/// A recording's stroke period ([`stroke_period`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokePeriod {
    /// Strokes per second.
    pub rate_hz: f64,
    /// Normalized autocorrelation of the log envelope at one period (a push and its
    /// return when they alternate).
    pub strength: f64,
    /// Push and pull: how much louder (dB) every other stroke is, when the period read is a
    /// push and a lighter return ([`alternation_db`]); `rate_hz` is then the strokes' rate,
    /// twice the period's.
    pub alternation_db: Option<f64>,
    /// Share of the envelope's 10 ms frames [`LIFT_QUIET_DB`] or more under its 95th
    /// percentile.
    pub quiet_share: f64,
    /// What is heard in those quiet frames: their median level re the recording's mean
    /// power (dB) and the frequency under which half their power lies (Hz), `None` without
    /// quiet frames.
    pub floor: Option<(f64, f64)>,
}

/// The floor heard in the quiet frames of `x` (`hop` samples each, their levels
/// `levels_db`; quiet: under `under_db`): of those, the quieter half (the rest are the
/// strokes' tails), their mean power re that of `x` (dB) and the frequency under which half
/// of their power lies (Hz). On the blade on a grindstone: −29.9 dB and 253 Hz (all the
/// quiet frames: −25.2 dB and 3.8 kHz, the tails' hiss).
fn quiet_floor(
    x: &[f64],
    hop: usize,
    levels_db: &[f64],
    under_db: f64,
    fs: f64,
) -> Option<(f64, f64)> {
    let mut quiet: Vec<f64> = levels_db
        .iter()
        .copied()
        .filter(|&l| l < under_db)
        .collect();
    if quiet.is_empty() {
        return None;
    }
    quiet.sort_by(f64::total_cmp);
    let median_db = quiet[quiet.len() / 2];
    let samples: Vec<f64> = x
        .chunks_exact(hop)
        .zip(levels_db)
        .filter(|(_, &l)| l <= median_db)
        .flat_map(|(c, _)| c.iter().copied())
        .collect();
    let power = |v: &[f64]| v.iter().map(|s| s * s).sum::<f64>() / v.len().max(1) as f64;
    let re_db = 10.0 * (power(&samples).max(1e-30) / power(x).max(1e-30)).log10();
    let psd = crate::spectrum::Psd::welch(&samples, fs);
    let total: f64 = psd.density.iter().skip(1).sum();
    let mut acc = 0.0;
    let mut corner_hz = 0.5 * fs;
    for (k, d) in psd.density.iter().enumerate().skip(1) {
        acc += d;
        if acc >= 0.5 * total {
            corner_hz = k as f64 * psd.df_hz;
            break;
        }
    }
    Some((re_db, corner_hz))
}

/// The stroke period of a recording `x` at `sample_rate_hz`: its rate and strength, the
/// normalized autocorrelation of its broadband log envelope at that period, when the
/// autocorrelation has a prominent peak at a rate of [`STROKE_PERIOD_RATES_HZ`]. Of peaks
/// within 80 % of the highest, the shortest period (a stroke, not two or three).
///
/// The modulation spectrum's octave bands place a stroke rate only to an octave, and a
/// stroke that lifts off (a blade on a grindstone: 40 dB on/off, a sharp start at 2.6 Hz)
/// spreads its power over the octaves above, so no band stands over its neighbours; the
/// period is exact and reads both.
pub fn stroke_period(x: &[f64], sample_rate_hz: f64) -> Option<StrokePeriod> {
    let hop = (PERIOD_FRAME_S * sample_rate_hz).round() as usize;
    if hop == 0 || !sample_rate_hz.is_finite() {
        return None;
    }
    let frame_s = hop as f64 / sample_rate_hz;
    let mut e: Vec<f64> = x
        .chunks_exact(hop)
        .map(|c| 10.0 * (c.iter().map(|v| v * v).sum::<f64>() / hop as f64 + 1e-20).log10())
        .collect();
    let m = e.len();
    let lo = (1.0 / (STROKE_PERIOD_RATES_HZ[1] * frame_s)).floor() as usize;
    let hi = ((1.0 / (STROKE_PERIOD_RATES_HZ[0] * frame_s)).ceil() as usize).min(m / 3);
    if hi <= lo + 1 {
        return None;
    }
    let mut sorted = e.clone();
    sorted.sort_by(f64::total_cmp);
    let top = sorted[(0.95 * (m - 1) as f64) as usize];
    let quiet_share = sorted.partition_point(|&v| v < top - LIFT_QUIET_DB) as f64 / m as f64;
    let heard = quiet_floor(x, hop, &e, top - LIFT_QUIET_DB, sample_rate_hz);
    let floor = top - PERIOD_FLOOR_DB;
    for v in &mut e {
        *v = v.max(floor);
    }
    // A constant envelope correlates to 0 at every lag: no peak, no period.
    let r = autocorrelation(&e, hi + 1);
    let mut lowest = f64::INFINITY;
    let mut peaks = Vec::new();
    for k in 1..=hi {
        lowest = lowest.min(r[k - 1]);
        if k >= lo && r[k] > r[k - 1] && r[k] >= r[k + 1] && r[k] - lowest > PERIOD_PROMINENCE {
            peaks.push((k, r[k]));
        }
    }
    let best = peaks.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    peaks.iter().find(|p| p.1 >= 0.8 * best).map(|&(k, v)| {
        let mean = e.iter().sum::<f64>() / m as f64;
        let var_db2 = e.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / m as f64;
        let alternation_db = alternation_db(&r, k, var_db2);
        let strokes = if alternation_db.is_some() { 2.0 } else { 1.0 };
        StrokePeriod {
            rate_hz: strokes / (k as f64 * frame_s),
            strength: v,
            alternation_db,
            quiet_share,
            floor: heard,
        }
    })
}

/// Push and pull read off the log envelope's autocorrelation `r` (its variance `var_db2`,
/// dB²) when its period is `k` frames: a peak at about half the period (0.4–0.6 of it)
/// under the period's own says the period is two strokes, the second lighter. Model the
/// envelope as a stroke shape repeating every half period (variance σ²) plus a square wave
/// of ±a dB every other stroke: r(k/2) = (σ² − a²)/V and r(k) = (σ² + a²)/V, V the
/// variance, so a² = (r(k) − r(k/2))·V/2 and the push is 2a dB over the return. `None`
/// without such a half-period peak (one-way strokes, lifted strokes) or where the two
/// strokes are alike (2a under [`ALTERNATION_MIN_DB`]). The corpus's hand saw:
/// r 0.71 at its 0.57 s period and 0.36 at half of it. A return far lighter than the push
/// (under about a third) correlates negatively with it, r(k/2) is a trough, and the period
/// reads as one stroke (the search's `stroke_return` can still find it).
fn alternation_db(r: &[f64], k: usize, var_db2: f64) -> Option<f64> {
    let lo = ((0.4 * k as f64).round() as usize).max(1);
    let hi = ((0.6 * k as f64).round() as usize).min(r.len().saturating_sub(2));
    let half = (lo..=hi)
        .filter(|&j| r[j] > r[j - 1] && r[j] >= r[j + 1] && r[j] > 0.0)
        .max_by(|&a, &b| r[a].total_cmp(&r[b]))?;
    let contrast_db = 2.0 * ((r[k] - r[half]).max(0.0) * var_db2 / 2.0).sqrt();
    (contrast_db >= ALTERNATION_MIN_DB).then_some(contrast_db)
}

/// What the profile suggests, each as a value of its control.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Estimate {
    /// Strokes: depth and rate (Hz), when the modulation spectrum has a peak.
    pub strokes: Option<(f64, f64)>,
    /// The share of each stroke the body is lifted off, when the recording falls quiet
    /// between strokes.
    pub stroke_lift: Option<f64>,
    /// The return stroke's pressure re the push's, when every other stroke is lighter.
    pub stroke_return: Option<f64>,
    /// The noise floor heard between lifted strokes: its level re the recording's mean power
    /// (dB) and its corner (Hz) ([`Estimate::with_floor`]).
    pub floor: Option<(f64, f64)>,
    /// Bumpiness, when every band moves together without a stroke peak.
    pub bumpiness: Option<f64>,
    /// Wander, when the envelopes spread more than a steady roll's (or the recording surges).
    pub wander: Option<f64>,
    /// The wander's rate (Hz), when the recording surges (its slow modulation stands over its
    /// 4 Hz band).
    pub wander_rate_hz: Option<f64>,
    /// Crackle, when the waveform is heavy-tailed.
    pub crackle: Option<f64>,
}

/// Mean over the envelope bands of each modulation band's power (dB), `None` where no band
/// holds it.
fn mean_modulation(p: &Profile) -> Vec<Option<f64>> {
    (0..MODULATION_CENTRES_HZ.len())
        .map(|k| {
            let v: Vec<f64> = p.modulation.iter().filter_map(|b| b[k]).collect();
            (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
        })
        .collect()
}

fn mean(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// The estimate of `p` (a recording's profile) and `period`, its [`stroke_period`].
pub fn estimate(p: &Profile, period: Option<StrokePeriod>) -> Estimate {
    let m = mean_modulation(p);
    // A stroke peak: a modulation band at 0.5–8 Hz over both its neighbours.
    let mut strokes = None;
    let mut best = STROKE_PEAK_DB;
    for k in 0..m.len() {
        if MODULATION_CENTRES_HZ[k] > 8.0 {
            break;
        }
        let Some(here) = m[k] else { continue };
        let around: Vec<f64> = [k.checked_sub(1), Some(k + 1)]
            .iter()
            .flatten()
            .filter_map(|&j| m.get(j).copied().flatten())
            .collect();
        if around.is_empty() {
            continue;
        }
        let over = here - around.iter().cloned().fold(f64::MIN, f64::max);
        if over > best {
            best = over;
            // Deeper strokes for a sharper peak (9 dB over the neighbours at depth 1,
            // docs/MODEL.md).
            strokes = Some(((0.3 + over / 12.0).min(1.0), MODULATION_CENTRES_HZ[k]));
        }
    }
    // A strong stroke period: strokes at its exact rate, at least as deep as the share of
    // the level that comes back every stroke. Quiet between strokes: the body is lifted off
    // for that share of each, at full depth (at depth d the lifted body still presses
    // 1 − d), and what is heard then is the floor (a room, the machine).
    let mut stroke_lift = None;
    let mut stroke_return = None;
    let mut floor = None;
    if let Some(period) = period.filter(|p| p.strength >= STROKE_PERIOD_STRENGTH) {
        // The level goes as the pressure: the return's is the push's less the contrast.
        stroke_return = period.alternation_db.map(|db| 10f64.powf(-db / 20.0));
        stroke_lift = (period.quiet_share > LIFT_QUIET_SHARE).then_some(period.quiet_share);
        floor = period.floor.filter(|_| stroke_lift.is_some());
        let depth = if stroke_lift.is_some() {
            1.0
        } else {
            strokes.map_or(0.0, |s| s.0).max(period.strength.min(1.0))
        };
        strokes = Some((depth, period.rate_hz));
    }
    // Surges: the slowest modulation over the 4 Hz band's; their rate where it has fallen.
    let slowest = m[..2].iter().flatten().cloned().fold(f64::NAN, f64::max);
    let at_4_hz = MODULATION_CENTRES_HZ
        .iter()
        .position(|&c| c == 4.0)
        .and_then(|k| m[k]);
    let surges = match at_4_hz {
        Some(m4) if slowest - m4 >= SURGE_EXCESS_DB => {
            let rate_hz = MODULATION_CENTRES_HZ
                .iter()
                .zip(&m)
                .take_while(|(_, v)| v.is_none_or(|v| slowest - v < SURGE_FALL_DB))
                .last()
                .map_or(1.0, |(&c, _)| c);
            // Deeper for a larger excess: by hand, passing traffic (+8.6 dB) came closest at
            // wander 0.7–1 with a rate of 0.5–1 Hz.
            Some(((0.4 + (slowest - m4) / 20.0).min(1.0), rate_hz))
        }
        _ => None,
    };
    let correlation = mean(&p.stats.correlation).unwrap_or(0.0);
    // Strokes move every band together: as deep as the peak says, or as the bands'
    // correlation does, whichever is more.
    let strokes = strokes.map(|(depth, rate_hz)| {
        let [c0, c1] = STROKE_CORRELATION;
        (
            depth.max(((correlation - c0) / (c1 - c0)).clamp(0.0, 1.0)),
            rate_hz,
        )
    });
    // Surges move every band together too: the correlation is theirs, not knocks'.
    let bumpiness = (strokes.is_none() && surges.is_none() && correlation > BUMPY_CORRELATION)
        .then(|| (0.3 + (correlation - BUMPY_CORRELATION)).min(1.0));
    // The spread the strokes explain is theirs, not the wander's.
    let spread =
        mean(&p.stats.spread).unwrap_or(0.0) - strokes.map_or(0.0, |s| s.0 * STROKE_SPREAD);
    // Spread 0.16 → 0.29 from wander 0 to 1 on a roll (docs/MODEL.md).
    // A body lifted off between strokes spreads the envelopes far more than any hand's
    // wander: none is read off them then.
    let spread_wander = (stroke_lift.is_none() && spread > STEADY_SPREAD + 0.03)
        .then(|| ((spread - STEADY_SPREAD) / 0.13).clamp(0.2, 1.0));
    let wander = match (spread_wander, surges) {
        (Some(a), Some((b, _))) => Some(a.max(b)),
        (a, b) => a.or(b.map(|s| s.0)),
    };
    let wander_rate_hz = surges.map(|s| s.1);
    // Sound lifted off between strokes is heavy-tailed by its on and off alone (gated on
    // for a share q of the time: q⁻¹ times the kurtosis, and more for the strokes' rise and
    // fall): the lift's, not crackle's, so none is read then.
    let crackle = (stroke_lift.is_none() && p.kurtosis > CRACKLY_KURTOSIS)
        .then(|| (0.2 + 0.1 * (p.kurtosis - CRACKLY_KURTOSIS)).min(1.0));
    Estimate {
        strokes,
        stroke_lift,
        stroke_return,
        floor,
        bumpiness,
        wander,
        wander_rate_hz,
        crackle,
    }
}

impl Estimate {
    /// Does the estimate set any texture control?
    pub fn is_empty(&self) -> bool {
        self.strokes.is_none()
            && self.stroke_lift.is_none()
            && self.bumpiness.is_none()
            && self.wander.is_none()
            && self.wander_rate_hz.is_none()
            && self.crackle.is_none()
    }

    /// `p` with the estimate's controls set.
    pub fn apply(&self, p: &Params) -> Params {
        let mut q = *p;
        if let Some((depth, rate_hz)) = self.strokes {
            q.set_clamped(ParamId::Strokes, depth);
            q.set_clamped(ParamId::StrokeRateHz, rate_hz);
        }
        if let (Some(l), Some((_, rate_hz))) = (self.stroke_lift, self.strokes) {
            q.set_clamped(ParamId::StrokeLift, l);
            // The recording's heavy tail is the lift's: no clicks of grit or crackle on top
            // (on the blade on a grindstone's swept roll they took the kurtosis to ×6–8).
            q.set_clamped(ParamId::Crackle, 0.0);
            q.set_clamped(ParamId::Grit, 0.0);
            // The object's ring must die within the lift, as the recording does: its 1 kHz
            // decay no longer than takes LIFT_QUIET_DB within the gap (8.69 dB per time
            // constant).
            let material =
                Material::from_disk(q.get(ParamId::MaterialX), q.get(ParamId::MaterialY));
            let tau_s = material.decay_s(1000.0, 1.0);
            let gap_s = l / rate_hz;
            let most = gap_s * 8.69 / LIFT_QUIET_DB / tau_s;
            q.set_clamped(ParamId::Decay, q.get(ParamId::Decay).min(most));
        }
        if let (Some(g), Some((depth, _))) = (self.stroke_return, self.strokes) {
            // At depth d the return presses 1 − d·(1 − return): the share that gives g.
            q.set_clamped(ParamId::StrokeReturn, 1.0 - (1.0 - g) / depth.max(1e-3));
        }
        if let Some(b) = self.bumpiness {
            q.set_clamped(ParamId::Bumpiness, b);
        }
        if let Some(w) = self.wander {
            q.set_clamped(ParamId::Wander, w);
        }
        if let Some(r) = self.wander_rate_hz {
            q.set_clamped(ParamId::WanderRateHz, r);
        }
        if let Some(c) = self.crackle {
            q.set_clamped(ParamId::Crackle, c);
        }
        q
    }

    /// `p` with the floor heard between the strokes, when the estimate has one, at its level
    /// under `sound_db` (the mean power in dB of `p`'s mono render without it): `floor_db`
    /// is per channel, and the mono render (L + R)/2 of the two independent channels is
    /// 3 dB under either. The corner is the quiet frames' median-power frequency (a one-pole
    /// low-pass's half power lies under its corner).
    pub fn with_floor(&self, p: &Params, sound_db: f64) -> Params {
        let mut q = *p;
        if let Some((re_db, corner_hz)) = self.floor {
            q.set_clamped(ParamId::FloorDb, sound_db + re_db + 10.0 * 2f64.log10());
            q.set_clamped(ParamId::FloorHz, corner_hz);
        }
        q
    }

    /// One line for the report.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if let Some((d, r)) = self.strokes {
            parts.push(format!("strokes {d:.2} at {r:.2} Hz"));
        }
        if let Some(l) = self.stroke_lift {
            parts.push(format!("lifted {:.0} % of each stroke", 100.0 * l));
        }
        if let Some(g) = self.stroke_return {
            parts.push(format!("returns at {:.0} % of the push", 100.0 * g));
        }
        if let Some((db, hz)) = self.floor {
            parts.push(format!("a floor {db:.0} dB under, to {hz:.0} Hz"));
        }
        if let Some(b) = self.bumpiness {
            parts.push(format!("bumpiness {b:.2}"));
        }
        match (self.wander, self.wander_rate_hz) {
            (Some(w), Some(r)) => parts.push(format!("wander {w:.2} up to {r} Hz (surges)")),
            (Some(w), None) => parts.push(format!("wander {w:.2}")),
            _ => {}
        }
        if let Some(c) = self.crackle {
            parts.push(format!("crackle {c:.2}"));
        }
        if parts.is_empty() {
            "steady".into()
        } else {
            parts.join(", ")
        }
    }
}

/// The starts screened: every restart's parameters with the high band, and again with the
/// estimate's textures when it has any; then the same without the high band.
///
/// Without it too, because the high band is a texture of its own, not only brightness: on a
/// render of the default preset (micro 0) as the recording, its restart with micro 0.5 is
/// 14.5 dB off in spectrum, 4.1 dB in modulation and 1.06 in texture where micro 0 gives
/// 1.7 dB, 2.3 dB and 0.75, and the search (which moves micro by at most 0.3 in a sweep) did
/// not come back from 0.5 to 0 within 240 candidates.
pub fn starts(restarts: &[Params], e: &Estimate) -> Vec<Params> {
    let mut out = Vec::with_capacity(4 * restarts.len());
    for micro in [START_MICRO, 0.0] {
        for p in restarts {
            let mut q = *p;
            q.set_clamped(ParamId::Micro, micro);
            if !e.is_empty() {
                out.push(e.apply(&q));
            }
            out.push(q);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::analysis::compare::profile;

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                // Sum of four uniforms: near-Gaussian, enough for envelopes.
                (0..4)
                    .map(|_| trundle_dsp::block::splitmix_uniform(&mut s) - 0.5)
                    .sum::<f64>()
            })
            .collect()
    }

    /// Steady noise starts steady; noise swelling at 2 Hz in every band reads as strokes at
    /// 2 Hz, at full depth (every band moves together) and with no wander (the spread is the
    /// strokes').
    #[test]
    fn strokes_are_read_off_a_modulation_peak() {
        let fs = 16_000.0;
        let x = noise(4 * 16_000, 3);
        let steady = estimate(
            &profile(&x, fs, 8000.0, "recording").unwrap(),
            stroke_period(&x, fs),
        );
        assert!(steady.strokes.is_none(), "{steady:?}");
        assert!(steady.crackle.is_none(), "{steady:?}");
        let swelling: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| v * (core::f64::consts::TAU * 1.0 * i as f64 / fs).sin().abs())
            .collect();
        let e = estimate(
            &profile(&swelling, fs, 8000.0, "recording").unwrap(),
            stroke_period(&swelling, fs),
        );
        let (depth, rate) = e.strokes.expect("a stroke peak");
        assert_eq!(rate, 2.0, "{e:?}");
        // Every band swells at once (mean correlation past a rub's at depth 1): full depth,
        // whatever the peak's height alone would read.
        assert_eq!(depth, 1.0, "{e:?}");
        // Its envelopes spread 0.23 (σ/μ, the bands' mean), what strokes at depth 1 make on
        // a rub: the strokes', not a wandering hand's (the spread alone read wander 0.53).
        assert!(e.wander.is_none(), "{e:?}");
    }

    /// Strokes that lift off (noise on for 65 % of each 2.6 Hz stroke, starting sharp and
    /// dying 30 dB, then 60 dB down: a blade held to a grindstone) are read at their exact
    /// rate off the envelope's period, where the modulation spectrum's octave bands say 2 Hz;
    /// steady noise has no period.
    #[test]
    fn lifting_strokes_are_read_off_the_envelope_period() {
        let fs = 16_000.0;
        let x = noise(6 * 16_000, 7);
        assert!(
            stroke_period(&x, fs).is_none_or(|p| p.strength < STROKE_PERIOD_STRENGTH),
            "{:?}",
            stroke_period(&x, fs)
        );
        let rate_hz = 2.6;
        let lifting: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let u = (i as f64 / fs * rate_hz).fract();
                let db = if u < 0.65 { -30.0 * u / 0.65 } else { -60.0 };
                v * 10f64.powf(db / 20.0)
            })
            .collect();
        let period = stroke_period(&lifting, fs).expect("a period");
        // 10 ms frames place a 385 ms period to within half a frame (1.3 %).
        assert!((period.rate_hz / rate_hz - 1.0).abs() < 0.015, "{period:?}");
        assert!(period.strength > 0.8, "{period:?}");
        // One way, no return: no push and pull.
        assert_eq!(period.alternation_db, None, "{period:?}");
        let e = estimate(
            &profile(&lifting, fs, 8000.0, "recording").unwrap(),
            Some(period),
        );
        assert_eq!(e.strokes.map(|s| s.1), Some(period.rate_hz), "{e:?}");
        assert!(e.strokes.is_some_and(|s| s.0 >= period.strength), "{e:?}");
        // Silent for 35 % of each stroke, and 25 dB down or more in the last few % of the
        // fading part too (where depends on where the 95th percentile of the 10 ms frames'
        // noisy levels falls): lifted for 35–50 %.
        let lift = e.stroke_lift.expect("lifted");
        assert!(lift > 0.35 && lift < 0.5, "{e:?}");
        // The modulation spectrum's octave bands alone place it an octave band off.
        let blind = estimate(&profile(&lifting, fs, 8000.0, "recording").unwrap(), None);
        assert_eq!(blind.strokes.map(|s| s.1), Some(2.0), "{blind:?}");
    }

    /// Push and pull (noise swelling as |sin| at 3 strokes per second, every other stroke
    /// 8 dB lighter: a hand saw) is read as strokes at 3 Hz, not as its 1.5 Hz period, with
    /// the return's contrast; the same strokes alike read no alternation, and lifted strokes
    /// (one way) none either.
    #[test]
    fn a_push_and_a_lighter_pull_are_read_as_alternating_strokes() {
        let fs = 16_000.0;
        let x = noise(6 * 16_000, 11);
        let strokes = |return_db: f64| -> Vec<f64> {
            x.iter()
                .enumerate()
                .map(|(i, v)| {
                    let t = i as f64 / fs;
                    let pull = (t * 3.0).floor() as usize % 2 == 1;
                    let g = if pull {
                        10f64.powf(-return_db / 20.0)
                    } else {
                        1.0
                    };
                    v * g * (core::f64::consts::PI * 3.0 * t).sin().abs()
                })
                .collect()
        };
        let saw = stroke_period(&strokes(8.0), fs).expect("a period");
        // 10 ms frames place the 667 ms period within half a frame.
        assert!((saw.rate_hz / 3.0 - 1.0).abs() < 0.02, "{saw:?}");
        // The contrast read through a log envelope of noise (10 ms frames of it wobble by
        // ~1.5 dB) and the |sin| dips floored 50 dB down: within 2.5 dB of the 8 dB set.
        let db = saw.alternation_db.expect("push and pull");
        assert!((db - 8.0).abs() < 2.5, "{saw:?}");
        let e = estimate(
            &profile(&strokes(8.0), fs, 8000.0, "recording").unwrap(),
            Some(saw),
        );
        let g = e.stroke_return.expect("a return");
        assert!((20.0 * g.log10() + db).abs() < 1e-9, "{e:?}");
        let p = e.apply(&Params::default());
        assert!(p.get(ParamId::StrokeReturn) < 0.6, "{e:?}");
        let alike = stroke_period(&strokes(0.0), fs).expect("a period");
        assert!((alike.rate_hz / 3.0 - 1.0).abs() < 0.02, "{alike:?}");
        assert_eq!(alike.alternation_db, None, "{alike:?}");
    }

    /// Steady noise does not surge; noise whose level drifts over seconds in every band (a
    /// sum of slow random sines, 0.2–0.7 Hz, ±60 %) reads as surges: slow wander with a rate
    /// of at most 1 Hz, and no bumps though every band moves together.
    #[test]
    fn surges_are_read_off_the_slow_modulation() {
        let fs = 16_000.0;
        let x = noise(6 * 16_000, 5);
        let steady = estimate(
            &profile(&x, fs, 8000.0, "recording").unwrap(),
            stroke_period(&x, fs),
        );
        assert!(steady.wander_rate_hz.is_none(), "{steady:?}");
        let surging: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let t = i as f64 / fs;
                let tau = core::f64::consts::TAU;
                let g = 1.0
                    + 0.35 * (tau * 0.23 * t + 1.0).sin()
                    + 0.25 * (tau * 0.41 * t + 2.0).sin()
                    + 0.2 * (tau * 0.67 * t + 0.5).sin();
                v * g
            })
            .collect();
        let e = estimate(
            &profile(&surging, fs, 8000.0, "recording").unwrap(),
            stroke_period(&surging, fs),
        );
        let rate = e.wander_rate_hz.expect("surges");
        assert!(rate <= 1.0, "{e:?}");
        assert!(e.wander.is_some_and(|w| w >= 0.6), "{e:?}");
        assert!(e.bumpiness.is_none(), "{e:?}");
        assert!(e.describe().contains("surges"), "{}", e.describe());
    }
}
