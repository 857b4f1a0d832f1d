//! A ball (and any extra balls, [`crate::balls`]) on one object: the whole chain, driven by
//! a [`Params`] set.
//!
//! ```text
//! Params ─┬► Source (series → pulses → AM → low-pass) ──┐ engine crossfade
//!         └► PhysicsEngine (Hunt–Crossley, RK4) × norm ──┴► force ─► Space (position comb) ─► DC block ─► Object (modal bank) ─► × gain ─► out
//!                                                          └──────────── output = force ─────────────────────────┘
//! ```
//!
//! The force comes from the signal model ([`Source`]) or from the physics engine
//! ([`PhysicsEngine`]), chosen by the `engine` parameter; the mapping of the controls onto
//! the physics and the level normalization are in [`crate::engine`]; the choice, the
//! physics controls' smoothing and the crossfade on a change of engine are
//! [`crate::engine_mix::EngineMix`]'s. With `engine = signal` the output is exactly
//! (bit for bit) what it was before the physics engine existed. The impact log
//! ([`Voice::drain_impacts`]) reports the impacts of whichever engine runs (the physics
//! ball's contacts, see [`crate::engine_mix`]).
//!
//! Lifecycle ([`crate`] docs): [`Voice::new`] allocates; [`Voice::set_sample_rate`] may
//! allocate; [`Voice::reset`] and [`Voice::process`] never do. Blocks of any length are
//! split into chunks of [`CHUNK`] samples, so the output does not depend on the block size:
//! the same seed and parameters give the same samples whether rendered in blocks of 1 or
//! 8192.

use crate::balls::{BallId, BallPool, BallTarget, Expression};
use crate::crowd::{Crowd, CrowdControls, MAX_DETAIL};
use crate::dcblock::DcBlock;
use crate::engine_mix::EngineMix;
use crate::gesture::{Gesture, GestureControls, PulseScale};
use crate::object::fitted::LoadedObject;
use crate::object::{Object, ObjectControls};
use crate::params::{ParamId, Params};
use crate::physics::PhysicsEngine;
use crate::smooth::Smoother;
use crate::source::{ImpactRecord, Source, SourceControls};
use crate::space::{Space, SpaceControls};
use crate::CHUNK;
use std::sync::Arc;

/// Gain applied to the raw force when the output is the force (its peaks are then about
/// −6 dBFS at the default settings).
pub const FORCE_LEVEL: f32 = 1.0;

/// A complete rolling voice.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate; `reset`, `set_params` and `process` do not.
#[derive(Clone, Debug)]
pub struct Voice {
    fs: f64,
    params: Params,
    source: Source,
    space: Space,
    dc: DcBlock,
    object: Object,
    /// The object's twins, played by the signal model's force and by the unscaled physics
    /// force while the physics engine runs (the level match of [`EngineMix`]), and their DC
    /// blockers.
    twins: [Object; 2],
    twin_dc: [DcBlock; 2],
    twin_in: [f32; CHUNK],
    twin_out: [[f32; CHUNK]; 2],
    gain: Smoother,
    /// 0 = object output, 1 = force output (crossfaded over the smoothing time).
    force_mix: Smoother,
    seed: u64,
    /// Samples processed since reset (the start of a render snaps the smoothers).
    started: bool,
    /// Position within the current chunk grid (so block size never changes the result).
    chunk_pos: usize,
    force: [f32; CHUNK],
    /// The chunk's output: the mid (mono) channel, and the side (L = mid + side,
    /// R = mid − side).
    sound: [f32; CHUNK],
    side: [f32; CHUNK],
    coupled: [f32; CHUNK],
    /// The engine choice: the physics engine, its smoothing, the crossfade.
    engines: EngineMix,
    /// Extra balls started like notes (see [`crate::balls`]).
    balls: BallPool,
    /// The level law's gain on the summed force ([`crate::balls::level_for_balls`]).
    ball_level: Smoother,
    /// The scene's crowd: balls 1…N−1 rolling with the scene's ball ([`crate::crowd`]).
    crowd: Crowd,
    /// The gesture: drop, spin, seams, paths with gravity ([`crate::gesture`]).
    gesture: Gesture,
    /// The last chunk's force and DC-blocked force were exactly zero (the DC blocker's
    /// state is then zero too): with a zero force it may be skipped.
    quiet: bool,
}

fn source_controls(p: &Params) -> SourceControls {
    SourceControls {
        size: p.get(ParamId::Size),
        velocity: p.get(ParamId::Velocity),
        roughness: p.get(ParamId::Roughness),
        asymmetry: p.get(ParamId::Asymmetry),
        sharpness: p.get(ParamId::Sharpness),
        action_x: p.get(ParamId::ActionX),
        action_y: p.get(ParamId::ActionY),
        asymmetry_law: p.asymmetry_law(),
        contact_scale: crate::contact::scene_contact_scale(p),
    }
}

fn space_controls(p: &Params) -> SpaceControls {
    SpaceControls {
        amount: p.get(ParamId::Comb),
        position: (p.get(ParamId::PositionX), p.get(ParamId::PositionY)),
        listen: (p.get(ParamId::ListenX), p.get(ParamId::ListenY)),
        trajectory: p.trajectory(),
        size_m: p.get(ParamId::ObjectSize),
        velocity: p.get(ParamId::Velocity),
    }
}

fn crowd_controls(p: &Params) -> CrowdControls {
    CrowdControls {
        count: p.get(ParamId::Crowd).round() as usize,
        spread: p.get(ParamId::CrowdSpread),
        detail: p.get(ParamId::CrowdDetail).round() as usize,
    }
}

/// The object controls of a parameter set (as the voice maps them).
pub fn object_controls(p: &Params) -> ObjectControls {
    ObjectControls {
        material_x: p.get(ParamId::MaterialX),
        material_y: p.get(ParamId::MaterialY),
        size_m: p.get(ParamId::ObjectSize),
        shape: p.shape(),
        modes: p.modes(),
        decay: p.get(ParamId::Decay),
        listen: (p.get(ParamId::ListenX), p.get(ParamId::ListenY)),
        width: p.width(),
    }
}

impl Voice {
    /// A voice at `sample_rate_hz` (sanitized to 8–384 kHz) with parameters `params`.
    ///
    /// # Allocation
    /// Allocates the signal chain and the physics engine (rolling-filter rings, modal
    /// arrays), whichever engine is selected, so that switching never allocates.
    pub fn new(sample_rate_hz: f64, params: &Params) -> Self {
        let fs = crate::sanitize_sample_rate(sample_rate_hz);
        let seed = params.seed();
        let mut v = Self {
            fs,
            params: *params,
            source: Source::new(fs, source_controls(params), seed),
            space: Space::new(fs, space_controls(params)),
            dc: DcBlock::new(fs),
            object: Object::new(fs, object_controls(params)),
            twins: [
                Object::new(fs, object_controls(params)),
                Object::new(fs, object_controls(params)),
            ],
            twin_dc: [DcBlock::new(fs), DcBlock::new(fs)],
            twin_in: [0.0; CHUNK],
            twin_out: [[0.0; CHUNK]; 2],
            gain: Smoother::new(params.gain_linear()),
            force_mix: Smoother::new(if params.force_only() { 1.0 } else { 0.0 }),
            seed,
            started: false,
            chunk_pos: 0,
            force: [0.0; CHUNK],
            sound: [0.0; CHUNK],
            side: [0.0; CHUNK],
            coupled: [0.0; CHUNK],
            engines: EngineMix::new(fs, params),
            balls: BallPool::new(fs),
            ball_level: Smoother::new(1.0),
            crowd: Crowd::new(fs, MAX_DETAIL, seed),
            gesture: Gesture::new(fs, GestureControls::from_params(params), seed),
            quiet: false,
        };
        v.object.set_quality(params.quality());
        v.object.set_controls(object_controls(params));
        for t in &mut v.twins {
            t.set_quality(params.quality());
            t.set_controls(object_controls(params));
        }
        v.balls.set_gesture(GestureControls::from_params(params));
        v.crowd.set_controls(crowd_controls(params));
        v.reset();
        v
    }

    /// Play a fitted object ([`crate::object::fitted`]) instead of the recipe object
    /// (shape × material × size); `None` goes back to the recipe. The object is prepared
    /// off the audio thread ([`LoadedObject::new`] allocates); this call is real-time safe:
    /// no allocation, and it returns the previous fitted object so that the caller drops
    /// it (and frees it) off the audio thread. Applies at the next chunk; the modes that no
    /// longer sound ring out (no click). The object's twins (the level match) follow.
    pub fn set_loaded_object(
        &mut self,
        object: Option<Arc<LoadedObject>>,
    ) -> Option<Arc<LoadedObject>> {
        for t in &mut self.twins {
            // The twins' previous references are never the last: `self.object` holds one.
            drop(t.set_loaded(object.clone()));
        }
        self.object.set_loaded(object)
    }

    /// The fitted object the voice plays, if any.
    pub fn loaded_object(&self) -> Option<&Arc<LoadedObject>> {
        self.object.loaded()
    }

    /// Choose the physics engine's RK4 substeps per output sample, 1..=8 (the accuracy knob
    /// of [`crate::physics`]); 0 = automatic (internal rate ≥ 96 kHz, see
    /// [`crate::engine::auto_oversample`]). Real-time safe; applies from the next chunk.
    pub fn set_physics_oversample(&mut self, oversample: usize) {
        self.engines.set_oversample(oversample);
    }

    /// Switch the object's high band on (the default) or off: for measuring what it costs
    /// and what it adds (`trundle bench`, `tests/full_band.rs`). Real-time safe.
    pub fn set_high_band(&mut self, on: bool) {
        self.object.set_high_band(on);
        for t in &mut self.twins {
            t.set_high_band(on);
        }
    }

    /// Switch the physics engine's level match to the signal model on (the default) or off
    /// ([`crate::engine_mix`]): for measuring the crossfade and the physics force itself.
    /// Real-time safe.
    pub fn set_engine_level_match(&mut self, on: bool) {
        self.engines.set_level_match(on);
    }

    /// The physics engine (health report, settings in force), for inspection.
    pub fn physics(&self) -> &PhysicsEngine {
        self.engines.physics()
    }

    /// The sample rate in Hz (after sanitizing).
    pub fn sample_rate(&self) -> f64 {
        self.fs
    }

    /// Change the sample rate (may allocate: call off the audio thread) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::sanitize_sample_rate(sample_rate_hz);
        self.source.set_sample_rate(self.fs);
        self.space.set_sample_rate(self.fs);
        self.dc.set_sample_rate(self.fs);
        self.balls.set_sample_rate(self.fs);
        self.crowd.set_sample_rate(self.fs);
        self.balls
            .set_gesture(GestureControls::from_params(&self.params));
        self.object.set_sample_rate(self.fs);
        for (t, d) in self.twins.iter_mut().zip(&mut self.twin_dc) {
            t.set_sample_rate(self.fs);
            d.set_sample_rate(self.fs);
        }
        self.engines.set_sample_rate(self.fs);
        self.gesture.set_sample_rate(self.fs);
        self.reset();
    }

    /// Back to the state after `new` with the current parameters: reseeded, silent, time 0.
    /// Real-time safe.
    pub fn reset(&mut self) {
        self.source.set_seed(self.seed);
        self.source.reset();
        self.space.reset();
        self.dc.reset();
        self.balls.reset(self.seed);
        self.crowd.reset(self.seed);
        self.ball_level.snap(1.0);
        self.object.reset();
        for (t, d) in self.twins.iter_mut().zip(&mut self.twin_dc) {
            t.reset();
            d.reset();
        }
        self.engines.reset();
        self.gesture.reset(self.seed);
        self.gain.snap_to_target();
        self.force_mix.snap_to_target();
        self.started = false;
        self.chunk_pos = 0;
        self.quiet = false;
    }

    /// The current parameter targets.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Set new parameter targets. Continuous parameters glide (no zipper noise, no clicks);
    /// the seed restarts the series; shape and mode count apply at the next chunk.
    /// Real-time safe.
    pub fn set_params(&mut self, params: &Params) {
        self.params = *params;
        self.source.set_controls(source_controls(params));
        self.space.set_controls(space_controls(params));
        self.object.set_quality(params.quality());
        self.object.set_controls(object_controls(params));
        for t in &mut self.twins {
            t.set_quality(params.quality());
            t.set_controls(object_controls(params));
        }
        self.gain.set_target(params.gain_linear());
        self.force_mix
            .set_target(if params.force_only() { 1.0 } else { 0.0 });
        let seed = params.seed();
        let seed_changed = seed != self.seed;
        if seed_changed {
            self.seed = seed;
            self.source.set_seed(seed);
        }
        self.engines.set_params(params, seed_changed);
        self.crowd.set_controls(crowd_controls(params));
        if seed_changed {
            self.crowd.reset(seed);
        }
        self.gesture
            .set_controls(GestureControls::from_params(params));
        self.balls.set_gesture(GestureControls::from_params(params));
    }

    /// Start the gesture again now (a drop falls, a spin begins). Real-time safe.
    pub fn restart_gesture(&mut self) {
        self.gesture.restart();
    }

    /// The gesture stage, for inspection.
    pub fn gesture(&self) -> &Gesture {
        &self.gesture
    }

    /// Hand the gesture's schedule to the source and the position stage: the rolling speed
    /// V × the gesture's factor, the bowl's radius. Does nothing when the gesture is
    /// neutral (the voice is then exactly what it was without gestures).
    fn apply_gesture(&mut self) {
        if self.gesture.is_neutral() {
            return;
        }
        let f = self.gesture.rolling_factor();
        let mut sc = source_controls(&self.params);
        sc.velocity = (sc.velocity * f).clamp(0.0, 1.0);
        self.source.set_controls(sc);
        let mut pc = space_controls(&self.params);
        pc.velocity *= f;
        self.space.set_controls(pc);
        self.space.set_path_scale(self.gesture.path_scale());
        // The physics engine's ball follows the same schedule (its rolling speed; the
        // bounces themselves are the gesture's pulses in either engine).
        let mut q = self.params;
        q.set_clamped(ParamId::Velocity, sc.velocity);
        self.engines.set_params(&q, false);
    }

    /// Record impacts for [`drain_impacts`](Self::drain_impacts).
    pub fn set_impact_log(&mut self, enabled: bool) {
        self.source.set_impact_log(enabled);
        self.engines.set_impact_log(enabled);
        self.gesture.set_impact_log(enabled);
    }

    /// Hand the impacts generated since the last call to `f` (oldest first); returns how
    /// many were dropped because the record was full (drain at least every ~30 000 impacts).
    pub fn drain_impacts(&mut self, mut f: impl FnMut(ImpactRecord)) -> u64 {
        // The gesture's impacts (bounces, spin contacts, seams) are merged in time order.
        let log = self.gesture.impact_log();
        let mut merged = |r: ImpactRecord| {
            while let Some(g) = log.peek().filter(|g| g.time_s <= r.time_s) {
                f(g);
                log.pop();
            }
            f(r);
        };
        let dropped = if self.engines.physics_selected() {
            // The signal model runs beside the physics only as its level reference.
            self.source.drain_impacts(|_| {});
            self.engines.drain_impacts(&mut merged)
        } else {
            self.source.drain_impacts(&mut merged) + self.engines.drain_impacts(|_| {})
        };
        while let Some(g) = log.pop() {
            f(g);
        }
        dropped + log.take_dropped()
    }

    /// Start an extra ball for `note` with note velocity `velocity` (0…1): pitch sets its
    /// size, velocity its speed (mapping in [`crate::balls`]). Real-time safe.
    pub fn note_on(&mut self, note: u8, velocity: f64) {
        let (sc, pc) = (source_controls(&self.params), space_controls(&self.params));
        self.balls.note_on(note, velocity, sc, pc);
    }

    /// Stop the extra ball(s) of `note`: they roll to a halt. Real-time safe.
    pub fn note_off(&mut self, note: u8) {
        self.balls.note_off(note);
    }

    /// Start an extra ball named as the host names a note (voice id, channel, key), so that
    /// per-ball gestures can address it ([`crate::balls`], "Expression per ball").
    /// Real-time safe.
    pub fn ball_on(&mut self, id: BallId, velocity: f64) {
        let (sc, pc) = (source_controls(&self.params), space_controls(&self.params));
        self.balls.ball_on(id, velocity, sc, pc);
    }

    /// Stop the extra ball(s) named by `target`: they roll to a halt. Real-time safe.
    pub fn ball_off(&mut self, target: BallTarget) {
        self.balls.ball_off(target);
    }

    /// A gesture for the ball(s) named by `target`: pressure, timbre, tuning, volume, pan
    /// or a poly-modulation offset ([`crate::balls`]). Real-time safe.
    pub fn express(&mut self, target: BallTarget, expression: Expression) {
        self.balls.express(target, expression);
    }

    /// Hand every extra ball that ended since the last call (rolled to rest, stolen, or
    /// stopped by a reset) to `f`: a host is told so it can free its note (CLAP note end).
    pub fn drain_ended_balls(&mut self, f: impl FnMut(BallId)) {
        self.balls.drain_ended(f);
    }

    /// Stop every extra ball. Real-time safe.
    pub fn all_notes_off(&mut self) {
        self.balls.all_notes_off();
    }

    /// Number of extra balls sounding.
    pub fn active_balls(&self) -> usize {
        self.balls.active()
    }

    /// The ball's current position on the object (normalised, see [`crate::space`]).
    pub fn ball_position(&self) -> (f64, f64) {
        self.space.ball()
    }

    /// The position stage, for inspection.
    pub fn space(&self) -> &Space {
        &self.space
    }

    /// The source (action parameters in force), for inspection.
    pub fn source(&self) -> &Source {
        &self.source
    }

    /// The object (modes, active count) for inspection.
    pub fn object(&self) -> &Object {
        &self.object
    }

    /// Mutable access to the source (pulse evaluation mode).
    pub fn source_mut(&mut self) -> &mut Source {
        &mut self.source
    }

    /// Render `out.len()` samples of the mono mix (the mid, (L + R)/2), overwriting `out`.
    /// Any length, including 0.
    pub fn process(&mut self, out: &mut [f32]) {
        self.start();
        let mut done = 0;
        while done < out.len() {
            if self.chunk_pos == 0 {
                self.render_chunk();
            }
            let take = (CHUNK - self.chunk_pos).min(out.len() - done);
            out[done..done + take]
                .copy_from_slice(&self.sound[self.chunk_pos..self.chunk_pos + take]);
            done += take;
            self.chunk_pos = (self.chunk_pos + take) % CHUNK;
        }
    }

    /// Render `left.len()` stereo frames into `left` and `right` (overwritten; they must
    /// have the same length, the shorter sets the count). Any length, including 0. The
    /// force output is the same on both channels. `(left + right)/2` is exactly what
    /// [`process`](Self::process) renders.
    pub fn process_stereo(&mut self, left: &mut [f32], right: &mut [f32]) {
        self.start();
        let n = left.len().min(right.len());
        let mut done = 0;
        while done < n {
            if self.chunk_pos == 0 {
                self.render_chunk();
            }
            let take = (CHUNK - self.chunk_pos).min(n - done);
            let range = self.chunk_pos..self.chunk_pos + take;
            for ((l, r), (&m, &s)) in left[done..done + take]
                .iter_mut()
                .zip(&mut right[done..done + take])
                .zip(self.sound[range.clone()].iter().zip(&self.side[range]))
            {
                *l = flush_output(m + s);
                *r = flush_output(m - s);
            }
            done += take;
            self.chunk_pos = (self.chunk_pos + take) % CHUNK;
        }
    }

    /// Snap the smoothers on the first call after a reset (a render starts at its targets).
    fn start(&mut self) {
        if !self.started {
            self.apply_gesture();
            self.source.snap_controls();
            self.crowd.snap_controls(self.crowd_scene());
            if self.params.velocity() > 0.0 {
                // A crowd starts at its level (`balls`' law), not gliding down from one ball's.
                let rolling = self.balls.active() + self.crowd.count();
                self.ball_level.snap(crate::balls::level_for_balls(rolling));
            }
            self.space.snap_controls();
            self.object.snap_controls();
            for t in &mut self.twins {
                t.snap_controls();
            }
            self.gain.snap_to_target();
            self.force_mix.snap_to_target();
            self.engines.snap();
            self.started = true;
        }
    }

    /// The scene's controls as the crowd follows them: the scene ball's, at the gesture's
    /// rolling speed.
    fn crowd_scene(&self) -> SourceControls {
        let mut sc = source_controls(&self.params);
        if !self.gesture.is_neutral() {
            sc.velocity = (sc.velocity * self.gesture.rolling_factor()).clamp(0.0, 1.0);
        }
        sc
    }

    /// How the gesture's impacts become pulses: the source's contact and level in force.
    fn pulse_scale(&self) -> PulseScale {
        crate::gesture::pulse_scale(&self.source, self.params.size())
    }

    fn render_chunk(&mut self) {
        let fs = self.fs;
        let signal_only = self.engines.signal_only();
        self.apply_gesture();
        if self.quiet
            && signal_only
            && self.gesture.is_idle()
            && self.balls.active() == 0
            && self.crowd.is_idle()
            && self.source.is_idle()
            && self.space.is_idle()
            && self.object.is_idle()
            && !self.gain.is_moving()
            && !self.force_mix.is_moving()
        {
            // Idle (the silence skip below, taken before the source): nothing rolls, nothing
            // rings, nothing glides. Only time moves on; the output is exact zeros — the same
            // samples and the same state as the full path (`force` and `coupled` are still
            // all zero from the last chunk: that is what `quiet` records).
            self.source.skip_chunk(CHUNK);
            self.engines.skip_chunk();
            self.gesture.skip_chunk(CHUNK);
            self.sound.fill(0.0);
            self.side.fill(0.0);
            return;
        }
        let v_before = self.source.velocity();
        self.engines.force_chunk(&mut self.source, &mut self.force);
        if !self.gesture.is_neutral() {
            // The gesture's impacts join the rolling force before the position stage.
            let k = self.pulse_scale();
            let speed = (v_before, self.source.velocity());
            self.gesture.process(&mut self.force, k, speed);
        } else {
            self.gesture.skip_chunk(CHUNK);
        }
        self.space.process(&mut self.force);
        if self.balls.active() > 0 {
            // Extra balls roll on the same object: their forces add before it.
            let (sc, pc) = (source_controls(&self.params), space_controls(&self.params));
            self.balls.add_chunk(&mut self.force, sc, pc);
        }
        if self.crowd.count() > 1 || !self.crowd.is_idle() {
            // The crowd rolls with the scene's ball (`crowd`): its force joins here, at the
            // scene ball's place.
            let sc = self.crowd_scene();
            self.crowd.add_chunk(&mut self.force, sc);
        }
        // The level law for summed balls (`balls`): N rolling balls at 1/√N each (the
        // scene's ball counts with its crowd).
        let scene_balls = if self.params.velocity() > 0.0 {
            self.crowd.count()
        } else {
            0
        };
        let rolling = self.balls.active() + scene_balls;
        self.ball_level
            .set_target(crate::balls::level_for_balls(rolling));
        if self.ball_level.is_moving() || self.ball_level.value() != 1.0 {
            let (a, b) = self.ball_level.advance(CHUNK, fs);
            let step = (b - a) / CHUNK as f64;
            for (i, f) in self.force.iter_mut().enumerate() {
                *f *= (a + step * (i + 1) as f64) as f32;
            }
        }
        let silent_force = self.force.iter().all(|&f| f == 0.0);
        if self.quiet
            && silent_force
            && signal_only
            && self.source.at_rest()
            && self.gesture.is_idle()
            && self.balls.active() == 0
            && self.crowd.is_idle()
            && self.object.is_silent()
        {
            // Silence skip (docs/MODEL.md "Speed and accuracy"): the ball at rest on the signal
            // engine, no extra ball, the DC blocker settled (its input and output were zero
            // last chunk, so `coupled` is still all zero) and the object rung out. The
            // object only advances its control smoothers (it touches no mode for a zero
            // input, see `object`), and the output is exactly zero: the same samples and
            // state as the full path, at a fraction of its cost.
            self.object.set_ball(self.space.ball());
            self.object
                .process_chunk_stereo(&self.coupled, &mut self.sound, &mut self.side);
            self.gain.advance(CHUNK, fs);
            self.force_mix.advance(CHUNK, fs);
            return;
        }
        // The object hears the force without its static load (see `dcblock`), at the
        // ball's place.
        self.dc.process(&self.force, &mut self.coupled);
        self.quiet = silent_force && self.coupled.iter().all(|&c| c == 0.0);
        self.object.set_ball(self.space.ball());
        self.object
            .process_chunk_stereo(&self.coupled, &mut self.sound, &mut self.side);
        if let Some((reference, physics)) = self.engines.level_forces() {
            // The level match (`engine_mix`): both engines' forces through the twins.
            for (i, f) in [reference, physics].into_iter().enumerate() {
                self.twin_dc[i].process(f, &mut self.twin_in);
                self.twins[i].set_ball(self.space.ball());
                self.twins[i].process_chunk(&self.twin_in, &mut self.twin_out[i]);
            }
            self.engines
                .observe_level(&self.twin_out[0], &self.twin_out[1]);
        }
        let (g0, g1) = self.gain.advance(CHUNK, fs);
        let (x0, x1) = self.force_mix.advance(CHUNK, fs);
        let inv = 1.0 / CHUNK as f32;
        let (g0, g1, x0, x1) = (g0 as f32, g1 as f32, x0 as f32, x1 as f32);
        if x0 == 0.0 && x1 == 0.0 {
            // The object's output alone (x = 0 throughout): the gain and the flush, in a
            // pass without a branch per sample.
            for (i, (m, s)) in self.sound.iter_mut().zip(&mut self.side).enumerate() {
                let t = (i + 1) as f32 * inv;
                let g = g0 + (g1 - g0) * t;
                *m = flush_output(g * *m);
                *s = flush_output(g * *s);
            }
            return;
        }
        for i in 0..CHUNK {
            let t = (i + 1) as f32 * inv;
            let g = g0 + (g1 - g0) * t;
            let x = x0 + (x1 - x0) * t;
            let (y, side) = if x == 0.0 {
                (self.sound[i], self.side[i])
            } else {
                (
                    (1.0 - x) * self.sound[i] + x * FORCE_LEVEL * self.force[i],
                    (1.0 - x) * self.side[i],
                )
            };
            // Last line of defence: never hand a host NaN, infinity or a subnormal (the
            // object's state is flushed, but the force output — a low-pass tail — and a
            // tiny gain can reach the subnormal range; a validator found −4·10⁻⁴⁰).
            self.sound[i] = flush_output(g * y);
            self.side[i] = flush_output(g * side);
        }
    }
}

/// A sample as it may leave the voice: NaN, infinities and subnormals become 0 (zeros and
/// normal numbers pass unchanged). Written with comparisons only, so loops over it
/// vectorize.
#[inline]
fn flush_output(x: f32) -> f32 {
    let a = x.abs();
    if (f32::MIN_POSITIVE..=f32::MAX).contains(&a) | (a == 0.0) {
        x
    } else {
        0.0
    }
}
