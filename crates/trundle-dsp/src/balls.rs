//! Many balls on one object: a preallocated pool of extra balls started and stopped like
//! notes (MIDI in the plugin, a preset's `balls` list in the CLI).
//!
//! Balls rolling on the same table excite the same resonator, so every ball here has its own
//! action chain — its own [`Source`] (impact series, pulses, AM, low-pass; its own seed) and
//! its own [`Space`] (its position on the object) — and their forces are **summed before the
//! one shared object** (docs/MODEL.md §6: the object is linear, so one modal bank serves them all;
//! this is what makes a 16-ball scene cheap). Everything else (roughness, asymmetry,
//! sharpness, the action disk, the comb and trajectory settings) is the scene's.
//!
//! ## Note mapping (documented for sound designers)
//! * **pitch → ball size**: note 36 (C2) is the largest ball S = 1, note 96 (C7) the
//!   smallest S = 0.1, linear in between and clamped outside ([`size_for_note`]);
//! * **note velocity → ball speed**: V = velocity (0…1, as the host sends it), floored at
//!   0.05 so a soft note still rolls;
//! * **note off** (or a preset ball's `stop_s`): the ball **rolls to rest**, its speed
//!   falling at [`STOP_DECELERATION_M_S2`] — a time that follows its speed (0.27 s from
//!   V 0.5 to V 0.1, 0.6 s from full speed) — then settling softly below
//!   [`STOP_SOFT_SPEED`]; its impacts soften as it slows, never a cut, and the object rings
//!   out; the slot is freed once the ball is still and its last pulse has ended;
//! * **position**: each ball starts at its own place on the object, a fixed scatter by
//!   note number, and follows the scene's trajectory from there;
//! * **seed**: the scene seed combined with the note number and how many notes came
//!   before it since the last reset — the same note sequence gives the same samples.
//!
//! When every slot is busy, the oldest ball is stopped abruptly and reused (voice
//! stealing). Balls use the signal engine.
//!
//! ## Level law
//! Balls rolling independently are uncorrelated, so their forces add in power: N balls
//! would be √N times (10·log₁₀N dB) louder than one, +12 dB for sixteen, and a scene's level
//! would depend on how many keys are held. The voice scales the summed force of the N balls
//! rolling (the scene's own ball while its velocity is above 0, and every extra ball) by
//! [`level_for_balls`] = 1/√N, gliding over the controls' smoothing time when N changes:
//! a crowd is as loud as one ball, and denser. What remains (many balls' peaks meeting) is
//! the output limiter's (`crate::limiter`).
//!
//! # Allocation
//! [`BallPool::new`] and [`BallPool::set_sample_rate`] allocate every slot; starting,
//! stopping and processing never allocate.

use crate::source::{Source, SourceControls};
use crate::space::{Space, SpaceControls};
use crate::CHUNK;

/// Most extra balls a voice holds.
pub const MAX_BALLS: usize = 16;

/// How fast a ball told to stop slows down (m/s², in units of V per second): a braked roll
/// — a hand, a felt, the ball's own rolling friction on a soft surface. (Free rolling
/// friction on a hard table, μ_r·g ≈ 0.01·9.8 m/s², would take tens of seconds.)
pub const STOP_DECELERATION_M_S2: f64 = 1.5;

/// Below this speed (V) a stopping ball settles exponentially (time constant
/// [`STOP_SOFT_SPEED`]/[`STOP_DECELERATION_M_S2`] = 67 ms) instead of linearly.
pub const STOP_SOFT_SPEED: f64 = 0.1;

/// How long (seconds) a stopped ball stays allocated after it came to rest, so its last
/// pulses (at most [`crate::pulse::T0_MAX_S`]) play out.
const RELEASE_S: f64 = 0.010;

/// The level law's gain for `rolling` balls: 1/√N (1 for none or one).
pub fn level_for_balls(rolling: usize) -> f64 {
    1.0 / (rolling.max(1) as f64).sqrt()
}

/// Ball size S for a note number: 36 → 1, 96 → 0.1, linear, clamped.
pub fn size_for_note(note: u8) -> f64 {
    (1.0 - (f64::from(note) - 36.0) / 60.0 * 0.9).clamp(0.1, 1.0)
}

/// Ball speed V for a note velocity (0…1).
pub fn velocity_for_note(velocity: f64) -> f64 {
    if velocity.is_finite() {
        velocity.clamp(0.05, 1.0)
    } else {
        0.5
    }
}

/// Start position of a ball for a note: a fixed scatter over the object (normalised).
pub fn position_for_note(note: u8) -> (f64, f64) {
    // Golden-angle spiral indexed by the note: distinct, well spread, deterministic.
    let k = f64::from(note % 64) + 1.0;
    let r = 0.15 + 0.7 * (k / 64.0).sqrt();
    let a = k * 2.399_963_229_728_653;
    (r * a.cos(), r * a.sin())
}

#[derive(Clone, Debug)]
struct Ball {
    source: Source,
    space: Space,
    note: u8,
    active: bool,
    stopping: bool,
    /// Samples since the ball came to rest (after a note off).
    rest_samples: usize,
    /// Start order, for stealing the oldest.
    order: u64,
    size: f64,
    velocity: f64,
    position: (f64, f64),
}

/// The pool of extra balls.
#[derive(Clone, Debug)]
pub struct BallPool {
    fs: f64,
    balls: Vec<Ball>,
    started: u64,
    base_seed: u64,
    buf: [f32; CHUNK],
    /// Number of active balls (kept in step with the slots: the idle check reads it every
    /// chunk without touching them).
    count: usize,
}

impl BallPool {
    /// A pool of [`MAX_BALLS`] idle balls at `sample_rate_hz`.
    pub fn new(sample_rate_hz: f64) -> Self {
        let fs = crate::sanitize_sample_rate(sample_rate_hz);
        let make = || Ball {
            source: Source::new(fs, SourceControls::default(), 0),
            space: Space::new(fs, SpaceControls::default()),
            note: 0,
            active: false,
            stopping: false,
            rest_samples: 0,
            order: 0,
            size: 0.4,
            velocity: 0.0,
            position: (0.0, 0.0),
        };
        Self {
            fs,
            balls: (0..MAX_BALLS).map(|_| make()).collect(),
            started: 0,
            base_seed: 0,
            buf: [0.0; CHUNK],
            count: 0,
        }
    }

    /// Change the sample rate (allocates) and stop every ball.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        *self = Self::new(sample_rate_hz);
    }

    /// Stop every ball at once and restart the seed sequence (real-time safe).
    pub fn reset(&mut self, base_seed: u64) {
        for b in &mut self.balls {
            b.active = false;
        }
        self.started = 0;
        self.base_seed = base_seed;
        self.count = 0;
    }

    /// Number of balls sounding.
    pub fn active(&self) -> usize {
        self.count
    }

    /// Start a ball for `note` with note velocity `velocity` (0…1), using the scene's
    /// controls `scene` and `space` for everything but size, speed, position and seed.
    /// Steals the oldest ball when the pool is full. Real-time safe.
    pub fn note_on(
        &mut self,
        note: u8,
        velocity: f64,
        scene: SourceControls,
        space: SpaceControls,
    ) {
        let slot = match self.balls.iter().position(|b| !b.active) {
            Some(i) => i,
            None => {
                let mut oldest = 0;
                for (i, b) in self.balls.iter().enumerate() {
                    if b.order < self.balls[oldest].order {
                        oldest = i;
                    }
                }
                oldest
            }
        };
        self.started += 1;
        let seed = self
            .base_seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(u64::from(note) << 32)
            .wrapping_add(self.started);
        let b = &mut self.balls[slot];
        b.note = note;
        b.active = true;
        b.stopping = false;
        b.rest_samples = 0;
        b.order = self.started;
        b.size = size_for_note(note);
        b.velocity = velocity_for_note(velocity);
        b.position = position_for_note(note);
        let (sc, pc) = Self::controls(b, scene, space);
        b.source.set_controls(sc);
        b.source.set_seed(seed);
        b.source.reset();
        b.space.set_controls(pc);
        b.space.reset();
        self.count = self.balls.iter().filter(|b| b.active).count();
    }

    /// Stop the ball(s) playing `note` (they roll to a halt). Real-time safe.
    pub fn note_off(&mut self, note: u8) {
        for b in &mut self.balls {
            if b.active && !b.stopping && b.note == note {
                b.stopping = true;
            }
        }
    }

    /// Stop every ball (they roll to a halt).
    pub fn all_notes_off(&mut self) {
        for b in &mut self.balls {
            if b.active {
                b.stopping = true;
            }
        }
    }

    fn controls(
        b: &Ball,
        scene: SourceControls,
        space: SpaceControls,
    ) -> (SourceControls, SpaceControls) {
        (
            SourceControls {
                size: b.size,
                velocity: b.velocity,
                ..scene
            },
            SpaceControls {
                position: b.position,
                velocity: b.velocity,
                ..space
            },
        )
    }

    /// Add every active ball's force for one chunk to `force` (`force.len() == CHUNK`),
    /// following the scene's controls. Real-time safe; costs nothing with no ball.
    pub fn add_chunk(&mut self, force: &mut [f32], scene: SourceControls, space: SpaceControls) {
        let n = force.len().min(CHUNK);
        let slow_by = STOP_DECELERATION_M_S2 * n as f64 / self.fs;
        for b in self.balls.iter_mut().filter(|b| b.active) {
            if b.stopping {
                // Rolling to rest (module docs): the speed falls linearly, then settles
                // softly below STOP_SOFT_SPEED (the loudness √V would otherwise drop its last
                // 13 dB in 30 ms).
                let v = b.velocity;
                b.velocity = (v - slow_by * (v / STOP_SOFT_SPEED).min(1.0)).max(0.0);
                if b.velocity < 1e-4 {
                    b.velocity = 0.0;
                }
            }
            let (sc, pc) = Self::controls(b, scene, space);
            b.source.set_controls(sc);
            b.space.set_controls(pc);
            let buf = &mut self.buf[..n];
            b.source.process_chunk(buf);
            b.space.process(buf);
            for (f, x) in force.iter_mut().zip(buf.iter()) {
                *f += *x;
            }
            // Stopped: its loudness √V is 50 dB down and its last pulses have played.
            if b.stopping && b.source.velocity() < 1e-5 {
                b.rest_samples += n;
                if b.rest_samples as f64 >= RELEASE_S * self.fs {
                    b.active = false;
                    self.count -= 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn note_mapping_is_monotone_and_bounded() {
        assert_eq!(size_for_note(36), 1.0);
        assert!((size_for_note(96) - 0.1).abs() < 1e-12);
        assert_eq!(size_for_note(0), 1.0);
        assert_eq!(size_for_note(127), 0.1);
        for n in 36..96 {
            assert!(size_for_note(n + 1) < size_for_note(n));
        }
        assert_eq!(velocity_for_note(0.0), 0.05);
        assert_eq!(velocity_for_note(f64::NAN), 0.5);
        for n in 0..128u8 {
            let (x, y) = position_for_note(n);
            assert!(x.hypot(y) <= 0.86);
        }
    }

    #[test]
    fn balls_start_stop_and_free_their_slot() {
        let mut pool = BallPool::new(48_000.0);
        let (sc, pc) = (SourceControls::default(), SpaceControls::default());
        pool.note_on(60, 0.8, sc, pc);
        pool.note_on(64, 0.8, sc, pc);
        assert_eq!(pool.active(), 2);
        let mut f = [0.0f32; CHUNK];
        let mut energy = 0.0;
        for _ in 0..100 {
            f.fill(0.0);
            pool.add_chunk(&mut f, sc, pc);
            energy += f.iter().map(|x| x * x).sum::<f32>();
        }
        assert!(energy > 0.0);
        pool.note_off(60);
        // It rolls to rest: V 0.8 at 1.5 m/s² takes 0.53 s (plus the smoothing's tail and
        // the release of its last pulses), then the slot is free.
        let mut chunks = 0;
        while pool.active() == 2 {
            f.fill(0.0);
            pool.add_chunk(&mut f, sc, pc);
            chunks += 1;
            assert!(chunks < 10_000, "never stopped");
        }
        // Linear to V 0.1, then exponential (67 ms) down to 10⁻⁴: 9 time constants more.
        let linear = (0.8 - STOP_SOFT_SPEED) / STOP_DECELERATION_M_S2;
        let t = chunks as f64 * CHUNK as f64 / 48_000.0 - linear;
        assert!(
            (0.4..0.9).contains(&t),
            "stopped {t} s after the linear part"
        );
        assert_eq!(pool.active(), 1);
        // A full pool steals the oldest.
        for n in 0..(MAX_BALLS as u8 + 3) {
            pool.note_on(40 + n, 0.5, sc, pc);
        }
        assert_eq!(pool.active(), MAX_BALLS);
    }
}
