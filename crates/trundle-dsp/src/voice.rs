//! One ball on one object: the whole chain, driven by a [`Params`] set.
//!
//! ```text
//! Params ─► Source (series → pulses → AM → low-pass) ─► force ─► Space (position comb) ─► DC block ─► Object (modal bank) ─► × gain ─► out
//!                                                       └──────────── output = force ─────────────────────────┘
//! ```
//!
//! Lifecycle ([`crate`] docs): [`Voice::new`] allocates; [`Voice::set_sample_rate`] may
//! allocate; [`Voice::reset`] and [`Voice::process`] never do. Blocks of any length are
//! split into chunks of [`CHUNK`] samples, so the output does not depend on the block size:
//! the same seed and parameters give the same samples whether rendered in blocks of 1 or
//! 8192.

use crate::dcblock::DcBlock;
use crate::modulation::AsymmetryLaw;
use crate::object::{Object, ObjectControls};
use crate::params::{ParamId, Params};
use crate::shape::Shape;
use crate::smooth::Smoother;
use crate::source::{ImpactRecord, Source, SourceControls};
use crate::space::{Space, SpaceControls, Trajectory};
use crate::CHUNK;

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
    gain: Smoother,
    /// 0 = object output, 1 = force output (crossfaded over the smoothing time).
    force_mix: Smoother,
    seed: u64,
    /// Samples processed since reset (the start of a render snaps the smoothers).
    started: bool,
    /// Position within the current chunk grid (so block size never changes the result).
    chunk_pos: usize,
    force: [f32; CHUNK],
    sound: [f32; CHUNK],
    coupled: [f32; CHUNK],
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
        asymmetry_law: AsymmetryLaw::from_index(p.get(ParamId::AsymmetryLaw) as usize),
    }
}

fn space_controls(p: &Params) -> SpaceControls {
    SpaceControls {
        amount: p.get(ParamId::Comb),
        position: (p.get(ParamId::PositionX), p.get(ParamId::PositionY)),
        listen: (p.get(ParamId::ListenX), p.get(ParamId::ListenY)),
        trajectory: Trajectory::from_index(p.get(ParamId::Trajectory) as usize),
        size_m: p.get(ParamId::ObjectSize),
        velocity: p.get(ParamId::Velocity),
    }
}

fn object_controls(p: &Params) -> ObjectControls {
    ObjectControls {
        material_x: p.get(ParamId::MaterialX),
        material_y: p.get(ParamId::MaterialY),
        size_m: p.get(ParamId::ObjectSize),
        shape: Shape::from_index(p.get(ParamId::Shape) as usize),
        modes: p.modes(),
        decay: p.get(ParamId::Decay),
    }
}

impl Voice {
    /// A voice at `sample_rate_hz` (sanitized to 8–384 kHz) with parameters `params`.
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
            gain: Smoother::new(params.gain_linear()),
            force_mix: Smoother::new(if params.force_only() { 1.0 } else { 0.0 }),
            seed,
            started: false,
            chunk_pos: 0,
            force: [0.0; CHUNK],
            sound: [0.0; CHUNK],
            coupled: [0.0; CHUNK],
        };
        v.reset();
        v
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
        self.object.set_sample_rate(self.fs);
        self.reset();
    }

    /// Back to the state after `new` with the current parameters: reseeded, silent, time 0.
    /// Real-time safe.
    pub fn reset(&mut self) {
        self.source.set_seed(self.seed);
        self.source.reset();
        self.space.reset();
        self.dc.reset();
        self.object.reset();
        self.gain.snap_to_target();
        self.force_mix.snap_to_target();
        self.started = false;
        self.chunk_pos = 0;
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
        self.object.set_controls(object_controls(params));
        self.gain.set_target(params.gain_linear());
        self.force_mix
            .set_target(if params.force_only() { 1.0 } else { 0.0 });
        let seed = params.seed();
        if seed != self.seed {
            self.seed = seed;
            self.source.set_seed(seed);
        }
    }

    /// Record impacts for [`drain_impacts`](Self::drain_impacts).
    pub fn set_impact_log(&mut self, enabled: bool) {
        self.source.set_impact_log(enabled);
    }

    /// Hand the impacts generated since the last call to `f` (oldest first); returns how
    /// many were dropped because the record was full (drain at least every ~30 000 impacts).
    pub fn drain_impacts(&mut self, f: impl FnMut(ImpactRecord)) -> u64 {
        self.source.drain_impacts(f)
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

    /// Render `out.len()` samples (mono), overwriting `out`. Any length, including 0.
    pub fn process(&mut self, out: &mut [f32]) {
        if !self.started {
            self.source.snap_controls();
            self.space.snap_controls();
            self.object.snap_controls();
            self.gain.snap_to_target();
            self.force_mix.snap_to_target();
            self.started = true;
        }
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

    fn render_chunk(&mut self) {
        let fs = self.fs;
        self.source.process_chunk(&mut self.force);
        self.space.process(&mut self.force);
        // The object hears the force without its static load (see `dcblock`).
        self.dc.process(&self.force, &mut self.coupled);
        self.object.process_chunk(&self.coupled, &mut self.sound);
        let (g0, g1) = self.gain.advance(CHUNK, fs);
        let (x0, x1) = self.force_mix.advance(CHUNK, fs);
        let inv = 1.0 / CHUNK as f32;
        let (g0, g1, x0, x1) = (g0 as f32, g1 as f32, x0 as f32, x1 as f32);
        for i in 0..CHUNK {
            let t = (i + 1) as f32 * inv;
            let g = g0 + (g1 - g0) * t;
            let x = x0 + (x1 - x0) * t;
            let y = if x == 0.0 {
                self.sound[i]
            } else {
                (1.0 - x) * self.sound[i] + x * FORCE_LEVEL * self.force[i]
            };
            // Last line of defence: never hand a host NaN or infinity.
            self.sound[i] = if y.is_finite() { g * y } else { 0.0 };
        }
    }
}
