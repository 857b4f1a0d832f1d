//! # trundle-dsp — the sound model of Trundle
//!
//! Rolling (and, on the same engine, rubbing and scratching) sounds by the source–filter
//! model of Conan, Aramaki, Ystad, Kronland-Martinet et al. (the "action–object" paradigm):
//! an **action** — the ball/surface interaction force, a series of micro-impacts with
//! specific statistics — drives an **object**, a Mathews–Smith resonant filter bank.
//!
//! The voice is a chain of stages ([`stage::Stage`], one lifecycle), each in the folder of
//! what it models:
//!
//! ```text
//!  Params (one table) ──► every stage's controls (Stage::set_params)
//!
//!  source::chain ─────────► scene::engine_mix ──► scene::gesture ──► scene::space ──► + scene::balls
//!  series → pulse → AM      signal model, or       drops, spins,     position comb      (note balls)
//!  → low-pass (the force)   physics (Hunt–Crossley  seams                                + scene::crowd
//!                           ball, RK4), crossfade                                         (N balls)
//!                                                                                            │ force f(t)
//!        ┌───────────────────────────────────────────────────────────────────────────────────┘
//!        ▼
//!  source::dcblock ──► object::resonator (Mathews–Smith phasor bank; material disk, shape,
//!                      size, modes, high band, or a fitted object) ──► mid, side ──► gain ──► out
//!                      scene::twins: the same object for the physics engine's level match
//!  (scene::limiter, the output safety limiter, runs after the voice in the plugin and the CLI)
//! ```
//!
//! The crate is layered; a module imports only from its own layer or the ones before it:
//!
//! ```text
//!  block, smooth ─► params ─► stage ─► analysis ─► object ─► source ─► physics ─► scene ─► fit
//! ```
//!
//! | module | models | paper |
//! |---|---|---|
//! | [`block`] | the internal chunk, the flush threshold, the supported sample rates (a leaf) | — |
//! | [`smooth`] | the one-pole control smoother | — |
//! | [`params`] | the single parameter table (IDs, ranges, units, defaults) | — |
//! | [`stage`] | the one lifecycle every stage of the voice implements | — |
//! | [`analysis`] | impact extraction, ARMA(1,1) Gauss–Newton fit, residual statistics; the Toeplitz solver | TASLP §IV-B, §IV-E; Levinson 1947 |
//! | [`object`] | the resonant object: shape × material × size → a Mathews–Smith phasor bank heard at two pickups, a high band, fitted objects | CMJ "Object part"; Mathews & Smith 2003; Aramaki 2011 |
//! | [`source`] | the signal model of the force: impact series (Table I, the action disk), pulses, AM, low-pass, Hertz contact; the contact's high band (micro-roughness) and crackle | TASLP §IV–V, Fig. 5; Johnson §11.4 |
//! | [`physics`] | fractal surface, Rath's rolling filter, Hunt–Crossley ball (RK4); the controls mapped onto it; the elasto-plastic stick-slip friction contact on the object's modes | TASLP §II-A, §III; Rath 2003; Dupont et al. 2002; Avanzini, Serafin & Rocchesso 2005 |
//! | [`scene`] | the voice and what it plays: balls, crowd, gestures, space, engine mix, limiter, events, presets | — |
//! | `fit` (feature `fit`) | modal analysis of a recorded strike (band-split ESPRIT), residual envelope, roll fitting | Roy & Kailath 1989; Hua & Sarkar 1990 |
//!
//! ## Use
//!
//! A parameter set from the one table ([`Params`], [`PARAMS`]), a [`Voice`] that renders it,
//! events at sample offsets ([`scene::events`]), and the analysis that reads the statistics back:
//!
//! ```
//! use trundle_dsp::analysis::impacts;
//! use trundle_dsp::scene::events::{process_with_events, TimedEvent, VoiceEvent};
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
//! let impacts = impacts::extract_impacts(&force, fs, 0.05);
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
//! | pulse duration | t₀ | s | bounded, see [`source::pulse`] |
//! | mode frequency | f | Hz | 20 Hz … Nyquist |
//! | mode decay time (1/e) | τ | s | 0.2 ms … 60 s |
//!
//! ## Lifecycle (every stage, [`stage::Stage`])
//!
//! 1. `new(…)` — the only place that allocates (with `set_sample_rate`); documented in an
//!    `# Allocation` section.
//! 2. `set_sample_rate(fs)` — may allocate; call off the audio thread.
//! 3. `reset(seed)` — real-time safe, restores the state after `new` and reseeds the random
//!    generators: the same seed and parameters give the same samples.
//! 4. `set_params(&Params)` — real-time safe: the stage takes its controls from the one
//!    parameter table (continuous ones glide).
//! 5. `process(…)` — real-time safe: no allocation, locking, logging or I/O; statically
//!    dispatched. The voice renders any block length in chunks of [`block::CHUNK`] (the
//!    output is identical whatever the block size).
//!
//! Decaying state is kept out of the subnormal range by the core itself (state below
//! [`block::FLUSH_THRESHOLD`] is flushed to zero between internal chunks); nothing relies on the
//! host's floating-point mode.

#![warn(missing_docs)]

pub mod analysis;
pub mod block;
#[cfg(feature = "fit")]
pub mod fit;
pub mod object;
pub mod params;
pub mod physics;
pub mod scene;
pub mod smooth;
pub mod source;
pub mod stage;

pub use params::{ParamError, ParamId, ParamSpec, Params, PARAMS};
pub use scene::voice::Voice;
pub use source::chain::{ImpactRecord, Source};
