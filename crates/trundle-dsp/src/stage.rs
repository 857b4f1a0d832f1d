//! One lifecycle for every stage of the voice: the object, the source, the space, the crowd,
//! the gestures, the engine mix, the note balls, the DC blocker and the limiter all implement
//! [`Stage`], and controls reach every one of them the same way, from the one parameter set
//! ([`Stage::set_params`]).
//!
//! | step | when | may allocate |
//! |---|---|---|
//! | `new(…)` (each stage's own) | building the voice | yes |
//! | [`Stage::set_sample_rate`] | the host changes the rate; resets | yes (call off the audio thread) |
//! | [`Stage::reset`] | back to the state after `new`, reseeded | no |
//! | [`Stage::set_params`] | new control targets (continuous ones glide) | no |
//! | [`Stage::snap`] | the first chunk of a render starts at the targets | no |
//! | [`Stage::is_idle`] | a chunk would change nothing but time | no |
//! | [`Stage::process`] | one chunk of at most [`crate::block::CHUNK`] samples | no |
//!
//! Processing is statically dispatched (each stage's [`Stage::Io`] is what it reads and
//! writes in a chunk); the voice ([`crate::scene::voice`]) lists its stages once and fans
//! every lifecycle call out over that list.

use crate::params::Params;

/// A stage of the voice: one lifecycle (see the module docs).
pub trait Stage {
    /// What one chunk of processing reads and writes (buffers, the scene's state).
    type Io<'a>;

    /// Change the sample rate (sanitized by the stage) and reset. May allocate: call off
    /// the audio thread.
    fn set_sample_rate(&mut self, sample_rate_hz: f64);

    /// Back to the state after `new` with the current control targets, random generators
    /// reseeded from `seed`: the same seed and parameters give the same samples.
    /// Real-time safe.
    fn reset(&mut self, seed: u64);

    /// Take this stage's controls from the parameter set: targets that glide, choices that
    /// apply at the next chunk; a changed seed restarts what it seeds. Real-time safe.
    fn set_params(&mut self, params: &Params);

    /// Jump every glide to its target (the first chunk of a render). Real-time safe.
    fn snap(&mut self);

    /// True when processing a chunk would change nothing but time (nothing sounds, rings
    /// or glides).
    fn is_idle(&self) -> bool;

    /// Process one chunk. Real-time safe: no allocation, locking, logging or I/O.
    fn process(&mut self, io: Self::Io<'_>);
}
