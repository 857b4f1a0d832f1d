//! The object's twins: two copies of the scene's object that the level match of the physics
//! engine plays ([`crate::scene::engine_mix`]) — one hears the signal model's force, the
//! other the unscaled physics force — so that the physics ball is as loud as the signal
//! model's through the same object. They run only while the physics engine does.

use crate::block::CHUNK;
use crate::object::fitted::LoadedObject;
use crate::object::resonator::{Object, ObjectControls};
use crate::params::Params;
use crate::scene::engine_mix::EngineMix;
use crate::source::dcblock::DcBlock;
use crate::stage::Stage;
use std::sync::Arc;

/// The level match's two objects and their DC blockers.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate (the objects' banks); nothing else does.
#[derive(Clone, Debug)]
pub struct Twins {
    objects: [Object; 2],
    dc: [DcBlock; 2],
    input: [f32; CHUNK],
    out: [[f32; CHUNK]; 2],
}

impl Twins {
    /// Two objects for `params` at `sample_rate_hz`.
    pub fn new(sample_rate_hz: f64, params: &Params) -> Self {
        let controls = ObjectControls::from_params(params);
        let mut t = Self {
            objects: [
                Object::new(sample_rate_hz, controls),
                Object::new(sample_rate_hz, controls),
            ],
            dc: [DcBlock::new(sample_rate_hz), DcBlock::new(sample_rate_hz)],
            input: [0.0; CHUNK],
            out: [[0.0; CHUNK]; 2],
        };
        t.set_params(params);
        t
    }

    /// Play a fitted object, as the scene's object does ([`Object::set_loaded`]). The
    /// previous references are never the last (the scene's object holds one): nothing is
    /// freed here. Real-time safe.
    pub fn set_loaded(&mut self, object: Option<Arc<LoadedObject>>) {
        for o in &mut self.objects {
            drop(o.set_loaded(object.clone()));
        }
    }

    /// The high band on or off, as the scene's object ([`Object::set_high_band`]).
    pub fn set_high_band(&mut self, on: bool) {
        for o in &mut self.objects {
            o.set_high_band(on);
        }
    }
}

impl Stage for Twins {
    /// The engine mix whose level the twins match, and the ball's place on the object.
    type Io<'a> = (&'a mut EngineMix, (f64, f64));

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        for (o, d) in self.objects.iter_mut().zip(&mut self.dc) {
            o.set_sample_rate(fs);
            d.set_sample_rate(fs);
        }
    }

    fn reset(&mut self, _seed: u64) {
        for (o, d) in self.objects.iter_mut().zip(&mut self.dc) {
            o.reset();
            d.reset();
        }
    }

    fn set_params(&mut self, params: &Params) {
        for o in &mut self.objects {
            Stage::set_params(o, params);
        }
    }

    fn snap(&mut self) {
        for o in &mut self.objects {
            o.snap_controls();
        }
    }

    /// The twins play only while the physics engine runs, which keeps the engine mix busy.
    fn is_idle(&self) -> bool {
        true
    }

    /// While the physics engine runs: both engines' forces through the twins, and the
    /// level match's gain updated from what they sound like.
    fn process(&mut self, (engines, ball): (&mut EngineMix, (f64, f64))) {
        if let Some((reference, physics)) = engines.level_forces() {
            for (i, f) in [reference, physics].into_iter().enumerate() {
                self.dc[i].process(f, &mut self.input);
                self.objects[i].set_ball(ball);
                self.objects[i].process_chunk(&self.input, &mut self.out[i]);
            }
            engines.observe_level(&self.out[0], &self.out[1]);
        }
    }
}
