//! A ball (and any extra balls, [`crate::scene::balls`]) on one object: the whole chain, driven by
//! a [`Params`] set.
//!
//! ```text
//! Params ──► every stage's set_params (stage::Stage)
//!
//! source ─► engines ─► gesture ─► space ─► + balls ─► + crowd ─► × hand ─► bumps ─► × level law ─► force
//! (signal   (or the     (drops,   (position  (notes)   (N balls)  (strokes, (knocks,   (1/√N)
//!  model)    physics,    spins)    comb)                           wander)   swells)
//!            crossfade)
//! force ─► dc ─► object (modal bank) ─► mid, side ─► × gain ─► + floor ─► body EQ ─► out   (or the force)
//!                twins: the object again, for the physics engine's level match
//! ```
//!
//! The stages are listed once (`stages!` below): building them, changing the sample rate,
//! resetting, handing them the parameters, snapping and the idle test fan out over that
//! list; `Voice::render_chunk` runs them in the order drawn above.
//!
//! The force comes from the signal model ([`Source`]) or the physics engine ([`PhysicsEngine`],
//! its mapping and level in [`crate::physics::mapping`]), as `engine` says; the choice, smoothing
//! and crossfade are [`crate::scene::engine_mix::EngineMix`]'s (`engine = signal`: bit for bit
//! as before the physics engine). The impact log ([`Voice::drain_impacts`]) reports whichever
//! engine's impacts.
//!
//! Lifecycle ([`crate::stage`]): [`Voice::new`] and [`Voice::set_sample_rate`] may allocate,
//! [`Voice::reset`] and [`Voice::process`] never. Blocks are split into chunks of [`CHUNK`]
//! samples: the same seed and parameters give the same samples in blocks of 1 or 8192.

use crate::block::{flush_output, CHUNK};
use crate::object::fitted::LoadedObject;
use crate::object::resonator::{Object, ObjectControls};
use crate::params::{ParamId, Params};
use crate::physics::PhysicsEngine;
use crate::scene::balls::{level_for_balls, BallId, BallPool, BallTarget, Expression};
use crate::scene::body_eq::{BodyEq, BodyEqCurve};
use crate::scene::bumps::{BumpControls, Bumps};
use crate::scene::crowd::{scene_controls, Crowd, CrowdControls, MAX_DETAIL};
use crate::scene::engine_mix::EngineMix;
use crate::scene::floor::Floor;
use crate::scene::gesture::{Gesture, GestureControls};
use crate::scene::hand::{Hand, HandControls};
use crate::scene::space::{Space, SpaceControls};
use crate::scene::twins::Twins;
use crate::smooth::Smoother;
use crate::source::chain::{ImpactRecord, Source, SourceControls};
use crate::source::crackle::Crackle;
use crate::source::dcblock::DcBlock;
use crate::source::micro::Micro;
use crate::stage::Stage;
use std::sync::Arc;

/// Gain applied to the raw force when the output is the force (its peaks are then about
/// −6 dBFS at the default settings).
pub const FORCE_LEVEL: f32 = 1.0;

/// The voice's stages ([`Stage`]), in the order a chunk flows through them, each with how
/// it is built from the parameters. Building, re-rating, resetting, snapping, giving
/// controls and the idle test fan out over this one list: a new stage is its own file and
/// one line here (and one call where it processes in [`Voice::render_chunk`]).
macro_rules! stages {
    ($($(#[doc = $doc:literal])* $name:ident: $ty:ty = $build:expr,)*) => {
        /// The voice's stages (see `stages!`).
        #[derive(Clone, Debug)]
        struct Stages {
            $($(#[doc = $doc])* $name: $ty,)*
        }

        impl Stages {
            /// Every stage for `params` at `fs` (sanitized), seeded with `seed`. Allocates.
            fn new(fs: f64, params: &Params, seed: u64) -> Self {
                Self {
                    $($name: {
                        let build: fn(f64, &Params, u64) -> $ty = $build;
                        build(fs, params, seed)
                    },)*
                }
            }

            fn set_sample_rate(&mut self, fs: f64) {
                $(Stage::set_sample_rate(&mut self.$name, fs);)*
            }

            fn reset(&mut self, seed: u64) {
                $(Stage::reset(&mut self.$name, seed);)*
            }

            fn set_params(&mut self, params: &Params) {
                $(Stage::set_params(&mut self.$name, params);)*
            }

            fn snap(&mut self) {
                $(Stage::snap(&mut self.$name);)*
            }

            fn is_idle(&self) -> bool {
                true $(&& Stage::is_idle(&self.$name))*
            }
        }
    };
}

stages! {
    /// The signal model's force: series → pulses → AM → low-pass.
    source: Source = |fs, p, seed| Source::new(fs, SourceControls::from_params(p), seed),
    /// The engine choice: the physics engine, its smoothing, the crossfade.
    engines: EngineMix = |fs, p, _| EngineMix::new(fs, p),
    /// The gesture: drop, spin, seams, paths with gravity ([`crate::scene::gesture`]).
    gesture: Gesture = |fs, p, seed| Gesture::new(fs, GestureControls::from_params(p), seed),
    /// The sparse loud layer over the contact ([`crate::source::crackle`]).
    crackle: Crackle = |fs, p, seed| Crackle::new(fs, p, seed),
    /// The contact's high band ([`crate::source::micro`]).
    micro: Micro = |fs, p, seed| Micro::new(fs, p, seed),
    /// The ball's place on the object and the position comb ([`crate::scene::space`]).
    space: Space = |fs, p, _| Space::new(fs, SpaceControls::from_params(p)),
    /// Extra balls started like notes ([`crate::scene::balls`]).
    balls: BallPool = |fs, p, _| {
        let mut b = BallPool::new(fs);
        b.set_gesture(GestureControls::from_params(p));
        b
    },
    /// The scene's crowd: balls 1…N−1 rolling with the scene's ball ([`crate::scene::crowd`]).
    crowd: Crowd = |fs, p, seed| {
        let mut c = Crowd::new(fs, MAX_DETAIL, seed);
        c.set_controls(CrowdControls::from_params(p));
        c
    },
    /// The hand: strokes and wander of speed and pressure ([`crate::scene::hand`]).
    hand: Hand = |fs, p, seed| Hand::new(fs, HandControls::from_params(p), seed),
    /// Bumps: knocks and swells of the force ([`crate::scene::bumps`]).
    bumps: Bumps = |fs, p, seed| Bumps::new(fs, BumpControls::from_params(p), seed),
    /// The force's coupling into the object ([`crate::source::dcblock`]).
    dc: DcBlock = |fs, _, _| DcBlock::new(fs),
    /// The object ([`crate::object::resonator`]).
    object: Object = |fs, p, _| {
        let mut o = Object::new(fs, ObjectControls::from_params(p));
        Stage::set_params(&mut o, p);
        o
    },
    /// The object's twins, for the physics engine's level match ([`crate::scene::twins`]).
    twins: Twins = |fs, p, _| Twins::new(fs, p),
    /// The noise floor on the output, after the gain ([`crate::scene::floor`]).
    floor: Floor = |fs, p, seed| Floor::new(fs, p, seed),
    /// The body EQ on the output, after the gain ([`crate::scene::body_eq`]).
    body_eq: BodyEq = |fs, p, _| BodyEq::new(fs, p),
}

/// A complete rolling voice.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate; `reset`, `set_params` and `process` do not.
#[derive(Clone, Debug)]
pub struct Voice {
    fs: f64,
    params: Params,
    /// The stages, in chunk order.
    chain: Stages,
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
    /// The micro force's directly radiated share (valid when `micro_on`).
    direct: [f32; CHUNK],
    micro_on: bool,
    /// The level law's gain on the summed force ([`crate::scene::balls::level_for_balls`]).
    ball_level: Smoother,
    /// The last chunk's force and DC-blocked force were exactly zero (the DC blocker's
    /// state is then zero too): with a zero force it may be skipped.
    quiet: bool,
}

/// The object controls of a parameter set (as the voice maps them,
/// [`ObjectControls::from_params`]).
pub fn object_controls(p: &Params) -> ObjectControls {
    ObjectControls::from_params(p)
}

impl Voice {
    /// A voice at `sample_rate_hz` (sanitized to 8–384 kHz) with parameters `params`.
    ///
    /// # Allocation
    /// Allocates the signal chain and the physics engine (rolling-filter rings, modal
    /// arrays), whichever engine is selected, so that switching never allocates.
    pub fn new(sample_rate_hz: f64, params: &Params) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let seed = params.seed();
        let mut v = Self {
            fs,
            params: *params,
            chain: Stages::new(fs, params, seed),
            gain: Smoother::new(params.gain_linear()),
            force_mix: Smoother::new(if params.force_only() { 1.0 } else { 0.0 }),
            seed,
            started: false,
            chunk_pos: 0,
            force: [0.0; CHUNK],
            sound: [0.0; CHUNK],
            side: [0.0; CHUNK],
            coupled: [0.0; CHUNK],
            direct: [0.0; CHUNK],
            micro_on: false,
            ball_level: Smoother::new(1.0),
            quiet: false,
        };
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
        self.chain.twins.set_loaded(object.clone());
        self.chain.object.set_loaded(object)
    }

    /// Play a body EQ curve on the output ([`crate::scene::body_eq`]; the `body_eq` control
    /// sets how much of it); `None` = no EQ (the output exactly as without it). The curve is
    /// built off the audio thread; this call designs the filter (fixed arrays, no
    /// allocation: real-time safe) and returns the previous curve so the caller drops it
    /// off the audio thread. Applies from the next chunk.
    pub fn set_body_eq(&mut self, curve: Option<Arc<BodyEqCurve>>) -> Option<Arc<BodyEqCurve>> {
        self.chain.body_eq.set_curve(curve)
    }

    /// The body EQ stage (its curve, designed gains and error), for inspection.
    pub fn body_eq(&self) -> &BodyEq {
        &self.chain.body_eq
    }

    /// The fitted object the voice plays, if any.
    pub fn loaded_object(&self) -> Option<&Arc<LoadedObject>> {
        self.chain.object.loaded()
    }

    /// Choose the physics engine's RK4 substeps per output sample, 1..=8 (the accuracy knob
    /// of [`crate::physics`]); 0 = automatic (internal rate ≥ 96 kHz, see
    /// [`crate::physics::mapping::auto_oversample`]). Real-time safe; applies from the next chunk.
    pub fn set_physics_oversample(&mut self, oversample: usize) {
        self.chain.engines.set_oversample(oversample);
    }

    /// Switch the object's high band on (the default) or off: for measuring what it costs
    /// and what it adds (`trundle bench`, `tests/full_band.rs`). Real-time safe.
    pub fn set_high_band(&mut self, on: bool) {
        self.chain.object.set_high_band(on);
        self.chain.twins.set_high_band(on);
    }

    /// Switch the micro-roughness's directly radiated share on (the default) or off
    /// ([`crate::source::micro`]): for measuring what the object's modes alone make of it.
    /// Real-time safe.
    pub fn set_micro_direct(&mut self, on: bool) {
        self.chain.micro.set_direct(on);
    }

    /// Switch the physics engine's level match to the signal model on (the default) or off
    /// ([`crate::scene::engine_mix`]): for measuring the crossfade and the physics force itself.
    /// Real-time safe.
    pub fn set_engine_level_match(&mut self, on: bool) {
        self.chain.engines.set_level_match(on);
    }

    /// The physics engine (health report, settings in force), for inspection.
    pub fn physics(&self) -> &PhysicsEngine {
        self.chain.engines.physics()
    }

    /// The sample rate in Hz (after sanitizing).
    pub fn sample_rate(&self) -> f64 {
        self.fs
    }

    /// Change the sample rate (may allocate: call off the audio thread) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.chain.set_sample_rate(self.fs);
        self.reset();
    }

    /// Back to the state after `new` with the current parameters: reseeded, silent, time 0.
    /// Real-time safe.
    pub fn reset(&mut self) {
        self.chain.reset(self.seed);
        self.ball_level.snap(1.0);
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
        self.chain.set_params(params);
        self.gain.set_target(params.gain_linear());
        self.force_mix
            .set_target(if params.force_only() { 1.0 } else { 0.0 });
        self.seed = params.seed();
    }

    /// Start the gesture again now (a drop falls, a spin begins). Real-time safe.
    pub fn restart_gesture(&mut self) {
        self.chain.gesture.restart();
    }

    /// The gesture stage, for inspection.
    pub fn gesture(&self) -> &Gesture {
        &self.chain.gesture
    }

    /// Hand the gesture's schedule to the source and the position stage: the rolling speed
    /// V × the gesture's factor × the hand's ([`crate::scene::hand`]), the bowl's radius.
    /// Does nothing when the gesture and the hand are neutral (the voice is then exactly what
    /// it was without them).
    fn apply_gesture(&mut self) {
        let Some(f) = self.rolling_factor() else {
            return;
        };
        let c = &mut self.chain;
        let mut sc = SourceControls::from_params(&self.params);
        sc.velocity = (sc.velocity * f).clamp(0.0, 1.0);
        c.source.set_controls(sc);
        let mut pc = SpaceControls::from_params(&self.params);
        pc.velocity *= f;
        c.space.set_controls(pc);
        c.space.set_path_scale(c.gesture.path_scale());
        // The physics engine's ball follows the same schedule (its rolling speed; the
        // bounces themselves are the gesture's pulses in either engine).
        let mut q = self.params;
        q.set_clamped(ParamId::Velocity, sc.velocity);
        c.engines.set_params(&q, false);
    }

    /// Record impacts for [`drain_impacts`](Self::drain_impacts).
    pub fn set_impact_log(&mut self, enabled: bool) {
        self.chain.source.set_impact_log(enabled);
        self.chain.engines.set_impact_log(enabled);
        self.chain.gesture.set_impact_log(enabled);
    }

    /// Hand the impacts generated since the last call to `f` (oldest first); returns how
    /// many were dropped because the record was full (drain at least every ~30 000 impacts).
    pub fn drain_impacts(&mut self, mut f: impl FnMut(ImpactRecord)) -> u64 {
        // The gesture's impacts (bounces, spin contacts, seams) are merged in time order.
        let log = self.chain.gesture.impact_log();
        let mut merged = |r: ImpactRecord| {
            while let Some(g) = log.peek().filter(|g| g.time_s <= r.time_s) {
                f(g);
                log.pop();
            }
            f(r);
        };
        let dropped = if self.chain.engines.physics_selected() {
            // The signal model runs beside the physics only as its level reference.
            self.chain.source.drain_impacts(|_| {});
            self.chain.engines.drain_impacts(&mut merged)
        } else {
            self.chain.source.drain_impacts(&mut merged) + self.chain.engines.drain_impacts(|_| {})
        };
        while let Some(g) = log.pop() {
            f(g);
        }
        dropped + log.take_dropped()
    }

    /// Start an extra ball for `note` with note velocity `velocity` (0…1): pitch sets its
    /// size, velocity its speed (mapping in [`crate::scene::balls`]). Real-time safe.
    pub fn note_on(&mut self, note: u8, velocity: f64) {
        let (sc, pc) = (
            SourceControls::from_params(&self.params),
            SpaceControls::from_params(&self.params),
        );
        self.chain.balls.note_on(note, velocity, sc, pc);
    }

    /// Stop the extra ball(s) of `note`: they roll to a halt. Real-time safe.
    pub fn note_off(&mut self, note: u8) {
        self.chain.balls.note_off(note);
    }

    /// Start an extra ball named as the host names a note (voice id, channel, key), so that
    /// per-ball gestures can address it ([`crate::scene::balls`], "Expression per ball").
    /// Real-time safe.
    pub fn ball_on(&mut self, id: BallId, velocity: f64) {
        let (sc, pc) = (
            SourceControls::from_params(&self.params),
            SpaceControls::from_params(&self.params),
        );
        self.chain.balls.ball_on(id, velocity, sc, pc);
    }

    /// Stop the extra ball(s) named by `target`: they roll to a halt. Real-time safe.
    pub fn ball_off(&mut self, target: BallTarget) {
        self.chain.balls.ball_off(target);
    }

    /// A gesture for the ball(s) named by `target`: pressure, timbre, tuning, volume, pan
    /// or a poly-modulation offset ([`crate::scene::balls`]). Real-time safe.
    pub fn express(&mut self, target: BallTarget, expression: Expression) {
        self.chain.balls.express(target, expression);
    }

    /// Hand every extra ball that ended since the last call (rolled to rest, stolen, or
    /// stopped by a reset) to `f`: a host is told so it can free its note (CLAP note end).
    pub fn drain_ended_balls(&mut self, f: impl FnMut(BallId)) {
        self.chain.balls.drain_ended(f);
    }

    /// Stop every extra ball. Real-time safe.
    pub fn all_notes_off(&mut self) {
        self.chain.balls.all_notes_off();
    }

    /// Number of extra balls sounding.
    pub fn active_balls(&self) -> usize {
        self.chain.balls.active()
    }

    /// The ball's current position on the object (normalised, see [`crate::scene::space`]).
    pub fn ball_position(&self) -> (f64, f64) {
        self.chain.space.ball()
    }

    /// The position stage, for inspection.
    pub fn space(&self) -> &Space {
        &self.chain.space
    }

    /// The source (action parameters in force), for inspection.
    pub fn source(&self) -> &Source {
        &self.chain.source
    }

    /// The object (modes, active count) for inspection.
    pub fn object(&self) -> &Object {
        &self.chain.object
    }

    /// Mutable access to the source (pulse evaluation mode).
    pub fn source_mut(&mut self) -> &mut Source {
        &mut self.chain.source
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
            let scene = scene_controls(&self.params, self.rolling_factor());
            self.chain.crowd.follow(scene);
            self.chain.snap();
            if self.params.velocity() > 0.0 {
                // A crowd starts at its level (`balls`' law), not gliding down from one ball's.
                let rolling = self.chain.balls.active() + self.chain.crowd.count();
                self.ball_level.snap(level_for_balls(rolling));
            }
            self.gain.snap_to_target();
            self.force_mix.snap_to_target();
            self.started = true;
        }
    }

    /// The gesture's factor on the rolling speed times the hand's, `None` when both are
    /// neutral.
    fn rolling_factor(&self) -> Option<f64> {
        let g = &self.chain.gesture;
        let gesture = (!g.is_neutral()).then(|| g.rolling_factor());
        match (gesture, self.chain.hand.speed_factor()) {
            (None, None) => None,
            (g, h) => Some(g.unwrap_or(1.0) * h.unwrap_or(1.0)),
        }
    }

    /// One chunk through the stages, the floor (none when off), the body EQ (or its bypass).
    fn render_chunk(&mut self) {
        self.render_dry_chunk();
        let (c, sound) = (&mut self.chain, 1.0 - self.force_mix.value() as f32);
        Stage::process(&mut c.floor, (&mut self.sound, &mut self.side, sound));
        Stage::process(&mut c.body_eq, (&mut self.sound, &mut self.side));
    }

    /// One chunk through the chain of stages: the force (engine, gesture, space, extra
    /// balls, crowd, the level law), then the object, then the output.
    fn render_dry_chunk(&mut self) {
        let signal_only = self.chain.engines.signal_only();
        self.apply_gesture();
        if self.quiet
            && self.chain.is_idle()
            && !self.gain.is_moving()
            && !self.force_mix.is_moving()
        {
            // Idle (the silence skip below, taken before the source): nothing rolls, nothing
            // rings, nothing glides. Only time moves on; the output is exact zeros — the same
            // samples and the same state as the full path (`force` and `coupled` are still
            // all zero from the last chunk: that is what `quiet` records).
            self.chain.source.skip_chunk(CHUNK);
            self.chain.engines.skip_chunk();
            self.chain.gesture.skip_chunk(CHUNK);
            self.sound.fill(0.0);
            self.side.fill(0.0);
            return;
        }
        let c = &mut self.chain;
        let v_before = c.source.velocity();
        Stage::process(&mut c.engines, (&mut c.source, &c.object, &mut self.force));
        let speed = (v_before, c.source.velocity());
        // The gesture's impacts join the rolling force before the position stage.
        let size = self.params.size();
        Stage::process(&mut c.gesture, (&mut self.force, &c.source, size, speed));
        // The contact's textures (off: not called, the samples are those without them).
        if !c.crackle.is_off() {
            Stage::process(&mut c.crackle, (&mut self.force, speed));
        }
        self.micro_on = !c.micro.is_off();
        if self.micro_on {
            Stage::process(&mut c.micro, (&mut self.force, &mut self.direct, speed));
        }
        Stage::process(&mut c.space, &mut self.force);
        Stage::process(&mut c.balls, (&mut self.force, &self.params));
        let rolling_factor = self.rolling_factor();
        let c = &mut self.chain;
        Stage::process(
            &mut c.crowd,
            (&mut self.force, &self.params, rolling_factor),
        );
        // The hand's pressure and the bumps act on the whole scene's contact force.
        Stage::process(&mut c.hand, &mut self.force);
        Stage::process(&mut c.bumps, (&mut self.force, &c.source, size, speed));
        self.apply_ball_level();
        let c = &mut self.chain;
        let turning = c.engines.friction_on() && c.space.travels(); // `resonator::turn`
        c.object.set_turning(turning);
        let silent_force = self.force.iter().all(|&f| f == 0.0);
        if self.quiet
            && silent_force
            && signal_only
            && c.source.at_rest()
            && c.gesture.is_idle()
            && c.balls.active() == 0
            && c.crowd.is_idle()
            && c.object.is_silent()
        {
            // Silence skip (docs/MODEL.md "Speed and accuracy"): the ball at rest on the signal
            // engine, no extra ball, the DC blocker settled (its input and output were zero
            // last chunk, so `coupled` is still all zero) and the object rung out. The
            // object only advances its control smoothers (it touches no mode for a zero
            // input, see `object`), and the output is exactly zero: the same samples and
            // state as the full path, at a fraction of its cost.
            c.object.set_ball(c.space.ball());
            Stage::process(
                &mut c.object,
                (&self.coupled, &mut self.sound, &mut self.side),
            );
            self.gain.advance(CHUNK, self.fs);
            self.force_mix.advance(CHUNK, self.fs);
            return;
        }
        // The object hears the force without its static load (`dcblock`), at the ball.
        Stage::process(&mut c.dc, (&self.force, &mut self.coupled));
        self.quiet = silent_force && self.coupled.iter().all(|&c| c == 0.0);
        c.object.set_ball(c.space.ball());
        Stage::process(
            &mut c.object,
            (&self.coupled, &mut self.sound, &mut self.side),
        );
        if self.micro_on {
            for (s, d) in self.sound.iter_mut().zip(&self.direct) {
                *s += d;
            }
        }
        // The level match (`engine_mix`): both engines' forces through the twins.
        let ball = c.space.ball();
        Stage::process(&mut c.twins, (&mut c.engines, ball));
        self.output();
    }

    /// The level law for summed balls (`balls`): N rolling balls at 1/√N each (the scene's
    /// ball counts with its crowd), applied to the chunk's force.
    fn apply_ball_level(&mut self) {
        let scene_balls = if self.params.velocity() > 0.0 {
            self.chain.crowd.count()
        } else {
            0
        };
        let rolling = self.chain.balls.active() + scene_balls;
        self.ball_level.set_target(level_for_balls(rolling));
        if self.ball_level.is_moving() || self.ball_level.value() != 1.0 {
            let (a, b) = self.ball_level.advance(CHUNK, self.fs);
            let step = (b - a) / CHUNK as f64;
            for (i, f) in self.force.iter_mut().enumerate() {
                *f *= (a + step * (i + 1) as f64) as f32;
            }
        }
    }

    /// The output stage: the object's sound or the force (crossfaded), the gain, and the
    /// last line of defence against NaN, infinities and subnormals.
    fn output(&mut self) {
        let fs = self.fs;
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
            // Last line of defence: no NaN, infinity or subnormal for a host (a force tail
            // and a tiny gain can reach the subnormal range: a validator found −4·10⁻⁴⁰).
            self.sound[i] = flush_output(g * y);
            self.side[i] = flush_output(g * side);
        }
    }
}
