//! Which engine makes the force, and the crossfade when that changes.
//!
//! The voice's force comes from the signal model ([`Source`]) or from the physics engine
//! ([`PhysicsEngine`], see [`crate::physics::mapping`] for how the controls map onto it). This type
//! owns the physics engine, its smoothed controls and the crossfade between the two:
//!
//! * **Smoothing.** Size, velocity, roughness and asymmetry glide for the physics engine as
//!   they do for the signal model (the surface, law and seed do not); its settings are
//!   recomputed once per chunk, and only while a control is moving.
//! * **Crossfade.** A change of `engine` fades the two forces linearly over
//!   [`ENGINE_CROSSFADE_S`] (both engines run meanwhile), so switching never clicks; otherwise
//!   only the selected engine runs, and with `engine = signal` the force is exactly the
//!   source's, bit for bit.
//! * **Level.** The physics force (newtons) is handed on **minus the ball's weight**, in units
//!   of that weight times [`PHYSICS_FORCE_SCALE`] (see [`crate::physics::mapping`]): a ball at rest on
//!   the surface pushes with exactly its weight and hands on exactly nothing — no thump when
//!   the engine starts, switches in or comes to rest (a DC blocker fed the static load would
//!   answer its onset with a one-sided 5 Hz bump). Between contacts the handed-on force is
//!   −1 weight; on average over a roll it is 0 (the contacts carry the weight).
//! * **One level for both engines** (#17). The two engines' sounds differ in level by up to
//!   ±35 dB across size, speed and roughness (the physics force grows with the ball's speed
//!   and relief by physical laws, the signal model's by the papers' loudness law √V), so the
//!   physics force is scaled, continuously, to the signal model's loudness at the same
//!   controls: while the physics engine runs, the signal model runs beside it and the voice
//!   plays both forces (the physics one unscaled) through twins of the object (together
//!   ≈ 35 ns per sample at 32 modes, measured by `trundle bench`: the physics voice went
//!   from 47 to 82 ns per sample); the physics force's gain is the
//!   ratio of the two twins' mean squares, each averaged over [`LEVEL_MATCH_S`] (a running mean from the engine's start,
//!   then exponential). Matching the sounds, not the forces, matters: the physics force
//!   carries far more of its power above the object's loudest modes. The level follows the
//!   signal model's laws; the physics keeps its own impacts, dynamics and spectrum. While
//!   both are silent (a ball at rest) or extra balls roll, the gain holds.
//! * **Impacts.** Each contact of the physics ball (the force rising from zero and falling
//!   back to it) is logged like the signal model's impacts ([`ImpactRecord`]): the time of
//!   its peak, the peak force in units of the ball's weight, the contact's duration (to the
//!   output sample).
//!
//! * **Friction** (`friction` > 0, [`crate::physics::friction`]). The stick-slip contact runs
//!   on the voice's object's own modes (read each chunk) with the rubbing body drawn at the
//!   velocity V; its force on the object (in units of [`FRICTION_FORCE_REF_N`] or of the
//!   static friction force, whichever is larger) is blended
//!   over the engine's force by the `friction` amount (smoothed). At 0 it does not run and
//!   the force is the engine's, bit for bit.
//!
//! Lifecycle as every DSP type ([`crate`] docs): [`EngineMix::new`] allocates (the physics
//! engine); the rest is real-time safe.

use crate::block::CHUNK;
use crate::object::quality::Quality;
use crate::object::resonator::Object;
use crate::params::{ParamId, Params};
use crate::physics::friction::{contact_mass_kg, Friction};
use crate::physics::friction_body::FrictionBody;
use crate::physics::mapping::{
    auto_oversample, quality_oversample, Engine, PhysicsControls, ENGINE_CROSSFADE_S,
    PHYSICS_FORCE_SCALE,
};
use crate::physics::{PhysicsEngine, MAX_OVERSAMPLE};
use crate::smooth::Smoother;
use crate::source::chain::{ImpactLog, ImpactRecord, Source};
use crate::stage::Stage;

/// Averaging time of the level match between the engines (s): long enough that the gain
/// does not follow single impacts or the AM, short enough to follow a gesture.
pub const LEVEL_MATCH_S: f64 = 0.5;

/// The friction force (N) that the voice hands on as a force of 1 (the signal model's
/// forces are of order 1): a rub at 1 N of pressure is about as loud as a roll. Above it the
/// force is handed on in units of the static friction force μ_s·N instead, so pressure past
/// ~1 N changes which mode locks and how the contact sounds, not its scale: in newtons a rub
/// at 20 N was 26 dB over one at 1 N, and a locked high-Q mode went 30 dB over the output's
/// bound (the property test in `tests/props.rs` found it).
pub const FRICTION_FORCE_REF_N: f64 = 1.0;

/// The running sound powers of the two engines and the gain that matches them.
#[derive(Clone, Copy, Debug)]
struct LevelMatch {
    /// Chunks averaged since the physics engine started.
    chunks: u32,
    /// Running mean square of the object's sound of the signal model's force.
    reference: f64,
    /// Running mean square of the object's sound of the physics force (before the gain).
    physics: f64,
    /// The gain in force on the physics force.
    gain: f64,
}

impl LevelMatch {
    const START: LevelMatch = LevelMatch {
        chunks: 0,
        reference: 0.0,
        physics: 0.0,
        gain: 1.0,
    };

    fn mean_square(x: &[f32]) -> f64 {
        x.iter().map(|&v| f64::from(v) * f64::from(v)).sum::<f64>() / x.len().max(1) as f64
    }

    /// Fold in one chunk of each engine's sound (both through twins of the object, the
    /// physics force unscaled: an open loop, no feedback from the gain).
    fn update(&mut self, reference: &[f32], physics: &[f32], fs: f64) {
        let alpha = (1.0 / f64::from(self.chunks + 1)).max(CHUNK as f64 / (LEVEL_MATCH_S * fs));
        self.chunks = self.chunks.saturating_add(1);
        self.reference += alpha * (Self::mean_square(reference) - self.reference);
        self.physics += alpha * (Self::mean_square(physics) - self.physics);
        if self.physics > 1e-24 && self.reference > 1e-24 {
            self.gain = (self.reference / self.physics).sqrt().clamp(1e-3, 1e3);
        }
    }
}

/// The engine choice, the physics engine and the crossfade between the engines' forces.
///
/// # Allocation
/// `new` allocates the physics engine; nothing else does.
#[derive(Clone, Debug)]
pub struct EngineMix {
    /// The seed in force (a change restarts the physics engine's surface).
    seed: u64,
    fs: f64,
    /// The physics engine (runs only while selected or fading).
    physics: PhysicsEngine,
    /// Smoothed size, velocity, roughness, asymmetry for the physics engine.
    ctrl: [Smoother; 4],
    /// The physics controls' targets (law and seed are not smoothed).
    target: PhysicsControls,
    /// RK4 substeps per sample; 0 = from the quality, else [`auto_oversample`].
    oversample: usize,
    quality: Quality,
    /// The physics engine ran in the previous chunk (else its controls snap on restart).
    running: bool,
    /// Crossfade position: 0 = signal, 1 = physics.
    mix: f32,
    /// Where the crossfade goes (0 or 1).
    mix_target: f32,
    phys_force: [f32; CHUNK],
    /// The signal model's force while the physics engine runs (the level reference).
    reference: [f32; CHUNK],
    /// The physics force of the last chunk before the level match's gain.
    raw_physics: [f32; CHUNK],
    level: LevelMatch,
    /// The gain applied at the end of the last physics chunk.
    applied_gain: f64,
    /// The level match runs (the default; off for measurements).
    level_match: bool,
    /// Output samples since reset (the time base of the physics impacts).
    samples: u64,
    /// The contact under way: (start sample, peak sample, peak force / weight).
    contact: Option<(u64, u64, f32)>,
    log: ImpactLog,
    /// The stick-slip contact ([`crate::physics::friction`]).
    friction: Friction,
    /// The friction amount (0 = off), smoothed.
    friction_amount: Smoother,
    /// The bow velocity at the end of the last friction chunk (m/s).
    bow_m_s: f64,
    friction_force: [f32; CHUNK],
}

fn mix_target(p: &Params) -> f32 {
    match p.engine() {
        Engine::Signal => 0.0,
        Engine::Physics => 1.0,
    }
}

impl EngineMix {
    /// The engines for parameters `params` at `fs` (already sanitized), settled on the
    /// selected engine.
    pub fn new(fs: f64, params: &Params) -> Self {
        let pc = PhysicsControls::from_params(params);
        Self {
            seed: params.seed(),
            fs,
            physics: PhysicsEngine::new(&pc.settings(fs, auto_oversample(fs))),
            ctrl: [
                Smoother::new(pc.size),
                Smoother::new(pc.velocity),
                Smoother::new(pc.roughness),
                Smoother::new(pc.asymmetry),
            ],
            target: pc,
            oversample: 0,
            quality: params.quality(),
            running: false,
            mix: mix_target(params),
            mix_target: mix_target(params),
            phys_force: [0.0; CHUNK],
            reference: [0.0; CHUNK],
            raw_physics: [0.0; CHUNK],
            level: LevelMatch::START,
            applied_gain: 1.0,
            level_match: true,
            samples: 0,
            contact: None,
            log: ImpactLog::new(),
            friction: Self::friction_for(fs, params),
            friction_amount: Smoother::new(params.get(ParamId::Friction)),
            bow_m_s: params.velocity(),
            friction_force: [0.0; CHUNK],
        }
    }

    fn friction_for(fs: f64, params: &Params) -> Friction {
        let mut f = Friction::new(fs);
        Self::friction_controls(&mut f, params);
        f
    }

    fn friction_controls(f: &mut Friction, params: &Params) {
        f.set_contact(
            FrictionBody::of(params.rub_body()),
            params.get(ParamId::PressureN),
        );
        f.set_mass(contact_mass_kg(
            params.shape(),
            params.get(ParamId::ObjectSize),
        ));
    }

    /// The stick-slip contact, for inspection.
    pub fn friction(&self) -> &Friction {
        &self.friction
    }

    /// The friction contact runs (its amount or its target is not 0).
    pub fn friction_on(&self) -> bool {
        self.friction_amount.value() != 0.0 || self.friction_amount.target() != 0.0
    }

    /// Blend the friction force over the engine's `force` (module docs), the bow at the
    /// source's velocity `bow_m_s` at the chunk's end.
    fn friction_chunk(&mut self, object: &Object, bow_m_s: f64, force: &mut [f32; CHUNK]) {
        if !self.friction_on() {
            return;
        }
        self.friction.set_object_modes(object.modes());
        let (b0, b1) = (self.bow_m_s, bow_m_s);
        self.bow_m_s = bow_m_s;
        self.friction.process(b0, b1, &mut self.friction_force);
        let (a0, a1) = self.friction_amount.advance(CHUNK, self.fs);
        let step = (a1 - a0) / CHUNK as f64;
        let scale = 1.0 / FRICTION_FORCE_REF_N.max(self.friction.static_force_n());
        // The force handed on stays within what the contact transmits (its bound at the
        // faster end of the chunk's bow; see `Friction::force_bound_n`).
        let bound = (self.friction.force_bound_n(b0.abs().max(b1.abs())) * scale) as f32;
        for (i, (y, fr)) in force.iter_mut().zip(&self.friction_force).enumerate() {
            let a = (a0 + step * (i + 1) as f64) as f32;
            let f = ((f64::from(*fr) * scale) as f32).clamp(-bound, bound);
            *y = (1.0 - a) * *y + a * f;
        }
        if !self.friction_on() {
            // Off again: the next start is from rest.
            self.friction.reset();
        }
    }

    /// Record the physics ball's contacts for [`drain_impacts`](Self::drain_impacts).
    pub fn set_impact_log(&mut self, enabled: bool) {
        self.log.set_enabled(enabled);
    }

    /// Hand the recorded contacts (oldest first) to `f` and clear the record; returns how
    /// many were dropped because the ring was full.
    pub fn drain_impacts(&mut self, f: impl FnMut(ImpactRecord)) -> u64 {
        self.log.drain(f)
    }

    /// Let a chunk pass without running either engine (the voice's idle skip).
    pub fn skip_chunk(&mut self) {
        self.samples += CHUNK as u64;
    }

    fn oversample(&self) -> usize {
        if self.oversample == 0 {
            quality_oversample(self.quality).unwrap_or_else(|| auto_oversample(self.fs))
        } else {
            self.oversample
        }
    }

    /// Choose the physics engine's RK4 substeps per output sample, 1..=8 (the accuracy knob
    /// of [`crate::physics`]); 0 = from the quality (automatic: internal rate ≥ 96 kHz).
    pub fn set_oversample(&mut self, oversample: usize) {
        self.oversample = oversample.min(MAX_OVERSAMPLE);
        self.apply();
    }

    /// The physics engine (health report, settings in force), for inspection.
    pub fn physics(&self) -> &PhysicsEngine {
        &self.physics
    }

    /// Push the smoothed physics controls into the engine.
    fn apply(&mut self) {
        let c = PhysicsControls {
            size: self.ctrl[0].value(),
            velocity: self.ctrl[1].value(),
            roughness: self.ctrl[2].value(),
            asymmetry: self.ctrl[3].value(),
            ..self.target
        };
        let s = c.settings(self.fs, self.oversample());
        self.physics.set_settings(&s);
    }

    fn snap_controls(&mut self) {
        for s in &mut self.ctrl {
            s.snap_to_target();
        }
        self.apply();
    }

    /// A new sample rate (already sanitized); call [`EngineMix::reset`] after it.
    pub fn set_sample_rate(&mut self, fs: f64) {
        self.fs = fs;
        self.friction.set_sample_rate(fs);
        self.apply();
    }

    /// Back to the state after `new` with the current targets.
    pub fn reset(&mut self) {
        self.snap_controls();
        self.physics.reset();
        self.running = false;
        self.mix = self.mix_target;
        self.samples = 0;
        self.level = LevelMatch::START;
        self.applied_gain = 1.0;
        self.contact = None;
        self.log.clear();
        self.friction.reset();
        self.friction_amount.snap_to_target();
    }

    /// Jump the crossfade to its target (the start of a render).
    pub fn snap(&mut self) {
        self.mix = self.mix_target;
        self.friction_amount.snap_to_target();
    }

    /// New targets from `params`; `seed_changed` restarts the physics engine's surface.
    pub fn set_params(&mut self, params: &Params, seed_changed: bool) {
        let quality = params.quality();
        if quality != self.quality {
            self.quality = quality;
            self.apply();
        }
        let pc = PhysicsControls::from_params(params);
        for (s, v) in self
            .ctrl
            .iter_mut()
            .zip([pc.size, pc.velocity, pc.roughness, pc.asymmetry])
        {
            s.set_target(v);
        }
        let fixed_changed = pc.ball != self.target.ball
            || pc.object_compliance_per_pa != self.target.object_compliance_per_pa
            || pc.asymmetry_law != self.target.asymmetry_law;
        self.target = pc;
        if fixed_changed {
            self.apply();
        }
        self.mix_target = mix_target(params);
        Self::friction_controls(&mut self.friction, params);
        self.friction_amount
            .set_target(params.get(ParamId::Friction));
        if seed_changed {
            // A new surface: the seed of the profile takes effect at the engine's reset.
            self.apply();
            self.physics.reset();
        }
    }

    /// The physics engine is selected (whatever the crossfade): its impacts, not the signal
    /// model's (which may run beside it as the level reference), are the ball's.
    pub fn physics_selected(&self) -> bool {
        self.mix_target == 1.0
    }

    /// Only the signal model runs, no crossfade is under way and friction is off.
    pub fn signal_only(&self) -> bool {
        self.mix == 0.0 && self.mix_target == 0.0 && !self.friction_on()
    }

    /// One chunk of the physics force, normalized (see [`crate::physics::mapping`]) into `phys_force`.
    fn physics_chunk(&mut self) {
        if !self.running {
            self.snap_controls();
            self.running = true;
            self.level = LevelMatch::START;
            self.applied_gain = 1.0;
        } else {
            let mut moving = false;
            for s in &mut self.ctrl {
                moving |= s.is_moving();
                s.advance(CHUNK, self.fs);
            }
            if moving {
                self.apply();
            }
        }
        self.physics.process(&mut self.phys_force);
        let st = self.physics.settings();
        let weight = st.mass_kg * crate::physics::GRAVITY_M_S2;
        let per_weight = (1.0 / weight) as f32;
        let scale = PHYSICS_FORCE_SCALE as f32;
        let dt = 1.0 / self.fs;
        for i in 0..CHUNK {
            let w = self.phys_force[i] * per_weight;
            let t = self.samples + i as u64;
            // Contacts: the force leaves zero and comes back to it.
            match (&mut self.contact, w > 0.0) {
                (None, true) => self.contact = Some((t, t, w)),
                (Some(c), true) => {
                    if w > c.2 {
                        (c.1, c.2) = (t, w);
                    }
                }
                (Some(c), false) => {
                    let (start, peak_at, peak) = *c;
                    self.contact = None;
                    if self.log.enabled() {
                        self.log.record(ImpactRecord {
                            time_s: peak_at as f64 * dt,
                            amplitude: f64::from(peak),
                            duration_s: (t - start) as f64 * dt,
                        });
                    }
                }
                (None, false) => {}
            }
            // The weight is carried by the contacts on average: hand on the rest.
            self.phys_force[i] = (w - 1.0) * scale;
        }
        self.samples += CHUNK as u64;
    }

    /// Scale the physics chunk by the level match's gain (module docs), gliding from the
    /// gain of the previous chunk.
    fn match_level(&mut self) {
        self.raw_physics = self.phys_force;
        let (g0, g1) = (self.applied_gain, self.level.gain);
        let step = (g1 - g0) / CHUNK as f64;
        for (i, x) in self.phys_force.iter_mut().enumerate() {
            *x *= (g0 + step * (i + 1) as f64) as f32;
        }
        self.applied_gain = g1;
    }

    /// The signal model's force and the unscaled physics force of the last chunk, when the
    /// level match wants them played through the object's twins (the physics engine runs).
    pub fn level_forces(&self) -> Option<(&[f32; CHUNK], &[f32; CHUNK])> {
        (self.level_match && self.running && self.mix_target == 1.0)
            .then_some((&self.reference, &self.raw_physics))
    }

    /// The twins' sounds of the last chunk from the signal model's force (`reference`) and
    /// from the unscaled physics force (`physics`): updates the level match's gain.
    pub fn observe_level(&mut self, reference: &[f32], physics: &[f32]) {
        self.level.update(reference, physics, self.fs);
    }

    /// Switch the level match off (the physics force keeps its fixed calibration,
    /// [`PHYSICS_FORCE_SCALE`]) or on (the default): for measuring the crossfade and the
    /// physics force itself. Real-time safe.
    pub fn set_level_match(&mut self, on: bool) {
        self.level_match = on;
        if !on {
            self.level.gain = 1.0;
        }
    }

    /// The gain the level match applies to the physics force now (1 before it has run).
    pub fn physics_level_gain(&self) -> f64 {
        self.level.gain
    }

    /// One chunk of the force: the source's, the physics engine's, or the crossfade of both;
    /// then the friction contact on `object`'s modes blended over it (when on).
    pub fn force_chunk(&mut self, source: &mut Source, object: &Object, force: &mut [f32; CHUNK]) {
        self.engine_chunk(source, force);
        self.friction_chunk(object, source.velocity(), force);
    }

    fn engine_chunk(&mut self, source: &mut Source, force: &mut [f32; CHUNK]) {
        let (m0, target) = (self.mix, self.mix_target);
        if m0 == 0.0 && target == 0.0 {
            // Signal engine only: exactly the source's force.
            source.process_chunk(force);
            self.running = false;
            self.samples += CHUNK as u64;
        } else if m0 == 1.0 && target == 1.0 {
            // The signal model runs beside the physics as its level reference.
            source.process_chunk(&mut self.reference);
            self.physics_chunk();
            self.match_level();
            *force = self.phys_force;
        } else {
            // Crossfade: both engines, linear ramp of ENGINE_CROSSFADE_S.
            source.process_chunk(force);
            self.reference = *force;
            self.physics_chunk();
            self.match_level();
            let step = (1.0 / (ENGINE_CROSSFADE_S * self.fs)) as f32;
            let step = if target > m0 { step } else { -step };
            let mut m = m0;
            for (f, p) in force.iter_mut().zip(&self.phys_force) {
                m = (m + step).clamp(0.0, 1.0);
                *f = (1.0 - m) * *f + m * *p;
            }
            self.mix = m;
        }
    }
}

impl Stage for EngineMix {
    /// The scene ball's source (the signal model, and the physics' level reference) and the
    /// chunk of force written.
    type Io<'a> = (&'a mut Source, &'a Object, &'a mut [f32; CHUNK]);

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        EngineMix::set_sample_rate(self, crate::block::sanitize_sample_rate(sample_rate_hz));
    }

    fn reset(&mut self, seed: u64) {
        self.seed = seed;
        EngineMix::reset(self);
    }

    fn set_params(&mut self, params: &Params) {
        let seed_changed = params.seed() != self.seed;
        self.seed = params.seed();
        EngineMix::set_params(self, params, seed_changed);
    }

    fn snap(&mut self) {
        EngineMix::snap(self);
    }

    /// Only the signal model runs and no crossfade is under way.
    fn is_idle(&self) -> bool {
        self.signal_only()
    }

    fn process(&mut self, (source, object, force): (&mut Source, &Object, &mut [f32; CHUNK])) {
        self.force_chunk(source, object, force);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::chain::SourceControls;

    fn params(engine: &str) -> Params {
        let mut p = Params::default();
        p.set_text("engine", engine).unwrap();
        p
    }

    #[test]
    fn the_signal_engine_hands_on_the_source_exactly() {
        let fs = 48_000.0;
        let p = params("signal");
        let mut mix = EngineMix::new(fs, &p);
        let mut a = Source::new(fs, SourceControls::default(), 3);
        let mut b = Source::new(fs, SourceControls::default(), 3);
        for _ in 0..50 {
            let mut x = [0f32; CHUNK];
            let mut y = [0f32; CHUNK];
            mix.engine_chunk(&mut a, &mut x);
            b.process_chunk(&mut y);
            assert_eq!(x, y);
        }
        assert!(mix.signal_only());
    }

    #[test]
    fn switching_engines_fades_over_the_crossfade_time() {
        let fs = 48_000.0;
        let mut mix = EngineMix::new(fs, &params("signal"));
        let mut src = Source::new(fs, SourceControls::default(), 1);
        let mut f = [0f32; CHUNK];
        mix.engine_chunk(&mut src, &mut f);
        mix.set_params(&params("physics"), false);
        assert!(!mix.signal_only());
        let chunks = (ENGINE_CROSSFADE_S * fs / CHUNK as f64).ceil() as usize;
        for k in 0..chunks {
            assert!(mix.mix < 1.0, "faded in after {k} chunks");
            mix.engine_chunk(&mut src, &mut f);
            assert!(f.iter().all(|x| x.is_finite()));
        }
        // f32 steps of 1/960 sum to just under 1 after 960 samples; the next chunk lands.
        assert!(
            mix.mix > 0.999,
            "the fade lasts {ENGINE_CROSSFADE_S} s: {}",
            mix.mix
        );
        mix.engine_chunk(&mut src, &mut f);
        assert_eq!(mix.mix, 1.0);
        // And back.
        mix.set_params(&params("signal"), false);
        for _ in 0..=chunks {
            mix.engine_chunk(&mut src, &mut f);
        }
        assert!(mix.signal_only());
    }

    #[test]
    fn reset_settles_on_the_selected_engine() {
        let mut mix = EngineMix::new(44_100.0, &params("signal"));
        mix.set_params(&params("physics"), true);
        mix.reset();
        assert_eq!(mix.mix, 1.0);
        assert!(!mix.running);
    }
}
