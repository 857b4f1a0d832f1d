//! Crackle: a sparse loud layer over the contact's dense floor (docs/MODEL.md, "High band
//! and crackle").
//!
//! Real contacts are not one stationary process: over the dense floor of small events (the
//! impact series) come rare large ones — a stick-slip pop when static friction lets go, a
//! burst when a hard grain is crushed, a stylus hitting dust in the groove. They are what
//! gives a real rub its heavy tails (signal kurtosis 3.6–7.6 in real rubs, scrapes and a
//! stylus, against a Gaussian's 3). Here they are:
//!
//! * **When** — a Poisson process of rate r = [`CRACKLE_MAX_HZ`]·`crackle`·√V (V the speed,
//!   m/s): more pops the faster the contact slides (more stick-slip cycles per second, more
//!   grains crossed), none at rest.
//! * **How strong** — heavy-tailed: a Pareto strength x = (1 − u)^(−1/α) with
//!   α = [`PARETO_ALPHA`] (finite mean, infinite variance: most pops small, a few very
//!   large), capped at [`PARETO_MAX`], times the contact's running force RMS σ_F (its
//!   |F − F̄|² over [`RMS_S`], so the layer scales with the floor it sits on and is silent
//!   without contact) times 10^((6 + 36·`crackle_level`)/20): a typical pop (x = 1) peaks
//!   6 dB (level 0) to 42 dB (level 1) above σ_F.
//! * **What** — each pop a short broadband contact pulse: a raised cosine of
//!   [`CLICK_S`] (0.1 ms, flat to ≈ 10 kHz), pushing (positive), added to the force; it rings
//!   the object like any impact.
//!
//! Deterministic from the seed (SplitMix64), real-time safe (the pulse ring is allocated in
//! `new`). At `crackle` = 0 the voice does not call it: the samples are those without it.

use crate::block::{CHUNK, FLUSH_THRESHOLD};
use crate::params::{ParamId, Params};
use crate::smooth::Smoother;
use crate::source::pulse::{PulseEval, PulseShape, PulseTrain};
use crate::stage::Stage;

/// Pops per second at `crackle` = 1 and V = 1 m/s.
pub const CRACKLE_MAX_HZ: f64 = 60.0;
/// Pareto tail index α of the pops' strengths (α = 2: finite mean, infinite variance before
/// the cap — most pops small, a few very large).
pub const PARETO_ALPHA: f64 = 2.0;
/// Largest pop, in units of the typical one (the Pareto draw is capped here, so the
/// kurtosis a few seconds of pops make does not hang on one draw: with α = 1.5 and a cap of
/// 30 three seeds of one rub gave kurtosis 3.4, 24 and 8.7).
pub const PARETO_MAX: f64 = 10.0;
/// The strongest pop, in the force's own units (the signal model's force, where the voice's
/// loudest floor of impacts peaks near 1–4). A pop is one more contact of the same ball and
/// object — a grain crushed, static friction letting go — not a blow from outside, so however
/// quiet the floor and however high `crackle_level`, no pop pushes harder than this. Without
/// the cap a loud floor (σ_F 0.19 at V 1 on the smallest ball) and the top level made pops
/// 180 in force, 51 dB over the floor's own peaks and +37 dBFS at the output (found by the
/// property test).
pub const POP_MAX_FORCE: f64 = 16.0;
/// Duration of one pop's pulse (s).
pub const CLICK_S: f64 = 1.0e-4;
/// Time constant of the running force RMS the pops are scaled to (s).
pub const RMS_S: f64 = 0.05;
/// The typical pop's peak over the force RMS at `crackle_level` = 0 (dB).
pub const LEVEL_MIN_DB: f64 = 6.0;
/// How much louder the typical pop is at `crackle_level` = 1 than at 0 (dB).
pub const LEVEL_SPAN_DB: f64 = 36.0;

/// The pops' rate (Hz) for `crackle` and speed V: [`CRACKLE_MAX_HZ`]·crackle·√V.
pub fn rate_hz(crackle: f64, velocity: f64) -> f64 {
    CRACKLE_MAX_HZ * crackle.clamp(0.0, 1.0) * velocity.clamp(0.0, 1.0).sqrt()
}

/// A Pareto strength (x_m = 1, α = [`PARETO_ALPHA`], capped at [`PARETO_MAX`]) from a
/// uniform `u` ∈ [0, 1).
pub fn pareto(u: f64) -> f64 {
    (1.0 - u.clamp(0.0, 1.0 - 1e-12))
        .powf(-1.0 / PARETO_ALPHA)
        .min(PARETO_MAX)
}

/// The typical pop's peak over the force RMS for `crackle_level` ∈ [0, 1] (linear).
pub fn level_gain(crackle_level: f64) -> f64 {
    10f64.powf((LEVEL_MIN_DB + LEVEL_SPAN_DB * crackle_level.clamp(0.0, 1.0)) / 20.0)
}

/// The crackle stage.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate the pulse ring; nothing else does.
#[derive(Clone, Debug)]
pub struct Crackle {
    fs: f64,
    seed: u64,
    rng: u64,
    amount: Smoother,
    level: Smoother,
    shape: PulseShape,
    train: PulseTrain,
    /// Exponential time (units of the mean interval) to the next pop.
    wait: f64,
    /// Running mean and mean square of the force.
    mean: f32,
    power: f32,
    /// Samples any pop still reaches, from the next chunk's start.
    ringing: usize,
    buf: [f32; CHUNK],
}

impl Crackle {
    /// A silent stage at `sample_rate_hz` (sanitized) seeded with `seed`.
    pub fn new(sample_rate_hz: f64, params: &Params, seed: u64) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let mut c = Self {
            fs,
            seed,
            rng: 0,
            amount: Smoother::new(params.get(ParamId::Crackle)),
            level: Smoother::new(params.get(ParamId::CrackleLevel)),
            shape: PulseShape::new(1.0, PulseEval::Table),
            train: PulseTrain::new(fs),
            wait: 0.0,
            mean: 0.0,
            power: 0.0,
            ringing: 0,
            buf: [0.0; CHUNK],
        };
        c.reset(seed);
        c
    }

    /// Back to silence, reseeded from `seed`. Real-time safe.
    pub fn reset(&mut self, seed: u64) {
        self.seed = seed;
        self.rng = seed ^ 0xa54f_f53a_5f1d_36f1;
        self.train.reset();
        self.wait = -(1.0 - self.uniform()).ln();
        self.mean = 0.0;
        self.power = 0.0;
        self.ringing = 0;
        self.amount.snap_to_target();
        self.level.snap_to_target();
    }

    /// True when the control is off (target and value 0) and no pop still sounds.
    pub fn is_off(&self) -> bool {
        self.amount.target() == 0.0 && self.amount.value() == 0.0 && self.ringing == 0
    }

    /// A uniform value in [0, 1) (SplitMix64).
    fn uniform(&mut self) -> f64 {
        crate::block::splitmix_uniform(&mut self.rng)
    }

    /// Add one chunk of pops to `force` (whose running RMS scales them); `speed` is the
    /// rolling speed V at the chunk's start and end. Real-time safe.
    pub fn process_chunk(&mut self, force: &mut [f32], speed: (f64, f64)) {
        let n = force.len().min(CHUNK);
        let fs = self.fs;
        let (_, amount) = self.amount.advance(n, fs);
        let (_, level) = self.level.advance(n, fs);
        // The floor the pops sit on: the force's running RMS about its mean.
        let k = 1.0 - (-1.0 / (RMS_S * fs)).exp() as f32;
        for &f in force[..n].iter() {
            self.mean += k * (f - self.mean);
            let d = f - self.mean;
            self.power += k * (d * d - self.power);
        }
        for s in [&mut self.mean, &mut self.power] {
            if s.abs() < FLUSH_THRESHOLD {
                *s = 0.0;
            }
        }
        let sigma = f64::from(self.power).sqrt();
        let rate = rate_hz(amount, 0.5 * (speed.0 + speed.1));
        let width = (CLICK_S * fs).max(2.0);
        let lead = 0.5 * width + 1.0;
        // The Poisson process in units of its mean interval: `wait` left to the next pop.
        let span = rate * n as f64 / fs;
        let mut used = 0.0;
        while rate > 0.0 && used + self.wait <= span {
            used += self.wait;
            self.wait = -(1.0 - self.uniform()).ln();
            let strength = pareto(self.uniform());
            let at = used / span * n as f64;
            let peak = (sigma * level_gain(level) * strength).min(POP_MAX_FORCE);
            if peak > 0.0 {
                self.train
                    .add(&self.shape, at + lead, CLICK_S * fs, peak as f32);
                self.ringing = self.ringing.max((at + lead + width) as usize + 1);
            }
        }
        if rate > 0.0 {
            self.wait -= span - used;
        }
        if self.ringing > 0 {
            let buf = &mut self.buf[..n];
            self.train.read(buf);
            for (f, x) in force[..n].iter_mut().zip(buf.iter()) {
                *f += *x;
            }
            self.ringing = self.ringing.saturating_sub(n);
        }
    }
}

impl Stage for Crackle {
    /// The chunk of force (the pops are added) and the rolling speed at its start and end.
    type Io<'a> = (&'a mut [f32], (f64, f64));

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.train = PulseTrain::new(self.fs);
        Crackle::reset(self, self.seed);
    }

    fn reset(&mut self, seed: u64) {
        Crackle::reset(self, seed);
    }

    fn set_params(&mut self, params: &Params) {
        self.amount.set_target(params.get(ParamId::Crackle));
        self.level.set_target(params.get(ParamId::CrackleLevel));
        if params.seed() != self.seed {
            Crackle::reset(self, params.seed());
        }
    }

    fn snap(&mut self) {
        self.amount.snap_to_target();
        self.level.snap_to_target();
    }

    fn is_idle(&self) -> bool {
        self.is_off() || (self.mean == 0.0 && self.power == 0.0 && self.ringing == 0)
    }

    fn process(&mut self, (force, speed): Self::Io<'_>) {
        self.process_chunk(force, speed);
    }
}
