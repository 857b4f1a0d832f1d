//! A fitted object (`trundle fit-object`, [`crate::fit`]) as the voice's object.
//!
//! [`FittedObject`] is the object file's content (modes and the third-octave envelope of
//! what they leave unexplained; the file format is [`from_json`] / [`to_json`]).
//! [`LoadedObject::new`] validates it and prepares it for the bank — off the audio thread,
//! it allocates — and [`crate::Voice::set_loaded_object`] swaps it in without allocating.
//!
//! ## How a fitted object is played (docs/MODEL.md §6, "Fitted objects")
//! * **Modes, with their phase** (object file version 2, [`FittedObject::play_phase`]).
//!   Each fitted mode aₖ·e^{−t/τₖ}·cos(2πfₖt + φₖ) becomes an explicit mode of the bank
//!   with its frequency, decay and the complex input gain gₖ + i·hₖ = aₖ·(−sin φₖ + i·cos φₖ)
//!   ([`crate::object::bank`]): struck by a unit impulse at sample 0 — the onset, t = 0 of
//!   the fit — its output at sample n is aₖ·rₖⁿ·cos(nωₖ + φₖ) with rₖ = e^{−1/(τₖ·f_s)}
//!   and ωₖ = 2πfₖ/f_s, the fitted mode at t = n/f_s exactly, at any playback rate f_s
//!   (fₖ and τₖ are in Hz and seconds). The strike's first milliseconds keep their
//!   waveform, its click (the modes' sum Σaₖ·cos φₖ at t = 0) included. A phase within
//!   10⁻⁹ of ±π/2 keeps a real gain, so a sine-phase object does not pay for the phased
//!   kernel.
//! * **Modes in sine phase** (version-1 files, which keep the sound they always had). The
//!   gain is real: every impulse response starts in sine phase, the fitted phase reduced to
//!   the gain's sign, sₖ = sign(−sin φₖ) (the sine component of the fitted cosine), the
//!   amplitude aₖ kept. Energy and spectrum are kept; the waveform of the first
//!   milliseconds is not.
//! * **The band part: the attack and the rest.** Each third-octave band is played by
//!   [`BAND_MODES`] modes spread evenly (in log frequency) through the band, ringing at the
//!   residual envelope's decay (or the band's own time 1/(π·bandwidth) where the envelope has
//!   none). They are modes of the same bank, driven by the same force as the fitted modes:
//!   an impulse gives each band's decaying burst (the mallet's contact, the noisy onset,
//!   dense high modes), and a ball rolling on the object drives them as it drives the modes,
//!   band-limited noise following its excitation. Their level fills only what the played
//!   modes do not explain of the recording's own third-octave spectrum
//!   ([`FittedObject::spectrum`], over [`SPECTRUM_SPAN_S`], by the fit's one measure,
//!   `band_energies`), measured once in [`LoadedObject::new`]: with phases, what the modes
//!   explain is their phase-correct spectrum (the fitted modes themselves), so a band the
//!   modes already fill or exceed gets no band energy and nothing is counted twice; the
//!   fill is then calibrated by measuring the band part as played by the same measure
//!   (`explained`), since a short band mode leaks into its neighbours and the measure's
//!   filters do not pass a whole band flat (about 1 dB). Short modes (< [`SHORT_MODE_S`])
//!   in a band where the modes exceed the recording are scaled down to it. Files without a
//!   spectrum fall back to the envelope (its level relative to the recording's energy,
//!   estimated as E = Σaₖ²τₖ·(1 − e^{−2D/τₖ}) / (1 − Σ10^{Lᵦ/10})), plus, in sine phase,
//!   what the sine phase loses of the modes' own energy. Slowly decaying bands make
//!   narrow, tonal band modes: the third-octave energy is right, the fine spectrum between
//!   partials is not. A short measured transient (the first milliseconds of the residual,
//!   played as a sample at each onset) was not chosen: under a rolling force there is no
//!   onset to trigger it, while band modes are linear in the force, strike or roll; and
//!   with phases the strike's click is already in the modes.
//! * **Quality.** [`crate::object::quality::Quality::max_modes`] caps the explicit fitted modes
//!   (16 / 64 / 256 / 256 / all), loudest (aₖ²τₖ) first; the energy of the others is added
//!   to the band part of their third-octave band (at the energy-weighted decay), so a lower
//!   quality keeps the object's spectrum and loudness.
//! * **Sample rate.** Frequencies and decays are in Hz and seconds: a fitted object plays
//!   at any rate; modes and bands at or above Nyquist are dropped.
//! * **Stereo.** A fitted object has no mode shapes; each mode gets a deterministic
//!   pseudo-random side weight dₖ = w·[`SIDE_SPREAD`]·uₖ, uₖ ∈ [−1, 1] from its index, so
//!   L = g(1 + d), R = g(1 − d) and L + R is the mono object at every width, as for the
//!   built-in objects.
//! * **Controls as modifiers.** `decay` scales every decay time; the material disk tilts
//!   decays and gains with frequency relative to its default point (the ratio of the two
//!   damping laws, normalized at [`TILT_REF_HZ`], bounded to ×1/20 … ×20, and the amplitude
//!   tilt (f/1 kHz)^{tilt − tilt₀}); `object_size` transposes (f × 1 m/size, 1 m = as
//!   fitted); `width` spreads the image. The ball position, the listening point, `shape`
//!   and `modes` are ignored (no mode shapes, no series). At the parameters' defaults the
//!   object plays exactly as fitted.

// SplitMix64: the deterministic side units and signs.
use crate::analysis::third_octave::{band_centre_hz, band_index, BANDS};
use crate::block::splitmix64 as mix;
use std::sync::Arc;

/// One fitted mode: aₖ·e^{−t/τₖ}·cos(2πfₖt + φₖ), t in seconds from the start of the free
/// decay ([`FittedObject::onset_s`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitMode {
    /// Frequency fₖ (Hz).
    pub freq_hz: f64,
    /// 1/e amplitude decay time τₖ (s).
    pub decay_s: f64,
    /// Amplitude aₖ at t = 0 (full scale = 1).
    pub amplitude: f64,
    /// Phase φₖ at t = 0 (rad).
    pub phase_rad: f64,
    /// Standard uncertainty of τₖ (s) as the fit estimated it; 0 = not stated (files
    /// written before it existed, modes set by hand).
    pub decay_sd_s: f64,
    /// Pitch glide Δfₖ (Hz; 0 = a fixed mode): struck once, the mode sounds at
    /// fₖ + Δfₖ·e^{−t/τgₖ} (a membrane's tension relaxing, docs/MODEL.md §6). Object file
    /// version 3; absent in older files.
    pub glide_hz: f64,
    /// The glide's 1/e time τgₖ (s; 0 when `glide_hz` is 0). Played as a glide that follows
    /// the mode's own amplitude: f = fₖ + Δfₖ·(a/a₀)^{τₖ/τgₖ}, a₀ the amplitude a unit
    /// impulse gives (see [`LoadedMode::glide_exp`]).
    pub glide_s: f64,
}

/// One band of the residual's spectral envelope.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopeBand {
    /// Third-octave centre frequency (Hz).
    pub centre_hz: f64,
    /// The band's energy relative to the whole recording's (dB).
    pub level_db: f64,
    /// 1/e amplitude decay time (s), bounded to 0.2 ms … 60 s.
    pub decay_s: f64,
}

/// A fitted object: the modes, the residual's spectral envelope and how well it fits.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedObject {
    /// Sample rate of the recording (Hz).
    pub sample_rate_hz: f64,
    /// The modes, ascending in frequency.
    pub modes: Vec<FitMode>,
    /// Third-octave envelope of what the modes leave unexplained.
    pub envelope: Vec<EnvelopeBand>,
    /// The modal analysis covered [lo, hi) Hz.
    pub modal_range_hz: (f64, f64),
    /// Start of the free decay in the recording (s): the strike's peak within 20 ms of its
    /// onset, t = 0 of the modes (the attack before it is the contact, not the object).
    pub onset_s: f64,
    /// Length of the fitted free decay (s).
    pub duration_s: f64,
    /// Residual energy relative to the signal's over the fitted decay (dB).
    pub residual_db: f64,
    /// Peak |x| of the recording (full scale = 1).
    pub peak: f64,
    /// The recording's own third-octave spectrum over the first [`SPECTRUM_SPAN_S`] of the
    /// fitted decay ([`band_energies`](crate::analysis::third_octave::band_energies)); empty in files written before it existed. The band
    /// part fills what the played modes miss of it.
    pub spectrum: Vec<SpectrumBand>,
    /// The modes are played from their fitted phase φₖ (complex input gains; object file
    /// version 2). False for version-1 files, played as they always were: in sine phase,
    /// the phase reduced to the gain's sign.
    pub play_phase: bool,
}

/// One band of a recording's spectrum ([`FittedObject::spectrum`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectrumBand {
    /// Third-octave centre frequency (Hz).
    pub centre_hz: f64,
    /// The band's energy in dB re the modes' measure: 10·log10(4·∫x²dt) over the span, so a
    /// lone mode a·e^{−t/τ}·cos(…) that has rung out inside it gives 10·log10(a²τ).
    pub level_db: f64,
}

/// The span of the recording [`FittedObject::spectrum`] and the played modes are compared
/// over (s, from the start of the free decay; less when the decay is shorter).
pub const SPECTRUM_SPAN_S: f64 = 0.5;

/// The newest object file version this build reads, and the one it writes for an object
/// played with its phases ([`FittedObject::play_phase`]); an object read from a version-1
/// file (sine phase) is written back as version 1, so it keeps its sound.
/// Version 3 adds the modes' optional glide ([`FitMode::glide_hz`]); an object without a
/// gliding mode is still written as version 2, byte for byte as before.
pub const OBJECT_VERSION: u64 = 3;

/// Longest decay an object file may give (s): beyond it a mode does not decay.
pub const MAX_DECAY_S: f64 = 3600.0;

/// Largest amplitude an object file may give (full scale = 1).
pub const MAX_AMPLITUDE: f64 = 1000.0;

/// Modes per third-octave band of the band part.
pub const BAND_MODES: usize = 3;

/// Most fitted modes a loaded object keeps (the loudest).
pub const MAX_FITTED_MODES: usize = 2048;

/// Largest side weight of a fitted mode at width 1.
pub const SIDE_SPREAD: f64 = 0.6;

/// The material disk's tilt is normalized here (Hz): decays at this frequency are scaled by
/// `decay` only.
pub const TILT_REF_HZ: f64 = 1000.0;

impl FittedObject {
    /// Check every number: finite; frequencies in (0, f_s/2) of the recording, decays
    /// positive, amplitudes not negative; the error names the field (`modes[3].freq_hz`).
    pub fn validate(&self) -> Result<(), String> {
        let fs = self.sample_rate_hz;
        if !(fs.is_finite() && (1000.0..=1e7).contains(&fs)) {
            return Err(format!(
                "\"sample_rate_hz\" must be a sample rate in Hz (1000 … 10⁷), got {fs}"
            ));
        }
        if self.modes.len() > 100_000 || self.envelope.len() > 1000 {
            return Err("too many modes or envelope bands (at most 100000 and 1000)".into());
        }
        for (i, m) in self.modes.iter().enumerate() {
            let field = |f: &str| format!("modes[{i}].{f}");
            for (name, v) in [
                ("freq_hz", m.freq_hz),
                ("decay_s", m.decay_s),
                ("amplitude", m.amplitude),
                ("phase_rad", m.phase_rad),
            ] {
                if !v.is_finite() {
                    return Err(format!("{} must be a finite number, got {v}", field(name)));
                }
            }
            if !(m.freq_hz > 0.0 && m.freq_hz < 0.5 * fs) {
                return Err(format!(
                    "{} = {} Hz is outside (0, {} Hz), half the sample rate",
                    field("freq_hz"),
                    m.freq_hz,
                    0.5 * fs
                ));
            }
            if !(m.decay_s > 0.0 && m.decay_s <= MAX_DECAY_S) {
                return Err(format!(
                    "{} = {} must be positive and at most {MAX_DECAY_S} s",
                    field("decay_s"),
                    m.decay_s
                ));
            }
            if !(0.0..=MAX_AMPLITUDE).contains(&m.amplitude) {
                return Err(format!(
                    "{} = {} must be between 0 and {MAX_AMPLITUDE} (full scale = 1)",
                    field("amplitude"),
                    m.amplitude
                ));
            }
            if !(m.glide_hz.is_finite() && m.glide_s.is_finite()) {
                return Err(format!(
                    "{} must be finite numbers",
                    field("glide_hz/glide_s")
                ));
            }
            if m.glide_hz != 0.0
                && !(m.glide_s > 0.0
                    && m.glide_s <= MAX_DECAY_S
                    && m.freq_hz + m.glide_hz > 0.0
                    && m.freq_hz + m.glide_hz < 0.5 * fs)
            {
                return Err(format!(
                    "{} = {} Hz needs {} in (0, {MAX_DECAY_S}] s and f + Δf in (0, {} Hz)",
                    field("glide_hz"),
                    m.glide_hz,
                    field("glide_s"),
                    0.5 * fs
                ));
            }
            if m.phase_rad.abs() > 1e3 {
                return Err(format!(
                    "{} = {} is not a phase",
                    field("phase_rad"),
                    m.phase_rad
                ));
            }
        }
        for (i, b) in self.envelope.iter().enumerate() {
            let field = |f: &str| format!("envelope[{i}].{f}");
            for (name, v) in [
                ("centre_hz", b.centre_hz),
                ("level_db", b.level_db),
                ("decay_s", b.decay_s),
            ] {
                if !v.is_finite() {
                    return Err(format!("{} must be a finite number, got {v}", field(name)));
                }
            }
            if !(b.centre_hz > 0.0 && b.centre_hz < 0.5 * fs) {
                return Err(format!(
                    "{} = {} Hz is outside (0, {} Hz), half the sample rate",
                    field("centre_hz"),
                    b.centre_hz,
                    0.5 * fs
                ));
            }
            if !(b.decay_s > 0.0 && b.decay_s <= MAX_DECAY_S) {
                return Err(format!(
                    "{} = {} must be positive and at most {MAX_DECAY_S} s",
                    field("decay_s"),
                    b.decay_s
                ));
            }
            if !(-400.0..=60.0).contains(&b.level_db) {
                return Err(format!(
                    "{} = {} dB is outside −400 … 60 dB",
                    field("level_db"),
                    b.level_db
                ));
            }
        }
        for (i, b) in self.spectrum.iter().enumerate() {
            if !(b.centre_hz.is_finite() && b.centre_hz > 0.0 && b.centre_hz < 0.5 * fs) {
                return Err(format!(
                    "spectrum[{i}].centre_hz = {} Hz is outside (0, {} Hz)",
                    b.centre_hz,
                    0.5 * fs
                ));
            }
            if !(b.level_db.is_finite() && (-400.0..=100.0).contains(&b.level_db)) {
                return Err(format!(
                    "spectrum[{i}].level_db = {} is outside −400 … 100 dB",
                    b.level_db
                ));
            }
        }
        for (name, v, lo, hi) in [
            ("duration_s", self.duration_s, 0.0, 1e6),
            ("residual_db", self.residual_db, -400.0, 100.0),
            ("onset_s", self.onset_s, 0.0, 1e6),
            ("peak", self.peak, 0.0, 1e3),
            ("modal_range_hz[0]", self.modal_range_hz.0, 0.0, 1e7),
            ("modal_range_hz[1]", self.modal_range_hz.1, 0.0, 1e7),
        ] {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(format!(
                    "\"{name}\" must be a number in {lo} … {hi}, got {v}"
                ));
            }
        }
        Ok(())
    }
}

/// An object file's content with the name of the recording it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectFile {
    /// The fitted object.
    pub object: FittedObject,
    /// The recording's file name (`"source"`; may be empty).
    pub source: String,
}

/// A mode of a [`LoadedObject`], ready for the bank.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadedMode {
    /// Frequency (Hz) as fitted.
    pub freq_hz: f64,
    /// Decay (s) as fitted.
    pub decay_s: f64,
    /// Real part of the complex gain, −aₖ·sin φₖ (played with phase), or the signed
    /// amplitude sₖ·aₖ (sine phase; module docs).
    pub gain: f64,
    /// Imaginary part of the complex gain, aₖ·cos φₖ (0 in sine phase).
    pub gain_im: f64,
    /// Side unit uₖ ∈ [−1, 1] (the side weight is w·[`SIDE_SPREAD`]·uₖ).
    pub side: f64,
    /// Third-octave band ([`band_index`]) where its energy goes when the quality drops it.
    pub band: usize,
    /// Glide Δf (Hz, as fitted; 0 = a fixed mode).
    pub glide_hz: f64,
    /// Exponent of the amplitude-following glide, τₖ/τgₖ: the mode plays at
    /// f + Δf·(|z|²/|g + ih|²)^{glide_exp/2}, |z| its state and |g + ih| its input gain, so a
    /// unit impulse glides as f + Δf·e^{−t/τg} exactly, a softer strike or a roll (smaller
    /// |z|) less.
    pub glide_exp: f64,
}

/// A band of the band part of a [`LoadedObject`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadedBand {
    /// Amplitude of each of its [`BAND_MODES`] modes (0: the band is silent).
    pub amplitude: f64,
    /// Decay (s).
    pub decay_s: f64,
}

/// A fitted object prepared for the bank: validated, modes in loudness order with their
/// gains and side units, the band part's amplitudes. Built off the audio thread
/// ([`LoadedObject::new`] allocates) and shared by `Arc` with the voice's objects.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedObject {
    file: ObjectFile,
    modes: Vec<LoadedMode>,
    bands: [LoadedBand; BANDS],
    /// Side units of the band modes.
    band_side: [[f64; BAND_MODES]; BANDS],
    /// The band part plays (see [`LoadedObject::with_band_part`]).
    band_part: bool,
}

/// Modes shorter than this (s) get the correction for the energy their phase gains
/// (see `phase_energies`).
pub const SHORT_MODE_S: f64 = 0.05;

/// The span (samples) [`band_energies`](crate::analysis::third_octave::band_energies) compares over for a fit.
pub fn spectrum_span(fit_duration_s: f64, sample_rate_hz: f64) -> usize {
    let span = if fit_duration_s > 0.0 {
        fit_duration_s.min(SPECTRUM_SPAN_S)
    } else {
        SPECTRUM_SPAN_S
    };
    (span * sample_rate_hz).ceil() as usize
}

fn unit(z: u64) -> f64 {
    (mix(z) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

impl LoadedObject {
    /// Validate and prepare (allocates: call off the audio thread). Keeps at most
    /// [`MAX_FITTED_MODES`] modes, the loudest.
    pub fn new(file: ObjectFile) -> Result<Self, String> {
        let fit = &file.object;
        fit.validate()?;
        let d = fit.duration_s;
        let held = |tau: f64| {
            if d > 0.0 {
                1.0 - (-2.0 * d / tau).exp()
            } else {
                1.0
            }
        };
        let mut modes: Vec<LoadedMode> = fit
            .modes
            .iter()
            .enumerate()
            .filter(|(_, m)| m.amplitude > 0.0)
            .map(|(i, m)| {
                let (gain, gain_im) = if fit.play_phase {
                    let (sin, cos) = m.phase_rad.sin_cos();
                    // A sine phase (φ = ±π/2 up to rounding) keeps a real gain, and the
                    // cheaper kernel, when no mode needs more.
                    let cos = if cos.abs() < 1e-9 { 0.0 } else { cos };
                    (-m.amplitude * sin, m.amplitude * cos)
                } else if -m.phase_rad.sin() < 0.0 {
                    (-m.amplitude, 0.0)
                } else {
                    (m.amplitude, 0.0)
                };
                LoadedMode {
                    freq_hz: m.freq_hz,
                    decay_s: m.decay_s,
                    gain,
                    gain_im,
                    side: unit(i as u64),
                    band: band_index(m.freq_hz),
                    glide_hz: m.glide_hz,
                    glide_exp: if m.glide_hz != 0.0 {
                        m.decay_s / m.glide_s
                    } else {
                        0.0
                    },
                }
            })
            .collect();
        let energy = |m: &LoadedMode| (m.gain * m.gain + m.gain_im * m.gain_im) * m.decay_s;
        modes.sort_by(|a, b| energy(b).total_cmp(&energy(a)));
        modes.truncate(MAX_FITTED_MODES);
        let e_modes: f64 = modes.iter().map(|m| energy(m) * held(m.decay_s)).sum();
        let env_share: f64 = fit
            .envelope
            .iter()
            .map(|b| 10f64.powf(b.level_db.min(0.0) / 10.0))
            .sum();
        let e_rec = if e_modes > 0.0 {
            e_modes / (1.0 - env_share).max(0.1)
        } else {
            // No modes: the envelope alone, at a nominal level (the voice normalizes).
            1.0
        };
        // Per band, the band part's energy (a²τ units) and energy × decay.
        let mut acc = [(0.0f64, 0.0f64); BANDS];
        for b in &fit.envelope {
            if b.level_db < -120.0 {
                continue;
            }
            let i = band_index(b.centre_hz);
            let tau = b.decay_s.clamp(
                crate::object::material::DECAY_MIN_S,
                crate::object::material::DECAY_MAX_S,
            );
            let e = 10f64.powf(b.level_db.min(0.0) / 10.0) * e_rec / held(tau);
            acc[i].0 += e;
            acc[i].1 += e * tau;
        }
        // What the sine phase changes: per band, the energy of the modes with their fitted
        // phases against the energy of the modes as played ([`phase_energies`]). Energy
        // lost (the strike's click, overlapping short modes that added up in phase) goes to
        // the band part, ringing for the band's own time; energy gained (the sine phase's
        // slower skirts, short modes that cancelled) scales the band's short modes down.
        let (exact, played, has_short) = phase_energies(fit);
        // With the recording's own spectrum, the band part fills what the played modes miss
        // of it, band by band (over the same span, by the same measure), ringing at the
        // envelope's decay (or the band's own time where the envelope has none).
        let target: Option<[f64; BANDS]> = (!fit.spectrum.is_empty()).then(|| {
            let mut t = [0.0; BANDS];
            for b in &fit.spectrum {
                t[band_index(b.centre_hz)] = 10f64.powf(b.level_db / 10.0);
            }
            t
        });
        let len = spectrum_span(fit.duration_s, fit.sample_rate_hz);
        let span_s = len as f64 / fit.sample_rate_hz;
        // The share of a decay's energy inside the compared span (its last 30 % faded: about
        // the first 85 %).
        let inside = |tau: f64| 1.0 - (-2.0 * 0.85 * span_s / tau).exp();
        let (exact, mut acc) = match target {
            None => (exact, acc),
            Some(t) => {
                let mut fill = [(0.0f64, 0.0f64); BANDS];
                for i in 0..BANDS {
                    let tau = if acc[i].0 > 0.0 {
                        acc[i].1 / acc[i].0
                    } else {
                        let bw = band_centre_hz(i) * (2f64.powf(1.0 / 6.0) - 2f64.powf(-1.0 / 6.0));
                        1.0 / (core::f64::consts::PI * bw)
                    };
                    let miss = t[i] - played[i];
                    if miss > 0.0 {
                        let e = miss / inside(tau);
                        fill[i] = (e, e * tau);
                    }
                }
                // What the band part adds, measured as the target was, sets its level
                // (objects played with phase; version-1 objects keep their sound).
                if fit.play_phase {
                    calibrate_fill(&mut fill, &t, &played, fit.sample_rate_hz, len);
                }
                // The target replaces the modes-with-phases estimate and the envelope.
                (t, fill)
            }
        };
        let phase_fill = target.is_none();
        let mut mode_scale = [1.0f64; BANDS];
        for i in 0..BANDS {
            let (ex, pl) = (exact[i], played[i]);
            if !has_short[i] && ex <= pl {
                continue;
            }
            if ex > pl && phase_fill {
                // The click: it rings for the band's own time, 1/(π·bandwidth).
                let bw = band_centre_hz(i) * (2f64.powf(1.0 / 6.0) - 2f64.powf(-1.0 / 6.0));
                let tau = 1.0 / (core::f64::consts::PI * bw);
                let e = ex - pl;
                acc[i].0 += e;
                acc[i].1 += e * tau;
            } else if ex < pl && pl > 0.0 {
                mode_scale[i] = (ex / pl).max(0.01).sqrt();
            }
        }
        for m in modes.iter_mut().filter(|m| m.decay_s < SHORT_MODE_S) {
            m.gain *= mode_scale[m.band];
            m.gain_im *= mode_scale[m.band];
        }
        let mut bands = [LoadedBand {
            amplitude: 0.0,
            decay_s: 0.0,
        }; BANDS];
        for (i, &(e, et)) in acc.iter().enumerate() {
            if e > 0.0 {
                let tau = (et / e).clamp(
                    crate::object::material::DECAY_MIN_S,
                    crate::object::material::DECAY_MAX_S,
                );
                bands[i] = LoadedBand {
                    amplitude: (e / (BAND_MODES as f64 * tau)).sqrt(),
                    decay_s: tau,
                };
            }
        }
        let mut band_side = [[0.0; BAND_MODES]; BANDS];
        for (i, s) in band_side.iter_mut().enumerate() {
            for (j, x) in s.iter_mut().enumerate() {
                *x = unit(0x5eed_0000 + (i * BAND_MODES + j) as u64);
            }
        }
        Ok(Self {
            file,
            modes,
            bands,
            band_side,
            band_part: true,
        })
    }

    /// Prepare and share (allocates).
    pub fn shared(file: ObjectFile) -> Result<Arc<Self>, String> {
        Self::new(file).map(Arc::new)
    }

    /// Switch the band part off (the modes alone, with the quality's cap dropping the
    /// others) or on (the default): for measuring what it adds.
    pub fn with_band_part(mut self, on: bool) -> Self {
        self.band_part = on;
        self
    }

    /// True when the band part plays.
    pub fn band_part(&self) -> bool {
        self.band_part
    }

    /// The object file it was built from.
    pub fn file(&self) -> &ObjectFile {
        &self.file
    }

    /// The modes, loudest (aₖ²τₖ) first.
    pub fn modes(&self) -> &[LoadedMode] {
        &self.modes
    }

    /// The band part, by band index.
    pub fn bands(&self) -> &[LoadedBand; BANDS] {
        &self.bands
    }

    /// Side unit of mode `j` of band `i`.
    pub fn band_side(&self, i: usize, j: usize) -> f64 {
        self.band_side[i][j]
    }

    /// Sign of the gain of mode `j` of band `i` (deterministic, alternating in effect).
    pub fn band_sign(i: usize, j: usize) -> f64 {
        if mix(0xb00d + (i * BAND_MODES + j) as u64) & 1 == 0 {
            1.0
        } else {
            -1.0
        }
    }

    /// Frequency of mode `j` of band `i` (Hz, before transposition): evenly spread in log
    /// frequency through the third-octave band.
    pub fn band_mode_hz(i: usize, j: usize) -> f64 {
        band_centre_hz(i) * 2f64.powf(((j as f64 + 0.5) / BAND_MODES as f64 - 0.5) / 3.0)
    }
}

mod explained;
use explained::{calibrate_fill, phase_energies};

#[cfg(feature = "presets")]
mod file_json;

#[cfg(feature = "presets")]
pub use file_json::{from_json, to_json};
