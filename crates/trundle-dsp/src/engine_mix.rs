//! Which engine makes the force, and the crossfade when that changes.
//!
//! The voice's force comes from the signal model ([`Source`]) or from the physics engine
//! ([`PhysicsEngine`], see [`crate::engine`] for how the controls map onto it). This type
//! owns the physics engine, its smoothed controls and the crossfade between the two:
//!
//! * **Smoothing.** Size, velocity, roughness and asymmetry glide for the physics engine as
//!   they do for the signal model (the surface, law and seed do not); its settings are
//!   recomputed once per chunk, and only while a control is moving.
//! * **Crossfade.** A change of `engine` fades the two forces linearly over
//!   [`ENGINE_CROSSFADE_S`] (both engines run meanwhile), so switching never clicks; otherwise
//!   only the selected engine runs, and with `engine = signal` the force is exactly the
//!   source's, bit for bit.
//! * **Level.** The physics force (newtons) is handed on in units of the ball's weight times
//!   [`PHYSICS_FORCE_SCALE`] (see [`crate::engine`]).
//!
//! Lifecycle as every DSP type ([`crate`] docs): [`EngineMix::new`] allocates (the physics
//! engine); the rest is real-time safe.

use crate::engine::{
    auto_oversample, Engine, PhysicsControls, ENGINE_CROSSFADE_S, PHYSICS_FORCE_SCALE,
};
use crate::object::Quality;
use crate::params::Params;
use crate::physics::{PhysicsEngine, MAX_OVERSAMPLE};
use crate::smooth::Smoother;
use crate::source::Source;
use crate::CHUNK;

/// The engine choice, the physics engine and the crossfade between the engines' forces.
///
/// # Allocation
/// `new` allocates the physics engine; nothing else does.
#[derive(Clone, Debug)]
pub struct EngineMix {
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
        }
    }

    fn oversample(&self) -> usize {
        if self.oversample == 0 {
            self.quality
                .physics_oversample()
                .unwrap_or_else(|| auto_oversample(self.fs))
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
        self.apply();
    }

    /// Back to the state after `new` with the current targets.
    pub fn reset(&mut self) {
        self.snap_controls();
        self.physics.reset();
        self.running = false;
        self.mix = self.mix_target;
    }

    /// Jump the crossfade to its target (the start of a render).
    pub fn snap(&mut self) {
        self.mix = self.mix_target;
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
        self.target = pc;
        self.mix_target = mix_target(params);
        if seed_changed {
            // A new surface: the seed of the profile takes effect at the engine's reset.
            self.apply();
            self.physics.reset();
        }
    }

    /// Only the signal model runs and no crossfade is under way.
    pub fn signal_only(&self) -> bool {
        self.mix == 0.0 && self.mix_target == 0.0
    }

    /// One chunk of the physics force, normalized (see [`crate::engine`]) into `phys_force`.
    fn physics_chunk(&mut self) {
        if !self.running {
            self.snap_controls();
            self.running = true;
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
        let norm = (PHYSICS_FORCE_SCALE / (st.mass_kg * crate::physics::GRAVITY_M_S2)) as f32;
        for x in &mut self.phys_force {
            *x *= norm;
        }
    }

    /// One chunk of the force: the source's, the physics engine's, or the crossfade of both.
    pub fn force_chunk(&mut self, source: &mut Source, force: &mut [f32; CHUNK]) {
        let (m0, target) = (self.mix, self.mix_target);
        if m0 == 0.0 && target == 0.0 {
            // Signal engine only: exactly the source's force.
            source.process_chunk(force);
            self.running = false;
        } else if m0 == 1.0 && target == 1.0 {
            self.physics_chunk();
            *force = self.phys_force;
        } else {
            // Crossfade: both engines, linear ramp of ENGINE_CROSSFADE_S.
            source.process_chunk(force);
            self.physics_chunk();
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::SourceControls;

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
            mix.force_chunk(&mut a, &mut x);
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
        mix.force_chunk(&mut src, &mut f);
        mix.set_params(&params("physics"), false);
        assert!(!mix.signal_only());
        let chunks = (ENGINE_CROSSFADE_S * fs / CHUNK as f64).ceil() as usize;
        for k in 0..chunks {
            assert!(mix.mix < 1.0, "faded in after {k} chunks");
            mix.force_chunk(&mut src, &mut f);
            assert!(f.iter().all(|x| x.is_finite()));
        }
        // f32 steps of 1/960 sum to just under 1 after 960 samples; the next chunk lands.
        assert!(
            mix.mix > 0.999,
            "the fade lasts {ENGINE_CROSSFADE_S} s: {}",
            mix.mix
        );
        mix.force_chunk(&mut src, &mut f);
        assert_eq!(mix.mix, 1.0);
        // And back.
        mix.set_params(&params("signal"), false);
        for _ in 0..=chunks {
            mix.force_chunk(&mut src, &mut f);
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
