//! Fitting an object to a recording: high-resolution modal analysis of one recorded strike.
//!
//! ```text
//! strike x[n] ─► checks (length, silence, clipping, decay, a second onset) ─► onset … end
//!   (end: where the level meets the floor, or the recording's end when that "floor" is long
//!   modes still falling)
//!   ─► per band [lo, hi): heterodyne by f_c, Kaiser low-pass, decimate by D ≈ f_s/4B
//!      ─► ESPRIT (Hankel, eigenvectors of YYᴴ, shift invariance; order from the
//!         eigenvalue floor) on the first 640 samples ─► poles
//!      ─► the poles refined jointly over the whole ring (variable projection,
//!         Levenberg–Marquardt; each decay's standard uncertainty) ─► least-squares
//!         complex amplitudes ─► modes in [lo, hi)
//!   ─► a long mode not refined: its late ring fitted alone to the recording's end; split
//!      into an early and a late ring when they explain more (late.rs)
//!   ─► all amplitudes re-solved jointly, full band, over the whole decay (poles fixed)
//!   ─► modes (f, τ ± sd, amplitude, phase) ─► resynthesis ─► residual
//!   ─► the residual's third-octave envelope (level, decay): the full-band part
//! ```
//!
//! Subspace methods resolve modes closer than an FFT's bin and estimate decays directly
//! (ESPRIT: Roy & Kailath 1989; matrix pencil: Hua & Sarkar 1990); splitting the band first
//! keeps each eigenproblem small (L ≤ 160) whatever the sample rate and the number of modes
//! (the approach of sub-band ESPRIT in Laroche 1993 and Badeau et al. 2006). See
//! [`bands`] (band splitting), [`subspace`] (ESPRIT and the order rule), [`refine`] (the
//! decays over the whole ring, without the short window's bias, and their uncertainty),
//! [`joint`] (every amplitude solved at once on the recording, so close modes' skirts
//! cancel), [`late`] (a merged long mode split into its early and late rings) and
//! [`explained`] (how much of the recording the fit explains, band by band).
//!
//! A mode k is the real damped sinusoid aₖ·e^{−t/τₖ}·cos(2πfₖt + φₖ), t from the start of
//! the free decay (the strike's peak: the attack before it is the contact force, which
//! Trundle's action model supplies).

pub mod bands;
pub mod cmaes;
pub mod deconvolve;
pub mod envelope;
pub mod explained;
pub mod glide;
pub mod joint;
#[cfg(feature = "presets")]
pub mod json;
pub mod late;
pub mod refine;
pub mod roll;
pub mod subspace;

use core::f64::consts::TAU;
use core::fmt;
use nalgebra::Complex;

pub use envelope::{log_spectral_distance_db, third_octave_envelope, EnvelopeBand};

pub use crate::object::fitted::{FitMode, FittedObject, SpectrumBand};

/// Why a recording is not one decaying strike.
#[derive(Clone, Debug, PartialEq)]
pub enum FitError {
    /// Sample rate outside 8 … 384 kHz or not finite.
    SampleRate(f64),
    /// Shorter than [`MIN_SECONDS`] (or its decay is).
    TooShort {
        /// What was there (s).
        seconds: f64,
    },
    /// Peak below [`SILENCE_DB`].
    Silence {
        /// Peak level (dBFS).
        peak_db: f64,
    },
    /// A run of identical samples at the peak: the recording clipped.
    Clipped {
        /// Run length (samples).
        run: usize,
        /// Where (s).
        at_s: f64,
    },
    /// The level at the end is not [`MIN_DECAY_DB`] below the maximum: noise or a sustained
    /// sound (a roll), not a strike.
    NoDecay {
        /// Largest fall after the maximum (dB).
        fall_db: f64,
    },
    /// A second onset after the strike.
    SeveralStrikes {
        /// When (s).
        at_s: f64,
        /// How far the level jumped above its recent maximum (dB).
        rise_db: f64,
    },
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FitError::SampleRate(r) => write!(f, "sample rate {r} Hz is outside 8000 … 384000 Hz"),
            FitError::TooShort { seconds } => write!(
                f,
                "too short: {:.1} ms of sound, a strike needs at least {:.0} ms",
                seconds * 1e3,
                MIN_SECONDS * 1e3
            ),
            FitError::Silence { peak_db } => write!(
                f,
                "silent: peak {peak_db:.1} dBFS is below {SILENCE_DB} dBFS"
            ),
            FitError::Clipped { run, at_s } => write!(
                f,
                "clipped: {run} identical samples at the peak at {at_s:.3} s (record it with more headroom)"
            ),
            FitError::NoDecay { fall_db } => write!(
                f,
                "not a decaying strike: the level ends only {fall_db:.1} dB under its maximum (needs {MIN_DECAY_DB} dB; noise, or a sustained sound?)"
            ),
            FitError::SeveralStrikes { at_s, rise_db } => write!(
                f,
                "several strikes: a second onset at {at_s:.3} s ({rise_db:.1} dB jump); trim the file to one strike"
            ),
        }
    }
}

impl std::error::Error for FitError {}

/// Shortest recording (and decay) accepted (s).
pub const MIN_SECONDS: f64 = 0.05;
/// Peak level under which a recording is silence (dBFS).
pub const SILENCE_DB: f64 = -100.0;
/// Fall, in dB below the maximum frame, a strike must show (stationary noise in 10 ms
/// frames fluctuates by about ±1 dB; a sustained tone not at all).
pub const MIN_DECAY_DB: f64 = 12.0;
/// Identical consecutive samples at the peak that mean clipping (a 50 Hz sine at 16 bits
/// holds its crest for at most 3).
pub const CLIP_RUN: usize = 5;
/// A frame this much louder than the loudest of the previous 100 ms is a second onset.
pub const ONSET_RISE_DB: f64 = 8.0;
/// Lowest mode frequency analysed (Hz).
pub const MIN_MODE_HZ: f64 = 50.0;
/// Highest mode frequency analysed (Hz), also bounded to 0.45·f_s.
pub const MAX_MODE_HZ: f64 = 20_000.0;
/// Modes whose energy aₖ²τₖ lies this far under the strongest mode's are dropped.
pub const MODE_FLOOR_DB: f64 = -90.0;
/// A fit with gliding modes is kept when its residual is at most this much (dB) above the
/// fixed modes' ([`glide`]).
pub const GLIDE_RESIDUAL_DB: f64 = 1.0;
/// A level that stays within 6 dB of the recording's last tenth for longer than the decay
/// before it, yet falls by this much (dB) along it, is long modes ringing on, not a noise
/// floor ([`check_strike`]; stationary noise in 10 ms frames wanders by about ±1 dB).
pub const TAIL_FALL_DB: f64 = 6.0;
/// Most decimated samples per band (the span analysed by ESPRIT).
pub const BAND_SAMPLES: usize = 640;

/// Frame levels (dB, 10 ms frames, hop 5 ms) of `x`.
fn frame_db(x: &[f64], fs: f64) -> (Vec<f64>, usize) {
    let len = ((0.01 * fs) as usize).max(1);
    let hop = len.div_ceil(2);
    let mut out = Vec::new();
    let mut s = 0;
    while s < x.len() {
        let e = x[s..(s + len).min(x.len())]
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            / len as f64;
        out.push(10.0 * e.max(1e-30).log10());
        s += hop;
    }
    (out, hop)
}

/// Fall (dB) of a least-squares line through frame levels `db` (hop `hop` samples).
fn tail_fall_db(db: &[f64], hop: usize, fs: f64) -> f64 {
    let n = db.len() as f64;
    if db.len() < 4 {
        return 0.0;
    }
    let dt = hop as f64 / fs;
    let tm = 0.5 * (n - 1.0) * dt;
    let lm = db.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &l) in db.iter().enumerate() {
        let t = i as f64 * dt - tm;
        sxy += t * (l - lm);
        sxx += t * t;
    }
    -sxy / sxx * (n - 1.0) * dt
}

/// The checks of a strike; returns (start of the free decay, end) in samples: the start is
/// the strike's peak within 20 ms of its onset (the contact is over), the end where the
/// decay reaches the noise floor (or the recording's end when that "floor" is long modes
/// still ringing: [`TAIL_FALL_DB`]). A quieter pre-sound before the strike (a frame 20 ms or
/// more after the first sound that jumps [`ONSET_RISE_DB`] over all before it, up to the
/// loudest frame: a music box's mechanism, a previous ring) is left out: the onset is
/// that jump.
pub fn check_strike(x: &[f64], sample_rate_hz: f64) -> Result<(usize, usize), FitError> {
    let fs = sample_rate_hz;
    if !(fs.is_finite()
        && (crate::block::MIN_SAMPLE_RATE_HZ..=crate::block::MAX_SAMPLE_RATE_HZ).contains(&fs))
    {
        return Err(FitError::SampleRate(fs));
    }
    let seconds = x.len() as f64 / fs;
    if seconds < MIN_SECONDS {
        return Err(FitError::TooShort { seconds });
    }
    let (ipeak, peak) =
        x.iter().enumerate().fold(
            (0, 0.0f64),
            |a, (i, v)| if v.abs() > a.1 { (i, v.abs()) } else { a },
        );
    let peak_db = 20.0 * peak.max(1e-30).log10();
    if peak_db < SILENCE_DB {
        return Err(FitError::Silence { peak_db });
    }
    let mut run = 1;
    for i in 1..x.len() {
        if x[i] == x[i - 1] && x[i].abs() >= 0.99 * peak {
            run += 1;
            if run >= CLIP_RUN {
                return Err(FitError::Clipped {
                    run,
                    at_s: (i + 1 - run) as f64 / fs,
                });
            }
        } else {
            run = 1;
        }
    }
    // Onset: first sample above 5 % of the peak, backed up to where |x| was under 0.5 %
    // (at most 5 ms before).
    let first = x
        .iter()
        .position(|v| v.abs() >= 0.05 * peak)
        .unwrap_or(ipeak);
    let back = (0.005 * fs) as usize;
    let mut onset = first;
    while onset > 0 && first - onset < back && x[onset - 1].abs() >= 0.005 * peak {
        onset -= 1;
    }
    let (db, hop) = frame_db(&x[onset..], fs);
    let (fmax, lmax) =
        db.iter().enumerate().fold(
            (0, f64::NEG_INFINITY),
            |a, (i, &v)| if v > a.1 { (i, v) } else { a },
        );
    // The fall is measured to the end of the recording (the median level of its last
    // tenth): a strike dies away and stays down; a roll or noise dips and comes back.
    let mut tail: Vec<f64> = db[fmax + (db.len() - fmax) * 9 / 10..].to_vec();
    tail.sort_by(f64::total_cmp);
    let floor = tail[tail.len() / 2];
    if lmax - floor < MIN_DECAY_DB {
        return Err(FitError::NoDecay {
            fall_db: lmax - floor,
        });
    }
    // A pre-sound: a frame at least 20 ms after the onset that jumps ONSET_RISE_DB over
    // every frame before it (the overlapping frame just before excepted), up to the loudest
    // frame, is where the strike starts; what came before it (a music box's pin lifting
    // the tooth, a previous ring) is not part of the strike and is left out.
    let settle = ((0.02 * fs) as usize).div_ceil(hop).max(2);
    let mut attack_from = onset;
    for i in settle..=fmax {
        let before = db[..i - 1].iter().fold(f64::NEG_INFINITY, |a, &v| a.max(v));
        if db[i] - before >= ONSET_RISE_DB {
            attack_from = onset + (i - 1) * hop;
        }
    }
    let window = ((0.1 * fs) as usize / hop).max(1);
    for i in fmax + 1..db.len() {
        let recent = db[i.saturating_sub(window)..i]
            .iter()
            .fold(f64::NEG_INFINITY, |a, &v| a.max(v));
        if db[i] > lmax - 50.0 && db[i] - recent >= ONSET_RISE_DB {
            return Err(FitError::SeveralStrikes {
                at_s: (onset + i * hop) as f64 / fs,
                rise_db: db[i] - recent,
            });
        }
    }
    // End: where the level reaches that floor (noise when the strike has died out, the
    // last of its decay when the file cuts it) + 6 dB, or 90 dB under the maximum.
    let stop = (floor + 6.0).max(lmax - 90.0);
    let mut end_frame = (fmax..db.len()).find(|&i| db[i] < stop).unwrap_or(db.len());
    // A "floor" that lasts longer than the decay before it and still falls (by
    // [`TAIL_FALL_DB`] or more along a line through its levels: noise stays level) is not
    // the end of the strike but its long, weak modes ringing on (the low tom's 109 and
    // 147 Hz modes, T60 5–10 s, ring 1.4 s after its loud decay has reached them at 0.6 s):
    // the strike is then fitted to the end of the recording.
    if db.len() - end_frame > end_frame - fmax
        && tail_fall_db(&db[end_frame..], hop, fs) >= TAIL_FALL_DB
    {
        end_frame = db.len();
    }
    let end = (onset + end_frame * hop + hop).min(x.len());
    let span = (end - onset) as f64 / fs;
    if span < MIN_SECONDS {
        return Err(FitError::TooShort { seconds: span });
    }
    // The free decay starts at the strike's peak (the contact has ended by then): the
    // modes are fitted, and referred, from there.
    let attack = (0.02 * fs) as usize;
    let free = x[attack_from..(attack_from + attack).min(end)]
        .iter()
        .enumerate()
        .fold(
            (0, 0.0f64),
            |a, (i, v)| if v.abs() > a.1 { (i, v.abs()) } else { a },
        )
        .0
        + attack_from;
    if (end - free) as f64 / fs < MIN_SECONDS {
        return Err(FitError::TooShort {
            seconds: (end - free) as f64 / fs,
        });
    }
    Ok((free, end))
}

/// Sum of modes, t from sample 0, `len` samples at `sample_rate_hz` (a gliding mode as
/// [`glide::gliding_phasor`]).
pub fn resynthesize(modes: &[FitMode], sample_rate_hz: f64, len: usize) -> Vec<f64> {
    let mut y = vec![0.0; len];
    for m in modes {
        if m.glide_hz != 0.0 {
            let c = Complex::from_polar(m.amplitude, m.phase_rad);
            for (i, v) in y.iter_mut().enumerate() {
                let t = i as f64 / sample_rate_hz;
                *v += (c * glide::gliding_phasor(m, t)).re;
                if t > 40.0 * m.decay_s {
                    break;
                }
            }
            continue;
        }
        let z = Complex::from_polar(
            (-1.0 / (m.decay_s * sample_rate_hz)).exp(),
            TAU * m.freq_hz / sample_rate_hz,
        );
        let mut p = Complex::from_polar(m.amplitude, m.phase_rad);
        for v in y.iter_mut() {
            *v += p.re;
            p *= z;
            if p.norm_sqr() < 1e-40 {
                break;
            }
        }
    }
    y
}

/// Residual energy of `y` against `x` relative to x's energy (dB).
pub fn residual_db(x: &[f64], y: &[f64]) -> f64 {
    let e: f64 = x.iter().zip(y).map(|(a, b)| (a - b).powi(2)).sum();
    let s: f64 = x.iter().map(|a| a * a).sum();
    10.0 * (e / s.max(1e-300)).max(1e-30).log10()
}

/// How [`fit_strike_with`] fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FitOptions {
    /// Refine each band's poles over the whole ring ([`refine`]; decays without the short
    /// window's bias, and their uncertainty). Off: ESPRIT's poles, no `decay_sd_s`.
    pub refine_decays: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            refine_decays: true,
        }
    }
}

/// Fit one recorded strike (mono, full scale ±1): the modal analysis of the module docs,
/// with the default [`FitOptions`].
///
/// # Allocation
/// Allocates freely (an offline analysis; never call it on the audio thread).
pub fn fit_strike(x: &[f64], sample_rate_hz: f64) -> Result<FittedObject, FitError> {
    fit_strike_with(x, sample_rate_hz, FitOptions::default())
}

/// [`fit_strike`] with explicit options.
///
/// # Allocation
/// Allocates freely (an offline analysis; never call it on the audio thread).
pub fn fit_strike_with(
    x: &[f64],
    sample_rate_hz: f64,
    options: FitOptions,
) -> Result<FittedObject, FitError> {
    let fs = sample_rate_hz;
    let (onset, end) = check_strike(x, fs)?;
    let peak = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let sig = &x[onset..end];
    let hi = MAX_MODE_HZ.min(0.45 * fs);
    let mut modes = Vec::new();
    for band in bands::layout(MIN_MODE_HZ, hi) {
        modes.extend(fit_band(sig, fs, band, options.refine_decays));
    }
    // Drop modes far under the strongest (energy a²τ).
    let strongest = modes.iter().fold(0.0f64, |a, m: &FitMode| {
        a.max(m.amplitude * m.amplitude * m.decay_s)
    });
    let floor = strongest * 10f64.powf(MODE_FLOOR_DB / 10.0);
    modes.retain(|m| m.amplitude * m.amplitude * m.decay_s >= floor);
    modes.sort_by(|a, b| a.freq_hz.total_cmp(&b.freq_hz));
    let mut model = resynthesize(&modes, fs, sig.len());
    let mut residual_db = residual_db(sig, &model);
    // Where the bands' amplitudes overshoot a third-octave band of the recording by
    // `joint::OVERSHOOT_DB` or more (skirts that do not cancel), the amplitudes of all
    // modes are solved jointly over the whole decay (`joint`), and kept when they explain
    // more of it. Only a fit that explains something already: 2K free amplitudes lower any
    // residual a little, and a decaying noise burst must stay a fit that explains nothing.
    if modes.len() <= joint::MAX_MODES
        && !explained::is_poor(residual_db)
        && joint::overshoot_db(sig, &model, fs) >= joint::OVERSHOOT_DB
    {
        if let Some(mut j) = joint::solve(sig, &modes, fs) {
            let strongest = j.iter().fold(0.0f64, |a, m: &FitMode| {
                a.max(m.amplitude * m.amplitude * m.decay_s)
            });
            let floor = strongest * 10f64.powf(MODE_FLOOR_DB / 10.0);
            j.retain(|m| m.amplitude * m.amplitude * m.decay_s >= floor);
            let y = resynthesize(&j, fs, sig.len());
            let r = self::residual_db(sig, &y);
            if r < residual_db && j.iter().all(|m| m.amplitude <= peak.max(1e-9) * 100.0) {
                modes = j;
                model = y;
                residual_db = r;
            }
        }
    }
    // A long mode ESPRIT's window could not measure and the refinement did not take, looked
    // at again after that window to the recording's end (`late`): split into its early and
    // late rings when they differ, kept when the pair explains more of the recording.
    if options.refine_decays {
        let layout = bands::layout(MIN_MODE_HZ, hi);
        if let Some(s) = late::split(&x[onset..], sig.len(), fs, &layout, &modes) {
            let y = resynthesize(&s, fs, sig.len());
            let r = self::residual_db(sig, &y);
            if r < residual_db {
                modes = s;
                model = y;
                residual_db = r;
            }
        }
    }
    // Gliding modes (`glide`): kept when they explain the recording as well as the fixed
    // modes they replace, within GLIDE_RESIDUAL_DB (a listener hears the glide; a pair of
    // fixed modes beating in its place explains about as much energy).
    if let Some(g) = glide::find(sig, fs, &modes, &model) {
        let y = resynthesize(&g, fs, sig.len());
        let r = self::residual_db(sig, &y);
        if r < residual_db + GLIDE_RESIDUAL_DB {
            modes = g;
            model = y;
            residual_db = r;
        }
    }
    let residual: Vec<f64> = sig.iter().zip(&model).map(|(a, b)| a - b).collect();
    let envelope = third_octave_envelope(&residual, sig, fs);
    // The recording's own spectrum, by the measure the player compares the played modes
    // with (`analysis::third_octave::band_energies`).
    let span = crate::object::fitted::spectrum_span(sig.len() as f64 / fs, fs).min(sig.len());
    let spectrum = crate::analysis::third_octave::band_energies(&sig[..span], fs)
        .iter()
        .enumerate()
        .filter(|(i, &e)| e > 0.0 && crate::analysis::third_octave::band_centre_hz(*i) < 0.45 * fs)
        .map(|(i, &e)| SpectrumBand {
            centre_hz: crate::analysis::third_octave::band_centre_hz(i),
            level_db: (10.0 * e.log10()).max(-400.0),
        })
        .collect();
    Ok(FittedObject {
        sample_rate_hz: fs,
        modes,
        envelope,
        modal_range_hz: (MIN_MODE_HZ, hi),
        onset_s: onset as f64 / fs,
        duration_s: sig.len() as f64 / fs,
        residual_db,
        peak,
        spectrum,
        play_phase: true,
    })
}

/// The modes of one band: ESPRIT on the band signal, poles mapped back to full rate,
/// amplitudes corrected for the filter's gain at the pole, modes outside [lo, hi) dropped.
fn fit_band(sig: &[f64], fs: f64, band: bands::Band, refine_decays: bool) -> Vec<FitMode> {
    let Some(bs) = bands::BandSignal::new(sig, fs, band, BAND_SAMPLES) else {
        return vec![];
    };
    let Some(mut fit) = subspace::esprit(&bs.samples[bs.start..]) else {
        return vec![];
    };
    let d = bs.decimation as f64;
    let fc = band.centre_hz();
    let start_s = (bs.start * bs.decimation) as f64 / fs;
    // The poles of the band's own modes refined over the whole ring (the same band and
    // decimation, up to `refine::REFINE_SAMPLES` samples, cut where the band has fallen
    // 80 dB or to 3 dB over its noise floor); the others stay in the model as ESPRIT gave
    // them. A refinement that moves a mode out of the band or by more than a quarter of
    // ESPRIT's resolution is not the same mode, and one that makes a decay longer than 20
    // times the span analysed is not measured: the band keeps ESPRIT's poles.
    let mut alpha_sd = vec![0.0; fit.poles.len()];
    let in_band = |z: &Complex<f64>| {
        let f = fc + z.arg() / d * fs / TAU;
        z.norm() > 0.0 && z.norm() < 1.0 && (band.lo_hz..band.hi_hz).contains(&f)
    };
    let all_decaying: Vec<Complex<f64>> = fit
        .poles
        .iter()
        .copied()
        .filter(|z| z.norm() > 0.0 && z.norm() < 1.0)
        .collect();
    let free: Vec<bool> = all_decaying.iter().map(in_band).collect();
    let long = refine_decays
        .then(|| bands::BandSignal::new(sig, fs, band, refine::REFINE_SAMPLES))
        .flatten();
    if let Some(long) = long {
        let y = &long.samples[long.start..];
        let power: Vec<f64> = y.iter().map(|v| v.norm_sqr()).collect();
        let peak = power.iter().fold(0.0f64, |a, &v| a.max(v));
        let mut tail: Vec<f64> = power[power.len() * 9 / 10..].to_vec();
        tail.sort_by(f64::total_cmp);
        let floor = tail.get(tail.len() / 2).copied().unwrap_or(0.0);
        let ring = power
            .iter()
            .rposition(|&v| v > (peak * 1e-8).max(2.0 * floor))
            .map_or(0, |i| i + 1)
            .max(bs.samples.len() - bs.start);
        let window = (bs.samples.len() - bs.start) as f64;
        let span = ring.min(y.len());
        if let Some(r) = refine::refine(&y[..span], &all_decaying, &free) {
            let same = all_decaying
                .iter()
                .zip(&r.poles)
                .zip(&free)
                .all(|((a, b), &f)| {
                    !f || (in_band(b)
                        && (b.arg() - a.arg()).abs() < 0.25 * TAU / window
                        && -b.norm().ln() * 20.0 * span as f64 >= 1.0)
                });
            if same {
                let mut j = 0;
                for (i, z) in fit.poles.iter_mut().enumerate() {
                    if z.norm() > 0.0 && z.norm() < 1.0 {
                        *z = r.poles[j];
                        alpha_sd[i] = r.alpha_sd[j];
                        j += 1;
                    }
                }
            }
        }
    }
    // Full-rate baseband poles of the modes kept.
    let mut poles = Vec::new();
    for (zd, &a_sd) in fit.poles.iter().zip(&alpha_sd) {
        let r = zd.norm();
        if !(r > 0.0 && r < 1.0) {
            continue;
        }
        // z = z_d^{1/D} on the principal branch (|arg| < π/D covers the decimated band).
        let decay_s = -d / (fs * r.ln());
        let w_bb = zd.arg() / d; // rad per full-rate sample
        let freq_hz = fc + w_bb * fs / TAU;
        // A mode must still sound at the first steady sample (after the band filter's
        // transient): one that has fallen below e⁻³ (−26 dB) by then was not observed, only
        // extrapolated (an attack transient, not a resonance), and one shorter than a
        // decimated sample is noise.
        if !(band.lo_hz..band.hi_hz).contains(&freq_hz)
            || decay_s < start_s / 3.0
            || decay_s < d / fs
        {
            continue;
        }
        // τ = D/(f_s·α), α = −ln r: sd(τ) = τ·sd(α)/α.
        let decay_sd_s = decay_s * a_sd / (-r.ln());
        poles.push((
            freq_hz,
            decay_s,
            decay_sd_s,
            Complex::from_polar(r.powf(1.0 / d), w_bb),
        ));
    }
    // All the band's poles (kept or not) explain the band signal jointly; least squares over
    // every decimated sample from t = 0, the filter's transient included (exact basis).
    let all: Vec<Complex<f64>> = fit
        .poles
        .iter()
        .filter(|z| z.norm() < 1.0 + 1e-9 && z.norm() > 0.0)
        .map(|zd| Complex::from_polar(zd.norm().powf(1.0 / d), zd.arg() / d))
        .collect();
    let gains: Vec<Complex<f64>> = all.iter().map(|&z| bs.gain_at(z)).collect();
    let first = (bs.start * bs.decimation / 2)
        .div_ceil(bs.decimation)
        .min(bs.start);
    let rows = &bs.samples[first..];
    let Some(c) = subspace::amplitudes_with(rows, all.len(), |m, k| {
        bs.basis(all[k], m + first, gains[k])
    }) else {
        return vec![];
    };
    let mut out = Vec::new();
    for (freq_hz, decay_s, decay_sd_s, z) in poles {
        let Some(k) = all.iter().position(|&p| p == z) else {
            continue;
        };
        // ×2: the band holds the positive-frequency half of the real cosine.
        let ck = c[k] * 2.0;
        if !ck.norm().is_finite() {
            continue;
        }
        out.push(FitMode {
            freq_hz,
            decay_s,
            amplitude: ck.norm(),
            phase_rad: ck.arg(),
            decay_sd_s,
            glide_hz: 0.0,
            glide_s: 0.0,
        });
    }
    out
}
