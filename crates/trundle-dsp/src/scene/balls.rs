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
//! **Dropped balls** (docs/MODEL.md §11): when the scene's `gesture` is `drop`, a note drops
//! its ball instead — note velocity sets the height, 1 cm + 99 cm × velocity
//! ([`crate::scene::gesture::height_for_note`]); it bounces by the scene's restitution, then rolls
//! at the scene's V (with the scene's seams, grit and path), settles after `roll_time_s`
//! and frees its slot (or rolls on until its note off when `roll_time_s` = 0).
//!
//! When every slot is busy, the oldest ball is stopped abruptly and reused (voice
//! stealing). Balls use the signal engine.
//!
//! ## Expression per ball
//! A ball is addressed as the host addresses a note ([`BallTarget`]: a voice id, or a key
//! and a channel, any of them a wildcard) and follows its own gestures ([`Expression`]):
//!
//! | gesture | acts on | law |
//! |---|---|---|
//! | pressure p ∈ [0, 1] | contact load → loudness | force × (1 + p): up to +6 dB |
//! | timbre / brightness b ∈ [0, 1] | roughness | ρ = ρ_scene + (b − ½), clamped to [0, 1] |
//! | tuning / pitch bend t (semitones) | speed | V = V_note · 2^(t/12): an octave up, twice as fast |
//! | volume g (linear gain) | loudness | force × g |
//! | pan q ∈ [−1, 1] | where the ball rolls | x = x_note + q (clamped): towards a pickup |
//! | poly modulation of `velocity`, `roughness`, `size` | that control | value + offset, clamped to its range |
//!
//! A neutral gesture (p = 0, b = ½, t = 0, g = 1, q = 0, offsets 0) leaves the ball exactly as
//! it would be without expression. Loudness changes glide linearly over one chunk (no zipper
//! noise); speed, roughness and size go through the source's own smoothing.
//!
//! ## Level law
//! Balls rolling independently are uncorrelated, so their forces add in power: N balls
//! would be √N times (10·log₁₀N dB) louder than one, +12 dB for sixteen, and a scene's level
//! would depend on how many keys are held. The voice scales the summed force of the N balls
//! rolling (the scene's own ball while its velocity is above 0, and every extra ball) by
//! [`level_for_balls`] = 1/√N, gliding over the controls' smoothing time when N changes:
//! a crowd is as loud as one ball, and denser. What remains (many balls' peaks meeting) is
//! the output limiter's (`crate::scene::limiter`).
//!
//! # Allocation
//! [`BallPool::new`] and [`BallPool::set_sample_rate`] allocate every slot; starting,
//! stopping and processing never allocate.

use crate::block::CHUNK;
use crate::params::Params;
use crate::scene::gesture::{Gesture, GestureControls, GestureKind};
use crate::scene::space::{Space, SpaceControls};
use crate::scene::stop::{STOP_DECELERATION_M_S2, STOP_SOFT_SPEED};
use crate::source::chain::{Source, SourceControls};
use crate::stage::Stage;

/// Most extra balls a voice holds.
pub const MAX_BALLS: usize = 16;

/// How long (seconds) a stopped ball stays allocated after it came to rest, so its last
/// pulses (at most [`crate::source::pulse::T0_MAX_S`]) play out.
const RELEASE_S: f64 = 0.010;

/// How a ball is named by the host: the note it was started by. Every field may be a
/// wildcard (`None`); a [`BallTarget`] with a voice id names only that ball.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BallTarget {
    /// The host's voice (note) id, if it gave one.
    pub voice_id: Option<i32>,
    /// MIDI channel 0–15 (for MPE: the note's own channel).
    pub channel: Option<u8>,
    /// Key (note number) 0–127.
    pub key: Option<u8>,
}

impl BallTarget {
    /// Every ball.
    pub const ALL: Self = Self {
        voice_id: None,
        channel: None,
        key: None,
    };

    /// The balls started on `channel` (MPE: one note per channel).
    pub fn channel(channel: u8) -> Self {
        Self {
            channel: Some(channel),
            ..Self::ALL
        }
    }

    /// Whether a ball started as `id` is named by this target: by voice id when the target
    /// gives one, otherwise by key and channel (wildcards match anything).
    pub fn matches(&self, id: &BallId) -> bool {
        if let Some(v) = self.voice_id {
            return id.voice_id == Some(v);
        }
        self.channel.is_none_or(|c| c == id.channel) && self.key.is_none_or(|k| k == id.key)
    }
}

/// What a sounding ball was started as (reported back when it ends, for the host's voice
/// bookkeeping: CLAP's note-end event).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BallId {
    /// The host's voice id, if it gave one.
    pub voice_id: Option<i32>,
    /// MIDI channel 0–15.
    pub channel: u8,
    /// Key (note number) 0–127.
    pub key: u8,
}

/// A per-ball gesture (module docs: the table of what each does).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Expression {
    /// Pressure (aftertouch) 0…1 → contact load: force × (1 + p).
    Pressure(f64),
    /// Timbre / brightness (MPE CC 74, CLAP brightness) 0…1 → roughness offset b − ½.
    Brightness(f64),
    /// Tuning in semitones (pitch bend, CLAP tuning) → speed × 2^(t/12).
    TuningSemitones(f64),
    /// Volume as a linear gain (CLAP volume, 0…4).
    Volume(f64),
    /// Pan −1…1 → the ball's x on the object, towards the left or right pickup.
    Pan(f64),
    /// Poly modulation of `velocity`: an offset in m/s.
    VelocityOffset(f64),
    /// Poly modulation of `roughness`: an offset in roughness units.
    RoughnessOffset(f64),
    /// Poly modulation of `size`: an offset in size units.
    SizeOffset(f64),
}

/// A ball's gestures, neutral by default.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Gestures {
    pressure: f64,
    brightness: f64,
    tuning_st: f64,
    volume: f64,
    pan: f64,
    velocity_offset: f64,
    roughness_offset: f64,
    size_offset: f64,
}

impl Default for Gestures {
    fn default() -> Self {
        Self {
            pressure: 0.0,
            brightness: 0.5,
            tuning_st: 0.0,
            volume: 1.0,
            pan: 0.0,
            velocity_offset: 0.0,
            roughness_offset: 0.0,
            size_offset: 0.0,
        }
    }
}

impl Gestures {
    /// Take one gesture; non-finite values are ignored, others clamped to their range.
    fn apply(&mut self, e: Expression) {
        let ok = |x: f64| x.is_finite();
        match e {
            Expression::Pressure(p) if ok(p) => self.pressure = p.clamp(0.0, 1.0),
            Expression::Brightness(b) if ok(b) => self.brightness = b.clamp(0.0, 1.0),
            Expression::TuningSemitones(t) if ok(t) => self.tuning_st = t.clamp(-128.0, 128.0),
            Expression::Volume(g) if ok(g) => self.volume = g.clamp(0.0, 4.0),
            Expression::Pan(q) if ok(q) => self.pan = q.clamp(-1.0, 1.0),
            Expression::VelocityOffset(d) if ok(d) => self.velocity_offset = d.clamp(-1.0, 1.0),
            Expression::RoughnessOffset(d) if ok(d) => self.roughness_offset = d.clamp(-1.0, 1.0),
            Expression::SizeOffset(d) if ok(d) => self.size_offset = d.clamp(-1.0, 1.0),
            _ => {}
        }
    }

    /// The loudness factor.
    fn gain(&self) -> f64 {
        (1.0 + self.pressure) * self.volume
    }
}

/// Append `id` to the ended list (dropped when the list is full: the host then frees the
/// voice itself). A free function so the chunk loop can call it while it holds the balls.
fn push_ended(ended: &mut [BallId], count: &mut usize, id: BallId) {
    if let Some(slot) = ended.get_mut(*count) {
        *slot = id;
        *count += 1;
    }
}

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
    id: BallId,
    gestures: Gestures,
    /// The loudness factor reached at the end of the last chunk (ramped from, per chunk).
    gain: f64,
    active: bool,
    stopping: bool,
    /// Samples since the ball came to rest (after a note off).
    rest_samples: usize,
    /// Start order, for stealing the oldest.
    order: u64,
    size: f64,
    velocity: f64,
    position: (f64, f64),
    /// The ball's own gesture (a dropped ball), when `dropping`.
    gesture: Gesture,
    dropping: bool,
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
    /// Balls that ended (came to rest, were stolen or reset) since the last
    /// [`drain_ended`](Self::drain_ended); at most one per slot between drains is kept.
    ended: [BallId; 2 * MAX_BALLS],
    ended_count: usize,
    /// The scene's gesture (a `drop` scene drops every new ball).
    gesture: GestureControls,
}

impl BallPool {
    /// A pool of [`MAX_BALLS`] idle balls at `sample_rate_hz`.
    pub fn new(sample_rate_hz: f64) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let make = || Ball {
            source: Source::new(fs, SourceControls::default(), 0),
            space: Space::new(fs, SpaceControls::default()),
            id: BallId::default(),
            gestures: Gestures::default(),
            gain: 1.0,
            active: false,
            stopping: false,
            rest_samples: 0,
            order: 0,
            size: 0.4,
            velocity: 0.0,
            position: (0.0, 0.0),
            gesture: Gesture::with_log_capacity(
                fs,
                GestureControls::from_params(&Params::default()),
                0,
                1,
            ),
            dropping: false,
        };
        Self {
            fs,
            balls: (0..MAX_BALLS).map(|_| make()).collect(),
            started: 0,
            base_seed: 0,
            buf: [0.0; CHUNK],
            count: 0,
            ended: [BallId::default(); 2 * MAX_BALLS],
            ended_count: 0,
            gesture: GestureControls::from_params(&Params::default()),
        }
    }

    /// The scene's gesture controls: with `drop`, new balls are dropped (module docs).
    /// Real-time safe.
    pub fn set_gesture(&mut self, c: GestureControls) {
        self.gesture = c;
    }

    fn record_ended(&mut self, id: BallId) {
        push_ended(&mut self.ended, &mut self.ended_count, id);
    }

    /// Hand every ball that ended since the last call to `f` (came to rest after its note
    /// off, was stolen, or was stopped by a reset), oldest first. Real-time safe.
    pub fn drain_ended(&mut self, mut f: impl FnMut(BallId)) {
        for id in &self.ended[..self.ended_count] {
            f(*id);
        }
        self.ended_count = 0;
    }

    /// Change the sample rate (allocates) and stop every ball.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        *self = Self::new(sample_rate_hz);
    }

    /// Stop every ball at once and restart the seed sequence (real-time safe).
    pub fn reset(&mut self, base_seed: u64) {
        for i in 0..self.balls.len() {
            if self.balls[i].active {
                self.balls[i].active = false;
                self.record_ended(self.balls[i].id);
            }
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
        let id = BallId {
            voice_id: None,
            channel: 0,
            key: note,
        };
        self.ball_on(id, velocity, scene, space);
    }

    /// Start a ball named `id` (its key sets the size, as [`note_on`](Self::note_on)), with
    /// neutral gestures. Real-time safe.
    pub fn ball_on(
        &mut self,
        id: BallId,
        velocity: f64,
        scene: SourceControls,
        space: SpaceControls,
    ) {
        let note = id.key.min(127);
        let slot = match self.balls.iter().position(|b| !b.active) {
            Some(i) => i,
            None => {
                let mut oldest = 0;
                for (i, b) in self.balls.iter().enumerate() {
                    if b.order < self.balls[oldest].order {
                        oldest = i;
                    }
                }
                let stolen = self.balls[oldest].id;
                self.record_ended(stolen);
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
        b.id = BallId { key: note, ..id };
        b.gestures = Gestures::default();
        b.gain = 1.0;
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
        b.dropping = self.gesture.kind == GestureKind::Drop;
        if b.dropping {
            // A dropped ball: the note's velocity is its height; it rolls at the scene's V.
            b.velocity = scene.velocity.clamp(0.0, 1.0);
            let c = GestureControls {
                height_m: crate::scene::gesture::height_for_note(velocity),
                velocity: b.velocity,
                // Balls use the signal engine: their bounces are the model's pulses.
                hc_kappa: 0.0,
                ..self.gesture
            };
            b.gesture.set_controls(c);
            b.gesture.reset(seed);
            // Falling: not rolling yet (the source starts at rest, not gliding down from V).
            let mut at_rest = sc;
            at_rest.velocity = 0.0;
            b.source.set_controls(at_rest);
            b.source.reset();
        }
        self.count = self.balls.iter().filter(|b| b.active).count();
    }

    /// Stop the ball(s) playing `note` (they roll to a halt). Real-time safe.
    pub fn note_off(&mut self, note: u8) {
        self.ball_off(BallTarget {
            key: Some(note),
            ..BallTarget::ALL
        });
    }

    /// Stop the ball(s) named by `target`: they roll to a halt. Real-time safe.
    pub fn ball_off(&mut self, target: BallTarget) {
        for b in &mut self.balls {
            if b.active && !b.stopping && target.matches(&b.id) {
                b.stopping = true;
            }
        }
    }

    /// Apply a gesture to the ball(s) named by `target` (module docs). Real-time safe.
    pub fn express(&mut self, target: BallTarget, expression: Expression) {
        for b in &mut self.balls {
            if b.active && target.matches(&b.id) {
                b.gestures.apply(expression);
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

    /// The ball's controls: the scene's, with its own size, speed and position and its
    /// gestures applied (module docs). Neutral gestures give the note's values exactly.
    fn controls(
        b: &Ball,
        scene: SourceControls,
        space: SpaceControls,
    ) -> (SourceControls, SpaceControls) {
        let g = &b.gestures;
        let tuning = g.tuning_st;
        let mut velocity = b.velocity;
        if tuning != 0.0 {
            velocity *= (tuning / 12.0).exp2();
        }
        if g.velocity_offset != 0.0 && !b.stopping {
            velocity += g.velocity_offset;
        }
        let velocity = velocity.clamp(0.0, 1.0);
        let roughness = scene.roughness + (g.brightness - 0.5) + g.roughness_offset;
        let (x, y) = b.position;
        (
            SourceControls {
                size: (b.size + g.size_offset).clamp(0.1, 1.0),
                velocity,
                roughness: roughness.clamp(0.0, 1.0),
                ..scene
            },
            SpaceControls {
                position: ((x + g.pan).clamp(-1.0, 1.0), y),
                velocity,
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
            let (mut sc, mut pc) = Self::controls(b, scene, space);
            if b.dropping {
                // The drop's schedule: silent fall, bounces, then rolling at the ball's speed.
                let f = b.gesture.rolling_factor();
                sc.velocity *= f;
                pc.velocity *= f;
                b.space.set_path_scale(b.gesture.path_scale());
            }
            b.source.set_controls(sc);
            b.space.set_controls(pc);
            let buf = &mut self.buf[..n];
            let v_before = b.source.velocity();
            b.source.process_chunk(buf);
            if b.dropping {
                let k = crate::scene::gesture::pulse_scale(&b.source, sc.size);
                b.gesture.process(buf, k, (v_before, b.source.velocity()));
            }
            b.space.process(buf);
            let target = b.gestures.gain();
            if target == 1.0 && b.gain == 1.0 {
                for (f, x) in force.iter_mut().zip(buf.iter()) {
                    *f += *x;
                }
            } else {
                // A loudness gesture glides linearly across the chunk (no zipper noise).
                let (g0, step) = (b.gain as f32, ((target - b.gain) / n as f64) as f32);
                for (i, (f, x)) in force.iter_mut().zip(buf.iter()).enumerate() {
                    *f += *x * (g0 + step * (i + 1) as f32);
                }
                b.gain = target;
            }
            // Stopped: its loudness √V is 50 dB down and its last pulses have played (a
            // dropped ball also once its gesture has settled).
            let settled = b.dropping && b.gesture.is_finished() && b.source.at_rest();
            if (b.stopping || settled) && b.source.velocity() < 1e-5 {
                b.rest_samples += n;
                if b.rest_samples as f64 >= RELEASE_S * self.fs {
                    b.active = false;
                    self.count -= 1;
                    push_ended(&mut self.ended, &mut self.ended_count, b.id);
                }
            }
        }
    }
}

impl Stage for BallPool {
    /// The chunk of force the balls add to, and the parameters their controls follow.
    type Io<'a> = (&'a mut [f32], &'a Params);

    /// Stops every ball (the gesture controls are kept).
    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        let gesture = self.gesture;
        BallPool::set_sample_rate(self, sample_rate_hz);
        self.set_gesture(gesture);
    }

    fn reset(&mut self, seed: u64) {
        BallPool::reset(self, seed);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_gesture(GestureControls::from_params(params));
    }

    fn snap(&mut self) {}

    fn is_idle(&self) -> bool {
        self.active() == 0
    }

    /// Extra balls roll on the same object: their forces add before it.
    fn process(&mut self, (force, params): (&mut [f32], &Params)) {
        if self.active() > 0 {
            let (sc, pc) = (
                SourceControls::from_params(params),
                SpaceControls::from_params(params),
            );
            self.add_chunk(force, sc, pc);
        }
    }
}

#[cfg(test)]
mod tests;
