//! The object struck once by a unit impulse (`trundle render --impulse`, `trundle
//! fit-object`): the scene's object alone, no ball, no source — an offline render that
//! compares a fitted object with its recording.

use std::sync::Arc;

use crate::block::CHUNK;
use crate::object::fitted::LoadedObject;
use crate::object::resonator::Object;
use crate::params::{ParamId, Params};
use crate::scene::voice::object_controls;

/// The impulse response ends this far under its peak (dB).
pub const IMPULSE_FLOOR_DB: f64 = -90.0;

/// The object struck once by a unit impulse (`trundle render --impulse`): no ball, no
/// source; `object`, or the recipe object of `params` when `None`, with `params`'
/// controls. Returns L and R scaled to the modes' own amplitude units
/// ([`Object::gain_norm`](crate::object::resonator::Object::gain_norm)): for a fitted object, the
/// recording's full scale, (L + R)/2 = Σ aₖ·e^{−t/τₖ}·cos(2πfₖt + φₖ) plus the band part
/// (version-1 objects, in sine phase: Σ sₖ·aₖ·e^{−t/τₖ}·sin(2πfₖt)).
/// `max_frames` long when `fixed_length`, else until it has decayed by
/// [`IMPULSE_FLOOR_DB`] (held for 50 ms) or `max_frames`.
///
/// # Allocation
/// Allocates (an offline render).
pub fn impulse_response(
    params: &Params,
    object: Option<Arc<LoadedObject>>,
    sample_rate_hz: f64,
    max_frames: usize,
    fixed_length: bool,
) -> (Vec<f32>, Vec<f32>) {
    let controls = object_controls(params);
    let mut obj = Object::new(sample_rate_hz, controls);
    obj.set_quality(params.quality());
    obj.set_controls(controls);
    obj.set_ball((
        params.get(ParamId::PositionX),
        params.get(ParamId::PositionY),
    ));
    obj.set_loaded(object);
    obj.reset();
    let mut force = [0f32; CHUNK];
    force[0] = 1.0;
    let (mut mid, mut side) = ([0f32; CHUNK], [0f32; CHUNK]);
    let (mut l, mut r) = (Vec::new(), Vec::new());
    let mut peak = 0f32;
    let mut quiet = 0usize;
    let floor = 10f32.powf(IMPULSE_FLOOR_DB as f32 / 20.0);
    let hold = (0.05 * sample_rate_hz) as usize;
    while l.len() < max_frames {
        obj.process_chunk_stereo(&force, &mut mid, &mut side);
        force[0] = 0.0;
        let norm = obj.gain_norm();
        let scale = if norm > 0.0 { (1.0 / norm) as f32 } else { 0.0 };
        let take = CHUNK.min(max_frames - l.len());
        let mut chunk_peak = 0f32;
        for i in 0..take {
            let (a, b) = ((mid[i] + side[i]) * scale, (mid[i] - side[i]) * scale);
            chunk_peak = chunk_peak.max(a.abs()).max(b.abs());
            l.push(a);
            r.push(b);
        }
        peak = peak.max(chunk_peak);
        if !fixed_length {
            if chunk_peak <= peak * floor || obj.is_silent() {
                quiet += take;
                if quiet >= hold {
                    break;
                }
            } else {
                quiet = 0;
            }
        }
    }
    (l, r)
}
