//! Bumps (docs/MODEL.md, "Slow textures: bumps, strokes, a hand"): the slow broadband events
//! of a real surface — a stone under a wheel, a flat spot, an uneven board.
//!
//! Bumps come at random at about `bump_rate_hz`: the intervals are gamma-distributed of shape
//! 2 (the sum of two exponential draws, mean 1/rate), irregular like a Poisson process but
//! rarely two at once. Each bump has a strength X drawn exponential of mean 1 (many small
//! stones, a few big ones; capped at [`MAX_STRENGTH`]) and is two things at once:
//!
//! * a **knock**: one strong impact through the same contact and pulse shaping as the rolling
//!   impacts and the gesture's ([`crate::scene::gesture::pulse_scale`]), of series-amplitude
//!   A = [`KNOCK_GAIN`]·b·X·V^1.2 (b = `bumpiness`, V the rolling speed in m/s; Hertz's peak
//!   force ∝ v^(6/5), as the gesture's bounces). A large A makes a short pulse (duration
//!   ζ·A^−θ), so a knock is broadband and rings every mode of the object at once;
//! * a **swell** of the contact force while the ball rides over it: the force × (1 +
//!   [`SWELL_GAIN`]·b·X·e(t)), e(t) ∝ e^(−t/[`SWELL_DECAY_S`]) − e^(−t/[`SWELL_ATTACK_S`])
//!   (peak 1).
//!
//! Both act on every band together: the band envelopes' cross-band correlation rises (real
//! wheels 0.58 in issue #25's audit, Trundle 0.29 before) and so does their 0.5–4 Hz
//! modulation. Everything follows from the seed; the swell moves once per chunk (linear
//! within it), the knocks are placed to the sample. With `bumpiness` 0 (and nothing still
//! sounding) the stage is neutral: the voice's samples are those of a voice without it, bit
//! for bit.

use crate::block::CHUNK;
use crate::params::{ParamId, Params};
use crate::scene::gesture::{pulse_scale, PulseScale, HERTZ_EXPONENT};
use crate::source::chain::Source;
use crate::source::pulse::{duration_s, PulseEval, PulseShape, PulseTrain, T0_MAX_S};
use crate::stage::Stage;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// Series-amplitude equivalent of a knock of strength 1 at bumpiness 1 and 1 m/s.
pub const KNOCK_GAIN: f64 = 4.0;
/// The swell's peak gain on the contact force for a bump of strength 1 at bumpiness 1
/// (× (1 + this) at its peak).
pub const SWELL_GAIN: f64 = 3.0;
/// The swell's rise time constant (s).
pub const SWELL_ATTACK_S: f64 = 0.01;
/// The swell's decay time constant (s): a ball riding over a stone.
pub const SWELL_DECAY_S: f64 = 0.12;
/// Largest bump strength X (its exponential law cut here).
pub const MAX_STRENGTH: f64 = 4.0;

/// The bumps' controls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BumpControls {
    /// Bumpiness 0…1 (0 = a smooth surface).
    pub bumpiness: f64,
    /// Mean rate of the bumps (Hz).
    pub rate_hz: f64,
    /// Pulse sharpness ξ (the knocks' shape, as the rolling impacts').
    pub sharpness: f64,
}

impl BumpControls {
    /// The controls from a parameter set.
    pub fn from_params(p: &Params) -> Self {
        Self {
            bumpiness: p.get(ParamId::Bumpiness),
            rate_hz: p.get(ParamId::BumpRateHz),
            sharpness: p.get(ParamId::Sharpness),
        }
    }
}

/// Peak of e^(−t/τ_d) − e^(−t/τ_a) (at t* = ln(τ_d/τ_a)·τ_a·τ_d/(τ_d − τ_a)).
fn swell_peak() -> f64 {
    let (a, d) = (SWELL_ATTACK_S, SWELL_DECAY_S);
    let t = (d / a).ln() * a * d / (d - a);
    (-t / d).exp() - (-t / a).exp()
}

/// The bumps stage.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate the pulse ring; nothing else allocates.
#[derive(Clone, Debug)]
pub struct Bumps {
    fs: f64,
    c: BumpControls,
    shape: PulseShape,
    train: PulseTrain,
    buf: [f32; CHUNK],
    /// Samples since the reset.
    now: f64,
    /// The next bump (s since the reset; infinite when none is due).
    next_s: f64,
    /// The swell's slow and fast exponentials (their difference is the swell).
    slow: f64,
    fast: f64,
    /// 1 / the swell's peak.
    norm: f64,
    /// Last sample any knock reaches (samples since reset).
    ring_until: f64,
    rng: SmallRng,
    seed: u64,
}

impl Bumps {
    /// A bumps stage at `sample_rate_hz` (sanitized) with `c`, seeded with `seed`.
    pub fn new(sample_rate_hz: f64, c: BumpControls, seed: u64) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let mut b = Self {
            fs,
            c,
            shape: PulseShape::new(c.sharpness.clamp(0.5, 8.0), PulseEval::Table),
            train: PulseTrain::new(fs),
            buf: [0.0; CHUNK],
            now: 0.0,
            next_s: f64::INFINITY,
            slow: 0.0,
            fast: 0.0,
            norm: 1.0 / swell_peak(),
            ring_until: 0.0,
            rng: SmallRng::seed_from_u64(seed),
            seed,
        };
        b.reset(seed);
        b
    }

    /// Change the sample rate (allocates the pulse ring) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.train = PulseTrain::new(self.fs);
        self.reset(self.seed);
    }

    /// Back to time 0 with `seed`. Real-time safe.
    pub fn reset(&mut self, seed: u64) {
        self.seed = seed;
        self.rng = SmallRng::seed_from_u64(seed ^ 0xbb67_ae85_84ca_a73b);
        self.now = 0.0;
        self.train.reset();
        self.ring_until = 0.0;
        self.slow = 0.0;
        self.fast = 0.0;
        self.shape.snap_sharpness(self.c.sharpness.clamp(0.5, 8.0));
        self.next_s = f64::INFINITY;
        self.arm();
    }

    /// New controls; they apply from now. Real-time safe.
    pub fn set_controls(&mut self, c: BumpControls) {
        self.c = c;
        self.shape.set_sharpness(c.sharpness.clamp(0.5, 8.0));
        self.arm();
    }

    /// The controls in force.
    pub fn controls(&self) -> &BumpControls {
        &self.c
    }

    /// Schedule the next bump from now if bumps are on and none is due; forget it if off.
    fn arm(&mut self) {
        if self.c.bumpiness > 0.0 {
            if !self.next_s.is_finite() {
                self.next_s = self.now / self.fs + self.interval_s();
            }
        } else {
            self.next_s = f64::INFINITY;
        }
    }

    /// A gamma (shape 2) interval of mean 1/rate.
    fn interval_s(&mut self) -> f64 {
        let rate = self.c.rate_hz.clamp(0.01, 1000.0);
        let (u, v): (f64, f64) = (self.rng.random(), self.rng.random());
        -((1.0 - u) * (1.0 - v)).ln() / (2.0 * rate)
    }

    /// True when the stage changes nothing: no bumps, no swell, no knock sounding.
    pub fn is_neutral(&self) -> bool {
        self.c.bumpiness <= 0.0
            && self.slow == 0.0
            && self.fast == 0.0
            && self.now >= self.ring_until
    }

    /// The swell's gain now.
    fn gain(&self) -> f64 {
        1.0 + SWELL_GAIN * self.norm * (self.slow - self.fast)
    }

    /// One chunk (`force.len() ≤ CHUNK`): the force × the swell, then the knocks added; time
    /// moves on. `speed` is the rolling speed V (m/s) at the chunk's start and end. Real-time
    /// safe.
    pub fn process(&mut self, force: &mut [f32], k: PulseScale, speed: (f64, f64)) {
        let n = force.len().min(CHUNK);
        if self.is_neutral() {
            self.now += n as f64;
            return;
        }
        let fs = self.fs;
        let lead = 0.5 * T0_MAX_S * fs + 1.0;
        let g0 = self.gain();
        // The swell decays over the chunk; bumps in it kick it at its end.
        let dt = n as f64 / fs;
        self.slow *= (-dt / SWELL_DECAY_S).exp();
        self.fast *= (-dt / SWELL_ATTACK_S).exp();
        let b = self.c.bumpiness.clamp(0.0, 1.0);
        while self.next_s * fs - self.now < n as f64 {
            let s = (self.next_s * fs - self.now).max(0.0);
            let u: f64 = self.rng.random();
            let x = (-(1.0 - u).ln()).min(MAX_STRENGTH);
            let v = (speed.0 + (speed.1 - speed.0) * s / n as f64).max(0.0);
            let a = KNOCK_GAIN * b * x * v.powf(HERTZ_EXPONENT);
            if a > 0.0 {
                // Played `lead` samples late, so its pulse is never cut.
                let center = s + lead;
                let t0 = duration_s(k.zeta_s, k.theta, a);
                self.train
                    .add(&self.shape, center, t0 * fs, (a * k.gain) as f32);
                let hw = 0.5 * (t0 * fs).max(2.0);
                self.ring_until = self.ring_until.max(self.now + center + hw + 1.0);
                self.slow += b * x;
                self.fast += b * x;
            }
            self.next_s += self.interval_s();
        }
        if b <= 0.0 {
            self.next_s = f64::INFINITY;
        }
        if self.slow.abs() < 1e-9 && self.fast.abs() < 1e-9 {
            // Rung out: the gain is exactly 1 again.
            self.slow = 0.0;
            self.fast = 0.0;
        }
        let g1 = self.gain();
        if g0 != 1.0 || g1 != 1.0 {
            let step = (g1 - g0) / n as f64;
            for (i, f) in force[..n].iter_mut().enumerate() {
                *f *= (g0 + step * (i + 1) as f64) as f32;
            }
        }
        if self.now < self.ring_until {
            let buf = &mut self.buf[..n];
            self.train.read(buf);
            for (f, x) in force[..n].iter_mut().zip(buf.iter()) {
                *f += *x;
            }
        }
        self.now += n as f64;
    }
}

impl Stage for Bumps {
    /// The chunk of force (the whole scene's) the bumps swell and knock, the scene ball's
    /// source (how a knock becomes a pulse), the ball's size and its rolling speed at the
    /// chunk's start and end.
    type Io<'a> = (&'a mut [f32], &'a Source, f64, (f64, f64));

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        Bumps::set_sample_rate(self, sample_rate_hz);
    }

    fn reset(&mut self, seed: u64) {
        Bumps::reset(self, seed);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_controls(BumpControls::from_params(params));
    }

    /// The bumps keep their own schedule: nothing glides.
    fn snap(&mut self) {}

    fn is_idle(&self) -> bool {
        self.is_neutral()
    }

    fn process(&mut self, (force, source, size, speed): (&mut [f32], &Source, f64, (f64, f64))) {
        if self.is_neutral() {
            self.now += force.len().min(CHUNK) as f64;
        } else {
            Bumps::process(self, force, pulse_scale(source, size), speed);
        }
    }
}
