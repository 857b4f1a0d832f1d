//! The impacts of a voice: the touched body's object struck by a short force pulse when the
//! bodies strike (as `scene::impulse` strikes it), ringing out on its own, run only while it
//! rings. Hertz contact: the peak force of an impact grows as the approach speed to the 6/5
//! (Johnson, Contact Mechanics §11.4), so a strike's amplitude is `gain × v^1.2`.

use trundle_dsp::block::CHUNK;
use trundle_dsp::object::resonator::{Object, ObjectControls};
use trundle_dsp::params::{ParamId, Params};

/// A struck object stops being run when a chunk's peak falls under this (−120 dBFS).
const QUIET: f32 = 1e-6;

/// One object struck at chunk boundaries.
#[derive(Clone, Debug)]
pub struct Strike {
    object: Object,
    mid: [f32; CHUNK],
    side: [f32; CHUNK],
    /// Next sample of `mid` to hand out (`CHUNK`: a new chunk is due).
    pos: usize,
    /// Force of the strike due at the next chunk.
    pending: f32,
    ringing: bool,
    /// Amplitude per (m/s)^1.2 of approach.
    gain: f64,
}

impl Strike {
    /// An object for `params` at `sample_rate_hz`, struck with `gain` per (m/s)^1.2.
    ///
    /// # Allocation
    /// Allocates the modal bank.
    pub fn new(sample_rate_hz: f64, params: &Params, gain: f64) -> Self {
        let mut object = Object::new(sample_rate_hz, ObjectControls::from_params(params));
        object.set_quality(params.quality());
        object.reset();
        Self {
            object,
            mid: [0.0; CHUNK],
            side: [0.0; CHUNK],
            pos: CHUNK,
            pending: 0.0,
            ringing: false,
            gain,
        }
    }

    /// Follow `params` (material, size, shape; the ball's position on the object).
    /// Real-time safe.
    pub fn set_params(&mut self, params: &Params) {
        self.object
            .set_controls(ObjectControls::from_params(params));
        self.object.set_ball((
            params.get(ParamId::PositionX),
            params.get(ParamId::PositionY),
        ));
    }

    /// Silence it at once (a slot handed to another contact).
    pub fn reset(&mut self) {
        self.object.reset();
        self.pos = CHUNK;
        self.pending = 0.0;
        self.ringing = false;
    }

    /// Strike it with an approach speed of `speed_m_s` at the next chunk.
    pub fn strike(&mut self, speed_m_s: f64) {
        let norm = self.object.gain_norm();
        let scale = if norm > 0.0 { 1.0 / norm } else { 0.0 };
        self.pending += (self.gain * speed_m_s.max(0.0).powf(1.2) * scale) as f32;
    }

    /// Is it sounding (or about to)?
    pub fn active(&self) -> bool {
        self.ringing || self.pending != 0.0 || self.pos < CHUNK
    }

    /// Add its next `out.len()` samples to `out`.
    pub fn add_to(&mut self, out: &mut [f32]) {
        for y in out.iter_mut() {
            if self.pos == CHUNK {
                if !self.ringing && self.pending == 0.0 {
                    return;
                }
                let mut force = [0f32; CHUNK];
                force[0] = self.pending;
                self.pending = 0.0;
                self.object
                    .process_chunk_stereo(&force, &mut self.mid, &mut self.side);
                let peak = self.mid.iter().fold(0f32, |m, x| m.max(x.abs()));
                self.ringing = peak > QUIET;
                self.pos = 0;
            }
            *y += self.mid[self.pos];
            self.pos += 1;
        }
    }
}
