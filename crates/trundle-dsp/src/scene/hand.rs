//! A hand, not a machine (docs/MODEL.md, "Slow textures: bumps, strokes, a hand"): the
//! slow motion of whoever pushes the ball, as a factor on its rolling speed and a gain on its
//! contact force.
//!
//! * **strokes** — periodic back-and-forth gestures (sawing, scrubbing, sanding) at
//!   `stroke_rate_hz` strokes per second, each one way. Within a stroke (phase u ∈ [0, 1))
//!   the speed follows |stroke velocity| p(u) = min(1, sin(πu)/sin(πh)), a sine clipped at
//!   the speed it reaches a fraction h = ½ − (½ − [`STROKE_SHARPEST`])·shape into the stroke:
//!   a smooth sine back-and-forth at shape 0 (h = ½), a hard push held through the stroke
//!   with a quick turn-around at shape 1 (the speed falls to zero and rises again within
//!   h = [`STROKE_SHARPEST`] of a stroke each side of the turn). With depth d the rolling
//!   speed is V·(1 − d + d·p(u)·peak), so at d = 1 it passes through zero at every
//!   turn-around; the contact force (the pressure) swells with it,
//!   × (1 − d·[`STROKE_PRESSURE`]·(1 − p(u)·peak)). Each stroke's length and peak are drawn anew (log-normal, [`STROKE_LENGTH_JITTER`], [`STROKE_PEAK_JITTER`]): a hand, not a
//!   metronome. Speed and force move together, so every band of the sound swells at the
//!   stroke rate (the sawing of issue #25's audit: cross-band envelope correlation 0.21 and a
//!   modulation peak near 2 Hz). Every other stroke is the return, its pressure × `stroke_return`
//!   (a hand saw cuts on the push and is drawn back lighter: the corpus's hand saw swells
//!   loud–soft–loud, its log envelope correlating 0.71 over a push and pull and 0.36 over one
//!   stroke), so at a return under 1 the level repeats every two strokes. The first stroke is a
//!   push.
//! * **wander** — slow random wander of speed and pressure, 1/f-like: the sum of
//!   [`WANDER_CORNERS_HZ`]'s octave-spaced Ornstein–Uhlenbeck random walks (each a one-pole
//!   smoothed white noise of unit variance, corner f_k; equal variance per octave is a 1/f
//!   spectrum between the corners, the 1/f fluctuation of human timing, Gilden,
//!   Thornton & Mallon 1995, "1/f noise in human cognition", Science 267), normalized to unit variance, z(t). The speed factor is
//!   exp(d·[`WANDER_SPEED_LN`]·z): log-normal, so at depth d = 1 one standard deviation is
//!   ×1.6 up and ÷1.6 down (about ±60 %), and the envelopes skew towards loud moments as real
//!   ones do. The pressure wanders as exp(d·[`WANDER_PRESSURE_LN`]·z_p), z_p sharing
//!   [`WANDER_PRESSURE_SHARE`] of the speed's walk (a hand pressing harder as it goes faster).
//!
//! The state moves once per chunk ([`CHUNK`] samples; the gain is interpolated linearly within
//! it), every random number comes from the seed: deterministic, independent of the host's
//! block size, allocation-free. With both depths 0 the stage is neutral and the voice does not
//! touch it: the samples are those of a voice without it, bit for bit.

use crate::block::CHUNK;
use crate::params::{ParamId, Params};
use crate::smooth::Smoother;
use crate::stage::Stage;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;

/// Corners of the wander's random walks (Hz), an octave apart.
pub const WANDER_CORNERS_HZ: [f64; 7] = [0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0];
/// The wander's speed swing at depth 1: ln of the factor one standard deviation reaches
/// (ln 1.6).
pub const WANDER_SPEED_LN: f64 = 0.47;
/// The wander's pressure swing at depth 1: ln of the gain one standard deviation reaches
/// (ln 1.4).
pub const WANDER_PRESSURE_LN: f64 = 0.336;
/// Correlation of the pressure's wander with the speed's.
pub const WANDER_PRESSURE_SHARE: f64 = 0.6;
/// How far the pressure falls at a turn-around at stroke depth 1 (a fraction of it).
pub const STROKE_PRESSURE: f64 = 0.5;
/// The fraction of a stroke its speed takes to rise from a turn-around to full at shape 1
/// (at shape 0 it is ½: a sine).
pub const STROKE_SHARPEST: f64 = 0.06;
/// Standard deviation of ln of a stroke's length (its duration around 1/rate).
pub const STROKE_LENGTH_JITTER: f64 = 0.12;
/// Standard deviation of ln of a stroke's peak speed.
pub const STROKE_PEAK_JITTER: f64 = 0.15;
/// The largest share of a stroke the body can be lifted for (the rest, at least a fifth,
/// is the stroke).
pub const STROKE_LIFT_MAX: f64 = 0.8;
/// Phase a render starts at: mid-stroke, at full speed (not silent at its first sample).
pub const STROKE_START_PHASE: f64 = 0.5;

/// The hand's controls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandControls {
    /// Stroke depth 0…1 (0 = a steady push).
    pub strokes: f64,
    /// Strokes per second, each one way (Hz).
    pub stroke_rate_hz: f64,
    /// Stroke shape 0…1 (0 = sine, 1 = hard push, quick turn-around).
    pub stroke_shape: f64,
    /// The share of each stroke the rubbing body is lifted off, 0…[`STROKE_LIFT_MAX`].
    pub stroke_lift: f64,
    /// The return stroke's pressure, a share of the push's, 0…1 (1 = both ways alike).
    pub stroke_return: f64,
    /// Wander depth 0…1 (0 = a steady hand).
    pub wander: f64,
    /// The fastest wander walk's corner (Hz): walks above it are left out ([`walk_weight`]).
    pub wander_rate_hz: f64,
}

impl HandControls {
    /// The controls from a parameter set.
    pub fn from_params(p: &Params) -> Self {
        Self {
            strokes: p.get(ParamId::Strokes),
            stroke_rate_hz: p.get(ParamId::StrokeRateHz),
            stroke_shape: p.get(ParamId::StrokeShape),
            stroke_lift: p.get(ParamId::StrokeLift),
            stroke_return: p.get(ParamId::StrokeReturn),
            wander: p.get(ParamId::Wander),
            wander_rate_hz: p.get(ParamId::WanderRateHz),
        }
    }
}

/// The weight of the wander's walk of corner `corner_hz` when the fastest walk is
/// `rate_hz`: 1 at or below the rate, falling to 0 an octave above it, linearly in octaves
/// (log₂(rate/corner) + 1, held within [0, 1]), so the rate glides smoothly across the
/// corners. At the highest corner (8 Hz, the default) every weight is exactly 1.
pub fn walk_weight(corner_hz: f64, rate_hz: f64) -> f64 {
    ((rate_hz / corner_hz).log2() + 1.0).clamp(0.0, 1.0)
}

/// Every walk's [`walk_weight`] at `rate_hz` and 1/√Σweight², the factor that brings their
/// weighted sum to unit variance. Computed when the rate changes, not per chunk; a
/// non-finite rate counts as the highest corner (every walk in).
pub fn walk_weights(rate_hz: f64) -> ([f64; WANDER_CORNERS_HZ.len()], f64) {
    let rate_hz = if rate_hz.is_finite() {
        rate_hz
    } else {
        WANDER_CORNERS_HZ[WANDER_CORNERS_HZ.len() - 1]
    };
    let weights = WANDER_CORNERS_HZ.map(|f| walk_weight(f, rate_hz));
    let energy: f64 = weights.iter().map(|k| k * k).sum();
    (weights, 1.0 / energy.max(1e-12).sqrt())
}

/// |stroke velocity| at phase `u` ∈ [0, 1] of a stroke of shape `shape` ∈ [0, 1]:
/// min(1, sin(πu)/sin(πh)), h = ½ − (½ − [`STROKE_SHARPEST`])·shape; 0 at both turn-arounds,
/// 1 mid-stroke (from h to 1 − h).
pub fn stroke_profile(u: f64, shape: f64) -> f64 {
    let h = 0.5 - (0.5 - STROKE_SHARPEST) * shape.clamp(0.0, 1.0);
    let pi = core::f64::consts::PI;
    ((pi * u.clamp(0.0, 1.0)).sin().max(0.0) / (pi * h).sin()).min(1.0)
}

/// The hand stage: a factor on the rolling speed ([`Hand::speed_factor`]) and a gain on the
/// contact force ([`Stage::process`]).
///
/// # Allocation
/// Nothing allocates.
#[derive(Clone, Debug)]
pub struct Hand {
    fs: f64,
    c: HandControls,
    strokes: Smoother,
    wander: Smoother,
    /// Phase within the stroke, 0…1.
    phase: f64,
    /// This stroke's length (× 1/rate) and peak speed (× V).
    length: f64,
    peak: f64,
    /// This stroke is a return (every other one; the first is a push).
    returning: bool,
    /// The random walks of the speed and of the pressure's own part (unit variance each).
    walks: [f64; WANDER_CORNERS_HZ.len()],
    walks_p: [f64; WANDER_CORNERS_HZ.len()],
    /// The walks' weights at the wander's rate and their unit-variance factor
    /// ([`walk_weights`]).
    weights: [f64; WANDER_CORNERS_HZ.len()],
    weights_norm: f64,
    /// Speed factor and force gain now (at the chunk boundary).
    speed: f64,
    gain: f64,
    rng: SmallRng,
    seed: u64,
}

impl Hand {
    /// A hand at `sample_rate_hz` (sanitized) with `c`, seeded with `seed`.
    pub fn new(sample_rate_hz: f64, c: HandControls, seed: u64) -> Self {
        let (weights, weights_norm) = walk_weights(c.wander_rate_hz);
        let mut h = Self {
            fs: crate::block::sanitize_sample_rate(sample_rate_hz),
            c,
            strokes: Smoother::new(c.strokes.clamp(0.0, 1.0)),
            wander: Smoother::new(c.wander.clamp(0.0, 1.0)),
            phase: STROKE_START_PHASE,
            length: 1.0,
            peak: 1.0,
            returning: false,
            walks: [0.0; WANDER_CORNERS_HZ.len()],
            walks_p: [0.0; WANDER_CORNERS_HZ.len()],
            weights,
            weights_norm,
            speed: 1.0,
            gain: 1.0,
            rng: SmallRng::seed_from_u64(seed),
            seed,
        };
        h.reset(seed);
        h
    }

    /// Back to time 0 with `seed`: mid-stroke, the walks drawn from their stationary law.
    /// Real-time safe.
    pub fn reset(&mut self, seed: u64) {
        self.seed = seed;
        self.rng = SmallRng::seed_from_u64(seed ^ 0x3c6e_f372_fe94_f82b);
        self.strokes.snap_to_target();
        self.wander.snap_to_target();
        self.phase = STROKE_START_PHASE;
        self.returning = false;
        self.new_stroke();
        for i in 0..WANDER_CORNERS_HZ.len() {
            self.walks[i] = self.rng.sample(StandardNormal);
            self.walks_p[i] = self.rng.sample(StandardNormal);
        }
        self.update_outputs();
    }

    /// New control targets (the depths glide). Real-time safe.
    pub fn set_controls(&mut self, c: HandControls) {
        if c.wander_rate_hz.to_bits() != self.c.wander_rate_hz.to_bits() {
            (self.weights, self.weights_norm) = walk_weights(c.wander_rate_hz);
        }
        self.c = c;
        self.strokes.set_target(c.strokes.clamp(0.0, 1.0));
        self.wander.set_target(c.wander.clamp(0.0, 1.0));
    }

    /// The controls in force.
    pub fn controls(&self) -> &HandControls {
        &self.c
    }

    /// True when the hand changes nothing: both depths 0 and at rest there.
    pub fn is_neutral(&self) -> bool {
        self.strokes.target() == 0.0
            && self.strokes.value() == 0.0
            && self.wander.target() == 0.0
            && self.wander.value() == 0.0
    }

    /// The factor on the rolling speed now, `None` when the hand is neutral.
    pub fn speed_factor(&self) -> Option<f64> {
        (!self.is_neutral()).then_some(self.speed)
    }

    /// The gain on the contact force now (1 when neutral).
    pub fn pressure(&self) -> f64 {
        if self.is_neutral() {
            1.0
        } else {
            self.gain
        }
    }

    /// Draw the next stroke's length and peak.
    fn new_stroke(&mut self) {
        let a: f64 = self.rng.sample(StandardNormal);
        let b: f64 = self.rng.sample(StandardNormal);
        self.length = (STROKE_LENGTH_JITTER * a.clamp(-3.0, 3.0)).exp();
        self.peak = (STROKE_PEAK_JITTER * b.clamp(-3.0, 3.0)).exp();
    }

    /// The speed factor and force gain of the state now.
    fn update_outputs(&mut self) {
        let d = self.strokes.value();
        let (mut speed, mut gain) = (1.0, 1.0);
        if d > 0.0 {
            // The stroke plays in the first 1 − lift of the phase; then the body is off.
            let touching = 1.0 - self.c.stroke_lift.clamp(0.0, STROKE_LIFT_MAX);
            if self.phase < touching {
                let p = stroke_profile(self.phase / touching, self.c.stroke_shape) * self.peak;
                speed = 1.0 - d + d * p;
                gain = 1.0 - d * STROKE_PRESSURE * (1.0 - p);
                if self.returning {
                    // The return presses lighter, by the depth's share.
                    gain *= 1.0 - d * (1.0 - self.c.stroke_return.clamp(0.0, 1.0));
                }
            } else {
                speed = 1.0 - d;
                gain = 1.0 - d;
            }
        }
        let w = self.wander.value();
        if w > 0.0 {
            // The walks below the rate, weighted and summed to unit variance.
            let (mut z, mut own) = (0.0, 0.0);
            for ((&k, &a), &b) in self.weights.iter().zip(&self.walks).zip(&self.walks_p) {
                z += k * a;
                own += k * b;
            }
            let (z, own) = (z * self.weights_norm, own * self.weights_norm);
            let s = WANDER_PRESSURE_SHARE;
            let zp = s * z + (1.0 - s * s).sqrt() * own;
            speed *= (w * WANDER_SPEED_LN * z).exp();
            gain *= (w * WANDER_PRESSURE_LN * zp).exp();
        }
        self.speed = speed.max(0.0);
        self.gain = gain.max(0.0);
    }

    /// Move the hand on by `n` samples.
    fn advance(&mut self, n: usize) {
        let dt = n as f64 / self.fs;
        self.strokes.advance(n, self.fs);
        self.wander.advance(n, self.fs);
        if self.strokes.value() > 0.0 {
            let rate = self.c.stroke_rate_hz.clamp(0.05, 100.0);
            self.phase += dt * rate / self.length;
            while self.phase >= 1.0 {
                self.phase -= 1.0;
                self.returning = !self.returning;
                self.new_stroke();
            }
        }
        if self.wander.value() > 0.0 {
            for (i, &f) in WANDER_CORNERS_HZ.iter().enumerate() {
                let a = (-core::f64::consts::TAU * f * dt).exp();
                let k = (1.0 - a * a).sqrt();
                let (u, v): (f64, f64) = (
                    self.rng.sample(StandardNormal),
                    self.rng.sample(StandardNormal),
                );
                self.walks[i] = a * self.walks[i] + k * u;
                self.walks_p[i] = a * self.walks_p[i] + k * v;
            }
        }
        self.update_outputs();
    }

    /// One chunk (`force.len() ≤ CHUNK`): the force × the pressure, gliding linearly from
    /// its value at the chunk's start to its value at the end; the hand moves on. Does
    /// nothing when neutral. Real-time safe.
    pub fn process(&mut self, force: &mut [f32]) {
        if self.is_neutral() {
            return;
        }
        let n = force.len().min(CHUNK);
        let g0 = self.gain;
        self.advance(n);
        let step = (self.gain - g0) / n.max(1) as f64;
        for (i, f) in force[..n].iter_mut().enumerate() {
            *f *= (g0 + step * (i + 1) as f64) as f32;
        }
    }
}

impl Stage for Hand {
    /// The chunk of force (the whole scene's: the ball, its crowd, the note balls) the
    /// pressure scales.
    type Io<'a> = &'a mut [f32];

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.reset(self.seed);
    }

    fn reset(&mut self, seed: u64) {
        Hand::reset(self, seed);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_controls(HandControls::from_params(params));
    }

    fn snap(&mut self) {
        self.strokes.snap_to_target();
        self.wander.snap_to_target();
        self.update_outputs();
    }

    /// A moving hand is never idle (its state moves with time).
    fn is_idle(&self) -> bool {
        self.is_neutral()
    }

    fn process(&mut self, force: &mut [f32]) {
        Hand::process(self, force);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_profile_is_zero_at_the_turn_arounds_and_one_mid_stroke() {
        for shape in [0.0, 0.5, 1.0] {
            assert!(stroke_profile(0.0, shape).abs() < 1e-12);
            assert!(stroke_profile(1.0, shape) < 1e-12);
            assert!((stroke_profile(0.5, shape) - 1.0).abs() < 1e-12);
        }
        // A hard push is at full speed from 6 % of the stroke on; a sine is not.
        assert_eq!(stroke_profile(0.07, 1.0), 1.0);
        assert!(stroke_profile(0.03, 1.0) > 0.45 && stroke_profile(0.03, 1.0) < 0.55);
        assert!(stroke_profile(0.1, 0.0) < 0.35);
    }

    /// With a lift the stroke plays in the first 1 − lift of each stroke and the body is off
    /// for the rest: at depth 1 no speed and no force there (a third of the time at lift ⅓);
    /// with no lift the contact never leaves.
    #[test]
    fn a_lifted_stroke_is_silent_for_its_lift() {
        let c = |lift: f64| HandControls {
            strokes: 1.0,
            stroke_rate_hz: 3.0,
            stroke_shape: 1.0,
            stroke_lift: lift,
            stroke_return: 1.0,
            wander: 0.0,
            wander_rate_hz: 8.0,
        };
        for (lift, share) in [(0.0, 0.0), (1.0 / 3.0, 1.0 / 3.0)] {
            let mut h = Hand::new(48_000.0, c(lift), 9);
            let (mut off, mut n) = (0, 0);
            for _ in 0..20_000 {
                h.advance(CHUNK);
                let silent = h.pressure() == 0.0 && h.speed_factor() == Some(0.0);
                off += usize::from(silent);
                n += 1;
            }
            // 20 000 chunks span ~100 strokes whose lengths jitter by 12 %: the share of
            // lifted chunks is within 2 % of the lift.
            let got = off as f64 / n as f64;
            assert!((got - share).abs() < 0.02, "lift {lift}: {got}");
        }
    }

    /// Every other stroke is a return pressed `stroke_return` as hard as the push (at depth
    /// 1, the pressure's mean over each kind of stroke), and the first stroke is a push; at
    /// return 1 the two are alike.
    #[test]
    fn the_return_stroke_presses_its_share_of_the_push() {
        let c = |ret: f64| HandControls {
            strokes: 1.0,
            stroke_rate_hz: 3.0,
            stroke_shape: 0.5,
            stroke_lift: 0.0,
            stroke_return: ret,
            wander: 0.0,
            wander_rate_hz: 8.0,
        };
        for ret in [1.0, 0.4, 0.0] {
            let mut h = Hand::new(48_000.0, c(ret), 5);
            assert!(!h.returning);
            let (mut push, mut pull) = ((0.0, 0usize), (0.0, 0usize));
            for _ in 0..20_000 {
                h.advance(CHUNK);
                let acc = if h.returning { &mut pull } else { &mut push };
                acc.0 += h.pressure();
                acc.1 += 1;
            }
            let ratio = (pull.0 / pull.1 as f64) / (push.0 / push.1 as f64);
            // ~100 strokes of each kind, their lengths and peaks jittering by 12–15 %: the
            // means' ratio within 3 % of the share.
            assert!((ratio - ret).abs() < 0.03, "return {ret}: {ratio}");
            assert!(push.1.abs_diff(pull.1) < push.1 / 5, "{push:?} {pull:?}");
        }
    }

    #[test]
    fn the_wander_has_the_documented_swing() {
        // Depth 1: ln(speed factor) has standard deviation WANDER_SPEED_LN (the walks are
        // unit-variance and summed to unit variance) at every rate; 2000 chunks × many
        // seeds average it.
        for rate_hz in [8.0, 1.0, 0.3] {
            let c = HandControls {
                strokes: 0.0,
                stroke_rate_hz: 2.0,
                stroke_shape: 0.5,
                stroke_lift: 0.0,
                stroke_return: 1.0,
                wander: 1.0,
                wander_rate_hz: rate_hz,
            };
            let (mut s1, mut s2, mut n) = (0.0, 0.0, 0.0);
            for seed in 0..20 {
                let mut h = Hand::new(48_000.0, c, seed);
                for _ in 0..2000 {
                    let l = h.speed_factor().unwrap().ln();
                    s1 += l;
                    s2 += l * l;
                    n += 1.0;
                    h.advance(CHUNK * 8);
                }
            }
            let sd = (s2 / n - (s1 / n).powi(2)).sqrt();
            // 20 takes of ~21 s: the slowest walk (0.125 Hz, correlated over ~1.3 s) leaves
            // ~10 % scatter in the estimate, more when it carries a larger share (at 0.3 Hz
            // two walks, ~330 independent stretches of the slower: ~12 %).
            assert!(
                (sd / WANDER_SPEED_LN - 1.0).abs() < 0.2,
                "rate {rate_hz} Hz: sd {sd}"
            );
        }
    }

    #[test]
    fn the_walks_above_the_wander_rate_are_left_out_gradually() {
        // At the default every walk counts fully (the wander as before the control).
        for &f in &WANDER_CORNERS_HZ {
            assert_eq!(walk_weight(f, 8.0), 1.0);
        }
        assert_eq!(walk_weight(1.0, 1.0), 1.0);
        assert_eq!(walk_weight(2.0, 1.0), 0.0);
        assert!((walk_weight(2.0, 2f64.sqrt()) - 0.5).abs() < 1e-12);
        // The slowest walk is always in: the wander never falls silent.
        assert!(walk_weight(WANDER_CORNERS_HZ[0], 0.25) == 1.0);
        // The unit-variance factor: 1/√7 with every walk in, a non-finite rate as 8 Hz.
        let (k, norm) = walk_weights(8.0);
        assert!(k.iter().all(|&k| k == 1.0));
        assert_eq!(norm, 1.0 / 7f64.sqrt());
        assert_eq!(walk_weights(f64::NAN), (k, norm));
    }
}
