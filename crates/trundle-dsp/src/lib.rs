//! # trundle-dsp — the sound model of Trundle
//!
//! Rolling (and, on the same engine, rubbing and scratching) sounds by the source–filter
//! model of Conan, Aramaki, Ystad, Kronland-Martinet et al. (the "action–object" paradigm):
//! an **action** — the ball/surface interaction force, a series of micro-impacts with
//! specific statistics — drives an **object**, a Mathews–Smith resonant filter bank.
//!
//! ```text
//!  controls (S size, V velocity, ρ roughness, m asymmetry, ξ sharpness, seed)
//!     │
//!     ▼
//!  series ──────► pulse ──────► modulation ─────────► lowpass ──────┐
//!  (Aⁿ, Δⁿ_T)     φ_ξ(t), t₀(A)  1 + m·sin(2π·3V/S·t)   f_c(V), gain(V) │ force f(t)
//!  ARMA(1,1)                                                          ▼
//!                                              modal (Mathews–Smith phasor bank) ──► out
//!                                              ▲ material (wood/metal/glass disk),
//!                                              │ shape (string/bar/plate/membrane/shell),
//!                                              │ object size, number of modes
//! ```
//!
//! | module | models | paper |
//! |---|---|---|
//! | [`series`] | impact amplitudes Aⁿ and intervals Δⁿ_T, ARMA(1,1) from one Gaussian draw, Table I | TASLP §IV-B, §IV-E, §V-C, Table I |
//! | [`pulse`] | raised-cosine impact pattern with sharpness ξ, t₀ = 7.88·10⁻⁴·S·A^−0.29 s | TASLP eq 9, 12, 16; CMMR eq 3 |
//! | [`contact`] | the ball's and the object's materials: Hertz contact scale on t₀, the low-pass and the physics κ | Johnson §11.4; TASLP §III-E |
//! | [`modulation`] | amplitude modulation 1 + m·sin(2πν_m t), ν_m = 3V/S | TASLP eq 7, 8, 17 |
//! | [`lowpass`] | velocity low-pass and loudness law | CMJ "Navigation strategy", CMMR §3.4 |
//! | [`source`] | the whole action chain: series → pulses → AM → low-pass | TASLP Fig. 5 |
//! | [`material`] | the material disk, damping α(ω) = exp(α_G + α_R·ω) | CMJ "Object part", Aramaki 2011 |
//! | [`shape`] | mode frequency series per object shape | CMJ "Intuitive control" |
//! | [`modal`] | Mathews–Smith complex one-pole ("phasor") filter bank | Mathews & Smith 2003 |
//! | [`voice`] | one ball on one object: source (or physics) + object, smoothing, lifecycle | — |
//! | [`engine_mix`] | the engine choice, the physics controls' smoothing, the crossfade | — |
//! | [`events`] | the one event loop: notes and automation split the block where they fall, acted on at the next 64-sample chunk | — |
//! | [`limiter`] | a look-ahead, stereo-linked safety limiter (−1 dBFS ceiling) | — |
//! | [`engine`] | engine choice; the controls mapped onto the physics (S → R, m_e, κ; V → v; ρ → β, relief) | TASLP §II-A, §III-B, §V-C; Rath 2003 §5 |
//! | [`params`] | the single parameter table (IDs, ranges, units, defaults) | — |
//! | [`analysis`] | impact extraction, ARMA(1,1) Gauss–Newton fit, residual statistics | TASLP §IV-B, §IV-E |
//! | `fit` (feature `fit`) | modal analysis of a recorded strike (band-split ESPRIT), residual envelope | Roy & Kailath 1989; Hua & Sarkar 1990 |
//! | [`surface`], [`physics`] | fractal surface, Rath's rolling filter, Hunt–Crossley ball (RK4) | TASLP §II-A, §III; Rath 2003 |
//!
//! ## Use
//!
//! A parameter set from the one table ([`Params`], [`PARAMS`]), a [`Voice`] that renders it,
//! events at sample offsets ([`events`]), and the analysis that reads the statistics back:
//!
//! ```
//! use trundle_dsp::analysis;
//! use trundle_dsp::events::{process_with_events, TimedEvent, VoiceEvent};
//! use trundle_dsp::{ParamId, Params, Voice};
//!
//! // A rough surface, a slow ball, heard as the raw force (what the analysis reads).
//! let mut params = Params::default();
//! params.set(ParamId::Roughness, 0.8)?;
//! params.set_text("velocity", "0.3 m/s")?; // the table's text format, units accepted
//! params.set_text("output", "force")?;
//!
//! let fs = 48_000.0;
//! let mut voice = Voice::new(fs, &params); // allocates; `process` never does
//! let mut force = vec![0f32; 48_000]; // one second
//!
//! // A second ball (MIDI note 60) joins at 0.5 s (24 000 is on the 64-sample chunk grid).
//! let note = TimedEvent {
//!     offset: 24_000,
//!     event: VoiceEvent::NoteOn { note: 60, velocity: 0.8 },
//! };
//! process_with_events(&mut voice, &mut force, [note], |_, _, _| {});
//! assert!(force.iter().all(|x| x.is_finite()));
//!
//! // The same seed and parameters give the same samples.
//! let mut again = Voice::new(fs, &params);
//! let mut first_half = vec![0f32; 24_000];
//! again.process(&mut first_half);
//! assert_eq!(&force[..24_000], &first_half[..]);
//!
//! // Impacts found in the force: a rolling ball makes hundreds per second.
//! let impacts = analysis::extract_impacts(&force, fs, 0.05);
//! assert!(impacts.len() > 100, "{} impacts", impacts.len());
//! # Ok::<(), trundle_dsp::ParamError>(())
//! ```
//!
//! ## Quantities and units
//!
//! | quantity | symbol | unit | range |
//! |---|---|---|---|
//! | ball size (normalized radius) | S | — | 0.1 … 1 |
//! | ball velocity | V | m/s (normalized, 1 m/s = V 1) | 0 … 1 |
//! | roughness | ρ | — | 0 … 1 |
//! | asymmetry (AM depth) | m | — | 0 … 1 |
//! | pulse sharpness | ξ | — | 0.5 … 8 |
//! | impact interval | Δ_T | s | > 0 |
//! | pulse duration | t₀ | s | bounded, see [`pulse`] |
//! | mode frequency | f | Hz | 20 Hz … Nyquist |
//! | mode decay time (1/e) | τ | s | 0.2 ms … 60 s |
//!
//! ## Lifecycle (every DSP type)
//!
//! 1. `new(…)` — the only place that allocates (with `set_sample_rate`); documented in an
//!    `# Allocation` section.
//! 2. `set_sample_rate(fs)` — may allocate; call off the audio thread.
//! 3. `reset()` — real-time safe, restores the state after `new` and reseeds the random
//!    generator: the same seed and parameters give the same samples.
//! 4. `process(&mut [f32])` — real-time safe: no allocation, locking, logging or I/O, any
//!    block length (the output is identical whatever the block size).
//!
//! Decaying state is kept out of the subnormal range by the core itself (state below
//! [`FLUSH_THRESHOLD`] is flushed to zero between internal chunks); nothing relies on the
//! host's floating-point mode.

#![warn(missing_docs)]

pub mod action;
pub mod analysis;
pub mod balls;
pub mod contact;
pub mod crowd;
pub mod dcblock;
pub mod disk;
pub mod engine;
pub mod engine_mix;
pub mod events;
#[cfg(feature = "fit")]
pub mod fit;
pub mod gesture;
pub mod limiter;
pub mod lowpass;
pub mod material;
pub mod modal;
pub mod modulation;
pub mod object;
pub mod params;
pub mod physics;
#[cfg(feature = "presets")]
pub mod preset;
pub mod pulse;
pub mod series;
pub mod shape;
pub mod smooth;
pub mod source;
pub mod space;
pub mod surface;
pub mod voice;

pub use params::{ParamError, ParamId, ParamSpec, Params, PARAMS};
pub use source::{ImpactRecord, Source};
pub use voice::Voice;

/// Magnitude under which recursive state is flushed to exact zero (far above the f32
/// subnormal limit 1.18·10⁻³⁸ and far below audibility, −400 dBFS).
pub const FLUSH_THRESHOLD: f32 = 1.0e-20;

/// Largest block the core processes in one internal chunk; longer blocks are split. State
/// flushing and coefficient updates happen between chunks, so this also bounds how long a
/// parameter ramp step lasts.
pub const CHUNK: usize = 64;

/// Lowest sample rate the core accepts (Hz).
pub const MIN_SAMPLE_RATE_HZ: f64 = 8_000.0;
/// Highest sample rate the core accepts (Hz).
pub const MAX_SAMPLE_RATE_HZ: f64 = 384_000.0;

/// Clamp a host-supplied sample rate into the supported range; a non-finite rate becomes
/// 48 kHz. Returns the rate the core will run at.
pub fn sanitize_sample_rate(sample_rate_hz: f64) -> f64 {
    if sample_rate_hz.is_finite() {
        sample_rate_hz.clamp(MIN_SAMPLE_RATE_HZ, MAX_SAMPLE_RATE_HZ)
    } else {
        48_000.0
    }
}
